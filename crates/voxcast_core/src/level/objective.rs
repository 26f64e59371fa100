//! What the player must do to go on ([`Objective`]) and the state it is checked against
//! ([`Situation`], as the sandbox sees it, with the state the step opened in, so an objective can
//! ask for a change — a slider moved, a pixel clicked — and not only for a state that a click
//! made before the step could already have left behind).

use crate::composite::Method;
use serde::{Deserialize, Serialize};

/// What the player must do to go on: its `kind`, and the fields that kind takes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case", tag = "kind", deny_unknown_fields)]
pub enum Objective {
    /// Only reading: Next is open at once.
    Read,
    /// Every objective in `of` at once (an action and the outcome the step's words name, such
    /// as "turn opacity correction off, then move the step slider").
    All { of: Vec<Objective> },
    /// Click a pixel of the virtual camera's image while the step is open (a ray selected
    /// before it opened does not count).
    SelectRay,
    /// Set the virtual camera to at least this many pixels across.
    VirtualPixelsAtLeast { pixels: u32 },
    /// Set the step to at most this many voxels.
    StepAtMost { voxels: f32 },
    /// Set the step to at least this many voxels.
    StepAtLeast { voxels: f32 },
    /// Move the step slider: the step differs from the one the step opened with.
    StepMoved,
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
    /// Choose a classification: `table`, `iso-contours`, `boundaries` or `value-gradient`.
    Classification { mode: String },
    /// Make the transfer function's opacity at `value` at most `alpha`.
    TfAlphaAtMost { value: f32, alpha: f32 },
    /// Make the transfer function binary at `threshold`, as the lecture's first classification
    /// is (0 background, 1 object): opacity at most 0.02 at every value up to `threshold −
    /// within` and at least 0.95 at every value from `threshold + within` up.
    TfBinary { threshold: f32, within: f32 },
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
    /// Put a point light inside the volume's box.
    LightInsideVolume,
    /// Predict the interpolated value at `point` (voxel coordinates) to within `tolerance`.
    PredictValue { point: [f32; 3], tolerance: f32 },
    /// Predict the red component of the ray's colour after the last of `points` (voxel
    /// coordinates), composited back to front from the first as the lecture's worked example
    /// does (one sample a point, the transfer function's colour and opacity at each point's
    /// value), to within `tolerance`.
    PredictComposite {
        points: Vec<[f32; 3]>,
        tolerance: f32,
    },
    /// Predict how many samples the selected ray takes, exactly.
    PredictSamples,
    /// Predict the step (in the breakdown's `t` units) on the selected ray if it were marched
    /// in a fixed number of `steps` instead of at a fixed step — its length in the volume
    /// divided by `steps` — to within `tolerance`.
    PredictFixedCountStep { steps: u32, tolerance: f32 },
    /// Predict how many cells of the lattice the selected ray crosses, exactly (the walk of
    /// `crate::cells`).
    PredictCells,
    /// Composite back to front (`true`) or front to back.
    BackToFront { on: bool },
    /// Have a light of this kind: `headlight`, `point`, `directional` or `spot`.
    LightKind { light: String },
    /// Give a point light a falloff with distance (kl or kq above zero).
    Attenuated,
    /// Move a point or spot light farther from the volume's centre than it stood when the
    /// step opened (by at least a twentieth of the box's diagonal).
    LightMovedAway,
    /// Have one warm light and one cool one: red above blue by at least 0.2 in one, blue
    /// above red by at least 0.2 in another.
    WarmAndCoolLights,
    /// Choose the specular term: `phong` (R·V, the lecture's) or `blinn-phong` (N·H).
    Specular { model: String },
    /// Have at least `count` lights.
    LightsAtLeast { count: usize },
    /// Have at least `count` lights of distinct colours (no channel within 0.1 of each other's).
    DistinctLightColours { count: usize },
    /// Open, in the selected ray's breakdown, a shaded sample that at least `lights` lights
    /// reach: it faces each of them and their falloff and spotlight factor leave something
    /// ([`crate::shade::ShadeTerms::lights_reaching`]).
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
    /// Show the live preview as the cost view `view` (`samples`, `skipped`, `stops`, `depth`,
    /// `depth-of-hits`), or as `picture`: the volume rendered.
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
    /// Click, while the step is open, a ray whose sampled part the crop box or clip plane
    /// shortened.
    SelectCutRay,
    /// Turn empty-space skipping on or off.
    Skipping { on: bool },
    /// Show Render image's render as the cost view `view` (`samples`, `skipped`, `stops`,
    /// `depth`, `depth-of-hits`), rendered with the settings on screen.
    CostViewed { view: String },
    /// Set the preview's resolution to at most `scale`.
    PreviewScaleAtMost { scale: f32 },
    /// Set the preview's resolution to at least `scale`.
    PreviewScaleAtLeast { scale: f32 },
    /// Turn the preview on or off.
    Preview { on: bool },
    /// Measure the trade of the knob `knob` for the view on screen (Speed against accuracy ›
    /// Measure): `step`, `interpolation`, `cutoff`, `jitter`, `supersampling`, `preview-scale`,
    /// `preview-step-multiplier` or `adaptive-quality`.
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
    /// Name the effect that cast trace `trace` of the Cornell box: 0 and 1 primary rays (two
    /// cameras), 2 reflection, 3 ambient occlusion, 4 shadow rays.
    NameEffect { trace: u32 },
    /// Answer one of RayVis's study questions about trace `trace` (0 to 4) of the Cornell box,
    /// checked against what the code finds in the trace: `camera` (where its camera stood),
    /// `hits` (where its hitting rays start), `density-high` or `density-low` (where its
    /// hitting rays crowd, or its missing rays are scarce).
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

/// The state an objective is checked against, as the sandbox sees it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Situation {
    pub method: Option<Method>,
    /// The step in voxels.
    pub step_voxels: f32,
    /// The virtual camera's pixels across (its image's width; 0 without one).
    pub virtual_pixels_across: u32,
    pub ray_selected: bool,
    /// How many pixels of the virtual camera's image the player has clicked (a count that
    /// only grows, so a click while a step is open shows against [`Situation::at_open`]).
    pub ray_clicks: u32,
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
    /// The value the player typed and the true one (the value at the step's point, the worked
    /// composite's red component, or the number asked about the selected ray).
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
    /// Each light's distance from the volume's centre in box diagonals (`None`: a headlight or
    /// a directional light, which stands nowhere).
    pub light_distances: Vec<Option<f32>>,
    /// The specular term: `phong` or `blinn-phong`.
    pub specular: &'static str,
    /// Some point light has kl or kq above zero.
    pub attenuated: bool,
    /// The highlight takes the sample's colour (Levoy).
    pub levoy_highlight: bool,
    /// How many lights reach the opened sample (`None`: none opened, or it was not shaded).
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
    /// The situation when the step opened (its scene set up), for the objectives that ask for
    /// a change; `None` before the step's scene is ready.
    pub at_open: Option<Box<Situation>>,
}

