//! Rendered images: linear float pixels, 8-bit PNG output, and the error measures used to compare
//! two renders (speed/accuracy table, GPU/CPU agreement).
//!
//! Pixels are written to PNG as `round(255 · clamp(x, 0, 1))` per channel with no transfer curve
//! (as VTK writes its renders), so a PNG holds exactly the numbers the ray caster computed.

use glam::Vec3;
use std::path::Path;

/// An RGB image of linear floats, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Vec3>,
}

/// How two images differ, per channel, in units of the full range [0, 1].
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ImageDiff {
    pub rmse: f64,
    pub max_abs: f32,
    pub mean_abs: f64,
}

impl LinearImage {
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![Vec3::ZERO; width as usize * height as usize],
        }
    }

    pub fn get(&self, x: u32, y: u32) -> Vec3 {
        self.pixels[(y * self.width + x) as usize]
    }

    /// This image stretched to `width × height` with bilinear filtering between texel centres,
    /// clamped at the edges: what a GPU's linear sampler shows of a smaller render target.
    pub fn resized_bilinear(&self, width: u32, height: u32) -> Self {
        let mut out = Self::new(width, height);
        let (sw, sh) = (self.width.max(1), self.height.max(1));
        let coord = |d: u32, n: u32, s: u32| {
            let f = ((d as f32 + 0.5) * s as f32 / n as f32 - 0.5).clamp(0.0, (s - 1) as f32);
            let i = (f as u32).min(s - 1);
            (i, (i + 1).min(s - 1), f - i as f32)
        };
        for y in 0..height {
            let (y0, y1, fy) = coord(y, height, sh);
            for x in 0..width {
                let (x0, x1, fx) = coord(x, width, sw);
                let top = self.get(x0, y0).lerp(self.get(x1, y0), fx);
                let bottom = self.get(x0, y1).lerp(self.get(x1, y1), fx);
                out.set(x, y, top.lerp(bottom, fy));
            }
        }
        out
    }

    pub fn set(&mut self, x: u32, y: u32, v: Vec3) {
        self.pixels[(y * self.width + x) as usize] = v;
    }

    /// 8-bit RGB, as written to PNG.
    pub fn to_rgb8(&self) -> image::RgbImage {
        let mut out = image::RgbImage::new(self.width, self.height);
        for (dst, src) in out.pixels_mut().zip(&self.pixels) {
            *dst = image::Rgb(to_u8(*src));
        }
        out
    }

    /// Reads an 8-bit PNG back as linear floats (`v / 255`).
    pub fn from_rgb8(img: &image::RgbImage) -> Self {
        Self {
            width: img.width(),
            height: img.height(),
            pixels: img
                .pixels()
                .map(|p| Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32) / 255.0)
                .collect(),
        }
    }

    /// Writes a PNG (atomically: to a temporary file beside it, then renamed).
    pub fn save_png(&self, path: &Path) -> Result<(), image::ImageError> {
        save_rgb8_atomic(&self.to_rgb8(), path)
    }

    /// The image as the bytes of an 8-bit PNG file (what [`LinearImage::save_png`] writes).
    pub fn png_bytes(&self) -> Result<Vec<u8>, image::ImageError> {
        let mut bytes = std::io::Cursor::new(Vec::new());
        self.to_rgb8()
            .write_to(&mut bytes, image::ImageFormat::Png)?;
        Ok(bytes.into_inner())
    }

    /// Per-channel differences to `other`; `None` if the sizes differ.
    pub fn diff(&self, other: &Self) -> Option<ImageDiff> {
        if (self.width, self.height) != (other.width, other.height) {
            return None;
        }
        let mut sq = 0.0f64;
        let mut abs = 0.0f64;
        let mut max = 0.0f32;
        for (a, b) in self.pixels.iter().zip(&other.pixels) {
            let d = (*a - *b).abs();
            sq += d.length_squared() as f64;
            abs += (d.x + d.y + d.z) as f64;
            max = max.max(d.max_element());
        }
        let n = (self.pixels.len() * 3) as f64;
        Some(ImageDiff {
            rmse: (sq / n).sqrt(),
            max_abs: max,
            mean_abs: abs / n,
        })
    }

    /// A heat map of the largest channel difference per pixel: black (none) through red to
    /// yellow and white at `full_scale` or more.
    pub fn diff_heatmap(&self, other: &Self, full_scale: f32) -> Option<Self> {
        if (self.width, self.height) != (other.width, other.height) {
            return None;
        }
        let pixels = self
            .pixels
            .iter()
            .zip(&other.pixels)
            .map(|(a, b)| {
                let x = ((*a - *b).abs().max_element() / full_scale.max(f32::MIN_POSITIVE))
                    .clamp(0.0, 1.0)
                    * 3.0;
                Vec3::new(
                    x.min(1.0),
                    (x - 1.0).clamp(0.0, 1.0),
                    (x - 2.0).clamp(0.0, 1.0),
                )
            })
            .collect();
        Some(Self {
            width: self.width,
            height: self.height,
            pixels,
        })
    }
}

