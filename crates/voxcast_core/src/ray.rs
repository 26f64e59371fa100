//! Rays and the ray–box slab test: where a ray enters and leaves the volume's box.
//!
//! Twin: `shaders/ray.wgsl` (`intersect_box`, `slab`).
//!
//! The slab test (Kay & Kajiya 1986; Williams et al., "An efficient and robust ray–box
//! intersection algorithm", 2005) intersects the ray `p(t) = origin + t·dir` with the three pairs of
//! planes bounding the box: on axis `a` the ray is between them for `t` in
//! `[(lo_a − o_a)/d_a, (hi_a − o_a)/d_a]` (swapped if `d_a < 0`); the box is the intersection of
//! the three intervals, `[t_enter, t_exit]`, empty if `t_enter > t_exit`.
//!
//! Robustness, case by case: a zero direction component (axis-parallel rays) would give `0/0 =
//! NaN` when the origin lies on a plane, so that axis is decided directly — the ray is inside the
//! slab for all `t` if `lo_a ≤ o_a ≤ hi_a`, else it misses. Intervals are closed, so rays along an
//! edge or through a corner hit (with `t_enter = t_exit` for a corner). The interval is finally
//! clipped to `[t_min, t_max]` of the ray: a camera inside the box starts at `t_min = 0`.

use glam::Vec3;

/// A ray `origin + t·dir` for `t` in `[t_min, t_max]`, `dir` of unit length.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
    pub t_min: f32,
    pub t_max: f32,
}

impl Ray {
    /// A ray from `origin` along `dir` (normalised here), for `t ≥ 0`.
    /// Returns `None` for a zero or non-finite direction or a non-finite origin.
    pub fn new(origin: Vec3, dir: Vec3) -> Option<Self> {
        let dir = dir.try_normalize()?;
        origin.is_finite().then_some(Self {
            origin,
            dir,
            t_min: 0.0,
            t_max: f32::INFINITY,
        })
    }

    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}

/// `[t_enter, t_exit]` of `ray` in the box `[lo, hi]`, clipped to the ray's `[t_min, t_max]`;
/// `None` if it misses.
#[inline]
pub fn intersect_box(ray: &Ray, lo: Vec3, hi: Vec3) -> Option<(f32, f32)> {
    // Axis by axis in straight lines: a loop indexing `Vec3`s compiled to a branch per access
    // and a select per operand (232 instructions a call, 4 % of a CT render's).
    let t = (ray.t_min, ray.t_max);
    let t = slab(ray.origin.x, ray.dir.x, lo.x, hi.x, t)?;
    let t = slab(ray.origin.y, ray.dir.y, lo.y, hi.y, t)?;
    let (t_enter, t_exit) = slab(ray.origin.z, ray.dir.z, lo.z, hi.z, t)?;
    (t_enter <= t_exit).then_some((t_enter, t_exit))
}

/// One axis of the slab test: `(t_enter, t_exit)` narrowed to the slab `[lo, hi]` of a ray
/// component from `o` along `d`; `None` where a ray parallel to it lies outside.
#[inline(always)]
fn slab(o: f32, d: f32, lo: f32, hi: f32, (t_enter, t_exit): (f32, f32)) -> Option<(f32, f32)> {
    if d == 0.0 {
        return (o >= lo && o <= hi).then_some((t_enter, t_exit));
    }
    let inv = 1.0 / d;
    let t0 = (lo - o) * inv;
    let t1 = (hi - o) * inv;
    // `max`/`min` ignore a NaN operand, so an overflowing `inv` cannot poison the interval.
    Some((t_enter.max(t0.min(t1)), t_exit.min(t0.max(t1))))
}

/// The 12 edges of the box `[lo, hi]`, each as its two corners (corner `i` takes `hi` on the
/// axes whose bit is set in `i`: x 1, y 2, z 4).
pub fn box_edges(lo: Vec3, hi: Vec3) -> [(Vec3, Vec3); 12] {
    let corner =
        |i: usize| Vec3::select(glam::BVec3::new(i & 1 != 0, i & 2 != 0, i & 4 != 0), hi, lo);
    let mut edges = [(lo, lo); 12];
    let mut n = 0;
    for a in 0..8usize {
        for bit in [1usize, 2, 4] {
            if a & bit == 0 {
                edges[n] = (corner(a), corner(a | bit));
                n += 1;
            }
        }
    }
    edges
}

