//! Vendor projects (`codegen plc --vendor`): every example with a `[plc]` section, in each form it
//! takes (event-based int, bits and AEEM; state-based; the sequence beside the interlocks; the hybrid
//! controller), written for every vendor; each file checked by a tool of its own (blark parses every
//! TwinCAT file, the PLCopen TC6 2.01 schema validates every CODESYS file, `tests/l5x_structure.py`
//! checks every Studio 5000 file's structure; no independent parser reads TIA's SCL), and each shown to
//! hold the generic program — the one `codegen run --target plc` scans.

use std::path::{Path, PathBuf};
use std::process::Command;

use codegen::config::ScanPolicy;
use codegen::plc::state_based::{Engine, StateOptions};
use codegen::plc::{Avalanche, Encoding, Form, Written};
use codegen::project::Project;
use codegen::scan::files::Source;
use codegen::scan::vendor::Vendor;
use codegen::scan::{Pou, Type};
use end_to_end::{example, root, Scratch};

/// Every example with a `[plc]` section (and the hybrid one) with the forms it is written in.
fn programs() -> Vec<(String, Written)> {
    let event = |encoding, avalanche| Form::Event { encoding, avalanche, policy: None };
    let state = Form::State {
        options: StateOptions { memory: false, exact: false, choice: None::<ScanPolicy> },
        engine: Engine::Explicit,
    };
    let int = || event(Encoding::Int, Avalanche::Auto);
    let bits = || event(Encoding::Bits, Avalanche::Auto);
    let aeem = || event(Encoding::Bits, Avalanche::Aeem);
    let memory = Form::State {
        options: StateOptions { memory: true, exact: false, choice: None::<ScanPolicy> },
        engine: Engine::Explicit,
    };
    let state_guards = state.clone();
    let cases: Vec<(&str, Vec<(&str, Form)>)> = vec![
        ("cell/cell.toml", vec![("int", int()), ("bits", bits()), ("aeem", aeem())]),
        ("cell/cell-state.toml", vec![("state", state.clone())]),
        ("distribution/distribution.toml", vec![("state", state)]),
        // A state-based program with memory, small (the cell's takes minutes to build).
        ("../codegen/tests/data/sfbc_memory/memory.toml", vec![("state-memory", memory)]),
        ("factory/factory.toml", vec![("int", int()), ("bits", bits())]),
        ("station/station.toml", vec![("int", int())]),
        ("station-rtpn/net1.toml", vec![("sequence", int())]),
        ("station-rtpn/net3.toml", vec![("sequence", int())]),
        ("hybrid/hybrid.toml", vec![("hybrid", Form::Hybrid)]),
        // A timer (TON) started inside an IF: Logix's TONR where it stands.
        ("cylinder/cylinder.toml", vec![("int", int())]),
        // Variables of a Supremica module as INTs, and guards over them in the rungs' conditions.
        ("efa/buffer.toml", vec![("int", int()), ("bits", bits())]),
        // The same state-based: the count an INT, the guards BOOL contacts on the rungs; one command
        // per scan by its `[state] choice` (ST only: the choice section is no ladder).
        ("efa/buffer-state.toml", vec![("choice", state_guards)]),
    ];
    let mut out = Vec::new();
    for (manifest, forms) in cases {
        let project = Project::load(&example(manifest)).unwrap_or_else(|e| panic!("{manifest}: {e}"));
        for (what, form) in forms {
            let written = project.plc(&form).unwrap_or_else(|e| panic!("{manifest} {what}: {e}"));
            out.push((format!("{manifest} {what}"), written));
        }
    }
    out
}

/// Writes `files` under `dir`, returning their paths.
fn write(dir: &Path, files: &[(String, String)]) -> Vec<PathBuf> {
    std::fs::create_dir_all(dir).unwrap();
    files
        .iter()
        .map(|(name, text)| {
            let path = dir.join(name);
            std::fs::write(&path, text).unwrap();
            path
        })
        .collect()
}

