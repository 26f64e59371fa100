//! The sandbox's command-line options; the page reads the same names from its address.

use crate::cli::args::{CameraArgs, SettingsArgs, VolumeArgs, parse_size};
use clap::Args;
use std::path::PathBuf;

/// Options of the sandbox itself (no subcommand).
#[derive(Args, Debug, Clone)]
pub struct SandboxArgs {
    #[command(flatten)]
    pub volume: VolumeArgs,
    #[command(flatten)]
    pub settings: SettingsArgs,
    #[command(flatten)]
    pub camera: CameraArgs,
    #[command(flatten)]
    pub cpu: crate::cli::args::CpuArgs,
    /// Render the preview of this view once, save it to this PNG and exit (no window needed).
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// With --screenshot DIR: one picture per method × step (1, ½ voxel) × shading (off, on),
    /// named like `accumulate_step0.5_shaded.png` (the GPU/CPU agreement test uses this).
    #[arg(long, requires = "screenshot")]
    pub sweep: bool,
    /// With --screenshot FILE: first time this many frames of the preview drawn at full
    /// quality and the full size (no window, so a frame is the volume's), print their median
    /// and then capture — a frame to set beside another renderer's offscreen frame.
    #[arg(long, requires = "screenshot", conflicts_with = "sweep")]
    pub time_frames: Option<u32>,
    /// Capture the preview of this view and render the same view on the CPU (what the "Render
    /// image" button does), save the render here, the capture and the difference heat-map
    /// beside it (NAME_preview.png, NAME_diff.png), print the differences and exit.
    #[arg(long, conflicts_with_all = ["screenshot", "measure_frames"])]
    pub compare: Option<PathBuf>,
    /// Measure the preview's frame time over this many frames (after a warm-up), print it and
    /// exit.
    #[arg(long, conflicts_with = "screenshot")]
    pub measure_frames: Option<u32>,
    /// With --measure-frames: orbit the camera this many degrees a frame (engages adaptive
    /// quality). With --time-frames: turn the offscreen view this much each timed frame (full
    /// quality; the picture is then taken where the orbit ends).
    #[arg(long, default_value_t = 0.0)]
    pub auto_orbit: f32,
    /// With --measure-frames: turn adaptive quality off.
    #[arg(long, requires = "measure_frames")]
    pub no_adaptive: bool,
    /// With --measure-frames: draw the GPU preview's resting view whole every frame, never in
    /// strips — the window waits for each full-quality frame, so its frame time is what one
    /// costs (to compare with another renderer's frame).
    #[arg(long, requires = "measure_frames")]
    pub whole_frames: bool,
    /// Measure this knob's trade as the "Speed against accuracy" panel's Measure does (a
    /// preview's knob timed as the preview's own images in this window), print its table and
    /// exit.
    #[arg(long, value_name = "KNOB", value_parser = parse_knob,
          conflicts_with_all = ["screenshot", "compare", "measure_frames", "play_levels"])]
    pub measure_knob: Option<voxcast_core::knob::Knob>,
    /// Let preview rays pass through scene geometry (the light's marker) instead of stopping
    /// at it (the depth prepass is ignored).
    #[arg(long)]
    pub no_depth_termination: bool,
    /// The virtual camera's pixels across and down (one ray each).
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub rays: u32,
    /// Start with the virtual camera, its rays and samples hidden (the preview alone; they can
    /// be shown from the panel).
    #[arg(long)]
    pub no_rays: bool,
    /// The most sample spheres shown for the virtual camera's rays (see the Rays panel).
    #[arg(long, default_value_t = voxcast_core::tunables::SAMPLE_BUDGET.default as usize)]
    pub sample_budget: usize,
    /// Play every level to the end in the window as a player would (with --levels, only the
    /// levels added), save a screenshot of each level's first step in this folder (with the
    /// progress file and report.txt) and exit; the exit code says whether every objective
    /// behaved.
    #[arg(long, conflicts_with_all = ["screenshot", "compare", "measure_frames"])]
    pub play_levels: Option<PathBuf>,
    /// With --play-levels: play only the levels numbered FIRST to LAST in the levels list
    /// (`3-7`; `12-` to the end), so that a long play-through can run in parts side by side.
    #[arg(long, value_name = "FIRST-LAST", requires = "play_levels", value_parser = parse_level_range)]
    pub play_range: Option<std::ops::RangeInclusive<usize>>,
    /// Add the levels in this file, or in the .json files of this folder, to the levels list
    /// (after the built-in ones); a file with errors is left out and said why (`voxcast
    /// levels check PATH` prints every problem).
    #[arg(long, value_name = "PATH", conflicts_with_all = ["screenshot", "compare"])]
    pub levels: Option<PathBuf>,
    /// Play the level a link holds (the page's address with #level=…, as the level editor's
    /// Copy link makes it).
    #[arg(long, value_name = "URL", conflicts_with_all = ["screenshot", "compare", "play_levels"])]
    pub link: Option<String>,
    /// Start with this level (its id, as `voxcast answers` lists them, or its number in the
    /// levels list) as a study: played to its end with the preview off, then again with it on;
    /// each run's answers are kept with the run's name.
    #[arg(long, value_name = "LEVEL", conflicts_with_all = ["screenshot", "compare", "measure_frames", "play_levels"])]
    pub study: Option<String>,
    #[arg(long, help = voxcast_core::tunables::PREVIEW_SCALE.doc, value_parser = parse_preview_scale)]
    pub preview_scale: Option<f32>,
    #[arg(long, help = voxcast_core::tunables::PREVIEW_BACKEND.doc, value_parser = ["gpu", "cpu"])]
    pub preview_backend: Option<String>,
    /// Window or screenshot size in pixels (default 1280x720; without it, a window larger than
    /// the screen is made smaller to fit).
    #[arg(long, value_parser = parse_size)]
    pub size: Option<(u32, u32)>,
    /// With a ray density as the volume (`--volume density:…`): also draw its rays as lines
    /// (`mesh`) or its vector field (`field`); repeat for both.
    #[arg(long, value_parser = ["mesh", "field"])]
    pub ray_view: Vec<String>,
    #[arg(long, help = voxcast_core::tunables::RAY_STRIDE.doc)]
    pub ray_stride: Option<usize>,
    #[arg(long, help = voxcast_core::tunables::SAMPLE_CUBE.doc)]
    pub ray_cube: Option<u32>,
    #[arg(long, help = voxcast_core::tunables::FIELD_MIN_COUNT.doc)]
    pub ray_min_count: Option<u64>,
    /// With `--ray-view mesh`: mark each ray's start with a cross and its end with an
    /// arrowhead.
    #[arg(long)]
    pub ray_glyphs: bool,
}

