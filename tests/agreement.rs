//! The GPU preview agrees with the exact CPU render: for every embedded dataset, every method,
//! steps 1 and ½ voxel, shading off and on, the preview's screenshot (`voxcast --screenshot DIR
//! --sweep`, on real Vulkan: Mesa's lavapipe in CI) and the core's image of the same view differ
//! by at most 2/255 per channel. The figures are printed; a failure writes the CPU, GPU and
//! difference images to `tests/out/agreement/`.
//!
//! Without a Vulkan device the tests are reported as ignored, unless `VOXCAST_REQUIRE_GPU=1`
//! (as `.ci/run` sets it), which makes a missing device a failure.

mod support;

use std::path::{Path, PathBuf};
use std::process::Command;
use voxcast_core::builtin::{DATASETS, load_builtin};
use voxcast_core::camera::Camera;
use voxcast_core::image_out::LinearImage;
use voxcast_core::preset;
use voxcast_core::render::render_with_threads;
use voxcast_core::settings::{RenderSettings, agreement_cases};
use voxcast_core::trace::Scene;

const SIZE: u32 = 128;
/// The largest per-channel difference allowed, in 8-bit steps.
const TOLERANCE: f32 = 2.0;

fn out_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/out/agreement")
}

use support::{Completion, Outcome, run_or_skip};

fn main() {
    support::run(&[
        (
            "render_image_compares_the_preview_with_the_render",
            render_image_compares_the_preview_with_the_render,
        ),
        (
            "preview_matches_the_cpu_render",
            preview_matches_the_cpu_render,
        ),
        (
            "the_preview_as_webgl2_compiles_it_matches_the_cpu_render",
            the_preview_as_webgl2_compiles_it_matches_the_cpu_render,
        ),
        (
            "the_preview_leaps_reads_records_and_times_its_frames",
            the_preview_leaps_reads_records_and_times_its_frames,
        ),
    ])
}

/// The preview takes the core's accelerations for Accumulate — the cells' visibility with the
/// bricks' distances (leaps), the lattice records (values and gradients from 8 texels) — before
/// it is captured, and `--time-frames` times its full-size frames, resting or orbiting: what
/// BENCHMARKS.md sets beside VTK's GPU mapper.
fn the_preview_leaps_reads_records_and_times_its_frames() -> Outcome {
    let dir = out_dir();
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("timed.png");
    let mut command = Command::new(env!("CARGO_BIN_EXE_voxcast"));
    command
        .args(["--volume", "builtin:bunny", "--size", "96x64"])
        .args(["--time-frames", "3", "--screenshot"])
        .arg(&path);
    let (stdout, stderr) = match run_or_skip(&mut command) {
        Ok(out) => out,
        Err(skip) => return skip,
    };
    assert!(stderr.contains("cells' visibility uploaded"), "{stderr}");
    assert!(stderr.contains("lattice records uploaded"), "{stderr}");
    let line = stdout
        .lines()
        .find(|l| l.starts_with("preview frame: median"))
        .unwrap_or_else(|| panic!("no frame time in {stdout}"));
    println!("{line}");
    assert!(line.contains("over 3 frames at 96×64, resting"), "{line}");
    assert!(path.exists(), "the capture follows the timing");

    // Orbiting: each timed frame turns the view, and the picture is taken where it ends.
    let turned = dir.join("timed_orbit.png");
    let mut command = Command::new(env!("CARGO_BIN_EXE_voxcast"));
    command
        .args(["--volume", "builtin:bunny", "--size", "96x64"])
        .args(["--time-frames", "3", "--auto-orbit", "30", "--screenshot"])
        .arg(&turned);
    let (stdout, _) = match run_or_skip(&mut command) {
        Ok(out) => out,
        Err(skip) => return skip,
    };
    assert!(stdout.contains("orbiting 30° a frame"), "{stdout}");
    let (a, b) = (image::open(&path).unwrap(), image::open(&turned).unwrap());
    assert_ne!(a.as_bytes(), b.as_bytes(), "the orbit turned the view");
    Ok(Completion::Completed)
}

