//! `voxcast --measure-frames N [--auto-orbit DEG]`: the sandbox measures its own frame time —
//! optionally while orbiting the camera, which engages adaptive quality — prints the mean and
//! median over N frames after a warm-up, and exits. BENCHMARKS.md's preview figures come from it.
//! The virtual camera's rays are shown whole (no growing animation), with all their samples.

use super::orbit::Orbit;
use super::state::{MainCamera, View};
use bevy::prelude::*;

/// What to measure.
#[derive(Resource, Clone)]
pub struct MeasureRequest {
    pub frames: u32,
    /// Degrees of orbit per frame (0: a resting camera).
    pub orbit_degrees: f32,
    /// A label printed with the figures.
    pub label: String,
}

/// Frames drawn before measuring (pipelines compiled, textures uploaded, quality settled).
const WARM_UP: u32 = 15;

pub(super) fn plugin(app: &mut App) {
    app.add_systems(Update, measure_frames);
}

fn measure_frames(
    request: Res<MeasureRequest>,
    time: Res<Time<Real>>,
    mut seen: Local<u32>,
    mut samples: Local<Vec<f32>>,
    mut cameras: Query<(&mut Orbit, &mut Transform, &mut View), With<MainCamera>>,
    mut exit: MessageWriter<AppExit>,
    animation: Option<ResMut<super::inspect::RayAnimation>>,
) {
    *seen += 1;
    // Every ray and sample on screen from the start: the cost of the whole scene.
    if let Some(mut a) = animation
        && a.distance.is_finite()
    {
        a.skip();
    }
    if request.orbit_degrees != 0.0 {
        for (mut orbit, mut transform, mut view) in &mut cameras {
            orbit.yaw += request.orbit_degrees.to_radians();
            *transform = orbit.transform();
            if let Ok(v) = voxcast_core::camera::Camera::new(
                transform.translation,
                orbit.focus,
                orbit.up,
                view.0.projection,
            ) {
                view.0 = v;
            }
        }
    }
    if *seen <= WARM_UP {
        return;
    }
    // Real time: virtual time clamps a frame at 250 ms.
    samples.push(time.delta_secs() * 1000.0);
    if samples.len() as u32 == request.frames {
        let mut sorted = samples.clone();
        sorted.sort_by(f32::total_cmp);
        let mean = sorted.iter().sum::<f32>() / sorted.len() as f32;
        let median = sorted[sorted.len() / 2];
        println!(
            "{}: frame time mean {mean:.1} ms, median {median:.1} ms ({:.1} fps) over {} frames",
            request.label,
            1000.0 / median,
            sorted.len()
        );
        exit.write(AppExit::Success);
    }
}
