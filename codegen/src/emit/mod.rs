//! Emitting the Rust source the firmware compiles: the tables of a supervisor set in their layout as one
//! image of bytes in flash (`firmware::table::image`: the records of every automaton, the out-mask pool,
//! and the `SupervisorSet` sliced from it; checked when written and again by the firmware's build
//! script, which hands the compiler a digest instead of evaluating the check), with the side
//! tables the runtime's hot path needs, event ids as constants, event and automaton names apart for
//! logs, the choice-policy type and the runtime's type sized exactly, and the run-time configuration,
//! under a provenance header ([`crate::provenance`]).
//!
//! # Overview
//!
//! * [`rust`] — the writer. The side tables (per event the automata holding it, per plant the
//!   controllable events it generates, the choice sites) come from `firmware::build::SideTables`, with
//!   the runtime's limits checked ([`firmware::table::MAX_AUTOMATA`], every controllable event generated
//!   by a plant). Same inputs, byte-identical output: nothing in it depends on the time, the machine or a
//!   hash map's order.
//! * `header` — the comment block both writers open with: what the file holds, its provenance, the
//!   run-time options.
//! * [`board`] — the board tables of the manifest's `[board]` section ([`BoardSpec`](crate::config::BoardSpec)): pins of inputs and
//!   outputs for a real board.
//! * [`state`] — the state-based firmware's tables (`[runtime] mode = "state"`): the state feedback of
//!   [`crate::feedback`] as cubes over the packed signal word, no supervisor tables.
//! * [`timers`] — the manifest's timers (`TIMERS`, `firmware::timer::TimerSpec`s), which every tables
//!   file ends with (empty without `[[timers]]`), outside the image and its digest.
//! * [`policy`] — the firmware types the run-time configuration ([`RuntimeConfig`](crate::config::RuntimeConfig)) names, and the RAM
//!   each choice policy costs.
//!
//! Why a `codegen emit` subcommand rather than a `build.rs` calling this library: `codegen` depends on the
//! firmware's runtime (the virtual plant and the host tests run the very code that ships), so the
//! firmware cannot depend on `codegen` without a cycle. The committed `apps/cell/src/generated/cell.rs` is
//! kept fresh by a test that emits it again and compares the bytes.

pub mod board;
mod error;
mod header;
pub mod policy;
pub mod rust;
pub mod state;
pub mod timers;

pub use crate::provenance::{Input, Provenance};
pub use board::BoardError;
pub use error::EmitError;
pub use rust::emit;

/// How emitted tables declare the digest a firmware built on them answers the link's TABLES with
/// (`firmware::link::TABLES`), up to the digest's 16 hex digits: an image's in the event-based tables
/// (the Cortex-M3's, and the Cortex-M0+'s in `m0plus`), the whole tables' in the state-based ones.
pub(crate) const DIGEST_ITEM: &str = "pub const DIGEST: &str = \"";

/// The digests the emitted tables `text` declare (`pub const DIGEST: &str = "…";`), in the order
/// written, without repeats: the tables a firmware built on `text` may report over the link.
///
/// ```
/// let text = "pub const DIGEST: &str = \"00112233445566ff\";\nmod m0plus {\n    pub const DIGEST: &str = \"0123456789abcdef\";\n}\n";
/// assert_eq!(codegen::emit::digests(text), ["00112233445566ff", "0123456789abcdef"]);
/// ```
pub fn digests(text: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for line in text.lines() {
        let digest = line.trim_start().strip_prefix(DIGEST_ITEM).and_then(|rest| rest.strip_suffix("\";"));
        if let Some(d) = digest.filter(|d| !out.iter().any(|o| o == d)) {
            out.push(d.to_owned());
        }
    }
    out
}