/// Runs `script` with the paths under `.venv`'s Python; panics with its output unless it exits 0.
fn python(script: &str, args: &[PathBuf]) {
    let venv = root().join(".venv");
    let out = Command::new(venv.join("bin/python")).arg("-c").arg(script).args(args).output().unwrap();
    assert!(
        out.status.success(),
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// blark (one process for every file: its grammar loads once) parses each file; any exception fails.
const BLARK: &str = "import sys\nimport blark.parse as p\nbad = []\nfor f in sys.argv[1:]:\n    for r in p.parse(f):\n        if r.exception is not None:\n            bad.append(f'{f}: {r.exception}')\nprint('\\n'.join(bad))\nsys.exit(1 if bad else 0)\n";

/// The largest `.TcPOU` blark parses here, in bytes.
const BLARK_BYTES: u64 = 16 * 1024;

/// The TC6 2.01 schema (`argv[1]`) validates each file after it.
const SCHEMA: &str = "import sys\nfrom lxml import etree\ns = etree.XMLSchema(etree.parse(sys.argv[1]))\nbad = [f for f in sys.argv[2:] if not s.validate(etree.parse(f))]\nprint(bad, s.error_log)\nsys.exit(1 if bad else 0)\n";

/// The text inside the first `<![CDATA[…]]>` after `tag` in `xml`.
fn cdata_after<'a>(xml: &'a str, tag: &str) -> &'a str {
    let from = xml.find(tag).unwrap_or_else(|| panic!("no {tag}"));
    let rest = &xml[from..];
    let start = rest.find("<![CDATA[").unwrap() + "<![CDATA[".len();
    let end = rest[start..].find("]]>").unwrap();
    &rest[start..start + end]
}

/// `xml` without its `<addData>…</addData>` elements (and the line breaks and indentation before them).
fn without_add_data(xml: &str) -> String {
    let mut out = String::new();
    let mut rest = xml;
    while let Some(i) = rest.find("<addData>") {
        out.push_str(rest[..i].trim_end_matches([' ', '\n']));
        let end = rest[i..].find("</addData>").unwrap() + i + "</addData>".len();
        rest = &rest[end..];
    }
    out.push_str(rest);
    out
}

/// The TwinCAT files of one program hold the generic `.st`'s program: each `.TcPOU`'s body is the
/// generic POU's body, its declaration lines the generic POU's, and each I/O variable of the `.TcGVL`
/// the generic located declaration with its address.
fn twincat_holds(what: &str, files: &[(String, String)], st: &str) {
    for (name, text) in files.iter().filter(|(n, _)| n.ends_with(".TcPOU")) {
        let declaration = cdata_after(text, "<Declaration>");
        let body = cdata_after(text, "<Implementation>");
        let first = declaration.lines().next().unwrap();
        let generic =
            &st[st.find(&format!("{first}\n")).unwrap_or_else(|| panic!("{what} {name}: {first}"))..];
        let kw = first.split_once(' ').unwrap().0;
        let end = generic.find(&format!("\nEND_{kw}\n")).unwrap() + 1;
        let generic = &generic[..end];
        assert!(generic.ends_with(body), "{what} {name}: the body is not the generic one");
        for line in declaration.lines() {
            assert!(generic.contains(line), "{what} {name}: {line}");
        }
    }
    for (name, text) in files.iter().filter(|(n, _)| n.ends_with(".TcGVL")) {
        for line in cdata_after(text, "<Declaration>").lines().filter(|l| l.contains(" AT ")) {
            let (var, rest) = line.split_once(" AT ").unwrap();
            let ty = rest.split_once(" : ").unwrap().1.split_once(';').unwrap().0;
            let addr = line.rsplit_once("generic ").unwrap().1.trim_end_matches(" *)");
            let generic = format!("{var} AT {addr} : {ty};");
            assert!(st.contains(&generic), "{what} {name}: {generic}");
        }
    }
}

