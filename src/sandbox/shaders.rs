//! Registers the WGSL in `shaders/` (compiled into the binary, so the sandbox needs no files):
//! the library modules under their `#define_import_path`s and the fragment shader under
//! [`VOLUME_SHADER`].

use super::material::VOLUME_SHADER;
use bevy::prelude::*;

/// Every WGSL file: (file name, source). The order does not matter to Bevy's composer.
pub const SOURCES: &[(&str, &str)] = &[
    ("types.wgsl", include_str!("../../shaders/types.wgsl")),
    ("bindings.wgsl", include_str!("../../shaders/bindings.wgsl")),
    ("ray.wgsl", include_str!("../../shaders/ray.wgsl")),
    ("step.wgsl", include_str!("../../shaders/step.wgsl")),
    ("sample.wgsl", include_str!("../../shaders/sample.wgsl")),
    ("transfer.wgsl", include_str!("../../shaders/transfer.wgsl")),
    ("classify.wgsl", include_str!("../../shaders/classify.wgsl")),
    ("shade.wgsl", include_str!("../../shaders/shade.wgsl")),
    (
        "composite.wgsl",
        include_str!("../../shaders/composite.wgsl"),
    ),
    ("skip.wgsl", include_str!("../../shaders/skip.wgsl")),
    ("trace.wgsl", include_str!("../../shaders/trace.wgsl")),
    ("volume.wgsl", include_str!("../../shaders/volume.wgsl")),
];

/// Keeps the library shaders alive (they are referenced by import path, not by handle).
#[derive(Resource)]
struct LibraryShaders(#[allow(dead_code)] Vec<Handle<Shader>>);

pub(super) fn plugin(app: &mut App) {
    let mut shaders = app.world_mut().resource_mut::<Assets<Shader>>();
    let mut library = Vec::new();
    for (name, source) in SOURCES {
        let shader = Shader::from_wgsl(*source, format!("voxcast/{name}"));
        if *name == "volume.wgsl" {
            shaders
                .insert(&VOLUME_SHADER, shader)
                .expect("a UUID handle always inserts");
        } else {
            library.push(shaders.add(shader));
        }
    }
    app.insert_resource(LibraryShaders(library));
}
