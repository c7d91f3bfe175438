//! Dense, checked ids for states and events.

use std::fmt;

/// The id did not fit: more states or events than the model supports.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{what} index {index} exceeds the limit of {limit}")]
pub struct IdError {
    what: &'static str,
    index: usize,
    limit: usize,
}

macro_rules! dense_id {
    ($(#[$doc:meta])* $name:ident, $what:literal) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
        pub struct $name(u32);

        impl $name {
            /// The largest index an id may hold.
            pub const LIMIT: usize = u32::MAX as usize - 1;

            /// An id for `index`, or an error when it exceeds [`Self::LIMIT`].
            pub fn new(index: usize) -> Result<Self, IdError> {
                u32::try_from(index)
                    .ok()
                    .filter(|&i| i as usize <= Self::LIMIT)
                    .map($name)
                    .ok_or(IdError { what: $what, index, limit: Self::LIMIT })
            }

            /// The index this id stands for, usable to index a `Vec`.
            pub fn index(self) -> usize {
                self.0 as usize
            }

            /// The raw value, for compact storage.
            pub fn as_u32(self) -> u32 {
                self.0
            }

            /// An id from a raw value produced by [`Self::as_u32`].
            pub fn from_u32(raw: u32) -> Self {
                $name(raw)
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                self.0.fmt(f)
            }
        }
    };
}

dense_id!(
    /// Index of a state within one automaton.
    StateId,
    "state"
);
dense_id!(
    /// Index of an event, either within one automaton's alphabet or within an [`EventTable`](super::EventTable).
    EventId,
    "event"
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_round_trip_and_refuse_overflow() {
        assert_eq!(StateId::new(7).unwrap().index(), 7);
        assert!(StateId::new(StateId::LIMIT + 1).is_err());
        let msg = EventId::new(usize::MAX).unwrap_err().to_string();
        assert!(msg.contains("event index"), "{msg}");
    }
}
