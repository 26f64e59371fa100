//! The volume's lattice in the scene: the box it spans always, and for a small grid (up to
//! [`LATTICE_MAX`] points a side, like the sampling level's 8³ or the worked 2³ voxel) the lines
//! through its lattice points, so the voxels a ray passes can be counted even with the preview
//! off. Drawn as overlay lines (`overlay`): sharp at any preview resolution.

use crate::sandbox::shared::state::VolumeState;
use bevy::prelude::*;

/// The largest grid whose lattice lines are drawn (more would be a blur of lines).
pub const LATTICE_MAX: u32 = 16;

pub(crate) fn plugin(app: &mut App) {
    app.add_systems(
        Update,
        draw_lattice.in_set(crate::sandbox::shared::schedule::Frame::Show),
    );
}

/// The segments: the box's 12 edges, and the lattice lines when every axis has at most
/// [`LATTICE_MAX`] points.
pub fn lattice_lines(volume: &voxcast_core::volume::Volume) -> Vec<(Vec3, Vec3)> {
    let (lo, hi) = volume.bounds();
    let dims = volume.dims();
    let mut lines = voxcast_core::ray::box_edges(lo, hi).to_vec();
    if dims.max_element() > LATTICE_MAX {
        return lines;
    }
    let at = |i: u32, axis: usize| volume.spacing()[axis] * i as f32;
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        for i in 0..dims[u] {
            for j in 0..dims[v] {
                let mut a = Vec3::ZERO;
                a[u] = at(i, u);
                a[v] = at(j, v);
                let mut b = a;
                a[axis] = lo[axis];
                b[axis] = hi[axis];
                lines.push((a, b));
            }
        }
    }
    lines
}

fn draw_lattice(
    mut lines: ResMut<crate::sandbox::scene::overlay::OverlayLines>,
    volume: Res<VolumeState>,
    mut cache: Local<Vec<(Vec3, Vec3)>>,
) {
    if volume.is_changed() || cache.is_empty() {
        *cache = lattice_lines(&volume.volume);
    }
    let (edge, lattice) = (
        Color::srgba(0.7, 0.7, 0.7, 0.6),
        Color::srgba(0.6, 0.6, 0.6, 0.3),
    );
    for (i, (a, b)) in cache.iter().enumerate() {
        // The box's 12 edges first, then the lattice lines.
        lines.line(*a, *b, if i < 12 { edge } else { lattice }, 1.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_small_grid_gets_its_lattice_and_a_large_one_only_its_box() {
        let blobs = voxcast_core::builtin::blobs();
        let lines = lattice_lines(&blobs);
        // 12 edges, then 8 × 8 lines along each of the 3 axes.
        assert_eq!(lines.len(), 12 + 3 * 64);
        let (lo, hi) = blobs.bounds();
        for (a, b) in &lines {
            for p in [a, b] {
                assert!(p.cmpge(lo - 1e-6).all() && p.cmple(hi + 1e-6).all());
            }
            // Each runs along one axis from face to face.
            assert_eq!(
                (*b - *a)
                    .abs()
                    .cmpgt(Vec3::splat(1e-6))
                    .bitmask()
                    .count_ones(),
                1
            );
        }
        let bunny = voxcast_core::builtin::load_builtin("bunny").unwrap().volume;
        assert_eq!(lattice_lines(&bunny).len(), 12);
    }
}
