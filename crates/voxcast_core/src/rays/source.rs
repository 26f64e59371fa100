//! Where a ray data set comes from: a scene and its traces, by name — a `.rayvis` file
//! (`rayvis`), or `builtin:cornell`, the Cornell box with the five traces of RayVis's study
//! that Voxcast traces through it at [`CORNELL`]'s settings (`builtin:cornell-1m`: at [`CORNELL_1M`]'s, a million
//! rays, the scale RayVis's study drew).

use super::cornell;
use super::data::RayData;
use super::effects::{Effect, TraceParams, TraceSlices, camera, trace_effects_in};
use crate::slices::{Deadline, Step};

/// How `builtin:cornell` is traced: 256 × 256 primary rays, four ambient-occlusion rays of
/// 100 mm (about a fifth of the box) per hit, seed 1.
pub const CORNELL: TraceParams = TraceParams {
    width: 256,
    height: 256,
    light: cornell::LIGHT,
    ao_rays: 4,
    ao_radius: 100.0,
    seed: 1,
};

/// How `builtin:cornell-1m` is traced: as [`CORNELL`] with 400 × 400 primary rays per camera,
/// about 1.2 million rays in all.
pub const CORNELL_1M: TraceParams = TraceParams {
    width: 400,
    height: 400,
    ..CORNELL
};

/// The embedded ray data sets, `builtin:NAME`, and what each is.
pub const BUILTIN: &[(&str, &str)] = &[
    (
        "cornell",
        "the Cornell box (five walls, two blocks) with RayVis's study's five traces, traced by \
         Voxcast: primary rays of two cameras (0, 1), reflection (2), ambient-occlusion (3) and \
         shadow rays (4)",
    ),
    (
        "cornell-1m",
        "the same at 400 × 400 primary rays per camera: about 1.2 million rays, the scale \
         RayVis's study drew",
    ),
];

/// Why a ray data source cannot be had.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SourceError {
    #[error("no embedded ray data set is called '{0}' (there is: {1})")]
    UnknownBuiltin(String, String),
    #[error("{0}: {1}")]
    File(String, String),
}

/// The `.rayvis` file handed over last (a web page has no paths: the file a student opens there
/// is kept here under its name), the one [`load_in`] reads before looking on disk.
static HANDED: std::sync::Mutex<Option<(String, std::sync::Arc<[u8]>)>> =
    std::sync::Mutex::new(None);

/// Keeps a `.rayvis` file's bytes under `name`, which [`load`] then opens as it would a path;
/// it replaces the file handed over before (one is kept: a ray file may be large).
pub fn hand_over(name: &str, bytes: Vec<u8>) {
    *HANDED.lock().unwrap_or_else(|e| e.into_inner()) = Some((name.to_string(), bytes.into()));
}

fn handed(name: &str) -> Option<std::sync::Arc<[u8]>> {
    let handed = HANDED.lock().unwrap_or_else(|e| e.into_inner());
    handed
        .as_ref()
        .filter(|(n, _)| n == name)
        .map(|(_, bytes)| bytes.clone())
}

/// The ray data named `name`: `builtin:NAME`, a file handed over under that name
/// ([`hand_over`]) or a `.rayvis` file's path.
pub fn load(name: &str) -> Result<RayData, SourceError> {
    load_in(name, &mut TraceSlices::default(), Deadline::NONE).map(Step::whole)
}

/// [`load`] in slices ([`crate::slices`]): a builtin's rays traced a block of pixels at a time
/// until `deadline`; a file is read whole.
pub fn load_in(
    name: &str,
    slices: &mut TraceSlices,
    deadline: Deadline,
) -> Result<Step<RayData>, SourceError> {
    let Some(builtin) = name.strip_prefix("builtin:") else {
        let bytes = match handed(name) {
            Some(bytes) => bytes,
            None => std::fs::read(name)
                .map_err(|e| SourceError::File(name.into(), crate::error::io_words(&e)))?
                .into(),
        };
        return super::rayvis::read(&bytes, name)
            .map(Step::Done)
            .map_err(|e| SourceError::File(name.into(), e.to_string()));
    };
    match builtin {
        "cornell" => Ok(cornell_with(&CORNELL, slices, deadline)),
        "cornell-1m" => Ok(cornell_with(&CORNELL_1M, slices, deadline)),
        other => Err(SourceError::UnknownBuiltin(
            other.into(),
            BUILTIN
                .iter()
                .map(|(n, _)| format!("builtin:{n}"))
                .collect::<Vec<_>>()
                .join(", "),
        )),
    }
}

