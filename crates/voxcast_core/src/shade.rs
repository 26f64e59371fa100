//! Local illumination of a sample: Phong or Blinn–Phong with the gradient as the normal.
//!
//! Twin: `shaders/shade.wgsl` (`shade`).
//!
//! With `N` the unit normal, `L` the unit direction to the light, `V` the unit direction to the
//! viewer, `c` the sample's colour and `f = 1/(kc + kl·d + kq·d²)` the attenuation of a point light
//! at distance `d` (lecture "Volumetric Illumination"; 1 for directional lights):
//!
//! ```text
//! colour = ka·c + f·light·( kd·max(N·L, 0)·c + ks·spec ),
//! spec   = max(N·H, 0)^n, H = normalize(L + V)     (Blinn–Phong)
//!        = max(R·V, 0)^n, R = 2(N·L)N − L          (Phong)
//! ```
//!
//! clamped to `[0, 1]` per channel; the highlight is white (not tinted by `c`), and there is no
//! highlight where `N·L ≤ 0`. The normal is the negated, normalised gradient (pointing from high
//! to low values: out of dense material), computed by central differences
//! ([`crate::sample::gradient`]). Where `|∇f|` is below the threshold the normal is undefined and
//! the sample keeps its unshaded colour — never a NaN. With two-sided lighting a normal facing
//! away from the viewer is flipped.

use glam::Vec3;

/// The specular model.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum SpecularModel {
    /// `max(R·V, 0)^n` with `R` the mirrored light direction (Phong 1975).
    Phong,
    /// `max(N·H, 0)^n` with the half vector `H` (Blinn 1977; what OpenGL and VTK use).
    #[default]
    BlinnPhong,
}

/// Where the light is.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Light {
    /// A directional light along the camera's view direction (VTK's default "headlight").
    #[default]
    Headlight,
    /// A point light at a world position; attenuated with distance.
    Point(Vec3),
    /// A directional light shining *along* this world direction (from infinitely far away).
    Directional(Vec3),
}

/// A light resolved for one view: either a position or the unit direction *towards* the light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ResolvedLight {
    Point(Vec3),
    Toward(Vec3),
}

impl Light {
    /// Resolves a headlight with the camera's forward direction.
    pub fn resolve(self, camera_forward: Vec3) -> ResolvedLight {
        match self {
            Light::Headlight => ResolvedLight::Toward(-camera_forward.normalize_or(Vec3::NEG_Z)),
            Light::Point(p) => ResolvedLight::Point(p),
            Light::Directional(d) => ResolvedLight::Toward(-d.normalize_or(Vec3::NEG_Z)),
        }
    }
}

/// The Phong parameters (see [`crate::tunables`] for each one's documentation).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Phong {
    pub ka: f32,
    pub kd: f32,
    pub ks: f32,
    pub shininess: f32,
    pub model: SpecularModel,
    pub two_sided: bool,
    pub gradient_threshold: f32,
    pub kc: f32,
    pub kl: f32,
    pub kq: f32,
    /// Light colour and intensity (linear RGB).
    pub light_color: Vec3,
    pub light: Light,
}

impl Default for Phong {
    fn default() -> Self {
        use crate::tunables as t;
        Self {
            ka: t::AMBIENT.default,
            kd: t::DIFFUSE.default,
            ks: t::SPECULAR.default,
            shininess: t::SHININESS.default,
            model: SpecularModel::default(),
            two_sided: t::TWO_SIDED.default != 0.0,
            gradient_threshold: t::GRADIENT_THRESHOLD.default,
            kc: t::ATTENUATION_CONSTANT.default,
            kl: t::ATTENUATION_LINEAR.default,
            kq: t::ATTENUATION_QUADRATIC.default,
            light_color: Vec3::ONE,
            light: Light::Headlight,
        }
    }
}

