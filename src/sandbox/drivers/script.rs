//! `voxcast --play-levels DIR`: plays every level to the end in the real window, as a player
//! would — the Levels panel's commands (start, Next), then for each step the change its
//! control makes (a method chosen, a slider moved, a ray clicked, a point added to the transfer
//! function, Render image pressed) — and takes a window screenshot of each level's first step
//! (`DIR/NN_id.png`), of the steps that open a ray's breakdown, compare Render image with the
//! preview, crop the volume, show a cost view or measure a knob once they are done (`DIR/NN_id_stepK.png`), and of free play at the end
//! (`DIR/free_play.png`). It checks that no objective is met before the player acts and that
//! each is met after; `DIR/report.txt` lists every step, and the exit code is non-zero on a
//! failure.

use crate::sandbox::checks::compare::Comparison;
use crate::sandbox::checks::trade::StepTrade;
use crate::sandbox::data::loading::Loading;
use crate::sandbox::inspect::breakdown::BreakdownState;
use crate::sandbox::inspect::rays::{Inspection, RayAnimation, RaySelection};
use crate::sandbox::inspect::virtual_camera::VirtualCamera;
use crate::sandbox::levels::{Lessons, LevelCommand};
use crate::sandbox::shared::mode::Mode;
use crate::sandbox::shared::render_change::{Author, PreviewChanges, RenderChanges};
use crate::sandbox::shared::state::{RenderState, VolumeState};
use bevy::prelude::*;
use bevy::render::view::screenshot::{Screenshot, save_to_disk};
use std::path::PathBuf;
use voxcast_core::classify::Classification;
use voxcast_core::level::Objective;
use voxcast_core::shade::{Light, LightSource};
use voxcast_core::step::Length;
use voxcast_core::transfer::{ControlPoint, TransferFunction};

/// Frames a new scene is drawn before its screenshot (pipelines compile synchronously here).
const SETTLE_FRAMES: u32 = 8;
/// Frames a done step waits before its picture (the panel's new textures and glyphs).
const STEP_SHOT_DELAY: u32 = 10;
/// Frames a screenshot is given to arrive.
const SHOT_FRAMES: u32 = 4;
/// Frames an objective is given to be met after acting (a comparison renders meanwhile)...
const MET_FRAMES: u32 = 600;
/// ... and at least this long: a measurement is timed in seconds, so a fast machine draws
/// [`MET_FRAMES`] frames before one ends (Measure's ladder, the preview's cost view).
const MET_TIME: std::time::Duration = std::time::Duration::from_secs(60);

/// Where the screenshots and the report go, and which levels are played.
#[derive(Resource)]
pub struct PlayLevels {
    pub dir: PathBuf,
    /// Only the levels added from files (`--levels`).
    pub added_only: bool,
    /// Only the levels at these places in the list (`--play-range`).
    pub range: Option<std::ops::RangeInclusive<usize>>,
}

impl PlayLevels {
    /// Whether `level`, at place `i` in the list, is played.
    fn plays(&self, i: usize, level: &voxcast_core::level::Level) -> bool {
        let added = level.origin != voxcast_core::level::Origin::Embedded;
        (added || !self.added_only) && self.range.as_ref().is_none_or(|r| r.contains(&i))
    }
}

/// Where the run is.
#[derive(Resource, Default)]
struct Run {
    level: usize,
    phase: Phase,
    frames: u32,
    report: Vec<String>,
    failed: bool,
    /// When the run started (the report gives each level's seconds).
    started: Option<bevy::platform::time::Instant>,
    /// When the current level was asked for (the report gives how long its scene took).
    asked: Option<bevy::platform::time::Instant>,
    /// The frame a done step's screenshot was asked for (Next waits for it).
    step_shot: Option<u32>,
    /// The frame the current step was first seen met.
    met_at: Option<u32>,
    /// When the player first acted on the current step.
    acted_at: Option<bevy::platform::time::Instant>,
    /// Frames spent in free play after the last level (for its screenshot).
    ending: u32,
}

#[derive(Default, Clone, Copy, PartialEq, Debug)]
enum Phase {
    /// Ask for the level.
    #[default]
    Start,
    /// Wait for its scene, then screenshot.
    Settle,
    /// Wait for the screenshot.
    Shot,
    /// Check the step is not met yet, then act until it is.
    Act { acted: bool },
}

pub(crate) fn plugin(app: &mut App) {
    app.init_resource::<Run>()
        .add_systems(
            Update,
            drive.in_set(crate::sandbox::shared::schedule::Frame::Drive),
        )
        .add_systems(Last, write_ambiguities.run_if(run_once));
}

/// Writes the frame's unordered conflicts beside the report (`ambiguities.txt`), once the
/// schedules have been built by their first run.
fn write_ambiguities(world: &mut World) {
    let Some(dir) = world.get_resource::<PlayLevels>().map(|p| p.dir.clone()) else {
        return;
    };
    let mut text = super::ambiguities::conflicts(world).join("\n");
    text.push('\n');
    if let Err(e) = std::fs::write(dir.join("ambiguities.txt"), text) {
        eprintln!("ambiguities.txt: {e}");
    }
}

