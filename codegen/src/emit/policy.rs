//! The firmware types the run-time configuration names in the emitted file, and the RAM each choice
//! policy costs there.

use crate::config::{ChoicePolicy, OnFault};

/// The firmware type implementing `policy`, given the constants the emitted file defines.
pub fn rust_type(policy: ChoicePolicy) -> &'static str {
    match policy {
        ChoicePolicy::First => "firmware::choice::First",
        ChoicePolicy::Random => "firmware::choice::Random",
        ChoicePolicy::GlobalQueue => "firmware::choice::GlobalQueue",
        ChoicePolicy::RandomGlobalQueue => "firmware::choice::RandomGlobalQueue<EVENT_WORDS>",
        ChoicePolicy::LocalQueue => "firmware::choice::LocalQueue<SITES>",
        ChoicePolicy::RandomLocalQueue => "firmware::choice::RandomLocalQueue<EVENT_WORDS, SITES>",
    }
}

/// RAM of `policy`'s state in bytes for `words` event bitset words and `sites` choice sites (the size of
/// the firmware type, padding included).
pub fn ram_bytes(policy: ChoicePolicy, words: usize, sites: usize) -> usize {
    match policy {
        ChoicePolicy::First | ChoicePolicy::Random => 0,
        ChoicePolicy::GlobalQueue => 1,
        ChoicePolicy::RandomGlobalQueue => 4 * words,
        ChoicePolicy::LocalQueue => 1 + sites,
        ChoicePolicy::RandomLocalQueue => 4 * words * sites,
    }
}

/// The firmware's value for `on_fault`.
pub fn fault_value(on_fault: OnFault) -> &'static str {
    match on_fault {
        OnFault::Continue => "firmware::fault::FaultPolicy::Continue",
        OnFault::SafeState => "firmware::fault::FaultPolicy::SafeState",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ram_matches_the_firmware_types() {
        use firmware::choice;
        use std::mem::size_of;
        assert_eq!(ram_bytes(ChoicePolicy::First, 1, 3), size_of::<choice::First>());
        assert_eq!(ram_bytes(ChoicePolicy::Random, 1, 3), size_of::<choice::Random>());
        assert_eq!(ram_bytes(ChoicePolicy::GlobalQueue, 1, 3), size_of::<choice::GlobalQueue>());
        assert_eq!(
            ram_bytes(ChoicePolicy::RandomGlobalQueue, 2, 3),
            size_of::<choice::RandomGlobalQueue<2>>()
        );
        assert_eq!(ram_bytes(ChoicePolicy::LocalQueue, 1, 3), size_of::<choice::LocalQueue<3>>());
        assert_eq!(
            ram_bytes(ChoicePolicy::RandomLocalQueue, 2, 3),
            size_of::<choice::RandomLocalQueue<2, 3>>()
        );
    }
}
