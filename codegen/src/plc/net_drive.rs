//! How the closed loop (`codegen run --target plc`) drives what a sequence net reads beyond the plant's
//! sensors, and waits for its own delays (docs/petri-nets.md, "Closed loop").
//!
//! A net's free inputs (`[net] free`) are nondeterministic for `codegen verify`, which proves the net for
//! every value they take at every moment; so any way the closed loop drives them is covered by its
//! figures. The closed loop drives them deterministically from the run's seed: a free input in the
//! condition of a transition with a delay (`[net.delays]`) and read negated by none (a timeout such as
//! `d4s`: the net only ever waits for it to rise) is held TRUE, so the transition's `TON` alone decides
//! when it fires; every other one (a workpiece present, `si`, which also selects a branch by `NOT si`;
//! an operator's acknowledgement) is drawn afresh from the seed at every round, so each of its branches
//! happens.
//!
//! The net's delays are the program's own `TON`s, which no `[[timers]]` entry carries: their clock
//! moves on the link's TIME alone, and a round in which nothing moved is a stall only once the longest
//! of them (and one scan) has passed ([`crate::closed_loop::OwnDelays`]).

use crate::closed_loop::OwnDelays;
use crate::net::condition::{Expr, Value};
use crate::net::interpretation::{Direction, Interpretation};
use crate::plc::sequence::INSTANCE;
use crate::plc::token_passing::Idents;

/// The free inputs of a sequence net as the closed loop drives them, and its delays.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct NetDrive {
    /// The program's variables of the timeout inputs (read by a delayed transition, never negated), held
    /// TRUE.
    pub held: Vec<String>,
    /// The program's variables of the other free inputs, drawn from the seed at every round.
    pub drawn: Vec<String>,
    /// The shortest and the longest delay of `[net.delays]`, in ms (`None` without any).
    pub delays: Option<(u32, u32)>,
    /// The paths of the places' variables in the program.
    pub places: Vec<String>,
    /// The paths of the delayed transitions' `TON`s in the program.
    pub timers: Vec<String>,
}

impl NetDrive {
    /// The drive of `net`'s program: its free inputs by the role the conditions give them.
    pub fn new(net: &Interpretation) -> NetDrive {
        let id = Idents::new(net);
        let mut drive = NetDrive::default();
        for (k, s) in net.signals.iter().enumerate() {
            if s.direction != Direction::Input || s.carried || s.initial != Value::Either {
                continue;
            }
            let delayed =
                net.conditions.iter().zip(&net.delays).any(|(c, &d)| d > 0 && c.vars().contains(&&k));
            let timeout = delayed && !net.conditions.iter().any(|c| negated(c, k, false));
            let list = if timeout { &mut drive.held } else { &mut drive.drawn };
            list.push(id.signal[k].clone());
        }
        drive.places = id.place.iter().map(|p| format!("{INSTANCE}.{p}")).collect();
        drive.timers = (id.timer.iter().zip(&net.delays))
            .filter(|&(_, &d)| d > 0)
            .map(|(t, _)| format!("{INSTANCE}.{t}"))
            .collect();
        let delays = net.delays.iter().copied().filter(|&d| d > 0);
        drive.delays = delays.clone().min().zip(delays.max());
        drive
    }

    /// What the session waits for before it calls a round in which nothing moved a stall, for a program
    /// scanned every `cycle_ms`: the longest delay and one scan, in quanta one scan shorter than the
    /// shortest delay — so a delay that starts within a quantum (a command fired in it) cannot end in it
    /// too, before the plant had its turn.
    pub fn own_delays(&self, cycle_ms: u32) -> Option<OwnDelays> {
        let (shortest, longest) = self.delays?;
        Some(OwnDelays {
            wait_ms: u64::from(longest) + u64::from(cycle_ms),
            quantum_ms: u64::from(shortest.saturating_sub(cycle_ms).max(cycle_ms.max(1))),
        })
    }
}

/// Whether `e` reads signal `k` under a negation (`under` says whether `e` itself is under one).
fn negated(e: &Expr<usize>, k: usize, under: bool) -> bool {
    match e {
        Expr::Const(_) => false,
        Expr::Var(v) => under && *v == k,
        Expr::Not(inner) => negated(inner, k, !under),
        Expr::And(es) | Expr::Or(es) => es.iter().any(|x| negated(x, k, under)),
    }
}
