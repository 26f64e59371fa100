//! In a browser: what the page reports of the sandbox each frame (`voxcast_status()`, read by
//! the page's test and by `#voxcast-step`, which a screen reader speaks): the mode, the level's
//! step, where the named controls and the scene are, the volume, Render image's state, the
//! level editor's link.

use crate::sandbox::checks::compare::Comparison;
use crate::sandbox::data::loading::Loading;
use crate::sandbox::levels::Lessons;
use crate::sandbox::preview::live::LiveView;
use crate::sandbox::shared::mode::Mode;
use crate::sandbox::shared::quality::Backend;
use crate::sandbox::shared::quality::PreviewSettings;
use crate::sandbox::shared::state::VolumeState;
use crate::sandbox::shared::viewport::Viewport;
use crate::sandbox::shared::web::{PageStatus, publish};
use bevy::prelude::*;
use bevy_egui::EguiContexts;

/// What the page reports, each feature's state as it publishes it.
#[derive(bevy::ecs::system::SystemParam)]
pub(super) struct Reported<'w> {
    mode: Res<'w, State<Mode>>,
    lessons: Res<'w, Lessons>,
    volume: Res<'w, VolumeState>,
    loading: Res<'w, Loading>,
    comparison: Res<'w, Comparison>,
    preview: Res<'w, PreviewSettings>,
    viewport: Option<Res<'w, Viewport>>,
    live: Option<Res<'w, LiveView>>,
    progressive: Option<Res<'w, crate::sandbox::preview::progressive::Progressive>>,
    pacing: Option<Res<'w, crate::sandbox::shared::pacing::Pacing>>,
    draft: Option<Res<'w, crate::sandbox::levels::editor::Draft>>,
}

/// Publishes this frame's state for the page.
pub(super) fn publish_status(
    mut contexts: EguiContexts,
    reported: Reported,
    mut render_started: Local<Option<bevy::platform::time::Instant>>,
    mut render_wall: Local<Option<f64>>,
) -> Result {
    let Reported {
        mode,
        lessons,
        volume,
        loading,
        comparison,
        preview,
        viewport,
        live,
        progressive,
        pacing,
        draft,
    } = reported;
    // Render image's time on the wall clock, from the click to the result (the slices and the
    // frames drawn between them).
    match (comparison.busy(), *render_started) {
        (true, None) => *render_started = Some(bevy::platform::time::Instant::now()),
        (false, Some(t)) => {
            *render_wall = Some(t.elapsed().as_secs_f64());
            *render_started = None;
        }
        _ => {}
    }
    let ctx = contexts.ctx_mut()?;
    let rect = |r: bevy_egui::egui::Rect| [r.min.x, r.min.y, r.width(), r.height()];
    let screen = ctx.content_rect();
    let targets = super::targets(ctx);
    let step = lessons.step_in(*mode.get()).map(|s| s.text.clone());
    publish(|s| {
        s.mode = match mode.get() {
            Mode::FreePlay => "free play".into(),
            Mode::Level(l) => format!("level {}", l + 1),
        };
        if step.as_deref() != Some(s.step_text.as_str()) {
            s.step_text = step.clone().unwrap_or_default();
            set_step(&s.step_text);
        }
        s.levels_message = lessons.message.clone().unwrap_or_default();
        editor_status(s, draft.as_deref());
        s.targets = targets
            .0
            .iter()
            .map(|(n, r)| (n.clone(), rect(*r)))
            .collect();
        s.scene = rect(Viewport::rect(viewport.as_deref(), ctx));
        s.canvas = [screen.width(), screen.height()];
        s.volume = volume.source.clone();
        s.load_error = loading.error.clone().unwrap_or_default();
        s.loading = loading.under_way().is_some();
        s.load_progress = loading.fraction().unwrap_or(-1.0);
        s.render = if comparison.busy() {
            "rendering".into()
        } else if let Some(r) = &comparison.result {
            format!(
                "done in {:.3} s of work, {:.3} s on the clock",
                r.seconds,
                render_wall.unwrap_or(0.0)
            )
        } else {
            String::new()
        };
        s.resting = pacing.as_ref().is_some_and(|p| p.resting);
        s.working = pacing.as_ref().is_some_and(|p| p.working);
        s.woken_by = pacing.as_ref().map_or("", |p| p.woken_by).into();
        preview_status(s, &preview, live.as_deref(), progressive.as_deref());
    });
    Ok(())
}

/// The level editor's draft: its number of steps, the link made and its last message.
fn editor_status(s: &mut PageStatus, draft: Option<&crate::sandbox::levels::editor::Draft>) {
    s.editor_steps = draft
        .and_then(|d| d.level.as_ref())
        .map_or(0, |l| l.steps.len());
    s.editor_link = draft.and_then(|d| d.link.clone()).unwrap_or_default();
    s.editor_message = draft.and_then(|d| d.message.clone()).unwrap_or_default();
}

/// The preview: its backend (or off), the CPU live view's state, and whether the resting view
/// is drawn at its best.
fn preview_status(
    s: &mut PageStatus,
    preview: &PreviewSettings,
    live: Option<&LiveView>,
    progressive: Option<&crate::sandbox::preview::progressive::Progressive>,
) {
    s.live = live.map(|l| l.status()).unwrap_or_default();
    s.settled = match preview.backend {
        Backend::Cpu => live.is_some_and(|l| l.showing_exact()),
        Backend::Gpu => progressive.is_none_or(|p| p.full_quality_shown()),
    };
    s.backend = match (preview.enabled, preview.backend) {
        (false, _) => "off",
        (true, Backend::Gpu) => "gpu",
        (true, Backend::Cpu) => "cpu",
    }
    .into();
}

/// The step's text in the page, for a screen reader.
fn set_step(text: &str) {
    if let Some(element) = web_sys::window()
        .and_then(|w| w.document())
        .and_then(|d| d.get_element_by_id("voxcast-step"))
    {
        element.set_text_content(Some(text));
    }
}