impl Hands<'_, '_> {
    /// Whether the CPU live view draws the volume.
    fn live_view_on(&self) -> bool {
        self.preview.now.as_ref().is_some_and(|p| p.cpu_live())
    }

    /// Whether the volume is on screen at full quality: the CPU live view's exact render, or
    /// the GPU preview at rest with its progressive pass (if any) finished.
    fn full_quality(&self) -> bool {
        if self.live_view_on() {
            self.live.as_ref().is_none_or(|l| l.showing_exact())
        } else {
            !self.motion.as_ref().is_some_and(|m| m.moving)
                && self
                    .progressive
                    .as_ref()
                    .is_none_or(|p| p.full_quality_shown())
        }
    }
}

/// What the player's hands change.
#[derive(bevy::ecs::system::SystemParam)]
struct Hands<'w, 's> {
    render: RenderChanges<'w>,
    selection: ResMut<'w, RaySelection>,
    breakdown: ResMut<'w, BreakdownState>,
    comparison: ResMut<'w, Comparison>,
    show_render_image: MessageWriter<'w, crate::sandbox::checks::compare::ShowRenderImage>,
    animation: ResMut<'w, RayAnimation>,
    trade: ResMut<'w, StepTrade>,
    cameras: Query<'w, 's, &'static mut VirtualCamera>,
    inspection: Res<'w, Inspection>,
    live: Option<Res<'w, crate::sandbox::preview::live::LiveView>>,
    preview: PreviewChanges<'w>,
    inspect: ResMut<'w, crate::sandbox::inspect::rays::InspectSettings>,
    progressive: Option<Res<'w, crate::sandbox::preview::progressive::Progressive>>,
    motion: Option<Res<'w, crate::sandbox::shared::quality::Motion>>,
    volume: Res<'w, VolumeState>,
    main_view: Query<
        'w,
        's,
        &'static crate::sandbox::shared::state::View,
        With<crate::sandbox::shared::state::MainCamera>,
    >,
    loading: ResMut<'w, Loading>,
    rays: Res<'w, crate::sandbox::data::source::RayScene>,
    ray_choices: ResMut<'w, crate::sandbox::data::choices::RayChoices>,
}

/// What the play-through tells the sandbox: the levels' commands, and the exit at its end.
#[derive(bevy::ecs::system::SystemParam)]
struct Tells<'w> {
    levels: MessageWriter<'w, LevelCommand>,
    exit: MessageWriter<'w, AppExit>,
}

fn drive(
    mut commands: Commands,
    mut run: ResMut<Run>,
    mut lessons: ResMut<Lessons>,
    mode: Res<State<Mode>>,
    request: Res<PlayLevels>,
    mut hands: Hands,
    mut tells: Tells,
) {
    let run = &mut *run;
    run.frames += 1;
    // With --levels, the added levels alone; with --play-range, the levels in it.
    while lessons
        .levels
        .get(run.level)
        .is_some_and(|l| !request.plays(run.level, l))
    {
        run.level += 1;
    }
    let mut out = Out {
        commands: &mut commands,
        send: &mut tells.levels,
        dir: &request.dir,
    };
    if run.level >= lessons.levels.len() {
        end_in_free_play(run, &mut out, &mut hands, &mut tells.exit);
        return;
    }
    let level = lessons.levels[run.level].clone();
    let in_level = *mode.get() == Mode::Level(run.level);
    match run.phase {
        Phase::Start => {
            run.started
                .get_or_insert_with(bevy::platform::time::Instant::now);
            out.send.write(LevelCommand::Start(run.level));
            run.asked = Some(bevy::platform::time::Instant::now());
            (run.phase, run.frames) = (Phase::Settle, 0);
        }
        Phase::Settle => settle(run, &level, in_level, &lessons, &mut hands, &mut out),
        Phase::Shot => {
            if run.frames >= SHOT_FRAMES {
                (run.phase, run.frames) = (Phase::Act { acted: false }, 0);
            }
        }
        Phase::Act { .. } if !in_level => {
            // Leaving the level (its last Next) ends it.
            let seconds = run
                .started
                .get_or_insert_with(bevy::platform::time::Instant::now)
                .elapsed();
            run.report.push(format!(
                "{}: done at {:.1} s",
                level.id,
                seconds.as_secs_f32()
            ));
            run.level += 1;
            (run.phase, run.frames) = (Phase::Start, 0);
        }
        Phase::Act { acted } => play_step(run, acted, &level, &mut lessons, &mut hands, &mut out),
    }
}

/// What the driver writes out: screenshots (into `dir`) and the Levels panel's commands.
struct Out<'a, 'c, 's, 'm> {
    commands: &'a mut Commands<'c, 's>,
    send: &'a mut MessageWriter<'m, LevelCommand>,
    dir: &'a std::path::Path,
}

