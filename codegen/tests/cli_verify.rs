//! `codegen verify` on the distribution station of Mušič & Matko (2005): the three nets give the paper's
//! three verdicts, with the traces, blocking places and diagnoses it reports; bad input exits 2.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn codegen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_codegen")).args(args).output().expect("run codegen")
}

fn station(file: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/station-rtpn").join(file).display().to_string()
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_verify");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// `verify --json` on a net: exit code and the report.
fn verify(net: &str) -> (i32, Value) {
    let out = codegen(&["verify", &station(net), "--json"]);
    assert!(out.stderr.is_empty(), "{}", String::from_utf8_lossy(&out.stderr));
    (out.status.code().unwrap(), serde_json::from_slice(&out.stdout).unwrap())
}

fn strings(v: &Value) -> Vec<&str> {
    v.as_array().unwrap().iter().map(|s| s.as_str().unwrap()).collect()
}

#[test]
fn net_1_blocks_once_p7_is_marked_because_the_piston_interlock_disables_arm_left() {
    let (code, r) = verify("net1.toml");
    assert_eq!(code, 1);
    assert_eq!(r["verdict"], "blocking");
    assert_eq!(
        strings(&r["trace"]),
        ["t1", "al1", "t2", "al0", "t5", "ar1", "sl0", "sr1", "t7", "af1", "sb0", "sf1", "ar0", "t8"]
    );
    assert_eq!(strings(&r["marking"]), ["p7"]);
    let refused = &r["refused"][0];
    assert_eq!((refused["place"].as_str(), refused["event"].as_str()), (Some("p7"), Some("al1")));
    assert_eq!(strings(&refused["refused_by"]), ["S_arm_left_piston_in"]);
    assert_eq!((r["nodes"].as_u64(), r["edges"].as_u64()), (Some(95), Some(182)));
}

#[test]
fn net_2_blocks_when_p6_is_entered_through_t18_and_t13() {
    let (code, r) = verify("net2.toml");
    assert_eq!(code, 1);
    assert_eq!(r["verdict"], "blocking");
    let trace = strings(&r["trace"]);
    assert_eq!(trace.last(), Some(&"t13"));
    let t18 = trace.iter().position(|l| *l == "t18").expect("through t18");
    assert!(!trace[t18..].contains(&"t9") && !trace[t18..].contains(&"t11"), "t18 then t13: {trace:?}");
    assert_eq!(strings(&r["marking"]), ["p6"]);
    let refused = &r["refused"][0];
    assert_eq!((refused["place"].as_str(), refused["event"].as_str()), (Some("p6"), Some("af1")));
    assert_eq!(strings(&refused["refused_by"]), ["S_piston_out_arm_away"]);
    assert_eq!((r["nodes"].as_u64(), r["edges"].as_u64()), (Some(434), Some(1101)));
}

#[test]
fn net_3_is_nonblocking_and_draws_its_graph() {
    let dot = scratch("net3.dot");
    let out = codegen(&["verify", &station("net3.toml"), "--json", "--dot", &dot.display().to_string()]);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let r: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(r["verdict"], "nonblocking");
    assert!(r.get("trace").is_none() && r.get("marking").is_none());
    assert_eq!((r["nodes"].as_u64(), r["edges"].as_u64()), (Some(352), Some(908)));
    assert_eq!(
        (r["admissible"]["states"].as_u64(), r["admissible"]["transitions"].as_u64()),
        (Some(372), Some(1610))
    );
    let text = std::fs::read_to_string(&dot).unwrap();
    assert!(text.starts_with("digraph io_reachability {") && !text.contains("color=red"));
    assert_eq!(text.matches(" -> ").count(), 908);
}

#[test]
fn limits_and_bad_input_exit_2_with_a_message() {
    let out = codegen(&["verify", &station("net2.toml"), "--state-limit", "400"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "error: IO-reachability graph: more than 400 nodes (raise --state-limit)\n"
    );
    let manifest = scratch("bad.toml");
    let text = std::fs::read_to_string(station("net3.toml")).unwrap();
    let plants = Path::new(&station("plants")).display().to_string();
    let specs = Path::new(&station("specs")).display().to_string();
    let bad = text
        .replace("\"plants/", &format!("\"{plants}/"))
        .replace("\"specs/", &format!("\"{specs}/"))
        .replace("pnml = \"net3.pnml\"", "pnml = \"missing.pnml\"")
        .replace("t8 = \"sf\"", "t8 = \"sf AND sx\"");
    std::fs::write(&manifest, &bad).unwrap();
    let _ = std::fs::remove_file(scratch("missing.pnml"));
    let out = codegen(&["verify", &manifest.display().to_string()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("error: ") && err.contains("missing.pnml: cannot read"), "{err}");
    std::fs::copy(station("net3.pnml"), scratch("missing.pnml")).unwrap();
    let out = codegen(&["verify", &manifest.display().to_string()]);
    let line = bad.lines().position(|l| l.starts_with("t8 = ")).unwrap() + 1;
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        format!(
            "error: {}: a map does not fit the model:\n  {line}: net: conditions.t8: unknown signal 'sx'\n",
            manifest.display()
        )
    );
    assert_eq!(out.status.code(), Some(2));
}
