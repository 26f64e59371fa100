//! The value histogram the transfer-function editor is drawn over.
//!
//! Bins split the volume's value range (data units) evenly; the last bin is closed so the maximum
//! counts. Medical volumes are dominated by air, so the editor usually shows counts on a log
//! scale: [`Histogram::heights`] gives both, normalised to `[0, 1]`.

use crate::volume::{Grid, GridVisitor, Volume, Voxel};

/// Counts of voxel values in evenly spaced bins over `[lo, hi]` (data units).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Histogram {
    pub lo: f32,
    pub hi: f32,
    pub counts: Vec<u64>,
}

/// How bar heights are scaled for display.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HistogramScale {
    Linear,
    /// `ln(1 + count)`: shows rare values next to a huge background peak.
    Log,
}

impl Histogram {
    /// Counts every voxel of `volume` into `bins` bins (at least one).
    pub fn of(volume: &Volume, bins: usize) -> Self {
        let (lo, hi) = volume.value_range();
        let counts = volume.visit(Count {
            lo,
            hi,
            bins: bins.max(1),
        });
        Self { lo, hi, counts }
    }

    /// Width of one bin in data units (zero for a constant volume).
    pub fn bin_width(&self) -> f32 {
        (self.hi - self.lo) / self.counts.len() as f32
    }

    /// The bin a value falls in, clamped to the histogram. Public: the inverse of a bin's
    /// range, which a caller drawing the histogram over a transfer function needs.
    pub fn bin_of(&self, value: f32) -> usize {
        bin_index(value, self.lo, self.hi, self.counts.len())
    }

    /// Bar heights in `[0, 1]`, the tallest bar at 1.
    pub fn heights(&self, scale: HistogramScale) -> Vec<f32> {
        let f = |c: u64| match scale {
            HistogramScale::Linear => c as f64,
            HistogramScale::Log => (c as f64).ln_1p(),
        };
        let max = self.counts.iter().map(|&c| f(c)).fold(0.0, f64::max);
        self.counts
            .iter()
            .map(|&c| if max > 0.0 { (f(c) / max) as f32 } else { 0.0 })
            .collect()
    }

    /// The value below which `fraction` of the voxels lie (bin resolution), for summaries.
    /// Public: a library's caller picks a window or an isovalue with it.
    pub fn percentile(&self, fraction: f64) -> f32 {
        let total: u64 = self.counts.iter().sum();
        let target = (fraction.clamp(0.0, 1.0) * total as f64).ceil() as u64;
        let mut seen = 0;
        for (i, &c) in self.counts.iter().enumerate() {
            seen += c;
            if seen >= target.max(1) {
                return self.lo + (i as f32 + 0.5) * self.bin_width();
            }
        }
        self.hi
    }
}

/// The exact value at each `fraction` of the voxels (nearest rank: the smallest value with at
/// least that fraction of the voxels at or below it), in data units. Narrows in on each rank
/// with histograms of the remaining range, then sorts the few values left, so memory stays
/// small whatever the volume's size.
pub fn percentiles(volume: &Volume, fractions: &[f64]) -> Vec<f32> {
    let data = volume.data();
    let (slope, intercept) = volume.rescale();
    let n = data.len();
    let value = |i: usize| data.raw_f32(i) * slope + intercept;
    fractions
        .iter()
        .map(|&f| {
            if n == 0 {
                return f32::NAN;
            }
            // 1-based rank among the sorted values.
            let rank = ((f.clamp(0.0, 1.0) * n as f64).ceil() as usize).clamp(1, n);
            let (mut lo, mut hi) = volume.value_range();
            let mut below = 0usize; // voxels under `lo`
            const BINS: usize = 1024;
            const FEW: usize = 1 << 16;
            loop {
                let in_range = |v: f32| v >= lo && v <= hi;
                let count = (0..n).filter(|&i| in_range(value(i))).count();
                if count <= FEW || hi <= lo {
                    if hi <= lo {
                        return lo;
                    }
                    let mut vals: Vec<f32> = (0..n).map(value).filter(|&v| in_range(v)).collect();
                    let k = (rank - below - 1).min(vals.len().saturating_sub(1));
                    let (_, v, _) = vals.select_nth_unstable_by(k, f32::total_cmp);
                    return *v;
                }
                // Per bin: count, smallest and largest value (bins are monotonic in the value,
                // so a bin's values are exactly those within its smallest and largest).
                let mut bins = vec![(0usize, f32::INFINITY, f32::NEG_INFINITY); BINS];
                for i in 0..n {
                    let v = value(i);
                    if in_range(v) {
                        let b = &mut bins[bin_index(v, lo, hi, BINS)];
                        *b = (b.0 + 1, b.1.min(v), b.2.max(v));
                    }
                }
                let mut seen = below;
                for &(c, bin_lo, bin_hi) in &bins {
                    if seen + c >= rank {
                        (lo, hi) = (bin_lo, bin_hi);
                        break;
                    }
                    seen += c;
                }
                below = seen;
            }
        })
        .collect()
}

