//! The transfer-function JSON of the VTK peer (`../shared/tools/peer/tf/*.json`), so that runs
//! compare one to one with VTK.
//!
//! VTK keeps separate piecewise-linear colour (`[[value, r, g, b], …]`) and opacity
//! (`[[value, a], …]`) functions, both clamped at their ends. Voxcast's transfer function has RGBA
//! control points; evaluating both VTK functions at the union of their breakpoints gives RGBA
//! points whose piecewise-linear interpolation equals VTK's pair exactly (each function is linear
//! between its own breakpoints, so also between the finer union).
//!
//! The file's rendering fields become settings: `opacity_unit_distance` → reference step (world
//! units, as VTK corrects `1 − (1 − a)^(d/unit)`), `shade`/`diffuse`/`specular`/`specular_power`
//! → Phong with a headlight (VTK's default light), `interpolation`, the first of `iso_values` →
//! First's target, `background`. VTK's default light has a black *ambient* colour
//! (vtkEncodedGradientShader multiplies the material's ambient by it), so the file's `ambient`
//! has no effect in VTK; Voxcast sets `ka = 0` to render the same picture, and says so. VTK-only fields Voxcast does not model
//! (`gradient_opacity`, `average_range`) are reported as notes.

use crate::error::SettingsError;
use crate::sample::Interpolation;
use crate::settings::RenderSettings;
use crate::shade::{Light, LightSource, SpecularModel};
use crate::step::Length;
use crate::transfer::{ControlPoint, TransferFunction};
use glam::Vec3;

#[derive(serde::Deserialize)]
struct PeerTf {
    #[serde(default)]
    name: String,
    color: Vec<[f32; 4]>,
    opacity: Vec<[f32; 2]>,
    #[serde(default)]
    gradient_opacity: Option<serde_json::Value>,
    #[serde(default)]
    opacity_unit_distance: Option<f32>,
    #[serde(default)]
    interpolation: Option<String>,
    #[serde(default)]
    shade: Option<bool>,
    ambient: Option<f32>,
    diffuse: Option<f32>,
    specular: Option<f32>,
    specular_power: Option<f32>,
    #[serde(default)]
    iso_values: Vec<f32>,
    #[serde(default)]
    average_range: Option<serde_json::Value>,
    #[serde(default)]
    background: Option<[f32; 3]>,
}

/// A peer transfer function read into Voxcast's terms.
#[derive(Clone, Debug)]
pub struct PeerTransfer {
    pub transfer: TransferFunction,
    /// Applies the file's rendering fields to `settings`.
    apply: PeerSettings,
    /// What the file asks for that Voxcast does not model.
    pub notes: Vec<String>,
}

#[derive(Clone, Debug, Default)]
struct PeerSettings {
    reference: Option<f32>,
    interpolation: Option<Interpolation>,
    shade: Option<bool>,
    ka: Option<f32>,
    kd: Option<f32>,
    ks: Option<f32>,
    n: Option<f32>,
    target: Option<f32>,
    background: Option<Vec3>,
}

impl PeerTransfer {
    /// Writes the file's rendering fields into `settings`.
    pub fn apply(&self, settings: &mut RenderSettings) {
        let a = &self.apply;
        if let Some(u) = a.reference {
            settings.reference_step = Length::World(u);
        }
        if let Some(i) = a.interpolation {
            settings.interpolation = i;
        }
        if let Some(s) = a.shade {
            settings.shading = s;
            settings.phong.lights = vec![LightSource::new(Light::Headlight)];
            settings.phong.model = SpecularModel::BlinnPhong;
        }
        let p = &mut settings.phong;
        for (dst, src) in [
            (&mut p.ka, a.ka),
            (&mut p.kd, a.kd),
            (&mut p.ks, a.ks),
            (&mut p.shininess, a.n),
        ] {
            if let Some(v) = src {
                *dst = v;
            }
        }
        if a.target.is_some() {
            settings.target = a.target;
        }
        if let Some(bg) = a.background {
            settings.background = bg;
        }
    }
}

