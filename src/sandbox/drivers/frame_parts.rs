//! Where a measured frame's time goes (`--measure-frames`): clock marks between the main
//! world's stages (input, the sandbox's systems, egui's UI, egui's tessellation) and the render
//! world's (asset uploads, the window's next swap-chain image, queueing and preparing, the
//! render graph's passes recorded and submitted, presenting), as medians of each part. On a
//! software rasterizer the drawing itself is done where the driver does it: on submitting, on
//! presenting, or on its own threads meanwhile.
//! The two worlds run side by side (pipelined rendering), so a frame takes about the longer of
//! the two, plus what they take from each other's cores.

use crate::sandbox::shared::schedule::Frame;
use bevy::platform::time::Instant;
use bevy::prelude::*;
use bevy::render::renderer::{RenderGraph, RenderGraphSystems};
use bevy::render::{Render, RenderApp, RenderSystems};
use bevy_egui::EguiPostUpdateSet;
use std::sync::{Arc, Mutex};

/// The main world's parts, in the order of its marks.
const MAIN_PARTS: [&str; 5] = [
    "input and time",
    "the sandbox's systems",
    "egui's UI",
    "egui's tessellation",
    "the rest",
];
/// The render world's parts.
const RENDER_PARTS: [&str; 6] = [
    "asset uploads",
    "the window's next image",
    "queue and prepare",
    "recording the passes",
    "submitting them",
    "presenting",
];

/// The marks of the frame under way and the parts of the frames so far, in milliseconds.
#[derive(Default)]
struct Clock {
    main: [Option<Instant>; 7],
    render: [Option<Instant>; 7],
    main_frames: Vec<[f64; 5]>,
    render_frames: Vec<[f64; 6]>,
}

/// The clock both worlds write to.
#[derive(Resource, Clone, Default)]
pub struct FrameClock(Arc<Mutex<Clock>>);

/// Each main-world part as the spans between its marks (the rest: two spans).
const MAIN_SPANS: [&[(usize, usize)]; 5] = [
    &[(0, 1)],
    &[(1, 2)],
    &[(3, 4)],
    &[(4, 5)],
    &[(2, 3), (5, 6)],
];
/// Each render-world part: the span between consecutive marks.
const RENDER_SPANS: [&[(usize, usize)]; 6] = [
    &[(0, 1)],
    &[(1, 2)],
    &[(2, 3)],
    &[(3, 4)],
    &[(4, 5)],
    &[(5, 6)],
];

/// A frame's parts from its marks, in milliseconds (`None` if a mark is missing: a frame the
/// clock joined halfway).
fn parts<const M: usize, const P: usize>(
    marks: &[Option<Instant>; M],
    spans: [&[(usize, usize)]; P],
) -> Option<[f64; P]> {
    let mut out = [0.0; P];
    for (part, spans) in out.iter_mut().zip(spans) {
        for &(a, b) in spans {
            *part += marks[b]?.saturating_duration_since(marks[a]?).as_secs_f64() * 1000.0;
        }
    }
    Some(out)
}

/// Frames kept per world: more than a measurement asks for (one of more frames gets the parts
/// of its last 2048 at least), and a page that goes on after reporting (`--measure-frames` in a
/// browser) does not grow without end.
const KEPT: usize = 4096;

/// Adds a frame's parts, dropping the oldest half once [`KEPT`] are held.
fn keep<const P: usize>(frames: &mut Vec<[f64; P]>, parts: [f64; P]) {
    if frames.len() >= KEPT {
        frames.drain(..KEPT / 2);
    }
    frames.push(parts);
}

/// Mark `K` of the main world's frame; the last one closes the frame.
fn main_mark<const K: usize>(clock: Res<FrameClock>) {
    let Ok(mut c) = clock.0.lock() else { return };
    c.main[K] = Some(Instant::now());
    if K == 6 {
        if let Some(p) = parts(&c.main, MAIN_SPANS) {
            keep(&mut c.main_frames, p);
        }
        c.main = [None; 7];
    }
}

/// Mark `K` of the render world's frame; the last one closes it.
fn render_mark<const K: usize>(clock: Res<FrameClock>) {
    let Ok(mut c) = clock.0.lock() else { return };
    c.render[K] = Some(Instant::now());
    if K == 6 {
        if let Some(p) = parts(&c.render, RENDER_SPANS) {
            keep(&mut c.render_frames, p);
        }
        c.render = [None; 7];
    }
}

