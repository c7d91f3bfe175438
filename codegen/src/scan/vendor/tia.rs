//! Siemens TIA Portal (S7-1200/1500): the program as external sources to import (Project tree →
//! External source files → Add new external file, then Generate blocks from source) — `<base>.udt`
//! (the structure types), `<base>.scl` (a `FUNCTION_BLOCK` per POU, the `PROGRAM` one too, and the
//! `ORGANIZATION_BLOCK` calling it), `<base>.db` (the `PROGRAM`'s instance `DATA_BLOCK`) — and the
//! located I/O as a PLC tag table, `<base>_tags.csv`, in the columns of TIA's tag export.
//!
//! Dialect (SCL): a block's own variables are written `#name`, a PLC tag (the I/O) `"name"`, block and
//! type names `"name"`; `TON` instances are `IEC_TIMER` (called and read as in IEC ST); the elementary
//! types take SCL's spelling. The statements are the generic ones, printed by the same printer with
//! those names ([`crate::scan::Pou::body_with`]).

use std::fmt::Write as _;

use super::split_io;
use crate::scan::files::{File, Source};
use crate::scan::ir::{Pou, Type, Var, VarClass};
use crate::scan::st::safe_comment;

/// A type as SCL declares it.
fn data_type(ty: &Type) -> String {
    match ty {
        Type::Bool => "Bool".into(),
        Type::Int => "Int".into(),
        Type::Dint => "DInt".into(),
        Type::Udint => "UDInt".into(),
        Type::Time => "Time".into(),
        Type::Array(upper, of) => format!("Array[0..{upper}] of {}", data_type(of)),
        Type::Named(n) if n == "TON" => "IEC_TIMER".into(),
        Type::Named(n) => format!("\"{n}\""),
    }
}

/// A declaration line at `pad`.
fn declaration(v: &Var, pad: &str) -> String {
    let init = v.init.as_ref().map(|e| format!(" := {}", e.text())).unwrap_or_default();
    let comment = if v.comment.is_empty() { String::new() } else { format!("   // {}", v.comment) };
    format!("{pad}{} : {}{init};{comment}\n", v.name, data_type(&v.ty))
}

/// The source's header as a comment block.
fn comment(header: &[String]) -> String {
    let mut out = String::from("(*\n");
    for l in header {
        let _ = writeln!(out, "   {}", safe_comment(l));
    }
    out.push_str("*)\n");
    out
}

/// `pou` (its located variables taken out) as an SCL `FUNCTION_BLOCK`: its variables `#`, the rest
/// (the PLC tags) `"…"`.
fn block(pou: &Pou) -> String {
    let mut out =
        format!("FUNCTION_BLOCK \"{}\"\n{{ S7_Optimized_Access := 'TRUE' }}\nVERSION : 0.1\n", pou.name);
    for (class, vars) in pou.blocks() {
        let kw = match class {
            VarClass::Input => "VAR_INPUT",
            VarClass::Output => "VAR_OUTPUT",
            VarClass::Local => "VAR",
        };
        let _ = writeln!(out, "   {kw}");
        for v in vars {
            out.push_str(&declaration(v, "      "));
        }
        out.push_str("   END_VAR\n");
    }
    let names = |n: &str| if pou.var(n).is_some() { format!("#{n}") } else { format!("\"{n}\"") };
    let _ = write!(out, "\nBEGIN\n{}END_FUNCTION_BLOCK\n\n", pou.body_with(&names));
    out
}

/// SCL text with the dialect's name marks taken off — every `"` and each `#` that starts a name (not
/// the `#` of a literal such as `T#20ms`): the generic ST text of the same statements. What shows a
/// block's body is the generic program.
pub fn unmarked(scl: &str) -> String {
    let mut out = String::with_capacity(scl.len());
    let mut prev = ' ';
    for c in scl.chars() {
        let mark = c == '"' || (c == '#' && !prev.is_ascii_alphanumeric());
        if !mark {
            out.push(c);
        }
        prev = c;
    }
    out
}

