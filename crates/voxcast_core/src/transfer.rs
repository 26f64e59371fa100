//! The transfer function: data value → colour and opacity, and its baked lookup table.
//!
//! Twin: `shaders/transfer.wgsl` (`lut_lookup`).
//!
//! A transfer function is a list of RGBA control points over the data's values (data units),
//! piecewise linear between them and constant beyond the first and last point (VTK's "clamping").
//! Two points at the same value make a step. Opacity `a` is per *reference step* of path length
//! (see [`crate::composite::correct_opacity`]).
//!
//! The renderer never evaluates the control points directly: they are baked once into a
//! [`Lut`] of [`LUT_SIZE`] evenly spaced entries over the volume's value range, and every sample
//! interpolates linearly between two entries. The CPU renderer and the GPU preview read the same
//! table, so they classify identically; a control point between two entries is smoothed by at
//! most one entry's width (1/4095 of the range).

use crate::error::SettingsError;
use glam::{Vec3, Vec4};

/// Entries in a baked lookup table (also the GPU's 1-D texture width; ≤ 8192 on every device).
pub const LUT_SIZE: usize = 4096;

/// One control point: at `value` (data units) the colour is `color` and the opacity `alpha`.
#[derive(
    Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
pub struct ControlPoint {
    pub value: f32,
    /// Linear RGB in [0, 1].
    pub color: [f32; 3],
    /// Opacity per reference step, in [0, 1].
    pub alpha: f32,
}

impl ControlPoint {
    pub fn new(value: f32, color: [f32; 3], alpha: f32) -> Self {
        Self {
            value,
            color,
            alpha,
        }
    }

    pub fn rgba(&self) -> Vec4 {
        Vec4::new(self.color[0], self.color[1], self.color[2], self.alpha)
    }
}

/// A validated, sorted piecewise-linear transfer function.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct TransferFunction {
    pub name: String,
    points: Vec<ControlPoint>,
}

/// A transfer function as its file holds it: a name, and its points sorted by value.
#[derive(serde::Deserialize, schemars::JsonSchema)]
#[schemars(rename = "TransferFunction")]
struct TransferFunctionJson {
    /// What it shows, in words.
    #[serde(default)]
    name: String,
    /// At least one point: a value, the colour (linear RGB, each 0 to 1) and opacity (0 to 1)
    /// it gets; between points both change linearly.
    points: Vec<ControlPoint>,
}

impl schemars::JsonSchema for TransferFunction {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        TransferFunctionJson::schema_name()
    }

    fn json_schema(generator: &mut schemars::SchemaGenerator) -> schemars::Schema {
        TransferFunctionJson::json_schema(generator)
    }
}

impl<'de> serde::Deserialize<'de> for TransferFunction {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let raw = TransferFunctionJson::deserialize(d)?;
        Self::new(raw.name, raw.points).map_err(serde::de::Error::custom)
    }
}

impl TransferFunction {
    /// Validates (at least one point, finite values, channels in [0, 1]) and sorts by value,
    /// keeping the given order of points at equal values.
    pub fn new(
        name: impl Into<String>,
        mut points: Vec<ControlPoint>,
    ) -> Result<Self, SettingsError> {
        if points.is_empty() {
            return Err(SettingsError::Invalid(
                "a transfer function needs at least one control point".into(),
            ));
        }
        for (i, p) in points.iter().enumerate() {
            if !p.value.is_finite() {
                return Err(SettingsError::Invalid(format!(
                    "control point {i}: value {} is not finite",
                    p.value
                )));
            }
            for (c, ch) in p
                .color
                .iter()
                .chain([&p.alpha])
                .zip(["red", "green", "blue", "alpha"])
            {
                if !(0.0..=1.0).contains(c) {
                    return Err(SettingsError::Invalid(format!(
                        "control point {i} at {}: {ch} {c} must lie in [0, 1]",
                        p.value
                    )));
                }
            }
        }
        points.sort_by(|a, b| a.value.total_cmp(&b.value));
        Ok(Self {
            name: name.into(),
            points,
        })
    }

    /// A single colour with a single opacity everywhere.
    pub fn constant(color: [f32; 3], alpha: f32) -> Result<Self, SettingsError> {
        Self::new("constant", vec![ControlPoint::new(0.0, color, alpha)])
    }

    /// A grey ramp from transparent black at `lo` to `alpha_hi`-opaque white at `hi`.
    pub fn ramp(lo: f32, hi: f32, alpha_hi: f32) -> Result<Self, SettingsError> {
        Self::new(
            "ramp",
            vec![
                ControlPoint::new(lo, [0.0; 3], 0.0),
                ControlPoint::new(hi, [1.0; 3], alpha_hi),
            ],
        )
    }

    pub fn points(&self) -> &[ControlPoint] {
        &self.points
    }

