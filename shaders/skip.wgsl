// Twin: crates/voxcast_core/src/skip.rs, skip/blocks.rs and skip/cells.rs (`EmptyBlocks`,
// `BlockRanges`, `VisibleCells`: `visible`, `brick_distance`, `leap_exit_at`), with
// `BlockWalk::exit` as `block_exit`, `EmptyBlocks::current` as `exit_if_empty` and
// `VisibleCells::lookup` as `brick_at`: blocks of cells the transfer
// function makes transparent (value ranges with a one-point apron) are crossed without
// sampling; once the cells' visibility is uploaded, a ray leaps out of the cube of empty
// bricks its brick's distance guarantees, and a sample in a cell the table makes transparent
// is not interpolated — exact, since such a sample would have had opacity 0. First, Maximum
// and Minimum pass blocks by their value ranges (see trace.wgsl).
// GPU-only: `block_of` (the core's walk carries its block's index from cell to cell; a GPU ray
// finds it from the cell), `block_range` (a texel of the ranges, where the core indexes
// `BlockRanges`) and `nearest_exit` (both exits' per-axis choice, which the core's loops make
// as they go).
#define_import_path voxcast::skip

#import voxcast::bindings::{params, empty_texture, range_texture, cells_texture}

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
    // The three axes at once, as in `leap_exit_at`.
    let up = vec3<f32>((b + vec3(1u)) * #{BLOCK}u);
    let down = vec3<f32>(b * #{BLOCK}u);
    return nearest_exit(down, b > vec3(0u), up, b + vec3(1u) < params.blocks, o_v, d_v);
}

/// The texel of the brick holding the cell with lower corner `lo`: its visibility word's two
/// halves and its distance.
fn brick_at(lo: vec3<u32>) -> vec4<u32> {
    return textureLoad(cells_texture, vec3<i32>(lo >> vec3(2u)), 0);
}

/// The distance of the brick holding cell `lo` (0 where it holds a visible cell).
fn brick_distance(brick: vec4<u32>) -> u32 {
    return brick.b;
}

/// Whether the cell with lower corner `lo` can be visible: its bit in its brick's word.
fn visible(lo: vec3<u32>, brick: vec4<u32>) -> bool {
    let bit = (lo.x & 3u) | ((lo.y & 3u) << 2u) | ((lo.z & 3u) << 4u);
    let half = select(brick.r, brick.g, bit >= 32u);
    return ((half >> (bit & 31u)) & 1u) != 0u;
}

/// For a sample in cell `lo` of a brick at `distance` > 0: the t where the ray (voxel-space
/// origin o_v, direction d_v, world-unit t) leaves the cube of bricks within `distance − 1` of
/// it, shrunk by the margin, through the faces it moves towards; faces on the volume's border
/// are infinitely far. (The core multiplies by the inverse direction; the margin covers the
/// rounding either way.)
fn leap_exit_at(lo: vec3<u32>, distance: u32, o_v: vec3<f32>, d_v: vec3<f32>) -> f32 {
    let b = lo >> vec3(2u);
    let reach = max(distance, 1u) - 1u;
    // The three axes at once, with no loop and no axis chosen by a variable (a rasterizer
    // that runs lanes in step pays every iteration and every dynamic pick): per axis the face
    // the ray moves towards, open unless it lies on the volume's border or the ray does not
    // move along the axis.
    let above = b + vec3(reach + 1u);
    let up = vec3<f32>(above * 4u) - params.brick_margin;
    let down = vec3<f32>((b - vec3(reach)) * 4u) + params.brick_margin;
    return nearest_exit(down, b > vec3(reach), up, above < params.bricks, o_v, d_v);
}

/// The nearest t (world units, 3.4e38 if none) at which the ray (voxel-space origin o_v,
/// direction d_v) meets, on each axis, the face it moves towards — `down` (voxel coordinate)
/// when it moves down the axis, `up` when up — counting a face only where it is open
/// (`down_open`, `up_open`) and the ray moves along the axis. Floats chosen by booleans only:
/// WebGL2's GLSL has no choice between boolean or integer vectors.
fn nearest_exit(
    down: vec3<f32>,
    down_open: vec3<bool>,
    up: vec3<f32>,
    up_open: vec3<bool>,
    o_v: vec3<f32>,
    d_v: vec3<f32>,
) -> f32 {
    let forward = d_v > vec3(0.0);
    let exits = (select(down, up, forward) - o_v) / d_v;
    let down_ok = select(vec3(0.0), vec3(1.0), down_open);
    let up_ok = select(vec3(0.0), vec3(1.0), up_open);
    let moving = select(vec3(0.0), vec3(1.0), d_v != vec3(0.0));
    let open = select(down_ok, up_ok, forward) * moving;
    let t = select(vec3(3.4e38), exits, open > vec3(0.5));
    return min(min(min(3.4e38, t.x), t.y), t.z);
}
