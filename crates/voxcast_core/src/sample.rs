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

use crate::minmax::{fmax, fmin};
use crate::volume::{Grid, Voxel};
use glam::{Vec3, Vec3A, Vec4};

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

/// The cell around a point: lower lattice index per axis and the fractions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cell {
    pub lo: [usize; 3],
    /// Position inside the cell per axis, in `[0, 1]`.
    pub t: Vec3,
}

impl Cell {
    /// The upper lattice index per axis: one above `lo`, or `lo` itself on an axis with one
    /// point (both corners are that point).
    #[inline(always)]
    pub fn hi<T: Voxel>(&self, g: &Grid<'_, T>) -> [usize; 3] {
        [0, 1, 2].map(|a| self.lo[a] + (g.corner_step[a] != 0) as usize)
    }
}

/// Locates `p_voxel` in the lattice (clamped to it).
#[inline(always)]
pub fn cell<T: Voxel>(g: &Grid<'_, T>, p_voxel: Vec3) -> Cell {
    let mut lo = [0usize; 3];
    let mut t = Vec3::ZERO;
    for a in 0..3 {
        // `fmax` first maps NaN to 0 (its comparison is false), so x ∈ [0, n − 1] always.
        let x = fmin(fmax(p_voxel[a], 0.0), g.last[a]);
        // The corner is at most `max_lo` (clamped as a float: the same floor, and cheaper than
        // a clamp of the index). SAFETY: the clamped x is finite and in [0, n − 2] ⊂ [0, 2²⁴]
        // (`MAX_AXIS`), so it fits an i32; and as it is ≥ 0, truncation is the floor.
        let i = unsafe { fmin(x, g.max_lo[a]).to_int_unchecked::<i32>() } as usize;
        lo[a] = i;
        t[a] = x - i as f32;
    }
    Cell { lo, t }
}

/// `a + (b − a)·t`, the one interpolation formula used everywhere (and in the WGSL twin).
#[inline(always)]
pub fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

/// Trilinear interpolation of the raw values at `p_voxel` (raw units; see [`Grid::to_data`]).
#[inline(always)]
pub fn sample_trilinear<T: Voxel>(g: &Grid<'_, T>, p_voxel: Vec3) -> f32 {
    trilinear_in_cell(g, &cell(g, p_voxel))
}

