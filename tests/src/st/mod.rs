//! Structured Text for the tests: a parser of the subset `codegen plc` writes ([`parse`]) and a
//! scan-cycle interpreter of it ([`run`]). No ST runtime installs from the registries here (no matiec,
//! Beremiz or OpenPLC package; RuSTy needs LLVM 21), so the harness carries its own, written from the
//! standard's grammar; it reads the emitted text, never codegen's syntax tree.

pub mod parse;
pub mod run;

pub use parse::{parse, sections, Stmt, Unit};
pub use run::Plc;
