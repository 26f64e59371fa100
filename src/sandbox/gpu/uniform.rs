//! The preview's uniform: the core's resolved scene in the layout `shaders/types.wgsl` declares,
//! and every constant the shaders use, defined here and passed as shader defs.
//!
//! Twin: `shaders/types.wgsl` (`VolumeUniform`); a test checks each member's offset.

use bevy::math::{UVec3, Vec3, Vec4};
use bevy::render::render_resource::ShaderType;
use bevy::shader::ShaderDefVal;
use voxcast_core::camera::ImageRays;
use voxcast_core::classify::Classifier;
use voxcast_core::composite::{Method, Order};
use voxcast_core::sample::Interpolation;
use voxcast_core::shade::{Cone, Highlight, MAX_LIGHTS, ResolvedLight, SpecularModel};
use voxcast_core::trace::Scene;
use voxcast_core::transfer::LUT_SIZE;

/// Bit flags of [`VolumeUniform::flags`].
pub const FLAG_OPACITY_CORRECTION: u32 = 1;
pub const FLAG_EARLY_TERMINATION: u32 = 2;
pub const FLAG_JITTER: u32 = 4;
pub const FLAG_SHADING: u32 = 8;
pub const FLAG_TRILINEAR: u32 = 16;
pub const FLAG_TWO_SIDED: u32 = 32;
pub const FLAG_BLINN_PHONG: u32 = 64;
pub const FLAG_BACK_TO_FRONT: u32 = 128;
pub const FLAG_LEVOY_HIGHLIGHT: u32 = 256;
/// The cells' visibility is uploaded for the current table: Accumulate's skipping leaves out
/// the samples in cells it makes transparent (set by `state`, not by the settings).
pub const FLAG_SKIP_CELLS: u32 = 512;
/// The lattice records are uploaded: Accumulate reads a sample's value and gradient from them
/// (set by `state`, not by the settings).
pub const FLAG_RECORDS: u32 = 1024;
/// Levoy's depth cue sets every light's falloff from the picture plane.
pub const FLAG_DEPTH_CUE: u32 = 2048;

/// Light kinds of [`LightUniform::kind`].
pub const LIGHT_POINT: u32 = 0;
pub const LIGHT_TOWARD: u32 = 1;
/// A point light with a cone.
pub const LIGHT_SPOT: u32 = 2;

/// Classification codes of [`VolumeUniform::classification`].
pub const CLASSIFY_TABLE: u32 = 0;
pub const CLASSIFY_ISO_CONTOURS: u32 = 1;
pub const CLASSIFY_BOUNDARIES: u32 = 2;
pub const CLASSIFY_VALUE_GRADIENT: u32 = 3;

/// The most isovalues the preview classifies with: the core refuses more.
pub use voxcast_core::classify::{MAX_ISOVALUES, MAX_REGIONS};

/// What a preview pipeline is compiled for: the uniform's members that choose which code runs
/// (the method, the flags, the classification, the skip switch, whether the volume holds
/// voxels with no data, the number of lights), compiled in as constants
/// (`shaders/bindings.wgsl`). Each combination a session uses is compiled once and kept (Bevy
/// caches pipelines), so a frame runs only the branches its settings take; changing one of
/// these settings compiles a pipeline (once) instead of branching in every sample.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct PreviewVariant {
    pub method: u32,
    pub flags: u32,
    pub classification: u32,
    pub skip_empty: u32,
    /// 1 where the volume has voxels with no data (each sample then checks its corners).
    pub no_data: u32,
    /// How many lights shine: each light's share is called with its index written out
    /// (`shaders/shade.wgsl`), as SwiftShader reads a uniform's array lane by lane where the index
    /// is a loop's variable (a fifth of the bunny's frame there, BENCHMARKS.md).
    pub lights: u32,
}

impl PreviewVariant {
    /// The variant the uniform's members call for.
    pub fn of(u: &VolumeUniform) -> Self {
        Self {
            method: u.method,
            flags: u.flags,
            classification: u.classification,
            skip_empty: u.skip_empty,
            no_data: u.no_data,
            lights: u.light_count,
        }
    }
}

