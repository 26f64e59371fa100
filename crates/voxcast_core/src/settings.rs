//! Render settings: every choice the ray caster offers, validated in one place.
//!
//! Defaults and ranges come from [`crate::tunables`], where each is documented once.

use crate::classify::Classification;
use crate::clip::Clip;
use crate::composite::{Method, Order};
use crate::error::SettingsError;
use crate::sample::Interpolation;
use crate::shade::{Light, LightSource, MAX_LIGHTS, Phong};
use crate::step::Length;
use crate::tunables as t;
use glam::Vec3;

/// Everything that decides how the rays are cast and composited.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct RenderSettings {
    /// How samples become a pixel ([`Method::doc`]).
    pub method: Method,
    /// [`t::STEP`].
    pub step: Length,
    /// How values between lattice points are reconstructed.
    pub interpolation: Interpolation,
    /// [`t::OPACITY_CORRECTION`].
    pub opacity_correction: bool,
    /// [`t::REFERENCE_STEP`].
    pub reference_step: Length,
    /// [`t::EARLY_TERMINATION`].
    pub early_termination: bool,
    /// [`t::SKIPPING`].
    pub skipping: bool,
    /// [`t::CUTOFF`].
    pub cutoff: f32,
    /// Sample order for Accumulate.
    pub order: Order,
    /// [`t::JITTER`].
    pub jitter: bool,
    /// Seed of the jitter hash (a different seed gives a different noise pattern).
    pub jitter_seed: u32,
    /// [`t::TARGET`]; `None` is the middle of the volume's value range.
    pub target: Option<f32>,
    /// [`t::SUM_RANGE`]; `None` is [`crate::scene::default_sum_range`].
    pub sum_range: Option<(f32, f32)>,
    /// [`t::REFINE_STEPS`].
    pub refine_steps: u32,
    /// [`t::MAX_SAMPLES`].
    pub max_samples: u32,
    /// [`t::SUPERSAMPLING`].
    pub supersampling: u32,
    /// [`t::SHADING`].
    pub shading: bool,
    /// Phong parameters and the light, used when `shading` is on.
    pub phong: Phong,
    /// Colour behind the volume (linear RGB).
    pub background: Vec3,
    /// How opacity is assigned ([`crate::classify`]).
    pub classification: Classification,
    /// The crop box and clip plane ([`crate::clip`]).
    pub clip: Clip,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            method: Method::Accumulate,
            step: Length::Voxels(t::STEP.default),
            interpolation: Interpolation::Trilinear,
            opacity_correction: t::OPACITY_CORRECTION.default != 0.0,
            reference_step: Length::Voxels(t::REFERENCE_STEP.default),
            early_termination: t::EARLY_TERMINATION.default != 0.0,
            skipping: t::SKIPPING.default != 0.0,
            cutoff: t::CUTOFF.default,
            order: Order::FrontToBack,
            jitter: t::JITTER.default != 0.0,
            jitter_seed: 0,
            target: None,
            sum_range: None,
            refine_steps: t::REFINE_STEPS.default as u32,
            max_samples: t::MAX_SAMPLES.default as u32,
            supersampling: t::SUPERSAMPLING.default as u32,
            shading: t::SHADING.default != 0.0,
            phong: Phong::default(),
            background: Vec3::ZERO,
            classification: Classification::Table,
            clip: Clip::default(),
        }
    }
}

fn check(tn: &t::Tunable, v: f32) -> Result<(), SettingsError> {
    SettingsError::check_range(tn.key, v, tn.min, tn.max)
}

