//! Where each pixel's rays can first meet a visible cell: a lower bound on `t` per pixel, from
//! the bricks on the surface of the visible region that face the camera, projected onto the
//! image — so a ray starts its march there instead of leaping up to it, and a ray whose pixel
//! no such brick covers has nothing to march at all. The CPU's counterpart of the proxy
//! geometry a GPU ray caster rasterises for its rays' entry points.
//!
//! Why it is exact. Widen each [`VisibleCells`] brick that holds a visible cell by [`WIDEN`]
//! voxels on every side (far more than any rounding of a sample's position): a sample whose
//! cell is visible lies in such a box. Where a ray first touches a widened box, it crosses a
//! face *facing* the camera — the eye lies beyond its plane (perspective), or the view runs
//! into it (orthographic). If the brick across that face also holds a visible cell, its
//! widened box holds that point too, and that brick is one step nearer the eye: so, step by
//! step, the ray touches — no later — the box of a brick with a facing face on the volume's
//! border or next to a brick without visible cells. Only those bricks are projected: each
//! lowers the bound of the pixels its box may cover (its corners' bounding rectangle, one pixel
//! wider on each side) to its distance from the eye (perspective) or its nearest depth
//! (orthographic), which no point of the box comes before. The argument needs every ray to
//! start outside the widened boxes: a perspective eye inside their bounding box, or an
//! orthographic image plane cutting it, turns the bounds off. `tests/lanes.rs` renders random
//! scenes with the lanes (which start at the bounds) and the scalar march (which does not) and
//! compares every bit; this file's tests check the bound itself against every visible sample.

use crate::camera::ImageRays;
use crate::skip::VisibleCells;
use glam::Vec3;
use rayon::prelude::*;

/// How far (voxels) each brick's box is widened before it is projected.
pub const WIDEN: f32 = 1.0;

/// The relative slack taken off each bound (rounding of the distance itself).
const SLACK: f32 = 1e-4;

/// Per pixel of a `width × height` image, the smallest `t` at which any of its rays can reach
/// a visible cell (`f32::INFINITY`: none can).
#[derive(Clone, Debug, PartialEq)]
pub struct EntryBounds {
    width: u32,
    near: Vec<f32>,
}

impl EntryBounds {
    /// The bounds for the rays of `rays` (an image of `width × height`) through a volume of
    /// voxel `spacing` whose visible cells are `cells`; `None` where rays may start inside
    /// the visible region (see the module docs) or no cell is visible (the march's own box of
    /// the visible bricks then stops every ray at once).
    pub fn new(
        cells: &VisibleCells,
        spacing: Vec3,
        rays: &ImageRays,
        (width, height): (u32, u32),
    ) -> Option<Self> {
        let surface = cells.surface_bricks();
        let box_of = |b: [u32; 3]| {
            let lo = Vec3::new(b[0] as f32, b[1] as f32, b[2] as f32) * 4.0 - WIDEN;
            (lo * spacing, (lo + 4.0 + 2.0 * WIDEN) * spacing)
        };
        let (lo, hi) =
            surface
                .iter()
                .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &(b, _)| {
                    let (a, c) = box_of(b);
                    (lo.min(a), hi.max(c))
                });
        if surface.is_empty() || !(lo.is_finite() && hi.is_finite()) {
            return None;
        }
        let view = View::new(rays, (width, height));
        // A ray that may start inside the visible region: no bounds.
        let starts_inside = if rays.perspective {
            rays.eye.cmpge(lo).all() && rays.eye.cmple(hi).all()
        } else {
            view.nearest_depth(lo, hi) <= 0.0
        };
        if starts_inside || !view.is_finite() {
            return None;
        }
        // The bricks with an open face towards the camera.
        let eye_v = rays.eye / spacing;
        let facing = |b: [u32; 3]| -> u8 {
            let mut faces = 0;
            for a in 0..3 {
                let (low, high) = ((b[a] * 4) as f32, (b[a] * 4 + 4) as f32);
                let (down, up) = if rays.perspective {
                    (eye_v[a] < low, eye_v[a] > high)
                } else {
                    (rays.forward[a] > 0.0, rays.forward[a] < 0.0)
                };
                faces |= u8::from(down) << (2 * a) | u8::from(up) << (2 * a + 1);
            }
            faces
        };
        let front: Vec<[u32; 3]> = surface
            .iter()
            .filter(|(b, open)| open & facing(*b) != 0)
            .map(|(b, _)| *b)
            .collect();
        if front.is_empty() {
            return None; // not reached from outside the visible region: some face faces the eye
        }
        let pixels = width as usize * height as usize;
        // One buffer per thread, merged by their minimum (a few bricks, or a huge image whose
        // buffers would weigh more than the work saved: one buffer).
        let parts = if pixels > 1 << 22 {
            1
        } else {
            rayon::current_num_threads().min(front.len() / 2048).max(1)
        };
        let near = front
            .par_chunks(front.len().div_ceil(parts))
            .map(|chunk| {
                let mut near = vec![f32::INFINITY; pixels];
                for &b in chunk {
                    let (lo, hi) = box_of(b);
                    view.cover(lo, hi, &mut near);
                }
                near
            })
            .reduce_with(|mut a, b| {
                a.iter_mut().zip(&b).for_each(|(a, b)| *a = a.min(*b));
                a
            })?;
        Some(Self { width, near })
    }

    /// The bound for pixel `(x, y)`.
    #[inline(always)]
    pub fn at(&self, x: u32, y: u32) -> f32 {
        self.near[(y * self.width + x) as usize]
    }
}

