//! Acceleration made visible, block by block: which of the volume's 8³ skip blocks
//! ([`crate::skip`]) a set of rays crossed, and in which the march had to look.
//!
//! Each ray is marched exactly as the render marches it (same interval, jitter, skipping and
//! early termination) to find where it stopped; then its path up to there is walked through
//! the blocks (Amanatides–Woo, as the GPU preview's skipping walks them). A block is
//! **crossed** by a ray whose marched part passes through it, and **sampled** when the ray has
//! sample positions in it that the march looks at: every position where nothing is skipped,
//! and under Accumulate's empty-space skipping only those in blocks the transfer function does
//! not make wholly transparent. This is the block-level picture — what the GPU preview skips; the CPU
//! skips finer, by cells and bricks (`crate::skip::VisibleCells`), which the blocks are too
//! coarse to show.
//! First, Maximum and Minimum pass blocks by their running value (not drawn here): under them
//! every crossed block with positions counts as sampled.

use crate::ray::Ray;
use crate::skip::{BLOCK, BlockWalk};
use crate::step::{first_index_from, plan_steps, sample_t};
use crate::trace::{Marcher, Scene};
use crate::volume::{Grid, GridVisitor, Voxel};
use glam::{UVec3, Vec3};

/// One block's counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlockCount {
    /// The block's coordinates (block `b` spans voxels `8·b … 8·(b+1)` per axis).
    pub block: UVec3,
    /// Rays whose marched part passes through it.
    pub crossed: u32,
    /// Rays that looked at a sample position in it.
    pub sampled: u32,
}

/// The blocks a set of rays touched, in block-index order (x fastest).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BlockTraffic {
    /// Blocks per axis.
    pub blocks: UVec3,
    pub touched: Vec<BlockCount>,
    /// Whether "sampled" leaves out empty blocks (Accumulate's empty-space skipping is on).
    pub skipping: bool,
}

impl BlockTraffic {
    /// The world-space box of block `b` of a volume with `spacing` and lattice `dims`.
    pub fn world_box(b: UVec3, spacing: Vec3, dims: UVec3) -> (Vec3, Vec3) {
        let last = dims.saturating_sub(UVec3::ONE).max(UVec3::ONE);
        let lo = (b * BLOCK as u32).min(last);
        let hi = ((b + UVec3::ONE) * BLOCK as u32).min(last);
        (lo.as_vec3() * spacing, hi.as_vec3() * spacing)
    }

    /// The largest crossing count (0 when no block was touched).
    pub fn most_crossed(&self) -> u32 {
        self.touched.iter().map(|b| b.crossed).max().unwrap_or(0)
    }
}

