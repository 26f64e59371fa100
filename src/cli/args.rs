//! The scene options every command shares (volume, transfer function, settings, camera), and how
//! they become a core scene. Help texts are the core's tunable docs ([`voxcast_core::tunables`]).

use super::CliError;
use clap::Args;
use std::path::{Path, PathBuf};
use voxcast_core::camera::{Camera, Projection};
use voxcast_core::clip::ClipPlane;
use voxcast_core::composite::{Method, Order};
use voxcast_core::error::io_words;
use voxcast_core::glam::Vec3;
use voxcast_core::io::raw::{RawSpec, parse_dims};
use voxcast_core::io::{Endian, FileType, Loaded};
use voxcast_core::preset::{self, Preset};
use voxcast_core::sample::Interpolation;
use voxcast_core::settings::RenderSettings;
use voxcast_core::shade::{Highlight, Light, LightSource, SpecularModel};
use voxcast_core::step::Length;
use voxcast_core::transfer::TransferFunction;
use voxcast_core::tunables as t;
use voxcast_core::{Prepared, builtin, peer};

mod parse;
pub use parse::*;

/// Where the volume comes from.
#[derive(Args, Debug, Clone)]
pub struct VolumeArgs {
    /// A volume file (.nrrd, .nhdr, .nii, .nii.gz, .hdr, .raw) or builtin:NAME (bunny,
    /// brainsmall, shells, marschner-lobb, bucky, blobs, head, voxel, masked).
    #[arg(long, default_value = "builtin:bunny")]
    pub volume: String,
    /// Raw files: dimensions NXxNYxNZ (overrides the file name).
    #[arg(long, value_name = "NXxNYxNZ")]
    pub dims: Option<String>,
    /// Raw files: scalar type (uint8, int16, uint16, float32, …; overrides the file name).
    #[arg(long = "type", value_name = "TYPE")]
    pub scalar_type: Option<String>,
    /// Raw files: byte order.
    #[arg(long, value_parser = ["little", "big"])]
    pub endian: Option<String>,
    /// Raw files: spacing sx,sy,sz in world units.
    #[arg(long, value_name = "SX,SY,SZ", value_parser = parse_vec3)]
    pub spacing: Option<Vec3>,
    /// Raw files: bytes to skip before the data.
    #[arg(long, default_value_t = 0)]
    pub header_bytes: u64,
}

/// A volume read for a command: ready to render (its caches kept across the command's
/// renders), with what the reader noted.
pub struct Opened {
    pub volume: Prepared,
    pub notes: Vec<String>,
}

impl From<Loaded> for Opened {
    fn from(Loaded { volume, notes }: Loaded) -> Self {
        Self {
            volume: volume.into(),
            notes,
        }
    }
}

impl VolumeArgs {
    /// Loads the volume, applying the raw-file options.
    pub fn load(&self) -> Result<Opened, CliError> {
        Ok(self.read()?.into())
    }

    fn read(&self) -> Result<Loaded, CliError> {
        let raw_options = self.dims.is_some()
            || self.scalar_type.is_some()
            || self.endian.is_some()
            || self.spacing.is_some()
            || self.header_bytes > 0;
        if raw_options && !self.volume.starts_with("builtin:") {
            let path = Path::new(&self.volume);
            let mut spec = RawSpec::from_file_name(path).unwrap_or(RawSpec {
                dims: [0; 3],
                ty: FileType::U8,
                endian: Endian::Little,
                spacing: Vec3::ONE,
                header_bytes: 0,
            });
            if let Some(d) = &self.dims {
                spec.dims = parse_dims(d).ok_or_else(|| {
                    CliError::usage(format!("--dims '{d}': expected NXxNYxNZ, e.g. 256x256x113"))
                })?;
            }
            if let Some(ty) = &self.scalar_type {
                spec.ty = FileType::parse(ty).ok_or_else(|| {
                    CliError::usage(format!("--type '{ty}': unknown scalar type"))
                })?;
            }
            if self.endian.as_deref() == Some("big") {
                spec.endian = Endian::Big;
            }
            if let Some(s) = self.spacing {
                spec.spacing = s;
            }
            spec.header_bytes = self.header_bytes;
            if spec.dims == [0; 3] {
                return Err(CliError::usage(format!(
                    "{}: give --dims and --type, or name the file like 'name_256x256x113_uint16.raw'",
                    self.volume
                )));
            }
            return Ok(voxcast_core::io::raw::load(path, &spec)?);
        }
        Ok(builtin::load_source(&self.volume)?)
    }
}

