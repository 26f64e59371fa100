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
            .map(|l| l.trim_start_matches('/').trim())
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

    /// The functions `source` defines.
    fn defined(source: &str) -> Vec<String> {
        source
            .lines()
            .filter_map(|l| l.trim_start().strip_prefix("fn "))
            .filter_map(|l| l.split('(').next())
            .map(str::to_string)
            .collect()
    }

    /// The names in backticks of `text`, with the text before each.
    fn quoted(text: &str) -> Vec<(&str, &str)> {
        let parts: Vec<&str> = text.split('`').collect();
        (1..parts.len())
            .step_by(2)
            .map(|i| (parts[i - 1], parts[i]))
            .collect()
    }

    /// A function's name, as opposed to a type's or a path's.
    fn is_function(name: &str) -> bool {
        let last = name.rsplit("::").next().unwrap_or(name);
        last.starts_with(|c: char| c.is_ascii_lowercase())
            && last.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
    }

    /// Every WGSL function has a core twin its header names and the core defines — in the
    /// parentheses after a Rust file's path (`file.rs (`name`, `Type::method`)`: the Rust
    /// name, and the WGSL name where it has no `::`) or as `Rust::name` as `wgsl_name` — or is
    /// listed after "GPU-only:" with why. The twin files' names match the shaders'.
    #[test]
    fn every_shader_function_has_a_checked_twin_or_is_gpu_only() {
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
            let stem = name.trim_end_matches(".wgsl");
            if twin.starts_with("crates/voxcast_core/src/") && stem != "volume" {
                assert!(
                    twin.ends_with(&format!("/{stem}.rs")),
                    "{name} mirrors {twin}: the file names must match"
                );
            }
            let (claims, gpu_only) = head.split_once("GPU-only:").unwrap_or((&head, ""));
            // Every Rust file the header names, with its parenthesised list.
            let mut rust = String::new();
            let mut twins: Vec<String> = Vec::new();
            let words: Vec<&str> = claims.split(' ').collect();
            for (i, word) in words.iter().enumerate() {
                let path = word
                    .trim_start_matches('(')
                    .trim_end_matches("'s")
                    .trim_end_matches([',', ':', '.', ')']);
                if !path.ends_with(".rs") {
                    continue;
                }
                let file = [
                    format!("{root}/{path}"),
                    format!("{root}/crates/voxcast_core/src/{path}"),
                ]
                .into_iter()
                .find_map(|p| twin_source(&p).ok())
                .unwrap_or_else(|| panic!("{name}: no Rust file {path}"));
                rust.push_str(&file);
                let after = words[i + 1..].join(" ");
                if let Some(list) = after.strip_prefix('(').and_then(|r| r.split(')').next()) {
                    twins.extend(quoted(list).into_iter().map(|(_, q)| q.to_string()));
                }
            }
            let aliases: Vec<(&str, &str)> = {
                let q = quoted(claims);
                q.windows(2)
                    .filter(|w| w[1].0 == " as ")
                    .map(|w| (w[0].1, w[1].1))
                    .collect()
            };
            let has_fn = |rust_name: &str| {
                let last = rust_name.rsplit("::").next().unwrap();
                rust.contains(&format!("fn {last}(")) || rust.contains(&format!("fn {last}<"))
            };
            let wgsl = defined(source);
            let mut covered: Vec<&str> = Vec::new();
            for t in twins.iter().map(String::as_str).filter(|t| is_function(t)) {
                assert!(has_fn(t), "{name}: its twins have no fn {t}");
                let last = t.rsplit("::").next().unwrap();
                if !t.contains("::") {
                    assert!(
                        wgsl.iter().any(|f| f == last),
                        "{name} has no fn {t} (named in its header)"
                    );
                }
                covered.push(last);
                mirrored += 1;
            }
            for (rust_name, wgsl_name) in &aliases {
                assert!(
                    has_fn(rust_name),
                    "{name}: its twins have no fn {rust_name}"
                );
                assert!(
                    wgsl.iter().any(|f| f == wgsl_name),
                    "{name} has no fn {wgsl_name}"
                );
                covered.push(wgsl_name);
                mirrored += 1;
            }
            let gpu: Vec<&str> = quoted(gpu_only).into_iter().map(|(_, q)| q).collect();
            for g in gpu
                .iter()
                .filter(|g| is_function(g) && !covered.contains(g))
            {
                assert!(
                    wgsl.iter().any(|f| f == g),
                    "{name}: GPU-only `{g}` is not defined"
                );
            }
            for f in &wgsl {
                assert!(
                    covered.contains(&f.as_str()) || gpu.contains(&f.as_str()),
                    "{name}: fn {f} names no core twin in its header and is not listed as GPU-only"
                );
            }
        }
        assert!(mirrored >= 40, "only {mirrored} functions named in headers");
    }

    /// shaders/README.md's table names, for each file, functions its header names as twins.
    #[test]
    fn the_shader_readme_lists_twins_the_headers_name() {
        let root = env!("CARGO_MANIFEST_DIR");
        let readme = std::fs::read_to_string(format!("{root}/shaders/README.md")).unwrap();
        let mut rows = 0;
        for line in readme.lines().filter(|l| l.starts_with("| `")) {
            let cells: Vec<&str> = line.split(" | ").collect();
            let file = cells[0].trim_start_matches("| `").trim_end_matches('`');
            let Some((_, source)) = super::SOURCES.iter().find(|(n, _)| *n == file) else {
                panic!("shaders/README.md names {file}, which is not a shader");
            };
            let head = header(source);
            let (claims, gpu) = head.split_once("GPU-only:").unwrap_or((&head, ""));
            let (listed, listed_gpu) = cells
                .last()
                .unwrap()
                .split_once("(GPU-only:")
                .unwrap_or((cells.last().unwrap(), ""));
            for (_, f) in quoted(listed_gpu)
                .into_iter()
                .filter(|(_, f)| is_function(f))
            {
                assert!(
                    gpu.contains(&format!("`{f}`")),
                    "shaders/README.md lists `{f}` as GPU-only for {file}, whose header does not"
                );
            }
            for (_, f) in quoted(listed).into_iter().filter(|(_, f)| is_function(f)) {
                assert!(
                    claims.contains(&format!("`{f}`")) || claims.contains(&format!("::{f}`")),
                    "shaders/README.md lists `{f}` for {file}, whose header names no such twin"
                );
                assert!(
                    defined(source).iter().any(|d| d == f) || f.contains("::"),
                    "{file} has no fn {f}"
                );
            }
            rows += 1;
        }
        assert_eq!(rows, super::SOURCES.len(), "every shader has its row");
    }
}
