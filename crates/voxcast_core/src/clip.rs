//! Looking inside: a crop box and a clip plane cut the part of each ray that samples the volume.
//!
//! Twin: `shaders/clip.wgsl` (`clip_interval`).
//!
//! Both cut the ray's interval, never the data: the **crop box** keeps a sub-box of the volume
//! (given per axis as fractions of its extent), so a ray enters where it crosses the cropped box;
//! the **clip plane** keeps the half-space behind it — the points `p` with `n·p ≤ d` — so it
//! removes the side its normal points to. The ray `p(t) = o + t·dir` is in that half-space for
//! `t ≤ (d − n·o)/(n·dir)` when `n·dir > 0`, for `t ≥ …` when `n·dir < 0`, and for all or no `t`
//! when it runs parallel to the plane (decided by `n·o ≤ d`, as the slab test decides a zero
//! direction component). Samples then start at the new entry, so a First hit on the cut face
//! shows the tissue there and Accumulate sees only what is left. Every method, the skipping
//! marches and the breakdown use the same interval, so a cut changes no other rule.

use crate::error::SettingsError;
use crate::ray::{Ray, box_edges, intersect_box};
use crate::tunables as t;
use glam::Vec3;

/// The crop box and the clip plane, as the user sets them (relative to the volume).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Clip {
    /// [`t::CROP`]: lower corner of the kept box, per axis as a fraction of the volume's extent.
    pub crop_lo: Vec3,
    /// [`t::CROP`]: upper corner of the kept box.
    pub crop_hi: Vec3,
    /// [`t::CLIP_PLANE`]; `None` keeps both sides.
    pub plane: Option<ClipPlane>,
}

impl Default for Clip {
    fn default() -> Self {
        Self {
            crop_lo: Vec3::ZERO,
            crop_hi: Vec3::ONE,
            plane: None,
        }
    }
}

/// A clip plane, relative to the volume: it removes the side its normal points to.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ClipPlane {
    /// Direction the removed side lies in (any length but zero; normalised when resolved).
    pub normal: Vec3,
    /// [`t::CLIP_POSITION`]: −1 removes everything, 0 cuts through the centre, 1 keeps all.
    pub position: f32,
}

impl Clip {
    /// Whether this keeps the whole volume (no crop, no plane).
    pub fn is_none(&self) -> bool {
        !self.is_cropped() && self.plane.is_none()
    }

    /// Whether the crop box keeps less than the whole volume.
    pub fn is_cropped(&self) -> bool {
        self.crop_lo != Vec3::ZERO || self.crop_hi != Vec3::ONE
    }

    /// Checks every value against its documented range.
    pub fn validate(&self) -> Result<(), SettingsError> {
        for a in 0..3 {
            SettingsError::check_range(t::CROP.key, self.crop_lo[a], t::CROP.min, t::CROP.max)?;
            SettingsError::check_range(t::CROP.key, self.crop_hi[a], t::CROP.min, t::CROP.max)?;
            if self.crop_lo[a] > self.crop_hi[a] {
                return Err(SettingsError::Invalid(format!(
                    "crop box: on axis {} the lower side ({}) lies above the upper side ({})",
                    ["x", "y", "z"][a],
                    self.crop_lo[a],
                    self.crop_hi[a]
                )));
            }
        }
        if let Some(p) = self.plane {
            SettingsError::check_range(
                t::CLIP_POSITION.key,
                p.position,
                t::CLIP_POSITION.min,
                t::CLIP_POSITION.max,
            )?;
            if !p.normal.is_finite() || p.normal.length_squared() == 0.0 {
                return Err(SettingsError::Invalid(
                    "clip plane: the normal must be a finite, non-zero direction".into(),
                ));
            }
        }
        Ok(())
    }

    /// The cut in world units for a volume whose box is `bounds`.
    pub fn resolve(&self, bounds: (Vec3, Vec3)) -> ResolvedClip {
        let (lo, hi) = bounds;
        let size = hi - lo;
        let (normal, d, position_scale) = match self.plane {
            Some(p) => {
                let n = p.normal.normalize_or_zero();
                let centre = 0.5 * (lo + hi);
                // Half the box's extent along n (its support distance): position ±1 touches the
                // farthest corners, so 1 keeps everything and −1 nothing.
                let half = 0.5 * n.abs().dot(size);
                (n, n.dot(centre) + p.position * half, half)
            }
            None => (Vec3::ZERO, 0.0, 0.0),
        };
        // lo·(1 − f) + hi·f is exact at f = 0 and f = 1: an uncut side is the box's own.
        let at = |f: Vec3| lo * (Vec3::ONE - f) + hi * f;
        ResolvedClip {
            lo: at(self.crop_lo),
            hi: at(self.crop_hi),
            normal,
            d,
            position_scale,
        }
    }
}

/// The cut in world units: the cropped box, and the plane `normal·p ≤ d` (a zero normal with
/// `d = 0` keeps everything).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResolvedClip {
    pub lo: Vec3,
    pub hi: Vec3,
    pub normal: Vec3,
    pub d: f32,
    /// World units the plane moves per unit of [`ClipPlane::position`] (0 without a plane).
    pub position_scale: f32,
}