#[cfg(test)]
mod tests {
    use super::*;

    const LO: Vec3 = Vec3::ZERO;
    const HI: Vec3 = Vec3::new(4.0, 2.0, 1.0);

    fn hit(o: Vec3, d: Vec3) -> Option<(f32, f32)> {
        intersect_box(&Ray::new(o, d).unwrap(), LO, HI)
    }

    #[test]
    fn axis_parallel_in_every_direction() {
        assert_eq!(hit(Vec3::new(-1.0, 1.0, 0.5), Vec3::X), Some((1.0, 5.0)));
        assert_eq!(hit(Vec3::new(5.0, 1.0, 0.5), Vec3::NEG_X), Some((1.0, 5.0)));
        assert_eq!(hit(Vec3::new(2.0, -3.0, 0.5), Vec3::Y), Some((3.0, 5.0)));
        assert_eq!(hit(Vec3::new(2.0, 3.0, 0.5), Vec3::NEG_Y), Some((1.0, 3.0)));
        assert_eq!(hit(Vec3::new(2.0, 1.0, 3.0), Vec3::NEG_Z), Some((2.0, 3.0)));
        assert_eq!(hit(Vec3::new(2.0, 1.0, -1.0), Vec3::Z), Some((1.0, 2.0)));
        // Parallel and outside a slab: miss.
        assert_eq!(hit(Vec3::new(-1.0, 3.0, 0.5), Vec3::X), None);
    }

    #[test]
    fn along_an_edge_and_through_a_corner() {
        // Along the edge y = 0, z = 0 (origin on two planes, zero direction components).
        assert_eq!(hit(Vec3::new(-1.0, 0.0, 0.0), Vec3::X), Some((1.0, 5.0)));
        assert_eq!(hit(Vec3::new(-1.0, 2.0, 1.0), Vec3::X), Some((1.0, 5.0)));
        // Touching the corner (4, 2, 1) only: outside before it (x > 4), outside after (z > 1).
        assert!(
            hit(Vec3::new(5.0, 3.0, 0.0), Vec3::new(1.0, 1.0, -1.0)).is_none(),
            "pointing away misses"
        );
        let r = hit(Vec3::new(5.0, 3.0, 0.0), Vec3::new(-1.0, -1.0, 1.0)).unwrap();
        assert!(
            (r.0 - 3f32.sqrt()).abs() < 1e-5 && (r.1 - r.0).abs() < 1e-5,
            "{r:?}"
        );
    }

    #[test]
    fn origin_inside_starts_at_zero() {
        assert_eq!(hit(Vec3::new(1.0, 1.0, 0.5), Vec3::X), Some((0.0, 3.0)));
    }

    #[test]
    fn grazing_a_face_hits_and_just_outside_misses() {
        assert!(hit(Vec3::new(-1.0, 2.0, 0.5), Vec3::X).is_some());
        assert!(hit(Vec3::new(-1.0, 2.0001, 0.5), Vec3::X).is_none());
        // A nearly parallel ray with a tiny (denormal) component.
        let r = Ray {
            origin: Vec3::new(-1.0, 1.0, 0.5),
            dir: Vec3::new(1.0, 1e-40, 0.0),
            t_min: 0.0,
            t_max: f32::INFINITY,
        };
        let (a, b) = intersect_box(&r, LO, HI).unwrap();
        assert!((a - 1.0).abs() < 1e-6 && (b - 5.0).abs() < 1e-6);
    }

    #[test]
    fn rejects_degenerate_rays() {
        assert!(Ray::new(Vec3::ZERO, Vec3::ZERO).is_none());
        assert!(Ray::new(Vec3::ZERO, Vec3::new(f32::NAN, 0.0, 1.0)).is_none());
        assert!(Ray::new(Vec3::splat(f32::INFINITY), Vec3::X).is_none());
    }

    #[test]
    fn a_box_has_twelve_edges_each_along_one_axis() {
        let edges = box_edges(LO, HI);
        let mut lengths: Vec<f32> = edges.iter().map(|(a, b)| a.distance(*b)).collect();
        lengths.sort_by(f32::total_cmp);
        assert_eq!(
            lengths,
            [1.0, 1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 2.0, 4.0, 4.0, 4.0, 4.0]
        );
        assert!(
            edges
                .iter()
                .all(|(a, b)| (*b - *a).cmpgt(Vec3::ZERO).bitmask().count_ones() == 1)
        );
    }
}
