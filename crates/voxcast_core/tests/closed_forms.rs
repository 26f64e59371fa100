//! Closed forms the ray caster must reproduce: Beer–Lambert for constant density, maximum,
//! minimum and average of a linear ramp, First hit on a sphere, and the lecture's worked example.

mod common;

use common::*;
use voxcast_core::composite::{Method, Order};
use voxcast_core::glam::Vec3;
use voxcast_core::step::Length;
use voxcast_core::trace::StopReason;

/// Constant density with a constant transfer function: with opacity correction the ray's
/// opacity is 1 − (1 − α)^(L/Δs_ref) = 1 − e^(−σL) whatever the step; without it, 1 − (1 − α)^N.
#[test]
fn constant_density_is_beer_lambert_for_any_step() {
    let v = constant([16, 16, 16], 1.0);
    let alpha = 0.1f32;
    let sigma = -(1.0 - alpha as f64).ln(); // per reference step (1 voxel = 1 world unit)
    let rays = [
        (Vec3::new(-3.0, 7.5, 7.5), Vec3::X),
        (Vec3::new(7.3, 20.0, 6.1), Vec3::NEG_Y),
        (Vec3::new(-5.0, -4.0, -3.0), Vec3::new(1.0, 0.9, 0.8)),
    ];
    for (origin, dir) in rays {
        for dt in [1.0f32, 0.7, 0.33, 2.5, 0.01, 15.0, 100.0] {
            let mut s = plain(dt);
            s.opacity_correction = true;
            let t = trace(&v, &white(alpha), &s, origin, dir);
            let [a, b] = t.interval.unwrap();
            let expect = 1.0 - (-sigma * (b - a) as f64).exp();
            // f32 compositing loses about one rounding per sample.
            let tol = 2e-5 + 3e-8 * t.samples.len() as f32;
            close(
                t.opacity,
                expect as f32,
                tol,
                &format!("corrected, dt {dt}, dir {dir}"),
            );
            // Colour 1 everywhere: premultiplied colour equals opacity.
            close(t.color[0], t.opacity, 1e-5, "C = O for white");

            s.opacity_correction = false;
            let t = trace(&v, &white(alpha), &s, origin, dir);
            let n = t.samples.len() as i32;
            let expect = 1.0 - (1.0 - alpha as f64).powi(n);
            close(
                t.opacity,
                expect as f32,
                2e-5 + 3e-8 * n as f32,
                &format!("uncorrected, dt {dt}, {n} samples"),
            );
        }
    }
}

/// With the reference step equal to the step and correction off, Beer–Lambert holds at the
/// sample positions: the two settings agree when the span is a whole number of steps.
#[test]
fn correction_is_identity_at_the_reference_step() {
    let v = constant([9, 9, 9], 1.0);
    let mut s = plain(0.5);
    s.reference_step = Length::Voxels(0.5);
    // Along +x through the box [0, 8]: 17 samples, the first and last standing for half a step.
    let on = trace(&v, &white(0.2), &s, Vec3::new(-1.0, 4.0, 4.0), Vec3::X);
    close(
        on.opacity,
        1.0 - 0.8f32.powi(16),
        1e-5,
        "16 reference steps of path",
    );
}

/// Maximum, minimum and average of the ramp f = x along oblique rays, against the sample
/// positions' closed forms.
#[test]
fn projections_of_a_linear_ramp() {
    let v = field([33, 9, 9], Vec3::ONE, |p| p.x);
    let tf = grey(0.0, 32.0, 1.0);
    for (dt, dir) in [
        (0.5f32, Vec3::new(1.0, 0.1, 0.05)),
        (0.37, Vec3::new(1.0, -0.2, 0.1)),
        (1.3, Vec3::X),
    ] {
        let origin = Vec3::new(-2.0, 4.0, 4.0);
        let mut s = plain(dt);
        s.method = Method::Maximum;
        let t = trace(&v, &tf, &s, origin, dir);
        let plan = t.plan.unwrap();
        let d = dir.normalize();
        let x_at = |k: u32| origin.x + d.x * (plan.t_enter + k as f32 * plan.dt);
        let last = x_at(plan.count - 1);
        close(
            t.projected_value.unwrap(),
            last,
            1e-4,
            "maximum is at the last sample",
        );
        close(
            t.pixel[0],
            last / 32.0,
            1e-3,
            "maximum through the grey ramp",
        );

        s.method = Method::Minimum;
        let t = trace(&v, &tf, &s, origin, dir);
        close(
            t.projected_value.unwrap(),
            x_at(0),
            1e-4,
            "minimum is at the entry",
        );

        s.method = Method::Average;
        let t = trace(&v, &tf, &s, origin, dir);
        let mean = (x_at(0) + last) / 2.0; // arithmetic series
        close(
            t.projected_value.unwrap(),
            mean,
            1e-3,
            "average of equally spaced samples",
        );
        assert_eq!(t.samples.len() as u32, plan.count);
    }
}

