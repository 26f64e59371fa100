//! What a level or one of its steps puts on screen when it opens: the data set, the transfer
//! function, the settings, the main and the virtual camera, the selected ray — and where a
//! file a level names is found (beside the level: a path on the desktop, a URL on the page).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A camera placed by a level: where its eye is, what it looks at, which way is up.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CameraPlace {
    /// The eye, in world units (the volume's box runs from its origin over its extent).
    pub eye: [f32; 3],
    /// The point it looks at, in world units.
    pub target: [f32; 3],
    /// Which way is up on screen (default +y).
    #[serde(default = "up", skip_serializing_if = "is_up")]
    pub up: [f32; 3],
    /// The vertical field of view in degrees (default: the sandbox's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fov_y_deg: Option<f32>,
    /// A virtual camera's pixels across and down (default: the level's `rays`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pixels: Option<[u32; 2]>,
}

fn up() -> [f32; 3] {
    [0.0, 1.0, 0.0]
}

fn is_up(v: &[f32; 3]) -> bool {
    *v == up()
}

/// A transfer function a level names: a preset by name, a file (a path or URL ending in
/// `.json`, beside the level) or the function itself.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum TransferChoice {
    /// A preset's name (`voxcast levels check` lists them) or a transfer-function file ending
    /// in `.json`, relative to the level's file.
    Named(String),
    /// The transfer function written out: its points of value, colour and opacity.
    Inline(crate::transfer::TransferFunction),
}

impl TransferChoice {
    /// The file it names, if it names one (a name ending in `.json`).
    pub fn file(&self) -> Option<&str> {
        match self {
            TransferChoice::Named(n) if n.to_ascii_lowercase().ends_with(".json") => Some(n),
            _ => None,
        }
    }
}

/// What a step puts on screen as it opens, each part optional: a snapshot of the scene (the
/// editor writes every part), or only what the step changes (`settings` are written over the
/// player's).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StepScene {
    /// The data set: `builtin:NAME`, or a file beside the level (relative path or URL).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub volume: Option<String>,
    /// The transfer function.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transfer: Option<TransferChoice>,
    /// Render settings written over the current ones, as in a preset: `{"method": "first",
    /// "target": 120}` (docs/levels.md lists them; `voxcast levels check` reads them).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(with = "Option<serde_json::Map<String, serde_json::Value>>")]
    pub settings: Option<serde_json::Map<String, serde_json::Value>>,
    /// The main camera.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub camera: Option<CameraPlace>,
    /// The virtual camera (its pixels too).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub virtual_camera: Option<CameraPlace>,
    /// The selected ray: the virtual camera's pixel (x across, y down, from 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ray: Option<[u32; 2]>,
}

impl StepScene {
    /// Whether it puts nothing on screen.
    pub fn is_empty(&self) -> bool {
        *self == StepScene::default()
    }
}

/// Where a level was read from: the files it names are found beside it.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum Origin {
    /// Compiled in: a name is a builtin or a path from where the sandbox started.
    #[default]
    Embedded,
    /// A file on the desktop.
    File(std::path::PathBuf),
    /// A URL (the page): its names are URLs beside it.
    Url(String),
}

impl Origin {
    /// Where `name` is, for a level from here: `builtin:` and `density:` names, absolute paths
    /// and full URLs as they are; a relative name beside the level's file or URL.
    pub fn resolve(&self, name: &str) -> String {
        let absolute = name.starts_with("builtin:")
            || name.starts_with("density:")
            || name.contains("://")
            || std::path::Path::new(name).is_absolute();
        if absolute {
            return name.to_string();
        }
        match self {
            Origin::Embedded => name.to_string(),
            Origin::File(path) => path
                .parent()
                .map_or_else(|| name.into(), |dir| dir.join(name))
                .display()
                .to_string(),
            Origin::Url(url) => {
                let url = url.split(['?', '#']).next().unwrap_or(url);
                let dir = url.rfind('/').map_or("", |i| &url[..=i]);
                format!("{dir}{name}")
            }
        }
    }

    /// The level's own file or URL, in words.
    pub fn words(&self) -> String {
        match self {
            Origin::Embedded => "built in".into(),
            Origin::File(p) => p.display().to_string(),
            Origin::Url(u) => u.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_found_beside_the_level() {
        let file = Origin::File("/home/t/course/ct.json".into());
        assert_eq!(file.resolve("head.nrrd"), "/home/t/course/head.nrrd");
        assert_eq!(
            file.resolve("data/head.nrrd"),
            "/home/t/course/data/head.nrrd"
        );
        assert_eq!(file.resolve("builtin:head"), "builtin:head");
        assert_eq!(file.resolve("/data/x.nrrd"), "/data/x.nrrd");
        let url = Origin::Url("http://127.0.0.1:8000/levels/ct.json?x=1".into());
        assert_eq!(
            url.resolve("head.nrrd"),
            "http://127.0.0.1:8000/levels/head.nrrd"
        );
        assert_eq!(
            url.resolve("density:builtin:cornell"),
            "density:builtin:cornell"
        );
        assert_eq!(Origin::Embedded.resolve("x.nrrd"), "x.nrrd");
        assert_eq!(
            Origin::File("level.json".into()).resolve("x.nrrd"),
            "x.nrrd",
            "a level in the current folder"
        );
    }

    #[test]
    fn a_transfer_function_is_a_preset_a_file_or_written_out() {
        let named: TransferChoice = serde_json::from_str("\"bunny\"").unwrap();
        assert_eq!(named.file(), None);
        let file: TransferChoice = serde_json::from_str("\"tf/skin.JSON\"").unwrap();
        assert_eq!(file.file(), Some("tf/skin.JSON"));
        let inline: TransferChoice = serde_json::from_str(
            r#"{"name": "ramp", "points": [{"value": 0, "color": [0, 0, 0], "alpha": 0}]}"#,
        )
        .unwrap();
        assert!(matches!(inline, TransferChoice::Inline(t) if t.name == "ramp"));
        let cam: CameraPlace =
            serde_json::from_str(r#"{"eye": [1, 2, 3], "target": [0, 0, 0]}"#).unwrap();
        assert_eq!(cam.up, [0.0, 1.0, 0.0]);
        assert_eq!(
            serde_json::to_string(&cam).unwrap(),
            r#"{"eye":[1.0,2.0,3.0],"target":[0.0,0.0,0.0]}"#
        );
    }
}
