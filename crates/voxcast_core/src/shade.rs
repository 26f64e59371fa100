//! Local illumination of a sample: the lecture's "Volumetric Illumination" with the gradient as
//! the normal, summed over up to [`MAX_LIGHTS`] lights.
//!
//! Twin: `shaders/shade.wgsl` (`shade`).
//!
//! The lecture writes, for a material with emission `M_e`, ambient `M_a`, diffuse `M_d` and
//! specular `M_s` reflectivity, a global ambient light `G_a` and lights i with ambient,
//! diffuse and specular intensities `I_a,i`, `I_d,i`, `I_s,i`, attenuation `f_i` and spotlight
//! factor `s_i`:
//!
//! ```text
//! colour = M_e + G_a·M_a + Σ_i f_i·s_i·[I_a,i·M_a + I_d,i·M_d·max(N·L_i, 0) + I_s,i·M_s·spec_i]
//! f_i    = 1/(kc + kl·d + kq·d²)    (d the distance to a point or spot light; 1 for others)
//! ```
//!
//! Voxcast takes the materials from the transfer function's colour `c`: `M_e = ke·c`,
//! `M_a = ka·c`, `M_d = kd·c`, `M_s = ks·h` with the highlight's tint `h` (1, a white highlight
//! as OpenGL and VTK, or `c`, Levoy's); `G_a` is a grey level, `I_d,i = I_s,i = I_i` the
//! light's colour and `I_a,i = a_i·I_i` a share of it. With
//!
//! ```text
//! spec_i = max(N·H_i, 0)^n, H_i = normalize(L_i + V)     (Blinn–Phong)
//!        = max(R_i·V, 0)^n, R_i = 2(N·L_i)N − L_i         (Phong, the lecture's)
//! s_i    = max(−L_i·D_i, 0)^e inside a spot's cone of cutoff angle θ (−L_i·D_i ≥ cos θ), else 0
//! ```
//!
//! clamped to `[0, 1]` per channel, with no highlight where `N·L_i ≤ 0`. The defaults — no
//! emission, `G_a = 1`, no light's own ambient, no spot — leave `ka·c + Σ_i f_i·I_i·(kd·max(N·L_i,
//! 0)·c + ks·spec_i·h)`, Voxcast's shortened form, bit for bit.
//!
//! **Levoy's variant** is the lecture's slide "Illumination or Shading" (Levoy 1988): `c_p·ka +
//! c_p/(k1 + k2·d(x))·(kd·N·L + ks·(N·H)^n)` multiplies the highlight by the colour `c_p` too,
//! so a red sample has a red highlight. Its `d(x)` is the distance from the picture plane (depth
//! cueing: far samples are dimmer), not a light's: [`Phong::depth_cue`] sets every light's
//! falloff to `f = 1/(k1 + k2·d(x))` ([`crate::tunables::DEPTH_CUE_CONSTANT`],
//! [`crate::tunables::DEPTH_CUE_LINEAR`]) with `d(x) = (x − o)·F`, `o` the ray's start on the
//! picture plane and `F` the camera's forward direction. The slide writes `N·L` and `N·H`
//! without the `max(·, 0)` of its own Phong slide: Voxcast keeps the clamp in both variants (a
//! negative `N·L` would subtract light and darken a face below its ambient colour).
//!
//! The normal is the negated, normalised gradient (pointing from high to low values: out of
//! dense material), computed by central differences ([`crate::sample::gradient`]). Where `|∇f|`
//! is below the threshold the normal is undefined and the sample keeps its unshaded colour —
//! never a NaN. With two-sided lighting a normal facing away from the viewer is flipped.

mod lights;
mod terms;

pub use lights::{
    Cone, Light, LightSource, MAX_LIGHTS, ResolvedLight, ResolvedLights, ResolvedSource, Spot,
};
pub use terms::{Coefficients, LightTerms, ShadeTerms};

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

impl SpecularModel {
    pub const ALL: [SpecularModel; 2] = [SpecularModel::BlinnPhong, SpecularModel::Phong];

