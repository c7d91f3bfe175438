//! Timeouts (the manifest's `[[timers]]`): a timer raises its uncontrollable timeout event `ms`
//! milliseconds after one of its start events unless one of its stop events comes first; a start while
//! it runs restarts it.
//!
//! [`Timers`] holds a bounded set of them, `N` known at compile time, in a fixed array: no heap, no
//! hardware. The loop that owns them tells them every event the runtime took or fired
//! ([`Timers::observe`]) and how much time passed ([`Timers::advance`]); they hand back the timeouts that
//! fell due, in the order they fell due, for the loop to apply as it applies the plant's events. Where
//! time comes from is the application's: a hardware timer's millisecond count on a board, the host's
//! virtual time through the link in a lock-step closed loop (so a run stays a function of its seeds).
//!
//! # Examples
//!
//! ```
//! use firmware::timer::{TimerSpec, Timers};
//!
//! // extend (0) starts it, at_end (1) stops it, ext_timeout (4) after 2 s.
//! static SPECS: [TimerSpec; 1] = [TimerSpec { start: &[0], stop: &[1], timeout: 4, ms: 2000 }];
//! let mut timers = Timers::new(&SPECS);
//! timers.observe(0);
//! let mut raised = [0u8; 1];
//! assert_eq!(timers.advance(1999, &mut raised), 0, "not yet");
//! assert_eq!(timers.advance(1, &mut raised), 1);
//! assert_eq!(raised, [4]);
//! timers.observe(0);
//! timers.observe(1);
//! assert_eq!(timers.advance(5000, &mut raised), 0, "stopped in time");
//! ```

/// One timer: which events start and stop it, the timeout it raises and after how long.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TimerSpec {
    /// Event ids that (re)arm the timer.
    pub start: &'static [u8],
    /// Event ids that disarm it.
    pub stop: &'static [u8],
    /// The timeout's event id.
    pub timeout: u8,
    /// Delay from the last start to the timeout, in ms (a 0 fires at the next [`Timers::advance`]).
    pub ms: u32,
}

/// `N` timers and the time each running one has left.
#[derive(Debug)]
pub struct Timers<const N: usize> {
    specs: &'static [TimerSpec; N],
    /// Per timer, the ms left until its timeout; `None` while idle.
    left: [Option<u32>; N],
}

impl<const N: usize> Timers<N> {
    /// Every timer idle.
    pub const fn new(specs: &'static [TimerSpec; N]) -> Self {
        Self { specs, left: [None; N] }
    }

    /// Every timer idle again (the link's RESET).
    pub fn reset(&mut self) {
        self.left = [None; N];
    }

    /// The runtime took or fired `event`: a timer it starts runs its full delay from now, a timer it
    /// stops is idle. An event that both starts and stops one (the manifest refuses it) starts it.
    pub fn observe(&mut self, event: u8) {
        for (spec, left) in self.specs.iter().zip(&mut self.left) {
            if spec.start.contains(&event) {
                *left = Some(spec.ms);
            } else if spec.stop.contains(&event) {
                *left = None;
            }
        }
    }

    /// Whether some timer runs.
    pub fn running(&self) -> bool {
        self.left.iter().any(Option::is_some)
    }

    /// The ms until the next timeout, if a timer runs (a host or a board's timer can sleep that long).
    pub fn next_due(&self) -> Option<u32> {
        self.left.iter().flatten().copied().min()
    }

