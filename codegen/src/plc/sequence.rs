//! A sequence net as PLC code beside the interlocks, in one program (DESIGN §11, "Code"): the net's
//! token passing ([`super::token_passing`]) as a function block in Structured Text, the same block as a
//! Sequential Function Chart in PLCopen TC6 XML, and the `PROGRAM` that calls the sequence and then the
//! interlocks' block.
//!
//! **Token passing** (`<name>_seq`, a `FUNCTION_BLOCK`): first its `reset` input — while TRUE, each
//! place back to its initial marking, each delay's `TON` stopped and each output FALSE, as at power-up —
//! then the lowering's rungs as statements: the delays' timers, one statement per transition in net order, then the place actions held
//! ([`Actions::Held`]: each output signal set to the value of a marked place that names it, kept when
//! none does). Sensors are inputs, actuators outputs, and each actuator an input place's action
//! names has a feedback input `is_<signal>` (its value now) for the output enabling.
//!
//! **SFC** (the same block in the XML): [`token_passing::chart`] — a step per place, a transition per
//! net transition, an action block per step.
//!
//! **One program** ([`beside`]): the sequence *requests*, the interlocks *allow* — the seed paper's
//! structure. The interlocks' block is built with a `req_<event>` input per controllable event
//! ([`super::PlcOptions::requests`]): an event is enabled when every supervisor allows it *and* it is
//! requested. The `PROGRAM` calls the sequence (sensors from their input variables, actuators' feedback
//! from their output variables, free inputs from variables of its own, and the program's `reset`, so
//! one `reset` brings the sequence and the supervisors back together), then the interlocks' block with
//! `req_<s>1 := seq.<s> AND NOT <s>` and `req_<s>0 := NOT seq.<s> AND <s>` per demanded actuator, then
//! copies the outputs. A demanded command the supervisors disable waits, requested, until they allow it.
//!
//! **Delays** (`[net.delays]`) mean what the lowering says: a transition fires once its input places
//! have been marked for D.

use super::io::Source;
use super::token_passing::{self, Actions, Idents};
use super::{PlcError, Program};
use crate::config::{Action, Edge};
use crate::net::interpretation::{Direction, Interpretation};
use crate::scan::ir::{Expr, Op, Pou, Section, Stmt, Type, Var, VarClass};
use crate::scan::ld::CoilKind;
use crate::scan::sfc::Chart;

/// The sequence block's instance in the program: the paths of its places and timers start with it.
pub const INSTANCE: &str = "seq";

/// The identifiers of `net`'s block, and the name of its `reset` input (`reset` unless a signal has it).
fn idents(net: &Interpretation) -> (Idents, String) {
    let mut id = Idents::new(net);
    let reset = id.plain("reset");
    (id, reset)
}

