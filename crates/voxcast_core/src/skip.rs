//! Empty-space skipping: whole blocks of the volume that the transfer function makes transparent
//! are crossed without sampling them — exactly, not approximately.
//!
//! The lattice cells are grouped into blocks of [`BLOCK`]³ cells ("macrocells", Levoy 1990,
//! "Efficient ray tracing of volume data"; Parker et al. 1999). For each block the smallest and
//! largest lattice value is stored over every lattice point its cells touch *plus an apron of one
//! point on every side*. Any sample whose cell lies in the block — or, through rounding of its
//! position, in a cell next to it — interpolates only those points, so its value lies in the
//! block's range; if the transfer function's opacity is zero over that whole range, the sample's
//! opacity is exactly zero. In Accumulate such a sample changes neither colour nor opacity
//! (`C + (1 − O)·0·c = C`), so skipping it leaves the image bit for bit the same; the samples
//! that are taken keep their positions `t_enter + (j + k)·dt`.
//!
//! A ray walks the blocks with the 3-D DDA of Amanatides & Woo ("A fast voxel traversal
//! algorithm for ray tracing", 1987): from block to block it steps along the axis whose next face
//! is nearest. Samples in empty blocks are skipped, except within a small margin of a face;
//! samples in other blocks are taken without any further test. Blocks on the volume's border
//! extend to infinity outwards, because sampling clamps positions outside the lattice onto it.
//! The block walk is what the GPU preview does for Accumulate until the cells below are
//! uploaded (the blocks' flags are a texture there), and what the CPU's First, Maximum, Minimum
//! and Sum do with their own block tests; the recorded breakdown
//! ([`crate::trace::trace_ray`]) visits every sample.
//!
//! Finer, for Accumulate on the CPU: [`VisibleCells`] keeps one bit per cell (can any point in
//! it be seen?) in 4×4×4 bricks of one 64-bit word each, and per brick its chessboard distance
//! to the nearest brick holding a visible cell, in all directions and ahead of a ray in each
//! octant. A sample in an empty brick lets the ray *leap* out of the whole cube of bricks that
//! distance guarantees empty ([`VisibleCells::leap_exit_at`], the "distance to occupied" of
//! Cohen & Sheffer 1994, "Proximity clouds"), a ray is only marched inside the box of the
//! bricks that hold visible cells ([`VisibleCells::visible_interval`]) and from its pixel's
//! entry bound on ([`crate::entry`]), and every other sample is taken only where its cell's bit
//! is set. All keep a margin against rounding, so no sample that could be seen is ever passed
//! over. The CPU's Accumulate takes this route, eight samples at a time on the lanes or one at a
//! time, and no longer walks the blocks (the cells' route was 5–30 % faster one at a time).

use crate::minmax::{fmax, fmin};
use crate::transfer::Lut;
use crate::volume::{Grid, GridVisitor, Volume, Voxel};
use glam::{UVec3, Vec3};
use rayon::prelude::*;

/// Cells per block edge.
pub const BLOCK: usize = 8;

/// Per-block value ranges of a volume, in data units.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockRanges {
    /// Blocks per axis.
    pub blocks: UVec3,
    /// `(min, max)` per block, x fastest.
    pub ranges: Vec<(f32, f32)>,
}

/// Boxes per axis for `n` lattice points when a box holds `size` cells along it:
/// ⌈(n − 1)/size⌉, at least one.
pub(crate) fn box_count(n: usize, size: usize) -> usize {
    (n - 1).div_ceil(size).max(1)
}

/// Blocks per axis for `n` lattice points: ⌈(n − 1)/BLOCK⌉, at least one.
fn block_count(n: usize) -> usize {
    box_count(n, BLOCK)
}

