//! The joint histogram of value × gradient magnitude that the value-and-gradient
//! classification's rectangles are drawn over ([`crate::classify::Region`]).
//!
//! Each lattice point counts once, with its value and the magnitude of its central-difference
//! gradient ([`crate::sample::lattice_gradient`], data units per world unit) — the quantities
//! the classification reads at a sample. A boundary between two materials draws an arch from
//! one material's value to the other's, high in gradient between them; each material is a
//! spot at low gradient (Kindlmann and Durkin 1998). On a large volume every `stride`-th point
//! along each axis counts, so that at most `max_points` are read (a frame's work for the
//! sandbox, whatever the volume's size).

use crate::sample::lattice_gradient;
use crate::volume::{Grid, GridVisitor, Volume, Voxel};

/// Counts of lattice points in `bins[0] × bins[1]` bins over values `value` (data units) and
/// gradient magnitudes `gradient` (data units per world unit).
#[derive(Clone, Debug, PartialEq)]
pub struct JointHistogram {
    pub value: [f32; 2],
    pub gradient: [f32; 2],
    /// Bins along value, then along gradient magnitude.
    pub bins: [usize; 2],
    /// Row by row from the lowest gradient: `counts[g·bins[0] + v]`.
    pub counts: Vec<u64>,
    /// Every `stride`-th lattice point along each axis was counted.
    pub stride: usize,
}

impl JointHistogram {
    /// Counts `volume`'s lattice points (every `stride`-th along each axis, the smallest stride
    /// that reads at most `max_points`) into `bins` bins (at least one each way). Points whose
    /// value or gradient holds no data are left out.
    pub fn of(volume: &Volume, bins: [usize; 2], max_points: usize) -> Self {
        let n = volume.voxel_count() as f64;
        let mut stride = 1usize;
        while n / (stride as f64).powi(3) > max_points.max(1) as f64 {
            stride += 1;
        }
        let pairs = volume.visit(Pairs { stride });
        let bins = [bins[0].max(1), bins[1].max(1)];
        let (lo, hi) = volume.value_range();
        let g_hi = pairs.iter().map(|p| p.1).fold(0.0f32, f32::max);
        let value = [lo, if hi > lo { hi } else { lo + 1.0 }];
        let gradient = [0.0, if g_hi > 0.0 { g_hi } else { 1.0 }];
        let mut counts = vec![0u64; bins[0] * bins[1]];
        for &(v, g) in &pairs {
            let (bv, bg) = (bin(v, value, bins[0]), bin(g, gradient, bins[1]));
            counts[bg * bins[0] + bv] += 1;
        }
        Self {
            value,
            gradient,
            bins,
            counts,
            stride,
        }
    }

    /// The count in value bin `v`, gradient bin `g`.
    pub fn count(&self, v: usize, g: usize) -> u64 {
        self.counts[g * self.bins[0] + v]
    }

    /// Each bin's shade in `[0, 1]` on a log scale (`ln(1 + count)`, the fullest bin at 1), in
    /// the order of [`JointHistogram::counts`].
    pub fn shades(&self) -> Vec<f32> {
        let max = self.counts.iter().copied().max().unwrap_or(0);
        let top = (max as f64).ln_1p();
        self.counts
            .iter()
            .map(|&c| {
                if top > 0.0 {
                    ((c as f64).ln_1p() / top) as f32
                } else {
                    0.0
                }
            })
            .collect()
    }
}

/// The bin of `x` among `n` over `[lo, hi]`, the top edge in the last bin.
fn bin(x: f32, [lo, hi]: [f32; 2], n: usize) -> usize {
    let f = (x - lo) / (hi - lo);
    ((f * n as f32) as usize).min(n - 1)
}

/// Collects `(value, |∇f|)` at every `stride`-th lattice point.
struct Pairs {
    stride: usize,
}

impl GridVisitor for Pairs {
    type Output = Vec<(f32, f32)>;

    fn visit<T: Voxel>(self, g: Grid<'_, T>) -> Self::Output {
        let [nx, ny, nz] = g.dims;
        let s = self.stride;
        let mut out = Vec::with_capacity(nx.div_ceil(s) * ny.div_ceil(s) * nz.div_ceil(s));
        for k in (0..nz).step_by(s) {
            for j in (0..ny).step_by(s) {
                for i in (0..nx).step_by(s) {
                    let v = g.to_data(g.raw(i, j, k));
                    let grad = lattice_gradient(&g, [i, j, k]).length();
                    if v.is_finite() && grad.is_finite() {
                        out.push((v, grad));
                    }
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{UVec3, Vec3};

    fn ramp_x(n: u32, spacing: f32) -> Volume {
        // f = 2·i: the gradient is 2 per lattice step, 2/spacing per world unit, everywhere
        // but the two end planes (one-sided differences there are the same 2 per step).
        let data: Vec<f32> = (0..n * n * n).map(|i| 2.0 * (i % n) as f32).collect();
        Volume::new(
            "ramp",
            UVec3::splat(n),
            Vec3::splat(spacing),
            crate::volume::VoxelData::F32(data),
        )
        .unwrap()
    }

    #[test]
    fn a_ramp_is_one_row_at_its_gradient() {
        let h = JointHistogram::of(&ramp_x(8, 0.5), [8, 4], 1 << 20);
        assert_eq!(h.stride, 1);
        assert_eq!(h.value, [0.0, 14.0]);
        assert_eq!(h.gradient, [0.0, 4.0], "2 per step over 0.5 world units");
        // Every point in the top gradient row; each value bin holds one plane of 64 points.
        for v in 0..8 {
            assert_eq!(h.count(v, 3), 64, "value bin {v}");
            for g in 0..3 {
                assert_eq!(h.count(v, g), 0);
            }
        }
        assert_eq!(h.counts.iter().sum::<u64>(), 512);
        let shades = h.shades();
        assert_eq!(shades.iter().cloned().fold(0.0, f32::max), 1.0);
    }

    #[test]
    fn a_large_volume_is_read_with_a_stride() {
        let h = JointHistogram::of(&ramp_x(20, 1.0), [4, 4], 1000);
        assert_eq!(
            h.stride, 2,
            "20³ = 8000 points: every second one along each axis"
        );
        assert_eq!(h.counts.iter().sum::<u64>(), 1000);
    }

    #[test]
    fn a_constant_volume_has_one_bin_and_no_nan() {
        let v = Volume::new(
            "flat",
            UVec3::splat(3),
            Vec3::ONE,
            crate::volume::VoxelData::F32(vec![5.0; 27]),
        )
        .unwrap();
        let h = JointHistogram::of(&v, [0, 0], 100);
        assert_eq!(h.bins, [1, 1]);
        assert_eq!(h.counts, vec![27]);
        assert!(h.value[1] > h.value[0] && h.gradient[1] > h.gradient[0]);
    }
}
