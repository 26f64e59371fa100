//! Ray sets Voxcast traces itself through a triangle scene, one per trace of RayVis's study
//! (its Table 4.2, with the study's trace ids): primary rays of two pinhole cameras (traces 0
//! and 1), and from every hit of the first camera's primary rays a mirror reflection ray
//! (trace 2), a few short ambient-occlusion rays (trace 3, cosine-distributed over the
//! hemisphere of the surface's normal) and a shadow ray towards a directional light (trace 4,
//! where the surface faces it: one turned away is dark without a ray). Seeded and reproducible:
//! every random number is a hash of the seed, the primary ray and the secondary ray's index,
//! so any thread count gives the same sets.
//!
//! Trace ids: [`Effect::id`]. Every ray's direction has unit length (`t` is a distance); a
//! ray that hits nothing keeps `t_hit = −1`. A ray may go as far as it takes to leave the box
//! around the scene and the camera (padded by [`WORLD_PADDING`]): a miss is counted up to
//! there, as a renderer's far plane would end it, not a thousand scene sizes away.

use super::mesh::{Hit, TriangleScene};
use super::set::{RayRecord, RaySet};
use crate::camera::{Camera, Projection};
use crate::hash::pcg_hash;
use crate::slices::{Deadline, Step};
use glam::Vec3;
use rayon::prelude::*;

/// One trace's effect, in the order (and with the ids) of RayVis's study.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Effect {
    /// The first camera's primary rays.
    Primary,
    /// The second camera's primary rays.
    SecondPrimary,
    Reflection,
    AmbientOcclusion,
    Shadow,
}

impl Effect {
    pub const ALL: [Effect; 5] = [
        Effect::Primary,
        Effect::SecondPrimary,
        Effect::Reflection,
        Effect::AmbientOcclusion,
        Effect::Shadow,
    ];

    /// Its trace id in the data set (the study's: primary rays 0 and 1, shadow rays 4).
    pub const fn id(self) -> u32 {
        self as u32
    }

    /// Its name, in words.
    pub const fn words(self) -> &'static str {
        match self {
            Effect::Primary => "primary rays from camera 1",
            Effect::SecondPrimary => "primary rays from camera 2",
            Effect::Reflection => "reflection rays",
            Effect::AmbientOcclusion => "ambient-occlusion rays",
            Effect::Shadow => "shadow rays",
        }
    }

    /// One effect of each kind, in the order a choice lists them.
    pub const KINDS: [Effect; 4] = [
        Effect::Primary,
        Effect::Reflection,
        Effect::AmbientOcclusion,
        Effect::Shadow,
    ];

    /// The effect with trace id `id`.
    pub fn of(id: u32) -> Option<Effect> {
        Effect::ALL.get(id as usize).copied()
    }

    /// Whether traces `a` and `b` hold the same kind of effect (both primary traces do).
    pub fn same_kind(a: u32, b: u32) -> bool {
        matches!((Effect::of(a), Effect::of(b)), (Some(x), Some(y)) if x.kind() == y.kind())
    }

    /// The kind of effect, without which camera: both primary traces are "primary rays" (the
    /// study counted naming either trace's effect as right).
    pub const fn kind(self) -> &'static str {
        match self {
            Effect::Primary | Effect::SecondPrimary => "primary rays",
            other => other.words(),
        }
    }
}

/// How the sets are traced (each documented where the CLI and the panel show it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceParams {
    /// The camera's image: one primary ray per pixel centre.
    pub width: u32,
    pub height: u32,
    /// The direction the light shines along.
    pub light: Vec3,
    /// Ambient-occlusion rays per primary hit, and how far they look.
    pub ao_rays: u32,
    pub ao_radius: f32,
    pub seed: u32,
}

/// How far off its surface a secondary ray starts, as a fraction of the scene's size (so it
/// does not hit the surface it leaves through rounding).
pub const SURFACE_OFFSET: f32 = 1e-4;

/// How much larger than the box around the scene and the camera the world is, as a fraction
/// of that box's diagonal.
pub const WORLD_PADDING: f32 = 0.01;

/// Where a ray from `origin` (inside the box `lo..hi`) along `dir` leaves it.
fn exit_distance(origin: Vec3, dir: Vec3, lo: Vec3, hi: Vec3) -> f32 {
    let mut t = f32::INFINITY;
    for a in 0..3 {
        if dir[a] > 0.0 {
            t = t.min((hi[a] - origin[a]) / dir[a]);
        } else if dir[a] < 0.0 {
            t = t.min((lo[a] - origin[a]) / dir[a]);
        }
    }
    t.max(0.0)
}