/// `round(255 · clamp(v, 0, 1))` per channel.
pub fn to_u8(v: Vec3) -> [u8; 3] {
    let q = |x: f32| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    [q(v.x), q(v.y), q(v.z)]
}

/// Writes `img` to `path` through a temporary file and a rename, so a failed or interrupted write
/// never leaves a half-written PNG where a good one was.
pub fn save_rgb8_atomic(img: &image::RgbImage, path: &Path) -> Result<(), image::ImageError> {
    let tmp = path.with_extension("png.tmp");
    img.save_with_format(&tmp, image::ImageFormat::Png)?;
    std::fs::rename(&tmp, path).map_err(image::ImageError::IoError)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_bytes_are_the_saved_file() {
        let mut a = LinearImage::new(3, 2);
        a.set(2, 1, Vec3::new(1.0, 0.5, 0.25));
        let path = std::env::temp_dir().join(format!("voxcast-png-{}.png", std::process::id()));
        a.save_png(&path).unwrap();
        assert_eq!(a.png_bytes().unwrap(), std::fs::read(&path).unwrap());
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn quantisation_and_diff() {
        assert_eq!(to_u8(Vec3::new(-1.0, 0.5, 2.0)), [0, 128, 255]);
        let mut a = LinearImage::new(2, 1);
        let b = LinearImage::new(2, 1);
        a.set(1, 0, Vec3::new(0.3, 0.0, 0.0));
        let d = a.diff(&b).unwrap();
        assert!((d.max_abs - 0.3).abs() < 1e-6);
        assert!((d.rmse - (0.09f64 / 6.0).sqrt()).abs() < 1e-6);
        assert!(a.diff(&LinearImage::new(1, 1)).is_none());
        let h = a.diff_heatmap(&b, 0.3).unwrap();
        assert_eq!(h.get(0, 0), Vec3::ZERO);
        assert_eq!(h.get(1, 0), Vec3::ONE);
    }

    #[test]
    fn bilinear_resize_keeps_the_ends_and_blends_between() {
        let mut small = LinearImage::new(2, 1);
        small.set(0, 0, Vec3::ZERO);
        small.set(1, 0, Vec3::ONE);
        let big = small.resized_bilinear(4, 2);
        // Texel centres at x = 0.25 and 0.75 of the width: the outer pixels clamp to them.
        assert_eq!(big.get(0, 0), Vec3::ZERO);
        assert_eq!(big.get(3, 1), Vec3::ONE);
        assert_eq!(big.get(1, 0), Vec3::splat(0.25));
        assert_eq!(big.get(2, 1), Vec3::splat(0.75));
        assert_eq!(small.resized_bilinear(2, 1), small, "same size: unchanged");
    }
}
