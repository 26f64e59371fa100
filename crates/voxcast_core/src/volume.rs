//! The voxel grid: scalar values on a regular lattice, held once in their native type.
//!
//! A CT scan stores 16-bit Hounsfield units, an MRI 8- or 16-bit intensities, a simulation 32-bit
//! floats. [`Volume`] keeps each in its own type ([`VoxelData`]) — an 8-bit grid costs one byte a
//! voxel, never a float copy — and the samplers are generic over [`Voxel`], so each type gets its
//! own compiled hot loop. Values reach the rest of the pipeline as `f32` *data units*:
//! `raw · slope + intercept` (NIfTI's `scl_slope`/`scl_inter`; identity for other formats).
//!
//! Where values sit and what box the volume spans is written down once, in the crate docs
//! ([`crate`]): voxel `(i, j, k)` at `(i·sx, j·sy, k·sz)`, box `[0, (n−1)·s]`.

use crate::error::VolumeError;
use glam::{UVec3, Vec3};

/// The scalar types a volume can hold natively.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ScalarType {
    U8,
    I16,
    U16,
    F32,
}

impl ScalarType {
    /// Bytes one value occupies.
    pub const fn bytes(self) -> usize {
        match self {
            Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::F32 => 4,
        }
    }

    /// The Open SciVis / NumPy style name (`uint8`, `int16`, `uint16`, `float32`).
    pub const fn name(self) -> &'static str {
        match self {
            Self::U8 => "uint8",
            Self::I16 => "int16",
            Self::U16 => "uint16",
            Self::F32 => "float32",
        }
    }
}

/// A scalar type a volume can be made of. Sealed to the four [`ScalarType`]s.
pub trait Voxel: Copy + Send + Sync + 'static + private::Sealed {
    const TYPE: ScalarType;
    /// For integer types: `(offset, count)` such that `raw + offset` indexes a table of `count`
    /// entries covering every value of the type. `None` for floats.
    const TABLE: Option<(i32, usize)>;
    fn to_f32(self) -> f32;
}

mod private {
    pub trait Sealed {}
    impl Sealed for u8 {}
    impl Sealed for i16 {}
    impl Sealed for u16 {}
    impl Sealed for f32 {}
}

impl Voxel for u8 {
    const TYPE: ScalarType = ScalarType::U8;
    const TABLE: Option<(i32, usize)> = Some((0, 1 << 8));
    #[inline(always)]
    fn to_f32(self) -> f32 {
        self as f32
    }
}
impl Voxel for i16 {
    const TYPE: ScalarType = ScalarType::I16;
    const TABLE: Option<(i32, usize)> = Some((1 << 15, 1 << 16));
    #[inline(always)]
    fn to_f32(self) -> f32 {
        self as f32
    }
}
impl Voxel for u16 {
    const TYPE: ScalarType = ScalarType::U16;
    const TABLE: Option<(i32, usize)> = Some((0, 1 << 16));
    #[inline(always)]
    fn to_f32(self) -> f32 {
        self as f32
    }
}
impl Voxel for f32 {
    const TYPE: ScalarType = ScalarType::F32;
    const TABLE: Option<(i32, usize)> = None;
    #[inline(always)]
    fn to_f32(self) -> f32 {
        self
    }
}

/// The values of a volume in their native type, x fastest.
#[derive(Clone, Debug, PartialEq)]
pub enum VoxelData {
    U8(Vec<u8>),
    I16(Vec<i16>),
    U16(Vec<u16>),
    F32(Vec<f32>),
}

