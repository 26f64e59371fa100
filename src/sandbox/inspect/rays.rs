//! The virtual camera's rays and samples: one ray per pixel of its image, traced by the core
//! (`trace_ray`, which records every sample), its pixels rendered by the core, and every sample
//! shown in the scene as a small sphere in its transfer-function colour. The spheres are real
//! meshes drawn from a pool (shared mesh, one material per quantised colour), so they write
//! depth and the preview's rays stop at them. Nothing is recomputed unless the virtual camera,
//! the settings or the volume changed.
//!
//! Rays grow outwards from the camera at an adjustable speed and samples appear as a ray passes
//! them; the animation can be skipped. The lines themselves are painted over the preview by
//! the rays' overlay (`ui/ray_overlay.rs`), so they stay readable inside the volume.

use crate::sandbox::inspect::virtual_camera::VirtualCamera;
use crate::sandbox::shared::state::{MainCamera, RenderState, View, VolumeState};
use bevy::prelude::*;
use bevy::tasks::{Task, futures::check_ready};
use std::collections::HashMap;
use std::sync::atomic::AtomicBool;
use voxcast_core::clip::clip_interval;
use voxcast_core::image_out::LinearImage;
use voxcast_core::render::render;
use voxcast_core::trace::{RayTrace, Scene, trace_ray};
use voxcast_core::tunables as t;

/// One ray of the virtual camera: where it starts, its direction and its stretch in the box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayPath {
    pub origin: Vec3,
    pub dir: Vec3,
    /// `[t_enter, t_exit]` in the volume's box, if the ray meets it.
    pub interval: Option<(f32, f32)>,
}

/// The virtual camera's rays, their traces and its image, as last computed.
#[derive(Resource, Default)]
pub struct Inspection {
    /// Image size in pixels.
    pub size: UVec2,
    /// One per pixel, row by row.
    pub paths: Vec<RayPath>,
    /// Every ray's recorded trace, row by row; `None` when the samples exceed the budget.
    pub traces: Option<Vec<RayTrace>>,
    /// Samples over all rays, when traced; else how many were traced before the budget ran out.
    pub samples: usize,
    /// The virtual camera's image, rendered by the core.
    pub image: Option<LinearImage>,
    /// Why the samples are not shown (the budget), if they are not.
    pub message: Option<String>,
    /// The skip blocks the rays crossed and looked into (`voxcast_core::traffic`).
    pub blocks: Option<voxcast_core::traffic::BlockTraffic>,
    /// Bumped at every recomputation.
    pub generation: u64,
}

/// The pixel (ray) under the pointer in the image window, and the one selected.
#[derive(Resource, Default, Clone, Copy, PartialEq)]
pub struct RaySelection {
    pub hovered: Option<UVec2>,
    pub selected: Option<UVec2>,
    /// How many times a pixel was clicked (only grows): a level's step that asks for a click
    /// sees one made while it is open.
    pub clicks: u32,
}

impl RaySelection {
    /// A click on pixel `p`: it selects the pixel, or unselects it if it was the selected one.
    pub fn click(&mut self, p: UVec2) {
        self.selected = (self.selected != Some(p)).then_some(p);
        self.clicks = self.clicks.wrapping_add(1);
    }

    /// Nothing selected or hovered (a new image): the clicks counted so far stay counted.
    pub fn clear(&mut self) {
        *self = RaySelection {
            clicks: self.clicks,
            ..RaySelection::default()
        };
    }

    /// The selected ray's index in [`Inspection::paths`].
    pub fn selected_index(&self, size: UVec2) -> Option<usize> {
        self.selected.map(|p| ray_index(p, size))
    }

    /// The hovered ray's index in [`Inspection::paths`].
    pub fn hovered_index(&self, size: UVec2) -> Option<usize> {
        self.hovered.map(|p| ray_index(p, size))
    }
}

/// Index of pixel `p`'s ray in an image of `size` (rows in order, x fastest).
pub fn ray_index(p: UVec2, size: UVec2) -> usize {
    (p.y * size.x + p.x) as usize
}

