//! This module is the home of [`BoardSpec`], the manifest's `[board]` section: which GPIO makes which
//! uncontrollable event and which controllable event drives which GPIO (checked against the set's events
//! and written as `firmware::board` tables by [`crate::emit`]).
//!
//! ```toml
//! [board]
//! name = "pico"
//! sampling = "interrupt"          # or "timer", with sample_period_us
//! [[board.inputs]]
//! event = "s_c1"
//! pin = 2
//! edge = "rising"                 # rising | falling | both
//! pull = "up"                     # floating | up | down
//! [[board.outputs]]
//! event = "e1_lig"
//! pin = 16
//! action = "set"                  # set | clear | pulse (with pulse_ms)
//! ```

use serde::Deserialize;

/// The `[board]` section.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoardSpec {
    /// Board name, for logs.
    pub name: String,
    /// How inputs are read.
    #[serde(default)]
    pub sampling: SamplingSpec,
    /// Sampling period in microseconds (timer sampling only).
    pub sample_period_us: Option<u32>,
    /// Input pins, in the order the firmware checks them.
    #[serde(default)]
    pub inputs: Vec<InputSpec>,
    /// Output actions.
    #[serde(default)]
    pub outputs: Vec<OutputSpec>,
    /// Controllable events that drive no pin (the supervisors fire them, nothing outside sees them):
    /// every other command must drive a pin, or the tables would believe the plant moved when it did not.
    #[serde(default)]
    pub internal: Vec<String>,
}

/// How inputs are read.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SamplingSpec {
    /// GPIO edge interrupts.
    #[default]
    Interrupt,
    /// Timer sampling.
    Timer,
}

/// One input pin.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InputSpec {
    /// The uncontrollable event an edge makes.
    pub event: String,
    /// GPIO number.
    pub pin: u8,
    /// `rising`, `falling` or `both`.
    pub edge: String,
    /// `floating` (default), `up` or `down`.
    #[serde(default = "floating")]
    pub pull: String,
}

fn floating() -> String {
    String::from("floating")
}

/// One output action.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// The controllable event that runs it.
    pub event: String,
    /// GPIO number.
    pub pin: u8,
    /// `set`, `clear` or `pulse`.
    pub action: String,
    /// Pulse length in milliseconds (`pulse` only).
    pub pulse_ms: Option<u16>,
}
