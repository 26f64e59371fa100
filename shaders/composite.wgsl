// Twin: crates/voxcast_core/src/composite.rs (`correct_opacity`, `accumulate_front_to_back`,
// `accumulate_back_to_front`, `blend_background`, `reaches`, `crossing_fraction`,
// `sum_to_value`): compositing, each a small pure function.
#define_import_path voxcast::composite

/// α' = 1 − (1 − α)^(ds/ds_ref), exact at α = 0 and α = 1.
fn correct_opacity(alpha: f32, ds: f32, ds_ref: f32) -> f32 {
    if alpha <= 0.0 {
        return 0.0;
    }
    if alpha >= 1.0 {
        return select(0.0, 1.0, ds > 0.0);
    }
    let e = ds / ds_ref;
    let keep = 1.0 - alpha;
    if e == 1.0 {
        return alpha;
    } else if e == 0.5 {
        return 1.0 - sqrt(keep);
    } else if e == 2.0 {
        return 1.0 - keep * keep;
    }
    return 1.0 - pow(keep, e);
}

/// Front to back: C + (1 − O)·α·c, O + (1 − O)·α (premultiplied colour in rgb, opacity in a).
fn accumulate_front_to_back(acc: vec4<f32>, color: vec3<f32>, alpha: f32) -> vec4<f32> {
    let w = (1.0 - acc.a) * alpha;
    return vec4(acc.rgb + color * w, acc.a + w);
}

/// Back to front: C·(1 − α) + c·α, O·(1 − α) + α.
fn accumulate_back_to_front(acc: vec4<f32>, color: vec3<f32>, alpha: f32) -> vec4<f32> {
    return vec4(acc.rgb * (1.0 - alpha) + color * alpha, acc.a * (1.0 - alpha) + alpha);
}

/// C + (1 − O)·background.
fn blend_background(acc: vec4<f32>, background: vec3<f32>) -> vec3<f32> {
    return acc.rgb + background * (1.0 - acc.a);
}

/// Whether a value counts as a First hit: at or above the target (never a NaN).
fn reaches(value: f32, target_value: f32) -> bool {
    return value >= target_value;
}

/// Where between two samples the linear interpolation equals target, in [0, 1].
fn crossing_fraction(prev: f32, cur: f32, target_value: f32) -> f32 {
    let d = cur - prev;
    if d == 0.0 {
        return 0.0;
    }
    return clamp((target_value - prev) / d, 0.0, 1.0);
}

/// Sum's table position: s clamped to range = (a, b) and stretched over table = (lo, hi).
fn sum_to_value(s: f32, range: vec2<f32>, table: vec2<f32>) -> f32 {
    let x = clamp((s - range.x) / (range.y - range.x), 0.0, 1.0);
    return table.x + (table.y - table.x) * select(0.0, x, x == x);
}