/// A located address in TIA's form: `%IX0.2` → `%I0.2`, `%QX1.0` → `%Q1.0`.
pub fn address(generic: &str) -> String {
    generic.replacen("X", "", 1)
}

/// The TIA Portal sources of `source`.
pub fn files(source: &Source) -> Vec<File> {
    let header = comment(&source.header.lines());
    let program = &source.program;
    let base = &program.base;
    let mut out = Vec::new();
    if !program.types.is_empty() {
        let mut udt = header.clone();
        for (name, members) in &program.types {
            let _ = write!(udt, "TYPE \"{name}\"\nVERSION : 0.1\n   STRUCT\n");
            for m in members {
                udt.push_str(&declaration(m, "      "));
            }
            udt.push_str("   END_STRUCT;\nEND_TYPE\n\n");
        }
        out.push((format!("{base}.udt"), udt));
    }
    let mut scl = header.clone();
    let mut io = Vec::new();
    for (p, _) in &program.pous {
        let (p, located) = split_io(p);
        io.extend(located);
        scl.push_str(&block(&p));
    }
    let main = format!("{base}_main");
    let _ = write!(
        scl,
        "ORGANIZATION_BLOCK \"{base}_task\"\nTITLE = '{base}: every {} ms (a Cyclic interrupt OB)'\n{{ S7_Optimized_Access := 'TRUE' }}\nVERSION : 0.1\n\nBEGIN\n\"{main}_DB\"();\nEND_ORGANIZATION_BLOCK\n",
        program.cycle_ms
    );
    out.push((format!("{base}.scl"), scl));
    let db = format!(
        "{header}DATA_BLOCK \"{main}_DB\"\n{{ S7_Optimized_Access := 'TRUE' }}\nVERSION : 0.1\nNON_RETAIN\n\"{main}\"\n\nBEGIN\n\nEND_DATA_BLOCK\n"
    );
    out.push((format!("{base}.db"), db));
    if !io.is_empty() {
        let mut tags = String::from("Name;Path;Data Type;Logical Address;Comment\n");
        for v in &io {
            let at = address(v.address.as_deref().unwrap_or_default());
            let _ = writeln!(
                tags,
                "{};{base}_io;{};{at};{}",
                v.name,
                data_type(&v.ty),
                v.comment.replace(';', ",")
            );
        }
        out.push((format!("{base}_tags.csv"), tags));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scan::ir::{Expr, Section, Stmt};

    #[test]
    fn locals_are_hashed_tags_quoted_and_timers_iec_timer() {
        let mut x = Var::new("x", Type::Bool, "");
        x.address = Some("%IX0.2".into());
        let pou = Pou {
            program: true,
            name: "p_main".into(),
            vars: vec![(
                VarClass::Local,
                vec![Var::new("t", Type::Named("TON".into()), ""), Var::new("y", Type::Bool, ""), x],
            )],
            sections: vec![Section::new(
                "run",
                "",
                vec![
                    Stmt::Call(
                        "t".into(),
                        vec![("IN".into(), Expr::var("x")), ("PT".into(), Expr::Time(20))],
                    ),
                    Stmt::set("y", Expr::var("t.Q").op(crate::scan::Op::And, Expr::var("x"))),
                ],
            )],
        };
        let (rest, io) = split_io(&pou);
        let text = block(&rest);
        assert!(text.contains("      t : IEC_TIMER;\n"), "{text}");
        assert!(text.contains("#t(IN := \"x\", PT := T#20ms);\n#y := #t.Q AND \"x\";\n"), "{text}");
        assert_eq!(address(io[0].address.as_deref().unwrap()), "%I0.2");
        // The same statements as the generic body, the dialect's marks taken off.
        let body = text.split("BEGIN\n").nth(1).unwrap().trim_end_matches("END_FUNCTION_BLOCK\n\n");
        assert_eq!(unmarked(body), pou.body());
    }
}
