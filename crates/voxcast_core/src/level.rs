//! Tutorial levels as data (`assets/levels/*.json`): what a level's scene holds, its steps'
//! text, the control each step is about, and the objective that unlocks the next step — plus
//! the objective checks and the player's saved progress.
//!
//! Text never contradicts the code: a step's text may quote a tunable as `{tunable:KEY}` (its
//! default) and is filled in from `crate::tunables` when the level is read; an unknown key is
//! an error, and a test reads every embedded level.

use crate::composite::Method;
use crate::error::SettingsError;
use crate::tunables;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// The embedded levels, in the order they are taught.
const EMBEDDED: &[&str] = &[
    include_str!("../../../assets/levels/01_rays.json"),
    include_str!("../../../assets/levels/02_sampling.json"),
    include_str!("../../../assets/levels/11_jitter.json"),
    include_str!("../../../assets/levels/09_trilinear.json"),
    include_str!("../../../assets/levels/12_nearest.json"),
    include_str!("../../../assets/levels/03_methods.json"),
    include_str!("../../../assets/levels/04_opacity.json"),
    include_str!("../../../assets/levels/05_first_hit.json"),
    include_str!("../../../assets/levels/06_levoy.json"),
    include_str!("../../../assets/levels/19_value_gradient.json"),
    include_str!("../../../assets/levels/10_light.json"),
    include_str!("../../../assets/levels/16_lights.json"),
    include_str!("../../../assets/levels/07_transfer.json"),
    include_str!("../../../assets/levels/13_clipping.json"),
    include_str!("../../../assets/levels/14_acceleration.json"),
    include_str!("../../../assets/levels/08_preview_render.json"),
    include_str!("../../../assets/levels/15_slow_hardware.json"),
    include_str!("../../../assets/levels/17_ray_density.json"),
    include_str!("../../../assets/levels/18_which_effect.json"),
];

/// What a level's scene holds: only what it teaches.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LevelScene {
    /// `builtin:NAME` or a path.
    pub volume: String,
    /// Whether the live GPU preview is drawn.
    #[serde(default)]
    pub preview: bool,
    /// The virtual camera's pixels across and down (`None`: no virtual camera).
    #[serde(default)]
    pub rays: Option<u32>,
    /// Whether the light's marker sphere is in the scene (levels about a point light or about
    /// depth against geometry).
    #[serde(default)]
    pub light: bool,
    /// The settings panel's sections the level shows (`None`: all of them).
    #[serde(default)]
    pub panel: Option<Vec<Section>>,
    /// A preset (by name) the level starts with instead of its volume's own: a transfer
    /// function that shows every method the level teaches.
    #[serde(default)]
    pub preset: Option<String>,
    /// The virtual camera shoots the lecture's worked ray ([`crate::worked::lecture_ray`]: one
    /// pixel, its eye at P3 looking towards P1) under the settings that put one sample on each
    /// point ([`crate::worked::lecture_ray_settings`]).
    #[serde(default)]
    pub lecture_ray: bool,
    /// The preview resolution the level starts at (a level about it starts from a known one);
    /// `None` keeps the player's.
    #[serde(default)]
    pub preview_scale: Option<f32>,
}

/// A section of the settings panel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Section {
    Dataset,
    RayCasting,
    SpeedAccuracy,
    ShadingAndLight,
    TransferFunction,
    VirtualCamera,
    Preview,
    LookingInside,
    RayData,
}

/// A panel control a step is about (highlighted while the step is shown).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Control {
    Method,
    Step,
    VirtualPixels,
    PixelGrid,
    Breakdown,
    OpacityCorrection,
    EarlyTermination,
    Target,
    SumRange,
    Shading,
    Classification,
    TransferFunction,
    RenderImage,
    Light,
    Order,
    StepTrade,
    Jitter,
    Interpolation,
    Supersampling,
    CropBox,
    ClipPlane,
    Skipping,
    PreviewScale,
    PreviewOn,
    /// The Ray data section's source, trace and Compute.
    RaySource,
    /// The Ray data section's views (volume, ray mesh, vector field).
    RayViews,
}

impl Control {
    /// The panel section holding the control (`None`: it is in a window of its own).
    pub fn section(self) -> Option<Section> {
        match self {
            Control::Method
            | Control::Step
            | Control::OpacityCorrection
            | Control::EarlyTermination
            | Control::Target
            | Control::SumRange
            | Control::Order
            | Control::Jitter
            | Control::Interpolation
            | Control::Supersampling
            | Control::Skipping => Some(Section::RayCasting),
            Control::VirtualPixels => Some(Section::VirtualCamera),
            Control::Shading | Control::Light => Some(Section::ShadingAndLight),
            Control::Classification | Control::TransferFunction => Some(Section::TransferFunction),
            Control::StepTrade => Some(Section::SpeedAccuracy),
            Control::CropBox | Control::ClipPlane => Some(Section::LookingInside),
            Control::PreviewScale | Control::PreviewOn => Some(Section::Preview),
            Control::RaySource | Control::RayViews => Some(Section::RayData),
            Control::PixelGrid | Control::Breakdown | Control::RenderImage => None,
        }
    }
}