/// Checks one light: its attenuation, colour and place.
fn validate_light(l: &LightSource) -> Result<(), SettingsError> {
    check(&t::ATTENUATION_CONSTANT, l.kc)?;
    check(&t::ATTENUATION_LINEAR, l.kl)?;
    check(&t::ATTENUATION_QUADRATIC, l.kq)?;
    check(&t::LIGHT_AMBIENT, l.ambient)?;
    if l.kc + l.kl + l.kq <= 0.0 {
        return Err(SettingsError::Invalid(
            "attenuation kc + kl + kq must be positive (else a point light is infinitely bright)"
                .into(),
        ));
    }
    if !l.color.is_finite() || l.color.min_element() < 0.0 {
        return Err(SettingsError::Invalid(
            "light colour must be finite and non-negative".into(),
        ));
    }
    match l.light {
        Light::Headlight => Ok(()),
        Light::Point(v) if v.is_finite() => Ok(()),
        Light::Directional(v) if v.is_finite() && v.length_squared() > 0.0 => Ok(()),
        Light::Spot(s) if s.position.is_finite() => {
            check(&t::SPOT_CUTOFF, s.cutoff)?;
            check(&t::SPOT_EXPONENT, s.exponent)?;
            if s.direction.is_finite() && s.direction.length_squared() > 0.0 {
                Ok(())
            } else {
                Err(SettingsError::Invalid(
                    "a spot light's direction must be finite and not zero".into(),
                ))
            }
        }
        other => Err(SettingsError::Invalid(format!(
            "{other:?} is not a finite position or direction"
        ))),
    }
}

impl RenderSettings {
    /// Sample positions a ray along the volume's diagonal (the longest there is) needs at this
    /// step.
    pub fn longest_ray_samples(&self, volume: &crate::volume::Volume) -> f64 {
        let (lo, hi) = volume.bounds();
        let dt = self.step.world(volume.spacing().min_element());
        (hi - lo).as_dvec3().length() / f64::from(dt) + 1.0
    }

    /// A warning in words when the sample cap would cut the longest rays through `volume`
    /// short at this step (they would stop inside it); `None` when every ray fits.
    pub fn cap_warning(&self, volume: &crate::volume::Volume) -> Option<String> {
        let need = self.longest_ray_samples(volume);
        (need > f64::from(self.max_samples)).then(|| {
            format!(
                "At this step a ray across the volume needs up to {} samples, more than the cap \
                 ({}): longer rays stop inside the volume. Raise the step or the cap.",
                crate::numbers::sig64(need),
                self.max_samples
            )
        })
    }

    /// Checks every value against its documented range.
    pub fn validate(&self) -> Result<(), SettingsError> {
        self.step.validate(t::STEP.key)?;
        self.reference_step.validate(t::REFERENCE_STEP.key)?;
        check(&t::CUTOFF, self.cutoff)?;
        if let Some(target) = self.target {
            check(&t::TARGET, target)?;
        }
        if let Some((a, b)) = self.sum_range {
            check(&t::SUM_RANGE, a)?;
            check(&t::SUM_RANGE, b)?;
            if a >= b {
                return Err(SettingsError::Invalid(format!(
                    "{}: the low end ({a}) must lie below the high end ({b})",
                    t::SUM_RANGE.key
                )));
            }
        }
        check(&t::REFINE_STEPS, self.refine_steps as f32)?;
        check(&t::MAX_SAMPLES, self.max_samples as f32)?;
        check(&t::SUPERSAMPLING, self.supersampling as f32)?;
        let p = &self.phong;
        check(&t::AMBIENT, p.ka)?;
        check(&t::DIFFUSE, p.kd)?;
        check(&t::SPECULAR, p.ks)?;
        check(&t::SHININESS, p.shininess)?;
        check(&t::GRADIENT_THRESHOLD, p.gradient_threshold)?;
        check(&t::EMISSION, p.ke)?;
        check(&t::GLOBAL_AMBIENT, p.global_ambient)?;
        check(&t::DEPTH_CUE_CONSTANT, p.depth_kc)?;
        check(&t::DEPTH_CUE_LINEAR, p.depth_kl)?;
        if p.depth_cue && p.depth_kc <= 0.0 {
            return Err(SettingsError::Invalid(format!(
                "{} must be positive with the depth cue on (else samples on the picture plane \
                 are infinitely bright)",
                t::DEPTH_CUE_CONSTANT.key
            )));
        }
        if p.lights.len() > MAX_LIGHTS {
            return Err(SettingsError::Invalid(format!(
                "{} lights: at most {MAX_LIGHTS} (the preview's shader holds that many)",
                p.lights.len()
            )));
        }
        for (i, l) in p.lights.iter().enumerate() {
            validate_light(l)
                .map_err(|e| SettingsError::Invalid(format!("light {}: {e}", i + 1)))?;
        }
        if !self.background.is_finite()
            || self.background.min_element() < 0.0
            || self.background.max_element() > 1.0
        {
            return Err(SettingsError::Invalid(
                "background channels must lie in [0, 1]".into(),
            ));
        }
        self.clip.validate()?;
        self.classification.validate()
    }
}

