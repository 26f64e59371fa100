//! A ray data set and RayVis's rules for it.
//!
//! A ray has an id, an origin, a direction (not necessarily of unit length: its `t` is measured
//! in units of the direction's length, the point at `t` being `origin + t·direction`), and three
//! distances along it: `t_min` where it starts, `t_max` how far it may go, and `t_hit` where it
//! hit something (negative when it hit nothing). A ray **hits** when `t_hit ≥ 0` and
//! `t_hit < t_max − tolerance` — RayVis's miss-detection tolerance, 0 by default: a renderer that
//! reports a miss as a hit at `t_max` is told apart with a small positive tolerance. The
//! **counted segment** of a hit is `(t_min, t_hit)`, of a miss `(t_min, t_max)`.

use glam::Vec3;

/// One ray of a set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayRecord {
    pub id: u32,
    pub origin: Vec3,
    /// Not necessarily unit length: `t` is in units of its length.
    pub direction: Vec3,
    pub t_min: f32,
    pub t_max: f32,
    /// Negative: no hit.
    pub t_hit: f32,
}

/// Which rays a view counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Filter {
    #[default]
    All,
    Hit,
    Miss,
}

impl Filter {
    pub const ALL: [Filter; 3] = [Filter::All, Filter::Hit, Filter::Miss];

    /// Its name on the command line.
    pub const fn name(self) -> &'static str {
        match self {
            Filter::All => "all",
            Filter::Hit => "hit",
            Filter::Miss => "miss",
        }
    }

    /// The filter named `name`.
    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|f| f.name() == name)
    }
}

/// Why a ray cannot be traversed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum RayProblem {
    #[error("its origin or direction is not finite")]
    NotFinite,
    #[error("its direction is zero")]
    ZeroDirection,
    #[error("its t_min or t_max is NaN, or t_max < t_min")]
    BadInterval,
}

impl RayRecord {
    /// Whether the ray hit something (see the module's text).
    pub fn is_hit(&self, tolerance: f32) -> bool {
        self.t_hit >= 0.0 && self.t_hit < self.t_max - tolerance
    }

    /// Whether `filter` counts the ray.
    pub fn passes(&self, filter: Filter, tolerance: f32) -> bool {
        match filter {
            Filter::All => true,
            Filter::Hit => self.is_hit(tolerance),
            Filter::Miss => !self.is_hit(tolerance),
        }
    }

    /// The counted segment `(t_start, t_end)`: to the hit, or to `t_max` for a miss.
    pub fn segment(&self, tolerance: f32) -> (f32, f32) {
        let end = if self.is_hit(tolerance) {
            self.t_hit
        } else {
            self.t_max
        };
        (self.t_min, end)
    }

    /// The point at `t`.
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.direction * t
    }

    /// Whether the ray can be traversed at all.
    pub fn check(&self) -> Result<(), RayProblem> {
        if !(self.origin.is_finite() && self.direction.is_finite()) {
            return Err(RayProblem::NotFinite);
        }
        if self.direction == Vec3::ZERO {
            return Err(RayProblem::ZeroDirection);
        }
        if self.t_min.is_nan() || self.t_max.is_nan() || self.t_max < self.t_min {
            return Err(RayProblem::BadInterval);
        }
        Ok(())
    }
}

/// One trace of a ray data set: the rays one effect cast (primary, shadow, reflection, …).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RaySet {
    pub trace_id: u32,
    pub rays: Vec<RayRecord>,
}

impl RaySet {
    /// The rays `filter` counts, every `stride`-th of them (stride 0 is taken as 1).
    pub fn selected(
        &self,
        filter: Filter,
        tolerance: f32,
        stride: usize,
    ) -> impl Iterator<Item = &RayRecord> {
        self.rays
            .iter()
            .filter(move |r| r.passes(filter, tolerance))
            .step_by(stride.max(1))
    }

    /// How many rays hit and how many missed.
    pub fn hits_and_misses(&self, tolerance: f32) -> (usize, usize) {
        let hits = self.rays.iter().filter(|r| r.is_hit(tolerance)).count();
        (hits, self.rays.len() - hits)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(t_hit: f32, t_max: f32) -> RayRecord {
        RayRecord {
            id: 0,
            origin: Vec3::ZERO,
            direction: Vec3::X,
            t_min: 0.0,
            t_max,
            t_hit,
        }
    }

    #[test]
    fn hits_misses_and_the_tolerance() {
        assert!(ray(3.0, 10.0).is_hit(0.0));
        assert!(!ray(-1.0, 10.0).is_hit(0.0), "negative: no hit");
        assert!(!ray(10.0, 10.0).is_hit(0.0), "a hit at t_max is a miss");
        assert!(ray(9.95, 10.0).is_hit(0.0));
        assert!(!ray(9.95, 10.0).is_hit(0.1), "within the tolerance: a miss");
        assert_eq!(ray(3.0, 10.0).segment(0.0), (0.0, 3.0));
        assert_eq!(ray(-1.0, 10.0).segment(0.0), (0.0, 10.0));
    }

    #[test]
    fn filters_and_stride_select_rays() {
        let set = RaySet {
            trace_id: 7,
            rays: (0..10)
                .map(|i| RayRecord {
                    id: i,
                    ..ray(if i % 2 == 0 { 1.0 } else { -1.0 }, 5.0)
                })
                .collect(),
        };
        assert_eq!(set.hits_and_misses(0.0), (5, 5));
        let ids =
            |f: Filter, s: usize| -> Vec<u32> { set.selected(f, 0.0, s).map(|r| r.id).collect() };
        assert_eq!(ids(Filter::Hit, 1), [0, 2, 4, 6, 8]);
        assert_eq!(ids(Filter::Miss, 2), [1, 5, 9]);
        assert_eq!(
            ids(Filter::All, 0),
            (0..10).collect::<Vec<_>>(),
            "stride 0 = 1"
        );
        assert_eq!(Filter::parse("miss"), Some(Filter::Miss));
        assert_eq!(Filter::parse("most"), None);
    }

    #[test]
    fn malformed_rays_are_told_apart() {
        let mut r = ray(1.0, 5.0);
        assert!(r.check().is_ok());
        r.direction = Vec3::ZERO;
        assert_eq!(r.check(), Err(RayProblem::ZeroDirection));
        r.direction = Vec3::new(f32::NAN, 0.0, 1.0);
        assert_eq!(r.check(), Err(RayProblem::NotFinite));
        let mut r = ray(1.0, 5.0);
        r.t_max = -1.0;
        assert_eq!(r.check(), Err(RayProblem::BadInterval));
        r.t_max = f32::INFINITY;
        assert!(
            r.check().is_ok(),
            "an endless miss is a ray (the density caps it)"
        );
    }
}