/// `x^n` for `x ≥ 0`: by repeated squaring when `n` is a whole number (the usual case, and
/// several times faster than `powf`), else `powf`.
#[inline(always)]
pub fn power(x: f32, n: f32) -> f32 {
    if n.fract() == 0.0 && (0.0..=1024.0).contains(&n) {
        // Binary exponentiation, inline (Rust's `powi` calls a library loop).
        let (mut base, mut e, mut acc) = (x, n as u32, 1.0f32);
        while e > 0 {
            if e & 1 == 1 {
                acc *= base;
            }
            base *= base;
            e >>= 1;
        }
        acc
    } else {
        x.powf(n)
    }
}

/// The terms of one shading computation, for the ray inspector.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct ShadeTerms {
    /// False where the gradient was below the threshold (the colour is left unshaded).
    pub lit: bool,
    pub normal: [f32; 3],
    pub n_dot_l: f32,
    /// ka·c (per channel).
    pub ambient: [f32; 3],
    /// f·light·kd·max(N·L,0)·c.
    pub diffuse: [f32; 3],
    /// f·light·ks·spec.
    pub specular: [f32; 3],
    pub attenuation: f32,
}

/// What shading needs about one ray: the direction to the viewer, the light, and (for a
/// directional light) the Blinn half vector, which is the same for every sample of the ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viewing {
    /// Unit vector towards the viewer (minus the ray direction).
    pub view: Vec3,
    pub light: ResolvedLight,
    /// `normalize(L + V)` for a directional light (`None` for point lights, or when L = −V).
    half: Option<Vec3>,
}

impl Viewing {
    pub fn new(view: Vec3, light: ResolvedLight) -> Self {
        let half = match light {
            ResolvedLight::Toward(l) => (l + view).try_normalize(),
            ResolvedLight::Point(_) => None,
        };
        Self { view, light, half }
    }
}

