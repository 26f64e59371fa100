//! Acceleration made visible: what each pixel's rays cost, as a heat map.
//!
//! [`render_cost`] runs the very march of [`crate::render`] (same rays, same skipping, same
//! early termination) and keeps, per pixel instead of the colour, what it did: the samples it
//! interpolated, the sample positions it passed (interpolated or skipped as empty space: what a
//! caster without skipping would have interpolated), and how its rays stopped. [`CostMap::image`]
//! draws one of these as the Radeon Raytracing Analyzer draws its traversal counters: a heat map
//! through [`crate::colormap::inferno`] scaled to the image's largest count, or the stop reasons
//! in flat colours. Turning early termination or skipping off and rendering again shows where the
//! work they save lies, pixel by pixel.

use crate::camera::Camera;
use crate::colormap::inferno;
use crate::image_out::LinearImage;
use crate::render::{Cancelled, Job, RenderStats};
use crate::trace::{Scene, StopReason};
use crate::volume::{Grid, GridVisitor, Voxel};
use glam::{Vec3, Vec4};
use std::sync::atomic::AtomicBool;

/// What a cost image shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CostView {
    /// Samples interpolated per pixel.
    Samples,
    /// Sample positions passed over without interpolating (empty space skipped).
    Skipped,
    /// How the rays stopped: ran through, stopped early, cut short by the cap, or missed.
    Stops,
}

impl CostView {
    pub const ALL: [CostView; 3] = [CostView::Samples, CostView::Skipped, CostView::Stops];

    /// The view's name in the UI and on the command line.
    pub const fn name(self) -> &'static str {
        match self {
            CostView::Samples => "samples",
            CostView::Skipped => "skipped",
            CostView::Stops => "stops",
        }
    }

    /// What the view shows, in words (the legend).
    pub const fn doc(self) -> &'static str {
        match self {
            CostView::Samples => {
                "Samples interpolated per pixel: the work of the march, dark (none) to pale \
                 yellow (the most in this image)."
            }
            CostView::Skipped => {
                "Sample positions passed without interpolating, per pixel: the work empty-space \
                 skipping saved, dark (none) to pale yellow (the most)."
            }
            CostView::Stops => {
                "How each pixel's rays stopped: blue, they left the volume; orange, early \
                 termination or a First hit stopped them; red, the sample cap; black, they missed \
                 the volume or the cut left nothing."
            }
        }
    }

    /// The view named `name`, if any.
    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|v| v.name() == name)
    }
}

/// Colours of [`CostView::Stops`].
pub const LEFT_COLOR: Vec3 = Vec3::new(0.2, 0.45, 1.0);
pub const EARLY_COLOR: Vec3 = Vec3::new(1.0, 0.55, 0.1);
pub const CAPPED_COLOR: Vec3 = Vec3::new(1.0, 0.1, 0.1);

/// Per pixel, summed over its rays: samples interpolated, positions passed, rays stopped early
/// (early termination or a First hit), rays the cap cut short, rays that took any position.
#[derive(Clone, Debug, PartialEq)]
pub struct CostMap {
    pub width: u32,
    pub height: u32,
    /// Rays per pixel (supersampling²).
    pub rays_per_pixel: u32,
    /// `[samples, positions, early, capped, marched]` per pixel, row by row.
    pub pixels: Vec<[u32; 5]>,
    pub stats: RenderStats,
}

impl CostMap {
    /// The count `view` shows for one pixel (`Stops` has none: 0).
    pub fn count(&self, view: CostView, p: &[u32; 5]) -> u32 {
        match view {
            CostView::Samples => p[0],
            CostView::Skipped => p[1] - p[0],
            CostView::Stops => 0,
        }
    }

    /// The largest count `view` shows in the image.
    pub fn max(&self, view: CostView) -> u32 {
        self.pixels
            .iter()
            .map(|p| self.count(view, p))
            .max()
            .unwrap_or(0)
    }

    /// The view as an image: counts through inferno, 0 to the image's maximum; or the stops'
    /// colours, blended by the share of the pixel's rays that stopped each way.
    pub fn image(&self, view: CostView) -> LinearImage {
        let mut image = LinearImage::new(self.width, self.height);
        let max = self.max(view).max(1) as f32;
        let rays = self.rays_per_pixel.max(1) as f32;
        for (i, p) in self.pixels.iter().enumerate() {
            let c = match view {
                CostView::Stops => {
                    let (early, capped, marched) = (p[2] as f32, p[3] as f32, p[4] as f32);
                    let left = marched - early - capped;
                    (LEFT_COLOR * left + EARLY_COLOR * early + CAPPED_COLOR * capped) / rays
                }
                _ => inferno(self.count(view, p) as f32 / max),
            };
            image.set(i as u32 % self.width, i as u32 / self.width, c);
        }
        image
    }
}

