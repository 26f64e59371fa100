//! The preview's knobs timed as the preview's own images in a real window on lavapipe
//! (`voxcast --measure-knob`): the GPU preview's frames and the CPU live view's exact renders
//! at the window's size, the errors the core's. Speed is not judged (it is a benchmark's to
//! report), only that each setting was timed as the panel says: a median inside its spread,
//! every setting of the knob, the drawer named. Needs an X display, like `tests/levels.rs`.

mod support;

use support::{Completion, Outcome, gpu_required, windowed};

fn main() {
    support::run(&[
        (
            "the_preview_knobs_are_timed_as_the_preview_draws_them",
            || measured(),
        ),
        ("a_backend_that_does_not_draw_a_knob_says_so", stood_in),
        ("a_measured_frame_is_told_part_by_part", frame_parts),
    ])
}

/// `--measure-frames` in a real window says where a frame goes: every part of the main world
/// and of the render world, each a number of milliseconds, the render world's parts ending in
/// presenting, and no part longer than the frames it belongs to allow.
fn frame_parts() -> Outcome {
    let Some(mut command) = windowed(env!("CARGO_BIN_EXE_voxcast")) else {
        assert!(!gpu_required(), "no X display and no xvfb-run");
        return Ok(Completion::ignored_with(
            "no X display and no xvfb-run here (package xvfb)",
        ));
    };
    command
        .args(["--measure-frames", "10", "--auto-orbit", "5", "--no-rays"])
        .args(["--size", "480x270", "--volume", "builtin:bucky"])
        .env("XDG_RUNTIME_DIR", std::env::temp_dir());
    let output = command.output().expect("the binary runs");
    let out = String::from_utf8_lossy(&output.stdout);
    let err = String::from_utf8_lossy(&output.stderr);
    if !output.status.success()
        && let Some(skip) = support::skipped_for_want_of_a_gpu(&err)
    {
        return skip;
    }
    assert!(output.status.success(), "{out}\n{err}");
    let line = out
        .lines()
        .find(|l| l.contains("frame time"))
        .expect("a frame time");
    let median: f64 = line
        .split("median ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no median in {line}"));
    let parts = line
        .split("where a frame goes (medians, ms): ")
        .nth(1)
        .unwrap_or_else(|| panic!("no parts in {line}"));
    let (main, render) = parts.split_once("; render world ").expect("both worlds");
    let number = |text: &str, name: &str| -> f64 {
        let at = text
            .find(name)
            .unwrap_or_else(|| panic!("no {name} in {text}"));
        let rest = &text[at + name.len()..].trim_start();
        rest.split([' ', ',', ')'])
            .next()
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| panic!("{name} has no number in {text}"))
    };
    for name in [
        "main world",
        "input and time",
        "the sandbox's systems",
        "egui's UI",
        "egui's tessellation",
        "the rest",
    ] {
        let ms = number(main, name);
        assert!(
            (0.0..=10.0 * median).contains(&ms),
            "{name} {ms} ms: {line}"
        );
    }
    for name in [
        "asset uploads",
        "the window's next image",
        "queue and prepare",
        "recording the passes",
        "submitting them",
        "presenting",
    ] {
        let ms = number(render, name);
        assert!(
            (0.0..=10.0 * median).contains(&ms),
            "{name} {ms} ms: {line}"
        );
    }
    // The render world's total is the sum of its parts, as printed.
    let total: f64 = render.split(' ').next().unwrap().parse().unwrap();
    assert!(total > 0.0, "{line}");
    Ok(Completion::Completed)
}

/// `voxcast --measure-knob KNOB --preview-backend BACKEND` in a small window: its output, or
/// the test's outcome where it cannot run here.
fn measure(knob: &str, backend: &str) -> Result<std::process::Output, Outcome> {
    let Some(mut command) = windowed(env!("CARGO_BIN_EXE_voxcast")) else {
        assert!(!gpu_required(), "no X display and no xvfb-run");
        return Err(Ok(Completion::ignored_with(
            "no X display and no xvfb-run here (package xvfb)",
        )));
    };
    command
        .args(["--measure-knob", knob, "--preview-backend", backend])
        .args(["--size", "640x360", "--volume", "builtin:bucky"])
        .env("XDG_RUNTIME_DIR", std::env::temp_dir());
    let output = command.output().expect("the binary runs");
    let stderr = String::from_utf8_lossy(&output.stderr);
    if !output.status.success()
        && let Some(skip) = support::skipped_for_want_of_a_gpu(&stderr)
    {
        return Err(skip);
    }
    Ok(output)
}

/// A table's rows: (setting, median, fastest, slowest) in ms.
fn rows(table: &str) -> Vec<(String, f64, f64, f64)> {
    table
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| ---") && !l.contains("time (ms)"))
        .map(|l| {
            let cells: Vec<&str> = l.split('|').map(str::trim).collect();
            let (lo, hi) = cells[3].split_once('–').expect("fastest–slowest");
            let ms = |s: &str| s.parse::<f64>().unwrap_or_else(|e| panic!("{s}: {e}\n{l}"));
            (cells[1].to_string(), ms(cells[2]), ms(lo), ms(hi))
        })
        .collect()
}

fn measured() -> Outcome {
    for (knob, backend, drawer, settings) in [
        (
            "preview-scale",
            "cpu",
            "CPU live view",
            ["0.25", "0.5", "0.75", "full resolution (reference)"],
        ),
        (
            "preview-step-multiplier",
            "gpu",
            "GPU preview",
            ["×8", "×4", "×2", "×1 (reference)"],
        ),
    ] {
        let output = match measure(knob, backend) {
            Ok(o) => o,
            Err(skip) => return skip,
        };
        let out = String::from_utf8_lossy(&output.stdout);
        let err = String::from_utf8_lossy(&output.stderr);
        assert!(output.status.success(), "{knob} {backend}: {out}\n{err}");
        assert!(
            out.contains(&format!("one finished image of the {drawer}")),
            "{out}"
        );
        let rows = rows(&out);
        let names: Vec<&str> = rows.iter().map(|r| r.0.as_str()).collect();
        assert_eq!(names, settings, "{out}");
        for (name, median, fastest, slowest) in &rows {
            assert!(
                0.0 < *fastest && fastest <= median && median <= slowest,
                "{knob} {name}: {fastest} ≤ {median} ≤ {slowest}\n{out}"
            );
        }
    }
    Ok(Completion::Completed)
}

/// The CPU live view samples at the step itself: its step multiplier is not its to time, and
/// the command says that the core's renders stand in.
fn stood_in() -> Outcome {
    let output = match measure("preview-step-multiplier", "cpu") {
        Ok(o) => o,
        Err(skip) => return skip,
    };
    let out = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{out}");
    assert!(out.contains("changes only the GPU preview"), "{out}");
    assert!(out.contains("time: the core's render at 192×108"), "{out}");
    assert_eq!(rows(&out).len(), 4, "{out}");
    Ok(Completion::Completed)
}
