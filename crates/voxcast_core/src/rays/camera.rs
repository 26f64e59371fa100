//! The virtual camera's rays through the current volume as a ray data set, so the ray density
//! shows how densely a compositing method samples the grid. One ray per pixel centre, row by
//! row (ray id `y·width + x`), as the exact render casts it (same jitter). Its segment is the
//! part of the ray inside the volume after the crop box and clip plane: `t_min` where it
//! enters, `t_max` where it leaves. It **hits** where it stopped early — early termination's
//! cutoff, or First's target — at the sample that stopped it (for First, the sample past the
//! crossing: the refined hit lies up to one step before it). A ray that never enters the volume
//! has an empty segment (`t_min = t_max = 0`) and counts in no cell.

use super::set::{RayRecord, RaySet};
use crate::camera::Camera;
use crate::clip::clip_interval;
use crate::step::{plan_steps, sample_t};
use crate::trace::{Marcher, NoRecord, Scene, StopReason};
use crate::volume::{Grid, GridVisitor, Voxel};
use rayon::prelude::*;

/// The largest image the virtual camera's ray set is made for, per side.
pub const MAX_SIDE: u32 = 512;

/// The rays of `camera`'s `width × height` image through `scene`'s volume (each side at most
/// [`MAX_SIDE`]; larger sizes are clamped).
pub fn virtual_camera_rays(scene: &Scene<'_>, camera: &Camera, width: u32, height: u32) -> RaySet {
    struct Visit<'x, 'a> {
        scene: &'x Scene<'a>,
        camera: &'x Camera,
        size: (u32, u32),
    }
    impl GridVisitor for Visit<'_, '_> {
        type Output = Vec<RayRecord>;
        fn visit<T: Voxel>(self, grid: Grid<'_, T>) -> Vec<RayRecord> {
            let marcher = Marcher::new(self.scene, grid);
            let (w, h) = self.size;
            let rays = self.camera.rays(w, h);
            (0..w * h)
                .into_par_iter()
                .map(|id| {
                    let (px, py) = (id % w, id / w);
                    let ray = rays.ray(px as f32 + 0.5, py as f32 + 0.5);
                    let Some((t0, t1)) = clip_interval(&ray, &self.scene.clip) else {
                        return RayRecord {
                            id,
                            origin: ray.origin,
                            direction: ray.dir,
                            t_min: 0.0,
                            t_max: 0.0,
                            t_hit: -1.0,
                        };
                    };
                    let jitter = self.scene.jitter([px, py]);
                    let out = marcher.march(&ray, jitter, &mut NoRecord);
                    let stopped = matches!(out.stop, StopReason::Cutoff | StopReason::FirstHit);
                    let t_hit = if stopped && out.positions > 0 {
                        let plan = plan_steps(
                            t0,
                            t1,
                            self.scene.dt,
                            jitter,
                            self.scene.settings.max_samples,
                        );
                        sample_t(&plan, out.positions - 1)
                    } else {
                        -1.0
                    };
                    RayRecord {
                        id,
                        origin: ray.origin,
                        direction: ray.dir,
                        t_min: t0,
                        t_max: t1,
                        t_hit,
                    }
                })
                .collect()
        }
    }
    let size = (width.clamp(1, MAX_SIDE), height.clamp(1, MAX_SIDE));
    let rays = scene.volume.visit(Visit {
        scene,
        camera,
        size,
    });
    RaySet { trace_id: 0, rays }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builtin::load_builtin;
    use crate::composite::Method;
    use crate::preset;
    use crate::settings::RenderSettings;
    use crate::trace::trace_ray;

    fn setup(
        name: &str,
    ) -> (
        crate::Prepared,
        crate::transfer::TransferFunction,
        RenderSettings,
        Camera,
    ) {
        let v = load_builtin(name).unwrap().volume;
        let p = preset::for_volume(v.name()).unwrap();
        let s = p.settings_over(&RenderSettings::default()).unwrap();
        let (lo, hi) = v.bounds();
        let view = p.view.unwrap();
        let cam = Camera::framing(lo, hi, view.from, view.up).unwrap();
        (v.into(), p.transfer, s, cam)
    }

    /// The hits are the rays the march stopped early, at the sample that stopped them (the
    /// recorded trace of the same ray ends there); without early termination Accumulate stops
    /// none.
    #[test]
    fn the_rays_hit_where_the_march_stopped_them() {
        let (v, tf, s, cam) = setup("bunny");
        let scene = Scene::new(&v, &tf, &s, cam.forward()).unwrap();
        let set = virtual_camera_rays(&scene, &cam, 40, 30);
        assert_eq!(set.rays.len(), 1200);
        assert!(set.rays.iter().enumerate().all(|(i, r)| r.id == i as u32));
        let (hits, misses) = set.hits_and_misses(0.0);
        assert!(hits > 100 && misses > 100, "{hits} hits, {misses} misses");
        let rays = cam.rays(40, 30);
        for r in &set.rays {
            assert!(r.t_min <= r.t_max);
            let (x, y) = (r.id % 40, r.id / 40);
            let trace = trace_ray(&scene, &rays.ray(x as f32 + 0.5, y as f32 + 0.5), [x, y]);
            if r.is_hit(0.0) {
                assert_eq!(trace.stop, StopReason::Cutoff);
                assert_eq!(trace.samples.last().unwrap().t, r.t_hit);
                assert!(r.t_hit >= r.t_min && r.t_hit <= r.t_max);
            } else {
                assert_ne!(trace.stop, StopReason::Cutoff);
            }
        }
        let no_stop = RenderSettings {
            early_termination: false,
            ..s.clone()
        };
        let scene = Scene::new(&v, &tf, &no_stop, cam.forward()).unwrap();
        let set = virtual_camera_rays(&scene, &cam, 40, 30);
        assert_eq!(set.hits_and_misses(0.0).0, 0);
    }

    /// First hits at the sample past the crossing: the refined hit lies within one step before.
    #[test]
    fn first_hits_lie_just_past_the_crossing() {
        let (v, tf, s, cam) = setup("shells");
        let first = RenderSettings {
            method: Method::First,
            ..s
        };
        let scene = Scene::new(&v, &tf, &first, cam.forward()).unwrap();
        let set = virtual_camera_rays(&scene, &cam, 24, 24);
        let rays = cam.rays(24, 24);
        let mut hits = 0;
        for r in set.rays.iter().filter(|r| r.is_hit(0.0)) {
            hits += 1;
            let (x, y) = (r.id % 24, r.id / 24);
            let trace = trace_ray(&scene, &rays.ray(x as f32 + 0.5, y as f32 + 0.5), [x, y]);
            let hit = trace.first_hit.expect("the trace finds the same hit");
            assert_eq!(hit.bracket[1], r.t_hit);
            assert!(hit.t <= r.t_hit && hit.t >= r.t_hit - scene.dt - 1e-4);
        }
        assert!(hits > 0);
        // Sizes past the limit are clamped.
        assert_eq!(virtual_camera_rays(&scene, &cam, 4000, 1).rays.len(), 512);
    }
}