/// The block traffic of `rays`, each with the key (pixel) that decides its jitter.
pub fn block_traffic(scene: &Scene<'_>, rays: &[(Ray, [u32; 2])]) -> BlockTraffic {
    struct Visit<'s, 'a> {
        scene: &'s Scene<'a>,
        rays: &'s [(Ray, [u32; 2])],
    }
    impl GridVisitor for Visit<'_, '_> {
        type Output = Vec<u32>;
        fn visit<T: Voxel>(self, grid: Grid<'_, T>) -> Vec<u32> {
            let m = Marcher::new(self.scene, grid);
            let mut none = crate::breakdown::NoRecord;
            self.rays
                .iter()
                .map(|(ray, key)| m.march(ray, self.scene.jitter(*key), &mut none).positions)
                .collect()
        }
    }
    let positions = scene.volume.visit(Visit { scene, rays });
    // Only the block lattice is needed; a scene without skipping has no ranges computed.
    let grid = match scene.blocks {
        Some(ranges) => ranges.grid(),
        None => crate::skip::block_grid(scene.volume.dims()),
    };
    let blocks = UVec3::new(grid[0] as u32, grid[1] as u32, grid[2] as u32);
    let empty = scene.empty.as_deref().map(|(e, _)| e.flags());
    let mut crossed = vec![0u32; grid[0] * grid[1] * grid[2]];
    let mut sampled = crossed.clone();
    let inv_spacing = 1.0 / scene.volume.spacing();
    let max_lo = scene
        .volume
        .dims()
        .saturating_sub(UVec3::splat(2))
        .as_vec3();
    for ((ray, key), &passed) in rays.iter().zip(&positions) {
        let Some((t0, t1)) = crate::clip::clip_interval(ray, &scene.clip) else {
            continue;
        };
        let plan = plan_steps(
            t0,
            t1,
            scene.dt,
            scene.jitter(*key),
            scene.settings.max_samples,
        );
        if passed == 0 || plan.count == 0 {
            continue;
        }
        // Where the march stopped: through to the end, or at the last position it passed.
        let ran_through = passed >= plan.count && !plan.capped;
        let t_end = if ran_through {
            t1
        } else {
            sample_t(&plan, passed - 1)
        };
        let (o_v, d_v) = (ray.origin * inv_spacing, ray.dir * inv_spacing);
        let start = (o_v + d_v * t0).floor().clamp(Vec3::ZERO, max_lo);
        let start = [start.x as usize, start.y as usize, start.z as usize];
        let mut walk = BlockWalk::new(grid, start, o_v, d_v);
        let inv_dt = 1.0 / plan.dt;
        let mut t_in = t0;
        loop {
            let exit = walk.exit();
            // A sample on a block face belongs to the block it enters (its cell's), so a ray
            // that stopped on a face crossed into the next block.
            let last = if ran_through {
                exit >= t_end
            } else {
                exit > t_end
            };
            let index = walk.index();
            crossed[index] += 1;
            let k_lo = first_index_from(&plan, t_in, inv_dt);
            let k_hi = if last {
                passed
            } else {
                first_index_from(&plan, exit, inv_dt).min(passed)
            };
            let looked = k_hi > k_lo && !empty.is_some_and(|e| e[index]);
            if looked {
                sampled[index] += 1;
            }
            if last || !exit.is_finite() {
                break;
            }
            t_in = exit;
            walk.advance();
        }
    }
    let touched = crossed
        .iter()
        .zip(&sampled)
        .enumerate()
        .filter(|(_, (c, _))| **c > 0)
        .map(|(i, (&crossed, &sampled))| {
            let (x, y, z) = (
                i % grid[0],
                (i / grid[0]) % grid[1],
                i / (grid[0] * grid[1]),
            );
            BlockCount {
                block: UVec3::new(x as u32, y as u32, z as u32),
                crossed,
                sampled,
            }
        })
        .collect();
    BlockTraffic {
        blocks,
        touched,
        skipping: empty.is_some(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::RenderSettings;
    use crate::transfer::TransferFunction;
    use crate::volume::{Volume, VoxelData};

    /// A 33³ volume (4³ blocks) of air with a dense cube in the voxels 16 … 24 of every axis.
    fn cube() -> crate::Prepared {
        let n = 33usize;
        let data: Vec<u8> = (0..n * n * n)
            .map(|i| {
                let (x, y, z) = (i % n, (i / n) % n, i / (n * n));
                let inside = [x, y, z].iter().all(|c| (16..=24).contains(c));
                if inside { 255 } else { 0 }
            })
            .collect();
        Volume::new(
            "cube",
            UVec3::splat(n as u32),
            Vec3::ONE,
            VoxelData::U8(data),
        )
        .unwrap()
        .into()
    }

    fn traffic(v: &crate::Prepared, s: &RenderSettings, rays: &[(Ray, [u32; 2])]) -> BlockTraffic {
        let tf = TransferFunction::ramp(100.0, 200.0, 1.0).unwrap();
        let scene = Scene::new(v, &tf, s, Vec3::Z).unwrap();
        block_traffic(&scene, rays)
    }

    /// Along x through the row of blocks y = z = 2 (voxel 20 is in the cube).
    fn along_x() -> (Ray, [u32; 2]) {
        (
            Ray::new(Vec3::new(-5.0, 20.5, 20.5), Vec3::X).unwrap(),
            [0, 0],
        )
    }

    #[test]
    fn an_axis_ray_crosses_its_row_and_skips_the_air() {
        let v = cube();
        let s = RenderSettings {
            early_termination: false,
            ..Default::default()
        };
        let t = traffic(&v, &s, &[along_x()]);
        assert_eq!(t.blocks, UVec3::splat(4));
        assert!(t.skipping);
        let xs: Vec<u32> = t.touched.iter().map(|b| b.block.x).collect();
        assert_eq!(xs, [0, 1, 2, 3], "the whole row, in order");
        assert!(t.touched.iter().all(|b| b.block.y == 2 && b.block.z == 2));
        assert!(t.touched.iter().all(|b| b.crossed == 1));
        // Blocks 2 and 3 hold the cube (block 3 by its apron): looked at; block 0 is air.
        assert_eq!(t.touched[0].sampled, 0, "air skipped");
        assert_eq!(t.touched[2].sampled, 1);
        // Skipping off: every block the ray has positions in is looked at.
        let off = traffic(
            &v,
            &RenderSettings {
                skipping: false,
                ..s
            },
            &[along_x()],
        );
        assert!(!off.skipping);
        assert!(off.touched.iter().all(|b| b.sampled == 1));
    }

    #[test]
    fn early_termination_ends_the_crossing_in_the_cube() {
        let v = cube();
        let t = traffic(&v, &RenderSettings::default(), &[along_x()]);
        let xs: Vec<u32> = t.touched.iter().map(|b| b.block.x).collect();
        assert_eq!(xs, [0, 1, 2], "the opaque cube stops the ray in block 2");
    }

    #[test]
    fn a_missing_ray_touches_nothing_and_counts_add_up() {
        let v = cube();
        let miss = (
            Ray::new(Vec3::new(-5.0, 50.0, 20.0), Vec3::X).unwrap(),
            [1, 0],
        );
        let t = traffic(&v, &RenderSettings::default(), &[miss]);
        assert!(t.touched.is_empty());
        // Many rays: a block is never sampled by more rays than crossed it, and a diagonal
        // ray crosses at least one block per axis it advances through.
        let rays: Vec<(Ray, [u32; 2])> = (0..40)
            .map(|i| {
                let a = i as f32 * 0.15;
                let dir = Vec3::new(a.cos(), 0.3 + 0.01 * i as f32, a.sin());
                let ray = Ray::new(Vec3::splat(16.0) - dir.normalize() * 40.0, dir).unwrap();
                (ray, [i, 0])
            })
            .collect();
        let t = traffic(&v, &RenderSettings::default(), &rays);
        assert!(t.touched.iter().all(|b| b.sampled <= b.crossed));
        assert!(t.most_crossed() > 1);
        let (lo, hi) = BlockTraffic::world_box(UVec3::new(3, 0, 0), Vec3::ONE, v.dims());
        assert_eq!(
            (lo, hi),
            (Vec3::new(24.0, 0.0, 0.0), Vec3::new(32.0, 8.0, 8.0))
        );
    }

    /// Skipping and early termination off: the blocks a ray samples are exactly the blocks of
    /// its sample positions' cells (brute force, position by position), for rays in many
    /// directions and with jitter.
    #[test]
    fn sampled_blocks_are_the_blocks_of_the_sample_positions() {
        let v = cube();
        let s = RenderSettings {
            skipping: false,
            early_termination: false,
            jitter: true,
            step: crate::step::Length::Voxels(0.7),
            ..Default::default()
        };
        let tf = TransferFunction::ramp(100.0, 200.0, 1.0).unwrap();
        let scene = Scene::new(&v, &tf, &s, Vec3::Z).unwrap();
        for i in 0..60u32 {
            let a = i as f32 * 0.37;
            let dir = Vec3::new(a.cos(), (0.7 * a).sin(), (1.3 * a).cos() + 0.2);
            let ray = Ray::new(Vec3::splat(16.3) - dir.normalize() * 45.0, dir).unwrap();
            let key = [i, 7];
            let t = block_traffic(&scene, &[(ray, key)]);
            let Some((t0, t1)) = crate::clip::clip_interval(&ray, &scene.clip) else {
                assert!(t.touched.is_empty());
                continue;
            };
            let plan = plan_steps(t0, t1, scene.dt, scene.jitter(key), s.max_samples);
            let mut want: Vec<UVec3> = (0..plan.count)
                .map(|k| {
                    let pv = ray.at(sample_t(&plan, k)) / v.spacing();
                    let lo = pv.floor().clamp(Vec3::ZERO, Vec3::splat(31.0)).as_uvec3();
                    lo / BLOCK as u32
                })
                .collect();
            want.sort_by_key(|b| (b.z, b.y, b.x));
            want.dedup();
            let got: Vec<UVec3> = t
                .touched
                .iter()
                .filter(|b| b.sampled > 0)
                .map(|b| b.block)
                .collect();
            assert_eq!(got, want, "ray {i}");
        }
    }
}
