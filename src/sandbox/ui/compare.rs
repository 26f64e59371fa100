//! The "Render image" window: starts the exact CPU render of the current view, shows its
//! progress with Cancel, then the preview's capture, the render and their difference heat-map
//! side by side with the figures, and saves them as PNGs.

use crate::sandbox::checks::compare::{
    Compared, Comparison, HEAT_FULL_SCALE, Part, save_png, save_pngs,
};
use crate::sandbox::shared::files::PICKS_FILES;
use crate::sandbox::shared::state::{MainCamera, RenderState, View, VolumeState};
use bevy::prelude::*;
use bevy_egui::{EguiContexts, egui};
use voxcast_core::cost::CostView;
use voxcast_core::image_out::LinearImage;
use voxcast_core::numbers::{count, duration, sig, sig64};

/// The window's own state: open or not, the textures of the shown result, the save path.
#[derive(Resource)]
pub(crate) struct CompareWindow {
    pub open: bool,
    /// Uploaded textures (preview, render, heat-map) and the result generation they show.
    textures: Option<(u64, [Option<egui::TextureHandle>; 3])>,
    path: String,
    saved: Option<Result<String, String>>,
    /// The cost view's texture and the (result generation, view) it shows.
    cost_texture: Option<((u64, CostView), egui::TextureHandle)>,
}

impl Default for CompareWindow {
    fn default() -> Self {
        Self {
            open: false,
            textures: None,
            path: "voxcast_render.png".into(),
            saved: None,
            cost_texture: None,
        }
    }
}

fn texture(ctx: &egui::Context, name: &str, img: &LinearImage) -> egui::TextureHandle {
    let rgb = img.to_rgb8();
    let color = egui::ColorImage::from_rgb([img.width as usize, img.height as usize], rgb.as_raw());
    ctx.load_texture(name, color, egui::TextureOptions::NEAREST)
}

/// The scene on screen, which a render is of or not: the main camera's view, the render
/// settings and the volume, and the part of the window the scene is drawn in.
#[derive(bevy::ecs::system::SystemParam)]
pub(super) struct SceneNow<'w, 's> {
    views: Query<'w, 's, &'static View, With<MainCamera>>,
    render: Res<'w, RenderState>,
    volume: Res<'w, VolumeState>,
    viewport: Option<Res<'w, crate::sandbox::shared::viewport::Viewport>>,
}

pub(super) fn compare_window(
    mut contexts: EguiContexts,
    mut window: ResMut<CompareWindow>,
    mut comparison: ResMut<Comparison>,
    now: SceneNow,
    // The mode (a new one closes the window) and the requests to open or close it.
    mode: Res<State<crate::sandbox::shared::mode::Mode>>,
    mut shows: MessageReader<crate::sandbox::checks::compare::ShowRenderImage>,
) -> Result {
    if let Some(show) = shows.read().last() {
        window.open = show.0;
    }
    // A new level (or free play) brings its own scene: the last render is of another.
    if mode.is_changed() && !mode.is_added() {
        window.open = false;
    }
    if !window.open {
        return Ok(());
    }
    let ctx = contexts.ctx_mut()?.clone();
    let mut open = window.open;
    // Over the scene, below the level's text.
    let scene = crate::sandbox::shared::viewport::Viewport::rect(now.viewport.as_deref(), &ctx);
    // Inside the scene's part of the window, which it never leaves, movable and shrinkable.
    let window_frame = egui::Window::new("Render image")
        .open(&mut open)
        .constrain_to(scene)
        .default_pos(scene.min + egui::vec2(8.0, 8.0))
        .default_width((scene.width() - 16.0).clamp(160.0, 720.0))
        .max_width(scene.width() - 8.0)
        .max_height(scene.height() - 8.0)
        .resizable(true)
        .scroll([false, true]);
    let shown = window_frame.show(&ctx, |ui| {
        let current = comparison.result.as_ref().is_none_or(|r| {
            r.snapshot
                .is_current(now.views.single().ok(), &now.render, &now.volume)
        });
        contents(ui, &mut window, &mut comparison, current)
    });
    if let Some(shown) = shown {
        super::target(shown.response, "render image window");
    }
    window.open = open;
    Ok(())
}

/// The window's contents: the Render button, progress and Cancel, and the last result
/// (`current`: made from the view and settings shown now).
fn contents(
    ui: &mut egui::Ui,
    window: &mut CompareWindow,
    comparison: &mut Comparison,
    current: bool,
) {
    ui.horizontal(|ui| {
        let button = ui.add_enabled(!comparison.busy(), egui::Button::new("Render image"));
        if button
            .on_hover_text(
                "Render the current view on the CPU (the exact reference) and compare \
                 it with the preview",
            )
            .clicked()
        {
            comparison.start();
        }
        if comparison.busy() {
            let (done, total) = comparison.progress().unwrap_or((0, 0));
            let fraction = if total == 0 {
                0.0
            } else {
                done as f32 / total as f32
            };
            // Cancel first: the bar takes the rest of the row, however narrow the window.
            if ui.button("Cancel").clicked() {
                comparison.cancel();
            }
            ui.add(egui::ProgressBar::new(fraction).text(format!(
                "Rendering… {}",
                voxcast_core::numbers::percent(fraction)
            )));
        }
    });
    if let Some(message) = &comparison.message {
        ui.colored_label(egui::Color32::LIGHT_RED, message);
    }
    let Some(result) = &comparison.result else {
        ui.label("No render yet.");
        return;
    };
    result_view(ui, window, &mut comparison.cost_view, result);
    if !current {
        ui.colored_label(
            egui::Color32::YELLOW,
            "The view or settings changed since this render: render again to compare.",
        );
    }
}