/// What the player must do to go on.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Objective {
    /// Only reading: Next is open at once.
    Read,
    /// Select any ray (a pixel of the virtual camera's image).
    SelectRay,
    /// Set the virtual camera to at least this many pixels across.
    VirtualPixelsAtLeast { pixels: u32 },
    /// Set the step to at most this many voxels.
    StepAtMost { voxels: f32 },
    /// Set the step to at least this many voxels.
    StepAtLeast { voxels: f32 },
    /// Turn jitter on or off.
    Jitter { on: bool },
    /// Turn trilinear interpolation on (else: nearest).
    Interpolation { trilinear: bool },
    /// Cast at least `rays` × `rays` rays a pixel.
    SupersamplingAtLeast { rays: u32 },
    /// Choose this compositing method.
    Method { method: Method },
    /// Open the sample with the highest value on the selected ray.
    OpenHighestSample,
    /// Turn early ray termination on or off.
    EarlyTermination { on: bool },
    /// Turn opacity correction on or off.
    OpacityCorrection { on: bool },
    /// Turn shading on or off.
    Shading { on: bool },
    /// Set First's target value within `[lo, hi]` (data units).
    TargetBetween { lo: f32, hi: f32 },
    /// Choose a classification: `table`, `iso-contours` or `boundaries`.
    Classification { mode: String },
    /// Make the transfer function's opacity at `value` at most `alpha`.
    TfAlphaAtMost { value: f32, alpha: f32 },
    /// Make the transfer function's colour at `value` within `tolerance` (per channel) of
    /// `color`, with opacity at least `alpha`.
    TfColorNear {
        value: f32,
        color: [f32; 3],
        tolerance: f32,
        alpha: f32,
    },
    /// Render the view on the CPU and compare: largest difference at most `max` (/255).
    Compared { max: f32 },
    /// Put the point light inside the volume's box.
    LightInsideVolume,
    /// Predict the interpolated value at `point` (voxel coordinates) to within `tolerance`.
    PredictValue { point: [f32; 3], tolerance: f32 },
    /// The player types the red component of the ray's colour after the last of `points`,
    /// composited back to front as the lecture's worked example does
    /// (`crate::worked::back_to_front`), within `tolerance`.
    PredictComposite {
        points: Vec<[f32; 3]>,
        tolerance: f32,
    },
    /// Composite back to front (`true`) or front to back.
    BackToFront { on: bool },
    /// Have a light of this kind: `headlight`, `point` or `directional`.
    LightKind { light: String },
    /// Give a point light a falloff with distance (kl or kq above zero).
    Attenuated,
    /// Have at least `count` lights.
    LightsAtLeast { count: usize },
    /// Have at least `count` lights of distinct colours (no channel within 0.1 of each other's).
    DistinctLightColours { count: usize },
    /// Open, in the selected ray's breakdown, a shaded sample lit by at least `lights` lights.
    OpenLitSample { lights: usize },
    /// Choose the highlight's colour: Levoy's (the sample's colour, `true`) or white.
    LevoyHighlight { on: bool },
    /// Shade with the lecture's full illumination model: emission above zero, a spot light
    /// with an ambient share of its own, and an ambient coefficient above zero (without which
    /// every ambient term is zero).
    FullModel,
    /// Turn Levoy's depth cue on or off.
    DepthCue { on: bool },
    /// Draw a value-and-gradient rectangle (with some opacity) around `value` at the lowest
    /// gradients, reaching no higher than `max_gradient`.
    RegionAround { value: f32, max_gradient: f32 },
    /// Show the live preview as the cost view `view` (`samples`, `skipped`, `stops`).
    PreviewCostView { view: String },
    /// Show or hide the skip blocks the virtual camera's rays crossed.
    SkipBlocks { on: bool },
    /// Measure the step size's trade for the view on screen.
    TradeMeasured,
    /// Turn the clip plane on or off.
    ClipPlane { on: bool },
    /// Put the clip plane (on) at a position within `[lo, hi]`.
    ClipPositionBetween { lo: f32, hi: f32 },
    /// Crop the box to at most `fraction` of the volume's extent along some axis.
    CropAtMost { fraction: f32 },
    /// Select a ray whose sampled part the crop box or clip plane shortened.
    SelectCutRay,
    /// Turn empty-space skipping on or off.
    Skipping { on: bool },
    /// Show Render image's render as the cost view `view` (`samples`, `skipped`, `stops`),
    /// rendered with the settings on screen.
    CostViewed { view: String },
    /// Set the preview's resolution to at most `scale`.
    PreviewScaleAtMost { scale: f32 },
    /// Set the preview's resolution to at least `scale`.
    PreviewScaleAtLeast { scale: f32 },
    /// Turn the preview on or off.
    Preview { on: bool },
    /// Measure the trade of the knob named `knob` (`crate::knob::Knob::name`) for the view on
    /// screen.
    KnobMeasured { knob: String },
    /// Show a ray density computed from `source` (`camera`: the virtual camera's rays; else a
    /// ray data source such as `builtin:cornell`), of trace `trace` when given, from at least
    /// `side_at_least` rays across (the virtual camera's).
    RayDensity {
        source: String,
        #[serde(default)]
        trace: Option<u32>,
        #[serde(default)]
        side_at_least: u32,
    },
    /// Show or hide a view of the ray density: `volume`, `mesh` or `field`.
    RayView { view: String, on: bool },
    /// Tell which effect (its trace id, `crate::rays::effects::Effect::id`) cast the rays on
    /// show.
    NameEffect { trace: u32 },
    /// Answer one of RayVis's study questions about a trace of the Cornell box
    /// ([`crate::rays::study::Question`]: `camera`, `hits`, `density-high` or `density-low`),
    /// checked against what the code finds in the trace.
    StudyQuestion { trace: u32, question: String },
}

/// What a ray density on show was computed from, as the objectives see it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RayDensityFacts {
    /// `camera`, or the ray data source.
    pub source: String,
    pub trace: Option<u32>,
    /// The virtual camera's rays across (0 for other sources).
    pub side: u32,
}

/// One step of a level.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Step {
    pub text: String,
    #[serde(default)]
    pub control: Option<Control>,
    pub objective: Objective,
}

/// A level: an id (its progress key), a title, the concept it teaches, its scene and steps.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Level {
    pub id: String,
    pub title: String,
    pub concept: String,
    pub scene: LevelScene,
    pub steps: Vec<Step>,
}

