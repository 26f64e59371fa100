//! The ray-density grid: how many rays pass through each cell of a grid over the scene, and
//! their mean direction there — RayVis's volume and vector-field views, computed exactly.
//!
//! Cells have edge `S` and are aligned to the world origin: cell `(i, j, k)` spans
//! `[iS, (i+1)S)` on each axis. They are grouped in cubic chunks of `N` cells, and only chunks
//! that a counted segment touches are stored (RayVis's two-level sparse structure). Each ray's
//! counted segment ([`crate::rays::set`]) is walked cell by cell with the 3-D DDA of Amanatides &
//! Woo ("A fast voxel traversal algorithm for ray tracing", 1987); a cell counts the ray once
//! when the segment passes through it with positive length, and adds the ray's *unit* direction
//! to its sum (normalised at the end: the mean direction).
//!
//! **Ties.** A point on a cell face belongs to the cell the segment enters from there: a segment
//! starting on the face `x = iS` going towards −x starts in cell `i − 1`; one ending on a face
//! does not enter the next cell; a segment through an edge or corner steps every axis it
//! crosses at once, so the cells it only touches are not counted. A segment lying *in* a face
//! plane (its direction parallel to it) is counted in the cell above the plane (the half-open
//! rule). Rounding can make a crossing computed incrementally miss an exact corner; the side
//! cell it then touches is passed for a rounding's length.
//!
//! **Bad rays are skipped and counted, never fatal**: a ray that is not finite, has a zero
//! direction or `t_max < t_min` ([`RayRecord::check`]) or starts beyond ±2³⁰ cells; a segment
//! longer than [`DensityParams::max_cells_per_ray`] cells (an endless miss) is cut there and
//! counted as capped.
//!
//! The direction sums are kept in fixed point (2⁻²⁰ per component: integer additions, in any
//! order the same), so the counts and the mean directions are the same for any number of
//! threads. The work: the chunks are found first by walking the rays through cells of edge
//! `N·S` (the estimate shown before computing, and how many rays cross each chunk); then the
//! chunks are cut into slabs across x, one a thread, balanced by those crossings, and each
//! thread walks every ray that can reach its slab and adds the visits inside it to its own
//! cells — no visit is written down and read back, and no two threads write one cell. A ray
//! that crosses several slabs is walked by each from its start (so every walk takes the same
//! steps, bit for bit); a walk stops once it has passed its slab, and a ray that cannot reach a
//! slab is not walked for it.

mod count;
mod estimate;
mod sliced;
mod walk;
pub use count::compute;
use count::{Slab, SlabWalk, assemble, compute_in, slabs};
pub use estimate::{Estimate, MAX_BYTES, estimate, estimate_within};
use estimate::{chunks_touched, chunks_touched_within, merge_touched, touched_by};
pub use sliced::{DensitySlices, density_in};
use walk::{Skip, start_cell, walk_cells_while, walkable};
pub use walk::{Walk, walk_cells};

use super::set::{Filter, RayRecord, RaySet};
use crate::render::Cancelled;
use crate::slices::Deadline;
use glam::{IVec3, Vec3};
use rayon::prelude::*;
use std::collections::{BTreeMap, HashMap};
use std::hash::{BuildHasherDefault, Hasher};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Rays per block of work (the unit of progress and cancelling).
const RAYS_PER_BLOCK: usize = 4096;

/// Cell visits a walk lists before adding them to the cells (see [`count::add_visits`]).
const PENDING_VISITS: usize = 1024;

/// Fixed-point units per unit of a direction component in the sums.
const DIRECTION_SCALE: f32 = (1u32 << 20) as f32;

/// The largest cell coordinate a segment may start at (beyond, `i32` steps could overflow).
const MAX_START_CELL: f32 = (1u32 << 30) as f32;

/// What a density is computed from (see the module's text).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DensityParams {
    /// Cell edge `S`, world units.
    pub cell: f32,
    /// Cells per chunk edge `N`.
    pub chunk: u32,
    pub filter: Filter,
    /// RayVis's miss-detection tolerance.
    pub tolerance: f32,
    /// Every `stride`-th counted ray.
    pub stride: usize,
    /// The most cells one ray is walked through.
    pub max_cells_per_ray: u32,
}

impl Default for DensityParams {
    fn default() -> Self {
        Self {
            cell: 1.0,
            chunk: 16,
            filter: Filter::All,
            tolerance: 0.0,
            stride: 1,
            max_cells_per_ray: 1 << 16,
        }
    }
}

impl DensityParams {
    /// Checks the values a user can type.
    pub fn check(&self) -> Result<(), String> {
        if !(self.cell.is_finite() && self.cell > 0.0) {
            return Err(format!("cell size {} must be a positive number", self.cell));
        }
        if !(1..=64).contains(&self.chunk) {
            return Err(format!("chunk size {} must be 1 … 64 cells", self.chunk));
        }
        if !(self.tolerance.is_finite() && self.tolerance >= 0.0) {
            return Err(format!(
                "miss tolerance {} must be 0 or more",
                self.tolerance
            ));
        }
        if self.max_cells_per_ray == 0 {
            return Err("the cells per ray must be at least 1".into());
        }
        Ok(())
    }