/// Transfer function and render settings.
#[derive(Args, Debug, Clone, Default)]
pub struct SettingsArgs {
    /// Transfer function: a preset name (bunny, brainsmall, brainsmall-projections, shells,
    /// marschner-lobb, bucky, voxel, head, head-brain, blobs, masked, ct_skin_bone, mri_brain;
    /// inferno, matplotlib's colour map over the volume's values, for Sum), a Voxcast preset or
    /// transfer-function JSON file, or a peer TF JSON (../shared/tools/peer/tf/*.json).
    /// Default: the volume's preset.
    #[arg(long)]
    pub tf: Option<String>,
    /// Render settings as JSON (RenderSettings fields), applied before the flags below.
    #[arg(long, value_name = "FILE")]
    pub settings: Option<PathBuf>,
    /// Compositing method (default accumulate).
    #[arg(long, value_parser = method_parser())]
    pub method: Option<Method>,
    #[arg(long, help = t::STEP.doc, allow_negative_numbers = true)]
    pub step: Option<f32>,
    /// Step in world units instead of voxels (overrides --step).
    #[arg(long, value_name = "W", allow_negative_numbers = true)]
    pub step_world: Option<f32>,
    #[arg(long, help = t::REFERENCE_STEP.doc, allow_negative_numbers = true)]
    pub reference_step: Option<f32>,
    /// Turn opacity correction off (see --reference-step).
    #[arg(long)]
    pub no_opacity_correction: bool,
    #[arg(long, help = t::CUTOFF.doc, allow_negative_numbers = true)]
    pub cutoff: Option<f32>,
    /// Turn early ray termination off.
    #[arg(long)]
    pub no_early_termination: bool,
    /// Turn empty-space skipping off (the image stays the same; only the time changes).
    #[arg(long)]
    pub no_skipping: bool,
    /// Accumulate's sample order.
    #[arg(long, value_parser = ["front-to-back", "back-to-front"])]
    pub order: Option<String>,
    #[arg(long, help = t::JITTER.doc)]
    pub jitter: bool,
    /// Seed of the jitter pattern.
    #[arg(long)]
    pub jitter_seed: Option<u32>,
    #[arg(long, help = t::TARGET.doc, allow_negative_numbers = true)]
    pub target: Option<f32>,
    #[arg(long, help = t::SUM_RANGE.doc, value_name = "LOW,HIGH", value_parser = parse_range, allow_negative_numbers = true)]
    pub sum_range: Option<(f32, f32)>,
    #[arg(long, help = t::REFINE_STEPS.doc, allow_negative_numbers = true)]
    pub refine_steps: Option<u32>,
    /// Reconstruction between lattice points.
    #[arg(long, value_parser = ["nearest", "trilinear"])]
    pub interpolation: Option<String>,
    #[arg(long, help = t::MAX_SAMPLES.doc, allow_negative_numbers = true)]
    pub max_samples: Option<u32>,
    #[arg(long, help = t::SUPERSAMPLING.doc, allow_negative_numbers = true)]
    pub supersampling: Option<u32>,
    #[arg(long, help = t::SHADING.doc, value_parser = ["on", "off"])]
    pub shading: Option<String>,
    #[arg(long, help = t::AMBIENT.doc, allow_negative_numbers = true)]
    pub ka: Option<f32>,
    #[arg(long, help = t::DIFFUSE.doc, allow_negative_numbers = true)]
    pub kd: Option<f32>,
    #[arg(long, help = t::SPECULAR.doc, allow_negative_numbers = true)]
    pub ks: Option<f32>,
    #[arg(long, help = t::SHININESS.doc, allow_negative_numbers = true)]
    pub shininess: Option<f32>,
    #[arg(long, help = t::ATTENUATION_CONSTANT.doc, allow_negative_numbers = true)]
    pub kc: Option<f32>,
    #[arg(long, help = t::ATTENUATION_LINEAR.doc, allow_negative_numbers = true)]
    pub kl: Option<f32>,
    #[arg(long, help = t::ATTENUATION_QUADRATIC.doc, allow_negative_numbers = true)]
    pub kq: Option<f32>,
    #[arg(long, help = t::EMISSION.doc, allow_negative_numbers = true)]
    pub ke: Option<f32>,
    #[arg(long, help = t::GLOBAL_AMBIENT.doc, allow_negative_numbers = true)]
    pub global_ambient: Option<f32>,
    #[arg(long, help = t::LIGHT_AMBIENT.doc, allow_negative_numbers = true)]
    pub light_ambient: Option<f32>,
    #[arg(long, help = t::SPOT_CUTOFF.doc, allow_negative_numbers = true)]
    pub spot_cutoff: Option<f32>,
    #[arg(long, help = t::SPOT_EXPONENT.doc, allow_negative_numbers = true)]
    pub spot_exponent: Option<f32>,
    #[arg(long, help = t::DEPTH_CUE.doc, value_parser = ["on", "off"])]
    pub depth_cue: Option<String>,
    #[arg(long = "depth-k1", help = t::DEPTH_CUE_CONSTANT.doc, allow_negative_numbers = true)]
    pub depth_k1: Option<f32>,
    #[arg(long = "depth-k2", help = t::DEPTH_CUE_LINEAR.doc, allow_negative_numbers = true)]
    pub depth_k2: Option<f32>,
    /// A light: headlight, point:X,Y,Z (world position), dir:X,Y,Z (direction it shines
    /// along) or spot:X,Y,Z>DX,DY,DZ (a spot light at X,Y,Z shining along DX,DY,DZ), each
    /// optionally @R,G,B for its colour (linear, 0 … 1 or brighter); repeat for up to 4 lights,
    /// or none for ambient light only. kc, kl, kq and --light-ambient apply to every light,
    /// --spot-cutoff and --spot-exponent to every spot.
    #[arg(long, value_parser = parse_light)]
    pub light: Vec<Option<LightSource>>,
    /// The highlight's colour: white (OpenGL, VTK) or levoy (multiplied by the sample's colour,
    /// as Levoy's formula in the lecture).
    #[arg(long, value_parser = ["white", "levoy"])]
    pub highlight: Option<String>,
    #[arg(long, help = SpecularModel::SPECULAR_DOC, value_parser = ["phong", "blinn-phong"])]
    pub specular: Option<String>,
    #[arg(long, help = t::TWO_SIDED.doc, value_parser = ["on", "off"])]
    pub two_sided: Option<String>,
    #[arg(long, help = t::GRADIENT_THRESHOLD.doc, allow_negative_numbers = true)]
    pub gradient_threshold: Option<f32>,
    /// Classification: table, iso:V1,V2,…[@THICKNESS_VOXELS] (Levoy's isovalue contours),
    /// boundaries[@FULL_GRADIENT] (Levoy's region boundaries), or
    /// rects:F0,F1,G0,G1@OPACITY[/…] (up to 4 rectangles over value F0…F1 × gradient magnitude
    /// G0…G1, data units per world unit, each with its opacity; `voxcast info` draws that
    /// plane's histogram).
    #[arg(long, allow_hyphen_values = true)]
    pub classify: Option<String>,
    /// Background colour r,g,b in [0, 1].
    #[arg(long, value_parser = parse_vec3)]
    pub background: Option<Vec3>,
    /// Crop box: LO,HI for x, then y, then z, as fractions of the volume's extent
    /// (e.g. 0,1,0,1,0.5,1 keeps the upper half in z). Rays sample only inside it.
    #[arg(long, value_parser = parse_crop, value_name = "X0,X1,Y0,Y1,Z0,Z1")]
    pub crop: Option<(Vec3, Vec3)>,
    /// Clip plane: NX,NY,NZ@POSITION removes the side the normal points to; POSITION runs from
    /// −1 (removes everything) through 0 (the centre) to 1 (keeps all). @0 when left out.
    #[arg(long, value_parser = parse_clip_plane, allow_hyphen_values = true, value_name = "NX,NY,NZ@POSITION")]
    pub clip_plane: Option<ClipPlane>,
}

