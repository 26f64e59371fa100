//! Compositing: how the samples along a ray become one pixel. Each method is a small pure function.
//!
//! Twin: `shaders/composite.wgsl` (same function names).
//!
//! Notation (thesis §2.2.4, lecture "Resampling & Compositing"): sample `n` has colour `c_n` and
//! opacity `α_n`; `C_n`, `O_n` are the composited colour (premultiplied) and opacity after it,
//! `C_0 = 0`, `O_0 = 0`.
//!
//! * **Accumulate, front to back** (the order rays are marched):
//!   `C_n = C_{n−1} + (1 − O_{n−1})·α_n·c_n`, `O_n = O_{n−1} + (1 − O_{n−1})·α_n`.
//!   The thesis (seed 000, §2.2.4) writes `C_n = C_{n−1} + (1 − O_{n−1})·c_n`, with `c_n` the
//!   sample's colour as it stands: read literally, a nearly transparent sample would add its
//!   full colour. Voxcast multiplies by `α_n` — the sample's colour *premultiplied* by its
//!   opacity, the emission–absorption model of Levoy 1988, Engel et al. and VTK — so a sample
//!   adds colour in proportion to the light it stops, and `C_n` stays within `O_n`. The two
//!   agree when the thesis's `c_n` is taken as already premultiplied.
//!   Once `O_n` reaches the cutoff, later samples can change the pixel by at most `1 − O_n`:
//!   early ray termination stops there.
//! * **Accumulate, back to front** (the lecture's order, Levoy 1988): from the last sample to
//!   the first, `C ← C·(1 − α_n) + c_n·α_n`, `O ← O·(1 − α_n) + α_n`. The same image, within float
//!   rounding, but it must visit every sample.
//! * **Opacity correction** (Engel et al., *Real-Time Volume Graphics*, §9.1.3): a transfer
//!   function's `α` is the opacity of a reference path length `Δs_ref`; a sample standing for a
//!   length `Δs` gets `α' = 1 − (1 − α)^(Δs/Δs_ref)`. For constant `α` the transmittance along `L`
//!   is then `(1 − α)^(L/Δs_ref) = e^(−σL)`, `σ = −ln(1 − α)/Δs_ref`: Beer–Lambert, whatever the step.
//! * **Average / Maximum / Minimum** (lecture "Projection schemes"): the mean, largest or
//!   smallest interpolated value of the samples inside the volume, then the transfer function.
//! * **Sum** (RayVis's density volume, seed 002 Listing A.3): `S = Σ v_n·Δs`, every sample's
//!   value times the length it stands for, in voxels (so a ray crossing `n` voxels of value
//!   `v` sums to about `n·v`, whatever the step): additive, like an X-ray that is never
//!   normalised. `S` is clamped to a user range `[a, b]` ([`sum_to_value`]) and that range is
//!   stretched over the transfer function's table, which spans the volume's values: `S = a`
//!   looks up the lowest value, `S = b` the highest. With the inferno preset this is RayVis's view of ray counts.
//! * **First** (the lecture's "distance to first voxel (of value at or above the given value)",
//!   seed 000's First): the first sample whose interpolated value is at or above the target
//!   ([`reaches`]). When it is the ray's first sample the ray hits where it enters the volume;
//!   otherwise the value rose past the target between that sample and the one before, and the
//!   place is refined there ([`crossing_fraction`]), coloured by the transfer function at the
//!   target and shaded: an isosurface. A ray that never reaches the target shows the
//!   background (seed 000 writes `f(0)`, the transfer function at 0; Voxcast leaves the pixel
//!   empty so the background shows, as every other method does where nothing was found).
//!
//! Every method finishes by blending the background under what is not opaque:
//! `pixel = C + (1 − O)·background` ([`blend_background`]).

use glam::Vec3;

/// How the samples along a ray are combined.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Hash,
    serde::Serialize,
    serde::Deserialize,
    schemars::JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Emission–absorption: colours and opacities accumulated front to back.
    #[default]
    Accumulate,
    /// The first sample at or above the target value (an isosurface), shaded.
    First,
    /// The transfer function of the mean value along the ray.
    Average,
    /// The transfer function of the largest value (maximum intensity projection, MIP).
    Maximum,
    /// The transfer function of the smallest value (minimum intensity projection).
    Minimum,
    /// The transfer function of the sum of value × length along the ray, over a user range.
    Sum,
}

impl Method {
    pub const ALL: [Method; 6] = [
        Method::Accumulate,
        Method::First,
        Method::Average,
        Method::Maximum,
        Method::Minimum,
        Method::Sum,
    ];

