//! The camera: one ray per pixel centre (or n×n per pixel with supersampling).
//!
//! Twin: the sandbox's virtual camera, and `shaders/ray.wgsl`, which receives the same rays
//! through the rasterised box.
//!
//! The camera looks from `eye` at `target` with `up` as the screen's up; in its view space it
//! looks along −z with +y up (Bevy/OpenGL). Pixel `(px, py)` (row 0 at the top) has its centre at
//! normalised device coordinates
//!
//! ```text
//! x = 2·(px + ½)/width − 1,   y = 1 − 2·(py + ½)/height.
//! ```
//!
//! A **perspective** camera with vertical field of view `fov` shoots from the eye through
//! `forward + x·tan(fov/2)·aspect·right + y·tan(fov/2)·up'`, normalised (`aspect = width/height`,
//! `up'` the up vector made orthogonal to `forward`, as VTK's `OrthogonalizeViewUp`). An
//! **orthographic** camera of view height `h` shoots along `forward` from
//! `eye + x·(h/2)·aspect·right + y·(h/2)·up'`. The JSON is that of `../shared/tools/peer/cams`:
//! `{"eye": [..], "center": [..], "up": [..], "fov_y_deg": 30}`.

use crate::error::SettingsError;
use crate::ray::Ray;
use glam::Vec3;

/// How the view volume is shaped.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase", tag = "kind")]
pub enum Projection {
    /// Rays fan out from the eye; `fov_y_deg` is the vertical field of view in degrees.
    Perspective { fov_y_deg: f32 },
    /// Parallel rays; `height` is the view's height in world units.
    Orthographic { height: f32 },
}

/// A validated camera.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    pub projection: Projection,
}

/// The peer's camera JSON, plus an optional orthographic height.
#[derive(serde::Deserialize)]
struct CameraJson {
    eye: Vec3,
    #[serde(alias = "target")]
    center: Vec3,
    #[serde(default = "default_up")]
    up: Vec3,
    #[serde(default)]
    fov_y_deg: Option<f32>,
    #[serde(default)]
    orthographic_height: Option<f32>,
}

fn default_up() -> Vec3 {
    Vec3::Y
}

impl Camera {
    /// Validates: finite vectors, `eye ≠ target`, `up` not parallel to the view direction,
    /// field of view in (0°, 180°) or positive orthographic height.
    pub fn new(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        projection: Projection,
    ) -> Result<Self, SettingsError> {
        if !(eye.is_finite() && target.is_finite() && up.is_finite()) {
            return Err(SettingsError::Invalid(
                "camera: eye, target and up must be finite".into(),
            ));
        }
        let f = (target - eye).try_normalize().ok_or_else(|| {
            SettingsError::Invalid("camera: eye and target are the same point".into())
        })?;
        let u = up
            .try_normalize()
            .ok_or_else(|| SettingsError::Invalid("camera: up vector is zero".into()))?;
        if f.cross(u).length() < 1e-6 {
            return Err(SettingsError::Invalid(
                "camera: up is parallel to the view direction".into(),
            ));
        }
        match projection {
            Projection::Perspective { fov_y_deg } => {
                if !(fov_y_deg.is_finite() && fov_y_deg > 0.0 && fov_y_deg < 180.0) {
                    return Err(SettingsError::Invalid(format!(
                        "camera: field of view {fov_y_deg}° must lie strictly between 0° and 180°"
                    )));
                }
            }
            Projection::Orthographic { height } => {
                SettingsError::check_positive("orthographic height", height)?
            }
        }
        Ok(Self {
            eye,
            target,
            up,
            projection,
        })
    }

    /// Perspective camera from the peer's JSON (`eye`, `center`, `up`, `fov_y_deg`), or
    /// orthographic if it gives `orthographic_height`.
    pub fn from_json(text: &str) -> Result<Self, SettingsError> {
        let j: CameraJson = serde_json::from_str(text)
            .map_err(|e| SettingsError::Invalid(format!("camera: {e}")))?;
        let projection = match (j.orthographic_height, j.fov_y_deg) {
            (Some(height), _) => Projection::Orthographic { height },
            (None, fov) => Projection::Perspective {
                fov_y_deg: fov.unwrap_or(30.0),
            },
        };
        Self::new(j.eye, j.center, j.up, projection)
    }

    /// The JSON [`Camera::from_json`] reads.
    pub fn to_json(&self) -> String {
        let mut v = serde_json::json!({
            "eye": self.eye, "center": self.target, "up": self.up,
        });
        match self.projection {
            Projection::Perspective { fov_y_deg } => v["fov_y_deg"] = fov_y_deg.into(),
            Projection::Orthographic { height } => v["orthographic_height"] = height.into(),
        }
        serde_json::to_string_pretty(&v).expect("camera serialises")
    }

