//! The density's tests: closed forms of the walk and its ties, counts against a brute-force
//! count, the same result for any number of threads, and bad rays skipped.

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