impl Situation {
    /// What the render settings and transfer function alone tell the objectives, for a volume
    /// whose box is `lo..hi` with voxels `voxel` world units apart (the smallest spacing); the
    /// rest (selection, windows, the preview, measurements) starts empty.
    pub fn from_settings(
        settings: &crate::settings::RenderSettings,
        transfer: &crate::transfer::TransferFunction,
        (lo, hi): (glam::Vec3, glam::Vec3),
        voxel: f32,
    ) -> Self {
        use crate::shade::{Highlight, Light};
        let lights = &settings.phong.lights;
        let (centre, diagonal) = ((lo + hi) * 0.5, (hi - lo).length().max(f32::MIN_POSITIVE));
        Situation {
            method: Some(settings.method),
            step_voxels: settings.step.voxels(voxel),
            early_termination: settings.early_termination,
            opacity_correction: settings.opacity_correction,
            shading: settings.shading,
            target: settings.target,
            classification: classification_mode(&settings.classification),
            regions: match &settings.classification {
                crate::classify::Classification::ValueGradient { regions } => regions.clone(),
                _ => Vec::new(),
            },
            transfer: Some(transfer.clone()),
            light_inside_volume: lights.iter().any(
                |l| matches!(l.light, Light::Point(p) if p.cmpge(lo).all() && p.cmple(hi).all()),
            ),
            back_to_front: settings.order == crate::composite::Order::BackToFront,
            light_kinds: lights.iter().map(|l| l.light.kind_label()).collect(),
            spot_ambient: lights
                .iter()
                .any(|l| matches!(l.light, Light::Spot(_)) && l.ambient > 0.0),
            emission: settings.phong.ke,
            ka: settings.phong.ka,
            depth_cue: settings.phong.depth_cue,
            light_colors: lights.iter().map(|l| l.color.to_array()).collect(),
            light_distances: lights
                .iter()
                .map(|l| l.light.position().map(|p| p.distance(centre) / diagonal))
                .collect(),
            specular: settings.phong.model.name(),
            attenuated: lights.iter().any(|l| l.attenuated()),
            levoy_highlight: settings.phong.highlight == Highlight::Levoy,
            jitter: settings.jitter,
            trilinear: settings.interpolation == crate::sample::Interpolation::Trilinear,
            supersampling: settings.supersampling,
            clip: settings.clip.clone(),
            skipping: settings.skipping,
            ..Situation::default()
        }
    }
}

