//! Tutorial levels as data (`assets/levels/*.json`): what a level's scene holds, its steps'
//! text, the control each step is about, and the objective that unlocks the next step
//! (`objective.rs`: the checks) — plus the player's saved progress (`progress.rs`).
//!
//! Text never contradicts the code: a step's text may quote a tunable as `{tunable:KEY}` (its
//! default) and is filled in from `crate::tunables` when the level is read; an unknown key is
//! an error, and a test reads every embedded level.

pub mod check;
mod file;
pub mod link;
mod objective;
mod progress;
mod ray_answer;
pub mod report;
mod scene;
mod schema;

pub use file::{files_at, shortest_f32s, to_text};
pub use objective::{Objective, RayDensityFacts, Situation, classification_mode, distinct_colours};
pub use progress::{
    Answer, CSV_HEADER, Progress, StudyRun, now_seconds, players_progress_path, utc_time,
};
pub use ray_answer::{RayAnswer, ray_answer};
pub use scene::{CameraPlace, Origin, StepScene, TransferChoice};
pub use schema::{SCHEMA_FILE, schema, schema_text};

use crate::error::SettingsError;
use crate::tunables;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// The embedded levels, in the order they are taught: their files' numbers are that order.
const EMBEDDED: &[&str] = &[
    include_str!("../../../assets/levels/01_rays.json"),
    include_str!("../../../assets/levels/02_sampling.json"),
    include_str!("../../../assets/levels/03_jitter.json"),
    include_str!("../../../assets/levels/04_trilinear.json"),
    include_str!("../../../assets/levels/05_nearest.json"),
    include_str!("../../../assets/levels/06_methods.json"),
    include_str!("../../../assets/levels/07_opacity.json"),
    include_str!("../../../assets/levels/08_first_hit.json"),
    include_str!("../../../assets/levels/09_levoy.json"),
    include_str!("../../../assets/levels/10_value_gradient.json"),
    include_str!("../../../assets/levels/11_light.json"),
    include_str!("../../../assets/levels/12_lights.json"),
    include_str!("../../../assets/levels/13_transfer.json"),
    include_str!("../../../assets/levels/14_binary.json"),
    include_str!("../../../assets/levels/15_clipping.json"),
    include_str!("../../../assets/levels/16_acceleration.json"),
    include_str!("../../../assets/levels/17_preview_render.json"),
    include_str!("../../../assets/levels/18_slow_hardware.json"),
    include_str!("../../../assets/levels/19_ray_density.json"),
    include_str!("../../../assets/levels/20_which_effect.json"),
];

/// What a level's scene holds: only what it teaches. It opens with the data set's own
/// settings and transfer function, then `preset`, `transfer` and `settings` over them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LevelScene {
    /// The data set: `builtin:NAME` (bunny, brainsmall, shells, marschner-lobb, bucky, blobs,
    /// head, voxel, masked), `density:builtin:cornell@trace=N`, or a volume file (NRRD,
    /// NIfTI, raw) beside the level: a relative path on the desktop, a URL on the page.
    pub volume: String,
    /// Whether the live preview is drawn.
    #[serde(default, skip_serializing_if = "is_false")]
    pub preview: bool,
    /// The virtual camera's pixels across and down (absent: no virtual camera).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rays: Option<u32>,
    /// Whether the light's marker sphere is in the scene (levels about a point light or about
    /// depth against geometry).
    #[serde(default, skip_serializing_if = "is_false")]
    pub light: bool,
    /// The settings panel's sections the level shows (absent: all of them).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub panel: Option<Vec<Section>>,
    /// A preset (by name) the level starts with instead of its data set's own: its transfer
    /// function and the settings that suit it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preset: Option<String>,
    /// The transfer function the level starts with (after `preset`): a preset's name, a
    /// `.json` file beside the level, or the function written out.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transfer: Option<TransferChoice>,
    /// Render settings written over the data set's (and `preset`'s), as a preset writes
    /// them: `{"method": "first", "target": 120}`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "Option<serde_json::Map<String, serde_json::Value>>")]
    pub settings: Option<serde_json::Map<String, serde_json::Value>>,
    /// Where the main camera starts (absent: framing the volume from its preset's side).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub camera: Option<CameraPlace>,
    /// Where the virtual camera starts (absent: the sandbox places it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub virtual_camera: Option<CameraPlace>,
    /// The ray selected as the level starts: the virtual camera's pixel (x across, y down).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ray: Option<[u32; 2]>,
    /// The virtual camera shoots the lecture's worked ray ([`crate::worked::lecture_ray`]: one
    /// pixel, its eye at P3 looking towards P1) under the settings that put one sample on each
    /// point ([`crate::worked::lecture_ray_settings`]).
    #[serde(default, skip_serializing_if = "is_false")]
    pub lecture_ray: bool,
    /// The preview resolution the level starts at (a level about it starts from a known one);
    /// absent: the player's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preview_scale: Option<f32>,
}