/// The smallest and largest raw value in each of `boxes` boxes of lattice points (box `b`
/// spans points `span(b, n)` inclusive along an axis of `n`), each pair handed to `finish`;
/// scanned in parallel over z-slabs, x fastest. Values that are not finite (no data) are left
/// out: a box without any gives `(∞, −∞)`.
pub(crate) fn raw_ranges<T: Voxel, O: Send>(
    g: &Grid<'_, T>,
    boxes: [usize; 3],
    span: impl Fn(usize, usize) -> (usize, usize) + Sync,
    finish: impl Fn((f32, f32)) -> O + Sync,
) -> Vec<O> {
    (0..boxes[2])
        .into_par_iter()
        .flat_map_iter(|bz| {
            let mut out = Vec::with_capacity(boxes[0] * boxes[1]);
            let (z0, z1) = span(bz, g.dims[2]);
            for by in 0..boxes[1] {
                let (y0, y1) = span(by, g.dims[1]);
                for bx in 0..boxes[0] {
                    let (x0, x1) = span(bx, g.dims[0]);
                    let mut lo = f32::INFINITY;
                    let mut hi = f32::NEG_INFINITY;
                    for k in z0..=z1 {
                        for j in y0..=y1 {
                            let row = g.index(x0, j, k);
                            for v in &g.data[row..=row + (x1 - x0)] {
                                let v = v.to_f32();
                                if v.is_finite() {
                                    lo = fmin(lo, v);
                                    hi = fmax(hi, v);
                                }
                            }
                        }
                    }
                    out.push(finish((lo, hi)));
                }
            }
            out
        })
        .collect()
}

/// Blocks per axis for a lattice of `dims` points, as [`BlockRanges::grid`] gives them.
pub fn block_grid(dims: glam::UVec3) -> [usize; 3] {
    dims.to_array().map(|n| block_count(n as usize))
}

impl BlockRanges {
    /// Blocks per axis, as indices.
    pub fn grid(&self) -> [usize; 3] {
        [
            self.blocks.x as usize,
            self.blocks.y as usize,
            self.blocks.z as usize,
        ]
    }

    /// Scans the volume once (in parallel over z-slabs of blocks).
    pub fn of(volume: &Volume) -> Self {
        struct Scan;
        impl GridVisitor for Scan {
            type Output = BlockRanges;
            fn visit<T: Voxel>(self, g: Grid<'_, T>) -> BlockRanges {
                let nb = [
                    block_count(g.dims[0]),
                    block_count(g.dims[1]),
                    block_count(g.dims[2]),
                ];
                // The block's lattice points and a one-point apron, clamped to the lattice.
                let span = |b: usize, n: usize| {
                    (
                        (b * BLOCK).saturating_sub(1),
                        ((b + 1) * BLOCK + 1).min(n - 1),
                    )
                };
                let ranges = raw_ranges(&g, nb, span, |(lo, hi)| {
                    if lo > hi {
                        // A block of no data: a range no test can find a value in (finite,
                        // for the GPU's texture of ranges).
                        return (f32::MAX, f32::MIN);
                    }
                    let (a, b) = (g.to_data(lo), g.to_data(hi));
                    (a.min(b), a.max(b))
                });
                BlockRanges {
                    blocks: UVec3::new(nb[0] as u32, nb[1] as u32, nb[2] as u32),
                    ranges,
                }
            }
        }
        volume.visit(Scan)
    }
}

/// Which blocks the current transfer function makes fully transparent.
#[derive(Clone, Debug, PartialEq)]
pub struct EmptyBlocks {
    blocks: [usize; 3],
    empty: Vec<bool>,
}

impl EmptyBlocks {
    /// Marks blocks whose value range (widened by a hair for float rounding) has zero table
    /// opacity.
    pub fn new(ranges: &BlockRanges, lut: &Lut) -> Self {
        let width = (lut.hi - lut.lo).abs();
        let empty = ranges
            .ranges
            .iter()
            .map(|&(lo, hi)| {
                if lo > hi {
                    return true; // no data at all
                }
                let eps = 1e-5 * (width + lo.abs().max(hi.abs()));
                !lut.any_visible_in(lo - eps, hi + eps)
            })
            .collect();
        Self {
            blocks: [
                ranges.blocks.x as usize,
                ranges.blocks.y as usize,
                ranges.blocks.z as usize,
            ],
            empty,
        }
    }

    /// Blocks per axis.
    pub fn blocks(&self) -> [usize; 3] {
        self.blocks
    }

