//! The supervisors a project deploys ([`SupervisorChoice`]): the full set, each supervisor reduced, or
//! one monolithic supervisor, full or reduced — and the proof, made before any of them is used, that
//! the plants under the chosen supervisors have the full set's closed loop (generated and marked
//! languages).
//!
//! The proof takes the cheapest route that is still a proof:
//! - `full`: nothing to prove.
//! - `reduced`: for each supervisor `S` and its reduction `R`, against the plants `G` that share an
//!   event with `S`: `L(G ‖ R) = L(G ‖ S)` and likewise the marked languages. The whole closed loop is
//!   the intersection of the (inversely projected) local closed loops with the plant's language, so
//!   equal local closed loops give equal whole ones, and no product of all the plants is built.
//! - `monolithic`, `monolithic-reduced`: the closed loop of all plants with the chosen supervisor
//!   against the one with the full set, both built whole (the monolithic supervisor is that size anyway).

use std::fmt;

use crate::config::SupervisorChoice;
use crate::model::{Automaton, Kind};

use super::language;
use super::{product, reduction, supc, Config, Supervisor, SynthError};

/// How the chosen set's closed loop was shown to be the full set's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Proof {
    /// The chosen set is the full set.
    Same,
    /// Each reduced supervisor's closed loop with its local plant equals the full supervisor's.
    PerSupervisor,
    /// The closed loop of all plants with the chosen supervisor equals the one with the full set; the
    /// size of that closed loop.
    ClosedLoop {
        /// Its states.
        states: usize,
        /// Its transitions.
        transitions: usize,
    },
}

/// What a project deploys, in numbers: the choice, the chosen and the full set's sizes, the proof and
/// (for a reduction) the lower bounds.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Summary {
    /// The choice.
    pub choice: SupervisorChoice,
    /// Supervisors deployed.
    pub supervisors: usize,
    /// Their states and transitions, summed.
    pub size: (usize, usize),
    /// The full set's supervisors, states and transitions.
    pub full: (usize, usize, usize),
    /// The sum of the reductions' lower bounds (reduced choices only).
    pub lower_bound: Option<usize>,
    /// How the closed loop was shown equal.
    pub proof: Proof,
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let plural = |n: usize| if n == 1 { "" } else { "s" };
        let (n, s, t) = (self.supervisors, self.size.0, self.size.1);
        write!(f, "{}: {n} supervisor{}, {s} states / {t} transitions", self.choice, plural(n))?;
        if let Some(bound) = self.lower_bound {
            write!(f, " (lower bound {bound} states)")?;
        }
        let (n, s, t) = self.full;
        let full = format!("the full set: {n} supervisor{}, {s} states / {t} transitions", plural(n));
        match self.proof {
            Proof::Same => write!(f, " (the full set)"),
            Proof::PerSupervisor => write!(
                f,
                "; {full}; closed loop proven equal to the full set's (each supervisor against its local plant)"
            ),
            Proof::ClosedLoop { states, transitions } => write!(
                f,
                "; {full}; closed loop proven equal to the full set's ({states} states / {transitions} \
                 transitions)"
            ),
        }
    }
}

impl Summary {
    /// The summary of a full set of `supervisors`, used as they are.
    pub fn full(supervisors: &[Automaton]) -> Summary {
        let states = supervisors.iter().map(|a| a.states.len()).sum();
        let transitions = supervisors.iter().map(|a| a.transitions.len()).sum();
        Summary {
            choice: SupervisorChoice::Full,
            supervisors: supervisors.len(),
            size: (states, transitions),
            full: (supervisors.len(), states, transitions),
            lower_bound: None,
            proof: Proof::Same,
        }
    }
}

/// The plants sharing an event with `a`.
fn local_plants(plants: &[Automaton], a: &Automaton) -> Vec<Automaton> {
    plants.iter().filter(|p| p.events.iter().any(|e| a.event_id(&e.name).is_some())).cloned().collect()
}

/// The closed loop of `plants` under `supervisors`.
fn closed_loop(
    plants: &[Automaton],
    supervisors: &[&Automaton],
    cfg: &Config,
) -> Result<Automaton, SynthError> {
    let parts: Vec<Automaton> =
        plants.iter().cloned().chain(supervisors.iter().map(|&s| s.clone())).collect();
    product(&parts, cfg)
}

/// Refuses a chosen set whose closed loop differs from the full set's, naming where.
fn same(
    choice: SupervisorChoice,
    what: &str,
    full: &Automaton,
    chosen: &Automaton,
) -> Result<(), SynthError> {
    match language::equal(full, chosen)? {
        None => Ok(()),
        Some(difference) => Err(SynthError::ClosedLoopDiffers {
            choice: choice.to_string(),
            what: what.to_owned(),
            difference: Box::new(difference),
        }),
    }
}

