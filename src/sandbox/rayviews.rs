//! RayVis's views around the density on show: the scene's meshes (grey or in their colours,
//! lit from the eye, writing depth so the preview's rays stop at them — RayVis shortens each
//! march at the scene's hit), the ray mesh (one line list: every counted ray from its start to
//! its hit or end) and the vector field (one line list: an arrow per sample cube). All hang
//! from one root placed at minus the density's origin, so the rays' world lines up with the
//! volume's coordinates.
//!
//! The line lists are built on the background pool (a million rays are two million vertices)
//! and swapped in when ready; the window keeps drawing the previous ones meanwhile. With the
//! CPU live view (a software rasterizer draws every line on the CPU) a long list has a thinned
//! twin, drawn instead of it while the view moves, so orbiting stays fluid; at rest the whole
//! list is drawn once and kept (`preview`'s kept pass).

use super::raydata::{RayChoices, RayScene, Shown, ViewChoices};
use super::state::{MainCamera, View, VolumeState};
use bevy::asset::RenderAssetUsages;
use bevy::camera::visibility::RenderLayers;
use bevy::mesh::PrimitiveTopology;
use bevy::prelude::*;
use bevy::tasks::{AsyncComputeTaskPool, Task, futures::check_ready};
use std::sync::Arc;
use voxcast_core::rays::field::{Arrow, arrows};
use voxcast_core::rays::layered::{AMBIENT, SceneShading};
use voxcast_core::rays::lines::{LineParams, padded, ray_lines};
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

/// Which of a list's versions an entity draws.
#[derive(Component, Clone, Copy, PartialEq, Eq, Debug)]
enum Detail {
    /// The whole list, which has no thinned twin.
    All,
    /// The whole list, drawn at rest (its thinned twin while the view moves).
    AtRest,
    /// The thinned twin, drawn while the view moves.
    WhileMoving,
}

/// The most segments drawn while the view moves with the CPU live view: beyond it a list is
/// thinned to every n-th ray or arrow. Lavapipe takes about 3 µs a line on 2 cores (Intel
/// Xeon, 640×360): orbiting with 4 000 lines drew a frame in 105 ms, with 40 000 in 216 ms,
/// with all 412 000 in 0.7–0.8 s (BENCHMARKS.md).
const MOVING_SEGMENTS: usize = 10_000;

/// What the views show, for the panel: lines and arrows drawn, rays left out.
#[derive(Resource, Default, Clone, Debug, PartialEq)]
pub struct ViewReport {
    pub lines: usize,
    pub arrows: usize,
    /// Rays of the filter that never entered the drawn box, or were malformed.
    pub left_out: usize,
    /// Why the vector field is not drawn.
    pub field_error: Option<String>,
    /// The line lists are being built.
    pub building: bool,
    /// Some line list is in the scene.
    pub drawn: bool,
    /// While the view moves with the CPU live view, every n-th ray and arrow is drawn.
    pub moving_every: Option<usize>,
}

/// The line lists on the way, and what they were asked for.
#[derive(Resource, Default)]
struct Building {
    wanted: Option<(usize, ViewChoices)>,
    task: Option<Task<Geometry>>,
}

/// A line list: positions and linear colours, two vertices a segment.
type LineList = (Vec<[f32; 3]>, Vec<[f32; 4]>);

/// Built line lists.
struct Geometry {
    rays: Option<LineList>,
    field: Option<LineList>,
    report: ViewReport,
}

/// Every `n`-th item of `list` (items of `per_item` segments), `n` the smallest that leaves at
/// most [`MOVING_SEGMENTS`] segments; `None` when the list is within that already.
fn thinned(list: &LineList, per_item: usize) -> Option<(LineList, usize)> {
    let vertices = 2 * per_item;
    let items = list.0.len() / vertices;
    if items * per_item <= MOVING_SEGMENTS {
        return None;
    }
    let n = (items * per_item).div_ceil(MOVING_SEGMENTS);
    fn pick<V: Copy>(v: &[V], vertices: usize, n: usize) -> Vec<V> {
        v.chunks_exact(vertices)
            .step_by(n)
            .flatten()
            .copied()
            .collect()
    }
    let few = (pick(&list.0, vertices, n), pick(&list.1, vertices, n));
    Some((few, n))
}