    /// Whether each block (x fastest) is empty.
    pub fn flags(&self) -> &[bool] {
        &self.empty
    }

    /// The fraction of blocks marked empty.
    pub fn empty_fraction(&self) -> f32 {
        self.empty.iter().filter(|&&e| e).count() as f32 / self.empty.len() as f32
    }

    /// Starts a walk through the blocks along a ray (see [`BlockWalk::new`]).
    #[inline]
    pub fn walk(&self, start_cell_lo: [usize; 3], o_v: Vec3, d_v: Vec3) -> BlockWalk {
        BlockWalk::new(self.blocks, start_cell_lo, o_v, d_v)
    }

    /// Whether the walk's current block is empty, and the `t` where the ray leaves it.
    #[inline(always)]
    pub fn current(&self, w: &BlockWalk) -> (bool, f32) {
        (self.empty[w.index()], w.exit())
    }

    /// Moves the walk into the next block along the ray.
    #[inline(always)]
    pub fn advance(&self, w: &mut BlockWalk) {
        w.advance();
    }
}

/// A ray's walk through the blocks, in order along the ray: the 3-D DDA of Amanatides & Woo.
#[derive(Clone, Copy, Debug)]
pub struct BlockWalk {
    blocks: [usize; 3],
    b: [usize; 3],
    step: [i8; 3],
    /// `t` at which the ray crosses the next block face, per axis.
    t_next: Vec3,
    /// `t` between two faces, per axis.
    t_delta: Vec3,
}

impl BlockWalk {
    /// Starts at the block holding the cell with lower lattice corner `start_cell_lo` (the first
    /// sample's), for a ray given in voxel space for world-unit `t` (origin `o_v`, direction
    /// `d_v`), in a grid of `blocks` blocks per axis.
    #[inline]
    pub fn new(blocks: [usize; 3], start_cell_lo: [usize; 3], o_v: Vec3, d_v: Vec3) -> Self {
        Self::sized(BLOCK, blocks, start_cell_lo, o_v, d_v)
    }

    /// [`BlockWalk::new`] for blocks of `size`³ cells (a coarser level of the same walk).
    #[inline]
    pub fn sized(
        size: usize,
        blocks: [usize; 3],
        start_cell_lo: [usize; 3],
        o_v: Vec3,
        d_v: Vec3,
    ) -> Self {
        let b = [0, 1, 2].map(|a| (start_cell_lo[a] / size).min(blocks[a] - 1));
        let mut w = BlockWalk {
            blocks,
            b,
            step: [0; 3],
            t_next: Vec3::INFINITY,
            t_delta: Vec3::INFINITY,
        };
        for a in 0..3 {
            let d = d_v[a];
            if d > 0.0 {
                w.step[a] = 1;
                w.t_delta[a] = size as f32 / d;
                if b[a] + 1 < blocks[a] {
                    w.t_next[a] = (((b[a] + 1) * size) as f32 - o_v[a]) / d;
                }
            } else if d < 0.0 {
                w.step[a] = -1;
                w.t_delta[a] = size as f32 / -d;
                if b[a] > 0 {
                    w.t_next[a] = ((b[a] * size) as f32 - o_v[a]) / d;
                }
            }
        }
        w
    }

    /// The current block's index (x fastest).
    #[inline(always)]
    pub fn index(&self) -> usize {
        let [x, y, z] = self.b;
        x + self.blocks[0] * (y + self.blocks[1] * z)
    }

    /// The `t` where the ray leaves the current block (infinite for the last along the ray).
    #[inline(always)]
    pub fn exit(&self) -> f32 {
        self.t_next.min_element()
    }

    /// Moves into the next block along the ray (call while [`BlockWalk::exit`] is finite).
    #[inline(always)]
    pub fn advance(&mut self) {
        let t = self.t_next;
        let a = if t.x <= t.y && t.x <= t.z {
            0
        } else if t.y <= t.z {
            1
        } else {
            2
        };
        self.b[a] = (self.b[a] as isize + self.step[a] as isize) as usize;
        let at_border = if self.step[a] > 0 {
            self.b[a] + 1 == self.blocks[a]
        } else {
            self.b[a] == 0
        };
        self.t_next[a] = if at_border {
            f32::INFINITY
        } else {
            self.t_next[a] + self.t_delta[a]
        };
    }
}