    /// `ms` milliseconds passed: writes the timeouts that fell due into `raised`, earliest first (ties
    /// in timer order), each timer idle after its own, and returns how many. Holds at most `N`; a
    /// `raised` shorter than that keeps the rest due for the next call.
    pub fn advance(&mut self, ms: u32, raised: &mut [u8]) -> usize {
        let mut count = 0;
        while let Some(slot) = raised.get_mut(count) {
            // The earliest due timer within `ms`, first in order among equals.
            let due = self
                .left
                .iter()
                .enumerate()
                .filter_map(|(i, l)| l.filter(|&l| l <= ms).map(|l| (l, i)))
                .min();
            let Some((_, i)) = due else { break };
            if let (Some(left), Some(spec)) = (self.left.get_mut(i), self.specs.get(i)) {
                *left = None;
                *slot = spec.timeout;
                count += 1;
            }
        }
        for l in self.left.iter_mut().flatten() {
            *l -= ms.min(*l);
        }
        count
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    static TWO: [TimerSpec; 2] = [
        TimerSpec { start: &[0], stop: &[1], timeout: 10, ms: 300 },
        TimerSpec { start: &[2], stop: &[1, 3], timeout: 11, ms: 100 },
    ];

    #[test]
    fn timeouts_fall_due_earliest_first_and_a_restart_counts_from_the_restart() {
        let mut t = Timers::new(&TWO);
        let mut raised = [0u8; 2];
        t.observe(0);
        assert_eq!(t.advance(250, &mut raised), 0);
        t.observe(0); // restart: 300 ms from here
        t.observe(2);
        assert_eq!(t.next_due(), Some(100));
        assert_eq!(t.advance(99, &mut raised), 0);
        assert_eq!(t.advance(1, &mut raised), 1);
        assert_eq!(raised[0], 11);
        assert_eq!(t.advance(199, &mut raised), 0, "300 ms after the restart, not after the first start");
        assert_eq!(t.advance(1, &mut raised), 1);
        assert_eq!(raised[0], 10);
        assert!(!t.running());
    }

    #[test]
    fn a_long_step_raises_every_due_timeout_in_order_and_a_stop_disarms() {
        let mut t = Timers::new(&TWO);
        let mut raised = [0u8; 2];
        t.observe(0);
        t.observe(2);
        assert_eq!(t.advance(1000, &mut raised), 2);
        assert_eq!(raised, [11, 10]);
        t.observe(0);
        t.observe(2);
        t.observe(1); // stops both
        assert_eq!(t.advance(1000, &mut raised), 0);
        t.observe(2);
        t.reset();
        assert_eq!(t.advance(1000, &mut raised), 0);
    }

    proptest::proptest! {
        /// Any starts, stops and steps of time on two timers: the timeouts are those of absolute
        /// deadlines (the last start's time + ms, cleared by a stop or the timeout), in deadline order,
        /// ties in timer order.
        #[test]
        fn timeouts_are_the_absolute_deadlines_passed(
            ops in proptest::collection::vec((0u8..5, 0u32..400), 0..60),
        ) {
            let mut t = Timers::new(&TWO);
            let mut deadline: [Option<u64>; 2] = [None; 2];
            let mut now = 0u64;
            for (event, ms) in ops {
                if event < 4 {
                    t.observe(event);
                    for (spec, d) in TWO.iter().zip(&mut deadline) {
                        if spec.start.contains(&event) {
                            *d = Some(now + u64::from(spec.ms));
                        } else if spec.stop.contains(&event) {
                            *d = None;
                        }
                    }
                    continue;
                }
                now += u64::from(ms);
                let mut due: Vec<(u64, usize)> = deadline
                    .iter()
                    .enumerate()
                    .filter_map(|(i, d)| d.filter(|&d| d <= now).map(|d| (d, i)))
                    .collect();
                due.sort_unstable();
                let expected: Vec<u8> = due.iter().map(|&(_, i)| TWO[i].timeout).collect();
                for &(_, i) in &due {
                    deadline[i] = None;
                }
                let mut raised = [0u8; 2];
                let n = t.advance(ms, &mut raised);
                proptest::prop_assert_eq!(&raised[..n], &expected[..]);
                let next = deadline.iter().flatten().map(|&d| (d - now) as u32).min();
                proptest::prop_assert_eq!(t.next_due(), next);
            }
        }
    }

    #[test]
    fn a_short_output_keeps_the_rest_due() {
        let mut t = Timers::new(&TWO);
        let mut one = [0u8; 1];
        t.observe(0);
        t.observe(2);
        assert_eq!(t.advance(500, &mut one), 1);
        assert_eq!(one, [11]);
        assert_eq!(t.advance(0, &mut one), 1, "the other one is still due");
        assert_eq!(one, [10]);
    }
}