/// Shades colour `c` at `p_world` with gradient `grad`, for the ray `v` describes. Returns the
/// shaded colour and its terms.
#[inline(always)]
pub fn shade(c: Vec3, grad: Vec3, p_world: Vec3, v: &Viewing, k: &Phong) -> (Vec3, ShadeTerms) {
    let (view, light) = (v.view, v.light);
    let len = grad.length();
    if !(len > k.gradient_threshold && len.is_finite()) {
        return (c, ShadeTerms::default());
    }
    let mut n = grad * (-1.0 / len);
    if k.two_sided && n.dot(view) < 0.0 {
        n = -n;
    }
    let (l, attenuation) = match light {
        ResolvedLight::Toward(l) => (l, 1.0),
        ResolvedLight::Point(pos) => {
            let to = pos - p_world;
            let d = to.length();
            let denom = k.kc + k.kl * d + k.kq * d * d;
            let f = if denom > 0.0 { 1.0 / denom } else { 1.0 };
            (to.normalize_or(view), f)
        }
    };
    let n_dot_l = n.dot(l);
    let lambert = n_dot_l.max(0.0);
    let spec = if n_dot_l > 0.0 {
        let base = match k.model {
            SpecularModel::BlinnPhong => {
                n.dot(v.half.unwrap_or_else(|| (l + view).normalize_or(n)))
            }
            SpecularModel::Phong => (n * (2.0 * n_dot_l) - l).dot(view),
        };
        power(base.max(0.0), k.shininess)
    } else {
        0.0
    };
    let ambient = c * k.ka;
    let diffuse = c * (k.light_color * (attenuation * k.kd * lambert));
    let specular = k.light_color * (attenuation * k.ks * spec);
    let out = (ambient + diffuse + specular).clamp(Vec3::ZERO, Vec3::ONE);
    (
        out,
        ShadeTerms {
            lit: true,
            normal: n.to_array(),
            n_dot_l,
            ambient: ambient.to_array(),
            diffuse: diffuse.to_array(),
            specular: specular.to_array(),
            attenuation,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn k() -> Phong {
        Phong {
            ka: 0.1,
            kd: 0.6,
            ks: 0.3,
            shininess: 8.0,
            ..Phong::default()
        }
    }

    #[test]
    fn facing_light_and_viewer_gives_the_sum_of_terms() {
        // Gradient pointing into the surface (−z), so the normal is +z, towards light and viewer.
        let (c, t) = shade(
            Vec3::splat(0.5),
            Vec3::new(0.0, 0.0, -3.0),
            Vec3::ZERO,
            &Viewing::new(Vec3::Z, ResolvedLight::Toward(Vec3::Z)),
            &k(),
        );
        assert!(t.lit);
        assert!(
            (c - Vec3::splat(0.1 * 0.5 + 0.6 * 0.5 + 0.3))
                .abs()
                .max_element()
                < 1e-6
        );
    }

    #[test]
    fn flat_regions_keep_their_colour_without_nan() {
        let (c, t) = shade(
            Vec3::new(0.2, 0.4, 0.6),
            Vec3::ZERO,
            Vec3::ZERO,
            &Viewing::new(Vec3::Z, ResolvedLight::Toward(Vec3::Z)),
            &k(),
        );
        assert_eq!(c, Vec3::new(0.2, 0.4, 0.6));
        assert!(!t.lit);
        let (c, _) = shade(
            Vec3::ONE,
            Vec3::splat(f32::INFINITY),
            Vec3::ZERO,
            &Viewing::new(Vec3::Z, ResolvedLight::Toward(Vec3::Z)),
            &k(),
        );
        assert!(c.is_finite());
    }

    #[test]
    fn two_sided_flips_back_faces() {
        let grad = Vec3::new(0.0, 0.0, 1.0); // normal −z, away from the viewer at +z
        let mut one = k();
        one.two_sided = false;
        let (c1, _) = shade(
            Vec3::ONE,
            grad,
            Vec3::ZERO,
            &Viewing::new(Vec3::Z, ResolvedLight::Toward(Vec3::Z)),
            &one,
        );
        assert!(
            (c1 - Vec3::splat(0.1)).abs().max_element() < 1e-6,
            "ambient only"
        );
        let (c2, _) = shade(
            Vec3::ONE,
            grad,
            Vec3::ZERO,
            &Viewing::new(Vec3::Z, ResolvedLight::Toward(Vec3::Z)),
            &k(),
        );
        assert!(c2.x > 0.9);
    }

    #[test]
    fn point_light_attenuates() {
        let mut p = k();
        p.kc = 1.0;
        p.kl = 0.5;
        p.kq = 0.25;
        let (_, t) = shade(
            Vec3::ONE,
            Vec3::NEG_Z,
            Vec3::ZERO,
            &Viewing::new(Vec3::Z, ResolvedLight::Point(Vec3::new(0.0, 0.0, 2.0))),
            &p,
        );
        assert!((t.attenuation - 1.0 / (1.0 + 1.0 + 1.0)).abs() < 1e-6);
    }

    #[test]
    fn power_matches_powf() {
        for (x, n) in [
            (0.5f32, 10.0f32),
            (0.99, 128.0),
            (0.0, 3.0),
            (1.0, 7.0),
            (0.3, 2.5),
        ] {
            let (a, b) = (power(x, n), x.powf(n));
            assert!((a - b).abs() <= 1e-5 * b.max(1e-30), "{x}^{n}: {a} vs {b}");
        }
    }

    #[test]
    fn phong_and_blinn_agree_at_the_mirror_direction() {
        let mut p = k();
        for model in [SpecularModel::Phong, SpecularModel::BlinnPhong] {
            p.model = model;
            let (_, t) = shade(
                Vec3::ZERO,
                Vec3::NEG_Z,
                Vec3::ZERO,
                &Viewing::new(Vec3::Z, ResolvedLight::Toward(Vec3::Z)),
                &p,
            );
            assert!((t.specular[0] - 0.3).abs() < 1e-6, "{model:?}");
        }
    }
}