/// The pixel of ray `i` in an image of `size`: the inverse of [`ray_index`].
pub fn ray_pixel(i: usize, size: UVec2) -> UVec2 {
    let w = size.x.max(1) as usize;
    UVec2::new((i % w) as u32, (i / w) as u32)
}

/// How the rays and samples are shown.
#[derive(Resource, Clone, PartialEq)]
pub struct InspectSettings {
    pub shown: bool,
    /// Volume diagonals per second ([`t::RAY_SPEED`]).
    pub speed: f32,
    /// Sphere transparency follows the sample's opacity.
    pub show_opacity: bool,
    pub budget: usize,
    /// Draw the skip blocks the rays crossed (`crate::sandbox::inspect::blocks`).
    pub show_blocks: bool,
}

impl Default for InspectSettings {
    fn default() -> Self {
        Self {
            shown: true,
            speed: t::RAY_SPEED.default,
            show_opacity: false,
            budget: t::SAMPLE_BUDGET.default as usize,
            show_blocks: false,
        }
    }
}

/// How far the rays have grown, world units from their origins.
#[derive(Resource, Default)]
pub struct RayAnimation {
    pub distance: f32,
}

impl RayAnimation {
    /// Shows every ray whole at once.
    pub fn skip(&mut self) {
        self.distance = f32::INFINITY;
    }
    pub fn replay(&mut self) {
        self.distance = 0.0;
    }
}

/// One pooled sphere: which ray it shows a sample of.
#[derive(Component)]
pub struct SampleSphere {
    pub ray: usize,
    /// Distance of the sample along its ray (when it appears).
    t: f32,
}

/// The spheres' shared mesh and materials.
#[derive(Resource, Default)]
struct Pool {
    /// The virtual camera the spheres belong to: they are its children and leave with it.
    owner: Option<Entity>,
    entities: Vec<Entity>,
    mesh: Option<Handle<Mesh>>,
    /// One material per quantised colour (and opacity, when it is shown).
    materials: HashMap<[u8; 4], Handle<StandardMaterial>>,
}

pub(crate) fn plugin(app: &mut App) {
    app.init_resource::<Inspection>()
        .init_resource::<InspectSettings>()
        .init_resource::<RaySelection>()
        .init_resource::<RayAnimation>()
        .init_resource::<Pool>()
        .init_resource::<InspectJob>()
        .add_message::<crate::sandbox::shared::pacing::KeepDrawing>()
        .add_systems(
            Update,
            (
                recompute,
                collect_inspection,
                place_spheres,
                fit_spheres_to_view,
                grow_rays,
                show_spheres,
            )
                .chain()
                .in_set(crate::sandbox::shared::schedule::Frame::Trace),
        );
}

/// The tracing under way off the frame, and what to do when it is done.
#[derive(Resource, Default)]
struct InspectJob {
    task: Option<Task<Inspection>>,
    /// Grow the rays again when it arrives (a new camera or volume).
    replay: bool,
}

/// Starts tracing the virtual camera's rays (on the task pool) when something they depend on
/// changed; a newer change replaces a tracing under way.
fn recompute(
    volume: Res<VolumeState>,
    render_state: Res<RenderState>,
    settings: Res<InspectSettings>,
    cameras: Query<Ref<VirtualCamera>>,
    mut inspection: ResMut<Inspection>,
    mut selection: ResMut<RaySelection>,
    mut job: ResMut<InspectJob>,
) {
    let Ok(vc) = cameras.single() else {
        // The mode has no virtual camera: nothing to inspect.
        job.task = None;
        if inspection.size != UVec2::ZERO {
            *inspection = Inspection {
                generation: inspection.generation + 1,
                ..default()
            };
            selection.clear();
        }
        return;
    };
    if vc.is_added() {
        selection.clear();
    }
    let changed = vc.is_changed()
        || volume.is_changed()
        || render_state.is_changed()
        || settings.is_changed();
    if !changed {
        return;
    }
    job.replay |= vc.is_changed() || volume.is_changed();
    let (volume, render_state, vc) = ((*volume).clone(), (*render_state).clone(), *vc);
    let (budget, generation) = (settings.budget, inspection.generation);
    job.task = Some(crate::sandbox::shared::tasks::spawn(async move {
        let mut next = Inspection {
            generation,
            ..default()
        };
        compute(&volume, &render_state, &vc, budget, &mut next);
        next
    }));
}

