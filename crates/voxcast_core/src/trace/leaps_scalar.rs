//! The lanes' look at a ray's next brick and their leap over empty bricks where there is no
//! SSE (64-bit ARM): the scalar functions themselves (`VisibleCells::brick_of`,
//! `VisibleCells::leap_exit_at`, `first_index_from`) behind the interface of `leaps.rs`, whose
//! functions are `unsafe` only because the SSE ones are (they need the instructions).

use crate::skip::VisibleCells;
use crate::step::StepPlan;
use glam::Vec3;

/// One ray's constants for its looks and leaps.
pub(super) struct Leaps<'c> {
    cells: &'c VisibleCells,
    origin: Vec3,
    dir: Vec3,
    inv_d: Vec3,
    last: Vec3,
    max_lo: Vec3,
}

/// Where a position lies: its cell's lower corner and its brick's index in the visibility
/// words.
pub(super) struct Look {
    lo: [usize; 3],
    pub(super) index: usize,
}

impl<'c> Leaps<'c> {
    /// # Safety
    /// None (as `leaps.rs`'s, which needs SSE 4.1).
    pub(super) unsafe fn new(
        cells: &'c VisibleCells,
        (origin, dir, inv_d): (Vec3, Vec3, Vec3),
        (last, max_lo): (Vec3, Vec3),
    ) -> Self {
        Self {
            cells,
            origin,
            dir,
            inv_d,
            last,
            max_lo,
        }
    }

    /// The brick of the cell holding the ray's position at `t`.
    ///
    /// # Safety
    /// None (as `leaps.rs`'s).
    #[inline]
    pub(super) unsafe fn look(&self, t: f32) -> Look {
        let x = (self.origin + self.dir * t)
            .max(Vec3::ZERO)
            .min(self.last)
            .min(self.max_lo);
        let lo = [x.x as usize, x.y as usize, x.z as usize];
        Look {
            lo,
            index: self.cells.brick_of(lo),
        }
    }

    /// [`VisibleCells::leap_exit_at`] for the brick of `look`, `distance` its distance ahead.
    ///
    /// # Safety
    /// None (as `leaps.rs`'s).
    #[inline]
    pub(super) unsafe fn exit(&self, look: &Look, distance: u8) -> f32 {
        self.cells
            .leap_exit_at(look.lo, distance, self.origin, self.inv_d)
    }
}

/// [`crate::step::first_index_from`].
///
/// # Safety
/// None (as `leaps.rs`'s).
#[inline]
pub(super) unsafe fn first_index_from(plan: &StepPlan, t: f32, inv_dt: f32) -> u32 {
    crate::step::first_index_from(plan, t, inv_dt)
}
