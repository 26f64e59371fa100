//! The picture and its cost map from one march: Render image's two views of the same rays,
//! each bit for bit what [`crate::render::render_in`] and [`super::render_cost_in`] give
//! (tests/slices.rs), for the time of one march instead of two.

use super::{CostMap, cost_map, ray_cost};
use crate::image_out::LinearImage;
use crate::render::{Cancelled, Job, RenderStats, TileSlices};
use crate::slices::{Deadline, Step};
use glam::{Vec3, Vec4};
use rayon::prelude::*;
use std::ops::{Add, Mul};

/// One ray's (then one pixel's) colour over the background and its [`ray_cost`], summed and
/// averaged over a pixel's rays together.
#[derive(Clone, Copy, Debug, Default)]
pub struct PictureAndCost {
    picture: Vec3,
    cost: Vec4,
}

impl Add for PictureAndCost {
    type Output = Self;
    fn add(self, other: Self) -> Self {
        Self {
            picture: self.picture + other.picture,
            cost: self.cost + other.cost,
        }
    }
}

impl Mul<f32> for PictureAndCost {
    type Output = Self;
    fn mul(self, k: f32) -> Self {
        Self {
            picture: self.picture * k,
            cost: self.cost * k,
        }
    }
}

/// The picture of `job` (its occluders and surface left out), what it measured, and its cost
/// map, in slices as [`crate::render::render_in`].
pub fn render_with_cost_in(
    job: &Job<'_, '_>,
    slices: &mut TileSlices<PictureAndCost>,
    deadline: Deadline,
) -> Result<Step<(LinearImage, RenderStats, CostMap)>, Cancelled> {
    let job = job.volume_alone();
    let step = job.run_on_volume(
        |out, background, _| PictureAndCost {
            picture: out.pixel(background),
            cost: ray_cost(out),
        },
        slices,
        deadline,
    )?;
    let Step::Done((pixels, stats)) = step else {
        return Ok(Step::Paused);
    };
    let cost = cost_map(&job, &pixels, |p| p.cost, stats);
    let image = LinearImage {
        width: job.width,
        height: job.height,
        pixels: pixels.par_iter().map(|p| p.picture).collect(),
    };
    Ok(Step::Done((image, stats, cost)))
}