/// The state an objective is checked against, as the sandbox sees it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Situation {
    pub method: Option<Method>,
    /// The step in voxels.
    pub step_voxels: f32,
    /// The virtual camera's pixels across (its image's width; 0 without one).
    pub virtual_pixels_across: u32,
    pub ray_selected: bool,
    /// Values of the selected ray's samples, and the index of the opened one.
    pub ray_values: Vec<f32>,
    pub opened_sample: Option<usize>,
    pub early_termination: bool,
    pub opacity_correction: bool,
    pub shading: bool,
    pub target: Option<f32>,
    /// `table`, `iso-contours`, `boundaries` or `value-gradient`.
    pub classification: &'static str,
    /// The value-and-gradient rectangles, when that classification is chosen.
    pub regions: Vec<crate::classify::Region>,
    pub transfer: Option<crate::transfer::TransferFunction>,
    /// The largest preview/render difference of the last comparison (/255), if current.
    pub compared_max: Option<f32>,
    pub light_inside_volume: bool,
    /// The value the player typed and the true one (the value at the step's point, or the
    /// worked composite's red component).
    pub prediction: Option<(f32, f32)>,
    pub back_to_front: bool,
    /// Each light's kind: `headlight`, `point`, `directional` or `spot`.
    pub light_kinds: Vec<&'static str>,
    /// Some spot light has an ambient share of its own.
    pub spot_ambient: bool,
    /// The emission coefficient ke.
    pub emission: f32,
    /// The ambient coefficient ka (the lights' ambient terms are I_a·ka·c).
    pub ka: f32,
    /// Levoy's depth cue is on.
    pub depth_cue: bool,
    /// Each light's colour.
    pub light_colors: Vec<[f32; 3]>,
    /// Some point light has kl or kq above zero.
    pub attenuated: bool,
    /// The highlight takes the sample's colour (Levoy).
    pub levoy_highlight: bool,
    /// How many lights shaded the opened sample (`None`: none opened, or it was not shaded).
    pub opened_sample_lights: Option<usize>,
    /// A step-trade measurement matches the view and settings on screen.
    pub trade_measured: bool,
    pub jitter: bool,
    /// Trilinear interpolation (else nearest).
    pub trilinear: bool,
    /// Rays per pixel side.
    pub supersampling: u32,
    /// The crop box and clip plane.
    pub clip: crate::clip::Clip,
    /// The selected ray's sampled part was shortened by the cut.
    pub ray_cut: bool,
    pub skipping: bool,
    /// The cost view Render image shows of a render of what is on screen, if any.
    pub cost_view: Option<&'static str>,
    pub preview_on: bool,
    pub preview_scale: f32,
    /// The cost view the live preview shows, if any.
    pub preview_cost_view: Option<&'static str>,
    /// The skip blocks the virtual camera's rays crossed are drawn.
    pub skip_blocks_shown: bool,
    /// The knob of a trade measured for what is on screen, if any.
    pub measured_knob: Option<&'static str>,
    /// The ray density on show, if any.
    pub ray_density: Option<RayDensityFacts>,
    /// The ray density's views shown (`volume`, `mesh`, `field`).
    pub ray_views: Vec<&'static str>,
    /// The effect (trace id) the player named.
    pub named_effect: Option<u32>,
    /// The study question answered right this step: its trace and question key.
    pub studied: Option<(u32, String)>,
}

impl Objective {
    /// Whether `s` meets the objective.
    pub fn met(&self, s: &Situation) -> bool {
        match self {
            Objective::Read => true,
            Objective::SelectRay => s.ray_selected,
            Objective::VirtualPixelsAtLeast { pixels } => s.virtual_pixels_across >= *pixels,
            // A slider lands on 0.25 as 0.2500001: a thousandth of a voxel is allowed.
            Objective::StepAtMost { voxels } => s.step_voxels <= voxels + 1e-3,
            Objective::StepAtLeast { voxels } => s.step_voxels >= voxels - 1e-3,
            Objective::Jitter { on } => s.jitter == *on,
            Objective::Interpolation { trilinear } => s.trilinear == *trilinear,
            Objective::SupersamplingAtLeast { rays } => s.supersampling >= *rays,
            Objective::Method { method } => s.method == Some(*method),
            Objective::OpenHighestSample => {
                let highest = s
                    .ray_values
                    .iter()
                    .copied()
                    .fold(f32::NEG_INFINITY, f32::max);
                s.opened_sample
                    .and_then(|k| s.ray_values.get(k))
                    .is_some_and(|v| *v == highest)
            }
            Objective::EarlyTermination { on } => s.early_termination == *on,
            Objective::OpacityCorrection { on } => s.opacity_correction == *on,
            Objective::Shading { on } => s.shading == *on,
            Objective::TargetBetween { lo, hi } => s.target.is_some_and(|t| t >= *lo && t <= *hi),
            Objective::Classification { mode } => s.classification == mode,
            Objective::TfAlphaAtMost { value, alpha } => s
                .transfer
                .as_ref()
                .is_some_and(|t| t.evaluate(*value).w <= *alpha),
            Objective::TfColorNear {
                value,
                color,
                tolerance,
                alpha,
            } => s.transfer.as_ref().is_some_and(|t| {
                let c = t.evaluate(*value);
                c.w >= *alpha && (0..3).all(|i| (c[i] - color[i]).abs() <= *tolerance)
            }),
            Objective::Compared { max } => s.compared_max.is_some_and(|m| m <= *max),
            Objective::LightInsideVolume => s.light_inside_volume,
            Objective::PredictValue { tolerance, .. }
            | Objective::PredictComposite { tolerance, .. } => s
                .prediction
                .is_some_and(|(typed, truth)| (typed - truth).abs() <= *tolerance),
            Objective::BackToFront { on } => s.back_to_front == *on,
            Objective::LightKind { light } => s.light_kinds.contains(&light.as_str()),
            Objective::Attenuated => s.attenuated,
            Objective::LightsAtLeast { count } => s.light_kinds.len() >= *count,
            Objective::DistinctLightColours { count } => {
                distinct_colours(&s.light_colors) >= *count
            }
            Objective::OpenLitSample { lights } => {
                s.opened_sample_lights.is_some_and(|n| n >= *lights)
            }
            Objective::LevoyHighlight { on } => s.levoy_highlight == *on,
            Objective::FullModel => s.emission > 0.0 && s.spot_ambient && s.ka > 0.0,
            Objective::DepthCue { on } => s.depth_cue == *on,
            Objective::RegionAround {
                value,
                max_gradient,
            } => s.regions.iter().any(|r| {
                r.contains(*value, 0.0) && r.gradient[1] <= *max_gradient && r.opacity > 0.0
            }),
            Objective::PreviewCostView { view } => s.preview_cost_view == Some(view.as_str()),
            Objective::SkipBlocks { on } => s.skip_blocks_shown == *on,
            Objective::TradeMeasured => s.trade_measured,
            Objective::ClipPlane { on } => s.clip.plane.is_some() == *on,
            Objective::ClipPositionBetween { lo, hi } => s
                .clip
                .plane
                .is_some_and(|p| p.position >= *lo && p.position <= *hi),
            Objective::CropAtMost { fraction } => {
                let kept = s.clip.crop_hi - s.clip.crop_lo;
                kept.min_element() <= fraction + 1e-3
            }
            Objective::SelectCutRay => s.ray_selected && s.ray_cut,
            Objective::Skipping { on } => s.skipping == *on,
            Objective::CostViewed { view } => s.cost_view == Some(view.as_str()),
            // A slider lands on 0.5 as 0.50000006: a thousandth is allowed.
            Objective::PreviewScaleAtMost { scale } => s.preview_scale <= scale + 1e-3,
            Objective::PreviewScaleAtLeast { scale } => s.preview_scale >= scale - 1e-3,
            Objective::Preview { on } => s.preview_on == *on,
            Objective::KnobMeasured { knob } => s.measured_knob == Some(knob.as_str()),
            Objective::RayDensity {
                source,
                trace,
                side_at_least,
            } => s.ray_density.as_ref().is_some_and(|f| {
                f.source == *source
                    && f.side >= *side_at_least
                    && trace.is_none_or(|t| f.trace == Some(t))
            }),
            Objective::RayView { view, on } => s.ray_views.contains(&view.as_str()) == *on,
            Objective::StudyQuestion { trace, question } => {
                s.studied.as_ref() == Some(&(*trace, question.clone()))
            }
            Objective::NameEffect { trace } => s
                .named_effect
                .is_some_and(|named| crate::rays::effects::Effect::same_kind(named, *trace)),
        }
    }
}