/// For every lattice cell, whether the transfer function can make any point in it visible: the
/// finest level of skipping. A sample's value is interpolated from its cell's 8 corners, so it
/// lies between their smallest and largest value; where the table's opacity is zero over that
/// range, the sample is transparent and its interpolation can be left out — exactly.
#[derive(Clone, Debug, PartialEq)]
pub struct VisibleCells {
    /// Cells per axis (`n − 1`, or 1 on a one-point axis).
    cells: [usize; 3],
    /// Bricks of 4×4×4 cells per axis; each brick is one 64-bit word (bit `x + 4y + 16z`), so a
    /// ray's consecutive cells mostly share a word.
    bricks: [usize; 3],
    bits: Vec<u64>,
    /// Per brick, its chessboard distance in bricks to the nearest brick holding a visible
    /// cell: 0 for such a brick, at most [`MAX_LEAP`] (also where no cell can be seen at all).
    distance: Vec<u8>,
    /// Per octant of directions ([`octant`]), each brick's distance as `distance` counts it but
    /// to the nearest brick with a visible cell *ahead* of a ray moving in that octant (none
    /// behind it on any axis it moves along): a ray there leaps out of the cube of bricks ahead
    /// of it, as large as that allows — near a surface it runs along, farther than the cube
    /// around it. Computed for an octant when a ray first asks.
    forward: [std::sync::OnceLock<Vec<u8>>; 8],
    /// The bricks with a visible cell on the surface of the visible region, with their open
    /// faces ([`crate::entry::EntryBounds`] projects those facing the camera); found when
    /// first asked.
    surface: std::sync::OnceLock<Vec<([u32; 3], u8)>>,
    /// The box (voxel space) of the bricks holding a visible cell, widened by
    /// [`BRICK_MARGIN`] and unbounded on the volume's borders; `None` when no cell can be seen.
    visible_box: Option<(Vec3, Vec3)>,
}

/// The largest brick distance [`VisibleCells`] keeps: a leap spans at most this many bricks to
/// either side of the one it starts in.
pub const MAX_LEAP: u8 = 255;

