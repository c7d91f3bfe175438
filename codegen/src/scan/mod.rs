//! The scan-cycle program layer: one IR for every PLC program the writers build, its printers, the
//! standard's naming and strict rules, and the one assembler of a program's files. It knows IEC 61131-3
//! and PLCopen, not supervisors or nets: the forms of [`crate::plc`] build programs in it.
//!
//! | part | module |
//! |---|---|
//! | the IR: expressions, statements, typed declarations, POUs of labelled sections | [`ir`] |
//! | Ladder Diagram rungs: their ST statements, `<LD>` body and instruction-list cost | [`ld`] |
//! | Sequential Function Charts and their `<SFC>` body | [`sfc`] |
//! | a program: types, POUs with their graphical bodies, the task | [`program`] |
//! | the Structured Text printer | [`st`] |
//! | the PLCopen TC6 2.01 printer | [`xml`] |
//! | IEC identifiers for any model name | [`names`] |
//! | the Ed. 3 rules every program is held to before it is printed | [`strict`] |
//! | the three files under one header (provenance as data) | [`files`] |
//!
//! A vendor's project format (TwinCAT, TIA Portal, CODESYS, Studio 5000) is one more printer over
//! [`program::Program`]: the IR carries every type, so a printer never re-derives what the writer knew.
//! Output is deterministic: the same program gives the same bytes (the XML's creation time is fixed).

pub mod files;
pub mod ir;
pub mod ld;
pub mod names;
pub mod program;
pub mod sfc;
pub mod st;
pub mod strict;
pub mod vendor;
pub mod xml;

pub use files::{File, Header};
pub use ir::{Expr, Op, Pou, Section, Stmt, StructType, Type, Var, VarClass};
pub use program::{Graphic, Program};
