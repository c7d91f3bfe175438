//! The figures of a hybrid controller and the report of both — reduced and unreduced supervisor side by
//! side, as the paper's Table 4 (transitions, places, their total, PLC memory).
//!
//! **Cost model.** The program's size is counted on its rungs as the instruction list a PLC compiles
//! them to (`scan::ld`'s model: one instruction per contact, one to close each nested block, one per
//! coil, two per timer call) at [`BYTES_PER_INSTRUCTION`] bytes each (a 16-bit word per instruction, as
//! the compact PLCs' instruction lists); its data are its memory bits, a byte per eight. The paper's
//! 380 and 422 bytes are Siemens S7-300 load memory of its own net, which this model does not
//! reproduce; the comparison between the two supervisors is what it shows.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde::Serialize;

use super::Side;
use crate::model::Automaton;
use crate::net::interpretation::Interpretation;

/// Bytes per instruction-list instruction in the cost model.
pub const BYTES_PER_INSTRUCTION: usize = 2;

/// The figures of one controller.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Figures {
    /// Supervisor states (auto-net places).
    pub supervisor_states: usize,
    /// Places: the plant net's and the auto-net's.
    pub places: usize,
    /// Transitions: the plant net's and the auto-net's.
    pub transitions: usize,
    /// Places and transitions together (Table 4's third column).
    pub places_and_transitions: usize,
    /// Inhibitor arcs from the auto-net to the plant net.
    pub inhibitor_arcs: usize,
    /// BOOL memory bits: places, supervisor states, event bits, `Init` and `fired`.
    pub memory_bits: usize,
    /// Events whose bit the auto-net resets where it uses it (AEEM).
    pub aeem_events: usize,
    /// On-delay timers.
    pub timers: usize,
    /// Networks (rungs).
    pub networks: usize,
    /// Instruction-list instructions.
    pub instructions: usize,
    /// Program bytes under the cost model.
    pub program_bytes: usize,
    /// Data bytes: the memory bits, eight to a byte.
    pub data_bytes: usize,
}

impl Figures {
    /// The figures with their names, in the report's order.
    fn rows(&self) -> [(&'static str, usize); 12] {
        [
            ("supervisor states", self.supervisor_states),
            ("places", self.places),
            ("transitions", self.transitions),
            ("places + transitions", self.places_and_transitions),
            ("inhibitor arcs", self.inhibitor_arcs),
            ("memory bits", self.memory_bits),
            ("AEEM events", self.aeem_events),
            ("timers", self.timers),
            ("networks", self.networks),
            ("IL instructions", self.instructions),
            ("program bytes", self.program_bytes),
            ("data bytes", self.data_bytes),
        ]
    }

    /// The figures of `side` on the plant net `net`.
    pub fn new(net: &Interpretation, side: &Side) -> Figures {
        let c = &side.controller;
        let places = net.net.places.len() + side.supervisor.states.len();
        let transitions = net.net.transitions.len() + c.auto_transitions.len();
        let instructions = c.rungs.iter().map(|r| r.il().instructions).sum();
        Figures {
            supervisor_states: side.supervisor.states.len(),
            places,
            transitions,
            places_and_transitions: places + transitions,
            inhibitor_arcs: c.inhibitors.len(),
            memory_bits: c.bools.len(),
            aeem_events: c.aeem.len(),
            timers: c.timers.len(),
            networks: c.rungs.len(),
            instructions,
            program_bytes: instructions * BYTES_PER_INSTRUCTION,
            data_bytes: c.bools.len().div_ceil(8),
        }
    }
}

/// The report of [`super::generate`] (`codegen plc --json` prints it under `hybrid`).
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Report {
    /// The plant net: places and transitions.
    pub net: (usize, usize),
    /// Its reachability graph: states and transitions.
    pub plant: (usize, usize),
    /// The controller with the reduced supervisor.
    pub reduced: Figures,
    /// The controller with the unreduced supervisor.
    pub full: Figures,
    /// The AEEM events of the reduced supervisor.
    pub aeem_reduced: Vec<String>,
    /// The AEEM events of the full supervisor.
    pub aeem_full: Vec<String>,
    /// The control data of the reduced supervisor: state name → disabled events (states disabling
    /// nothing left out).
    pub condat: BTreeMap<String, Vec<String>>,
}

impl Report {
    /// The report of the two controllers on `net` with the plant `plant`.
    pub fn new(net: &Interpretation, plant: &Automaton, reduced: &Side, full: &Side) -> Report {
        let condat = reduced
            .supervisor
            .states
            .iter()
            .zip(&reduced.condat)
            .filter(|(_, d)| !d.is_empty())
            .map(|(s, d)| (s.name.clone(), d.clone()))
            .collect();
        Report {
            net: (net.net.places.len(), net.net.transitions.len()),
            plant: (plant.states.len(), plant.transitions.len()),
            reduced: Figures::new(net, reduced),
            full: Figures::new(net, full),
            aeem_reduced: reduced.controller.aeem.clone(),
            aeem_full: full.controller.aeem.clone(),
            condat,
        }
    }

    /// The report as text: the two controllers side by side.
    pub fn text(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "hybrid controller: net {} places / {} transitions, reachability graph (the plant) {} states / {} transitions",
            self.net.0, self.net.1, self.plant.0, self.plant.1
        );
        let _ = writeln!(s, "  {:<22}{:>10}{:>10}", "", "reduced", "full");
        for ((what, r), (_, f)) in self.reduced.rows().into_iter().zip(self.full.rows()) {
            let _ = writeln!(s, "  {what:<22}{r:>10}{f:>10}");
        }
        let _ = writeln!(
            s,
            "  cost model: {} bytes per IL instruction (contacts, block closes, coils; a timer call 2)",
            super::report::BYTES_PER_INSTRUCTION
        );
        let _ = writeln!(
            s,
            "  AEEM events: reduced [{}], full [{}]",
            self.aeem_reduced.join(" "),
            self.aeem_full.join(" ")
        );
        let entries: Vec<String> = self.condat.iter().map(|(k, d)| format!("{k}: {}", d.join(" "))).collect();
        let _ = writeln!(s, "  condat (reduced): {}", entries.join("  "));
        s
    }
}
