//! Shading's tests: the lecture's terms in closed form, lights of every kind, the full model
//! against the shortened one, Levoy's highlight and depth cue.

use super::*;

fn k() -> Phong {
    Phong {
        ka: 0.1,
        kd: 0.6,
        ks: 0.3,
        shininess: 8.0,
        ..Phong::default()
    }
}

#[test]
fn facing_light_and_viewer_gives_the_sum_of_terms() {
    // Gradient pointing into the surface (−z), so the normal is +z, towards light and viewer.
    let (c, t) = shade(
        Vec3::splat(0.5),
        Vec3::new(0.0, 0.0, -3.0),
        Vec3::ZERO,
        &Viewing::new(
            Vec3::Z,
            &ResolvedLights::one(ResolvedLight::Toward(Vec3::Z)),
        ),
        &k(),
    );
    assert!(t.lit);
    assert!(
        (c - Vec3::splat(0.1 * 0.5 + 0.6 * 0.5 + 0.3))
            .abs()
            .max_element()
            < 1e-6
    );
}

#[test]
fn flat_regions_keep_their_colour_without_nan() {
    let (c, t) = shade(
        Vec3::new(0.2, 0.4, 0.6),
        Vec3::ZERO,
        Vec3::ZERO,
        &Viewing::new(
            Vec3::Z,
            &ResolvedLights::one(ResolvedLight::Toward(Vec3::Z)),
        ),
        &k(),
    );
    assert_eq!(c, Vec3::new(0.2, 0.4, 0.6));
    assert!(!t.lit);
    let (c, _) = shade(
        Vec3::ONE,
        Vec3::splat(f32::INFINITY),
        Vec3::ZERO,
        &Viewing::new(
            Vec3::Z,
            &ResolvedLights::one(ResolvedLight::Toward(Vec3::Z)),
        ),
        &k(),
    );
    assert!(c.is_finite());
}

#[test]
fn two_sided_flips_back_faces() {
    let grad = Vec3::new(0.0, 0.0, 1.0); // normal −z, away from the viewer at +z
    let mut one = k();
    one.two_sided = false;
    let (c1, _) = shade(
        Vec3::ONE,
        grad,
        Vec3::ZERO,
        &Viewing::new(
            Vec3::Z,
            &ResolvedLights::one(ResolvedLight::Toward(Vec3::Z)),
        ),
        &one,
    );
    assert!(
        (c1 - Vec3::splat(0.1)).abs().max_element() < 1e-6,
        "ambient only"
    );
    let (c2, _) = shade(
        Vec3::ONE,
        grad,
        Vec3::ZERO,
        &Viewing::new(
            Vec3::Z,
            &ResolvedLights::one(ResolvedLight::Toward(Vec3::Z)),
        ),
        &k(),
    );
    assert!(c2.x > 0.9);
}

/// The lights of `p` resolved for a viewer looking along −z.
fn lights(p: &Phong) -> ResolvedLights {
    p.resolve(Vec3::NEG_Z)
}

#[test]
fn point_light_attenuates() {
    let mut p = k();
    p.lights = vec![LightSource {
        light: Light::Point(Vec3::new(0.0, 0.0, 2.0)),
        kc: 1.0,
        kl: 0.5,
        kq: 0.25,
        ..LightSource::default()
    }];
    let (_, t) = shade(
        Vec3::ONE,
        Vec3::NEG_Z,
        Vec3::ZERO,
        &Viewing::new(Vec3::Z, &lights(&p)),
        &p,
    );
    assert!((t.lights[0].attenuation - 1.0 / (1.0 + 1.0 + 1.0)).abs() < 1e-6);
}

