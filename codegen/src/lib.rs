//! Host side of the SCT toolchain: reads plant, specification and supervisor automata in the field's file
//! formats, synthesises local modular supervisors, packs them into microcontroller tables and drives the
//! firmware against a virtual plant.
//!
//! Data flows one way along the pipeline [`project`] owns: manifest or model files ([`manifest`],
//! [`formats`]) → automata ([`model`]) → supervisors ([`synth`]) → tables ([`pack`]) → emitted source
//! ([`emit`]) → firmware image ([`target`]); the closed loop ([`closed_loop`]) then runs that firmware
//! against the virtual plant ([`plant`]) and judges it ([`monitor`]) over a byte [`link`]. A sequence drawn
//! as a Petri net is verified under the supervisors ([`net`]). Imports follow
//! the same direction: every module imports only modules of lower layers (`ARCHITECTURE.md`,
//! `tests/layers.rs`), so there is no circle.
#![deny(missing_docs)]

pub mod closed_loop;
pub mod config;
pub mod emit;
pub mod feedback;
pub mod formats;
pub mod interpreter;
pub mod link;
pub mod manifest;
pub mod maps;
pub mod model;
pub mod monitor;
pub mod net;
pub mod pack;
pub mod plant;
pub mod plc;
pub mod problems;
pub mod project;
pub mod provenance;
pub mod scan;
pub mod sim;
pub mod symbolic;
pub mod synth;
pub mod target;
