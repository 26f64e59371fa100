//! Skipping's tests: ranges with their apron, the block walk, the cells' bits and distances,
//! and images the same bit for bit with and without skipping.

use super::cells::{brick_distances, forward_distances};
use super::*;
use crate::transfer::TransferFunction;
use crate::volume::VoxelData;

#[test]
fn block_ranges_include_an_apron() {
    // 17 points per axis: blocks cover points 0..=8 and 8..=16, with aprons 0..=9 and 7..=16.
    let n = 17u32;
    let mut data = vec![0u8; (n * n * n) as usize];
    data[9] = 200; // point (9, 0, 0): in block 1's cells, in block 0's apron
    data[(16 * n * n) as usize] = 50; // point (0, 0, 16): block (0, 0, 1) only
    let v = Volume::new("t", UVec3::splat(n), Vec3::ONE, VoxelData::U8(data)).unwrap();
    let r = BlockRanges::of(&v);
    assert_eq!(r.blocks, UVec3::new(2, 2, 2));
    assert_eq!(r.ranges[0], (0.0, 200.0));
    assert_eq!(r.ranges[1], (0.0, 200.0));
    assert_eq!(r.ranges[2], (0.0, 0.0));
    assert_eq!(r.ranges[4], (0.0, 50.0));
    let tf = TransferFunction::ramp(100.0, 200.0, 1.0).unwrap();
    let e = EmptyBlocks::new(&r, &tf.bake(0.0, 200.0));
    assert_eq!(
        e.empty,
        vec![false, false, true, true, true, true, true, true]
    );
    assert!((e.empty_fraction() - 0.75).abs() < 1e-6);
}

#[test]
fn the_walk_visits_blocks_in_order_along_the_ray() {
    let v = Volume::new(
        "t",
        UVec3::new(33, 17, 9),
        Vec3::ONE,
        VoxelData::U8(vec![0; 33 * 17 * 9]),
    )
    .unwrap();
    let r = BlockRanges::of(&v);
    let tf = TransferFunction::constant([1.0; 3], 0.0).unwrap();
    let e = EmptyBlocks::new(&r, &tf.bake(0.0, 1.0));
    assert_eq!(r.blocks, UVec3::new(4, 2, 1));
    // Along +x from x = −2 at y = 9: blocks (0,1), (1,1), (2,1), (3,1), leaving at x = 8, 16, 24.
    let o = Vec3::new(-2.0, 9.0, 4.0);
    let mut w = e.walk([0, 9, 4], o, Vec3::X);
    let mut exits = vec![];
    loop {
        let (empty, t) = e.current(&w);
        assert!(empty);
        exits.push(t);
        if !t.is_finite() {
            break;
        }
        e.advance(&mut w);
    }
    assert_eq!(exits, vec![10.0, 18.0, 26.0, f32::INFINITY]);
    // Diagonally in −x, −y: faces alternate between the axes.
    let d = Vec3::new(-1.0, -0.5, 0.0);
    let mut w = e.walk([31, 15, 0], Vec3::new(31.0, 15.0, 1.0), d);
    let mut blocks = vec![w.b];
    while e.current(&w).1.is_finite() {
        e.advance(&mut w);
        blocks.push(w.b);
    }
    assert_eq!(
        blocks,
        vec![[3, 1, 0], [2, 1, 0], [2, 0, 0], [1, 0, 0], [0, 0, 0]]
    );
}

#[test]
fn visible_cells_follow_their_corners() {
    // 3×2×2 points: two cells along x. Cell 0 spans values 0..=10, cell 1 spans 10..=250.
    let data = vec![0u8, 10, 250, 0, 10, 10, 0, 10, 10, 0, 10, 10];
    let v = Volume::new("t", UVec3::new(3, 2, 2), Vec3::ONE, VoxelData::U8(data)).unwrap();
    let tf = TransferFunction::ramp(100.0, 200.0, 1.0).unwrap();
    let vis = VisibleCells::new(&v, &tf.bake(0.0, 250.0));
    assert!(!vis.visible([0, 0, 0]));
    assert!(vis.visible([1, 0, 0]));
    assert!((vis.visible_fraction() - 0.5).abs() < 1e-6);
    // One-point axes have one cell.
    let v = Volume::new(
        "t",
        UVec3::new(1, 1, 1),
        Vec3::ONE,
        VoxelData::U8(vec![150]),
    )
    .unwrap();
    assert!(VisibleCells::new(&v, &tf.bake(0.0, 250.0)).visible([0, 0, 0]));
}

#[test]
fn empty_bricks_are_left_at_their_shrunk_faces() {
    // 9 points along x (8 cells = 2 bricks); only the last cell can be seen.
    let mut data = vec![0u8; 9 * 2 * 2];
    for j in 0..2 {
        for k in 0..2 {
            data[8 + 9 * (j + 2 * k)] = 200;
        }
    }
    let v = Volume::new("t", UVec3::new(9, 2, 2), Vec3::ONE, VoxelData::U8(data)).unwrap();
    let tf = TransferFunction::ramp(100.0, 200.0, 1.0).unwrap();
    let vis = VisibleCells::new(&v, &tf.bake(0.0, 200.0));
    assert_eq!(vis.lookup([0, 0, 0]), Cell::EmptyBrick);
    assert_eq!(vis.lookup([5, 0, 0]), Cell::Invisible);
    assert_eq!(vis.lookup([7, 0, 0]), Cell::Visible);
    let inv = 1.0 / Vec3::X;
    let o = Vec3::new(-3.0, 0.5, 0.5);
    // From x = 1, leave brick 0 just before x = 4 (its neighbour holds a visible cell).
    assert_eq!(vis.distances(), &[1, 0]);
    let t = vis.leap_exit([1, 0, 0], o, inv);
    assert!((t - (7.0 - BRICK_MARGIN)).abs() < 1e-5, "{t}");
    // A sample at x = 3.9999 (t = 6.9999) is too close to the face: no leap.
    assert!(vis.leap_exit([3, 0, 0], o, inv) < 6.9999);
}