    /// A perspective camera with a 30° field of view looking at `bounds`' centre from direction
    /// `from` (eye − target), far enough that the whole box fits (the peer's `--auto-camera`).
    pub fn framing(lo: Vec3, hi: Vec3, from: Vec3, up: Vec3) -> Result<Self, SettingsError> {
        let fov = 30.0f32;
        let center = (lo + hi) * 0.5;
        let radius = ((hi - lo).length() * 0.5).max(1e-3);
        let dist = radius / (fov.to_radians() * 0.5).sin() * 1.02;
        let dir = from
            .try_normalize()
            .ok_or_else(|| SettingsError::Invalid("camera: view direction is zero".into()))?;
        Self::new(
            center + dir * dist,
            center,
            up,
            Projection::Perspective { fov_y_deg: fov },
        )
    }

    /// Unit vector from the eye towards the target.
    pub fn forward(&self) -> Vec3 {
        (self.target - self.eye).normalize()
    }

    /// The camera's orthonormal basis `(right, up', forward)`.
    pub fn basis(&self) -> (Vec3, Vec3, Vec3) {
        let f = self.forward();
        let r = f.cross(self.up).normalize();
        let u = r.cross(f);
        (r, u, f)
    }

    /// The ray through image position `(x, y)` in pixels from the top-left corner (`x + ½` is
    /// the centre of column `x`), for an image of `width × height` pixels.
    pub fn ray(&self, x: f32, y: f32, width: u32, height: u32) -> Ray {
        self.rays(width, height).ray(x, y)
    }

    /// The rays of a `width × height` image, with the camera's basis worked out once.
    pub fn rays(&self, width: u32, height: u32) -> ImageRays {
        let (right, up, forward) = self.basis();
        let aspect = width as f32 / height as f32;
        let half_height = match self.projection {
            Projection::Perspective { fov_y_deg } => (fov_y_deg.to_radians() * 0.5).tan(),
            Projection::Orthographic { height } => height * 0.5,
        };
        ImageRays {
            eye: self.eye,
            right: right * (half_height * aspect),
            up: up * half_height,
            forward,
            perspective: matches!(self.projection, Projection::Perspective { .. }),
            inv_size: (1.0 / width as f32, 1.0 / height as f32),
        }
    }

    /// Where the ray through image position `(x, y)` crosses the image plane `distance` in front
    /// of the eye (the plane the sandbox draws the pixel grid on).
    pub fn image_plane_point(
        &self,
        x: f32,
        y: f32,
        width: u32,
        height: u32,
        distance: f32,
    ) -> Vec3 {
        let ray = self.ray(x, y, width, height);
        let forward = self.forward();
        // Perspective rays reach the plane after distance / cos; orthographic ones start on the
        // eye's plane and travel straight along forward.
        ray.origin
            + ray.dir * ((distance - (ray.origin - self.eye).dot(forward)) / ray.dir.dot(forward))
    }

    /// The image position `(x, y)` in pixels (from the top-left corner) of the world point `p`
    /// in a `width × height` image: the inverse of [`Camera::ray`]. `None` for a point on or
    /// behind the eye's plane (perspective) — nothing there reaches the image.
    pub fn project(&self, p: Vec3, width: u32, height: u32) -> Option<(f32, f32)> {
        let rays = self.rays(width, height);
        let d = p - self.eye;
        let depth = d.dot(rays.forward);
        let (nx, ny) = if rays.perspective {
            if depth <= 0.0 {
                return None;
            }
            (
                d.dot(rays.right) / rays.right.length_squared() / depth,
                d.dot(rays.up) / rays.up.length_squared() / depth,
            )
        } else {
            (
                d.dot(rays.right) / rays.right.length_squared(),
                d.dot(rays.up) / rays.up.length_squared(),
            )
        };
        Some((
            (nx + 1.0) * 0.5 * width as f32,
            (1.0 - ny) * 0.5 * height as f32,
        ))
    }

    /// The ray through the centre of pixel `(px, py)`.
    pub fn pixel_ray(&self, px: u32, py: u32, width: u32, height: u32) -> Ray {
        self.ray(px as f32 + 0.5, py as f32 + 0.5, width, height)
    }
}

/// The rays of one image (see [`Camera::rays`]): the camera's basis scaled to the image plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageRays {
    pub eye: Vec3,
    /// Right and up, scaled to half the view's width and height (at unit distance for a
    /// perspective camera, in world units for an orthographic one).
    pub right: Vec3,
    pub up: Vec3,
    pub forward: Vec3,
    pub perspective: bool,
    /// `(1/width, 1/height)` of the image in pixels.
    pub inv_size: (f32, f32),
}

