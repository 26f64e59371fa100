// Twin: crates/voxcast_core/src/transfer.rs (`Lut::locate`, `Lut::lookup`), both in
// `Lut::lookup` as `lut_lookup`: the same baked table, read entry by entry and interpolated
// linearly.
#define_import_path voxcast::transfer

#import voxcast::bindings::{params, lut_texture}

/// Colour (rgb) and opacity (a) of a value in data units.
fn lut_lookup(value: f32) -> vec4<f32> {
    let last = f32(#{LUT_SIZE}u - 1u);
    let x = min(max((value - params.lut_lo) * params.lut_scale, 0.0), last);
    let i = min(u32(x), #{LUT_SIZE}u - 2u);
    let t = x - f32(i);
    let a = textureLoad(lut_texture, vec2<i32>(i32(i), 0), 0);
    let b = textureLoad(lut_texture, vec2<i32>(i32(i) + 1, 0), 0);
    return a + (b - a) * t;
}
