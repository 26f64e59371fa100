//! Two of RayVis's study questions about a trace of the Cornell box (its Table 4.1), answered
//! by the code from the trace itself, so a level can check what a student says:
//!
//! * **Where was the camera?** — where the trace's rays start, if they all start at one point
//!   (a pinhole camera's eye): in front of the open side level with the box, in front of it
//!   and higher than the box, inside the box, or behind it.
//! * **Where are the hitting rays located?** — the surface most of the trace's hitting rays
//!   start from (a secondary ray leaves its surface a hair's breadth off it).

use super::effects::SURFACE_OFFSET;
use super::mesh::TriangleScene;
use super::set::RaySet;
use glam::Vec3;

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
}

impl Question {
    /// Its key in a level's objective.
    pub fn parse(key: &str) -> Option<Self> {
        match key {
            "camera" => Some(Question::Camera),
            "hits" => Some(Question::Hits),
            _ => None,
        }
    }

    /// What the student reads.
    pub fn words(self, trace: u32) -> String {
        match self {
            Question::Camera => format!("where was the camera of trace {trace}"),
            Question::Hits => format!("where do the hitting rays of trace {trace} start"),
        }
    }

    /// The options, in words; the answer is one of them.
    pub fn options(self, scene: &TriangleScene) -> Vec<String> {
        match self {
            Question::Camera => CameraPlace::ALL.iter().map(|p| p.words().into()).collect(),
            Question::Hits => surfaces(scene),
        }
    }

    /// The answer for the rays `set` of `scene`, in the words of [`Question::options`]; `None`
    /// where the trace has no answer (rays from many points have no camera; no ray hits).
    pub fn answer(self, scene: &TriangleScene, set: &RaySet) -> Option<String> {
        match self {
            Question::Camera => {
                let eye = set.rays.first()?.origin;
                if set.rays.iter().any(|r| r.origin != eye) {
                    return None;
                }
                Some(CameraPlace::of(eye, scene.bounds()?).words().into())
            }
            Question::Hits => {
                let names = surfaces(scene);
                let mut counts = vec![0usize; names.len()];
                for r in set.rays.iter().filter(|r| r.is_hit(0.0)) {
                    if let Some(name) = surface_of(scene, r.origin) {
                        counts[names.iter().position(|n| *n == name)?] += 1;
                    }
                }
                let (best, &n) = counts.iter().enumerate().max_by_key(|(_, n)| **n)?;
                (n > 0).then(|| names[best].clone())
            }
        }
    }
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
            camera.answer(&d.scene, trace(Effect::Primary)).as_deref(),
            Some(CameraPlace::FrontLevel.words())
        );
        assert_eq!(
            camera
                .answer(&d.scene, trace(Effect::SecondPrimary))
                .as_deref(),
            Some(CameraPlace::FrontHigher.words())
        );
        assert_eq!(camera.answer(&d.scene, trace(Effect::Shadow)), None);
        let hits = Question::Hits
            .answer(&d.scene, trace(Effect::Shadow))
            .unwrap();
        let options = Question::Hits.options(&d.scene);
        assert!(options.contains(&hits) && options.contains(&"the blocks".to_string()));
        assert_eq!(options.iter().filter(|o| o.contains("block")).count(), 1);
        for o in camera.options(&d.scene) {
            assert_eq!(Question::parse("camera"), Some(camera), "{o}");
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
            let got = Question::Hits.answer(&scene, &set(&points));
            assert_eq!(got.as_deref(), Some(want));
        }
        assert_eq!(Question::Hits.answer(&scene, &set(&[(floor, false)])), None);
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