/// The supervisors `choice` deploys from the `full` set (ready supervisors and the synthesised ones, each
/// with its local plant) of `plants` and `specs`, with their summary; refuses, naming the first string on
/// which they differ, a choice whose closed loop is not the full set's (a monolithic supervisor where
/// the full set conflicts, for one).
pub fn deploy(
    plants: &[Automaton],
    specs: &[Automaton],
    full: Vec<Supervisor>,
    choice: SupervisorChoice,
    cfg: &Config,
) -> Result<(Vec<Supervisor>, Summary), SynthError> {
    let sum = |set: &[Supervisor]| {
        set.iter().fold((0, 0), |(s, t), x| (s + x.automaton.states.len(), t + x.automaton.transitions.len()))
    };
    let (fs, ft) = sum(&full);
    let full_size = (full.len(), fs, ft);
    let mut lower_bound = None;
    let (chosen, proof) = match choice {
        SupervisorChoice::Full => (full, Proof::Same),
        SupervisorChoice::Reduced => {
            let mut bound = 0;
            let mut chosen = Vec::with_capacity(full.len());
            for s in full {
                cfg.stage(&format!("reducing {}", s.automaton.name));
                let local: Vec<Automaton> =
                    plants.iter().filter(|p| s.plants.contains(&p.name)).cloned().collect();
                let r = reduction(&local, &s.automaton, cfg)?;
                let what = format!("{} against {}", s.automaton.name, names(&local));
                same(
                    choice,
                    &what,
                    &closed_loop(&local, &[&s.automaton], cfg)?,
                    &closed_loop(&local, &[&r.automaton], cfg)?,
                )?;
                bound += r.lower_bound;
                chosen.push(Supervisor { automaton: r.automaton, ..s });
            }
            lower_bound = Some(bound);
            (chosen, Proof::PerSupervisor)
        }
        SupervisorChoice::Monolithic | SupervisorChoice::MonolithicReduced => {
            cfg.stage("monolithic supervisor");
            let ready: Vec<Automaton> =
                full.iter().filter(|s| s.specs.is_empty()).map(|s| s.automaton.clone()).collect();
            let all_specs: Vec<Automaton> = specs.iter().chain(&ready).cloned().collect();
            let mut automaton = supc(plants, &all_specs, cfg)?;
            automaton.name = String::from("S_monolithic");
            if choice == SupervisorChoice::MonolithicReduced {
                cfg.stage("reducing S_monolithic");
                let r = reduction(plants, &automaton, cfg)?;
                lower_bound = Some(r.lower_bound);
                automaton = r.automaton;
            }
            cfg.stage("closed loop proof");
            let full_refs: Vec<&Automaton> = full.iter().map(|s| &s.automaton).collect();
            let want = closed_loop(plants, &full_refs, cfg)?;
            let got = closed_loop(plants, &[&automaton], cfg)?;
            same(choice, "S_monolithic against every plant", &want, &got)?;
            let proof = Proof::ClosedLoop { states: want.states.len(), transitions: want.transitions.len() };
            let supervisor = Supervisor {
                automaton,
                specs: all_specs.iter().map(|a| a.name.clone()).collect(),
                plants: plants.iter().map(|a| a.name.clone()).collect(),
            };
            (vec![supervisor], proof)
        }
    };
    let summary = Summary {
        choice,
        supervisors: chosen.len(),
        size: sum(&chosen),
        full: full_size,
        lower_bound,
        proof,
    };
    Ok((chosen, summary))
}

fn names(automata: &[Automaton]) -> String {
    automata.iter().map(|a| a.name.as_str()).collect::<Vec<_>>().join(", ")
}

/// A ready supervisor as a member of the full set: no specification, the plants sharing an event with it.
pub fn ready(plants: &[Automaton], a: &Automaton) -> Supervisor {
    Supervisor {
        automaton: Automaton { kind: Kind::Supervisor, ..a.clone() },
        specs: Vec::new(),
        plants: local_plants(plants, a).into_iter().map(|p| p.name).collect(),
    }
}

/// A difference of two closed loops in words: the string and which side generates or marks it.
pub(crate) fn describe(d: &language::Difference) -> String {
    use language::DifferenceKind as K;
    let side = match d.kind {
        K::GeneratedOnlyByFirst => "only the full set's generates",
        K::GeneratedOnlyBySecond => "only the chosen set's generates",
        K::MarkedOnlyByFirst => "only the full set's marks",
        K::MarkedOnlyBySecond => "only the chosen set's marks",
    };
    let trace = if d.trace.is_empty() { String::from("ε") } else { d.trace.join(" ") };
    format!("{side} '{trace}'")
}