/// Renders what every pixel of `camera`'s view costs (see the module's text); progress and
/// cancel as [`crate::render::render`].
pub fn render_cost(
    scene: &Scene<'_>,
    camera: &Camera,
    (width, height): (u32, u32),
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<CostMap, Cancelled> {
    /// Missed rays are counted in the last channel in units of this (above any ray count).
    const MISSED: f32 = 1024.0;
    struct Visit<'x, 'a> {
        job: Job<'x, 'a>,
    }
    impl GridVisitor for Visit<'_, '_> {
        type Output = Result<(Vec<Vec4>, RenderStats), Cancelled>;
        fn visit<T: Voxel>(self, grid: Grid<'_, T>) -> Self::Output {
            self.job.run(grid, |out, _, _| {
                let early = matches!(out.stop, StopReason::Cutoff | StopReason::FirstHit);
                let capped = out.stop == StopReason::SampleCap;
                let missed = matches!(out.stop, StopReason::Missed | StopReason::CutAway);
                Vec4::new(
                    out.samples as f32,
                    out.positions as f32,
                    f32::from(u8::from(early)),
                    f32::from(u8::from(capped)) + MISSED * f32::from(u8::from(missed)),
                )
            })
        }
    }
    let job = Job::plain(scene, camera, (width, height), progress, cancel);
    let (pixels, stats) = scene.volume.visit(Visit { job })?;
    // The job averages over a pixel's rays; multiplied back, every count is a whole number
    // again (they stay far below 2^24, where f32 holds integers exactly).
    let n = scene.settings.supersampling.max(1);
    let rays = (n * n) as f32;
    let whole = |x: f32| (x * rays).round() as u32;
    let pixels = pixels
        .into_iter()
        .map(|p| {
            let last = whole(p.w);
            let (missed, capped) = (last / MISSED as u32, last % MISSED as u32);
            [whole(p.x), whole(p.y), whole(p.z), capped, n * n - missed]
        })
        .collect();
    Ok(CostMap {
        width,
        height,
        rays_per_pixel: n * n,
        pixels,
        stats,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::RenderSettings;
    use crate::step::Length;

    fn head() -> crate::Volume {
        crate::builtin::load_builtin("head").unwrap().volume
    }

    fn cost(v: &crate::Volume, s: &RenderSettings) -> CostMap {
        let tf = crate::preset::for_volume("head").unwrap().transfer;
        let (lo, hi) = v.bounds();
        let camera = Camera::framing(lo, hi, Vec3::new(0.3, 0.2, 1.0), Vec3::Y).unwrap();
        let scene = Scene::new(v, &tf, s, camera.forward()).unwrap();
        render_cost(
            &scene,
            &camera,
            (40, 30),
            &|_, _| {},
            &AtomicBool::new(false),
        )
        .unwrap()
    }

    /// The map's counts add up to the render's totals, and every pixel's rays are accounted
    /// for: missed, left, stopped early or capped.
    #[test]
    fn counts_add_up_to_the_renders() {
        let v = head();
        for n in [1u32, 3] {
            let s = RenderSettings {
                supersampling: n,
                ..Default::default()
            };
            let m = cost(&v, &s);
            let samples: u64 = m.pixels.iter().map(|p| p[0] as u64).sum();
            let positions: u64 = m.pixels.iter().map(|p| p[1] as u64).sum();
            assert_eq!(samples, m.stats.samples);
            assert_eq!(positions, m.stats.positions);
            assert!(m.pixels.iter().all(|p| p[0] <= p[1] && p[2] + p[3] <= p[4]));
            assert!(m.pixels.iter().all(|p| p[4] <= n * n));
            assert!(m.pixels.iter().any(|p| p[4] == 0), "some rays miss");
            assert!(
                m.pixels.iter().any(|p| p[2] > 0),
                "the opaque scalp stops rays"
            );
        }
    }

    /// Early termination off: no ray stops early, and the samples rise; skipping off: nothing
    /// is skipped, and the samples equal the positions.
    #[test]
    fn the_switches_show_in_the_map() {
        let v = head();
        let on = cost(&v, &RenderSettings::default());
        let no_early = cost(
            &v,
            &RenderSettings {
                early_termination: false,
                ..Default::default()
            },
        );
        assert!(no_early.pixels.iter().all(|p| p[2] == 0));
        assert!(no_early.stats.samples > on.stats.samples);
        let no_skip = cost(
            &v,
            &RenderSettings {
                skipping: false,
                ..Default::default()
            },
        );
        assert_eq!(no_skip.max(CostView::Skipped), 0);
        assert!(no_skip.pixels.iter().all(|p| p[0] == p[1]));
        assert!(
            on.max(CostView::Skipped) > 0,
            "the air around the head is skipped"
        );
        // The heat map spans inferno: the busiest pixel is its last colour.
        let image = on.image(CostView::Samples);
        assert!(image.pixels.contains(&inferno(1.0)));
        let stops = on.image(CostView::Stops);
        assert!(stops.pixels.contains(&EARLY_COLOR) && stops.pixels.contains(&Vec3::ZERO));
        let coarse = cost(
            &v,
            &RenderSettings {
                step: Length::Voxels(1e6),
                ..Default::default()
            },
        );
        assert!(
            coarse.pixels.iter().all(|p| p[1] <= 1),
            "one position a ray"
        );
    }

    #[test]
    fn views_have_names_and_words() {
        for v in CostView::ALL {
            assert_eq!(CostView::parse(v.name()), Some(v));
            assert!(v.doc().len() > 40);
        }
        assert_eq!(CostView::parse("nothing"), None);
    }
}
