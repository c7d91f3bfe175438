//! The livelock example of the design notes (§4.1) under QEMU: a global queue cycles 1, 3, 1, 3 and never
//! reaches the marked state 4; the local queues, fixed or random, keep reaching it.

use codegen::closed_loop::Options;
use codegen::config::ChoicePolicy;
use codegen::monitor::Report;
use codegen::project::Project;
use end_to_end::{example, qemu_closed_loop};

fn run(policy: ChoicePolicy) -> Report {
    let mut project = Project::load(&example("livelock/livelock.toml")).unwrap();
    project.runtime.policy = policy;
    let report = qemu_closed_loop(&project, &Options { events: 3_000, ..Options::default() });
    eprintln!("{policy}:\n{report}");
    assert_eq!(report.violations, 0, "{report}");
    report
}

#[test]
fn global_queue_livelocks_and_local_queues_reach_the_marked_state() {
    let global = run(ChoicePolicy::GlobalQueue);
    assert_eq!(global.marked_visits, 0, "{global}");
    assert_eq!(global.uncontrollable, 0, "only a and b, forever: {global}");
    for policy in [ChoicePolicy::LocalQueue, ChoicePolicy::RandomLocalQueue] {
        let local = run(policy);
        assert!(local.marked_visits >= 300, "{policy}: {local}");
        assert!(local.longest_marked_gap <= 50, "{policy}: {local}");
    }
}