/// The combinations on which the GPU preview must agree with the CPU render (the sandbox's
/// `--screenshot DIR --sweep` and its test): every method at steps 1 and ½ voxel, shading off and
/// on; plus nearest interpolation, jitter, back-to-front order and no opacity correction for
/// Accumulate, and a crop box with an oblique clip plane for Accumulate and First; the lecture's
/// full illumination model (emission, global ambient, the lights' own ambient, a spot light
/// whose cone edge crosses the volume, Phong's R·V) for Accumulate and First, and Levoy's
/// depth cue; two overlapping value-and-gradient rectangles for Accumulate in both orders. Each
/// with a file stem naming it.
pub fn agreement_cases(
    base: &RenderSettings,
    volume: &crate::volume::Volume,
    transfer: &crate::transfer::TransferFunction,
) -> Vec<(String, RenderSettings)> {
    let bounds = volume.bounds();
    let mut out = Vec::new();
    for method in Method::ALL {
        for step in [1.0f32, 0.5] {
            for shading in [false, true] {
                let s = RenderSettings {
                    method,
                    step: Length::Voxels(step),
                    shading,
                    ..base.clone()
                };
                let name = format!(
                    "{}_step{}_{}",
                    method.name(),
                    step,
                    if shading { "shaded" } else { "flat" }
                );
                out.push((name, s));
            }
        }
    }
    let accumulate = RenderSettings {
        method: Method::Accumulate,
        step: Length::Voxels(0.5),
        shading: true,
        ..base.clone()
    };
    out.push((
        "accumulate_nearest".into(),
        RenderSettings {
            interpolation: Interpolation::Nearest,
            ..accumulate.clone()
        },
    ));
    out.push((
        "accumulate_supersampled".into(),
        RenderSettings {
            supersampling: 2,
            jitter: true,
            jitter_seed: 7,
            ..accumulate.clone()
        },
    ));
    out.push((
        "accumulate_jitter".into(),
        RenderSettings {
            jitter: true,
            jitter_seed: 7,
            ..accumulate.clone()
        },
    ));
    out.push((
        "accumulate_back_to_front".into(),
        RenderSettings {
            order: Order::BackToFront,
            ..accumulate.clone()
        },
    ));
    // Four coloured lights (every slot the GPU holds), one an attenuated point light, and
    // Levoy's highlight: the sum over lights on both sides. The sweep hides the lights' markers
    // as Render image does (the CPU render has no meshes).
    let lights = crate::shade::Phong {
        lights: vec![
            LightSource {
                color: Vec3::new(0.9, 0.5, 0.4),
                ..LightSource::new(Light::Headlight)
            },
            LightSource {
                color: Vec3::new(0.3, 0.5, 1.0),
                ..LightSource::new(Light::Directional(Vec3::new(1.0, -0.5, -0.6)))
            },
            LightSource {
                color: Vec3::new(0.4, 1.0, 0.4),
                ..LightSource::new(Light::Directional(Vec3::new(-1.0, -0.5, -0.6)))
            },
            LightSource {
                color: Vec3::new(1.0, 0.9, 0.6),
                kl: 0.004,
                ..LightSource::new(Light::Point(Vec3::new(-40.0, 150.0, 120.0)))
            },
        ],
        highlight: crate::shade::Highlight::Levoy,
        ..base.phong.clone()
    };
    out.push((
        "accumulate_lights".into(),
        RenderSettings {
            phong: lights.clone(),
            ..accumulate.clone()
        },
    ));
    out.push((
        "first_lights".into(),
        RenderSettings {
            method: Method::First,
            phong: lights,
            ..accumulate.clone()
        },
    ));
    let clip = crate::clip::Clip {
        crop_lo: Vec3::new(0.1, 0.0, 0.15),
        crop_hi: Vec3::new(1.0, 0.85, 1.0),
        plane: Some(crate::clip::ClipPlane {
            normal: Vec3::new(0.6, 0.3, 0.75),
            position: 0.1,
        }),
    };
    for method in [Method::Accumulate, Method::First] {
        out.push((
            format!("{}_clipped", method.name()),
            RenderSettings {
                method,
                clip: clip.clone(),
                ..accumulate.clone()
            },
        ));
    }
    for (name, phong) in full_models(&base.phong, bounds) {
        for method in [Method::Accumulate, Method::First] {
            if name == "depth_cue" && method == Method::First {
                continue;
            }
            out.push((
                format!("{}_{name}", method.name()),
                RenderSettings {
                    method,
                    phong: phong.clone(),
                    ..accumulate.clone()
                },
            ));
        }
    }
    // Opacity matters to Accumulate only (the projections and First read values): both its
    // orders.
    let classification = value_gradient_rectangles(volume);
    for (name, order) in [
        ("", Order::FrontToBack),
        ("_back_to_front", Order::BackToFront),
    ] {
        out.push((
            format!("accumulate_value_gradient{name}"),
            RenderSettings {
                order,
                classification: classification.clone(),
                ..accumulate.clone()
            },
        ));
    }
    // Levoy's two other classifications (the table's colour, their own opacity), and
    // lighting from one side only (back faces dark, not flipped).
    for (name, classification) in [
        (
            "iso_contours",
            crate::classify::Classification::IsoContours {
                isovalues: visible_isovalues(volume, transfer),
                thickness_voxels: 1.5,
            },
        ),
        (
            "boundaries",
            crate::classify::Classification::Boundaries {
                full_gradient: None,
            },
        ),
    ] {
        out.push((
            format!("accumulate_{name}"),
            RenderSettings {
                classification,
                ..accumulate.clone()
            },
        ));
    }
    out.push((
        if base.phong.two_sided {
            "accumulate_one_sided"
        } else {
            "accumulate_two_sided"
        }
        .into(),
        RenderSettings {
            phong: Phong {
                two_sided: !base.phong.two_sided,
                ..base.phong.clone()
            },
            ..accumulate.clone()
        },
    ));
    out.push((
        "accumulate_uncorrected".into(),
        RenderSettings {
            opacity_correction: false,
            ..accumulate
        },
    ));
    out
}

