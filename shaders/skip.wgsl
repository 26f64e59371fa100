// Twin: crates/voxcast_core/src/skip.rs (`EmptyBlocks`, `BlockRanges`, `BlockWalk::exit`):
// blocks of cells the transfer function makes transparent (value ranges with a one-point
// apron) are crossed without sampling — exact, since a skipped sample would have had opacity 0.
// First, Maximum and Minimum pass blocks by their value ranges (see trace.wgsl).
#define_import_path voxcast::skip

#import voxcast::bindings::{params, empty_texture, range_texture}

/// The block holding the cell with lower corner `cell_lo`.
fn block_of(cell_lo: vec3<u32>) -> vec3<u32> {
    return min(cell_lo / #{BLOCK}u, params.blocks - vec3(1u));
}

/// If that block is empty, the t where the ray leaves it (see `block_exit`); else a negative
/// number.
fn exit_if_empty(b: vec3<u32>, o_v: vec3<f32>, d_v: vec3<f32>) -> f32 {
    if textureLoad(empty_texture, vec3<i32>(b), 0).r < 0.5 {
        return -1.0;
    }
    return block_exit(b, o_v, d_v);
}

/// The block's value range (lo, hi), apron included.
fn block_range(b: vec3<u32>) -> vec2<f32> {
    return textureLoad(range_texture, vec3<i32>(b), 0).rg;
}

/// The t where the ray (voxel-space origin o_v, direction d_v, for world-unit t) leaves block
/// b. Border blocks extend outwards.
fn block_exit(b: vec3<u32>, o_v: vec3<f32>, d_v: vec3<f32>) -> f32 {
    var t_exit = 3.4e38;
    for (var a = 0; a < 3; a++) {
        let d = d_v[a];
        if d > 0.0 && b[a] + 1u < params.blocks[a] {
            t_exit = min(t_exit, (f32((b[a] + 1u) * #{BLOCK}u) - o_v[a]) / d);
        } else if d < 0.0 && b[a] > 0u {
            t_exit = min(t_exit, (f32(b[a] * #{BLOCK}u) - o_v[a]) / d);
        }
    }
    return t_exit;
}