pub(crate) fn plugin(app: &mut App) {
    let clock = FrameClock::default();
    app.insert_resource(clock.clone())
        .add_systems(First, main_mark::<0>);
    app.add_systems(
        Update,
        (
            main_mark::<1>.before(Frame::Grab),
            main_mark::<2>.after(Frame::Show),
        ),
    )
    .add_systems(
        PostUpdate,
        (
            main_mark::<3>.before(EguiPostUpdateSet::EndPass),
            main_mark::<4>
                .after(EguiPostUpdateSet::EndPass)
                .before(EguiPostUpdateSet::ProcessOutput),
            main_mark::<5>.after(EguiPostUpdateSet::ProcessOutput),
        ),
    )
    .add_systems(Last, main_mark::<6>);
    if let Some(render) = app.get_sub_app_mut(RenderApp) {
        render
            .insert_resource(clock)
            .add_systems(
                Render,
                (
                    render_mark::<0>.in_set(RenderSystems::ExtractCommands),
                    render_mark::<1>.in_set(RenderSystems::CreateViews),
                    render_mark::<2>.in_set(RenderSystems::Queue),
                    render_mark::<6>.in_set(RenderSystems::Cleanup),
                ),
            )
            // The render graph runs inside the Render set: its passes are recorded, then
            // submitted; presenting follows it.
            .add_systems(
                RenderGraph,
                (
                    render_mark::<3>.in_set(RenderGraphSystems::Begin),
                    render_mark::<4>
                        .after(RenderGraphSystems::Render)
                        .before(RenderGraphSystems::Submit),
                    render_mark::<5>.in_set(RenderGraphSystems::Finish),
                ),
            );
    }
}

/// The median of each part over the last `frames` frames.
fn medians<const N: usize>(frames: &[[f64; N]], last: usize) -> Option<[f64; N]> {
    let frames = &frames[frames.len().saturating_sub(last)..];
    if frames.is_empty() {
        return None;
    }
    Some(std::array::from_fn(|i| {
        let v: Vec<f64> = frames.iter().map(|f| f[i]).collect();
        voxcast_core::numbers::median(&v).unwrap_or_default()
    }))
}

/// The parts of the last `frames` frames in words, or `None` before any frame was measured.
pub fn words(clock: &FrameClock, frames: usize) -> Option<String> {
    let c = clock.0.lock().ok()?;
    let list = |names: &[&str], values: &[f64]| {
        names
            .iter()
            .zip(values)
            .map(|(n, v)| format!("{n} {v:.1}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let main = medians(&c.main_frames, frames)?;
    let mut text = format!(
        "where a frame goes (medians, ms): main world {:.1} ({})",
        main.iter().sum::<f64>(),
        list(&MAIN_PARTS, &main)
    );
    if let Some(render) = medians(&c.render_frames, frames) {
        text += &format!(
            "; render world {:.1} ({})",
            render.iter().sum::<f64>(),
            list(&RENDER_PARTS, &render)
        );
    }
    Some(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The main world's marks become its parts, frame by frame, and the medians are each
    /// part's own.
    #[test]
    fn marks_become_parts_and_medians() {
        let mut app = App::new();
        app.add_plugins(MinimalPlugins);
        crate::sandbox::shared::schedule::configure(&mut app);
        app.configure_sets(
            PostUpdate,
            (EguiPostUpdateSet::EndPass, EguiPostUpdateSet::ProcessOutput).chain(),
        );
        plugin(&mut app);
        for _ in 0..5 {
            app.update();
        }
        let clock = app.world().resource::<FrameClock>().clone();
        let frames = clock.0.lock().unwrap().main_frames.len();
        assert_eq!(frames, 5);
        let text = words(&clock, 3).unwrap();
        assert!(text.contains("egui's tessellation"), "{text}");
        assert!(!text.contains("render world"), "{text}");
        let m = medians(&[[1.0, 9.0], [3.0, 7.0], [2.0, 8.0]], 3).unwrap();
        assert_eq!(m, [2.0, 8.0]);
        // The last two, an even count: the mean of the middle two (numbers::median).
        assert_eq!(medians(&[[1.0], [5.0], [4.0]], 2), Some([4.5]));
        assert_eq!(medians::<1>(&[], 2), None);
    }

    /// A part is the time between its marks; the main world's rest adds two spans; a frame
    /// with a missing mark has no parts.
    #[test]
    fn parts_are_the_spans_between_marks() {
        let t0 = Instant::now();
        let at = |ms: u64| Some(t0 + std::time::Duration::from_millis(ms));
        let marks = [at(0), at(1), at(4), at(10), at(13), at(15), at(20)];
        let p = parts(&marks, MAIN_SPANS).unwrap();
        let round = p.map(|v| (v * 1000.0).round() / 1000.0);
        assert_eq!(round, [1.0, 3.0, 3.0, 2.0, 6.0 + 5.0]);
        let r = parts(&marks, RENDER_SPANS).unwrap();
        assert!((r.iter().sum::<f64>() - 20.0).abs() < 1e-6);
        let mut missing = marks;
        missing[3] = None;
        assert_eq!(parts(&missing, MAIN_SPANS), None);
    }

    /// A clock that runs on keeps its latest frames only.
    #[test]
    fn the_clock_keeps_its_latest_frames() {
        let mut frames = Vec::new();
        for i in 0..KEPT + 10 {
            keep(&mut frames, [i as f64]);
        }
        assert!(frames.len() <= KEPT);
        assert_eq!(frames.last(), Some(&[(KEPT + 9) as f64]));
        assert_eq!(medians(&frames, 1), Some([(KEPT + 9) as f64]));
    }
}
