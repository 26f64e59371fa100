// Twin: src/sandbox/gpu/uniform.rs (`VolumeUniform`) and the conventions in crates/voxcast_core/src/lib.rs.
//
// Conventions (as in the core): voxel (i, j, k) sits at world (i·sx, j·sy, k·sz); the box spans
// [0, (n−1)·s] (one spacing of thickness around a one-point axis); voxel space is world space
// divided by the spacing; distances t along a ray are world units, directions unit length;
// colours are linear floats in [0, 1], accumulated colour premultiplied by opacity.
// Rust owns this layout: a test checks every member's offset against the Rust struct.
#define_import_path voxcast::types

/// One light of the scene, as the core's `ResolvedSource`.
struct LightUniform {
    /// A point or spot light's position, or the unit direction towards a directional light.
    at: vec3<f32>,
    /// LIGHT_POINT, LIGHT_TOWARD or LIGHT_SPOT.
    kind: u32,
    /// Colour and intensity I (linear RGB).
    color: vec3<f32>,
    /// Attenuation 1/(kc + kl·d + kq·d²) of a point or spot light at distance d.
    kc: f32,
    /// The light's own ambient intensity I_a (its colour times its ambient share).
    ambient: vec3<f32>,
    kl: f32,
    /// A spot light's unit direction (the way it shines), as the core's `Cone`.
    spot_along: vec3<f32>,
    kq: f32,
    /// The cosine of a spot light's cutoff angle, and its exponent.
    spot_cos_cutoff: f32,
    spot_exponent: f32,
}

struct VolumeUniform {
    /// The volume's box after the crop box (world units; see clip.wgsl).
    crop_lo: vec3<f32>,
    dt: f32,
    crop_hi: vec3<f32>,
    dt_ref: f32,
    inv_spacing: vec3<f32>,
    cutoff: f32,
    spacing: vec3<f32>,
    target_value: f32,
    /// n − 1 per axis, as floats (for clamping positions onto the lattice).
    last: vec3<f32>,
    slope: f32,
    /// max(n − 2, 0) per axis: the largest lower cell corner.
    max_lo: vec3<u32>,
    intercept: f32,
    /// 1 where an axis has more than one point, else 0.
    corner_step: vec3<u32>,
    lut_lo: f32,
    lut_scale: f32,
    /// Raw units per texel value: 255 for 8-bit data stored as R8Unorm, else 1.
    raw_scale: f32,
    method: u32,
    flags: u32,
    refine_steps: u32,
    max_samples: u32,
    jitter_seed: u32,
    /// How many of `lights` shine (0 … MAX_LIGHTS); compiled into the pipeline too, as
    /// VARIANT_LIGHTS, which shade.wgsl reads.
    light_count: u32,
    classification: u32,
    iso_count: u32,
    ka: f32,
    kd: f32,
    ks: f32,
    shininess: f32,
    gradient_threshold: f32,
    iso_r: f32,
    inv_full_gradient: f32,
    background: vec3<f32>,
    /// 1 to stop rays at opaque scene geometry (the depth prepass), else 0.
    depth_termination: u32,
    iso_values: vec4<f32>,
    iso_alphas: vec4<f32>,
    /// The camera's rays, as the core's `ImageRays`: eye, right and up scaled to half the view,
    /// forward, 1/width and 1/height of the image, and 1 for perspective.
    cam_eye: vec3<f32>,
    cam_perspective: u32,
    cam_right: vec3<f32>,
    cam_inv_width: f32,
    cam_up: vec3<f32>,
    cam_inv_height: f32,
    cam_forward: vec3<f32>,
    /// 1 where Accumulate may skip empty blocks (see skip.wgsl), else 0.
    skip_empty: u32,
    /// Blocks per axis of the empty-block texture.
    blocks: vec3<u32>,
    /// How far inside an empty block (voxels) a sample must lie to be skipped.
    skip_margin: f32,
    /// 1 where First, Maximum and Minimum may pass blocks by their value ranges, else 0.
    skip_ranges: u32,
    /// 1 where a block that can only tie the running extreme may be passed (integer data).
    ties_skippable: u32,
    /// 1 when some voxels hold no data (non-finite floats), else 0; compiled into the pipeline
    /// too, as NO_DATA (bindings.wgsl), which sample.wgsl reads.
    no_data: u32,
    /// Raw texels above this hold no data (the largest finite raw value; see sample.wgsl).
    no_data_above: f32,
    /// Rays per pixel side: n×n rays averaged per pixel (1: one through the centre).
    supersampling: u32,
    /// Sum's range: sums from sum_lo to sum_hi are stretched over the table.
    sum_lo: f32,
    sum_hi: f32,
    /// The clip plane keeps the points p with clip_normal·p ≤ clip_d; a zero normal keeps all.
    clip_normal: vec3<f32>,
    clip_d: f32,
    /// Bricks of 4×4×4 cells per axis of the cells texture (see skip.wgsl).
    bricks: vec3<u32>,
    /// How far inside the cube of empty bricks (voxels) a leap stops.
    brick_margin: f32,
    /// Emission ke, global ambient G_a, and Levoy's depth cue 1/(k1 + k2·d) (see shade.wgsl).
    ke: f32,
    global_ambient: f32,
    depth_kc: f32,
    depth_kl: f32,
    /// The value-and-gradient rectangles (classify.wgsl): how many, each one's opacity, and
    /// each one's [value lo, value hi, gradient lo, gradient hi].
    region_count: u32,
    region_opacity: vec4<f32>,
    regions: array<vec4<f32>, #{MAX_REGIONS}>,
    /// The lights (shade.wgsl sums over the first light_count, VARIANT_LIGHTS).
    lights: array<LightUniform, #{MAX_LIGHTS}>,
}
