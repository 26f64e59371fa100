//! The volume material: the uniform, the volume texture and the transfer-function table bound for
//! `shaders/volume.wgsl`, drawn on the back faces of the volume's box with no depth test or
//! write, so the camera may be inside the box and opaque scene geometry stops the rays through
//! the depth prepass instead.

use crate::sandbox::gpu::uniform::{PreviewVariant, VolumeUniform, shader_defs};
use bevy::asset::{RenderAssetUsages, uuid_handle};
use bevy::mesh::MeshVertexBufferLayoutRef;
use bevy::pbr::{MaterialPipeline, MaterialPipelineKey};
use bevy::prelude::*;
use bevy::render::render_resource::{
    AsBindGroup, CompareFunction, Extent3d, Face, RenderPipelineDescriptor,
    SpecializedMeshPipelineError, TextureDimension, TextureFormat,
};
use bevy::shader::ShaderRef;
use voxcast_core::Volume;
use voxcast_core::skip::{BlockRanges, EmptyBlocks, VisibleCells};
use voxcast_core::transfer::Lut;
use voxcast_core::volume::{Grid, GridVisitor, ScalarType, Voxel};

/// The fragment shader, `shaders/volume.wgsl`, registered under this handle.
pub const VOLUME_SHADER: Handle<Shader> = uuid_handle!("6a1c3e0e-4f0f-4b8e-9a3a-2f4e0d1c7b55");

/// The preview's material; its pipeline is compiled for the uniform's [`PreviewVariant`].
#[derive(Asset, TypePath, AsBindGroup, Clone, Debug)]
#[bind_group_data(PreviewVariant)]
pub struct VolumeMaterial {
    #[uniform(0)]
    pub uniform: VolumeUniform,
    #[texture(1, dimension = "3d", sample_type = "float", filterable = false)]
    pub volume: Handle<Image>,
    #[texture(2, sample_type = "float", filterable = false)]
    pub lut: Handle<Image>,
    #[texture(3, dimension = "3d", sample_type = "float", filterable = false)]
    pub empty: Handle<Image>,
    #[texture(4, dimension = "3d", sample_type = "float", filterable = false)]
    pub ranges: Handle<Image>,
    #[texture(5, dimension = "3d", sample_type = "u_int")]
    pub cells: Handle<Image>,
    #[texture(6, dimension = "3d", sample_type = "s_int")]
    pub records: Handle<Image>,
}

impl From<&VolumeMaterial> for PreviewVariant {
    fn from(material: &VolumeMaterial) -> Self {
        PreviewVariant::of(&material.uniform)
    }
}

impl Material for VolumeMaterial {
    fn fragment_shader() -> ShaderRef {
        ShaderRef::Handle(VOLUME_SHADER)
    }

    fn alpha_mode(&self) -> AlphaMode {
        AlphaMode::Premultiplied
    }

    fn enable_prepass() -> bool {
        false
    }

    fn enable_shadows() -> bool {
        false
    }

    fn specialize(
        _pipeline: &MaterialPipeline,
        descriptor: &mut RenderPipelineDescriptor,
        _layout: &MeshVertexBufferLayoutRef,
        key: MaterialPipelineKey<Self>,
    ) -> Result<(), SpecializedMeshPipelineError> {
        descriptor.primitive.cull_mode = Some(Face::Front);
        if let Some(depth) = descriptor.depth_stencil.as_mut() {
            depth.depth_write_enabled = Some(false);
            depth.depth_compare = Some(CompareFunction::Always);
        }
        if let Some(fragment) = descriptor.fragment.as_mut() {
            fragment
                .shader_defs
                .extend(shader_defs(key.bind_group_data));
        }
        Ok(())
    }
}

/// A 3-D texture of `size` texels holding `data` in `format`, for the render world only.
fn texture_3d(size: [u32; 3], data: Vec<u8>, format: TextureFormat) -> Image {
    Image::new(
        Extent3d {
            width: size[0],
            height: size[1],
            depth_or_array_layers: size[2],
        },
        TextureDimension::D3,
        data,
        format,
        RenderAssetUsages::RENDER_WORLD,
    )
}

/// What a voxel with no data is stored as in the volume texture (see [`volume_image`]).
pub const NO_DATA_TEXEL: f32 = f32::MAX;