/// One objective of every kind, in the order the format lists them, with the values the
/// docs show: what the editor puts down when a kind is chosen.
const EXAMPLES: &[&str] = &[
    r#"{"kind": "read"}"#,
    r#"{"kind": "all", "of": [{"kind": "opacity-correction", "on": false}, {"kind": "step-moved"}]}"#,
    r#"{"kind": "select-ray"}"#,
    r#"{"kind": "virtual-pixels-at-least", "pixels": 8}"#,
    r#"{"kind": "step-at-most", "voxels": 0.25}"#,
    r#"{"kind": "step-at-least", "voxels": 2.0}"#,
    r#"{"kind": "step-moved"}"#,
    r#"{"kind": "jitter", "on": true}"#,
    r#"{"kind": "interpolation", "trilinear": false}"#,
    r#"{"kind": "supersampling-at-least", "rays": 2}"#,
    r#"{"kind": "method", "method": "maximum"}"#,
    r#"{"kind": "open-highest-sample"}"#,
    r#"{"kind": "early-termination", "on": false}"#,
    r#"{"kind": "opacity-correction", "on": false}"#,
    r#"{"kind": "shading", "on": false}"#,
    r#"{"kind": "target-between", "lo": 120.0, "hi": 200.0}"#,
    r#"{"kind": "classification", "mode": "boundaries"}"#,
    r#"{"kind": "tf-alpha-at-most", "value": 40.0, "alpha": 0.02}"#,
    r#"{"kind": "tf-binary", "threshold": 150.0, "within": 10.0}"#,
    r#"{"kind": "tf-color-near", "value": 140.0, "color": [1, 0, 0], "tolerance": 0.3, "alpha": 0.5}"#,
    r#"{"kind": "compared", "max": 2.0}"#,
    r#"{"kind": "light-inside-volume"}"#,
    r#"{"kind": "predict-value", "point": [0.5, 0.5, 0.5], "tolerance": 0.01}"#,
    r#"{"kind": "predict-composite", "points": [[0.2, 0.3, 0.8], [0.5, 0.5, 0.5]], "tolerance": 0.01}"#,
    r#"{"kind": "predict-samples"}"#,
    r#"{"kind": "predict-fixed-count-step", "steps": 16, "tolerance": 0.01}"#,
    r#"{"kind": "predict-cells"}"#,
    r#"{"kind": "back-to-front", "on": true}"#,
    r#"{"kind": "light-kind", "light": "point"}"#,
    r#"{"kind": "attenuated"}"#,
    r#"{"kind": "light-moved-away"}"#,
    r#"{"kind": "warm-and-cool-lights"}"#,
    r#"{"kind": "specular", "model": "phong"}"#,
    r#"{"kind": "lights-at-least", "count": 2}"#,
    r#"{"kind": "distinct-light-colours", "count": 2}"#,
    r#"{"kind": "open-lit-sample", "lights": 2}"#,
    r#"{"kind": "levoy-highlight", "on": true}"#,
    r#"{"kind": "full-model"}"#,
    r#"{"kind": "depth-cue", "on": true}"#,
    r#"{"kind": "region-around", "value": 110, "max_gradient": 40}"#,
    r#"{"kind": "preview-cost-view", "view": "depth"}"#,
    r#"{"kind": "skip-blocks", "on": true}"#,
    r#"{"kind": "trade-measured"}"#,
    r#"{"kind": "clip-plane", "on": true}"#,
    r#"{"kind": "clip-position-between", "lo": -0.6, "hi": -0.2}"#,
    r#"{"kind": "crop-at-most", "fraction": 0.5}"#,
    r#"{"kind": "select-cut-ray"}"#,
    r#"{"kind": "skipping", "on": true}"#,
    r#"{"kind": "cost-viewed", "view": "stops"}"#,
    r#"{"kind": "preview-scale-at-most", "scale": 0.5}"#,
    r#"{"kind": "preview-scale-at-least", "scale": 1.0}"#,
    r#"{"kind": "preview", "on": false}"#,
    r#"{"kind": "knob-measured", "knob": "preview-scale"}"#,
    r#"{"kind": "ray-density", "source": "builtin:cornell", "trace": 0}"#,
    r#"{"kind": "ray-view", "view": "mesh", "on": true}"#,
    r#"{"kind": "name-effect", "trace": 4}"#,
    r#"{"kind": "study-question", "trace": 1, "question": "camera"}"#,
];

impl Objective {
    /// One objective of every kind ([`EXAMPLES`]).
    pub fn examples() -> Vec<Objective> {
        EXAMPLES
            .iter()
            .map(|text| serde_json::from_str(text).expect("the examples read (tested)"))
            .collect()
    }

    /// The kind's name, as a level file writes it (`step-at-most`).
    pub fn kind(&self) -> String {
        serde_json::to_value(self).expect("an objective is plain data")["kind"]
            .as_str()
            .unwrap_or_default()
            .to_string()
    }

