//! Each 4×4×4 brick of cells' smallest and largest raw value: the finest bound the
//! projections test, per sample, before they interpolate it.
//!
//! A sample interpolates its cell's 8 corners, so its value lies between their smallest and
//! largest (the data are integers: the lerps of integer corners never leave that range). A
//! brick's range covers the corners of every cell whose lower corner lies in it — lattice
//! points `4b ..= 4b + 4` per axis, clamped to the lattice — so where a Maximum has already
//! found a value at least as large as a brick's largest, no sample in that brick's cells can
//! change it (and likewise for Minimum). Unlike the blocks of [`crate::skip`], a brick is
//! looked up by the cell a sample lies in, not by where the ray crosses its faces, so it needs
//! no apron and no margin. Raw units, as the samples are compared before they are rescaled.
//!
//! At the other end, [`Superblocks`]: the blocks' ranges gathered into 32³ cells, the level
//! at which a projection's ray chooses what to sample first (`crate::trace`'s `extreme.rs`).

use crate::skip::{BlockRanges, box_count, raw_ranges};
use crate::volume::{Grid, GridVisitor, Volume, Voxel};

/// Cells per brick edge.
pub const BRICK: usize = 4;

/// The raw value range of every brick of cells, for integer volumes.
#[derive(Clone, Debug, PartialEq)]
pub struct BrickRanges {
    /// Bricks per axis: `⌈cells / 4⌉` with `max(n − 1, 1)` cells on an axis of `n` points.
    pub bricks: [usize; 3],
    /// Smallest raw value per brick, x fastest.
    pub min: Vec<f32>,
    /// Largest raw value per brick, x fastest.
    pub max: Vec<f32>,
}

impl BrickRanges {
    /// Scans the volume once (in parallel over z-slabs of bricks); `None` for float data,
    /// whose interpolated values this bound does not cover (no data, rounding).
    pub fn of(volume: &Volume) -> Option<Self> {
        struct Scan;
        impl GridVisitor for Scan {
            type Output = Option<BrickRanges>;
            fn visit<T: Voxel>(self, g: Grid<'_, T>) -> Option<BrickRanges> {
                T::TABLE?;
                let nb = g.dims.map(|n| box_count(n, BRICK));
                // The brick's cells and their upper corners, clamped to the lattice.
                let span = |b: usize, n: usize| (b * BRICK, (b * BRICK + BRICK).min(n - 1));
                let (min, max) = raw_ranges(&g, nb, span, |r| r).into_iter().unzip();
                Some(BrickRanges {
                    bricks: nb,
                    min,
                    max,
                })
            }
        }
        volume.visit(Scan)
    }

    /// The index of the brick holding the cell with lower corner `lo`.
    pub fn index(&self, lo: [usize; 3]) -> usize {
        let [x, y, z] = lo.map(|c| c / BRICK);
        x + self.bricks[0] * (y + self.bricks[1] * z)
    }
}

/// Blocks per superblock edge.
pub const SUPER: usize = 4;

/// The blocks' value ranges gathered into superblocks of [`SUPER`]³ blocks.
#[derive(Clone, Debug)]
pub struct Superblocks {
    /// Superblocks per axis.
    pub(crate) grid: [usize; 3],
    /// The union of its blocks' ranges per superblock, x fastest (data units).
    pub(crate) ranges: Vec<(f32, f32)>,
}

