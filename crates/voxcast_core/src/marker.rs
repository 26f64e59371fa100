//! The light's marker in the sandbox: a small opaque sphere that stands in the scene where a
//! point light is (and, for a directional light, where its direction comes from). Its size and
//! colour live here so the sandbox draws it and tests predict it from one definition; so does
//! the colour of the virtual camera's body.

use glam::Vec3;

/// The marker's radius as a fraction of the volume's diagonal.
pub const LIGHT_MARKER_RADIUS: f32 = 0.025;

/// The marker's colour (unlit; the 8-bit value a screenshot holds, as a fraction of 255).
pub const LIGHT_MARKER_COLOR: Vec3 = Vec3::new(1.0, 0.85, 0.25);

/// The virtual camera's body's colour (unlit, as [`LIGHT_MARKER_COLOR`]).
pub const BODY_COLOR: Vec3 = Vec3::new(0.25, 0.55, 0.9);

/// How far from the volume's centre, in diagonals, a directional light's marker stands.
pub const DIRECTIONAL_MARKER_DISTANCE: f32 = 0.9;

/// The marker's radius for a volume spanning `lo..hi`.
pub fn light_marker_radius(lo: Vec3, hi: Vec3) -> f32 {
    LIGHT_MARKER_RADIUS * (hi - lo).length()
}

/// Where the marker of a light shining along `direction` stands for a volume spanning `lo..hi`
/// (`None` for a zero direction).
pub fn directional_marker_position(direction: Vec3, lo: Vec3, hi: Vec3) -> Option<Vec3> {
    let d = direction.try_normalize()?;
    Some((lo + hi) * 0.5 - d * DIRECTIONAL_MARKER_DISTANCE * (hi - lo).length())
}

/// The direction a light shines along when its marker stands at `marker` (towards the volume's
/// centre); the inverse of [`directional_marker_position`].
pub fn direction_from_marker(marker: Vec3, lo: Vec3, hi: Vec3) -> Option<Vec3> {
    ((lo + hi) * 0.5 - marker).try_normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn direction_and_marker_round_trip() {
        let (lo, hi) = (Vec3::ZERO, Vec3::new(2.0, 1.0, 4.0));
        for d in [Vec3::X, Vec3::new(1.0, -2.0, 0.5), Vec3::NEG_Z] {
            let m = directional_marker_position(d, lo, hi).unwrap();
            let back = direction_from_marker(m, lo, hi).unwrap();
            assert!((back - d.normalize()).length() < 1e-5, "{d} → {back}");
        }
        assert!(directional_marker_position(Vec3::ZERO, lo, hi).is_none());
        assert!(direction_from_marker((lo + hi) * 0.5, lo, hi).is_none());
    }

    #[test]
    fn the_radius_follows_the_volume() {
        let r = light_marker_radius(Vec3::ZERO, Vec3::new(3.0, 4.0, 0.0));
        assert!((r - 5.0 * LIGHT_MARKER_RADIUS).abs() < 1e-6);
    }
}