/// Each SCL block of one program holds the generic POU's statements: its body with the dialect's
/// marks (`#local`, `"tag"`) taken off is the generic body byte for byte.
fn tia_holds(what: &str, scl: &str, source: &codegen::scan::files::Source) {
    for (pou, _) in &source.program.pous {
        let from =
            scl.find(&format!("FUNCTION_BLOCK \"{}\"\n", pou.name)).unwrap_or_else(|| panic!("{what}"));
        let block = &scl[from..];
        let body = &block
            [block.find("BEGIN\n").unwrap() + "BEGIN\n".len()..block.find("END_FUNCTION_BLOCK").unwrap()];
        assert_eq!(codegen::scan::vendor::tia::unmarked(body), pou.body(), "{what} {}", pou.name);
    }
}

/// The CDATA texts of the elements `tag` in the first `<within>…</within>` after `from` in `xml`.
fn cdata_lines(xml: &str, from: &str, within: &str, tag: &str) -> Vec<String> {
    let start = xml.find(from).unwrap_or_else(|| panic!("no {from}"));
    let rest = &xml[start..];
    let open = rest.find(&format!("<{within}>")).unwrap_or_else(|| panic!("no {within} after {from}"));
    let close = rest.find(&format!("</{within}>")).unwrap();
    let mut out = Vec::new();
    let mut part = &rest[open..close];
    while let Some(i) = part.find(&format!("<{tag}")) {
        part = &part[i..];
        let s = part.find("<![CDATA[").unwrap() + "<![CDATA[".len();
        let e = part[s..].find("]]>").unwrap() + s;
        out.push(part[s..e].to_owned());
        part = &part[e..];
    }
    out
}

