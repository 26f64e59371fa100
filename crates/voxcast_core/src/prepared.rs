//! A volume with the structures its renders reuse: the value range of every block (empty-space
//! skipping), of every brick and superblock (the projections' bounds), and every lattice point's
//! integer differences (exact gradients without 56 reads), each computed on first use and kept
//! for the next render of the same volume; and the empty space of the latest transfer function
//! (its transparent blocks and visible cells), kept while the transfer function stays: a scene
//! built for a new camera or step reuses it instead of scanning every voxel again.
//!
//! [`Volume`] itself holds only what a file says (lattice, values, rescale) and so compares,
//! clones and serialises as data; whoever renders one volume many times (the sandbox, the bench,
//! a test that sweeps settings) keeps one `Prepared` and builds each [`crate::scene::Scene`]
//! from it.

use crate::bricks::{BrickRanges, Superblocks};
use crate::sample::Differences;
use crate::skip::{BlockRanges, EmptyBlocks, VisibleCells};
use crate::transfer::Lut;
use crate::volume::{Grid, GridVisitor, Volume, Voxel};
use std::sync::{Arc, Mutex, OnceLock};

/// The blocks and cells a transfer function leaves transparent ([`crate::skip`]).
pub type EmptySpace = Arc<(EmptyBlocks, VisibleCells)>;

/// The most memory precomputed gradients may take (8 bytes a voxel): beyond it, gradients are
/// computed from the values each time (same result, slower). 1 GB (a 512³ volume); in a web
/// page 256 MB (a 320³ volume), as its 4 GB of memory at most also holds the file being read,
/// the voxels and the GPU's copy of them.
pub const MAX_DIFFERENCE_BYTES: usize = if cfg!(target_arch = "wasm32") {
    256 << 20
} else {
    1 << 30
};

/// A volume and its render caches. Dereferences to the [`Volume`].
#[derive(Debug)]
pub struct Prepared {
    volume: Volume,
    /// Per-block value ranges for empty-space skipping, computed on first use.
    blocks: OnceLock<BlockRanges>,
    /// Per-brick raw value ranges for Maximum and Minimum, computed on first use.
    bricks: OnceLock<Option<BrickRanges>>,
    /// The block ranges gathered into superblocks for Maximum and Minimum, on first use.
    superblocks: OnceLock<Superblocks>,
    /// Lattice differences for fast exact gradients, computed on first use where they fit.
    differences: OnceLock<Option<Vec<Differences>>>,
    /// The latest table's empty space, with the table it was found for.
    empty: Mutex<Option<(Lut, EmptySpace)>>,
}

impl From<Volume> for Prepared {
    fn from(volume: Volume) -> Self {
        Self::new(volume)
    }
}

impl std::ops::Deref for Prepared {
    type Target = Volume;
    fn deref(&self) -> &Volume {
        &self.volume
    }
}

impl Prepared {
    /// Nothing is computed yet: each structure on the first render that needs it.
    pub fn new(volume: Volume) -> Self {
        Self {
            volume,
            blocks: OnceLock::new(),
            bricks: OnceLock::new(),
            superblocks: OnceLock::new(),
            differences: OnceLock::new(),
            empty: Mutex::new(None),
        }
    }

    pub fn volume(&self) -> &Volume {
        &self.volume
    }

    /// The volume back, its caches dropped. Public: the way out of [`Prepared`] for a caller
    /// that edits the volume.
    pub fn into_volume(self) -> Volume {
        self.volume
    }

    /// The value range of each block of cells (empty-space skipping, [`crate::skip`]): computed
    /// once, on first use.
    pub fn block_ranges(&self) -> &BlockRanges {
        self.blocks.get_or_init(|| BlockRanges::of(&self.volume))
    }

    /// The blocks and cells `lut` makes transparent: the ones found for the previous call's
    /// table if it was this one, else found now (every cell's corners scanned: on a 512² × 200
    /// CT some 20 ms on two threads) and kept for the next call.
    pub fn empty_space(&self, lut: &Lut) -> EmptySpace {
        // The lock is not held while the cells are scanned: the scan runs on rayon's threads,
        // which another caller waiting on the lock could be holding.
        let cached = self.empty.lock().ok().and_then(|c| {
            c.as_ref()
                .filter(|(l, _)| l == lut)
                .map(|(_, space)| space.clone())
        });
        if let Some(space) = cached {
            return space;
        }
        let space = Arc::new((
            EmptyBlocks::new(self.block_ranges(), lut),
            VisibleCells::new(&self.volume, lut),
        ));
        if let Ok(mut c) = self.empty.lock() {
            *c = Some((lut.clone(), space.clone()));
        }
        space
    }

    /// Whether the block ranges have been computed (no render has had to wait for them since).
    #[cfg(test)]
    pub fn has_block_ranges(&self) -> bool {
        self.blocks.get().is_some()
    }

    /// The raw value range of each 4³ brick of cells ([`crate::bricks`]): computed once, on
    /// first use; `None` for float data.
    pub fn brick_ranges(&self) -> Option<&BrickRanges> {
        self.bricks
            .get_or_init(|| BrickRanges::of(&self.volume))
            .as_ref()
    }