/// The token-passing function block `<name>_seq` of `net`, and the same block's chart.
pub fn block(net: &Interpretation, name: &str) -> Result<(Pou, Chart), PlcError> {
    let (id, reset) = idents(net);
    let lowered = token_passing::lower(net, &id, Actions::Held, &[], &[])?;
    let chart = token_passing::chart(net, &id)?;
    let mut inputs = Vec::new();
    let mut outputs = Vec::new();
    let mut cold = Vec::new();
    for (k, s) in net.signals.iter().enumerate() {
        if s.direction == Direction::Output {
            cold.push(Stmt::set(&id.signal[k], Expr::Bool(false)));
        }
        match s.direction {
            Direction::Input => {
                inputs.push(Var::new(&id.signal[k], Type::Bool, format!("input signal {}", s.name)))
            }
            Direction::Output => {
                outputs.push(Var::new(
                    &id.signal[k],
                    Type::Bool,
                    format!("{}, demanded by the marked places", s.name),
                ));
                if s.carried {
                    inputs.push(Var::new(
                        &id.feedback[k],
                        Type::Bool,
                        format!("the actuator {} now", s.name),
                    ));
                }
            }
        }
    }
    let mut locals: Vec<Var> = net
        .net
        .places
        .iter()
        .enumerate()
        .map(|(k, p)| {
            Var::new(&id.place[k], Type::Bool, format!("place {}", p.id)).init(Expr::Bool(p.initial == 1))
        })
        .collect();
    locals.push(Var::new(&id.fired, Type::Bool, "a transition fired this scan"));
    for (t, tr) in net.net.transitions.iter().enumerate().filter(|&(t, _)| net.delays[t] > 0) {
        let what = format!("transition {}: its input places marked for {} ms", tr.id, net.delays[t]);
        locals.push(Var::new(&id.timer[t], Type::Named("TON".into()), what));
    }
    inputs.push(
        Var::new(&reset, Type::Bool, "TRUE: the scan starts from the initial marking, timers stopped")
            .init(Expr::Bool(false)),
    );
    let places = net.net.places.iter().zip(&id.place);
    let mut restart: Vec<Stmt> = places.map(|(p, v)| Stmt::set(v, Expr::Bool(p.initial == 1))).collect();
    restart.extend(lowered.timers.iter().flat_map(|r| &r.coils).filter_map(|c| match c.kind {
        CoilKind::OnDelay(ms) => Some(Stmt::Call(
            c.variable.clone(),
            vec![("IN".into(), Expr::Bool(false)), ("PT".into(), Expr::Time(ms))],
        )),
        _ => None,
    }));
    restart.extend(cold);
    let passing: Vec<Stmt> =
        lowered.timers.iter().chain(&lowered.firing).flat_map(|r| r.statements()).collect();
    let actions: Vec<Stmt> = lowered.actions.iter().flat_map(|r| r.statements()).collect();
    let pou = Pou {
        program: false,
        name: format!("{name}_seq"),
        vars: vec![(VarClass::Input, inputs), (VarClass::Output, outputs), (VarClass::Local, locals)],
        sections: vec![
            Section::new(
                "reset",
                "the initial marking, its timers stopped, its outputs FALSE: the first scan again",
                vec![Stmt::when(Expr::var(&reset), restart)],
            ),
            Section::new("transitions", "token passing, one transition per scan", passing),
            Section::new("outputs", "place actions", actions),
        ],
    };
    Ok((pou, chart))
}

/// The sequence beside the interlocks in one PLC program ([`super::generate_with_sequence`]).
pub struct Sequence {
    /// The token-passing function block (`<name>_seq`), for the ST file.
    pub block: Pou,
    /// The same block as a chart, for the XML.
    pub chart: Chart,
    /// The one `PROGRAM`: the sequence called, then the interlocks' block with the sequence's requests,
    /// then the outputs.
    pub main: Pou,
}

/// Where a signal the automata carry lives in the interlocks' program: a sensor's level is its input
/// variable (negated where the variable's rising edge is the signal's falling one); an actuator's value
/// is the output variable its events set and clear. Both edges must meet in one variable.
fn level(net: &Interpretation, program: &Program, k: usize) -> Result<Expr, PlcError> {
    let signal = &net.signals[k];
    let missing = || {
        let wanted = match signal.direction {
            Direction::Input => "a sensor: map its events to one input variable in [[plc.inputs]]",
            Direction::Output => {
                "an actuator: map its events to one output variable, set and clear, in [[plc.outputs]]"
            }
        };
        PlcError::Signal { signal: signal.name.clone(), wanted }
    };
    let mut found: Option<(&str, bool)> = None;
    for value in [true, false] {
        let Some(e) = net.event_for(k, value) else { continue };
        let here = match signal.direction {
            Direction::Input => match program.io.sources.get(&e) {
                Some(Source::Input { variable, edge, .. }) => {
                    (variable.as_str(), (*edge == Edge::Falling) == value)
                }
                _ => return Err(missing()),
            },
            Direction::Output => {
                let act = if value { Action::Set } else { Action::Clear };
                let o =
                    program.io.outputs.iter().find(|o| o.actions.iter().any(|&(x, a, _)| x == e && a == act));
                (o.ok_or_else(missing)?.variable.as_str(), false)
            }
        };
        if found.is_some_and(|(v, _)| v != here.0) {
            return Err(missing());
        }
        found = Some(here);
    }
    let (variable, negated) = found.ok_or_else(missing)?;
    Ok(if negated { !Expr::var(variable) } else { Expr::var(variable) })
}