/// Writes `transfer` and the rendering fields of `settings` as the peer's JSON, so VTK renders
/// what Voxcast renders (the reference step goes out in world units; `voxel` is the smallest
/// spacing). Levoy classification, attenuation, point lights and jitter have no equivalent there.
pub fn to_json(transfer: &TransferFunction, settings: &RenderSettings, voxel: f32) -> String {
    let p = transfer.points();
    let mut v = serde_json::json!({
        "name": transfer.name,
        "color": p.iter().map(|c| [c.value, c.color[0], c.color[1], c.color[2]]).collect::<Vec<_>>(),
        "opacity": p.iter().map(|c| [c.value, c.alpha]).collect::<Vec<_>>(),
        "opacity_unit_distance": settings.reference_step.world(voxel),
        "interpolation": match settings.interpolation { Interpolation::Trilinear => "linear", Interpolation::Nearest => "nearest" },
        "shade": settings.shading,
        // VTK ignores it under its default light (see the module docs).
        "ambient": settings.phong.ka,
        "diffuse": settings.phong.kd,
        "specular": settings.phong.ks,
        "specular_power": settings.phong.shininess,
        "background": settings.background,
    });
    if let Some(t) = settings.target {
        v["iso_values"] = serde_json::json!([t]);
    }
    serde_json::to_string_pretty(&v).expect("serialises")
}

/// Whether `text` looks like the peer's format (separate `color` and `opacity` lists).
pub fn is_peer_json(text: &str) -> bool {
    serde_json::from_str::<serde_json::Value>(text)
        .ok()
        .is_some_and(|v| v.get("color").is_some() && v.get("opacity").is_some())
}

/// Piecewise-linear, clamped evaluation of VTK-style `(x, value)` lists.
fn eval<const N: usize>(points: &[[f32; N]], x: f32) -> [f32; N] {
    let first = points[0];
    let last = points[points.len() - 1];
    if x <= first[0] {
        return first;
    }
    if x >= last[0] {
        return last;
    }
    let hi = points.partition_point(|p| p[0] <= x);
    let (a, b) = (points[hi - 1], points[hi]);
    let t = (x - a[0]) / (b[0] - a[0]);
    let mut out = a;
    for i in 1..N {
        out[i] = a[i] + (b[i] - a[i]) * t;
    }
    out[0] = x;
    out
}

