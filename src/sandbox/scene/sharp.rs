//! The scene's meshes at the window's full resolution while the GPU preview is drawn smaller
//! and stretched (a preview scale below 1, or adaptive quality while moving): the volume may
//! be coarse, the meshes may not.
//!
//! A second camera, the sharp camera, draws the meshes (sample spheres, the light markers, the
//! virtual camera's body) at the viewport's size into an image that egui paints first. The
//! preview camera then draws only the volume, over a transparent background, and sees each
//! solid mesh through a depth-only twin (its depth, no colour): the preview's rays still stop
//! at the meshes, and where they do, the preview holds only the volume in front of them, through
//! which the sharp mesh beneath shows. At full resolution the preview camera draws everything
//! itself as before and the sharp camera is off (a software rasterizer pays for every pass).

use crate::sandbox::shared::layers::{DEPTH_LAYER, SCENE_LAYER, Solid, VOLUME_LAYER};
use crate::sandbox::shared::state::MainCamera;
use crate::sandbox::shared::viewport::Viewport;
use bevy::camera::RenderTarget;
use bevy::camera::visibility::RenderLayers;
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::mesh::MeshVertexBufferLayoutRef;
use bevy::pbr::{
    ExtendedMaterial, MaterialExtension, MaterialExtensionKey, MaterialExtensionPipeline,
};
use bevy::prelude::*;
use bevy::render::render_resource::{
    AsBindGroup, ColorWrites, RenderPipelineDescriptor, SpecializedMeshPipelineError,
    TextureFormat, TextureUsages,
};
use bevy::window::PrimaryWindow;

/// The depth-only twin of a [`Solid`] mesh (its child, so it follows the mesh).
#[derive(Component)]
struct DepthTwin;

/// The camera that draws the meshes at the viewport's full resolution (a child of the main
/// camera: it sees what the main camera sees, from where it sees it).
#[derive(Component)]
pub struct SharpCamera;

/// The sharp camera's image, and its size in pixels.
#[derive(Resource)]
pub struct SharpTarget {
    pub image: Handle<Image>,
    pub size: UVec2,
}

/// A material that writes depth and no colour: the base material's shaders with every colour
/// write masked off.
#[derive(Asset, AsBindGroup, TypePath, Clone, Default)]
pub struct NoColour {}

impl MaterialExtension for NoColour {
    fn specialize(
        _pipeline: &MaterialExtensionPipeline,
        descriptor: &mut RenderPipelineDescriptor,
        _layout: &MeshVertexBufferLayoutRef,
        _key: MaterialExtensionKey<Self>,
    ) -> Result<(), SpecializedMeshPipelineError> {
        if let Some(fragment) = descriptor.fragment.as_mut() {
            for target in fragment.targets.iter_mut().flatten() {
                target.write_mask = ColorWrites::empty();
            }
        }
        Ok(())
    }
}

type DepthOnly = ExtendedMaterial<StandardMaterial, NoColour>;

/// The one material every twin shares.
#[derive(Resource)]
struct TwinMaterial(Handle<DepthOnly>);

/// Who draws what: the preview camera's layers and whether it clears to transparent, and
/// whether the sharp camera draws.
#[derive(Clone, Debug, PartialEq)]
pub struct GpuPlan {
    pub preview_layers: RenderLayers,
    pub transparent: bool,
    pub sharp: bool,
}

impl GpuPlan {
    /// The plan for the GPU preview at `scale` of the viewport's resolution.
    pub fn for_scale(scale: f32) -> Self {
        if scale < 1.0 {
            Self {
                preview_layers: RenderLayers::from_layers(&[VOLUME_LAYER, DEPTH_LAYER]),
                transparent: true,
                sharp: true,
            }
        } else {
            Self {
                preview_layers: everything(),
                transparent: false,
                sharp: false,
            }
        }
    }
}

/// The layers a preview camera at full resolution sees: the meshes and the volume.
pub fn everything() -> RenderLayers {
    RenderLayers::from_layers(&[
        0,
        crate::sandbox::shared::layers::OCCLUDER_LAYER,
        VOLUME_LAYER,
        SCENE_LAYER,
    ])
}

/// The layers the sharp camera sees: the meshes.
fn meshes() -> RenderLayers {
    RenderLayers::from_layers(&[
        0,
        crate::sandbox::shared::layers::OCCLUDER_LAYER,
        SCENE_LAYER,
    ])
}

pub(crate) fn plugin(app: &mut App) {
    app.add_plugins(MaterialPlugin::<DepthOnly>::default())
        .add_systems(Startup, make_twin_material)
        .add_systems(
            Update,
            (
                spawn_sharp_camera,
                twin_solids,
                fit_sharp_target,
                follow_projection,
            )
                .chain()
                .in_set(crate::sandbox::shared::schedule::Frame::Show),
        );
}

fn make_twin_material(mut commands: Commands, mut materials: ResMut<Assets<DepthOnly>>) {
    let material = materials.add(DepthOnly {
        base: StandardMaterial {
            unlit: true,
            ..default()
        },
        extension: NoColour {},
    });
    commands.insert_resource(TwinMaterial(material));
}

