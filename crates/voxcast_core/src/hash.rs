//! The integer hash behind jitter: reproducible bit for bit on the CPU and in WGSL.
//!
//! Twin: `shaders/step.wgsl` (`pcg_hash`, `jitter_fraction`).
//!
//! PCG-RXS-M-XS on 32 bits (Jarzynski & Olano, "Hash Functions for GPU Rendering", JCGT 2020):
//! only wrapping `u32` multiplies, adds, shifts and xors, which WGSL defines exactly as Rust does.

/// One round of the PCG hash.
#[inline(always)]
pub fn pcg_hash(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// A fraction in `[0, 1)` for pixel `(x, y)` and `seed`: the top 24 bits of the hash, so the
/// conversion to `f32` is exact.
#[inline(always)]
pub fn jitter_fraction(x: u32, y: u32, seed: u32) -> f32 {
    let h = pcg_hash(x ^ pcg_hash(y ^ pcg_hash(seed)));
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_values_pin_the_algorithm() {
        // Fixed by this implementation; the WGSL twin is tested against the same numbers.
        assert_eq!(pcg_hash(0), 129_708_002);
        assert_eq!(pcg_hash(1), 2_831_084_092);
    }

    #[test]
    fn fractions_are_in_range_and_spread() {
        let mut sum = 0.0f64;
        let n = 10_000;
        for i in 0..n {
            let f = jitter_fraction(i % 100, i / 100, 7);
            assert!((0.0..1.0).contains(&f));
            sum += f as f64;
        }
        assert!((sum / n as f64 - 0.5).abs() < 0.02);
    }
}