/// Takes in a finished tracing.
fn collect_inspection(
    mut job: ResMut<InspectJob>,
    mut inspection: ResMut<Inspection>,
    mut selection: ResMut<RaySelection>,
    mut animation: ResMut<RayAnimation>,
) {
    let Some(task) = job.task.as_mut() else {
        return;
    };
    let Some(next) = check_ready(task) else {
        return;
    };
    job.task = None;
    if next.size != inspection.size {
        selection.clear();
    }
    *inspection = next;
    if std::mem::take(&mut job.replay) {
        animation.replay();
    }
}

/// Fills `inspection` for the virtual camera `vc` (the systems' work, callable from tests).
pub fn compute(
    volume: &VolumeState,
    render_state: &RenderState,
    vc: &VirtualCamera,
    budget: usize,
    inspection: &mut Inspection,
) {
    let (w, h) = (vc.width.max(1), vc.height.max(1));
    let v = &volume.volume;
    let cut = render_state.settings.clip.resolve(v.bounds());
    let view = vc.view;
    inspection.size = UVec2::new(w, h);
    inspection.generation += 1;
    let rays = view.rays(w, h);
    inspection.paths = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let r = rays.ray(x as f32 + 0.5, y as f32 + 0.5);
            RayPath {
                origin: r.origin,
                dir: r.dir,
                interval: clip_interval(&r, &cut),
            }
        })
        .collect();
    let Ok(scene) = Scene::new(
        v,
        &render_state.transfer,
        &render_state.settings,
        view.forward(),
    ) else {
        inspection.traces = None;
        inspection.image = None;
        inspection.message = Some("these settings cannot be traced".into());
        return;
    };
    inspection.image = render(&scene, &view, w, h, &|_, _| {}, &AtomicBool::new(false))
        .ok()
        .map(|(img, _)| img);
    let keyed: Vec<(voxcast_core::ray::Ray, [u32; 2])> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| (view.pixel_ray(x, y, w, h), [x, y]))
        .collect();
    inspection.blocks = Some(voxcast_core::traffic::block_traffic(&scene, &keyed));
    let mut traces = Vec::with_capacity((w * h) as usize);
    let mut samples = 0usize;
    for y in 0..h {
        for x in 0..w {
            let trace = trace_ray(&scene, &view.pixel_ray(x, y, w, h), [x, y]);
            samples += trace.samples.len();
            if samples > budget {
                break;
            }
            traces.push(trace);
        }
        if samples > budget {
            break;
        }
    }
    inspection.samples = samples;
    if samples > budget {
        inspection.traces = None;
        inspection.message = Some(format!(
            "More than {budget} samples ({w}×{h} rays): the rays are drawn without them. Lower \
             the virtual camera's pixels, lengthen the step, or raise the sample budget."
        ));
    } else {
        inspection.traces = Some(traces);
        inspection.message = None;
    }
}

/// A sample sphere's radius: 0.3 of the step, so neighbours along a ray keep a gap of 0.4 step
/// between them and every sample shows on its own (at most 0.6 voxel, for coarse steps).
pub fn sphere_radius(volume: &VolumeState, render_state: &RenderState) -> f32 {
    let voxel = volume.volume.spacing().min_element();
    let step = render_state.settings.step.world(voxel);
    (step * SPHERE_RADIUS_PER_STEP).min(voxel * 0.6)
}

/// A sample sphere's radius as a fraction of the step (less than ½: samples never touch).
pub const SPHERE_RADIUS_PER_STEP: f32 = 0.3;

/// The smallest share of [`sphere_radius`] a ray seen end-on keeps (so its samples stay
/// visible, even where they must overlap on screen).
pub const END_ON_FLOOR: f32 = 0.2;

/// A sample sphere's radius on a ray along `dir` seen along `forward`: on screen the samples
/// of a ray are `step · sin θ` apart (θ between the ray and the line of sight), so the sphere
/// shrinks with `sin θ` to keep the gap between neighbours — down to [`END_ON_FLOOR`].
pub fn sphere_radius_seen(radius: f32, dir: Vec3, forward: Vec3) -> f32 {
    let sin = dir
        .normalize_or_zero()
        .cross(forward.normalize_or_zero())
        .length();
    radius * sin.max(END_ON_FLOOR)
}

