//! The recorded ray: [`trace_ray`] runs the same march as the image with a recorder that keeps
//! every sample's numbers, for the breakdown and `voxcast trace`.

use super::*;

/// Traces `ray` through the scene, recording every sample. `jitter_key` is the pixel (or
/// sub-pixel) the ray belongs to, which decides its jitter.
pub fn trace_ray(scene: &Scene<'_>, ray: &Ray, jitter_key: [u32; 2]) -> RayTrace {
    struct Visit<'s, 'a> {
        scene: &'s Scene<'a>,
        ray: &'s Ray,
        jitter: f32,
    }
    impl GridVisitor for Visit<'_, '_> {
        type Output = (RayOutcome, Breakdown, Option<(f32, f32)>);
        fn visit<T: Voxel>(self, grid: Grid<'_, T>) -> Self::Output {
            let m = Marcher::new(self.scene, grid);
            let mut rec = Breakdown::default();
            let out = m.march(self.ray, self.jitter, &mut rec);
            (out, rec, m.interval(self.ray))
        }
    }
    let (out, rec, interval) = scene.volume.visit(Visit {
        scene,
        ray,
        jitter: scene.jitter(jitter_key),
    });
    let pixel = out.pixel(scene.settings.background);
    RayTrace {
        origin: ray.origin.to_array(),
        dir: ray.dir.to_array(),
        method: scene.settings.method,
        order: scene.settings.order,
        interval: interval.map(|(a, b)| [a, b]),
        box_interval: intersect_box(ray, scene.bounds.0, scene.bounds.1).map(|(a, b)| [a, b]),
        plan: rec.plan,
        samples: rec.samples,
        first_hit: rec.first_hit,
        projected_value: rec.projected,
        sum: rec.sum,
        stop: out.stop,
        color: out.color.to_array(),
        opacity: out.opacity,
        background: scene.settings.background.to_array(),
        pixel: pixel.to_array(),
    }
}

impl<'s, 'a, 'g, T: Voxel> Marcher<'s, 'a, 'g, T> {
    /// The record of a sample that is classified but not composited (First and the
    /// projections), with the running statistics where there are some.
    pub(super) fn record_plain(
        &self,
        plan: &StepPlan,
        k: u32,
        t: f32,
        pv: Vec3,
        v: f32,
        stats: Option<ValueStats>,
    ) -> SampleRecord {
        let cl = self.classify(v, (pv, None), None, true);
        let ds = segment_length(plan, k, t);
        let rgb = cl.rgba.truncate();
        self.record(
            k,
            t,
            ds,
            pv,
            v,
            &cl,
            cl.alpha,
            cl.grad,
            None,
            rgb,
            Vec4::ZERO,
            stats,
        )
    }

    #[allow(clippy::too_many_arguments)] // the march's per-sample hot path: see trace.rs
    pub(super) fn record(
        &self,
        k: u32,
        t: f32,
        ds: f32,
        pv: Vec3,
        v: f32,
        cl: &Classified,
        alpha_corrected: f32,
        grad: Option<Vec3>,
        shading: Option<ShadeTerms>,
        color: Vec3,
        composite_after: Vec4,
        stats_after: Option<ValueStats>,
    ) -> SampleRecord {
        let (lo, hi) = self.s.volume.value_range();
        SampleRecord {
            index: k,
            t,
            ds,
            p_world: (pv * self.g.spacing).to_array(),
            p_voxel: pv.to_array(),
            reconstruction: sample_detail(&self.g, pv, self.interp),
            value_normalized: if hi > lo {
                ((v - lo) / (hi - lo)).clamp(0.0, 1.0)
            } else {
                0.0
            },
            tf_rgba: cl.rgba.to_array(),
            alpha: cl.alpha,
            alpha_corrected,
            gradient: grad.map(|g| g.to_array()),
            shading,
            color: color.to_array(),
            composite_after: composite_after.to_array(),
            stats_after,
        }
    }
}
