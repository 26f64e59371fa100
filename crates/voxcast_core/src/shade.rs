//! Local illumination of a sample: Phong or Blinn–Phong with the gradient as the normal, summed
//! over up to [`MAX_LIGHTS`] lights.
//!
//! Twin: `shaders/shade.wgsl` (`shade`).
//!
//! With `N` the unit normal, `V` the unit direction to the viewer, `c` the sample's colour, and
//! for each light i its colour `I_i`, the unit direction `L_i` towards it and the attenuation
//! `f_i = 1/(kc_i + kl_i·d_i + kq_i·d_i²)` of a point light at distance `d_i` (1 for directional
//! lights) — the lecture's "Volumetric Illumination", which sums over lights i:
//!
//! ```text
//! colour = ka·c + Σ_i f_i·I_i·( kd·max(N·L_i, 0)·c + ks·spec_i·h ),
//! spec_i = max(N·H_i, 0)^n, H_i = normalize(L_i + V)     (Blinn–Phong)
//!        = max(R_i·V, 0)^n, R_i = 2(N·L_i)N − L_i         (Phong)
//! h      = 1 (a white highlight, as OpenGL and VTK) or c (Levoy's highlight)
//! ```
//!
//! clamped to `[0, 1]` per channel, with no highlight where `N·L_i ≤ 0`. **Levoy's variant** is
//! the lecture's slide "Illumination or Shading" (Levoy 1988): `c_p·ka + c_p/(k1 + k2·d)·(kd·N·L +
//! ks·(N·H)^n)` multiplies the highlight by the colour `c_p` too, so a red sample has a red
//! highlight; with `h = 1` a red sample has a white one. The slide writes `N·L` and `N·H`
//! without the `max(·, 0)` of its own Phong slide: Voxcast keeps the clamp in both variants (a
//! negative `N·L` would subtract light and darken a face below its ambient colour).
//!
//! The normal is the negated, normalised gradient (pointing from high to low values: out of
//! dense material), computed by central differences ([`crate::sample::gradient`]). Where `|∇f|`
//! is below the threshold the normal is undefined and the sample keeps its unshaded colour —
//! never a NaN. With two-sided lighting a normal facing away from the viewer is flipped.

use glam::Vec3;

/// The most lights a scene has: the GPU's uniform holds this many (`shaders/types.wgsl`), and
/// the settings refuse more.
pub const MAX_LIGHTS: usize = 4;

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

/// Where a light is.
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

    /// Words for the interface.
    pub fn kind_label(self) -> &'static str {
        match self {
            Light::Headlight => "headlight",
            Light::Point(_) => "point",
            Light::Directional(_) => "directional",
        }
    }
}

/// One light: where it is, its colour, and its attenuation (which only a point light uses; see
/// [`crate::tunables`] for each term's documentation).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct LightSource {
    pub light: Light,
    /// Colour and intensity (linear RGB).
    pub color: Vec3,
    pub kc: f32,
    pub kl: f32,
    pub kq: f32,
}

impl Default for LightSource {
    fn default() -> Self {
        use crate::tunables as t;
        Self {
            light: Light::Headlight,
            color: Vec3::ONE,
            kc: t::ATTENUATION_CONSTANT.default,
            kl: t::ATTENUATION_LINEAR.default,
            kq: t::ATTENUATION_QUADRATIC.default,
        }
    }
}

impl LightSource {
    /// A white, unattenuated light at `light`.
    pub fn new(light: Light) -> Self {
        Self {
            light,
            ..Self::default()
        }
    }

    /// Whether its light falls off with distance (a point light with kl or kq above zero).
    pub fn attenuated(&self) -> bool {
        matches!(self.light, Light::Point(_)) && (self.kl > 0.0 || self.kq > 0.0)
    }
}

/// The Phong parameters (see [`crate::tunables`] for each one's documentation) and the lights.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Phong {
    pub ka: f32,
    pub kd: f32,
    pub ks: f32,
    pub shininess: f32,
    pub model: SpecularModel,
    pub highlight: Highlight,
    pub two_sided: bool,
    pub gradient_threshold: f32,
    /// At most [`MAX_LIGHTS`]; none leaves the ambient term only.
    pub lights: Vec<LightSource>,
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
            highlight: Highlight::default(),
            two_sided: t::TWO_SIDED.default != 0.0,
            gradient_threshold: t::GRADIENT_THRESHOLD.default,
            lights: vec![LightSource::default()],
        }
    }
}

impl Phong {
    /// The lights resolved for a camera looking along `camera_forward` (the headlights).
    pub fn resolve(&self, camera_forward: Vec3) -> ResolvedLights {
        let mut out = ResolvedLights::default();
        for l in self.lights.iter().take(MAX_LIGHTS) {
            out.items[out.len] = ResolvedSource {
                at: l.light.resolve(camera_forward),
                color: l.color,
                kc: l.kc,
                kl: l.kl,
                kq: l.kq,
            };
            out.len += 1;
        }
        out
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

/// One light resolved for a view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResolvedSource {
    pub at: ResolvedLight,
    pub color: Vec3,
    pub kc: f32,
    pub kl: f32,
    pub kq: f32,
}

impl Default for ResolvedSource {
    fn default() -> Self {
        Self {
            at: ResolvedLight::Toward(Vec3::Z),
            color: Vec3::ZERO,
            kc: 1.0,
            kl: 0.0,
            kq: 0.0,
        }
    }
}

impl ResolvedSource {
    #[inline(always)]
    fn attenuation(&self, d: f32) -> f32 {
        let denom = self.kc + self.kl * d + self.kq * d * d;
        if denom > 0.0 { 1.0 / denom } else { 1.0 }
    }
}

/// The lights of one view, without allocation (every ray copies them).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ResolvedLights {
    items: [ResolvedSource; MAX_LIGHTS],
    len: usize,
}

