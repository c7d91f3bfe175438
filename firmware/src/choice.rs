//! The six choice policies of the runtime: which one controllable event to fire when the supervisors
//! leave several enabled.
//!
//! | policy | RAM | rule |
//! |---|---|---|
//! | [`First`] | 0 | lowest enabled event id (PLC rung order) |
//! | [`Random`] | 0 (uses the runtime's generator) | uniform among the enabled |
//! | [`GlobalQueue`] | 1 B | one cursor over all controllable events in id order |
//! | [`RandomGlobalQueue`] | 4·W B | a random order of all controllable events per round |
//! | [`LocalQueue`] | 1 + S B | a cursor per choice site |
//! | [`RandomLocalQueue`] | 4 + 4·S B | a random order per choice site and round |
//!
//! W is the word count of an event bitset, S the number of choice sites with two or more controllable
//! out-events ([`crate::table::SupervisorSet::sites`]); a site with one such event needs no memory.
//!
//! A *choice site* is a state of the plant that owns the event. The local policies first pick a plant
//! among those that own an enabled event (cyclically, or in a random order per round), then the plant's
//! current state picks among its own enabled events, in the order its transition records list them. So a
//! choice made in one place never starves another, which a single global cursor can do: in the livelock
//! example of the design notes a global queue cycles 1, 3, 1, 3 and never reaches the marked state, while a
//! local queue runs 1, 3, 4, 1, 2, 4, 1, 3, 1.
//!
//! The random queues draw their order lazily: a round is the set of events not yet taken, and each pick
//! is uniform among the enabled events still in the round (a new round starts when none is). Every
//! event enabled at each visit is thus taken once per round, in a random order, and no permutation has
//! to be stored.

use crate::event_set::EventSet;
use crate::rng::{Entropy, Rng};
use crate::table::{SupervisorSet, MAX_SITE_EVENTS, NO_OWNER};

/// What a policy may look at: the tables and the automata's current states.
#[derive(Clone, Copy)]
pub struct View<'a> {
    /// The tables.
    pub set: &'a SupervisorSet,
    /// Current state offset of every automaton.
    pub states: &'a [u16],
}

/// A choice policy.
pub trait Policy<const W: usize> {
    /// One event of `enabled` (non-empty), or `None` when `enabled` is empty.
    fn choose<E: Entropy>(&mut self, view: View<'_>, enabled: &EventSet<W>, rng: &mut Rng<E>) -> Option<u8>;

    /// Back to the state after boot (on a link reset).
    fn reset(&mut self);
}

/// `first`: the lowest enabled event id.
#[derive(Clone, Debug, Default)]
pub struct First;

impl<const W: usize> Policy<W> for First {
    fn choose<E: Entropy>(&mut self, _: View<'_>, enabled: &EventSet<W>, _: &mut Rng<E>) -> Option<u8> {
        enabled.first()
    }

    fn reset(&mut self) {}
}

/// `random`: uniform among the enabled events.
#[derive(Clone, Debug, Default)]
pub struct Random;

impl<const W: usize> Policy<W> for Random {
    fn choose<E: Entropy>(&mut self, _: View<'_>, enabled: &EventSet<W>, rng: &mut Rng<E>) -> Option<u8> {
        enabled.nth(rng.below(enabled.len()))
    }

