//! The ray mesh view (RayVis's first view): every counted ray as a line from where it starts
//! (`t_min`) to where it hit (`t_hit`) or, for a miss, where it ends (`t_max`), after the
//! filter and the stride.
//!
//! A miss may run on for ever (`t_max` = ∞ or 10³⁸): every line is clipped to a box — the
//! scene's, padded — so what is drawn stays finite; a ray that never enters the box is not
//! drawn. Malformed rays ([`RayRecord::check`]) are skipped and counted.

use super::set::{Filter, RayRecord, RaySet};
use glam::Vec3;

/// One line of the ray mesh (world units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayLine {
    pub from: Vec3,
    pub to: Vec3,
    pub hit: bool,
}

/// Which rays are drawn, and the box they are clipped to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineParams {
    pub filter: Filter,
    pub tolerance: f32,
    /// Every `stride`-th ray the filter passes (0 is taken as 1).
    pub stride: usize,
    /// The box every line is clipped to (low and high corners).
    pub clip: (Vec3, Vec3),
}

/// The lines, and how many selected rays were malformed or never entered the box.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RayLines {
    pub lines: Vec<RayLine>,
    pub malformed: usize,
    pub outside: usize,
}

/// Segments per ray of [`glyphs`]: a three-armed cross at the start, an arrowhead of four
/// strokes at the end.
pub const GLYPH_SEGMENTS: usize = 7;

/// A ray line's start and end glyphs (RayVis marks where a ray begins and where it ends), as
/// segments of `size` world units: a cross of three axis-aligned strokes centred on `from`,
/// and an arrowhead at `to`, four strokes back along the line at 30° to it, in two planes at
/// right angles. A line of no length gets the cross only (its arrowhead strokes are empty).
pub fn glyphs(l: &RayLine, size: f32) -> [(Vec3, Vec3); GLYPH_SEGMENTS] {
    let h = 0.5 * size;
    let cross = [Vec3::X, Vec3::Y, Vec3::Z].map(|a| (l.from - a * h, l.from + a * h));
    let dir = (l.to - l.from).normalize_or_zero();
    let (u, v) = dir.any_orthonormal_pair();
    let (back, side) = (
        size * 30f32.to_radians().cos(),
        size * 30f32.to_radians().sin(),
    );
    let head = [u, -u, v, -v].map(|p| {
        if dir == Vec3::ZERO {
            (l.to, l.to)
        } else {
            (l.to, l.to - dir * back + p * side)
        }
    });
    [
        cross[0], cross[1], cross[2], head[0], head[1], head[2], head[3],
    ]
}

/// The lines of `set` (see the module's text), in the rays' order.
pub fn ray_lines(set: &RaySet, p: &LineParams) -> RayLines {
    let mut out = RayLines::default();
    for r in set.selected(p.filter, p.tolerance, p.stride) {
        if r.check().is_err() {
            out.malformed += 1;
            continue;
        }
        match line(r, p) {
            Some(l) => out.lines.push(l),
            None => out.outside += 1,
        }
    }
    out
}

/// One ray's line, clipped to the box; `None` when nothing of it lies inside.
fn line(r: &RayRecord, p: &LineParams) -> Option<RayLine> {
    let (t0, t1) = r.segment(p.tolerance);
    let (lo, hi) = p.clip;
    // Slabs: the part of the segment inside the box, axis by axis. An axis the ray is
    // parallel to limits nothing when the origin lies within the box's slab, else everything.
    let (mut enter, mut exit) = (t0, t1);
    for axis in 0..3 {
        let (o, d) = (r.origin[axis], r.direction[axis]);
        if d == 0.0 {
            if o < lo[axis] || o > hi[axis] {
                return None;
            }
            continue;
        }
        let a = (lo[axis] - o) / d;
        let b = (hi[axis] - o) / d;
        enter = enter.max(a.min(b));
        exit = exit.min(a.max(b));
    }
    (enter <= exit).then(|| RayLine {
        from: r.at(enter),
        to: r.at(exit),
        hit: r.is_hit(p.tolerance),
    })
}