/// Two isovalues in `volume`'s range that the table makes visible (an isovalue's contour takes
/// the table's opacity there, so an invisible one would draw an empty image that agrees
/// trivially): a third and two thirds of the way through the visible values, or a third and
/// two thirds of the range where none is visible.
fn visible_isovalues(
    volume: &crate::volume::Volume,
    transfer: &crate::transfer::TransferFunction,
) -> Vec<f32> {
    let (lo, hi) = volume.value_range();
    let range = (hi - lo).max(1e-6);
    let visible: Vec<f32> = (0..64)
        .map(|i| lo + range * (i as f32 + 0.5) / 64.0)
        .filter(|&v| transfer.evaluate(v).w > 0.02)
        .collect();
    match visible.len() {
        0 => vec![lo + range / 3.0, lo + 2.0 * range / 3.0],
        n => vec![visible[n / 3], visible[2 * n / 3]],
    }
}

/// Two overlapping rectangles over value × gradient magnitude for `volume`: low values at low
/// gradients, and higher values at gradients from a tenth of a value range per voxel up.
fn value_gradient_rectangles(volume: &crate::volume::Volume) -> crate::classify::Classification {
    let (lo, hi) = volume.value_range();
    let range = (hi - lo).max(1e-6);
    let steep = range / volume.spacing().min_element();
    crate::classify::Classification::ValueGradient {
        regions: vec![
            crate::classify::Region {
                value: [lo + 0.15 * range, lo + 0.65 * range],
                gradient: [0.0, 0.15 * steep],
                opacity: 0.5,
            },
            crate::classify::Region {
                value: [lo + 0.4 * range, hi],
                gradient: [0.1 * steep, steep],
                opacity: 0.8,
            },
        ],
    }
}