impl VoxelData {
    pub fn len(&self) -> usize {
        match self {
            Self::U8(v) => v.len(),
            Self::I16(v) => v.len(),
            Self::U16(v) => v.len(),
            Self::F32(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn scalar_type(&self) -> ScalarType {
        match self {
            Self::U8(_) => ScalarType::U8,
            Self::I16(_) => ScalarType::I16,
            Self::U16(_) => ScalarType::U16,
            Self::F32(_) => ScalarType::F32,
        }
    }

    /// The raw value at a linear index, as `f32` (no rescale).
    pub fn raw_f32(&self, index: usize) -> f32 {
        match self {
            Self::U8(v) => v[index] as f32,
            Self::I16(v) => v[index] as f32,
            Self::U16(v) => v[index] as f32,
            Self::F32(v) => v[index],
        }
    }
}

/// A borrowed, typed view of a volume: what the samplers and the ray marcher work on.
#[derive(Clone, Copy, Debug)]
pub struct Grid<'a, T: Voxel> {
    pub data: &'a [T],
    /// Lattice points per axis.
    pub dims: [usize; 3],
    /// World units between lattice points, per axis.
    pub spacing: Vec3,
    /// Data units per raw unit.
    pub slope: f32,
    /// Data units at raw zero.
    pub intercept: f32,
    /// Largest lattice coordinate per axis, `n − 1`, as a float (for clamping).
    pub(crate) last: Vec3,
    /// Largest lower cell corner per axis, `max(n − 2, 0)`, as a float (exact: an axis has at
    /// most [`MAX_AXIS`] points).
    pub(crate) max_lo: Vec3,
    /// Index distance from a cell's lower to its upper corner per axis: `1, nx, nx·ny`, or 0 on
    /// an axis with one point (both corners are that point).
    pub(crate) corner_step: [usize; 3],
}

impl<'a, T: Voxel> Grid<'a, T> {
    /// A view of `data` (x fastest) with these dimensions; panics if the length does not match
    /// (a [`Volume`] guarantees it).
    pub fn new(data: &'a [T], dims: [usize; 3], spacing: Vec3, slope: f32, intercept: f32) -> Self {
        assert_eq!(data.len(), dims[0] * dims[1] * dims[2], "grid data length");
        assert!(dims.iter().all(|&n| n > 0), "grid dimensions");
        let strides = [1, dims[0], dims[0] * dims[1]];
        Self {
            data,
            dims,
            spacing,
            slope,
            intercept,
            last: Vec3::new(
                (dims[0] - 1) as f32,
                (dims[1] - 1) as f32,
                (dims[2] - 1) as f32,
            ),
            max_lo: Vec3::from_array(dims.map(|n| n.saturating_sub(2) as f32)),
            corner_step: [0, 1, 2].map(|a| if dims[a] > 1 { strides[a] } else { 0 }),
        }
    }
}

impl<T: Voxel> Grid<'_, T> {
    /// Linear index of lattice point `(i, j, k)` (x fastest).
    #[inline(always)]
    pub fn index(&self, i: usize, j: usize, k: usize) -> usize {
        i + self.dims[0] * (j + self.dims[1] * k)
    }

    /// The raw value at a lattice point, as `f32`.
    #[inline(always)]
    pub fn raw(&self, i: usize, j: usize, k: usize) -> f32 {
        self.data[self.index(i, j, k)].to_f32()
    }

    /// Raw units → data units.
    #[inline(always)]
    pub fn to_data(&self, raw: f32) -> f32 {
        raw * self.slope + self.intercept
    }
}

/// Something that wants the volume's typed view, whatever its scalar type (a generic closure).
pub trait GridVisitor {
    type Output;
    fn visit<T: Voxel>(self, grid: Grid<'_, T>) -> Self::Output;
}

/// A scalar volume on a regular lattice. Construct with [`Volume::new`], which validates.
/// It holds only data and what follows from it at once; the structures renders reuse live in
/// [`crate::prepared::Prepared`].
#[derive(Clone, Debug, PartialEq)]
pub struct Volume {
    name: String,
    dims: UVec3,
    spacing: Vec3,
    data: VoxelData,
    slope: f32,
    intercept: f32,
    /// (min, max) of the stored (raw) values that are data.
    raw: (f32, f32),
    /// Voxels that hold no data (non-finite floats: masked cells).
    no_data: u64,
    /// The mean raw value over the voxels with data (0 when none does).
    raw_mean: f64,
}

impl Volume {
    /// Validates and builds a volume: every axis at least one voxel, the data length equal to the
    /// product of the dimensions, spacing finite and positive. Non-finite float values are kept
    /// as "no data" ([`Volume::no_data_count`]).
    pub fn new(
        name: impl Into<String>,
        dims: UVec3,
        spacing: Vec3,
        data: VoxelData,
    ) -> Result<Self, VolumeError> {
        Self::with_rescale(name, dims, spacing, data, 1.0, 0.0)
    }

