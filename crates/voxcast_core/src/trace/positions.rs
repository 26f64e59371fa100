//! Eight sample positions of a ray located at once, over any backend of [`Simd`]: shared by
//! Accumulate's lanes (`lanes.rs`) and the projections' (`value_lanes.rs`).

use super::simd::Simd;
use crate::step::StepPlan;
use glam::Vec3;

/// Eight sample positions of a ray located: their indices `k` and `t`, and per axis the lower
/// corner of their cell and the fraction inside it.
pub(super) struct Cells<S: Simd> {
    pub k: S::I,
    pub t: S::F,
    pub i: [S::I; 3],
    pub f: [S::F; 3],
}

/// Locates positions `k .. k + 8` of the ray: each lane computes what `sample_t` and
/// `crate::sample::cell` compute for one, in the same operations (`last` and `max_lo` are the
/// grid's).
#[inline(always)]
pub(super) fn cells<S: Simd>(
    s: S,
    plan: &StepPlan,
    k: u32,
    (o_v, d_v): (Vec3, Vec3),
    (last, max_lo): (Vec3, Vec3),
) -> Cells<S> {
    let ks = s.add_i(s.splat_i(k as i32), s.iota());
    // sample_t: min(t_enter + (jitter + k)·dt, t_exit).
    let t = s.min(
        s.add(
            s.splat(plan.t_enter),
            s.mul(s.add(s.splat(plan.jitter), s.to_f(ks)), s.splat(plan.dt)),
        ),
        s.splat(plan.t_exit),
    );
    let (ix, fx) = axis(s, (o_v.x, d_v.x), t, (last.x, max_lo.x));
    let (iy, fy) = axis(s, (o_v.y, d_v.y), t, (last.y, max_lo.y));
    let (iz, fz) = axis(s, (o_v.z, d_v.z), t, (last.z, max_lo.z));
    Cells {
        k: ks,
        t,
        i: [ix, iy, iz],
        f: [fx, fy, fz],
    }
}

/// `crate::sample::cell` along one axis for eight positions at `t` of a ray with origin `o` and
/// direction `d` on that axis: `x = min(max(p, 0), last)`, `i = ⌊min(x, max_lo)⌋`, `f = x − i`.
/// A function, not a closure, so that it inlines where the backend's instructions are enabled
/// (a closure here was left out of line, and its intrinsics with it).
#[inline(always)]
fn axis<S: Simd>(s: S, (o, d): (f32, f32), t: S::F, (last, max_lo): (f32, f32)) -> (S::I, S::F) {
    let p = s.add(s.splat(o), s.mul(s.splat(d), t));
    let x = s.min(s.max(p, s.splat(0.0)), s.splat(last));
    let i = s.trunc(s.min(x, s.splat(max_lo)));
    (i, s.sub(x, s.to_f(i)))
}

impl<S: Simd> Cells<S> {
    /// The index of each lane's lower corner in a lattice of `nx` points per row and `nxy`
    /// per slice.
    #[inline(always)]
    pub(super) fn corner(&self, s: S, nx: i32, nxy: i32) -> S::I {
        let [ix, iy, iz] = self.i;
        s.add_i(
            ix,
            s.add_i(s.mul_i(iy, s.splat_i(nx)), s.mul_i(iz, s.splat_i(nxy))),
        )
    }
}
