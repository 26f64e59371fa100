//! Reconstruction: the value and gradient of the volume at any point, from its lattice values.
//!
//! Twin: `shaders/sample.wgsl` (same function names).
//!
//! **Nearest** takes the lattice point closest to `p_voxel` (`floor(x + ½)` per axis, clamped).
//!
//! **Trilinear** interpolation (lecture "Interpolation"; Engel et al., *Real-Time Volume
//! Graphics*, §3.2) blends the 8 lattice points around `p_voxel = (i + tx, j + ty, k + tz)`:
//!
//! ```text
//! f(p) = Σ_{a,b,c ∈ {0,1}} w_abc · f(i+a, j+b, k+c),
//! w_abc = (a ? tx : 1−tx) · (b ? ty : 1−ty) · (c ? tz : 1−tz)
//! ```
//!
//! evaluated as seven nested linear interpolations (x, then y, then z). The weights are
//! non-negative and sum to one, so the result never leaves the range of its corners. Corners are
//! numbered `a + 2b + 4c`; points outside the lattice are clamped onto it (the "clamp to edge" of
//! a GPU texture), and an axis with one lattice point uses that point for both corners.
//!
//! **Gradients** are central differences on the lattice (lecture "Illumination"), one-sided at
//! the borders, interpolated with the same weights as the value:
//!
//! ```text
//! ∂f/∂x (i) = (f(i+1) − f(i−1)) / (2·sx)     inside,
//!             (f(1) − f(0)) / sx, (f(n−1) − f(n−2)) / sx   at the borders, 0 if n = 1.
//! ```
//!
//! Inside the volume this equals the central difference of the *interpolated* field with an
//! offset of exactly one voxel (`(f(p + sx·x̂) − f(p − sx·x̂)) / 2sx`, the thesis's "centralDiff"
//! with Δ = one voxel), because interpolation is linear. Units: data units per world unit.

use crate::volume::{Grid, Voxel};
use glam::Vec3;

/// How the volume is reconstructed between lattice points.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "lowercase")]
pub enum Interpolation {
    /// The closest lattice point's value: blocky, shows the voxels.
    Nearest,
    /// Blend of the 8 surrounding lattice points: smooth.
    #[default]
    Trilinear,
}

/// The cell around a point: lower and upper lattice index per axis and the fractions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cell {
    pub lo: [usize; 3],
    pub hi: [usize; 3],
    /// Position inside the cell per axis, in `[0, 1]`.
    pub t: Vec3,
}

/// Locates `p_voxel` in the lattice (clamped to it).
#[inline(always)]
pub fn cell(dims: [usize; 3], p_voxel: Vec3) -> Cell {
    let mut lo = [0usize; 3];
    let mut hi = [0usize; 3];
    let mut t = Vec3::ZERO;
    for a in 0..3 {
        let n = dims[a];
        let last = (n - 1) as f32;
        // `max` first, so NaN (never produced by the marcher) would land on 0.
        let x = p_voxel[a].max(0.0).min(last);
        let i = (x as usize).min(n.saturating_sub(2));
        lo[a] = i;
        hi[a] = (i + 1).min(n - 1);
        t[a] = x - i as f32;
    }
    Cell { lo, hi, t }
}

/// `a + (b − a)·t`, the one interpolation formula used everywhere (and in the WGSL twin).
#[inline(always)]
pub fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

/// Trilinear interpolation of the raw values at `p_voxel` (raw units; see [`Grid::to_data`]).
#[inline(always)]
pub fn sample_trilinear<T: Voxel>(g: &Grid<'_, T>, p_voxel: Vec3) -> f32 {
    let c = cell(g.dims, p_voxel);
    let sy = g.dims[0];
    let sz = g.dims[0] * g.dims[1];
    let base = c.lo[0] + sy * c.lo[1] + sz * c.lo[2];
    let dx = c.hi[0] - c.lo[0];
    let dy = (c.hi[1] - c.lo[1]) * sy;
    let dz = (c.hi[2] - c.lo[2]) * sz;
    let d = g.data;
    let v = |o: usize| d[base + o].to_f32();
    let x00 = lerp(v(0), v(dx), c.t.x);
    let x10 = lerp(v(dy), v(dy + dx), c.t.x);
    let x01 = lerp(v(dz), v(dz + dx), c.t.x);
    let x11 = lerp(v(dz + dy), v(dz + dy + dx), c.t.x);
    lerp(lerp(x00, x10, c.t.y), lerp(x01, x11, c.t.y), c.t.z)
}

/// The lattice point nearest to `p_voxel` (clamped), as indices.
#[inline(always)]
pub fn nearest_index(dims: [usize; 3], p_voxel: Vec3) -> [usize; 3] {
    let mut out = [0usize; 3];
    for a in 0..3 {
        let last = (dims[a] - 1) as f32;
        out[a] = (p_voxel[a] + 0.5).floor().max(0.0).min(last) as usize;
    }
    out
}