    /// What it computes, for tooltips and help (one text for the panel and the CLI).
    pub const SPECULAR_DOC: &'static str = "The highlight's base: Blinn-Phong's N·H with the half \
        vector H between the light and the eye (OpenGL's and VTK's), or Phong's R·V with R the \
        light mirrored about the normal, as the lecture writes it; both raised to the \
        shininess n";

    /// Words for the interface.
    pub fn label(self) -> &'static str {
        match self {
            SpecularModel::BlinnPhong => "N·H (Blinn-Phong)",
            SpecularModel::Phong => "R·V (Phong, the lecture's)",
        }
    }

    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            SpecularModel::BlinnPhong => "blinn-phong",
            SpecularModel::Phong => "phong",
        }
    }
}

/// The highlight's colour.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum Highlight {
    /// The light's colour only (OpenGL, VTK): a red sample shows a white highlight.
    #[default]
    White,
    /// Multiplied by the sample's colour too, as Levoy's shading formula in the lecture.
    Levoy,
}

impl Highlight {
    /// What it does, for tooltips and help.
    pub fn doc(self) -> &'static str {
        match self {
            Highlight::White => {
                "The highlight ks·spec takes the light's colour only, as OpenGL and VTK: a red \
                 sample under a white light shows a white highlight"
            }
            Highlight::Levoy => {
                "The highlight is multiplied by the sample's colour too, as Levoy's formula in the \
                 lecture c_p·ka + c_p/(k1 + k2·d)·(kd·N·L + ks·(N·H)^n): a red sample shows a red \
                 highlight"
            }
        }
    }

    /// Words for the interface.
    pub fn label(self) -> &'static str {
        match self {
            Highlight::White => "White (OpenGL, VTK)",
            Highlight::Levoy => "Sample's colour (Levoy)",
        }
    }
}

/// The Phong parameters (see [`crate::tunables`] for each one's documentation) and the lights.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Phong {
    /// [`crate::tunables::EMISSION`].
    pub ke: f32,
    /// [`crate::tunables::GLOBAL_AMBIENT`].
    pub global_ambient: f32,
    pub ka: f32,
    pub kd: f32,
    pub ks: f32,
    pub shininess: f32,
    pub model: SpecularModel,
    pub highlight: Highlight,
    pub two_sided: bool,
    pub gradient_threshold: f32,
    /// [`crate::tunables::DEPTH_CUE`]: Levoy's depth cue sets every light's falloff.
    pub depth_cue: bool,
    /// [`crate::tunables::DEPTH_CUE_CONSTANT`].
    pub depth_kc: f32,
    /// [`crate::tunables::DEPTH_CUE_LINEAR`].
    pub depth_kl: f32,
    /// At most [`MAX_LIGHTS`]; none leaves the ambient term only.
    pub lights: Vec<LightSource>,
}

impl Default for Phong {
    fn default() -> Self {
        use crate::tunables as t;
        Self {
            ke: t::EMISSION.default,
            global_ambient: t::GLOBAL_AMBIENT.default,
            ka: t::AMBIENT.default,
            kd: t::DIFFUSE.default,
            ks: t::SPECULAR.default,
            shininess: t::SHININESS.default,
            model: SpecularModel::default(),
            highlight: Highlight::default(),
            two_sided: t::TWO_SIDED.default != 0.0,
            gradient_threshold: t::GRADIENT_THRESHOLD.default,
            depth_cue: t::DEPTH_CUE.default != 0.0,
            depth_kc: t::DEPTH_CUE_CONSTANT.default,
            depth_kl: t::DEPTH_CUE_LINEAR.default,
            lights: vec![LightSource::default()],
        }
    }
}

impl Phong {
    /// The lights resolved for a camera looking along `camera_forward` (the headlights).
    pub fn resolve(&self, camera_forward: Vec3) -> ResolvedLights {
        ResolvedLights::new(&self.lights, camera_forward)
    }

    /// Whether any term of the lecture's full model beyond Voxcast's shortened form is on:
    /// emission, a global ambient other than 1, a light's own ambient, a spot light, or
    /// Levoy's depth cue.
    pub fn full_form(&self) -> bool {
        self.ke != 0.0
            || self.global_ambient != 1.0
            || self.depth_cue
            || self
                .lights
                .iter()
                .any(|l| l.ambient != 0.0 || matches!(l.light, Light::Spot(_)))
    }