/// The picture or one of the cost views for the render's panel, with the view's legend.
fn cost_choice(
    ui: &mut egui::Ui,
    window: &mut CompareWindow,
    cost_view: &mut Option<CostView>,
    result: &Compared,
) {
    let Some(cost) = &result.cost else {
        return;
    };
    let render = super::cost_view::Shown {
        label: "Show the render as:",
        picture: "The rendered image",
        to_first: "Render with First to see it.",
    };
    // A depth chosen for a First render, then another method rendered: the picture again.
    let method = result.snapshot.settings.method;
    super::cost_view::choice(ui, &render, cost_view, method);
    let Some(view) = *cost_view else {
        return;
    };
    let key = (result.generation, view);
    if window.cost_texture.as_ref().map(|t| t.0) != Some(key) {
        let tex = texture(ui.ctx(), "cost", &cost.image(view));
        window.cost_texture = Some((key, tex));
    }
    let total = |i: usize| cost.pixels.iter().map(|p| p[i] as u64).sum::<u64>();
    let legend = match view {
        CostView::Depth | CostView::DepthOfHits => match cost.depth_as(view) {
            Some(depth) => format!("{} {}.", view.doc(), depth.scale_words()),
            None => view.doc().to_string(),
        },
        CostView::Stops => {
            let rays = cost.stats.rays.max(1) as f32;
            let share = |n: u64| voxcast_core::numbers::percent(n as f32 / rays);
            let marched = total(4);
            format!(
                "{} Of the rays: {} stopped early, {} ran through, {} hit the cap, {} took no \
                 sample.",
                view.doc(),
                share(total(2)),
                share(marched - total(2) - total(3)),
                share(total(3)),
                share(cost.stats.rays - marched),
            )
        }
        _ if cost.max(view) == 0 => format!("{} None in this image.", view.doc()),
        _ => format!(
            "{} {}; in all {}.",
            view.doc(),
            voxcast_core::cost::scale_words(cost.full_scale, cost.max(view)),
            sig64(match view {
                CostView::Samples => total(0),
                _ => total(1) - total(0),
            } as f64)
        ),
    };
    ui.label(egui::RichText::new(legend).small());
}

/// A comparison's result: what was rendered and how fast, how far the preview is from the
/// render, the three images side by side, and saving them.
fn result_view(
    ui: &mut egui::Ui,
    window: &mut CompareWindow,
    cost_view: &mut Option<CostView>,
    result: &Compared,
) {
    let ctx = ui.ctx().clone();
    if window.textures.as_ref().map(|t| t.0) != Some(result.generation) {
        let gpu = result
            .gpu
            .as_ref()
            .ok()
            .map(|g| texture(&ctx, "preview", g));
        let cpu = Some(texture(&ctx, "render", &result.cpu));
        let heat = result.diff.as_ref().map(|(_, h)| texture(&ctx, "heat", h));
        window.textures = Some((result.generation, [gpu, cpu, heat]));
        window.saved = None;
    }
    figures(ui, result);
    cost_choice(ui, window, cost_view, result);
    let Some((_, textures)) = &window.textures else {
        return;
    };
    let mut textures = textures.clone();
    let mut render_label = "CPU render";
    if let (Some(view), Some(((_, shown), tex))) = (*cost_view, &window.cost_texture)
        && view == *shown
    {
        textures[1] = Some(tex.clone());
        render_label = match view {
            CostView::Samples => "samples interpolated",
            CostView::Skipped => "positions skipped",
            CostView::Stops => "how rays stopped",
            CostView::Depth => "distance to the first hit",
            CostView::DepthOfHits => "distance to the first hit, hits' range",
        };
    }
    let preview = if result.snapshot.live {
        "CPU live view"
    } else {
        "GPU preview"
    };
    images(
        ui,
        result.snapshot.size,
        [preview, render_label, "difference"],
        &textures,
    );
    save_row(ui, window, result);
}

