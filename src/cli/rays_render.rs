//! `voxcast rays render`: the ray density over its scene as a PNG — the density volume marched
//! with Sum, stopped at the scene, coloured by inferno and laid over the scene's shading
//! (`voxcast_core::rays::layered`), as the sandbox's Ray data view draws it.

use super::CliError;
use super::progress::Progress;
use super::rays_input::{GridArgs, SourceArg, check_folders, dense_density, grid_params, source};
use clap::Args;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use voxcast_core::camera::{Camera, Projection};
use voxcast_core::colormap::inferno_transfer;
use voxcast_core::composite::Method;
use voxcast_core::glam::Vec3;
use voxcast_core::numbers::sig;
use voxcast_core::rays::cornell;
use voxcast_core::rays::data::RayData;
use voxcast_core::rays::grid::DenseDensity;
use voxcast_core::rays::layered::{DensityView, SceneShading};
use voxcast_core::settings::RenderSettings;
use voxcast_core::step::Length;
use voxcast_core::trace::Scene;

#[derive(Args, Debug)]
pub struct RenderArgs {
    #[command(flatten)]
    pub source: SourceArg,
    #[command(flatten)]
    pub grid: GridArgs,
    /// Image size in pixels.
    #[arg(long, value_name = "WxH", default_value = "512x512", value_parser = super::args::parse_size)]
    pub size: (u32, u32),
    /// eye=X,Y,Z,target=X,Y,Z,up=X,Y,Z,fov=DEG[,ortho=HEIGHT] in world units. Default: the
    /// Cornell box's own camera for builtin:cornell, else the scene seen from the front.
    #[arg(long, value_name = "SPEC")]
    pub camera: Option<String>,
    /// Samples per cell along each ray (RayVis's "step size as fractions of the cell size"):
    /// the step is 1/K of a cell.
    #[arg(long, value_name = "K", default_value_t = 2.0)]
    pub samples_per_cell: f32,
    /// The Sum range (rays per cell times cells along a pixel's ray) spread over inferno.
    /// Default: fitted to the view, 0 to the sum that 95 % of a 32 × 32 grid of the view's
    /// rays (those that gather any) stay below.
    #[arg(long, value_name = "LOW,HIGH", value_parser = super::args::parse_range, allow_negative_numbers = true)]
    pub sum_range: Option<(f32, f32)>,
    /// How the scene is drawn under the density: grey (RayVis's default), colour (each mesh's
    /// own), instance (a colour per mesh instance), normals, barycentrics, or hidden (the
    /// density alone; meshes do not stop the rays).
    #[arg(long, default_value = "grey", value_parser = ["grey", "colour", "color", "instance", "normals", "barycentrics", "hidden"])]
    pub scene: String,
    /// The PNG to write.
    #[arg(long, value_name = "FILE.png")]
    pub out: PathBuf,
}

/// The most samples per cell accepted (a thousand already costs a thousand times one).
const MAX_SAMPLES_PER_CELL: f32 = 1000.0;

pub fn render(a: &RenderArgs) -> Result<(), CliError> {
    let params = grid_params(&a.grid, a.source.miss_tolerance)?;
    let k = a.samples_per_cell;
    if !(k.is_finite() && k > 0.0 && k <= MAX_SAMPLES_PER_CELL) {
        return Err(CliError::usage(format!(
            "--samples-per-cell {k}: must lie in (0, {MAX_SAMPLES_PER_CELL}]"
        )));
    }
    let shading = SceneShading::parse(&a.scene).unwrap_or_default();
    let given_camera = a
        .camera
        .as_deref()
        .map(super::args::parse_camera_spec)
        .transpose()?;
    check_folders([&a.out])?;
    let data = source(&a.source)?;
    let dense = dense_density(&data, &a.source.source, &params, &a.grid)?;
    let camera = match given_camera {
        Some(c) => c,
        None => default_camera(&a.source.source, &data, &dense)?,
    };
    let volume = voxcast_core::Prepared::from(
        dense
            .to_volume()
            .map_err(|e| CliError::failed(e.to_string()))?,
    );
    let (lo, hi) = volume.value_range();
    let mut settings = RenderSettings {
        method: Method::Sum,
        step: Length::Voxels(1.0 / k),
        sum_range: a.sum_range,
        early_termination: false,
        jitter: false,
        shading: false,
        background: Vec3::ZERO,
        ..RenderSettings::default()
    };
    let tf = inferno_transfer(lo, hi);
    let first = Scene::new(&volume, &tf, &settings, camera.forward())?;
    let view = |volume_scene| DensityView {
        volume_scene,
        origin: dense.origin(),
        triangles: &data.scene,
        shading,
        camera: &camera,
    };
    if a.sum_range.is_none() {
        let fitted = view(&first).fit_sum_range(a.size);
        settings.sum_range = Some(fitted.unwrap_or(first.sum_range));
    }
    let scene = Scene::new(&volume, &tf, &settings, camera.forward())?;
    let range = scene.sum_range;
    let progress = Progress::new("rendering");
    let started = Instant::now();
    let (image, stats) = view(&scene)
        .render(
            a.size,
            &|done, total| progress.update(done, total),
            &AtomicBool::new(false),
        )
        .map_err(|_| CliError::failed("cancelled"))?;
    progress.finish();
    let seconds = started.elapsed().as_secs_f64();
    image
        .save_png(&a.out)
        .map_err(|e| CliError::failed(format!("cannot write {}: {e}", a.out.display())))?;
    println!(
        "rendered {}×{} in {:.2} s ({} M samples/s): Sum of rays per cell from {} to {} over \
         inferno, {} samples per cell, scene {} → {}",
        a.size.0,
        a.size.1,
        seconds,
        sig((stats.samples as f64 / seconds.max(1e-9) / 1e6) as f32),
        sig(range.0),
        sig(range.1),
        sig(k),
        shading.name(),
        a.out.display()
    );
    if let Some(w) = stats.cap_warning(settings.max_samples) {
        println!("note: {w}");
    }
    Ok(())
}

/// The Cornell box's own camera for `builtin:cornell`; else the scene (or, without one, the
/// density's box) seen from −z, framed.
fn default_camera(name: &str, data: &RayData, dense: &DenseDensity) -> Result<Camera, CliError> {
    if name.starts_with("builtin:cornell") {
        return Ok(Camera::new(
            cornell::CAMERA_EYE,
            cornell::CAMERA_TARGET,
            Vec3::Y,
            Projection::Perspective {
                fov_y_deg: cornell::CAMERA_FOV_Y_DEG,
            },
        )?);
    }
    let (lo, hi) = data.scene.bounds().unwrap_or_else(|| {
        let lo = dense.first_cell.as_vec3() * dense.cell;
        (lo, lo + dense.dims.as_vec3() * dense.cell)
    });
    Ok(Camera::framing(lo, hi, Vec3::NEG_Z, Vec3::Y)?)
}