/// Reads the peer's transfer-function JSON.
pub fn from_json(text: &str) -> Result<PeerTransfer, SettingsError> {
    let p: PeerTf = serde_json::from_str(text)
        .map_err(|e| SettingsError::Invalid(format!("peer transfer function: {e}")))?;
    if p.color.is_empty() || p.opacity.is_empty() {
        return Err(SettingsError::Invalid(
            "peer transfer function: 'color' and 'opacity' need at least one point each".into(),
        ));
    }
    let mut color = p.color.clone();
    let mut opacity = p.opacity.clone();
    color.sort_by(|a, b| a[0].total_cmp(&b[0]));
    opacity.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let mut xs: Vec<f32> = color
        .iter()
        .map(|c| c[0])
        .chain(opacity.iter().map(|o| o[0]))
        .collect();
    xs.sort_by(f32::total_cmp);
    xs.dedup();
    let points = xs
        .into_iter()
        .map(|x| {
            let c = eval(&color, x);
            let o = eval(&opacity, x);
            ControlPoint::new(x, [c[1], c[2], c[3]], o[1])
        })
        .collect();
    let transfer = TransferFunction::new(p.name.clone(), points)?;
    let mut notes = Vec::new();
    if p.gradient_opacity.is_some() {
        notes.push(
            "'gradient_opacity' (VTK-specific) is not modelled; try --classify boundaries".into(),
        );
    }
    if p.ambient.is_some_and(|a| a != 0.0) && p.shade == Some(true) {
        notes.push(format!(
            "'ambient' {} has no effect under VTK's default light (its ambient colour is black): ka = 0 to match VTK",
            p.ambient.unwrap_or(0.0)
        ));
    }
    if p.average_range.is_some() {
        notes.push(
            "'average_range' (VTK GPU mapper only) is not modelled: Average uses every sample"
                .into(),
        );
    }
    let interpolation = match p.interpolation.as_deref() {
        None => None,
        Some("linear") => Some(Interpolation::Trilinear),
        Some("nearest") => Some(Interpolation::Nearest),
        Some(other) => {
            return Err(SettingsError::Invalid(format!(
                "peer transfer function: interpolation '{other}' (expected linear or nearest)"
            )));
        }
    };
    if let Some(u) = p.opacity_unit_distance {
        SettingsError::check_positive("opacity_unit_distance", u)?;
    }
    Ok(PeerTransfer {
        transfer,
        apply: PeerSettings {
            reference: p.opacity_unit_distance,
            interpolation,
            shade: p.shade,
            ka: p.ambient.map(|_| 0.0),
            kd: p.diffuse,
            ks: p.specular,
            n: p.specular_power,
            target: p.iso_values.first().copied(),
            background: p.background.map(Vec3::from),
        },
        notes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const CT: &str = r#"{"name": "x",
      "color": [[-1024, 0, 0, 0], [200, 0.9, 0.8, 0.7], [3000, 1, 1, 1]],
      "opacity": [[-1024, 0], [0, 0], [500, 0.5], [3000, 0.9]],
      "opacity_unit_distance": 2.0, "shade": true, "ambient": 0.1, "specular_power": 20,
      "iso_values": [400], "background": [0.1, 0.2, 0.3]}"#;

    #[test]
    fn union_of_breakpoints_reproduces_both_functions() {
        let p = from_json(CT).unwrap();
        assert!(is_peer_json(CT));
        let xs: Vec<f32> = p.transfer.points().iter().map(|c| c.value).collect();
        assert_eq!(xs, vec![-1024.0, 0.0, 200.0, 500.0, 3000.0]);
        // Between breakpoints the union function equals VTK's pair.
        let color = [
            [-1024.0, 0.0, 0.0, 0.0],
            [200.0, 0.9, 0.8, 0.7],
            [3000.0, 1.0, 1.0, 1.0],
        ];
        let opacity = [[-1024.0, 0.0], [0.0, 0.0], [500.0, 0.5], [3000.0, 0.9]];
        for x in [-2000.0, -500.0, 100.0, 350.0, 1234.5, 4000.0] {
            let got = p.transfer.evaluate(x);
            let c = eval(&color, x);
            let o = eval(&opacity, x);
            assert!(
                (got.x - c[1]).abs() < 1e-6
                    && (got.y - c[2]).abs() < 1e-6
                    && (got.w - o[1]).abs() < 1e-6,
                "{x}"
            );
        }
    }

    #[test]
    fn settings_follow_the_file() {
        let p = from_json(CT).unwrap();
        let mut s = RenderSettings::default();
        p.apply(&mut s);
        assert!(s.shading);
        assert_eq!(s.reference_step, Length::World(2.0));
        assert_eq!(s.phong.ka, 0.0, "VTK's default light has no ambient colour");
        assert_eq!(s.phong.shininess, 20.0);
        assert_eq!(s.target, Some(400.0));
        assert_eq!(s.background, Vec3::new(0.1, 0.2, 0.3));
    }

    #[test]
    fn writing_and_reading_back_is_lossless() {
        let p = from_json(CT).unwrap();
        let mut s = RenderSettings::default();
        p.apply(&mut s);
        let back = from_json(&to_json(&p.transfer, &s, 0.5)).unwrap();
        assert_eq!(back.transfer.points(), p.transfer.points());
        let mut s2 = RenderSettings::default();
        back.apply(&mut s2);
        assert_eq!(s2, s);
    }

    #[test]
    fn bad_files_are_errors() {
        assert!(from_json(r#"{"color": [], "opacity": [[0, 1]]}"#).is_err());
        assert!(from_json(r#"{"color": [[0,1,1,1]], "opacity": [[0, 2]]}"#).is_err());
        assert!(from_json("[").is_err());
    }
}