/// Spawns the sharp camera once the main camera is there.
fn spawn_sharp_camera(
    mut commands: Commands,
    main: Query<Entity, With<MainCamera>>,
    sharp: Query<(), With<SharpCamera>>,
) {
    let Ok(main) = main.single() else { return };
    if !sharp.is_empty() {
        return;
    }
    commands.spawn((
        SharpCamera,
        Camera3d::default(),
        Camera {
            // Before the preview camera (0) and the window's (1); it draws into an image.
            order: -1,
            is_active: false,
            ..default()
        },
        Msaa::Off,
        Tonemapping::None,
        DebandDither::Disabled,
        meshes(),
        Transform::IDENTITY,
        ChildOf(main),
    ));
}

/// A solid whose mesh changed.
type NewMesh = (With<Solid>, Changed<Mesh3d>);

/// Gives every new solid mesh its twin, keeps the twin's mesh the solid's, and removes the
/// twin when the mesh stops being solid.
fn twin_solids(
    mut commands: Commands,
    material: Res<TwinMaterial>,
    added: Query<(Entity, &Mesh3d, Option<&Children>), Added<Solid>>,
    changed: Query<(&Mesh3d, &Children), NewMesh>,
    mut twins: Query<&mut Mesh3d, (With<DepthTwin>, Without<Solid>)>,
    twin_of: Query<(Entity, &ChildOf), With<DepthTwin>>,
    mut removed: RemovedComponents<Solid>,
) {
    for (entity, mesh, children) in &added {
        if children.is_some_and(|c| c.iter().any(|child| twins.contains(child))) {
            continue;
        }
        commands.spawn((
            DepthTwin,
            Mesh3d(mesh.0.clone()),
            MeshMaterial3d(material.0.clone()),
            RenderLayers::layer(DEPTH_LAYER),
            Transform::IDENTITY,
            Visibility::Inherited,
            ChildOf(entity),
        ));
    }
    for (mesh, children) in &changed {
        for &child in children {
            if let Ok(mut twin) = twins.get_mut(child)
                && twin.0 != mesh.0
            {
                twin.0 = mesh.0.clone();
            }
        }
    }
    let gone: Vec<Entity> = removed.read().collect();
    if gone.is_empty() {
        return;
    }
    for (twin, parent) in &twin_of {
        if gone.contains(&parent.parent()) {
            commands.entity(twin).despawn();
        }
    }
}

/// Keeps the sharp camera's image at the viewport's full size while it draws.
fn fit_sharp_target(
    mut commands: Commands,
    window: Query<&Window, With<PrimaryWindow>>,
    viewport: Option<Res<Viewport>>,
    target: Option<Res<SharpTarget>>,
    mut images: ResMut<Assets<Image>>,
    cameras: Query<(Entity, &Camera, Option<&RenderTarget>), With<SharpCamera>>,
) {
    let Ok(window) = window.single() else { return };
    let Ok((camera, c, drawn_into)) = cameras.single() else {
        return;
    };
    if !c.is_active {
        return;
    }
    let (_, size) = Viewport::of(viewport.as_deref(), window);
    if let Some(t) = target.as_ref().filter(|t| t.size == size) {
        // A camera spawned again (with a new main camera) is given the image it lacks.
        let given = matches!(drawn_into, Some(RenderTarget::Image(i)) if i.handle == t.image);
        if !given {
            commands
                .entity(camera)
                .insert(RenderTarget::Image(t.image.clone().into()));
        }
        return;
    }
    let mut image = Image::new_target_texture(size.x, size.y, TextureFormat::Rgba8UnormSrgb, None);
    image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
    let handle = images.add(image);
    commands
        .entity(camera)
        .insert(RenderTarget::Image(handle.clone().into()));
    commands.insert_resource(SharpTarget {
        image: handle,
        size,
    });
}

/// The sharp camera projects as the main camera does.
fn follow_projection(
    main: Query<Ref<Projection>, With<MainCamera>>,
    mut sharp: Query<&mut Projection, (With<SharpCamera>, Without<MainCamera>)>,
) {
    let (Ok(p), Ok(mut s)) = (main.single(), sharp.single_mut()) else {
        return;
    };
    // A new sharp camera starts with the default projection: copy it then too.
    if p.is_changed() || s.is_added() {
        *s = (*p).clone();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn below_full_resolution_the_preview_sees_the_volume_and_the_twins_only() {
        let coarse = GpuPlan::for_scale(0.5);
        assert!(coarse.sharp && coarse.transparent);
        assert!(
            coarse
                .preview_layers
                .intersects(&RenderLayers::layer(VOLUME_LAYER))
        );
        assert!(
            coarse
                .preview_layers
                .intersects(&RenderLayers::layer(DEPTH_LAYER))
        );
        // The meshes' own layers are the sharp camera's alone.
        assert!(!coarse.preview_layers.intersects(&meshes()));
        assert!(!meshes().intersects(&RenderLayers::layer(VOLUME_LAYER)));
        assert!(!meshes().intersects(&RenderLayers::layer(DEPTH_LAYER)));

        let full = GpuPlan::for_scale(1.0);
        assert!(!full.sharp && !full.transparent);
        assert!(full.preview_layers.intersects(&meshes()));
        assert!(
            !full
                .preview_layers
                .intersects(&RenderLayers::layer(DEPTH_LAYER))
        );
    }
}