    /// Colour and opacity at `value`: linear between the neighbouring points, clamped outside.
    pub fn evaluate(&self, value: f32) -> Vec4 {
        let p = &self.points;
        let first = p[0];
        let last = p[p.len() - 1];
        if value <= first.value {
            return first.rgba();
        }
        if value >= last.value {
            return last.rgba();
        }
        // First point strictly above `value`; its predecessor is at or below.
        let hi = p.partition_point(|c| c.value <= value);
        let (a, b) = (p[hi - 1], p[hi]);
        let t = (value - a.value) / (b.value - a.value);
        a.rgba() + (b.rgba() - a.rgba()) * t
    }

    /// Bakes the table over `[lo, hi]` (the volume's value range; a constant volume gets a
    /// range of width 1 so the table stays well defined).
    pub fn bake(&self, lo: f32, hi: f32) -> Lut {
        let hi = if hi > lo { hi } else { lo + 1.0 };
        let step = (hi - lo) as f64 / (LUT_SIZE - 1) as f64;
        let entries = (0..LUT_SIZE)
            .map(|i| self.evaluate((lo as f64 + i as f64 * step) as f32))
            .collect();
        Lut::from_entries(lo, hi, entries)
    }

    /// Serialises as pretty JSON (the format [`TransferFunction::from_json`] reads).
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("transfer functions always serialise")
    }

    /// Reads Voxcast's transfer-function JSON: `{"name": .., "points": [{"value", "color", "alpha"}]}`.
    pub fn from_json(text: &str) -> Result<Self, SettingsError> {
        serde_json::from_str(text)
            .map_err(|e| SettingsError::Invalid(format!("transfer function: {e}")))
    }
}

/// A baked transfer function: `LUT_SIZE` RGBA entries evenly spaced over `[lo, hi]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Lut {
    pub lo: f32,
    pub hi: f32,
    /// `(LUT_SIZE − 1) / (hi − lo)`: entries per data unit.
    pub scale: f32,
    /// `LUT_SIZE − 1` as a float: the largest position in the table.
    last: f32,
    pub entries: Vec<Vec4>,
    /// For each entry `i`, whether any opacity in `[i, i+1]` is non-zero: used to skip work.
    opaque: Vec<bool>,
    /// `visible_before[i]`: how many of the entries before `i` have non-zero opacity.
    visible_before: Vec<u32>,
}

impl Lut {
    fn from_entries(lo: f32, hi: f32, entries: Vec<Vec4>) -> Self {
        let opaque = (0..entries.len())
            .map(|i| entries[i].w > 0.0 || entries.get(i + 1).is_some_and(|e| e.w > 0.0))
            .collect();
        let mut visible_before = Vec::with_capacity(entries.len() + 1);
        let mut count = 0u32;
        for e in &entries {
            visible_before.push(count);
            count += (e.w > 0.0) as u32;
        }
        visible_before.push(count);
        Self {
            visible_before,
            lo,
            hi,
            scale: (entries.len() - 1) as f32 / (hi - lo),
            last: (entries.len() - 1) as f32,
            entries,
            opaque,
        }
    }

    /// Position of `value` in entries (clamped), split into index and fraction.
    #[inline(always)]
    pub fn locate(&self, value: f32) -> (usize, f32) {
        let x = crate::minmax::fmin(
            crate::minmax::fmax((value - self.lo) * self.scale, 0.0),
            self.last,
        );
        // SAFETY: `fmax` first maps NaN to 0, so x is finite and in [0, LUT_SIZE − 1]: it fits
        // an i32, and as x ≥ 0 truncation is the floor.
        let i = (unsafe { x.to_int_unchecked::<i32>() } as usize).min(self.entries.len() - 2);
        (i, x - i as f32)
    }

    /// Colour (rgb) and opacity (w) at `value`, interpolated linearly between two entries.
    #[inline(always)]
    pub fn lookup(&self, value: f32) -> Vec4 {
        let (i, t) = self.locate(value);
        let a = self.entries[i];
        let b = self.entries[i + 1];
        a + (b - a) * t
    }

    /// Opacity only, with a fast exit where both entries are transparent.
    #[inline(always)]
    pub fn alpha(&self, value: f32) -> f32 {
        self.lookup_if_visible(value).map_or(0.0, |c| c.w)
    }

    /// [`Lut::lookup`], or `None` (without reading the entries) where both entries are fully
    /// transparent.
    #[inline(always)]
    pub fn lookup_if_visible(&self, value: f32) -> Option<Vec4> {
        let (i, t) = self.locate(value);
        if !self.opaque[i] {
            return None;
        }
        let a = self.entries[i];
        Some(a + (self.entries[i + 1] - a) * t)
    }

    /// The colour part of [`Lut::lookup`].
    #[inline(always)]
    pub fn color(&self, value: f32) -> Vec3 {
        self.lookup(value).truncate()
    }

    /// True where every entry is fully transparent: nothing of the volume can be seen.
    pub fn is_empty(&self) -> bool {
        self.entries.iter().all(|e| e.w == 0.0)
    }

