//! [`VisibleCells`]: one bit per cell in 4×4×4 bricks, each brick's distance to the nearest
//! visible one (in all directions and ahead of a ray in each octant), and the box of the bricks
//! that hold visible cells.

use super::*;

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
            .get_or_init(|| surface_bricks(self.bricks, &self.bits))
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
pub(super) fn brick_distances(bricks: [usize; 3], words: &[u64]) -> Vec<u8> {
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
pub(super) fn forward_distances(bricks: [usize; 3], words: &[u64], octant: usize) -> Vec<u8> {
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
pub(super) fn visible_box(bricks: [usize; 3], words: &[u64]) -> Option<(Vec3, Vec3)> {
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

/// The bricks (of `bricks` per axis, one visibility word each in `words`, x fastest) that
/// hold a visible cell and have a face on the volume's border or next to a brick without one,
/// with those faces as bits (`2a` for the lower face on axis `a`, `2a + 1` for the upper).
pub(crate) fn surface_bricks(bricks: [usize; 3], words: &[u64]) -> Vec<([u32; 3], u8)> {
    let [nx, ny, nz] = bricks;
    let visible = |x: usize, y: usize, z: usize| words[x + nx * (y + ny * z)] != 0;
    let mut out = Vec::new();
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                if !visible(x, y, z) {
                    continue;
                }
                let open = [
                    x == 0 || !visible(x - 1, y, z),
                    x + 1 == nx || !visible(x + 1, y, z),
                    y == 0 || !visible(x, y - 1, z),
                    y + 1 == ny || !visible(x, y + 1, z),
                    z == 0 || !visible(x, y, z - 1),
                    z + 1 == nz || !visible(x, y, z + 1),
                ];
                let faces = open
                    .iter()
                    .enumerate()
                    .fold(0u8, |f, (i, &o)| f | u8::from(o) << i);
                if faces != 0 {
                    out.push(([x as u32, y as u32, z as u32], faces));
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The surface bricks and their open faces against their definition, brick by brick.
    #[test]
    fn surface_bricks_are_the_visible_ones_with_open_faces() {
        let bricks = [5, 4, 3];
        let words: Vec<u64> = (0..60u64).map(|i| u64::from(i % 7 != 3)).collect();
        let surface = surface_bricks(bricks, &words);
        let at = |x: i64, y: i64, z: i64| {
            let inside = (0..5).contains(&x) && (0..4).contains(&y) && (0..3).contains(&z);
            inside && words[(x + 5 * (y + 4 * z)) as usize] != 0
        };
        let steps = [
            (-1, 0, 0),
            (1, 0, 0),
            (0, -1, 0),
            (0, 1, 0),
            (0, 0, -1),
            (0, 0, 1),
        ];
        let mut expected = Vec::new();
        for z in 0..3i64 {
            for y in 0..4i64 {
                for x in 0..5i64 {
                    let faces = steps.iter().enumerate().fold(0u8, |f, (i, (a, b, c))| {
                        f | u8::from(!at(x + a, y + b, z + c)) << i
                    });
                    if at(x, y, z) && faces != 0 {
                        expected.push(([x as u32, y as u32, z as u32], faces));
                    }
                }
            }
        }
        assert_eq!(surface, expected);
        assert!(surface.len() < words.iter().filter(|w| **w != 0).count());
    }
}
