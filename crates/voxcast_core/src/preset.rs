//! Presets: a transfer function plus the settings that suit it, one for every bundled dataset.
//!
//! Presets are data (`assets/presets/*.json`, compiled in):
//!
//! ```json
//! {"name": "bunny", "description": "…", "volumes": ["bunny_sdf"],
//!  "view": {"from": [0.3, 0.4, 1.0], "up": [0, 1, 0]},
//!  "transfer": {"name": "bunny", "points": [{"value": 110, "color": [0.9, 0.7, 0.5], "alpha": 0}, …]},
//!  "settings": {"shading": true, "target": 128.0}}
//! ```
//!
//! `settings` holds only what the preset changes; everything else keeps its default. The CT and
//! MRI presets are the peer's transfer functions (`../shared/tools/peer/tf`) converted exactly,
//! so Voxcast and VTK render the same inputs.

use crate::error::SettingsError;
use crate::settings::RenderSettings;
use crate::transfer::TransferFunction;

/// A named transfer function with the settings it is meant for.
#[derive(Clone, Debug, PartialEq, serde::Deserialize)]
pub struct Preset {
    pub name: String,
    #[serde(default)]
    pub description: String,
    /// Names of the volumes this preset is the default for.
    #[serde(default)]
    pub volumes: Vec<String>,
    /// The direction to look from and the up vector that show the volume best.
    #[serde(default)]
    pub view: Option<View>,
    pub transfer: TransferFunction,
    /// The settings the preset changes, as a JSON object (applied over defaults or current ones).
    #[serde(default)]
    pub settings: serde_json::Map<String, serde_json::Value>,
}

/// A preferred view direction: the default camera looks at the volume's centre from `from`
/// (eye − target, any length) with `up` as the screen's up.
#[derive(Clone, Copy, Debug, PartialEq, serde::Deserialize)]
pub struct View {
    pub from: glam::Vec3,
    pub up: glam::Vec3,
}

const EMBEDDED: &[&str] = &[
    include_str!("../../../assets/presets/bunny.json"),
    include_str!("../../../assets/presets/brainsmall.json"),
    include_str!("../../../assets/presets/brainsmall-projections.json"),
    include_str!("../../../assets/presets/shells.json"),
    include_str!("../../../assets/presets/marschner-lobb.json"),
    include_str!("../../../assets/presets/bucky.json"),
    include_str!("../../../assets/presets/voxel.json"),
    include_str!("../../../assets/presets/head.json"),
    include_str!("../../../assets/presets/head-brain.json"),
    include_str!("../../../assets/presets/blobs.json"),
    include_str!("../../../assets/presets/masked.json"),
    include_str!("../../../assets/presets/ct_skin_bone.json"),
    include_str!("../../../assets/presets/mri_brain.json"),
];

impl Preset {
    /// Reads a preset's JSON.
    pub fn from_json(text: &str) -> Result<Self, SettingsError> {
        let p: Preset = serde_json::from_str(text)
            .map_err(|e| SettingsError::Invalid(format!("preset: {e}")))?;
        p.settings_over(&RenderSettings::default())?;
        Ok(p)
    }

    /// `base` with this preset's settings written over it.
    pub fn settings_over(&self, base: &RenderSettings) -> Result<RenderSettings, SettingsError> {
        settings_written_over(base, &self.settings)
            .map_err(|e| SettingsError::Invalid(format!("preset {}: {e}", self.name)))
    }
}

/// `base` with `changes` (some of the settings' fields, as their JSON names them) written over
/// it, checked: a preset's, a level's or a step's settings.
pub fn settings_written_over(
    base: &RenderSettings,
    changes: &serde_json::Map<String, serde_json::Value>,
) -> Result<RenderSettings, String> {
    let mut value = serde_json::to_value(base).expect("settings serialise");
    merge(&mut value, &serde_json::Value::Object(changes.clone()));
    let s: RenderSettings = serde_json::from_value(value).map_err(|e| e.to_string())?;
    s.validate().map_err(|e| e.to_string())?;
    Ok(s)
}

/// The transfer function and settings `volume` starts with: its preset's, or a grey ramp over
/// its value range with the default settings.
pub fn defaults_for(volume: &crate::volume::Volume) -> (TransferFunction, RenderSettings) {
    if let Some(p) = for_loaded(volume)
        && let Ok(settings) = p.settings_over(&RenderSettings::default())
    {
        return (p.transfer, settings);
    }
    let (lo, hi) = volume.value_range();
    let ramp = TransferFunction::ramp(lo, hi, 0.5)
        .or_else(|_| TransferFunction::constant([1.0; 3], 0.5))
        .expect("a constant transfer function is valid");
    (ramp, RenderSettings::default())
}

/// Deep-merges JSON objects: `patch`'s fields replace `base`'s, recursively. An object whose keys
/// are not all in `base` (another enum variant, such as `{"world": 1}` over `{"voxels": 0.5}`)
/// replaces it whole.
fn merge(base: &mut serde_json::Value, patch: &serde_json::Value) {
    match (base, patch) {
        (serde_json::Value::Object(b), serde_json::Value::Object(p))
            if p.keys().all(|k| b.contains_key(k)) =>
        {
            for (k, v) in p {
                merge(b.entry(k.clone()).or_insert(serde_json::Value::Null), v);
            }
        }
        (b, p) => *b = p.clone(),
    }
}

