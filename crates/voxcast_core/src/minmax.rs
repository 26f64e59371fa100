//! `min` and `max` of two floats as single instructions, for the hot loops (a leaf: the
//! samplers and the skipping structures both use them).

/// `max(a, b)` as one `maxss` (Rust's `f32::max` adds NaN handling the marcher never needs).
/// If `a` is NaN the comparison is false and the result is `b`: the samplers rely on this to map
/// a NaN position onto the lattice.
#[inline(always)]
pub(crate) fn fmax(a: f32, b: f32) -> f32 {
    if a > b { a } else { b }
}

/// `min(a, b)` as one `minss` (see [`fmax`]).
#[inline(always)]
pub(crate) fn fmin(a: f32, b: f32) -> f32 {
    if a < b { a } else { b }
}