    /// The GPU's integer code (Rust owns it; the shader receives it as a uniform).
    pub const fn code(self) -> u32 {
        match self {
            Method::Accumulate => 0,
            Method::First => 1,
            Method::Average => 2,
            Method::Maximum => 3,
            Method::Minimum => 4,
            Method::Sum => 5,
        }
    }

    pub const fn name(self) -> &'static str {
        match self {
            Method::Accumulate => "accumulate",
            Method::First => "first",
            Method::Average => "average",
            Method::Maximum => "maximum",
            Method::Minimum => "minimum",
            Method::Sum => "sum",
        }
    }

    /// The method's name in words, as the panel and the levels say it ([`Method::name`] is
    /// its key on the command line and in files); its description starts with it.
    pub const fn title(self) -> &'static str {
        match self {
            Method::Accumulate => "Accumulate",
            Method::First => "First hit",
            Method::Average => "Average",
            Method::Maximum => "Maximum",
            Method::Minimum => "Minimum",
            Method::Sum => "Sum",
        }
    }

    /// The one-line description shown with the method (documented once, reused as tooltip).
    pub const fn doc(self) -> &'static str {
        match self {
            Method::Accumulate => {
                "Accumulate: every sample adds its colour, weighted by its opacity and by what is \
                 still transparent in front of it: C_n = C_{n−1} + (1 − O_{n−1})·α_n·c_n."
            }
            Method::First => {
                "First hit: the first place the value is at or above the target (where it rose past \
                 it, refined between two samples; where the ray enters, if it starts above), \
                 coloured by the transfer function at the target and shaded: an isosurface."
            }
            Method::Average => {
                "Average: the transfer function of the mean value of the samples inside the volume \
                 (like an X-ray)."
            }
            Method::Maximum => {
                "Maximum: the transfer function of the largest value along the ray (maximum \
                 intensity projection): bright structures show through everything."
            }
            Method::Minimum => {
                "Minimum: the transfer function of the smallest value along the ray (minimum \
                 intensity projection): dark cavities show through."
            }
            Method::Sum => {
                "Sum: the value times the length each sample stands for (in voxels), added up \
                 along the ray — RayVis's ray-density view — then stretched from the sum range \
                 over the transfer function: S = Σ v_n·Δs."
            }
        }
    }

    /// Whether the method composites opacities (so opacity correction, early termination,
    /// the cutoff and the order apply); `Err` says why not.
    pub const fn uses_opacity(self) -> Result<(), &'static str> {
        match self {
            Method::Accumulate => Ok(()),
            Method::First => Err("First stops at the first value at or above the target and \
                                   shows its colour: no opacities are composited"),
            Method::Average | Method::Maximum | Method::Minimum | Method::Sum => Err(
                "Average, Maximum, Minimum and Sum project one value per ray and look it up in \
                 the transfer function: no opacities are composited",
            ),
        }
    }

    /// Whether the method uses the sum range; `Err` says why not.
    pub const fn uses_sum_range(self) -> Result<(), &'static str> {
        match self {
            Method::Sum => Ok(()),
            _ => Err("Only Sum adds values up and stretches a range over the transfer function"),
        }
    }

    /// Whether the method uses the target value; `Err` says why not.
    pub const fn uses_target(self) -> Result<(), &'static str> {
        match self {
            Method::First => Ok(()),
            _ => Err("Only First looks for a target value"),
        }
    }

    /// Whether the method shades its samples; `Err` says why not.
    pub const fn uses_shading(self) -> Result<(), &'static str> {
        match self {
            Method::Accumulate | Method::First => Ok(()),
            Method::Average | Method::Maximum | Method::Minimum | Method::Sum => Err(
                "Average, Maximum, Minimum and Sum show the transfer function's colour of the \
                 projected value, unshaded",
            ),
        }
    }

    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| {
            m.name().eq_ignore_ascii_case(s)
                || (s.eq_ignore_ascii_case("mip") && *m == Method::Maximum)
        })
    }
}

/// The order Accumulate visits samples in.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum Order {
    /// From the camera outwards; allows early ray termination.
    #[default]
    FrontToBack,
    /// From the far end towards the camera (Levoy's formulation); visits every sample.
    BackToFront,
}

