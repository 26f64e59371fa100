//! `(1 − α)^e` for the opacity correction of the samples that stand for one whole step: a
//! render raises every such sample by the same power `e = dt/dt_ref`, so that power is
//! prepared once, as two small tables and a polynomial, and each sample then costs about
//! twenty instructions instead of a call to the library's `powf` (some sixty, plus the
//! registers saved around the call) — a quarter of a CT render's instructions went there at
//! the default step (0.4785 of the CT's 1 mm reference, no power the square-root and product
//! paths of [`crate::composite::correct_opacity`] know).
//!
//! Method: `keep = 2^(−i) · m` with `m ∈ [1, 2)`; the top [`FRACTION_BITS`] bits of `m`'s
//! fraction pick `c_j`, the midpoint of `m`'s slice of `[1, 2)`, and
//!
//! `keep^e = 2^(−i·e) · c_j^e · (1 + z)^e`, `z = m/c_j − 1`, `|z| ≤ 2⁻⁹`,
//!
//! with `2^(−i·e)` and `c_j^e` from the tables (`f64`, computed by the standard library once
//! a scene) and `(1 + z)^e` by its binomial series `Σ C(e, n)·zⁿ` up to [`DEGREE`]. The
//! result, within a few units in 10¹⁵ of `keep^e` (the series' tail is bounded when the
//! tables are built: [`StepPower::new`] declines a power whose tail would be larger), is
//! rounded once to `f32` — correctly rounded but for a result within about 10⁻¹⁴ of a
//! halfway point, where the library's `powf` (whose own error is near a third of a unit in
//! the last place) is off by one unit about once in 5 000 (the test below counts both).
//!
//! The render's scalar march and its eight lanes call the same function for the same samples,
//! so they still give the same bits; the GPU raises with WGSL's `pow` (its agreement with the
//! CPU is a tolerance, `tests/agreement.rs`).

/// Bits of the fraction that pick a table entry: `2^FRACTION_BITS` entries, `|z| ≤ 2^−(bits+1)`.
pub const FRACTION_BITS: u32 = 8;
const ENTRIES: usize = 1 << FRACTION_BITS;
/// Octaves of `keep` in the table: `1 − α` for `0 < α < 1` in `f32` lies in `[2⁻²⁴, 1]`.
const OCTAVES: usize = 25;
/// Degree of the binomial series for `(1 + z)^e`.
pub const DEGREE: usize = 4;
// `StepPower::keep_power` evaluates the series term by term to this degree (Estrin's scheme).
const _: () = assert!(DEGREE == 4);
/// The largest relative error the series' tail may add (`2⁻⁴⁷`): a power whose tail bound is
/// larger (steps above about five reference steps) is left to `powf`.
const TAIL_BOUND: f64 = 7.105_427_357_601_002e-15;

/// A render's whole-step power `e`, prepared ([`StepPower::keep_power`]).
#[derive(Clone)]
pub struct StepPower {
    e: f32,
    /// `2^(−i·e)` for octave `i`.
    octave: [f64; OCTAVES],
    /// `c_j^e` and `1/c_j` for entry `j`.
    entries: [[f64; 2]; ENTRIES],
    /// `C(e, n)` for `n = 0 ..= DEGREE`.
    series: [f64; DEGREE + 1],
}

impl std::fmt::Debug for StepPower {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StepPower").field("e", &self.e).finish()
    }
}

impl StepPower {
    /// The tables for `e`, or `None` where `e` is not a positive finite number or the series
    /// would not be accurate enough for it (then `powf` raises).
    pub fn new(e: f32) -> Option<Box<Self>> {
        if !(e > 0.0 && e.is_finite()) {
            return None;
        }
        let ef = f64::from(e);
        let mut series = [1.0; DEGREE + 1];
        for n in 1..=DEGREE {
            series[n] = series[n - 1] * (ef - (n - 1) as f64) / n as f64;
        }
        // The Lagrange remainder: |C(e, D+1)|·|z|^(D+1)·(1 + ξ)^(e−D−1), with (1 + ξ) ≥ 1 − |z|.
        let z_max = 0.5f64.powi(FRACTION_BITS as i32 + 1);
        let next = series[DEGREE] * (ef - DEGREE as f64) / (DEGREE + 1) as f64;
        let tail = next.abs()
            * z_max.powi(DEGREE as i32 + 1)
            * (1.0 - z_max).powf((ef - DEGREE as f64 - 1.0).min(0.0));
        if tail.is_nan() || tail > TAIL_BOUND {
            return None;
        }
        let mut power = Box::new(Self {
            e,
            octave: [0.0; OCTAVES],
            entries: [[0.0; 2]; ENTRIES],
            series,
        });
        for (i, o) in power.octave.iter_mut().enumerate() {
            // i·e is exact in f64 (5 bits times 24), so only exp2 rounds.
            *o = (-(i as f64) * ef).exp2();
        }
        for (j, entry) in power.entries.iter_mut().enumerate() {
            let c = 1.0 + (2 * j + 1) as f64 / (2 * ENTRIES) as f64;
            *entry = [c.powf(ef), 1.0 / c];
        }
        Some(power)
    }

    /// The power these tables raise by.
    pub fn exponent(&self) -> f32 {
        self.e
    }