/// The transfer function and settings a run uses, with anything worth telling the user.
pub struct Resolved {
    pub transfer: TransferFunction,
    pub settings: RenderSettings,
    pub preset: Option<Preset>,
    pub notes: Vec<String>,
}

impl SettingsArgs {
    /// Picks the transfer function (flag, else the volume's preset, else a grey ramp) and applies
    /// preset, settings file and flags in that order.
    pub fn resolve(&self, loaded: &Opened) -> Result<Resolved, CliError> {
        let volume = &loaded.volume;
        let mut notes = loaded.notes.clone();
        let mut settings = RenderSettings::default();
        let mut preset = None;
        let transfer = match &self.tf {
            None => match preset::for_loaded(volume) {
                Some(p) => {
                    settings = p.settings_over(&settings)?;
                    let tf = p.transfer.clone();
                    preset = Some(p);
                    tf
                }
                None => {
                    let (lo, hi) = volume.value_range();
                    notes.push(
                        "no preset for this volume: a grey ramp transfer function is used".into(),
                    );
                    TransferFunction::ramp(lo, hi, 0.5)?
                }
            },
            Some(name) if name == voxcast_core::colormap::INFERNO_PRESET => {
                let (lo, hi) = volume.value_range();
                voxcast_core::colormap::inferno_transfer(lo, hi)
            }
            Some(name) => {
                if let Some(p) = preset::by_name(name) {
                    settings = p.settings_over(&settings)?;
                    let tf = p.transfer.clone();
                    preset = Some(p);
                    tf
                } else {
                    let text = std::fs::read_to_string(name).map_err(|e| {
                        CliError::usage(format!(
                            "--tf {name}: not a preset name, and cannot read it as a file: {}",
                            io_words(&e)
                        ))
                    })?;
                    if peer::is_peer_json(&text) {
                        let p = peer::from_json(&text)
                            .map_err(|e| CliError::usage(format!("{name}: {e}")))?;
                        p.apply(&mut settings);
                        notes.extend(p.notes.iter().cloned());
                        p.transfer
                    } else if text.contains("\"transfer\"") {
                        let p = Preset::from_json(&text)
                            .map_err(|e| CliError::usage(format!("{name}: {e}")))?;
                        settings = p.settings_over(&settings)?;
                        let tf = p.transfer.clone();
                        preset = Some(p);
                        tf
                    } else {
                        TransferFunction::from_json(&text)
                            .map_err(|e| CliError::usage(format!("{name}: {e}")))?
                    }
                }
            }
        };
        if let Some(path) = &self.settings {
            let text = std::fs::read_to_string(path).map_err(|e| {
                CliError::usage(format!("--settings {}: {}", path.display(), io_words(&e)))
            })?;
            let patch = Preset {
                name: path.display().to_string(),
                description: String::new(),
                volumes: vec![],
                view: None,
                transfer: transfer.clone(),
                settings: serde_json::from_str(&text)
                    .map_err(|e| CliError::usage(format!("--settings {}: {e}", path.display())))?,
            };
            settings = patch.settings_over(&settings)?;
        }
        self.apply_flags(&mut settings)?;
        settings.validate()?;
        Ok(Resolved {
            transfer,
            settings,
            preset,
            notes,
        })
    }

