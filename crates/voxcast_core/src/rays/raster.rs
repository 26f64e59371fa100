//! Line lists drawn on the CPU over a camera's view: how the CPU live view shows the ray mesh
//! and the vector field, where a software rasterizer takes microseconds a line (lavapipe: about
//! 3 µs on 2 cores, BENCHMARKS.md) and here one line costs a few pixels' worth.
//!
//! A segment's ends are carried into the camera's view space, cut at the near plane (a segment
//! that reaches behind the eye keeps its part in front of it), projected as
//! [`Camera::project`] projects (perspective or orthographic), cut to the image
//! (Liang–Barsky), and stepped one pixel at a time along its longer screen axis (a DDA: one
//! pixel per column or per row, so a line is one pixel wide and has no gaps). Each pixel takes
//! the colour interpolated between the ends and is blended over what is there by its alpha
//! (premultiplied: `C = a·c + (1 − a)·C`, `A = a + (1 − a)·A`), in the list's order — so the
//! result is the same on any number of threads: each thread draws every segment into its own
//! band of rows.

use crate::camera::{Camera, Projection};
use glam::{Vec2, Vec3, Vec4};
use rayon::prelude::*;

/// An image of premultiplied RGBA, row 0 at the top, clear (all zero) where nothing is drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct LineImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec4>,
    /// The smallest rectangle `[x0, y0, x1, y1)` holding every pixel drawn so far (empty:
    /// `x1 ≤ x0`), so that a caller can show that part alone.
    pub drawn: [u32; 4],
}

/// No pixel: the rectangle every drawn pixel widens.
const NOTHING: [u32; 4] = [u32::MAX, u32::MAX, 0, 0];

impl LineImage {
    /// A clear image.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![Vec4::ZERO; width as usize * height as usize],
            drawn: NOTHING,
        }
    }

    /// The pixel at column `x`, row `y`.
    pub fn get(&self, x: u32, y: u32) -> Vec4 {
        self.pixels[(y * self.width + x) as usize]
    }

    /// [`LineImage::drawn`], `None` when nothing is drawn.
    pub fn drawn_rect(&self) -> Option<[u32; 4]> {
        let [x0, y0, x1, y1] = self.drawn;
        (x1 > x0 && y1 > y0).then_some(self.drawn)
    }
}

/// The union of two rectangles `[x0, y0, x1, y1)`.
fn union(a: [u32; 4], b: [u32; 4]) -> [u32; 4] {
    [
        a[0].min(b[0]),
        a[1].min(b[1]),
        a[2].max(b[2]),
        a[3].max(b[3]),
    ]
}

/// A line list: two vertices a segment, world positions and colours (RGBA, straight alpha, in
/// whatever colour space the image is shown in).
#[derive(Clone, Copy, Debug)]
pub struct Lines<'a> {
    pub positions: &'a [[f32; 3]],
    pub colours: &'a [[f32; 4]],
    /// Added to every position: where the list's world sits in the camera's.
    pub offset: Vec3,
    /// Every `every`-th segment is drawn (0 is taken as 1): a thinned list at the same cost
    /// as a short one.
    pub every: usize,
}

/// Rows of the image one thread draws (the segments are cut to its band).
const BAND_ROWS: u32 = 32;