impl Out<'_, '_, '_, '_> {
    /// A screenshot of the window, saved as `name` in the report's folder.
    fn shot(&mut self, name: &str) {
        self.commands
            .spawn(Screenshot::primary_window())
            .observe(save_to_disk(self.dir.join(name)));
    }
}

/// Every level played: free play again, its screenshot, then the report and the exit.
fn end_in_free_play(
    run: &mut Run,
    out: &mut Out,
    hands: &mut Hands,
    exit: &mut MessageWriter<AppExit>,
) {
    run.ending += 1;
    if run.ending == SETTLE_FRAMES {
        hands.animation.skip();
        out.shot("free_play.png");
    } else if run.ending >= SETTLE_FRAMES + SHOT_FRAMES
        && (out.dir.join("free_play.png").exists() || run.ending > SETTLE_FRAMES + MET_FRAMES)
    {
        // The picture is written on another thread: wait for it before exiting.
        finish(run, out.dir, exit);
    }
}

/// The level's scene on screen: its time noted, then its picture once the volume is drawn at
/// full quality (or after a while).
fn settle(
    run: &mut Run,
    level: &voxcast_core::level::Level,
    in_level: bool,
    lessons: &Lessons,
    hands: &mut Hands,
    out: &mut Out,
) {
    let ready = in_level && lessons.scene_ready() && hands.loading.under_way().is_none();
    if !ready {
        run.frames = 0;
        return;
    }
    if let Some(asked) = run.asked.take() {
        run.report.push(format!(
            "{}: scene set up in {:.2} s",
            level.id,
            asked.elapsed().as_secs_f32()
        ));
    }
    // The rays drawn whole, not growing.
    hands.animation.skip();
    // The picture waits (a little) for the volume at full quality.
    let drawn = hands.full_quality();
    if run.frames >= SETTLE_FRAMES && (drawn || run.frames >= MET_FRAMES / 4) {
        out.shot(&format!("{:02}_{}.png", run.level + 1, level.id));
        (run.phase, run.frames) = (Phase::Shot, 0);
    }
}

/// The level's current step: checked not met before acting, then acted on every frame until
/// it is met (or given up on), pictured where its result is worth a look, and left with Next.
fn play_step(
    run: &mut Run,
    acted: bool,
    level: &voxcast_core::level::Level,
    lessons: &mut Lessons,
    hands: &mut Hands,
    out: &mut Out,
) {
    let Some(step) = level.steps.get(lessons.step).cloned() else {
        return;
    };
    let what = format!("{} step {}", level.id, lessons.step + 1);
    if !acted && run.frames < 2 {
        // The check runs once the scene is set: give it a frame.
        return;
    }
    if !acted {
        if lessons.met && step.objective != Objective::Read {
            run.report
                .push(format!("{what}: FAILED, met before the player acted"));
            run.failed = true;
        }
        run.phase = Phase::Act { acted: true };
        run.frames = 0;
        run.acted_at = Some(bevy::platform::time::Instant::now());
    }
    if lessons.met {
        step_met(run, level, &step.objective, lessons.step, hands, out);
        return;
    }
    if run.frames > MET_FRAMES && run.acted_at.is_some_and(|t| t.elapsed() > MET_TIME) {
        run.report
            .push(format!("{what}: FAILED, not met after acting ({step:?})"));
        run.failed = true;
        out.send.write(LevelCommand::FreePlay);
        return;
    }
    // The hands edit copies of the settings, each sent as one change.
    let mut edited = Edits {
        render: hands.render.now.clone(),
        preview: hands.preview.now.as_deref().cloned(),
    };
    act(run.level, &step.objective, hands, &mut edited, lessons);
    hands.render.edited(Author::Script, edited.render);
    if let Some(p) = edited.preview {
        hands.preview.edited(Author::Script, p);
    }
}