/// The camera as the projection needs it.
struct View {
    eye: Vec3,
    forward: Vec3,
    /// Right and up over their squared lengths: a view-space offset's dot product with them
    /// is its image coordinate in `[-1, 1]` (divided by depth for a perspective camera).
    right: Vec3,
    up: Vec3,
    perspective: bool,
    size: (f32, f32),
    last: (i64, i64),
}

impl View {
    fn new(rays: &ImageRays, (width, height): (u32, u32)) -> Self {
        Self {
            eye: rays.eye,
            forward: rays.forward,
            right: rays.right / rays.right.length_squared(),
            up: rays.up / rays.up.length_squared(),
            perspective: rays.perspective,
            size: (width as f32, height as f32),
            last: (i64::from(width) - 1, i64::from(height) - 1),
        }
    }

    fn is_finite(&self) -> bool {
        self.eye.is_finite()
            && self.forward.is_finite()
            && self.right.is_finite()
            && self.up.is_finite()
    }

    /// The smallest depth along the view of the box `[lo, hi]`.
    fn nearest_depth(&self, lo: Vec3, hi: Vec3) -> f32 {
        let f = self.forward;
        let nearest = Vec3::select(f.cmpge(Vec3::ZERO), lo, hi);
        (nearest - self.eye).dot(f)
    }

