//! Editing a transfer function as the sandbox's editor does: add a point on the curve, move,
//! recolour or delete one, and find the point under the pointer. Each edit returns a new,
//! validated function (the old one is kept on error), and every index it returns is the
//! point's place after sorting.

use crate::error::SettingsError;
use crate::transfer::{ControlPoint, TransferFunction};

impl TransferFunction {
    /// A point at `value` with opacity `alpha` and the colour the function already has there.
    /// Returns the function and the new point's index.
    pub fn with_point_added(&self, value: f32, alpha: f32) -> Result<(Self, usize), SettingsError> {
        let c = self.evaluate(value);
        let point = ControlPoint::new(value, [c.x, c.y, c.z], alpha.clamp(0.0, 1.0));
        let mut points = self.points().to_vec();
        // Inserted after any point at the same value, so sorting keeps it last among them.
        let at = points.partition_point(|p| p.value <= value);
        points.insert(at, point);
        Ok((Self::new(self.name.clone(), points)?, at))
    }

    /// Point `index` moved to `value` with opacity `alpha` (clamped to [0, 1]). It may pass its
    /// neighbours; the returned index is where it lands.
    pub fn with_point_moved(
        &self,
        index: usize,
        value: f32,
        alpha: f32,
    ) -> Result<(Self, usize), SettingsError> {
        let mut points = self.points().to_vec();
        let Some(p) = points.get(index).copied() else {
            return Err(no_point(index, points.len()));
        };
        points.remove(index);
        let moved = ControlPoint::new(value, p.color, alpha.clamp(0.0, 1.0));
        let at = points.partition_point(|q| q.value <= value);
        points.insert(at, moved);
        Ok((Self::new(self.name.clone(), points)?, at))
    }

    /// Point `index` with another colour (each channel in [0, 1]).
    pub fn with_point_color(&self, index: usize, color: [f32; 3]) -> Result<Self, SettingsError> {
        let mut points = self.points().to_vec();
        let n = points.len();
        let p = points.get_mut(index).ok_or_else(|| no_point(index, n))?;
        p.color = color;
        Self::new(self.name.clone(), points)
    }

    /// Point `index` removed; the last point cannot be.
    pub fn with_point_removed(&self, index: usize) -> Result<Self, SettingsError> {
        let mut points = self.points().to_vec();
        if index >= points.len() {
            return Err(no_point(index, points.len()));
        }
        if points.len() == 1 {
            return Err(SettingsError::Invalid(
                "a transfer function keeps at least one control point".into(),
            ));
        }
        points.remove(index);
        Self::new(self.name.clone(), points)
    }

    /// The point nearest to `(value, alpha)` within `radius`, distances measured with value
    /// scaled by `value_scale` (so value and opacity count alike on screen).
    pub fn point_near(
        &self,
        value: f32,
        alpha: f32,
        value_scale: f32,
        radius: f32,
    ) -> Option<usize> {
        self.points()
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let dv = (p.value - value) * value_scale;
                let da = p.alpha - alpha;
                (i, (dv * dv + da * da).sqrt())
            })
            .filter(|(_, d)| *d <= radius)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| i)
    }
}

fn no_point(index: usize, len: usize) -> SettingsError {
    SettingsError::Invalid(format!("no control point {index} (the function has {len})"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn tf() -> TransferFunction {
        TransferFunction::new(
            "t",
            vec![
                ControlPoint::new(0.0, [0.0, 0.0, 1.0], 0.0),
                ControlPoint::new(50.0, [1.0, 0.0, 0.0], 0.5),
                ControlPoint::new(100.0, [1.0, 1.0, 1.0], 1.0),
            ],
        )
        .unwrap()
    }

    proptest! {
        /// A point added on the curve (at the curve's own opacity) changes nothing.
        #[test]
        fn adding_a_point_on_the_curve_keeps_the_function(v in -20.0f32..120.0, probe in -20.0f32..120.0) {
            let t = tf();
            let a = t.evaluate(v).w;
            let (added, i) = t.with_point_added(v, a).unwrap();
            prop_assert_eq!(added.points().len(), 4);
            prop_assert_eq!(added.points()[i].value, v);
            let (before, after) = (t.evaluate(probe), added.evaluate(probe));
            prop_assert!((before - after).abs().max_element() < 1e-4, "{} vs {}", before, after);
        }

        /// Moving keeps the points sorted and the moved point's colour; the index follows it.
        #[test]
        fn moving_keeps_order_and_colour(i in 0usize..3, v in -50.0f32..150.0, a in -1.0f32..2.0) {
            let t = tf();
            let (m, j) = t.with_point_moved(i, v, a).unwrap();
            let p = m.points()[j];
            prop_assert_eq!(p.value, v);
            prop_assert_eq!(p.alpha, a.clamp(0.0, 1.0));
            prop_assert_eq!(p.color, t.points()[i].color);
            prop_assert!(m.points().windows(2).all(|w| w[0].value <= w[1].value));
        }
    }

    #[test]
    fn recolouring_and_deleting() {
        let t = tf().with_point_color(1, [0.0, 1.0, 0.0]).unwrap();
        assert_eq!(t.points()[1].color, [0.0, 1.0, 0.0]);
        assert!(t.with_point_color(1, [2.0, 0.0, 0.0]).is_err());
        assert!(t.with_point_color(7, [0.0; 3]).is_err());
        let one = t
            .with_point_removed(0)
            .unwrap()
            .with_point_removed(0)
            .unwrap();
        assert_eq!(one.points().len(), 1);
        assert!(one.with_point_removed(0).is_err(), "the last point stays");
        assert!(tf().with_point_moved(3, 0.0, 0.0).is_err());
        assert!(tf().with_point_moved(0, f32::NAN, 0.0).is_err());
    }

    #[test]
    fn finds_the_nearest_point_within_reach() {
        let t = tf();
        // Value scale 1/100: the whole range counts as much as full opacity.
        assert_eq!(t.point_near(52.0, 0.48, 0.01, 0.05), Some(1));
        assert_eq!(t.point_near(75.0, 0.75, 0.01, 0.05), None);
        assert_eq!(t.point_near(98.0, 0.9, 0.01, 0.2), Some(2));
    }
}