/// "Render image" without a window (`voxcast --compare`): the same capture, CPU render and
/// difference the button produces, for two datasets and methods, within the tolerance, and the
/// three pictures written; the third case has the camera inside the volume, the fourth two
/// coloured lights, one a point light whose marker (an opaque sphere) stands in the volume:
/// hidden while the preview is captured, since the CPU render has no meshes.
fn render_image_compares_the_preview_with_the_render() -> Outcome {
    let dir = out_dir().join("compare");
    std::fs::create_dir_all(&dir).unwrap();
    let inside = "eye=40,30,20,target=10,35,50,up=0,1,0,fov=70";
    for (volume, method, camera) in [
        ("bunny", "accumulate", None),
        ("brainsmall", "maximum", None),
        ("shells", "accumulate", Some(inside)),
        ("bucky", "accumulate", Some("light")),
    ] {
        let path = dir.join(format!("{volume}.png"));
        let mut command = Command::new(env!("CARGO_BIN_EXE_voxcast"));
        match camera {
            Some("light") => {
                // An attenuated orange point light and a blue directional one, Levoy's
                // highlight: the GPU's sum over lights against the core's.
                command.args(["--light", "point:15.5,15.5,15.5@1,0.6,0.4"]);
                command.args(["--light", "dir:1,-1,-1@0.3,0.5,1", "--kl", "0.01"]);
                command.args(["--highlight", "levoy"]);
            }
            Some(c) => {
                command.args(["--camera", c]);
            }
            None => {}
        }
        command
            .args(["--volume", &format!("builtin:{volume}"), "--method", method])
            .args(["--size", "160x90", "--compare"])
            .arg(&path);
        let (stdout, _) = match run_or_skip(&mut command) {
            Ok(out) => out,
            Err(skip) => return skip,
        };
        println!("{volume} {method}: {}", stdout.lines().next().unwrap_or(""));
        let max: f32 = stdout
            .split("max ")
            .nth(1)
            .and_then(|r| r.split('/').next())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("no figures in: {stdout}"));
        assert!(max <= TOLERANCE, "{volume} {method}: {max}/255");
        for name in [
            format!("{volume}.png"),
            format!("{volume}_preview.png"),
            format!("{volume}_diff.png"),
        ] {
            let img = image::open(dir.join(&name)).unwrap();
            assert_eq!((img.width(), img.height()), (160, 90), "{name}");
        }
    }
    Ok(Completion::Completed)
}

fn preview_matches_the_cpu_render() -> Outcome {
    let names: Vec<&str> = DATASETS.iter().map(|(n, _)| *n).collect();
    sweep_agrees(&names, &[], "")
}

/// WebGL2's preview (`src/sandbox/shared/quality.rs`, `GPU_READS_DEPTH`): compiled without the
/// `DEPTH_PREPASS` shader def, its rays never reading the scene's depth. The sandbox compiles
/// the same variant on any GPU when rays pass through geometry (`--no-depth-termination`: no
/// depth prepass), which this sweep draws on lavapipe.
fn the_preview_as_webgl2_compiles_it_matches_the_cpu_render() -> Outcome {
    sweep_agrees(
        &["bunny", "head", "masked"],
        &["--no-depth-termination"],
        "webgl2",
    )
}

/// Data sets swept at once: one sandbox on lavapipe keeps about one core busy (it waits on
/// its frames), so two at a time use the two cores CI has.
const SWEEPS_AT_ONCE: usize = 2;

/// One data set's sweep: its lines for the log, its largest difference and its failures.
struct Swept {
    lines: Vec<String>,
    worst: f32,
    failures: Vec<String>,
}

