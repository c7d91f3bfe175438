//! One PLC program as its files hold it: structure types, POUs each with the graphical body the XML
//! carries for it, and the cyclic task that runs the program.

use super::ir::{Pou, StructType, VarClass};
use super::ld::Rung;
use super::sfc::Chart;

/// What the PLCopen XML carries for a POU besides (or instead of) its ST body.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Graphic {
    /// Nothing: the XML body is the ST one.
    Text,
    /// Ladder Diagram rungs, an `<LD>` body beside the ST one: the same logic (the state-based and hybrid
    /// programs), or the rungs that part of the ST body runs (the event-based block's supervisors, whose
    /// interface — inputs, event latching, choice, outputs — is ST only).
    Ladder(Vec<Rung>),
    /// Ladder Diagram rungs that the ST body runs one after another, each followed, when it conducts,
    /// by ST statements of its own (the state-based program's memory updates): the body's statement
    /// per rung is `IF condition THEN` the coils, then that ST `END_IF`. A vendor whose rungs can call
    /// ST (Studio 5000's `JSR`) writes them as ladder; the PLCopen XML carries the ST body only.
    LadderCallingSt(Vec<Rung>),
    /// A Sequential Function Chart instead of the ST body: the XML gives the POU's interface without
    /// its locals (the chart's steps and their times stand for them) and the chart.
    Chart(Chart),
}

/// A program: what its `.st`, `_config.st` and `.xml` files are written from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Program {
    /// The stem of the file, configuration, resource, task and instance names; the task runs the
    /// `PROGRAM` named `<base>_main`.
    pub base: String,
    /// Structure types, declared before the POUs.
    pub types: Vec<StructType>,
    /// The POUs, callees before their callers, each with its graphical body.
    pub pous: Vec<(Pou, Graphic)>,
    /// The task's interval in milliseconds.
    pub cycle_ms: u32,
}

impl Program {
    /// The POUs as the XML declares them: a charted POU with its interface only (no locals, no ST),
    /// each with its graphical body.
    pub fn xml_pous(&self) -> Vec<(Pou, &Graphic)> {
        self.pous
            .iter()
            .map(|(p, g)| match g {
                Graphic::Chart(_) => {
                    let mut p = p.clone();
                    p.vars.retain(|(class, _)| *class != VarClass::Local);
                    p.sections.clear();
                    (p, g)
                }
                _ => (p.clone(), g),
            })
            .collect()
    }
}
