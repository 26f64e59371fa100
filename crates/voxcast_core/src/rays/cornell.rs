//! `builtin:cornell`: the Cornell box as Cornell University's graphics group publishes its
//! measurements (millimetres; x to the left, y up, z into the box): floor, ceiling, back wall,
//! a red left and a green right wall, a short and a tall block; the front is open, and the
//! camera looks in through it. The ceiling's light is not a mesh: the ray sets light the box with
//! a directional light through the open front instead (`effects`).

use super::mesh::{Mesh, TriangleScene};
use glam::Vec3;

fn v(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

/// The box's five walls and two blocks.
pub fn scene() -> TriangleScene {
    let white = v(0.73, 0.73, 0.73);
    let walls = Mesh::from_quads(
        "walls",
        white,
        &[
            // Floor, ceiling, back wall.
            [
                v(552.8, 0.0, 0.0),
                v(0.0, 0.0, 0.0),
                v(0.0, 0.0, 559.2),
                v(549.6, 0.0, 559.2),
            ],
            [
                v(556.0, 548.8, 0.0),
                v(556.0, 548.8, 559.2),
                v(0.0, 548.8, 559.2),
                v(0.0, 548.8, 0.0),
            ],
            [
                v(549.6, 0.0, 559.2),
                v(0.0, 0.0, 559.2),
                v(0.0, 548.8, 559.2),
                v(556.0, 548.8, 559.2),
            ],
        ],
    );
    let red = Mesh::from_quads(
        "left wall",
        v(0.65, 0.05, 0.05),
        &[[
            v(552.8, 0.0, 0.0),
            v(549.6, 0.0, 559.2),
            v(556.0, 548.8, 559.2),
            v(556.0, 548.8, 0.0),
        ]],
    );
    let green = Mesh::from_quads(
        "right wall",
        v(0.12, 0.45, 0.15),
        &[[
            v(0.0, 0.0, 559.2),
            v(0.0, 0.0, 0.0),
            v(0.0, 548.8, 0.0),
            v(0.0, 548.8, 559.2),
        ]],
    );
    TriangleScene {
        meshes: vec![
            walls,
            red,
            green,
            block(
                "short block",
                165.0,
                [
                    v(130.0, 0.0, 65.0),
                    v(82.0, 0.0, 225.0),
                    v(240.0, 0.0, 272.0),
                    v(290.0, 0.0, 114.0),
                ],
            ),
            block(
                "tall block",
                330.0,
                [
                    v(423.0, 0.0, 247.0),
                    v(265.0, 0.0, 296.0),
                    v(314.0, 0.0, 456.0),
                    v(472.0, 0.0, 406.0),
                ],
            ),
        ],
    }
}

/// A block standing on the floor: its footprint's corners (in order) raised to `height`; the
/// top and four sides (the bottom lies on the floor).
fn block(name: &str, height: f32, base: [Vec3; 4]) -> Mesh {
    let up = Vec3::Y * height;
    let top = base.map(|p| p + up);
    let mut quads = vec![top];
    for i in 0..4 {
        let j = (i + 1) % 4;
        quads.push([base[i], top[i], top[j], base[j]]);
    }
    Mesh::from_quads(name, v(0.73, 0.73, 0.73), &quads)
}

/// The published camera: at (278, 273, −800) looking along +z, 39.3° vertical field of view.
pub const CAMERA_EYE: Vec3 = Vec3::new(278.0, 273.0, -800.0);
pub const CAMERA_TARGET: Vec3 = Vec3::new(278.0, 273.0, 0.0);
pub const CAMERA_FOV_Y_DEG: f32 = 39.3;

/// The second camera of the study's two primary traces: in front of the box, to the right
/// and above the first, looking down and across into the box.
pub const SECOND_CAMERA_EYE: Vec3 = Vec3::new(-150.0, 700.0, -650.0);
pub const SECOND_CAMERA_TARGET: Vec3 = Vec3::new(300.0, 200.0, 280.0);

/// The second camera (the first one's field of view).
pub fn second_camera() -> crate::camera::Camera {
    super::effects::camera(SECOND_CAMERA_EYE, SECOND_CAMERA_TARGET, CAMERA_FOV_Y_DEG)
        .expect("the second camera is valid")
}

/// The direction the directional light shines along (not normalised): in through the open
/// front, from above and from the left, so both blocks cast shadows on the floor and the back
/// wall.
pub const LIGHT: Vec3 = Vec3::new(-0.35, -0.55, 1.0);

/// [`LIGHT`] as a unit vector (public beside [`LIGHT`], for a caller lighting the box).
pub fn light_direction() -> Vec3 {
    LIGHT.normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_box_has_its_thirty_triangles_and_its_size() {
        let s = scene();
        // 3 walls + 2 side walls, 5 quads per block: 15 quads.
        assert_eq!(s.triangle_count(), 30);
        let (lo, hi) = s.bounds().unwrap();
        assert_eq!(lo, Vec3::ZERO);
        assert_eq!(hi, v(556.0, 548.8, 559.2));
    }

    #[test]
    fn the_camera_sees_the_tall_block_the_back_wall_above_it_and_the_short_blocks_top() {
        let s = scene();
        let d = (CAMERA_TARGET - CAMERA_EYE).normalize();
        // The view's centre: the tall block's front face, about z = 292 at x = 278.
        let hit = s.intersect(CAMERA_EYE, d, 0.0, 1e4).unwrap();
        assert_eq!(s.meshes[hit.mesh].name, "tall block");
        let z = (CAMERA_EYE + d * hit.t).z;
        assert!((285.0..300.0).contains(&z), "{z}");
        // Above it, the back wall, exactly where aimed (t = 1 in units of the direction).
        let wall = v(278.0, 500.0, 559.2);
        let hit = s
            .intersect(CAMERA_EYE, wall - CAMERA_EYE, 0.0, 2.0)
            .unwrap();
        assert_eq!(s.meshes[hit.mesh].name, "walls");
        assert!((hit.t - 1.0).abs() < 1e-5);
        assert!(hit.normal.abs_diff_eq(Vec3::NEG_Z, 1e-6), "{}", hit.normal);
        // Down and to the right onto the short block's top.
        let top = v(186.0, 165.0, 168.0);
        let hit = s.intersect(CAMERA_EYE, top - CAMERA_EYE, 0.0, 2.0).unwrap();
        assert_eq!(s.meshes[hit.mesh].name, "short block");
        assert!((hit.t - 1.0).abs() < 1e-4);
        assert!(hit.normal.abs_diff_eq(Vec3::Y, 1e-6), "{}", hit.normal);
    }
}
