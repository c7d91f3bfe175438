//! The random source of the random choice policies: a xorshift32 generator seeded, and periodically
//! reseeded, from an [`Entropy`] source.
//!
//! xorshift32 costs 4 bytes of RAM and a handful of instructions per draw, and every bit of its output
//! varies (the reference tool's 8-bit LCG has a low bit that just alternates, so "random" choice between
//! two events degenerates into a fixed cycle). Draws in a range use the high bits (multiply and shift),
//! never a modulus of the low ones. Every `reseed_every` draws the generator mixes in fresh entropy: on a
//! board, ADC noise and timer jitter; under QEMU, a stream derived from the manifest seed, so runs repeat.
//!
//! # Examples
//!
//! ```
//! use firmware::rng::{Rng, SeedEntropy};
//!
//! let mut rng = Rng::new(SeedEntropy::new(7), 1000);
//! let d = rng.below(6);
//! assert!(d < 6);
//! ```

/// A source of seed material.
pub trait Entropy {
    /// Some bits of entropy (need not be uniform; they are mixed in, not used directly).
    fn entropy(&mut self) -> u32;
}

/// Deterministic entropy from a seed (the manifest's `seed`): a Weyl sequence through the murmur3
/// finaliser, so that the same seed gives the same run (QEMU, host tests). The 64-bit seed is folded to
/// 32 bits: 32-bit arithmetic keeps the reseed small and cheap on a Cortex-M.
#[derive(Clone, Debug)]
pub struct SeedEntropy(u32);

impl SeedEntropy {
    /// The stream of `seed`.
    pub const fn new(seed: u64) -> Self {
        Self(seed as u32 ^ (seed >> 32) as u32)
    }
}

impl Entropy for SeedEntropy {
    fn entropy(&mut self) -> u32 {
        self.0 = self.0.wrapping_add(0x9E37_79B9);
        let mut z = self.0;
        z = (z ^ (z >> 16)).wrapping_mul(0x85EB_CA6B);
        z = (z ^ (z >> 13)).wrapping_mul(0xC2B2_AE35);
        z ^ (z >> 16)
    }
}

/// xorshift32 with periodic reseeding from `E`.
#[derive(Clone, Debug)]
pub struct Rng<E> {
    state: u32,
    draws_left: u16,
    reseed_every: u16,
    entropy: E,
}

/// The state used when mixing would leave xorshift's one fixed point, zero.
const NONZERO: u32 = 0x6D2B_79F5;

impl<E: Entropy> Rng<E> {
    /// A generator seeded from `entropy`, reseeded every `reseed_every` draws (0: never).
    pub fn new(entropy: E, reseed_every: u16) -> Self {
        let mut rng = Self { state: NONZERO, draws_left: reseed_every, reseed_every, entropy };
        rng.reseed();
        rng
    }

    /// Mixes fresh entropy into the state.
    pub fn reseed(&mut self) {
        let mixed = self.state.rotate_left(13) ^ self.entropy.entropy();
        self.state = if mixed == 0 { NONZERO } else { mixed };
        self.draws_left = self.reseed_every;
    }

    /// The next 32 random bits.
    pub fn next_u32(&mut self) -> u32 {
        // One countdown per draw; with no reseeding it just wraps.
        self.draws_left = self.draws_left.wrapping_sub(1);
        if self.draws_left == 0 && self.reseed_every != 0 {
            self.reseed();
        }
        let mut x = self.state;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.state = x;
        x
    }

    /// A number in `0..n` (0 when `n` is 0), from the high bits.
    pub fn below(&mut self, n: u32) -> u32 {
        widening_mul(self.next_u32(), n).0
    }
}