/// Trilinear interpolation inside a located cell (raw units).
#[inline(always)]
pub fn trilinear_in_cell<T: Voxel>(g: &Grid<'_, T>, c: &Cell) -> f32 {
    let [dx, dy, dz] = g.corner_step;
    let base = g.index(c.lo[0], c.lo[1], c.lo[2]);
    // One bounds check for the whole cell: every corner offset is a sum of some of dx, dy, dz.
    let d = &g.data[base..=base + dx + dy + dz];
    // SAFETY: `o` ≤ dx + dy + dz < d.len() for every offset used below.
    let v = |o: usize| unsafe { d.get_unchecked(o) }.to_f32();
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
        // Clamped first, the value is non-negative, so truncation is the floor.
        out[a] = (p_voxel[a] + 0.5).max(0.0).min(last) as i32 as usize;
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

/// The raw difference along axis `a` at lattice index `idx` per lattice step: central inside,
/// one-sided at the borders, zero on a one-point axis.
#[inline(always)]
fn lattice_difference<T: Voxel>(g: &Grid<'_, T>, idx: [usize; 3], a: usize) -> f32 {
    let n = g.dims[a];
    let lo = idx[a].saturating_sub(1);
    let hi = (idx[a] + 1).min(n - 1);
    let inv_steps = match hi - lo {
        0 => return 0.0,
        1 => 1.0,
        _ => 0.5,
    };
    let mut p = idx;
    let mut m = idx;
    p[a] = hi;
    m[a] = lo;
    (g.raw(p[0], p[1], p[2]) - g.raw(m[0], m[1], m[2])) * inv_steps
}

/// Raw units per lattice step → data units per world unit, per axis.
#[inline(always)]
fn gradient_scale<T: Voxel>(g: &Grid<'_, T>) -> Vec3 {
    g.slope / g.spacing
}

/// The lattice gradient at one lattice point, in data units per world unit.
#[inline(always)]
pub fn lattice_gradient<T: Voxel>(g: &Grid<'_, T>, idx: [usize; 3]) -> Vec3 {
    Vec3::new(
        lattice_difference(g, idx, 0),
        lattice_difference(g, idx, 1),
        lattice_difference(g, idx, 2),
    ) * gradient_scale(g)
}

/// The gradient at `p_voxel`: lattice gradients blended with the trilinear weights (or the
/// nearest lattice point's gradient), in data units per world unit.
///
/// Per corner the raw differences (per lattice step) are blended in the same order as
/// [`sample_trilinear`] (x, then y, then z) and scaled to world units at the end. Cells at least
/// one point away from every border take a fast path with one bounds check; it computes the
/// very same numbers (every difference there is central, `× 0.5`).
#[inline]
pub fn gradient<T: Voxel>(g: &Grid<'_, T>, p_voxel: Vec3, interpolation: Interpolation) -> Vec3 {
    if interpolation == Interpolation::Nearest {
        return lattice_gradient(g, nearest_index(g.dims, p_voxel));
    }
    let c = cell(g, p_voxel);
    let interior = (0..3).all(|a| c.lo[a] >= 1 && c.lo[a] + 2 < g.dims[a]);
    let mut gc = [Vec3A::ZERO; 8];
    if interior {
        let sy = g.dims[0];
        let sz = g.dims[0] * g.dims[1];
        let base = c.lo[0] + sy * c.lo[1] + sz * c.lo[2];
        // Every point read lies within one step below and two steps above the cell's corner.
        let first = base - 1 - sy - sz;
        let d = &g.data[first..=base + 2 + 2 * sy + 2 * sz];
        // SAFETY: every offset below is (a + b·sy + c·sz) with a, b, c in −1..=2, so
        // first ≤ base + offset ≤ base + 2 + 2·sy + 2·sz: inside `d`.
        let f = |a: isize, b: isize, c: isize| {
            let i = (base as isize + a + b * sy as isize + c * sz as isize) as usize;
            unsafe { d.get_unchecked(i - first) }.to_f32()
        };
        // The 32 distinct points: the cell's 8 corners and one more on each side along each axis.
        let mut core = [0.0f32; 8];
        for (b, v) in core.iter_mut().enumerate() {
            *v = f(
                (b & 1) as isize,
                ((b >> 1) & 1) as isize,
                ((b >> 2) & 1) as isize,
            );
        }
        for (b, out) in gc.iter_mut().enumerate() {
            let (x, y, z) = (
                (b & 1) as isize,
                ((b >> 1) & 1) as isize,
                ((b >> 2) & 1) as isize,
            );
            // Central differences: the neighbour inside the cell comes from `core`.
            let dx = if x == 0 {
                core[b | 1] - f(-1, y, z)
            } else {
                f(2, y, z) - core[b & !1]
            };
            let dy = if y == 0 {
                core[b | 2] - f(x, -1, z)
            } else {
                f(x, 2, z) - core[b & !2]
            };
            let dz = if z == 0 {
                core[b | 4] - f(x, y, -1)
            } else {
                f(x, y, 2) - core[b & !4]
            };
            *out = Vec3A::new(dx, dy, dz) * 0.5;
        }
    } else {
        let hi = c.hi(g);
        for (b, out) in gc.iter_mut().enumerate() {
            let idx = [
                if b & 1 == 0 { c.lo[0] } else { hi[0] },
                if b & 2 == 0 { c.lo[1] } else { hi[1] },
                if b & 4 == 0 { c.lo[2] } else { hi[2] },
            ];
            *out = Vec3A::new(
                lattice_difference(g, idx, 0),
                lattice_difference(g, idx, 1),
                lattice_difference(g, idx, 2),
            );
        }
    }
    // Four-lane SIMD for the three components; the same operations in the same order as scalar.
    Vec3::from(blend_corner_gradients(&gc, c.t)) * gradient_scale(g)
}

/// One lattice point's record for fast exact gradients and values: its differences per axis,
/// as exact integers — `f(i+1) − f(i−1)` inside, `2·(f(1) − f(0))` and `2·(f(n−1) − f(n−2))` at
/// the borders, 0 on a one-point axis, so that `D·½` is `lattice_difference` exactly — and in
/// the fourth lane its raw value. One 8-byte read of a cell corner gives both, and the value
/// and the gradient are blended together, four lanes at once ([`value_and_gradient_in_cell`]).
pub type Differences = [i16; 4];

/// Every lattice point's [`Differences`], for integer volumes whose values fit `i16` and whose
/// range keeps the differences within it (`max − min ≤ 16383`): gradients then read 8 points
/// instead of 32, and the value comes with them, with the very same result. `None` for float
/// volumes and wider ranges (gradients are then computed directly).
pub fn lattice_differences<T: Voxel>(g: &Grid<'_, T>) -> Option<Vec<Differences>> {
    T::TABLE?;
    let (lo, hi) = g
        .data
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), v| {
            (fmin(a, v.to_f32()), fmax(b, v.to_f32()))
        });
    if hi - lo > 16383.0 || lo < f32::from(i16::MIN) || hi > f32::from(i16::MAX) {
        return None;
    }
    use rayon::prelude::*;
    let [nx, ny, nz] = g.dims;
    // Per axis: the neighbours' indices (clamped) and the factor 2/steps that makes a one-sided
    // difference comparable with a central one; zero on a one-point axis.
    let span = |x: usize, n: usize| {
        let (lo, hi) = (x.saturating_sub(1), (x + 1).min(n - 1));
        (lo, hi, if hi > lo { 2.0 / (hi - lo) as f32 } else { 0.0 })
    };
    let mut out = vec![[0i16; 4]; g.data.len()];
    out.par_chunks_mut(nx)
        .enumerate()
        .for_each(|(row, points)| {
            let (j, k) = (row % ny, row / ny);
            let line = |jj: usize, kk: usize| &g.data[g.index(0, jj, kk)..g.index(0, jj, kk) + nx];
            let (y0, y1, fy) = span(j, ny);
            let (z0, z1, fz) = span(k, nz);
            let (here, ym, yp, zm, zp) = (
                line(j, k),
                line(y0, k),
                line(y1, k),
                line(j, z0),
                line(j, z1),
            );
            for (i, d) in points.iter_mut().enumerate() {
                let (x0, x1, fx) = span(i, nx);
                // Exact: integer differences of at most 2·16383 in magnitude.
                d[0] = ((here[x1].to_f32() - here[x0].to_f32()) * fx) as i16;
                d[1] = ((yp[i].to_f32() - ym[i].to_f32()) * fy) as i16;
                d[2] = ((zp[i].to_f32() - zm[i].to_f32()) * fz) as i16;
                // Exact: the value lies in i16's range (checked above).
                d[3] = here[i].to_f32() as i16;
            }
        });
    Some(out)
}