impl Superblocks {
    /// The union of each superblock's block ranges (its blocks' aprons included).
    pub fn of(blocks: &BlockRanges) -> Self {
        let fine = blocks.grid();
        let grid = fine.map(|n| n.div_ceil(SUPER));
        let mut ranges = vec![(f32::INFINITY, f32::NEG_INFINITY); grid[0] * grid[1] * grid[2]];
        for z in 0..fine[2] {
            for y in 0..fine[1] {
                for x in 0..fine[0] {
                    let (lo, hi) = blocks.ranges[x + fine[0] * (y + fine[1] * z)];
                    let at = x / SUPER + grid[0] * (y / SUPER + grid[1] * (z / SUPER));
                    let r = &mut ranges[at];
                    *r = (r.0.min(lo), r.1.max(hi));
                }
            }
        }
        Self { grid, ranges }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::{Interpolation, cell, sample};
    use crate::volume::VoxelData;
    use glam::{UVec3, Vec3};

    fn volume(dims: [u32; 3], data: VoxelData) -> Volume {
        Volume::new("b", UVec3::from_array(dims), Vec3::ONE, data).unwrap()
    }

    /// Every interpolated value of random points lies in its cell's brick's range.
    #[test]
    fn every_sample_lies_in_its_bricks_range() {
        let dims = [11u32, 6, 9];
        let n = (dims[0] * dims[1] * dims[2]) as usize;
        // A scrambled pattern with a wide range, so bricks differ.
        let data: Vec<i16> = (0..n).map(|i| ((i * 7919) % 2003) as i16 - 1000).collect();
        let v = volume(dims, VoxelData::I16(data.clone()));
        let b = BrickRanges::of(&v).expect("integer data");
        assert_eq!(b.bricks, [3, 2, 2]);
        let g = Grid::new(&data, dims.map(|d| d as usize), Vec3::ONE, 1.0, 0.0);
        let mut state = 1u32;
        let mut next = || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / (1u32 << 24) as f32
        };
        for _ in 0..20_000 {
            let p = Vec3::new(next() * 12.0 - 0.5, next() * 7.0 - 0.5, next() * 10.0 - 0.5);
            let at = b.index(cell(&g, p).lo);
            let s = sample(&g, p, Interpolation::Trilinear);
            assert!(
                b.min[at] <= s && s <= b.max[at],
                "{p}: {s} outside brick {at}"
            );
        }
    }

    #[test]
    fn one_point_axes_and_float_data() {
        let v = volume([1, 1, 1], VoxelData::U8(vec![7]));
        let b = BrickRanges::of(&v).unwrap();
        assert_eq!(
            (b.bricks, b.min.clone(), b.max.clone()),
            ([1, 1, 1], vec![7.0], vec![7.0])
        );
        // Five points along x: four cells, one brick spanning points 0..=4.
        let v = volume([5, 1, 1], VoxelData::U16(vec![3, 1, 4, 1, 5]));
        let b = BrickRanges::of(&v).unwrap();
        assert_eq!(
            (b.bricks, b.min.clone(), b.max.clone()),
            ([1, 1, 1], vec![1.0], vec![5.0])
        );
        // Six points: the second brick holds cell 4, whose corners are points 4 and 5.
        let v = volume([6, 1, 1], VoxelData::U8(vec![9, 9, 9, 9, 2, 3]));
        let b = BrickRanges::of(&v).unwrap();
        assert_eq!(
            (b.min.clone(), b.max.clone()),
            (vec![2.0, 2.0], vec![9.0, 3.0])
        );
        let f = volume([2, 1, 1], VoxelData::F32(vec![0.0, 1.0]));
        assert!(BrickRanges::of(&f).is_none());
    }

    #[test]
    fn superblocks_hold_the_union_of_their_blocks_ranges() {
        // 5 × 1 × 2 blocks: superblocks of 4 along x make two columns, one slab deep.
        let ranges = (0..10).map(|i| (i as f32, 10.0 * i as f32)).collect();
        let blocks = BlockRanges {
            blocks: UVec3::new(5, 1, 2),
            ranges,
        };
        let s = Superblocks::of(&blocks);
        assert_eq!(s.grid, [2, 1, 1]);
        // Blocks x = 0..4 of both z layers (0..=3 and 5..=8), then x = 4 (4 and 9).
        assert_eq!(s.ranges, vec![(0.0, 80.0), (4.0, 90.0)]);
    }
}
