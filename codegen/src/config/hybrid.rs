//! The manifest's `[hybrid]` section: the plant is the automation net of `[net]` (its conditions read
//! the sensors declared there as `free`, its place actions drive the actuators declared as `outputs`,
//! its delays are on-delay timers) and every transition is labelled by the event it generates; the
//! manifest's `specs` are automata over those events (Uzam & Gelen 2013, the hybrid controller).
//!
//! ```toml
//! [hybrid]
//! controllable = ["s1", "s2"]                  # events a controller may disable (the others: sensors)
//! [hybrid.events]                             # event of every transition of the net, by transition id
//! t1 = "s1"
//! t2 = "f1"
//! ```
//!
//! Plain values: names are checked against the net and the specifications by `plc::hybrid`, which
//! reports the line of a bad one (the spans kept here, located by the `[net]` section's lines).

use std::collections::BTreeMap;

use serde::Deserialize;
use toml::Spanned;

/// The `[hybrid]` section.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HybridSpec {
    /// The controllable events; every other event is uncontrollable.
    #[serde(default)]
    pub controllable: Vec<Spanned<String>>,
    /// The event of each transition of the net, by transition id.
    pub events: BTreeMap<Spanned<String>, Spanned<String>>,
}
