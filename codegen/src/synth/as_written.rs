//! Which specifications are controllable as written: for each specification E and its local plant G
//! (the plant subsystems sharing an event with it, as the local modular architecture takes them), whether
//! the language of G ‖ E is controllable with respect to G — no reachable state of the product where the
//! plant generates an uncontrollable event that E refuses. A controllable specification needs no
//! supervisor beyond itself (its supervisor only enforces nonblocking, if anything); the others are the
//! ones synthesis changes. The RTPN paper reports exactly this first ("all but the last two
//! specifications are controllable") before it synthesises for the rest.

use crate::model::{Automaton, Dfa, EventId};

use super::product::{tuple_name, Exploration, Options};
use super::{Config, Inputs, SynthError};

/// The verdict on one specification as written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AsWritten {
    /// The specification's name.
    pub spec: String,
    /// The plant subsystems of its local plant.
    pub plants: Vec<String>,
    /// The verdict.
    pub verdict: Verdict,
}

/// Whether a specification is controllable as written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Controllable with respect to its local plant.
    Controllable,
    /// Not controllable: the shortest string to a state where it refuses an uncontrollable event its
    /// plant generates.
    Refuses(Refusal),
    /// Not decided: the product of the specification and its local plant passed a limit of the
    /// configuration (the message says which). Synthesis may still have run, symbolically.
    Undecided(String),
}

/// Where a specification refuses what its plant cannot be stopped from doing.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Refusal {
    /// The shortest string of events (breadth-first) from the initial state of G ‖ E.
    pub trace: Vec<String>,
    /// The state it reaches, as the tuple of local plant and specification states.
    pub state: String,
    /// The uncontrollable event the plant generates there and the specification refuses (the first in
    /// event order).
    pub event: String,
}

impl AsWritten {
    /// Whether the specification is controllable with respect to its local plant (`None`: undecided).
    pub fn controllable(&self) -> Option<bool> {
        match self.verdict {
            Verdict::Controllable => Some(true),
            Verdict::Refuses(_) => Some(false),
            Verdict::Undecided(_) => None,
        }
    }
}

/// Whether the plant `plant` shares an event with the specification `spec`: a subsystem of its local plant.
pub(crate) fn shares_event(plant: &Dfa, spec: &Dfa) -> bool {
    plant.alphabet.iter().any(|&e| spec.has_event(e))
}

/// The verdict on each of `specs` against its local plant among `plants`, in the order given; a product
/// past `cfg`'s limits leaves its specification [`Verdict::Undecided`].
pub fn specifications(
    plants: &[Automaton],
    specs: &[Automaton],
    cfg: &Config,
) -> Result<Vec<AsWritten>, SynthError> {
    let inputs = Inputs::new(plants.iter().chain(specs))?;
    let (plant_dfas, spec_dfas) = inputs.dfas.split_at(plants.len());
    let mut out = Vec::with_capacity(specs.len());
    for (spec, spec_dfa) in specs.iter().zip(spec_dfas) {
        let local: Vec<usize> =
            (0..plants.len()).filter(|&i| shares_event(&plant_dfas[i], spec_dfa)).collect();
        let components: Vec<&Dfa> = local.iter().map(|&i| &plant_dfas[i]).chain([spec_dfa]).collect();
        let options = Options { plants: local.len(), parents: true };
        let plants_named = local.iter().map(|&i| plants[i].name.clone()).collect();
        let walk = match Exploration::run(&components, &inputs.controllable, options, cfg, &spec.name) {
            Ok(walk) => walk,
            Err(e) => {
                out.push(AsWritten {
                    spec: spec.name.clone(),
                    plants: plants_named,
                    verdict: Verdict::Undecided(e.to_string()),
                });
                continue;
            }
        };
        let sources: Vec<&Automaton> = local.iter().map(|&i| &plants[i]).chain([spec]).collect();
        let name = |e: u32| inputs.table.name(EventId::from_u32(e)).to_owned();
        // States are numbered breadth-first: the lowest bad state is one of the nearest.
        let verdict = match walk.bad.first() {
            None => Verdict::Controllable,
            Some(&(s, e)) => Verdict::Refuses(Refusal {
                trace: walk.trace(s).into_iter().map(name).collect(),
                state: tuple_name(&walk, &sources, s),
                event: name(e),
            }),
        };
        out.push(AsWritten { spec: spec.name.clone(), plants: plants_named, verdict });
    }
    Ok(out)
}