    fn apply_flags(&self, s: &mut RenderSettings) -> Result<(), CliError> {
        let on = |v: &Option<String>| v.as_deref().map(|v| v == "on");
        if let Some(m) = self.method {
            s.method = m;
        }
        if let Some(v) = self.step {
            s.step = Length::Voxels(v);
        }
        if let Some(v) = self.step_world {
            s.step = Length::World(v);
        }
        if let Some(v) = self.reference_step {
            s.reference_step = Length::Voxels(v);
        }
        if self.no_opacity_correction {
            s.opacity_correction = false;
        }
        if let Some(v) = self.cutoff {
            s.cutoff = v;
        }
        if self.no_early_termination {
            s.early_termination = false;
        }
        if self.no_skipping {
            s.skipping = false;
        }
        if let Some(o) = &self.order {
            s.order = if o == "back-to-front" {
                Order::BackToFront
            } else {
                Order::FrontToBack
            };
        }
        if self.jitter {
            s.jitter = true;
        }
        if let Some(v) = self.jitter_seed {
            s.jitter_seed = v;
        }
        if let Some(v) = self.target {
            s.target = Some(v);
        }
        if let Some(r) = self.sum_range {
            s.sum_range = Some(r);
        }
        if let Some(v) = self.refine_steps {
            s.refine_steps = v;
        }
        if let Some(i) = &self.interpolation {
            s.interpolation = if i == "nearest" {
                Interpolation::Nearest
            } else {
                Interpolation::Trilinear
            };
        }
        if let Some(v) = self.max_samples {
            s.max_samples = v;
        }
        if let Some(v) = self.supersampling {
            s.supersampling = v;
        }
        if let Some(v) = on(&self.shading) {
            s.shading = v;
        }
        let p = &mut s.phong;
        for (dst, src) in [
            (&mut p.ka, self.ka),
            (&mut p.kd, self.kd),
            (&mut p.ks, self.ks),
            (&mut p.shininess, self.shininess),
            (&mut p.gradient_threshold, self.gradient_threshold),
            (&mut p.ke, self.ke),
            (&mut p.global_ambient, self.global_ambient),
            (&mut p.depth_kc, self.depth_k1),
            (&mut p.depth_kl, self.depth_k2),
        ] {
            if let Some(v) = src {
                *dst = v;
            }
        }
        if !self.light.is_empty() {
            p.lights = self.light.iter().flatten().copied().collect();
        }
        for l in &mut p.lights {
            for (dst, src) in [
                (&mut l.kc, self.kc),
                (&mut l.kl, self.kl),
                (&mut l.kq, self.kq),
                (&mut l.ambient, self.light_ambient),
            ] {
                if let Some(v) = src {
                    *dst = v;
                }
            }
            if let Light::Spot(spot) = &mut l.light {
                spot.cutoff = self.spot_cutoff.unwrap_or(spot.cutoff);
                spot.exponent = self.spot_exponent.unwrap_or(spot.exponent);
            }
        }
        if let Some(v) = on(&self.depth_cue) {
            p.depth_cue = v;
        }
        if let Some(h) = &self.highlight {
            p.highlight = if h == "levoy" {
                Highlight::Levoy
            } else {
                Highlight::White
            };
        }
        if let Some(model) = SpecularModel::ALL
            .into_iter()
            .find(|m| self.specular.as_deref() == Some(m.name()))
        {
            p.model = model;
        }
        if let Some(v) = on(&self.two_sided) {
            p.two_sided = v;
        }
        if let Some(c) = &self.classify {
            s.classification = parse_classification(c)?;
        }
        if let Some(bg) = self.background {
            s.background = bg;
        }
        if let Some((lo, hi)) = self.crop {
            s.clip.crop_lo = lo;
            s.clip.crop_hi = hi;
        }
        if let Some(p) = self.clip_plane {
            s.clip.plane = Some(p);
        }
        Ok(())
    }
}