/// The lecture's full model and Levoy's depth cue over `base`, for a volume in `bounds`.
fn full_models(base: &crate::shade::Phong, (lo, hi): (Vec3, Vec3)) -> [(&'static str, Phong); 2] {
    let (centre, size) = ((lo + hi) * 0.5, (hi - lo).length().max(1e-3));
    let spot_at = hi + (hi - lo) * Vec3::new(0.3, 0.6, 0.4);
    let full = Phong {
        ke: 0.15,
        global_ambient: 0.6,
        model: crate::shade::SpecularModel::Phong,
        lights: vec![
            LightSource {
                ambient: 0.3,
                color: Vec3::new(0.8, 0.8, 0.9),
                ..LightSource::new(Light::Headlight)
            },
            LightSource {
                ambient: 0.5,
                color: Vec3::new(1.0, 0.7, 0.4),
                kl: 0.5 / size,
                // Aimed at the centre, with a cone whose edge falls inside the volume.
                ..LightSource::new(Light::Spot(crate::shade::Spot {
                    position: spot_at,
                    direction: centre - spot_at,
                    cutoff: 14.0,
                    exponent: 3.0,
                }))
            },
        ],
        ..base.clone()
    };
    let cued = Phong {
        highlight: crate::shade::Highlight::Levoy,
        depth_cue: true,
        depth_kc: 0.5,
        depth_kl: 1.5 / size,
        lights: vec![
            LightSource::new(Light::Headlight),
            LightSource {
                kl: 0.01,
                ..LightSource::new(Light::Point(spot_at))
            },
        ],
        ..base.clone()
    };
    [("full_model", full), ("depth_cue", cued)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_bad_values_are_named() {
        assert!(RenderSettings::default().validate().is_ok());
        let mut s = RenderSettings {
            cutoff: 1.5,
            ..Default::default()
        };
        let e = s.validate().unwrap_err().to_string();
        assert!(e.contains("cutoff"), "{e}");
        s.cutoff = 0.9;
        s.step = Length::Voxels(-1.0);
        assert!(s.validate().unwrap_err().to_string().contains("step"));
        s.step = Length::Voxels(0.5);
        s.phong.lights[0].kc = 0.0;
        let e = s.validate().unwrap_err().to_string();
        assert!(e.starts_with("light 1: "), "{e}");
        s.phong.lights = vec![LightSource::default(); MAX_LIGHTS];
        assert!(s.validate().is_ok());
        s.phong.lights.push(LightSource::default());
        assert!(s.validate().unwrap_err().to_string().contains("at most 4"));
        s.phong.lights.clear();
        assert!(s.validate().is_ok(), "no light: ambient only");
    }

    #[test]
    fn json_round_trip_with_partial_input() {
        let s: RenderSettings =
            serde_json::from_str(r#"{"method": "maximum", "step": {"world": 0.25}}"#).unwrap();
        assert_eq!(s.method, Method::Maximum);
        assert_eq!(s.step, Length::World(0.25));
        assert_eq!(s.cutoff, t::CUTOFF.default);
        let back: RenderSettings =
            serde_json::from_str(&serde_json::to_string(&s).unwrap()).unwrap();
        assert_eq!(back, s);
    }
}