/// Every embedded preset.
pub fn all() -> Vec<Preset> {
    EMBEDDED
        .iter()
        .map(|text| Preset::from_json(text).expect("embedded presets are valid (tested)"))
        .collect()
}

/// The embedded preset called `name`.
/// `-` and `_` are taken as the same (`marschner-lobb`, `ct_skin_bone`).
pub fn by_name(name: &str) -> Option<Preset> {
    let same = |a: &str| a.replace('_', "-") == name.replace('_', "-");
    all().into_iter().find(|p| same(&p.name))
}

/// The preset meant for a volume of this name, if any.
pub fn for_volume(volume_name: &str) -> Option<Preset> {
    all()
        .into_iter()
        .find(|p| p.volumes.iter().any(|v| v == volume_name))
}

/// The preset a loaded volume starts with: a ray density's ([`density`]) for one, else the
/// one named for it ([`for_volume`]).
pub fn for_loaded(volume: &crate::volume::Volume) -> Option<Preset> {
    if crate::rays::as_volume::is_density(volume) {
        let (lo, hi) = volume.value_range();
        return Some(density(lo, hi));
    }
    for_volume(volume.name())
}

/// A ray density's preset: inferno over its counts `[lo, hi]`, Sum, no shading, seen from −z
/// (the Cornell box's camera looks along +z).
pub fn density(lo: f32, hi: f32) -> Preset {
    let settings = serde_json::json!({"method": "sum", "shading": false});
    Preset {
        name: crate::colormap::INFERNO_PRESET.into(),
        description: crate::colormap::INFERNO_DOC.into(),
        volumes: Vec::new(),
        view: Some(View {
            from: glam::Vec3::NEG_Z,
            up: glam::Vec3::Y,
        }),
        transfer: crate::colormap::inferno_transfer(lo, hi),
        settings: settings.as_object().cloned().unwrap_or_default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builtin::{DATASETS, load_builtin};

    #[test]
    fn every_embedded_preset_is_valid_and_every_builtin_has_one() {
        let presets = all();
        assert_eq!(presets.len(), EMBEDDED.len());
        for (name, _) in DATASETS {
            let v = load_builtin(name).unwrap().volume;
            let p = for_volume(v.name()).unwrap_or_else(|| panic!("no preset for {name}"));
            let s = p.settings_over(&RenderSettings::default()).unwrap();
            assert!(
                s.target.is_some(),
                "{}: presets give First a target",
                p.name
            );
            let (lo, hi) = v.value_range();
            let t = s.target.unwrap();
            assert!(
                t > lo && t < hi,
                "{}: target {t} outside {lo}..{hi}",
                p.name
            );
            assert!(
                !p.transfer.bake(lo, hi).is_empty(),
                "{}: shows something",
                p.name
            );
            let view = p.view.expect("every preset has a view");
            let (a, b) = v.bounds();
            assert!(
                crate::camera::Camera::framing(a, b, view.from, view.up).is_ok(),
                "{}",
                p.name
            );
        }
        for shared in ["ct_cranium", "mri_mni152"] {
            assert!(for_volume(shared).is_some(), "{shared}");
        }
    }

    /// A description is read by students under the dataset's name: words, not the file names
    /// of the project's benchmarks ("as VTK renders the peer's bunny.json" was one).
    #[test]
    fn descriptions_name_no_files() {
        for p in all() {
            let d = &p.description;
            assert!(
                !d.contains(".json") && !d.contains("peer") && !d.contains('_'),
                "{}: {d}",
                p.name
            );
        }
    }

    #[test]
    fn a_ray_density_starts_with_sum_and_inferno() {
        let v = crate::volume::Volume::new(
            "x",
            glam::UVec3::new(2, 2, 2),
            glam::Vec3::ONE,
            crate::volume::VoxelData::F32(vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]),
        )
        .unwrap();
        assert_eq!(for_loaded(&v), None);
        let d = v.with_name(crate::rays::grid::NAME_PREFIX);
        let p = for_loaded(&d).unwrap();
        let s = p.settings_over(&RenderSettings::default()).unwrap();
        assert_eq!(s.method, crate::composite::Method::Sum);
        assert!(!s.shading);
        assert_eq!(p.transfer, crate::colormap::inferno_transfer(0.0, 7.0));
        let bunny = crate::builtin::load_builtin("bunny").unwrap().volume;
        assert_eq!(for_loaded(&bunny), for_volume("bunny_sdf"));
    }

    #[test]
    fn settings_patch_only_what_they_name() {
        let p = by_name("shells").unwrap();
        let base = RenderSettings {
            cutoff: 0.5,
            ..Default::default()
        };
        let s = p.settings_over(&base).unwrap();
        assert_eq!(s.cutoff, 0.5);
        assert_eq!(s.target, Some(128.0));
    }
}
