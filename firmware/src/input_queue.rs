//! The input buffer between the receive interrupt and the decision loop: a lock-free single-producer,
//! single-consumer byte queue that never loses an event silently.
//!
//! The interrupt owns an [`InputProducer`], the loop an [`InputConsumer`]. When the queue is full,
//! [`InputProducer::push`] hands the byte back; the interrupt then calls
//! [`InputProducer::count_overflow`], and the loop sees the count through [`InputConsumer::overflows`]
//! (the reference tool's 256-slot ring wraps and overwrites without a trace).
//!
//! # Examples
//!
//! ```
//! use firmware::input_queue::InputQueue;
//!
//! // `N` slots hold `N - 1` bytes.
//! let mut q = InputQueue::<3>::new();
//! let (mut tx, mut rx) = q.split();
//! assert_eq!(tx.push(1), Ok(()));
//! assert_eq!(tx.push(2), Ok(()));
//! assert_eq!(tx.push(3), Err(3));
//! tx.count_overflow();
//! assert_eq!(rx.pop(), Some(1));
//! assert_eq!(rx.overflows(), 1);
//! ```

use core::sync::atomic::{AtomicU32, Ordering};
use heapless::spsc::{Consumer, Producer, Queue};

/// A queue of `N` slots holding at most `N - 1` link bytes, plus the count of bytes it had to refuse.
pub struct InputQueue<const N: usize> {
    queue: Queue<u8, N>,
    overflows: AtomicU32,
}

/// The interrupt's end of an [`InputQueue`].
pub struct InputProducer<'q> {
    inner: Producer<'q, u8>,
    overflows: &'q AtomicU32,
}

/// The decision loop's end of an [`InputQueue`].
pub struct InputConsumer<'q> {
    inner: Consumer<'q, u8>,
    overflows: &'q AtomicU32,
}

impl<const N: usize> InputQueue<N> {
    /// An empty queue; `const` so it can live in a `static` or an RTIC local.
    pub const fn new() -> Self {
        Self { queue: Queue::new(), overflows: AtomicU32::new(0) }
    }

    /// The two ends: one for the interrupt, one for the loop.
    pub fn split(&mut self) -> (InputProducer<'_>, InputConsumer<'_>) {
        let (inner_tx, inner_rx) = self.queue.split();
        (
            InputProducer { inner: inner_tx, overflows: &self.overflows },
            InputConsumer { inner: inner_rx, overflows: &self.overflows },
        )
    }
}

impl<const N: usize> Default for InputQueue<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl InputProducer<'_> {
    /// Appends `byte`, or hands it back when the queue is full.
    pub fn push(&mut self, byte: u8) -> Result<(), u8> {
        self.inner.enqueue(byte)
    }

    /// Whether a push would succeed now (the interrupt masks its source while this is false).
    pub fn has_room(&self) -> bool {
        self.inner.ready()
    }

    /// Counts one byte lost to a full queue. Only the producer writes the count, so a load and a
    /// store suffice (also on cores without atomic read-modify-write, such as the Cortex-M0+).
    pub fn count_overflow(&mut self) {
        let n = self.overflows.load(Ordering::Relaxed);
        self.overflows.store(n.wrapping_add(1), Ordering::Relaxed);
    }
}

impl InputConsumer<'_> {
    /// The oldest byte, if any.
    pub fn pop(&mut self) -> Option<u8> {
        self.inner.dequeue()
    }

    /// Whether the queue holds no byte.
    pub fn is_empty(&self) -> bool {
        !self.inner.ready()
    }

    /// Bytes refused because the queue was full, since the queue was made.
    pub fn overflows(&self) -> u32 {
        self.overflows.load(Ordering::Relaxed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fifo_order_and_overflow_count_across_wraps() {
        let mut q = InputQueue::<5>::new();
        let (mut tx, mut rx) = q.split();
        let mut expected = std::collections::VecDeque::new();
        let mut lost = 0;
        for round in 0..20u8 {
            for i in 0..(round % 7) {
                let b = round.wrapping_mul(11).wrapping_add(i);
                match tx.push(b) {
                    Ok(()) => expected.push_back(b),
                    Err(back) => {
                        assert_eq!(back, b);
                        tx.count_overflow();
                        lost += 1;
                    }
                }
            }
            assert_eq!(tx.has_room(), expected.len() < 4);
            for _ in 0..(round % 3) {
                assert_eq!(rx.pop(), expected.pop_front());
            }
            assert_eq!(rx.is_empty(), expected.is_empty());
        }
        assert!(lost > 0);
        assert_eq!(rx.overflows(), lost);
    }
}
