//! The six choice policies of the runtime: which one controllable event to fire when the supervisors
//! leave several enabled. Each implements [`Choose`]; the emitted tables name theirs `Policy`.
//!
//! | policy | RAM | rule |
//! |---|---|---|
//! | [`First`] | 0 | lowest enabled event id (PLC rung order) |
//! | [`Random`] | 0 (uses the runtime's generator) | uniform among the enabled |
//! | [`GlobalQueue`] | 1 B | one cursor over all controllable events in id order |
//! | [`RandomGlobalQueue`] | 4·W B | a random order of all controllable events per round |
//! | [`LocalQueue`] | 1 + S B | a cursor per choice site |
//! | [`RandomLocalQueue`] | 4·W·S B | a random order per choice site and round |
//!
//! W is the word count of an event bitset, S the number of choice sites with two or more controllable
//! out-events ([`View::sites`]); a site with one such event needs no memory.
//!
//! A *choice site* is a state of the plant that generates the event. The local policies first pick a
//! plant among those that generate an enabled event (`local-queue`: cyclically; `random-local-queue`:
//! uniformly, so that no interleaving of the plants is ruled out — a fixed plant order would keep the
//! closed loop out of states a machine reaches only by waiting), then the plant's current state picks
//! among its own enabled events in event-id order (the order of its out-mask). So a choice made in one
//! place never starves another, which a single global cursor can do: in the livelock example of the
//! design notes a global queue cycles 1, 3, 1, 3 and never reaches the marked state, while a local queue
//! runs 1, 3, 4, 1, 2, 4, 1, 3, 1.
//!
//! The random queues draw their order lazily: a round is the set of events not yet taken, and each pick
//! is uniform among the enabled events still in the round (a new round starts when none is). Every event
//! enabled at each visit is thus taken once per round, in a random order, and no permutation is stored.
//!
//! Every policy works on bitsets; only `random-local-queue` reads the chosen plant's out-mask, to start a
//! site's round.

use crate::event_set::EventSet;
use crate::rng::{widening_mul, Entropy, Rng};

/// What a policy may look at besides the enabled set: the plants (the first automata, or the state
/// vector's components), the events each generates, where each is and what it allows there, and the
/// choice sites. `Q` names a plant's state: its position in the supervisor tables
/// ([`crate::table::Position`]), a reading's code in the state tables.
#[derive(Clone, Copy)]
pub struct View<'a, const W: usize, Q> {
    /// The controllable events.
    pub controllable: &'a [u32; W],
    /// Per plant: the controllable events it generates. Every controllable event belongs to one plant.
    pub plant_events: &'a [[u32; W]],
    /// The choice sites: states of a plant where two or more of its controllable events leave.
    pub sites: &'a [Q],
    /// Where every plant (automaton) is: its current state.
    pub records: &'a [Q],
    /// What every plant (automaton) allows in its current state: out-mask or-ed with the events outside
    /// its alphabet.
    pub allowed: &'a [[u32; W]],
}

impl<const W: usize, Q: Copy + Eq> View<'_, W, Q> {
    /// Number of plants.
    fn plants(&self) -> usize {
        self.plant_events.len()
    }

    /// Plant `p`: the controllable events it generates, those of them its current state has
    /// transitions for, and that state (for [`View::site`]).
    fn plant(&self, p: usize) -> Option<(EventSet<W>, EventSet<W>, Q)> {
        let ((generated, allowed), &at) =
            self.plant_events.iter().zip(self.allowed).zip(self.records).nth(p)?;
        let generated = EventSet(*generated);
        Some((generated, generated.and(&EventSet(*allowed)), at))
    }

    /// The index of the choice site `at`, if it is one. A scan: sites are states of the plants, small
    /// automata, so there are few, and the scan beats a binary search's bookkeeping.
    fn site(&self, at: Q) -> Option<usize> {
        self.sites.iter().position(|&s| s == at)
    }
}

/// A choice policy: picks one event of the enabled set, keeping what memory its rule needs.
pub trait Choose<const W: usize> {
    /// Whether the policy reads the plants' states (`View::records` and `View::allowed`): the local
    /// policies do; a decider that must compute them (`crate::state`) skips that for the others.
    const READS_SITES: bool = false;