/// A step met: pictured (a few frames on, for the panels' new textures and glyphs) where its
/// result is worth a look, reported, and left with Next.
fn step_met(
    run: &mut Run,
    level: &voxcast_core::level::Level,
    objective: &Objective,
    step: usize,
    hands: &mut Hands,
    out: &mut Out,
) {
    // The breakdown, Render image, crop, lights and cost steps are pictured once done.
    let pictured = matches!(
        objective,
        Objective::OpenHighestSample
            | Objective::Compared { .. }
            | Objective::CropAtMost { .. }
            | Objective::CostViewed { .. }
            | Objective::KnobMeasured { .. }
            | Objective::OpenLitSample { .. }
            | Objective::LevoyHighlight { .. }
            | Objective::FullModel
            | Objective::DepthCue { on: true }
            | Objective::RegionAround { .. }
            | Objective::SkipBlocks { .. }
            | Objective::Skipping { on: true }
            | Objective::PreviewCostView { .. }
            | Objective::RayDensity { .. }
            | Objective::RayView { .. }
    );
    let met_at = *run.met_at.get_or_insert(run.frames);
    match run.step_shot {
        None if pictured && run.frames < met_at + STEP_SHOT_DELAY => return,
        None if pictured => {
            out.shot(&format!(
                "{:02}_{}_step{}.png",
                run.level + 1,
                level.id,
                step + 1
            ));
            run.step_shot = Some(run.frames);
            return;
        }
        Some(at) if run.frames < at + SHOT_FRAMES => return,
        _ => run.step_shot = None,
    }
    run.met_at = None;
    run.report.push(format!(
        "{} step {}: ok after {} frames",
        level.id,
        step + 1,
        run.frames
    ));
    if *objective == Objective::TradeMeasured
        && let Some((t, _)) = &hands.trade.result
    {
        run.report.extend(trade_lines(t));
    }
    if matches!(
        objective,
        Objective::Compared { .. } | Objective::CostViewed { .. }
    ) {
        // Done comparing: the player closes the window.
        hands
            .show_render_image
            .write(crate::sandbox::checks::compare::ShowRenderImage(false));
    }
    out.send.write(LevelCommand::Next);
    (run.phase, run.frames) = (Phase::Act { acted: false }, 0);
}

/// What the hands edit in a frame: copies of the render state and the preview's settings
/// (none without a preview), each sent as one change.
struct Edits {
    render: RenderState,
    preview: Option<crate::sandbox::shared::quality::PreviewSettings>,
}

/// Does what the objective asks of level `level`'s current step, through the state the step's
/// control edits. Called every frame until the objective is met (each action is idempotent).
/// Each kind of action has its function below; this match names every objective, so a new
/// one does not compile until it is given to one.
fn act(
    level: usize,
    objective: &Objective,
    hands: &mut Hands,
    edits: &mut Edits,
    lessons: &mut Lessons,
) {
    match objective {
        Objective::Read => {}
        Objective::All { of } => {
            for o in of {
                act(level, o, hands, edits, lessons);
            }
        }
        Objective::StepMoved
        | Objective::StepAtMost { .. }
        | Objective::StepAtLeast { .. }
        | Objective::Jitter { .. }
        | Objective::SupersamplingAtLeast { .. }
        | Objective::Skipping { .. }
        | Objective::Interpolation { .. }
        | Objective::Method { .. }
        | Objective::EarlyTermination { .. }
        | Objective::OpacityCorrection { .. }
        | Objective::Shading { .. }
        | Objective::BackToFront { .. } => {
            sampling(objective, &mut edits.render.settings, hands, lessons)
        }
        Objective::TargetBetween { .. }
        | Objective::Classification { .. }
        | Objective::RegionAround { .. }
        | Objective::ClipPlane { .. }
        | Objective::ClipPositionBetween { .. }
        | Objective::CropAtMost { .. } => {
            classification_and_cut(objective, &mut edits.render.settings, hands)
        }
        Objective::LightMovedAway
        | Objective::WarmAndCoolLights
        | Objective::LightInsideVolume
        | Objective::LightKind { .. }
        | Objective::Attenuated
        | Objective::LightsAtLeast { .. }
        | Objective::DistinctLightColours { .. } => {
            lights(objective, &mut edits.render.settings, hands, lessons)
        }
        Objective::Specular { .. }
        | Objective::FullModel
        | Objective::DepthCue { .. }
        | Objective::LevoyHighlight { .. } => {
            shading_model(objective, &mut edits.render.settings, hands)
        }
        Objective::TfAlphaAtMost { .. }
        | Objective::TfBinary { .. }
        | Objective::TfColorNear { .. } => transfer(objective, &mut edits.render.transfer, hands),
        Objective::PreviewScaleAtMost { .. }
        | Objective::PreviewScaleAtLeast { .. }
        | Objective::Preview { .. }
        | Objective::PreviewCostView { .. } => preview(objective, edits.preview.as_mut()),
        Objective::SelectRay
        | Objective::SelectCutRay
        | Objective::VirtualPixelsAtLeast { .. }
        | Objective::OpenHighestSample
        | Objective::OpenLitSample { .. }
        | Objective::SkipBlocks { .. } => rays_and_samples(objective, hands, lessons),
        Objective::CostViewed { .. }
        | Objective::Compared { .. }
        | Objective::TradeMeasured
        | Objective::KnobMeasured { .. }
        | Objective::RayDensity { .. }
        | Objective::RayView { .. } => windows_and_data(objective, hands, edits.preview.as_mut()),
        Objective::PredictValue { .. }
        | Objective::PredictComposite { .. }
        | Objective::PredictSamples
        | Objective::PredictCells
        | Objective::PredictFixedCountStep { .. }
        | Objective::NameEffect { .. }
        | Objective::StudyQuestion { .. } => answers(level, objective, hands, lessons),
    }
}

