//! The page and its JSON API (docs/sim.md documents every endpoint): one function from a request to a
//! response, so that the server only moves bytes and tests call the handlers directly.
//!
//! | request | answer |
//! |---|---|
//! | `GET /` | the page (`sim.js` and `sim.css` beside it) |
//! | `GET /api/automata` | the project's name and its automata: name, role, states, transitions |
//! | `GET /api/state?depth=K` | everything the page shows ([`State`]) |
//! | `POST /api/step` `{"event": E}` | takes E; the new state, or 409 with the reason |
//! | `POST /api/revert` `{"to": K}` | back to the state after K steps of the trace |
//! | `POST /api/reset` | back to the initial state, the trace empty |
//! | `POST /api/run` `{"events": N}` | N events by the controller's policy and the steered plant |

use serde::{Deserialize, Serialize};

use super::findings::Located;
use super::state_based::Word;
use super::{draw, sequence, Actor, Events, Sim};

/// The page.
const INDEX: &str = include_str!("assets/index.html");
/// Its script.
const SCRIPT: &str = include_str!("assets/sim.js");
/// Its style sheet.
const STYLE: &str = include_str!("assets/sim.css");

/// The neighbourhood depth when the page asks for none.
pub const DEPTH: usize = 2;
/// Most events one run request takes.
pub const MOST_EVENTS: u64 = 1_000_000;

/// An answer: status, content type and body.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Response {
    /// The HTTP status.
    pub status: u16,
    /// The content type.
    pub content_type: &'static str,
    /// The body.
    pub body: String,
}

impl Response {
    fn text(status: u16, content_type: &'static str, body: &str) -> Self {
        Response { status, content_type, body: body.to_owned() }
    }

    fn json(status: u16, value: &impl Serialize) -> Self {
        match serde_json::to_string(value) {
            Ok(body) => Response { status, content_type: "application/json", body },
            Err(e) => Response::error(500, &e.to_string()),
        }
    }

    fn error(status: u16, message: &str) -> Self {
        Response::json_value(status, serde_json::json!({ "error": message }))
    }

    fn json_value(status: u16, value: serde_json::Value) -> Self {
        Response { status, content_type: "application/json", body: value.to_string() }
    }
}

/// One automaton in `GET /api/automata`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct AutomatonInfo {
    /// Its name.
    pub name: String,
    /// `plant` or `supervisor`.
    pub role: &'static str,
    /// Its number of states.
    pub states: usize,
    /// Its number of transitions.
    pub transitions: usize,
}

/// The answer of `GET /api/automata`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Automata {
    /// The project's name.
    pub name: String,
    /// Plants first, then supervisors.
    pub automata: Vec<AutomatonInfo>,
}

/// One automaton in [`State`].
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Shown {
    /// Its name.
    pub name: String,
    /// `plant` or `supervisor`.
    pub role: &'static str,
    /// Its current state's name.
    pub current: String,
    /// Its number of states.
    pub states: usize,
    /// The states drawn.
    pub shown: usize,
    /// Whether more states lie beyond the drawing (a deeper neighbourhood shows them).
    pub partial: bool,
    /// The drawing (SVG), or why there is none.
    pub svg: Result<String, String>,
    /// A supervisor's transitions taken by the trace, of all of them.
    pub coverage: Option<(usize, usize)>,
}

/// One step of the trace in [`State`].
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct TraceStep {
    /// The event.
    pub event: String,
    /// Who took it.
    pub by: Actor,
}

/// The answer of `GET /api/state` and of every `POST`: all the page shows.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct State {
    /// The project's name.
    pub name: String,
    /// The controller's choice policy (a run's).
    pub policy: String,
    /// The neighbourhood depth drawn.
    pub depth: usize,
    /// Every automaton, plants first.
    pub automata: Vec<Shown>,
    /// The events in the current state.
    pub events: Events,
    /// The trace from the initial state.
    pub trace: Vec<TraceStep>,
    /// `check`'s findings, located, or why they are missing.
    pub findings: Result<Vec<Located>, String>,
    /// Steps the last run took, when the last request was a run.
    pub ran: Option<usize>,
    /// A state-based project's signal word and rung values now, or why there are none; `None` (JSON
    /// `null`) for a project without a `[state]` section.
    pub program: Option<Result<Word, String>>,
    /// A project's Petri net at this point (its marking, transitions enabled and fired, its drawing), or
    /// why there is none; `None` (JSON `null`) for a project without a net.
    pub net: Option<Result<sequence::Shown, String>>,
}