    /// The objectives it is made of: itself, or every part of an [`Objective::All`] (nested
    /// ones flattened), in order.
    pub fn parts(&self) -> Vec<&Objective> {
        match self {
            Objective::All { of } => of.iter().flat_map(Objective::parts).collect(),
            other => vec![other],
        }
    }

    /// For a prediction: how far a try may lie from the code's answer (0 for a count, which
    /// must be the whole number itself); `None` for an objective that asks for none.
    pub fn tolerance(&self) -> Option<f32> {
        match self {
            Objective::PredictValue { tolerance, .. }
            | Objective::PredictComposite { tolerance, .. }
            | Objective::PredictFixedCountStep { tolerance, .. } => Some(*tolerance),
            Objective::PredictSamples | Objective::PredictCells => Some(0.0),
            _ => None,
        }
    }

    /// Whether it asks a number about the selected ray (answered by `super::ray_answer`).
    pub fn asks_about_ray(&self) -> bool {
        matches!(
            self,
            Objective::PredictSamples
                | Objective::PredictCells
                | Objective::PredictFixedCountStep { .. }
        )
    }

    /// Whether `s` meets the objective.
    pub fn met(&self, s: &Situation) -> bool {
        let open = s.at_open.as_deref();
        // A click while the step is open: more clicks than when it opened.
        let clicked = open.is_some_and(|o| s.ray_clicks > o.ray_clicks);
        match self {
            Objective::Read => true,
            Objective::All { of } => of.iter().all(|o| o.met(s)),
            Objective::SelectRay => s.ray_selected && clicked,
            Objective::VirtualPixelsAtLeast { pixels } => s.virtual_pixels_across >= *pixels,
            // A slider lands on 0.25 as 0.2500001: a thousandth of a voxel is allowed.
            Objective::StepAtMost { voxels } => s.step_voxels <= voxels + 1e-3,
            Objective::StepAtLeast { voxels } => s.step_voxels >= voxels - 1e-3,
            Objective::StepMoved => {
                open.is_some_and(|o| (s.step_voxels - o.step_voxels).abs() > 1e-3)
            }
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
            Objective::TfBinary { threshold, within } => s
                .transfer
                .as_ref()
                .is_some_and(|t| is_binary(t, *threshold, *within)),
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
            Objective::PredictValue { .. }
            | Objective::PredictComposite { .. }
            | Objective::PredictFixedCountStep { .. }
            | Objective::PredictSamples
            | Objective::PredictCells => {
                let tolerance = self.tolerance().unwrap_or(0.0);
                s.prediction
                    .is_some_and(|(typed, truth)| (typed - truth).abs() <= tolerance)
            }
            Objective::BackToFront { on } => s.back_to_front == *on,
            Objective::LightKind { light } => s.light_kinds.contains(&light.as_str()),
            Objective::Attenuated => s.attenuated,
            Objective::LightMovedAway => open.is_some_and(|o| {
                s.light_distances
                    .iter()
                    .zip(&o.light_distances)
                    .any(|(now, then)| matches!((now, then), (Some(n), Some(t)) if *n >= t + 0.05))
            }),
            Objective::WarmAndCoolLights => {
                let warm = s.light_colors.iter().any(|c| c[0] - c[2] >= 0.2);
                let cool = s.light_colors.iter().any(|c| c[2] - c[0] >= 0.2);
                warm && cool
            }
            Objective::Specular { model } => s.specular == model,
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
            Objective::PreviewCostView { view } => match s.preview_cost_view {
                Some(shown) => shown == view,
                None => view == "picture",
            },
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
            Objective::SelectCutRay => s.ray_selected && s.ray_cut && clicked,
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

/// Whether `t` is binary at `threshold`: at most 0.02 opaque everywhere up to `threshold −
/// within`, at least 0.95 everywhere from `threshold + within` up, over its points' values
/// (beyond them it holds its end's opacity), checked at every point and 1,024 values between.
pub fn is_binary(t: &crate::transfer::TransferFunction, threshold: f32, within: f32) -> bool {
    let points = t.points();
    let (first, last) = (points[0].value, points[points.len() - 1].value);
    let (lo, hi) = (threshold - within, threshold + within);
    let span = (last - first).max(f32::MIN_POSITIVE);
    let values = points
        .iter()
        .map(|p| p.value)
        .chain((0..=1024).map(|i| first + span * i as f32 / 1024.0))
        .chain([lo, hi]);
    let mut below = false;
    let mut above = false;
    for v in values {
        let a = t.evaluate(v).w;
        if v <= lo {
            below = true;
            if a > 0.02 {
                return false;
            }
        }
        if v >= hi {
            above = true;
            if a < 0.95 {
                return false;
            }
        }
    }
    below && above
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