    /// As [`Volume::new`], with data units = `raw · slope + intercept`.
    pub fn with_rescale(
        name: impl Into<String>,
        dims: UVec3,
        spacing: Vec3,
        data: VoxelData,
        slope: f32,
        intercept: f32,
    ) -> Result<Self, VolumeError> {
        let count = checked_voxel_count(dims.x as u64, dims.y as u64, dims.z as u64)?;
        if data.len() as u64 != count {
            return Err(VolumeError::LengthMismatch {
                expected: count,
                found: data.len() as u64,
            });
        }
        if !(spacing.is_finite() && spacing.min_element() > 0.0) {
            return Err(VolumeError::BadSpacing(spacing.x, spacing.y, spacing.z));
        }
        if !(slope.is_finite() && intercept.is_finite() && slope != 0.0) {
            return Err(VolumeError::BadRescale { slope, intercept });
        }
        let RawStats {
            range: raw,
            no_data,
            mean: raw_mean,
        } = raw_stats(&data);
        Ok(Self {
            name: name.into(),
            dims,
            spacing,
            data,
            slope,
            intercept,
            raw,
            no_data,
            raw_mean,
        })
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    /// The same volume under another name.
    pub fn with_name(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }

    pub fn dims(&self) -> UVec3 {
        self.dims
    }

    pub fn spacing(&self) -> Vec3 {
        self.spacing
    }

    pub fn data(&self) -> &VoxelData {
        &self.data
    }

    pub fn scalar_type(&self) -> ScalarType {
        self.data.scalar_type()
    }

    /// `(slope, intercept)`: data units = raw · slope + intercept.
    pub fn rescale(&self) -> (f32, f32) {
        (self.slope, self.intercept)
    }

    /// (min, max) in data units over the voxels that hold data ((0, 0) when none does): the
    /// raw range rescaled (a negative slope swaps its ends).
    pub fn value_range(&self) -> (f32, f32) {
        let (a, b) = (
            self.raw.0 * self.slope + self.intercept,
            self.raw.1 * self.slope + self.intercept,
        );
        (a.min(b), a.max(b))
    }

    /// The mean value in data units over the voxels that hold data (0 when none does).
    pub fn mean_value(&self) -> f32 {
        if self.data.is_empty() || self.no_data == self.data.len() as u64 {
            return 0.0;
        }
        (self.raw_mean * self.slope as f64 + self.intercept as f64) as f32
    }

    /// (min, max) of the stored values that are data, before the rescale ((0, 0) when none).
    pub fn raw_value_range(&self) -> (f32, f32) {
        self.raw
    }

    /// How many voxels hold no data: NaN or ±∞ in a float volume, as masked cells of a real
    /// field are stored. A sample any of whose corners holds no data has no value: every method
    /// passes over it (transparent to Accumulate, left out of Average, Maximum and Minimum,
    /// never a First hit), and a gradient that needs one is zero.
    pub fn no_data_count(&self) -> u64 {
        self.no_data
    }

    pub fn voxel_count(&self) -> usize {
        self.data.len()
    }

    /// The world-space box the volume spans (see the crate's conventions).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let n = self.dims.as_vec3();
        let extent = (n - 1.0) * self.spacing;
        // An axis with one lattice point gets one spacing of thickness around it.
        let single = self.dims.cmpeq(UVec3::ONE);
        let half = self.spacing * 0.5;
        let lo = Vec3::select(single, -half, Vec3::ZERO);
        let hi = Vec3::select(single, half, extent);
        (lo, hi)
    }

    /// The centre of the volume's box.
    pub fn center(&self) -> Vec3 {
        let (lo, hi) = self.bounds();
        (lo + hi) * 0.5
    }

    /// The value of lattice point `(i, j, k)` in data units, or `None` outside the lattice.
    /// Public: the one checked way to read a voxel by its index.
    pub fn value_at(&self, i: u32, j: u32, k: u32) -> Option<f32> {
        if i >= self.dims.x || j >= self.dims.y || k >= self.dims.z {
            return None;
        }
        let index =
            i as usize + self.dims.x as usize * (j as usize + self.dims.y as usize * k as usize);
        Some(self.data.raw_f32(index) * self.slope + self.intercept)
    }