/// The volume as a 3-D texture: 8-bit data as R8Unorm, 16-bit integers and floats as R32Float
/// (which holds every 16-bit integer exactly).
pub fn volume_image(volume: &Volume) -> Image {
    struct Texels;
    impl GridVisitor for Texels {
        type Output = (TextureFormat, Vec<u8>);
        fn visit<T: Voxel>(self, g: Grid<'_, T>) -> Self::Output {
            if T::TYPE == ScalarType::U8 {
                let bytes = g.data.iter().map(|v| v.to_f32() as u8).collect();
                (TextureFormat::R8Unorm, bytes)
            } else {
                // A voxel with no data (NaN, ±∞) is stored as the largest float, above every
                // value that is data: the shader tests for it (`is_no_data`), as WGSL need not
                // keep NaN or infinities.
                let bytes = g
                    .data
                    .iter()
                    .map(|v| v.to_f32())
                    .map(|v| if v.is_finite() { v } else { NO_DATA_TEXEL })
                    .flat_map(f32::to_le_bytes)
                    .collect();
                (TextureFormat::R32Float, bytes)
            }
        }
    }
    let (format, data) = volume.visit(Texels);
    texture_3d(volume.dims().to_array(), data, format)
}

/// Which blocks are empty (1) as an R8Unorm 3-D texture; one texel when there is no skipping.
pub fn empty_blocks_image(blocks: Option<&EmptyBlocks>) -> Image {
    let (dims, data) = match blocks {
        Some(b) => (
            b.blocks(),
            b.flags()
                .iter()
                .map(|&e| if e { 255u8 } else { 0 })
                .collect(),
        ),
        None => ([1, 1, 1], vec![0u8]),
    };
    texture_3d(dims.map(|d| d as u32), data, TextureFormat::R8Unorm)
}

/// The cells that can be visible (`VisibleCells`), a brick of 4×4×4 cells a texel: its 64-bit
/// word as two halves (low bits in red, high in green) and the brick's distance to the nearest
/// brick with a visible cell (blue; what a ray leaps by) of an Rgba32Uint 3-D texture; one
/// clear texel when the preview does not skip cells.
pub fn visible_cells_image(cells: Option<&VisibleCells>) -> Image {
    let (dims, data) = match cells {
        Some(c) => (
            c.bricks(),
            c.words()
                .iter()
                .zip(c.distances())
                .flat_map(|(&w, &d)| [w as u32, (w >> 32) as u32, u32::from(d), 0])
                .flat_map(u32::to_le_bytes)
                .collect(),
        ),
        None => ([1, 1, 1], vec![0u8; 16]),
    };
    texture_3d(dims.map(|d| d as u32), data, TextureFormat::Rgba32Uint)
}

/// The most bytes the lattice records may take on the GPU (8 a lattice point): 256 MiB, a
/// 320³ volume; a larger one computes its gradients from the volume texture.
pub const MAX_RECORD_BYTES: usize = 256 << 20;

/// Every lattice point's record (`voxcast_core::sample::Differences`: the differences along x,
/// y and z and the raw value, exact integers) as an Rgba16Sint 3-D texture the size of the
/// volume, so a shaded sample reads its value and gradient from its cell's 8 texels, as the
/// core does; one clear texel when there are none.
pub fn records_image(records: Option<(&[voxcast_core::sample::Differences], UVec3)>) -> Image {
    let (dims, data) = match records {
        Some((r, dims)) => (
            dims,
            r.iter()
                .flat_map(|d| d.map(i16::to_le_bytes))
                .flatten()
                .collect(),
        ),
        None => (UVec3::ONE, vec![0u8; 8]),
    };
    texture_3d(dims.to_array(), data, TextureFormat::Rgba16Sint)
}

/// Each block's value range `(lo, hi)` (data units, apron included) as an Rg32Float 3-D
/// texture, for First, Maximum and Minimum to pass blocks by.
pub fn block_ranges_image(ranges: &BlockRanges) -> Image {
    let data = ranges
        .ranges
        .iter()
        .flat_map(|&(lo, hi)| [lo, hi])
        .flat_map(f32::to_le_bytes)
        .collect();
    texture_3d(ranges.blocks.to_array(), data, TextureFormat::Rg32Float)
}

/// The baked transfer function as one row of Rgba32Float texels.
pub fn lut_image(lut: &Lut) -> Image {
    let data = lut
        .entries
        .iter()
        .flat_map(|e| e.to_array())
        .flat_map(f32::to_le_bytes)
        .collect();
    Image::new(
        Extent3d {
            width: lut.entries.len() as u32,
            height: 1,
            depth_or_array_layers: 1,
        },
        TextureDimension::D2,
        data,
        TextureFormat::Rgba32Float,
        RenderAssetUsages::RENDER_WORLD | RenderAssetUsages::MAIN_WORLD,
    )
}