/// [`gradient`], reading precomputed [`lattice_differences`] (bit for bit the same result).
#[inline(always)]
pub fn gradient_from_differences<T: Voxel>(
    g: &Grid<'_, T>,
    diffs: &[Differences],
    p_voxel: Vec3,
    interpolation: Interpolation,
) -> Vec3 {
    if interpolation == Interpolation::Nearest {
        let [i, j, k] = nearest_index(g.dims, p_voxel);
        let v = difference_vector(&diffs[g.index(i, j, k)]) * 0.5;
        return Vec3::from(v) * gradient_scale(g);
    }
    gradient_in_cell(g, diffs, &cell(g, p_voxel))
}

/// [`gradient_from_differences`] (trilinear) inside a located cell: the march has already
/// found the cell for the value, so the gradient reuses it.
#[inline(always)]
pub fn gradient_in_cell<T: Voxel>(g: &Grid<'_, T>, diffs: &[Differences], c: &Cell) -> Vec3 {
    let [dx, dy, dz] = g.corner_step;
    let base = g.index(c.lo[0], c.lo[1], c.lo[2]);
    let d = &diffs[base..=base + dx + dy + dz];
    // SAFETY: every offset is a sum of some of dx, dy, dz, so below d.len().
    let v = |o: usize| difference_vector(unsafe { d.get_unchecked(o) });
    let gc = [
        v(0),
        v(dx),
        v(dy),
        v(dy + dx),
        v(dz),
        v(dz + dx),
        v(dz + dy),
        v(dz + dy + dx),
    ];
    // Halving the blend instead of each corner is exact: scaling by a power of two commutes
    // with every rounding here (no value comes near the subnormal range).
    Vec3::from(blend_corner_gradients(&gc, c.t) * 0.5) * gradient_scale(g)
}

/// The raw value and the gradient inside a located cell from the [`Differences`] records:
/// bit for bit [`trilinear_in_cell`] and [`gradient_in_cell`] (the same lerps, x then y then
/// z, in four lanes at once: three differences and the value).
#[inline(always)]
pub fn value_and_gradient_in_cell<T: Voxel>(
    g: &Grid<'_, T>,
    diffs: &[Differences],
    c: &Cell,
) -> (f32, Vec3) {
    let [dx, dy, dz] = g.corner_step;
    let base = g.index(c.lo[0], c.lo[1], c.lo[2]);
    let d = &diffs[base..=base + dx + dy + dz];
    // SAFETY: every offset is a sum of some of dx, dy, dz, so below d.len().
    let v = |o: usize| {
        let p = unsafe { d.get_unchecked(o) };
        Vec4::new(p[0] as f32, p[1] as f32, p[2] as f32, p[3] as f32)
    };
    let lx = |a: Vec4, b: Vec4| a + (b - a) * c.t.x;
    let (x00, x10) = (lx(v(0), v(dx)), lx(v(dy), v(dy + dx)));
    let (x01, x11) = (lx(v(dz), v(dz + dx)), lx(v(dz + dy), v(dz + dy + dx)));
    let y0 = x00 + (x10 - x00) * c.t.y;
    let y1 = x01 + (x11 - x01) * c.t.y;
    let b = y0 + (y1 - y0) * c.t.z;
    let grad = (b * 0.5).truncate() * gradient_scale(g);
    (b.w, grad)
}

