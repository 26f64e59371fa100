//! Every equation the breakdown prints adds up from its own printed numbers: for every method,
//! both compositing orders, with and without shading, on every sample of many rays.

mod common;

use common::{field, trace};
use voxcast_core::composite::{Method, Order};
use voxcast_core::explain::formula;
use voxcast_core::glam::Vec3;
use voxcast_core::recompute::check_equations;
use voxcast_core::settings::RenderSettings;
use voxcast_core::step::Length;
use voxcast_core::transfer::{ControlPoint, TransferFunction};

fn blobs() -> voxcast_core::Prepared {
    field([9, 8, 7], Vec3::new(1.0, 1.2, 0.9), |p| {
        let d = (p - Vec3::new(4.0, 3.5, 3.0)).length();
        200.0 * (-d * d / 8.0).exp() + 5.0 * p.x
    })
}

fn coloured() -> TransferFunction {
    TransferFunction::new(
        "test",
        vec![
            ControlPoint::new(0.0, [0.1, 0.0, 0.3], 0.0),
            ControlPoint::new(60.0, [0.9, 0.4, 0.1], 0.15),
            ControlPoint::new(220.0, [1.0, 1.0, 0.8], 0.7),
        ],
    )
    .unwrap()
}

#[test]
fn every_printed_equation_adds_up() {
    let volume = blobs();
    let tf = coloured();
    let mut checked = 0;
    for method in Method::ALL {
        for order in [Order::FrontToBack, Order::BackToFront] {
            for shading in [false, true] {
                let settings = RenderSettings {
                    method,
                    order,
                    shading,
                    step: Length::Voxels(0.7),
                    target: Some(120.0),
                    background: Vec3::new(0.2, 0.3, 0.4),
                    ..RenderSettings::default()
                };
                for (i, dir) in [
                    Vec3::new(1.0, 0.1, 0.05),
                    Vec3::new(0.3, 1.0, 0.2),
                    Vec3::new(0.2, 0.3, -1.0),
                    Vec3::new(-1.0, -0.4, 0.3),
                ]
                .into_iter()
                .enumerate()
                {
                    let dir = dir.normalize();
                    let origin =
                        Vec3::new(4.0, 4.2, 2.7) - dir * 20.0 + Vec3::splat(i as f32 * 0.3);
                    let t = trace(&volume, &tf, &settings, origin, dir);
                    let minimum = match method {
                        Method::Accumulate => 3,                                  // C, O, the pixel
                        Method::Sum => 3, // S, the table value, the pixel
                        Method::Average | Method::Maximum | Method::Minimum => 2, // mean, pixel
                        Method::First => 1, // the pixel
                    };
                    for k in (0..t.samples.len()).map(Some).chain([None]) {
                        let text = formula(&t, k);
                        match check_equations(&text) {
                            Ok(n) => {
                                assert!(
                                    t.samples.is_empty() || n >= minimum,
                                    "{method:?} {order:?}: only {n} equations in\n{text}"
                                );
                                checked += n;
                            }
                            Err(m) => panic!(
                                "{method:?} {order:?} shading {shading}, sample {k:?}: {} ({})\n{text}",
                                m.line, m.why
                            ),
                        }
                    }
                }
            }
        }
    }
    assert!(checked > 500, "only {checked} equations checked");
}

/// Back to front prints Levoy's update, not the front-to-back one.
#[test]
fn the_formula_follows_the_order() {
    let volume = blobs();
    let tf = coloured();
    let dir = Vec3::X;
    let origin = Vec3::new(-5.0, 3.5, 3.0);
    for (order, rule) in [
        (Order::FrontToBack, "C_(k−1) + (1 − O_(k−1))·α_k·c_k"),
        (Order::BackToFront, "C_(k−1)·(1 − α_k) + α_k·c_k"),
    ] {
        let settings = RenderSettings {
            order,
            early_termination: false,
            ..RenderSettings::default()
        };
        let t = trace(&volume, &tf, &settings, origin, dir);
        assert_eq!(t.order, order);
        let text = formula(&t, Some(t.samples.len() / 2));
        assert!(text.contains(rule), "{order:?}: {text}");
    }
}

/// Every shading equation the breakdown prints adds up from its printed numbers: the shortened
/// form, the lecture's full model (emission, global ambient, the lights' own ambient, a point
/// and a spot light with falloff) and Levoy's depth cue, on every shaded sample of several rays.
#[test]
fn every_printed_shading_equation_adds_up() {
    use voxcast_core::shade::{Light, LightSource, Phong, Spot};
    let volume = blobs();
    let tf = coloured();
    let spot_at = Vec3::new(4.0, 12.0, 14.0);
    let full = Phong {
        ke: 0.1,
        global_ambient: 0.7,
        lights: vec![
            LightSource {
                ambient: 0.3,
                ..LightSource::new(Light::Headlight)
            },
            LightSource {
                ambient: 0.2,
                kl: 0.05,
                kq: 0.002,
                color: Vec3::new(1.0, 0.6, 0.3),
                ..LightSource::new(Light::Point(Vec3::new(-6.0, 3.0, 9.0)))
            },
            LightSource {
                ambient: 0.5,
                kl: 0.02,
                ..LightSource::new(Light::Spot(Spot {
                    position: spot_at,
                    direction: Vec3::new(4.0, 3.5, 3.0) - spot_at,
                    cutoff: 20.0,
                    exponent: 3.0,
                }))
            },
        ],
        ..Phong::default()
    };
    let cued = Phong {
        depth_cue: true,
        depth_kc: 0.8,
        depth_kl: 0.04,
        highlight: voxcast_core::shade::Highlight::Levoy,
        ..full.clone()
    };
    let (mut checked, mut forms) = (0, [0usize; 2]);
    for phong in [Phong::default(), full, cued] {
        let settings = RenderSettings {
            shading: true,
            step: Length::Voxels(0.7),
            phong,
            ..RenderSettings::default()
        };
        for dir in [
            Vec3::new(1.0, 0.1, 0.05),
            Vec3::new(0.3, 1.0, 0.2),
            Vec3::new(0.2, 0.3, -1.0),
        ] {
            let dir = dir.normalize();
            let t = trace(
                &volume,
                &tf,
                &settings,
                Vec3::new(4.0, 4.2, 2.7) - dir * 20.0,
                dir,
            );
            for s in &t.samples {
                let Some(terms) = &s.shading else { continue };
                let [r, g, b, _] = s.tf_rgba;
                let text = voxcast_core::explain::shading(terms, [r, g, b], s.color);
                forms[terms.full_form() as usize] += 1;
                match check_equations(&text) {
                    Ok(n) => checked += n,
                    Err(m) => panic!("{} ({})\n{text}", m.line, m.why),
                }
                if terms.lit {
                    let said = |w: &str| text.contains(w);
                    assert_eq!(
                        said("the lecture's full model"),
                        terms.full_form(),
                        "{text}"
                    );
                    assert_eq!(said("depth cue"), terms.depth_cue, "{text}");
                    assert_eq!(
                        said("spotlight factor"),
                        terms.per_light().iter().any(|l| l.spotlight)
                    );
                }
            }
        }
    }
    assert!(
        forms[0] > 10 && forms[1] > 20,
        "samples per form: {forms:?}"
    );
    assert!(checked > 300, "only {checked} equations checked");
}
