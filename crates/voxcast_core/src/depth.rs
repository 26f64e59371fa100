//! First as "distance to the first voxel", the lecture's third projection scheme: a depth
//! image. Each pixel shows how far along its ray First found the target value — the refined
//! hit's distance from the eye, in world units — on a scale fixed by the view, not by the
//! image: white where the volume's box comes nearest to the eye, dark grey at its farthest
//! corner ([`depth_scale`]), so two depth images of one view compare by shade. A surface that
//! fills only a slice of the box's depth (a sphere in a head: hits 98–125 on a 73–178 scale)
//! then shows as nearly one grey; [`DepthMap::on_hits`] stretches the scale to the hits' own
//! range instead, so its shape shows. A pixel whose rays found no target keeps the background
//! colour.
//!
//! [`crate::cost::render_depth`] makes it: the cost map's march, which is the render's (same
//! rays, same skipping, same refinement), keeps each ray's hit distance; with supersampling a
//! pixel's depth is the mean over its rays that hit. The raw distances can be written as a
//! 2-D NRRD ([`DepthMap::nrrd`]) for other tools.

use crate::camera::Camera;
use crate::image_out::LinearImage;
use crate::numbers::sig;
use crate::render::Cancelled;
use glam::Vec3;

/// The grey of the nearest distance on the scale (white)…
pub const NEAR_SHADE: f32 = 1.0;
/// …and of the farthest (dark grey, apart from a black background).
pub const FAR_SHADE: f32 = 0.15;