/// A secondary ray leaving a surface.
struct Leaving {
    origin: Vec3,
    normal: Vec3,
}

/// One pixel's records, by effect id: each camera's primary ray, then the first camera's
/// secondaries.
#[derive(Clone, Debug, Default)]
struct PixelRays {
    sets: [Vec<RayRecord>; 5],
}

/// A ray record from a trace through `scene`.
fn traced(scene: &TriangleScene, origin: Vec3, dir: Vec3, t_max: f32) -> (RayRecord, Option<Hit>) {
    let hit = scene.intersect(origin, dir, 0.0, t_max);
    let record = RayRecord {
        id: 0,
        origin,
        direction: dir,
        t_min: 0.0,
        t_max,
        t_hit: hit.map_or(-1.0, |h| h.t),
    };
    (record, hit)
}

/// A number in `[0, 1)` from the hash of `keys`.
fn uniform(keys: [u32; 4]) -> f32 {
    let h = keys.iter().fold(0u32, |h, &k| pcg_hash(h ^ k));
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// A unit direction on the hemisphere around unit `n`, cosine-distributed, from two uniform
/// numbers (Malley's method: a uniform point on the disc raised to the hemisphere).
pub fn cosine_direction(n: Vec3, u1: f32, u2: f32) -> Vec3 {
    let (a, b) = n.any_orthonormal_pair();
    let r = u1.sqrt();
    let phi = std::f32::consts::TAU * u2;
    let local = Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt());
    (a * local.x + b * local.y + n * local.z).normalize()
}

/// The pinhole camera of the sets.
pub fn camera(
    eye: Vec3,
    target: Vec3,
    fov_y_deg: f32,
) -> Result<Camera, crate::error::SettingsError> {
    Camera::new(eye, target, Vec3::Y, Projection::Perspective { fov_y_deg })
}

/// Traces the five sets (in [`Effect::ALL`]'s order) through `scene` from the two `cameras`
/// (the secondaries from the first one's hits).
pub fn trace_effects(scene: &TriangleScene, cameras: [&Camera; 2], p: &TraceParams) -> Vec<RaySet> {
    trace_effects_in(
        scene,
        cameras,
        p,
        &mut TraceSlices::default(),
        Deadline::NONE,
    )
    .whole()
}

/// The pixels traced so far by [`trace_effects_in`] (work in slices, [`crate::slices`]).
#[derive(Clone, Debug, Default)]
pub struct TraceSlices {
    pixels: Vec<PixelRays>,
}

/// Pixels traced between two looks at the deadline.
const PIXELS_PER_LOOK: u32 = 512;

/// [`trace_effects`] in slices: the pixels in order, a block at a time, until `deadline`.
pub fn trace_effects_in(
    scene: &TriangleScene,
    [camera, second]: [&Camera; 2],
    p: &TraceParams,
    slices: &mut TraceSlices,
    deadline: Deadline,
) -> Step<Vec<RaySet>> {
    let (lo, hi) = scene
        .bounds()
        .map_or((camera.eye, camera.eye), |(lo, hi)| (lo, hi));
    let (lo, hi) = (
        lo.min(camera.eye).min(second.eye),
        hi.max(camera.eye).max(second.eye),
    );
    let size = (hi - lo).length().max(f32::MIN_POSITIVE);
    let (lo, hi) = (lo - WORLD_PADDING * size, hi + WORLD_PADDING * size);
    let far = |o: Vec3, d: Vec3| exit_distance(o, d, lo, hi);
    let offset = SURFACE_OFFSET * size;
    let to_light = -p.light.normalize_or_zero();
    let rays = camera.rays(p.width.max(1), p.height.max(1));
    let second_rays = second.rays(p.width.max(1), p.height.max(1));
    let total = p.width * p.height;
    let id = |e: Effect| e.id() as usize;
    let trace_pixel = |i: u32| {
        let (px, py) = (i % p.width, i / p.width);
        let mut out = PixelRays::default();
        let other = second_rays.ray(px as f32 + 0.5, py as f32 + 0.5);
        let (primary, _) = traced(scene, other.origin, other.dir, far(other.origin, other.dir));
        out.sets[id(Effect::SecondPrimary)].push(primary);
        let ray = rays.ray(px as f32 + 0.5, py as f32 + 0.5);
        let (primary, hit) = traced(scene, ray.origin, ray.dir, far(ray.origin, ray.dir));
        out.sets[id(Effect::Primary)].push(primary);
        let Some(hit) = hit else { return out };
        let at = ray.origin + ray.dir * hit.t;
        let leave = Leaving {
            origin: at + hit.normal * offset,
            normal: hit.normal,
        };
        // A surface facing away from the light is dark without a ray.
        if to_light != Vec3::ZERO && leave.normal.dot(to_light) > 0.0 {
            let t_max = far(leave.origin, to_light);
            out.sets[id(Effect::Shadow)].push(traced(scene, leave.origin, to_light, t_max).0);
        }
        let mirror = ray.dir - 2.0 * ray.dir.dot(leave.normal) * leave.normal;
        let mirror = mirror.normalize();
        let t_max = far(leave.origin, mirror);
        out.sets[id(Effect::Reflection)].push(traced(scene, leave.origin, mirror, t_max).0);
        for k in 0..p.ao_rays {
            let u1 = uniform([p.seed, i, k, 1]);
            let u2 = uniform([p.seed, i, k, 2]);
            let d = cosine_direction(leave.normal, u1, u2);
            let t_max = p.ao_radius.min(far(leave.origin, d));
            out.sets[id(Effect::AmbientOcclusion)].push(traced(scene, leave.origin, d, t_max).0);
        }
        out
    };
    let mut first = true;
    while (slices.pixels.len() as u32) < total {
        if !first && deadline.passed() {
            return Step::Paused;
        }
        first = false;
        let start = slices.pixels.len() as u32;
        // Without a deadline, every pixel at once (on every core).
        let end = if deadline == Deadline::NONE {
            total
        } else {
            (start + PIXELS_PER_LOOK).min(total)
        };
        let block: Vec<PixelRays> = (start..end).into_par_iter().map(trace_pixel).collect();
        slices.pixels.extend(block);
    }
    let mut sets: Vec<RaySet> = Effect::ALL
        .iter()
        .map(|e| RaySet {
            trace_id: e.id(),
            rays: Vec::new(),
        })
        .collect();
    for pixel in std::mem::take(&mut slices.pixels) {
        for (set, rays) in sets.iter_mut().zip(pixel.sets) {
            set.rays.extend(rays);
        }
    }
    for set in &mut sets {
        for (id, r) in set.rays.iter_mut().enumerate() {
            r.id = id as u32;
        }
    }
    Step::Done(sets)
}