/// Random sparse bricks on grids with odd and one-brick axes, from none to 40 % non-zero:
/// (bricks per axis, density in %, words).
fn sparse_grids() -> Vec<([usize; 3], u64, Vec<u64>)> {
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    let mut grids = Vec::new();
    for dims in [[7, 5, 9], [1, 6, 4], [12, 1, 1], [3, 3, 3]] {
        for density in [0, 1, 3, 40] {
            let n = dims[0] * dims[1] * dims[2];
            let words = (0..n).map(|_| u64::from(next() % 100 < density)).collect();
            grids.push((dims, density, words));
        }
    }
    grids
}

/// The brick at index `i` (x fastest).
fn brick_xyz(i: usize, dims: [usize; 3]) -> [usize; 3] {
    [
        i % dims[0],
        (i / dims[0]) % dims[1],
        i / (dims[0] * dims[1]),
    ]
}

/// By brute force: the least chessboard distance from brick `p` to a brick with a non-zero
/// word whose offset from `p` `admit` accepts, at most [`MAX_LEAP`].
fn nearest(dims: [usize; 3], words: &[u64], p: [usize; 3], admit: impl Fn([i64; 3]) -> bool) -> u8 {
    (0..words.len())
        .filter(|&j| words[j] != 0)
        .map(|j| {
            let q = brick_xyz(j, dims);
            [0, 1, 2].map(|a| q[a] as i64 - p[a] as i64)
        })
        .filter(|&off| admit(off))
        .map(|off| off.iter().map(|o| o.unsigned_abs()).max().unwrap_or(0))
        .min()
        .map_or(MAX_LEAP, |m| m.min(u64::from(MAX_LEAP)) as u8)
}

#[test]
fn forward_distances_count_only_the_bricks_ahead() {
    for (dims, density, words) in sparse_grids() {
        let around = brick_distances(dims, &words);
        for octant in 0..8 {
            let sign = |a: usize| if octant >> a & 1 == 1 { -1i64 } else { 1 };
            let d = forward_distances(dims, &words, octant);
            for (i, &found) in d.iter().enumerate() {
                let p = brick_xyz(i, dims);
                let ahead = |off: [i64; 3]| (0..3).all(|a| off[a] * sign(a) >= 0);
                let want = nearest(dims, &words, p, ahead);
                assert_eq!(
                    found, want,
                    "{dims:?} {density} % octant {octant} brick {p:?}"
                );
                assert!(found >= around[i], "never shorter than the cube around");
            }
        }
    }
    assert_eq!(octant(Vec3::new(1.0, -0.5, 0.0)), 2);
    assert_eq!(octant(Vec3::new(-1.0, -1.0, -1.0)), 7);
}

#[test]
fn brick_distances_are_chessboard_distances() {
    for (dims, density, words) in sparse_grids() {
        let d = brick_distances(dims, &words);
        for (i, &found) in d.iter().enumerate() {
            let p = brick_xyz(i, dims);
            let expect = nearest(dims, &words, p, |_| true);
            assert_eq!(found, expect, "dims {dims:?} density {density} brick {p:?}");
        }
    }
}

#[test]
fn leaps_reach_as_far_as_the_distance() {
    // 41 points along x (40 cells = 10 bricks); only the last brick's cells can be seen.
    let mut data = vec![0u8; 41 * 2 * 2];
    for j in 0..2 {
        for k in 0..2 {
            data[40 + 41 * (j + 2 * k)] = 200;
        }
    }
    let v = Volume::new("t", UVec3::new(41, 2, 2), Vec3::ONE, VoxelData::U8(data)).unwrap();
    let tf = TransferFunction::ramp(100.0, 200.0, 1.0).unwrap();
    let vis = VisibleCells::new(&v, &tf.bake(0.0, 200.0));
    assert_eq!(vis.distances(), &[9, 8, 7, 6, 5, 4, 3, 2, 1, 0]);
    // From x = 1 (brick 0, distance 9) the ray may pass bricks 0..=8: up to x = 36.
    let t = vis.leap_exit([1, 0, 0], Vec3::ZERO, Vec3::ONE / Vec3::X);
    assert!((t - (36.0 - BRICK_MARGIN)).abs() < 1e-4, "{t}");
    // Going the other way it leaves through the volume's border: no face.
    let o = Vec3::new(1.0, 0.5, 0.5);
    assert_eq!(
        vis.leap_exit([1, 0, 0], o, Vec3::ONE / Vec3::NEG_X),
        f32::INFINITY
    );
    // Nor along an axis it does not move on.
    assert_eq!(
        vis.leap_exit([1, 0, 0], o, Vec3::ONE / Vec3::Y),
        f32::INFINITY
    );
}

#[test]
fn one_point_axes_have_one_block() {
    let v = Volume::new(
        "t",
        UVec3::new(1, 1, 20),
        Vec3::ONE,
        VoxelData::U8(vec![1; 20]),
    )
    .unwrap();
    let r = BlockRanges::of(&v);
    assert_eq!(r.blocks, UVec3::new(1, 1, 3));
}
