//! The runtime of local modular supervisors on a microcontroller: product system (plants), supervisors and
//! interface in one event-driven loop over tables packed by `codegen`.
//!
//! The library is `no_std`, allocates nothing and touches no hardware, so the exact code that ships also
//! runs on the host, where the virtual plant, property tests and benchmarks exercise it. The Cortex-M
//! applications (`src/bin/`) only wire it to interrupts and pins.
#![cfg_attr(not(test), no_std)]
#![deny(missing_docs)]

pub mod board;
pub mod choice;
pub mod event_set;
pub mod fault;
pub mod input_queue;
pub mod link;
pub mod rng;
pub mod runtime;
pub mod status;
pub mod table;