/// Resizes the spheres of each ray for the main camera's view, when it or the spheres change.
fn fit_spheres_to_view(
    views: Query<Ref<View>, With<MainCamera>>,
    inspection: Res<Inspection>,
    volume: Res<VolumeState>,
    render_state: Res<RenderState>,
    mut spheres: Query<(&SampleSphere, &mut Transform)>,
) {
    let Ok(view) = views.single() else { return };
    if !(view.is_changed() || inspection.is_changed() || render_state.is_changed()) {
        return;
    }
    let Some(traces) = &inspection.traces else {
        return;
    };
    let radius = sphere_radius(&volume, &render_state);
    let forward = view.0.forward();
    for (sphere, mut transform) in &mut spheres {
        let Some(trace) = traces.get(sphere.ray) else {
            continue;
        };
        let r = sphere_radius_seen(radius, Vec3::from_array(trace.dir), forward);
        if transform.scale.x != r {
            transform.scale = Vec3::splat(r);
        }
    }
}

/// The material key: display colour in 5-bit steps, and opacity when it is shown.
fn color_key(rgba: [f32; 4], show_opacity: bool) -> [u8; 4] {
    let q = |c: f32| ((c.clamp(0.0, 1.0) * 31.0).round() as u8) * 8;
    let a = if show_opacity {
        q(rgba[3].max(0.1))
    } else {
        255
    };
    [q(rgba[0]), q(rgba[1]), q(rgba[2]), a]
}

/// The samples the spheres mark, and how they are shown.
#[derive(bevy::ecs::system::SystemParam)]
struct Marked<'w> {
    inspection: Res<'w, Inspection>,
    settings: Res<'w, InspectSettings>,
}

/// Puts a pooled sphere on every sample after a recomputation (or a change of look).
fn place_spheres(
    mut commands: Commands,
    marked: Marked,
    volume: Res<VolumeState>,
    render_state: Res<RenderState>,
    mut pool: ResMut<Pool>,
    cameras: Query<Entity, With<VirtualCamera>>,
    mut assets: crate::sandbox::shared::state::MeshAssets,
) {
    let Marked {
        inspection,
        settings,
    } = marked;
    if !(inspection.is_changed() || settings.is_changed()) {
        return;
    }
    // A new camera (a new mode): the old spheres left with the old one.
    let owner = cameras.single().ok();
    if pool.owner != owner {
        pool.owner = owner;
        pool.entities.clear();
    }
    let Some(owner) = owner else { return };
    let radius = sphere_radius(&volume, &render_state);
    let mesh = pool
        .mesh
        .get_or_insert_with(|| assets.meshes.add(Sphere::new(1.0).mesh().ico(1).unwrap()))
        .clone();
    let samples = sample_points(&inspection);
    // Grow the pool as needed; spare spheres are hidden.
    while pool.entities.len() < samples.len() {
        let e = commands
            .spawn((
                Mesh3d(mesh.clone()),
                Transform::default(),
                Visibility::Hidden,
                ChildOf(owner),
            ))
            .id();
        pool.entities.push(e);
    }
    for (i, &entity) in pool.entities.clone().iter().enumerate() {
        let mut sphere = commands.entity(entity);
        let Some(&(ray, p, t, rgba)) = samples.get(i) else {
            sphere.insert(Visibility::Hidden).remove::<(
                SampleSphere,
                crate::sandbox::shared::layers::Solid,
                crate::sandbox::shared::layers::Occluder,
            )>();
            continue;
        };
        let key = color_key(rgba, settings.show_opacity);
        let material = pool.material(key, &mut assets.materials);
        // Opaque spheres stop the preview's rays (and are in the CPU live view's image), and
        // those of a preview drawn below full resolution through a depth-only twin (`sharp`);
        // transparent ones are drawn over the volume.
        let opaque = key[3] == 255;
        if opaque {
            sphere.insert(crate::sandbox::shared::layers::Solid);
        } else {
            sphere.remove::<crate::sandbox::shared::layers::Solid>();
        }
        let layer = if opaque {
            crate::sandbox::shared::layers::OCCLUDER_LAYER
        } else {
            0
        };
        sphere.insert((
            SampleSphere { ray, t },
            // The mesh is a unit sphere: the transform scales it to the sample's radius.
            crate::sandbox::shared::layers::Occluder { radius: 1.0 },
            bevy::camera::visibility::RenderLayers::layer(layer),
            MeshMaterial3d(material),
            Transform::from_translation(p).with_scale(Vec3::splat(radius)),
        ));
    }
}

