//! First: the march to the first sample at or above the target value, and the refinement of
//! the hit between it and the sample before (the lecture's "distance to the first voxel").

use super::*;

impl<'s, 'a, 'g, T: Voxel> Marcher<'s, 'a, 'g, T> {
    pub(super) fn first<R: Recorder>(
        &self,
        ray: &Ray,
        plan: &StepPlan,
        o_v: Vec3,
        d_v: Vec3,
        rec: &mut R,
    ) -> RayOutcome {
        let skipping = !R::ACTIVE && self.s.block_skipping && plan.count > 0;
        if let Some(ranges) = self.s.blocks.filter(|_| skipping) {
            return self.first_skipping(ranges, ray, plan, o_v, d_v);
        }
        let target = self.s.target;
        let mut prev = None;
        for k in 0..plan.count {
            let t = sample_t(plan, k);
            let pv = o_v + d_v * t;
            let v = self.value(pv);
            if R::ACTIVE {
                rec.sample(self.record_plain(plan, k, t, pv, v, None));
            }
            if reaches(v, target) {
                // The value rose past the target since the previous sample; or, at the first
                // sample, the ray enters the volume at or above it and hits right there.
                let (pt, p) = prev.unwrap_or((t, v));
                return self.hit(ray, (pt, p, t, v), o_v, d_v, k + 1, rec);
            }
            // A sample with no data is no lower end for a hit's bracket.
            prev = v.is_finite().then_some((t, v));
        }
        RayOutcome {
            samples: plan.count,
            positions: plan.count,
            stop: StopReason::LeftVolume,
            ..RayOutcome::MISS
        }
    }

    /// Refines the hit in `[ta, tb]` (the value below the target at `ta`, at or above it at `tb`;
    /// one point when the ray entered at or above it) by bisection then linear interpolation,
    /// and shades it.
    pub(super) fn hit<R: Recorder>(
        &self,
        ray: &Ray,
        (mut ta, mut va, mut tb, mut vb): (f32, f32, f32, f32),
        o_v: Vec3,
        d_v: Vec3,
        samples: u32,
        rec: &mut R,
    ) -> RayOutcome {
        let target = self.s.target;
        let bracket = [ta, tb];
        let mut steps = Vec::new();
        if tb > ta {
            for _ in 0..self.s.settings.refine_steps {
                let tm = 0.5 * (ta + tb);
                let vm = self.value(o_v + d_v * tm);
                if !vm.is_finite() {
                    break; // no data between the two samples: keep the bracket as it is
                }
                if R::ACTIVE {
                    steps.push(RefineStep { t: tm, value: vm });
                }
                if reaches(vm, target) {
                    (tb, vb) = (tm, vm);
                } else {
                    (ta, va) = (tm, vm);
                }
            }
        }
        let t = ta + (tb - ta) * crossing_fraction(va, vb, target);
        let pv = o_v + d_v * t;
        let rgba = self.s.lut.lookup(target);
        let viewing = Viewing::from_origin(ray.origin, -ray.dir, &self.s.lights);
        let (color, _, terms) = self.shade(rgba.truncate(), (pv, None), None, &viewing);
        if R::ACTIVE {
            let value = self.value(pv);
            steps.push(RefineStep { t, value });
            rec.first_hit(FirstHit {
                t,
                p_world: ray.at(t).to_array(),
                p_voxel: pv.to_array(),
                value,
                bracket,
                refinement: steps,
                tf_rgba: rgba.to_array(),
                shading: terms,
                color: color.to_array(),
            });
        }
        RayOutcome {
            color: color * rgba.w,
            opacity: rgba.w,
            samples,
            positions: samples,
            stop: StopReason::FirstHit,
            hit_t: t,
        }
    }
}