#[cfg(test)]
mod tests {
    use super::super::cornell;
    use super::*;

    fn params(width: u32, height: u32, seed: u32) -> TraceParams {
        TraceParams {
            width,
            height,
            light: cornell::light_direction(),
            ao_rays: 4,
            ao_radius: 100.0,
            seed,
        }
    }

    fn cameras() -> [Camera; 2] {
        [
            camera(
                cornell::CAMERA_EYE,
                cornell::CAMERA_TARGET,
                cornell::CAMERA_FOV_Y_DEG,
            )
            .unwrap(),
            cornell::second_camera(),
        ]
    }

    fn cornell_sets(width: u32, height: u32, seed: u32) -> Vec<RaySet> {
        let [a, b] = cameras();
        trace_effects(&cornell::scene(), [&a, &b], &params(width, height, seed))
    }

    /// Traced in slices, a block of pixels a call, the sets are the ones traced whole.
    #[test]
    fn tracing_in_slices_gives_the_same_rays() {
        let [a, b] = cameras();
        let (scene, p) = (cornell::scene(), params(40, 30, 9));
        let whole = trace_effects(&scene, [&a, &b], &p);
        let mut slices = TraceSlices::default();
        let (sliced, calls) = crate::slices::until_done(crate::slices::Duration::ZERO, |d| {
            Ok::<_, ()>(trace_effects_in(&scene, [&a, &b], &p, &mut slices, d))
        })
        .unwrap();
        assert_eq!(calls, (40 * 30usize).div_ceil(PIXELS_PER_LOOK as usize));
        assert_eq!(sliced, whole);
    }

