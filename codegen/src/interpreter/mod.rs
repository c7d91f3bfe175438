//! Structured Text read back and run: a parser of the subset `codegen plc` writes ([`parse`](mod@parse)),
//! the static type check a strict compiler makes ([`check`]) and a scan-cycle interpreter ([`run`]) —
//! what `codegen run --target plc` scans against the virtual plant, and what the tests run every
//! program form on. Strict as matiec and IronPLC are (IEC 61131-3 Ed. 3: no keyword as a name, no `__`
//! nor trailing `_` in a name, located variables only in a `PROGRAM`'s own `VAR` block and bound once,
//! `END_STRUCT;`, no implicit narrowing or sign change, `BOOL` never an integer, no write to a block's own
//! input nor into an instance from outside, an instance showing only its inputs and outputs, `CASE`
//! selectors and `FOR` bounds integers, the grammar's semicolons), so a program a strict compiler would
//! refuse is refused here before it runs. No ST runtime installs from the registries (no matiec, Beremiz
//! or OpenPLC package; RuSTy needs LLVM 21), so the product carries its own, written from the standard's
//! grammar. It reads the emitted text, never the program IR it was printed from (`crate::scan`), so a
//! printer's mistake shows here; blark, an independent parser, reads the same files in the tests.

pub mod check;
pub mod parse;
pub mod run;

pub use parse::{parse, sections, Stmt, Unit};
pub use run::{Plc, Value};