    /// The largest opacity of the table for values in `[a, b]` (data units). Public: the
    /// question empty-space skipping asks of a block's range, for a caller's own skipping.
    pub fn max_alpha_in(&self, a: f32, b: f32) -> f32 {
        let (i, _) = self.locate(a.min(b));
        let (j, _) = self.locate(a.max(b));
        self.entries[i..=j + 1]
            .iter()
            .fold(0.0f32, |m, e| m.max(e.w))
    }

    /// Whether any value in `[a, b]` (data units, `a ≤ b`) can have non-zero opacity: every entry
    /// an interpolation there could read is checked, in constant time (empty-space skipping).
    #[inline(always)]
    pub fn any_visible_in(&self, a: f32, b: f32) -> bool {
        self.visible_counts(b).1 > self.visible_counts(a).0
    }

    /// For value `v`: how many entries below the first entry an interpolation at `v` reads have
    /// non-zero opacity, and how many up to and including the last one it reads. A range `[a, b]`
    /// can be visible iff `visible_counts(b).1 > visible_counts(a).0`.
    #[inline(always)]
    pub fn visible_counts(&self, v: f32) -> (u32, u32) {
        let (i, _) = self.locate(v);
        (self.visible_before[i], self.visible_before[i + 2])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tf() -> TransferFunction {
        TransferFunction::new(
            "t",
            vec![
                ControlPoint::new(100.0, [1.0, 0.0, 0.0], 1.0),
                ControlPoint::new(0.0, [0.0, 0.0, 1.0], 0.0),
            ],
        )
        .unwrap()
    }

    #[test]
    fn sorted_piecewise_linear_and_clamped() {
        let t = tf();
        assert_eq!(t.points()[0].value, 0.0);
        assert_eq!(t.evaluate(-5.0), Vec4::new(0.0, 0.0, 1.0, 0.0));
        assert_eq!(t.evaluate(50.0), Vec4::new(0.5, 0.0, 0.5, 0.5));
        assert_eq!(t.evaluate(500.0), Vec4::new(1.0, 0.0, 0.0, 1.0));
    }

    #[test]
    fn steps_at_equal_values() {
        let t = TransferFunction::new(
            "step",
            vec![
                ControlPoint::new(0.0, [0.0; 3], 0.0),
                ControlPoint::new(10.0, [0.0; 3], 0.0),
                ControlPoint::new(10.0, [1.0; 3], 1.0),
                ControlPoint::new(20.0, [1.0; 3], 1.0),
            ],
        )
        .unwrap();
        assert_eq!(t.evaluate(9.999).w, 0.0);
        assert_eq!(t.evaluate(10.0).w, 1.0);
    }

    #[test]
    fn rejects_bad_points() {
        assert!(TransferFunction::new("e", vec![]).is_err());
        assert!(
            TransferFunction::new("n", vec![ControlPoint::new(f32::NAN, [0.0; 3], 0.0)]).is_err()
        );
        assert!(TransferFunction::new("a", vec![ControlPoint::new(0.0, [0.0; 3], 1.5)]).is_err());
        assert!(
            TransferFunction::new("c", vec![ControlPoint::new(0.0, [-0.1, 0.0, 0.0], 0.5)])
                .is_err()
        );
        assert!(TransferFunction::from_json(r#"{"points": []}"#).is_err());
    }

    #[test]
    fn lut_matches_the_function_at_entries_and_between() {
        let t = tf();
        let lut = t.bake(0.0, 100.0);
        for v in [0.0, 12.5, 50.0, 99.9, 100.0, -10.0, 1000.0] {
            let d = (lut.lookup(v) - t.evaluate(v)).abs().max_element();
            assert!(d < 1e-5, "{v}: {d}");
        }
        assert_eq!(lut.alpha(-1.0), 0.0);
        assert!(!lut.is_empty());
        let m = lut.max_alpha_in(0.0, 10.0);
        assert!((0.1..0.1 + 1.0 / 4095.0).contains(&m), "{m}");
        assert!(lut.any_visible_in(0.0, 10.0));
        assert!(lut.any_visible_in(99.0, 100.0));
        // Only entry 0 is transparent; a range reading entries 0 and 1 is visible.
        assert!(lut.any_visible_in(-5.0, 0.0));
        let lut = TransferFunction::ramp(50.0, 100.0, 1.0)
            .unwrap()
            .bake(0.0, 100.0);
        assert!(!lut.any_visible_in(0.0, 49.9));
        assert!(lut.any_visible_in(0.0, 50.1));
    }

    #[test]
    fn json_round_trip() {
        let t = tf();
        let back = TransferFunction::from_json(&t.to_json()).unwrap();
        assert_eq!(t, back);
    }

    #[test]
    fn constant_volume_gets_a_usable_table() {
        let lut = tf().bake(7.0, 7.0);
        assert!(lut.lookup(7.0).is_finite());
    }
}
