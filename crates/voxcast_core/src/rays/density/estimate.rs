//! What a density would take before it is computed: the chunks its rays pass through, found by
//! walking them through cells of the chunks' size, and the memory those chunks need.

use super::*;

/// The most memory a density may take, bytes: a computation whose [`estimate()`] needs more is
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
pub(super) fn chunks_touched(set: &RaySet, p: &DensityParams) -> Vec<(IVec3Key, u32)> {
    chunks_touched_within(set, p, usize::MAX).expect("no limit")
}

/// [`chunks_touched`], or `None` once one block of rays alone touches more than `limit`.
pub(super) fn chunks_touched_within(
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
pub(super) fn touched_by(
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
pub(super) fn merge_touched(maps: Vec<KeyMap<u32>>) -> Vec<(IVec3Key, u32)> {
    let mut all: BTreeMap<IVec3Key, u32> = BTreeMap::new();
    for (k, n) in maps.into_iter().flatten() {
        let e = all.entry(k).or_insert(0);
        *e = e.saturating_add(n);
    }
    all.into_iter().collect()
}