/// How many of `colors` differ from every other one by more than 0.1 in some channel (greedy:
/// each colour counts if it is distinct from those already counted).
pub fn distinct_colours(colors: &[[f32; 3]]) -> usize {
    let mut kept: Vec<[f32; 3]> = Vec::new();
    for c in colors {
        let new = kept
            .iter()
            .all(|k| (0..3).any(|i| (k[i] - c[i]).abs() > 0.1));
        if new {
            kept.push(*c);
        }
    }
    kept.len()
}

/// The name [`Objective::Classification`] uses for `c`.
pub fn classification_mode(c: &crate::classify::Classification) -> &'static str {
    match c {
        crate::classify::Classification::Table => "table",
        crate::classify::Classification::IsoContours { .. } => "iso-contours",
        crate::classify::Classification::Boundaries { .. } => "boundaries",
        crate::classify::Classification::ValueGradient { .. } => "value-gradient",
    }
}

/// `{tunable:KEY}` replaced by that tunable's default (as the code has it).
fn fill_in(text: &str) -> Result<String, SettingsError> {
    let mut out = String::new();
    let mut rest = text;
    while let Some(start) = rest.find("{tunable:") {
        out.push_str(&rest[..start]);
        let after = &rest[start + "{tunable:".len()..];
        let end = after.find('}').ok_or_else(|| {
            SettingsError::Invalid(format!("unclosed {{tunable:…}} in level text: {text}"))
        })?;
        let key = &after[..end];
        let t = tunables::ALL
            .iter()
            .find(|t| t.key == key)
            .ok_or_else(|| SettingsError::Invalid(format!("no tunable '{key}' (level text)")))?;
        out.push_str(&t.default.to_string());
        rest = &after[end + 1..];
    }
    out.push_str(rest);
    Ok(out)
}

impl Level {
    /// Reads a level's JSON, fills in quoted tunables and checks it has steps.
    pub fn from_json(text: &str) -> Result<Self, SettingsError> {
        let mut level: Level = serde_json::from_str(text)
            .map_err(|e| SettingsError::Invalid(format!("level: {e}")))?;
        if level.steps.is_empty() {
            return Err(SettingsError::Invalid(format!(
                "level {}: no steps",
                level.id
            )));
        }
        for step in &mut level.steps {
            step.text = fill_in(&step.text)?;
        }
        Ok(level)
    }

    /// The embedded levels, in teaching order.
    pub fn all() -> Vec<Level> {
        EMBEDDED
            .iter()
            .map(|text| Level::from_json(text).expect("embedded levels are valid (tested)"))
            .collect()
    }
}

/// Steps completed per level id, and the answers given, for the player and their teacher.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Progress {
    pub completed: BTreeMap<String, usize>,
    /// Every answer given, oldest first (kept from the first version that records them; older
    /// progress has none).
    #[serde(default)]
    pub answers: Vec<Answer>,
}

/// Where the player's progress is kept on a desktop: `$VOXCAST_CONFIG_DIR/progress.json`,
/// else `$XDG_CONFIG_HOME/voxcast/progress.json`, else `~/.config/voxcast/progress.json`;
/// `None` where none of these is set.
pub fn players_progress_path() -> Option<std::path::PathBuf> {
    use std::path::PathBuf;
    std::env::var_os("VOXCAST_CONFIG_DIR")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("XDG_CONFIG_HOME").map(|d| PathBuf::from(d).join("voxcast")))
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".config/voxcast")))
        .map(|dir| dir.join("progress.json"))
}

/// One answer to a level's question: a prediction when the step was done, or an effect named.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Answer {
    /// The level's id and the step, from 1.
    pub level: String,
    pub step: usize,
    /// What was asked, in words ("value at (0.5, 0.5, 0.5)", "which effect").
    pub question: String,
    /// What the player gave, and what the code computes.
    pub answer: String,
    pub expected: String,
    pub correct: bool,
    /// When, in seconds since 1970-01-01 UTC.
    pub at: u64,
    /// In a study, which run ([`StudyRun::words`]); `None` outside one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub run: Option<String>,
}

/// The runs of a study: a level played twice, first with the preview off, then with it on,
/// as the educational ray caster's user study compared them (Virtual Ray Tracer's thesis).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StudyRun {
    PreviewOff,
    PreviewOn,
}

