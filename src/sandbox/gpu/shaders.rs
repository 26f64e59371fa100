//! Registers the WGSL in `shaders/` (compiled into the binary, so the sandbox needs no files):
//! the library modules under their `#define_import_path`s and the fragment shader under
//! [`VOLUME_SHADER`].

use crate::sandbox::gpu::material::VOLUME_SHADER;
use bevy::prelude::*;

/// Every WGSL file: (file name, source). The order does not matter to Bevy's composer.
pub const SOURCES: &[(&str, &str)] = &[
    ("types.wgsl", include_str!("../../../shaders/types.wgsl")),
    (
        "bindings.wgsl",
        include_str!("../../../shaders/bindings.wgsl"),
    ),
    ("ray.wgsl", include_str!("../../../shaders/ray.wgsl")),
    ("clip.wgsl", include_str!("../../../shaders/clip.wgsl")),
    ("step.wgsl", include_str!("../../../shaders/step.wgsl")),
    ("sample.wgsl", include_str!("../../../shaders/sample.wgsl")),
    (
        "transfer.wgsl",
        include_str!("../../../shaders/transfer.wgsl"),
    ),
    (
        "classify.wgsl",
        include_str!("../../../shaders/classify.wgsl"),
    ),
    ("shade.wgsl", include_str!("../../../shaders/shade.wgsl")),
    (
        "composite.wgsl",
        include_str!("../../../shaders/composite.wgsl"),
    ),
    ("skip.wgsl", include_str!("../../../shaders/skip.wgsl")),
    ("trace.wgsl", include_str!("../../../shaders/trace.wgsl")),
    ("volume.wgsl", include_str!("../../../shaders/volume.wgsl")),
];

/// Keeps the library shaders alive (they are referenced by import path, not by handle).
#[derive(Resource)]
struct LibraryShaders(#[allow(dead_code)] Vec<Handle<Shader>>);

pub(crate) fn plugin(app: &mut App) {
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

#[cfg(test)]
mod tests {
    //! The WGSL mirrors the core file for file and name for name: each shader's header names
    //! its twin file and the functions it mirrors, and both must define them.

    /// The header comment of `source`: the lines before its `#define_import_path`.
    fn header(source: &str) -> String {
        source
            .lines()
            .take_while(|l| l.starts_with("//"))
            .collect::<Vec<_>>()
            .join(" ")
    }

    /// Every compositing method has its own branch in the preview's dispatch: a method added
    /// to the core without one would draw magenta, not pass for another.
    #[test]
    fn the_preview_dispatches_every_method_by_name() {
        let trace = super::SOURCES
            .iter()
            .find(|(name, _)| *name == "trace.wgsl")
            .map(|(_, source)| *source)
            .unwrap();
        for m in voxcast_core::composite::Method::ALL {
            let branch = format!("METHOD == #{{METHOD_{}}}u", m.name().to_uppercase());
            assert!(trace.contains(&branch), "trace.wgsl has no `{branch}`");
        }
    }

    /// A twin's Rust: its file, and the files of its folder where it has one (`skip.rs` and
    /// `skip/*.rs`), as one text.
    fn twin_source(path: &str) -> std::io::Result<String> {
        let mut text = std::fs::read_to_string(path)?;
        let folder = std::path::Path::new(path.trim_end_matches(".rs"));
        if let Ok(entries) = std::fs::read_dir(folder) {
            let mut files: Vec<_> = entries.filter_map(|e| Some(e.ok()?.path())).collect();
            files.sort();
            for f in files
                .iter()
                .filter(|f| f.extension().is_some_and(|x| x == "rs"))
            {
                text.push_str(&std::fs::read_to_string(f)?);
            }
        }
        Ok(text)
    }

    #[test]
    fn every_shader_names_a_twin_that_defines_its_functions() {
        let root = env!("CARGO_MANIFEST_DIR");
        let mut mirrored = 0;
        for (name, source) in super::SOURCES {
            let head = header(source);
            let Some(twin) = head
                .split("Twin: ")
                .nth(1)
                .and_then(|rest| rest.split_whitespace().next())
            else {
                assert_eq!(*name, "bindings.wgsl", "{name} names no twin");
                continue;
            };
            let twin = twin.trim_end_matches([',', ':', '.']);
            let rust = twin_source(&format!("{root}/{twin}"))
                .unwrap_or_else(|e| panic!("{name}: twin {twin}: {e}"));
            let stem = name.trim_end_matches(".wgsl");
            if twin.starts_with("crates/voxcast_core/src/") && stem != "volume" {
                assert!(
                    twin.ends_with(&format!("/{stem}.rs")),
                    "{name} mirrors {twin}: the file names must match"
                );
            }
            // Names in backticks inside the parentheses right after the twin's path.
            let Some(list) = head
                .split(twin)
                .nth(1)
                .filter(|r| r.trim_start().starts_with('('))
                .and_then(|r| r.split(')').next())
            else {
                continue;
            };
            for quoted in list.split('`').skip(1).step_by(2) {
                let function = quoted.rsplit("::").next().unwrap();
                if !function.starts_with(|c: char| c.is_ascii_lowercase()) {
                    continue; // a type: its fields are checked by the uniform's layout test
                }
                assert!(
                    rust.contains(&format!("fn {function}")),
                    "{name}: {twin} has no fn {function}"
                );
                if !quoted.contains("::") {
                    assert!(
                        source.contains(&format!("fn {function}(")),
                        "{name} has no fn {function} (named in its header)"
                    );
                }
                mirrored += 1;
            }
        }
        assert!(mirrored >= 20, "only {mirrored} functions named in headers");
    }
}