/// How the CPU renders.
#[derive(Args, Debug, Clone, Default)]
pub struct CpuArgs {
    /// Render as a CPU without the lanes' vector instructions does (an x86-64 without SSE 4.1,
    /// from before 2008, or one neither x86-64 nor 64-bit ARM): the eight-lane paths off,
    /// every sample one at a time — the same images, slower. For measuring what such a machine
    /// would see.
    #[arg(long, conflicts_with = "narrow_lanes")]
    pub no_lanes: bool,
    /// Render as an x86-64 CPU without AVX does (most low-cost laptops' Celeron and Pentium
    /// Silver up to 2021): the eight lanes in two halves of four (SSE 4.1) — the same images,
    /// a little slower. (On 64-bit ARM the lanes are NEON's, two halves of four, either way.)
    #[arg(long)]
    pub narrow_lanes: bool,
}

impl CpuArgs {
    /// Applies the options to the whole process (before any scene is built).
    pub fn apply(&self) {
        use voxcast_core::trace::Vectors;
        voxcast_core::trace::set_vectors(if self.no_lanes {
            Vectors::Off
        } else if self.narrow_lanes {
            Vectors::Narrow
        } else {
            Vectors::Wide
        });
    }
}

/// The camera options.
#[derive(Args, Debug, Clone, Default)]
pub struct CameraArgs {
    /// Camera: a JSON file ({"eye", "center", "up", "fov_y_deg"}, as ../shared/tools/peer/cams)
    /// or eye=X,Y,Z,target=X,Y,Z,up=X,Y,Z,fov=DEG[,ortho=HEIGHT]. Default: the preset's view.
    #[arg(long, allow_hyphen_values = true)]
    pub camera: Option<String>,
}