    #[test]
    fn every_effect_has_its_rays_and_its_rules() {
        let sets = cornell_sets(48, 48, 7);
        let scene = cornell::scene();
        let (lo, hi) = scene.bounds().unwrap();
        assert_eq!(sets.len(), 5);
        let ids: Vec<u32> = sets.iter().map(|s| s.trace_id).collect();
        assert_eq!(ids, [0, 1, 2, 3, 4]);
        let [reflection, ao, shadow] = [&sets[2], &sets[3], &sets[4]];
        let primary = &sets[0];
        assert_eq!(primary.rays.len(), 48 * 48);
        let (hits, misses) = primary.hits_and_misses(0.0);
        // The camera looks in through the open front: almost every ray hits, a few at the
        // image's edges pass outside the box.
        assert!(hits > 48 * 48 * 9 / 10, "{hits} hits, {misses} misses");
        // Misses end where they leave the world: the box around the scene and the camera.
        let eyes = cameras().map(|c| c.eye);
        let (w_lo, w_hi) = (lo.min(eyes[0]).min(eyes[1]), hi.max(eyes[0]).max(eyes[1]));
        let pad = WORLD_PADDING * (w_hi - w_lo).length() + 0.01;
        let (world_lo, world_hi) = (w_lo - pad, w_hi + pad);
        for r in sets.iter().flat_map(|s| &s.rays) {
            let end = r.at(r.t_max);
            assert!(
                end.cmpge(world_lo).all() && end.cmple(world_hi).all(),
                "{end}"
            );
        }
        for r in &primary.rays {
            assert!((r.direction.length() - 1.0).abs() < 1e-5);
            if r.is_hit(0.0) {
                let p = r.at(r.t_hit);
                assert!(p.cmpge(lo - 0.01).all() && p.cmple(hi + 0.01).all(), "{p}");
            }
        }
        // The second camera's primary rays: one a pixel, from its own eye.
        let second = &sets[1];
        assert_eq!(second.rays.len(), 48 * 48);
        assert!(second.rays.iter().all(|r| r.origin == eyes[1]));
        assert!(primary.rays.iter().all(|r| r.origin == eyes[0]));
        // Secondary rays leave from the first camera's hits: reflections one each, AO four.
        assert_eq!(reflection.rays.len(), hits);
        assert_eq!(ao.rays.len(), 4 * hits);
        // Shadow rays all point at the light; some surfaces lie in shadow, most are lit.
        let to_light = -cornell::light_direction();
        assert!(!shadow.rays.is_empty() && shadow.rays.len() <= hits);
        assert!(
            shadow
                .rays
                .iter()
                .all(|r| r.direction.abs_diff_eq(to_light, 1e-6))
        );
        let (shadowed, lit) = shadow.hits_and_misses(0.0);
        assert!(
            shadowed > 0 && lit > shadowed,
            "{shadowed} shadowed, {lit} lit"
        );
        // AO rays are short and on their surface's hemisphere; ids count up from 0.
        for set in &sets {
            assert!(set.rays.iter().enumerate().all(|(i, r)| r.id == i as u32));
        }
        for r in &ao.rays {
            assert!(r.t_max <= 100.0 && r.t_hit < 100.0);
        }
        assert!(ao.rays.iter().filter(|r| r.t_max == 100.0).count() > ao.rays.len() / 2);
    }

    #[test]
    fn the_floor_behind_the_tall_block_is_in_its_shadow_and_the_open_floor_is_lit() {
        let scene = cornell::scene();
        let l = cornell::light_direction();
        // From inside the tall block along the light: out of the block, then the surface its
        // shadow falls on.
        let inside = Vec3::new(368.5, 200.0, 351.25);
        let exit = scene.intersect(inside, l, 0.0, 1e4).unwrap();
        assert_eq!(scene.meshes[exit.mesh].name, "tall block");
        let behind = scene.intersect(inside, l, exit.t + 1e-3, 1e4).unwrap();
        assert_ne!(scene.meshes[behind.mesh].name, "tall block");
        let p = inside + l * behind.t;
        let shadow = traced(&scene, p + behind.normal * 0.05, -l, 1e4).0;
        assert!(shadow.is_hit(0.0), "{p} should be in shadow");
        let open = Vec3::new(100.0, 0.0, 50.0);
        let lit = traced(&scene, open + Vec3::Y * 0.05, -l, 1e4).0;
        assert!(!lit.is_hit(0.0));
    }

    #[test]
    fn the_sets_are_reproducible_and_follow_the_seed() {
        let a = cornell_sets(16, 16, 3);
        assert_eq!(a, cornell_sets(16, 16, 3));
        let b = cornell_sets(16, 16, 4);
        // Only the random rays (ambient occlusion) change with the seed.
        let ao = Effect::AmbientOcclusion.id() as usize;
        for (i, (x, y)) in a.iter().zip(&b).enumerate() {
            assert_eq!(x == y, i != ao, "trace {i}");
        }
    }

    #[test]
    fn cosine_directions_lie_on_the_hemisphere_with_the_cosine_mean() {
        let n = Vec3::new(0.3, -0.8, 0.52).normalize();
        let mut mean_cos = 0.0;
        let count = 4000;
        for k in 0..count {
            let d = cosine_direction(n, uniform([1, k, 0, 1]), uniform([1, k, 0, 2]));
            assert!((d.length() - 1.0).abs() < 1e-5);
            assert!(d.dot(n) >= -1e-6);
            mean_cos += d.dot(n) / count as f32;
        }
        // E[cos θ] under a cosine distribution is 2/3.
        assert!((mean_cos - 2.0 / 3.0).abs() < 0.02, "{mean_cos}");
    }
}
