//! The runtime of local modular supervisors on a microcontroller: product system (plants), supervisors and
//! interface in one event-driven loop over tables packed by `codegen`.
//!
//! The library is `no_std`, allocates nothing and touches no hardware, so the exact code that ships also
//! runs on the host, where the virtual plant, property tests and benchmarks exercise it.
#![cfg_attr(not(test), no_std)]
#![deny(missing_docs)]

pub mod table;
