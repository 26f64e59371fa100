//! The ray density over its scene, as RayVis draws it (seed 002, §3 and Listing A.3): each
//! pixel's ray marches the density volume with Sum, stops where it meets the scene — RayVis
//! shortens the march's `maxT` by the scene's hit distance; the sandbox's preview does the same
//! with its depth prepass — and its colour is laid over the scene's:
//! `pixel = C + (1 − O)·scene`, the scene's shaded colour where the ray met it, else the
//! background.
//!
//! The density volume lives in its own coordinates ([`super::grid::DenseDensity::to_volume`]):
//! world = volume + `origin`. The camera is given in world units and moved into the volume's;
//! the scene is traced in the world's.

use super::mesh::{Hit, TriangleScene};
use crate::camera::Camera;
use crate::image_out::LinearImage;
use crate::render::{Cancelled, Job, RenderStats, TileSlices};
use crate::slices::Deadline;
use crate::trace::Scene;
use glam::{Vec3, Vec4};
use std::sync::atomic::AtomicBool;

/// How the scene's meshes are drawn under the density (RayVis's scene shading modes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SceneShading {
    /// Smooth grey, lit from the eye (RayVis's default diffuse shading).
    #[default]
    Grey,
    /// Each mesh's own colour, lit the same way.
    Colour,
    /// Each mesh instance in a colour of its own ([`instance_colour`]), lit the same way: tells
    /// the instances apart where their own colours are alike.
    Instance,
    /// The surface's normal (turned towards the eye) as a colour, `0.5 + 0.5·n`, unlit.
    Normals,
    /// The barycentric coordinates within each triangle as a colour (red, green and blue at
    /// its first, second and third corner), unlit: shows the triangles.
    Barycentrics,
    /// Not drawn, and not stopping rays: the density alone.
    Hidden,
}

impl SceneShading {
    pub const ALL: [SceneShading; 6] = [
        Self::Grey,
        Self::Colour,
        Self::Instance,
        Self::Normals,
        Self::Barycentrics,
        Self::Hidden,
    ];

    /// The name the command line and the sandbox use.
    pub const fn name(self) -> &'static str {
        match self {
            Self::Grey => "grey",
            Self::Colour => "colour",
            Self::Instance => "instance",
            Self::Normals => "normals",
            Self::Barycentrics => "barycentrics",
            Self::Hidden => "hidden",
        }
    }

    /// One line for help and tooltips.
    pub const fn doc(self) -> &'static str {
        match self {
            Self::Grey => "The scene in smooth grey, lit from the eye (RayVis's default).",
            Self::Colour => "Each mesh in its own colour, lit from the eye.",
            Self::Instance => "Each mesh instance in a colour of its own, lit from the eye.",
            Self::Normals => "The surface normal as a colour (0.5 + 0.5·n), unlit.",
            Self::Barycentrics => {
                "Each triangle's barycentric coordinates as red, green and blue, unlit."
            }
            Self::Hidden => "No scene: the density alone, and rays are not stopped by meshes.",
        }
    }

    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|m| m.name() == s || (s == "color" && *m == Self::Colour))
    }
}

/// Light every surface gets whatever its angle, so walls seen edge-on stay visible.
pub const AMBIENT: f32 = 0.25;

/// Mesh instance `i`'s colour: hues a golden angle apart (no two neighbours alike), full
/// saturation at 0.85 brightness.
pub fn instance_colour(i: usize) -> Vec3 {
    let hue = (i as f32 * 0.618_034).fract() * 6.0;
    let x = 1.0 - ((hue % 2.0) - 1.0).abs();
    let rgb = match hue as u32 {
        0 => Vec3::new(1.0, x, 0.0),
        1 => Vec3::new(x, 1.0, 0.0),
        2 => Vec3::new(0.0, 1.0, x),
        3 => Vec3::new(0.0, x, 1.0),
        4 => Vec3::new(x, 0.0, 1.0),
        _ => Vec3::new(1.0, 0.0, x),
    };
    rgb * 0.85
}

/// The shaded colour of `hit` seen along `dir`: for grey, the mesh's colour and the
/// instance's, that base times `(AMBIENT + (1 − AMBIENT)·|n·d|)`; the normal or the
/// barycentric coordinates as they are; `None` when the scene is hidden.
pub fn shade_hit(scene: &TriangleScene, hit: &Hit, dir: Vec3, mode: SceneShading) -> Option<Vec3> {
    let base = match mode {
        SceneShading::Grey => Vec3::splat(0.8),
        SceneShading::Colour => scene.meshes[hit.mesh].color,
        SceneShading::Instance => instance_colour(hit.mesh),
        SceneShading::Normals => return Some(normal_colour(hit.normal)),
        SceneShading::Barycentrics => return Some(hit.barycentric.clamp(Vec3::ZERO, Vec3::ONE)),
        SceneShading::Hidden => return None,
    };
    let lambert = hit.normal.dot(dir.normalize_or_zero()).abs();
    Some(base * (AMBIENT + (1.0 - AMBIENT) * lambert))
}

