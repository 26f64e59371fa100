// Twin: crates/voxcast_core/src/ray.rs (`intersect_box`): the robust slab test.
#define_import_path voxcast::ray

struct Interval {
    t_enter: f32,
    t_exit: f32,
    hit: bool,
}

/// [t_enter, t_exit] of the ray origin + t·dir in the box [lo, hi], clipped to [t_min, t_max].
/// A zero direction component decides its axis directly (no 0/0).
fn intersect_box(origin: vec3<f32>, dir: vec3<f32>, t_min: f32, t_max: f32, lo: vec3<f32>, hi: vec3<f32>) -> Interval {
    var t_enter = t_min;
    var t_exit = t_max;
    for (var a = 0; a < 3; a++) {
        let o = origin[a];
        let d = dir[a];
        if d == 0.0 {
            if o < lo[a] || o > hi[a] {
                return Interval(0.0, 0.0, false);
            }
            continue;
        }
        let inv = 1.0 / d;
        let t0 = (lo[a] - o) * inv;
        let t1 = (hi[a] - o) * inv;
        t_enter = max(t_enter, min(t0, t1));
        t_exit = min(t_exit, max(t0, t1));
    }
    return Interval(t_enter, t_exit, t_enter <= t_exit);
}