/// How the rays sample and composite: the step, jitter, rays per pixel, skipping, interpolation,
/// method, early termination, opacity correction, shading on or off, the order.
fn sampling(
    objective: &Objective,
    s: &mut voxcast_core::settings::RenderSettings,
    hands: &Hands,
    lessons: &Lessons,
) {
    match objective {
        Objective::StepMoved => {
            // The slider moved to twice the step the step opened with.
            if let Some(open) = lessons.opened() {
                let voxel = hands.volume.volume.spacing().min_element();
                let now = s.step.voxels(voxel);
                if (now - open.step_voxels).abs() <= 1e-3 {
                    s.step = Length::Voxels(open.step_voxels * 2.0);
                }
            }
        }
        Objective::StepAtMost { voxels } | Objective::StepAtLeast { voxels } => {
            s.step = Length::Voxels(*voxels)
        }
        Objective::Jitter { on } => s.jitter = *on,
        Objective::SupersamplingAtLeast { rays } => s.supersampling = *rays,
        Objective::Skipping { on } => s.skipping = *on,
        Objective::Interpolation { trilinear } => {
            s.interpolation = if *trilinear {
                voxcast_core::sample::Interpolation::Trilinear
            } else {
                voxcast_core::sample::Interpolation::Nearest
            }
        }
        Objective::Method { method } => s.method = *method,
        Objective::EarlyTermination { on } => s.early_termination = *on,
        Objective::OpacityCorrection { on } => s.opacity_correction = *on,
        Objective::Shading { on } => s.shading = *on,
        Objective::BackToFront { on } => {
            s.order = if *on {
                voxcast_core::composite::Order::BackToFront
            } else {
                voxcast_core::composite::Order::FrontToBack
            }
        }
        _ => {}
    }
}

/// What is classified and what is cut away: the target, the classification, a region, the
/// clip plane and the crop box.
fn classification_and_cut(
    objective: &Objective,
    s: &mut voxcast_core::settings::RenderSettings,
    hands: &Hands,
) {
    match objective {
        Objective::TargetBetween { lo, hi } => s.target = Some(0.5 * (lo + hi)),
        Objective::Classification { mode } => {
            s.classification = match mode.as_str() {
                "iso-contours" => Classification::IsoContours {
                    isovalues: vec![s.target.unwrap_or(128.0)],
                    thickness_voxels: 1.0,
                },
                "boundaries" => Classification::Boundaries {
                    full_gradient: None,
                },
                "value-gradient" => Classification::ValueGradient {
                    regions: Vec::new(),
                },
                _ => Classification::Table,
            }
        }
        Objective::RegionAround {
            value,
            max_gradient,
        } => {
            // A rectangle dragged around the value, from the bottom to three quarters of the
            // highest gradient allowed.
            let (lo_v, hi_v) = hands.volume.volume.value_range();
            let half = 0.05 * (hi_v - lo_v);
            s.classification = Classification::ValueGradient {
                regions: vec![voxcast_core::classify::Region {
                    value: [value - half, value + half],
                    gradient: [0.0, 0.75 * max_gradient],
                    opacity: 0.6,
                }],
            };
        }
        Objective::ClipPlane { on } if s.clip.plane.is_some() != *on => {
            // "Face the camera" for the virtual camera: its rays cross the plane.
            let normal = hands
                .cameras
                .iter()
                .next()
                .map_or(Vec3::X, |vc| -vc.view.forward());
            s.clip.plane = on.then_some(voxcast_core::clip::ClipPlane {
                normal,
                position: 0.0,
            });
        }
        Objective::ClipPositionBetween { lo, hi } => {
            let normal = s.clip.plane.map_or(Vec3::X, |p| p.normal);
            s.clip.plane = Some(voxcast_core::clip::ClipPlane {
                normal,
                position: 0.5 * (lo + hi),
            });
        }
        Objective::CropAtMost { fraction } => {
            s.clip.crop_hi.x = (s.clip.crop_lo.x + fraction).min(1.0);
        }
        _ => {}
    }
}