    /// The block ranges gathered into superblocks ([`crate::bricks::Superblocks`]): computed
    /// once, on first use (with the block ranges, if they are not yet).
    pub fn superblocks(&self) -> &Superblocks {
        self.superblocks
            .get_or_init(|| Superblocks::of(self.block_ranges()))
    }

    /// Every lattice point's exact integer differences (see
    /// [`crate::sample::lattice_differences`]), computed once on first use; `None` for float
    /// data, ranges too wide for them, and volumes above [`MAX_DIFFERENCE_BYTES`].
    pub fn lattice_differences(&self) -> Option<&[Differences]> {
        self.differences
            .get_or_init(|| {
                struct Build;
                impl GridVisitor for Build {
                    type Output = Option<Vec<Differences>>;
                    fn visit<T: Voxel>(self, g: Grid<'_, T>) -> Self::Output {
                        crate::sample::lattice_differences(&g)
                    }
                }
                (self.volume.voxel_count() * 8 <= MAX_DIFFERENCE_BYTES)
                    .then(|| self.volume.visit(Build))
                    .flatten()
            })
            .as_deref()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::VoxelData;
    use glam::{UVec3, Vec3};

    fn ramp(n: u32) -> Volume {
        let data = (0..n * n * n).map(|i| (i % 251) as u8).collect();
        Volume::new("ramp", UVec3::splat(n), Vec3::ONE, VoxelData::U8(data)).unwrap()
    }

    #[test]
    fn caches_are_computed_once_and_match_a_fresh_computation() {
        let p = Prepared::from(ramp(9));
        assert!(!p.has_block_ranges());
        let first = p.block_ranges() as *const BlockRanges;
        assert!(p.has_block_ranges());
        assert_eq!(
            first,
            p.block_ranges() as *const BlockRanges,
            "kept, not rebuilt"
        );
        assert_eq!(p.block_ranges(), &BlockRanges::of(&ramp(9)));
        for dims in [UVec3::ONE, UVec3::new(9, 2, 17), UVec3::new(10, 8, 1)] {
            let v = Volume::new(
                "d",
                dims,
                Vec3::ONE,
                VoxelData::U8(vec![0; dims.element_product() as usize]),
            );
            let grid = crate::skip::block_grid(dims);
            assert_eq!(grid, BlockRanges::of(&v.unwrap()).grid(), "{dims}");
        }
        let diffs = p.lattice_differences().expect("u8 data has differences");
        assert_eq!(diffs.len(), 9 * 9 * 9);
        assert_eq!(diffs.as_ptr(), p.lattice_differences().unwrap().as_ptr());
    }

    #[test]
    fn the_empty_space_is_kept_for_its_table_and_found_again_for_another() {
        let p = Prepared::from(ramp(9));
        let tf = |lo: f32| crate::transfer::TransferFunction::ramp(lo, 250.0, 1.0).unwrap();
        let fresh = |lut: &Lut| {
            let cells = VisibleCells::new(&ramp(9), lut);
            let blocks = EmptyBlocks::new(&BlockRanges::of(&ramp(9)), lut);
            (cells.words().to_vec(), blocks.flags().to_vec())
        };
        let seen = |s: &EmptySpace| (s.1.words().to_vec(), s.0.flags().to_vec());
        let (a, b) = (tf(200.0).bake(0.0, 250.0), tf(100.0).bake(0.0, 250.0));
        let first = p.empty_space(&a);
        assert_eq!(seen(&first), fresh(&a));
        assert!(Arc::ptr_eq(&first, &p.empty_space(&a)), "kept, not rebuilt");
        let other = p.empty_space(&b);
        assert!(!Arc::ptr_eq(&first, &other), "another table, found again");
        assert_eq!(seen(&other), fresh(&b));
        assert_ne!(
            fresh(&a),
            fresh(&b),
            "the two tables leave different cells visible"
        );
        assert_eq!(seen(&p.empty_space(&a)), fresh(&a), "and back");
        // Scenes built for two cameras share it.
        let s = crate::settings::RenderSettings::default();
        let one = crate::scene::Scene::new(&p, &tf(200.0), &s, Vec3::Z).unwrap();
        let two = crate::scene::Scene::new(&p, &tf(200.0), &s, Vec3::X).unwrap();
        assert!(Arc::ptr_eq(
            one.empty.as_ref().unwrap(),
            two.empty.as_ref().unwrap()
        ));
    }

    #[test]
    fn float_volumes_have_no_differences_and_the_volume_comes_back_unchanged() {
        let v = Volume::new(
            "f",
            UVec3::new(2, 1, 1),
            Vec3::ONE,
            VoxelData::F32(vec![0.0, 1.5]),
        )
        .unwrap();
        let p = Prepared::from(v.clone());
        assert!(p.lattice_differences().is_none());
        assert_eq!(p.dims(), UVec3::new(2, 1, 1), "dereferences to the volume");
        assert_eq!(p.into_volume(), v);
    }
}
