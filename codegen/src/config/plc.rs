//! The manifest's `[plc]` section: which input variable and edge make each uncontrollable event, which
//! output variable each controllable event drives and how, the choice policy and the task's cycle.
//!
//! ```toml
//! [plc]
//! policy = "random"              # first | global-queue | local-queue | random (default: [runtime] policy)
//! cycle_ms = 10                  # the TASK's interval
//! instruction_ns = 1000          # one IL instruction's time (state-based scan-time figure)
//! [[plc.inputs]]
//! event = "s_c1"
//! variable = "sensor_c1"         # a BOOL of the PROGRAM
//! edge = "rising"                # rising | falling | both
//! address = "%IX0.2"             # optional: located variable
//! [[plc.outputs]]
//! event = "e1_lig"
//! variable = "conveyor"
//! action = "set"                 # set | clear | pulse (with scans = N, default 1)
//! ```
//!
//! One input variable may carry two events, one per edge (`sb1` rising, `sb0` falling of `sb`).
//!
//! An unmapped uncontrollable event is a member of the `EVENTS` input structure (rising edge). Once the
//! section maps anything (an input, an output or an internal event), every controllable event must drive
//! an output unless `internal` lists it (a command with no actuator): an unmapped controllable event not
//! listed is an error naming it.
//!
//! ```toml
//! [plc]
//! internal = ["count_done"]      # controllable events that drive no output (default: none)
//! ```

use serde::Deserialize;

use super::ChoicePolicy;

/// The `[plc]` section.
#[derive(Clone, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlcSpec {
    /// Choice policy; `None` takes the manifest's `[runtime] policy` when it has a scan-cycle form.
    pub policy: Option<ScanPolicy>,
    /// Interval of the cyclic task, in milliseconds.
    pub cycle_ms: Option<u32>,
    /// Time one instruction-list instruction takes on the target, in nanoseconds (the state-based
    /// program's scan-time figure; default 1000, one microsecond).
    pub instruction_ns: Option<u32>,
    /// Input variables, one per uncontrollable event they make.
    #[serde(default)]
    pub inputs: Vec<PlcInput>,
    /// Output variables and the controllable events that drive them.
    #[serde(default)]
    pub outputs: Vec<PlcOutput>,
    /// Controllable events that deliberately drive no output.
    #[serde(default)]
    pub internal: Vec<String>,
}

/// One input variable.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlcInput {
    /// The uncontrollable event an edge of the variable means.
    pub event: String,
    /// The BOOL variable's name.
    pub variable: String,
    /// Which change is the event.
    pub edge: Edge,
    /// Located address (`%IX0.2`), if the variable is bound to a physical input.
    pub address: Option<String>,
}

/// One output action.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlcOutput {
    /// The controllable event that runs the action.
    pub event: String,
    /// The BOOL variable's name (several events may share one).
    pub variable: String,
    /// What the event does to the variable.
    pub action: Action,
    /// Pulse length in scans (`pulse` only; default 1).
    pub scans: Option<u16>,
    /// Located address (`%QX2.0`), if the variable is bound to a physical output.
    pub address: Option<String>,
}

/// Which change of an input is its event.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Edge {
    /// FALSE → TRUE.
    Rising,
    /// TRUE → FALSE.
    Falling,
    /// Any change.
    Both,
}

/// What a controllable event does to its output variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Action {
    /// The variable becomes TRUE.
    Set,
    /// The variable becomes FALSE.
    Clear,
    /// The variable is TRUE for a number of scans.
    Pulse,
}

/// The choice policies the scan-cycle program implements (those of `firmware::choice` that need no
/// per-round permutation).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum ScanPolicy {
    /// Lowest enabled event id (rung order).
    First,
    /// One cursor over all controllable events.
    GlobalQueue,
    /// Plants cyclically, then a cursor per choice site (plant state).
    LocalQueue,
    /// Uniform among the enabled, from a MINSTD generator in the program.
    Random,
}

impl ScanPolicy {
    /// The manifest's name.
    pub fn name(self) -> &'static str {
        match self {
            ScanPolicy::First => "first",
            ScanPolicy::GlobalQueue => "global-queue",
            ScanPolicy::LocalQueue => "local-queue",
            ScanPolicy::Random => "random",
        }
    }

    /// The scan-cycle form of a firmware policy, if it has one.
    pub fn of_runtime(policy: ChoicePolicy) -> Option<ScanPolicy> {
        match policy {
            ChoicePolicy::First => Some(ScanPolicy::First),
            ChoicePolicy::GlobalQueue => Some(ScanPolicy::GlobalQueue),
            ChoicePolicy::LocalQueue => Some(ScanPolicy::LocalQueue),
            ChoicePolicy::Random => Some(ScanPolicy::Random),
            ChoicePolicy::RandomGlobalQueue | ChoicePolicy::RandomLocalQueue => None,
        }
    }
}

impl Edge {
    /// The manifest's name.
    pub fn name(self) -> &'static str {
        match self {
            Edge::Rising => "rising",
            Edge::Falling => "falling",
            Edge::Both => "both",
        }
    }
}

impl Action {
    /// The manifest's name.
    pub fn name(self) -> &'static str {
        match self {
            Action::Set => "set",
            Action::Clear => "clear",
            Action::Pulse => "pulse",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_section_parses_and_refuses_unknown_keys() {
        #[derive(Deserialize)]
        struct File {
            plc: PlcSpec,
        }
        let text = "[plc]\npolicy = \"local-queue\"\n[[plc.inputs]]\nevent = \"a\"\nvariable = \"x\"\nedge = \"both\"\n\
                    [[plc.outputs]]\nevent = \"b\"\nvariable = \"y\"\naction = \"pulse\"\nscans = 3\n";
        let spec = toml::from_str::<File>(text).unwrap().plc;
        assert_eq!(spec.policy, Some(ScanPolicy::LocalQueue));
        assert_eq!(spec.inputs[0].edge, Edge::Both);
        assert_eq!((spec.outputs[0].action, spec.outputs[0].scans), (Action::Pulse, Some(3)));
        assert!(toml::from_str::<File>("[plc]\ncycle = 3\n").is_err());
        let internal = toml::from_str::<File>("[plc]\ninternal = [\"x\"]\n").unwrap().plc.internal;
        assert_eq!(internal, ["x"]);
        assert!(toml::from_str::<File>("[plc]\npolicy = \"random-local-queue\"\n").is_err());
    }
}