/// `--preview-scale`: a fraction within the tunable's range.
fn parse_knob(s: &str) -> Result<voxcast_core::knob::Knob, String> {
    use voxcast_core::knob::Knob;
    Knob::parse(s).ok_or_else(|| {
        let names: Vec<_> = Knob::ALL.iter().map(|k| k.name()).collect();
        format!("give one of {}", names.join(", "))
    })
}

/// Levels numbered `FIRST-LAST` (from 1; `FIRST-` runs to the end), as indices in the list.
fn parse_level_range(s: &str) -> Result<std::ops::RangeInclusive<usize>, String> {
    let words = "give the levels' numbers as FIRST-LAST (3-7) or FIRST- (to the end), from 1";
    let (first, last) = s.split_once('-').ok_or(words)?;
    let first: usize = first.trim().parse().map_err(|_| words)?;
    let last: usize = match last.trim() {
        "" => usize::MAX,
        n => n.parse().map_err(|_| words)?,
    };
    if first == 0 || last < first {
        return Err(words.into());
    }
    Ok(first - 1..=last - 1)
}

fn parse_preview_scale(s: &str) -> Result<f32, String> {
    let t = &voxcast_core::tunables::PREVIEW_SCALE;
    match s.parse::<f32>() {
        Ok(v) if (t.min..=t.max).contains(&v) => Ok(v),
        _ => Err(format!("give a number from {} to {}", t.min, t.max)),
    }
}

#[cfg(test)]
mod tests {
    use super::parse_level_range;

    #[test]
    fn a_range_of_levels_is_read_from_one_and_checked() {
        assert_eq!(parse_level_range("3-7"), Ok(2..=6));
        assert_eq!(parse_level_range("12-"), Ok(11..=usize::MAX - 1));
        assert_eq!(parse_level_range(" 1 - 1 "), Ok(0..=0));
        for bad in ["", "7", "0-3", "5-2", "a-b", "-4", "1-x"] {
            assert!(parse_level_range(bad).is_err(), "{bad}");
        }
    }
}
