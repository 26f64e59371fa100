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
//! `N·S` (the estimate shown before computing), then blocks of rays are walked in parallel into
//! lists of cell visits that are added to the chunks' arrays.

use super::set::{Filter, RayRecord, RaySet};
use crate::render::Cancelled;
use glam::{IVec3, Vec3};
use rayon::prelude::*;
use std::collections::{BTreeMap, HashMap, HashSet};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Rays per block of work (the unit of progress and cancelling).
const RAYS_PER_BLOCK: usize = 4096;

/// Blocks walked at once before their visits are added (bounds the visit lists' memory).
const BLOCKS_PER_ROUND: usize = 8;

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

/// One stored chunk: per cell (x fastest) the ray count and the sum of unit directions (fixed
/// point, [`DIRECTION_SCALE`] per unit).
#[derive(Clone, Debug, PartialEq)]
pub struct Chunk {
    pub counts: Vec<u32>,
    pub directions: Vec<[i64; 3]>,
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

/// Counts one ray through a cell: its count and its fixed-point unit direction.
fn add_visit(count: &mut u32, sum: &mut [i64; 3], unit: [i32; 3]) {
    *count += 1;
    for (s, u) in sum.iter_mut().zip(unit) {
        *s += i64::from(u);
    }
}

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
        self.chunks.get(&c).map_or(0, |ch| ch.counts[i])
    }

    /// The mean unit direction of the rays through `cell` (zero where none passed).
    pub fn mean_direction(&self, cell: IVec3) -> Vec3 {
        let (c, i) = self.locate(cell);
        self.chunks.get(&c).map_or(Vec3::ZERO, |ch| {
            let [x, y, z] = ch.directions[i];
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
    (t0, t1): (f32, f32),
    s: f32,
    max: u32,
    mut visit: impl FnMut(IVec3),
) -> Walk {
    if t1.is_nan() || t0.is_nan() || t1 <= t0 {
        return Walk {
            visited: 0,
            capped: false,
        };
    }
    let p0 = origin + dir * t0;
    let q = p0 / s;
    let mut c = IVec3::ZERO;
    let mut step = IVec3::ZERO;
    let mut t_next = Vec3::INFINITY;
    let mut t_delta = Vec3::INFINITY;
    for a in 0..3 {
        let floor = q[a].floor();
        // On a face going down: the segment enters the cell below.
        let on_face = floor == q[a];
        c[a] = floor as i32 - i32::from(on_face && dir[a] < 0.0);
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
        visit(c);
        visited += 1;
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

/// The chunks the counted segments pass through, sorted: the rays walked through cells of edge
/// `N·S` (in parallel).
fn chunks_touched(set: &RaySet, p: &DensityParams) -> Vec<IVec3Key> {
    chunks_touched_within(set, p, usize::MAX).expect("no limit")
}

/// [`chunks_touched`], or `None` once one block of rays alone touches more than `limit`.
fn chunks_touched_within(set: &RaySet, p: &DensityParams, limit: usize) -> Option<Vec<IVec3Key>> {
    let edge = p.cell * p.chunk as f32;
    let max = p.max_cells_per_ray / p.chunk + 2;
    let rays: Vec<&RayRecord> = set.selected(p.filter, p.tolerance, p.stride).collect();
    let over = AtomicBool::new(false);
    let sets: Vec<HashSet<IVec3Key>> = rays
        .par_chunks(RAYS_PER_BLOCK)
        .map(|block| {
            let mut chunks = HashSet::new();
            for r in block {
                if over.load(Ordering::Relaxed) {
                    break;
                }
                if let Ok(t) = walkable(r, p) {
                    walk_cells(r.origin, r.direction, t, edge, max, |c| {
                        chunks.insert(c.to_array());
                    });
                }
                if chunks.len() > limit {
                    over.store(true, Ordering::Relaxed);
                }
            }
            chunks
        })
        .collect();
    if over.load(Ordering::Relaxed) {
        return None;
    }
    let mut all: Vec<IVec3Key> = sets.into_iter().flatten().collect();
    all.sort_unstable();
    all.dedup();
    Some(all)
}

/// One block's cell visits (global cell index, fixed-point unit direction), the visits to
/// cells of chunks the chunk pass did not find (a rounding's graze), and its report.
type Visits = (Vec<(u32, [i32; 3])>, Vec<(IVec3, [i32; 3])>, Report);

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

/// [`compute`] with the chunks found beforehand: `keys`, sorted (visits to others are added
/// one by one at the end).
fn compute_in(
    set: &RaySet,
    p: &DensityParams,
    keys: Vec<IVec3Key>,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<Density, Cancelled> {
    let per_chunk = (p.chunk as usize).pow(3);
    if keys.len() as u64 * per_chunk as u64 > u64::from(u32::MAX) {
        // Far more than memory holds anyway: refuse rather than wrap the indices.
        return Err(Cancelled);
    }
    let index: HashMap<IVec3Key, u32> = keys
        .iter()
        .enumerate()
        .map(|(i, k)| (*k, i as u32))
        .collect();
    let n = p.chunk as i32;
    let rays: Vec<&RayRecord> = set.selected(p.filter, p.tolerance, p.stride).collect();
    let total = rays.len();
    let done = AtomicUsize::new(0);
    // One record a cell (count beside the direction sum: one cache line a visit).
    let mut cells = vec![(0u32, [0i64; 3]); keys.len() * per_chunk];
    // The merge's parts: each thread adds the visits to its own range of cells.
    let parts = rayon::current_num_threads().max(1);
    let part_len = cells.len().div_ceil(parts).max(1);
    let mut report = Report::default();
    let mut stray_visits: Vec<(IVec3, [i32; 3])> = Vec::new();
    let blocks: Vec<&[&RayRecord]> = rays.chunks(RAYS_PER_BLOCK).collect();
    for round in blocks.chunks(BLOCKS_PER_ROUND) {
        if cancel.load(Ordering::Relaxed) {
            return Err(Cancelled);
        }
        let lists: Vec<Visits> = round
            .par_iter()
            .map(|block| {
                let mut visits = Vec::with_capacity(block.len() * 64);
                let mut stray = Vec::new();
                let mut r = Report::default();
                let mut cached: Option<(IVec3, u32)> = None;
                for ray in block.iter() {
                    let t = match walkable(ray, p) {
                        Ok(t) => t,
                        Err(Skip::Malformed) => {
                            r.malformed += 1;
                            continue;
                        }
                        Err(Skip::OutOfRange) => {
                            r.out_of_range += 1;
                            continue;
                        }
                    };
                    let u = ray.direction.normalize() * DIRECTION_SCALE;
                    let unit = [u.x as i32, u.y as i32, u.z as i32];
                    let walk = walk_cells(
                        ray.origin,
                        ray.direction,
                        t,
                        p.cell,
                        p.max_cells_per_ray,
                        |c| {
                            let (chunk, local) = locate(c, n);
                            let base = match cached {
                                Some((k, b)) if k == chunk => b,
                                _ => match index.get(&chunk.to_array()) {
                                    Some(&i) => {
                                        let b = i * per_chunk as u32;
                                        cached = Some((chunk, b));
                                        b
                                    }
                                    None => {
                                        stray.push((c, unit));
                                        return;
                                    }
                                },
                            };
                            visits.push((base + local as u32, unit));
                        },
                    );
                    r.rays += 1;
                    r.capped += usize::from(walk.capped);
                    r.visits += u64::from(walk.visited);
                }
                let now = done.fetch_add(block.len(), Ordering::Relaxed) + block.len();
                progress(now, total);
                (visits, stray, r)
            })
            .collect();
        cells
            .par_chunks_mut(part_len)
            .enumerate()
            .for_each(|(part, range)| {
                let start = part * part_len;
                let end = start + range.len();
                for (visits, _, _) in &lists {
                    for &(cell, unit) in visits {
                        let i = cell as usize;
                        if i >= start && i < end {
                            let c = &mut range[i - start];
                            add_visit(&mut c.0, &mut c.1, unit);
                        }
                    }
                }
            });
        for (_, strays, r) in lists {
            stray_visits.extend(strays);
            report.add(&r);
        }
    }
    let mut chunks: BTreeMap<IVec3Key, Chunk> = keys
        .iter()
        .enumerate()
        .map(|(i, k)| {
            let range = i * per_chunk..(i + 1) * per_chunk;
            (
                *k,
                Chunk {
                    counts: cells[range.clone()].iter().map(|c| c.0).collect(),
                    directions: cells[range].iter().map(|c| c.1).collect(),
                },
            )
        })
        .collect();
    for (c, unit) in stray_visits {
        let (chunk, i) = locate(c, n);
        let ch = chunks.entry(chunk.to_array()).or_insert_with(|| Chunk {
            counts: vec![0; per_chunk],
            directions: vec![[0; 3]; per_chunk],
        });
        add_visit(&mut ch.counts[i], &mut ch.directions[i], unit);
    }
    Ok(Density {
        params: *p,
        chunks,
        report,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

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
            .flat_map(|c| c.counts.iter())
            .map(|&c| u64::from(c))
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
        let half: Vec<IVec3Key> = chunks_touched(&set, &p).into_iter().step_by(2).collect();
        let some = compute_in(&set, &p, half, &|_, _| {}, &cancel).unwrap();
        assert!(all == some, "half found beforehand");
    }

    #[test]
    fn cancel_stops_it() {
        let set = random_set(10_000, 3);
        let cancel = AtomicBool::new(true);
        assert!(compute(&set, &DensityParams::default(), &|_, _| {}, &cancel).is_err());
    }
}
