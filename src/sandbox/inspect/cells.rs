//! The cells of the lattice the selected ray crosses, drawn in the scene as wireframe boxes
//! (the Amanatides–Woo walk of `voxcast_core::cells`, which the breakdown holds): the first
//! cell along the ray brightest, fading towards the last, so the walk's order shows.

use crate::sandbox::inspect::breakdown::BreakdownState;
use crate::sandbox::scene::overlay::OverlayLines;
use crate::sandbox::shared::state::VolumeState;
use bevy::prelude::*;

/// The most cells drawn (from the ray's entry on): beyond it the lines would hide the volume.
pub const MAX_CELLS_DRAWN: usize = 2000;

/// The cells' colour.
pub const CELL_COLOR: Color = Color::srgb(0.3, 0.95, 0.75);

pub(crate) fn plugin(app: &mut App) {
    app.add_systems(
        Update,
        draw_cells.in_set(crate::sandbox::shared::schedule::Frame::Show),
    );
}

/// The world box of cell `c` (by its lowest corner's voxel index) of a volume with box
/// `bounds`, `dims` voxels and `spacing`: an axis of one voxel is its whole slab.
pub fn cell_box(c: [u32; 3], (lo, hi): (Vec3, Vec3), dims: UVec3, spacing: Vec3) -> (Vec3, Vec3) {
    let flat = dims.cmpeq(UVec3::ONE);
    let c = UVec3::from(c).as_vec3();
    (
        Vec3::select(flat, lo, lo + c * spacing),
        Vec3::select(flat, hi, lo + (c + 1.0) * spacing),
    )
}

fn draw_cells(
    state: Res<BreakdownState>,
    volume: Res<VolumeState>,
    mut overlay: ResMut<OverlayLines>,
) {
    let Some(walk) = state.cells.as_ref().filter(|_| state.show_cells) else {
        return;
    };
    let v = &volume.volume;
    let n = walk.cells.len().min(MAX_CELLS_DRAWN);
    for (i, &c) in walk.cells.iter().take(n).enumerate() {
        let (lo, hi) = cell_box(c, v.bounds(), v.dims(), v.spacing());
        let fade = 1.0 - 0.6 * i as f32 / n.max(2) as f32;
        let color = CELL_COLOR.with_alpha(fade);
        for (a, b) in voxcast_core::ray::box_edges(lo, hi) {
            overlay.line(a, b, color, 1.5);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Cells tile the box: the first starts at its low corner, the last ends at its high one,
    /// and a one-voxel axis is one cell across the whole slab.
    #[test]
    fn cells_tile_the_volume_s_box() {
        let spacing = Vec3::new(0.5, 1.0, 2.0);
        let dims = UVec3::new(5, 3, 1);
        let bounds = (Vec3::new(0.0, 0.0, -1.0), Vec3::new(2.0, 2.0, 1.0));
        assert_eq!(
            cell_box([0, 0, 0], bounds, dims, spacing),
            (Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.5, 1.0, 1.0))
        );
        assert_eq!(cell_box([3, 1, 0], bounds, dims, spacing).1, bounds.1);
    }
}
