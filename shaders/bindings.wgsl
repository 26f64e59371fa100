// The preview's resources: the uniform, the volume as a 3-D texture read texel by texel (the
// core's exact trilinear weights, whatever the device's filtering precision; 8-bit data as
// R8Unorm, everything else as R32Float, which holds 16-bit integers exactly), and the baked
// transfer-function table (Rgba32Float, one row). Twin: src/sandbox/gpu/material.rs (`VolumeMaterial`).
#define_import_path voxcast::bindings

#import voxcast::types::VolumeUniform

@group(#{MATERIAL_BIND_GROUP}) @binding(0) var<uniform> params: VolumeUniform;
/// The pipeline's variant, compiled in (src/sandbox/gpu/uniform.rs, `PreviewVariant`): the uniform's
/// flags, method, classification, skip switch and no-data switch as constants (and the number of
/// lights, shade.wgsl), so each pipeline holds only the branches its settings take. The
/// uniform's own members carry the same values.
const FLAGS: u32 = #{VARIANT_FLAGS}u;
const METHOD: u32 = #{VARIANT_METHOD}u;
const CLASSIFICATION: u32 = #{VARIANT_CLASSIFICATION}u;
const SKIP_EMPTY: u32 = #{VARIANT_SKIP_EMPTY}u;
const NO_DATA: u32 = #{VARIANT_NO_DATA}u;
@group(#{MATERIAL_BIND_GROUP}) @binding(1) var volume_texture: texture_3d<f32>;
@group(#{MATERIAL_BIND_GROUP}) @binding(2) var lut_texture: texture_2d<f32>;
/// 1 for each block of cells the transfer function makes transparent (crates/voxcast_core/src/skip.rs).
@group(#{MATERIAL_BIND_GROUP}) @binding(3) var empty_texture: texture_3d<f32>;
/// Each block's value range (lo, hi) with a one-point apron, in data units
/// (crates/voxcast_core/src/skip.rs, `BlockRanges`).
@group(#{MATERIAL_BIND_GROUP}) @binding(4) var range_texture: texture_3d<f32>;
/// The cells that can be visible, a 4×4×4 brick a texel: its 64 bits in two halves (r, g) and
/// its distance in bricks to the nearest brick with a visible cell (b)
/// (crates/voxcast_core/src/skip.rs, `VisibleCells`).
@group(#{MATERIAL_BIND_GROUP}) @binding(5) var cells_texture: texture_3d<u32>;
/// Every lattice point's record: its differences along x, y, z and its raw value, exact
/// integers (crates/voxcast_core/src/sample.rs, `Differences`).
@group(#{MATERIAL_BIND_GROUP}) @binding(6) var records_texture: texture_3d<i32>;