/// `text` with each identifier replaced by `f(previous identifier before a '.', identifier)`.
fn map_identifiers(text: &str, f: &dyn Fn(Option<&str>, &str) -> String) -> String {
    let mut out = String::new();
    let chars: Vec<char> = text.chars().collect();
    let (mut i, mut last): (usize, Option<String>) = (0, None);
    while i < chars.len() {
        let c = chars[i];
        if c.is_ascii_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            let word: String = chars[start..i].iter().collect();
            let owner = if start > 0 && chars[start - 1] == '.' { last.as_deref() } else { None };
            out.push_str(&f(owner, &word));
            last = Some(word);
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// `text` without conversion calls: `INT_TO_DINT(e)` is `e`.
fn without_conversions(text: &str) -> String {
    let mut s = text.to_owned();
    while let Some(at) = s.find("_TO_") {
        let start = s[..at].rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).map_or(0, |i| i + 1);
        let open = at + s[at..].find('(').unwrap();
        let mut depth = 0;
        let close = open
            + s[open..]
                .char_indices()
                .find(|&(_, c)| {
                    depth += match c {
                        '(' => 1,
                        ')' => -1,
                        _ => 0,
                    };
                    depth == 0
                })
                .unwrap()
                .0;
        s = format!("{}{}{}", &s[..start], &s[open + 1..close], &s[close + 1..]);
    }
    s
}

/// A generic ST line as Logix ST writes it, by the rewrites docs/plc.md lists (`TRUE`/`FALSE` as
/// 1/0, conversions dropped, a timer's `Q` read as `DN`, a timer or block call expanded): written here
/// from the text, independently of the writer.
fn logix_lines(line: &str, pou: &Pou, blocks: &[&Pou]) -> Vec<String> {
    if line.starts_with("(*") {
        return vec![line.to_owned()];
    }
    let ty = |name: &str| pou.var(name).map(|(_, v)| v.ty.clone());
    let timer = |name: &str| ty(name) == Some(Type::Named("TON".into()));
    let rewrite = |text: &str| {
        map_identifiers(&without_conversions(text), &|owner, w| match (owner, w) {
            (None, "TRUE") => "1".into(),
            (None, "FALSE") => "0".into(),
            (Some(o), "Q") if timer(o) => "DN".into(),
            _ => w.to_owned(),
        })
    };
    // A call may stand inside an IF (a timer started there): its lines keep the call's indentation.
    let code = line.trim_start();
    let pad = &line[..line.len() - code.len()];
    let call = code.split_once('(').filter(|(head, _)| {
        code.ends_with(");") && head.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
    });
    let Some((inst, args)) = call.filter(|(inst, _)| ty(inst).is_some_and(|t| matches!(t, Type::Named(_))))
    else {
        return vec![rewrite(line)];
    };
    let mut parts: Vec<String> = Vec::new();
    for piece in args.trim_end_matches(");").split(", ") {
        match parts.last_mut() {
            Some(last) if !piece.contains(" := ") => *last = format!("{last}, {piece}"),
            _ => parts.push(piece.to_owned()),
        }
    }
    let mut out = Vec::new();
    if timer(inst) {
        for p in &parts {
            let (name, e) = p.split_once(" := ").unwrap();
            let (member, value) = match name {
                "IN" => ("TimerEnable", rewrite(e)),
                _ => ("PRE", e.trim_start_matches("T#").trim_end_matches("ms").to_owned()),
            };
            out.push(format!("{pad}{inst}.{member} := {value};"));
        }
        out.push(format!("{pad}TONR({inst});"));
        return out;
    }
    let Some(Type::Named(block)) = ty(inst) else { unreachable!() };
    let block = blocks.iter().find(|b| b.name == block).unwrap();
    let mut positional = vec![inst.to_owned()];
    for p in &parts {
        let (name, e) = p.split_once(" := ").unwrap();
        match block.var(name).map(|(_, v)| &v.ty) {
            Some(Type::Named(_) | Type::Array(..)) => positional.push(rewrite(e)),
            _ => out.push(format!("{pad}{inst}.{name} := {};", rewrite(e))),
        }
    }
    out.push(format!("{pad}{}({});", block.name, positional.join(", ")));
    out
}

/// A rung condition read back: a contact's ST, or elements in series (AND) or in parallel (OR).
enum Condition {
    Contact(String),
    Series(Vec<Condition>),
    Parallel(Vec<Condition>),
}

impl Condition {
    /// The ST text as the generic printer writes it: an OR inside an AND parenthesised.
    fn st(&self) -> String {
        match self {
            Condition::Contact(c) => c.clone(),
            Condition::Series(es) if es.len() == 1 => es[0].st(),
            Condition::Parallel(es) if es.len() == 1 => es[0].st(),
            Condition::Series(es) => es
                .iter()
                .map(|e| match e {
                    Condition::Parallel(b) if b.len() > 1 => format!("({})", e.st()),
                    _ => e.st(),
                })
                .collect::<Vec<_>>()
                .join(" AND "),
            Condition::Parallel(es) => es.iter().map(Condition::st).collect::<Vec<_>>().join(" OR "),
        }
    }
}

/// Reads rung text from `at`: instructions and `[… ,… ]` branches in series up to a `,`, a `]` or the
/// end; contacts into the condition, the other instructions (the coils) into `coils`.
fn read_series(
    t: &str,
    at: &mut usize,
    coils: &mut Vec<(String, String)>,
    read: &dyn Fn(&str) -> String,
) -> Condition {
    let mut series = Vec::new();
    while *at < t.len() {
        let rest = &t[*at..];
        if rest.starts_with(',') || rest.starts_with(']') || rest.starts_with(';') {
            break;
        }
        if rest.starts_with('[') {
            *at += 1;
            let mut branches = vec![read_series(t, at, coils, read)];
            while t[*at..].starts_with(',') {
                *at += 1;
                branches.push(read_series(t, at, coils, read));
            }
            assert!(t[*at..].starts_with(']'), "{t}");
            *at += 1;
            series.push(Condition::Parallel(branches));
            continue;
        }
        let close = rest.find(')').unwrap();
        let (op, arg) = rest[..close].split_once('(').unwrap();
        *at += close + 1;
        while t[*at..].starts_with(' ') {
            *at += 1;
        }
        match op {
            "XIC" => series.push(Condition::Contact(read(arg))),
            "XIO" => series.push(Condition::Contact(format!("NOT {}", read(arg)))),
            _ => coils.push((op.to_owned(), arg.to_owned())),
        }
    }
    Condition::Series(series)
}

/// A ladder rung's text as the ST statements its rung stands for (a coil after the condition: `OTE`
/// an assignment, `TON` the timer's call, `OTL`/`OTU` a set/reset under `IF`).
fn rung_statements(text: &str, pou: &Pou) -> Vec<String> {
    let timer = |name: &str| pou.var(name).is_some_and(|(_, v)| v.ty == Type::Named("TON".into()));
    let operand = |a: &str| match a.split_once('.') {
        Some((t, "DN")) if timer(t) => format!("{t}.Q"),
        _ => a.to_owned(),
    };
    let mut coils = Vec::new();
    let mut at = 0;
    let cond = read_series(text, &mut at, &mut coils, &operand);
    assert_eq!(&text[at..], ";", "{text}");
    let empty = matches!(&cond, Condition::Series(es) if es.is_empty());
    let cond = cond.st();
    let mut out = Vec::new();
    let mut latched = Vec::new();
    for (op, arg) in coils {
        match op.as_str() {
            "OTL" => latched.push(format!("{arg} := TRUE;")),
            "OTU" => latched.push(format!("{arg} := FALSE;")),
            "OTE" => out.push(format!("{arg} := {cond};")),
            "TON" => {
                let args: Vec<&str> = arg.split(',').collect();
                out.push(format!("{}(IN := {cond}, PT := T#{}ms);", args[0], args[1]));
            }
            other => panic!("rung instruction {other}"),
        }
    }
    if empty {
        out.extend(latched);
    } else if !latched.is_empty() {
        out.push(format!("IF {cond} THEN"));
        out.extend(latched.iter().map(|l| format!("    {l}")));
        out.push("END_IF;".into());
    }
    out
}

/// The routine `name` in `program` (a `<Program>` element's text): its type and its ST lines or its
/// rungs' texts.
fn routine(program: &str, name: &str) -> (String, Vec<String>) {
    let from = format!("<Routine Name=\"{name}\" Type=\"");
    let at = program.find(&from).unwrap_or_else(|| panic!("no routine {name}"));
    let kind = program[at + from.len()..].split('"').next().unwrap().to_owned();
    let lines = match kind.as_str() {
        "RLL" => cdata_lines(program, &from, "RLLContent", "Text"),
        _ => cdata_lines(program, &from, "STContent", "Line"),
    };
    (kind, lines)
}

/// The Logix ST lines (section markers left out) that the routine `name` of `program` runs: an ST
/// routine's lines; a ladder routine's rungs read back as ST (then rewritten as Logix ST), a rung
/// ending in `JSR(r,0)` with the lines `r` runs inside its `IF` after its coils, a rung that is a
/// `JSR` alone the lines `r` runs.
fn routine_st(program: &str, name: &str, pou: &Pou) -> Vec<String> {
    let (kind, lines) = routine(program, name);
    if kind == "ST" {
        return lines.into_iter().filter(|l| !l.starts_with("(*")).collect();
    }
    let logix =
        |st: Vec<String>| -> Vec<String> { st.iter().flat_map(|l| logix_lines(l, pou, &[])).collect() };
    let mut out = Vec::new();
    for text in lines {
        let Some((head, callee)) = text.strip_suffix(",0);").and_then(|t| t.rsplit_once("JSR(")) else {
            out.extend(logix(rung_statements(&text, pou)));
            continue;
        };
        let called = routine_st(program, callee, pou);
        if head.is_empty() {
            out.extend(called);
            continue;
        }
        let mut st = logix(rung_statements(&format!("{head};"), pou));
        assert_eq!(st.pop().as_deref(), Some("END_IF;"), "{text}");
        st.extend(called.iter().map(|l| format!("    {l}")));
        st.push("END_IF;".into());
        out.extend(st);
    }
    out
}

/// The Studio 5000 file of one program holds the generic program: each Add-On Instruction's `Logic`
/// routine and each ST program routine is the generic POU's body line for line after the dialect's
/// rewrites; a ladder routine's rungs, read back as ST, are the generic body's statements, with the
/// ST routines they call by `JSR` in their place.
fn rockwell_holds(what: &str, l5x: &str, source: &Source) {
    let blocks: Vec<&Pou> = source.program.pous.iter().map(|(p, _)| p).filter(|p| !p.program).collect();
    for (pou, _) in &source.program.pous {
        let generic = pou.body();
        if pou.program {
            let from = format!("<Program Name=\"{}\"", pou.name);
            let program = &l5x[l5x.find(&from).unwrap()..];
            let program = &program[..program.find("</Program>").unwrap()];
            if routine(program, "MainRoutine").0 == "RLL" {
                let st = routine_st(program, "MainRoutine", pou);
                let generic: Vec<String> = generic
                    .lines()
                    .filter(|l| !l.starts_with("(*"))
                    .flat_map(|l| logix_lines(l, pou, &blocks))
                    .collect();
                assert_eq!(st, generic, "{what} {}: the routines are not the generic body", pou.name);
                continue;
            }
            let lines = cdata_lines(l5x, &from, "STContent", "Line");
            let expected: Vec<String> = generic.lines().flat_map(|l| logix_lines(l, pou, &blocks)).collect();
            assert_eq!(lines, expected, "{what} {}", pou.name);
        } else {
            let from = format!("<AddOnInstructionDefinition Name=\"{}\"", pou.name);
            let lines = cdata_lines(l5x, &from, "STContent", "Line");
            let expected: Vec<String> = generic.lines().flat_map(|l| logix_lines(l, pou, &blocks)).collect();
            assert_eq!(lines, expected, "{what} {}", pou.name);
        }
    }
}

/// Runs the L5X structure check (`tests/l5x_structure.py`) on `files`; whether it passed, and its output.
fn l5x_structure(files: &[PathBuf]) -> (bool, String) {
    let out = Command::new(root().join(".venv/bin/python"))
        .arg(root().join("tests/l5x_structure.py"))
        .args(files)
        .output()
        .unwrap();
    (
        out.status.success(),
        format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr)),
    )
}

