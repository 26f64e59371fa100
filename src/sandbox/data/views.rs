//! RayVis's views around the density on show: the scene's meshes (grey or in their colours,
//! lit from the eye, writing depth so the preview's rays stop at them — RayVis shortens each
//! march at the scene's hit), the ray mesh (one line list: every counted ray from its start to
//! its hit or end) and the vector field (one line list: an arrow per sample cube). All hang
//! from one root placed at minus the density's origin, so the rays' world lines up with the
//! volume's coordinates.
//!
//! The line lists are built on the background pool (a million rays are two million vertices)
//! and swapped in when ready; the window keeps drawing the previous ones meanwhile. With the
//! CPU live view the lists are not meshes the window draws (a software rasterizer takes
//! microseconds a line): the CPU draws them over its image (`cpu_lines`).

use crate::sandbox::data::choices::{RayChoices, ViewChoices, ViewReport};
use crate::sandbox::data::cpu_lines::{CpuLines, CpuList};
use crate::sandbox::data::source::{RayScene, Shown};
use crate::sandbox::shared::state::{MainCamera, View, VolumeState};
use bevy::asset::RenderAssetUsages;
use bevy::camera::visibility::RenderLayers;
use bevy::mesh::PrimitiveTopology;
use bevy::prelude::*;
use bevy::tasks::{Task, futures::check_ready};
use std::sync::Arc;
use voxcast_core::rays::field::{Arrow, arrows};
use voxcast_core::rays::layered::{AMBIENT, SceneShading};
use voxcast_core::rays::lines::{GLYPH_SEGMENTS, LineParams, glyphs, padded, ray_lines};
use voxcast_core::rays::mesh::TriangleScene;

/// How far beyond the scene's box the ray mesh is drawn, as a share of its longest side.
const CLIP_PAD: f32 = 0.5;

/// The root every view hangs from, and the density it shows.
#[derive(Component)]
struct RayRoot(Arc<Shown>);

/// One of the scene's meshes (its index), coloured per vertex as the eye moves.
#[derive(Component)]
struct SceneMesh(usize);

/// The ray mesh's or the vector field's line list.
#[derive(Component, Clone, Copy, PartialEq, Eq)]
enum Lines {
    Rays,
    Field,
}

/// The line lists on the way, and what they were asked for.
#[derive(Resource, Default)]
struct Building {
    wanted: Option<(usize, ViewChoices)>,
    task: Option<Task<Geometry>>,
}

/// A line list: positions and linear colours, two vertices a segment.
type LineList = (Vec<[f32; 3]>, Vec<[f32; 4]>);

/// Built line lists: for the GPU's meshes (linear colours) and for the CPU (display colours).
struct Geometry {
    rays: Option<LineList>,
    field: Option<LineList>,
    cpu: Vec<Arc<CpuList>>,
    report: ViewReport,
}

pub(crate) fn plugin(app: &mut App) {
    app.init_resource::<ViewReport>()
        .init_resource::<Building>()
        .add_systems(
            Update,
            (
                place_root,
                spawn_scene,
                build_lines,
                swap_lines,
                show_lines,
                shade_scene,
            )
                .chain()
                .in_set(crate::sandbox::shared::schedule::Frame::Show),
        );
}

/// The density on show, if it was computed here.
fn shown(rays: &RayScene, volume: &VolumeState) -> Option<Arc<Shown>> {
    rays.on_show(volume).cloned()
}

/// Spawns the root for a new density, despawns it when another volume is shown.
fn place_root(
    mut commands: Commands,
    rays: Res<RayScene>,
    volume: Res<VolumeState>,
    roots: Query<(Entity, &RayRoot)>,
    mut building: ResMut<Building>,
    mut report: ResMut<ViewReport>,
) {
    if !(rays.is_changed() || volume.is_changed()) {
        return;
    }
    let now = shown(&rays, &volume);
    for (e, root) in &roots {
        if now.as_ref().is_some_and(|s| Arc::ptr_eq(s, &root.0)) {
            return;
        }
        commands.entity(e).despawn();
    }
    *building = Building::default();
    *report = ViewReport::default();
    if let Some(s) = now {
        commands.spawn((
            RayRoot(s.clone()),
            Transform::from_translation(-s.computed.origin),
            Visibility::Inherited,
        ));
    }
}