    /// Bytes one stored chunk takes (a count and a fixed-point direction sum per cell).
    pub fn chunk_bytes(&self) -> usize {
        (self.chunk as usize).pow(3) * (4 + 24)
    }
}

/// One stored chunk: its cells, x fastest.
#[derive(Clone, Debug, PartialEq)]
pub struct Chunk {
    pub cells: Vec<CellSum>,
}

/// One cell: the ray count and the sum of unit directions (fixed point, 2²⁰ per
/// unit), side by side so that a visit writes one cache line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CellSum {
    pub count: u32,
    pub direction: [i64; 3],
}

impl CellSum {
    /// Counts one ray through the cell, with its fixed-point unit direction.
    fn add(&mut self, unit: [i32; 3]) {
        self.count += 1;
        for (s, u) in self.direction.iter_mut().zip(unit) {
            *s += i64::from(u);
        }
    }
}

impl Chunk {
    fn new(per_chunk: usize) -> Self {
        Self {
            cells: vec![CellSum::default(); per_chunk],
        }
    }
}

/// What happened to the rays.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Report {
    /// Rays walked (after the filter and stride).
    pub rays: usize,
    /// Rays skipped as not finite, with a zero direction or `t_max < t_min`.
    pub malformed: usize,
    /// Rays skipped for starting too far out.
    pub out_of_range: usize,
    /// Rays cut short at the cells-per-ray cap.
    pub capped: usize,
    /// Cell visits in all (the sum of every count).
    pub visits: u64,
}

impl Report {
    /// Adds another block's report.
    fn add(&mut self, r: &Report) {
        self.rays += r.rays;
        self.malformed += r.malformed;
        self.out_of_range += r.out_of_range;
        self.capped += r.capped;
        self.visits += r.visits;
    }
}

/// The chunk holding `cell` in chunks of `n` cells a side, and the cell's index in it (x
/// fastest).
fn locate(cell: IVec3, n: i32) -> (IVec3, usize) {
    let chunk = cell.div_euclid(IVec3::splat(n));
    let l = cell - chunk * n;
    (chunk, (l.x + n * (l.y + n * l.z)) as usize)
}

/// A hasher for chunk keys: three small integers need no protection against chosen keys (the
/// default SipHash took a tenth of a density's time), only a spread of their bits.
#[derive(Default)]
struct KeyHasher(u64);

impl Hasher for KeyHasher {
    fn write(&mut self, bytes: &[u8]) {
        // A key's integers arrive as their bytes: four at a time.
        for word in bytes.chunks(4) {
            let mut b = [0u8; 4];
            b[..word.len()].copy_from_slice(word);
            self.write_u64(u64::from(u32::from_le_bytes(b)));
        }
    }

    fn write_usize(&mut self, v: usize) {
        self.write_u64(v as u64);
    }

    fn write_u64(&mut self, v: u64) {
        // FxHash's round: rotate, mix in, multiply by an odd constant.
        self.0 = (self.0.rotate_left(5) ^ v).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

/// A map from chunk keys.
type KeyMap<V> = HashMap<IVec3Key, V, BuildHasherDefault<KeyHasher>>;

/// A computed ray density.
#[derive(Clone, Debug, PartialEq)]
pub struct Density {
    pub params: DensityParams,
    /// The stored chunks, by chunk coordinates (chunk `c` holds cells `cN … cN + N − 1`).
    pub chunks: BTreeMap<IVec3Key, Chunk>,
    pub report: Report,
}

/// Chunk coordinates as a map key (ordered, so iteration is deterministic).
pub type IVec3Key = [i32; 3];

impl Density {
    fn locate(&self, cell: IVec3) -> (IVec3Key, usize) {
        let (c, i) = locate(cell, self.params.chunk as i32);
        (c.to_array(), i)
    }

    /// Rays through `cell`.
    pub fn count(&self, cell: IVec3) -> u32 {
        let (c, i) = self.locate(cell);
        self.chunks.get(&c).map_or(0, |ch| ch.cells[i].count)
    }

    /// The mean unit direction of the rays through `cell` (zero where none passed).
    pub fn mean_direction(&self, cell: IVec3) -> Vec3 {
        let (c, i) = self.locate(cell);
        self.chunks.get(&c).map_or(Vec3::ZERO, |ch| {
            let [x, y, z] = ch.cells[i].direction;
            Vec3::new(x as f32, y as f32, z as f32).normalize_or_zero()
        })
    }

    /// Bytes the stored chunks take.
    pub fn memory_bytes(&self) -> usize {
        self.chunks.len() * self.params.chunk_bytes()
    }

    /// Bytes a dense grid over the same chunks' bounding box would take.
    pub fn dense_bytes(&self) -> usize {
        let Some((lo, hi)) = self.chunk_bounds() else {
            return 0;
        };
        let n = (hi - lo + IVec3::ONE).as_i64vec3();
        (n.x * n.y * n.z) as usize * self.params.chunk_bytes()
    }

    /// The lowest and highest stored chunk coordinates.
    pub fn chunk_bounds(&self) -> Option<(IVec3, IVec3)> {
        let mut keys = self.chunks.keys().map(|k| IVec3::from_array(*k));
        let first = keys.next()?;
        Some(keys.fold((first, first), |(lo, hi), k| (lo.min(k), hi.max(k))))
    }
}

#[cfg(test)]
mod tests;
