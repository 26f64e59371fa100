// Twin: crates/voxcast_core/src/clip.rs (`clip_interval`): the crop box and the clip plane cut
// the interval a ray samples; the core resolves both into world units (`ResolvedClip`), passed
// as `crop_lo`/`crop_hi` and the plane `clip_normal·p ≤ clip_d` (a zero normal keeps all).
#define_import_path voxcast::clip

#import voxcast::bindings::params
#import voxcast::ray::{Interval, intersect_box}

/// [t_enter, t_exit] of the ray origin + t·dir in what the cut keeps of the volume, clipped to
/// [t_min, t_max]. A ray parallel to the plane is kept whole or not at all (no 0/0).
fn clip_interval(origin: vec3<f32>, dir: vec3<f32>, t_min: f32, t_max: f32) -> Interval {
    let in_box = intersect_box(origin, dir, t_min, t_max, params.crop_lo, params.crop_hi);
    if !in_box.hit {
        return in_box;
    }
    var t_enter = in_box.t_enter;
    var t_exit = in_box.t_exit;
    let side = dot(params.clip_normal, origin) - params.clip_d;
    let along = dot(params.clip_normal, dir);
    if along == 0.0 {
        if side > 0.0 {
            return Interval(0.0, 0.0, false);
        }
    } else {
        let t = -side / along;
        if along > 0.0 {
            t_exit = min(t_exit, t);
        } else {
            t_enter = max(t_enter, t);
        }
    }
    return Interval(t_enter, t_exit, t_enter <= t_exit);
}
