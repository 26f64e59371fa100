// The preview's fragment shader: one ray per pixel of the volume's box, traced by `trace`.
// Twin: crates/voxcast_core/src/render.rs (the image renderer) and the camera's rays
// (camera.rs), with `Camera::ray` as `trace_sub_pixel`: origin at the eye (perspective) or on
// the eye's plane (orthographic). GPU-only: `fragment` (the shader's entry point, one pixel)
// and `srgb_to_linear` (the preview draws into an sRGB target; the CPU writes its display
// values as they are, see below).
//
// The box is drawn back faces only, so the camera may be inside it. With the depth prepass the
// ray stops at opaque scene geometry (prepass depth 0 means nothing was drawn there).
//
// Colour: the ray caster's values are display values (the CPU writes them to PNG as they are,
// as VTK does). The preview draws into an sRGB target, which encodes linear output; so the
// shader outputs, premultiplied, L(C + (1 − O)·bg) − (1 − O)·L(bg), with L the sRGB decoding:
// blended over a clear colour of bg this stores exactly the CPU's C + (1 − O)·bg.
#import bevy_pbr::forward_io::VertexOutput
#import bevy_pbr::view_transformations::{frag_coord_to_ndc, position_ndc_to_world}
#ifdef DEPTH_PREPASS
#import bevy_pbr::prepass_utils
#endif
#import voxcast::bindings::params
#import voxcast::trace::trace
#import voxcast::composite::blend_background

/// sRGB decoding of a display value in [0, 1].
fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    let lo = c / 12.92;
    let hi = pow((c + 0.055) / 1.055, vec3(2.4));
    return select(hi, lo, c <= vec3(0.04045));
}

@fragment
fn fragment(mesh: VertexOutput) -> @location(0) vec4<f32> {
    // The pixel, counted in the whole target: the camera's viewport may be a strip of it (the
    // sandbox's progressive pass, which draws the resting view a few rows a frame).
    let px = vec2<u32>(mesh.position.xy);
    let ndc = frag_coord_to_ndc(mesh.position).xy;
    // n×n rays on a regular grid inside the pixel, as render.rs casts them (n = 1: the centre),
    // each keyed for jitter by its sub-pixel; their premultiplied colour and opacity averaged.
    let n = max(params.supersampling, 1u);
    var sum = vec4(0.0);
    for (var sy = 0u; sy < n; sy++) {
        for (var sx = 0u; sx < n; sx++) {
            let sub = (vec2<f32>(f32(sx), f32(sy)) + 0.5) / f32(n);
            sum += trace_sub_pixel(vec2<f32>(px) + sub, ndc, mesh.position, px * n + vec2(sx, sy));
        }
    }
    let acc = sum / f32(n * n);
    let shown = blend_background(acc, params.background);
    let rgb = srgb_to_linear(clamp(shown, vec3(0.0), vec3(1.0))) - (1.0 - acc.a) * srgb_to_linear(params.background);
    return vec4(max(rgb, vec3(0.0)), acc.a);
}

/// The camera's ray through image position `pixel` (computed as camera.rs computes it),
/// stopped at the scene's geometry where the depth prepass drew some, traced.
fn trace_sub_pixel(pixel: vec2<f32>, ndc: vec2<f32>, frag: vec4<f32>, key: vec2<u32>) -> vec4<f32> {
    let ndc_x = 2.0 * pixel.x * params.cam_inv_width - 1.0;
    let ndc_y = 1.0 - 2.0 * pixel.y * params.cam_inv_height;
    let offset = params.cam_right * ndc_x + params.cam_up * ndc_y;
    var origin = params.cam_eye;
    var dir = params.cam_forward;
    if params.cam_perspective != 0u {
        dir = normalize(params.cam_forward + offset);
    } else {
        origin = params.cam_eye + offset;
    }
    var t_max = 3.4e38;
#ifdef DEPTH_PREPASS
    if params.depth_termination != 0u {
        let depth = prepass_utils::prepass_depth(frag, 0u);
        if depth > 0.0 {
            t_max = dot(position_ndc_to_world(vec3(ndc, depth)) - origin, dir);
        }
    }
#endif
    return trace(origin, dir, t_max, key);
}