impl ImageRays {
    /// The ray through image position `(x, y)` in pixels from the top-left corner.
    #[inline]
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        let ndc_x = 2.0 * x * self.inv_size.0 - 1.0;
        let ndc_y = 1.0 - 2.0 * y * self.inv_size.1;
        let offset = self.right * ndc_x + self.up * ndc_y;
        let (origin, dir) = if self.perspective {
            (self.eye, (self.forward + offset).normalize())
        } else {
            (self.eye + offset, self.forward)
        };
        Ray {
            origin,
            dir,
            t_min: 0.0,
            t_max: f32::INFINITY,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_inverts_the_rays() {
        for projection in [
            Projection::Perspective { fov_y_deg: 70.0 },
            Projection::Orthographic { height: 5.0 },
        ] {
            let c =
                Camera::new(Vec3::new(3.0, -2.0, 9.0), Vec3::ZERO, Vec3::Z, projection).unwrap();
            for (x, y, t) in [(0.0, 0.0, 1.0), (320.0, 240.0, 7.5), (12.5, 470.0, 30.0)] {
                let p = c.ray(x, y, 640, 480).at(t);
                let (px, py) = c.project(p, 640, 480).unwrap();
                assert!(
                    (px - x).abs() < 1e-2 && (py - y).abs() < 1e-2,
                    "{projection:?}: {px},{py}"
                );
            }
        }
        let c = cam();
        assert!(
            c.project(c.eye - c.forward(), 10, 10).is_none(),
            "behind the eye"
        );
    }

    #[test]
    fn the_image_plane_holds_the_pixel_grid() {
        for projection in [
            Projection::Perspective { fov_y_deg: 50.0 },
            Projection::Orthographic { height: 4.0 },
        ] {
            let c = Camera::new(Vec3::new(1.0, 2.0, 9.0), Vec3::ZERO, Vec3::Y, projection).unwrap();
            let f = c.forward();
            let centre = c.image_plane_point(2.0, 1.5, 4, 3, 2.5);
            assert!(
                (centre - (c.eye + f * 2.5)).length() < 1e-4,
                "{projection:?}"
            );
            for (x, y) in [(0.0, 0.0), (4.0, 0.0), (0.0, 3.0), (4.0, 3.0), (1.3, 2.2)] {
                let p = c.image_plane_point(x, y, 4, 3, 2.5);
                assert!(((p - c.eye).dot(f) - 2.5).abs() < 1e-4);
                // On the pixel's ray.
                let r = c.ray(x, y, 4, 3);
                assert!((p - r.origin).cross(r.dir).length() < 1e-4);
            }
        }
    }

    fn cam() -> Camera {
        Camera::new(
            Vec3::new(0.0, 0.0, 10.0),
            Vec3::ZERO,
            Vec3::Y,
            Projection::Perspective { fov_y_deg: 90.0 },
        )
        .unwrap()
    }

    #[test]
    fn centre_ray_looks_at_the_target_and_corners_span_the_fov() {
        let c = cam();
        let r = c.ray(50.0, 50.0, 100, 100);
        assert!((r.dir - Vec3::NEG_Z).length() < 1e-6);
        // Top edge of a 90° view is 45° up.
        let top = c.ray(50.0, 0.0, 100, 100);
        assert!((top.dir - Vec3::new(0.0, 1.0, -1.0).normalize()).length() < 1e-6);
        // Right edge with aspect 2.
        let right = c.ray(200.0, 50.0, 200, 100);
        assert!((right.dir - Vec3::new(2.0, 0.0, -1.0).normalize()).length() < 1e-6);
    }

    #[test]
    fn orthographic_rays_are_parallel() {
        let c = Camera::new(
            Vec3::new(0.0, 0.0, 10.0),
            Vec3::ZERO,
            Vec3::Y,
            Projection::Orthographic { height: 4.0 },
        )
        .unwrap();
        let r = c.ray(0.0, 0.0, 10, 10);
        assert_eq!(r.dir, Vec3::NEG_Z);
        assert!((r.origin - Vec3::new(-2.0, 2.0, 10.0)).length() < 1e-6);
    }

    #[test]
    fn rejects_degenerate_cameras() {
        let p = Projection::Perspective { fov_y_deg: 30.0 };
        assert!(Camera::new(Vec3::ONE, Vec3::ONE, Vec3::Y, p).is_err());
        assert!(Camera::new(Vec3::ZERO, Vec3::Y, Vec3::Y, p).is_err());
        assert!(
            Camera::new(
                Vec3::ZERO,
                Vec3::Z,
                Vec3::Y,
                Projection::Perspective { fov_y_deg: 180.0 }
            )
            .is_err()
        );
        assert!(
            Camera::new(
                Vec3::ZERO,
                Vec3::Z,
                Vec3::Y,
                Projection::Orthographic { height: -1.0 }
            )
            .is_err()
        );
        assert!(Camera::from_json("{").is_err());
    }

    #[test]
    fn reads_the_peer_camera_json() {
        let c = Camera::from_json(
            r#"{"eye":[1,2,3],"center":[0,0,0],"up":[0,0,1],"fov_y_deg":30.0,"note":"x"}"#,
        )
        .unwrap();
        assert_eq!(c.eye, Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(c.projection, Projection::Perspective { fov_y_deg: 30.0 });
        let back = Camera::from_json(&c.to_json()).unwrap();
        assert_eq!(back, c);
    }
}
