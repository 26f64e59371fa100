//! The vector field view (RayVis's third view): per sample cube of `k` cells a side, an arrow
//! along the mean unit direction of the rays that crossed it, coloured by their count and
//! scaled by it.
//!
//! A cube's count is the sum of its cells' counts (one ray crossing three of its cells counts
//! three times: the cube sums cell visits, as RayVis's does), its direction the sum of their
//! fixed-point direction sums, normalised. `k` must divide the chunk size, so a cube never
//! spans two chunks and each is summed from one stored chunk.
//!
//! **Length.** Every arrow fits in its cube: its length is `k·S·f` with `f ∈ [MIN_SCALE, 1]`;
//! by count `f = count / max`, by inverse count `f = min / count` (the rare directions stand
//! out), or the same for all. **Colour** is the count's place between the smallest and the
//! largest, `(count − min) / (max − min)`, through the inferno map by the caller.
//!
//! **Count threshold** (RayVis's): cubes whose count is below it draw no arrow, so the sparse
//! fringes stop hiding the main streams; lengths and colours span the arrows kept.

use super::density::Density;
use glam::{IVec3, Vec3};

/// The shortest arrow, as a share of its cube (a count far from the scaling end stays
/// visible).
pub const MIN_SCALE: f32 = 0.15;

/// How arrows are scaled.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ArrowScale {
    /// Longest where most rays passed.
    #[default]
    Count,
    /// Longest where fewest rays passed (the rare directions stand out).
    InverseCount,
    /// All the same length.
    Uniform,
}

impl ArrowScale {
    pub const ALL: [ArrowScale; 3] = [Self::Count, Self::InverseCount, Self::Uniform];

    /// The word the sandbox shows.
    pub const fn name(self) -> &'static str {
        match self {
            Self::Count => "by count",
            Self::InverseCount => "by inverse count",
            Self::Uniform => "uniform",
        }
    }

    /// One line for the tooltip.
    pub const fn doc(self) -> &'static str {
        match self {
            Self::Count => "Arrows are longest where most rays passed.",
            Self::InverseCount => "Arrows are longest where fewest rays passed.",
            Self::Uniform => "Every arrow fills its cube.",
        }
    }
}

/// One arrow of the field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arrow {
    /// The cube's centre (world units).
    pub centre: Vec3,
    /// The mean unit direction.
    pub direction: Vec3,
    /// Cell visits summed over the cube.
    pub count: u64,
    /// Length, world units (see the module's text).
    pub length: f32,
    /// The count's place between the field's smallest and largest, 0 … 1.
    pub shade: f32,
}

/// The arrows of `density` for sample cubes of `k` cells a side whose count is at least
/// `min_count`, ordered by cube (chunks in key order, then z, y, x): `Err` when `k` does not
/// divide the chunk size.
pub fn arrows(
    density: &Density,
    k: u32,
    scale: ArrowScale,
    min_count: u64,
) -> Result<Vec<Arrow>, String> {
    let n = density.params.chunk;
    if k == 0 || !n.is_multiple_of(k) {
        return Err(format!(
            "the sample cube ({k} cells) must divide the chunk size ({n} cells)"
        ));
    }
    let cell = density.params.cell;
    let per = n / k;
    let mut raw = Vec::new();
    for (key, chunk) in &density.chunks {
        let base = IVec3::from_array(*key) * n as i32;
        for cz in 0..per {
            for cy in 0..per {
                for cx in 0..per {
                    let mut count = 0u64;
                    let mut sum = [0i64; 3];
                    for z in cz * k..(cz + 1) * k {
                        for y in cy * k..(cy + 1) * k {
                            for x in cx * k..(cx + 1) * k {
                                let i = (x + n * (y + n * z)) as usize;
                                let cell = &chunk.cells[i];
                                count += u64::from(cell.count);
                                for (s, d) in sum.iter_mut().zip(cell.direction) {
                                    *s += d;
                                }
                            }
                        }
                    }
                    if count == 0 || count < min_count {
                        continue;
                    }
                    let first = base + IVec3::new(cx as i32, cy as i32, cz as i32) * k as i32;
                    let centre = (first.as_vec3() + 0.5 * k as f32) * cell;
                    let dir = Vec3::new(sum[0] as f32, sum[1] as f32, sum[2] as f32);
                    raw.push((centre, dir.normalize_or_zero(), count));
                }
            }
        }
    }
    let (lo, hi) = raw
        .iter()
        .fold((u64::MAX, 0), |(lo, hi), a| (lo.min(a.2), hi.max(a.2)));
    let side = k as f32 * cell;
    Ok(raw
        .into_iter()
        .map(|(centre, direction, count)| {
            let f = match scale {
                ArrowScale::Count => count as f64 / hi as f64,
                ArrowScale::InverseCount => lo as f64 / count as f64,
                ArrowScale::Uniform => 1.0,
            };
            let shade = if hi > lo {
                ((count - lo) as f64 / (hi - lo) as f64) as f32
            } else {
                1.0
            };
            Arrow {
                centre,
                direction,
                count,
                length: side * (f as f32).clamp(MIN_SCALE, 1.0),
                shade,
            }
        })
        .collect())
}

/// The sample cube sizes (cells) that divide `chunk`, smallest first.
pub fn cube_sizes(chunk: u32) -> Vec<u32> {
    (1..=chunk).filter(|k| chunk.is_multiple_of(*k)).collect()
}

#[cfg(test)]
mod tests {
    use super::super::density::{DensityParams, compute};
    use super::super::set::{RayRecord, RaySet};
    use super::*;
    use std::sync::atomic::AtomicBool;