/// A lattice point's [`Differences`] as a vector (not yet halved).
#[inline(always)]
fn difference_vector(d: &Differences) -> Vec3A {
    Vec3A::new(d[0] as f32, d[1] as f32, d[2] as f32)
}

/// The trilinear blend of 8 corner vectors (corners `a + 2b + 4c`), x then y then z.
#[inline(always)]
fn blend_corner_gradients(gc: &[Vec3A; 8], t: Vec3) -> Vec3A {
    let lx = |a: Vec3A, b: Vec3A| a + (b - a) * t.x;
    let (x00, x10) = (lx(gc[0], gc[1]), lx(gc[2], gc[3]));
    let (x01, x11) = (lx(gc[4], gc[5]), lx(gc[6], gc[7]));
    let y0 = x00 + (x10 - x00) * t.y;
    let y1 = x01 + (x11 - x01) * t.y;
    y0 + (y1 - y0) * t.z
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

/// [`sample_detail`] of a whole volume at `p_voxel` (voxel coordinates), for one-off questions
/// such as a tutorial's "what is the value here?".
pub fn detail_at(
    volume: &crate::volume::Volume,
    p_voxel: Vec3,
    interpolation: Interpolation,
) -> SampleDetail {
    struct At(Vec3, Interpolation);
    impl crate::volume::GridVisitor for At {
        type Output = SampleDetail;
        fn visit<T: Voxel>(self, g: Grid<'_, T>) -> SampleDetail {
            sample_detail(&g, self.0, self.1)
        }
    }
    volume.visit(At(p_voxel, interpolation))
}

/// The full breakdown of the reconstruction at `p_voxel`.
pub fn sample_detail<T: Voxel>(
    g: &Grid<'_, T>,
    p_voxel: Vec3,
    interpolation: Interpolation,
) -> SampleDetail {
    let value = g.to_data(sample(g, p_voxel, interpolation));
    let c = cell(g, p_voxel);
    let mut corners = [[0u32; 3]; 8];
    let mut values = [0.0; 8];
    let mut weights = [0.0; 8];
    let near = nearest_index(g.dims, p_voxel);
    let hi = c.hi(g);
    for b in 0..8 {
        let idx = match interpolation {
            Interpolation::Trilinear => [
                if b & 1 == 0 { c.lo[0] } else { hi[0] },
                if b & 2 == 0 { c.lo[1] } else { hi[1] },
                if b & 4 == 0 { c.lo[2] } else { hi[2] },
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
        Grid::new(data, dims, Vec3::ONE, 1.0, 0.0)
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
        let g = Grid::new(&d, dims, spacing, 1.0, 0.0);
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
    fn precomputed_differences_give_the_same_gradient_bit_for_bit() {
        // An integer field with borders, a one-point axis and big differences.
        for dims in [[5usize, 4, 3], [6, 1, 4], [2, 2, 2]] {
            let n = dims[0] * dims[1] * dims[2];
            let data: Vec<i16> = (0..n).map(|i| ((i * 7919) % 4000) as i16 - 1000).collect();
            let g = Grid::new(&data, dims, Vec3::new(0.7, 1.3, 2.0), 1.5, -3.0);
            let diffs = lattice_differences(&g).unwrap();
            for interp in [Interpolation::Trilinear, Interpolation::Nearest] {
                for i in 0..60 {
                    let f = i as f32;
                    let p = Vec3::new(
                        (f * 0.37) % 6.0 - 0.5,
                        (f * 0.61) % 4.5 - 0.3,
                        (f * 0.23) % 3.5 - 0.2,
                    );
                    let a = gradient(&g, p, interp);
                    let b = gradient_from_differences(&g, &diffs, p, interp);
                    assert_eq!(a, b, "{dims:?} {interp:?} at {p}");
                }
            }
        }
        // Too wide a range for exact i16 differences: computed directly instead.
        let wide: Vec<i16> = vec![-20000, 20000];
        assert!(lattice_differences(&Grid::new(&wide, [2, 1, 1], Vec3::ONE, 1.0, 0.0)).is_none());
        let floats = [0.5f32, 1.5];
        assert!(lattice_differences(&Grid::new(&floats, [2, 1, 1], Vec3::ONE, 1.0, 0.0)).is_none());
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