/// Draws `lines` into `image` as seen by `camera` (see the module's text); returns the
/// segments drawn (those with some part in the image).
pub fn draw_lines(image: &mut LineImage, camera: &Camera, lines: &Lines) -> usize {
    let (w, h) = (image.width, image.height);
    if w == 0 || h == 0 {
        return 0;
    }
    let view = View::new(camera, w, h);
    let every = lines.every.max(1);
    let segments = lines.positions.len().min(lines.colours.len()) / 2;
    // The segments with some part in the image, in screen space once; then each band draws
    // what falls in its rows.
    let whole = [0.0, 0.0, w as f32, h as f32];
    let projected: Vec<(Vec2, Vec2, Vec4, Vec4)> = (0..segments)
        .into_par_iter()
        .step_by(every)
        .filter_map(|i| {
            let p = |j: usize| Vec3::from_array(lines.positions[j]) + lines.offset;
            let c = |j: usize| Vec4::from_array(lines.colours[j]);
            let (a, b) = view.project(p(2 * i), p(2 * i + 1))?;
            clip_2d(a.0, b.0, whole)?;
            let (ca, cb) = (c(2 * i), c(2 * i + 1));
            Some((a.0, b.0, ca.lerp(cb, a.1), ca.lerp(cb, b.1)))
        })
        .collect();
    // Each band's segments, in the list's order: those whose rows reach it.
    let bands = h.div_ceil(BAND_ROWS) as usize;
    let mut in_band: Vec<Vec<u32>> = vec![Vec::new(); bands];
    for (i, (a, b, _, _)) in projected.iter().enumerate() {
        let (lo, hi) = (a.y.min(b.y).max(0.0), a.y.max(b.y).min(h as f32 - 1.0));
        let (first, last) = (
            (lo as u32 / BAND_ROWS) as usize,
            (hi as u32 / BAND_ROWS) as usize,
        );
        for band in in_band.iter_mut().take(last + 1).skip(first) {
            band.push(i as u32);
        }
    }
    let width = w as usize;
    let drawn = image
        .pixels
        .par_chunks_mut(width * BAND_ROWS as usize)
        .zip(in_band)
        .enumerate()
        .map(|(band, (pixels, segments))| {
            let y0 = band as u32 * BAND_ROWS;
            let rows = (pixels.len() / width) as u32;
            let rect = [0.0, y0 as f32, w as f32, (y0 + rows) as f32];
            let mut drawn = NOTHING;
            for i in segments {
                let (a, b, ca, cb) = projected[i as usize];
                if let Some(part) = clip_2d(a, b, rect) {
                    let r = step(pixels, width, y0, rows, (a, b), part, (ca, cb));
                    drawn = union(drawn, r);
                }
            }
            drawn
        })
        .reduce(|| NOTHING, union);
    image.drawn = union(image.drawn, drawn);
    projected.len()
}

/// The camera's view of an image: its basis scaled to the image plane.
struct View {
    eye: Vec3,
    right: Vec3,
    up: Vec3,
    forward: Vec3,
    perspective: bool,
    /// The near plane's distance: segments are cut there.
    near: f32,
    size: Vec2,
}

impl View {
    fn new(camera: &Camera, width: u32, height: u32) -> Self {
        let rays = camera.rays(width, height);
        let distance = (camera.target - camera.eye).length();
        Self {
            eye: rays.eye,
            right: rays.right / rays.right.length_squared(),
            up: rays.up / rays.up.length_squared(),
            forward: rays.forward,
            perspective: matches!(camera.projection, Projection::Perspective { .. }),
            near: 1e-4 * distance,
            size: Vec2::new(width as f32, height as f32),
        }
    }

    /// A segment's ends on screen (pixels from the top-left corner), each with where it lies
    /// along the segment (0 at `a`, 1 at `b`): its part in front of the near plane, `None` when
    /// it has none.
    fn project(&self, a: Vec3, b: Vec3) -> Option<((Vec2, f32), (Vec2, f32))> {
        let (da, db) = (a - self.eye, b - self.eye);
        let (za, zb) = (da.dot(self.forward), db.dot(self.forward));
        if !(za.is_finite() && zb.is_finite()) {
            return None;
        }
        let (mut s0, mut s1) = (0.0f32, 1.0f32);
        if self.perspective {
            if za < self.near && zb < self.near {
                return None;
            }
            // The part with z ≥ near.
            if za < self.near {
                s0 = (self.near - za) / (zb - za);
            } else if zb < self.near {
                s1 = (self.near - za) / (zb - za);
            }
        }
        let at = |s: f32| {
            let d = da + (db - da) * s;
            let z = if self.perspective {
                d.dot(self.forward)
            } else {
                1.0
            };
            let ndc = Vec2::new(d.dot(self.right), d.dot(self.up)) / z;
            Vec2::new((ndc.x + 1.0) * 0.5, (1.0 - ndc.y) * 0.5) * self.size
        };
        let (p0, p1) = (at(s0), at(s1));
        (p0.is_finite() && p1.is_finite()).then_some(((p0, s0), (p1, s1)))
    }
}

