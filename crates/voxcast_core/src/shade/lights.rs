//! The lights of the illumination model: where each one is (headlight, point, directional or
//! spot), its colour, its own ambient share, its falloff with distance and a spot's cone — and
//! the same lights resolved for one view, as every ray copies them.

use super::power;
use glam::Vec3;

/// The most lights a scene has: the GPU's uniform holds this many (`shaders/types.wgsl`), and
/// the settings refuse more.
pub const MAX_LIGHTS: usize = 4;

/// A spot light's cone: a point light that shines only within `cutoff` degrees of `direction`,
/// brightest along it (OpenGL's spot light; the lecture's spotlight factor s_i).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct Spot {
    /// Where the light stands (world units).
    pub position: Vec3,
    /// The direction the spot shines along (any length but zero).
    pub direction: Vec3,
    /// [`crate::tunables::SPOT_CUTOFF`], degrees.
    pub cutoff: f32,
    /// [`crate::tunables::SPOT_EXPONENT`].
    pub exponent: f32,
}

impl Default for Spot {
    fn default() -> Self {
        use crate::tunables as t;
        Self {
            position: Vec3::ZERO,
            direction: Vec3::NEG_Z,
            cutoff: t::SPOT_CUTOFF.default,
            exponent: t::SPOT_EXPONENT.default,
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
    /// A point light whose light leaves in a cone only ([`Spot`]); attenuated with distance.
    Spot(Spot),
}

impl Light {
    /// Resolves a headlight with the camera's forward direction.
    pub fn resolve(self, camera_forward: Vec3) -> ResolvedLight {
        match self {
            Light::Headlight => ResolvedLight::Toward(-camera_forward.normalize_or(Vec3::NEG_Z)),
            Light::Point(p) => ResolvedLight::Point(p),
            Light::Spot(s) => ResolvedLight::Point(s.position),
            Light::Directional(d) => ResolvedLight::Toward(-d.normalize_or(Vec3::NEG_Z)),
        }
    }

    /// Words for the interface.
    pub fn kind_label(self) -> &'static str {
        match self {
            Light::Headlight => "headlight",
            Light::Point(_) => "point",
            Light::Directional(_) => "directional",
            Light::Spot(_) => "spot",
        }
    }

    /// Where it stands, for a light that has a place (point and spot lights).
    pub fn position(self) -> Option<Vec3> {
        match self {
            Light::Point(p) => Some(p),
            Light::Spot(s) => Some(s.position),
            Light::Headlight | Light::Directional(_) => None,
        }
    }

    /// Whether it stands somewhere, so its light falls off with distance (point and spot).
    pub fn positional(self) -> bool {
        self.position().is_some()
    }
}

/// One light: where it is, its colour, its ambient share, and its attenuation (which only
/// point and spot lights use; see [`crate::tunables`] for each term's documentation).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct LightSource {
    pub light: Light,
    /// Colour and intensity I_i (linear RGB).
    pub color: Vec3,
    /// [`crate::tunables::LIGHT_AMBIENT`]: the light's ambient intensity I_a,i as a share of
    /// its colour.
    pub ambient: f32,
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
            ambient: t::LIGHT_AMBIENT.default,
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

    /// Whether its light falls off with distance (a point or spot light with kl or kq above
    /// zero).
    pub fn attenuated(&self) -> bool {
        self.light.positional() && (self.kl > 0.0 || self.kq > 0.0)
    }
}

/// A light resolved for one view: either a position or the unit direction *towards* the light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ResolvedLight {
    Point(Vec3),
    Toward(Vec3),
}

/// A spot's cone resolved: the unit direction it shines along, the cosine of its cutoff and
/// its exponent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    pub along: Vec3,
    pub cos_cutoff: f32,
    pub exponent: f32,
}

impl Cone {
    /// The spotlight factor s for a sample whose unit direction to the light is `l`:
    /// `max(−L·D, 0)^e` inside the cone (angle to the axis at most the cutoff), 0 outside.
    #[inline(always)]
    pub fn factor(&self, l: Vec3) -> f32 {
        let cos = -l.dot(self.along);
        if cos >= self.cos_cutoff {
            power(cos.max(0.0), self.exponent)
        } else {
            0.0
        }
    }
}

/// One light resolved for a view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResolvedSource {
    pub at: ResolvedLight,
    pub color: Vec3,
    /// I_a,i: the light's colour times its ambient share.
    pub ambient: Vec3,
    pub kc: f32,
    pub kl: f32,
    pub kq: f32,
    /// A spot light's cone (`at` is then its position).
    pub cone: Option<Cone>,
}