/// First on the field f = R − |p − c|: along the axes through the centre the field is linear
/// between lattice points, so the hit lies on the sphere exactly; in any direction the hit lies
/// on the reconstructed surface within 1e-3 voxel, and on the true sphere within the bound of
/// trilinear reconstruction (3/(8R) for this field).
#[test]
fn first_hit_finds_the_sphere() {
    let c = Vec3::splat(32.0);
    let r = 20.0f32;
    let v = field([65, 65, 65], Vec3::ONE, |p| r - (p - c).length());
    let tf = white(1.0);
    for dt in [1.0f32, 0.7, 0.25, 2.0] {
        let mut s = plain(dt);
        s.method = Method::First;
        s.target = Some(0.0);
        for dir in AXES {
            let t = trace(&v, &tf, &s, c - dir * 40.0, dir);
            assert_eq!(t.stop, StopReason::FirstHit);
            let hit = Vec3::from(t.first_hit.unwrap().p_world);
            close(
                (hit - c).length(),
                r,
                1e-3,
                &format!("axis hit, dt {dt}, {dir}"),
            );
        }
        for i in 0..40 {
            let a = i as f32 * 0.7;
            let dir = Vec3::new(
                a.cos() * (a * 0.3).sin(),
                (a * 0.3).cos(),
                a.sin() * (a * 0.3).sin(),
            );
            let t = trace(&v, &tf, &s, c - dir * 40.0, dir);
            let h = t.first_hit.expect("every ray through the centre hits");
            assert!(
                h.value.abs() <= 1e-3,
                "on the reconstructed surface: f = {}",
                h.value
            );
            let dist = (Vec3::from(h.p_world) - c).length();
            close(dist, r, 3.0 / (8.0 * r) + 1e-3, "near the true sphere");
            // The hit colour is the transfer function at the target, fully opaque.
            close(t.opacity, 1.0, 0.0, "opaque surface");
        }
    }
}

/// Seed 003's "first voxel of value at or above the given value": a ray whose first sample is
/// already at or above the target hits there, where it enters the volume — on a volume wholly
/// above the target, on the inside of the sphere field, and at the target exactly — while a ray
/// that never reaches the target leaves the volume and shows the background.
#[test]
fn first_hits_at_the_entry_when_the_ray_starts_at_or_above_the_target() {
    let tf = white(1.0);
    let mut s = plain(0.5);
    s.method = Method::First;
    s.background = Vec3::new(0.2, 0.3, 0.4);
    let above = constant([8, 8, 8], 5.0);
    for target in [5.0f32, 2.0, -1e6] {
        s.target = Some(target);
        for (origin, dir) in [
            (Vec3::new(-3.0, 3.5, 3.5), Vec3::X),
            (Vec3::new(3.2, 10.0, 2.7), Vec3::NEG_Y),
            (Vec3::new(-2.0, -1.0, -3.0), Vec3::new(1.0, 0.7, 0.9)),
        ] {
            let t = trace(&above, &tf, &s, origin, dir);
            assert_eq!(t.stop, StopReason::FirstHit, "target {target}, {dir}");
            let first = &t.samples[0];
            let h = t.first_hit.as_ref().unwrap();
            assert_eq!(h.t, first.t, "hit at the first sample, target {target}");
            assert_eq!(h.bracket, [first.t, first.t]);
            let [t_in, _] = t.interval.unwrap();
            assert!(h.t - t_in <= 0.5 * 1.0001, "within a step of the entry");
            close(t.opacity, 1.0, 0.0, "the target's colour, opaque");
            assert_eq!(t.pixel, [1.0; 3]);
        }
    }
    // Nothing reaches 6: every ray leaves the volume and the pixel is the background.
    s.target = Some(6.0);
    let t = trace(&above, &tf, &s, Vec3::new(-3.0, 3.5, 3.5), Vec3::X);
    assert_eq!(t.stop, StopReason::LeftVolume);
    assert!(t.first_hit.is_none());
    assert_eq!(t.pixel, s.background.to_array());
    // A ray starting inside the sphere field's high core hits at once, not where it later
    // falls below the target on its way out.
    let c = Vec3::splat(16.0);
    let sphere = field([33, 33, 33], Vec3::ONE, |p| 10.0 - (p - c).length());
    s.target = Some(0.0);
    let t = trace(&sphere, &tf, &s, c, Vec3::X);
    let h = t.first_hit.expect("the centre is above the target");
    assert_eq!(h.t, t.samples[0].t);
    close(
        Vec3::from(h.p_world).distance(c),
        0.0,
        0.5,
        "hit at the start",
    );
}