/// Builds [`State`] for `sim` drawn to `depth`.
pub fn state(sim: &Sim, depth: usize, ran: Option<usize>) -> State {
    let coverage = sim.coverage();
    let automata = sim
        .automata
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let drawing = draw::draw(sim, i, depth);
            Shown {
                name: a.name.clone(),
                role: role(sim, i),
                current: a.states.get(sim.state()[i] as usize).map_or_else(String::new, |s| s.name.clone()),
                states: a.states.len(),
                shown: drawing.as_ref().map_or(0, |d| d.shown),
                partial: drawing.as_ref().is_ok_and(|d| d.partial),
                svg: drawing.map(|d| d.svg),
                coverage: i.checked_sub(sim.plants).and_then(|s| coverage.get(s).copied()),
            }
        })
        .collect();
    let table = sim.set.events();
    State {
        name: sim.name.clone(),
        policy: format!("{:?}", sim.runtime.policy),
        depth,
        automata,
        events: sim.events(),
        trace: sim
            .trace
            .iter()
            .map(|s| TraceStep { event: table.name(s.event).to_owned(), by: s.by })
            .collect(),
        findings: sim.findings.clone(),
        ran,
        program: sim.program.as_ref().map(|p| p.as_ref().map(|p| p.shown(sim)).map_err(Clone::clone)),
        net: sim.net.as_ref().map(|n| n.as_ref().map(|n| n.shown(sim)).map_err(Clone::clone)),
    }
}

fn role(sim: &Sim, i: usize) -> &'static str {
    if i < sim.plants {
        "plant"
    } else {
        "supervisor"
    }
}

