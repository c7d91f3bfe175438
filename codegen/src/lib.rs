//! Host side of the SCT toolchain: reads plant, specification and supervisor automata in the field's file
//! formats, synthesises local modular supervisors, packs them into microcontroller tables and drives the
//! firmware against a virtual plant.
//!
//! Data flows one way: model files → [`model`] → synthesis → packing → emitted tables → firmware.
#![deny(missing_docs)]

pub mod check;
pub mod child;
pub mod emit;
pub mod formats;
pub mod link;
pub mod manifest;
pub mod model;
pub mod monitor;
pub mod pack;
pub mod plant;
pub mod qemu;
pub mod rp2040;
pub mod synth;