/// The raw value of the nearest lattice point.
#[inline(always)]
pub fn sample_nearest<T: Voxel>(g: &Grid<'_, T>, p_voxel: Vec3) -> f32 {
    let [i, j, k] = nearest_index(g.dims, p_voxel);
    g.raw(i, j, k)
}

/// The reconstructed raw value at `p_voxel` by `interpolation`.
#[inline(always)]
pub fn sample<T: Voxel>(g: &Grid<'_, T>, p_voxel: Vec3, interpolation: Interpolation) -> f32 {
    match interpolation {
        Interpolation::Trilinear => sample_trilinear(g, p_voxel),
        Interpolation::Nearest => sample_nearest(g, p_voxel),
    }
}

/// The central (or one-sided) raw difference along axis `a` at lattice index `idx`, divided by
/// the number of lattice steps it spans (so per voxel); zero on a one-point axis.
#[inline(always)]
fn lattice_difference<T: Voxel>(g: &Grid<'_, T>, idx: [usize; 3], a: usize) -> f32 {
    let n = g.dims[a];
    let lo = idx[a].saturating_sub(1);
    let hi = (idx[a] + 1).min(n - 1);
    if hi == lo {
        return 0.0;
    }
    let mut p = idx;
    let mut m = idx;
    p[a] = hi;
    m[a] = lo;
    (g.raw(p[0], p[1], p[2]) - g.raw(m[0], m[1], m[2])) / (hi - lo) as f32
}

/// The lattice gradient at one lattice point, in data units per world unit.
#[inline(always)]
pub fn lattice_gradient<T: Voxel>(g: &Grid<'_, T>, idx: [usize; 3]) -> Vec3 {
    Vec3::new(
        lattice_difference(g, idx, 0),
        lattice_difference(g, idx, 1),
        lattice_difference(g, idx, 2),
    ) * g.slope
        / g.spacing
}

/// The gradient at `p_voxel`: lattice gradients blended with the trilinear weights (or the
/// nearest lattice point's gradient), in data units per world unit.
#[inline]
pub fn gradient<T: Voxel>(g: &Grid<'_, T>, p_voxel: Vec3, interpolation: Interpolation) -> Vec3 {
    if interpolation == Interpolation::Nearest {
        return lattice_gradient(g, nearest_index(g.dims, p_voxel));
    }
    let c = cell(g.dims, p_voxel);
    let corner = |b: usize| {
        [
            if b & 1 == 0 { c.lo[0] } else { c.hi[0] },
            if b & 2 == 0 { c.lo[1] } else { c.hi[1] },
            if b & 4 == 0 { c.lo[2] } else { c.hi[2] },
        ]
    };
    let mut gc = [Vec3::ZERO; 8];
    for (b, out) in gc.iter_mut().enumerate() {
        *out = lattice_gradient(g, corner(b));
    }
    let lx = |a: Vec3, b: Vec3| a + (b - a) * c.t.x;
    let y0 = lx(gc[0], gc[1]) + (lx(gc[2], gc[3]) - lx(gc[0], gc[1])) * c.t.y;
    let y1 = lx(gc[4], gc[5]) + (lx(gc[6], gc[7]) - lx(gc[4], gc[5])) * c.t.y;
    y0 + (y1 - y0) * c.t.z
}

/// Everything about one reconstruction, for the ray inspector: the 8 corners (lattice indices,
/// values in data units, weights) and the result.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SampleDetail {
    /// Lattice indices of corners `a + 2b + 4c` (for Nearest: the chosen point, weight 1, and
    /// the other seven repeated with weight 0).
    pub corners: [[u32; 3]; 8],
    /// Corner values in data units.
    pub values: [f32; 8],
    /// Interpolation weights, summing to one.
    pub weights: [f32; 8],
    /// Position inside the cell, per axis, in `[0, 1]`.
    pub frac: [f32; 3],
    /// The reconstructed value in data units (identical to what the renderer uses).
    pub value: f32,
}