impl ResolvedLights {
    pub fn as_slice(&self) -> &[ResolvedSource] {
        &self.items[..self.len]
    }

    /// One light.
    pub fn one(at: ResolvedLight) -> Self {
        let mut out = Self::default();
        out.items[0] = ResolvedSource {
            at,
            color: Vec3::ONE,
            ..ResolvedSource::default()
        };
        out.len = 1;
        out
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

/// One light's share of a shading computation, for the ray inspector.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct LightTerms {
    /// `N·L_i` (unclamped; the diffuse term uses `max(N·L_i, 0)`).
    pub n_dot_l: f32,
    /// `f_i` (1 for a directional light).
    pub attenuation: f32,
    /// f_i·I_i·kd·max(N·L_i,0)·c.
    pub diffuse: [f32; 3],
    /// f_i·I_i·ks·spec_i·h.
    pub specular: [f32; 3],
}

/// The terms of one shading computation, for the ray inspector.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct ShadeTerms {
    /// False where the gradient was below the threshold (the colour is left unshaded).
    pub lit: bool,
    pub normal: [f32; 3],
    /// ka·c (per channel).
    pub ambient: [f32; 3],
    /// Σ_i of the lights' diffuse terms.
    pub diffuse: [f32; 3],
    /// Σ_i of the lights' specular terms.
    pub specular: [f32; 3],
    /// Which highlight, and its tint h: 1 (white) or the sample's colour (Levoy's).
    pub highlight: Highlight,
    pub tint: [f32; 3],
    /// Each light's terms; the first [`ShadeTerms::light_count`] are used.
    #[serde(serialize_with = "serialize_lights")]
    pub lights: [LightTerms; MAX_LIGHTS],
    pub light_count: usize,
}

impl ShadeTerms {
    /// The used lights' terms.
    pub fn per_light(&self) -> &[LightTerms] {
        &self.lights[..self.light_count.min(MAX_LIGHTS)]
    }
}

fn serialize_lights<S: serde::Serializer>(
    lights: &[LightTerms; MAX_LIGHTS],
    s: S,
) -> Result<S::Ok, S::Error> {
    // Unused slots are written too, so the JSON keeps one shape; light_count says which count.
    serde::Serialize::serialize(&lights[..], s)
}

/// What shading needs about one ray: the direction to the viewer, the lights, and (for each
/// directional light) the Blinn half vector, which is the same for every sample of the ray.
/// Built for every ray, so it borrows the lights rather than copying them (a copy was a call
/// to `memcpy` a ray: about 2 % of the bunny's render).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viewing<'l> {
    /// Unit vector towards the viewer (minus the ray direction).
    pub view: Vec3,
    pub lights: &'l ResolvedLights,
    /// `normalize(L + V)` per directional light (`None` for point lights, or when L = −V).
    half: [Option<Vec3>; MAX_LIGHTS],
}

impl<'l> Viewing<'l> {
    pub fn new(view: Vec3, lights: &'l ResolvedLights) -> Self {
        let mut half = [None; MAX_LIGHTS];
        for (h, l) in half.iter_mut().zip(lights.as_slice()) {
            if let ResolvedLight::Toward(d) = l.at {
                *h = (d + view).try_normalize();
            }
        }
        Self { view, lights, half }
    }

    /// Light `i`'s Blinn half vector, if it is directional and not straight behind the viewer.
    pub fn half(&self, i: usize) -> Option<Vec3> {
        self.half.get(i).copied().flatten()
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
        highlight: k.highlight,
        tint: tint.to_array(),
        light_count: v.lights.len,
        ..ShadeTerms::default()
    };
    let (mut diffuse, mut specular) = (Vec3::ZERO, Vec3::ZERO);
    for (i, light) in v.lights.as_slice().iter().enumerate() {
        let (l, attenuation) = match light.at {
            ResolvedLight::Toward(l) => (l, 1.0),
            ResolvedLight::Point(pos) => {
                let to = pos - p_world;
                let d = to.length();
                (to.normalize_or(view), light.attenuation(d))
            }
        };
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
        let d = c * (light.color * (attenuation * k.kd * lambert));
        let s = tint * light.color * (attenuation * k.ks * spec);
        diffuse += d;
        specular += s;
        terms.lights[i] = LightTerms {
            n_dot_l,
            attenuation,
            diffuse: d.to_array(),
            specular: s.to_array(),
        };
    }
    let ambient = c * k.ka;
    let out = (ambient + diffuse + specular).clamp(Vec3::ZERO, Vec3::ONE);
    terms.ambient = ambient.to_array();
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
