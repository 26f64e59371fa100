//! RayVis's study questions about a trace of the Cornell box (its Table 4.1), answered by the
//! code from the trace itself, so a level can check what a student says:
//!
//! * **Where was the camera?** — where the trace's rays start, if they all start at one point
//!   (a pinhole camera's eye): in front of the open side level with the box, in front of it
//!   and higher than the box, inside the box, or behind it.
//! * **Where are the hitting rays located?** — the surface most of the trace's hitting rays
//!   start from (a secondary ray leaves its surface a hair's breadth off it).
//! * **Where is the density of the hitting rays particularly high?** — where the densest cell
//!   of the trace's ray density (the hitting rays counted) lies, placed against the box as a
//!   camera is: rays that start at one eye crowd together there.
//! * **Where is the density of the missing rays particularly low?** — "low" needs a measure of
//!   what it is low against: every place the trace's rays never reach has none. So: of the
//!   surfaces the trace's rays start from (each with at least [`MIN_SHARE`] of them), the one
//!   where the smallest share of them miss. For the shadow rays (trace 4) a ray that misses
//!   reaches the light, so that is the surface most in shadow.

use super::density::Density;
use super::effects::SURFACE_OFFSET;
use super::mesh::TriangleScene;
use super::set::{Filter, RaySet};
use glam::Vec3;

/// The least share of a trace's rays a surface must start for the density-low question to
/// weigh it: a surface only a few strays start from (beside an edge) has no share to speak of.
pub const MIN_SHARE: f64 = 0.01;

/// Where a camera stood, relative to the box.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CameraPlace {
    FrontLevel,
    FrontHigher,
    Inside,
    Behind,
}

impl CameraPlace {
    pub const ALL: [CameraPlace; 4] = [
        CameraPlace::FrontLevel,
        CameraPlace::FrontHigher,
        CameraPlace::Inside,
        CameraPlace::Behind,
    ];

    pub fn words(self) -> &'static str {
        match self {
            CameraPlace::FrontLevel => "in front of the open side, level with the box",
            CameraPlace::FrontHigher => "in front of the open side, higher than the box's top",
            CameraPlace::Inside => "inside the box",
            CameraPlace::Behind => "behind the back wall",
        }
    }

    /// Where `eye` stands relative to the box `lo..hi` (the open side at `lo.z`).
    pub fn of(eye: Vec3, (lo, hi): (Vec3, Vec3)) -> Self {
        if eye.z > hi.z {
            CameraPlace::Behind
        } else if eye.z >= lo.z && eye.cmpge(lo).all() && eye.cmple(hi).all() {
            CameraPlace::Inside
        } else if eye.y > hi.y {
            CameraPlace::FrontHigher
        } else {
            CameraPlace::FrontLevel
        }
    }
}

/// A question of the study, and the options a student picks from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Question {
    /// Where was the camera in the trace?
    Camera,
    /// Where are the hitting rays located (the surface most of them start from)?
    Hits,
    /// Where is the density of the hitting rays highest (its densest cell)?
    DensityHigh,
    /// Where is the density of the missing rays particularly low (the surface where the
    /// smallest share of the rays that start there miss)?
    DensityLow,
}

impl Question {
    /// Every question, in the study's order.
    pub const ALL: [Question; 4] = [
        Question::Camera,
        Question::Hits,
        Question::DensityHigh,
        Question::DensityLow,
    ];

    /// Its key in a level's objective.
    pub fn parse(key: &str) -> Option<Self> {
        match key {
            "camera" => Some(Question::Camera),
            "hits" => Some(Question::Hits),
            "density-high" => Some(Question::DensityHigh),
            "density-low" => Some(Question::DensityLow),
            _ => None,
        }
    }

    /// What the student reads.
    pub fn words(self, trace: u32) -> String {
        match self {
            Question::Camera => format!("where was the camera of trace {trace}"),
            Question::Hits => format!("where do the hitting rays of trace {trace} start"),
            Question::DensityHigh => format!(
                "where is the density of the hitting rays of trace {trace} particularly high"
            ),
            Question::DensityLow => format!(
                "where is the density of the missing rays of trace {trace} particularly low: \
                 on which surface does the smallest share of the rays that start there miss"
            ),
        }
    }

    /// The options, in words; the answer is one of them.
    pub fn options(self, scene: &TriangleScene) -> Vec<String> {
        match self {
            Question::Camera | Question::DensityHigh => {
                CameraPlace::ALL.iter().map(|p| p.words().into()).collect()
            }
            Question::Hits | Question::DensityLow => surfaces(scene),
        }
    }