    /// `keep^e`, for `keep ∈ [2⁻²⁴, 1]` (anything else, NaN included, is `powf`'s).
    #[inline(always)]
    pub fn keep_power(&self, keep: f32) -> f32 {
        let bits = keep.to_bits();
        let i = 127u32.wrapping_sub(bits >> 23) as usize;
        if i >= OCTAVES {
            return keep.powf(self.e);
        }
        let [c_e, inv_c] = self.entries[((bits >> (23 - FRACTION_BITS)) as usize) & (ENTRIES - 1)];
        let m = f64::from(f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000));
        let z = m * inv_c - 1.0;
        let s = &self.series;
        let z2 = z * z;
        let series = (s[0] + s[1] * z) + z2 * ((s[2] + s[3] * z) + z2 * s[4]);
        ((self.octave[i] * c_e) * series) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One unit in the last place at `x` (positive).
    fn ulp(x: f32) -> f64 {
        f64::from(f32::from_bits(x.to_bits() + 1)) - f64::from(x)
    }

    /// A deterministic stream of numbers in `[0, 1)`.
    fn stream(mut state: u64) -> impl FnMut() -> f64 {
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn within_an_ulp_of_the_exact_power_and_correctly_rounded_more_often_than_powf() {
        let mut next = stream(0x9e37_79b9_7f4a_7c15);
        let (mut n, mut ours_exact, mut powf_exact) = (0, 0, 0);
        while n < 400_000 {
            // Opacities over eight decades; whole steps from a thousandth to five references.
            let alpha = (10f64.powf(-8.0 * next()) as f32).clamp(6e-8, 0.999_999_9);
            let e = 10f64.powf(-3.0 + 3.7 * next()) as f32;
            let Some(p) = StepPower::new(e) else {
                continue;
            };
            let keep = 1.0 - alpha;
            let exact = f64::from(keep).powf(f64::from(e));
            let ours = p.keep_power(keep);
            let rounded = exact as f32;
            assert!(
                (f64::from(ours) - exact).abs() <= ulp(rounded),
                "keep {keep} e {e}: {ours} against {exact}"
            );
            ours_exact += u32::from(ours == rounded);
            powf_exact += u32::from(keep.powf(e) == rounded);
            n += 1;
        }
        // Measured: 400 000 of 400 000 (the library's powf: 399 919).
        assert!(ours_exact >= 399_990, "{ours_exact} correctly rounded");
        assert!(
            ours_exact >= powf_exact,
            "{ours_exact} against powf's {powf_exact}"
        );
    }

    #[test]
    fn every_octave_and_entry_at_the_default_ct_step() {
        // Both ends of every table slice, at the CT's step (0.4785 reference steps).
        let e = 0.4785;
        let p = StepPower::new(e).expect("a small power");
        for i in 0..OCTAVES as u32 {
            for j in 0..ENTRIES as u32 {
                for low in [0, (1 << (23 - FRACTION_BITS)) - 1] {
                    let bits = ((127 - i) << 23) | (j << (23 - FRACTION_BITS)) | low;
                    let keep = f32::from_bits(bits);
                    if keep > 1.0 {
                        continue;
                    }
                    let exact = f64::from(keep).powf(f64::from(e));
                    assert_eq!(p.keep_power(keep), exact as f32, "keep {keep}");
                }
            }
        }
    }

    #[test]
    fn the_ends() {
        let p = StepPower::new(0.4785).expect("a small power");
        assert_eq!(p.keep_power(1.0), 1.0);
        assert_eq!(p.keep_power(0.5), 0.5f64.powf(0.4785) as f32);
        assert!(p.keep_power(f32::NAN).is_nan());
        assert_eq!(p.keep_power(2.0), 2f32.powf(0.4785), "outside: powf's");
        assert_eq!(p.exponent(), 0.4785);
        for e in [0.0, -1.0, f32::NAN, f32::INFINITY, 1e6] {
            assert!(StepPower::new(e).is_none(), "{e}");
        }
        // Up to some five reference steps the series is accurate enough; beyond, powf.
        assert!(StepPower::new(4.0).is_some());
        assert!(StepPower::new(30.0).is_none());
    }

    #[test]
    fn a_scene_prepares_its_whole_step_where_correction_is_on() {
        use crate::{settings::RenderSettings, step::Length};
        let volume = crate::builtin::shells();
        let tf = crate::transfer::TransferFunction::ramp(0.0, 1.0, 0.5).unwrap();
        let mut settings = RenderSettings {
            step: Length::Voxels(0.4785),
            ..RenderSettings::default()
        };
        let scene = crate::scene::Scene::plain(&volume, &tf, &settings, glam::Vec3::Z).unwrap();
        let p = scene.step_power.as_ref().expect("prepared");
        assert_eq!(p.exponent(), scene.dt / scene.dt_ref);
        // An interior sample takes the tables, one at the ray's end (shorter) powf.
        let alpha = 0.3;
        let whole = crate::composite::correct_opacity_with(alpha, scene.dt, scene.dt_ref, Some(p));
        assert_eq!(whole, 1.0 - p.keep_power(1.0 - alpha));
        let end = crate::composite::correct_opacity_with(alpha, 0.25, scene.dt_ref, Some(p));
        assert_eq!(
            end,
            crate::composite::correct_opacity(alpha, 0.25, scene.dt_ref)
        );
        settings.opacity_correction = false;
        let scene = crate::scene::Scene::plain(&volume, &tf, &settings, glam::Vec3::Z).unwrap();
        assert!(scene.step_power.is_none());
    }
}
