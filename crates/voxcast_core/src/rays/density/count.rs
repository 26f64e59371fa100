//! Counting: the chunks cut into slabs across x, one a thread, each walking every ray that can
//! reach it and adding its visits to its own cells; then the slabs assembled into the density.

use super::*;

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
pub(super) struct Slab {
    /// Its chunks: a range of the sorted keys (sorted by x first).
    pub(super) keys: std::ops::Range<usize>,
    pub(super) lo: i64,
    pub(super) hi: i64,
}

/// Cuts the sorted chunks into at most `parts` slabs across x, of about equal crossings: each
/// cut at the end of the plane of chunks whose running sum of crossings lies nearest its share.
pub(super) fn slabs(touched: &[(IVec3Key, u32)], n: i32, parts: usize) -> Vec<Slab> {
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
    pub(super) fn may_reach(&self, r: &RayRecord, (t0, t1): (f32, f32), s: f32) -> bool {
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
pub(super) struct SlabCount {
    pub(super) chunks: Vec<(IVec3Key, Chunk)>,
    pub(super) stray: Vec<(IVec3, [i32; 3])>,
    pub(super) report: Report,
}

/// Walks `rays` for one slab, adding the visits inside it to its own cells; the first slab
/// also counts the rays, malformed and out of range, for the report.
pub(super) fn count_slab(
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
pub(super) struct SlabWalk {
    pub(super) index: KeyMap<usize>,
    pub(super) chunks: Vec<Chunk>,
    pub(super) stray: Vec<(IVec3, [i32; 3])>,
    pub(super) report: Report,
    /// The chunk of the last visit: its lowest cell and where its cells start.
    pub(super) cached: Option<(IVec3, u32)>,
    pub(super) next_block: usize,
}

impl SlabWalk {
    pub(super) fn new(p: &DensityParams, slab: &Slab, keys: &[IVec3Key]) -> Self {
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
    pub(super) fn walk(
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
    pub(super) fn finish(self, keys: &[IVec3Key]) -> SlabCount {
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
pub(super) fn add_visits(chunks: &mut [Chunk], pending: &mut Vec<(u32, u32)>, unit: [i32; 3]) {
    for &(chunk, cell) in pending.iter() {
        chunks[chunk as usize].cells[cell as usize].add(unit);
    }
    pending.clear();
}

/// [`compute`] with the chunks found beforehand: `touched`, sorted, with their crossings
/// (visits to others are added one by one at the end).
pub(super) fn compute_in(
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
pub(super) fn assemble(p: &DensityParams, counted: Vec<SlabCount>) -> Density {
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