/// (Re)spawns the scene's meshes under the root when the root or the shading changes.
fn spawn_scene(
    mut commands: Commands,
    choices: Res<RayChoices>,
    roots: Query<(Entity, &RayRoot, Option<&Children>), Added<RayRoot>>,
    all_roots: Query<(Entity, &RayRoot)>,
    existing: Query<Entity, With<SceneMesh>>,
    mut last: Local<Option<SceneShading>>,
    mut assets: crate::sandbox::shared::state::MeshAssets,
) {
    let shading = choices.view.shading;
    let root = match roots.iter().next() {
        Some((e, r, _)) => Some((e, r.0.clone())),
        None if *last != Some(shading) => all_roots.iter().next().map(|(e, r)| (e, r.0.clone())),
        None => None,
    };
    let Some((root, shown)) = root else { return };
    *last = Some(shading);
    for e in &existing {
        commands.entity(e).despawn();
    }
    if shading == SceneShading::Hidden {
        return;
    }
    // One material for every mesh: white, unlit, coloured by its vertices.
    let material = assets.materials.add(StandardMaterial {
        unlit: true,
        double_sided: true,
        cull_mode: None,
        ..default()
    });
    for (i, m) in shown.computed.data.scene.meshes.iter().enumerate() {
        let positions: Vec<[f32; 3]> = m
            .triangles
            .iter()
            .flat_map(|t| t.map(|v| v.to_array()))
            .collect();
        let colours = vec![[0.8, 0.8, 0.8, 1.0]; positions.len()];
        let mesh = Mesh::new(PrimitiveTopology::TriangleList, usage())
            .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
            .with_inserted_attribute(Mesh::ATTRIBUTE_COLOR, colours);
        commands.spawn((
            SceneMesh(i),
            crate::sandbox::shared::layers::Solid,
            // The GPU's cameras draw it; the CPU live view has it in its image.
            RenderLayers::layer(crate::sandbox::shared::layers::SCENE_LAYER),
            Mesh3d(assets.meshes.add(mesh)),
            MeshMaterial3d(material.clone()),
            Transform::IDENTITY,
            ChildOf(root),
        ));
    }
}

fn usage() -> RenderAssetUsages {
    RenderAssetUsages::RENDER_WORLD | RenderAssetUsages::MAIN_WORLD
}

/// Colours the scene's vertices as the core's layered render shades a hit: flat, lit from
/// the eye (`shade_hit`), again whenever the view moves.
fn shade_scene(
    choices: Res<RayChoices>,
    views: Query<Ref<View>, With<MainCamera>>,
    scene: Query<(Ref<SceneMesh>, &Mesh3d, &ChildOf)>,
    roots: Query<&RayRoot>,
    mut meshes: ResMut<Assets<Mesh>>,
) {
    let Ok(view) = views.single() else { return };
    for (m, handle, parent) in &scene {
        if !(view.is_changed() || m.is_added() || choices.is_changed()) {
            continue;
        }
        let Ok(root) = roots.get(parent.parent()) else {
            continue;
        };
        let Some(mut mesh) = meshes.get_mut(&handle.0) else {
            continue;
        };
        let colours = vertex_shades(
            &root.0.computed.data.scene,
            m.0,
            view.0.eye + root.0.computed.origin,
            choices.view.shading,
        );
        mesh.insert_attribute(Mesh::ATTRIBUTE_COLOR, colours);
    }
}

/// Linear colours of mesh `index`'s vertices (three a triangle) seen from `eye` (the rays'
/// world), as the core's `shade_hit` shades a hit: the base (grey, the mesh's own colour or
/// its instance's) × (ambient + (1 − ambient)·|n·d|); the normal turned to the eye; or the
/// corners red, green and blue, so the GPU's interpolation gives the barycentric coordinates.
fn vertex_shades(
    scene: &TriangleScene,
    index: usize,
    eye: Vec3,
    shading: SceneShading,
) -> Vec<[f32; 4]> {
    use voxcast_core::rays::layered::{instance_colour, normal_colour};
    let m = &scene.meshes[index];
    let base = match shading {
        SceneShading::Colour => m.color,
        SceneShading::Instance => instance_colour(index),
        _ => Vec3::splat(0.8),
    };
    m.triangles
        .iter()
        .flat_map(|[a, b, c]| {
            let n = (*b - *a).cross(*c - *a).normalize_or_zero();
            let corners = [Vec3::X, Vec3::Y, Vec3::Z];
            let mut k = 0;
            [*a, *b, *c].map(|v| {
                let to_eye = (eye - v).normalize_or_zero();
                let s = match shading {
                    SceneShading::Normals => {
                        normal_colour(if n.dot(to_eye) < 0.0 { -n } else { n })
                    }
                    SceneShading::Barycentrics => corners[k],
                    _ => base * (AMBIENT + (1.0 - AMBIENT) * n.dot(to_eye).abs()),
                };
                k += 1;
                [s.x, s.y, s.z, 1.0]
            })
        })
        .collect()
}

