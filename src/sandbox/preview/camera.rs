//! The preview's camera: the components every view of the preview uses, the depth prepass where
//! its rays stop at the scene's meshes, and the view the sandbox opens with.

use crate::sandbox::scene::sharp;
use crate::sandbox::shared::quality::GPU_READS_DEPTH;
use crate::sandbox::shared::state::{MainCamera, View};
use bevy::core_pipeline::prepass::DepthPrepass;
use bevy::core_pipeline::tonemapping::{DebandDither, Tonemapping};
use bevy::prelude::*;

/// The view the sandbox opens with (also the screenshot's).
#[derive(Resource, Clone, Copy)]
pub struct InitialView(pub voxcast_core::camera::Camera);

/// The camera components every view of the preview uses: no tonemapping or dithering (the
/// preview's values must equal the CPU's), no MSAA. A view whose rays stop at scene geometry
/// adds a [`DepthPrepass`] ([`with_depth`]); without one the preview is compiled without
/// `DEPTH_PREPASS`, as WebGL2 always compiles it.
pub fn preview_camera(view: &voxcast_core::camera::Camera) -> impl Bundle {
    let projection = match view.projection {
        voxcast_core::camera::Projection::Perspective { fov_y_deg } => {
            Projection::Perspective(PerspectiveProjection {
                fov: fov_y_deg.to_radians(),
                ..default()
            })
        }
        voxcast_core::camera::Projection::Orthographic { height } => {
            Projection::Orthographic(OrthographicProjection {
                scaling_mode: bevy::camera::ScalingMode::FixedVertical {
                    viewport_height: height,
                },
                ..OrthographicProjection::default_3d()
            })
        }
    };
    (
        Camera3d::default(),
        projection,
        Msaa::Off,
        Tonemapping::None,
        DebandDither::Disabled,
        sharp::everything(),
        MainCamera,
        View(*view),
        Transform::from_translation(view.eye).looking_at(view.target, view.up),
    )
}

/// A depth prepass for a view of the preview whose rays stop at scene geometry (where the GPU
/// can read it: see [`GPU_READS_DEPTH`]).
pub fn with_depth(mut camera: EntityCommands<'_>, stops_at_geometry: bool) {
    if stops_at_geometry && GPU_READS_DEPTH {
        camera.insert(DepthPrepass);
    }
}
