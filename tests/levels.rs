//! Every level played to the end in the real window on lavapipe (`voxcast --play-levels`): the
//! commands the Levels panel sends and, for each step, the change its control makes; window
//! screenshots. Twice: with the volume drawn by the CPU live view (what a machine without a
//! GPU gets) and by the GPU preview. The play of an edited level also holds the window's
//! schedules to `tests/data/ambiguities.txt` (Bevy's ambiguity detection). Needs an X display: the test uses `$DISPLAY`, or
//! starts one with `xvfb-run`; without either (or without a Vulkan device) it is reported as
//! ignored, unless `VOXCAST_REQUIRE_GPU=1` (as `.ci/run` sets it).

mod support;

use std::path::{Path, PathBuf};
use support::{Completion, Outcome, gpu_required, run_or_skip, windowed};
use voxcast_core::level::Level;

fn main() {
    // All four at once, whatever the cores: two at a time left the third play-through to run
    // alone after the first two (344 s against 174 s). At once the test took 309 s alone but
    // 302–357 s in cold CI runs, the three sharing two cores (BENCHMARKS.md, "CI's time").
    support::run_side_by_side(
        &[
            ("every_level_plays_through_in_the_cpu_live_view", || {
                play("cpu", "1-")
            }),
            // The GPU preview's play in two parts: the 16th level on measures the frame trade.
            ("levels_1_to_15_play_through_in_the_gpu_preview", || {
                play("gpu", "1-15")
            }),
            ("levels_16_on_play_through_in_the_gpu_preview", || {
                play("gpu", "16-")
            }),
            ("a_level_written_in_the_editor_plays_through", play_edited),
        ],
        Some(4),
    )
}

fn out_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/out/levels")
}

/// Plays the levels numbered `range` (`--play-range`: `FIRST-LAST`, or `FIRST-` to the end)
/// with the volume drawn by `backend` (`cpu` or `gpu`).
fn play(backend: &str, range: &str) -> Outcome {
    let Some(mut command) = windowed(env!("CARGO_BIN_EXE_voxcast")) else {
        assert!(!gpu_required(), "no X display and no xvfb-run");
        return Ok(Completion::ignored_with(
            "no X display and no xvfb-run here (package xvfb)",
        ));
    };
    let dir = out_dir().join(format!("{backend}_{range}"));
    let _ = std::fs::remove_dir_all(&dir);
    command
        .arg("--play-levels")
        .arg(&dir)
        .args(["--play-range", range])
        .args(["--preview-backend", backend])
        // Small and at half resolution: every frame is drawn by lavapipe on the CPU.
        .args(["--size", "1024x576", "--preview-scale", "0.5"])
        .env("XDG_RUNTIME_DIR", std::env::temp_dir());
    if let Err(skip) = run_or_skip(&mut command) {
        return skip;
    }
    let report = std::fs::read_to_string(dir.join("report.txt")).unwrap();
    assert!(!report.contains("FAILED"), "{report}");
    let levels = Level::all();
    let progress = std::fs::read_to_string(dir.join("progress.json")).unwrap();
    let progress: voxcast_core::level::Progress = serde_json::from_str(&progress).unwrap();
    let (first, last) = range.split_once('-').unwrap();
    let first: usize = first.parse().unwrap();
    let last: usize = last.parse().unwrap_or(levels.len());
    let played = levels.iter().enumerate().take(last).skip(first - 1);
    assert!(played.len() > 0, "no level numbered {range}");
    for (i, level) in played {
        for k in 1..=level.steps.len() {
            assert!(
                report.contains(&format!("{} step {k}: ok", level.id)),
                "{}: step {k}\n{report}",
                level.id
            );
        }
        assert_eq!(progress.completed[&level.id], level.steps.len());
        // The screenshot: the window, with more than a blank background in it.
        let shot = dir.join(format!("{:02}_{}.png", i + 1, level.id));
        let img = image::open(&shot)
            .unwrap_or_else(|e| panic!("{}: {e}", shot.display()))
            .to_rgb8();
        assert_eq!(img.dimensions(), (1024, 576), "{}", shot.display());
        let mut colours: Vec<[u8; 3]> = img.pixels().map(|p| p.0).collect();
        colours.sort_unstable();
        colours.dedup();
        assert!(colours.len() > 50, "{} is nearly blank", shot.display());
        if i == 0 {
            // The first level shows the virtual camera: its body is drawn (by the sharp
            // camera, as the preview runs at half resolution on the GPU).
            let body = voxcast_core::marker::BODY_COLOR * 255.0;
            let near =
                |p: &image::Rgb<u8>| (0..3).all(|c| (f32::from(p.0[c]) - body[c]).abs() <= 12.0);
            let drawn = img.pixels().filter(|p| near(p)).count();
            assert!(
                drawn >= 500,
                "{}: the virtual camera's body covers {drawn} pixels",
                shot.display()
            );
        }
    }
    // Free play at the end, and the done steps that open a breakdown or compare a render.
    let free = image::open(dir.join("free_play.png")).expect("free play's screenshot");
    assert_eq!((free.width(), free.height()), (1024, 576));
    let steps = std::fs::read_dir(&dir)
        .unwrap()
        .filter(|e| {
            let name = e.as_ref().unwrap().file_name();
            name.to_string_lossy().contains("_step")
        })
        .count();
    assert!(
        steps >= 2,
        "the breakdown and Render image steps are pictured"
    );
    Ok(Completion::Completed)
}

