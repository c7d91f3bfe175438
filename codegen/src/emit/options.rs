//! The run-time choices an emitted table carries (manifest `[runtime]`), and what each choice policy
//! costs in RAM.

use std::fmt;

/// A choice policy of the runtime (`firmware::choice`); `random-local-queue` is the default. Also the
/// manifest's `[runtime] policy`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Policy {
    /// Lowest enabled event id.
    First,
    /// Uniform among the enabled.
    Random,
    /// One cursor over all controllable events.
    GlobalQueue,
    /// A random order of all controllable events per round.
    RandomGlobalQueue,
    /// A cursor per choice site.
    LocalQueue,
    /// A random order per choice site and round.
    #[default]
    RandomLocalQueue,
}

impl Policy {
    /// Every policy, in the order of the design notes.
    pub const ALL: [Policy; 6] = [
        Policy::First,
        Policy::Random,
        Policy::GlobalQueue,
        Policy::RandomGlobalQueue,
        Policy::LocalQueue,
        Policy::RandomLocalQueue,
    ];

    /// The manifest's name.
    pub fn name(self) -> &'static str {
        match self {
            Policy::First => "first",
            Policy::Random => "random",
            Policy::GlobalQueue => "global-queue",
            Policy::RandomGlobalQueue => "random-global-queue",
            Policy::LocalQueue => "local-queue",
            Policy::RandomLocalQueue => "random-local-queue",
        }
    }

    /// The policy a manifest name denotes.
    pub fn from_name(name: &str) -> Option<Policy> {
        Policy::ALL.into_iter().find(|p| p.name() == name)
    }

    /// RAM of the policy's state in bytes for `words` event bitset words and `sites` choice sites (the
    /// size of the firmware type, padding included).
    pub fn ram_bytes(self, words: usize, sites: usize) -> usize {
        match self {
            Policy::First | Policy::Random => 0,
            Policy::GlobalQueue => 1,
            Policy::RandomGlobalQueue => 4 * words,
            Policy::LocalQueue => 1 + sites,
            Policy::RandomLocalQueue => 4 * words * sites,
        }
    }

    /// The firmware type implementing the policy, given the constants the emitted file defines.
    pub fn rust_type(self) -> &'static str {
        match self {
            Policy::First => "firmware::choice::First",
            Policy::Random => "firmware::choice::Random",
            Policy::GlobalQueue => "firmware::choice::GlobalQueue",
            Policy::RandomGlobalQueue => "firmware::choice::RandomGlobalQueue<EVENT_WORDS>",
            Policy::LocalQueue => "firmware::choice::LocalQueue<SITES>",
            Policy::RandomLocalQueue => "firmware::choice::RandomLocalQueue<EVENT_WORDS, SITES>",
        }
    }
}

impl fmt::Display for Policy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The reaction to a fault (`firmware::fault::FaultPolicy`); the manifest's `[runtime] on_fault`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum OnFault {
    /// Count, report, keep deciding.
    #[default]
    Continue,
    /// Count, report, outputs off, stop deciding until a reset.
    SafeState,
}

impl OnFault {
    /// The manifest's name.
    pub fn name(self) -> &'static str {
        match self {
            OnFault::Continue => "continue",
            OnFault::SafeState => "safe-state",
        }
    }

    /// The firmware's value.
    pub fn rust_value(self) -> &'static str {
        match self {
            OnFault::Continue => "firmware::fault::FaultPolicy::Continue",
            OnFault::SafeState => "firmware::fault::FaultPolicy::SafeState",
        }
    }
}

/// Everything about the run an emitted file fixes besides the tables.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Options {
    /// Name of the set (the manifest's `name`).
    pub name: String,
    /// Choice policy.
    pub policy: Policy,
    /// Seed of the random policies under QEMU (a board reseeds from its own entropy).
    pub seed: u64,
    /// Inexact-synchronisation guard.
    pub guard: bool,
    /// Fault reaction.
    pub on_fault: OnFault,
    /// Input buffer capacity in events.
    pub input_buffer: usize,
    /// Random draws between two reseeds (0: never).
    pub reseed_every: u16,
    /// Pin map for a real board (`[board]`); without it the board tables are empty.
    pub board: Option<super::BoardSpec>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            name: String::from("set"),
            policy: Policy::default(),
            seed: 0,
            guard: true,
            on_fault: OnFault::default(),
            input_buffer: 32,
            reseed_every: 1024,
            board: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for p in Policy::ALL {
            assert_eq!(Policy::from_name(p.name()), Some(p));
        }
        assert_eq!(Policy::from_name("fifo"), None);
    }

    #[test]
    fn ram_matches_the_firmware_types() {
        use firmware::choice;
        use std::mem::size_of;
        assert_eq!(Policy::First.ram_bytes(1, 3), size_of::<choice::First>());
        assert_eq!(Policy::Random.ram_bytes(1, 3), size_of::<choice::Random>());
        assert_eq!(Policy::GlobalQueue.ram_bytes(1, 3), size_of::<choice::GlobalQueue>());
        assert_eq!(Policy::RandomGlobalQueue.ram_bytes(2, 3), size_of::<choice::RandomGlobalQueue<2>>());
        assert_eq!(Policy::LocalQueue.ram_bytes(1, 3), size_of::<choice::LocalQueue<3>>());
        assert_eq!(Policy::RandomLocalQueue.ram_bytes(2, 3), size_of::<choice::RandomLocalQueue<2, 3>>());
    }
}
