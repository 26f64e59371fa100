// Twin: crates/voxcast_core/src/shade.rs (`shade`, `power`), and shade/lights.rs's
// `Cone::factor` as `spot_factor`: the lecture's illumination model with the negated, normalised gradient as the
// normal — emission, global ambient, and per light its ambient, Phong or Blinn–Phong diffuse
// and specular terms, falloff and spotlight factor; Levoy's highlight takes the sample's colour
// and Levoy's depth cue sets every light's falloff from the picture plane.
// GPU-only: `add_light` (the body of the core's loop over the lights in `shade`, called once per
// light with its index written out: see `shade`).
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

/// The spotlight factor of light i for a sample whose unit direction to it is l: the core's
/// `Cone::factor`.
fn spot_factor(i: u32, l: vec3<f32>) -> f32 {
    let light = params.lights[i];
    let cos_a = -dot(l, light.spot_along);
    if cos_a >= light.spot_cos_cutoff {
        return power(max(cos_a, 0.0), light.spot_exponent);
    }
    return 0.0;
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
    // Levoy's depth cue: one falloff from the picture plane (through the eye) for every light.
    var cue = 1.0;
    if (FLAGS & #{FLAG_DEPTH_CUE}u) != 0u {
        let d = dot(p_world - params.cam_eye, params.cam_forward);
        let denom = params.depth_kc + params.depth_kl * d;
        cue = select(1.0, 1.0 / denom, denom > 0.0);
    }
    // One share per light, each called with its index written out (the pipeline is compiled
    // for the scene's number of lights, VARIANT_LIGHTS): a GPU that runs a group's lanes in
    // step, as SwiftShader does, reads a light indexed by a loop's variable lane by lane.
    var sum = LightShare(vec3(0.0), vec3(0.0), vec3(0.0));
#if VARIANT_LIGHTS > 0
    sum = add_light(sum, 0u, c, n, tint, cue, p_world, view);
#endif
#if VARIANT_LIGHTS > 1
    sum = add_light(sum, 1u, c, n, tint, cue, p_world, view);
#endif
#if VARIANT_LIGHTS > 2
    sum = add_light(sum, 2u, c, n, tint, cue, p_world, view);
#endif
#if VARIANT_LIGHTS > 3
    sum = add_light(sum, 3u, c, n, tint, cue, p_world, view);
#endif
    let emission = c * params.ke;
    let ambient = c * (params.global_ambient * params.ka);
    return clamp(emission + ambient + sum.ambient + sum.diffuse + sum.specular, vec3(0.0), vec3(1.0));
}

/// A sample's light from the scene's lights so far: their ambient, diffuse and specular terms.
struct LightShare {
    ambient: vec3<f32>,
    diffuse: vec3<f32>,
    specular: vec3<f32>,
}

/// `sum` with light i's share added (the core's loop over the lights, one light at a time): for
/// colour c, unit normal n, specular tint, depth cue, at p_world seen along view.
fn add_light(sum: LightShare, i: u32, c: vec3<f32>, n: vec3<f32>, tint: vec3<f32>, cue: f32, p_world: vec3<f32>, view: vec3<f32>) -> LightShare {
    let light = params.lights[i];
    var l = light.at;
    var attenuation = 1.0;
    if light.kind != #{LIGHT_TOWARD}u {
        let to = light.at - p_world;
        let d = length(to);
        let denom = light.kc + light.kl * d + light.kq * d * d;
        attenuation = select(1.0, 1.0 / denom, denom > 0.0);
        l = select(view, to / d, d > 0.0);
    }
    if (FLAGS & #{FLAG_DEPTH_CUE}u) != 0u {
        attenuation = cue;
    }
    var spot = 1.0;
    if light.kind == #{LIGHT_SPOT}u {
        spot = spot_factor(i, l);
    }
    let fs = attenuation * spot;
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
    return LightShare(
        sum.ambient + c * (light.ambient * (fs * params.ka)),
        sum.diffuse + c * (light.color * (fs * params.kd * lambert)),
        sum.specular + tint * light.color * (fs * params.ks * spec),
    );
}
