//! The preview's settings as every feature reads them: who draws the volume (the GPU preview or
//! the CPU live view), its resolution and step for slow hardware, whether the view is moving,
//! and the image it renders into. The systems that act on them are in `preview/`.

use bevy::prelude::*;
use voxcast_core::tunables as t;

/// Which renderer draws the volume in the window (documented in
/// `voxcast_core::tunables::PREVIEW_BACKEND`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Backend {
    /// The GPU preview, the WGSL twin of the core.
    #[default]
    Gpu,
    /// The core itself on background threads: exact at rest, progressive.
    Cpu,
}

impl Backend {
    /// Its name in words.
    pub fn words(self) -> &'static str {
        match self {
            Backend::Gpu => "GPU preview",
            Backend::Cpu => "CPU live view",
        }
    }

    /// The backend for an adapter: the CPU where the "GPU" is a software rasterizer.
    pub fn for_adapter(name: &str, device_type: &str) -> Self {
        let name = name.to_ascii_lowercase();
        let software = device_type == "Cpu"
            || [
                "llvmpipe",
                "lavapipe",
                "softpipe",
                "swiftshader",
                "basic render driver",
            ]
            .iter()
            .any(|s| name.contains(s));
        if software { Backend::Cpu } else { Backend::Gpu }
    }
}

/// An adapter's name and kind (`DeviceType` in words) as [`Backend::for_adapter`] reads them:
/// wgpu's, or in a browser's WebGPU, where wgpu names no adapter, the browser's own name for it
/// (`browser`: the name, and whether it is the browser's fallback adapter — a software
/// rasterizer, counted as a CPU).
pub fn adapter_identity(
    name: &str,
    device_type: &str,
    browser: Option<&(String, bool)>,
) -> (String, String) {
    match browser {
        Some((browser_name, fallback)) if name.is_empty() => (
            browser_name.clone(),
            if *fallback { "Cpu" } else { device_type }.to_string(),
        ),
        _ => (name.to_string(), device_type.to_string()),
    }
}

/// How the preview trades quality for speed (each documented in `voxcast_core::tunables`).
#[derive(Resource, Clone, PartialEq, Debug)]
pub struct PreviewSettings {
    pub enabled: bool,
    /// Who draws the volume: the GPU preview or the CPU live view.
    pub backend: Backend,
    /// The backend was chosen by the user (the command line), not from the adapter.
    pub backend_chosen: bool,
    pub scale: f32,
    pub step_multiplier: f32,
    pub adaptive: bool,
    pub moving_scale: f32,
    pub moving_step_multiplier: f32,
    /// What the preview shows: the picture (`None`) or what its rays cost, counted by the core
    /// (the CPU live view draws it, whichever backend draws the picture).
    pub cost_view: Option<voxcast_core::cost::CostView>,
}

/// Whether the GPU preview can read the depth prepass. WebGL2 cannot read a depth texture in a
/// shader (its GLSL has no fetch from one), so there the main camera has no depth prepass, the
/// preview is compiled without `DEPTH_PREPASS` (the shader def that turns the reading off) and
/// its rays pass through the scene's meshes, which are drawn over it; the CPU live view and
/// Render image still stop at them.
pub const GPU_READS_DEPTH: bool = !cfg!(all(target_arch = "wasm32", feature = "webgl2"));

impl Default for PreviewSettings {
    fn default() -> Self {
        Self {
            enabled: true,
            backend: Backend::Gpu,
            backend_chosen: false,
            scale: t::PREVIEW_SCALE.default,
            step_multiplier: t::PREVIEW_STEP_MULTIPLIER.default,
            adaptive: t::ADAPTIVE_QUALITY.default != 0.0,
            moving_scale: t::MOVING_SCALE.default,
            moving_step_multiplier: t::MOVING_STEP_MULTIPLIER.default,
            cost_view: None,
        }
    }
}

impl PreviewSettings {
    /// Whether the CPU live view draws the volume (the preview is on and drawn by the CPU, or
    /// shows a cost view: the core counts what each ray did).
    pub fn cpu_live(&self) -> bool {
        self.enabled && (self.backend == Backend::Cpu || self.cost_view.is_some())
    }

    /// Whether the GPU preview draws the volume (the preview is on, drawn by the GPU, and
    /// shows the picture).
    pub fn gpu_live(&self) -> bool {
        self.enabled && self.backend == Backend::Gpu && self.cost_view.is_none()
    }

    /// The resolution fraction and step multiplier in effect; `full` asks for the settings'
    /// own step at the resting resolution (while a comparison captures the preview).
    pub fn effective(&self, moving: bool, full: bool) -> (f32, f32) {
        if full {
            (self.scale, 1.0)
        } else if self.adaptive && moving {
            (
                self.moving_scale.min(self.scale),
                self.moving_step_multiplier.max(self.step_multiplier),
            )
        } else {
            (self.scale, self.step_multiplier)
        }
    }
}

/// Whether the view changed in the last moments.
#[derive(Resource, Default, Clone, Copy, PartialEq)]
pub struct Motion {
    pub moving: bool,
    /// When the view last changed, seconds since start (`preview::paint` keeps it).
    pub last_change: f32,
}

/// Set while the preview must draw at full quality whatever the motion and step multiplier
/// (a comparison with the CPU render is capturing it).
#[derive(Resource, Default, Clone, Copy, PartialEq)]
pub struct FullQuality(pub bool);

/// `size` pixels at `scale` of each edge, rounded, at least one pixel: the preview's target
/// and the CPU live view's resting frame for a resolution fraction.
pub fn scaled_size(size: UVec2, scale: f32) -> UVec2 {
    (size.as_vec2() * scale).round().as_uvec2().max(UVec2::ONE)
}

/// The image the main camera renders into, and its size in pixels.
#[derive(Resource)]
pub struct PreviewTarget {
    pub image: Handle<Image>,
    pub size: UVec2,
}