impl Default for ResolvedSource {
    fn default() -> Self {
        Self {
            at: ResolvedLight::Toward(Vec3::Z),
            color: Vec3::ZERO,
            ambient: Vec3::ZERO,
            kc: 1.0,
            kl: 0.0,
            kq: 0.0,
            cone: None,
        }
    }
}

impl ResolvedSource {
    /// `1/(kc + kl·d + kq·d²)` at distance `d` (1 where that is not positive).
    #[inline(always)]
    pub fn attenuation(&self, d: f32) -> f32 {
        let denom = self.kc + self.kl * d + self.kq * d * d;
        if denom > 0.0 { 1.0 / denom } else { 1.0 }
    }

    /// `light` resolved for a camera looking along `camera_forward`.
    pub fn new(l: &LightSource, camera_forward: Vec3) -> Self {
        Self {
            at: l.light.resolve(camera_forward),
            color: l.color,
            ambient: l.color * l.ambient,
            kc: l.kc,
            kl: l.kl,
            kq: l.kq,
            cone: match l.light {
                Light::Spot(s) => Some(Cone {
                    along: s.direction.normalize_or(Vec3::NEG_Z),
                    cos_cutoff: s.cutoff.to_radians().cos(),
                    exponent: s.exponent,
                }),
                _ => None,
            },
        }
    }
}

/// The lights of one view, without allocation (every ray copies them), and the view's forward
/// direction (the picture plane's normal, for Levoy's depth cue).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResolvedLights {
    pub(super) items: [ResolvedSource; MAX_LIGHTS],
    pub(super) len: usize,
    /// The camera's unit forward direction.
    pub forward: Vec3,
}

impl Default for ResolvedLights {
    fn default() -> Self {
        Self {
            items: [ResolvedSource::default(); MAX_LIGHTS],
            len: 0,
            forward: Vec3::NEG_Z,
        }
    }
}

impl ResolvedLights {
    pub fn as_slice(&self) -> &[ResolvedSource] {
        &self.items[..self.len]
    }

    /// Up to [`MAX_LIGHTS`] of `lights` resolved for a camera looking along `camera_forward`.
    pub fn new(lights: &[LightSource], camera_forward: Vec3) -> Self {
        let mut out = Self {
            forward: camera_forward.normalize_or(Vec3::NEG_Z),
            ..Self::default()
        };
        for l in lights.iter().take(MAX_LIGHTS) {
            out.items[out.len] = ResolvedSource::new(l, camera_forward);
            out.len += 1;
        }
        out
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_spot_lights_its_cone_only_brightest_on_its_axis() {
        let cone = ResolvedSource::new(
            &LightSource::new(Light::Spot(Spot {
                position: Vec3::new(0.0, 0.0, 10.0),
                direction: Vec3::new(0.0, 0.0, -2.0),
                cutoff: 30.0,
                exponent: 2.0,
            })),
            Vec3::NEG_Z,
        )
        .cone
        .unwrap();
        // On the axis: the sample's direction to the light is +z, the spot shines along −z.
        assert_eq!(cone.factor(Vec3::Z), 1.0);
        // 20° off the axis: cos² 20°.
        let at = |deg: f32| Vec3::new(deg.to_radians().sin(), 0.0, deg.to_radians().cos());
        let want = 20f32.to_radians().cos().powi(2);
        assert!((cone.factor(at(20.0)) - want).abs() < 1e-6);
        // Beyond the cutoff and behind the light: none.
        assert_eq!(cone.factor(at(31.0)), 0.0);
        assert_eq!(cone.factor(Vec3::NEG_Z), 0.0);
    }

    #[test]
    fn a_spot_resolves_to_its_position_and_falls_off_as_a_point_light() {
        let spot = Light::Spot(Spot {
            position: Vec3::ONE,
            ..Spot::default()
        });
        assert_eq!(spot.resolve(Vec3::Z), ResolvedLight::Point(Vec3::ONE));
        let l = LightSource {
            kl: 0.5,
            ..LightSource::new(spot)
        };
        assert!(l.attenuated());
        assert_eq!(spot.kind_label(), "spot");
    }

    #[test]
    fn a_lights_ambient_is_its_colour_times_its_share() {
        let l = LightSource {
            color: Vec3::new(1.0, 0.5, 0.0),
            ambient: 0.4,
            ..LightSource::default()
        };
        let r = ResolvedSource::new(&l, Vec3::Z);
        assert_eq!(r.ambient, Vec3::new(0.4, 0.2, 0.0));
    }
}
