//! `codegen sim`: the contract as written — `codegen sim PROJECT --port N` serves
//! `http://127.0.0.1:N/` (200, HTML) until stopped, and the page's API answers with the project's automata
//! names — and the page itself in headless Chromium (`sim_browser.py`, Selenium from `.venv`): on the
//! cell step, revert, run 1 000 events, coverage (its screenshot is docs/images/sim.png); on the factory
//! and the AGV the same with findings on the graphs, and the AGV's large supervisor expanded; on the
//! station's Petri-net sequence the marking moving with a step.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use codegen::project::Project;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf()
}

/// A `codegen sim` process, stopped when dropped.
struct Served {
    child: Child,
    port: u16,
}

impl Drop for Served {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Starts `codegen sim manifest --port port` (with `more` arguments), not waiting for it to serve.
fn spawn(manifest: &Path, port: u16, more: &[&str]) -> Served {
    let child = Command::new(env!("CARGO_BIN_EXE_codegen"))
        .args(["sim", &manifest.display().to_string(), "--port", &port.to_string()])
        .args(more)
        .stdout(Stdio::piped())
        .spawn()
        .expect("start codegen sim");
    Served { child, port }
}

impl Served {
    /// Waits for the server's first line (it serves from then on) and takes the port it names.
    fn ready(mut self) -> Served {
        let mut line = String::new();
        BufReader::new(self.child.stdout.take().unwrap()).read_line(&mut line).unwrap();
        self.port = line
            .rsplit_once("http://127.0.0.1:")
            .and_then(|(_, rest)| rest.split('/').next())
            .and_then(|p| p.parse().ok())
            .unwrap_or_else(|| panic!("no address in {line:?}"));
        self
    }
}

/// Starts `codegen sim manifest --port port` and waits until it serves.
fn serve(manifest: &Path, port: u16) -> Served {
    spawn(manifest, port, &[]).ready()
}

/// A port nobody listens on now.
fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port()
}

/// `GET path` on 127.0.0.1:port: status line, headers and body.
fn get(port: u16, path: &str) -> (String, String, String) {
    let mut stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
    stream.set_read_timeout(Some(Duration::from_secs(120))).unwrap();
    write!(stream, "GET {path} HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n").unwrap();
    let mut answer = String::new();
    stream.read_to_string(&mut answer).unwrap();
    let (head, body) = answer.split_once("\r\n\r\n").unwrap_or((&answer, ""));
    let (status, headers) = head.split_once("\r\n").unwrap_or((head, ""));
    (status.to_owned(), headers.to_lowercase(), body.to_owned())
}

#[test]
fn the_page_and_the_automata_names_on_the_port_asked() {
    let manifest = root().join("examples/cell/cell.toml");
    let port = free_port();
    let served = serve(&manifest, port);
    assert_eq!(served.port, port);
    let (status, headers, body) = get(port, "/");
    assert!(status.contains(" 200 "), "{status}");
    assert!(headers.contains("content-type: text/html"), "{headers}");
    assert!(body.contains("<html"), "{body}");
    let (status, _, body) = get(port, "/api/automata");
    assert!(status.contains(" 200 "), "{status}");
    let json: serde_json::Value = serde_json::from_str(&body).unwrap();
    let names: Vec<&str> =
        json["automata"].as_array().unwrap().iter().map(|a| a["name"].as_str().unwrap()).collect();
    let project = Project::load(&manifest).unwrap();
    let mut expected: Vec<&str> = project.set.members().iter().map(|m| m.automaton.name.as_str()).collect();
    let mut got = names.clone();
    expected.sort_unstable();
    got.sort_unstable();
    assert_eq!(got, expected);
    assert!(names.contains(&"G1"), "{names:?}");
}

/// One browser over four servers: the cell (step, revert, run, coverage, the screenshot), the factory
/// and the AGV (the same with findings on the graphs; the AGV's merged supervisor of 7 800 states drawn
/// around its current state and expanded) and the station's third net (the marking after a step). The
/// AGV's server synthesises for about half a minute, so it starts first on a port chosen here and the
/// script waits for it after the others.
#[test]
fn the_page_steps_reverts_and_runs_in_headless_chromium() {
    let agv = spawn(&root().join("examples/agv/agv.toml"), free_port(), &["--supervisors", "full"]);
    let cell = serve(&root().join("examples/cell/cell.toml"), 0);
    let factory = serve(&root().join("examples/factory/factory.toml"), 0);
    let net = serve(&root().join("examples/station-rtpn/net3.toml"), 0);
    let shot = root().join("docs/images/sim.png");
    let url = |name: &str, s: &Served| format!("{name}=http://127.0.0.1:{}/", s.port);
    let out = Command::new(root().join(".venv/bin/python"))
        .arg(root().join("codegen/tests/sim_browser.py"))
        .arg(&shot)
        .args([url("cell", &cell), url("factory", &factory), url("agv", &agv), url("net", &net)])
        .output()
        .expect("run .venv/bin/python (scripts/setup.sh installs Selenium and Chromium)");
    let said = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "{said}");
    println!("{said}");
    assert!(
        std::fs::metadata(&shot).map(|m| m.len() > 0).unwrap_or(false),
        "no screenshot at {}",
        shot.display()
    );
}