#[test]
fn lights_add_up_each_with_its_colour() {
    // The normal is +z; a red headlight from the viewer's side and a blue light from +x at
    // 60° to the normal: diffuse is kd·c·(red·1 + blue·cos 60°), the highlights add too.
    let mut p = k();
    p.ks = 0.0;
    let oblique = Vec3::new(
        -(60f32.to_radians().sin()),
        0.0,
        -(60f32.to_radians().cos()),
    );
    p.lights = vec![
        LightSource {
            color: Vec3::X,
            ..LightSource::new(Light::Headlight)
        },
        LightSource {
            color: Vec3::Z,
            ..LightSource::new(Light::Directional(oblique))
        },
    ];
    let c = Vec3::splat(0.5);
    let (out, t) = shade(
        c,
        Vec3::NEG_Z,
        Vec3::ZERO,
        &Viewing::new(Vec3::Z, &lights(&p)),
        &p,
    );
    let want = c * 0.1 + c * 0.6 * (Vec3::X + Vec3::Z * 0.5);
    assert!((out - want).abs().max_element() < 1e-6, "{out} vs {want}");
    assert_eq!(t.per_light().len(), 2);
    assert!((t.lights[1].n_dot_l - 0.5).abs() < 1e-6);
    let sum: Vec3 = t
        .per_light()
        .iter()
        .map(|l| Vec3::from_array(l.diffuse))
        .sum();
    assert!((sum - Vec3::from_array(t.diffuse)).abs().max_element() < 1e-7);
}

#[test]
fn no_light_leaves_the_ambient_term() {
    let mut p = k();
    p.lights.clear();
    let c = Vec3::new(0.2, 0.4, 0.6);
    let (out, t) = shade(
        c,
        Vec3::NEG_Z,
        Vec3::ZERO,
        &Viewing::new(Vec3::Z, &lights(&p)),
        &p,
    );
    assert!((out - c * 0.1).abs().max_element() < 1e-7);
    assert!(t.lit && t.per_light().is_empty());
}

#[test]
fn levoys_highlight_takes_the_samples_colour() {
    // At the mirror direction spec = 1: the white highlight adds ks to every channel,
    // Levoy's adds ks·c.
    let c = Vec3::new(0.8, 0.1, 0.0);
    let mut p = k();
    p.kd = 0.0;
    p.ka = 0.0;
    let white = shade(
        c,
        Vec3::NEG_Z,
        Vec3::ZERO,
        &Viewing::new(Vec3::Z, &lights(&p)),
        &p,
    )
    .0;
    p.highlight = Highlight::Levoy;
    let levoy = shade(
        c,
        Vec3::NEG_Z,
        Vec3::ZERO,
        &Viewing::new(Vec3::Z, &lights(&p)),
        &p,
    )
    .0;
    assert!(
        (white - Vec3::splat(0.3)).abs().max_element() < 1e-6,
        "{white}"
    );
    assert!((levoy - c * 0.3).abs().max_element() < 1e-6, "{levoy}");
    let terms = shade(
        c,
        Vec3::NEG_Z,
        Vec3::ZERO,
        &Viewing::new(Vec3::Z, &lights(&p)),
        &p,
    )
    .1;
    assert_eq!(terms.tint, c.to_array(), "the breakdown shows h");
}