impl Order {
    /// How the sandbox names the order.
    pub const fn name(self) -> &'static str {
        match self {
            Order::FrontToBack => "front to back",
            Order::BackToFront => "back to front",
        }
    }

    /// One line for tooltips and help.
    pub const fn doc(self) -> &'static str {
        match self {
            Order::FrontToBack => "From the camera outwards; allows early ray termination.",
            Order::BackToFront => {
                "From the far end towards the camera (Levoy's formulation); visits every sample."
            }
        }
    }
}

/// `α' = 1 − (1 − α)^(ds/ds_ref)`: the opacity of a sample standing for path length `ds`
/// when the transfer function's `α` is for `ds_ref`. Exact at α = 0 and α = 1. The steps
/// users pick most — the reference step itself, half of it, twice it — take a square root or
/// a product instead of `powf` (correctly rounded, so never further from the exact value:
/// the profile put `powf` at 4 % of a render).
#[inline(always)]
pub fn correct_opacity(alpha: f32, ds: f32, ds_ref: f32) -> f32 {
    correct_opacity_with(alpha, ds, ds_ref, None)
}

/// [`correct_opacity`] where a render has prepared its whole step's power
/// ([`crate::power::StepPower`], for `e = dt/dt_ref`): a sample whose `ds/ds_ref` is that
/// power is raised by its tables instead of `powf` (at least as close to the exact value).
#[inline(always)]
pub fn correct_opacity_with(
    alpha: f32,
    ds: f32,
    ds_ref: f32,
    whole_step: Option<&crate::power::StepPower>,
) -> f32 {
    if alpha <= 0.0 {
        return 0.0;
    }
    if alpha >= 1.0 {
        return if ds > 0.0 { 1.0 } else { 0.0 };
    }
    let e = ds / ds_ref;
    let keep = 1.0 - alpha;
    if e == 1.0 {
        alpha
    } else if e == 0.5 {
        1.0 - keep.sqrt()
    } else if e == 2.0 {
        1.0 - keep * keep
    } else if let Some(p) = whole_step.filter(|p| p.exponent() == e) {
        1.0 - p.keep_power(keep)
    } else {
        1.0 - keep.powf(e)
    }
}

/// One front-to-back step: `C + (1 − O)·α·c`, `O + (1 − O)·α`.
#[inline(always)]
pub fn accumulate_front_to_back(c: Vec3, o: f32, color: Vec3, alpha: f32) -> (Vec3, f32) {
    let w = (1.0 - o) * alpha;
    (c + color * w, o + w)
}

/// One back-to-front step: `C·(1 − α) + c·α`, `O·(1 − α) + α`.
#[inline(always)]
pub fn accumulate_back_to_front(c: Vec3, o: f32, color: Vec3, alpha: f32) -> (Vec3, f32) {
    (c * (1.0 - alpha) + color * alpha, o * (1.0 - alpha) + alpha)
}

/// `C + (1 − O)·background`: the pixel.
#[inline(always)]
pub fn blend_background(c: Vec3, o: f32, background: Vec3) -> Vec3 {
    c + background * (1.0 - o)
}

/// Whether a value counts as a First hit: at or above `target` (never a NaN).
#[inline(always)]
pub fn reaches(value: f32, target: f32) -> bool {
    value >= target
}

/// Where between two samples the linearly interpolated value equals `target`, as a fraction of
/// the way from `prev` to `cur` (in [0, 1]): `(target − prev) / (cur − prev)`.
#[inline(always)]
pub fn crossing_fraction(prev: f32, cur: f32, target: f32) -> f32 {
    let d = cur - prev;
    if d == 0.0 {
        return 0.0;
    }
    ((target - prev) / d).clamp(0.0, 1.0)
}

/// Sum's table position: the sum `s` clamped to `[a, b]` and stretched over the table's
/// values `[lo, hi]`: `lo + (hi − lo)·clamp((s − a)/(b − a), 0, 1)`. `a < b` (the settings
/// check it); NaN maps to `lo`.
#[inline(always)]
pub fn sum_to_value(s: f32, (a, b): (f32, f32), (lo, hi): (f32, f32)) -> f32 {
    let x = crate::minmax::fmin(crate::minmax::fmax((s - a) / (b - a), 0.0), 1.0);
    lo + (hi - lo) * x
}

