//! Triangle scenes for ray data sets, and the ray tracer that makes the sets: meshes of
//! triangles, each with a flat colour, and the nearest hit along a ray by brute force
//! (Möller & Trumbore's test against every triangle). A scene has tens of triangles (the
//! Cornell box has 30), where a hierarchy would cost more than it saves; this crate's
//! `benches/ray_density.rs` measures the tracer's rays per second.

use glam::Vec3;

/// One triangle mesh with its colour (display values, as RayVis's `meshColor`).
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    pub name: String,
    pub color: Vec3,
    pub triangles: Vec<[Vec3; 3]>,
}

impl Mesh {
    /// A mesh of quads, each split into two triangles (corners in order around the quad).
    pub fn from_quads(name: &str, color: Vec3, quads: &[[Vec3; 4]]) -> Self {
        let triangles = quads
            .iter()
            .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
            .collect();
        Self {
            name: name.into(),
            color,
            triangles,
        }
    }
}

/// A scene: meshes in world space.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleScene {
    pub meshes: Vec<Mesh>,
}

/// Where a ray met the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance in units of the ray direction's length.
    pub t: f32,
    pub mesh: usize,
    pub triangle: usize,
    /// The triangle's unit normal, turned to face the ray's origin.
    pub normal: Vec3,
    /// The hit's barycentric coordinates: the weights of the triangle's three corners.
    pub barycentric: Vec3,
}

/// The barycentric coordinates of `p` (in the plane of `tri`): the weights `(w0, w1, w2)`,
/// summing to 1, with `p = w0·a + w1·b + w2·c`.
pub fn barycentric(tri: &[Vec3; 3], p: Vec3) -> Vec3 {
    let (e1, e2, d) = (tri[1] - tri[0], tri[2] - tri[0], p - tri[0]);
    let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (d1, d2) = (d.dot(e1), d.dot(e2));
    let den = d11 * d22 - d12 * d12;
    if den.abs() <= f32::MIN_POSITIVE {
        return Vec3::new(1.0, 0.0, 0.0);
    }
    let v = (d22 * d1 - d12 * d2) / den;
    let w = (d11 * d2 - d12 * d1) / den;
    Vec3::new(1.0 - v - w, v, w)
}

/// Möller & Trumbore: the `t` at which `origin + t·dir` crosses triangle `tri`, if it does
/// (both faces; a ray in the triangle's plane misses it).
#[inline]
pub fn intersect_triangle(origin: Vec3, dir: Vec3, tri: &[Vec3; 3]) -> Option<f32> {
    let e1 = tri[1] - tri[0];
    let e2 = tri[2] - tri[0];
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < f32::MIN_POSITIVE * 16.0 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let s = origin - tri[0];
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = dir.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    Some(e2.dot(q) * inv)
}

impl TriangleScene {
    /// How many triangles the scene holds.
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(|m| m.triangles.len()).sum()
    }

    /// The nearest hit of `origin + t·dir` with `t` in `(t_min, t_max)`.
    pub fn intersect(&self, origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> Option<Hit> {
        let mut best: Option<(f32, usize, usize)> = None;
        for (m, mesh) in self.meshes.iter().enumerate() {
            for (i, tri) in mesh.triangles.iter().enumerate() {
                if let Some(t) = intersect_triangle(origin, dir, tri)
                    && t > t_min
                    && t < best.map_or(t_max, |b| b.0)
                {
                    best = Some((t, m, i));
                }
            }
        }
        let (t, mesh, triangle) = best?;
        let tri = &self.meshes[mesh].triangles[triangle];
        let n = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalize_or_zero();
        let normal = if n.dot(dir) > 0.0 { -n } else { n };
        Some(Hit {
            t,
            mesh,
            triangle,
            normal,
            barycentric: barycentric(tri, origin + dir * t),
        })
    }

    /// The box around every vertex.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut points = self
            .meshes
            .iter()
            .flat_map(|m| m.triangles.iter().flatten());
        let first = *points.next()?;
        Some(points.fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p))))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_quad() -> TriangleScene {
        TriangleScene {
            meshes: vec![Mesh::from_quads(
                "floor",
                Vec3::ONE,
                &[[
                    Vec3::new(0.0, 0.0, 0.0),
                    Vec3::new(1.0, 0.0, 0.0),
                    Vec3::new(1.0, 0.0, 1.0),
                    Vec3::new(0.0, 0.0, 1.0),
                ]],
            )],
        }
    }

    #[test]
    fn a_ray_down_onto_a_quad_hits_at_its_height() {
        let s = unit_quad();
        assert_eq!(s.triangle_count(), 2);
        // Not unit length: t is in units of the direction's length.
        let hit = s
            .intersect(
                Vec3::new(0.3, 2.0, 0.6),
                Vec3::new(0.0, -4.0, 0.0),
                0.0,
                10.0,
            )
            .unwrap();
        assert!((hit.t - 0.5).abs() < 1e-6, "{}", hit.t);
        assert_eq!(hit.normal, Vec3::Y);
        // From below, the normal turns to face the ray.
        let below = s
            .intersect(Vec3::new(0.3, -1.0, 0.6), Vec3::Y, 0.0, 10.0)
            .unwrap();
        assert_eq!(below.normal, Vec3::NEG_Y);
        // Outside the quad, behind the origin, beyond t_max, or parallel: no hit.
        assert!(
            s.intersect(Vec3::new(1.5, 2.0, 0.5), Vec3::NEG_Y, 0.0, 10.0)
                .is_none()
        );
        assert!(
            s.intersect(Vec3::new(0.5, 2.0, 0.5), Vec3::Y, 0.0, 10.0)
                .is_none()
        );
        assert!(
            s.intersect(Vec3::new(0.5, 2.0, 0.5), Vec3::NEG_Y, 0.0, 1.5)
                .is_none()
        );
        assert!(
            s.intersect(Vec3::new(-1.0, 0.0, 0.5), Vec3::X, 0.0, 10.0)
                .is_none()
        );
        assert!(
            s.intersect(Vec3::new(0.5, 2.0, 0.5), Vec3::ZERO, 0.0, 10.0)
                .is_none()
        );
        assert!(s.intersect(Vec3::NAN, Vec3::NEG_Y, 0.0, 10.0).is_none());
    }

    #[test]
    fn the_nearest_of_two_is_taken() {
        let mut s = unit_quad();
        let mut upper = s.meshes[0].clone();
        for t in &mut upper.triangles {
            for p in t {
                p.y = 1.0;
            }
        }
        upper.name = "upper".into();
        s.meshes.push(upper);
        let hit = s
            .intersect(Vec3::new(0.5, 3.0, 0.5), Vec3::NEG_Y, 0.0, 10.0)
            .unwrap();
        assert_eq!((hit.mesh, hit.t), (1, 2.0));
        // Starting past the upper one (t_min), the floor.
        let hit = s
            .intersect(Vec3::new(0.5, 3.0, 0.5), Vec3::NEG_Y, 2.5, 10.0)
            .unwrap();
        assert_eq!((hit.mesh, hit.t), (0, 3.0));
        assert_eq!(s.bounds(), Some((Vec3::ZERO, Vec3::new(1.0, 1.0, 1.0))));
    }
}