impl VisibleCells {
    /// Classifies every cell of `volume` against `lut` (in parallel over z).
    pub fn new(volume: &Volume, lut: &Lut) -> Self {
        struct Scan<'l>(&'l Lut);
        impl GridVisitor for Scan<'_> {
            type Output = VisibleCells;
            fn visit<T: Voxel>(self, g: Grid<'_, T>) -> VisibleCells {
                let lut = self.0;
                let cells = g.dims.map(|n| (n - 1).max(1));
                let bricks = brick_count(g.dims);
                let nx = g.dims[0];
                let [_, sy, sz] = g.corner_step;
                let test = RangeTest::new::<T>(&g, lut);
                let slab = bricks[0] * bricks[1];
                let mut bits = vec![0u64; slab * bricks[2]];
                // One z-slab of bricks per task: its words are contiguous.
                bits.par_chunks_mut(slab)
                    .enumerate()
                    .for_each(|(bz, words)| {
                        let mut columns: Vec<(f32, f32)> = Vec::with_capacity(nx);
                        for k in bz * 4..(bz * 4 + 4).min(cells[2]) {
                            for j in 0..cells[1] {
                                let start = g.index(0, j, k);
                                // The four lattice rows around this row of cells.
                                let r = |o: usize| &g.data[start + o..start + o + nx];
                                let (a, b, c, d) = (r(0), r(sy), r(sz), r(sy + sz));
                                // Per column i: min and max of the 4 points (i, j..j+1, k..k+1).
                                columns.clear();
                                columns.extend(a.iter().zip(b).zip(c).zip(d).map(
                                    |(((a, b), c), d)| {
                                        let v = [a.to_f32(), b.to_f32(), c.to_f32(), d.to_f32()];
                                        (
                                            fmin(fmin(v[0], v[1]), fmin(v[2], v[3])),
                                            fmax(fmax(v[0], v[1]), fmax(v[2], v[3])),
                                        )
                                    },
                                ));
                                let row_words = &mut words[bricks[0] * (j / 4)..];
                                let bit_yz = 4 * (j % 4) + 16 * (k % 4);
                                for i in 0..cells[0] {
                                    let (p, q) = (columns[i], columns[(i + 1).min(nx - 1)]);
                                    if test.any_visible(&g, lut, fmin(p.0, q.0), fmax(p.1, q.1)) {
                                        row_words[i / 4] |= 1 << (bit_yz + i % 4);
                                    }
                                }
                            }
                        }
                    });
                let distance = brick_distances(bricks, &bits);
                let visible_box = visible_box(bricks, &bits);
                VisibleCells {
                    cells,
                    bricks,
                    bits,
                    distance,
                    forward: Default::default(),
                    surface: Default::default(),
                    visible_box,
                }
            }
        }
        volume.visit(Scan(lut))
    }

    /// Whether the cell with lower corner `lo` can be visible.
    #[inline(always)]
    pub fn visible(&self, lo: [usize; 3]) -> bool {
        self.lookup(lo) == Cell::Visible
    }

    /// The cell's state: visible, invisible, or in a brick with no visible cell at all.
    #[inline(always)]
    pub fn lookup(&self, lo: [usize; 3]) -> Cell {
        let word = self.bits[self.brick_of(lo)];
        let bit = (lo[0] & 3) | (lo[1] & 3) << 2 | (lo[2] & 3) << 4;
        if word & (1 << bit) != 0 {
            Cell::Visible
        } else if word == 0 {
            Cell::EmptyBrick
        } else {
            Cell::Invisible
        }
    }

    /// For a sample in the cell `lo` of an empty brick: the `t` where the ray (origin `o_v`,
    /// inverse direction `inv_d`, voxel space, world-unit `t`) leaves the cube of bricks around
    /// it that holds no visible cell — every brick within its distance
    /// ([`VisibleCells::distances`]) less one, so at least its own brick — shrunk by
    /// [`BRICK_MARGIN`]. The sample lies in that cube, so every later sample before that `t`
    /// lies inside it by more than any rounding of its position: its cell is invisible. (A
    /// sample within the margin of the face it moves towards gets a `t` before its own: no
    /// leap.) The cube's faces on the volume's border are infinitely far (positions outside
    /// are clamped in), and so is the `t` of a ray that leaves only through those.
    #[inline]
    pub fn leap_exit(&self, lo: [usize; 3], o_v: Vec3, inv_d: Vec3) -> f32 {
        self.leap_exit_at(lo, self.brick_distance(lo), o_v, inv_d)
    }

    /// The distance ([`VisibleCells::distances`]) of the brick holding cell `lo`: 0 where it
    /// holds a visible cell.
    #[inline(always)]
    pub fn brick_distance(&self, lo: [usize; 3]) -> u8 {
        self.distance[self.brick_of(lo)]
    }

    /// The index of the brick holding the cell with lower corner `lo`, in the distance maps.
    #[inline(always)]
    pub fn brick_of(&self, lo: [usize; 3]) -> usize {
        self.brick_index(lo.map(|l| l >> 2))
    }

    /// Each brick's distance to the nearest brick with a visible cell ahead of a ray moving in
    /// `octant` ([`octant`]; 0 for a brick with one, at most [`MAX_LEAP`]): with it,
    /// [`VisibleCells::leap_exit_at`] leaves the cube of bricks ahead of the ray, whose faces
    /// towards the ray's motion are those of the cube around it of the same distance.
    pub fn forward_distances(&self, octant: usize) -> &[u8] {
        self.forward[octant & 7].get_or_init(|| forward_distances(self.bricks, &self.bits, octant))
    }

    /// The bricks holding a visible cell with a face on the volume's border or next to a
    /// brick without one (x, y, z in bricks), each with those faces as bits (`2a` the lower
    /// face on axis `a`, `2a + 1` the upper); found on the first call.
    pub fn surface_bricks(&self) -> &[([u32; 3], u8)] {
        self.surface
            .get_or_init(|| crate::entry::surface_bricks(self.bricks, &self.bits))
    }

    /// [`VisibleCells::leap_exit`] with the brick's distance already read (the distance of
    /// [`VisibleCells::brick_distance`], or of [`VisibleCells::forward_distances`] for a ray in
    /// that octant).
    #[inline(always)]
    pub fn leap_exit_at(&self, lo: [usize; 3], distance: u8, o_v: Vec3, inv_d: Vec3) -> f32 {
        let b = lo.map(|l| (l >> 2) as u32);
        let reach = u32::from(distance).max(1) - 1;
        let mut t_exit = f32::INFINITY;
        for a in 0..3 {
            // Only the face the ray moves towards; none along an axis it does not move on.
            let face = if inv_d[a] > 0.0 && inv_d[a] < f32::INFINITY {
                let above = b[a] + reach + 1;
                if above >= self.bricks[a] as u32 {
                    continue;
                }
                (above * 4) as f32 - BRICK_MARGIN
            } else if inv_d[a] < 0.0 && inv_d[a] > f32::NEG_INFINITY {
                if b[a] <= reach {
                    continue;
                }
                ((b[a] - reach) * 4) as f32 + BRICK_MARGIN
            } else {
                continue;
            };
            t_exit = fmin(t_exit, (face - o_v[a]) * inv_d[a]);
        }
        t_exit
    }

    /// Where along a ray (voxel space: origin `o_v`, inverse direction `inv_d`, world-unit `t`)
    /// cells can be visible: the `t` interval in the box of the bricks holding a visible cell,
    /// widened by [`BRICK_MARGIN`] so that every sample outside it — rounding included — lies in
    /// a cell outside the box, an invisible one. `None` where the ray misses the box (or no cell
    /// can be seen).
    #[inline]
    pub fn visible_interval(&self, o_v: Vec3, inv_d: Vec3) -> Option<(f32, f32)> {
        let (lo, hi) = self.visible_box?;
        let (mut t0, mut t1) = (f32::NEG_INFINITY, f32::INFINITY);
        for a in 0..3 {
            let (low, high) = (lo[a], hi[a]);
            if inv_d[a].is_infinite() {
                // Parallel to this axis' faces: inside between them or never.
                if !(o_v[a] > low && o_v[a] < high) {
                    return None;
                }
                continue;
            }
            let (ta, tb) = ((low - o_v[a]) * inv_d[a], (high - o_v[a]) * inv_d[a]);
            t0 = fmax(t0, fmin(ta, tb));
            t1 = fmin(t1, fmax(ta, tb));
        }
        (t0 <= t1).then_some((t0, t1))
    }

    /// The index of brick `b` (x fastest) in [`VisibleCells::words`].
    #[inline(always)]
    pub fn brick_index(&self, b: [usize; 3]) -> usize {
        b[0] + self.bricks[0] * (b[1] + self.bricks[1] * b[2])
    }

    /// Per brick (x fastest), its chessboard distance in bricks to the nearest brick with a
    /// visible cell (0 for such a brick; at most [`MAX_LEAP`]).
    pub fn distances(&self) -> &[u8] {
        &self.distance
    }

    /// Bricks of 4×4×4 cells per axis.
    pub fn bricks(&self) -> [usize; 3] {
        self.bricks
    }

    /// One word a brick (x fastest), bit `x + 4y + 16z` for the brick's cell `(x, y, z)`: set
    /// where that cell can be visible (what the GPU preview uploads).
    pub fn words(&self) -> &[u64] {
        &self.bits
    }

    /// The fraction of cells that can be visible.
    pub fn visible_fraction(&self) -> f32 {
        let ones: u32 = self.bits.iter().map(|b| b.count_ones()).sum();
        ones as f32 / (self.cells[0] * self.cells[1] * self.cells[2]) as f32
    }
}