/// The sweep of the preview of `names` (with `args`) against the CPU render, every case within
/// [`TOLERANCE`]; its images in `tests/out/agreement/NAME[_suffix]`.
fn sweep_agrees(names: &[&str], args: &[&str], suffix: &str) -> Outcome {
    let next = std::sync::atomic::AtomicUsize::new(0);
    let swept = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..SWEEPS_AT_ONCE {
            scope.spawn(|| {
                loop {
                    let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    let Some(name) = names.get(i) else { break };
                    let one = sweep_one(name, args, suffix);
                    swept.lock().unwrap().push((i, one));
                }
            });
        }
    });
    let mut swept = swept.into_inner().unwrap();
    swept.sort_by_key(|(i, _)| *i);
    let (mut worst, mut failures) = (0.0f32, Vec::new());
    for (_, one) in swept {
        let one = match one {
            Ok(one) => one,
            Err(skip) => return skip,
        };
        for line in &one.lines {
            println!("{line}");
        }
        worst = worst.max(one.worst);
        failures.extend(one.failures);
    }
    println!("largest difference over all cases: {worst}/255");
    assert!(
        failures.is_empty(),
        "preview and render disagree (images in {}):\n{}",
        out_dir().display(),
        failures.join("\n")
    );
    Ok(Completion::Completed)
}

/// Data set `name`'s sweep: the sandbox's screenshots of every case, each against the CPU's
/// image of the same view (`Err`: the test is skipped for want of a GPU).
fn sweep_one(name: &str, args: &[&str], suffix: &str) -> Result<Swept, Outcome> {
    let dir = out_dir().join(if suffix.is_empty() {
        name.to_string()
    } else {
        format!("{name}_{suffix}")
    });
    let _ = std::fs::remove_dir_all(&dir);
    let mut command = Command::new(env!("CARGO_BIN_EXE_voxcast"));
    command
        .args([
            "--volume",
            &format!("builtin:{name}"),
            "--sweep",
            "--size",
            &format!("{SIZE}x{SIZE}"),
        ])
        .args(args)
        .arg("--screenshot")
        .arg(&dir);
    run_or_skip(&mut command)?;
    let volume = voxcast_core::Prepared::from(load_builtin(name).unwrap().volume);
    let p = preset::for_volume(volume.name()).unwrap();
    let base = p.settings_over(&RenderSettings::default()).unwrap();
    let view = p.view.unwrap();
    let (lo, hi) = volume.bounds();
    let camera = Camera::framing(lo, hi, view.from, view.up).unwrap();
    let mut swept = Swept {
        lines: Vec::new(),
        worst: 0.0,
        failures: Vec::new(),
    };
    for (stem, s) in agreement_cases(&base, volume.volume(), &p.transfer) {
        let scene = Scene::new(&volume, &p.transfer, &s, camera.forward()).unwrap();
        let (cpu, _) = render_with_threads(&scene, &camera, SIZE, SIZE, 1).unwrap();
        let cpu = LinearImage::from_rgb8(&cpu.to_rgb8());
        let gpu = LinearImage::from_rgb8(
            &image::open(dir.join(format!("{stem}.png")))
                .unwrap()
                .to_rgb8(),
        );
        let d = gpu.diff(&cpu).unwrap();
        let max = d.max_abs * 255.0;
        swept.lines.push(format!(
            "{name:16} {stem:28} max {max:3.0}/255  RMSE {:.3}/255",
            d.rmse * 255.0
        ));
        swept.worst = swept.worst.max(max);
        if max > TOLERANCE {
            cpu.save_png(&dir.join(format!("{stem}_cpu.png"))).unwrap();
            gpu.diff_heatmap(&cpu, 8.0 / 255.0)
                .unwrap()
                .save_png(&dir.join(format!("{stem}_diff.png")))
                .unwrap();
            swept.failures.push(format!("{name} {stem}: {max}/255"));
        }
    }
    Ok(swept)
}
