//! The cells of the volume's lattice a ray crosses, in order along it: the walk of Amanatides &
//! Woo (1987), the same one the ray density counts with ([`crate::rays::density::walk_cells`]).
//!
//! A *cell* is the cube between eight neighbouring voxels: cell `(i, j, k)` spans `[i, i+1]` on
//! each axis in voxel coordinates, so an `n`-voxel axis has `n − 1` cells (an axis of one voxel
//! is one cell thick). Every sample inside one cell reads the same 8 voxels. The walk starts in
//! the cell holding the ray's entry point and crosses one face at a time — whichever of the
//! next x, y or z faces comes first along the ray — until the exit point. So a ray crosses
//! `1 + Σ` (whole voxel coordinates strictly between its entry and exit, per axis) cells
//! ([`planes_between`]); one passing exactly through an edge or a corner crosses two or three
//! planes in one step and counts the cells it only touches no more than the walk does (see the
//! ties in [`crate::rays::density`]).

use crate::volume::Volume;
use glam::{IVec3, Vec3};

/// The most cells listed for one ray (a 2048³ volume's diagonal crosses about 6,000).
pub const MAX_CELLS: u32 = 1 << 16;

/// One ray's walk through the cells.
#[derive(Clone, Debug, PartialEq)]
pub struct CellsCrossed {
    /// Where the ray enters and leaves the sampled interval, in voxel coordinates.
    pub entry: [f32; 3],
    pub exit: [f32; 3],
    /// The cells crossed, in order along the ray (each by its lowest corner's voxel index).
    pub cells: Vec<[u32; 3]>,
}

/// Walks the ray `origin + t·dir` (world units) through `volume`'s cells over `interval`
/// (`[t_enter, t_exit]`, inside the box, as [`crate::breakdown::RayTrace::interval`] gives it).
pub fn cells_crossed(volume: &Volume, origin: Vec3, dir: Vec3, [t0, t1]: [f32; 2]) -> CellsCrossed {
    let dims = volume.dims();
    let spacing = volume.spacing();
    let (lo, _) = volume.bounds();
    // Voxel coordinates from the box's low corner (the lattice's first point, or on an axis
    // of one voxel its slab's face: that axis is one cell, `[0, 1]`).
    let o_v = (origin - lo) / spacing;
    let d_v = dir / spacing;
    // On the box's faces, not a rounding past them.
    let top = (dims.as_vec3() - 1.0).max(Vec3::ONE);
    let at = |t: f32| (o_v + d_v * t).clamp(Vec3::ZERO, top);
    let last = (dims.as_ivec3() - 2).max(IVec3::ZERO);
    let mut cells = Vec::new();
    let clamp = |c: IVec3| c.clamp(IVec3::ZERO, last).as_uvec3().to_array();
    crate::rays::density::walk_cells(o_v, d_v, (t0, t1), 1.0, MAX_CELLS, |c| {
        let c = clamp(c);
        // A rounding at the box's face can step out and back: each cell once in a row.
        if cells.last() != Some(&c) {
            cells.push(c);
        }
    });
    if cells.is_empty() && t0.is_finite() && t1 >= t0 {
        // A ray that only touches the box (a corner, a face): the cell it touches.
        cells.push(clamp(at(0.5 * (t0 + t1)).floor().as_ivec3()));
    }
    CellsCrossed {
        entry: at(t0).to_array(),
        exit: at(t1).to_array(),
        cells,
    }
}

/// The whole numbers strictly between `a` and `b`, per axis: the cell faces a straight line
/// from `a` to `b` crosses.
pub fn planes_between(a: [f32; 3], b: [f32; 3]) -> [u32; 3] {
    [0, 1, 2].map(|i| {
        let (lo, hi) = (a[i].min(b[i]), a[i].max(b[i]));
        // Integers n with lo < n < hi.
        let first = lo.floor() + 1.0;
        let last = hi.ceil() - 1.0;
        if last >= first {
            (last - first + 1.0) as u32
        } else {
            0
        }
    })
}

#[cfg(test)]
mod tests;
