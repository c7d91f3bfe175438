//! Mutants the monitor must kill: the cell's Cortex-M3 firmware built from wrong tables, run under QEMU
//! against the virtual plant, with the monitor judging against the true cell. Each mutant must end in a
//! safety violation, named; the unmutated firmware, in the same harness, in none (and it visits the
//! marked states as `tests/cell.rs` requires).
//!
//! - a supervisor left out of the tables;
//! - a transition of a supervisor retargeted to another of its states (the tables' check accepts it);
//! - a supervisor state's out-mask swapped for another of as many events (the check accepts it too): the
//!   supervisor now allows a command the true one disables.
//!
//! Not here, by design: the inexact-synchronisation guard removed — the monitor cannot tell an input the
//! firmware had not read from one that arrived while it chose, so a guardless firmware shows as
//! desynchronisations, never as a violation; and a policy choosing a disabled event — the runtime fires
//! only what its enabled set holds (`firmware/tests/reference.rs` checks every fired event is enabled).

use std::path::{Path, PathBuf};

use codegen::closed_loop::{run_under_qemu, Options};
use codegen::emit::{emit, timers, Provenance};
use codegen::monitor::{ChoiceModel, Report};
use codegen::pack::ranked;
use codegen::pack::tables::{Packed, Record};
use codegen::pack::{PackSet, Role};
use codegen::project::Project;
use codegen::target::image::build_qemu_image;
use end_to_end::{example, Scratch};

/// Events per run: a violation comes within the first few hundred events, or after the plant's steering
/// restarts a loop the mutant got stuck in (every 2 000 events).
const EVENTS: u64 = 8_000;

/// Builds the QEMU firmware on `packed` (with the cell's `[runtime]`) in `scratch`.
fn image(project: &Project, packed: &Packed, scratch: &Scratch) -> PathBuf {
    let m0plus = Err("mutants run on the Cortex-M3".to_owned());
    let mut text =
        emit(packed, m0plus, &project.name, &project.runtime, None, &Provenance::default()).unwrap();
    // Every tables file ends with its timer table (the cell has none), as `Project::emit` writes it.
    text += &timers::rust(&project.timers, &[]).unwrap();
    let tables = scratch.path().join("tables.rs");
    std::fs::write(&tables, text).unwrap();
    build_qemu_image(&tables, &scratch.path().join("firmware.elf")).unwrap_or_else(|e| panic!("{e}"))
}

/// Runs `elf` against the true cell.
fn judge(project: &Project, elf: &Path) -> Report {
    let options =
        Options { events: EVENTS, choices: ChoiceModel::of(project.runtime.policy), ..Options::default() };
    run_under_qemu(elf, &project.set, &project.name, &options, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"))
}

/// The change `mutate` proposes for the first record it finds one for, `supervisors` in that order,
/// applied to the block; `None` when no record allows one.
fn mutate_supervisor(
    packed: &mut Packed,
    supervisors: impl Iterator<Item = usize>,
    mutate: impl Fn(&Packed, usize, &Record, &[Record]) -> Option<(usize, u8)>,
) -> Option<String> {
    for a in supervisors {
        let records = packed.records(a).unwrap();
        for r in &records {
            if let Some((at, value)) = mutate(packed, a, r, &records) {
                let block = &mut packed.automata[a].block;
                let before = block[at];
                block[at] = value;
                return Some(format!("{}: byte {at} {before} -> {value}", packed.automata[a].name));
            }
        }
    }
    None
}

/// Whether out-mask `m` holds a controllable event that out-mask `n` does not.
fn allows_more(packed: &Packed, m: usize, n: usize) -> bool {
    (0..packed.words()).any(|w| packed.masks[m][w] & !packed.masks[n][w] & packed.controllable[w] != 0)
}

#[test]
fn the_monitor_kills_every_mutant_of_the_cells_tables() {
    let project = Project::load(&example("cell/cell.toml")).unwrap();
    let truth = ranked::encode(&project.set).unwrap();
    assert!(!truth.wide, "the mutations below write 1-byte fields");
    let mut verdicts = Vec::new();

    // The unmutated firmware: no violation, so the harness itself does not make them.
    let scratch = Scratch::new("mutant-none");
    let report = judge(&project, &image(&project, &truth, &scratch));
    assert_eq!(report.violations, 0, "the true firmware: {report}");
    assert!(report.longest_marked_gap < 2_000, "the true firmware: {report}");

    // A supervisor left out: the tables of the plants and the other supervisors.
    let members = project.set.members();
    let left_out = members.iter().rposition(|m| m.role == Role::Supervisor).unwrap();
    let of = |role| members.iter().enumerate().filter(move |(i, m)| m.role == role && *i != left_out);
    let partial = PackSet::new(
        of(Role::Plant).map(|(_, m)| m.automaton.clone()).collect(),
        of(Role::Supervisor).map(|(_, m)| m.automaton.clone()).collect(),
    )
    .unwrap();
    assert_eq!(partial.events(), project.set.events(), "the same event numbering");
    verdicts.push((format!("{} left out", members[left_out].name()), ranked::encode(&partial).unwrap()));

    // A transition retargeted to a state that allows a command the true target disables.
    let mut retargeted = truth.clone();
    let supervisors = truth.plants..truth.automata.len();
    let what = mutate_supervisor(&mut retargeted, supervisors.clone().rev(), |p, _, r, records| {
        r.targets.iter().enumerate().find_map(|(i, &t)| {
            let target = records.iter().find(|x| x.handle == t)?;
            let other = records
                .iter()
                .find(|x| x.handle != t && x.handle <= 255 && allows_more(p, x.mask, target.mask))?;
            Some((r.at + 1 + i, other.handle as u8))
        })
    })
    .expect("a transition to retarget");
    verdicts.push((format!("transition retargeted ({what})"), retargeted));

    // An out-mask swapped for another of as many events that allows a command the original does not.
    let mut swapped = truth.clone();
    let what = mutate_supervisor(&mut swapped, supervisors, |p, a, r, _| {
        let ones = |m: usize| p.masks[m].iter().map(|w| w.count_ones()).sum::<u32>();
        // Within the supervisor's alphabet, as the check requires of its masks.
        let inside = |m: usize| p.masks[m].iter().zip(&p.automata[a].alphabet).all(|(w, al)| w & !al == 0);
        let other = (0..p.masks.len().min(256))
            .find(|&m| m != r.mask && ones(m) == ones(r.mask) && inside(m) && allows_more(p, m, r.mask))?;
        Some((r.at, other as u8))
    })
    .expect("a mask to swap");
    verdicts.push((format!("out-mask swapped ({what})"), swapped));

    for (i, (name, packed)) in verdicts.iter().enumerate() {
        let scratch = Scratch::new(&format!("mutant-{i}"));
        let report = judge(&project, &image(&project, packed, &scratch));
        eprintln!("mutant {name}: {} violations (first: {:?})", report.violations, report.findings.first());
        assert!(report.violations > 0, "mutant survived: {name}\n{report}");
        assert!(!report.findings.is_empty(), "{name}: the violation is named");
    }
}