/// A unit normal as a colour, `0.5 + 0.5·n`.
pub fn normal_colour(n: Vec3) -> Vec3 {
    Vec3::splat(0.5) + 0.5 * n
}

/// A triangle scene as the opaque surface a density's rays stop at (the CPU's twin of the
/// preview's depth prepass): rays in the volume's coordinates, the scene at `origin` + them.
#[derive(Clone, Copy)]
pub struct SceneSurface<'v> {
    pub triangles: &'v TriangleScene,
    pub origin: Vec3,
    pub shading: SceneShading,
}

impl SceneSurface<'_> {
    /// Where `ray` (volume coordinates) meets the scene, if it is drawn: distance and colour.
    pub fn hit(&self, ray: &crate::ray::Ray) -> Option<(f32, Vec3)> {
        if self.shading == SceneShading::Hidden {
            return None;
        }
        let hit =
            self.triangles
                .intersect(ray.origin + self.origin, ray.dir, ray.t_min, ray.t_max)?;
        Some((
            hit.t,
            shade_hit(self.triangles, &hit, ray.dir, self.shading)?,
        ))
    }
}

/// One view of a density over its scene: the density volume resolved with its settings, where
/// its voxel `(0, 0, 0)` lies in the world (`origin`), the scene, how it is drawn, and the
/// camera (world units).
#[derive(Clone, Copy)]
pub struct DensityView<'v, 'a> {
    pub volume_scene: &'v Scene<'a>,
    pub origin: Vec3,
    pub triangles: &'v TriangleScene,
    pub shading: SceneShading,
    pub camera: &'v Camera,
}

/// Rays per side of the grid [`DensityView::fit_sum_range`] samples.
pub const FIT_GRID: u32 = 32;

/// The share of the sampled sums [`DensityView::fit_sum_range`] keeps below the range's top.
pub const FIT_PERCENTILE: f32 = 0.95;

impl DensityView<'_, '_> {
    /// The camera moved into the volume's coordinates.
    fn shifted_camera(&self) -> Camera {
        Camera {
            eye: self.camera.eye - self.origin,
            target: self.camera.target - self.origin,
            ..*self.camera
        }
    }

    /// Where `ray` (volume coordinates) meets the scene, if it is drawn: distance and colour.
    fn surface(&self, ray: &crate::ray::Ray) -> Option<(f32, Vec3)> {
        SceneSurface {
            triangles: self.triangles,
            origin: self.origin,
            shading: self.shading,
        }
        .hit(ray)
    }

    /// The picture at `width × height`. Progress and cancel as [`crate::render::render`].
    pub fn render(
        &self,
        (width, height): (u32, u32),
        progress: &(dyn Fn(usize, usize) + Sync),
        cancel: &AtomicBool,
    ) -> Result<(LinearImage, RenderStats), Cancelled> {
        let shifted = self.shifted_camera();
        let surface = |ray: &crate::ray::Ray| self.surface(ray);
        let mut job = Job::plain(
            self.volume_scene,
            &shifted,
            (width, height),
            progress,
            cancel,
        );
        job.surface = Some(&surface);
        let (pixels, stats) = job
            .run_on_volume(
                |out, background, behind| {
                    let under = behind.unwrap_or(background);
                    Vec4::from((out.color + under * (1.0 - out.opacity), 1.0))
                },
                &mut TileSlices::default(),
                Deadline::NONE,
            )?
            .whole();
        let mut image = LinearImage::new(width, height);
        for (i, p) in pixels.into_iter().enumerate() {
            image.set(i as u32 % width, i as u32 / width, p.truncate());
        }
        Ok((image, stats))
    }