    fn reset(&mut self) {}
}

/// `global-queue`: the first enabled event at or after the cursor in id order; the cursor moves past it.
#[derive(Clone, Debug, Default)]
pub struct GlobalQueue {
    cursor: u8,
}

impl<const W: usize> Policy<W> for GlobalQueue {
    fn choose<E: Entropy>(&mut self, _: View<'_>, enabled: &EventSet<W>, _: &mut Rng<E>) -> Option<u8> {
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

impl<const W: usize> Policy<W> for RandomGlobalQueue<W> {
    fn choose<E: Entropy>(&mut self, view: View<'_>, enabled: &EventSet<W>, rng: &mut Rng<E>) -> Option<u8> {
        let mut candidates = enabled.and(&self.round);
        if candidates.is_empty() {
            self.round = EventSet::from_words(view.set.controllable).unwrap_or(EventSet::EMPTY);
            candidates = *enabled;
        }
        let c = candidates.nth(rng.below(candidates.len()))?;
        self.round.remove(c);
        Some(c)
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

impl<const W: usize, const S: usize> Policy<W> for LocalQueue<S> {
    fn choose<E: Entropy>(&mut self, view: View<'_>, enabled: &EventSet<W>, _: &mut Rng<E>) -> Option<u8> {
        let plants = view.set.plant_count();
        for i in 0..plants {
            let p = (usize::from(self.plant_cursor) + i) % plants;
            let site = SiteEvents::at(view, p, enabled);
            if site.enabled == 0 {
                continue;
            }
            let k = match site.slot.and_then(|s| self.cursors.get_mut(s)) {
                Some(cursor) => {
                    let k = first_cyclic(site.enabled, *cursor);
                    *cursor = if k + 1 >= site.count { 0 } else { k + 1 };
                    k
                }
                None => site.enabled.trailing_zeros() as u8,
            };
            self.plant_cursor = u8::try_from((p + 1) % plants).unwrap_or(0);
            return site.event(k);
        }
        enabled.first()
    }

    fn reset(&mut self) {
        *self = Self::default();
    }
}

/// `random-local-queue` (the default): plants in a random order per round, then at each choice site its
/// events in a random order per round.
#[derive(Clone, Debug)]
pub struct RandomLocalQueue<const S: usize> {
    plant_round: u32,
    rounds: [u32; S],
}

impl<const S: usize> Default for RandomLocalQueue<S> {
    fn default() -> Self {
        Self { plant_round: 0, rounds: [0; S] }
    }
}

impl<const W: usize, const S: usize> Policy<W> for RandomLocalQueue<S> {
    fn choose<E: Entropy>(&mut self, view: View<'_>, enabled: &EventSet<W>, rng: &mut Rng<E>) -> Option<u8> {
        let plants = view.set.plant_count().min(32);
        let mut with_events = 0u32;
        for p in 0..plants {
            if SiteEvents::at(view, p, enabled).enabled != 0 {
                with_events |= 1 << p;
            }
        }
        if with_events == 0 {
            return enabled.first();
        }
        let p = pick_from_round(&mut self.plant_round, with_events, all_below(plants), rng);
        let site = SiteEvents::at(view, usize::from(p), enabled);
        let k = match site.slot.and_then(|s| self.rounds.get_mut(s)) {
            Some(round) => pick_from_round(round, site.enabled, all_below(usize::from(site.count)), rng),
            None => pick_bit(site.enabled, rng),
        };
        site.event(k)
    }

    fn reset(&mut self) {
        *self = Self::default();
    }
}

/// The owned controllable out-events of one plant's current state.
struct SiteEvents {
    /// Transition records of the state.
    records: &'static [u8],
    /// Owner table, to skip events the plant does not own.
    owner: &'static [u8],
    plant: u8,
    /// How many owned controllable out-events the state has (at most [`MAX_SITE_EVENTS`] counted).
    count: u8,
    /// Bit `k`: the `k`-th of them is enabled.
    enabled: u32,
    /// The site's index in the site table, when it has two or more.
    slot: Option<usize>,
}

impl SiteEvents {
    fn at<const W: usize>(view: View<'_>, plant: usize, enabled: &EventSet<W>) -> Self {
        let (set, owner) = (view.set, view.set.owner);
        let state = view.states.get(plant).copied().unwrap_or(0);
        let records = set.automata.get(plant).map_or(&[][..], |a| a.records(state));
        let plant = u8::try_from(plant).unwrap_or(NO_OWNER);
        let (mut count, mut bits) = (0u8, 0u32);
        for r in records.chunks_exact(3) {
            if owner.get(usize::from(r[0])) == Some(&plant) && usize::from(count) < MAX_SITE_EVENTS {
                if enabled.contains(r[0]) {
                    bits |= 1 << count;
                }
                count += 1;
            }
        }
        let slot = if count >= 2 { set.site(plant, state) } else { None };
        Self { records, owner, plant, count, enabled: bits, slot }
    }

    /// The `k`-th owned controllable out-event.
    fn event(&self, k: u8) -> Option<u8> {
        self.records
            .chunks_exact(3)
            .map(|r| r[0])
            .filter(|&e| self.owner.get(usize::from(e)) == Some(&self.plant))
            .nth(usize::from(k))
    }
}

/// The lowest set bit of `bits` (non-zero) at or after `from`, wrapping around.
fn first_cyclic(bits: u32, from: u8) -> u8 {
    let upper = if from >= 32 { 0 } else { bits & (u32::MAX << from) };
    let b = if upper != 0 { upper } else { bits };
    b.trailing_zeros() as u8
}

/// `n` low bits set.
fn all_below(n: usize) -> u32 {
    if n >= 32 {
        u32::MAX
    } else {
        (1 << n) - 1
    }
}

/// A uniformly drawn set bit of `bits` (non-zero).
fn pick_bit<E: Entropy>(bits: u32, rng: &mut Rng<E>) -> u8 {
    let mut w = bits;
    for _ in 0..rng.below(bits.count_ones()) {
        w &= w - 1;
    }
    w.trailing_zeros() as u8
}

/// Draws from `candidates ∩ round` (refilling `round` with `all` when that is empty) and takes the drawn
/// bit out of the round.
fn pick_from_round<E: Entropy>(round: &mut u32, candidates: u32, all: u32, rng: &mut Rng<E>) -> u8 {
    let mut pool = candidates & *round;
    if pool == 0 {
        *round = all;
        pool = candidates;
    }
    let k = pick_bit(pool, rng);
    *round &= !(1 << k);
    k
}