/// Every constant the WGSL uses, with the pipeline's `variant`, as shader defs.
pub fn shader_defs(variant: PreviewVariant) -> Vec<ShaderDefVal> {
    let mut defs: Vec<ShaderDefVal> = vec![
        ShaderDefVal::UInt("VARIANT_FLAGS".into(), variant.flags),
        ShaderDefVal::UInt("VARIANT_METHOD".into(), variant.method),
        ShaderDefVal::UInt("VARIANT_CLASSIFICATION".into(), variant.classification),
        ShaderDefVal::UInt("VARIANT_SKIP_EMPTY".into(), variant.skip_empty),
        ShaderDefVal::UInt("VARIANT_NO_DATA".into(), variant.no_data),
        ShaderDefVal::UInt("VARIANT_LIGHTS".into(), variant.lights),
        ShaderDefVal::UInt("LUT_SIZE".into(), LUT_SIZE as u32),
        ShaderDefVal::UInt("BLOCK".into(), voxcast_core::skip::BLOCK as u32),
        ShaderDefVal::UInt("FLAG_OPACITY_CORRECTION".into(), FLAG_OPACITY_CORRECTION),
        ShaderDefVal::UInt("FLAG_EARLY_TERMINATION".into(), FLAG_EARLY_TERMINATION),
        ShaderDefVal::UInt("FLAG_JITTER".into(), FLAG_JITTER),
        ShaderDefVal::UInt("FLAG_SHADING".into(), FLAG_SHADING),
        ShaderDefVal::UInt("FLAG_TRILINEAR".into(), FLAG_TRILINEAR),
        ShaderDefVal::UInt("FLAG_TWO_SIDED".into(), FLAG_TWO_SIDED),
        ShaderDefVal::UInt("FLAG_BLINN_PHONG".into(), FLAG_BLINN_PHONG),
        ShaderDefVal::UInt("FLAG_BACK_TO_FRONT".into(), FLAG_BACK_TO_FRONT),
        ShaderDefVal::UInt("FLAG_LEVOY_HIGHLIGHT".into(), FLAG_LEVOY_HIGHLIGHT),
        ShaderDefVal::UInt("FLAG_SKIP_CELLS".into(), FLAG_SKIP_CELLS),
        ShaderDefVal::UInt("FLAG_RECORDS".into(), FLAG_RECORDS),
        ShaderDefVal::UInt("FLAG_DEPTH_CUE".into(), FLAG_DEPTH_CUE),
        ShaderDefVal::UInt("MAX_LIGHTS".into(), MAX_LIGHTS as u32),
        ShaderDefVal::UInt("LIGHT_POINT".into(), LIGHT_POINT),
        ShaderDefVal::UInt("LIGHT_TOWARD".into(), LIGHT_TOWARD),
        ShaderDefVal::UInt("LIGHT_SPOT".into(), LIGHT_SPOT),
        ShaderDefVal::UInt("CLASSIFY_TABLE".into(), CLASSIFY_TABLE),
        ShaderDefVal::UInt("CLASSIFY_ISO_CONTOURS".into(), CLASSIFY_ISO_CONTOURS),
        ShaderDefVal::UInt("CLASSIFY_BOUNDARIES".into(), CLASSIFY_BOUNDARIES),
        ShaderDefVal::UInt("CLASSIFY_VALUE_GRADIENT".into(), CLASSIFY_VALUE_GRADIENT),
        ShaderDefVal::UInt("MAX_REGIONS".into(), MAX_REGIONS as u32),
    ];
    for m in Method::ALL {
        defs.push(ShaderDefVal::UInt(
            format!("METHOD_{}", m.name().to_uppercase()),
            m.code(),
        ));
    }
    defs
}

