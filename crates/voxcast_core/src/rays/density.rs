//! The ray-density grid: how many rays pass through each cell of a grid over the scene, and
//! their mean direction there — RayVis's volume and vector-field views, computed exactly.
//!
//! Cells have edge `S` and are aligned to the world origin: cell `(i, j, k)` spans
//! `[iS, (i+1)S)` on each axis. They are grouped in cubic chunks of `N` cells, and only chunks
//! that a counted segment touches are stored (RayVis's two-level sparse structure). Each ray's
//! counted segment ([`crate::rays::set`]) is walked cell by cell with the 3-D DDA of Amanatides &
//! Woo ("A fast voxel traversal algorithm for ray tracing", 1987); a cell counts the ray once
//! when the segment passes through it with positive length, and adds the ray's *unit* direction
//! to its sum (normalised at the end: the mean direction).
//!
//! **Ties.** A point on a cell face belongs to the cell the segment enters from there: a segment
//! starting on the face `x = iS` going towards −x starts in cell `i − 1`; one ending on a face
//! does not enter the next cell; a segment through an edge or corner steps every axis it
//! crosses at once, so the cells it only touches are not counted. A segment lying *in* a face
//! plane (its direction parallel to it) is counted in the cell above the plane (the half-open
//! rule). Rounding can make a crossing computed incrementally miss an exact corner; the side
//! cell it then touches is passed for a rounding's length.
//!
//! **Bad rays are skipped and counted, never fatal**: a ray that is not finite, has a zero
//! direction or `t_max < t_min` ([`RayRecord::check`]) or starts beyond ±2³⁰ cells; a segment
//! longer than [`DensityParams::max_cells_per_ray`] cells (an endless miss) is cut there and
//! counted as capped.
//!
//! The direction sums are kept in fixed point (2⁻²⁰ per component: integer additions, in any
//! order the same), so the counts and the mean directions are the same for any number of
//! threads. The work: the chunks are found first by walking the rays through cells of edge
//! `N·S` (the estimate shown before computing, and how many rays cross each chunk); then the
//! chunks are cut into slabs across x, one a thread, balanced by those crossings, and each
//! thread walks every ray that can reach its slab and adds the visits inside it to its own
//! cells — no visit is written down and read back, and no two threads write one cell. A ray
//! that crosses several slabs is walked by each from its start (so every walk takes the same
//! steps, bit for bit); a walk stops once it has passed its slab, and a ray that cannot reach a
//! slab is not walked for it.

mod sliced;
pub use sliced::{DensitySlices, density_in};

use super::set::{Filter, RayRecord, RaySet};
use crate::render::Cancelled;
use crate::slices::Deadline;
use glam::{IVec3, Vec3};
use rayon::prelude::*;
use std::collections::{BTreeMap, HashMap};
use std::hash::{BuildHasherDefault, Hasher};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Rays per block of work (the unit of progress and cancelling).
const RAYS_PER_BLOCK: usize = 4096;

/// Cell visits a walk lists before adding them to the cells (see [`add_visits`]).
const PENDING_VISITS: usize = 1024;

/// Fixed-point units per unit of a direction component in the sums.
const DIRECTION_SCALE: f32 = (1u32 << 20) as f32;

/// The largest cell coordinate a segment may start at (beyond, `i32` steps could overflow).
const MAX_START_CELL: f32 = (1u32 << 30) as f32;

/// What a density is computed from (see the module's text).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DensityParams {
    /// Cell edge `S`, world units.
    pub cell: f32,
    /// Cells per chunk edge `N`.
    pub chunk: u32,
    pub filter: Filter,
    /// RayVis's miss-detection tolerance.
    pub tolerance: f32,
    /// Every `stride`-th counted ray.
    pub stride: usize,
    /// The most cells one ray is walked through.
    pub max_cells_per_ray: u32,
}

impl Default for DensityParams {
    fn default() -> Self {
        Self {
            cell: 1.0,
            chunk: 16,
            filter: Filter::All,
            tolerance: 0.0,
            stride: 1,
            max_cells_per_ray: 1 << 16,
        }
    }
}

impl DensityParams {
    /// Checks the values a user can type.
    pub fn check(&self) -> Result<(), String> {
        if !(self.cell.is_finite() && self.cell > 0.0) {
            return Err(format!("cell size {} must be a positive number", self.cell));
        }
        if !(1..=64).contains(&self.chunk) {
            return Err(format!("chunk size {} must be 1 … 64 cells", self.chunk));
        }
        if !(self.tolerance.is_finite() && self.tolerance >= 0.0) {
            return Err(format!(
                "miss tolerance {} must be 0 or more",
                self.tolerance
            ));
        }
        if self.max_cells_per_ray == 0 {
            return Err("the cells per ray must be at least 1".into());
        }
        Ok(())
    }

    /// Bytes one stored chunk takes (a count and a fixed-point direction sum per cell).
    pub fn chunk_bytes(&self) -> usize {
        (self.chunk as usize).pow(3) * (4 + 24)
    }
}

/// One stored chunk: its cells, x fastest.
#[derive(Clone, Debug, PartialEq)]
pub struct Chunk {
    pub cells: Vec<CellSum>,
}

/// One cell: the ray count and the sum of unit directions (fixed point, 2²⁰ per
/// unit), side by side so that a visit writes one cache line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CellSum {
    pub count: u32,
    pub direction: [i64; 3],
}

impl CellSum {
    /// Counts one ray through the cell, with its fixed-point unit direction.
    fn add(&mut self, unit: [i32; 3]) {
        self.count += 1;
        for (s, u) in self.direction.iter_mut().zip(unit) {
            *s += i64::from(u);
        }
    }
}

impl Chunk {
    fn new(per_chunk: usize) -> Self {
        Self {
            cells: vec![CellSum::default(); per_chunk],
        }
    }
}