#[test]
fn every_plc_example_is_written_for_every_vendor_checked_and_the_generic_program() {
    let scratch = Scratch::new("vendor");
    let (mut twincat, mut codesys, mut rockwell) = (Vec::new(), Vec::new(), Vec::new());
    for (i, (what, written)) in programs().iter().enumerate() {
        let generic = written.files();
        // The generic files are the sources' files: what a vendor prints is what `codegen plc` wrote.
        let again: Vec<_> = written.sources().iter().flat_map(|s| s.files().unwrap()).collect();
        assert_eq!(again, generic, "{what}");
        for (j, source) in written.sources().iter().enumerate() {
            let (st, xml) = (&generic[3 * j].1, &generic[3 * j + 2].1);
            let one = std::slice::from_ref(source);

            let files = Vendor::Twincat.files(one).unwrap();
            assert!(files.iter().any(|(n, _)| n.ends_with(".TcPOU")), "{what}");
            twincat_holds(what, &files, st);
            let paths = write(&scratch.path().join(format!("{i}-{j}-twincat")), &files);
            twincat.extend(paths.into_iter().filter(|p| p.extension().is_some_and(|e| e != "TcTTO")));

            let files = Vendor::Codesys.files(one).unwrap();
            assert_eq!(files.len(), 1, "{what}");
            assert_eq!(without_add_data(&files[0].1), *xml, "{what}: CODESYS' file is the generic XML");
            codesys.extend(write(&scratch.path().join(format!("{i}-{j}-codesys")), &files));

            let files = Vendor::Tia.files(one).unwrap();
            let scl = &files.iter().find(|(n, _)| n.ends_with(".scl")).unwrap_or_else(|| panic!("{what}")).1;
            tia_holds(what, scl, source);

            let files = Vendor::Rockwell.files(one).unwrap();
            assert_eq!(files.len(), 1, "{what}");
            assert!(files[0].0.ends_with(".L5X"), "{what}");
            assert!(files[0].1.contains("\n<RSLogix5000Content "), "{what}");
            rockwell_holds(what, &files[0].1, source);
            if what.contains(" state") {
                // The state-based programs are ladder: the whole body, or its rungs beside the ST.
                assert!(files[0].1.contains("Type=\"RLL\""), "{what}");
            }
            rockwell.extend(write(&scratch.path().join(format!("{i}-{j}-rockwell")), &files));
        }
    }
    // blark on every declaration file, and on each POU file small enough for its parser (minutes on
    // the cell's 100 kB bodies): a larger body is the generic `.st`'s byte for byte (`twincat_holds`),
    // which `plc::` parses with blark already; what a POU file adds — its XML wrapper and declarations —
    // is the same in the small ones.
    let small =
        |p: &PathBuf| p.extension().unwrap() != "TcPOU" || std::fs::metadata(p).unwrap().len() < BLARK_BYTES;
    let parsed: Vec<PathBuf> = twincat.iter().filter(|p| small(p)).cloned().collect();
    assert!(parsed.iter().any(|p| p.extension().unwrap() == "TcPOU"), "no POU file small enough for blark");
    python(BLARK, &parsed);
    let xsd = root().join(".venv/plcopen/tc6_xml_v201.xsd");
    python(SCHEMA, &[vec![xsd], codesys].concat());
    // The checks can fail: a broken POU is refused by blark.
    let bad = scratch.path().join("bad.TcPOU");
    let good =
        std::fs::read_to_string(twincat.iter().find(|p| p.extension().unwrap() == "TcPOU").unwrap()).unwrap();
    std::fs::write(&bad, good.replacen(":=", ":= :=", 1)).unwrap();
    let out = Command::new(root().join(".venv/bin/python")).arg("-c").arg(BLARK).arg(&bad).output().unwrap();
    assert!(!out.status.success(), "blark accepts a broken POU");
    // Every Studio 5000 file passes the structure check, which refuses a file with an undeclared tag
    // read, a Logix-invalid name or an ST line outside CDATA.
    let (ok, out) = l5x_structure(&rockwell);
    assert!(ok, "{out}");
    let good = std::fs::read_to_string(&rockwell[0]).unwrap();
    let breaks = [
        ("<Tag Name=\"sct\"", "<Tag Name=\"sct_gone\""),
        ("<Tag Name=\"sct\"", "<Tag Name=\"sct_\""),
        (
            "<Line Number=\"0\"><![CDATA[(* section: run - the function block, then its outputs *)]]>",
            "<Line Number=\"0\">(* section: run - the function block, then its outputs *)",
        ),
    ];
    let calling =
        rockwell.iter().map(|p| std::fs::read_to_string(p).unwrap()).find(|t| t.contains("JSR(")).unwrap();
    let jsr_breaks = [
        ("JSR(events,0);", "JSR(events_gone,0);"),
        ("JSR(events,0);", "JSR(MainRoutine,0);"),
        ("<Routine Name=\"events\" Type=\"ST\">", "<Routine Name=\"events\" Type=\"FBD\">"),
        ("JSR(events,0);", "XIC(conveyor)OTE(conveyor);"),
    ];
    for (text, (from, to)) in
        breaks.iter().map(|b| (&good, b)).chain(jsr_breaks.iter().map(|b| (&calling, b)))
    {
        assert!(text.contains(from), "{from}");
        let bad = scratch.path().join("bad.L5X");
        std::fs::write(&bad, text.replacen(from, to, 1)).unwrap();
        let (ok, out) = l5x_structure(&[bad]);
        assert!(!ok && !out.is_empty(), "the L5X check accepts {to}");
    }
}
