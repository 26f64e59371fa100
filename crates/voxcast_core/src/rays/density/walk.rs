//! Walking one ray's counted segment through the cells (the 3-D DDA of Amanatides & Woo, with
//! the ties of the module's text), and which rays are walked at all.

use super::*;

/// The outcome of walking one segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Walk {
    pub visited: u32,
    pub capped: bool,
}

/// Walks the cells of edge `s` that the segment `origin + t·dir`, `t ∈ (t0, t1)`, passes through
/// with positive length, in order, calling `visit` with each (at most `max` of them; see the
/// module's text for the ties). The start must lie within ±2³⁰ cells (checked by the caller).
pub fn walk_cells(
    origin: Vec3,
    dir: Vec3,
    t: (f32, f32),
    s: f32,
    max: u32,
    mut visit: impl FnMut(IVec3),
) -> Walk {
    walk_cells_while(origin, dir, t, s, max, |c| {
        visit(c);
        true
    })
}

/// The cell a segment starting at `t0` starts in (the first [`walk_cells`] visits).
pub(super) fn start_cell(origin: Vec3, dir: Vec3, t0: f32, s: f32) -> IVec3 {
    let q = (origin + dir * t0) / s;
    let mut c = IVec3::ZERO;
    for a in 0..3 {
        let floor = q[a].floor();
        // On a face going down: the segment enters the cell below.
        let on_face = floor == q[a];
        c[a] = floor as i32 - i32::from(on_face && dir[a] < 0.0);
    }
    c
}

/// [`walk_cells`], stopping after a cell for which `visit` returns `false` (that cell is
/// counted in [`Walk::visited`]; the walk is not capped).
pub(super) fn walk_cells_while(
    origin: Vec3,
    dir: Vec3,
    (t0, t1): (f32, f32),
    s: f32,
    max: u32,
    mut visit: impl FnMut(IVec3) -> bool,
) -> Walk {
    if t1.is_nan() || t0.is_nan() || t1 <= t0 {
        return Walk {
            visited: 0,
            capped: false,
        };
    }
    let mut c = start_cell(origin, dir, t0, s);
    let mut step = IVec3::ZERO;
    let mut t_next = Vec3::INFINITY;
    let mut t_delta = Vec3::INFINITY;
    for a in 0..3 {
        if dir[a] > 0.0 {
            step[a] = 1;
            t_delta[a] = s / dir[a];
            t_next[a] = ((c[a] + 1) as f32 * s - origin[a]) / dir[a];
        } else if dir[a] < 0.0 {
            step[a] = -1;
            t_delta[a] = s / -dir[a];
            t_next[a] = (c[a] as f32 * s - origin[a]) / dir[a];
        }
    }
    let mut visited = 0u32;
    loop {
        if visited == max {
            return Walk {
                visited,
                capped: true,
            };
        }
        visited += 1;
        if !visit(c) {
            return Walk {
                visited,
                capped: false,
            };
        }
        let t = t_next.min_element();
        if t.is_nan() || t >= t1 {
            return Walk {
                visited,
                capped: false,
            };
        }
        // Every axis crossed at this t at once: an edge or corner is passed, not visited.
        for a in 0..3 {
            if t_next[a] == t {
                c[a] += step[a];
                t_next[a] += t_delta[a];
            }
        }
    }
}

/// Why a ray is not walked, if it is not.
pub(super) enum Skip {
    Malformed,
    OutOfRange,
}

pub(super) fn walkable(r: &RayRecord, p: &DensityParams) -> Result<(f32, f32), Skip> {
    r.check().map_err(|_| Skip::Malformed)?;
    let (t0, t1) = r.segment(p.tolerance);
    if t1.is_nan() {
        return Err(Skip::Malformed);
    }
    let start = r.at(t0) / p.cell;
    let far = start.abs().max_element();
    if far.is_nan() || far >= MAX_START_CELL {
        return Err(Skip::OutOfRange);
    }
    Ok((t0, t1))
}