/// The full breakdown of the reconstruction at `p_voxel`.
pub fn sample_detail<T: Voxel>(
    g: &Grid<'_, T>,
    p_voxel: Vec3,
    interpolation: Interpolation,
) -> SampleDetail {
    let value = g.to_data(sample(g, p_voxel, interpolation));
    let c = cell(g.dims, p_voxel);
    let mut corners = [[0u32; 3]; 8];
    let mut values = [0.0; 8];
    let mut weights = [0.0; 8];
    let near = nearest_index(g.dims, p_voxel);
    for b in 0..8 {
        let idx = match interpolation {
            Interpolation::Trilinear => [
                if b & 1 == 0 { c.lo[0] } else { c.hi[0] },
                if b & 2 == 0 { c.lo[1] } else { c.hi[1] },
                if b & 4 == 0 { c.lo[2] } else { c.hi[2] },
            ],
            Interpolation::Nearest => near,
        };
        corners[b] = [idx[0] as u32, idx[1] as u32, idx[2] as u32];
        values[b] = g.to_data(g.raw(idx[0], idx[1], idx[2]));
        weights[b] = match interpolation {
            Interpolation::Trilinear => {
                let w = |bit: usize, t: f32| if b & bit == 0 { 1.0 - t } else { t };
                w(1, c.t.x) * w(2, c.t.y) * w(4, c.t.z)
            }
            Interpolation::Nearest => {
                if b == 0 {
                    1.0
                } else {
                    0.0
                }
            }
        };
    }
    SampleDetail {
        corners,
        values,
        weights,
        frac: c.t.to_array(),
        value,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid<'a>(data: &'a [f32], dims: [usize; 3]) -> Grid<'a, f32> {
        Grid {
            data,
            dims,
            spacing: Vec3::ONE,
            slope: 1.0,
            intercept: 0.0,
        }
    }

    #[test]
    fn trilinear_reproduces_corners_and_centre() {
        let d: Vec<f32> = (0..8).map(|i| i as f32).collect();
        let g = grid(&d, [2, 2, 2]);
        for b in 0..8 {
            let p = Vec3::new((b & 1) as f32, ((b >> 1) & 1) as f32, ((b >> 2) & 1) as f32);
            assert_eq!(sample_trilinear(&g, p), b as f32);
        }
        assert_eq!(sample_trilinear(&g, Vec3::splat(0.5)), 3.5);
        // Clamped outside.
        assert_eq!(sample_trilinear(&g, Vec3::splat(-3.0)), 0.0);
        assert_eq!(sample_trilinear(&g, Vec3::splat(9.0)), 7.0);
    }

    #[test]
    fn detail_weights_sum_to_one_and_match_the_value() {
        let d: Vec<f32> = (0..27).map(|i| (i * i) as f32).collect();
        let g = grid(&d, [3, 3, 3]);
        let p = Vec3::new(0.3, 1.7, 1.2);
        let s = sample_detail(&g, p, Interpolation::Trilinear);
        assert!((s.weights.iter().sum::<f32>() - 1.0).abs() < 1e-6);
        let by_weights: f32 = s.values.iter().zip(&s.weights).map(|(v, w)| v * w).sum();
        assert!(
            (by_weights - s.value).abs() < 1e-3,
            "{by_weights} vs {}",
            s.value
        );
        assert_eq!(s.corners[0], [0, 1, 1]);
        assert_eq!(s.corners[7], [1, 2, 2]);
    }

    #[test]
    fn nearest_rounds_half_up_and_clamps() {
        let d = [10.0, 20.0, 30.0];
        let g = grid(&d, [3, 1, 1]);
        assert_eq!(sample_nearest(&g, Vec3::new(0.49, 0.0, 0.0)), 10.0);
        assert_eq!(sample_nearest(&g, Vec3::new(0.5, 0.0, 0.0)), 20.0);
        assert_eq!(sample_nearest(&g, Vec3::new(7.0, -4.0, 2.0)), 30.0);
    }

    #[test]
    fn gradient_of_a_linear_field_is_exact_including_borders() {
        // f = 2x − 3y + 0.5z on a 4×3×2 lattice with spacing (0.5, 2, 1).
        let dims = [4, 3, 2];
        let spacing = Vec3::new(0.5, 2.0, 1.0);
        let mut d = vec![];
        for k in 0..2 {
            for j in 0..3 {
                for i in 0..4 {
                    let w = Vec3::new(i as f32, j as f32, k as f32) * spacing;
                    d.push(2.0 * w.x - 3.0 * w.y + 0.5 * w.z);
                }
            }
        }
        let g = Grid {
            data: &d,
            dims,
            spacing,
            slope: 1.0,
            intercept: 0.0,
        };
        for p in [
            Vec3::ZERO,
            Vec3::new(3.0, 2.0, 1.0),
            Vec3::new(1.3, 0.2, 0.9),
        ] {
            let gr = gradient(&g, p, Interpolation::Trilinear);
            assert!(
                (gr - Vec3::new(2.0, -3.0, 0.5)).abs().max_element() < 1e-5,
                "{gr}"
            );
        }
    }

    #[test]
    fn one_point_axes_have_zero_gradient_and_constant_value() {
        let d = [5.0];
        let g = grid(&d, [1, 1, 1]);
        assert_eq!(sample_trilinear(&g, Vec3::new(0.3, -0.2, 0.4)), 5.0);
        assert_eq!(
            gradient(&g, Vec3::ZERO, Interpolation::Trilinear),
            Vec3::ZERO
        );
    }
}