    fn density(rays: Vec<RayRecord>, cell: f32, chunk: u32) -> Density {
        let set = RaySet { trace_id: 0, rays };
        let p = DensityParams {
            cell,
            chunk,
            ..Default::default()
        };
        compute(&set, &p, &|_, _| {}, &AtomicBool::new(false)).unwrap()
    }

    fn ray(origin: Vec3, direction: Vec3, t_max: f32) -> RayRecord {
        RayRecord {
            id: 0,
            origin,
            direction,
            t_min: 0.0,
            t_max,
            t_hit: -1.0,
        }
    }

    /// One ray along +x through 8 cells (chunk 4, cubes of 2): four arrows along +x, each
    /// counting 2 visits, centred on their cubes, all the same length and shade.
    #[test]
    fn an_axis_ray_gives_arrows_along_it() {
        let d = density(vec![ray(Vec3::new(0.0, 0.5, 0.5), Vec3::X, 8.0)], 1.0, 4);
        let a = arrows(&d, 2, ArrowScale::Count, 0).unwrap();
        assert_eq!(a.len(), 4);
        for (i, arrow) in a.iter().enumerate() {
            assert_eq!(arrow.count, 2);
            assert!((arrow.direction - Vec3::X).length() < 1e-6);
            assert_eq!(arrow.centre, Vec3::new(1.0 + 2.0 * i as f32, 1.0, 1.0));
            assert_eq!((arrow.length, arrow.shade), (2.0, 1.0));
        }
    }

    /// Conservation: the arrows' counts add up to every cell visit, for any cube size; the
    /// longest arrow by count is the fullest cube, by inverse count the emptiest.
    #[test]
    fn counts_are_conserved_and_scaled() {
        let mut rays = Vec::new();
        for i in 0..40 {
            let a = i as f32 * 0.37;
            let dir = Vec3::new(a.cos(), a.sin(), 0.3 * (a * 1.7).sin());
            rays.push(ray(Vec3::new(8.0, 8.0, 8.0), dir, 7.0 + (i % 5) as f32));
        }
        let d = density(rays, 1.0, 8);
        for k in cube_sizes(8) {
            for scale in ArrowScale::ALL {
                let a = arrows(&d, k, scale, 0).unwrap();
                let total: u64 = a.iter().map(|a| a.count).sum();
                assert_eq!(total, d.report.visits, "k = {k}");
                let side = k as f32;
                assert!(a.iter().all(|a| a.length <= side + 1e-6 && a.length > 0.0));
                let max = a.iter().max_by_key(|a| a.count).unwrap();
                let min = a.iter().min_by_key(|a| a.count).unwrap();
                match scale {
                    ArrowScale::Count => assert_eq!(max.length, side),
                    ArrowScale::InverseCount => assert_eq!(min.length, side),
                    ArrowScale::Uniform => assert!(a.iter().all(|a| a.length == side)),
                }
                assert!(a.iter().all(|a| (0.0..=1.0).contains(&a.shade)));
                assert!(a.iter().all(|a| (a.direction.length() - 1.0).abs() < 1e-5));
            }
        }
    }

    /// Two opposite rays through the same cells cancel: their mean direction is zero, and
    /// the arrow says so (zero, never NaN).
    #[test]
    fn opposite_rays_cancel() {
        let d = density(
            vec![
                ray(Vec3::new(0.0, 0.5, 0.5), Vec3::X, 4.0),
                ray(Vec3::new(4.0, 0.5, 0.5), -Vec3::X, 4.0),
            ],
            1.0,
            4,
        );
        let a = arrows(&d, 4, ArrowScale::Count, 0).unwrap();
        assert_eq!(a.len(), 1);
        assert_eq!((a[0].count, a[0].direction), (8, Vec3::ZERO));
    }

    #[test]
    fn a_cube_must_divide_the_chunk() {
        let d = density(vec![ray(Vec3::ZERO, Vec3::X, 2.0)], 1.0, 6);
        assert_eq!(cube_sizes(6), vec![1, 2, 3, 6]);
        assert!(
            arrows(&d, 4, ArrowScale::Count, 0)
                .unwrap_err()
                .contains("divide")
        );
        assert!(arrows(&d, 0, ArrowScale::Count, 0).is_err());
        assert!(arrows(&d, 3, ArrowScale::Count, 0).is_ok());
    }

    #[test]
    fn the_count_threshold_leaves_out_the_sparse_cubes() {
        // Two rays along +x: one through 8 cells, one through the first cube's 2 only.
        let d = density(
            vec![
                ray(Vec3::new(0.0, 0.5, 0.5), Vec3::X, 8.0),
                ray(Vec3::new(0.0, 0.5, 0.5), Vec3::X, 2.0),
            ],
            1.0,
            4,
        );
        let all = arrows(&d, 2, ArrowScale::Count, 0).unwrap();
        let most = all.iter().map(|a| a.count).max().unwrap();
        let least = all.iter().map(|a| a.count).min().unwrap();
        assert!(most > least, "{all:?}");
        let kept = arrows(&d, 2, ArrowScale::Count, most).unwrap();
        assert_eq!((all.len(), kept.len()), (4, 1));
        assert!(kept.iter().all(|a| a.count >= most));
        // The kept arrows span the colours and lengths themselves.
        assert!(kept.iter().any(|a| a.shade == 1.0));
        assert!(
            arrows(&d, 2, ArrowScale::Count, most + 1)
                .unwrap()
                .is_empty()
        );
    }

    #[test]
    fn no_rays_no_arrows() {
        let d = density(Vec::new(), 1.0, 4);
        assert!(
            arrows(&d, 2, ArrowScale::InverseCount, 0)
                .unwrap()
                .is_empty()
        );
    }
}