/// Every sample of every traced ray: its ray's index, position, distance along the ray and
/// colour and opacity looked up.
fn sample_points(inspection: &Inspection) -> Vec<(usize, Vec3, f32, [f32; 4])> {
    inspection
        .traces
        .iter()
        .flatten()
        .enumerate()
        .flat_map(|(r, trace)| {
            trace
                .samples
                .iter()
                .map(move |rec| (r, Vec3::from_array(rec.p_world), rec.t, rec.tf_rgba))
        })
        .collect()
}

impl Pool {
    /// The unlit material of colour `key` (translucent where its opacity is below one), made
    /// once.
    fn material(
        &mut self,
        key: [u8; 4],
        materials: &mut ResMut<Assets<StandardMaterial>>,
    ) -> Handle<StandardMaterial> {
        self.materials
            .entry(key)
            .or_insert_with(|| {
                let c = key.map(|v| v as f32 / 255.0);
                materials.add(StandardMaterial {
                    base_color: Color::srgba(c[0], c[1], c[2], c[3]),
                    unlit: true,
                    alpha_mode: if key[3] == 255 {
                        AlphaMode::Opaque
                    } else {
                        AlphaMode::Blend
                    },
                    ..default()
                })
            })
            .clone()
    }
}

/// How far the rays are drawn from their origins (the virtual camera's `eye` looking at
/// `target`): past the far side of the volume's box `(lo, hi)`.
pub fn reach(eye: Vec3, target: Vec3, (lo, hi): (Vec3, Vec3)) -> f32 {
    (target - eye).length() + (hi - lo).length()
}

/// Grows the rays while the animation runs, and keeps the window drawing until they reach
/// their full length.
fn grow_rays(
    time: Res<Time>,
    settings: Res<InspectSettings>,
    volume: Res<VolumeState>,
    cameras: Query<&VirtualCamera>,
    mut animation: ResMut<RayAnimation>,
    mut keep: MessageWriter<crate::sandbox::shared::pacing::KeepDrawing>,
) {
    if animation.distance.is_finite() {
        let (lo, hi) = volume.volume.bounds();
        animation.distance += settings.speed * (hi - lo).length() * time.delta_secs();
        let growing = cameras.single().is_ok_and(|vc| {
            settings.shown
                && vc.shown
                && animation.distance < reach(vc.view.eye, vc.view.target, (lo, hi))
        });
        if growing {
            keep.write(crate::sandbox::shared::pacing::KeepDrawing);
        }
    }
}

/// Shows the spheres the rays have reached (only the selected ray's while one is selected).
fn show_spheres(
    inspection: Res<Inspection>,
    selection: Res<RaySelection>,
    full: Option<Res<crate::sandbox::shared::quality::FullQuality>>,
    settings: Res<InspectSettings>,
    animation: Res<RayAnimation>,
    cameras: Query<&VirtualCamera>,
    mut spheres: Query<(&SampleSphere, &mut Visibility)>,
) {
    let vc_shown = cameras.single().is_ok_and(|c| c.shown);
    let selected = selection.selected_index(inspection.size);
    // Hidden while a comparison captures the preview: the CPU render has no meshes.
    let capturing = full.is_some_and(|f| f.0);
    for (s, mut visibility) in &mut spheres {
        let show = !capturing
            && settings.shown
            && vc_shown
            && s.t <= animation.distance
            && selected.is_none_or(|r| r == s.ray);
        visibility.set_if_neq(if show {
            Visibility::Visible
        } else {
            Visibility::Hidden
        });
    }
}

#[cfg(test)]
pub(crate) mod tests;