impl StudyRun {
    /// The run's words, as the answers keep them.
    pub fn words(self) -> &'static str {
        match self {
            StudyRun::PreviewOff => "preview off",
            StudyRun::PreviewOn => "preview on",
        }
    }

    /// Whether the preview is drawn in this run.
    pub fn preview(self) -> bool {
        self == StudyRun::PreviewOn
    }

    /// The run after this one, if any.
    pub fn next(self) -> Option<Self> {
        match self {
            StudyRun::PreviewOff => Some(StudyRun::PreviewOn),
            StudyRun::PreviewOn => None,
        }
    }

    /// Which of the two it is, from 1.
    pub fn number(self) -> usize {
        match self {
            StudyRun::PreviewOff => 1,
            StudyRun::PreviewOn => 2,
        }
    }
}

impl Answer {
    /// The answer given now.
    pub fn now(
        level: &str,
        step: usize,
        question: String,
        (answer, expected, correct): (String, String, bool),
    ) -> Self {
        let at = web_time::SystemTime::now()
            .duration_since(web_time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        Self {
            level: level.to_string(),
            step,
            question,
            answer,
            expected,
            correct,
            at,
            run: None,
        }
    }
}

/// `seconds` since 1970-01-01 as an ISO 8601 UTC time, `2026-12-04T09:53:47Z`.
pub fn utc_time(seconds: u64) -> String {
    let (days, rest) = ((seconds / 86_400) as i64, seconds % 86_400);
    // Howard Hinnant's days-to-civil.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1_460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z",
        rest / 3_600,
        rest / 60 % 60,
        rest % 60
    )
}