/// The head phantom's isovalues: along the axes, First stops on the scalp below the scalp's
/// level, on the skull between the scalp's and the bone's, and nowhere above the bone's (the
/// ellipsoids' surfaces, within the phantom's one-voxel soft edge).
#[test]
fn the_head_phantoms_isovalue_picks_skin_or_skull() {
    use voxcast_core::builtin::{HEAD_BONE, HEAD_SCALP, HEAD_SKIN, HEAD_SKULL, head};
    let v = voxcast_core::Prepared::from(head());
    let tf = white(1.0);
    let half = 31.5f32;
    let c = Vec3::splat(half);
    for (axis, dir) in [(2, Vec3::NEG_Z), (0, Vec3::X), (1, Vec3::NEG_Y)] {
        for (target, surface) in [
            (0.5 * HEAD_SKIN, Some(HEAD_SCALP[axis])),
            (0.5 * (HEAD_SKIN + HEAD_BONE), Some(HEAD_SKULL[axis])),
            (HEAD_BONE + 10.0, None),
        ] {
            let mut s = plain(0.5);
            s.method = Method::First;
            s.target = Some(target);
            let t = trace(&v, &tf, &s, c - dir * 60.0, dir);
            match surface {
                Some(f) => {
                    let hit = Vec3::from(t.first_hit.expect("a hit").p_world);
                    close(
                        (hit - c).length(),
                        f * half,
                        1.0,
                        &format!("{dir}, {target}"),
                    );
                }
                None => assert!(t.first_hit.is_none(), "{dir}, {target}"),
            }
        }
    }
}

