//! Beckhoff TwinCAT 3: the program as PLC project files — a `.TcPOU` per POU (its declaration and ST
//! implementation), a `.TcDUT` per structure type, a `.TcGVL` declaring the located I/O as `AT %I*` /
//! `AT %Q*` (linked to the terminals in the I/O tree, the generic address kept in a comment), and a
//! `.TcTTO` task calling the `PROGRAM` every cycle.
//!
//! Dialect: TwinCAT reads IEC 61131-3 ST as the generic file writes it; a located variable in a
//! `PROGRAM` is left to the global list so that the mapping is made in the I/O tree, not by fixed
//! addresses. The list is not `qualified_only`, so the bodies read the I/O by the same names. Graphical
//! bodies (LD, SFC) are not written: TwinCAT stores them as an undocumented archive of its editor's
//! objects (`<NWL><XmlArchive>`) that no tool outside TwinCAT checks, and the ST body is the program
//! the generic files run; TwinCAT's PLCopen XML import reads the `<LD>` bodies of the CODESYS file.

use std::fmt::Write as _;

use super::{cdata, guid, is_input, split_io};
use crate::scan::files::{File, Source};
use crate::scan::ir::{Pou, Var};

/// The `TcPlcObject` version attributes of TwinCAT 3.1 build 4024 files.
const OBJECT: &str = "<TcPlcObject Version=\"1.1.0.1\" ProductVersion=\"3.1.4024.0\">";

/// A TwinCAT file: the XML declaration, the header as an XML comment, `body` in a `TcPlcObject`.
fn object(header: &[String], body: &str) -> String {
    let mut out = String::from("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!--\n");
    for l in header {
        let _ = writeln!(out, "  {}", l.replace("--", "- -"));
    }
    let _ = write!(out, "-->\n{OBJECT}\n{body}</TcPlcObject>\n");
    out
}

/// `pou` as a `.TcPOU`: declaration and ST implementation.
fn pou(header: &[String], pou: &Pou) -> File {
    let kw = if pou.program { "PROGRAM" } else { "FUNCTION_BLOCK" };
    let declaration = format!("{kw} {}\n{}", pou.name, pou.declarations());
    let body = format!(
        "  <POU Name=\"{name}\" Id=\"{{{id}}}\" SpecialFunc=\"None\">\n    <Declaration>{}</Declaration>\n    <Implementation>\n      <ST>{}</ST>\n    </Implementation>\n  </POU>\n",
        cdata(&declaration),
        cdata(&pou.body()),
        name = pou.name,
        id = guid(&format!("TcPOU {}", pou.name)),
    );
    (format!("{}.TcPOU", pou.name), object(header, &body))
}

/// A structure type as a `.TcDUT`.
fn dut(header: &[String], name: &str, members: &[Var]) -> File {
    let mut decl = format!("TYPE {name} :\nSTRUCT\n");
    for m in members {
        decl.push_str(&m.text());
    }
    decl.push_str("END_STRUCT\nEND_TYPE\n");
    let body = format!(
        "  <DUT Name=\"{name}\" Id=\"{{{}}}\">\n    <Declaration>{}</Declaration>\n  </DUT>\n",
        guid(&format!("TcDUT {name}")),
        cdata(&decl)
    );
    (format!("{name}.TcDUT"), object(header, &body))
}

/// The located variables as a `.TcGVL` named `name`: `AT %I*` for inputs, `AT %Q*` for outputs.
fn gvl(header: &[String], name: &str, io: &[Var]) -> File {
    let mut decl = String::from("VAR_GLOBAL\n");
    for v in io {
        let was = v.address.clone().unwrap_or_default();
        let mut linked = v.clone();
        linked.address = Some(if is_input(v) { "%I*" } else { "%Q*" }.into());
        linked.comment = if v.comment.is_empty() {
            format!("generic {was}")
        } else {
            format!("{}; generic {was}", v.comment)
        };
        decl.push_str(&linked.text());
    }
    decl.push_str("END_VAR\n");
    let body = format!(
        "  <GVL Name=\"{name}\" Id=\"{{{}}}\">\n    <Declaration>{}</Declaration>\n  </GVL>\n",
        guid(&format!("TcGVL {name}")),
        cdata(&decl)
    );
    (format!("{name}.TcGVL"), object(header, &body))
}

/// The cyclic task calling `<base>_main` every `cycle_ms`, as a `.TcTTO` (cycle time in µs).
fn task(header: &[String], base: &str, cycle_ms: u32) -> File {
    let name = format!("{base}_task");
    let body = format!(
        "  <Task Name=\"{name}\" Id=\"{{{}}}\">\n    <CycleTime>{}</CycleTime>\n    <Priority>20</Priority>\n    <PouCall>\n      <Name>{base}_main</Name>\n    </PouCall>\n  </Task>\n",
        guid(&format!("TcTTO {name}")),
        u64::from(cycle_ms) * 1000
    );
    (format!("{name}.TcTTO"), object(header, &body))
}

/// The TwinCAT files of `source`: its DUTs, POUs, the I/O list (when the program has located
/// variables) and the task.
pub fn files(source: &Source) -> Vec<File> {
    let header = source.header.lines();
    let program = &source.program;
    let mut out: Vec<File> = program.types.iter().map(|(n, m)| dut(&header, n, m)).collect();
    let mut io = Vec::new();
    for (p, _) in &program.pous {
        let (p, located) = split_io(p);
        io.extend(located);
        out.push(pou(&header, &p));
    }
    if !io.is_empty() {
        out.push(gvl(&header, &format!("{}_io", program.base), &io));
    }
    out.push(task(&header, &program.base, program.cycle_ms));
    out
}