impl ResolvedClip {
    /// Whether the cut keeps all of the box `bounds`: no crop, no plane. Then
    /// [`clip_interval`] is [`intersect_box`] with `bounds`, exactly.
    pub fn keeps_box(&self, bounds: (Vec3, Vec3)) -> bool {
        (self.lo, self.hi) == bounds && !self.has_plane() && self.d == 0.0
    }

    /// Whether there is a clip plane.
    pub fn has_plane(&self) -> bool {
        self.normal != Vec3::ZERO
    }

    /// Where the clip plane crosses the cropped box: the corners of that polygon (3 to 6) in
    /// order around it; empty without a plane or where it misses the box.
    pub fn plane_polygon(&self) -> Vec<Vec3> {
        if !self.has_plane() {
            return Vec::new();
        }
        let scale = (self.hi - self.lo).max_element().max(f32::MIN_POSITIVE);
        let mut points: Vec<Vec3> = Vec::new();
        for (pa, pb) in box_edges(self.lo, self.hi) {
            let (sa, sb) = (self.normal.dot(pa) - self.d, self.normal.dot(pb) - self.d);
            if (sa <= 0.0) == (sb <= 0.0) && sa != 0.0 && sb != 0.0 {
                continue;
            }
            let p = if sa == sb {
                pa
            } else {
                pa + (pb - pa) * (sa / (sa - sb))
            };
            if points.iter().all(|q| q.distance(p) > 1e-5 * scale) {
                points.push(p);
            }
        }
        if points.len() < 3 {
            return Vec::new();
        }
        let centre = points.iter().copied().sum::<Vec3>() / points.len() as f32;
        let u = self.normal.any_orthonormal_vector();
        let v = self.normal.cross(u);
        points.sort_by(|a, b| {
            let angle = |p: &Vec3| (*p - centre).dot(v).atan2((*p - centre).dot(u));
            angle(a).total_cmp(&angle(b))
        });
        points
    }
}

/// `[t_enter, t_exit]` of `ray` in what the cut keeps of the volume, clipped to the ray's
/// `[t_min, t_max]`; `None` if nothing is left.
///
/// Always inlined: returned through memory, its pair was written as two `f32`s and read back
/// as one 64-bit load, which waited for the stores to reach the cache (a failed store
/// forward, once a ray: 4 % of a close-up's render).
#[inline(always)]
pub fn clip_interval(ray: &Ray, clip: &ResolvedClip) -> Option<(f32, f32)> {
    let (mut t_enter, mut t_exit) = intersect_box(ray, clip.lo, clip.hi)?;
    let side = clip.normal.dot(ray.origin) - clip.d;
    let along = clip.normal.dot(ray.dir);
    if along == 0.0 {
        if side > 0.0 {
            return None;
        }
    } else {
        let t = -side / along;
        if along > 0.0 {
            t_exit = t_exit.min(t);
        } else {
            t_enter = t_enter.max(t);
        }
    }
    (t_enter <= t_exit).then_some((t_enter, t_exit))
}

#[cfg(test)]
mod tests {
    use super::*;

    const BOUNDS: (Vec3, Vec3) = (Vec3::ZERO, Vec3::new(4.0, 2.0, 2.0));

    fn ray(o: Vec3, d: Vec3) -> Ray {
        Ray::new(o, d).unwrap()
    }

    fn plane(normal: Vec3, position: f32) -> Clip {
        Clip {
            plane: Some(ClipPlane { normal, position }),
            ..Clip::default()
        }
    }

    #[test]
    fn no_cut_is_the_box() {
        let c = Clip::default().resolve(BOUNDS);
        let r = ray(Vec3::new(-1.0, 1.0, 1.0), Vec3::X);
        assert_eq!(clip_interval(&r, &c), intersect_box(&r, BOUNDS.0, BOUNDS.1));
        assert!(Clip::default().is_none());
        assert!(c.keeps_box(BOUNDS));
        let cropped = Clip {
            crop_hi: Vec3::new(1.0, 0.5, 1.0),
            ..Clip::default()
        };
        assert!(!cropped.resolve(BOUNDS).keeps_box(BOUNDS));
        assert!(!plane(Vec3::X, 1.0).resolve(BOUNDS).keeps_box(BOUNDS));
    }

    #[test]
    fn crop_box_closed_form() {
        let clip = Clip {
            crop_lo: Vec3::new(0.25, 0.0, 0.0),
            crop_hi: Vec3::new(0.5, 1.0, 1.0),
            plane: None,
        };
        let c = clip.resolve(BOUNDS);
        assert_eq!((c.lo.x, c.hi.x), (1.0, 2.0));
        let r = ray(Vec3::new(-1.0, 1.0, 1.0), Vec3::X);
        assert_eq!(clip_interval(&r, &c), Some((2.0, 3.0)));
        // A zero-thickness crop is a slice: rays across it keep one point.
        let slice = Clip {
            crop_lo: Vec3::new(0.5, 0.0, 0.0),
            crop_hi: Vec3::new(0.5, 1.0, 1.0),
            plane: None,
        }
        .resolve(BOUNDS);
        assert_eq!(clip_interval(&r, &slice), Some((3.0, 3.0)));
    }