/// The preview's uniform (see `shaders/types.wgsl` for each member's meaning).
#[derive(Clone, Debug, Default, PartialEq, ShaderType)]
pub struct VolumeUniform {
    /// The volume's box after the crop box (world units).
    pub crop_lo: Vec3,
    pub dt: f32,
    pub crop_hi: Vec3,
    pub dt_ref: f32,
    pub inv_spacing: Vec3,
    pub cutoff: f32,
    pub spacing: Vec3,
    pub target_value: f32,
    pub last: Vec3,
    pub slope: f32,
    pub max_lo: UVec3,
    pub intercept: f32,
    pub corner_step: UVec3,
    pub lut_lo: f32,
    pub lut_scale: f32,
    pub raw_scale: f32,
    pub method: u32,
    pub flags: u32,
    pub refine_steps: u32,
    pub max_samples: u32,
    pub jitter_seed: u32,
    pub light_count: u32,
    pub classification: u32,
    pub iso_count: u32,
    pub ka: f32,
    pub kd: f32,
    pub ks: f32,
    pub shininess: f32,
    pub gradient_threshold: f32,
    pub iso_r: f32,
    pub inv_full_gradient: f32,
    pub background: Vec3,
    pub depth_termination: u32,
    pub iso_values: Vec4,
    pub iso_alphas: Vec4,
    pub cam_eye: Vec3,
    pub cam_perspective: u32,
    pub cam_right: Vec3,
    pub cam_inv_width: f32,
    pub cam_up: Vec3,
    pub cam_inv_height: f32,
    pub cam_forward: Vec3,
    pub skip_empty: u32,
    pub blocks: UVec3,
    pub skip_margin: f32,
    /// 1 where First, Maximum and Minimum may pass blocks by their value ranges.
    pub skip_ranges: u32,
    /// 1 where a block that can only tie the running extreme may be passed (integer data).
    pub ties_skippable: u32,
    /// 1 when some voxels hold no data.
    pub no_data: u32,
    /// Raw texels above this hold no data (see `material::volume_image`).
    pub no_data_above: f32,
    /// Rays per pixel side (n×n rays averaged per pixel).
    pub supersampling: u32,
    /// Sum's range: sums from `sum_lo` to `sum_hi` are stretched over the table.
    pub sum_lo: f32,
    pub sum_hi: f32,
    /// The clip plane keeps `clip_normal·p ≤ clip_d`; a zero normal keeps all.
    pub clip_normal: Vec3,
    pub clip_d: f32,
    /// Bricks of 4×4×4 cells per axis of the cells texture (`VisibleCells::bricks`).
    pub bricks: UVec3,
    /// How far inside the cube of empty bricks (voxels) a leap stops (`BRICK_MARGIN`).
    pub brick_margin: f32,
    /// Emission ke, global ambient G_a and Levoy's depth cue k1, k2 (`Phong`'s).
    pub ke: f32,
    pub global_ambient: f32,
    pub depth_kc: f32,
    pub depth_kl: f32,
    /// The value-and-gradient rectangles: how many, their opacities, and each one's
    /// `[value lo, value hi, gradient lo, gradient hi]`.
    pub region_count: u32,
    pub region_opacity: Vec4,
    pub regions: [Vec4; MAX_REGIONS],
    /// The lights; the first `light_count` shine.
    pub lights: [LightUniform; MAX_LIGHTS],
}

/// One light (see `LightUniform` in `shaders/types.wgsl`).
#[derive(Clone, Copy, Debug, Default, PartialEq, ShaderType)]
pub struct LightUniform {
    pub at: Vec3,
    pub kind: u32,
    pub color: Vec3,
    pub kc: f32,
    pub ambient: Vec3,
    pub kl: f32,
    pub spot_along: Vec3,
    pub kq: f32,
    pub spot_cos_cutoff: f32,
    pub spot_exponent: f32,
}