    /// One event of `enabled`, or `None` when `enabled` is empty.
    fn choose<E: Entropy, Q: Copy + Eq>(
        &mut self,
        view: View<'_, W, Q>,
        enabled: &EventSet<W>,
        rng: &mut Rng<E>,
    ) -> Option<u8>;

    /// Back to the state after boot (on a link reset).
    fn reset(&mut self);
}

/// `first`: the lowest enabled event id.
#[derive(Clone, Debug, Default)]
pub struct First;

impl<const W: usize> Choose<W> for First {
    fn choose<E: Entropy, Q: Copy + Eq>(
        &mut self,
        _: View<'_, W, Q>,
        enabled: &EventSet<W>,
        _: &mut Rng<E>,
    ) -> Option<u8> {
        enabled.first()
    }

    fn reset(&mut self) {}
}

/// `random`: uniform among the enabled events.
#[derive(Clone, Debug, Default)]
pub struct Random;

impl<const W: usize> Choose<W> for Random {
    fn choose<E: Entropy, Q: Copy + Eq>(
        &mut self,
        _: View<'_, W, Q>,
        enabled: &EventSet<W>,
        rng: &mut Rng<E>,
    ) -> Option<u8> {
        pick(enabled, &mut Bits::new(rng))
    }

    fn reset(&mut self) {}
}

/// `global-queue`: the first enabled event at or after the cursor in id order; the cursor moves past it.
#[derive(Clone, Debug, Default)]
pub struct GlobalQueue {
    cursor: u8,
}

impl<const W: usize> Choose<W> for GlobalQueue {
    fn choose<E: Entropy, Q: Copy + Eq>(
        &mut self,
        _: View<'_, W, Q>,
        enabled: &EventSet<W>,
        _: &mut Rng<E>,
    ) -> Option<u8> {
        let c = enabled.next_cyclic(self.cursor)?;
        self.cursor = c.wrapping_add(1);
        Some(c)
    }

    fn reset(&mut self) {
        self.cursor = 0;
    }
}

/// `random-global-queue`: every controllable event once per round, in a random order.
#[derive(Clone, Debug)]
pub struct RandomGlobalQueue<const W: usize> {
    round: EventSet<W>,
}

impl<const W: usize> Default for RandomGlobalQueue<W> {
    fn default() -> Self {
        Self { round: EventSet::EMPTY }
    }
}

impl<const W: usize> Choose<W> for RandomGlobalQueue<W> {
    fn choose<E: Entropy, Q: Copy + Eq>(
        &mut self,
        view: View<'_, W, Q>,
        enabled: &EventSet<W>,
        rng: &mut Rng<E>,
    ) -> Option<u8> {
        let all = EventSet(*view.controllable);
        pick_from_round(&mut self.round, enabled, all, &mut Bits::new(rng))
    }

    fn reset(&mut self) {
        self.round = EventSet::EMPTY;
    }
}

/// `local-queue`: plants in a cyclic order, then a cursor per choice site.
#[derive(Clone, Debug)]
pub struct LocalQueue<const S: usize> {
    plant_cursor: u8,
    cursors: [u8; S],
}

impl<const S: usize> Default for LocalQueue<S> {
    fn default() -> Self {
        Self { plant_cursor: 0, cursors: [0; S] }
    }
}

impl<const W: usize, const S: usize> Choose<W> for LocalQueue<S> {
    const READS_SITES: bool = true;

    fn choose<E: Entropy, Q: Copy + Eq>(
        &mut self,
        view: View<'_, W, Q>,
        enabled: &EventSet<W>,
        _: &mut Rng<E>,
    ) -> Option<u8> {
        let plants = view.plants();
        for i in 0..plants {
            let p = (usize::from(self.plant_cursor) + i) % plants;
            let Some((generated, _, at)) = view.plant(p) else { break };
            let candidates = enabled.and(&generated);
            let c = match view.site(at).and_then(|s| self.cursors.get_mut(s)) {
                Some(cursor) => {
                    let c = candidates.next_cyclic(*cursor);
                    if let Some(c) = c {
                        *cursor = c.wrapping_add(1);
                    }
                    c
                }
                None => candidates.first(),
            };
            if let Some(c) = c {
                self.plant_cursor = u8::try_from((p + 1) % plants).unwrap_or(0);
                return Some(c);
            }
        }
        enabled.first()
    }

