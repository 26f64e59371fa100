// Twin: crates/voxcast_core/src/sample.rs (`cell`, `lerp`, `sample_trilinear`, `nearest_index`,
// `sample_nearest`, `sample`, `lattice_differences`, `gradient`,
// `value_and_gradient_in_cell`) and volume.rs (`to_data`). Texels are read one by one with
// textureLoad and blended with the core's weights in the core's order (x, then y, then z), so the
// preview does not depend on a device's filtering precision.
// GPU-only: `is_no_data` and `no_data_at` (the core reads NaN and ±∞ as they are; WGSL need not
// keep NaN, so non-finite voxels are uploaded as the largest float and found so), `load_raw` and
// `load_record` (a texel read where the core indexes a slice), `gradient_blended` (`gradient`'s
// body: the core's non-finite result comes from a flag, as WGSL has no NaN to carry) and `mix4`
// (`lerp` on four lanes at once: a lattice record's differences and value).
#define_import_path voxcast::sample

#import voxcast::bindings::{params, volume_texture, records_texture, FLAGS, NO_DATA}

struct Cell {
    lo: vec3<u32>,
    hi: vec3<u32>,
    t: vec3<f32>,
}

/// Locates p_voxel in the lattice, clamped to it.
fn cell(p_voxel: vec3<f32>) -> Cell {
    let x = min(max(p_voxel, vec3(0.0)), params.last);
    let lo = min(vec3<u32>(x), params.max_lo);
    return Cell(lo, lo + params.corner_step, x - vec3<f32>(lo));
}

/// a + (b − a)·t, the one interpolation formula.
fn lerp(a: f32, b: f32, t: f32) -> f32 {
    return a + (b - a) * t;
}

/// Set by `lattice_differences` when a difference needs a lattice point that holds no data.
var<private> difference_undefined: bool;

/// Whether a raw texel holds no data: non-finite voxels are uploaded as the largest float
/// (src/sandbox/gpu/material.rs), above every value that is data. The core reads NaN and ±∞ as
/// they are; WGSL need not keep NaN, so the preview marks them so instead.
fn is_no_data(raw: f32) -> bool {
    return raw > params.no_data_above;
}

/// Whether the sample at p_voxel has no value: a corner of its cell (trilinear) or its
/// nearest lattice point holds no data — the core's non-finite interpolation.
fn no_data_at(p_voxel: vec3<f32>) -> bool {
    if NO_DATA == 0u {
        return false;
    }
    if (FLAGS & #{FLAG_TRILINEAR}u) == 0u {
        return is_no_data(load_raw(nearest_index(p_voxel)));
    }
    let c = cell(p_voxel);
    var any_missing = false;
    for (var i = 0u; i < 8u; i++) {
        // Component by component: WebGL2's GLSL has no select (mix) of integer vectors.
        let corner = vec3(
            select(c.lo.x, c.hi.x, (i & 1u) != 0u),
            select(c.lo.y, c.hi.y, (i & 2u) != 0u),
            select(c.lo.z, c.hi.z, (i & 4u) != 0u),
        );
        any_missing = any_missing || is_no_data(load_raw(corner));
    }
    return any_missing;
}

/// The raw value of one lattice point.
fn load_raw(i: vec3<u32>) -> f32 {
    return textureLoad(volume_texture, vec3<i32>(i), 0).r * params.raw_scale;
}

/// Raw units to data units: raw · slope + intercept.
fn to_data(raw: f32) -> f32 {
    return raw * params.slope + params.intercept;
}

/// Trilinear interpolation of the raw values at p_voxel.
fn sample_trilinear(p_voxel: vec3<f32>) -> f32 {
    let c = cell(p_voxel);
    let x00 = lerp(load_raw(c.lo), load_raw(vec3(c.hi.x, c.lo.y, c.lo.z)), c.t.x);
    let x10 = lerp(load_raw(vec3(c.lo.x, c.hi.y, c.lo.z)), load_raw(vec3(c.hi.x, c.hi.y, c.lo.z)), c.t.x);
    let x01 = lerp(load_raw(vec3(c.lo.x, c.lo.y, c.hi.z)), load_raw(vec3(c.hi.x, c.lo.y, c.hi.z)), c.t.x);
    let x11 = lerp(load_raw(vec3(c.lo.x, c.hi.y, c.hi.z)), load_raw(c.hi), c.t.x);
    return lerp(lerp(x00, x10, c.t.y), lerp(x01, x11, c.t.y), c.t.z);
}

/// The lattice point nearest to p_voxel (floor(x + ½), clamped).
fn nearest_index(p_voxel: vec3<f32>) -> vec3<u32> {
    return vec3<u32>(min(max(p_voxel + 0.5, vec3(0.0)), params.last));
}

fn sample_nearest(p_voxel: vec3<f32>) -> f32 {
    return load_raw(nearest_index(p_voxel));
}

/// The reconstructed raw value at p_voxel.
fn sample(p_voxel: vec3<f32>) -> f32 {
    if (FLAGS & #{FLAG_TRILINEAR}u) != 0u {
        return sample_trilinear(p_voxel);
    }
    return sample_nearest(p_voxel);
}

