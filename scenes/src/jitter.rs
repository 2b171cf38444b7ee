//! The scenes' one source of randomness: a tiny deterministic generator for
//! drop-position jitter (xorshift64* seeded through splitmix64, so seed 0 is fine).
//! No `rand` dependency, and the same seed gives the same scene on every platform.

use rapier3d::math::Real;

/// Uniform jitter in `[-amplitude, amplitude]`.
pub(crate) struct Jitter {
    state: u64,
    amplitude: Real,
}

impl Jitter {
    pub(crate) fn new(seed: u64, amplitude: Real) -> Self {
        let mut z = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        Jitter {
            state: if z == 0 { 0x2545_F491_4F6C_DD1D } else { z },
            amplitude,
        }
    }

    fn next_u64(&mut self) -> u64 {
        let mut x = self.state;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.state = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// The next jitter value.
    pub(crate) fn next(&mut self) -> Real {
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64; // [0, 1)
        ((unit * 2.0 - 1.0) * self.amplitude as f64) as Real
    }
}
