//! Structured Text for the tests: a parser of the subset `codegen plc` writes ([`parse`](mod@parse)), the static
//! type check a strict compiler makes ([`check`]) and a scan-cycle interpreter ([`run`]). Strict as
//! matiec and IronPLC are (IEC 61131-3 Ed. 3: no keyword as a name, located variables only in a
//! `PROGRAM`'s own `VAR` block and bound once, no implicit narrowing, the grammar's semicolons), so a
//! program a strict compiler would refuse fails the tests. No ST runtime installs from the registries here (no matiec,
//! Beremiz or OpenPLC package; RuSTy needs LLVM 21), so the harness carries its own, written from the
//! standard's grammar; it reads the emitted text, never codegen's syntax tree.

pub mod check;
pub mod parse;
pub mod run;

pub use parse::{parse, sections, Stmt, Unit};
pub use run::Plc;
