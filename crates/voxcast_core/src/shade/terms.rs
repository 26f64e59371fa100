//! The terms of one shading computation, kept for the ray inspector and printed, with numbers,
//! by [`crate::explain::shading`].

use super::{Highlight, MAX_LIGHTS};

/// The coefficients a shading used, so its terms can be printed with the numbers that made
/// them.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Coefficients {
    pub ke: f32,
    pub ga: f32,
    pub ka: f32,
    pub kd: f32,
    pub ks: f32,
    pub shininess: f32,
    /// Levoy's depth cue 1/(k1 + k2·d).
    pub depth_k1: f32,
    pub depth_k2: f32,
}

/// One light's share of a shading computation.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct LightTerms {
    /// The light's colour I_i.
    pub color: [f32; 3],
    /// `N·L_i` (unclamped; the diffuse term uses `max(N·L_i, 0)`).
    pub n_dot_l: f32,
    /// Its falloff's terms kc, kl, kq (used by point and spot lights without depth cue).
    pub kc: f32,
    pub kl: f32,
    pub kq: f32,
    /// Whether it stands somewhere (a point or spot light), so it falls off with distance.
    pub positional: bool,
    /// The distance `d` its falloff was computed from: to the light (point and spot lights), or
    /// from the picture plane (Levoy's depth cue); 0 where nothing falls off.
    pub distance: f32,
    /// `f_i` (1 for a directional light without depth cue).
    pub attenuation: f32,
    /// Whether the light is a spot light.
    pub spotlight: bool,
    /// The spotlight factor `s_i` (1 for any other light).
    pub spot: f32,
    /// `spec_i = max(N·H_i, 0)^n` or `max(R_i·V, 0)^n` (0 where `N·L_i ≤ 0`).
    pub spec: f32,
    /// The light's ambient intensity I_a,i.
    pub ambient_color: [f32; 3],
    /// f_i·s_i·I_a,i·ka·c.
    pub ambient: [f32; 3],
    /// f_i·s_i·I_i·kd·max(N·L_i,0)·c.
    pub diffuse: [f32; 3],
    /// f_i·s_i·I_i·ks·spec_i·h.
    pub specular: [f32; 3],
}

/// The terms of one shading computation, for the ray inspector.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct ShadeTerms {
    /// False where the gradient was below the threshold (the colour is left unshaded).
    pub lit: bool,
    pub normal: [f32; 3],
    /// The coefficients used.
    pub k: Coefficients,
    /// Whether Levoy's depth cue set each light's falloff (from the picture plane).
    pub depth_cue: bool,
    /// M_e = ke·c.
    pub emission: [f32; 3],
    /// G_a·M_a = G_a·ka·c (per channel).
    pub ambient: [f32; 3],
    /// Σ_i of the lights' ambient terms.
    pub light_ambient: [f32; 3],
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

    /// Whether any of the lecture's terms beyond Voxcast's default form is on: emission, a
    /// global ambient other than 1, a light's own ambient, a spot's cone or the depth cue.
    pub fn full_form(&self) -> bool {
        self.k.ke != 0.0
            || self.k.ga != 1.0
            || self.depth_cue
            || self
                .per_light()
                .iter()
                .any(|l| l.ambient != [0.0; 3] || l.spotlight)
    }

    /// How many lights reach the sample: it faces them (`N·L_i > 0`) and their falloff and
    /// spotlight factor leave something (`f_i·s_i > 0`), so their diffuse term is theirs to
    /// give. A light behind the surface, or a spot whose cone misses it, shades nothing here.
    pub fn lights_reaching(&self) -> usize {
        if !self.lit {
            return 0;
        }
        self.per_light()
            .iter()
            .filter(|l| l.n_dot_l > 0.0 && l.attenuation * l.spot > 0.0)
            .count()
    }
}

fn serialize_lights<S: serde::Serializer>(
    lights: &[LightTerms; MAX_LIGHTS],
    s: S,
) -> Result<S::Ok, S::Error> {
    // Unused slots are written too, so the JSON keeps one shape; light_count says which count.
    serde::Serialize::serialize(&lights[..], s)
}