/// Starts building the line lists when the density or their choices change.
fn build_lines(
    choices: Res<RayChoices>,
    roots: Query<&RayRoot>,
    mut building: ResMut<Building>,
    mut report: ResMut<ViewReport>,
) {
    let Some(root) = roots.iter().next() else {
        return;
    };
    let key = (Arc::as_ptr(&root.0) as usize, choices.view.clone());
    if building.wanted.as_ref() == Some(&key) {
        return;
    }
    let view = choices.view.clone();
    let shown = root.0.clone();
    building.task = Some(crate::sandbox::shared::tasks::spawn(async move {
        geometry(&shown, &view)
    }));
    building.wanted = Some(key);
    report.building = true;
}

/// The line lists `view` asks for.
fn geometry(shown: &Shown, view: &ViewChoices) -> Geometry {
    let c = &shown.computed;
    let mut report = ViewReport::default();
    let rays = view.mesh.then(|| {
        let bounds = c.data.scene.bounds().unwrap_or_else(|| {
            let lo = c.origin - 0.5 * c.density.params.cell;
            let v = &shown.volume;
            (lo, lo + v.bounds().1 + c.density.params.cell)
        });
        let lines = ray_lines(
            &c.set,
            &LineParams {
                filter: c.density.params.filter,
                tolerance: c.density.params.tolerance,
                stride: view.stride,
                clip: padded(bounds, CLIP_PAD),
            },
        );
        report.lines = lines.lines.len();
        report.left_out = lines.malformed + lines.outside;
        let (hit, miss) = (view.hit_colour, view.miss_colour);
        let mut positions = Vec::with_capacity(lines.lines.len() * 2);
        let mut colours = Vec::with_capacity(lines.lines.len() * 2);
        // Glyphs a hundredth of the drawn box across.
        let size = 0.01 * (bounds.1 - bounds.0).length();
        for l in &lines.lines {
            let [r, g, b] = if l.hit { hit } else { miss };
            positions.extend([l.from.to_array(), l.to.to_array()]);
            colours.extend([[r, g, b, 1.0]; 2]);
            if view.glyphs {
                for (a, z) in glyphs(l, size) {
                    positions.extend([a.to_array(), z.to_array()]);
                    colours.extend([[r, g, b, 1.0]; 2]);
                }
            }
        }
        (positions, colours)
    });
    let field = if view.field {
        match arrows(&c.density, view.cube, view.arrow_scale, view.min_count) {
            Ok(a) => {
                report.arrows = a.len();
                Some(arrow_lines(&a))
            }
            Err(e) => {
                report.field_error = Some(e);
                None
            }
        }
    } else {
        None
    };
    let per_ray = if view.glyphs { 1 + GLYPH_SEGMENTS } else { 1 };
    let cpu = [(&rays, per_ray), (&field, ARROW_SEGMENTS)]
        .into_iter()
        .filter_map(|(list, per_item)| {
            let (positions, colours) = list.as_ref().filter(|l| !l.0.is_empty())?;
            Some(Arc::new(CpuList {
                positions: positions.clone(),
                colours: colours.clone(),
                per_item,
            }))
        })
        .collect();
    // The meshes take linear colours.
    let linear = |list: Option<LineList>| {
        list.map(|(p, c)| {
            let c = c
                .into_iter()
                .map(|[r, g, b, a]| {
                    let l = Color::srgba(r, g, b, a).to_linear();
                    [l.red, l.green, l.blue, l.alpha]
                })
                .collect();
            (p, c)
        })
    };
    Geometry {
        rays: linear(rays),
        field: linear(field),
        cpu,
        report,
    }
}

/// The segments of one arrow: the shaft and four barbs.
const ARROW_SEGMENTS: usize = 5;

/// Each arrow as five segments — the shaft and four barbs — coloured by its count through
/// inferno (display colours); arrows without a mean direction (opposite rays cancelled) are
/// left out.
fn arrow_lines(arrows: &[Arrow]) -> LineList {
    let mut positions = Vec::with_capacity(arrows.len() * 10);
    let mut colours = Vec::with_capacity(arrows.len() * 10);
    for a in arrows.iter().filter(|a| a.direction != Vec3::ZERO) {
        let half = a.direction * (a.length * 0.5);
        let (tail, tip) = (a.centre - half, a.centre + half);
        let (u, v) = a.direction.any_orthonormal_pair();
        let back = tip - a.direction * (a.length * 0.3);
        let w = a.length * 0.12;
        positions.extend([tail, tip].map(|p| p.to_array()));
        for side in [u, -u, v, -v] {
            positions.extend([tip, back + side * w].map(|p| p.to_array()));
        }
        let s = voxcast_core::colormap::inferno(a.shade);
        colours.extend([[s.x, s.y, s.z, 1.0]; 2 * ARROW_SEGMENTS]);
    }
    (positions, colours)
}

/// Swaps finished line lists in.
/// Where the lines' meshes go, and the one unlit material they share (made once).
#[derive(bevy::ecs::system::SystemParam)]
struct LineAssets<'w, 's> {
    shapes: crate::sandbox::shared::state::MeshAssets<'w>,
    material: Local<'s, Option<Handle<StandardMaterial>>>,
}

