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

    /// The bin a value falls in, clamped to the histogram.
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
            counts[bin_index(grid.to_data(v.to_f32()), self.lo, self.hi, self.bins)] += 1;
        }
        counts
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::volume::VoxelData;
    use glam::{UVec3, Vec3};

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