/// Why there is no depth image.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum DepthError {
    #[error(
        "a depth image shows where First found its target value: choose the method First \
         (now {0})"
    )]
    NotFirst(&'static str),
    #[error(transparent)]
    Cancelled(#[from] Cancelled),
}

/// Each pixel's hit distance, row by row, and the view's scale.
#[derive(Clone, Debug, PartialEq)]
pub struct DepthMap {
    pub width: u32,
    pub height: u32,
    /// World units from the eye; NaN where no ray of the pixel found the target.
    pub depth: Vec<f32>,
    /// The scale: the volume's box nearest to the eye and its farthest corner, or (after
    /// [`DepthMap::on_hits`]) the nearest and farthest hit.
    pub near: f32,
    pub far: f32,
    /// Whether the scale is the hits' own range.
    pub on_hits: bool,
}

/// The distances from `camera`'s eye to the nearest point of the box `lo..hi` (0 with the eye
/// inside it) and to its farthest corner: the depth image's scale.
pub fn depth_scale(camera: &Camera, lo: Vec3, hi: Vec3) -> (f32, f32) {
    let eye = camera.eye;
    let near = eye.clamp(lo, hi).distance(eye);
    // The farthest corner lies, along each axis, on the face farther from the eye.
    let far = (eye - lo).abs().max((eye - hi).abs()).length();
    (near, far.max(near + f32::EPSILON))
}

impl DepthMap {
    /// The grey of distance `t`: [`NEAR_SHADE`] at `near` to [`FAR_SHADE`] at `far`, linear.
    pub fn shade(&self, t: f32) -> f32 {
        let x = ((t - self.near) / (self.far - self.near)).clamp(0.0, 1.0);
        NEAR_SHADE + (FAR_SHADE - NEAR_SHADE) * x
    }

    /// The image: each hit's grey, `background` where no ray hit.
    pub fn image(&self, background: Vec3) -> LinearImage {
        let grey = |t: f32| {
            if t.is_nan() {
                background
            } else {
                Vec3::splat(self.shade(t))
            }
        };
        LinearImage {
            width: self.width,
            height: self.height,
            pixels: self.depth.iter().map(|&t| grey(t)).collect(),
        }
    }

    /// The same distances on the hits' own scale: white the nearest hit, dark grey the
    /// farthest (all white where every hit lies at one distance; unchanged without hits).
    pub fn on_hits(&self) -> Self {
        let (near, far) = self.range().unwrap_or((self.near, self.far));
        Self {
            near,
            far: far.max(near + near.abs() * f32::EPSILON + f32::MIN_POSITIVE),
            on_hits: true,
            ..self.clone()
        }
    }

    /// The nearest and farthest hit in the image, if any ray hit.
    pub fn range(&self) -> Option<(f32, f32)> {
        let hits = self.depth.iter().copied().filter(|t| !t.is_nan());
        hits.fold(None, |r, t| match r {
            None => Some((t, t)),
            Some((a, b)) => Some((a.min(t), b.max(t))),
        })
    }

    /// The scale in words, and the hits' range — one wording for Render image, the preview's
    /// legend and `render --depth`.
    pub fn scale_words(&self) -> String {
        let hits = match self.range() {
            Some((a, b)) => format!("the hits here lie {} to {} away", sig(a), sig(b)),
            None => "no ray found the target value".into(),
        };
        if self.on_hits {
            return match self.range() {
                Some((a, b)) => format!(
                    "Distance from the eye, world units: white {} (the nearest hit), dark grey \
                     {} (the farthest); no hit: the background",
                    sig(a),
                    sig(b)
                ),
                None => "Distance from the eye: no ray found the target value".into(),
            };
        }
        format!(
            "Distance from the eye, world units: white {} (where the volume's box comes \
             nearest), dark grey {} (its farthest corner); {hits}; no hit: the background",
            sig(self.near),
            sig(self.far),
        )
    }

    /// The raw distances as a 2-D NRRD (32-bit floats, little-endian; NaN where no ray hit).
    pub fn nrrd(&self) -> Vec<u8> {
        let mut out = format!(
            "NRRD0004\n# Voxcast: First's hit distance from the eye (world units), NaN: no hit\n\
             type: float\ndimension: 2\nsizes: {} {}\nendian: little\nencoding: raw\n\n",
            self.width, self.height
        )
        .into_bytes();
        for t in &self.depth {
            out.extend_from_slice(&t.to_le_bytes());
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::composite::Method;
    use crate::cost::render_depth;
    use crate::settings::RenderSettings;
    use crate::trace::Scene;
    use crate::transfer::{ControlPoint, TransferFunction};
    use crate::volume::{Volume, VoxelData};
    use glam::UVec3;
    use std::sync::atomic::AtomicBool;

    /// A 20³ volume whose value is 1 inside the slab x ≥ 10 (voxel centres) and 0 elsewhere.
    fn slab() -> crate::Prepared {
        let n = 20usize;
        let data = (0..n * n * n)
            .map(|i| if i % n >= 10 { 1.0 } else { 0.0 })
            .collect();
        Volume::new(
            "slab",
            UVec3::splat(n as u32),
            Vec3::ONE,
            VoxelData::F32(data),
        )
        .unwrap()
        .into()
    }

    fn grey() -> TransferFunction {
        TransferFunction::new(
            "grey",
            vec![
                ControlPoint::new(0.0, [0.0; 3], 0.0),
                ControlPoint::new(1.0, [1.0; 3], 1.0),
            ],
        )
        .unwrap()
    }

    fn first() -> RenderSettings {
        RenderSettings {
            method: Method::First,
            target: Some(0.5),
            shading: false,
            ..RenderSettings::default()
        }
    }

    /// Looking along +x at the slab's face, every ray hits where the value crosses 0.5 —
    /// half way between the voxel centres 9 and 10 — so the depth is that plane's distance
    /// along each ray: the centre pixel's is the eye's distance to it, an edge pixel's longer
    /// by 1/cos of its angle.
    #[test]
    fn the_depth_of_a_plane_is_its_distance_along_each_ray() {
        let v = slab();
        let (lo, hi) = v.bounds();
        let centre = (lo + hi) * 0.5;
        let eye = Vec3::new(-30.0, centre.y, centre.z);
        let camera = Camera::new(
            eye,
            centre,
            Vec3::Y,
            crate::camera::Projection::Perspective { fov_y_deg: 20.0 },
        )
        .unwrap();
        let scene = Scene::new(&v, &grey(), &first(), camera.forward()).unwrap();
        let (w, h) = (21, 21);
        let map =
            render_depth(&scene, &camera, (w, h), &|_, _| {}, &AtomicBool::new(false)).unwrap();
        // The crossing: half way between the lattice points 9 and 10 (spacing 1).
        let plane_x = lo.x + 9.5;
        let rays = camera.rays(w, h);
        for y in 0..h {
            for x in 0..w {
                let ray = rays.ray(x as f32 + 0.5, y as f32 + 0.5);
                let expect = (plane_x - eye.x) / ray.dir.x;
                let t = map.depth[(y * w + x) as usize];
                assert!(
                    (t - expect).abs() < 1e-3 * expect,
                    "({x}, {y}): {t} vs {expect}"
                );
            }
        }
        // The scale: the box's near face and its far corners.
        let (near, far) = (map.near, map.far);
        assert!((near - (lo.x - eye.x)).abs() < 1e-4, "{near}");
        assert!(
            far > hi.x - eye.x && far < (hi - eye).length() + 1e-3,
            "{far}"
        );
        // Nearer is brighter; the image holds the hits' shades.
        let image = map.image(Vec3::ZERO);
        let centre_px = image.get(w / 2, h / 2).x;
        let corner_px = image.get(0, 0).x;
        assert!(
            centre_px > corner_px && corner_px > FAR_SHADE,
            "{centre_px} {corner_px}"
        );
    }

    /// On the hits' own range the nearest hit is white and the farthest dark grey, whatever
    /// part of the box they fill; the distances are the same, only the scale moved; one
    /// distance for every hit is all white; no hit leaves the scale alone.
    #[test]
    fn the_hits_range_stretches_the_scale_to_the_hits() {
        let map = DepthMap {
            width: 4,
            height: 1,
            depth: vec![100.0, 110.0, f32::NAN, 120.0],
            near: 50.0,
            far: 250.0,
            on_hits: false,
        };
        let hits = map.on_hits();
        let bits = |d: &DepthMap| d.depth.iter().map(|t| t.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&hits), bits(&map));
        assert_eq!((hits.near, hits.far, hits.on_hits), (100.0, 120.0, true));
        let bg = Vec3::new(0.0, 0.0, 0.3);
        let shades: Vec<f32> = hits.image(bg).pixels.iter().map(|p| p.x).collect();
        assert_eq!(shades[0], NEAR_SHADE);
        assert!((shades[1] - 0.5 * (NEAR_SHADE + FAR_SHADE)).abs() < 1e-6);
        assert!((shades[3] - FAR_SHADE).abs() < 1e-6);
        assert_eq!(hits.image(bg).pixels[2], bg);
        // On the box's scale the three hits span a tenth of the greys.
        let boxed: Vec<f32> = map.image(bg).pixels.iter().map(|p| p.x).collect();
        assert!((boxed[0] - boxed[3]).abs() < 0.1 * (NEAR_SHADE - FAR_SHADE) + 1e-6);
        assert!(hits.scale_words().contains("white 100 (the nearest hit)"));
        assert!(hits.scale_words().contains("dark grey 120 (the farthest)"));
        let flat = DepthMap {
            depth: vec![7.0; 4],
            ..map.clone()
        };
        assert!(
            flat.on_hits()
                .image(bg)
                .pixels
                .iter()
                .all(|p| p.x == NEAR_SHADE)
        );
        let none = DepthMap {
            depth: vec![f32::NAN; 4],
            ..map
        };
        assert_eq!((none.on_hits().near, none.on_hits().far), (50.0, 250.0));
    }

    /// Rays that find no target keep the background; other methods have no depth image; the
    /// NRRD holds the distances bit for bit.
    #[test]
    fn misses_other_methods_and_the_raw_file() {
        let v = slab();
        let (lo, hi) = v.bounds();
        // From the empty side, looking away from the slab: nothing to find.
        let camera = Camera::framing(lo, hi, Vec3::new(-1.0, 0.2, 0.1), Vec3::Y).unwrap();
        let mut s = first();
        s.target = Some(2.0);
        let scene = Scene::new(&v, &grey(), &s, camera.forward()).unwrap();
        let map =
            render_depth(&scene, &camera, (8, 6), &|_, _| {}, &AtomicBool::new(false)).unwrap();
        assert!(map.depth.iter().all(|t| t.is_nan()));
        assert_eq!(map.range(), None);
        let bg = Vec3::new(0.1, 0.2, 0.3);
        assert!(map.image(bg).pixels.iter().all(|p| *p == bg));
        assert!(map.scale_words().contains("no ray found the target value"));

        let s = RenderSettings::default();
        let scene = Scene::new(&v, &grey(), &s, camera.forward()).unwrap();
        let err = render_depth(&scene, &camera, (8, 6), &|_, _| {}, &AtomicBool::new(false));
        assert!(matches!(err, Err(DepthError::NotFirst(_))), "{err:?}");

        let scene = Scene::new(&v, &grey(), &first(), camera.forward()).unwrap();
        let map =
            render_depth(&scene, &camera, (8, 6), &|_, _| {}, &AtomicBool::new(false)).unwrap();
        assert!(map.range().is_some());
        let bytes = map.nrrd();
        let header_end = bytes.windows(2).position(|w| w == b"\n\n").unwrap() + 2;
        let header = std::str::from_utf8(&bytes[..header_end]).unwrap();
        assert!(header.contains("sizes: 8 6") && header.contains("type: float"));
        let floats: Vec<f32> = bytes[header_end..]
            .chunks(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
            .collect();
        assert_eq!(floats.len(), 48);
        for (a, b) in floats.iter().zip(&map.depth) {
            assert!(a.to_bits() == b.to_bits());
        }
    }

    /// The eye inside the box: the scale starts at 0.
    #[test]
    fn inside_the_box_the_scale_starts_at_the_eye() {
        let camera = Camera::new(
            Vec3::splat(1.0),
            Vec3::new(2.0, 1.0, 1.0),
            Vec3::Y,
            crate::camera::Projection::Perspective { fov_y_deg: 30.0 },
        )
        .unwrap();
        let (near, far) = depth_scale(&camera, Vec3::ZERO, Vec3::splat(4.0));
        assert_eq!(near, 0.0);
        assert!((far - Vec3::splat(3.0).length()).abs() < 1e-5);
    }
}