/// Each brick's chessboard distance (in bricks, capped at [`MAX_LEAP`]) to the nearest brick
/// whose word is non-zero: two raster passes of the 3×3×3 mask with unit weights, forward then
/// backward (Rosenfeld & Pfaltz 1966; Borgefors 1986 for three dimensions), exact for this
/// metric.
fn brick_distances(bricks: [usize; 3], words: &[u64]) -> Vec<u8> {
    let [nx, ny, nz] = bricks;
    let mut d: Vec<u8> = words
        .iter()
        .map(|&w| if w != 0 { 0 } else { MAX_LEAP })
        .collect();
    if d.iter().all(|&v| v == MAX_LEAP) {
        return d;
    }
    let at = |x: usize, y: usize, z: usize| x + nx * (y + ny * z);
    // The 13 neighbours before a brick in raster order (z, then y, then x).
    let before: Vec<[isize; 3]> = (-1..=1)
        .flat_map(|z| (-1..=1).flat_map(move |y| (-1..=1).map(move |x| [x, y, z])))
        .filter(|&[x, y, z]| (z, y, x) < (0, 0, 0))
        .collect();
    let n = d.len();
    let mut pass = |order: &mut dyn Iterator<Item = usize>, sign: isize| {
        for i in order {
            let (x, y, z) = (i % nx, (i / nx) % ny, i / (nx * ny));
            let mut best = d[i];
            for o in &before {
                let (a, b, c) = (
                    x as isize + sign * o[0],
                    y as isize + sign * o[1],
                    z as isize + sign * o[2],
                );
                if a < 0
                    || b < 0
                    || c < 0
                    || a >= nx as isize
                    || b >= ny as isize
                    || c >= nz as isize
                {
                    continue;
                }
                best = best.min(d[at(a as usize, b as usize, c as usize)].saturating_add(1));
            }
            d[i] = best;
        }
    };
    pass(&mut (0..n), 1);
    pass(&mut (0..n).rev(), -1);
    d
}