    /// Hands the typed view of this volume to `visitor`.
    pub fn visit<V: GridVisitor>(&self, visitor: V) -> V::Output {
        let dims = [
            self.dims.x as usize,
            self.dims.y as usize,
            self.dims.z as usize,
        ];
        macro_rules! go {
            ($v:expr) => {
                visitor.visit(Grid::new(
                    $v,
                    dims,
                    self.spacing,
                    self.slope,
                    self.intercept,
                ))
            };
        }
        match &self.data {
            VoxelData::U8(v) => go!(v),
            VoxelData::I16(v) => go!(v),
            VoxelData::U16(v) => go!(v),
            VoxelData::F32(v) => go!(v),
        }
    }
}

/// The most lattice points along one axis: 2²⁴, where `f32` positions stop resolving single
/// voxels (and lattice coordinates stay exact, positive `i32`s, which the samplers rely on).
pub const MAX_AXIS: u64 = 1 << 24;

/// `nx·ny·nz`, checked for zero axes, axes beyond [`MAX_AXIS`], and overflow of `usize` and of 2⁴⁰ voxels (a terabyte
/// of 8-bit data: far beyond any machine this runs on, small enough that byte counts never wrap).
pub fn checked_voxel_count(nx: u64, ny: u64, nz: u64) -> Result<u64, VolumeError> {
    if nx == 0 || ny == 0 || nz == 0 {
        return Err(VolumeError::ZeroDimension(nx, ny, nz));
    }
    const MAX_VOXELS: u64 = 1 << 40;
    let count = nx
        .checked_mul(ny)
        .and_then(|v| v.checked_mul(nz))
        .filter(|&c| c <= MAX_VOXELS && usize::try_from(c).is_ok())
        .filter(|_| nx.max(ny).max(nz) <= MAX_AXIS)
        .ok_or(VolumeError::TooManyVoxels(nx, ny, nz))?;
    Ok(count)
}

/// What a volume's stored values say at once, from passes over them at construction.
struct RawStats {
    /// (min, max) of the values that are data ((0, 0) when none is).
    range: (f32, f32),
    /// How many are not data (NaN or ±∞ in a float volume: masked cells).
    no_data: u64,
    /// The mean of the values that are data (0 when none is).
    mean: f64,
}

/// Range, count without data and mean of the stored values: integers summed exactly (each pass
/// vectorises), floats in one ordered pass.
fn raw_stats(data: &VoxelData) -> RawStats {
    fn ints<T: Voxel + Ord + Into<i64>>(v: &[T]) -> RawStats {
        let lo = v.iter().copied().min().map_or(0.0, Voxel::to_f32);
        let hi = v.iter().copied().max().map_or(0.0, Voxel::to_f32);
        // |value| < 2¹⁶ and at most 2⁴⁰ voxels: the sum fits an i64 exactly.
        let sum: i64 = v.iter().map(|&x| x.into()).sum();
        let mean = if v.is_empty() {
            0.0
        } else {
            sum as f64 / v.len() as f64
        };
        RawStats {
            range: (lo, hi),
            no_data: 0,
            mean,
        }
    }
    match data {
        VoxelData::U8(v) => ints(v),
        VoxelData::I16(v) => ints(v),
        VoxelData::U16(v) => ints(v),
        VoxelData::F32(v) => {
            let mut lo = f32::INFINITY;
            let mut hi = f32::NEG_INFINITY;
            let mut no_data = 0u64;
            let mut sum = 0.0f64;
            for &value in v {
                if value.is_finite() {
                    lo = lo.min(value);
                    hi = hi.max(value);
                    sum += value as f64;
                } else {
                    no_data += 1;
                }
            }
            let n = v.len() as u64 - no_data;
            RawStats {
                range: if lo > hi { (0.0, 0.0) } else { (lo, hi) },
                no_data,
                mean: if n == 0 { 0.0 } else { sum / n as f64 },
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vol(dims: UVec3, data: VoxelData) -> Result<Volume, VolumeError> {
        Volume::new("t", dims, Vec3::ONE, data)
    }

    /// A volume is its data: equal when name, lattice, values and rescale are.
    #[test]
    fn volumes_compare_as_data() {
        let fresh = crate::builtin::load_builtin("shells").unwrap().volume;
        let prepared = crate::prepared::Prepared::from(fresh.clone());
        prepared.block_ranges();
        prepared.lattice_differences();
        assert_eq!(prepared.into_volume(), fresh);
        let other = Volume::new("t", UVec3::ONE, Vec3::ONE, VoxelData::U8(vec![1])).unwrap();
        let renamed = Volume::new("u", UVec3::ONE, Vec3::ONE, VoxelData::U8(vec![1])).unwrap();
        let spaced =
            Volume::new("t", UVec3::ONE, Vec3::splat(2.0), VoxelData::U8(vec![1])).unwrap();
        let valued = Volume::new("t", UVec3::ONE, Vec3::ONE, VoxelData::U8(vec![2])).unwrap();
        for different in [&renamed, &spaced, &valued] {
            assert_ne!(&other, different);
        }
    }

    /// The mean counts only voxels with data and is in data units; computed at construction.
    #[test]
    fn the_mean_is_over_the_data_in_data_units() {
        let ints = vol(UVec3::new(4, 1, 1), VoxelData::I16(vec![-3, 0, 5, 30000])).unwrap();
        assert_eq!(ints.mean_value(), (-3.0 + 0.0 + 5.0 + 30000.0) / 4.0);
        let floats = vol(
            UVec3::new(4, 1, 1),
            VoxelData::F32(vec![1.0, f32::NAN, 2.0, f32::INFINITY]),
        )
        .unwrap();
        assert_eq!(floats.mean_value(), 1.5);
        let masked = vol(UVec3::new(2, 1, 1), VoxelData::F32(vec![f32::NAN; 2])).unwrap();
        assert_eq!(masked.mean_value(), 0.0);
        let rescaled = Volume::with_rescale(
            "r",
            UVec3::new(2, 1, 1),
            Vec3::ONE,
            VoxelData::U8(vec![10, 20]),
            -2.0,
            100.0,
        )
        .unwrap();
        assert_eq!(rescaled.mean_value(), 15.0 * -2.0 + 100.0);
    }

    #[test]
    fn rejects_zero_and_mismatched_dims() {
        assert!(matches!(
            vol(UVec3::new(0, 1, 1), VoxelData::U8(vec![])),
            Err(VolumeError::ZeroDimension(..))
        ));
        assert!(matches!(
            vol(UVec3::new(2, 2, 2), VoxelData::U8(vec![0; 7])),
            Err(VolumeError::LengthMismatch {
                expected: 8,
                found: 7
            })
        ));
        assert!(matches!(
            checked_voxel_count(u32::MAX as u64, u32::MAX as u64, u32::MAX as u64),
            Err(VolumeError::TooManyVoxels(..))
        ));
    }

    #[test]
    fn keeps_nan_and_inf_as_no_data_and_rejects_bad_spacing() {
        let v = vol(
            UVec3::new(4, 1, 1),
            VoxelData::F32(vec![2.0, f32::NAN, -1.0, f32::NEG_INFINITY]),
        )
        .unwrap();
        assert_eq!((v.no_data_count(), v.value_range()), (2, (-1.0, 2.0)));
        let none = vol(UVec3::ONE, VoxelData::F32(vec![f32::INFINITY])).unwrap();
        assert_eq!((none.no_data_count(), none.value_range()), (1, (0.0, 0.0)));
        let ints = vol(UVec3::ONE, VoxelData::U8(vec![7])).unwrap();
        assert_eq!(ints.no_data_count(), 0);
        let e = Volume::new(
            "t",
            UVec3::ONE,
            Vec3::new(1.0, 0.0, 1.0),
            VoxelData::U8(vec![0]),
        );
        assert!(matches!(e, Err(VolumeError::BadSpacing(..))));
        let e = Volume::new(
            "t",
            UVec3::ONE,
            Vec3::splat(f32::NAN),
            VoxelData::U8(vec![0]),
        );
        assert!(matches!(e, Err(VolumeError::BadSpacing(..))));
    }

    #[test]
    fn range_and_rescale() {
        let v = Volume::with_rescale(
            "t",
            UVec3::new(3, 1, 1),
            Vec3::ONE,
            VoxelData::I16(vec![-5, 7, 2]),
            -2.0,
            1.0,
        )
        .unwrap();
        assert_eq!(v.value_range(), (-13.0, 11.0));
        assert_eq!(v.value_at(1, 0, 0), Some(-13.0));
        assert_eq!(v.value_at(3, 0, 0), None);
    }

    #[test]
    fn bounds_follow_the_lattice_convention() {
        let v = Volume::new(
            "t",
            UVec3::new(4, 1, 3),
            Vec3::new(2.0, 3.0, 0.5),
            VoxelData::U8(vec![0; 12]),
        )
        .unwrap();
        let (lo, hi) = v.bounds();
        assert_eq!(lo, Vec3::new(0.0, -1.5, 0.0));
        assert_eq!(hi, Vec3::new(6.0, 1.5, 1.0));
    }
}