pub(super) fn plugin(app: &mut App) {
    app.init_resource::<ViewReport>()
        .init_resource::<Building>()
        .add_systems(
            Update,
            (
                place_root,
                spawn_scene,
                build_lines,
                swap_lines,
                choose_detail,
                shade_scene,
            )
                .chain()
                .in_set(super::Frame::Show),
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
    (mut meshes, mut materials): (ResMut<Assets<Mesh>>, ResMut<Assets<StandardMaterial>>),
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
    let material = materials.add(StandardMaterial {
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
            super::sharp::Solid,
            // The GPU's cameras draw it; the CPU live view has it in its image.
            RenderLayers::layer(super::sharp::SCENE_LAYER),
            Mesh3d(meshes.add(mesh)),
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
/// world): the mesh's base (grey or its own colour) × (ambient + (1 − ambient)·|n·d|).
fn vertex_shades(
    scene: &TriangleScene,
    index: usize,
    eye: Vec3,
    shading: SceneShading,
) -> Vec<[f32; 4]> {
    let m = &scene.meshes[index];
    let base = match shading {
        SceneShading::Colour => m.color,
        _ => Vec3::splat(0.8),
    };
    m.triangles
        .iter()
        .flat_map(|[a, b, c]| {
            let n = (*b - *a).cross(*c - *a).normalize_or_zero();
            [*a, *b, *c].map(|v| {
                let lambert = n.dot((v - eye).normalize_or_zero()).abs();
                let s = base * (AMBIENT + (1.0 - AMBIENT) * lambert);
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
    building.task = Some(AsyncComputeTaskPool::get().spawn(async move { geometry(&shown, &view) }));
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
        let colour = |rgb: [f32; 3]| {
            let l = Color::srgb(rgb[0], rgb[1], rgb[2]).to_linear();
            [l.red, l.green, l.blue, 1.0]
        };
        let (hit, miss) = (colour(view.hit_colour), colour(view.miss_colour));
        let mut positions = Vec::with_capacity(lines.lines.len() * 2);
        let mut colours = Vec::with_capacity(lines.lines.len() * 2);
        for l in &lines.lines {
            positions.extend([l.from.to_array(), l.to.to_array()]);
            let c = if l.hit { hit } else { miss };
            colours.extend([c, c]);
        }
        (positions, colours)
    });
    let field = if view.field {
        match arrows(&c.density, view.cube, view.arrow_scale) {
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
    Geometry {
        rays,
        field,
        report,
    }
}

/// The segments of one arrow: the shaft and four barbs.
const ARROW_SEGMENTS: usize = 5;

/// Each arrow as five segments — the shaft and four barbs — coloured by its count through
/// inferno; arrows without a mean direction (opposite rays cancelled) are left out.
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
        let l = Color::srgb(s.x, s.y, s.z).to_linear();
        colours.extend([[l.red, l.green, l.blue, 1.0]; 2 * ARROW_SEGMENTS]);
    }
    (positions, colours)
}

/// Swaps finished line lists in.
fn swap_lines(
    mut commands: Commands,
    mut building: ResMut<Building>,
    mut report: ResMut<ViewReport>,
    roots: Query<Entity, With<RayRoot>>,
    existing: Query<(Entity, &Lines)>,
    (mut meshes, mut materials): (ResMut<Assets<Mesh>>, ResMut<Assets<StandardMaterial>>),
    mut material: Local<Option<Handle<StandardMaterial>>>,
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
    let Ok(root) = roots.single() else { return };
    let material = material
        .get_or_insert_with(|| {
            materials.add(StandardMaterial {
                unlit: true,
                ..default()
            })
        })
        .clone();
    let lists = [
        (Lines::Rays, geometry.rays, 1),
        (Lines::Field, geometry.field, ARROW_SEGMENTS),
    ];
    for (kind, list, per_item) in lists {
        let Some(list) = list.filter(|l| !l.0.is_empty()) else {
            continue;
        };
        let twin = thinned(&list, per_item);
        let mut spawn = |(positions, colours): LineList, detail: Detail| {
            let mesh = Mesh::new(PrimitiveTopology::LineList, RenderAssetUsages::RENDER_WORLD)
                .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
                .with_inserted_attribute(Mesh::ATTRIBUTE_COLOR, colours);
            commands.spawn((
                kind,
                detail,
                Mesh3d(meshes.add(mesh)),
                MeshMaterial3d(material.clone()),
                Transform::IDENTITY,
                Visibility::Hidden,
                ChildOf(root),
            ));
        };
        report.drawn = true;
        match twin {
            Some((few, n)) => {
                report.moving_every = Some(report.moving_every.map_or(n, |m| m.max(n)));
                spawn(list, Detail::AtRest);
                spawn(few, Detail::WhileMoving);
            }
            None => spawn(list, Detail::All),
        }
    }
}

/// Shows each line list's version for the moment: the thinned twins while the view moves with
/// the CPU live view, the whole lists otherwise.
fn choose_detail(
    motion: Res<super::preview::Motion>,
    preview: Res<super::preview::PreviewSettings>,
    mut lists: Query<(&Detail, &mut Visibility)>,
) {
    let thin = motion.moving && preview.cpu_live();
    for (detail, mut visibility) in &mut lists {
        let shown = match detail {
            Detail::All => true,
            Detail::AtRest => !thin,
            Detail::WhileMoving => thin,
        };
        let want = if shown {
            Visibility::Inherited
        } else {
            Visibility::Hidden
        };
        visibility.set_if_neq(want);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A list of `items` items of `per_item` segments, each vertex marked with its item.
    fn list(items: usize, per_item: usize) -> LineList {
        let n = items * per_item * 2;
        let p = (0..n)
            .map(|i| [(i / (2 * per_item)) as f32, 0.0, 0.0])
            .collect();
        let c = (0..n)
            .map(|i| [(i / (2 * per_item)) as f32, 0.0, 0.0, 1.0])
            .collect();
        (p, c)
    }

    /// A list within the moving budget has no twin; a longer one keeps every n-th item whole,
    /// within the budget, positions and colours together.
    #[test]
    fn long_lists_get_a_thinned_twin_of_whole_items() {
        assert!(thinned(&list(MOVING_SEGMENTS, 1), 1).is_none());
        assert!(thinned(&list(MOVING_SEGMENTS / ARROW_SEGMENTS, ARROW_SEGMENTS), 5).is_none());
        for (items, per_item) in [(412_126, 1), (MOVING_SEGMENTS + 1, 1), (76_003, 5)] {
            let ((p, c), n) = thinned(&list(items, per_item), per_item).unwrap();
            assert!(n >= 2);
            assert!(
                p.len() / 2 <= MOVING_SEGMENTS,
                "{items}: {} segments",
                p.len() / 2
            );
            assert_eq!(p.len(), c.len());
            assert_eq!(p.len() % (2 * per_item), 0);
            // Item k of the twin is item k·n of the list, all its vertices.
            for (k, item) in p.chunks(2 * per_item).enumerate() {
                assert!(item.iter().all(|v| v[0] == (k * n) as f32));
            }
            assert_eq!(p.len() / (2 * per_item), items.div_ceil(n));
        }
    }
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