/// The lights: moved, placed, of a kind, attenuated, added, coloured.
fn lights(
    objective: &Objective,
    s: &mut voxcast_core::settings::RenderSettings,
    hands: &Hands,
    lessons: &Lessons,
) {
    let (lo, hi) = hands.volume.volume.bounds();
    let centre = (lo + hi) * 0.5;
    match objective {
        Objective::LightMovedAway => {
            // The first light that stands somewhere, dragged outwards from the centre to a
            // tenth of the box's diagonal farther than it stood when the step opened.
            let open = lessons
                .opened()
                .map(|o| o.light_distances.clone())
                .unwrap_or_default();
            let diagonal = (hi - lo).length();
            for (l, then) in s.phong.lights.iter_mut().zip(open) {
                let (Some(p), Some(then)) = (l.light.position(), then) else {
                    continue;
                };
                let out = (p - centre).try_normalize().unwrap_or(Vec3::X);
                let to = centre + out * (then + 0.1) * diagonal;
                if p.distance(centre) < to.distance(centre) {
                    l.light = match l.light {
                        Light::Spot(spot) => Light::Spot(voxcast_core::shade::Spot {
                            position: to,
                            ..spot
                        }),
                        _ => Light::Point(to),
                    };
                }
                break;
            }
        }
        Objective::WarmAndCoolLights => {
            while s.phong.lights.len() < 2 && s.phong.add_light() {}
            for (l, c) in s.phong.lights.iter_mut().zip(PALETTE) {
                l.color = c;
            }
        }
        Objective::LightInsideVolume => first_light(s).light = Light::Point(centre),
        Objective::LightKind { light } => {
            first_light(s).light = match light.as_str() {
                "point" => Light::Point(hi + (hi - lo) * 0.25),
                "directional" => Light::Directional(Vec3::new(-1.0, -1.0, -1.0).normalize()),
                _ => Light::Headlight,
            }
        }
        Objective::Attenuated => {
            let l = first_light(s);
            if !matches!(l.light, Light::Point(_)) {
                l.light = Light::Point(hi + (hi - lo) * 0.25);
            }
            l.kl = 0.5 / (hi - lo).length();
        }
        Objective::LightsAtLeast { count } => {
            // "Add a light" pressed until there are enough.
            while s.phong.lights.len() < *count && s.phong.add_light() {}
        }
        Objective::DistinctLightColours { count } => {
            for (l, c) in s.phong.lights.iter_mut().zip(PALETTE).take(*count) {
                l.color = c;
            }
        }
        _ => {}
    }
}

/// The shading model: the specular model, the full model, depth cueing, the highlight.
fn shading_model(
    objective: &Objective,
    s: &mut voxcast_core::settings::RenderSettings,
    hands: &Hands,
) {
    let (lo, hi) = hands.volume.volume.bounds();
    match objective {
        Objective::Specular { model } => {
            if let Some(m) = voxcast_core::shade::SpecularModel::ALL
                .into_iter()
                .find(|m| m.name() == model)
            {
                s.phong.model = m;
            }
        }
        Objective::FullModel => {
            // Emission raised, the last light made a spot aimed at the centre with an ambient
            // share, as a student would in the Shading and light panel.
            s.phong.ke = 0.15;
            s.phong.ka = s.phong.ka.max(0.2);
            let at = hi + (hi - lo) * Vec3::new(0.2, 0.5, 0.3);
            let spot = Light::Spot(voxcast_core::shade::Spot {
                position: at,
                direction: (lo + hi) * 0.5 - at,
                ..Default::default()
            });
            if s.phong.lights.is_empty() {
                s.phong.lights.push(LightSource::new(spot));
            }
            if let Some(l) = s.phong.lights.last_mut() {
                l.light = spot;
                l.ambient = 0.4;
            }
        }
        Objective::DepthCue { on } => {
            s.phong.depth_cue = *on;
            s.phong.depth_kl = 2.0 / (hi - lo).length();
        }
        Objective::LevoyHighlight { on } => {
            s.phong.highlight = if *on {
                voxcast_core::shade::Highlight::Levoy
            } else {
                voxcast_core::shade::Highlight::White
            }
        }
        _ => {}
    }
}

/// The transfer function's points, as the editor drags them.
fn transfer(objective: &Objective, transfer: &mut TransferFunction, hands: &Hands) {
    match objective {
        Objective::TfAlphaAtMost { value, alpha } => {
            if let Ok((t, _)) = transfer.with_point_added(*value, *alpha) {
                *transfer = t;
            }
        }
        Objective::TfBinary { threshold, within } => {
            // The editor's points dragged to a step: none below, full above, in the colour the
            // function gives the threshold.
            let (lo, hi) = hands.volume.volume.value_range();
            let c = transfer.evaluate(*threshold);
            let colour = [c.x, c.y, c.z];
            let points = vec![
                ControlPoint::new(lo.min(threshold - within), colour, 0.0),
                ControlPoint::new(threshold - 0.5 * within, colour, 0.0),
                ControlPoint::new(threshold + 0.5 * within, colour, 1.0),
                ControlPoint::new(hi.max(threshold + within), colour, 1.0),
            ];
            if let Ok(t) = TransferFunction::new("binary", points) {
                *transfer = t;
            }
        }
        Objective::TfColorNear {
            value,
            color,
            alpha,
            ..
        } => {
            if let Ok((t, i)) = transfer.with_point_added(*value, *alpha)
                && let Ok(t) = t.with_point_color(i, *color)
            {
                *transfer = t;
            }
        }
        _ => {}
    }
}

/// The preview's own settings: on or off, its resolution, a cost view.
fn preview(
    objective: &Objective,
    preview: Option<&mut crate::sandbox::shared::quality::PreviewSettings>,
) {
    match objective {
        Objective::PreviewScaleAtMost { scale } | Objective::PreviewScaleAtLeast { scale } => {
            if let Some(p) = preview {
                p.enabled = true;
                p.scale = *scale;
            }
        }
        Objective::Preview { on } => {
            if let Some(p) = preview {
                p.enabled = *on;
            }
        }
        Objective::PreviewCostView { view } => {
            if let Some(p) = preview {
                p.cost_view = voxcast_core::cost::CostView::parse(view);
            }
        }
        _ => {}
    }
}