    /// A Sum range fitted to the view: 0 to the [`FIT_PERCENTILE`] point of the sums gathered
    /// by a [`FIT_GRID`]² grid of the camera's rays (each stopped at the scene unless it is
    /// hidden), counting only rays that gathered something — so most of the picture spans
    /// inferno and the densest twentieth saturates. `None` when no sampled ray gathered
    /// anything.
    pub fn fit_sum_range(&self, (width, height): (u32, u32)) -> Option<(f32, f32)> {
        let rays = self.shifted_camera().rays(width, height);
        let mut sums: Vec<f32> = Vec::new();
        for j in 0..FIT_GRID {
            for i in 0..FIT_GRID {
                let x = (i as f32 + 0.5) / FIT_GRID as f32 * width as f32;
                let y = (j as f32 + 0.5) / FIT_GRID as f32 * height as f32;
                let mut ray = rays.ray(x, y);
                if let Some((t, _)) = self.surface(&ray) {
                    ray.t_max = t;
                }
                let t = crate::trace::trace_ray(self.volume_scene, &ray, [i, j]);
                if let Some(d) = t.sum
                    && d.sum > 0.0
                    && d.sum.is_finite()
                {
                    sums.push(d.sum);
                }
            }
        }
        if sums.is_empty() {
            return None;
        }
        let k = ((sums.len() - 1) as f32 * FIT_PERCENTILE) as usize;
        let top = *sums.select_nth_unstable_by(k, f32::total_cmp).1;
        (top > 0.0).then_some((0.0, top))
    }
}

#[cfg(test)]
mod tests {
    use super::super::mesh::Mesh;
    use super::*;
    use crate::camera::Projection;
    use crate::composite::Method;
    use crate::settings::RenderSettings;
    use crate::transfer::TransferFunction;
    use crate::volume::{Volume, VoxelData};
    use glam::UVec3;

    /// A constant density of 1 over 21³ cells of edge 1, whose voxel (0, 0, 0) sits at
    /// `origin`; a grey ramp, opaque, so a pixel's grey is Sum's fraction of its range.
    fn setup(origin: Vec3) -> (crate::Prepared, TransferFunction, RenderSettings, Camera) {
        let v = Volume::new(
            "ones",
            UVec3::splat(21),
            Vec3::ONE,
            VoxelData::F32(vec![1.0; 21 * 21 * 21]),
        )
        .unwrap();
        // The table spans [1, 2] (a constant volume): black at 1, white at 2.
        let tf = TransferFunction::ramp(1.0, 2.0, 1.0).unwrap();
        let tf = TransferFunction::new(
            "opaque grey",
            tf.points()
                .iter()
                .map(|p| crate::transfer::ControlPoint::new(p.value, p.color, 1.0))
                .collect(),
        )
        .unwrap();
        let s = RenderSettings {
            method: Method::Sum,
            sum_range: Some((0.0, 40.0)),
            early_termination: false,
            jitter: false,
            ..RenderSettings::default()
        };
        // Looking down −z at the volume's centre from 30 units away, orthographic.
        let centre = origin + Vec3::splat(10.0);
        let camera = Camera::new(
            centre + Vec3::Z * 30.0,
            centre,
            Vec3::Y,
            Projection::Orthographic { height: 10.0 },
        )
        .unwrap();
        (v.into(), tf, s, camera)
    }

    fn wall_at(z: f32, centre: Vec3) -> TriangleScene {
        let c = |x: f32, y: f32| Vec3::new(centre.x + x, centre.y + y, z);
        TriangleScene {
            meshes: vec![Mesh::from_quads(
                "wall",
                Vec3::new(0.2, 0.4, 0.6),
                &[[
                    c(-50.0, -50.0),
                    c(50.0, -50.0),
                    c(50.0, 50.0),
                    c(-50.0, 50.0),
                ]],
            )],
        }
    }

    fn centre_pixel(
        origin: Vec3,
        triangles: &TriangleScene,
        shading: SceneShading,
    ) -> (Vec3, RenderStats) {
        let (v, tf, s, camera) = setup(origin);
        let scene = Scene::new(&v, &tf, &s, camera.forward()).unwrap();
        let view = DensityView {
            volume_scene: &scene,
            origin,
            triangles,
            shading,
            camera: &camera,
        };
        let (image, stats) = view
            .render((9, 9), &|_, _| {}, &AtomicBool::new(false))
            .unwrap();
        (image.get(4, 4), stats)
    }