/// The Cornell box with its five traces at `p` (in slices).
fn cornell_with(p: &TraceParams, slices: &mut TraceSlices, deadline: Deadline) -> Step<RayData> {
    let scene = cornell::scene();
    let cam = camera(
        cornell::CAMERA_EYE,
        cornell::CAMERA_TARGET,
        cornell::CAMERA_FOV_Y_DEG,
    )
    .expect("the Cornell box's camera is valid");
    let second = cornell::second_camera();
    let Step::Done(traces) = trace_effects_in(&scene, [&cam, &second], p, slices, deadline) else {
        return Step::Paused;
    };
    Step::Done(RayData {
        description: format!(
            "the Cornell box, {}×{} primary rays from its published camera (trace 0) and from \
             a second one above and to the right (trace 1); from the first one's hits \
             reflection rays (2), {} ambient-occlusion rays of {} mm each (3) and shadow rays \
             towards a directional light through the open front (4); seed {}",
            p.width, p.height, p.ao_rays, p.ao_radius, p.seed
        ),
        scene,
        traces,
    })
}

/// The effect a trace of `builtin:cornell` holds.
pub fn effect_of(trace_id: u32) -> Option<Effect> {
    Effect::ALL.into_iter().find(|e| e.id() == trace_id)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file handed over opens by its name, as a path would; a damaged one is refused in
    /// words that name it; another name still goes to the disk.
    #[test]
    fn a_handed_rayvis_file_opens_by_its_name() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../tests/data/two_level.rayvis"
        );
        let bytes = std::fs::read(path).unwrap();
        let from_disk = load(path).unwrap();
        hand_over("picked in a page.rayvis", bytes.clone());
        let handed = load("picked in a page.rayvis").unwrap();
        assert_eq!(handed.traces.len(), from_disk.traces.len());
        assert_eq!(
            handed.all_rays().rays.len(),
            from_disk.all_rays().rays.len()
        );
        let elsewhere = load("not handed.rayvis").unwrap_err().to_string();
        assert!(elsewhere.starts_with("not handed.rayvis: "), "{elsewhere}");
        hand_over("damaged.rayvis", bytes[..bytes.len() / 2].to_vec());
        let damaged = load("damaged.rayvis").unwrap_err().to_string();
        assert!(damaged.starts_with("damaged.rayvis: "), "{damaged}");
        assert!(
            load("picked in a page.rayvis").is_err(),
            "only the last file handed over is kept"
        );
    }

    /// The million-ray box traces the same effects at 400 × 400 primary rays.
    #[test]
    fn the_million_ray_box_is_the_box_at_a_finer_camera() {
        let d = load("builtin:cornell-1m").unwrap();
        assert_eq!(d.trace(0).unwrap().rays.len(), 400 * 400);
        let all = d.all_rays().rays.len();
        assert!((1_000_000..1_400_000).contains(&all), "{all} rays");
        assert!(d.description.contains("400×400"));
    }

    #[test]
    fn the_cornell_box_loads_with_the_studys_five_traces_and_names_fail_clearly() {
        let d = load("builtin:cornell").unwrap();
        assert_eq!(d.traces.len(), 5);
        assert_eq!(d.trace(0).unwrap().rays.len(), 256 * 256);
        assert_eq!(d.trace(1).unwrap().rays.len(), 256 * 256);
        assert!(d.trace(5).is_none());
        assert_eq!(effect_of(4), Some(Effect::Shadow));
        let all = d.all_rays();
        assert_eq!(
            all.rays.len(),
            d.traces.iter().map(|t| t.rays.len()).sum::<usize>()
        );
        assert_eq!(effect_of(3), Some(Effect::AmbientOcclusion));
        let e = load("builtin:nosuch").unwrap_err().to_string();
        assert!(e.contains("builtin:cornell, builtin:cornell-1m"), "{e}");
        let e = load("/nonexistent/scene.rayvis").unwrap_err().to_string();
        assert!(e.contains("scene.rayvis: no such file"), "{e}");
    }
}