impl CameraArgs {
    /// The camera for `volume`: the flag, or a framing view from the preset's direction.
    pub fn camera(&self, loaded: &Opened, preset: Option<&Preset>) -> Result<Camera, CliError> {
        let (lo, hi) = loaded.volume.bounds();
        match &self.camera {
            None => {
                let (from, up) = preset
                    .and_then(|p| p.view)
                    .map_or((Vec3::new(1.0, 0.8, 1.6), Vec3::Y), |v| (v.from, v.up));
                Ok(Camera::framing(lo, hi, from, up)?)
            }
            Some(spec) if spec.contains('=') => parse_camera_spec(spec),
            Some(path) => {
                let text = std::fs::read_to_string(path)
                    .map_err(|e| CliError::usage(format!("--camera {path}: {}", io_words(&e))))?;
                Camera::from_json(&text)
                    .map_err(|e| CliError::usage(format!("--camera {path}: {e}")))
            }
        }
    }
}

/// `eye=1,2,3,target=0,0,0,up=0,1,0,fov=30` (a token with `=` starts a new key).
pub(crate) fn parse_camera_spec(spec: &str) -> Result<Camera, CliError> {
    let mut fields: Vec<(String, Vec<String>)> = Vec::new();
    for token in spec.split(',') {
        match token.split_once('=') {
            Some((k, v)) => fields.push((k.trim().to_owned(), vec![v.to_owned()])),
            None => match fields.last_mut() {
                Some(f) => f.1.push(token.to_owned()),
                None => {
                    return Err(CliError::usage(format!(
                        "--camera '{spec}': expected key=value pairs"
                    )));
                }
            },
        }
    }
    let get = |key: &str| fields.iter().find(|f| f.0 == key).map(|f| f.1.join(","));
    let vec = |key: &str, default: Option<Vec3>| -> Result<Vec3, CliError> {
        match get(key) {
            Some(v) => parse_vec3(&v).map_err(|e| CliError::usage(format!("--camera {key}: {e}"))),
            None => default
                .ok_or_else(|| CliError::usage(format!("--camera: '{key}=X,Y,Z' is required"))),
        }
    };
    let num = |key: &str| -> Result<Option<f32>, CliError> {
        get(key)
            .map(|v| {
                v.parse::<f32>()
                    .map_err(|_| CliError::usage(format!("--camera {key}: '{v}' is not a number")))
            })
            .transpose()
    };
    for (k, _) in &fields {
        if !["eye", "target", "center", "up", "fov", "ortho"].contains(&k.as_str()) {
            return Err(CliError::usage(format!(
                "--camera: unknown key '{k}' (eye, target, up, fov, ortho)"
            )));
        }
    }
    let eye = vec("eye", None)?;
    let target = match (get("target"), get("center")) {
        (None, Some(_)) => vec("center", None)?,
        _ => vec("target", None)?,
    };
    let projection = match num("ortho")? {
        Some(height) => Projection::Orthographic { height },
        None => Projection::Perspective {
            fov_y_deg: num("fov")?.unwrap_or(30.0),
        },
    };
    Ok(Camera::new(
        eye,
        target,
        vec("up", Some(Vec3::Y))?,
        projection,
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use voxcast_core::classify::Classification;

    #[test]
    fn camera_spec_parses_and_rejects() {
        let c = parse_camera_spec("eye=0,0,10,target=0,0,0,up=0,1,0,fov=45").unwrap();
        assert_eq!(c.eye, Vec3::new(0.0, 0.0, 10.0));
        assert_eq!(c.projection, Projection::Perspective { fov_y_deg: 45.0 });
        assert!(parse_camera_spec("eye=0,0,10,target=0,0,0,fov=x").is_err());
        assert!(parse_camera_spec("eye=0,0,10").is_err());
        assert!(parse_camera_spec("eye=0,0,10,target=0,0,0,zoom=2").is_err());
        let o = parse_camera_spec("eye=0,0,10,target=0,0,0,ortho=5").unwrap();
        assert_eq!(o.projection, Projection::Orthographic { height: 5.0 });
    }

    #[test]
    fn classification_and_small_parsers() {
        assert_eq!(
            parse_classification("table").unwrap(),
            Classification::Table
        );
        assert_eq!(
            parse_classification("iso:10,20@2").unwrap(),
            Classification::IsoContours {
                isovalues: vec![10.0, 20.0],
                thickness_voxels: 2.0
            }
        );
        assert!(parse_classification("iso:x").is_err());
        assert!(parse_classification("levoy").is_err());
        assert_eq!(parse_size("640x360").unwrap(), (640, 360));
        assert!(parse_size("0x10").is_err());
        assert!(parse_size("99999x10").is_err());
        assert!(parse_vec3("1,2").is_err());
        assert_eq!(parse_range("-1,2.5").unwrap(), (-1.0, 2.5));
        for bad in ["1", "2,1", "1,1", "1,inf", "a,b", "1,2,3", ""] {
            assert!(parse_range(bad).is_err(), "{bad} accepted");
        }
        assert!(parse_vec3("1,nan,2").is_err());
        assert!(parse_light("dir:0,0,0").is_err());
    }

    #[test]
    fn a_query_is_the_command_lines_options() {
        let same = |s: &str| s.to_owned();
        assert_eq!(
            query_to_args("?volume=builtin:head&no-rays&rays=8", same),
            ["--volume", "builtin:head", "--no-rays", "--rays", "8"]
        );
        assert_eq!(query_to_args("?tf=a+b", same), ["--tf", "a b"]);
        assert_eq!(query_to_args("?gpu=webgl2&no-rays", same), ["--no-rays"]);
        assert_eq!(
            query_to_args("?no-rays=&gpu=webgl2&fallback=webgpu", same),
            ["--no-rays"]
        );
        assert!(query_to_args("", same).is_empty());
        assert!(query_to_args("?", same).is_empty());
    }
}
