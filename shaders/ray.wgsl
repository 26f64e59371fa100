// Twin: crates/voxcast_core/src/ray.rs (`intersect_box`, `slab`): the robust slab test, axis by
// axis in straight lines as there.
#define_import_path voxcast::ray

struct Interval {
    t_enter: f32,
    t_exit: f32,
    hit: bool,
}

/// [t_enter, t_exit] of the ray origin + t·dir in the box [lo, hi], clipped to [t_min, t_max].
fn intersect_box(origin: vec3<f32>, dir: vec3<f32>, t_min: f32, t_max: f32, lo: vec3<f32>, hi: vec3<f32>) -> Interval {
    let x = slab(origin.x, dir.x, lo.x, hi.x, Interval(t_min, t_max, true));
    if !x.hit {
        return x;
    }
    let y = slab(origin.y, dir.y, lo.y, hi.y, x);
    if !y.hit {
        return y;
    }
    let z = slab(origin.z, dir.z, lo.z, hi.z, y);
    if !z.hit {
        return z;
    }
    return Interval(z.t_enter, z.t_exit, z.t_enter <= z.t_exit);
}

/// One axis of the slab test: `t` narrowed to the slab [lo, hi] of a ray component from `o`
/// along `d`; a miss where a ray parallel to it lies outside. A zero direction component
/// decides its axis directly (no 0/0).
fn slab(o: f32, d: f32, lo: f32, hi: f32, t: Interval) -> Interval {
    if d == 0.0 {
        if o >= lo && o <= hi {
            return t;
        }
        return Interval(0.0, 0.0, false);
    }
    let inv = 1.0 / d;
    let t0 = (lo - o) * inv;
    let t1 = (hi - o) * inv;
    return Interval(max(t.t_enter, min(t0, t1)), min(t.t_exit, max(t0, t1)), true);
}
