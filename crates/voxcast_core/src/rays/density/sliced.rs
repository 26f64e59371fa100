//! The density in slices ([`crate::slices`]): what a page's one thread does between frames. The
//! chunk pass walks a block of rays at a time, and the count then walks one slab over all the
//! chunks (as one thread would) a block at a time, each resuming where the last slice stopped.
//! The counts are the ones [`super::compute`] gives on any number of threads, bit for bit
//! (tested). Without a deadline it is [`super::compute`] itself, on every core.

use super::{
    Density, DensityParams, IVec3Key, KeyMap, RAYS_PER_BLOCK, RayRecord, RaySet, Slab, SlabWalk,
    assemble, chunks_touched_within, compute_in, merge_touched, slabs, touched_by,
};
use crate::render::Cancelled;
use crate::slices::{Deadline, Step};
use std::sync::atomic::{AtomicBool, Ordering};

/// A density's work kept between slices.
#[derive(Clone, Debug)]
pub struct DensitySlices {
    /// The most chunks the density may store (see [`super::estimate_within`]).
    limit: usize,
    /// The chunk pass: each block's chunks so far.
    maps: Vec<KeyMap<u32>>,
    /// The count: the one slab, the chunks' keys, and its walk so far.
    walk: Option<(Slab, Vec<IVec3Key>, SlabWalk)>,
}

impl DensitySlices {
    /// A density that may take at most `max_bytes` of chunks (none more is computed).
    pub fn within(max_bytes: usize, p: &DensityParams) -> Self {
        Self {
            limit: max_bytes / p.chunk_bytes().max(1),
            maps: Vec::new(),
            walk: None,
        }
    }
}

/// The density of `set` (as [`super::compute`]), `None` when its chunks would take more than
/// the bytes `slices` allows; in slices up to `deadline`. `progress(done, total)` counts the
/// rays of the chunk pass and then of the count.
pub fn density_in(
    set: &RaySet,
    p: &DensityParams,
    slices: &mut DensitySlices,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
    deadline: Deadline,
) -> Result<Step<Option<Density>>, Cancelled> {
    if deadline == Deadline::NONE {
        // Whole, on every core: the chunk pass once, and the slabs in parallel.
        let Some(touched) = chunks_touched_within(set, p, slices.limit) else {
            return Ok(Step::Done(None));
        };
        return compute_in(set, p, touched, progress, cancel).map(|d| Step::Done(Some(d)));
    }
    let rays: Vec<&RayRecord> = set.selected(p.filter, p.tolerance, p.stride).collect();
    let blocks = rays.len().div_ceil(RAYS_PER_BLOCK);
    let mut first = true;
    // The chunk pass, a block at a time.
    while slices.walk.is_none() {
        if slices.maps.len() == blocks {
            let touched = merge_touched(std::mem::take(&mut slices.maps));
            let mut one = slabs(&touched, p.chunk as i32, 1);
            let slab = one.pop().expect("one slab");
            let keys: Vec<IVec3Key> = touched.into_iter().map(|(k, _)| k).collect();
            let walk = SlabWalk::new(p, &slab, &keys);
            slices.walk = Some((slab, keys, walk));
            break;
        }
        if (!first && deadline.passed()) || cancel.load(Ordering::Relaxed) {
            return pause_or_stop(cancel);
        }
        first = false;
        let at = slices.maps.len() * RAYS_PER_BLOCK;
        let block = &rays[at..(at + RAYS_PER_BLOCK).min(rays.len())];
        let over = AtomicBool::new(false);
        let map = touched_by(block, p, slices.limit, &over);
        if over.load(Ordering::Relaxed) {
            return Ok(Step::Done(None));
        }
        slices.maps.push(map);
        progress(slices.maps.len() * RAYS_PER_BLOCK / 2, rays.len());
    }
    // The count: the one slab, a block of rays at a time.
    let (slab, _, walk) = slices.walk.as_mut().expect("the chunk pass is done");
    let total = rays.len();
    let tick = |_: usize| !cancel.load(Ordering::Relaxed);
    if !walk.walk(&rays, p, slab, true, &tick, deadline)? {
        let done = (walk.next_block * RAYS_PER_BLOCK).min(total);
        progress(total / 2 + done / 2, total);
        return Ok(Step::Paused);
    }
    progress(total, total);
    let (slab, keys, walk) = slices.walk.take().expect("walked");
    let count = walk.finish(&keys[slab.keys.clone()]);
    Ok(Step::Done(Some(assemble(p, vec![count]))))
}

fn pause_or_stop<T>(cancel: &AtomicBool) -> Result<Step<T>, Cancelled> {
    if cancel.load(Ordering::Relaxed) {
        Err(Cancelled)
    } else {
        Ok(Step::Paused)
    }
}
