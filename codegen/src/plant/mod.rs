//! The virtual plant: the plant models G1..Gn run on the host as the physical world a controller drives.
//!
//! The paper validated its firmware against a PC program that ran the plant models, answered the
//! controller's commands over a serial line and produced the plant's own events. This module is that
//! program's plant, made replayable: a [`VirtualPlant`] checks every command against the plants' current
//! state and takes it, and produces uncontrollable events after seeded random delays — sometimes several
//! back to back (a burst between two controller reads), sometimes at once after a command (a race with
//! the controller's next decision). [`crate::closed_loop`] couples it to a firmware over a byte link and
//! to the [`monitor`](crate::monitor) that judges the run.

mod rng;
mod simulator;

pub use rng::Rng;
pub use simulator::{PlantConfig, Refusal, VirtualPlant};