/// The sequence and the interlocks' `program` (built with requests) as one PLC program: see
/// [`Sequence`]. Each scan the `PROGRAM` calls the sequence with the sensors' input variables, the
/// actuators' output variables as feedback and the free inputs; then the interlocks' block, whose
/// `req_<event>` is the sequence's demand: an actuator's event is requested while the sequence demands
/// the value it gives and the output does not have it yet (an event of an actuator no place action
/// names is always requested: the interlocks alone decide it, as the verification lets it happen);
/// then the outputs, and the lamps from the sequence.
pub fn beside(net: &Interpretation, program: &Program, name: &str) -> Result<Sequence, PlcError> {
    let (block, chart) = block(net, name)?;
    let (id, reset) = idents(net);
    let mut main = program.main.clone();
    let taken: Vec<String> =
        main.vars.iter().flat_map(|(_, vs)| vs.iter().map(|v| v.name.to_ascii_uppercase())).collect();
    let mut own = Vec::new();
    let declare = |own: &mut Vec<Var>, v: Var| -> Result<(), PlcError> {
        if taken.contains(&v.name.to_ascii_uppercase())
            || own.iter().any(|w: &Var| w.name.eq_ignore_ascii_case(&v.name))
        {
            return Err(PlcError::Duplicate(v.name));
        }
        own.push(v);
        Ok(())
    };
    declare(&mut own, Var::new(INSTANCE, Type::Named(block.name.clone()), "the sequence net"))?;
    let mut args = Vec::new();
    let mut lamps = Vec::new();
    // The sensors a condition reads and the actuators a place action names: only theirs are passed
    // (the block's other inputs are read by nothing), so only they need a variable in [plc].
    let read: Vec<usize> = net.conditions.iter().flat_map(|c| c.vars()).copied().collect();
    let demanded: Vec<usize> = (0..net.signals.len())
        .filter(|&k| net.actions.iter().any(|a| a.iter().any(|&(s, _)| s == k)))
        .collect();
    for (k, s) in net.signals.iter().enumerate() {
        match (s.direction, s.carried) {
            (Direction::Input, true) if read.contains(&k) => {
                args.push((id.signal[k].clone(), level(net, program, k)?))
            }
            (Direction::Output, true) if demanded.contains(&k) => {
                args.push((id.feedback[k].clone(), level(net, program, k)?))
            }
            (_, true) => {}
            (Direction::Input, false) => {
                let mut v = Var::new(
                    &id.signal[k],
                    Type::Bool,
                    format!("input {} (no automaton carries it)", s.name),
                );
                if let crate::net::condition::Value::Is(b) = s.initial {
                    v = v.init(Expr::Bool(b));
                }
                declare(&mut own, v)?;
                args.push((id.signal[k].clone(), Expr::var(&id.signal[k])));
            }
            (Direction::Output, false) => {
                declare(
                    &mut own,
                    Var::new(&id.signal[k], Type::Bool, format!("lamp {}, set by the sequence", s.name)),
                )?;
                lamps.push(Stmt::set(&id.signal[k], Expr::var(format!("{INSTANCE}.{}", id.signal[k]))));
            }
        }
    }
    let mut requests = Vec::new();
    for (e, req) in &program.requests {
        let (k, value) = net.edges[e.index()];
        let ask = if demanded.contains(&k) {
            let out = level(net, program, k)?;
            let want = Expr::var(format!("{INSTANCE}.{}", id.signal[k]));
            if value {
                want.op(Op::And, !out)
            } else {
                (!want).op(Op::And, out)
            }
        } else {
            Expr::Bool(true)
        };
        requests.push((req.clone(), ask));
    }
    let names: Vec<&str> = requests.iter().map(|(r, _)| r.as_str()).collect();
    for (_, vars) in &mut main.vars {
        vars.retain(|v| !names.contains(&v.name.as_str()));
    }
    let run = &mut main.sections[0].stmts;
    for stmt in run.iter_mut() {
        if let Stmt::Call(_, call) = stmt {
            for (arg, value) in call.iter_mut() {
                if let Some((_, ask)) = requests.iter().find(|(r, _)| r == arg) {
                    *value = ask.clone();
                }
            }
        }
    }
    args.push((reset, Expr::var("reset")));
    run.insert(0, Stmt::Call(INSTANCE.into(), args));
    run.extend(lamps);
    main.sections[0].title = "the sequence, the interlocks with its requests, the outputs".into();
    main.vars.push((VarClass::Local, own));
    Ok(Sequence { block, chart, main })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::manifest::Manifest;
    use crate::model::testing::build;
    use crate::model::EventTable;
    use crate::net::model::{Net, Place, Transition};
    use std::path::Path;

    /// The manifest of the tests: the net's interpretation and a `[plc]` section (`plc` appended).
    fn manifest(plc: &str) -> Manifest {
        let text = format!("name = \"x\"\n[net]\npnml = \"n.pnml\"\n[net.conditions]\nt0 = \"sr\"\n[net.actions]\np1 = {{ af = 1 }}\n{plc}");
        Manifest::parse(Path::new("m.toml"), &text).unwrap()
    }

    /// The plant of the tests: an actuator `af` and a sensor edge `sr1`.
    fn plant() -> crate::model::Automaton {
        build("A", &["0", "1"], &["af1", "af0"], &[("0", "af1", "1"), ("1", "af0", "0"), ("0", "sr1", "0")])
    }

    /// The program written for the manifest `text` over the tests' plant and a net of one-arc
    /// transitions `(id, from, to)` between places `p0, p1, …` marked where `initial` says: the set, the
    /// bound net and the program.
    fn chain_program(
        text: &str,
        initial: &[bool],
        transitions: &[(&str, usize, usize)],
    ) -> (crate::pack::PackSet, Interpretation, crate::plc::Output) {
        let m = Manifest::parse(Path::new("m.toml"), text).unwrap();
        let n = Net {
            name: "n".into(),
            places: initial
                .iter()
                .enumerate()
                .map(|(i, &m)| Place { id: format!("p{i}"), initial: u32::from(m) })
                .collect(),
            transitions: transitions
                .iter()
                .map(|&(id, from, to)| Transition {
                    id: id.into(),
                    inputs: vec![(from, 1)],
                    outputs: vec![(to, 1)],
                    ..Transition::default()
                })
                .collect(),
        };
        let set = crate::pack::PackSet::new(vec![plant()], Vec::new()).unwrap();
        let opts = crate::plc::PlcOptions::new("x", &Default::default(), m.plc.as_ref(), None).unwrap();
        let net = Interpretation::bind(m.net.as_ref().unwrap(), &m.file, n, set.events()).unwrap();
        let out = crate::plc::generate_with_sequence(&set, &opts, &Default::default(), &net).unwrap();
        (set, net, out)
    }

    /// p0 –t0 (sr)→ p1, and a second way out of p0 (t2 into p1 and p2) that t1 joins back into p0: a
    /// safe net; p1 demands `af`.
    fn net() -> Interpretation {
        let t = |id: &str, inputs: Vec<(usize, u32)>, outputs: Vec<(usize, u32)>| Transition {
            id: id.into(),
            inputs,
            outputs,
            ..Transition::default()
        };
        let n = Net {
            name: "n".into(),
            places: (0..3).map(|i| Place { id: format!("p{i}"), initial: u32::from(i == 0) }).collect(),
            transitions: vec![
                t("t0", vec![(0, 1)], vec![(1, 1)]),
                t("t1", vec![(1, 1), (2, 1)], vec![(0, 1)]),
                t("t2", vec![(0, 1)], vec![(1, 1), (2, 1)]),
            ],
        };
        let a = plant();
        let table = EventTable::build([&a]).unwrap();
        let m = manifest("");
        Interpretation::bind(m.net.as_ref().unwrap(), &m.file, n, &table).unwrap()
    }

    #[test]
    fn token_passing_fires_one_transition_per_scan_behind_output_enabling() {
        let (fb, _) = block(&net(), "n").unwrap();
        let body = fb.body();
        assert!(body.contains("IF NOT fired AND P_p0 AND e_sr THEN\n    P_p0 := FALSE;\n    P_p1 := TRUE;\n    fired := TRUE;\nEND_IF;"), "{body}");
        assert!(body.contains("IF NOT fired AND P_p1 AND P_p2 AND is_af THEN"), "t1 waits for af: {body}");
        assert!(body.contains("IF P_p1 THEN\n    af := TRUE;\nEND_IF;"), "{body}");
        assert_eq!(fb.var("e_sr").map(|(c, _)| c), Some(VarClass::Input), "sr is the SR block's name");
        crate::scan::strict::check(&[], &[&fb]).unwrap();
    }

    #[test]
    fn the_sfc_diverges_and_converges_where_the_net_does() {
        let sfc = block(&net(), "n").unwrap().1.body();
        assert_eq!(sfc.matches("<step ").count(), 3);
        assert_eq!(sfc.matches("<selectionDivergence ").count(), 1, "p0 has two ways out");
        assert_eq!(sfc.matches("<selectionConvergence ").count(), 1, "p1 has two ways in");
        assert_eq!(sfc.matches("<simultaneousDivergence ").count(), 1, "t2 marks two places");
        assert_eq!(sfc.matches("<simultaneousConvergence ").count(), 1, "t1 joins two places");
        assert!(sfc.contains("initialStep=\"true\"") && sfc.contains("af := TRUE;"));
        let two = Interpretation {
            net: Net { places: vec![Place { id: "p".into(), initial: 2 }], ..Net::default() },
            ..net()
        };
        let err = block(&two, "w").unwrap_err().to_string();
        assert!(
            err.contains("place 'p' holds 2 tokens in the initial marking") && err.contains("only safe nets"),
            "{err}"
        );
        // t2 without its join: a second t2 puts a second token into p2.
        let mut unsafe_net = net();
        unsafe_net.net.transitions[1].inputs = vec![(1, 1)];
        let err = block(&unsafe_net, "u").unwrap_err().to_string();
        assert!(err.starts_with("place 'p2' holds 2 tokens after the firing sequence t2 t1 t2"), "{err}");
    }

    /// The one program: the sequence first, its demand as the interlocks' requests, the sensor's input
    /// variable as the sequence's input and the actuator's output as its feedback; a sensor reaching the
    /// interlocks only as an `EVENTS` member has no level the sequence could read, and is refused.
    #[test]
    fn the_sequence_requests_and_the_interlocks_allow_in_one_program() {
        let outputs = "[[plc.outputs]]\nevent = \"af1\"\nvariable = \"af\"\naction = \"set\"\n[[plc.outputs]]\nevent = \"af0\"\nvariable = \"af\"\naction = \"clear\"\n";
        let input = "[[plc.inputs]]\nevent = \"sr1\"\nvariable = \"x_sr\"\nedge = \"falling\"\n";
        let set = crate::pack::PackSet::new(vec![plant()], Vec::new()).unwrap();
        let generate = |plc: &str| {
            let m = manifest(&format!("[plc]\npolicy = \"first\"\n{plc}"));
            let opts = crate::plc::PlcOptions::new("x", &Default::default(), m.plc.as_ref(), None).unwrap();
            let net =
                Interpretation::bind(m.net.as_ref().unwrap(), &m.file, net().net, set.events()).unwrap();
            crate::plc::generate_with_sequence(&set, &opts, &Default::default(), &net)
        };
        let out = generate(&format!("{outputs}{input}")).unwrap();
        let main = out.program.main.body();
        let seq = main.find("seq(is_af := af, e_sr := NOT x_sr, reset := reset);").expect(&main);
        let sct = main
            .find("sct(x_sr := x_sr, req_af1 := seq.af AND NOT af, req_af0 := NOT seq.af AND af")
            .expect(&main);
        assert!(seq < sct, "the sequence decides before the interlocks: {main}");
        assert!(
            out.program.fb.body().contains("enabled[0] := st_A = 0 AND req_af1;"),
            "{}",
            out.program.fb.body()
        );
        assert!(out.files[0].1.contains("FUNCTION_BLOCK x_seq") && out.files[2].1.contains("<SFC>"));
        let err = generate(outputs).unwrap_err().to_string();
        assert!(err.contains("net: signal 'sr' has no variable in [plc]; it is a sensor"), "{err}");
    }
    /// The program's `reset` brings the sequence back in the scan the interlocks reset: the net moved off
    /// its initial marking (p1 marked, its delay's timer counting) and a timer of a place marked
    /// throughout (p2's) half run out; the scan that reads `reset` starts from the initial marking
    /// with every delay counting afresh, the sequence's demand and the interlocks' output FALSE.
    #[test]
    fn reset_brings_the_sequence_back_to_its_initial_marking_in_the_interlocks_scan() {
        let text = "name = \"x\"\n[net]\npnml = \"n.pnml\"\n[net.conditions]\nt0 = \"sr\"\nt2 = \"sr\"\n\
            [net.actions]\np1 = { af = 1 }\n[net.delays]\nt1 = 1000\nt2 = 1000\n[plc]\npolicy = \"first\"\n\
            [[plc.outputs]]\nevent = \"af1\"\nvariable = \"af\"\naction = \"set\"\n\
            [[plc.outputs]]\nevent = \"af0\"\nvariable = \"af\"\naction = \"clear\"\n\
            [[plc.inputs]]\nevent = \"sr1\"\nvariable = \"x_sr\"\nedge = \"rising\"\n";
        // p0 –t0 (sr)→ p1 –t1 (1 s)→ p0, and p2 –t2 (sr, 1 s)→ p3.
        let (_, _, out) =
            chain_program(text, &[true, false, true, false], &[("t0", 0, 1), ("t1", 1, 0), ("t2", 2, 3)]);
        let mut plc = crate::interpreter::Plc::load(&out.files[0].1).unwrap();
        plc.set_cycle_ms(100);
        let marking = |plc: &crate::interpreter::Plc| -> Vec<bool> {
            (0..4).map(|i| plc.get_bool(&format!("seq.P_p{i}")).unwrap()).collect()
        };
        plc.scan().unwrap();
        plc.set_bool("x_sr", true).unwrap();
        plc.scan().unwrap();
        plc.set_bool("x_sr", false).unwrap();
        for _ in 0..5 {
            plc.scan().unwrap();
        }
        assert_eq!(marking(&plc), [false, true, true, false], "t0 fired");
        assert!(plc.get_bool("seq.af").unwrap() && plc.get_bool("af").unwrap(), "p1 demands af, allowed");
        assert_eq!((plc.get_int("seq.T_t1.ET").unwrap(), plc.get_int("seq.T_t2.ET").unwrap()), (400, 600));
        plc.set_bool("reset", true).unwrap();
        plc.scan().unwrap();
        assert_eq!(marking(&plc), [true, false, true, false], "the initial marking");
        assert_eq!((plc.get_int("seq.T_t1.ET").unwrap(), plc.get_int("seq.T_t2.ET").unwrap()), (0, 0));
        assert!(!plc.get_bool("seq.T_t2.Q").unwrap() && plc.get_bool("seq.T_t2.RUNNING").unwrap());
        assert!(!plc.get_bool("seq.af").unwrap() && !plc.get_bool("af").unwrap(), "nothing demanded");
        // Released, t2's delay counts from the reset: 1 s after it, not 400 ms.
        plc.set_bool("reset", false).unwrap();
        plc.set_bool("x_sr", true).unwrap();
        let mut scans = 0;
        while !plc.get_bool("seq.P_p3").unwrap() && scans < 20 {
            plc.scan().unwrap();
            scans += 1;
        }
        assert_eq!(scans, 10, "t2 fires in the scan its timer reaches 1 s after the reset");
    }
    /// A net whose marking cycles with no command (p0 –t0→ p1 –t1→ p0, both always enabled) never
    /// settles: the closed loop's driver sees the program's whole state come back after two scans and
    /// stops counting the cycle as pending, so a SYNC is answered (and the round is the session's to
    /// judge) instead of waiting for the host's answer timeout.
    #[test]
    fn a_net_cycling_without_a_command_is_no_longer_pending_once_its_state_repeats() {
        use crate::plc::closed_loop::{Driver, IoMap, Scanner};
        let text = "name = \"x\"\n[net]\npnml = \"n.pnml\"\n[plc]\npolicy = \"first\"\n\
            [[plc.outputs]]\nevent = \"af1\"\nvariable = \"af\"\naction = \"set\"\n\
            [[plc.outputs]]\nevent = \"af0\"\nvariable = \"af\"\naction = \"clear\"\n\
            [[plc.inputs]]\nevent = \"sr1\"\nvariable = \"x_sr\"\nedge = \"rising\"\n";
        let (set, net, out) = chain_program(text, &[true, false], &[("t0", 0, 1), ("t1", 1, 0)]);
        let io = IoMap::new(&out.report, set.events()).unwrap();
        let mut d = Driver::new(&out.files[0].1, io).unwrap();
        d.drive_net(crate::plc::net_drive::NetDrive::new(&net), 0).unwrap();
        d.hold(true).unwrap();
        let mut pending = Vec::new();
        for _ in 0..4 {
            d.scan().unwrap();
            pending.push(d.pending().unwrap());
        }
        assert_eq!(pending, [true, true, false, false], "the marking moves every scan");
    }
}