/// The part `[s0, s1]` of the screen segment `a → b` inside `rect = [x0, y0, x1, y1]`
/// (Liang–Barsky), `None` when it misses it.
fn clip_2d(a: Vec2, b: Vec2, [x0, y0, x1, y1]: [f32; 4]) -> Option<(f32, f32)> {
    let d = b - a;
    let (mut s0, mut s1) = (0.0f32, 1.0f32);
    for (p, q) in [
        (-d.x, a.x - x0),
        (d.x, x1 - a.x),
        (-d.y, a.y - y0),
        (d.y, y1 - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                s0 = s0.max(r);
            } else {
                s1 = s1.min(r);
            }
        }
    }
    (s0 <= s1).then_some((s0, s1))
}

/// Steps the screen segment `a → b` over `[s0, s1]` one pixel at a time along its longer
/// axis, blending each pixel of the band (rows `y0 .. y0 + rows`) with the colour between
/// `ca` and `cb`; returns the rectangle of the pixels it drew.
fn step(
    pixels: &mut [Vec4],
    width: usize,
    y0: u32,
    rows: u32,
    (a, b): (Vec2, Vec2),
    (s0, s1): (f32, f32),
    (ca, cb): (Vec4, Vec4),
) -> [u32; 4] {
    let d = b - a;
    let length = d.abs().max_element() * (s1 - s0);
    // One step a pixel along the longer axis (at least the segment's start pixel).
    let n = length.ceil().max(1.0) as u32;
    let (ds, mut s) = ((s1 - s0) / n as f32, s0);
    let (dp, mut p) = (d * ds, a + d * s0);
    let (y_lo, y_hi, x_hi) = (y0 as f32, (y0 + rows) as f32, width as f32);
    // A line of one opaque colour (every ray of the mesh, every arrow) is written, not blended.
    let plain = ca == cb && ca.w >= 1.0;
    let solid = Vec4::from((ca.truncate(), 1.0));
    // Steps shorter than a pixel may land twice in one: it is blended once.
    let mut last = usize::MAX;
    let mut drawn = NOTHING;
    for _ in 0..=n {
        // The clipped ends may round onto the next pixel outside. Inside, the coordinates are
        // not negative, so truncation is their floor (a library call on baseline x86-64).
        if p.x >= 0.0 && p.x < x_hi && p.y >= y_lo && p.y < y_hi {
            let (x, y) = (p.x as u32, p.y as u32);
            let i = (y - y0) as usize * width + x as usize;
            if i != last {
                last = i;
                drawn = union(drawn, [x, y, x + 1, y + 1]);
                let dst = &mut pixels[i];
                if plain {
                    *dst = solid;
                } else {
                    let c = ca.lerp(cb, s);
                    let alpha = c.w.clamp(0.0, 1.0);
                    *dst = Vec4::from((c.truncate() * alpha, alpha)) + *dst * (1.0 - alpha);
                }
            }
        }
        p += dp;
        s += ds;
    }
    drawn
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A camera at the origin looking down −z with a 90° field of view: the point (x, y, −1)
    /// is at the image's edge for |x|, |y| = 1.
    fn camera() -> Camera {
        Camera::new(
            Vec3::ZERO,
            Vec3::NEG_Z,
            Vec3::Y,
            Projection::Perspective { fov_y_deg: 90.0 },
        )
        .unwrap()
    }

    fn lines<'a>(positions: &'a [[f32; 3]], colours: &'a [[f32; 4]]) -> Lines<'a> {
        Lines {
            positions,
            colours,
            offset: Vec3::ZERO,
            every: 1,
        }
    }

    fn lit(image: &LineImage) -> Vec<(u32, u32)> {
        (0..image.height)
            .flat_map(|y| (0..image.width).map(move |x| (x, y)))
            .filter(|&(x, y)| image.get(x, y) != Vec4::ZERO)
            .collect()
    }

    /// A horizontal segment through the view's centre lights one row, every column it spans,
    /// each pixel once, in its colour.
    #[test]
    fn a_horizontal_line_is_one_row_without_gaps() {
        let mut image = LineImage::new(64, 48);
        let red = [1.0, 0.0, 0.0, 1.0];
        let n = draw_lines(
            &mut image,
            &camera(),
            &lines(&[[-0.5, 0.01, -1.0], [0.5, 0.01, -1.0]], &[red, red]),
        );
        assert_eq!(n, 1);
        let px = lit(&image);
        // x from (−0.5·(4/3)⁻¹ + 1)·32 = 20 to 44 (the aspect stretches x by 4/3).
        let xs: Vec<u32> = px.iter().map(|p| p.0).collect();
        assert!(px.iter().all(|p| p.1 == px[0].1), "one row: {px:?}");
        assert_eq!(xs, (20..=44).collect::<Vec<_>>());
        assert_eq!(image.get(30, px[0].1), Vec4::new(1.0, 0.0, 0.0, 1.0));
        assert_eq!(image.drawn_rect(), Some([20, px[0].1, 45, px[0].1 + 1]));
        assert_eq!(LineImage::new(4, 4).drawn_rect(), None);
    }

    /// A steep segment lights one pixel per row; colours are interpolated along the line.
    #[test]
    fn a_steep_line_is_one_pixel_a_row_with_blended_colours() {
        let mut image = LineImage::new(40, 40);
        let (black, white) = ([0.0, 0.0, 0.0, 1.0], [1.0, 1.0, 1.0, 1.0]);
        draw_lines(
            &mut image,
            &camera(),
            &lines(&[[0.1, -0.8, -1.0], [0.2, 0.8, -1.0]], &[black, white]),
        );
        let px = lit(&image);
        let mut rows: Vec<u32> = px.iter().map(|p| p.1).collect();
        rows.dedup();
        assert_eq!(rows.len(), px.len(), "one pixel a row");
        assert!(rows.windows(2).all(|w| w[1] == w[0] + 1), "no gaps");
        // Row 0 is the top: the white end (y = +0.8) is near the top.
        let top = image.get(px[0].0, px[0].1);
        let bottom = image.get(px.last().unwrap().0, px.last().unwrap().1);
        assert!(top.x > 0.9 && bottom.x < 0.1, "{top} {bottom}");
    }

    /// Segments behind the eye draw nothing; one crossing the eye's plane keeps its part in
    /// front; one beside the view is cut away; `every` thins the list.
    #[test]
    fn lines_are_cut_at_the_near_plane_and_the_image() {
        let c = [1.0; 4];
        let mut image = LineImage::new(32, 32);
        assert_eq!(
            draw_lines(
                &mut image,
                &camera(),
                &lines(&[[0.0, 0.0, 1.0], [0.1, 0.0, 2.0]], &[c, c])
            ),
            0
        );
        assert!(lit(&image).is_empty());
        // From behind the eye to in front of it, off the axis: the front part only, which
        // runs from far away at the image's edge towards (0.5, 0, −1).
        let n = draw_lines(
            &mut image,
            &camera(),
            &lines(&[[0.5, 0.0, 1.0], [0.5, 0.0, -1.0]], &[c, c]),
        );
        assert_eq!(n, 1);
        let px = lit(&image);
        assert!(!px.is_empty());
        assert!(
            px.iter().all(|&(x, _)| x >= 24),
            "right of (0.5, 0, −1): {px:?}"
        );
        let mut image = LineImage::new(32, 32);
        assert_eq!(
            draw_lines(
                &mut image,
                &camera(),
                &lines(&[[3.0, 0.0, -1.0], [4.0, 0.5, -1.0]], &[c, c])
            ),
            0
        );
        // Ten segments, every third: four drawn.
        let positions: Vec<[f32; 3]> = (0..10)
            .flat_map(|i| {
                let y = -0.9 + 0.18 * i as f32;
                [[-0.5, y, -1.0], [0.5, y, -1.0]]
            })
            .collect();
        let colours = vec![c; 20];
        let mut thin = lines(&positions, &colours);
        thin.every = 3;
        assert_eq!(draw_lines(&mut image, &camera(), &thin), 4);
    }

    /// Alpha blends over what is drawn, in order; the image is the same for any number of
    /// threads (bands) and whatever the bands cut.
    #[test]
    fn blending_follows_the_list_and_not_the_threads() {
        let positions: Vec<[f32; 3]> = (0..200)
            .flat_map(|i| {
                let a = i as f32 * 0.37;
                [
                    [a.cos() * 0.9, a.sin() * 0.9, -1.0],
                    [-(a * 1.3).sin() * 0.8, (a * 0.7).cos() * 0.8, -1.5],
                ]
            })
            .collect();
        let colours: Vec<[f32; 4]> = (0..400)
            .map(|i| [(i % 7) as f32 / 7.0, 0.5, 1.0, 0.3 + (i % 5) as f32 * 0.1])
            .collect();
        let draw = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut image = LineImage::new(97, 71);
            pool.install(|| draw_lines(&mut image, &camera(), &lines(&positions, &colours)));
            image
        };
        let one = draw(1);
        assert!(one == draw(3), "thread count changed the image");
        let a = 0.5;
        let mut image = LineImage::new(16, 16);
        let half_red = [1.0, 0.0, 0.0, a];
        draw_lines(
            &mut image,
            &camera(),
            &lines(
                &[
                    [-0.9, 0.01, -1.0],
                    [0.9, 0.01, -1.0],
                    [-0.9, 0.01, -1.0],
                    [0.9, 0.01, -1.0],
                ],
                &[half_red; 4],
            ),
        );
        let p = lit(&image)[3];
        let c = image.get(p.0, p.1);
        // Twice half red: C = 0.5 + 0.5·0.5, A = 0.75.
        assert!(
            (c.x - 0.75).abs() < 1e-6 && (c.w - 0.75).abs() < 1e-6,
            "{c}"
        );
    }

    /// Non-finite positions and degenerate segments draw nothing or one pixel, never panic;
    /// an orthographic camera projects without perspective.
    #[test]
    fn odd_segments_and_orthographic_cameras() {
        let c = [1.0; 4];
        let mut image = LineImage::new(20, 20);
        let odd = [
            [f32::NAN, 0.0, -1.0],
            [0.0, 0.0, -1.0],
            [f32::INFINITY, 0.0, -1.0],
            [0.0, 0.0, -1.0],
            [0.0, 0.0, -1.0],
            [0.0, 0.0, -1.0],
        ];
        assert_eq!(draw_lines(&mut image, &camera(), &lines(&odd, &[c; 6])), 1);
        assert_eq!(lit(&image).len(), 1, "a point is one pixel");
        let ortho = Camera::new(
            Vec3::ZERO,
            Vec3::NEG_Z,
            Vec3::Y,
            Projection::Orthographic { height: 2.0 },
        )
        .unwrap();
        let mut near = LineImage::new(20, 20);
        let mut far = LineImage::new(20, 20);
        draw_lines(
            &mut near,
            &ortho,
            &lines(&[[-0.5, 0.0, -1.0], [0.5, 0.0, -1.0]], &[c, c]),
        );
        draw_lines(
            &mut far,
            &ortho,
            &lines(&[[-0.5, 0.0, -9.0], [0.5, 0.0, -9.0]], &[c, c]),
        );
        assert!(near == far, "depth does not shrink an orthographic line");
        let mut empty = LineImage::new(0, 5);
        assert_eq!(draw_lines(&mut empty, &camera(), &lines(&[], &[])), 0);
    }
}
