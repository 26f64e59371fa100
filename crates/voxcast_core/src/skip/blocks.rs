//! Blocks of [`BLOCK`]³ cells: their value ranges (with a one-point apron), which of them the
//! transfer function makes transparent, and a ray's walk from block to block.

use super::*;

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
pub(super) fn block_count(n: usize) -> usize {
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
    pub(super) empty: Vec<bool>,
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
    #[cfg(test)]
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
    pub(super) b: [usize; 3],
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
