//! The cell walk against the rule a student counts with, on random rays and at the extremes.

use super::*;
use crate::ray::{Ray, intersect_box};
use crate::volume::VoxelData;
use glam::UVec3;
use proptest::prelude::*;

fn volume(dims: UVec3, spacing: Vec3) -> Volume {
    let n = (dims.x * dims.y * dims.z) as usize;
    Volume::new("t", dims, spacing, VoxelData::U8(vec![0; n])).unwrap()
}

/// The walk of the ray from `origin` towards `target`, over its whole interval in the box.
fn walk(v: &Volume, origin: Vec3, target: Vec3) -> Option<CellsCrossed> {
    let ray = Ray::new(origin, target - origin)?;
    let (lo, hi) = v.bounds();
    let (t0, t1) = intersect_box(&ray, lo, hi)?;
    Some(cells_crossed(v, ray.origin, ray.dir, [t0, t1]))
}

/// Consecutive cells share a face, and every cell lies in the lattice.
fn assert_walk_is_connected(v: &Volume, w: &CellsCrossed) {
    let last = (v.dims().max(UVec3::splat(2)) - 2).to_array();
    for c in &w.cells {
        assert!((0..3).all(|a| c[a] <= last[a]), "{c:?} outside {last:?}");
    }
    for pair in w.cells.windows(2) {
        let d: u32 = (0..3).map(|a| pair[0][a].abs_diff(pair[1][a])).sum();
        assert!(d >= 1, "a cell twice in a row: {pair:?}");
        // Through an edge or a corner the walk steps two or three axes at once.
        assert!(d <= 3 && (0..3).all(|a| pair[0][a].abs_diff(pair[1][a]) <= 1));
    }
}

/// The lecture's 2×2×2 grid is one cell: any ray through it crosses just that one.
#[test]
fn a_single_cell_is_all_a_ray_can_cross() {
    let v = volume(UVec3::splat(2), Vec3::ONE);
    let w = walk(&v, Vec3::new(-3.0, 0.3, 0.6), Vec3::new(2.0, 0.7, 0.2)).unwrap();
    assert_eq!(w.cells, vec![[0, 0, 0]]);
    assert_eq!(planes_between(w.entry, w.exit), [0, 0, 0]);
}

/// Along the x axis through an 8³ grid: 7 cells, the x index climbing one by one, entry and
/// exit on the box's faces.
#[test]
fn an_axis_parallel_ray_crosses_a_row_of_cells() {
    let v = volume(UVec3::splat(8), Vec3::splat(0.5));
    let w = walk(&v, Vec3::new(-1.0, 1.3, 2.1), Vec3::new(5.0, 1.3, 2.1)).unwrap();
    let expect: Vec<[u32; 3]> = (0..7).map(|i| [i, 2, 4]).collect();
    assert_eq!(w.cells, expect);
    assert!((w.entry[0] - 0.0).abs() < 1e-5 && (w.exit[0] - 7.0).abs() < 1e-5);
    assert_eq!(planes_between(w.entry, w.exit), [6, 0, 0]);
    // Backwards: the same cells in the opposite order.
    let back = walk(&v, Vec3::new(5.0, 1.3, 2.1), Vec3::new(-1.0, 1.3, 2.1)).unwrap();
    assert_eq!(back.cells, expect.into_iter().rev().collect::<Vec<_>>());
}

/// A ray lying in a face plane between two rows of cells is counted in one row (the one above,
/// the half-open rule), never both.
#[test]
fn a_ray_in_a_face_plane_walks_one_row() {
    let v = volume(UVec3::splat(5), Vec3::ONE);
    let w = walk(&v, Vec3::new(-1.0, 2.0, 1.5), Vec3::new(9.0, 2.0, 1.5)).unwrap();
    assert_eq!(w.cells.len(), 4);
    assert!(w.cells.iter().all(|c| c[1] == 2 && c[2] == 1));
}

/// The main diagonal passes every cell corner on its way: it steps all three axes at once and
/// crosses n − 1 cells, not the 3(n − 1) − 2 the rule counts for a line that misses the corners.
#[test]
fn the_diagonal_steps_through_the_corners() {
    let v = volume(UVec3::splat(6), Vec3::ONE);
    let w = walk(&v, Vec3::splat(-1.0), Vec3::splat(7.0)).unwrap();
    let expect: Vec<[u32; 3]> = (0..5).map(|i| [i, i, i]).collect();
    assert_eq!(w.cells, expect);
    assert_walk_is_connected(&v, &w);
}

/// A 1-voxel-thick volume is one cell thick; a 1×1×1 volume is one cell, whatever the ray.
#[test]
fn thin_and_single_voxel_volumes_are_one_cell_thick() {
    let thin = volume(UVec3::new(6, 6, 1), Vec3::ONE);
    let w = walk(&thin, Vec3::new(-1.0, 0.5, -2.0), Vec3::new(6.0, 4.2, 2.0)).unwrap();
    assert!(w.cells.iter().all(|c| c[2] == 0));
    assert_walk_is_connected(&thin, &w);
    let p = planes_between(w.entry, w.exit);
    assert_eq!(w.cells.len() as u32, 1 + p[0] + p[1] + p[2]);
    let one = volume(UVec3::ONE, Vec3::splat(2.0));
    for target in [
        Vec3::new(0.3, -0.2, 0.1),
        Vec3::ZERO,
        Vec3::new(1.0, 1.0, 1.0),
    ] {
        let w = walk(&one, Vec3::new(-5.0, 3.0, 4.0), target).unwrap();
        assert_eq!(w.cells, vec![[0, 0, 0]]);
    }
}

/// A ray that starts inside the volume (a camera inside it) starts in the cell it stands in.
#[test]
fn a_ray_from_inside_starts_in_its_own_cell() {
    let v = volume(UVec3::splat(8), Vec3::ONE);
    let w = walk(&v, Vec3::new(3.5, 2.2, 4.9), Vec3::new(9.0, 2.2, 4.9)).unwrap();
    assert_eq!(w.cells.first(), Some(&[3, 2, 4]));
    assert_eq!(w.cells.len(), 4);
}

proptest! {
    /// Any ray through any box: the walk is connected, stays in the lattice, and crosses as
    /// many cells as the student's rule counts (a random ray misses every edge and corner).
    #[test]
    fn the_walk_crosses_as_many_cells_as_the_rule_counts(
        dims in (1u32..20, 1u32..20, 1u32..20),
        spacing in (0.1f32..3.0, 0.1f32..3.0, 0.1f32..3.0),
        from in (-1.0f32..2.0, -1.0f32..2.0, -1.0f32..2.0),
        to in (0.0f32..1.0, 0.0f32..1.0, 0.0f32..1.0),
    ) {
        let v = volume(UVec3::new(dims.0, dims.1, dims.2), Vec3::new(spacing.0, spacing.1, spacing.2));
        let (lo, hi) = v.bounds();
        let size = hi - lo;
        // An origin anywhere around or inside the box, towards a point inside it.
        let origin = lo + size * Vec3::new(from.0, from.1, from.2) * 3.0 - size;
        let target = lo + size * Vec3::new(to.0, to.1, to.2);
        let Some(w) = walk(&v, origin, target) else {
            return Ok(());
        };
        assert_walk_is_connected(&v, &w);
        let p = planes_between(w.entry, w.exit);
        // Only planes inside the lattice count: a thin axis has none.
        prop_assert_eq!(w.cells.len() as u32, 1 + p[0] + p[1] + p[2], "{:?}", w);
    }
}