/// What happened to the rays.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Report {
    /// Rays walked (after the filter and stride).
    pub rays: usize,
    /// Rays skipped as not finite, with a zero direction or `t_max < t_min`.
    pub malformed: usize,
    /// Rays skipped for starting too far out.
    pub out_of_range: usize,
    /// Rays cut short at the cells-per-ray cap.
    pub capped: usize,
    /// Cell visits in all (the sum of every count).
    pub visits: u64,
}

impl Report {
    /// Adds another block's report.
    fn add(&mut self, r: &Report) {
        self.rays += r.rays;
        self.malformed += r.malformed;
        self.out_of_range += r.out_of_range;
        self.capped += r.capped;
        self.visits += r.visits;
    }
}

/// The chunk holding `cell` in chunks of `n` cells a side, and the cell's index in it (x
/// fastest).
fn locate(cell: IVec3, n: i32) -> (IVec3, usize) {
    let chunk = cell.div_euclid(IVec3::splat(n));
    let l = cell - chunk * n;
    (chunk, (l.x + n * (l.y + n * l.z)) as usize)
}

/// A hasher for chunk keys: three small integers need no protection against chosen keys (the
/// default SipHash took a tenth of a density's time), only a spread of their bits.
#[derive(Default)]
struct KeyHasher(u64);

impl Hasher for KeyHasher {
    fn write(&mut self, bytes: &[u8]) {
        // A key's integers arrive as their bytes: four at a time.
        for word in bytes.chunks(4) {
            let mut b = [0u8; 4];
            b[..word.len()].copy_from_slice(word);
            self.write_u64(u64::from(u32::from_le_bytes(b)));
        }
    }

    fn write_usize(&mut self, v: usize) {
        self.write_u64(v as u64);
    }