/// The lecture's worked example, read one way everywhere: one unit voxel with corner values
/// f1..f8, a ray sampled at P1(0.2,0.3,0.8), P2(0.5,0.5,0.5), P3(0.8,0.7,0.2). The ray's colour
/// is (0,0,0,0) "before it hits P1" and asked "after it leaves P3", composited back to front:
/// P1 is the far end and the eye looks from beyond P3 towards it. The lecture gives no transfer
/// function; with the trilinear level's ramp (the `voxel` preset) that gives C = (0.540, 0.397,
/// 0.375), O = 0.813 — the numbers the trilinear level and the breakdown show; the opposite
/// reading would give red 0.472.
#[test]
fn lecture_worked_example() {
    // The slides number the corners f1 (0,0,0), f2 (1,0,0), f3 (1,1,0), f4 (0,1,0),
    // f5 (0,0,1), f6 (1,0,1), f7 (1,1,1), f8 (0,1,1).
    let f = [5.0f64, 5.1, 5.2, 4.6, 4.9, 5.1, 5.3, 4.7];
    // The embedded `builtin:voxel` holds exactly these corners (the tutorial's volume).
    let voxel = voxcast_core::builtin::worked_voxel();
    let v = voxcast_core::Prepared::from(voxel.clone());
    // The slides' formula, in f64.
    let formula = |p: f64, q: f64, r: f64| {
        f[0] * (1.0 - p) * (1.0 - q) * (1.0 - r)
            + f[1] * p * (1.0 - q) * (1.0 - r)
            + f[2] * p * q * (1.0 - r)
            + f[3] * (1.0 - p) * q * (1.0 - r)
            + f[4] * (1.0 - p) * (1.0 - q) * r
            + f[5] * p * (1.0 - q) * r
            + f[6] * p * q * r
            + f[7] * (1.0 - p) * q * r
    };
    // P1 (far) … P3 (near the eye).
    let points = [
        Vec3::new(0.2, 0.3, 0.8),
        Vec3::new(0.5, 0.5, 0.5),
        Vec3::new(0.8, 0.7, 0.2),
    ];
    // The trilinear level's ramp: blue (0.1, 0.3, 0.9) at opacity 0.2 for 4.6, orange
    // (1, 0.6, 0.2) at opacity 0.6 for 5.3, straight lines between.
    let tf = voxcast_core::preset::for_volume("voxel").unwrap().transfer;
    let ramp = |value: f64| {
        let x = ((value - 4.6) / 0.7).clamp(0.0, 1.0);
        let mix = |a: f64, b: f64| a + (b - a) * x;
        ([mix(0.1, 1.0), mix(0.3, 0.6), mix(0.9, 0.2)], mix(0.2, 0.6))
    };
    // By hand, back to front: C ← C(1 − α) + c·α, O ← O(1 − α) + α, from P1 to P3.
    let (mut c, mut o) = ([0.0f64; 3], 0.0f64);
    for p in points {
        let (rgb, alpha) = ramp(formula(p.x as f64, p.y as f64, p.z as f64));
        for k in 0..3 {
            c[k] = c[k] * (1.0 - alpha) + rgb[k] * alpha;
        }
        o = o * (1.0 - alpha) + alpha;
    }
    // The lecture's answer, to the three places it is quoted with.
    for (got, quoted) in c.iter().chain([&o]).zip([0.540, 0.397, 0.375, 0.813]) {
        assert!((got - quoted).abs() < 5e-4, "{got} is not {quoted}");
    }

    // The renderer: the lecture's ray (its virtual camera's one pixel, the eye at P3 looking
    // towards P1) under its settings, back to front; its samples, visited from the far end as
    // back to front does, are P1, P2, P3.
    let camera = voxcast_core::worked::lecture_ray();
    let ray = camera.ray(0.5, 0.5, 1, 1);
    close(ray.origin.distance(points[2]), 0.0, 1e-6, "the eye is P3");
    close(
        ray.dir.dot((points[0] - points[2]).normalize()),
        1.0,
        1e-6,
        "the ray runs towards P1",
    );
    let mut s = voxcast_core::worked::lecture_ray_settings(&plain(1.0));
    s.order = Order::BackToFront;
    let t = trace(&v, &tf, &s, ray.origin, ray.dir);
    assert_eq!(t.samples.len(), 3);
    for (rec, p) in t.samples.iter().zip(points) {
        close(
            Vec3::from(rec.p_voxel).distance(p),
            0.0,
            1e-5,
            "sample positions",
        );
        let expect = formula(p.x as f64, p.y as f64, p.z as f64) as f32;
        close(rec.reconstruction.value, expect, 1e-5, "trilinear value");
        let w: f32 = rec.reconstruction.weights.iter().sum();
        close(w, 1.0, 1e-6, "weights sum to one");
    }
    // The baked table is within a few thousandths of the ramp.
    for (got, hand) in t.color.iter().zip(c) {
        close(*got, hand as f32, 2e-3, "composited colour");
    }
    close(t.opacity, o as f32, 2e-3, "composited opacity");

    // The trilinear level's worked composite (`worked::back_to_front`, P1 first) is the same reading.
    let rows = voxcast_core::worked::back_to_front(&voxel, &tf, &points.map(|p| p.to_array()));
    let last = rows.last().unwrap().after;
    for (level, render) in last.iter().zip(t.color) {
        close(*level, render, 1e-5, "the level's colour is the render's");
    }
    close(
        last[3],
        t.opacity,
        1e-5,
        "the level's opacity is the render's",
    );
}

