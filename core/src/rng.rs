//! SplitMix64, a tiny seeded generator: the same numbers on every platform, no state
//! but one `u64`, no allocation. The tests, examples and tools draw their random
//! fields and rays from it; it is not for anything that needs unpredictable numbers.

/// The SplitMix64 state increment (2⁶⁴ / φ, odd).
pub const GOLDEN: u64 = 0x9E37_79B9_7F4A_7C15;

/// SplitMix64's output function: a bijective 64-bit mix of `z`.
pub const fn mix(z: u64) -> u64 {
    let z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    let z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A SplitMix64 generator: each draw adds [`GOLDEN`] to the state and [`mix`]es it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SplitMix(u64);

impl SplitMix {
    /// A generator for `seed`: its state starts at `seed ^ GOLDEN` (the seeding the
    /// integration tests were calibrated with).
    pub const fn new(seed: u64) -> SplitMix {
        SplitMix(seed ^ GOLDEN)
    }

    /// A generator whose state starts at `state`, as is.
    pub const fn from_state(state: u64) -> SplitMix {
        SplitMix(state)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(GOLDEN);
        mix(self.0)
    }

    /// Uniform in `[0, 1)`: the top 53 bits of [`SplitMix::next_u64`] over 2⁵³.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform integer in `[lo, hi]` (`next_u64` modulo the count).
    pub fn int(&mut self, lo: i64, hi: i64) -> i64 {
        lo + (self.next_u64() % (hi - lo + 1) as u64) as i64
    }

    /// Uniform index below `n` (`next_u64` modulo `n`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// `true` with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    /// `±1`, each with probability ½.
    pub fn sign(&mut self) -> f64 {
        if self.chance(0.5) {
            1.0
        } else {
            -1.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_values() {
        // The reference SplitMix64 sequence from state 0.
        let mut r = SplitMix::from_state(0);
        assert_eq!(r.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(r.next_u64(), 0x6E78_9E6A_A1B9_65F4);
        assert_eq!(SplitMix::new(5), SplitMix::from_state(5 ^ GOLDEN));
        let mut r = SplitMix::new(7);
        assert!((0.0..1.0).contains(&r.unit()));
        assert!((3..=4).contains(&r.int(3, 4)));
        assert!(r.below(3) < 3);
        assert!([1.0, -1.0].contains(&r.sign()));
    }
}