    /// Lowers the bound of every pixel the box `[lo, hi]` may cover to the box's distance.
    fn cover(&self, lo: Vec3, hi: Vec3, near: &mut [f32]) {
        let bound = if self.perspective {
            // The distance from the eye to the box.
            let gap = (lo - self.eye).max(self.eye - hi).max(Vec3::ZERO);
            gap.length()
        } else {
            self.nearest_depth(lo, hi)
        };
        let bound = bound * (1.0 - SLACK);
        let (mut x0, mut x1, mut y0, mut y1) = (
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::INFINITY,
            f32::NEG_INFINITY,
        );
        let mut behind = 0;
        let mut whole = false;
        // The corners' view coordinates: the lower corner's plus each axis' edge as needed.
        let coords = |v: Vec3| Vec3::new(v.dot(self.right), v.dot(self.up), v.dot(self.forward));
        let base = coords(lo - self.eye);
        let edge = hi - lo;
        let along = [
            coords(Vec3::new(edge.x, 0.0, 0.0)),
            coords(Vec3::new(0.0, edge.y, 0.0)),
            coords(Vec3::new(0.0, 0.0, edge.z)),
        ];
        // A corner at or behind the eye's plane makes the box's image unbounded.
        let margin = 1e-6 * (lo - self.eye).length().max((hi - self.eye).length());
        for i in 0..8 {
            let mut c = base;
            for (a, e) in along.iter().enumerate() {
                if i & (1 << a) != 0 {
                    c += *e;
                }
            }
            let (mut a, mut b) = (c.x, c.y);
            if self.perspective {
                if c.z <= margin {
                    behind += 1;
                    whole = true;
                    continue;
                }
                let inv = 1.0 / c.z;
                (a, b) = (a * inv, b * inv);
            }
            // Image coordinates: x = (a + 1)·w/2, y = (1 − b)·h/2.
            let x = (a + 1.0) * 0.5 * self.size.0;
            let y = (1.0 - b) * 0.5 * self.size.1;
            (x0, x1) = (x0.min(x), x1.max(x));
            (y0, y1) = (y0.min(y), y1.max(y));
        }
        if behind == 8 {
            return; // wholly behind the eye: no ray goes there
        }
        let span = |lo: f32, hi: f32, last: i64| -> Option<(usize, usize)> {
            if whole || !(lo.is_finite() && hi.is_finite()) {
                return Some((0, last as usize));
            }
            // Pixel p holds image positions [p, p + 1); one pixel more each side for rounding.
            let a = (lo.floor() as i64 - 1).max(0);
            let b = (hi.floor() as i64 + 1).min(last);
            (a <= b).then_some((a as usize, b as usize))
        };
        let (Some((x0, x1)), Some((y0, y1))) =
            (span(x0, x1, self.last.0), span(y0, y1, self.last.1))
        else {
            return;
        };
        let w = self.last.0 as usize + 1;
        for y in y0..=y1 {
            for n in &mut near[y * w + x0..=y * w + x1] {
                *n = if bound < *n { bound } else { *n };
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{Camera, Projection};
    use crate::clip::clip_interval;
    use crate::settings::RenderSettings;
    use crate::step::{Length, plan_steps, sample_t};
    use crate::transfer::TransferFunction;
    use crate::{Prepared, Volume, VoxelData};
    use glam::UVec3;
    use proptest::prelude::*;

    /// A ball of high values in a low, noisy box, of `dims` points and `spacing`.
    fn ball(dims: UVec3, spacing: Vec3, centre: Vec3, radius: f32, seed: u64) -> Prepared {
        let mut noise = seed | 1;
        let mut values = Vec::new();
        for k in 0..dims.z {
            for j in 0..dims.y {
                for i in 0..dims.x {
                    noise ^= noise << 13;
                    noise ^= noise >> 7;
                    noise ^= noise << 17;
                    let p = Vec3::new(i as f32, j as f32, k as f32);
                    let inside = (p - centre * dims.as_vec3()).length() < radius;
                    values.push(if inside { 200 } else { (noise % 40) as u8 });
                }
            }
        }
        Volume::new("ball", dims, spacing, VoxelData::U8(values))
            .unwrap()
            .into()
    }

    /// Every sample position of every pixel's ray whose cell is visible lies at or beyond the
    /// pixel's bound — the property that makes starting there exact.
    fn check(volume: &Prepared, camera: &Camera, (w, h): (u32, u32), jitter: f32) -> usize {
        let tf = TransferFunction::ramp(100.0, 255.0, 1.0).unwrap();
        let s = RenderSettings {
            step: Length::Voxels(0.37),
            ..RenderSettings::default()
        };
        let scene = crate::scene::Scene::new(volume, &tf, &s, camera.forward()).unwrap();
        let Some((_, cells)) = scene.empty.as_deref() else {
            return 0;
        };
        let rays = camera.rays(w, h);
        let Some(bounds) = EntryBounds::new(cells, volume.spacing(), &rays, (w, h)) else {
            return 0;
        };
        let dims = volume.dims().as_vec3();
        let (last, max_lo) = (dims - 1.0, (dims - 2.0).max(Vec3::ZERO));
        let inv = 1.0 / volume.spacing();
        let mut visible = 0;
        for y in 0..h {
            for x in 0..w {
                let ray = rays.ray(x as f32 + 0.5, y as f32 + 0.5);
                let Some((t0, t1)) = clip_interval(&ray, &scene.clip) else {
                    continue;
                };
                let plan = plan_steps(t0, t1, scene.dt, jitter, 1 << 16);
                let (o_v, d_v) = (ray.origin * inv, ray.dir * inv);
                for k in 0..plan.count {
                    let t = sample_t(&plan, k);
                    let p = (o_v + d_v * t).max(Vec3::ZERO).min(last).min(max_lo);
                    let lo = p.to_array().map(|c| c as usize);
                    if cells.visible(lo) {
                        visible += 1;
                        let bound = bounds.at(x, y);
                        assert!(t >= bound, "pixel ({x}, {y}) sample {k} at {t} < {bound}");
                    }
                }
            }
        }
        visible
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(96))]

        #[test]
        fn no_visible_sample_lies_before_its_pixels_bound(
            dims in proptest::array::uniform3(1u32..24),
            spacing in proptest::array::uniform3(0.4f32..2.5),
            centre in proptest::array::uniform3(0f32..1.0),
            radius in 1f32..10.0,
            seed in any::<u64>(),
            kind in 0u8..3,
            from in proptest::array::uniform3(-1f32..1.0),
            at in proptest::array::uniform3(-0.5f32..1.5),
            jitter in 0f32..1.0,
        ) {
            let v = ball(UVec3::from(dims), Vec3::from(spacing), Vec3::from(centre), radius, seed);
            let (lo, hi) = v.bounds();
            let from = Vec3::from(from);
            prop_assume!(from.length() > 1e-3);
            let camera = match kind {
                0 => Camera::framing(lo, hi, from, Vec3::Y),
                // Anywhere, also inside (the bounds then may turn themselves off).
                1 => Camera::new(
                    lo + (hi - lo) * Vec3::from(at),
                    (lo + hi) * 0.5,
                    Vec3::Y,
                    Projection::Perspective { fov_y_deg: 70.0 },
                ),
                _ => Camera::new(
                    (lo + hi) * 0.5 + from * (hi - lo).length(),
                    (lo + hi) * 0.5,
                    Vec3::Y,
                    Projection::Orthographic { height: (hi - lo).length() },
                ),
            };
            let Ok(camera) = camera else { return Ok(()) };
            check(&v, &camera, (23, 17), jitter);
        }
    }

    /// The bounds cut work on a real view: most rays of a framed ball start past the ball's
    /// front, and the corners' rays have nothing to march; a camera inside turns them off.
    #[test]
    fn a_framed_ball_is_bounded_and_a_camera_inside_is_not() {
        let v = ball(UVec3::new(32, 32, 32), Vec3::ONE, Vec3::splat(0.5), 8.0, 7);
        let (lo, hi) = v.bounds();
        let camera = Camera::framing(lo, hi, Vec3::new(0.3, 0.4, 1.0), Vec3::Y).unwrap();
        assert!(check(&v, &camera, (40, 30), 0.0) > 0);
        let tf = TransferFunction::ramp(100.0, 255.0, 1.0).unwrap();
        let s = RenderSettings::default();
        let scene = crate::scene::Scene::new(&v, &tf, &s, camera.forward()).unwrap();
        let (_, cells) = scene.empty.as_deref().unwrap();
        let b = EntryBounds::new(cells, v.spacing(), &camera.rays(40, 30), (40, 30)).unwrap();
        assert_eq!(b.at(0, 0), f32::INFINITY, "a corner ray misses the ball");
        // The ball's front is 8 voxels before its centre; its visible cells reach a voxel out,
        // their bricks up to 4·√3 more (seen at a slant), widened by one.
        let centre = b.at(20, 15);
        let to_centre = (camera.eye - (lo + hi) * 0.5).length();
        assert!(
            centre > to_centre - 20.0 && centre < to_centre - 8.0,
            "{centre} {to_centre}"
        );
        let inside = Camera::new(
            Vec3::splat(16.0),
            Vec3::ZERO,
            Vec3::Y,
            Projection::Perspective { fov_y_deg: 60.0 },
        )
        .unwrap();
        assert!(EntryBounds::new(cells, v.spacing(), &inside.rays(40, 30), (40, 30)).is_none());
    }
}