    fn write_u64(&mut self, v: u64) {
        // FxHash's round: rotate, mix in, multiply by an odd constant.
        self.0 = (self.0.rotate_left(5) ^ v).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

/// A map from chunk keys.
type KeyMap<V> = HashMap<IVec3Key, V, BuildHasherDefault<KeyHasher>>;

/// A computed ray density.
#[derive(Clone, Debug, PartialEq)]
pub struct Density {
    pub params: DensityParams,
    /// The stored chunks, by chunk coordinates (chunk `c` holds cells `cN … cN + N − 1`).
    pub chunks: BTreeMap<IVec3Key, Chunk>,
    pub report: Report,
}

/// Chunk coordinates as a map key (ordered, so iteration is deterministic).
pub type IVec3Key = [i32; 3];

impl Density {
    fn locate(&self, cell: IVec3) -> (IVec3Key, usize) {
        let (c, i) = locate(cell, self.params.chunk as i32);
        (c.to_array(), i)
    }

    /// Rays through `cell`.
    pub fn count(&self, cell: IVec3) -> u32 {
        let (c, i) = self.locate(cell);
        self.chunks.get(&c).map_or(0, |ch| ch.cells[i].count)
    }

    /// The mean unit direction of the rays through `cell` (zero where none passed).
    pub fn mean_direction(&self, cell: IVec3) -> Vec3 {
        let (c, i) = self.locate(cell);
        self.chunks.get(&c).map_or(Vec3::ZERO, |ch| {
            let [x, y, z] = ch.cells[i].direction;
            Vec3::new(x as f32, y as f32, z as f32).normalize_or_zero()
        })
    }

    /// Bytes the stored chunks take.
    pub fn memory_bytes(&self) -> usize {
        self.chunks.len() * self.params.chunk_bytes()
    }

    /// Bytes a dense grid over the same chunks' bounding box would take.
    pub fn dense_bytes(&self) -> usize {
        let Some((lo, hi)) = self.chunk_bounds() else {
            return 0;
        };
        let n = (hi - lo + IVec3::ONE).as_i64vec3();
        (n.x * n.y * n.z) as usize * self.params.chunk_bytes()
    }

    /// The lowest and highest stored chunk coordinates.
    pub fn chunk_bounds(&self) -> Option<(IVec3, IVec3)> {
        let mut keys = self.chunks.keys().map(|k| IVec3::from_array(*k));
        let first = keys.next()?;
        Some(keys.fold((first, first), |(lo, hi), k| (lo.min(k), hi.max(k))))
    }
}

/// The outcome of walking one segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Walk {
    pub visited: u32,
    pub capped: bool,
}

/// Walks the cells of edge `s` that the segment `origin + t·dir`, `t ∈ (t0, t1)`, passes through
/// with positive length, in order, calling `visit` with each (at most `max` of them; see the
/// module's text for the ties). The start must lie within ±2³⁰ cells (checked by the caller).
pub fn walk_cells(
    origin: Vec3,
    dir: Vec3,
    t: (f32, f32),
    s: f32,
    max: u32,
    mut visit: impl FnMut(IVec3),
) -> Walk {
    walk_cells_while(origin, dir, t, s, max, |c| {
        visit(c);
        true
    })
}

/// The cell a segment starting at `t0` starts in (the first [`walk_cells`] visits).
fn start_cell(origin: Vec3, dir: Vec3, t0: f32, s: f32) -> IVec3 {
    let q = (origin + dir * t0) / s;
    let mut c = IVec3::ZERO;
    for a in 0..3 {
        let floor = q[a].floor();
        // On a face going down: the segment enters the cell below.
        let on_face = floor == q[a];
        c[a] = floor as i32 - i32::from(on_face && dir[a] < 0.0);
    }
    c
}

/// [`walk_cells`], stopping after a cell for which `visit` returns `false` (that cell is
/// counted in [`Walk::visited`]; the walk is not capped).
fn walk_cells_while(
    origin: Vec3,
    dir: Vec3,
    (t0, t1): (f32, f32),
    s: f32,
    max: u32,
    mut visit: impl FnMut(IVec3) -> bool,
) -> Walk {
    if t1.is_nan() || t0.is_nan() || t1 <= t0 {
        return Walk {
            visited: 0,
            capped: false,
        };
    }
    let mut c = start_cell(origin, dir, t0, s);
    let mut step = IVec3::ZERO;
    let mut t_next = Vec3::INFINITY;
    let mut t_delta = Vec3::INFINITY;
    for a in 0..3 {
        if dir[a] > 0.0 {
            step[a] = 1;
            t_delta[a] = s / dir[a];
            t_next[a] = ((c[a] + 1) as f32 * s - origin[a]) / dir[a];
        } else if dir[a] < 0.0 {
            step[a] = -1;
            t_delta[a] = s / -dir[a];
            t_next[a] = (c[a] as f32 * s - origin[a]) / dir[a];
        }
    }
    let mut visited = 0u32;
    loop {
        if visited == max {
            return Walk {
                visited,
                capped: true,
            };
        }
        visited += 1;
        if !visit(c) {
            return Walk {
                visited,
                capped: false,
            };
        }
        let t = t_next.min_element();
        if t.is_nan() || t >= t1 {
            return Walk {
                visited,
                capped: false,
            };
        }
        // Every axis crossed at this t at once: an edge or corner is passed, not visited.
        for a in 0..3 {
            if t_next[a] == t {
                c[a] += step[a];
                t_next[a] += t_delta[a];
            }
        }
    }
}

/// Why a ray is not walked, if it is not.
enum Skip {
    Malformed,
    OutOfRange,
}

fn walkable(r: &RayRecord, p: &DensityParams) -> Result<(f32, f32), Skip> {
    r.check().map_err(|_| Skip::Malformed)?;
    let (t0, t1) = r.segment(p.tolerance);
    if t1.is_nan() {
        return Err(Skip::Malformed);
    }
    let start = r.at(t0) / p.cell;
    let far = start.abs().max_element();
    if far.is_nan() || far >= MAX_START_CELL {
        return Err(Skip::OutOfRange);
    }
    Ok((t0, t1))
}

/// The most memory a density may take, bytes: a computation whose [`estimate`] needs more is
/// refused before it starts, with the estimate and what to change.
pub const MAX_BYTES: usize = 2 << 30;

/// What computing a density would take: the chunks it would store and their bytes, found by
/// walking the rays through the chunks alone (cells of edge `N·S`) — cheap, and shown before
/// the computation starts. (A segment that grazes a chunk only by rounding may add one more.)
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Estimate {
    pub chunks: usize,
    pub bytes: usize,
}

/// The estimate for `set` under `params`.
pub fn estimate(set: &RaySet, p: &DensityParams) -> Estimate {
    estimate_within(set, p, usize::MAX).expect("no limit")
}

/// The estimate, or `None` as soon as it is sure to pass `max_bytes` (so a hopeless choice —
/// cells far too small — is refused at once instead of after walking every ray).
pub fn estimate_within(set: &RaySet, p: &DensityParams, max_bytes: usize) -> Option<Estimate> {
    let limit = max_bytes / p.chunk_bytes().max(1);
    let chunks = chunks_touched_within(set, p, limit)?.len();
    Some(Estimate {
        chunks,
        bytes: chunks * p.chunk_bytes(),
    })
}

/// The chunks the counted segments pass through, sorted, each with the number of rays that
/// cross it: the rays walked through cells of edge `N·S` (in parallel).
fn chunks_touched(set: &RaySet, p: &DensityParams) -> Vec<(IVec3Key, u32)> {
    chunks_touched_within(set, p, usize::MAX).expect("no limit")
}

/// [`chunks_touched`], or `None` once one block of rays alone touches more than `limit`.
fn chunks_touched_within(
    set: &RaySet,
    p: &DensityParams,
    limit: usize,
) -> Option<Vec<(IVec3Key, u32)>> {
    let rays: Vec<&RayRecord> = set.selected(p.filter, p.tolerance, p.stride).collect();
    let over = AtomicBool::new(false);
    let maps: Vec<KeyMap<u32>> = rays
        .par_chunks(RAYS_PER_BLOCK)
        .map(|block| touched_by(block, p, limit, &over))
        .collect();
    if over.load(Ordering::Relaxed) {
        return None;
    }
    Some(merge_touched(maps))
}

/// The chunks one block of rays passes through, with how many of its rays cross each; `over`
/// is set (and the walk stops) once they are more than `limit`.
fn touched_by(
    block: &[&RayRecord],
    p: &DensityParams,
    limit: usize,
    over: &AtomicBool,
) -> KeyMap<u32> {
    let edge = p.cell * p.chunk as f32;
    let max = p.max_cells_per_ray / p.chunk + 2;
    let mut chunks = KeyMap::default();
    for r in block {
        if over.load(Ordering::Relaxed) {
            break;
        }
        if let Ok(t) = walkable(r, p) {
            walk_cells(r.origin, r.direction, t, edge, max, |c| {
                *chunks.entry(c.to_array()).or_insert(0u32) += 1;
            });
        }
        if chunks.len() > limit {
            over.store(true, Ordering::Relaxed);
        }
    }
    chunks
}

/// The blocks' chunks as one sorted list, their crossings summed.
fn merge_touched(maps: Vec<KeyMap<u32>>) -> Vec<(IVec3Key, u32)> {
    let mut all: BTreeMap<IVec3Key, u32> = BTreeMap::new();
    for (k, n) in maps.into_iter().flatten() {
        let e = all.entry(k).or_insert(0);
        *e = e.saturating_add(n);
    }
    all.into_iter().collect()
}

/// Computes the density of `set` (see the module's text); `progress(done, total)` in rays, and
/// `cancel` stops it between blocks.
pub fn compute(
    set: &RaySet,
    p: &DensityParams,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<Density, Cancelled> {
    compute_in(set, p, chunks_touched(set, p), progress, cancel)
}

/// A thread's share of the grid: the chunks whose x coordinate lies in a range, and the cells
/// beneath them, `lo ≤ x < hi` in cells (the first and last slabs reach out to any x, for the
/// visits to chunks the chunk pass did not find).
#[derive(Clone, Debug, PartialEq)]
struct Slab {
    /// Its chunks: a range of the sorted keys (sorted by x first).
    keys: std::ops::Range<usize>,
    lo: i64,
    hi: i64,
}

/// Cuts the sorted chunks into at most `parts` slabs across x, of about equal crossings: each
/// cut at the end of the plane of chunks whose running sum of crossings lies nearest its share.
fn slabs(touched: &[(IVec3Key, u32)], n: i32, parts: usize) -> Vec<Slab> {
    // The ends of the planes: (index past the plane's last chunk, crossings up to there).
    let mut ends: Vec<(usize, u64)> = Vec::new();
    let mut sum = 0u64;
    for (i, (key, crossings)) in touched.iter().enumerate() {
        sum += u64::from(*crossings);
        if touched.get(i + 1).is_none_or(|next| next.0[0] != key[0]) {
            ends.push((i + 1, sum));
        }
    }
    let total = sum;
    let mut cuts: Vec<usize> = Vec::new();
    // The last plane's end is the end of the last slab, never a cut.
    let inner = &ends[..ends.len().saturating_sub(1)];
    for k in 1..parts.max(1) as u64 {
        let share = total * k / parts as u64;
        let after = cuts.last().copied().unwrap_or(0);
        let nearest = inner
            .iter()
            .filter(|(end, _)| *end > after)
            .min_by_key(|(_, sum)| sum.abs_diff(share));
        if let Some(&(end, _)) = nearest {
            cuts.push(end);
        }
    }
    let mut out = Vec::new();
    let (mut start, mut lo) = (0, i64::MIN);
    for end in cuts {
        let hi = (i64::from(touched[end - 1].0[0]) + 1) * i64::from(n);
        out.push(Slab {
            keys: start..end,
            lo,
            hi,
        });
        (start, lo) = (end, hi);
    }
    out.push(Slab {
        keys: start..touched.len(),
        lo,
        hi: i64::MAX,
    });
    out
}

impl Slab {
    /// Whether the ray's walk can visit a cell of the slab: not when it starts past the slab
    /// and moves away from it (exactly), nor when it ends short of it by more than the
    /// rounding of a walk that long can add.
    fn may_reach(&self, r: &RayRecord, (t0, t1): (f32, f32), s: f32) -> bool {
        let dx = r.direction.x;
        let start = i64::from(start_cell(r.origin, r.direction, t0, s).x);
        if (dx >= 0.0 && start >= self.hi) || (dx <= 0.0 && start < self.lo) {
            return false;
        }
        let (p0, p1) = (r.at(t0) / s, r.at(t1) / s);
        if !(p1.is_finite()) {
            return true;
        }
        // The crossings are summed step by step: a few ulps of the positions a step, far
        // below 2⁻²⁰ of them.
        let steps = (p1 - p0).abs().element_sum();
        let margin = 2.0 + steps * (p0.abs().max(p1.abs()).max_element() + 1.0) / (1 << 20) as f32;
        let end = p1.x;
        !((dx > 0.0 && end + margin < self.lo as f32)
            || (dx < 0.0 && end - margin >= self.hi as f32))
    }
}

/// What one slab's walk found: its chunks, the visits to chunks the chunk pass did not find
/// (a rounding's graze), and its part of the report.
struct SlabCount {
    chunks: Vec<(IVec3Key, Chunk)>,
    stray: Vec<(IVec3, [i32; 3])>,
    report: Report,
}

/// Walks `rays` for one slab, adding the visits inside it to its own cells; the first slab
/// also counts the rays, malformed and out of range, for the report.
fn count_slab(
    rays: &[&RayRecord],
    p: &DensityParams,
    slab: &Slab,
    keys: &[IVec3Key],
    first: bool,
    tick: &(dyn Fn(usize) -> bool + Sync),
) -> Result<SlabCount, Cancelled> {
    let mut walk = SlabWalk::new(p, slab, keys);
    walk.walk(rays, p, slab, first, tick, Deadline::NONE)?;
    Ok(walk.finish(&keys[slab.keys.clone()]))
}

/// One slab's walk so far: its cells, the visits to chunks the chunk pass did not find, its
/// part of the report, and the next block of rays (a walk done in slices resumes there).
#[derive(Clone, Debug)]
struct SlabWalk {
    index: KeyMap<usize>,
    chunks: Vec<Chunk>,
    stray: Vec<(IVec3, [i32; 3])>,
    report: Report,
    /// The chunk of the last visit: its lowest cell and where its cells start.
    cached: Option<(IVec3, u32)>,
    next_block: usize,
}

impl SlabWalk {
    fn new(p: &DensityParams, slab: &Slab, keys: &[IVec3Key]) -> Self {
        let per_chunk = (p.chunk as usize).pow(3);
        let keys = &keys[slab.keys.clone()];
        Self {
            index: keys.iter().enumerate().map(|(i, k)| (*k, i)).collect(),
            chunks: keys.iter().map(|_| Chunk::new(per_chunk)).collect(),
            stray: Vec::new(),
            report: Report::default(),
            cached: None,
            next_block: 0,
        }
    }

    /// Walks the blocks of `rays` from the next on, until every block is walked (true) or
    /// `deadline` passes (false; at least one block is walked a call).
    fn walk(
        &mut self,
        rays: &[&RayRecord],
        p: &DensityParams,
        slab: &Slab,
        first: bool,
        tick: &(dyn Fn(usize) -> bool + Sync),
        deadline: Deadline,
    ) -> Result<bool, Cancelled> {
        let n = p.chunk as i32;
        let mut pending = Vec::with_capacity(PENDING_VISITS);
        let mut walked = 0;
        while self.next_block * RAYS_PER_BLOCK < rays.len() {
            if walked > 0 && deadline.passed() {
                return Ok(false);
            }
            walked += 1;
            let at = self.next_block * RAYS_PER_BLOCK;
            let block = &rays[at..(at + RAYS_PER_BLOCK).min(rays.len())];
            self.next_block += 1;
            if !tick(block.len()) {
                return Err(Cancelled);
            }
            for ray in block {
                let t = match walkable(ray, p) {
                    Ok(t) => t,
                    Err(skip) => {
                        if first {
                            match skip {
                                Skip::Malformed => self.report.malformed += 1,
                                Skip::OutOfRange => self.report.out_of_range += 1,
                            }
                        }
                        continue;
                    }
                };
                self.report.rays += usize::from(first);
                if !slab.may_reach(ray, t, p.cell) {
                    continue;
                }
                let u = ray.direction.normalize() * DIRECTION_SCALE;
                let unit = [u.x as i32, u.y as i32, u.z as i32];
                let dx = ray.direction.x;
                let (mut visits, mut last_mine) = (0u64, false);
                let walk = walk_cells_while(
                    ray.origin,
                    ray.direction,
                    t,
                    p.cell,
                    p.max_cells_per_ray,
                    |c| {
                        let x = i64::from(c.x);
                        last_mine = slab.lo <= x && x < slab.hi;
                        if !last_mine {
                            // Past the slab: the walk only moves further away.
                            return !((dx > 0.0 && x >= slab.hi) || (dx < 0.0 && x < slab.lo));
                        }
                        visits += 1;
                        // Within the last visit's chunk (the usual case): no division, no lookup.
                        // (Cells lie within ±2³¹ of each other, so a wrapped difference is in
                        // 0..n only when the true one is.)
                        let inside = |(lo, i): (IVec3, u32)| {
                            let l = c.wrapping_sub(lo);
                            (l.cmpge(IVec3::ZERO) & l.cmplt(IVec3::splat(n)))
                                .all()
                                .then(|| (i, (l.x + n * (l.y + n * l.z)) as u32))
                        };
                        let at = match self.cached.and_then(inside) {
                            Some(at) => at,
                            None => {
                                let (chunk, local) = locate(c, n);
                                match self.index.get(&chunk.to_array()) {
                                    Some(&i) => {
                                        self.cached = Some((chunk * n, i as u32));
                                        (i as u32, local as u32)
                                    }
                                    None => {
                                        self.stray.push((c, unit));
                                        return true;
                                    }
                                }
                            }
                        };
                        pending.push(at);
                        if pending.len() == PENDING_VISITS {
                            add_visits(&mut self.chunks, &mut pending, unit);
                        }
                        true
                    },
                );
                add_visits(&mut self.chunks, &mut pending, unit);
                self.report.visits += visits;
                // The cap is counted by the slab holding the last cell the cap allowed.
                self.report.capped += usize::from(walk.capped && last_mine);
            }
        }
        Ok(true)
    }

    /// The slab's count, its chunks keyed by `keys` (the slab's own).
    fn finish(self, keys: &[IVec3Key]) -> SlabCount {
        SlabCount {
            chunks: keys.iter().copied().zip(self.chunks).collect(),
            stray: self.stray,
            report: self.report,
        }
    }
}

/// Adds a ray's `pending` visits (chunk, cell in it) to the chunks and empties the list: a loop
/// of independent additions, whose cache misses the processor overlaps (made inside the walk,
/// each one waits behind the walk's own work).
fn add_visits(chunks: &mut [Chunk], pending: &mut Vec<(u32, u32)>, unit: [i32; 3]) {
    for &(chunk, cell) in pending.iter() {
        chunks[chunk as usize].cells[cell as usize].add(unit);
    }
    pending.clear();
}

/// [`compute`] with the chunks found beforehand: `touched`, sorted, with their crossings
/// (visits to others are added one by one at the end).
fn compute_in(
    set: &RaySet,
    p: &DensityParams,
    touched: Vec<(IVec3Key, u32)>,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<Density, Cancelled> {
    let n = p.chunk as i32;
    let rays: Vec<&RayRecord> = set.selected(p.filter, p.tolerance, p.stride).collect();
    let total = rays.len();
    let slabs = slabs(&touched, n, rayon::current_num_threads());
    let keys: Vec<IVec3Key> = touched.into_iter().map(|(k, _)| k).collect();
    // Progress: the rays every slab has walked, over the slabs.
    let done = AtomicUsize::new(0);
    let tick = |rays: usize| {
        let now = done.fetch_add(rays, Ordering::Relaxed) + rays;
        progress(now / slabs.len(), total);
        !cancel.load(Ordering::Relaxed)
    };
    let counted: Vec<Result<SlabCount, Cancelled>> = slabs
        .par_iter()
        .enumerate()
        .map(|(i, slab)| count_slab(&rays, p, slab, &keys, i == 0, &tick))
        .collect();
    let counted = counted.into_iter().collect::<Result<Vec<_>, _>>()?;
    Ok(assemble(p, counted))
}

/// The density from its slabs' counts: their chunks, and the stray visits added one by one.
fn assemble(p: &DensityParams, counted: Vec<SlabCount>) -> Density {
    let n = p.chunk as i32;
    let per_chunk = (p.chunk as usize).pow(3);
    let mut chunks = BTreeMap::new();
    let mut report = Report::default();
    let mut stray_visits = Vec::new();
    for c in counted {
        chunks.extend(c.chunks);
        stray_visits.extend(c.stray);
        report.add(&c.report);
    }
    for (c, unit) in stray_visits {
        let (chunk, i) = locate(c, n);
        let ch = chunks
            .entry(chunk.to_array())
            .or_insert_with(|| Chunk::new(per_chunk));
        ch.cells[i].add(unit);
    }
    Density {
        params: *p,
        chunks,
        report,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    fn cells(origin: Vec3, dir: Vec3, t: (f32, f32), s: f32) -> Vec<IVec3> {
        let mut out = Vec::new();
        walk_cells(origin, dir, t, s, 1000, |c| out.push(c));
        out
    }

    #[test]
    fn an_axis_parallel_ray_visits_its_row() {
        let got = cells(Vec3::new(0.5, 0.5, 0.5), Vec3::X, (0.0, 3.2), 1.0);
        assert_eq!(got, (0..4).map(|i| IVec3::new(i, 0, 0)).collect::<Vec<_>>());
        // Ending exactly on a face does not enter the next cell.
        let got = cells(Vec3::new(0.5, 0.5, 0.5), Vec3::X, (0.0, 2.5), 1.0);
        assert_eq!(got.len(), 3);
        // Backwards, starting on a face: the cell below is the first.
        let got = cells(Vec3::new(2.0, 0.5, 0.5), Vec3::NEG_X, (0.0, 1.5), 1.0);
        assert_eq!(got, [IVec3::new(1, 0, 0), IVec3::new(0, 0, 0)]);
    }

    #[test]
    fn a_diagonal_through_corners_skips_the_cells_it_only_touches() {
        // From corner (0,0,0) along (1,1,1): cells (0,0,0), (1,1,1), (2,2,2).
        let got = cells(Vec3::ZERO, Vec3::ONE, (0.0, 3.0), 1.0);
        assert_eq!(got, [IVec3::ZERO, IVec3::ONE, IVec3::splat(2)]);
        // Along a face plane (y = 1 exactly, parallel to it): the cell above the plane.
        let got = cells(Vec3::new(0.5, 1.0, 0.5), Vec3::X, (0.0, 1.0), 1.0);
        assert_eq!(got, [IVec3::new(0, 1, 0), IVec3::new(1, 1, 0)]);
    }

    #[test]
    fn direction_length_sets_the_units_of_t_and_cells_the_units_of_space() {
        // Direction of length 2: t = 1 is two world units; cells of edge 0.5.
        let got = cells(
            Vec3::new(0.25, 0.25, 0.25),
            Vec3::new(2.0, 0.0, 0.0),
            (0.0, 1.0),
            0.5,
        );
        assert_eq!(
            got.len(),
            5,
            "x from 0.25 to 2.25 crosses cells 0 … 4 of edge 0.5"
        );
        let got = cells(Vec3::new(-0.7, 0.1, 0.1), Vec3::X, (0.0, 0.5), 1.0);
        assert_eq!(
            got,
            [IVec3::new(-1, 0, 0)],
            "negative cells are floor-aligned"
        );
        // A ray starting inside a cell counts it.
        let got = cells(Vec3::new(3.3, 3.3, 3.3), Vec3::Y, (0.0, 0.1), 1.0);
        assert_eq!(got, [IVec3::splat(3)]);
    }

    #[test]
    fn caps_and_empty_segments() {
        let w = walk_cells(Vec3::ZERO, Vec3::X, (0.0, f32::INFINITY), 1.0, 100, |_| {});
        assert_eq!(
            w,
            Walk {
                visited: 100,
                capped: true
            }
        );
        let w = walk_cells(Vec3::ZERO, Vec3::X, (1.0, 1.0), 1.0, 100, |_| {});
        assert_eq!(w.visited, 0, "zero length: nothing");
    }

    fn ray(id: u32, origin: Vec3, direction: Vec3, t_max: f32, t_hit: f32) -> RayRecord {
        RayRecord {
            id,
            origin,
            direction,
            t_min: 0.0,
            t_max,
            t_hit,
        }
    }

    /// Random rays in a box, some hitting, some missing, some malformed.
    fn random_set(n: u32, seed: u32) -> RaySet {
        let mut s = seed;
        let mut next = || {
            s = s.wrapping_mul(1664525).wrapping_add(1013904223);
            (s >> 8) as f32 / (1u32 << 24) as f32
        };
        let rays = (0..n)
            .map(|i| {
                let o = Vec3::new(next(), next(), next()) * 20.0 - 10.0;
                let d = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * (0.5 + 3.0 * next());
                let t_max = 1.0 + 10.0 * next();
                let t_hit = if next() < 0.5 { t_max * next() } else { -1.0 };
                ray(i, o, d, t_max, t_hit)
            })
            .collect();
        RaySet { trace_id: 1, rays }
    }

    fn density(set: &RaySet, p: &DensityParams, threads: usize) -> Density {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| compute(set, p, &|_, _| {}, &AtomicBool::new(false)).unwrap())
    }

    #[test]
    fn counts_are_conserved_and_the_same_on_any_thread_count() {
        let set = random_set(9000, 5);
        let p = DensityParams {
            cell: 0.7,
            chunk: 8,
            ..Default::default()
        };
        let one = density(&set, &p, 1);
        let three = density(&set, &p, 3);
        assert!(
            one == three,
            "counts and direction sums differ between 1 and 3 threads"
        );
        // Conservation: the counts add up to the cells each ray crossed.
        let crossed: u64 = set
            .rays
            .iter()
            .map(|r| {
                let t = r.segment(0.0);
                u64::from(
                    walk_cells(
                        r.origin,
                        r.direction,
                        t,
                        p.cell,
                        p.max_cells_per_ray,
                        |_| {},
                    )
                    .visited,
                )
            })
            .sum();
        let summed: u64 = one
            .chunks
            .values()
            .flat_map(|c| c.cells.iter())
            .map(|c| u64::from(c.count))
            .sum();
        assert_eq!(summed, crossed);
        assert_eq!(one.report.visits, crossed);
        assert_eq!(one.report.rays, 9000);
        // The estimate names exactly the chunks stored.
        let e = estimate(&set, &p);
        assert_eq!(e.chunks, one.chunks.len());
        assert_eq!(e.bytes, one.memory_bytes());
        assert!(one.memory_bytes() <= one.dense_bytes());
        // Within a limit it holds, the same estimate; below it, refused.
        assert_eq!(estimate_within(&set, &p, e.bytes), Some(e));
        assert_eq!(estimate_within(&set, &p, e.bytes / 2), None);
    }

    /// Against a brute-force reference: the segment sampled at 20 000 points finds every cell
    /// the walk counts, except cells the segment only grazes (less than a sampling step inside).
    #[test]
    fn the_walk_matches_fine_sampling() {
        let set = random_set(300, 77);
        for r in &set.rays {
            let (t0, t1) = r.segment(0.0);
            let s = 0.9;
            let walked: HashSet<IVec3> = {
                let mut v = HashSet::new();
                walk_cells(r.origin, r.direction, (t0, t1), s, 100_000, |c| {
                    assert!(v.insert(c), "a cell visited twice");
                });
                v
            };
            let n = 20_000;
            let step = (t1 - t0) / n as f32;
            let sampled: HashSet<IVec3> = (0..n)
                .map(|i| {
                    let t = t0 + (i as f32 + 0.5) * step;
                    (r.at(t) / s).floor().as_ivec3()
                })
                .collect();
            assert!(
                sampled.is_subset(&walked),
                "ray {}: the walk missed a cell",
                r.id
            );
            for c in walked.difference(&sampled) {
                // The segment's length inside a cell the sampling missed is below its step.
                let lo = c.as_vec3() * s;
                let hi = lo + s;
                let inv = 1.0 / r.direction;
                let (a, b) = ((lo - r.origin) * inv, (hi - r.origin) * inv);
                let enter = a.min(b).max_element().max(t0);
                let exit = a.max(b).min_element().min(t1);
                assert!(
                    exit - enter <= 2.0 * step,
                    "ray {}: cell {c} inside for {}",
                    r.id,
                    exit - enter
                );
            }
        }
    }

    #[test]
    fn filters_directions_and_bad_rays() {
        let set = RaySet {
            trace_id: 0,
            rays: vec![
                ray(0, Vec3::new(0.5, 0.5, 0.5), Vec3::X * 2.0, 2.0, 1.0), // hit at x = 2.5
                ray(1, Vec3::new(0.5, 0.5, 0.5), Vec3::Y, 2.0, -1.0),      // miss
                ray(2, Vec3::ZERO, Vec3::ZERO, 1.0, -1.0),                 // zero direction
                ray(3, Vec3::splat(f32::NAN), Vec3::X, 1.0, -1.0),         // not finite
                ray(4, Vec3::splat(1e12), Vec3::X, 1.0, -1.0),             // far out
                ray(5, Vec3::ZERO, Vec3::Z, f32::INFINITY, -1.0),          // endless miss
            ],
        };
        let p = DensityParams {
            max_cells_per_ray: 50,
            ..Default::default()
        };
        let d = density(&set, &p, 2);
        assert_eq!(
            (d.report.malformed, d.report.out_of_range, d.report.capped),
            (2, 1, 1)
        );
        assert_eq!(d.report.rays, 3);
        // Cell (0,0,0) is crossed by rays 0, 1 and 5: mean of +x, +y and +z.
        assert_eq!(d.count(IVec3::ZERO), 3);
        assert!((d.mean_direction(IVec3::ZERO) - Vec3::ONE.normalize()).length() < 1e-6);
        assert_eq!(d.count(IVec3::new(2, 0, 0)), 1, "ray 0 reaches x = 2.5");
        assert_eq!(d.count(IVec3::new(3, 0, 0)), 0);
        assert_eq!(d.count(IVec3::new(0, 0, 49)), 1, "ray 5 capped at 50 cells");
        assert_eq!(d.count(IVec3::new(0, 0, 50)), 0);
        let hits = density(
            &set,
            &DensityParams {
                filter: Filter::Hit,
                ..p
            },
            1,
        );
        assert_eq!(hits.report.rays, 1);
        assert_eq!(
            hits.count(IVec3::new(0, 1, 0)),
            0,
            "the miss is filtered out"
        );
        assert!(DensityParams { cell: 0.0, ..p }.check().is_err());
        assert!(DensityParams { chunk: 65, ..p }.check().is_err());
        assert!(
            DensityParams {
                tolerance: f32::NAN,
                ..p
            }
            .check()
            .is_err()
        );
    }

    /// Visits to chunks the chunk pass did not find (a rounding's graze) are added all the
    /// same: with none found beforehand, or half of them, the density is the one computed with
    /// all of them.
    #[test]
    fn visits_to_chunks_found_late_are_kept() {
        let set = random_set(3000, 11);
        let p = DensityParams {
            cell: 0.8,
            chunk: 4,
            ..Default::default()
        };
        let cancel = AtomicBool::new(false);
        let all = compute(&set, &p, &|_, _| {}, &cancel).unwrap();
        let none = compute_in(&set, &p, Vec::new(), &|_, _| {}, &cancel).unwrap();
        assert!(all == none, "nothing found beforehand");
        let half: Vec<(IVec3Key, u32)> = chunks_touched(&set, &p).into_iter().step_by(2).collect();
        let some = compute_in(&set, &p, half, &|_, _| {}, &cancel).unwrap();
        assert!(all == some, "half found beforehand");
    }

    /// In slices, a block of rays a call, the density is the one computed whole on every
    /// core, and a limit too small for its chunks refuses it as the whole does.
    #[test]
    fn a_density_in_slices_is_the_density() {
        use crate::slices::{Duration, until_done};
        let set = random_set(20_000, 5);
        let p = DensityParams {
            cell: 0.5,
            chunk: 4,
            ..Default::default()
        };
        let cancel = AtomicBool::new(false);
        let whole = compute(&set, &p, &|_, _| {}, &cancel).unwrap();
        let mut slices = DensitySlices::within(MAX_BYTES, &p);
        let (sliced, calls) = until_done(Duration::ZERO, |d| {
            density_in(&set, &p, &mut slices, &|_, _| {}, &cancel, d)
        })
        .unwrap();
        assert!(sliced.as_ref() == Some(&whole), "the same density");
        let blocks = 20_000usize.div_ceil(RAYS_PER_BLOCK);
        // A block of the chunk pass a call, then a block of the count (the last call of the
        // pass walks the first block of the count too).
        assert_eq!(calls, 2 * blocks - 1, "{blocks} blocks");
        let mut tight = DensitySlices::within(p.chunk_bytes(), &p);
        let (refused, _) = until_done(Duration::ZERO, |d| {
            density_in(&set, &p, &mut tight, &|_, _| {}, &cancel, d)
        })
        .unwrap();
        assert!(refused.is_none(), "more chunks than allowed");
        let stop = AtomicBool::new(true);
        let mut slices = DensitySlices::within(MAX_BYTES, &p);
        assert!(
            density_in(
                &set,
                &p,
                &mut slices,
                &|_, _| {},
                &stop,
                crate::slices::Deadline::after(Duration::ZERO)
            )
            .is_err()
        );
    }

    #[test]
    fn cancel_stops_it() {
        let set = random_set(10_000, 3);
        let cancel = AtomicBool::new(true);
        assert!(compute(&set, &DensityParams::default(), &|_, _| {}, &cancel).is_err());
    }

    /// Long rays across every slab (both ways along x, and straight across it), rays capped
    /// inside one, rays starting past a slab: the density and its report are the same for any
    /// number of slabs (one thread: one slab, every ray walked once).
    #[test]
    fn any_number_of_slabs_gives_the_same_density() {
        let mut set = random_set(3000, 21);
        let mut s = 7u32;
        let mut next = || {
            s = s.wrapping_mul(1664525).wrapping_add(1013904223);
            (s >> 8) as f32 / (1u32 << 24) as f32
        };
        for i in 0..600 {
            let o = Vec3::new(next(), next(), next()) * 20.0 - 10.0;
            let d = match i % 4 {
                0 => Vec3::new(1.0, 0.1 * next(), 0.1 * next()),
                1 => Vec3::new(-1.0, 0.2 * next(), -0.3 * next()),
                2 => Vec3::new(0.0, next() - 0.5, next() - 0.5),
                _ => Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5),
            };
            let t_max = 5.0 + 40.0 * next();
            set.rays.push(ray(10_000 + i, o, d, t_max, -1.0));
        }
        let p = DensityParams {
            cell: 0.5,
            chunk: 4,
            max_cells_per_ray: 50,
            ..Default::default()
        };
        let one = density(&set, &p, 1);
        assert!(one.report.capped > 0, "some rays are capped");
        for threads in [2, 3, 4, 7] {
            let many = density(&set, &p, threads);
            assert_eq!(many.report, one.report, "{threads} threads");
            assert!(many == one, "{threads} threads: the cells differ");
        }
    }

    /// The slabs cover every x once, in order, each a run of whole chunk planes.
    #[test]
    fn slabs_cut_whole_planes_in_order() {
        let touched: Vec<(IVec3Key, u32)> = (-3..5)
            .flat_map(|x| (0..3).map(move |y| ([x, y, 0], (x + 4) as u32)))
            .collect();
        for parts in 1..12 {
            let cut = slabs(&touched, 4, parts);
            assert!(cut.len() <= parts.min(8));
            assert_eq!(cut[0].lo, i64::MIN);
            assert_eq!(cut.last().unwrap().hi, i64::MAX);
            assert_eq!(cut[0].keys.start, 0);
            assert_eq!(cut.last().unwrap().keys.end, touched.len());
            for w in cut.windows(2) {
                assert_eq!(w[0].hi, w[1].lo);
                assert_eq!(w[0].keys.end, w[1].keys.start);
                // A plane is never split between two slabs.
                assert_ne!(
                    touched[w[0].keys.end - 1].0[0],
                    touched[w[1].keys.start].0[0]
                );
                assert_eq!(w[0].hi, 4 * i64::from(touched[w[1].keys.start].0[0]));
            }
        }
        assert_eq!(slabs(&[], 4, 2).len(), 1);
        // Two parts of planes weighing 1, 1, 1, 1, 4: cut where the sums are nearest half
        // (4 of 8), not past it.
        let touched: Vec<(IVec3Key, u32)> = [1, 1, 1, 1, 4]
            .iter()
            .enumerate()
            .map(|(x, &c)| ([x as i32, 0, 0], c))
            .collect();
        let cut = slabs(&touched, 4, 2);
        assert_eq!(cut.iter().map(|s| s.keys.len()).collect::<Vec<_>>(), [4, 1]);
        assert_eq!(cut[0].hi, 16);
    }

    /// A slab said to be out of a ray's reach gets no cell from its walk: rays far from the
    /// origin (where a position's rounding is largest) and long ones, slabs all around.
    #[test]
    fn a_slab_out_of_reach_is_never_walked_into() {
        let mut s = 99u32;
        let mut next = || {
            s = s.wrapping_mul(1664525).wrapping_add(1013904223);
            (s >> 8) as f32 / (1u32 << 24) as f32
        };
        let mut refused = 0;
        for i in 0..20_000 {
            let far = [1.0, 1e3, 1e5][i % 3];
            let o = (Vec3::new(next(), next(), next()) - 0.5) * far;
            let d = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * (0.1 + 4.0 * next());
            let r = ray(i as u32, o, d, far * next(), -1.0);
            let t = r.segment(0.0);
            let cell = 0.3 + next();
            let lo = ((o.x / cell) + (next() - 0.5) * 2.0 * far / cell) as i64;
            let slab = Slab {
                keys: 0..0,
                lo,
                hi: lo + 1 + (next() * 50.0) as i64,
            };
            if slab.may_reach(&r, t, cell) {
                continue;
            }
            refused += 1;
            walk_cells(r.origin, r.direction, t, cell, 1 << 20, |c| {
                let x = i64::from(c.x);
                assert!(!(slab.lo <= x && x < slab.hi), "ray {i} reaches {slab:?}");
            });
        }
        assert!(refused > 5000, "only {refused} refused");
    }
}