impl Progress {
    /// Reads progress from `path`. A missing file is a fresh start; a corrupt one too, with a
    /// message saying so (the file is left for the player to inspect, until the next save).
    pub fn load(path: &Path) -> (Self, Option<String>) {
        match std::fs::read_to_string(path) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => (Self::default(), None),
            Err(e) => (
                Self::default(),
                Some(format!(
                    "cannot read {}: {e}; starting afresh",
                    path.display()
                )),
            ),
            Ok(text) => Self::from_text(&text, &path.display().to_string()),
        }
    }

    /// Reads progress from the text kept in `place` (a file, the browser's storage): a damaged
    /// text is a fresh start, with a message that names `place`.
    pub fn from_text(text: &str, place: &str) -> (Self, Option<String>) {
        match Self::parse(text) {
            Ok(p) => (p, None),
            Err(e) => (
                Self::default(),
                Some(format!("{place} is damaged ({e}); starting afresh")),
            ),
        }
    }

    /// The progress in `text`, or what is wrong with it.
    pub fn parse(text: &str) -> Result<Self, String> {
        serde_json::from_str(text).map_err(|e| e.to_string())
    }

    /// The progress as the text [`Progress::from_text`] reads.
    pub fn to_text(&self) -> String {
        serde_json::to_string_pretty(self).expect("progress is plain data")
    }

    /// Writes progress atomically: to a temporary file beside it, then renamed over it.
    pub fn save(&self, path: &Path) -> std::io::Result<()> {
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)?;
        }
        let tmp = path.with_extension("json.tmp");
        std::fs::write(&tmp, self.to_text())?;
        std::fs::rename(&tmp, path)
    }

    /// Records that `steps` steps of level `id` are done (never lowers it).
    pub fn record(&mut self, id: &str, steps: usize) {
        let done = self.completed.entry(id.to_string()).or_default();
        *done = (*done).max(steps);
    }

    /// The answers as CSV, one row an answer in the order given, for a teacher's spreadsheet.
    pub fn answers_csv(&self) -> String {
        let field = |s: &str| {
            if s.contains([',', '"', '\n']) {
                format!("\"{}\"", s.replace('"', "\"\""))
            } else {
                s.to_string()
            }
        };
        let mut out = String::from("level,step,question,answer,expected,correct,time (UTC),run\n");
        for a in &self.answers {
            out += &[
                field(&a.level),
                a.step.to_string(),
                field(&a.question),
                field(&a.answer),
                field(&a.expected),
                if a.correct { "yes" } else { "no" }.to_string(),
                utc_time(a.at),
                a.run.as_deref().unwrap_or("").to_string(),
            ]
            .join(",");
            out.push('\n');
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Answers round-trip through the progress text; progress written before answers were
    /// kept reads with none; the CSV quotes what needs quoting and dates in UTC.
    #[test]
    fn answers_are_kept_and_exported() {
        let (old, message) = Progress::from_text(r#"{"completed": {"rays": 2}}"#, "old");
        assert_eq!(message, None);
        assert_eq!(old.completed["rays"], 2);
        assert!(old.answers.is_empty());
        let mut p = old;
        p.answers.push(Answer {
            level: "trilinear".into(),
            step: 2,
            question: "value at (0.5, 0.5, 0.5)".into(),
            answer: "4.99".into(),
            expected: "4.9875".into(),
            correct: true,
            at: 1_796_464_427,
            run: None,
        });
        p.answers.push(Answer {
            question: "which effect: \"trace 4\"".into(),
            answer: "reflection rays".into(),
            expected: "shadow rays".into(),
            correct: false,
            run: Some(StudyRun::PreviewOn.words().into()),
            ..p.answers[0].clone()
        });
        let (back, _) = Progress::from_text(&p.to_text(), "here");
        assert_eq!(back, p);
        let csv = p.answers_csv();
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(
            lines,
            [
                "level,step,question,answer,expected,correct,time (UTC),run",
                "trilinear,2,\"value at (0.5, 0.5, 0.5)\",4.99,4.9875,yes,2026-12-05T09:53:47Z,",
                "trilinear,2,\"which effect: \"\"trace 4\"\"\",reflection rays,shadow rays,no,\
                 2026-12-05T09:53:47Z,preview on",
            ]
        );
        for (seconds, iso) in [
            (0, "1970-01-01T00:00:00Z"),
            (951_782_400, "2000-02-29T00:00:00Z"),
            (4_107_542_399, "2100-02-28T23:59:59Z"),
        ] {
            assert_eq!(utc_time(seconds), iso);
        }
        let now = Answer::now("x", 1, "q".into(), ("a".into(), "b".into(), true));
        assert!(now.at > 1_700_000_000, "{}", now.at);
    }

    #[test]
    fn every_embedded_level_reads_and_quotes_only_real_tunables() {
        let levels = Level::all();
        assert_eq!(levels.len(), EMBEDDED.len());
        let mut ids = std::collections::HashSet::new();
        for l in &levels {
            assert!(ids.insert(l.id.clone()), "duplicate level id {}", l.id);
            for s in &l.steps {
                assert!(!s.text.contains("{tunable:"), "{}: {}", l.id, s.text);
            }
            assert!(
                crate::builtin::load_source(&l.scene.volume).is_ok(),
                "{}: volume {}",
                l.id,
                l.scene.volume
            );
        }
    }

    /// The first-hit level quotes the head phantom's levels, and its isovalue objective lies
    /// between the scalp's and the bone's (where the skull appears; tested in closed_forms).
    #[test]
    fn the_skull_level_matches_the_phantom() {
        use crate::builtin::{HEAD_BONE, HEAD_BRAIN, HEAD_SKIN};
        let level = Level::all()
            .into_iter()
            .find(|l| l.id == "first-hit")
            .unwrap();
        assert_eq!(level.scene.volume, "builtin:head");
        let text: String = level.steps.iter().map(|s| s.text.as_str()).collect();
        for v in [HEAD_SKIN, HEAD_BRAIN, HEAD_BONE] {
            assert!(text.contains(&format!("{v}")), "the text quotes {v}");
        }
        let (lo, hi) = level
            .steps
            .iter()
            .find_map(|s| match s.objective {
                Objective::TargetBetween { lo, hi } => Some((lo, hi)),
                _ => None,
            })
            .unwrap();
        assert!(HEAD_SKIN < lo && hi < HEAD_BONE);
        // The preset starts below the scalp: the skin shows until the player acts.
        let p = crate::preset::for_volume("head").unwrap();
        let s = p
            .settings_over(&crate::settings::RenderSettings::default())
            .unwrap();
        assert!(s.target.unwrap() < HEAD_SKIN);
    }

    #[test]
    fn light_objectives_count_lights_colours_and_the_opened_sample() {
        let white = [1.0, 1.0, 1.0];
        assert_eq!(distinct_colours(&[white, white]), 1);
        assert_eq!(
            distinct_colours(&[white, [0.95, 1.0, 0.92]]),
            1,
            "too close to tell"
        );
        assert_eq!(
            distinct_colours(&[white, [1.0, 0.4, 0.3], [0.3, 0.5, 1.0]]),
            3
        );
        let mut s = Situation {
            light_kinds: vec!["headlight", "directional"],
            light_colors: vec![white, white],
            ..Situation::default()
        };
        assert!(Objective::LightsAtLeast { count: 2 }.met(&s));
        assert!(!Objective::LightsAtLeast { count: 3 }.met(&s));
        assert!(
            Objective::LightKind {
                light: "directional".into()
            }
            .met(&s)
        );
        assert!(!Objective::DistinctLightColours { count: 2 }.met(&s));
        s.light_colors[1] = [0.3, 0.5, 1.0];
        assert!(Objective::DistinctLightColours { count: 2 }.met(&s));
        assert!(!Objective::OpenLitSample { lights: 2 }.met(&s));
        s.opened_sample_lights = Some(1);
        assert!(!Objective::OpenLitSample { lights: 2 }.met(&s));
        s.opened_sample_lights = Some(2);
        assert!(Objective::OpenLitSample { lights: 2 }.met(&s));
        assert!(!Objective::LevoyHighlight { on: true }.met(&s));
        s.levoy_highlight = true;
        assert!(Objective::LevoyHighlight { on: true }.met(&s));
        // The full model asks for both emission and a spot with its own ambient.
        s.emission = 0.1;
        assert!(!Objective::FullModel.met(&s));
        s.spot_ambient = true;
        assert!(
            !Objective::FullModel.met(&s),
            "ka = 0: no ambient term shows"
        );
        s.ka = 0.2;
        assert!(Objective::FullModel.met(&s));
        s.emission = 0.0;
        assert!(!Objective::FullModel.met(&s));
        assert!(Objective::DepthCue { on: false }.met(&s));
        s.depth_cue = true;
        assert!(Objective::DepthCue { on: true }.met(&s));
        let around = Objective::RegionAround {
            value: 110.0,
            max_gradient: 40.0,
        };
        let r = crate::classify::Region {
            value: [100.0, 120.0],
            gradient: [0.0, 30.0],
            opacity: 0.8,
        };
        assert!(!around.met(&s));
        s.regions = vec![r];
        assert!(around.met(&s));
        for off in [
            crate::classify::Region {
                gradient: [0.0, 60.0],
                ..r
            },
            crate::classify::Region {
                gradient: [5.0, 30.0],
                ..r
            },
            crate::classify::Region {
                value: [111.0, 130.0],
                ..r
            },
            crate::classify::Region { opacity: 0.0, ..r },
        ] {
            s.regions = vec![off];
            assert!(!around.met(&s), "{off:?}");
        }
    }

    #[test]
    fn cost_objectives_read_the_preview_and_the_blocks() {
        let mut s = Situation::default();
        let samples = Objective::PreviewCostView {
            view: "samples".into(),
        };
        assert!(!samples.met(&s));
        s.preview_cost_view = Some("stops");
        assert!(!samples.met(&s));
        s.preview_cost_view = Some("samples");
        assert!(samples.met(&s));
        assert!(!Objective::SkipBlocks { on: true }.met(&s));
        s.skip_blocks_shown = true;
        assert!(Objective::SkipBlocks { on: true }.met(&s));
    }

    /// Every number an objective checks is quoted in its step's text, so the text never asks
    /// for something other than what Next waits for (the first-hit step once said "past 80"
    /// while its objective wanted 120 to 200).
    #[test]
    fn every_steps_text_quotes_its_objectives_numbers() {
        let mut missing = Vec::new();
        for level in Level::all() {
            for (k, step) in level.steps.iter().enumerate() {
                let numbers: Vec<f32> = match &step.objective {
                    Objective::VirtualPixelsAtLeast { pixels } => vec![*pixels as f32],
                    Objective::StepAtMost { voxels } | Objective::StepAtLeast { voxels } => {
                        vec![*voxels]
                    }
                    Objective::TargetBetween { lo, hi } => vec![*lo, *hi],
                    Objective::TfAlphaAtMost { value, alpha } => vec![*value, *alpha],
                    Objective::TfColorNear { value, alpha, .. } => vec![*value, *alpha],
                    Objective::Compared { max } => vec![*max],
                    Objective::SupersamplingAtLeast { rays } => vec![*rays as f32],
                    Objective::LightsAtLeast { count }
                    | Objective::DistinctLightColours { count } => vec![*count as f32],
                    Objective::OpenLitSample { lights } => vec![*lights as f32],
                    Objective::ClipPositionBetween { lo, hi } => vec![*lo, *hi],
                    Objective::CropAtMost { fraction } => vec![*fraction],
                    Objective::PreviewScaleAtMost { scale }
                    | Objective::PreviewScaleAtLeast { scale } => vec![*scale],
                    Objective::PredictValue { point, tolerance } => {
                        point.iter().copied().chain([*tolerance]).collect()
                    }
                    Objective::PredictComposite { points, tolerance } => points
                        .iter()
                        .flatten()
                        .copied()
                        .chain([*tolerance])
                        .collect(),
                    _ => vec![],
                };
                for v in numbers {
                    if !step.text.contains(&format!("{v}")) {
                        missing.push(format!("{} step {}: {v}", level.id, k + 1));
                    }
                }
            }
        }
        assert!(missing.is_empty(), "not quoted: {missing:?}");
    }

    /// The sampling level quotes the steps and the reference the trade measures.
    #[test]
    fn the_sampling_level_quotes_the_trades_steps() {
        let level = Level::all()
            .into_iter()
            .find(|l| l.id == "sampling")
            .unwrap();
        let step = level
            .steps
            .iter()
            .find(|s| s.objective == Objective::TradeMeasured)
            .unwrap();
        for v in crate::trade::STEPS {
            assert!(step.text.contains(&format!("{v}")), "{v}");
        }
        assert_eq!(crate::trade::REFERENCE, 1.0 / 16.0);
        assert!(step.text.contains("1/16 voxel"));
        // The grid it names is the one it loads.
        let v = crate::builtin::load_source(&level.scene.volume)
            .unwrap()
            .volume;
        let d = v.dims();
        assert!(
            level.steps[0]
                .text
                .contains(&format!("{}×{}×{}", d.x, d.y, d.z))
        );
    }

    #[test]
    fn quoted_tunables_are_filled_in_and_unknown_ones_refused() {
        let t = fill_in("the step is {tunable:step} voxel").unwrap();
        assert_eq!(t, format!("the step is {} voxel", tunables::STEP.default));
        assert!(fill_in("{tunable:nonsense}").is_err());
        assert!(fill_in("{tunable:step").is_err());
    }

    #[test]
    fn objectives_check_the_situation() {
        let mut s = Situation {
            step_voxels: 0.5,
            virtual_pixels_across: 4,
            ray_values: vec![1.0, 7.0, 3.0],
            ..Default::default()
        };
        assert!(Objective::Read.met(&s));
        assert!(!Objective::SelectRay.met(&s));
        assert!(!Objective::StepAtMost { voxels: 0.25 }.met(&s));
        s.step_voxels = 0.2500001;
        assert!(Objective::StepAtMost { voxels: 0.25 }.met(&s));
        assert!(!Objective::StepAtLeast { voxels: 2.0 }.met(&s));
        s.step_voxels = 1.9999;
        assert!(
            Objective::StepAtLeast { voxels: 2.0 }.met(&s),
            "a slider's rounding"
        );
        assert!(!Objective::Jitter { on: true }.met(&s));
        s.jitter = true;
        assert!(Objective::Jitter { on: true }.met(&s));
        assert!(Objective::Interpolation { trilinear: false }.met(&s));
        s.trilinear = true;
        assert!(!Objective::Interpolation { trilinear: false }.met(&s));
        assert!(!Objective::SupersamplingAtLeast { rays: 2 }.met(&s));
        s.supersampling = 3;
        assert!(Objective::SupersamplingAtLeast { rays: 2 }.met(&s));
        let between = Objective::ClipPositionBetween { lo: -0.6, hi: -0.2 };
        assert!(Objective::ClipPlane { on: false }.met(&s));
        assert!(!between.met(&s), "no plane: no position");
        s.clip.plane = Some(crate::clip::ClipPlane {
            normal: glam::Vec3::X,
            position: -0.4,
        });
        assert!(Objective::ClipPlane { on: true }.met(&s) && between.met(&s));
        s.clip.plane.as_mut().unwrap().position = 0.0;
        assert!(!between.met(&s));
        let crop = Objective::CropAtMost { fraction: 0.5 };
        assert!(!crop.met(&s));
        s.clip.crop_lo.z = 0.3;
        s.clip.crop_hi.z = 0.8;
        assert!(crop.met(&s));
        s.ray_selected = true;
        assert!(!Objective::SelectCutRay.met(&s));
        s.ray_cut = true;
        assert!(Objective::SelectCutRay.met(&s));
        assert!(Objective::Skipping { on: false }.met(&s));
        let stops = Objective::CostViewed {
            view: "stops".into(),
        };
        assert!(!stops.met(&s));
        s.cost_view = Some("samples");
        assert!(!stops.met(&s));
        s.cost_view = Some("stops");
        assert!(stops.met(&s));
        s.preview_scale = 0.50000006;
        assert!(Objective::PreviewScaleAtMost { scale: 0.5 }.met(&s));
        assert!(!Objective::PreviewScaleAtLeast { scale: 1.0 }.met(&s));
        assert!(Objective::Preview { on: false }.met(&s));
        let measured = Objective::KnobMeasured {
            knob: "preview-scale".into(),
        };
        assert!(!measured.met(&s));
        s.measured_knob = Some("preview-scale");
        assert!(measured.met(&s));
        assert!(!Objective::VirtualPixelsAtLeast { pixels: 8 }.met(&s));
        assert!(
            !Objective::Method {
                method: Method::Maximum
            }
            .met(&s)
        );
        s.method = Some(Method::Maximum);
        assert!(
            Objective::Method {
                method: Method::Maximum
            }
            .met(&s)
        );
        s.opened_sample = Some(2);
        assert!(!Objective::OpenHighestSample.met(&s));
        s.opened_sample = Some(1);
        assert!(Objective::OpenHighestSample.met(&s));
        assert!(Objective::EarlyTermination { on: false }.met(&s));
        assert!(!Objective::Shading { on: true }.met(&s));
        s.target = Some(128.0);
        assert!(
            Objective::TargetBetween {
                lo: 120.0,
                hi: 136.0
            }
            .met(&s)
        );
        assert!(!Objective::TargetBetween { lo: 0.0, hi: 100.0 }.met(&s));
        s.classification = "boundaries";
        assert!(
            Objective::Classification {
                mode: "boundaries".into()
            }
            .met(&s)
        );
    }

    #[test]
    fn ray_data_objectives() {
        let mut s = Situation::default();
        let cornell = |trace| Objective::RayDensity {
            source: "builtin:cornell".into(),
            trace,
            side_at_least: 0,
        };
        let camera = Objective::RayDensity {
            source: "camera".into(),
            trace: None,
            side_at_least: 128,
        };
        assert!(!cornell(None).met(&s) && !camera.met(&s));
        s.ray_density = Some(RayDensityFacts {
            source: "builtin:cornell".into(),
            trace: Some(2),
            side: 0,
        });
        assert!(cornell(None).met(&s) && cornell(Some(2)).met(&s));
        assert!(!cornell(Some(3)).met(&s) && !camera.met(&s));
        s.ray_density = Some(RayDensityFacts {
            source: "camera".into(),
            trace: None,
            side: 64,
        });
        assert!(!camera.met(&s), "too few rays across");
        s.ray_density.as_mut().unwrap().side = 128;
        assert!(camera.met(&s));
        let field = |on| Objective::RayView {
            view: "field".into(),
            on,
        };
        assert!(!field(true).met(&s) && field(false).met(&s));
        s.ray_views = vec!["volume", "field"];
        assert!(field(true).met(&s) && !field(false).met(&s));
        assert!(!Objective::NameEffect { trace: 2 }.met(&s));
        s.named_effect = Some(3);
        assert!(!Objective::NameEffect { trace: 2 }.met(&s));
        s.named_effect = Some(2);
        assert!(Objective::NameEffect { trace: 2 }.met(&s));
        // Either primary trace is "primary rays".
        s.named_effect = Some(0);
        assert!(Objective::NameEffect { trace: 1 }.met(&s));
        assert!(!Objective::NameEffect { trace: 4 }.met(&s));
    }

    /// The names objectives use are real: knobs and cost views.
    #[test]
    fn objectives_name_real_knobs_and_views() {
        for l in Level::all() {
            for step in &l.steps {
                match &step.objective {
                    Objective::KnobMeasured { knob } => {
                        assert!(crate::knob::Knob::parse(knob).is_some(), "{}: {knob}", l.id)
                    }
                    Objective::CostViewed { view } => {
                        assert!(
                            crate::cost::CostView::parse(view).is_some(),
                            "{}: {view}",
                            l.id
                        )
                    }
                    Objective::RayView { view, .. } => {
                        assert!(
                            ["volume", "mesh", "field"].contains(&view.as_str()),
                            "{view}"
                        )
                    }
                    Objective::StudyQuestion { trace, question } => assert!(
                        crate::rays::study::Question::parse(question).is_some()
                            && crate::rays::effects::Effect::of(*trace).is_some(),
                        "{}: {question} of trace {trace}",
                        l.id
                    ),
                    Objective::NameEffect { trace } => assert!(
                        crate::rays::effects::Effect::ALL
                            .iter()
                            .any(|e| e.id() == *trace),
                        "{}: {trace}",
                        l.id
                    ),
                    _ => {}
                }
            }
        }
    }

    /// A level that limits the panel shows every control its steps are about.
    #[test]
    fn a_levels_panel_holds_its_steps_controls() {
        for l in Level::all() {
            let Some(panel) = &l.scene.panel else {
                continue;
            };
            for step in &l.steps {
                if let Some(section) = step.control.and_then(Control::section) {
                    assert!(panel.contains(&section), "{}: {section:?} hidden", l.id);
                }
            }
        }
    }

    #[test]
    fn named_objectives_name_real_modes() {
        for l in Level::all() {
            if let Some(name) = &l.scene.preset {
                assert!(
                    crate::preset::by_name(name).is_some(),
                    "{}: preset {name}",
                    l.id
                );
            }
            for step in &l.steps {
                if let Objective::Classification { mode } = &step.objective {
                    assert!(
                        ["table", "iso-contours", "boundaries", "value-gradient"]
                            .contains(&mode.as_str()),
                        "{}: {mode}",
                        l.id
                    );
                }
                if let Objective::LightKind { light } = &step.objective {
                    assert!(
                        ["headlight", "point", "directional"].contains(&light.as_str()),
                        "{}: {light}",
                        l.id
                    );
                }
            }
        }
    }

    #[test]
    fn progress_survives_a_round_trip_and_a_damaged_file_starts_afresh() {
        let dir = std::env::temp_dir().join(format!("voxcast-progress-{}", std::process::id()));
        let path = dir.join("sub/progress.json");
        let (fresh, note) = Progress::load(&path);
        assert_eq!((fresh, note), (Progress::default(), None));
        let mut p = Progress::default();
        p.record("rays", 3);
        p.record("rays", 1);
        p.save(&path).unwrap();
        assert_eq!(Progress::load(&path).0.completed["rays"], 3);
        std::fs::write(&path, "{ not json").unwrap();
        let (fresh, note) = Progress::load(&path);
        assert_eq!(fresh, Progress::default());
        assert!(note.unwrap().contains("damaged"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