/// The octant of direction `d`: bit `a` set where it moves towards −a (an axis it does not move
/// along counts as +).
pub fn octant(d: Vec3) -> usize {
    usize::from(d.x < 0.0) | usize::from(d.y < 0.0) << 1 | usize::from(d.z < 0.0) << 2
}

/// [`brick_distances`] restricted to the bricks ahead in `octant`: for brick `b`, the least
/// `max_a |v_a − b_a|` over bricks `v` with a non-zero word and `v_a − b_a` of the octant's sign
/// (or 0) on every axis. One raster pass from the far corner: a brick's value is one more than
/// the least of its (up to) 7 neighbours ahead, exact for this metric.
fn forward_distances(bricks: [usize; 3], words: &[u64], octant: usize) -> Vec<u8> {
    let [nx, ny, nz] = bricks;
    let mut d = vec![MAX_LEAP; words.len()];
    let step = |a: usize| if octant >> a & 1 == 1 { -1isize } else { 1 };
    let s = [step(0), step(1), step(2)];
    // Visit each axis from its far end (the direction of motion) back.
    let order = |n: usize, s: isize| -> Vec<usize> {
        if s > 0 {
            (0..n).rev().collect()
        } else {
            (0..n).collect()
        }
    };
    let (xs, ys, zs) = (order(nx, s[0]), order(ny, s[1]), order(nz, s[2]));
    let ahead = |c: usize, s: isize, n: usize| -> Option<usize> {
        let c = c as isize + s;
        (c >= 0 && c < n as isize).then_some(c as usize)
    };
    for &z in &zs {
        for &y in &ys {
            for &x in &xs {
                let i = x + nx * (y + ny * z);
                if words[i] != 0 {
                    d[i] = 0;
                    continue;
                }
                let mut best = MAX_LEAP;
                for m in 1..8usize {
                    let (mx, my, mz) = (m & 1 == 1, m & 2 == 2, m & 4 == 4);
                    let nb = (
                        if mx { ahead(x, s[0], nx) } else { Some(x) },
                        if my { ahead(y, s[1], ny) } else { Some(y) },
                        if mz { ahead(z, s[2], nz) } else { Some(z) },
                    );
                    if let (Some(a), Some(b), Some(c)) = nb {
                        best = best.min(d[a + nx * (b + ny * c)].saturating_add(1));
                    }
                }
                d[i] = best;
            }
        }
    }
    d
}