/// Running statistics of values along a ray, for Average, Maximum, Minimum and Sum.
///
/// The sum is kept in f64 here; the GPU preview (`shaders/trace.wgsl`, `projection`) adds the
/// same values in the same order in f32. Adding n values of magnitude at most M in f32 is off
/// from the exact sum by at most (n − 1)·u·n·M (u = 2⁻²⁴), so the mean by at most
/// (n − 1)·u·M: for the longest ray of a 1024³ volume at ¼ voxel (7 100 samples) 4·10⁻⁴·M, a
/// tenth of an 8-bit level of a table spread over 0 … M — well inside the preview's agreement
/// (2/255). Sum's value is off by the same share of the largest sum, a tenth of a level where
/// its range reaches that sum (the fitted range does); a range set far narrower than the sums
/// magnifies it. `long_rays_f32_sum_stays_within_its_bound`
/// checks the bound on such rays.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ValueStats {
    pub count: u32,
    pub sum: f64,
    pub max: f32,
    pub min: f32,
}

impl Default for ValueStats {
    fn default() -> Self {
        Self {
            count: 0,
            sum: 0.0,
            max: f32::NEG_INFINITY,
            min: f32::INFINITY,
        }
    }
}

impl ValueStats {
    #[inline(always)]
    pub fn add(&mut self, v: f32) {
        if !v.is_finite() {
            return; // no data: not a value of the ray's
        }
        self.count += 1;
        self.sum += v as f64;
        self.max = self.max.max(v);
        self.min = self.min.min(v);
    }

    /// Adds `n` samples of exactly zero (passed over by Sum's skipping): the same statistics
    /// as adding them one by one.
    pub fn add_zeros(&mut self, n: u32) {
        if n > 0 {
            self.count += n;
            self.max = self.max.max(0.0);
            self.min = self.min.min(0.0);
        }
    }

    /// The mean (`None` before any sample).
    pub fn mean(&self) -> Option<f32> {
        (self.count > 0).then(|| (self.sum / self.count as f64) as f32)
    }

    /// The value `method` projects (`None` for Accumulate/First or before any sample); for
    /// Sum, `ds` is the length each sample stands for, in voxels.
    pub fn projected(&self, method: Method, ds: f32) -> Option<f32> {
        if self.count == 0 {
            return None;
        }
        match method {
            Method::Average => self.mean(),
            Method::Maximum => Some(self.max),
            Method::Minimum => Some(self.min),
            Method::Sum => Some((self.sum * ds as f64) as f32),
            Method::Accumulate | Method::First => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each method's description opens with its name in words (the tooltip names what the
    /// drop-down shows), and no two methods share a name.
    #[test]
    fn each_description_opens_with_the_method_s_title() {
        for m in Method::ALL {
            assert!(m.doc().starts_with(&format!("{}:", m.title())), "{m:?}");
        }
        let titles: std::collections::BTreeSet<_> = Method::ALL.map(Method::title).into();
        assert_eq!(titles.len(), Method::ALL.len());
    }

    /// The GPU's f32 running sum against the core's f64 one on the longest rays a 1024³ volume
    /// gives at ¼ voxel, with values spread over 0 … 255, with one large value first (the
    /// worst order for the small ones after it) and with values that grow along the ray: the
    /// mean differs by no more than the bound in `ValueStats`'s doc, and that bound is under a
    /// tenth of an 8-bit level of a table over the values' range.
    #[test]
    fn long_rays_f32_sum_stays_within_its_bound() {
        let n = 7100usize;
        let m = 255.0f32;
        let u = f32::EPSILON as f64 / 2.0; // 2⁻²⁴
        let bound = (n - 1) as f64 * u * m as f64;
        assert!(bound / m as f64 * 255.0 < 0.11, "{bound}");
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 40) as f32 / (1u64 << 24) as f32
        };
        let rays: Vec<Vec<f32>> = vec![
            (0..n).map(|_| next() * m).collect(),
            std::iter::once(m)
                .chain((1..n).map(|_| next() * 1e-3))
                .collect(),
            (0..n).map(|i| m * i as f32 / n as f32).collect(),
        ];
        for values in rays {
            let mut gpu = 0.0f32;
            let mut core = ValueStats::default();
            for &v in &values {
                gpu += v;
                core.add(v);
            }
            let gpu_mean = gpu as f64 / n as f64;
            let core_mean = core.sum / n as f64;
            assert!(
                (gpu_mean - core_mean).abs() <= bound,
                "{gpu_mean} against {core_mean}: over the bound {bound}"
            );
        }
    }

    #[test]
    fn correction_is_exact_at_the_reference_and_composes() {
        assert_eq!(correct_opacity(0.3, 1.0, 1.0), 0.3);
        // Two half steps equal one full step.
        let h = correct_opacity(0.3, 0.5, 1.0);
        let (_, o) = accumulate_front_to_back(Vec3::ZERO, 0.0, Vec3::ONE, h);
        let (_, o) = accumulate_front_to_back(Vec3::ZERO, o, Vec3::ONE, h);
        assert!((o - 0.3).abs() < 1e-6);
        assert_eq!(correct_opacity(0.0, 3.0, 1.0), 0.0);
        assert_eq!(correct_opacity(1.0, 1e-6, 1.0), 1.0);
        assert_eq!(correct_opacity(1.0, 0.0, 1.0), 0.0);
    }