    /// Whether [`Question::answer`] reads the density (the densest cell); the low question
    /// is read from the density on show but answered from where the rays start.
    pub fn reads_density(self) -> bool {
        self == Question::DensityHigh
    }

    /// The rays whose density the question is read from (the hitting rays', the missing
    /// rays'), where it asks about a density.
    pub fn density_filter(self) -> Option<Filter> {
        match self {
            Question::DensityHigh => Some(Filter::Hit),
            Question::DensityLow => Some(Filter::Miss),
            Question::Camera | Question::Hits => None,
        }
    }

    /// The answer for the rays `set` of `scene` (and their `density`, for the density
    /// question: of the hitting rays), in the words of [`Question::options`]; `None` where the
    /// trace has no answer (rays from many points have no camera; no ray hits; no density).
    pub fn answer(
        self,
        scene: &TriangleScene,
        set: &RaySet,
        density: Option<&Density>,
    ) -> Option<String> {
        match self {
            Question::DensityHigh => {
                let at = densest_cell(density?)?;
                Some(CameraPlace::of(at, scene.bounds()?).words().into())
            }
            Question::Camera => {
                let eye = set.rays.first()?.origin;
                if set.rays.iter().any(|r| r.origin != eye) {
                    return None;
                }
                Some(CameraPlace::of(eye, scene.bounds()?).words().into())
            }
            Question::Hits => {
                let (names, starts) = starts_by_surface(scene, set)?;
                let (best, s) = starts.iter().enumerate().max_by_key(|(_, s)| s.hits)?;
                (s.hits > 0).then(|| names[best].clone())
            }
            Question::DensityLow => {
                let (names, starts) = starts_by_surface(scene, set)?;
                let total: usize = starts.iter().map(|s| s.all).sum();
                let missing = |s: &Starts| (s.all - s.hits) as f64 / s.all as f64;
                let (best, _) = starts
                    .iter()
                    .enumerate()
                    .filter(|(_, s)| s.all > 0 && s.all as f64 >= MIN_SHARE * total as f64)
                    .min_by(|a, b| missing(a.1).total_cmp(&missing(b.1)))?;
                Some(names[best].clone())
            }
        }
    }
}

/// The rays of a trace that start on one surface, and how many of them hit something.
#[derive(Clone, Copy, Default)]
struct Starts {
    all: usize,
    hits: usize,
}

/// [`surfaces`]' names and, for each, the rays of `set` that start on it ([`surface_of`]).
fn starts_by_surface(scene: &TriangleScene, set: &RaySet) -> Option<(Vec<String>, Vec<Starts>)> {
    let names = surfaces(scene);
    let mut starts = vec![Starts::default(); names.len()];
    for r in &set.rays {
        if let Some(name) = surface_of(scene, r.origin) {
            let s = &mut starts[names.iter().position(|n| *n == name)?];
            s.all += 1;
            s.hits += usize::from(r.is_hit(0.0));
        }
    }
    Some((names, starts))
}

/// The centre of the densest cell (world units): the first of the highest counts, chunks in
/// key order.
fn densest_cell(d: &Density) -> Option<Vec3> {
    let n = d.params.chunk as i32;
    let mut best: Option<(u32, Vec3)> = None;
    for (key, chunk) in &d.chunks {
        for (i, c) in chunk.cells.iter().enumerate() {
            if c.count > best.map_or(0, |b| b.0) {
                let i = i as i32;
                let local = glam::IVec3::new(i % n, (i / n) % n, i / (n * n));
                let cell = glam::IVec3::from_array(*key) * n + local;
                best = Some((c.count, (cell.as_vec3() + 0.5) * d.params.cell));
            }
        }
    }
    best.map(|b| b.1)
}

/// The scene's surfaces by name: each mesh's, the two blocks as one ("the blocks"), and the
/// Cornell box's white "walls" as the floor, the ceiling and the back wall.
fn surfaces(scene: &TriangleScene) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for m in &scene.meshes {
        let names: Vec<String> = if m.name == WHITE_WALLS {
            ["the floor", "the ceiling", "the back wall"]
                .map(String::from)
                .to_vec()
        } else if m.name.ends_with("block") {
            vec!["the blocks".into()]
        } else {
            vec![format!("the {}", m.name)]
        };
        for n in names {
            if !out.contains(&n) {
                out.push(n);
            }
        }
    }
    out
}

