//! The lecture's worked example (seed 003, "Example: Raycasting"), computed as the lecture
//! asks: the value at each point by trilinear interpolation, its colour `c` and opacity `α` from
//! the transfer function, and the ray composited back to front from the first point to the last
//! with `C ← C·(1 − α) + c·α`, `O ← O·(1 − α) + α`, starting from `(0, 0, 0, 0)` — one sample a
//! point, without opacity correction or shading, as on the slide.
//!
//! The lecture's ray runs from P1, the far end, where its colour is still (0, 0, 0, 0), to P3,
//! where it leaves towards the eye: the eye looks from beyond P3 towards P1. [`lecture_ray`]
//! places a one-pixel virtual camera there, and [`lecture_ray_settings`] makes its samples
//! fall on P3, P2 and P1 exactly.
//!
//! The lecture numbers the corners of its unit voxel f1 … f8 (f1 at the origin, f2 along x, f3
//! along x and y, f4 along y, then the same one unit along z); the core numbers them
//! `a + 2b + 4c` (0 … 7): [`lecture_corner`] translates.

use crate::camera::{Camera, Projection};
use crate::composite::accumulate_back_to_front;
use crate::sample::{Interpolation, detail_at};
use crate::settings::RenderSettings;
use crate::step::Length;
use crate::transfer::TransferFunction;
use crate::volume::Volume;
use glam::Vec3;

/// The volume that holds the lecture's voxel.
pub const LECTURE_VOXEL: &str = "builtin:voxel";

/// The lecture's three points on its ray, P1 (the far end) to P3 (nearest the eye), in voxel
/// coordinates of its unit voxel (`builtin:voxel`, where they are also world coordinates).
pub const LECTURE_POINTS: [[f32; 3]; 3] = [[0.2, 0.3, 0.8], [0.5, 0.5, 0.5], [0.8, 0.7, 0.2]];

/// The virtual camera that shoots the lecture's ray through its one pixel: its eye at P3,
/// looking towards P1. Inside the voxel, the ray's first sample is the eye itself.
pub fn lecture_ray() -> Camera {
    let [p1, _, p3] = LECTURE_POINTS.map(Vec3::from_array);
    Camera::new(p3, p1, Vec3::Y, Projection::Perspective { fov_y_deg: 30.0 })
        .expect("P1 and P3 differ and the ray is not along y")
}

/// `base` with what puts one sample on each of the lecture's points and composites them as
/// the slide does: the step |P2 − P3| along the ray, no opacity correction, no shading, no
/// jitter, trilinear, one ray a pixel. The order (front to back or back to front) is kept:
/// both give the slide's colour, and the breakdown lists the running composite in either.
pub fn lecture_ray_settings(base: &RenderSettings) -> RenderSettings {
    let [_, p2, p3] = LECTURE_POINTS.map(Vec3::from_array);
    RenderSettings {
        step: Length::World(p2.distance(p3)),
        opacity_correction: false,
        shading: false,
        jitter: false,
        interpolation: Interpolation::Trilinear,
        supersampling: 1,
        ..base.clone()
    }
}

/// The lecture's number (1 … 8, for f1 … f8) of the core's corner `a + 2b + 4c`.
pub fn lecture_corner(corner: usize) -> u8 {
    [1, 2, 4, 3, 5, 6, 8, 7][corner & 7]
}

/// One point of the worked composite.
#[derive(Clone, Debug, PartialEq)]
pub struct WorkedPoint {
    /// The point, voxel coordinates.
    pub point: [f32; 3],
    /// Its interpolated value (data units).
    pub value: f32,
    /// The transfer function's colour and opacity at the value.
    pub rgba: [f32; 4],
    /// The ray's colour and opacity after this point.
    pub after: [f32; 4],
}

/// The points composited back to front, in the order given (the first is the farthest from
/// the eye), with the transfer function as the renderer bakes it over the volume's range.
pub fn back_to_front(
    volume: &Volume,
    tf: &TransferFunction,
    points: &[[f32; 3]],
) -> Vec<WorkedPoint> {
    let (lo, hi) = volume.value_range();
    let lut = tf.bake(lo, hi);
    let (mut c, mut o) = (Vec3::ZERO, 0.0f32);
    points
        .iter()
        .map(|&point| {
            let value = detail_at(volume, Vec3::from_array(point), Interpolation::Trilinear).value;
            let rgba = lut.lookup(value);
            (c, o) = accumulate_back_to_front(c, o, rgba.truncate(), rgba.w);
            WorkedPoint {
                point,
                value,
                rgba: rgba.to_array(),
                after: [c.x, c.y, c.z, o],
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builtin::worked_voxel;
    use crate::transfer::ControlPoint;

    /// The lecture's f1 … f8 sit where it says: f1 = 5.0 at the origin … f8 = 4.7 at (0, 1, 1).
    #[test]
    fn lecture_names_follow_the_slide() {
        let v = worked_voxel();
        let d = detail_at(&v, Vec3::splat(0.25), Interpolation::Trilinear);
        let slide = [5.0, 5.1, 5.2, 4.6, 4.9, 5.1, 5.3, 4.7];
        for k in 0..8 {
            let f = lecture_corner(k) as usize;
            assert_eq!(d.values[k], slide[f - 1], "corner {k} is f{f}");
        }
        let mut seen: Vec<u8> = (0..8).map(lecture_corner).collect();
        seen.sort();
        assert_eq!(seen, [1, 2, 3, 4, 5, 6, 7, 8]);
    }

    /// By hand, with a grey ramp (colour and opacity both (v − 4.6)/0.7 at value v): each
    /// point's value is its trilinear interpolation, and the composite after it is the
    /// back-to-front formula applied in turn.
    #[test]
    fn the_composite_is_the_formula_in_turn() {
        let v = worked_voxel();
        let tf = TransferFunction::new(
            "ramp",
            vec![
                ControlPoint::new(4.6, [0.0; 3], 0.0),
                ControlPoint::new(5.3, [1.0; 3], 1.0),
            ],
        )
        .unwrap();
        let points = [[0.2, 0.3, 0.8], [0.5, 0.5, 0.5], [0.8, 0.7, 0.2]];
        let rows = back_to_front(&v, &tf, &points);
        let (mut c, mut o) = (0.0f32, 0.0f32);
        for (row, p) in rows.iter().zip(points) {
            let f = detail_at(&v, Vec3::from_array(p), Interpolation::Trilinear).value;
            assert_eq!(row.value, f);
            let a = (f - 4.6) / 0.7;
            assert!((row.rgba[3] - a).abs() < 1e-3, "{} vs {a}", row.rgba[3]);
            c = c * (1.0 - a) + a * a;
            o = o * (1.0 - a) + a;
            assert!((row.after[0] - c).abs() < 2e-3 && (row.after[3] - o).abs() < 2e-3);
        }
        // P2, the centre, is the mean of the corners.
        assert!((rows[1].value - 4.9875).abs() < 1e-5);
    }
}