/// The level the editor wrote (`tests/data/edited_level.json`, which the sandbox's editor test
/// checks is its output), added with `--levels` and played to its end in the window: with
/// `--levels` the play-through plays the added levels alone.
fn play_edited() -> Outcome {
    let Some(mut command) = windowed(env!("CARGO_BIN_EXE_voxcast")) else {
        assert!(!gpu_required(), "no X display and no xvfb-run");
        return Ok(Completion::ignored_with(
            "no X display and no xvfb-run here (package xvfb)",
        ));
    };
    let dir = out_dir().join("edited");
    let _ = std::fs::remove_dir_all(&dir);
    let level = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/edited_level.json");
    command
        .arg("--play-levels")
        .arg(&dir)
        .arg("--levels")
        .arg(&level)
        .args(["--preview-backend", "cpu", "--size", "1024x576"])
        .env("XDG_RUNTIME_DIR", std::env::temp_dir());
    if let Err(skip) = run_or_skip(&mut command) {
        return skip;
    }
    let report = std::fs::read_to_string(dir.join("report.txt")).unwrap();
    assert!(!report.contains("FAILED"), "{report}");
    for k in 1..=2 {
        assert!(
            report.contains(&format!("my-bucky step {k}: ok")),
            "{report}"
        );
    }
    assert!(
        !report.contains("rays step"),
        "only the added level: {report}"
    );
    let progress = std::fs::read_to_string(dir.join("progress.json")).unwrap();
    let progress: voxcast_core::level::Progress = serde_json::from_str(&progress).unwrap();
    assert_eq!(progress.completed["my-bucky"], 2);
    unordered_conflicts_are_explained(&dir);
    Ok(Completion::Completed)
}

/// The window's schedules as the play-through built them: every pair of the sandbox's systems
/// with no order between them that touch the same data is explained in
/// `tests/data/ambiguities.txt`, and every explanation there is of a pair still found.
fn unordered_conflicts_are_explained(dir: &Path) {
    let found = std::fs::read_to_string(dir.join("ambiguities.txt")).unwrap();
    let found: std::collections::BTreeSet<&str> = found.lines().filter(|l| !l.is_empty()).collect();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/ambiguities.txt");
    let explained = std::fs::read_to_string(&path).unwrap();
    let mut known = std::collections::BTreeSet::new();
    for line in explained
        .lines()
        .filter(|l| !l.starts_with('#') && !l.is_empty())
    {
        let (pair, why) = line
            .split_once(" — ")
            .unwrap_or_else(|| panic!("{}: no explanation: {line}", path.display()));
        assert!(why.len() > 20, "{}: explain {pair}", path.display());
        known.insert(pair);
    }
    let unexplained: Vec<_> = found.difference(&known).collect();
    let gone: Vec<_> = known.difference(&found).collect();
    assert!(
        unexplained.is_empty(),
        "unordered conflicts not explained in {}: order them (Frame sets) or explain why \
         their order does not matter:\n{}",
        path.display(),
        unexplained
            .iter()
            .map(|l| l.to_string())
            .collect::<Vec<_>>()
            .join("\n")
    );
    assert!(
        gone.is_empty(),
        "explained in {} but no longer found (remove them):\n{}",
        path.display(),
        gone.iter()
            .map(|l| l.to_string())
            .collect::<Vec<_>>()
            .join("\n")
    );
}
