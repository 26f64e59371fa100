//! The fast test behind the cells' bits: can a value between two raw values be visible?

use super::*;

/// "Can a value between these two raw values be visible?", answered fast. For integer types two
/// tables over every raw value give the table's visible-entry counts below and above each value,
/// so a test is two lookups; for floats the range is converted and looked up directly (widened
/// by a hair, as float interpolation may round just outside its corners' range).
pub(super) enum RangeTest {
    Table {
        offset: i32,
        below: Vec<u32>,
        above: Vec<u32>,
        descending: bool,
    },
    Float,
}

impl RangeTest {
    pub(super) fn new<T: Voxel>(g: &Grid<'_, T>, lut: &Lut) -> Self {
        match T::TABLE {
            Some((offset, count)) => {
                // Interpolating integers stays inside the corners' range exactly, and so does
                // the (monotone) rescale: no widening needed.
                let (below, above) = (0..count)
                    .map(|r| lut.visible_counts(g.to_data((r as i32 - offset) as f32)))
                    .unzip();
                RangeTest::Table {
                    offset,
                    below,
                    above,
                    descending: g.slope < 0.0,
                }
            }
            None => RangeTest::Float,
        }
    }

    /// Whether a value between raw `lo` and `hi` (`lo ≤ hi`) can have non-zero opacity.
    #[inline(always)]
    pub(super) fn any_visible<T: Voxel>(
        &self,
        g: &Grid<'_, T>,
        lut: &Lut,
        lo: f32,
        hi: f32,
    ) -> bool {
        match self {
            RangeTest::Table {
                offset,
                below,
                above,
                descending,
            } => {
                let (a, b) = if *descending { (hi, lo) } else { (lo, hi) };
                let ia = (a as i32 + offset) as usize;
                let ib = (b as i32 + offset) as usize;
                above[ib] > below[ia]
            }
            RangeTest::Float => {
                let (a, b) = (g.to_data(lo), g.to_data(hi));
                let (lo, hi) = (a.min(b), a.max(b));
                let eps = 1e-5 * ((lut.hi - lut.lo).abs() + lo.abs().max(hi.abs()));
                lut.any_visible_in(lo - eps, hi + eps)
            }
        }
    }
}
