//! The code's answers to the questions a step asks about the selected ray — how many samples it
//! takes, the step a fixed number of steps would give it, how many cells it crosses — each with its
//! working in the numbers the breakdown shows, for the panel to show once the step is done.

use super::Objective;
use crate::breakdown::RayTrace;
use crate::cells::{CellsCrossed, cells_crossed, planes_between};
use crate::numbers::sig;
use crate::volume::Volume;
use glam::Vec3;

/// The answer to a question about one ray.
#[derive(Clone, Debug, PartialEq)]
pub struct RayAnswer {
    /// The number the student's prediction is checked against.
    pub truth: f32,
    /// The question in words, as the answers file keeps it.
    pub question: String,
    /// How the number comes about, in the breakdown's numbers.
    pub working: String,
    /// The cells the ray crosses (for `predict-cells`, to draw them).
    pub cells: Option<CellsCrossed>,
}

/// The answer to `objective` (a part of it) about `trace` through `volume`; `None` when it
/// asks nothing about the ray, or the ray misses what is left of the volume.
pub fn ray_answer(objective: &Objective, trace: &RayTrace, volume: &Volume) -> Option<RayAnswer> {
    objective
        .parts()
        .into_iter()
        .find_map(|o| answer_one(o, trace, volume))
}

fn answer_one(o: &Objective, trace: &RayTrace, volume: &Volume) -> Option<RayAnswer> {
    let [a, b] = trace.interval?;
    let plan = trace.plan.as_ref()?;
    let span = format!("({} − {})", sig(b), sig(a));
    match o {
        Objective::PredictSamples => {
            let n = plan.count;
            let jitter = if plan.jitter > 0.0 {
                format!(" − {}", sig(plan.jitter))
            } else {
                String::new()
            };
            let mut working = format!(
                "floor({span} / {}{jitter}) + 1 = {n}: one sample at t = {}, then one every {} \
                 while t ≤ {}",
                sig(plan.dt),
                sig(a + plan.jitter * plan.dt),
                sig(plan.dt),
                sig(b)
            );
            if plan.capped {
                working.push_str(" (the sample cap stopped the ray there)");
            }
            Some(RayAnswer {
                truth: n as f32,
                question: "the samples the selected ray takes".into(),
                working,
                cells: None,
            })
        }
        Objective::PredictFixedCountStep { steps, .. } => {
            let step = (b - a) / (*steps).max(1) as f32;
            Some(RayAnswer {
                truth: step,
                question: format!("the step on the selected ray in {steps} steps"),
                working: format!(
                    "{span} / {steps} = {}: each step if this ray were marched in {steps}; at \
                     the fixed step of {} it takes {} samples",
                    sig(step),
                    sig(plan.dt),
                    plan.count
                ),
                cells: None,
            })
        }
        Objective::PredictCells => {
            let walk = cells_crossed(
                volume,
                Vec3::from(trace.origin),
                Vec3::from(trace.dir),
                [a, b],
            );
            let p = planes_between(walk.entry, walk.exit);
            let n = walk.cells.len();
            let rule = 1 + p[0] + p[1] + p[2];
            let mut working = format!(
                "it enters at {} and leaves at {} (voxels), passing {} whole x, {} whole y and \
                 {} whole z coordinates: 1 + {} + {} + {} = {rule}",
                point(walk.entry),
                point(walk.exit),
                p[0],
                p[1],
                p[2],
                p[0],
                p[1],
                p[2]
            );
            if rule as usize != n {
                working.push_str(&format!(
                    "; it passes through an edge or corner of the cells, where the walk crosses \
                     two or three faces in one step: {n} cells"
                ));
            }
            Some(RayAnswer {
                truth: n as f32,
                question: "the cells the selected ray crosses".into(),
                working,
                cells: Some(walk),
            })
        }
        _ => None,
    }
}