/// The raw differences along x, y and z at lattice index idx, per lattice step: central
/// inside, one-sided at the borders, zero on a one-point axis (the core's `lattice_difference`
/// for each axis). The three axes at once, with no axis chosen by a variable: a rasterizer that
/// runs lanes in step pays for every dynamic pick, and SwiftShader's Vulkan compiler stalled
/// for minutes on the per-axis version.
fn lattice_differences(idx: vec3<u32>) -> vec3<f32> {
    let lo = idx - min(idx, vec3(1u));
    let hi = min(idx + vec3(1u), vec3<u32>(params.last));
    let vp = vec3(
        load_raw(vec3(hi.x, idx.y, idx.z)),
        load_raw(vec3(idx.x, hi.y, idx.z)),
        load_raw(vec3(idx.x, idx.y, hi.z)),
    );
    let vm = vec3(
        load_raw(vec3(lo.x, idx.y, idx.z)),
        load_raw(vec3(idx.x, lo.y, idx.z)),
        load_raw(vec3(idx.x, idx.y, lo.z)),
    );
    let steps = hi - lo;
    if NO_DATA != 0u {
        let x = steps.x != 0u && (is_no_data(vp.x) || is_no_data(vm.x));
        let y = steps.y != 0u && (is_no_data(vp.y) || is_no_data(vm.y));
        let z = steps.z != 0u && (is_no_data(vp.z) || is_no_data(vm.z));
        if x || y || z {
            difference_undefined = true;
        }
    }
    let inv_steps = select(vec3(0.5), vec3(1.0), steps == vec3(1u));
    return select((vp - vm) * inv_steps, vec3(0.0), steps == vec3(0u));
}

/// The gradient at p_voxel in data units per world unit: lattice differences blended with the
/// trilinear weights in the same order as the value, scaled at the end; zero where a
/// difference needs a lattice point that holds no data (the core's non-finite gradient).
fn gradient(p_voxel: vec3<f32>) -> vec3<f32> {
    difference_undefined = false;
    let g = gradient_blended(p_voxel);
    if difference_undefined {
        return vec3(0.0);
    }
    return g;
}

fn gradient_blended(p_voxel: vec3<f32>) -> vec3<f32> {
    let scale = params.slope / params.spacing;
    if (FLAGS & #{FLAG_TRILINEAR}u) == 0u {
        return lattice_differences(nearest_index(p_voxel)) * scale;
    }
    let c = cell(p_voxel);
    let t = c.t;
    let g000 = lattice_differences(c.lo);
    let g100 = lattice_differences(vec3(c.hi.x, c.lo.y, c.lo.z));
    let g010 = lattice_differences(vec3(c.lo.x, c.hi.y, c.lo.z));
    let g110 = lattice_differences(vec3(c.hi.x, c.hi.y, c.lo.z));
    let g001 = lattice_differences(vec3(c.lo.x, c.lo.y, c.hi.z));
    let g101 = lattice_differences(vec3(c.hi.x, c.lo.y, c.hi.z));
    let g011 = lattice_differences(vec3(c.lo.x, c.hi.y, c.hi.z));
    let g111 = lattice_differences(c.hi);
    let x00 = g000 + (g100 - g000) * t.x;
    let x10 = g010 + (g110 - g010) * t.x;
    let x01 = g001 + (g101 - g001) * t.x;
    let x11 = g011 + (g111 - g011) * t.x;
    let y0 = x00 + (x10 - x00) * t.y;
    let y1 = x01 + (x11 - x01) * t.y;
    return (y0 + (y1 - y0) * t.z) * scale;
}

/// One lattice point's record as floats: differences x, y, z (not yet halved) and the raw value.
fn load_record(i: vec3<u32>) -> vec4<f32> {
    return vec4<f32>(textureLoad(records_texture, vec3<i32>(i), 0));
}

/// The raw value (w) and the gradient (xyz, data units per world unit) inside a located cell,
/// from the 8 corners' records: the same lerps as the value, x then y then z, four lanes at
/// once; the blend halved and scaled at the end, as the core does.
fn value_and_gradient_in_cell(c: Cell) -> vec4<f32> {
    let x00 = mix4(load_record(c.lo), load_record(vec3(c.hi.x, c.lo.y, c.lo.z)), c.t.x);
    let x10 = mix4(load_record(vec3(c.lo.x, c.hi.y, c.lo.z)), load_record(vec3(c.hi.x, c.hi.y, c.lo.z)), c.t.x);
    let x01 = mix4(load_record(vec3(c.lo.x, c.lo.y, c.hi.z)), load_record(vec3(c.hi.x, c.lo.y, c.hi.z)), c.t.x);
    let x11 = mix4(load_record(vec3(c.lo.x, c.hi.y, c.hi.z)), load_record(c.hi), c.t.x);
    let b = mix4(mix4(x00, x10, c.t.y), mix4(x01, x11, c.t.y), c.t.z);
    return vec4((b.xyz * 0.5) * (params.slope / params.spacing), b.w);
}

/// a + (b − a)·t for four lanes (`lerp` lane by lane).
fn mix4(a: vec4<f32>, b: vec4<f32>, t: f32) -> vec4<f32> {
    return a + (b - a) * t;
}