#[inline]
fn bin_index(value: f32, lo: f32, hi: f32, bins: usize) -> usize {
    if hi <= lo {
        return 0;
    }
    let x = (value - lo) / (hi - lo) * bins as f32;
    (x.max(0.0) as usize).min(bins - 1)
}

struct Count {
    lo: f32,
    hi: f32,
    bins: usize,
}

impl GridVisitor for Count {
    type Output = Vec<u64>;
    fn visit<T: Voxel>(self, grid: Grid<'_, T>) -> Vec<u64> {
        let mut counts = vec![0u64; self.bins];
        for &v in grid.data {
            let v = v.to_f32();
            if v.is_finite() {
                counts[bin_index(grid.to_data(v), self.lo, self.hi, self.bins)] += 1;
            }
        }
        counts
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::VoxelData;
    use glam::{UVec3, Vec3};

    /// Exact nearest-rank percentiles, against sorting every value: a background peak of
    /// 200 000 zeros (which holds the 1 % rank, where bin centres once reported 1.99), a
    /// spread of floats, and the extremes.
    #[test]
    fn percentiles_are_exact() {
        let mut seed = 12345u32;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed
        };
        let mut data: Vec<f32> = vec![0.0; 200_000];
        data.extend((0..62_144).map(|_| (next() % 100_000) as f32 * 0.013 - 7.0));
        let n = data.len() as u32;
        let v = Volume::new(
            "p",
            UVec3::new(n / 64, 64, 1),
            Vec3::ONE,
            VoxelData::F32(data.clone()),
        )
        .unwrap();
        let mut sorted = data.clone();
        sorted.sort_by(f32::total_cmp);
        let fractions = [0.0, 0.01, 0.25, 0.5, 0.76, 0.9, 0.99, 1.0];
        let got = percentiles(&v, &fractions);
        for (f, g) in fractions.iter().zip(&got) {
            let rank = ((f * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
            assert_eq!(*g, sorted[rank - 1], "{f}");
        }
        let c = Volume::new("c", UVec3::ONE, Vec3::ONE, VoxelData::U8(vec![7])).unwrap();
        assert_eq!(percentiles(&c, &[0.0, 0.5, 1.0]), vec![7.0; 3]);
    }

    #[test]
    fn counts_every_voxel_once_and_the_max_lands_in_the_last_bin() {
        let data: Vec<u8> = (0..=255).collect();
        let v = Volume::new(
            "ramp",
            UVec3::new(256, 1, 1),
            Vec3::ONE,
            VoxelData::U8(data),
        )
        .unwrap();
        let h = Histogram::of(&v, 16);
        assert_eq!(h.counts.iter().sum::<u64>(), 256);
        assert!(h.counts.iter().all(|&c| c == 16), "{:?}", h.counts);
        assert_eq!(h.bin_of(255.0), 15);
        assert_eq!(h.heights(HistogramScale::Linear)[0], 1.0);
    }

    #[test]
    fn constant_volume_has_one_full_bin() {
        let v = Volume::new(
            "c",
            UVec3::new(2, 2, 2),
            Vec3::ONE,
            VoxelData::F32(vec![3.0; 8]),
        )
        .unwrap();
        let h = Histogram::of(&v, 4);
        assert_eq!(h.counts, vec![8, 0, 0, 0]);
        let log = h.heights(HistogramScale::Log);
        assert_eq!(log, vec![1.0, 0.0, 0.0, 0.0]);
        assert_eq!(h.percentile(0.5), 3.0);
    }
}