/// The virtual camera's rays: one selected, a breakdown row opened, its pixels, the skip blocks.
fn rays_and_samples(objective: &Objective, hands: &mut Hands, lessons: &Lessons) {
    match objective {
        Objective::SelectRay => select_centre(hands, lessons),
        Objective::SelectCutRay => select_centre(hands, lessons),
        Objective::VirtualPixelsAtLeast { pixels } => {
            for mut vc in &mut hands.cameras {
                (vc.width, vc.height) = (*pixels, *pixels);
            }
        }
        Objective::OpenHighestSample => {
            // Click a ray, then the row of its highest value.
            let highest = hands.breakdown.trace.as_ref().and_then(|t| {
                (0..t.samples.len()).max_by(|&a, &b| {
                    let v = |i: usize| t.samples[i].reconstruction.value;
                    v(a).total_cmp(&v(b))
                })
            });
            match highest {
                Some(i) => hands.breakdown.opened = Some(i),
                None => select_centre(hands, lessons),
            }
        }
        Objective::OpenLitSample { lights } => {
            // Click a ray, then a row the lights shaded.
            let lit = hands.breakdown.trace.as_ref().and_then(|t| {
                t.samples.iter().position(|x| {
                    x.shading.is_some_and(|sh| sh.lights_reaching() >= *lights) && x.alpha > 0.0
                })
            });
            match lit {
                Some(i) => hands.breakdown.opened = Some(i),
                None => select_centre(hands, lessons),
            }
        }
        Objective::SkipBlocks { on } => hands.inspect.show_blocks = *on,
        _ => {}
    }
}

/// Render image and its cost view, the measurements, a ray density and its views.
fn windows_and_data(
    objective: &Objective,
    hands: &mut Hands,
    preview: Option<&mut crate::sandbox::shared::quality::PreviewSettings>,
) {
    match objective {
        Objective::CostViewed { view } => {
            // Render image pressed (again, if the settings changed), then the view chosen.
            hands
                .show_render_image
                .write(crate::sandbox::checks::compare::ShowRenderImage(true));
            let current = hands.comparison.result.as_ref().is_some_and(|r| {
                r.snapshot.is_current(
                    hands.main_view.single().ok(),
                    &hands.render.now,
                    &hands.volume,
                )
            });
            if !current && !hands.comparison.busy() {
                hands.comparison.start();
            }
            hands.comparison.cost_view = voxcast_core::cost::CostView::parse(view);
        }
        Objective::Compared { .. } => {
            // As the button does: the window opens and the comparison starts.
            hands
                .show_render_image
                .write(crate::sandbox::checks::compare::ShowRenderImage(true));
            if !hands.comparison.busy() {
                hands.comparison.start();
            }
        }
        Objective::TradeMeasured if hands.trade.progress().is_none() => hands.trade.request(),
        Objective::KnobMeasured { knob } => {
            if let Some(k) = voxcast_core::knob::Knob::parse(knob) {
                hands.trade.knob = k;
            }
            if hands.trade.progress().is_none() {
                hands.trade.request();
            }
        }
        Objective::RayDensity {
            source,
            trace,
            side_at_least,
        } => compute_density(hands, source, *trace, *side_at_least),
        Objective::RayView { view, on } => match view.as_str() {
            "mesh" => hands.ray_choices.view.mesh = *on,
            "field" => hands.ray_choices.view.field = *on,
            _ => {
                if let Some(p) = preview {
                    p.enabled = *on;
                }
            }
        },
        _ => {}
    }
}

