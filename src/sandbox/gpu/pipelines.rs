//! Whether the renderer is still compiling pipelines. The preview's pipeline is compiled per
//! [`crate::sandbox::gpu::uniform::PreviewVariant`]: after a change of method, shading, interpolation or
//! skipping, the new variant is compiled in the background (once; Bevy keeps it) and the preview
//! pass draws nothing until it is ready. Captures wait for it instead of counting frames; the
//! window keeps showing the last picture and says it is compiling.

use bevy::platform::time::Instant;
use bevy::prelude::*;
use bevy::render::render_resource::PipelineCache;
use bevy::render::{Render, RenderApp, RenderSystems};
use bevy_egui::egui;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// Set by the render world after each frame's pipeline work: true while any pipeline is queued
/// or being compiled. Read by the main world a frame later.
#[derive(Resource, Clone, Default)]
pub struct Compiling(Arc<AtomicBool>);

impl Compiling {
    /// Whether a pipeline was still being compiled at the end of the last rendered frame.
    pub fn now(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// In the window: while the GPU preview's pipeline is compiled, a line in the viewport says so
/// (over the last picture, which stays until the new pipeline draws).
pub(crate) fn window_plugin(app: &mut App) {
    app.add_systems(
        bevy_egui::EguiPrimaryContextPass,
        say_compiling.in_set(crate::sandbox::shared::schedule::Paint::Notes),
    );
}

fn say_compiling(
    mut contexts: bevy_egui::EguiContexts,
    compiling: Res<Compiling>,
    preview: Res<crate::sandbox::shared::quality::PreviewSettings>,
    viewport: Option<Res<crate::sandbox::shared::viewport::Viewport>>,
) -> Result {
    if !(compiling.now()
        && preview.enabled
        && preview.backend == crate::sandbox::shared::quality::Backend::Gpu)
    {
        return Ok(());
    }
    let ctx = contexts.ctx_mut()?;
    let rect = crate::sandbox::shared::viewport::Viewport::rect(viewport.as_deref(), ctx);
    ctx.layer_painter(egui::LayerId::background())
        .with_clip_rect(rect)
        .text(
            rect.center_top() + egui::vec2(0.0, 12.0),
            egui::Align2::CENTER_TOP,
            "Compiling the GPU preview for these settings…",
            egui::FontId::proportional(15.0),
            egui::Color32::from_gray(220),
        );
    Ok(())
}

/// When the current wave of compiling started (render world), to log how long it took, and
/// whether it has been given up on.
#[derive(Resource, Default)]
struct Started {
    at: Option<Instant>,
    given_up: bool,
}

pub(crate) fn plugin(app: &mut App) {
    let compiling = Compiling::default();
    app.insert_resource(compiling.clone());
    if let Some(render_app) = app.get_sub_app_mut(RenderApp) {
        render_app
            .insert_resource(compiling)
            .init_resource::<Started>()
            .add_systems(Render, note.in_set(RenderSystems::Cleanup));
    }
}

/// The longest a wave of compiling is waited for: a pipeline whose shader never arrives stays
/// queued forever, and a capture must not wait for it forever.
const MAX_WAIT_S: f64 = 60.0;

fn note(cache: Res<PipelineCache>, compiling: Res<Compiling>, mut started: ResMut<Started>) {
    // Render pipelines only: the preview's are, and Bevy queues compute pipelines a WebGL2
    // device cannot run (its sparse buffer updates), which stay waiting for ever.
    let waiting = cache.waiting_pipelines().any(|id| {
        cache.pipelines().nth(id).is_none_or(|p| {
            matches!(
                p.descriptor,
                bevy::render::render_resource::PipelineDescriptor::RenderPipelineDescriptor(_)
            )
        })
    });
    let waited = started.at.map_or(0.0, |at| at.elapsed().as_secs_f64());
    if waiting && waited >= MAX_WAIT_S && !started.given_up {
        warn!("a pipeline has been queued for {MAX_WAIT_S} s: no longer waiting for it");
        started.given_up = true;
    }
    compiling
        .0
        .store(waiting && !started.given_up, Ordering::Relaxed);
    match (waiting, started.at) {
        (true, None) => started.at = Some(Instant::now()),
        (false, Some(_)) => {
            info!("pipelines compiled in {waited:.2} s");
            *started = Started::default();
        }
        _ => {}
    }
}