impl VolumeUniform {
    /// The uniform for `scene` (whose light is already resolved for the view) seen through
    /// `rays`, the core camera's rays for the preview's image.
    pub fn from_scene(scene: &Scene<'_>, rays: &ImageRays, depth_termination: bool) -> Self {
        let v = scene.volume;
        let s = &scene.settings;
        let dims = v.dims();
        let (slope, intercept) = v.rescale();
        let mut flags = 0;
        for (on, bit) in [
            (s.opacity_correction, FLAG_OPACITY_CORRECTION),
            (s.early_termination, FLAG_EARLY_TERMINATION),
            (s.jitter, FLAG_JITTER),
            (s.shading, FLAG_SHADING),
            (s.interpolation == Interpolation::Trilinear, FLAG_TRILINEAR),
            (s.phong.two_sided, FLAG_TWO_SIDED),
            (s.phong.model == SpecularModel::BlinnPhong, FLAG_BLINN_PHONG),
            (s.order == Order::BackToFront, FLAG_BACK_TO_FRONT),
            (s.phong.highlight == Highlight::Levoy, FLAG_LEVOY_HIGHLIGHT),
            (s.phong.depth_cue, FLAG_DEPTH_CUE),
        ] {
            if on {
                flags |= bit;
            }
        }
        let mut lights = [LightUniform::default(); MAX_LIGHTS];
        for (u, l) in lights.iter_mut().zip(scene.lights.as_slice()) {
            let (kind, at) = match (l.at, l.cone) {
                (ResolvedLight::Point(p), Some(_)) => (LIGHT_SPOT, p),
                (ResolvedLight::Point(p), None) => (LIGHT_POINT, p),
                (ResolvedLight::Toward(d), _) => (LIGHT_TOWARD, d),
            };
            let cone = l.cone.unwrap_or(Cone {
                along: Vec3::NEG_Z,
                cos_cutoff: -1.0,
                exponent: 0.0,
            });
            *u = LightUniform {
                at,
                kind,
                color: l.color,
                kc: l.kc,
                ambient: l.ambient,
                kl: l.kl,
                spot_along: cone.along,
                kq: l.kq,
                spot_cos_cutoff: cone.cos_cutoff,
                spot_exponent: cone.exponent,
            };
        }
        let mut u = Self {
            crop_lo: scene.clip.lo,
            dt: scene.dt,
            crop_hi: scene.clip.hi,
            dt_ref: scene.dt_ref,
            inv_spacing: 1.0 / v.spacing(),
            cutoff: s.cutoff,
            spacing: v.spacing(),
            target_value: scene.target,
            last: (dims - 1).as_vec3(),
            slope,
            max_lo: dims.saturating_sub(UVec3::splat(2)),
            intercept,
            corner_step: UVec3::from(dims.to_array().map(|n| (n > 1) as u32)),
            lut_lo: scene.lut.lo,
            lut_scale: scene.lut.scale,
            raw_scale: if v.scalar_type() == voxcast_core::volume::ScalarType::U8 {
                255.0
            } else {
                1.0
            },
            method: s.method.code(),
            flags,
            refine_steps: s.refine_steps,
            max_samples: s.max_samples,
            jitter_seed: s.jitter_seed,
            light_count: scene.lights.as_slice().len() as u32,
            classification: CLASSIFY_TABLE,
            iso_count: 0,
            ka: s.phong.ka,
            kd: s.phong.kd,
            ks: s.phong.ks,
            shininess: s.phong.shininess,
            gradient_threshold: s.phong.gradient_threshold,
            iso_r: 0.0,
            inv_full_gradient: 0.0,
            background: s.background,
            depth_termination: depth_termination as u32,
            iso_values: Vec4::ZERO,
            iso_alphas: Vec4::ZERO,
            cam_eye: rays.eye,
            cam_perspective: rays.perspective as u32,
            cam_right: rays.right,
            cam_inv_width: rays.inv_size.0,
            cam_up: rays.up,
            cam_inv_height: rays.inv_size.1,
            cam_forward: rays.forward,
            skip_empty: 0,
            blocks: UVec3::ONE,
            skip_margin: voxcast_core::trace::SKIP_MARGIN_VOXELS,
            skip_ranges: 0,
            ties_skippable: 0,
            no_data: (v.no_data_count() > 0) as u32,
            no_data_above: v.raw_value_range().1,
            supersampling: s.supersampling.max(1),
            sum_lo: scene.sum_range.0,
            sum_hi: scene.sum_range.1,
            clip_normal: scene.clip.normal,
            clip_d: scene.clip.d,
            bricks: UVec3::from_array(
                voxcast_core::skip::brick_count(v.dims().to_array().map(|n| n as usize))
                    .map(|b| b as u32),
            ),
            brick_margin: voxcast_core::skip::BRICK_MARGIN,
            ke: s.phong.ke,
            global_ambient: s.phong.global_ambient,
            depth_kc: s.phong.depth_kc,
            depth_kl: s.phong.depth_kl,
            region_count: 0,
            region_opacity: Vec4::ZERO,
            regions: [Vec4::ZERO; MAX_REGIONS],
            lights,
        };
        match &scene.classifier {
            Classifier::Table => {}
            Classifier::IsoContours { isovalues, r } => {
                u.classification = CLASSIFY_ISO_CONTOURS;
                u.iso_count = isovalues.len().min(MAX_ISOVALUES) as u32;
                for (i, &(value, alpha)) in isovalues.iter().take(MAX_ISOVALUES).enumerate() {
                    u.iso_values[i] = value;
                    u.iso_alphas[i] = alpha;
                }
                u.iso_r = *r;
            }
            Classifier::Boundaries { inv_full_gradient } => {
                u.classification = CLASSIFY_BOUNDARIES;
                u.inv_full_gradient = *inv_full_gradient;
            }
            Classifier::ValueGradient { regions } => {
                u.classification = CLASSIFY_VALUE_GRADIENT;
                u.region_count = regions.len().min(MAX_REGIONS) as u32;
                for (i, r) in regions.iter().take(MAX_REGIONS).enumerate() {
                    let ([f0, f1], [g0, g1]) = (r.value, r.gradient);
                    u.regions[i] = Vec4::new(f0, f1, g0, g1);
                    u.region_opacity[i] = r.opacity;
                }
            }
        }
        u
    }
}

#[cfg(test)]
mod tests;