    /// Adds a light, as the panel's "Add a light" does: a white directional light from a side
    /// none of the first lights comes from, so its effect shows at once. `false` (and nothing
    /// added) when there are already [`MAX_LIGHTS`].
    pub fn add_light(&mut self) -> bool {
        const FROM: [Vec3; MAX_LIGHTS] = [
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(1.0, -0.5, -0.6),
            Vec3::new(-1.0, -0.5, -0.6),
            Vec3::new(0.0, 1.0, -0.4),
        ];
        let n = self.lights.len();
        if n >= MAX_LIGHTS {
            return false;
        }
        self.lights
            .push(LightSource::new(Light::Directional(FROM[n])));
        true
    }
}

/// `x^n` for `x ≥ 0`: by repeated squaring when `n` is a whole number (the usual case, and
/// several times faster than `powf`), else `powf`.
#[inline(always)]
pub fn power(x: f32, n: f32) -> f32 {
    // Whole and in [0, 1024]: a round trip through `u32` is exact only for whole numbers in its
    // range (negatives and NaN become 0). Not `fract`, which is a library call per sample on
    // an x86-64 without SSE 4.1.
    if (n as u32) as f32 == n && n <= 1024.0 {
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

/// What shading needs about one ray: the direction to the viewer, where the ray starts on the
/// picture plane (for the depth cue), the lights, and (for each directional light) the Blinn
/// half vector, which is the same for every sample of the ray. Built for every ray, so it
/// borrows the lights rather than copying them (a copy was a call to `memcpy` a ray: about 2 %
/// of the bunny's render).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viewing<'l> {
    /// Unit vector towards the viewer (minus the ray direction).
    pub view: Vec3,
    /// Where the ray starts, on the picture plane (the eye, for a perspective camera).
    pub origin: Vec3,
    pub lights: &'l ResolvedLights,
    /// `normalize(L + V)` per directional light (`None` for point lights, or when L = −V).
    half: [Option<Vec3>; MAX_LIGHTS],
}

impl<'l> Viewing<'l> {
    /// For a ray towards −`view` that starts at the world origin.
    pub fn new(view: Vec3, lights: &'l ResolvedLights) -> Self {
        Self::from_origin(Vec3::ZERO, view, lights)
    }

    /// For a ray from `origin` (on the picture plane) towards −`view`.
    pub fn from_origin(origin: Vec3, view: Vec3, lights: &'l ResolvedLights) -> Self {
        let mut half = [None; MAX_LIGHTS];
        for (h, l) in half.iter_mut().zip(lights.as_slice()) {
            if let ResolvedLight::Toward(d) = l.at {
                *h = (d + view).try_normalize();
            }
        }
        Self {
            view,
            origin,
            lights,
            half,
        }
    }

    /// Light `i`'s Blinn half vector, if it is directional and not straight behind the viewer.
    pub fn half(&self, i: usize) -> Option<Vec3> {
        self.half.get(i).copied().flatten()
    }

    /// The distance of `p_world` from the picture plane, along the camera's forward direction.
    #[inline(always)]
    pub fn depth(&self, p_world: Vec3) -> f32 {
        (p_world - self.origin).dot(self.lights.forward)
    }
}

/// Shades colour `c` at `p_world` with gradient `grad`, for the ray `v` describes. Returns the
/// shaded colour and its terms.
#[inline(always)]
pub fn shade(c: Vec3, grad: Vec3, p_world: Vec3, v: &Viewing<'_>, k: &Phong) -> (Vec3, ShadeTerms) {
    let view = v.view;
    let len = grad.length();
    if !(len > k.gradient_threshold && len.is_finite()) {
        return (c, ShadeTerms::default());
    }
    let mut n = grad * (-1.0 / len);
    if k.two_sided && n.dot(view) < 0.0 {
        n = -n;
    }
    let tint = match k.highlight {
        Highlight::White => Vec3::ONE,
        Highlight::Levoy => c,
    };
    let mut terms = ShadeTerms {
        lit: true,
        normal: n.to_array(),
        k: Coefficients {
            ke: k.ke,
            ga: k.global_ambient,
            ka: k.ka,
            kd: k.kd,
            ks: k.ks,
            shininess: k.shininess,
            depth_k1: k.depth_kc,
            depth_k2: k.depth_kl,
        },
        depth_cue: k.depth_cue,
        highlight: k.highlight,
        tint: tint.to_array(),
        light_count: v.lights.len,
        ..ShadeTerms::default()
    };
    // Levoy's depth cue: one falloff, from the picture plane, for every light.
    let cue = k.depth_cue.then(|| {
        let d = v.depth(p_world);
        let denom = k.depth_kc + k.depth_kl * d;
        (d, if denom > 0.0 { 1.0 / denom } else { 1.0 })
    });
    let (mut diffuse, mut specular, mut light_ambient) = (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
    for (i, light) in v.lights.as_slice().iter().enumerate() {
        let (l, mut distance, mut attenuation) = match light.at {
            ResolvedLight::Toward(l) => (l, 0.0, 1.0),
            ResolvedLight::Point(pos) => {
                let to = pos - p_world;
                let d = to.length();
                (to.normalize_or(view), d, light.attenuation(d))
            }
        };
        if let Some((d, f)) = cue {
            (distance, attenuation) = (d, f);
        }
        let spot = light.cone.map_or(1.0, |cone| cone.factor(l));
        // f_i·s_i (bit for bit f_i without a spot).
        let fs = attenuation * spot;
        let n_dot_l = n.dot(l);
        let lambert = n_dot_l.max(0.0);
        let spec = if n_dot_l > 0.0 {
            let base = match k.model {
                SpecularModel::BlinnPhong => {
                    n.dot(v.half[i].unwrap_or_else(|| (l + view).normalize_or(n)))
                }
                SpecularModel::Phong => (n * (2.0 * n_dot_l) - l).dot(view),
            };
            power(base.max(0.0), k.shininess)
        } else {
            0.0
        };
        let d = c * (light.color * (fs * k.kd * lambert));
        let s = tint * light.color * (fs * k.ks * spec);
        let a = c * (light.ambient * (fs * k.ka));
        diffuse += d;
        specular += s;
        light_ambient += a;
        terms.lights[i] = LightTerms {
            color: light.color.to_array(),
            kc: light.kc,
            kl: light.kl,
            kq: light.kq,
            positional: matches!(light.at, ResolvedLight::Point(_)),
            n_dot_l,
            distance,
            attenuation,
            spotlight: light.cone.is_some(),
            spot,
            spec,
            ambient_color: light.ambient.to_array(),
            ambient: a.to_array(),
            diffuse: d.to_array(),
            specular: s.to_array(),
        };
    }
    let emission = c * k.ke;
    let ambient = c * (k.global_ambient * k.ka);
    // The lecture's order; each added zero of the default form leaves the sum's bits as they
    // were.
    let sum = emission + ambient + light_ambient + diffuse + specular;
    let out = sum.clamp(Vec3::ZERO, Vec3::ONE);
    terms.emission = emission.to_array();
    terms.ambient = ambient.to_array();
    terms.light_ambient = light_ambient.to_array();
    terms.diffuse = diffuse.to_array();
    terms.specular = specular.to_array();
    (out, terms)
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
            &Viewing::new(
                Vec3::Z,
                &ResolvedLights::one(ResolvedLight::Toward(Vec3::Z)),
            ),
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
            &Viewing::new(
                Vec3::Z,
                &ResolvedLights::one(ResolvedLight::Toward(Vec3::Z)),
            ),
            &k(),
        );
        assert_eq!(c, Vec3::new(0.2, 0.4, 0.6));
        assert!(!t.lit);
        let (c, _) = shade(
            Vec3::ONE,
            Vec3::splat(f32::INFINITY),
            Vec3::ZERO,
            &Viewing::new(
                Vec3::Z,
                &ResolvedLights::one(ResolvedLight::Toward(Vec3::Z)),
            ),
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
            &Viewing::new(
                Vec3::Z,
                &ResolvedLights::one(ResolvedLight::Toward(Vec3::Z)),
            ),
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
            &Viewing::new(
                Vec3::Z,
                &ResolvedLights::one(ResolvedLight::Toward(Vec3::Z)),
            ),
            &k(),
        );
        assert!(c2.x > 0.9);
    }

    /// The lights of `p` resolved for a viewer looking along −z.
    fn lights(p: &Phong) -> ResolvedLights {
        p.resolve(Vec3::NEG_Z)
    }

    #[test]
    fn point_light_attenuates() {
        let mut p = k();
        p.lights = vec![LightSource {
            light: Light::Point(Vec3::new(0.0, 0.0, 2.0)),
            kc: 1.0,
            kl: 0.5,
            kq: 0.25,
            ..LightSource::default()
        }];
        let (_, t) = shade(
            Vec3::ONE,
            Vec3::NEG_Z,
            Vec3::ZERO,
            &Viewing::new(Vec3::Z, &lights(&p)),
            &p,
        );
        assert!((t.lights[0].attenuation - 1.0 / (1.0 + 1.0 + 1.0)).abs() < 1e-6);
    }

    #[test]
    fn lights_add_up_each_with_its_colour() {
        // The normal is +z; a red headlight from the viewer's side and a blue light from +x at
        // 60° to the normal: diffuse is kd·c·(red·1 + blue·cos 60°), the highlights add too.
        let mut p = k();
        p.ks = 0.0;
        let oblique = Vec3::new(
            -(60f32.to_radians().sin()),
            0.0,
            -(60f32.to_radians().cos()),
        );
        p.lights = vec![
            LightSource {
                color: Vec3::X,
                ..LightSource::new(Light::Headlight)
            },
            LightSource {
                color: Vec3::Z,
                ..LightSource::new(Light::Directional(oblique))
            },
        ];
        let c = Vec3::splat(0.5);
        let (out, t) = shade(
            c,
            Vec3::NEG_Z,
            Vec3::ZERO,
            &Viewing::new(Vec3::Z, &lights(&p)),
            &p,
        );
        let want = c * 0.1 + c * 0.6 * (Vec3::X + Vec3::Z * 0.5);
        assert!((out - want).abs().max_element() < 1e-6, "{out} vs {want}");
        assert_eq!(t.per_light().len(), 2);
        assert!((t.lights[1].n_dot_l - 0.5).abs() < 1e-6);
        let sum: Vec3 = t
            .per_light()
            .iter()
            .map(|l| Vec3::from_array(l.diffuse))
            .sum();
        assert!((sum - Vec3::from_array(t.diffuse)).abs().max_element() < 1e-7);
    }

    #[test]
    fn no_light_leaves_the_ambient_term() {
        let mut p = k();
        p.lights.clear();
        let c = Vec3::new(0.2, 0.4, 0.6);
        let (out, t) = shade(
            c,
            Vec3::NEG_Z,
            Vec3::ZERO,
            &Viewing::new(Vec3::Z, &lights(&p)),
            &p,
        );
        assert!((out - c * 0.1).abs().max_element() < 1e-7);
        assert!(t.lit && t.per_light().is_empty());
    }

    #[test]
    fn levoys_highlight_takes_the_samples_colour() {
        // At the mirror direction spec = 1: the white highlight adds ks to every channel,
        // Levoy's adds ks·c.
        let c = Vec3::new(0.8, 0.1, 0.0);
        let mut p = k();
        p.kd = 0.0;
        p.ka = 0.0;
        let white = shade(
            c,
            Vec3::NEG_Z,
            Vec3::ZERO,
            &Viewing::new(Vec3::Z, &lights(&p)),
            &p,
        )
        .0;
        p.highlight = Highlight::Levoy;
        let levoy = shade(
            c,
            Vec3::NEG_Z,
            Vec3::ZERO,
            &Viewing::new(Vec3::Z, &lights(&p)),
            &p,
        )
        .0;
        assert!(
            (white - Vec3::splat(0.3)).abs().max_element() < 1e-6,
            "{white}"
        );
        assert!((levoy - c * 0.3).abs().max_element() < 1e-6, "{levoy}");
        let terms = shade(
            c,
            Vec3::NEG_Z,
            Vec3::ZERO,
            &Viewing::new(Vec3::Z, &lights(&p)),
            &p,
        )
        .1;
        assert_eq!(terms.tint, c.to_array(), "the breakdown shows h");
    }

    /// The lecture's full model by hand: M_e + G_a·M_a + f·s·[I_a·M_a + I·M_d·N·L + I·M_s·spec]
    /// for a spot light straight above a surface facing it, 20° off the spot's axis.
    #[test]
    fn the_full_model_adds_emission_global_and_light_ambient_and_the_spot_factor() {
        let off = 20f32.to_radians();
        // The sample at the origin, normal +z; the light 5 up, its axis tilted 20° from −z.
        let spot = Spot {
            position: Vec3::new(0.0, 0.0, 5.0),
            direction: Vec3::new(off.sin(), 0.0, -off.cos()),
            cutoff: 30.0,
            exponent: 2.0,
        };
        let p = Phong {
            ke: 0.1,
            global_ambient: 0.5,
            ka: 0.2,
            kd: 0.6,
            ks: 0.3,
            shininess: 4.0,
            lights: vec![LightSource {
                color: Vec3::new(1.0, 0.5, 0.25),
                ambient: 0.4,
                kc: 1.0,
                kl: 0.1,
                kq: 0.0,
                light: Light::Spot(spot),
            }],
            ..Phong::default()
        };
        assert!(p.full_form());
        let c = Vec3::new(0.4, 0.3, 0.2);
        let resolved = lights(&p);
        let (out, t) = shade(
            c,
            Vec3::NEG_Z,
            Vec3::ZERO,
            &Viewing::new(Vec3::Z, &resolved),
            &p,
        );
        let f = 1.0 / (1.0 + 0.1 * 5.0);
        let s = off.cos().powi(2);
        let i = Vec3::new(1.0, 0.5, 0.25);
        // N·L = 1 and N·H = 1 (light and viewer straight above): spec = 1.
        let want = c * 0.1 + c * (0.5 * 0.2) + f * s * (i * 0.4 * 0.2 * c + i * 0.6 * c + i * 0.3);
        assert!((out - want).abs().max_element() < 1e-6, "{out} vs {want}");
        let l = t.per_light()[0];
        assert!((l.spot - s).abs() < 1e-6 && (l.attenuation - f).abs() < 1e-6);
        assert!(t.full_form());
        // Outside the cone only the global terms are left.
        let narrow = Phong {
            lights: vec![LightSource {
                light: Light::Spot(Spot {
                    cutoff: 10.0,
                    ..spot
                }),
                ..p.lights[0]
            }],
            ..p.clone()
        };
        let resolved = lights(&narrow);
        let (dark, _) = shade(
            c,
            Vec3::NEG_Z,
            Vec3::ZERO,
            &Viewing::new(Vec3::Z, &resolved),
            &narrow,
        );
        assert!(
            (dark - (c * 0.1 + c * 0.1)).abs().max_element() < 1e-7,
            "{dark}"
        );
    }

    /// Levoy's depth cue: f = 1/(k1 + k2·d) with d the distance from the picture plane, for
    /// every light (a point light's own falloff is replaced), not the distance to the light.
    #[test]
    fn the_depth_cue_dims_with_distance_from_the_picture_plane() {
        let mut p = k();
        p.ks = 0.0;
        p.depth_cue = true;
        p.depth_kc = 1.0;
        p.depth_kl = 0.05;
        p.lights = vec![LightSource {
            kl: 3.0,
            ..LightSource::new(Light::Point(Vec3::new(0.0, 0.0, 100.0)))
        }];
        // The camera looks along −z from z = 50 (its picture plane is z = 50).
        let resolved = p.resolve(Vec3::NEG_Z);
        let eye = Vec3::new(7.0, -3.0, 50.0);
        let v = Viewing::from_origin(eye, Vec3::Z, &resolved);
        let c = Vec3::splat(0.5);
        for z in [40.0f32, 10.0, -20.0] {
            let at = Vec3::new(1.0, 2.0, z);
            let (out, t) = shade(c, Vec3::NEG_Z, at, &v, &p);
            let d = 50.0 - z;
            let f = 1.0 / (1.0 + 0.05 * d);
            let n_dot_l = (Vec3::new(0.0, 0.0, 100.0) - at).normalize().z;
            let want = c * 0.1 + c * (0.6 * f * n_dot_l);
            assert!(
                (out - want).abs().max_element() < 1e-6,
                "z {z}: {out} vs {want}"
            );
            assert!((t.per_light()[0].distance - d).abs() < 1e-4);
        }
        // Off: the point light's own falloff at its distance.
        p.depth_cue = false;
        let (_, t) = shade(c, Vec3::NEG_Z, Vec3::ZERO, &v, &p);
        assert!((t.per_light()[0].attenuation - 1.0 / (1.0 + 3.0 * 100.0)).abs() < 1e-7);
    }

    /// The defaults are the shortened form: no term of the full model is on, and a sample's
    /// colour is ka·c + Σ f·I·(kd·N·L·c + ks·spec·h) to the last bit.
    #[test]
    fn the_defaults_are_the_shortened_form_bit_for_bit() {
        let p = Phong::default();
        assert!(!p.full_form());
        let resolved = lights(&p);
        let view = Vec3::new(0.2, 0.3, 0.9).normalize();
        let v = Viewing::new(view, &resolved);
        let c = Vec3::new(0.7, 0.35, 0.1);
        let grad = Vec3::new(-0.3, -0.2, -1.0);
        let (out, t) = shade(c, grad, Vec3::ZERO, &v, &p);
        let n = -grad.normalize();
        let l = Vec3::Z;
        let spec = power(n.dot(v.half(0).unwrap()).max(0.0), p.shininess);
        let short = c * p.ka
            + c * (Vec3::ONE * (1.0 * p.kd * n.dot(l).max(0.0)))
            + Vec3::ONE * Vec3::ONE * (1.0 * p.ks * spec);
        assert_eq!(out, short.clamp(Vec3::ZERO, Vec3::ONE));
        assert!(!t.full_form());
    }

    #[test]
    fn adding_lights_stops_at_the_most_the_gpu_holds() {
        let mut p = k();
        while p.add_light() {}
        assert_eq!(p.lights.len(), MAX_LIGHTS);
        let places: Vec<Light> = p.lights.iter().map(|l| l.light).collect();
        for (i, a) in places.iter().enumerate() {
            assert!(
                !places[i + 1..].contains(a),
                "each added light from its own side"
            );
        }
    }

    #[test]
    fn no_more_lights_than_the_gpu_holds_are_resolved() {
        let mut p = k();
        p.lights = vec![LightSource::default(); MAX_LIGHTS + 2];
        assert_eq!(lights(&p).as_slice().len(), MAX_LIGHTS);
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

    /// Repeated squaring exactly for whole exponents in 0..=1024 (±0 included), `powf`
    /// elsewhere — fractions, negatives, above 1024, beyond `u32`, NaN.
    #[test]
    fn power_squares_exactly_where_the_exponent_is_whole_and_small() {
        let squared = |x: f32, n: u32| {
            let (mut base, mut e, mut acc) = (x, n, 1.0f32);
            while e > 0 {
                if e & 1 == 1 {
                    acc *= base;
                }
                base *= base;
                e >>= 1;
            }
            acc
        };
        for x in [0.0f32, 0.3, 0.75, 0.999, 1.0] {
            for n in [0u32, 1, 2, 3, 13, 64, 1023, 1024] {
                assert_eq!(
                    power(x, n as f32).to_bits(),
                    squared(x, n).to_bits(),
                    "{x}^{n}"
                );
            }
            assert_eq!(power(x, -0.0), 1.0);
            for n in [0.5f32, 2.5, 1024.5, 1025.0, -2.0, 5e9, f32::INFINITY] {
                assert_eq!(power(x, n).to_bits(), x.powf(n).to_bits(), "{x}^{n}");
            }
            assert!(power(x, f32::NAN).is_nan() || x == 1.0);
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
                &Viewing::new(
                    Vec3::Z,
                    &ResolvedLights::one(ResolvedLight::Toward(Vec3::Z)),
                ),
                &p,
            );
            assert!((t.specular[0] - 0.3).abs() < 1e-6, "{model:?}");
        }
    }
}
