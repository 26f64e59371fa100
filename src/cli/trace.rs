//! `voxcast trace`: one ray's full calculation, as JSON, CSV or a readable table.

use super::CliError;
use super::args::{CameraArgs, SettingsArgs, VolumeArgs, parse_size, parse_vec3};
use clap::Args;
use voxcast_core::breakdown;
use voxcast_core::glam::Vec3;
use voxcast_core::ray::Ray;
use voxcast_core::trace::{Scene, trace_ray};

#[derive(Args, Debug)]
pub struct TraceArgs {
    #[command(flatten)]
    pub volume: VolumeArgs,
    #[command(flatten)]
    pub settings: SettingsArgs,
    #[command(flatten)]
    pub camera: CameraArgs,
    /// Ray origin x,y,z (see --space).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, requires = "dir", conflicts_with = "pixel")]
    pub origin: Option<Vec3>,
    /// Ray direction x,y,z (normalised for you; see --space).
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true, requires = "origin")]
    pub dir: Option<Vec3>,
    /// Space of --origin and --dir: world units, or voxels (voxel (i,j,k) at (i,j,k)).
    #[arg(long, default_value = "world", value_parser = ["world", "voxel"])]
    pub space: String,
    /// Instead of --origin/--dir: the ray through pixel X,Y of the camera's image (--size).
    #[arg(long, value_name = "X,Y")]
    pub pixel: Option<String>,
    /// Image size for --pixel.
    #[arg(long, default_value = "512x512", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Explain sample K (its compositing and, with shading on, its shading term by term)
    /// instead of the last one; First explains its hit.
    #[arg(long, value_name = "K")]
    pub sample: Option<usize>,
    /// Print the breakdown as JSON.
    #[arg(long, conflicts_with = "csv")]
    pub json: bool,
    /// Print the breakdown as CSV (one row per sample).
    #[arg(long)]
    pub csv: bool,
}

pub fn run(a: &TraceArgs) -> Result<(), CliError> {
    let loaded = a.volume.load()?;
    let resolved = a.settings.resolve(&loaded)?;
    for note in &resolved.notes {
        eprintln!("note: {note}");
    }
    let spacing = loaded.volume.spacing();
    let (ray, key, forward) = match (&a.pixel, a.origin, a.dir) {
        (Some(p), _, _) => {
            let (x, y) = p
                .split_once(',')
                .and_then(|(x, y)| {
                    Some((x.trim().parse::<u32>().ok()?, y.trim().parse::<u32>().ok()?))
                })
                .ok_or_else(|| CliError::usage(format!("--pixel '{p}': expected X,Y")))?;
            let (w, h) = a.size;
            if x >= w || y >= h {
                return Err(CliError::usage(format!(
                    "--pixel {x},{y} lies outside the {w}×{h} image"
                )));
            }
            let camera = a.camera.camera(&loaded, resolved.preset.as_ref())?;
            (camera.pixel_ray(x, y, w, h), [x, y], camera.forward())
        }
        (None, Some(o), Some(d)) => {
            let (o, d) = if a.space == "voxel" {
                (o * spacing, d * spacing)
            } else {
                (o, d)
            };
            let ray = Ray::new(o, d)
                .ok_or_else(|| CliError::usage("--dir must be a non-zero direction".to_string()))?;
            (ray, [0, 0], ray.dir)
        }
        _ => return Err(CliError::usage("give --origin and --dir, or --pixel")),
    };
    let scene = Scene::new(
        &loaded.volume,
        &resolved.transfer,
        &resolved.settings,
        forward,
    )?;
    let trace = trace_ray(&scene, &ray, key);
    if a.json {
        println!("{}", breakdown::to_json(&trace));
    } else if a.csv {
        print!("{}", breakdown::to_csv(&trace));
    } else {
        print_table(&trace, a.sample);
    }
    Ok(())
}

fn print_table(t: &voxcast_core::trace::RayTrace, sample: Option<usize>) {
    println!(
        "ray from ({:.4}, {:.4}, {:.4}) along ({:.5}, {:.5}, {:.5}), {}",
        t.origin[0],
        t.origin[1],
        t.origin[2],
        t.dir[0],
        t.dir[1],
        t.dir[2],
        t.method.name()
    );
    match (t.interval, t.plan) {
        (Some([a, b]), Some(p)) => println!(
            "enters at t = {a:.5}, leaves at t = {b:.5}; {} samples every {:.5} (jitter {:.4}){}",
            p.count,
            p.dt,
            p.jitter,
            if p.capped { ", capped" } else { "" }
        ),
        _ => println!("{}", t.stop.words()),
    }
    if let Some(cut) = t.cut_words() {
        println!("{cut}");
    }
    if t.samples.is_empty() {
        println!("no samples");
    } else {
        println!(
            "{:>5} {:>10} {:>26} {:>12} {:>34} {:>9} {:>9} {:>34}",
            "k", "t", "position (world)", "value", "TF rgba", "alpha", "alpha'", "C rgb, O after"
        );
    }
    for s in &t.samples {
        println!(
            "{:>5} {:>10.5} ({:>7.3}, {:>7.3}, {:>7.3}) {:>12.5} ({:.4}, {:.4}, {:.4}, {:.4}) {:>9.6} {:>9.6} ({:.5}, {:.5}, {:.5}, {:.5})",
            s.index,
            s.t,
            s.p_world[0],
            s.p_world[1],
            s.p_world[2],
            s.reconstruction.value,
            s.tf_rgba[0],
            s.tf_rgba[1],
            s.tf_rgba[2],
            s.tf_rgba[3],
            s.alpha,
            s.alpha_corrected,
            s.composite_after[0],
            s.composite_after[1],
            s.composite_after[2],
            s.composite_after[3],
        );
    }
    if let Some(h) = &t.first_hit {
        println!(
            "first hit at t = {:.6}, ({:.4}, {:.4}, {:.4}), value {:.5}, bracket [{:.5}, {:.5}], {} refinement steps",
            h.t,
            h.p_world[0],
            h.p_world[1],
            h.p_world[2],
            h.value,
            h.bracket[0],
            h.bracket[1],
            h.refinement.len().saturating_sub(1)
        );
    }
    if let Some(v) = t.projected_value {
        println!("projected value: {v:.6}");
    }
    println!(
        "stopped: {}; pixel ({:.5}, {:.5}, {:.5}), opacity {:.5}",
        t.stop.words(),
        t.pixel[0],
        t.pixel[1],
        t.pixel[2],
        t.opacity
    );
    println!();
    println!("{}", voxcast_core::explain::formula(t, sample));
    // The shading of the sample explained (or of First's hit), term by term.
    let shaded = match &t.first_hit {
        Some(h) => h.shading.map(|terms| (terms, h.tf_rgba, h.color)),
        None => sample
            .or(t.samples.len().checked_sub(1))
            .and_then(|k| t.samples.get(k))
            .and_then(|s| s.shading.map(|terms| (terms, s.tf_rgba, s.color))),
    };
    if let Some((terms, [r, g, b, _], color)) = shaded {
        println!();
        println!(
            "{}",
            voxcast_core::explain::shading(&terms, [r, g, b], color)
        );
    }
}