/// The scene's box grown by `pad` times its largest side on every face (the ray mesh's clip
/// box).
pub fn padded(bounds: (Vec3, Vec3), pad: f32) -> (Vec3, Vec3) {
    let (lo, hi) = bounds;
    let grow = (hi - lo).max_element() * pad;
    (lo - grow, hi + grow)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cross is centred on the start, the arrowhead's strokes leave the end backwards at
    /// 30° to the line, each `size` long.
    #[test]
    fn glyphs_mark_the_start_and_the_end() {
        let l = RayLine {
            from: Vec3::new(1.0, 2.0, 3.0),
            to: Vec3::new(1.0, 2.0, 13.0),
            hit: true,
        };
        let g = glyphs(&l, 0.5);
        for (a, b) in &g[..3] {
            assert!(((*a + *b) * 0.5).abs_diff_eq(l.from, 1e-6));
            assert!((a.distance(*b) - 0.5).abs() < 1e-6);
        }
        for (a, b) in &g[3..] {
            assert_eq!(*a, l.to);
            let stroke = *b - *a;
            assert!((stroke.length() - 0.5).abs() < 1e-5);
            let cos = stroke.normalize().dot(Vec3::NEG_Z);
            assert!((cos - 30f32.to_radians().cos()).abs() < 1e-5, "{cos}");
        }
        let dot = RayLine { to: l.from, ..l };
        assert!(glyphs(&dot, 0.5)[3..].iter().all(|(a, b)| a == b));
    }

    const BOX: (Vec3, Vec3) = (Vec3::splat(-10.0), Vec3::splat(10.0));

    fn params(filter: Filter, stride: usize) -> LineParams {
        LineParams {
            filter,
            tolerance: 0.0,
            stride,
            clip: BOX,
        }
    }

    fn ray(id: u32, direction: Vec3, t_max: f32, t_hit: f32) -> RayRecord {
        RayRecord {
            id,
            origin: Vec3::ZERO,
            direction,
            t_min: 0.5,
            t_max,
            t_hit,
        }
    }

    /// A hit ends at `t_hit`, a miss at `t_max`, both start at `t_min`; `t` is in units of the
    /// direction's length.
    #[test]
    fn hits_end_at_the_hit_and_misses_at_the_end() {
        let set = RaySet {
            trace_id: 0,
            rays: vec![
                ray(0, Vec3::new(2.0, 0.0, 0.0), 4.0, 3.0),
                ray(1, Vec3::Y, 4.0, -1.0),
            ],
        };
        let l = ray_lines(&set, &params(Filter::All, 1));
        assert_eq!(
            l.lines,
            vec![
                RayLine {
                    from: Vec3::new(1.0, 0.0, 0.0),
                    to: Vec3::new(6.0, 0.0, 0.0),
                    hit: true
                },
                RayLine {
                    from: Vec3::new(0.0, 0.5, 0.0),
                    to: Vec3::new(0.0, 4.0, 0.0),
                    hit: false
                },
            ]
        );
        let hits = ray_lines(&set, &params(Filter::Hit, 1));
        assert_eq!(hits.lines.len(), 1);
        assert!(hits.lines[0].hit);
        let misses = ray_lines(&set, &params(Filter::Miss, 1));
        assert!(misses.lines.iter().all(|l| !l.hit) && misses.lines.len() == 1);
    }

    /// An endless miss is cut at the box, a diagonal one too; a ray that passes the box by
    /// is not drawn; bad rays are counted, never drawn.
    #[test]
    fn endless_and_bad_rays() {
        let set = RaySet {
            trace_id: 0,
            rays: vec![
                ray(0, Vec3::Z, f32::INFINITY, -1.0),
                ray(1, Vec3::ONE, f32::MAX, -1.0),
                RayRecord {
                    origin: Vec3::new(50.0, 0.0, 0.0),
                    ..ray(2, Vec3::Y, f32::INFINITY, -1.0)
                },
                ray(3, Vec3::ZERO, 1.0, -1.0),
                ray(4, Vec3::new(f32::NAN, 0.0, 0.0), 1.0, -1.0),
                ray(5, Vec3::X, 0.1, -1.0),
            ],
        };
        let l = ray_lines(&set, &params(Filter::All, 1));
        assert_eq!(l.lines.len(), 2);
        assert_eq!(l.lines[0].to, Vec3::new(0.0, 0.0, 10.0));
        assert_eq!(l.lines[1].to, Vec3::splat(10.0));
        assert_eq!((l.outside, l.malformed), (1, 3));
        for line in &l.lines {
            assert!(line.from.is_finite() && line.to.is_finite());
        }
    }

    /// A ray lying in a face of the box, parallel to two axes, is still drawn.
    #[test]
    fn a_ray_along_a_face_is_drawn() {
        let set = RaySet {
            trace_id: 0,
            rays: vec![RayRecord {
                origin: Vec3::new(-10.0, -10.0, 0.0),
                ..ray(0, Vec3::Z, 3.0, -1.0)
            }],
        };
        let l = ray_lines(&set, &params(Filter::All, 1));
        assert_eq!(l.lines.len(), 1, "{l:?}");
        assert_eq!(l.lines[0].to, Vec3::new(-10.0, -10.0, 3.0));
    }

    /// Stride keeps every n-th ray the filter passes, starting with the first.
    #[test]
    fn stride_keeps_every_nth() {
        let rays = (0..10)
            .map(|i| ray(i, Vec3::X, 2.0, if i % 2 == 0 { 1.0 } else { -1.0 }))
            .collect();
        let set = RaySet { trace_id: 0, rays };
        assert_eq!(ray_lines(&set, &params(Filter::All, 3)).lines.len(), 4);
        assert_eq!(ray_lines(&set, &params(Filter::Hit, 2)).lines.len(), 3);
        assert_eq!(ray_lines(&set, &params(Filter::Miss, 0)).lines.len(), 5);
    }

    #[test]
    fn padding_grows_by_the_largest_side() {
        let (lo, hi) = padded((Vec3::ZERO, Vec3::new(10.0, 2.0, 1.0)), 0.1);
        assert_eq!((lo, hi), (Vec3::splat(-1.0), Vec3::new(11.0, 3.0, 2.0)));
    }
}
