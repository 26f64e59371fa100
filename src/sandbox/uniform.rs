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
/// (the method, the flags, the classification, the skip switch), compiled in as constants
/// (`shaders/bindings.wgsl`). Each combination a session uses is compiled once and kept (Bevy
/// caches pipelines), so a frame runs only the branches its settings take; changing one of
/// these settings compiles a pipeline (once) instead of branching in every sample.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct PreviewVariant {
    pub method: u32,
    pub flags: u32,
    pub classification: u32,
    pub skip_empty: u32,
}

impl PreviewVariant {
    /// The variant the uniform's members call for.
    pub fn of(u: &VolumeUniform) -> Self {
        Self {
            method: u.method,
            flags: u.flags,
            classification: u.classification,
            skip_empty: u.skip_empty,
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
mod tests {
    //! The WGSL is composed and validated with naga (no GPU), and the uniform's layout in WGSL
    //! is checked member by member against the Rust struct's encoding.
    use super::*;
    use bevy::render::render_resource::encase::UniformBuffer;
    use naga_oil::compose::{
        ComposableModuleDescriptor, Composer, NagaModuleDescriptor, ShaderDefValue,
    };
    use std::collections::HashMap;

    fn defs_for(variant: PreviewVariant) -> HashMap<String, ShaderDefValue> {
        let mut map: HashMap<String, ShaderDefValue> = shader_defs(variant)
            .into_iter()
            .map(|d| match d {
                ShaderDefVal::UInt(name, v) => (name, ShaderDefValue::UInt(v)),
                ShaderDefVal::Int(name, v) => (name, ShaderDefValue::Int(v)),
                ShaderDefVal::Bool(name, v) => (name, ShaderDefValue::Bool(v)),
            })
            .collect();
        map.insert("MATERIAL_BIND_GROUP".into(), ShaderDefValue::UInt(3));
        map
    }

    /// Every library module composed and a fragment entry that traces one ray, validated.
    fn module() -> naga::Module {
        module_for(PreviewVariant::default())
    }

    fn module_for(variant: PreviewVariant) -> naga::Module {
        let mut composer = Composer::default();
        // Dependencies first.
        for (name, source) in crate::sandbox::shaders::SOURCES {
            if *name == "volume.wgsl" {
                continue; // imports Bevy's view bindings; exercised on a GPU by tests/agreement.rs
            }
            let added = composer.add_composable_module(ComposableModuleDescriptor {
                source,
                file_path: name,
                shader_defs: defs_for(variant),
                ..Default::default()
            });
            if let Err(e) = added {
                panic!("{name}: {}", e.emit_to_string(&composer));
            }
        }
        let entry = "#import voxcast::trace::trace\n\
            @fragment fn main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {\n\
                return trace(vec3(0.0), vec3(0.0, 0.0, 1.0), 3.4e38, vec2<u32>(p.xy));\n\
            }\n";
        let module = composer
            .make_naga_module(NagaModuleDescriptor {
                source: entry,
                file_path: "entry.wgsl",
                shader_defs: defs_for(variant),
                ..Default::default()
            })
            .unwrap_or_else(|e| panic!("{}", e.emit_to_string(&composer)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("invalid WGSL: {e:?}"));
        module
    }

    #[test]
    fn the_wgsl_composes_and_validates() {
        module();
    }

    /// The pipeline variants compose and validate: each method with no flag, and with every
    /// flag under each classification (so every branch is compiled in at least once).
    #[test]
    fn every_variant_composes_and_validates() {
        let all_flags = FLAG_OPACITY_CORRECTION
            | FLAG_EARLY_TERMINATION
            | FLAG_JITTER
            | FLAG_SHADING
            | FLAG_TRILINEAR
            | FLAG_TWO_SIDED
            | FLAG_BLINN_PHONG
            | FLAG_BACK_TO_FRONT
            | FLAG_LEVOY_HIGHLIGHT
            | FLAG_SKIP_CELLS
            | FLAG_RECORDS
            | FLAG_DEPTH_CUE;
        let ways = [
            (0, CLASSIFY_TABLE, 0),
            (all_flags, CLASSIFY_ISO_CONTOURS, 1),
            (all_flags & !FLAG_BACK_TO_FRONT, CLASSIFY_BOUNDARIES, 1),
            (all_flags, CLASSIFY_VALUE_GRADIENT, 0),
        ];
        for method in Method::ALL {
            for (flags, classification, skip_empty) in ways {
                module_for(PreviewVariant {
                    method: method.code(),
                    flags,
                    classification,
                    skip_empty,
                });
            }
        }
    }

    /// The variant is the uniform's own switches, so the pipeline compiled for a material is
    /// the one its settings call for.
    #[test]
    fn the_variant_follows_the_settings() {
        let u = VolumeUniform {
            method: Method::Maximum.code(),
            flags: FLAG_SHADING | FLAG_RECORDS,
            classification: CLASSIFY_BOUNDARIES,
            skip_empty: 1,
            dt: 0.25,
            ..VolumeUniform::default()
        };
        let v = PreviewVariant::of(&u);
        assert_eq!(
            v,
            PreviewVariant {
                method: Method::Maximum.code(),
                flags: FLAG_SHADING | FLAG_RECORDS,
                classification: CLASSIFY_BOUNDARIES,
                skip_empty: 1,
            }
        );
        // What is not a switch (a step, a colour) does not make a new pipeline.
        let other_step = VolumeUniform { dt: 0.5, ..u };
        assert_eq!(PreviewVariant::of(&other_step), v);
    }

    /// Bytes of one member of `u`, by its WGSL name.
    fn member_bytes(u: &VolumeUniform, name: &str) -> Vec<u8> {
        let f = |v: f32| v.to_le_bytes().to_vec();
        let n = |v: u32| v.to_le_bytes().to_vec();
        let v3 = |v: Vec3| v.to_array().iter().flat_map(|x| x.to_le_bytes()).collect();
        let u3 = |v: UVec3| v.to_array().iter().flat_map(|x| x.to_le_bytes()).collect();
        let v4 = |v: Vec4| v.to_array().iter().flat_map(|x| x.to_le_bytes()).collect();
        match name {
            "crop_lo" => v3(u.crop_lo),
            "dt" => f(u.dt),
            "crop_hi" => v3(u.crop_hi),
            "dt_ref" => f(u.dt_ref),
            "inv_spacing" => v3(u.inv_spacing),
            "cutoff" => f(u.cutoff),
            "spacing" => v3(u.spacing),
            "target_value" => f(u.target_value),
            "last" => v3(u.last),
            "slope" => f(u.slope),
            "max_lo" => u3(u.max_lo),
            "intercept" => f(u.intercept),
            "corner_step" => u3(u.corner_step),
            "lut_lo" => f(u.lut_lo),
            "lut_scale" => f(u.lut_scale),
            "raw_scale" => f(u.raw_scale),
            "method" => n(u.method),
            "flags" => n(u.flags),
            "refine_steps" => n(u.refine_steps),
            "max_samples" => n(u.max_samples),
            "jitter_seed" => n(u.jitter_seed),
            "light_count" => n(u.light_count),
            "classification" => n(u.classification),
            "iso_count" => n(u.iso_count),
            "ka" => f(u.ka),
            "kd" => f(u.kd),
            "ks" => f(u.ks),
            "shininess" => f(u.shininess),
            "gradient_threshold" => f(u.gradient_threshold),
            "iso_r" => f(u.iso_r),
            "inv_full_gradient" => f(u.inv_full_gradient),
            "background" => v3(u.background),
            "depth_termination" => n(u.depth_termination),
            "iso_values" => v4(u.iso_values),
            "iso_alphas" => v4(u.iso_alphas),
            "cam_eye" => v3(u.cam_eye),
            "cam_perspective" => n(u.cam_perspective),
            "cam_right" => v3(u.cam_right),
            "cam_inv_width" => f(u.cam_inv_width),
            "cam_up" => v3(u.cam_up),
            "cam_inv_height" => f(u.cam_inv_height),
            "cam_forward" => v3(u.cam_forward),
            "skip_empty" => n(u.skip_empty),
            "blocks" => u3(u.blocks),
            "skip_margin" => f(u.skip_margin),
            "skip_ranges" => n(u.skip_ranges),
            "ties_skippable" => n(u.ties_skippable),
            "no_data" => n(u.no_data),
            "no_data_above" => f(u.no_data_above),
            "supersampling" => n(u.supersampling),
            "sum_lo" => f(u.sum_lo),
            "sum_hi" => f(u.sum_hi),
            "clip_normal" => v3(u.clip_normal),
            "clip_d" => f(u.clip_d),
            "bricks" => u3(u.bricks),
            "brick_margin" => f(u.brick_margin),
            "ke" => f(u.ke),
            "global_ambient" => f(u.global_ambient),
            "depth_kc" => f(u.depth_kc),
            "depth_kl" => f(u.depth_kl),
            "region_count" => n(u.region_count),
            "region_opacity" => v4(u.region_opacity),
            "regions" => u.regions.iter().flat_map(|r| v4(*r)).collect(),
            "lights" => lights_bytes(&u.lights, light_layout()),
            other => panic!("WGSL member {other} has no Rust twin"),
        }
    }

    /// The WGSL's light struct: each member's name and offset, and the array's stride.
    fn light_layout() -> (Vec<(String, u32)>, u32) {
        let module = module();
        let members = module
            .types
            .iter()
            .find_map(|(_, t)| match (&t.name, &t.inner) {
                (Some(name), naga::TypeInner::Struct { members, .. })
                    if name.contains("LightUniform") =>
                {
                    Some(members.clone())
                }
                _ => None,
            })
            .expect("LightUniform in the WGSL");
        let stride = module
            .types
            .iter()
            .find_map(|(_, t)| match t.inner {
                naga::TypeInner::Array { stride, .. } if stride >= 32 => Some(stride),
                _ => None,
            })
            .expect("the lights' array");
        let names = members
            .iter()
            .map(|m| (m.name.clone().unwrap(), m.offset))
            .collect();
        (names, stride)
    }

    /// The bytes the WGSL expects for `lights`, laid out by its own offsets and stride (the
    /// padding left as zeros, as encase writes it).
    fn lights_bytes(
        lights: &[LightUniform],
        (members, stride): (Vec<(String, u32)>, u32),
    ) -> Vec<u8> {
        let mut out = vec![0u8; stride as usize * lights.len()];
        for (i, l) in lights.iter().enumerate() {
            for (name, offset) in &members {
                let bytes: Vec<u8> = match name.as_str() {
                    "at" => {
                        l.at.to_array()
                            .iter()
                            .flat_map(|x| x.to_le_bytes())
                            .collect()
                    }
                    "kind" => l.kind.to_le_bytes().to_vec(),
                    "color" => l
                        .color
                        .to_array()
                        .iter()
                        .flat_map(|x| x.to_le_bytes())
                        .collect(),
                    "kc" => l.kc.to_le_bytes().to_vec(),
                    "ambient" => l
                        .ambient
                        .to_array()
                        .iter()
                        .flat_map(|x| x.to_le_bytes())
                        .collect(),
                    "kl" => l.kl.to_le_bytes().to_vec(),
                    "spot_along" => l
                        .spot_along
                        .to_array()
                        .iter()
                        .flat_map(|x| x.to_le_bytes())
                        .collect(),
                    "kq" => l.kq.to_le_bytes().to_vec(),
                    "spot_cos_cutoff" => l.spot_cos_cutoff.to_le_bytes().to_vec(),
                    "spot_exponent" => l.spot_exponent.to_le_bytes().to_vec(),
                    other => panic!("WGSL light member {other} has no Rust twin"),
                };
                let at = i * stride as usize + *offset as usize;
                out[at..at + bytes.len()].copy_from_slice(&bytes);
            }
        }
        out
    }

    #[test]
    fn the_uniform_layout_matches_the_wgsl() {
        let module = module();
        let (members, span) = module
            .types
            .iter()
            .find_map(|(_, t)| match (&t.name, &t.inner) {
                (Some(name), naga::TypeInner::Struct { members, span })
                    if name.contains("VolumeUniform") =>
                {
                    Some((members.clone(), *span))
                }
                _ => None,
            })
            .expect("VolumeUniform in the WGSL");
        // Every member gets a distinct value, so a misplaced one cannot pass.
        let mut counter = 0.0f32;
        let mut next = || {
            counter += 1.0;
            counter
        };
        let u = VolumeUniform {
            crop_lo: Vec3::new(next(), next(), next()),
            dt: next(),
            crop_hi: Vec3::new(next(), next(), next()),
            dt_ref: next(),
            inv_spacing: Vec3::new(next(), next(), next()),
            cutoff: next(),
            spacing: Vec3::new(next(), next(), next()),
            target_value: next(),
            last: Vec3::new(next(), next(), next()),
            slope: next(),
            max_lo: UVec3::new(101, 102, 103),
            intercept: next(),
            corner_step: UVec3::new(104, 105, 106),
            lut_lo: next(),
            lut_scale: next(),
            raw_scale: next(),
            method: 107,
            flags: 108,
            refine_steps: 109,
            max_samples: 110,
            jitter_seed: 111,
            light_count: 112,
            classification: 113,
            iso_count: 114,
            ka: next(),
            kd: next(),
            ks: next(),
            shininess: next(),
            gradient_threshold: next(),
            iso_r: next(),
            inv_full_gradient: next(),
            background: Vec3::new(next(), next(), next()),
            depth_termination: 115,
            iso_values: Vec4::new(next(), next(), next(), next()),
            iso_alphas: Vec4::new(next(), next(), next(), next()),
            cam_eye: Vec3::new(next(), next(), next()),
            cam_perspective: 116,
            cam_right: Vec3::new(next(), next(), next()),
            cam_inv_width: next(),
            cam_up: Vec3::new(next(), next(), next()),
            cam_inv_height: next(),
            cam_forward: Vec3::new(next(), next(), next()),
            skip_empty: 117,
            blocks: UVec3::new(118, 119, 120),
            skip_margin: next(),
            skip_ranges: 121,
            ties_skippable: 122,
            no_data: 123,
            no_data_above: next(),
            supersampling: 124,
            sum_lo: next(),
            sum_hi: next(),
            clip_normal: Vec3::new(next(), next(), next()),
            clip_d: next(),
            bricks: UVec3::new(125, 126, 127),
            brick_margin: next(),
            ke: next(),
            global_ambient: next(),
            depth_kc: next(),
            depth_kl: next(),
            region_count: 128,
            region_opacity: Vec4::new(next(), next(), next(), next()),
            regions: std::array::from_fn(|_| Vec4::new(next(), next(), next(), next())),
            lights: std::array::from_fn(|i| LightUniform {
                at: Vec3::new(next(), next(), next()),
                kind: 130 + i as u32,
                color: Vec3::new(next(), next(), next()),
                kc: next(),
                ambient: Vec3::new(next(), next(), next()),
                kl: next(),
                spot_along: Vec3::new(next(), next(), next()),
                kq: next(),
                spot_cos_cutoff: next(),
                spot_exponent: next(),
            }),
        };
        let mut buffer = UniformBuffer::new(Vec::<u8>::new());
        buffer.write(&u).unwrap();
        let bytes = buffer.into_inner();
        assert_eq!(
            bytes.len() as u32,
            span,
            "the Rust encoding and the WGSL struct differ in size"
        );
        assert_eq!(members.len(), 64, "members in the WGSL struct");
        for m in &members {
            let name = m.name.as_deref().unwrap();
            let expect = member_bytes(&u, name);
            let at = m.offset as usize;
            assert_eq!(
                &bytes[at..at + expect.len()],
                &expect[..],
                "member {name} at offset {at}"
            );
        }
    }
}
