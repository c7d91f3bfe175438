//! The runtime of local modular supervisors on a microcontroller: product system (plants), supervisors and
//! interface in one event-driven loop over tables packed by `codegen` — or, with `[runtime] mode =
//! "state"`, state feedback control over the plant's packed signals and no supervisor tables ([`state`]).
//!
//! The library is `no_std`, allocates nothing and touches no hardware, so the exact code that ships also
//! runs on the host, where the virtual plant, property tests and benchmarks exercise it. The crate holds no
//! application and has no build script: the Cortex-M applications (the cell's in `apps/cell/`, a user's
//! project) depend on it and only wire it to interrupts and pins. With the host-only feature `build`, the
//! crate also builds the tables it reads ([`build`]).
#![cfg_attr(not(test), no_std)]
#![deny(missing_docs)]

#[cfg(feature = "build")]
extern crate alloc;

pub mod board;
#[cfg(feature = "build")]
pub mod build;
pub mod choice;
pub mod event_loop;
pub mod event_set;
pub mod fault;
pub mod input_queue;
pub mod link;
pub mod rng;
pub mod runtime;
pub mod shell;
pub mod state;
pub mod status;
pub mod table;
pub mod timer;