    #[test]
    fn plane_through_the_centre_removes_the_side_the_normal_points_to() {
        let c = plane(Vec3::X, 0.0).resolve(BOUNDS);
        // Along +x: kept until the plane x = 2.
        assert_eq!(
            clip_interval(&ray(Vec3::new(-1.0, 1.0, 1.0), Vec3::X), &c),
            Some((1.0, 3.0))
        );
        // Along −x from the far side: enters at the plane.
        assert_eq!(
            clip_interval(&ray(Vec3::new(5.0, 1.0, 1.0), Vec3::NEG_X), &c),
            Some((3.0, 5.0))
        );
        // Parallel to the plane: all on the kept side, or nothing.
        assert!(clip_interval(&ray(Vec3::new(1.0, -1.0, 1.0), Vec3::Y), &c).is_some());
        assert!(clip_interval(&ray(Vec3::new(3.0, -1.0, 1.0), Vec3::Y), &c).is_none());
    }

    #[test]
    fn position_one_keeps_all_and_minus_one_nothing() {
        let dirs = [
            Vec3::new(1.0, 0.3, -0.2),
            Vec3::new(-0.5, 1.0, 0.7),
            Vec3::new(0.1, -0.2, -1.0),
        ];
        for n in dirs {
            let all = plane(n, 1.0).resolve(BOUNDS);
            let none = plane(n, -1.0).resolve(BOUNDS);
            for d in dirs {
                let r = ray(Vec3::new(2.0, 1.0, 1.0) - 10.0 * d, d);
                let full = intersect_box(&r, BOUNDS.0, BOUNDS.1).unwrap();
                let kept = clip_interval(&r, &all).unwrap();
                assert!((kept.0 - full.0).abs() < 1e-4 && (kept.1 - full.1).abs() < 1e-4);
                // Only a ray through the one corner the plane touches could keep a point.
                if let Some((a, b)) = clip_interval(&r, &none) {
                    assert!(b - a < 1e-4, "{a}..{b}");
                }
            }
        }
    }

    #[test]
    fn camera_inside_the_removed_part_starts_at_the_plane() {
        let c = plane(Vec3::NEG_X, 0.0).resolve(BOUNDS);
        // Origin at x = 1 (removed: −x·1 > −2), looking +x: enters at x = 2.
        let r = ray(Vec3::new(1.0, 1.0, 1.0), Vec3::X);
        assert_eq!(clip_interval(&r, &c), Some((1.0, 3.0)));
    }

    #[test]
    fn the_plane_polygon_lies_on_the_plane_and_on_the_box() {
        // Through the centre along x: a 2×2 square at x = 2.
        let c = plane(Vec3::X, 0.0).resolve(BOUNDS);
        let square = c.plane_polygon();
        assert_eq!(square.len(), 4);
        assert!(square.iter().all(|p| p.x == 2.0));
        // Oblique through the centre of a cube: a regular hexagon.
        let cube = (Vec3::ZERO, Vec3::splat(2.0));
        let hexagon = plane(Vec3::ONE, 0.0).resolve(cube).plane_polygon();
        assert_eq!(hexagon.len(), 6);
        for (i, p) in hexagon.iter().enumerate() {
            assert!((p.dot(Vec3::ONE.normalize()) - 3f32.sqrt()).abs() < 1e-5);
            let q = hexagon[(i + 1) % 6];
            assert!(
                (p.distance(q) - 2f32.sqrt()).abs() < 1e-5,
                "neighbours in order"
            );
        }
        // Touching one corner only, or no plane: nothing to draw.
        assert!(
            plane(Vec3::ONE, 1.0)
                .resolve(cube)
                .plane_polygon()
                .is_empty()
        );
        assert!(Clip::default().resolve(cube).plane_polygon().is_empty());
    }

    #[test]
    fn bad_cuts_are_named() {
        let mut c = Clip {
            crop_lo: Vec3::new(0.6, 0.0, 0.0),
            crop_hi: Vec3::new(0.4, 1.0, 1.0),
            plane: None,
        };
        assert!(c.validate().unwrap_err().to_string().contains("axis x"));
        c.crop_lo.x = -0.1;
        assert!(c.validate().unwrap_err().to_string().contains("crop"));
        let p = plane(Vec3::ZERO, 0.0);
        assert!(p.validate().unwrap_err().to_string().contains("normal"));
        let p = plane(Vec3::new(f32::NAN, 0.0, 1.0), 0.0);
        assert!(p.validate().is_err());
        let p = plane(Vec3::X, 1.5);
        assert!(p.validate().is_err());
        assert!(plane(Vec3::X, -1.0).validate().is_ok());
    }
}