/// The lecture's full model by hand: M_e + G_a·M_a + f·s·[I_a·M_a + I·M_d·N·L + I·M_s·spec]
/// for a spot light straight above a surface facing it, 20° off the spot's axis.
#[test]
fn the_full_model_adds_emission_global_and_light_ambient_and_the_spot_factor() {
    let off = 20f32.to_radians();
    // The sample at the origin, normal +z; the light 5 up, its axis tilted 20° from −z.
    let spot = Spot {
        position: Vec3::new(0.0, 0.0, 5.0),
        direction: Vec3::new(off.sin(), 0.0, -off.cos()),
        cutoff: 30.0,
        exponent: 2.0,
    };
    let p = Phong {
        ke: 0.1,
        global_ambient: 0.5,
        ka: 0.2,
        kd: 0.6,
        ks: 0.3,
        shininess: 4.0,
        lights: vec![LightSource {
            color: Vec3::new(1.0, 0.5, 0.25),
            ambient: 0.4,
            kc: 1.0,
            kl: 0.1,
            kq: 0.0,
            light: Light::Spot(spot),
        }],
        ..Phong::default()
    };
    assert!(p.full_form());
    let c = Vec3::new(0.4, 0.3, 0.2);
    let resolved = lights(&p);
    let (out, t) = shade(
        c,
        Vec3::NEG_Z,
        Vec3::ZERO,
        &Viewing::new(Vec3::Z, &resolved),
        &p,
    );
    let f = 1.0 / (1.0 + 0.1 * 5.0);
    let s = off.cos().powi(2);
    let i = Vec3::new(1.0, 0.5, 0.25);
    // N·L = 1 and N·H = 1 (light and viewer straight above): spec = 1.
    let want = c * 0.1 + c * (0.5 * 0.2) + f * s * (i * 0.4 * 0.2 * c + i * 0.6 * c + i * 0.3);
    assert!((out - want).abs().max_element() < 1e-6, "{out} vs {want}");
    let l = t.per_light()[0];
    assert!((l.spot - s).abs() < 1e-6 && (l.attenuation - f).abs() < 1e-6);
    assert!(t.full_form());
    // Outside the cone only the global terms are left.
    let narrow = Phong {
        lights: vec![LightSource {
            light: Light::Spot(Spot {
                cutoff: 10.0,
                ..spot
            }),
            ..p.lights[0]
        }],
        ..p.clone()
    };
    let resolved = lights(&narrow);
    let (dark, _) = shade(
        c,
        Vec3::NEG_Z,
        Vec3::ZERO,
        &Viewing::new(Vec3::Z, &resolved),
        &narrow,
    );
    assert!(
        (dark - (c * 0.1 + c * 0.1)).abs().max_element() < 1e-7,
        "{dark}"
    );
}

/// Levoy's depth cue: f = 1/(k1 + k2·d) with d the distance from the picture plane, for
/// every light (a point light's own falloff is replaced), not the distance to the light.
#[test]
fn the_depth_cue_dims_with_distance_from_the_picture_plane() {
    let mut p = k();
    p.ks = 0.0;
    p.depth_cue = true;
    p.depth_kc = 1.0;
    p.depth_kl = 0.05;
    p.lights = vec![LightSource {
        kl: 3.0,
        ..LightSource::new(Light::Point(Vec3::new(0.0, 0.0, 100.0)))
    }];
    // The camera looks along −z from z = 50 (its picture plane is z = 50).
    let resolved = p.resolve(Vec3::NEG_Z);
    let eye = Vec3::new(7.0, -3.0, 50.0);
    let v = Viewing::from_origin(eye, Vec3::Z, &resolved);
    let c = Vec3::splat(0.5);
    for z in [40.0f32, 10.0, -20.0] {
        let at = Vec3::new(1.0, 2.0, z);
        let (out, t) = shade(c, Vec3::NEG_Z, at, &v, &p);
        let d = 50.0 - z;
        let f = 1.0 / (1.0 + 0.05 * d);
        let n_dot_l = (Vec3::new(0.0, 0.0, 100.0) - at).normalize().z;
        let want = c * 0.1 + c * (0.6 * f * n_dot_l);
        assert!(
            (out - want).abs().max_element() < 1e-6,
            "z {z}: {out} vs {want}"
        );
        assert!((t.per_light()[0].distance - d).abs() < 1e-4);
    }
    // Off: the point light's own falloff at its distance.
    p.depth_cue = false;
    let (_, t) = shade(c, Vec3::NEG_Z, Vec3::ZERO, &v, &p);
    assert!((t.per_light()[0].attenuation - 1.0 / (1.0 + 3.0 * 100.0)).abs() < 1e-7);
}