/// The answers a step asks for: a prediction typed and checked, an effect named, a study's
/// question.
fn answers(level: usize, objective: &Objective, hands: &mut Hands, lessons: &mut Lessons) {
    match objective {
        Objective::PredictValue { .. } | Objective::PredictComposite { .. } => {
            // The player works the lecture's formula out; here the core's answer is typed and
            // checked, once (a try is kept for each Check).
            let answer = match objective {
                Objective::PredictValue { .. } => lessons.detail.as_ref().map(|d| d.value),
                _ => lessons
                    .composite
                    .as_ref()
                    .and_then(|rows| rows.last())
                    .map(|r| r.after[0]),
            };
            if let Some(v) = answer
                && lessons.tried.is_none()
            {
                lessons.prediction = v.to_string();
                lessons.submit_prediction(level);
            }
        }
        Objective::PredictSamples
        | Objective::PredictCells
        | Objective::PredictFixedCountStep { .. } => {
            // A question about the selected ray: one selected (the centre's, if none is), then
            // the core's answer for it typed and checked, once.
            if hands.selection.selected.is_none() {
                let centre = hands.inspection.size / 2;
                if hands.inspection.size != UVec2::ZERO {
                    hands.selection.click(centre);
                }
            }
            // Typed once the step's scene is on screen (its step size changes the count), and
            // again if the ray's answer changed since (a try is kept for each).
            if let Some(v) = lessons.ray_answer.as_ref().map(|r| r.truth)
                && lessons.scene_ready()
                && lessons.tried != Some(v)
            {
                lessons.prediction = v.to_string();
                lessons.submit_prediction(level);
            }
        }
        // The player judges the pictures; here the level's answer is chosen.
        Objective::NameEffect { trace } => lessons.named_effect = Some(*trace),
        Objective::StudyQuestion { trace, question } => {
            // The trace computed first, as the step asks; then the answer the code finds in
            // it, as a student who reads the density right would give it.
            use voxcast_core::rays::set::Filter;
            use voxcast_core::rays::study::Question;
            let Some(q) = Question::parse(question) else {
                return;
            };
            let Some(shown) = lessons.study_shown(*trace, q) else {
                hands.ray_choices.params.filter = q.density_filter().unwrap_or(Filter::All);
                compute_density(hands, "builtin:cornell", Some(*trace), 0);
                return;
            };
            if let Some(truth) = crate::sandbox::levels::study_truth(&shown, q) {
                lessons.answer_study(level, (*trace, question), &truth, &truth);
            }
        }
        _ => {}
    }
}

/// The colours the driver gives the lights: a warm one, a cool one, then two more.
const PALETTE: [Vec3; 4] = [
    Vec3::new(1.0, 0.45, 0.3),
    Vec3::new(0.3, 0.55, 1.0),
    Vec3::new(0.4, 1.0, 0.4),
    Vec3::new(1.0, 1.0, 1.0),
];

/// The measured trade, a line per step and one for the reference.
fn trade_lines(t: &voxcast_core::trade::Trade) -> Vec<String> {
    let mut lines: Vec<String> = t
        .rows
        .iter()
        .map(|r| {
            format!(
                "trade step {}: {:.2} ms, {} samples, max {:.1}/255, RMSE {:.2}/255",
                r.step_voxels,
                r.seconds * 1e3,
                r.samples,
                r.max_error * 255.0,
                r.rmse * 255.0
            )
        })
        .collect();
    lines.push(format!(
        "trade reference {}: {:.2} ms, {} samples",
        t.reference_voxels,
        t.reference_seconds * 1e3,
        t.reference_samples
    ));
    lines
}

/// The light the panel's first row edits (a headlight added if there is none).
fn first_light(s: &mut voxcast_core::settings::RenderSettings) -> &mut LightSource {
    if s.phong.lights.is_empty() {
        s.phong.lights.push(LightSource::default());
    }
    &mut s.phong.lights[0]
}

/// Chooses the density `source` (`camera` or a ray data source), `trace` and at least `side`
/// rays across in the Ray data section and presses Compute, unless it is on show or under way.
fn compute_density(hands: &mut Hands, source: &str, trace: Option<u32>, side: u32) {
    use crate::sandbox::data::source::SourceKind;
    if hands.loading.under_way().is_some() {
        return;
    }
    let c = &mut hands.ray_choices;
    c.source = match source {
        "camera" => SourceKind::Camera,
        "builtin:cornell" => SourceKind::Cornell,
        "builtin:cornell-1m" => SourceKind::CornellMillion,
        path => {
            c.path = path.to_string();
            SourceKind::File
        }
    };
    c.trace = trace;
    c.camera_side = c.camera_side.max(side);
    let choices = c.clone();
    let vc = hands.cameras.single().ok().copied();
    choices.compute(
        &mut hands.loading,
        &hands.rays,
        &hands.volume,
        &hands.render.now,
        vc.as_ref(),
    );
}

/// Clicks the pixel in the middle of the virtual camera's image, unless a ray is selected by
/// a click made while this step is open (twice if it is the one selected: a click on the
/// selected pixel unselects it).
fn select_centre(hands: &mut Hands, lessons: &Lessons) {
    let size = hands.inspection.size;
    let s = &mut hands.selection;
    let clicked_here = lessons.clicks_at_open().is_some_and(|c| s.clicks > c);
    if size == UVec2::ZERO || (s.selected.is_some() && clicked_here) {
        return;
    }
    let centre = size / 2;
    if s.selected == Some(centre) {
        s.click(centre);
    }
    s.click(centre);
}

/// Writes the report and exits (non-zero on a failure).
fn finish(run: &mut Run, dir: &std::path::Path, exit: &mut MessageWriter<AppExit>) {
    let text = run.report.join("\n") + "\n";
    print!("{text}");
    let written = std::fs::write(dir.join("report.txt"), &text);
    if let Err(e) = &written {
        eprintln!("error: cannot write the report: {e}");
    }
    exit.write(if run.failed || written.is_err() {
        AppExit::from_code(1)
    } else {
        AppExit::Success
    });
}