/// The voxel-space box of the bricks whose word is non-zero (see `VisibleCells::visible_box`).
fn visible_box(bricks: [usize; 3], words: &[u64]) -> Option<(Vec3, Vec3)> {
    let (mut lo, mut hi) = ([usize::MAX; 3], [0usize; 3]);
    for (i, _) in words.iter().enumerate().filter(|(_, w)| **w != 0) {
        let b = [
            i % bricks[0],
            (i / bricks[0]) % bricks[1],
            i / (bricks[0] * bricks[1]),
        ];
        for a in 0..3 {
            lo[a] = lo[a].min(b[a]);
            hi[a] = hi[a].max(b[a]);
        }
    }
    if lo[0] == usize::MAX {
        return None;
    }
    let side = |a: usize| {
        let low = if lo[a] == 0 {
            f32::NEG_INFINITY
        } else {
            (lo[a] * 4) as f32 - BRICK_MARGIN
        };
        let high = if hi[a] + 1 == bricks[a] {
            f32::INFINITY
        } else {
            ((hi[a] + 1) * 4) as f32 + BRICK_MARGIN
        };
        (low, high)
    };
    let (x, y, z) = (side(0), side(1), side(2));
    Some((Vec3::new(x.0, y.0, z.0), Vec3::new(x.1, y.1, z.1)))
}

/// Bricks of 4×4×4 cells per axis for a lattice of `dims` points (cells: `n − 1`, or 1 on a
/// one-point axis).
pub fn brick_count(dims: [usize; 3]) -> [usize; 3] {
    dims.map(|n| (n - 1).max(1).div_ceil(4))
}

/// A cell's state in [`VisibleCells`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cell {
    Visible,
    Invisible,
    /// Invisible, and so is every cell of its 4×4×4 brick.
    EmptyBrick,
}

/// How far inside an empty brick (in voxels) a sample must lie for the brick to be skipped.
pub const BRICK_MARGIN: f32 = 1e-3;

/// "Can a value between these two raw values be visible?", answered fast. For integer types two
/// tables over every raw value give the table's visible-entry counts below and above each value,
/// so a test is two lookups; for floats the range is converted and looked up directly (widened
/// by a hair, as float interpolation may round just outside its corners' range).
enum RangeTest {
    Table {
        offset: i32,
        below: Vec<u32>,
        above: Vec<u32>,
        descending: bool,
    },
    Float,
}

impl RangeTest {
    fn new<T: Voxel>(g: &Grid<'_, T>, lut: &Lut) -> Self {
        match T::TABLE {
            Some((offset, count)) => {
                // Interpolating integers stays inside the corners' range exactly, and so does
                // the (monotone) rescale: no widening needed.
                let (below, above) = (0..count)
                    .map(|r| lut.visible_counts(g.to_data((r as i32 - offset) as f32)))
                    .unzip();
                RangeTest::Table {
                    offset,
                    below,
                    above,
                    descending: g.slope < 0.0,
                }
            }
            None => RangeTest::Float,
        }
    }

    /// Whether a value between raw `lo` and `hi` (`lo ≤ hi`) can have non-zero opacity.
    #[inline(always)]
    fn any_visible<T: Voxel>(&self, g: &Grid<'_, T>, lut: &Lut, lo: f32, hi: f32) -> bool {
        match self {
            RangeTest::Table {
                offset,
                below,
                above,
                descending,
            } => {
                let (a, b) = if *descending { (hi, lo) } else { (lo, hi) };
                let ia = (a as i32 + offset) as usize;
                let ib = (b as i32 + offset) as usize;
                above[ib] > below[ia]
            }
            RangeTest::Float => {
                let (a, b) = (g.to_data(lo), g.to_data(hi));
                let (lo, hi) = (a.min(b), a.max(b));
                let eps = 1e-5 * ((lut.hi - lut.lo).abs() + lo.abs().max(hi.abs()));
                lut.any_visible_in(lo - eps, hi + eps)
            }
        }
    }
}

#[cfg(test)]
mod tests {
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
    fn nearest(
        dims: [usize; 3],
        words: &[u64],
        p: [usize; 3],
        admit: impl Fn([i64; 3]) -> bool,
    ) -> u8 {
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
}