/// The defaults are the shortened form: no term of the full model is on, and a sample's
/// colour is ka·c + Σ f·I·(kd·N·L·c + ks·spec·h) to the last bit.
#[test]
fn the_defaults_are_the_shortened_form_bit_for_bit() {
    let p = Phong::default();
    assert!(!p.full_form());
    let resolved = lights(&p);
    let view = Vec3::new(0.2, 0.3, 0.9).normalize();
    let v = Viewing::new(view, &resolved);
    let c = Vec3::new(0.7, 0.35, 0.1);
    let grad = Vec3::new(-0.3, -0.2, -1.0);
    let (out, t) = shade(c, grad, Vec3::ZERO, &v, &p);
    let n = -grad.normalize();
    let l = Vec3::Z;
    let spec = power(n.dot(v.half(0).unwrap()).max(0.0), p.shininess);
    let short = c * p.ka
        + c * (Vec3::ONE * (1.0 * p.kd * n.dot(l).max(0.0)))
        + Vec3::ONE * Vec3::ONE * (1.0 * p.ks * spec);
    assert_eq!(out, short.clamp(Vec3::ZERO, Vec3::ONE));
    assert!(!t.full_form());
}

#[test]
fn adding_lights_stops_at_the_most_the_gpu_holds() {
    let mut p = k();
    while p.add_light() {}
    assert_eq!(p.lights.len(), MAX_LIGHTS);
    let places: Vec<Light> = p.lights.iter().map(|l| l.light).collect();
    for (i, a) in places.iter().enumerate() {
        assert!(
            !places[i + 1..].contains(a),
            "each added light from its own side"
        );
    }
}

#[test]
fn no_more_lights_than_the_gpu_holds_are_resolved() {
    let mut p = k();
    p.lights = vec![LightSource::default(); MAX_LIGHTS + 2];
    assert_eq!(lights(&p).as_slice().len(), MAX_LIGHTS);
}

#[test]
fn power_matches_powf() {
    for (x, n) in [
        (0.5f32, 10.0f32),
        (0.99, 128.0),
        (0.0, 3.0),
        (1.0, 7.0),
        (0.3, 2.5),
    ] {
        let (a, b) = (power(x, n), x.powf(n));
        assert!((a - b).abs() <= 1e-5 * b.max(1e-30), "{x}^{n}: {a} vs {b}");
    }
}

/// Repeated squaring exactly for whole exponents in 0..=1024 (±0 included), `powf`
/// elsewhere — fractions, negatives, above 1024, beyond `u32`, NaN.
#[test]
fn power_squares_exactly_where_the_exponent_is_whole_and_small() {
    let squared = |x: f32, n: u32| {
        let (mut base, mut e, mut acc) = (x, n, 1.0f32);
        while e > 0 {
            if e & 1 == 1 {
                acc *= base;
            }
            base *= base;
            e >>= 1;
        }
        acc
    };
    for x in [0.0f32, 0.3, 0.75, 0.999, 1.0] {
        for n in [0u32, 1, 2, 3, 13, 64, 1023, 1024] {
            assert_eq!(
                power(x, n as f32).to_bits(),
                squared(x, n).to_bits(),
                "{x}^{n}"
            );
        }
        assert_eq!(power(x, -0.0), 1.0);
        for n in [0.5f32, 2.5, 1024.5, 1025.0, -2.0, 5e9, f32::INFINITY] {
            assert_eq!(power(x, n).to_bits(), x.powf(n).to_bits(), "{x}^{n}");
        }
        assert!(power(x, f32::NAN).is_nan() || x == 1.0);
    }
}

#[test]
fn phong_and_blinn_agree_at_the_mirror_direction() {
    let mut p = k();
    for model in [SpecularModel::Phong, SpecularModel::BlinnPhong] {
        p.model = model;
        let (_, t) = shade(
            Vec3::ZERO,
            Vec3::NEG_Z,
            Vec3::ZERO,
            &Viewing::new(
                Vec3::Z,
                &ResolvedLights::one(ResolvedLight::Toward(Vec3::Z)),
            ),
            &p,
        );
        assert!((t.specular[0] - 0.3).abs() < 1e-6, "{model:?}");
    }
}