/// The answer of `GET /api/automata`.
pub fn automata(sim: &Sim) -> Automata {
    Automata {
        name: sim.name.clone(),
        automata: sim
            .automata
            .iter()
            .enumerate()
            .map(|(i, a)| AutomatonInfo {
                name: a.name.clone(),
                role: role(sim, i),
                states: a.states.len(),
                transitions: a.transitions.len(),
            })
            .collect(),
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StepBody {
    event: String,
    depth: Option<usize>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RevertBody {
    to: usize,
    depth: Option<usize>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RunBody {
    events: u64,
    depth: Option<usize>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct ResetBody {
    depth: Option<usize>,
}

/// The `depth` query parameter of `url`, else [`DEPTH`].
fn query_depth(url: &str) -> Result<usize, String> {
    let Some((_, query)) = url.split_once('?') else { return Ok(DEPTH) };
    for pair in query.split('&') {
        if let Some(v) = pair.strip_prefix("depth=") {
            return v.parse().map_err(|_| format!("depth: '{v}' is not a number"));
        }
    }
    Ok(DEPTH)
}

fn parse<'a, T: Deserialize<'a>>(body: &'a str) -> Result<T, Response> {
    serde_json::from_str(body).map_err(|e| Response::error(400, &format!("request body: {e}")))
}

/// Answers one request: `method`, `url` (path and query) and `body` as received.
pub fn handle(sim: &mut Sim, method: &str, url: &str, body: &str) -> Response {
    let path = url.split('?').next().unwrap_or("");
    let result = match (method, path) {
        ("GET", "/" | "/index.html") => return Response::text(200, "text/html; charset=utf-8", INDEX),
        ("GET", "/sim.js") => return Response::text(200, "text/javascript; charset=utf-8", SCRIPT),
        ("GET", "/sim.css") => return Response::text(200, "text/css; charset=utf-8", STYLE),
        ("GET", "/api/automata") => return Response::json(200, &automata(sim)),
        ("GET", "/api/state") => {
            return match query_depth(url) {
                Ok(depth) => Response::json(200, &state(sim, depth, None)),
                Err(e) => Response::error(400, &e),
            }
        }
        ("POST", "/api/step") => parse::<StepBody>(body).and_then(|b| {
            sim.step_named(&b.event)
                .map(|()| (b.depth, None))
                .map_err(|e| Response::error(409, &e.to_string()))
        }),
        ("POST", "/api/revert") => parse::<RevertBody>(body).and_then(|b| {
            sim.revert(b.to).map(|()| (b.depth, None)).map_err(|e| Response::error(409, &e.to_string()))
        }),
        ("POST", "/api/reset") => {
            let b = if body.trim().is_empty() { Ok(ResetBody::default()) } else { parse::<ResetBody>(body) };
            b.map(|b| {
                sim.reset();
                (b.depth, None)
            })
        }
        ("POST", "/api/run") => parse::<RunBody>(body).and_then(|b| {
            if b.events > MOST_EVENTS {
                return Err(Response::error(400, &format!("events: at most {MOST_EVENTS} per run")));
            }
            sim.run(b.events).map(|n| (b.depth, Some(n))).map_err(|e| Response::error(500, &e.to_string()))
        }),
        (_, "/" | "/index.html" | "/sim.js" | "/sim.css" | "/api/automata" | "/api/state") => {
            return Response::error(405, &format!("{method} {path}: use GET"))
        }
        (_, "/api/step" | "/api/revert" | "/api/reset" | "/api/run") => {
            return Response::error(405, &format!("{method} {path}: use POST"))
        }
        _ => return Response::error(404, &format!("no such page or endpoint: {path}")),
    };
    match result {
        Ok((depth, ran)) => Response::json(200, &state(sim, depth.unwrap_or(DEPTH), ran)),
        Err(response) => response,
    }
}

#[cfg(test)]
mod tests {
    use serde_json::Value;

    use super::*;

    fn call(sim: &mut Sim, method: &str, url: &str, body: &str) -> (u16, Value) {
        let r = handle(sim, method, url, body);
        assert_eq!(r.content_type, "application/json", "{url}");
        (r.status, serde_json::from_str(&r.body).unwrap())
    }

    #[test]
    fn the_page_and_its_assets_are_served() {
        let mut sim = crate::sim::tests::small();
        let page = handle(&mut sim, "GET", "/", "");
        assert_eq!((page.status, page.content_type), (200, "text/html; charset=utf-8"));
        assert!(page.body.contains("sim.js"));
        assert_eq!(handle(&mut sim, "GET", "/sim.js", "").status, 200);
        assert_eq!(handle(&mut sim, "GET", "/sim.css", "").status, 200);
        assert_eq!(handle(&mut sim, "GET", "/nope", "").status, 404);
        assert_eq!(handle(&mut sim, "DELETE", "/api/run", "").status, 405);
    }

    #[test]
    fn automata_names_every_automaton_plants_first() {
        let mut sim = crate::sim::tests::small();
        let (status, v) = call(&mut sim, "GET", "/api/automata", "");
        assert_eq!(status, 200);
        let names: Vec<&str> =
            v["automata"].as_array().unwrap().iter().map(|a| a["name"].as_str().unwrap()).collect();
        assert_eq!(names, ["M", "R", "S"]);
        assert_eq!(v["automata"][2]["role"], "supervisor");
    }

    #[test]
    fn step_revert_reset_and_run_answer_the_new_state() {
        let mut sim = crate::sim::tests::small();
        let (status, v) = call(&mut sim, "POST", "/api/step", r#"{"event": "start"}"#);
        assert_eq!(status, 200);
        assert_eq!(v["automata"][2]["current"], "used");
        assert_eq!(v["trace"][0]["event"], "start");
        assert_eq!(v["trace"][0]["by"], "user");
        call(&mut sim, "POST", "/api/step", r#"{"event": "done"}"#);
        let (_, v) = call(&mut sim, "GET", "/api/state?depth=1", "");
        assert_eq!(v["depth"], 1);
        assert_eq!(v["events"]["disabled"][0]["event"], "start");
        assert_eq!(v["events"]["disabled"][0]["by"][0], "S");
        let (status, v) = call(&mut sim, "POST", "/api/step", r#"{"event": "start"}"#);
        assert_eq!(status, 409);
        assert!(v["error"].as_str().unwrap().contains("refused by S"), "{v}");
        let (status, v) = call(&mut sim, "POST", "/api/revert", r#"{"to": 1}"#);
        assert_eq!(status, 200);
        assert_eq!(v["trace"].as_array().unwrap().len(), 1);
        let (_, v) = call(&mut sim, "POST", "/api/run", r#"{"events": 50}"#);
        assert_eq!(v["ran"], 50);
        assert_eq!(v["trace"].as_array().unwrap().len(), 51);
        assert_eq!(v["automata"][2]["coverage"], serde_json::json!([2, 2]));
        let (_, v) = call(&mut sim, "POST", "/api/reset", "");
        assert_eq!(v["trace"].as_array().unwrap().len(), 0);
    }

    #[test]
    fn bad_requests_are_refused_with_a_reason() {
        let mut sim = crate::sim::tests::small();
        assert_eq!(call(&mut sim, "POST", "/api/step", "{").0, 400);
        assert_eq!(call(&mut sim, "POST", "/api/step", r#"{"event": "start", "x": 1}"#).0, 400);
        assert_eq!(call(&mut sim, "POST", "/api/step", r#"{"event": "nope"}"#).0, 409);
        assert_eq!(call(&mut sim, "POST", "/api/revert", r#"{"to": 9}"#).0, 409);
        assert_eq!(call(&mut sim, "POST", "/api/run", r#"{"events": 99999999}"#).0, 400);
        assert_eq!(call(&mut sim, "GET", "/api/state?depth=x", "").0, 400);
    }
}
