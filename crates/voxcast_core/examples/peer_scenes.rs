//! Renders the four peer scenes (issue 13's: the shared volumes, the peer's cameras, each
//! volume's own preset, 512², step ½ voxel) — and ch2, the MRI `benches/bench.sh` fetches into
//! `~/.cache/voxcast`, where it is — and prints, per scene, the median time, the sample
//! counts and a hash of the image's bytes — core only, so it builds in a minute, runs under
//! `valgrind --tool=callgrind` or `perf`, and tells at once whether a change to the march moved
//! a single bit of any picture.
//!
//! ```text
//! cargo run --release -p voxcast_core --example peer_scenes -- [--threads N] [--repeat N]
//!     [--only NAME] [--size N] [--step VOXELS] [--no-lanes | --narrow-lanes] [--method NAME] [--no-skipping]
//! ```
//!
//! `--method` renders another compositing method (maximum, minimum, average, sum, first) over
//! the same preset; `--no-skipping` turns every exact acceleration off (the hash must not move).
//!
//! Volumes come from `$VOXCAST_DATA` (default `../shared/data`), cameras from
//! `../shared/tools/peer/cams`; a missing one is left out with a note.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use voxcast_core::camera::Camera;
use voxcast_core::io::load;
use voxcast_core::preset;
use voxcast_core::render::render;
use voxcast_core::settings::RenderSettings;
use voxcast_core::step::Length;
use voxcast_core::trace::Scene;

const SCENES: [(&str, &str); 5] = [
    ("ct_cranium", "ct_cranium.nrrd"),
    ("mri_mni152", "mri_mni152.nii.gz"),
    ("mri_brainsmall", "mri_brainsmall.nrrd"),
    ("bunny_sdf", "bunny_sdf.nrrd"),
    ("mri_ch2", "ch2.nii.gz"),
];

struct Options {
    threads: usize,
    repeat: usize,
    only: Option<String>,
    size: u32,
    step: f32,
    simd: voxcast_core::trace::Vectors,
    method: Option<voxcast_core::composite::Method>,
    skipping: bool,
}

fn options() -> Result<Options, String> {
    let mut o = Options {
        threads: 2,
        repeat: 5,
        only: None,
        size: 512,
        step: 0.5,
        simd: voxcast_core::trace::Vectors::Wide,
        method: None,
        skipping: true,
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().ok_or(format!("{a} needs a value"));
        match a.as_str() {
            "--threads" => o.threads = value()?.parse().map_err(|e| format!("{e}"))?,
            "--repeat" => o.repeat = value()?.parse().map_err(|e| format!("{e}"))?,
            "--size" => o.size = value()?.parse().map_err(|e| format!("{e}"))?,
            "--step" => o.step = value()?.parse().map_err(|e| format!("{e}"))?,
            "--only" => o.only = Some(value()?),
            "--no-lanes" => o.simd = voxcast_core::trace::Vectors::Off,
            "--narrow-lanes" => o.simd = voxcast_core::trace::Vectors::Narrow,
            "--no-skipping" => o.skipping = false,
            "--method" => {
                let name = value()?;
                o.method = Some(
                    voxcast_core::composite::Method::ALL
                        .into_iter()
                        .find(|m| m.name().eq_ignore_ascii_case(&name))
                        .ok_or(format!("--method {name}: unknown"))?,
                );
            }
            other => return Err(format!("unknown argument {other}")),
        }
    }
    Ok(o)
}

/// FNV-1a over the image's 8-bit bytes.
fn hash(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

fn main() {
    let o = match options() {
        Ok(o) => o,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    };
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let data = std::env::var_os("VOXCAST_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("../shared/data"));
    let cams = root.join("../shared/tools/peer/cams");
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(o.threads)
        .build()
        .expect("a thread pool");
    println!(
        "{:<16} {:>9} {:>11} {:>12} {:>8} {:>18}",
        "scene", "time (s)", "positions", "interpolated", "M/s", "image hash"
    );
    for (name, file) in SCENES {
        if o.only.as_deref().is_some_and(|n| n != name) {
            continue;
        }
        let (path, cam) = if name == "mri_ch2" {
            let cache = std::env::var_os("XDG_CACHE_HOME")
                .map(PathBuf::from)
                .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))
                .unwrap_or_default();
            (
                cache.join("voxcast").join(file),
                root.join("benches/cams/mri_ch2.json"),
            )
        } else {
            (data.join(file), cams.join(format!("{name}.json")))
        };
        let (Ok(text), true) = (std::fs::read_to_string(&cam), path.exists()) else {
            eprintln!(
                "note: {} or {} missing: left out",
                path.display(),
                cam.display()
            );
            continue;
        };
        let volume = voxcast_core::Prepared::from(load(&path).expect("a readable volume").volume);
        let camera = Camera::from_json(&text).expect("a peer camera");
        // ch2 has no preset of its own: the peer's MRI transfer function, as bench.sh gives it.
        let p = preset::for_volume(volume.name())
            .or_else(|| preset::for_volume("mri_mni152"))
            .expect("a preset for the volume");
        let mut settings = p
            .settings_over(&RenderSettings::default())
            .expect("settings");
        settings.step = Length::Voxels(o.step);
        settings.skipping = o.skipping;
        if let Some(m) = o.method {
            settings.method = m;
        }
        let mut scene =
            Scene::new(&volume, &p.transfer, &settings, camera.forward()).expect("a valid scene");
        scene.simd = o.simd;
        let cancel = AtomicBool::new(false);
        let mut times = Vec::new();
        let mut last = None;
        for _ in 0..o.repeat.max(1) {
            let start = Instant::now();
            let out = pool.install(|| render(&scene, &camera, o.size, o.size, &|_, _| {}, &cancel));
            times.push(start.elapsed().as_secs_f64());
            last = Some(out.expect("not cancelled"));
        }
        let median = voxcast_core::numbers::median(&times).expect("timed");
        let (image, stats) = last.expect("one render");
        println!(
            "{name:<16} {median:>9.4} {:>11} {:>12} {:>8.1} {:>18x}",
            stats.positions,
            stats.samples,
            stats.positions as f64 / median / 1e6,
            hash(image.to_rgb8().as_raw())
        );
    }
}