fn swap_lines(
    mut commands: Commands,
    mut building: ResMut<Building>,
    mut report: ResMut<ViewReport>,
    mut cpu: ResMut<CpuLines>,
    roots: Query<(Entity, &RayRoot)>,
    existing: Query<(Entity, &Lines)>,
    mut assets: LineAssets,
) {
    let Some(task) = building.task.as_mut() else {
        return;
    };
    let Some(geometry) = check_ready(task) else {
        return;
    };
    building.task = None;
    *report = geometry.report;
    info!(
        "ray views: {} ray lines, {} arrows",
        report.lines, report.arrows
    );
    for (e, _) in &existing {
        commands.entity(e).despawn();
    }
    let Ok((root, shown)) = roots.single() else {
        cpu.set(Vec::new(), Vec3::ZERO);
        return;
    };
    cpu.set(geometry.cpu, -shown.0.computed.origin);
    let material = assets
        .material
        .get_or_insert_with(|| {
            assets.shapes.materials.add(StandardMaterial {
                unlit: true,
                ..default()
            })
        })
        .clone();
    for (kind, list) in [(Lines::Rays, geometry.rays), (Lines::Field, geometry.field)] {
        let Some((positions, colours)) = list.filter(|l| !l.0.is_empty()) else {
            continue;
        };
        let mesh = Mesh::new(PrimitiveTopology::LineList, RenderAssetUsages::RENDER_WORLD)
            .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
            .with_inserted_attribute(Mesh::ATTRIBUTE_COLOR, colours);
        commands.spawn((
            kind,
            Mesh3d(assets.shapes.meshes.add(mesh)),
            MeshMaterial3d(material.clone()),
            Transform::IDENTITY,
            Visibility::Hidden,
            ChildOf(root),
        ));
        report.drawn = true;
    }
}

/// The line lists' meshes are drawn by the GPU's cameras; with the CPU live view the CPU draws
/// the lists (`cpu_lines`) and the meshes are hidden.
fn show_lines(
    preview: Res<crate::sandbox::shared::quality::PreviewSettings>,
    mut lists: Query<&mut Visibility, With<Lines>>,
) {
    let want = if preview.cpu_live() {
        Visibility::Hidden
    } else {
        Visibility::Inherited
    };
    for mut visibility in &mut lists {
        visibility.set_if_neq(want);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use voxcast_core::rays::field::Arrow;

    /// An arrow is a shaft centred on its cube plus four barbs at the tip, all in one colour;
    /// an arrow without a direction is not drawn.
    #[test]
    fn arrows_are_a_shaft_and_four_barbs() {
        let a = Arrow {
            centre: Vec3::new(1.0, 2.0, 3.0),
            direction: Vec3::X,
            count: 5,
            length: 2.0,
            shade: 1.0,
        };
        let none = Arrow {
            direction: Vec3::ZERO,
            ..a
        };
        let (p, c) = arrow_lines(&[a, none]);
        assert_eq!((p.len(), c.len()), (10, 10));
        assert_eq!((p[0], p[1]), ([0.0, 2.0, 3.0], [2.0, 2.0, 3.0]));
        for barb in p[2..].chunks(2) {
            assert_eq!(barb[0], [2.0, 2.0, 3.0], "barbs start at the tip");
            assert!((barb[1][0] - 1.4).abs() < 1e-6, "and end 30 % back");
        }
        assert!(c.iter().all(|x| *x == c[0]));
    }

    /// The scene is shaded as the core's layered render shades a hit: a wall seen head-on is
    /// its full base, one seen edge-on the ambient share.
    #[test]
    fn the_scene_is_lit_from_the_eye() {
        let scene = voxcast_core::rays::cornell::scene();
        let wall = scene
            .meshes
            .iter()
            .position(|m| m.name == "left wall")
            .expect("the box has a red wall");
        let t = scene.meshes[wall].triangles[0];
        let centre = (t[0] + t[1] + t[2]) / 3.0;
        let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize();
        let above = vertex_shades(&scene, wall, centre + n * 1e6, SceneShading::Grey);
        assert!(above.iter().all(|c| (c[0] - 0.8).abs() < 1e-3), "{above:?}");
        let coloured = vertex_shades(&scene, wall, centre + n * 1e6, SceneShading::Colour);
        let base = scene.meshes[wall].color;
        assert!((coloured[0][0] - base.x).abs() < 1e-3 && (coloured[0][1] - base.y).abs() < 1e-3);
        let edge_on = vertex_shades(
            &scene,
            wall,
            centre + (t[1] - t[0]) * 1e6,
            SceneShading::Grey,
        );
        assert!((edge_on[0][0] - 0.8 * AMBIENT).abs() < 1e-2, "{edge_on:?}");
    }
}
