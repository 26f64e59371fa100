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
mod tests;