fn is_false(b: &bool) -> bool {
    !*b
}

impl LevelScene {
    /// `transfer` and `settings` (the data set's own) with the level's preset over them, where
    /// it names one, and the lecture's ray's settings where it shoots that ray: what the level
    /// opens with before its own `transfer` and `settings`.
    pub fn over_defaults(
        &self,
        transfer: &mut crate::transfer::TransferFunction,
        settings: &mut crate::settings::RenderSettings,
    ) {
        if let Some(p) = self.preset.as_deref().and_then(crate::preset::by_name) {
            *transfer = p.transfer.clone();
            if let Ok(s) = p.settings_over(settings) {
                *settings = s;
            }
        }
        if self.lecture_ray {
            *settings = crate::worked::lecture_ray_settings(settings);
        }
    }

    /// The scene a level opens with, as a step's scene: its volume, transfer function,
    /// settings, cameras and ray.
    pub fn snapshot(&self) -> StepScene {
        StepScene {
            volume: Some(self.volume.clone()),
            transfer: self.transfer.clone(),
            settings: self.settings.clone(),
            camera: self.camera,
            virtual_camera: self.virtual_camera,
            ray: self.ray,
        }
    }
}

/// A section of the settings panel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
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

/// A panel control a step is about (framed in yellow while the step is shown).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
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
    /// The Preview section's "Show the preview as": the picture, a cost view or the depth.
    PreviewView,
    /// The Ray data section's source, trace and Compute.
    RaySource,
    /// The Ray data section's views (volume, ray mesh, vector field).
    RayViews,
}

impl Control {
    /// Every control, in the order the format lists them.
    pub const ALL: [Control; 27] = [
        Control::Method,
        Control::Step,
        Control::VirtualPixels,
        Control::PixelGrid,
        Control::Breakdown,
        Control::OpacityCorrection,
        Control::EarlyTermination,
        Control::Target,
        Control::SumRange,
        Control::Shading,
        Control::Classification,
        Control::TransferFunction,
        Control::RenderImage,
        Control::Light,
        Control::Order,
        Control::StepTrade,
        Control::Jitter,
        Control::Interpolation,
        Control::Supersampling,
        Control::CropBox,
        Control::ClipPlane,
        Control::Skipping,
        Control::PreviewScale,
        Control::PreviewOn,
        Control::PreviewView,
        Control::RaySource,
        Control::RayViews,
    ];

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
            Control::PreviewScale | Control::PreviewOn | Control::PreviewView => {
                Some(Section::Preview)
            }
            Control::RaySource | Control::RayViews => Some(Section::RayData),
            Control::PixelGrid | Control::Breakdown | Control::RenderImage => None,
        }
    }
}

/// One step of a level: what it says, the control it frames, what opens Next, and what it
/// puts on screen as it opens.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Step {
    /// What the student reads. `{tunable:KEY}` is replaced by that setting's default.
    pub text: String,
    /// The panel control framed while the step is shown.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub control: Option<Control>,
    /// What opens Next (docs/levels.md: every kind, what it checks).
    pub objective: Objective,
    /// What the step puts on screen as it opens (absent: the scene as the last step left it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene: Option<StepScene>,
}

/// A level: an id (its progress key), a title, the concept it teaches, its scene and steps.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Level {
    /// The JSON Schema an editor checks the file against (docs/levels.schema.json).
    #[serde(rename = "$schema", default, skip_serializing_if = "Option::is_none")]
    pub schema: Option<String>,
    /// A short name, unique among the levels: the key of the students' progress and answers.
    pub id: String,
    /// The title in the levels list.
    pub title: String,
    /// The concept it teaches, in a sentence or two.
    pub concept: String,
    /// What its scene holds as it starts.
    pub scene: LevelScene,
    /// Its steps, at least one.
    pub steps: Vec<Step>,
    /// Where it was read from: the files it names are beside it.
    #[serde(skip)]
    pub origin: Origin,
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
    /// Where a file the level names lies (`builtin:` names as they are).
    pub fn resolve(&self, name: &str) -> String {
        self.origin.resolve(name)
    }

    /// The data set the level starts with, found beside it.
    pub fn volume_source(&self) -> String {
        self.resolve(&self.scene.volume)
    }

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

#[cfg(test)]
mod tests;