/// The mesh of the Cornell box holding its floor, ceiling and back wall.
const WHITE_WALLS: &str = "walls";

/// The surface a ray starting at `p` left, by [`surfaces`]' names: the nearest one a short step
/// along any axis reaches (a secondary ray starts [`SURFACE_OFFSET`] of the scene's size off its
/// surface, and one of the three axes meets a plane at most √3 times that far away).
fn surface_of(scene: &TriangleScene, p: Vec3) -> Option<String> {
    let (lo, hi) = scene.bounds()?;
    let reach = 2.0 * SURFACE_OFFSET * (hi - lo).length();
    let hit = [
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
    ]
    .iter()
    .filter_map(|&d| scene.intersect(p, d, 0.0, reach))
    .min_by(|a, b| a.t.total_cmp(&b.t))?;
    let name = &scene.meshes[hit.mesh].name;
    Some(if name == WHITE_WALLS {
        if hit.normal.y.abs() < 0.5 {
            "the back wall"
        } else if p.y < 0.5 * (lo.y + hi.y) {
            "the floor"
        } else {
            "the ceiling"
        }
        .into()
    } else if name.ends_with("block") {
        "the blocks".into()
    } else {
        format!("the {name}")
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rays::effects::Effect;
    use crate::rays::source::load;

    /// On the box's traces: trace 0's camera stood level in front of the open side, trace 1's
    /// higher than the box; rays from many points (shadow rays) have no camera; the shadow
    /// rays that hit something start mostly on one of the box's surfaces.
    #[test]
    fn the_study_questions_are_answered_from_the_traces() {
        let d = load("builtin:cornell").unwrap();
        let trace = |e: Effect| d.trace(e.id()).unwrap();
        let camera = Question::Camera;
        assert_eq!(
            camera
                .answer(&d.scene, trace(Effect::Primary), None)
                .as_deref(),
            Some(CameraPlace::FrontLevel.words())
        );
        assert_eq!(
            camera
                .answer(&d.scene, trace(Effect::SecondPrimary), None)
                .as_deref(),
            Some(CameraPlace::FrontHigher.words())
        );
        assert_eq!(camera.answer(&d.scene, trace(Effect::Shadow), None), None);
        let hits = Question::Hits
            .answer(&d.scene, trace(Effect::Shadow), None)
            .unwrap();
        let options = Question::Hits.options(&d.scene);
        assert!(options.contains(&hits) && options.contains(&"the blocks".to_string()));
        assert_eq!(options.iter().filter(|o| o.contains("block")).count(), 1);
        for o in camera.options(&d.scene) {
            assert_eq!(Question::parse("camera"), Some(camera), "{o}");
        }
        // The hitting primary rays of trace 0 crowd together at the eye: the densest cell is
        // there, in front of the open side, level with the box.
        let hits = crate::rays::density::DensityParams {
            cell: 20.0,
            filter: crate::rays::set::Filter::Hit,
            ..Default::default()
        };
        let primary = trace(Effect::Primary);
        let stop = std::sync::atomic::AtomicBool::new(false);
        let density = crate::rays::density::compute(primary, &hits, &|_, _| {}, &stop).unwrap();
        let high = Question::DensityHigh;
        assert_eq!(high.density_filter(), Some(crate::rays::set::Filter::Hit));
        assert_eq!(
            high.answer(&d.scene, primary, None),
            None,
            "no density, no answer"
        );
        assert_eq!(
            high.answer(&d.scene, primary, Some(&density)).as_deref(),
            Some(CameraPlace::FrontLevel.words())
        );
        let at = densest_cell(&density).unwrap();
        let eye = crate::rays::cornell::CAMERA_EYE;
        assert!(
            at.distance(eye) < 2.0 * 20.0,
            "the densest cell {at} is the eye's {eye}"
        );
    }

    /// Trace 4's shadow rays point up and out of the open side, towards the directional
    /// light: from the back wall most of them meet the ceiling first, so fewer of its rays
    /// miss than of any other surface's; the ceiling and the wall that face away from the
    /// light start almost none and are not weighed.
    #[test]
    fn the_missing_rays_are_scarcest_where_the_rays_are_most_in_shadow() {
        let d = load("builtin:cornell").unwrap();
        let shadow = d.trace(Effect::Shadow.id()).unwrap();
        let q = Question::DensityLow;
        assert_eq!(q.density_filter(), Some(crate::rays::set::Filter::Miss));
        assert!(!q.reads_density() && Question::DensityHigh.reads_density());
        assert_eq!(
            q.answer(&d.scene, shadow, None).as_deref(),
            Some("the back wall")
        );
        assert_eq!(q.options(&d.scene), Question::Hits.options(&d.scene));
        // Against the shares, counted independently: the back wall's is the smallest of
        // those weighed, and the ceiling (facing away from the light) is not weighed.
        let to_light = -crate::rays::cornell::light_direction();
        let (mut back, mut floor) = ((0, 0), (0, 0));
        let (lo, hi) = d.scene.bounds().unwrap();
        for r in &shadow.rays {
            assert!(r.direction.abs_diff_eq(to_light, 1e-5));
            let c = if (r.origin.z - hi.z).abs() < 1.0 {
                &mut back
            } else if (r.origin.y - lo.y).abs() < 1.0 && r.origin.z < hi.z - 1.0 {
                &mut floor
            } else {
                continue;
            };
            c.0 += 1;
            c.1 += usize::from(!r.is_hit(0.0));
        }
        let share = |c: (usize, usize)| c.1 as f64 / c.0 as f64;
        assert!(back.0 > 1000 && floor.0 > 1000, "{back:?} {floor:?}");
        assert!(
            share(back) < 0.5 && share(floor) > 0.5,
            "{back:?} {floor:?}"
        );
        // The which-effect level's words: the ceiling and the left wall face away from the light and start
        // almost none of the rays.
        for away in ["the ceiling", "the left wall"] {
            let n = shadow
                .rays
                .iter()
                .filter(|r| surface_of(&d.scene, r.origin).as_deref() == Some(away))
                .count();
            assert!(
                (n as f64) < MIN_SHARE * shadow.rays.len() as f64,
                "{away}: {n}"
            );
        }
    }

    /// Rays that leave a surface (a hair's breadth off it, as the tracer starts them) are
    /// placed on it; misses do not count.
    #[test]
    fn hitting_rays_are_placed_on_the_surface_they_leave() {
        use crate::rays::set::RayRecord;
        let scene = crate::rays::cornell::scene();
        let (lo, hi) = scene.bounds().unwrap();
        let off = SURFACE_OFFSET * (hi - lo).length();
        let set = |at: &[(Vec3, bool)]| RaySet {
            trace_id: 4,
            rays: at
                .iter()
                .enumerate()
                .map(|(i, &(origin, hit))| RayRecord {
                    id: i as u32,
                    origin,
                    direction: Vec3::new(0.0, 0.6, -0.8),
                    t_min: 0.0,
                    t_max: 100.0,
                    t_hit: if hit { 50.0 } else { -1.0 },
                })
                .collect(),
        };
        let floor = Vec3::new(450.0, off, 500.0);
        let back = Vec3::new(100.0, 300.0, 559.2 - off);
        let ceiling = Vec3::new(300.0, 548.8 - off, 300.0);
        let block = Vec3::new(185.0, 165.0 + off, 168.0);
        for (points, want) in [
            (
                vec![(floor, true), (floor, true), (back, true), (back, false)],
                "the floor",
            ),
            (
                vec![(back, true), (back, true), (floor, false), (floor, false)],
                "the back wall",
            ),
            (vec![(ceiling, true)], "the ceiling"),
            (vec![(block, true), (floor, false)], "the blocks"),
        ] {
            let got = Question::Hits.answer(&scene, &set(&points), None);
            assert_eq!(got.as_deref(), Some(want));
        }
        assert_eq!(
            Question::Hits.answer(&scene, &set(&[(floor, false)]), None),
            None
        );
    }

    #[test]
    fn a_camera_is_placed_by_the_box() {
        let b = (Vec3::ZERO, Vec3::splat(10.0));
        assert_eq!(
            CameraPlace::of(Vec3::new(5.0, 5.0, -20.0), b),
            CameraPlace::FrontLevel
        );
        assert_eq!(
            CameraPlace::of(Vec3::new(5.0, 15.0, -20.0), b),
            CameraPlace::FrontHigher
        );
        assert_eq!(CameraPlace::of(Vec3::splat(5.0), b), CameraPlace::Inside);
        assert_eq!(
            CameraPlace::of(Vec3::new(5.0, 5.0, 30.0), b),
            CameraPlace::Behind
        );
    }
}
