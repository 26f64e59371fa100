//! The uniform's tests: its layout against the WGSL, the variants, and the shaders compose.

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
    for (name, source) in crate::sandbox::gpu::shaders::SOURCES {
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
/// flag under each classification (so every branch is compiled in at least once), with and
/// without no-data voxels, with no light and with each number of lights up to the most.
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
        (0, CLASSIFY_TABLE, 0, 0, 0),
        (all_flags, CLASSIFY_ISO_CONTOURS, 1, 1, 1),
        (
            all_flags & !FLAG_BACK_TO_FRONT,
            CLASSIFY_BOUNDARIES,
            1,
            0,
            2,
        ),
        (all_flags, CLASSIFY_VALUE_GRADIENT, 0, 1, 3),
        (all_flags, CLASSIFY_TABLE, 1, 0, MAX_LIGHTS as u32),
    ];
    for method in Method::ALL {
        for (flags, classification, skip_empty, no_data, lights) in ways {
            module_for(PreviewVariant {
                method: method.code(),
                flags,
                classification,
                skip_empty,
                no_data,
                lights,
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
        no_data: 1,
        light_count: 2,
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
            no_data: 1,
            lights: 2,
        }
    );
    // What is not a switch (a step, a colour) does not make a new pipeline.
    let other_step = VolumeUniform { dt: 0.5, ..u };
    assert_eq!(PreviewVariant::of(&other_step), v);
}

/// A pipeline compiled for n lights shades with each of the n, once: `shade` calls `add_light`
/// once per light, each written out under `#if VARIANT_LIGHTS > i` (shaders/shade.wgsl), so a
/// larger `MAX_LIGHTS` without its call would leave the last lights dark on the GPU alone.
#[test]
fn a_pipeline_shades_with_each_of_its_lights_once() {
    fn calls_to(block: &naga::Block, target: naga::Handle<naga::Function>) -> usize {
        block
            .iter()
            .map(|statement| match statement {
                naga::Statement::Call { function, .. } => usize::from(*function == target),
                naga::Statement::Block(b) => calls_to(b, target),
                naga::Statement::If { accept, reject, .. } => {
                    calls_to(accept, target) + calls_to(reject, target)
                }
                naga::Statement::Loop {
                    body, continuing, ..
                } => calls_to(body, target) + calls_to(continuing, target),
                _ => 0,
            })
            .sum()
    }
    for lights in 0..=MAX_LIGHTS as u32 {
        let module = module_for(PreviewVariant {
            flags: FLAG_SHADING,
            lights,
            ..PreviewVariant::default()
        });
        let named = |name: &str| {
            module
                .functions
                .iter()
                .find(|(_, f)| f.name.as_deref().is_some_and(|n| n.starts_with(name)))
        };
        let (_, shade) = named("shade").expect("shade is compiled in");
        // With no light nothing calls `add_light`, and the composer leaves it out.
        let calls = named("add_light").map_or(0, |(h, _)| calls_to(&shade.body, h));
        assert_eq!(
            calls, lights as usize,
            "calls to add_light in a pipeline for {lights} lights"
        );
    }
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
fn lights_bytes(lights: &[LightUniform], (members, stride): (Vec<(String, u32)>, u32)) -> Vec<u8> {
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