/// The render's size, time and counts, and the preview's difference from it.
fn figures(ui: &mut egui::Ui, result: &Compared) {
    let s = &result.stats;
    let size = result.snapshot.size;
    // Millions a second of each count (positions: as BENCHMARKS.md's samples/s, comparable
    // across ray casters; interpolated: what this one reconstructed).
    let per_second = |n: u64| count((n as f64 / result.seconds.max(1e-9)) as u64);
    ui.label(format!(
        "{}×{} on the CPU in {}: {} rays, {} sample positions, {} interpolated ({} positions \
         and {} interpolated a second)",
        size.x,
        size.y,
        duration(result.seconds),
        count(s.rays),
        count(s.positions),
        count(s.samples),
        per_second(s.positions),
        per_second(s.samples)
    ));
    if let Some(warning) = s.cap_warning(result.snapshot.settings.max_samples) {
        ui.colored_label(egui::Color32::YELLOW, warning);
    }
    match &result.diff {
        Some((d, _)) => ui.label(format!(
            "preview − render: max {}/255, mean {}/255, RMSE {}/255 (heat-map: white at {:.0}/255)",
            sig(d.max_abs * 255.0),
            sig64(d.mean_abs * 255.0),
            sig64(d.rmse * 255.0),
            HEAT_FULL_SCALE * 255.0
        )),
        None => ui.label(format!(
            "No comparison: {}",
            result.gpu.as_ref().err().map_or("", |e| e.as_str())
        )),
    };
}

/// The three images side by side, each a third of the width at the scene's aspect, under
/// its label; an image missing (no preview to compare) leaves its place empty.
fn images(
    ui: &mut egui::Ui,
    size: bevy::math::UVec2,
    labels: [&str; 3],
    textures: &[Option<egui::TextureHandle>; 3],
) {
    let width = ((ui.available_width() - 16.0) / 3.0).max(64.0);
    let height = width * size.y as f32 / size.x.max(1) as f32;
    ui.horizontal(|ui| {
        for (label, tex) in labels.iter().zip(textures) {
            ui.vertical(|ui| {
                ui.label(*label);
                match tex {
                    Some(t) => {
                        ui.add(
                            egui::Image::new(egui::load::SizedTexture::from_handle(t))
                                .fit_to_exact_size(egui::vec2(width, height)),
                        );
                    }
                    None => {
                        ui.allocate_space(egui::vec2(width, height));
                    }
                }
            });
        }
    });
}

/// The PNGs' path and the save buttons (on a page, one a file), and what the last save said.
fn save_row(ui: &mut egui::Ui, window: &mut CompareWindow, result: &Compared) {
    // Wrapped: on a small screen the page's three buttons go on the next line rather than
    // past the window's edge.
    ui.horizontal_wrapped(|ui| {
        ui.text_edit_singleline(&mut window.path).on_hover_text(
            "The render's PNG; the preview and the heat-map are saved beside it as \
             NAME_preview.png and NAME_diff.png",
        );
        if PICKS_FILES {
            // A browser asks before a page downloads several files at once: one button each.
            for part in [Part::Render, Part::Preview, Part::Difference] {
                let target = part.label().to_lowercase();
                if super::target(ui.button(part.label()), &target).clicked() {
                    window.saved =
                        Some(
                            save_png(result, &window.path, part).map(|written| match written {
                                Some(p) => format!("downloaded {}", p.display()),
                                None => "this comparison has no such image".into(),
                            }),
                        );
                }
            }
        } else if super::target(ui.button("Save PNG"), "save png").clicked() {
            window.saved = Some(save_pngs(result, &window.path).map(|written| {
                let names: Vec<_> = written.iter().map(|p| p.display().to_string()).collect();
                format!("saved {}", names.join(", "))
            }));
        }
    });
    match &window.saved {
        Some(Ok(m)) => {
            ui.label(m);
        }
        Some(Err(e)) => {
            ui.colored_label(egui::Color32::LIGHT_RED, e);
        }
        None => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every string the window draws — busy or not, with a result compared, with one that
    /// could not be, stale or current, saved or not — has a glyph in the window's font.
    #[test]
    fn every_render_window_string_can_be_drawn() {
        for (capture, current) in [(true, true), (false, false)] {
            let mut window = CompareWindow {
                saved: Some(Err("file not found: /nowhere/x.png".into())),
                ..Default::default()
            };
            let mut comparison = Comparison::default();
            comparison.result = Some(crate::sandbox::checks::compare::tests::example(capture));
            comparison.message = Some("the preview had not drawn the volume yet".into());
            for view in [None, Some(CostView::Samples), Some(CostView::Stops)] {
                comparison.cost_view = view;
                let missing = crate::sandbox::ui::missing_glyphs(|ui| {
                    contents(ui, &mut window, &mut comparison, current)
                });
                assert!(missing.is_empty(), "no glyph for {missing:?}");
            }
        }
        let mut busy = Comparison::default();
        busy.start();
        let missing = crate::sandbox::ui::missing_glyphs(|ui| {
            ui.label("x".repeat(100)); // the empty window draws little text of its own
            contents(ui, &mut CompareWindow::default(), &mut busy, true)
        });
        assert!(missing.is_empty(), "no glyph for {missing:?}");
    }
}