    /// The square-root and product paths are as close to the exact value (in f64) as `powf`
    /// is, over every opacity the table can give and then some.
    #[test]
    fn the_common_steps_are_as_exact_as_powf() {
        for e in [0.5f32, 1.0, 2.0] {
            for i in 1..20_000 {
                let alpha = i as f32 / 20_000.0;
                let fast = correct_opacity(alpha, e, 1.0);
                let exact = 1.0 - (1.0 - f64::from(alpha)).powf(f64::from(e));
                let slow = 1.0 - (1.0 - alpha).powf(e);
                let err = |v: f32| (f64::from(v) - exact).abs();
                // Within the rounding of the final subtraction either way.
                assert!(
                    err(fast) <= err(slow) + f64::from(f32::EPSILON),
                    "α {alpha} e {e}: {fast} vs powf {slow}, exact {exact}"
                );
                assert!(
                    err(fast) <= 1.5 * f64::from(f32::EPSILON),
                    "α {alpha} e {e}"
                );
            }
        }
    }

    #[test]
    fn both_orders_agree() {
        let samples = [
            (Vec3::new(1.0, 0.0, 0.0), 0.3),
            (Vec3::new(0.0, 1.0, 0.0), 0.5),
            (Vec3::ONE, 0.2),
        ];
        let (mut cf, mut of) = (Vec3::ZERO, 0.0);
        for &(c, a) in &samples {
            (cf, of) = accumulate_front_to_back(cf, of, c, a);
        }
        let (mut cb, mut ob) = (Vec3::ZERO, 0.0);
        for &(c, a) in samples.iter().rev() {
            (cb, ob) = accumulate_back_to_front(cb, ob, c, a);
        }
        assert!((cf - cb).abs().max_element() < 1e-6);
        assert!((of - ob).abs() < 1e-6);
    }

    #[test]
    fn reaching_the_target() {
        assert!(reaches(3.0, 2.0));
        assert!(reaches(2.0, 2.0), "at the target counts");
        assert!(!reaches(1.0, 2.0));
        assert!(!reaches(f32::NAN, 2.0), "no data never hits");
        assert_eq!(crossing_fraction(1.0, 3.0, 2.0), 0.5);
        assert_eq!(crossing_fraction(2.0, 2.0, 2.0), 0.0);
    }

    #[test]
    fn stats_project() {
        let mut s = ValueStats::default();
        assert_eq!(s.projected(Method::Average, 1.0), None);
        assert_eq!(s.projected(Method::Sum, 1.0), None);
        for v in [1.0, 5.0, 3.0] {
            s.add(v);
        }
        assert_eq!(s.projected(Method::Average, 1.0), Some(3.0));
        assert_eq!(s.projected(Method::Maximum, 1.0), Some(5.0));
        assert_eq!(s.projected(Method::Minimum, 1.0), Some(1.0));
        assert_eq!(s.projected(Method::Sum, 0.5), Some(4.5));
        assert_eq!(s.projected(Method::Accumulate, 1.0), None);
        assert_eq!(Method::parse("MIP"), Some(Method::Maximum));
        assert_eq!(Method::parse("Sum"), Some(Method::Sum));
    }

    #[test]
    fn sum_stretches_its_range_over_the_table() {
        let (range, table) = ((10.0, 30.0), (-1.0, 3.0));
        assert_eq!(sum_to_value(10.0, range, table), -1.0);
        assert_eq!(sum_to_value(30.0, range, table), 3.0);
        assert_eq!(sum_to_value(20.0, range, table), 1.0);
        assert_eq!(sum_to_value(-5.0, range, table), -1.0, "clamped below");
        assert_eq!(sum_to_value(1e30, range, table), 3.0, "clamped above");
        assert_eq!(sum_to_value(f32::INFINITY, range, table), 3.0);
        assert_eq!(sum_to_value(f32::NAN, range, table), -1.0);
        for (i, m) in Method::ALL.iter().enumerate() {
            assert_eq!(m.code() as usize, i, "codes are the positions in ALL");
            assert_eq!(m.uses_sum_range().is_ok(), *m == Method::Sum);
        }
    }
}
