//! The skip blocks the virtual camera's rays crossed, drawn in the scene: each 8³ block a ray's
//! marched part passed through as a wireframe box, orange where the march had to look inside
//! (the block holds something the transfer function shows), blue where skipping passed it as
//! empty; the more rays crossed it, the more opaque its lines. Computed by the core
//! (`voxcast_core::traffic`) with the inspection's rays, off the frame.

use crate::sandbox::inspect::rays::{InspectSettings, Inspection};
use crate::sandbox::scene::overlay::OverlayLines;
use crate::sandbox::shared::state::VolumeState;
use bevy::prelude::*;
use voxcast_core::traffic::{BlockCount, BlockTraffic};

/// The most blocks drawn (the most crossed first): beyond it the lines would hide the volume.
pub const MAX_BLOCKS_DRAWN: usize = 1500;

/// Blocks the march looked into.
pub const SAMPLED_COLOR: Color = Color::srgb(1.0, 0.55, 0.1);
/// Blocks skipping passed as empty.
pub const SKIPPED_COLOR: Color = Color::srgb(0.25, 0.55, 1.0);

pub(crate) fn plugin(app: &mut App) {
    app.add_systems(
        Update,
        draw_blocks.in_set(crate::sandbox::shared::schedule::Frame::Show),
    );
}

/// The blocks to draw, the most crossed first, at most [`MAX_BLOCKS_DRAWN`].
pub fn drawn(traffic: &BlockTraffic) -> Vec<BlockCount> {
    let mut blocks = traffic.touched.clone();
    blocks.sort_by_key(|b| std::cmp::Reverse(b.crossed));
    blocks.truncate(MAX_BLOCKS_DRAWN);
    blocks
}

/// A block's colour: orange where any crossing ray looked inside, else blue; its opacity
/// rises with the number of rays that crossed it (log scale, the busiest block opaque).
pub fn block_color(b: &BlockCount, most: u32) -> Color {
    let base = if b.sampled > 0 {
        SAMPLED_COLOR
    } else {
        SKIPPED_COLOR
    };
    let share = voxcast_core::cost::heat(b.crossed, most);
    base.with_alpha(0.25 + 0.75 * share)
}

fn draw_blocks(
    settings: Res<InspectSettings>,
    inspection: Res<Inspection>,
    volume: Res<VolumeState>,
    mut overlay: ResMut<OverlayLines>,
) {
    if !settings.show_blocks {
        return;
    }
    let Some(traffic) = &inspection.blocks else {
        return;
    };
    let (spacing, dims) = (volume.volume.spacing(), volume.volume.dims());
    let most = traffic.most_crossed();
    for b in drawn(traffic) {
        let (lo, hi) = BlockTraffic::world_box(b.block, spacing, dims);
        let color = block_color(&b, most);
        for (a, e) in voxcast_core::ray::box_edges(lo, hi) {
            overlay.line(a, e, color, 1.0);
        }
    }
}

/// The counts in words, for the Rays panel.
pub fn summary(traffic: &BlockTraffic) -> String {
    let looked = traffic.touched.iter().filter(|b| b.sampled > 0).count();
    let passed = traffic.touched.len() - looked;
    let total = traffic.blocks.x * traffic.blocks.y * traffic.blocks.z;
    if traffic.skipping {
        format!(
            "The rays crossed {} of the {total} blocks: they looked into {looked} (orange) and \
             skipped {passed} as empty (blue).",
            traffic.touched.len()
        )
    } else {
        format!(
            "The rays crossed {} of the {total} blocks and sampled every one they had positions \
             in ({looked}, orange): nothing is skipped with these settings.",
            traffic.touched.len()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::math::UVec3;

    fn count(crossed: u32, sampled: u32) -> BlockCount {
        BlockCount {
            block: UVec3::ZERO,
            crossed,
            sampled,
        }
    }

    #[test]
    fn colours_say_looked_or_skipped_and_opacity_follows_the_crossings() {
        let looked = block_color(&count(10, 3), 10).to_srgba();
        let skipped = block_color(&count(1, 0), 10).to_srgba();
        assert_eq!(looked.with_alpha(1.0), SAMPLED_COLOR.to_srgba());
        assert_eq!(skipped.with_alpha(1.0), SKIPPED_COLOR.to_srgba());
        assert_eq!(looked.alpha, 1.0, "the busiest block is opaque");
        assert!(skipped.alpha < looked.alpha && skipped.alpha >= 0.25);
    }

    #[test]
    fn the_busiest_blocks_are_drawn_first_and_the_rest_left_out() {
        let traffic = BlockTraffic {
            blocks: UVec3::splat(100),
            touched: (0..MAX_BLOCKS_DRAWN as u32 + 10)
                .map(|i| count(i % 50 + 1, 0))
                .collect(),
            skipping: true,
        };
        let d = drawn(&traffic);
        assert_eq!(d.len(), MAX_BLOCKS_DRAWN);
        assert_eq!(d[0].crossed, 50);
        assert!(summary(&traffic).contains("skipped 1510 as empty"));
    }
}
