//! Vendor projects (`codegen plc --vendor`): every example with a `[plc]` section, in each form it
//! takes (event-based int, bits and AEEM; state-based; the sequence beside the interlocks; the hybrid
//! controller), written for every vendor; each file checked by a tool of its own (blark parses every
//! TwinCAT file, the PLCopen TC6 2.01 schema validates every CODESYS file; no independent parser reads
//! TIA's SCL), and each shown to hold the generic program — the one `codegen run --target plc` scans.

use std::path::{Path, PathBuf};
use std::process::Command;

use codegen::config::ScanPolicy;
use codegen::plc::state_based::{Engine, StateOptions};
use codegen::plc::{Avalanche, Encoding, Form, Written};
use codegen::project::Project;
use codegen::scan::vendor::Vendor;
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
    let cases: Vec<(&str, Vec<(&str, Form)>)> = vec![
        ("cell/cell.toml", vec![("int", int()), ("bits", bits()), ("aeem", aeem())]),
        ("cell/cell-state.toml", vec![("state", state)]),
        ("factory/factory.toml", vec![("int", int()), ("bits", bits())]),
        ("station-rtpn/net1.toml", vec![("sequence", int())]),
        ("hybrid/hybrid.toml", vec![("hybrid", Form::Hybrid)]),
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

#[test]
fn every_plc_example_is_written_for_every_vendor_checked_and_the_generic_program() {
    let scratch = Scratch::new("vendor");
    let (mut twincat, mut codesys) = (Vec::new(), Vec::new());
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
}