    fn reset(&mut self) {
        *self = Self::default();
    }
}

/// `random-local-queue` (the default): a plant drawn uniformly among those with enabled events, then at
/// its choice site the events in a random order per round.
#[derive(Clone, Debug)]
pub struct RandomLocalQueue<const W: usize, const S: usize> {
    rounds: [EventSet<W>; S],
}

impl<const W: usize, const S: usize> Default for RandomLocalQueue<W, S> {
    fn default() -> Self {
        Self { rounds: [EventSet::EMPTY; S] }
    }
}

impl<const W: usize, const S: usize> Choose<W> for RandomLocalQueue<W, S> {
    const READS_SITES: bool = true;

    fn choose<E: Entropy, Q: Copy + Eq>(
        &mut self,
        view: View<'_, W, Q>,
        enabled: &EventSet<W>,
        rng: &mut Rng<E>,
    ) -> Option<u8> {
        let (mut with_events, mut plant) = (0u32, 1u32);
        for generated in view.plant_events {
            if !enabled.and(&EventSet(*generated)).is_empty() {
                with_events |= plant;
            }
            plant = plant.wrapping_shl(1);
        }
        let mut bits = Bits::new(rng);
        let Some(p) = pick(&EventSet([with_events]), &mut bits) else {
            return enabled.first();
        };
        let Some((generated, offered, at)) = view.plant(usize::from(p)) else {
            return enabled.first();
        };
        let candidates = enabled.and(&generated);
        // The plant's state is a choice site when two or more of its events leave it.
        if !offered.several() {
            return candidates.first();
        }
        // Two or more events leave: a site of the table (a table without it falls back to the first).
        match view.site(at).and_then(|s| self.rounds.get_mut(s)) {
            Some(round) => pick_from_round(round, &candidates, offered, &mut bits),
            None => candidates.first(),
        }
    }

    fn reset(&mut self) {
        *self = Self::default();
    }
}

/// The random bits of one decision's picks: drawn from the generator at the first pick that needs
/// them; a pick among `n` takes the high part of `bits · n` and leaves the low part to the next, so a
/// decision with two picks (plant, then event) draws once.
struct Bits<'r, E> {
    rng: &'r mut Rng<E>,
    bits: Option<u32>,
}

impl<'r, E: Entropy> Bits<'r, E> {
    fn new(rng: &'r mut Rng<E>) -> Self {
        Self { rng, bits: None }
    }

    /// A number in `0..n`.
    fn below(&mut self, n: u32) -> u32 {
        let x = match self.bits {
            Some(bits) => bits,
            None => self.rng.next_u32(),
        };
        let (high, low) = widening_mul(x, n);
        self.bits = Some(low);
        high
    }
}

/// A uniformly drawn event of `set` (no draw when there is nothing to choose).
#[inline(always)]
fn pick<E: Entropy, const W: usize>(set: &EventSet<W>, bits: &mut Bits<'_, E>) -> Option<u8> {
    if set.several() {
        set.nth(bits.below(set.len()))
    } else {
        set.first()
    }
}

/// Draws from `candidates ∩ round` (starting a new round, `all`, when that is empty) and takes the drawn
/// event out of the round.
fn pick_from_round<E: Entropy, const W: usize>(
    round: &mut EventSet<W>,
    candidates: &EventSet<W>,
    all: EventSet<W>,
    bits: &mut Bits<'_, E>,
) -> Option<u8> {
    let mut pool = candidates.and(round);
    if pool.is_empty() {
        *round = all;
        pool = *candidates;
    }
    let c = pick(&pool, bits)?;
    round.remove(c);
    Some(c)
}