/// Sum of a constant volume is the value times the path length in voxels, whatever the step
/// and the spacing (each sample stands for one step of path); of the ramp f = x along +x it is
/// the integral x²/2 by the midpoint rule. The colour is the table's at the stretched value.
#[test]
fn sum_is_value_times_path_in_voxels() {
    let c = 3.0f32;
    for spacing in [Vec3::ONE, Vec3::new(2.0, 0.5, 1.0)] {
        let v = field([21, 9, 5], spacing, |_| c);
        // The table spans the volume's values: [c, c + 1] for a constant volume.
        let tf = grey(c, c + 1.0, 1.0);
        for (origin, dir) in [
            (Vec3::new(-3.0, 2.0, 2.0), Vec3::X),
            (Vec3::new(5.0, -3.0, 1.0), Vec3::Y),
            (Vec3::new(-5.0, -4.0, -3.0), Vec3::new(1.0, 0.9, 0.8)),
        ] {
            for dt in [1.0f32, 0.5, 0.3, 0.01, 2.5] {
                let mut s = plain(dt);
                s.method = Method::Sum;
                s.sum_range = Some((0.0, 100.0));
                let t = trace(&v, &tf, &s, origin, dir);
                let [a, b] = t.interval.unwrap();
                let path_voxels = (dir.normalize() * (b - a) / spacing).length();
                let d = t.sum.expect("Sum records its arithmetic");
                let n = t.samples.len() as f32;
                close(d.sum, c * n * d.ds_voxels, 1e-3 * d.sum, "S = Σv·Δs");
                // The samples cover the path to within one step.
                assert!(
                    (d.sum - c * path_voxels).abs() <= c * d.ds_voxels * 1.0001,
                    "spacing {spacing}, dt {dt}, dir {dir}: S = {} for {path_voxels} voxels",
                    d.sum
                );
                // A constant table: the stretched value is the range's fraction, grey by it.
                close(d.fraction, (d.sum / 100.0).min(1.0), 1e-6, "fraction");
                close(t.color[0], d.fraction, 1e-3, "grey at the fraction");
            }
        }
    }
    // The ramp f = x along +x through [0, 32]: ∫ x dx = 512 (midpoint samples are exact for a
    // linear function when the samples tile the path).
    let ramp = field([33, 3, 3], Vec3::ONE, |p| p.x);
    let mut s = plain(0.5);
    s.method = Method::Sum;
    let t = trace(
        &ramp,
        &grey(0.0, 32.0, 1.0),
        &s,
        Vec3::new(-1.0, 1.0, 1.0),
        Vec3::X,
    );
    let d = t.sum.unwrap();
    assert!(
        (d.sum - 512.0).abs() <= 32.0 * 0.5,
        "∫x dx = 512, S = {}",
        d.sum
    );
    // Default range: 0 to twice the mean value (16) times the longest side (32 voxels).
    assert_eq!(d.range, [0.0, 1024.0]);
    let negative = field([5, 2, 2], Vec3::ONE, |p| -p.x);
    assert_eq!(
        voxcast_core::scene::default_sum_range(&negative),
        (-16.0, 0.0),
        "mean −2, side 4"
    );
    assert_eq!(
        voxcast_core::scene::default_sum_range(&constant([3, 3, 3], 0.0)),
        (0.0, 1.0)
    );
}

/// Sum clamps outside its range and refuses an empty or reversed one.
#[test]
fn sum_range_clamps_and_is_checked() {
    let v = constant([9, 9, 9], 10.0);
    let tf = grey(10.0, 11.0, 1.0);
    let mut s = plain(0.5);
    s.method = Method::Sum;
    s.sum_range = Some((1000.0, 2000.0)); // far above the ~80 the ray gathers
    let t = trace(&v, &tf, &s, Vec3::new(-1.0, 4.0, 4.0), Vec3::X);
    assert_eq!(t.sum.unwrap().fraction, 0.0);
    assert_eq!(t.color, [0.0; 3]);
    s.sum_range = Some((0.0, 1.0)); // far below
    let t = trace(&v, &tf, &s, Vec3::new(-1.0, 4.0, 4.0), Vec3::X);
    assert_eq!(t.sum.unwrap().fraction, 1.0);
    close(t.color[0], 1.0, 1e-6, "white at the top");
    for bad in [
        (1.0, 1.0),
        (2.0, 1.0),
        (f32::NAN, 1.0),
        (0.0, f32::INFINITY),
    ] {
        s.sum_range = Some(bad);
        assert!(s.validate().is_err(), "{bad:?} accepted");
    }
}