/// `x · n` as its high and low words: a draw in `0..n` is the high word, and the low word is what is
/// left of the draw's randomness for a next one.
#[inline(always)]
pub(crate) fn widening_mul(x: u32, n: u32) -> (u32, u32) {
    // The Cortex-M0/M0+ has no 32 × 32 → 64-bit multiply: the product would be a call to the
    // compiler's 64 × 64 routine. The ranges drawn from (events, plants) all fit 16 bits. Among the ARM
    // targets, the cores without compare-and-swap are the ARMv6-M ones (no build script needed to tell).
    #[cfg(all(target_arch = "arm", not(target_has_atomic = "32")))]
    if let Ok(n) = u16::try_from(n) {
        return by_halves(x, n);
    }
    let product = u64::from(x) * u64::from(n);
    ((product >> 32) as u32, product as u32)
}

/// `x · n` as its high and low words, from 32-bit products only: `x`'s high half times `n`, plus the
/// carry of its low half times `n`. Exact for every `x` and `n`; no sum overflows, as
/// `(2¹⁶ − 1)² + 2¹⁶ − 2 < 2³²`.
#[cfg(any(all(target_arch = "arm", not(target_has_atomic = "32")), test))]
#[inline(always)]
fn by_halves(x: u32, n: u16) -> (u32, u32) {
    let n = u32::from(n);
    let high = ((x >> 16) * n + (((x & 0xFFFF) * n) >> 16)) >> 16;
    (high, x.wrapping_mul(n))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::{prop_assert_eq, proptest};

    /// `x · n` as high and low words, from the 64-bit product.
    fn wide(x: u32, n: u16) -> (u32, u32) {
        let product = u64::from(x) * u64::from(n);
        ((product >> 32) as u32, product as u32)
    }

    proptest! {
        #[test]
        fn the_product_by_halves_is_the_wide_product(x: u32, n: u16) {
            prop_assert_eq!(by_halves(x, n), wide(x, n));
        }
    }

    #[test]
    fn the_product_by_halves_at_its_extremes() {
        for (x, n) in [(u32::MAX, u16::MAX), (u32::MAX, 1), (0x0001_FFFF, u16::MAX), (0xFFFF_0000, 2), (0, 7)]
        {
            assert_eq!(by_halves(x, n), wide(x, n), "{x:#x} · {n}");
        }
    }

    struct Zero;
    impl Entropy for Zero {
        fn entropy(&mut self) -> u32 {
            NONZERO.rotate_left(13)
        }
    }

    #[test]
    fn same_seed_same_stream_other_seed_other_stream() {
        let a: Vec<u32> = {
            let mut r = Rng::new(SeedEntropy::new(1), 10);
            (0..50).map(|_| r.next_u32()).collect()
        };
        let mut r = Rng::new(SeedEntropy::new(1), 10);
        assert_eq!(a, (0..50).map(|_| r.next_u32()).collect::<Vec<_>>());
        let mut r = Rng::new(SeedEntropy::new(2), 10);
        assert_ne!(a, (0..50).map(|_| r.next_u32()).collect::<Vec<_>>());
    }

    #[test]
    fn entropy_that_cancels_the_state_never_sticks_at_zero() {
        let mut r = Rng::new(Zero, 3);
        assert!((0..20).all(|_| r.next_u32() != 0));
    }

    #[test]
    fn below_is_in_range_and_low_bit_does_not_alternate() {
        let mut r = Rng::new(SeedEntropy::new(3), 100);
        let draws: Vec<u32> = (0..4000).map(|_| r.below(2)).collect();
        assert!(draws.iter().all(|&d| d < 2));
        let ones = draws.iter().filter(|&&d| d == 1).count();
        assert!((1800..2200).contains(&ones), "{ones}");
        assert!(draws.windows(2).any(|w| w[0] == w[1]));
        let mut counts = [0u32; 6];
        for _ in 0..6000 {
            counts[r.below(6) as usize] += 1;
        }
        assert!(counts.iter().all(|&c| (850..1150).contains(&c)), "{counts:?}");
        assert_eq!(r.below(0), 0);
    }
}