/// A point rounded for reading.
fn point(p: [f32; 3]) -> String {
    format!("({}, {}, {})", sig(p[0]), sig(p[1]), sig(p[2]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ray::Ray;
    use crate::settings::RenderSettings;
    use crate::step::Length;
    use crate::trace::{Scene, trace_ray};
    use crate::volume::VoxelData;
    use glam::UVec3;

    fn traced(step: f32, jitter: bool, origin: Vec3, dir: Vec3) -> (Volume, RayTrace) {
        let dims = UVec3::splat(8);
        let data = (0..512).map(|i| (i % 7) as f32).collect();
        let v = Volume::new("t", dims, Vec3::splat(0.5), VoxelData::F32(data)).unwrap();
        let prepared = crate::prepared::Prepared::new(v.clone());
        let tf = crate::transfer::TransferFunction::ramp(0.0, 6.0, 0.3).unwrap();
        let s = RenderSettings {
            step: Length::Voxels(step),
            jitter,
            early_termination: false,
            ..RenderSettings::default()
        };
        let ray = Ray::new(origin, dir).unwrap();
        let scene = Scene::new(&prepared, &tf, &s, ray.dir).unwrap();
        (v, trace_ray(&scene, &ray, [3, 5]))
    }

    /// The count is the samples the trace recorded, with and without jitter, for steps fine
    /// and coarse; the working ends in it.
    #[test]
    fn the_sample_count_is_the_traces() {
        for (step, jitter) in [(0.3, false), (1.0, false), (0.37, true), (5.0, false)] {
            let (v, t) = traced(
                step,
                jitter,
                Vec3::new(-1.0, 0.3, 0.2),
                Vec3::new(1.0, 0.4, 0.5),
            );
            let a = ray_answer(&Objective::PredictSamples, &t, &v).unwrap();
            assert_eq!(
                a.truth as usize,
                t.samples.len(),
                "step {step} jitter {jitter}"
            );
            assert!(a.working.contains(&format!("= {}", t.samples.len())));
        }
    }

    /// A fixed count divides the ray's length in the volume; the cells are the walk's, as many
    /// as the rule counts for a ray that misses every edge and corner.
    #[test]
    fn the_fixed_count_step_and_the_cells() {
        let (v, t) = traced(
            0.5,
            false,
            Vec3::new(-1.0, 0.3, 0.2),
            Vec3::new(1.0, 0.43, 0.51),
        );
        let [a, b] = t.interval.unwrap();
        let o = Objective::PredictFixedCountStep {
            steps: 16,
            tolerance: 0.01,
        };
        let step = ray_answer(&o, &t, &v).unwrap();
        assert!((step.truth - (b - a) / 16.0).abs() < 1e-6);
        let cells = ray_answer(&Objective::PredictCells, &t, &v).unwrap();
        let walk = cells.cells.unwrap();
        assert_eq!(cells.truth as usize, walk.cells.len());
        let p = planes_between(walk.entry, walk.exit);
        assert_eq!(walk.cells.len() as u32, 1 + p[0] + p[1] + p[2]);
        assert!(cells.working.ends_with(&format!("= {}", walk.cells.len())));
        // Inside an `all`, the ray's question is still found; other objectives ask nothing.
        let all = Objective::All {
            of: vec![Objective::SelectRay, Objective::PredictCells],
        };
        assert_eq!(ray_answer(&all, &t, &v).unwrap().truth, cells.truth);
        assert!(ray_answer(&Objective::SelectRay, &t, &v).is_none());
    }

    /// In voxels this ray passes through x = 4 and y = 3 at one point: the walk crosses both
    /// faces in one step, one cell fewer than the rule counts, and the working says why.
    #[test]
    fn through_an_edge_the_walk_takes_one_step() {
        let (v, t) = traced(
            0.5,
            false,
            Vec3::new(-1.0, 0.3, 0.2),
            Vec3::new(1.0, 0.4, 0.5),
        );
        let cells = ray_answer(&Objective::PredictCells, &t, &v).unwrap();
        let walk = cells.cells.unwrap();
        let p = planes_between(walk.entry, walk.exit);
        assert_eq!(walk.cells.len() as u32 + 1, 1 + p[0] + p[1] + p[2]);
        assert!(
            cells.working.contains("edge or corner"),
            "{}",
            cells.working
        );
    }

    /// A ray that misses the box has no answer to check against.
    #[test]
    fn a_missing_ray_has_no_answer() {
        let (v, t) = traced(0.5, false, Vec3::new(-1.0, 9.0, 0.2), Vec3::X);
        assert!(t.interval.is_none());
        assert!(ray_answer(&Objective::PredictSamples, &t, &v).is_none());
    }
}