    #[test]
    fn the_scene_cuts_the_march_where_the_ray_meets_it() {
        for origin in [Vec3::ZERO, Vec3::new(-500.0, 30.0, 7.5)] {
            let centre = origin + Vec3::splat(10.0);
            let none = TriangleScene::default();
            // Through all 20 cells: S = 20 of the range's 40, grey 0.5.
            let (full, _) = centre_pixel(origin, &none, SceneShading::Grey);
            assert!((full.x - 0.5).abs() < 0.03, "{full}");
            // A wall halfway: S = 10, a quarter, and the wall is not seen (opaque density).
            let (half, _) = centre_pixel(origin, &wall_at(centre.z, centre), SceneShading::Grey);
            assert!((half.x - 0.25).abs() < 0.03, "{half}");
            // Hidden: the wall neither shows nor stops the rays.
            let (hidden, _) =
                centre_pixel(origin, &wall_at(centre.z, centre), SceneShading::Hidden);
            assert_eq!(hidden, full);
            // A wall in front of the volume: no sample at all, the wall's shade (it faces the
            // eye: fully lit).
            let (front, stats) = centre_pixel(
                origin,
                &wall_at(centre.z + 15.0, centre),
                SceneShading::Colour,
            );
            assert_eq!(stats.samples, 0);
            assert!(
                (front - Vec3::new(0.2, 0.4, 0.6)).abs().max_element() < 1e-5,
                "{front}"
            );
            let (grey, _) = centre_pixel(
                origin,
                &wall_at(centre.z + 15.0, centre),
                SceneShading::Grey,
            );
            assert!(
                (grey - Vec3::splat(0.8)).abs().max_element() < 1e-5,
                "{grey}"
            );
        }
    }

    #[test]
    fn the_fitted_range_tops_at_the_view_s_sums() {
        let origin = Vec3::new(3.0, -2.0, 1.0);
        let (v, tf, s, camera) = setup(origin);
        let scene = Scene::new(&v, &tf, &s, camera.forward()).unwrap();
        let centre = origin + Vec3::splat(10.0);
        let none = TriangleScene::default();
        let wall = wall_at(centre.z, centre);
        let fit = |triangles: &TriangleScene, shading: SceneShading, camera: &Camera| {
            DensityView {
                volume_scene: &scene,
                origin,
                triangles,
                shading,
                camera,
            }
            .fit_sum_range((8, 8))
        };
        // Orthographic down −z through the constant 1: every ray gathers about 20.
        let (lo, hi) = fit(&none, SceneShading::Grey, &camera).unwrap();
        assert_eq!(lo, 0.0);
        assert!((hi - 20.0).abs() <= 1.0, "{hi}");
        // A wall halfway halves it; hidden, the wall does not count.
        let (_, half) = fit(&wall, SceneShading::Grey, &camera).unwrap();
        assert!((half - 10.0).abs() <= 1.0, "{half}");
        let (_, hidden) = fit(&wall, SceneShading::Hidden, &camera).unwrap();
        assert_eq!(hidden, hi);
        // Looking away from the volume: nothing gathered, no range.
        let away =
            Camera::new(camera.eye, camera.eye + Vec3::Z, Vec3::Y, camera.projection).unwrap();
        assert_eq!(fit(&none, SceneShading::Grey, &away), None);
    }

    #[test]
    fn edge_on_walls_keep_the_ambient_light_and_names_parse() {
        let scene = wall_at(0.0, Vec3::ZERO);
        let hit = scene.intersect(Vec3::Z, Vec3::NEG_Z, 0.0, 10.0).unwrap();
        let lit = shade_hit(&scene, &hit, Vec3::NEG_Z, SceneShading::Grey).unwrap();
        assert_eq!(lit, Vec3::splat(0.8));
        let grazing = shade_hit(&scene, &hit, Vec3::X, SceneShading::Grey).unwrap();
        assert_eq!(grazing, Vec3::splat(0.8 * AMBIENT));
        assert_eq!(shade_hit(&scene, &hit, Vec3::X, SceneShading::Hidden), None);
        // The wall faces +z (towards the eye): its normal colour is (0.5, 0.5, 1), unlit.
        let normals = shade_hit(&scene, &hit, Vec3::X, SceneShading::Normals).unwrap();
        assert_eq!(normals, Vec3::new(0.5, 0.5, 1.0));
        let instance = shade_hit(&scene, &hit, Vec3::NEG_Z, SceneShading::Instance).unwrap();
        assert_eq!(instance, instance_colour(0));
        // Barycentrics: the weights of the hit triangle's corners, summing to 1.
        let b = shade_hit(&scene, &hit, Vec3::X, SceneShading::Barycentrics).unwrap();
        let tri = &scene.meshes[hit.mesh].triangles[hit.triangle];
        let at = b.x * tri[0] + b.y * tri[1] + b.z * tri[2];
        assert!(at.abs_diff_eq(Vec3::ZERO, 1e-5) && (b.element_sum() - 1.0).abs() < 1e-5);
        // Neighbouring instances differ.
        for i in 0..8 {
            let (a, c) = (instance_colour(i), instance_colour(i + 1));
            assert!((a - c).abs().max_element() > 0.2, "{i}: {a} {c}");
        }
        for m in SceneShading::ALL {
            assert_eq!(SceneShading::parse(m.name()), Some(m));
        }
        assert_eq!(SceneShading::parse("color"), Some(SceneShading::Colour));
        assert_eq!(SceneShading::parse("shiny"), None);
    }
}
