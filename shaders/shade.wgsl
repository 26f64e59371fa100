// Twin: crates/voxcast_core/src/shade.rs (`shade`, `power`): Phong / Blinn–Phong with the
// negated, normalised gradient as the normal, summed over the lights; Levoy's highlight takes
// the sample's colour.
#define_import_path voxcast::shade

#import voxcast::bindings::{params, FLAGS}

/// x^n for x ≥ 0: by squaring for whole n (as the core), else pow.
fn power(x: f32, n: f32) -> f32 {
    if fract(n) == 0.0 && n >= 0.0 && n <= 1024.0 {
        var base = x;
        var e = u32(n);
        var acc = 1.0;
        while e > 0u {
            if (e & 1u) == 1u {
                acc *= base;
            }
            base *= base;
            e = e >> 1u;
        }
        return acc;
    }
    return pow(x, n);
}

/// Shades colour c at p_world with gradient grad, seen along view (unit, towards the viewer),
/// summed over the scene's lights.
fn shade(c: vec3<f32>, grad: vec3<f32>, p_world: vec3<f32>, view: vec3<f32>) -> vec3<f32> {
    let len = length(grad);
    if !(len > params.gradient_threshold) {
        return c;
    }
    var n = grad * (-1.0 / len);
    if (FLAGS & #{FLAG_TWO_SIDED}u) != 0u && dot(n, view) < 0.0 {
        n = -n;
    }
    var tint = vec3(1.0);
    if (FLAGS & #{FLAG_LEVOY_HIGHLIGHT}u) != 0u {
        tint = c;
    }
    var diffuse = vec3(0.0);
    var specular = vec3(0.0);
    for (var i = 0u; i < params.light_count; i++) {
        let light = params.lights[i];
        var l = light.at;
        var attenuation = 1.0;
        if light.kind == #{LIGHT_POINT}u {
            let to = light.at - p_world;
            let d = length(to);
            let denom = light.kc + light.kl * d + light.kq * d * d;
            attenuation = select(1.0, 1.0 / denom, denom > 0.0);
            l = select(view, to / d, d > 0.0);
        }
        let n_dot_l = dot(n, l);
        let lambert = max(n_dot_l, 0.0);
        var spec = 0.0;
        if n_dot_l > 0.0 {
            var base: f32;
            if (FLAGS & #{FLAG_BLINN_PHONG}u) != 0u {
                let h = l + view;
                let h_len = length(h);
                base = dot(n, select(n, h / h_len, h_len > 0.0));
            } else {
                base = dot(n * (2.0 * n_dot_l) - l, view);
            }
            spec = power(max(base, 0.0), params.shininess);
        }
        diffuse += c * (light.color * (attenuation * params.kd * lambert));
        specular += tint * light.color * (attenuation * params.ks * spec);
    }
    let ambient = c * params.ka;
    return clamp(ambient + diffuse + specular, vec3(0.0), vec3(1.0));
}
