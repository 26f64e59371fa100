//! What the Ray data section computes next and how the views are drawn ([`RayChoices`]), the
//! computation it starts, the way back to the volume a density replaced, and what the views
//! show ([`ViewReport`]).

use crate::sandbox::data::loading::Loading;
use crate::sandbox::data::source::{Computed, RayScene, SourceKind};
use crate::sandbox::shared::render_change::{Author, ChangeRender};
use crate::sandbox::shared::schedule::Frame;
use crate::sandbox::shared::state::{RenderState, VolumeState};
use bevy::prelude::*;
use voxcast_core::level::RayDensityFacts;
use voxcast_core::rays::as_volume::{DensitySpec, finish_set, grid_for};
use voxcast_core::rays::data::RayData;
use voxcast_core::rays::density::{DensityParams, DensitySlices, density_in};
use voxcast_core::rays::field::ArrowScale;
use voxcast_core::rays::layered::SceneShading;
use voxcast_core::rays::mesh::TriangleScene;
use voxcast_core::scene::Scene;
use voxcast_core::tunables as t;

/// What the Ray data section computes next, and how the views are drawn.
#[derive(Resource, Clone, Debug, PartialEq)]
pub struct RayChoices {
    pub source: SourceKind,
    pub path: String,
    /// `None`: every trace.
    pub trace: Option<u32>,
    /// The grid and filter; `cell` 0: chosen from the scene (the volume's voxel for the
    /// virtual camera's rays).
    pub params: DensityParams,
    /// The virtual camera's rays across (and down, by its aspect).
    pub camera_side: u32,
    pub view: ViewChoices,
    /// Asked for the volume before the densities back (done by the next frame).
    pub back: bool,
}

impl Default for RayChoices {
    fn default() -> Self {
        Self {
            source: SourceKind::Cornell,
            path: String::new(),
            trace: None,
            params: DensityParams {
                cell: 0.0,
                ..DensityParams::default()
            },
            camera_side: t::RAY_CAMERA_SIDE.default as u32,
            view: ViewChoices::default(),
            back: false,
        }
    }
}

/// How RayVis's views are drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewChoices {
    pub volume: bool,
    pub mesh: bool,
    pub field: bool,
    /// The ray mesh draws every `stride`-th ray the filter passes.
    pub stride: usize,
    /// The ray mesh marks each ray's start (a cross) and end (an arrowhead).
    pub glyphs: bool,
    pub hit_colour: [f32; 3],
    pub miss_colour: [f32; 3],
    /// The vector field's sample cube, cells a side (divides the chunk).
    pub cube: u32,
    pub arrow_scale: ArrowScale,
    /// [`t::FIELD_MIN_COUNT`].
    pub min_count: u64,
    pub shading: SceneShading,
}

impl Default for ViewChoices {
    fn default() -> Self {
        Self {
            volume: true,
            mesh: false,
            field: false,
            stride: t::RAY_STRIDE.default as usize,
            glyphs: false,
            hit_colour: [1.0, 0.55, 0.1],
            miss_colour: [0.35, 0.7, 1.0],
            cube: t::SAMPLE_CUBE.default as u32,
            arrow_scale: ArrowScale::Count,
            min_count: t::FIELD_MIN_COUNT.default as u64,
            shading: SceneShading::Grey,
        }
    }
}

impl RayChoices {
    /// The density source the choices name (not for the virtual camera's rays).
    pub fn spec(&self) -> Option<DensitySpec> {
        let source = match (self.source, self.source.builtin()) {
            (_, Some(builtin)) => builtin.to_string(),
            (SourceKind::File, None) => self.path.trim().to_string(),
            _ => return None,
        };
        Some(DensitySpec {
            source,
            trace: self.trace,
            params: self.params,
        })
    }

    /// Starts computing the chosen density (a load, with progress and Cancel).
    pub fn compute(
        &self,
        loading: &mut Loading,
        rays: &RayScene,
        volume: &VolumeState,
        render: &RenderState,
        virtual_camera: Option<&crate::sandbox::inspect::virtual_camera::VirtualCamera>,
    ) {
        if let Some(spec) = self.spec() {
            if spec.source.is_empty() {
                loading.error = Some(if crate::sandbox::shared::files::PICKS_FILES {
                    "open a .rayvis file first (Open a .rayvis file…)".into()
                } else {
                    "give the path of a .rayvis file".into()
                });
                return;
            }
            loading.start_keeping_choices(spec.to_text());
            return;
        }
        // The virtual camera's rays go through the volume a density replaced, with its
        // settings and from where the first density's camera stood.
        let before = rays.on_show(volume).and(rays.before.as_ref());
        let (through, settings, camera) = match before {
            Some(b) => (
                b.volume.volume.clone(),
                b.render.clone(),
                b.camera.or(virtual_camera.map(|c| c.view)),
            ),
            None => (
                volume.volume.clone(),
                render.clone(),
                virtual_camera.map(|c| c.view),
            ),
        };
        let Some(camera) = camera else {
            loading.error = Some("there is no virtual camera to shoot the rays".into());
            return;
        };
        let aspect = virtual_camera.map_or(1.0, |c| c.height as f32 / c.width.max(1) as f32);
        let w = self
            .camera_side
            .clamp(1, voxcast_core::rays::camera::MAX_SIDE);
        let h = ((w as f32 * aspect).round() as u32).clamp(1, voxcast_core::rays::camera::MAX_SIDE);
        let mut params = self.params;
        if params.cell == 0.0 {
            params.cell = through.spacing().min_element();
        }
        let label = format!("the virtual camera's {w} × {h} rays");
        loading.run_async(label.clone(), false, move |progress, cancel| async move {
            let scene = Scene::plain(
                &through,
                &settings.transfer,
                &settings.settings,
                camera.forward(),
            )
            .map_err(|e| e.to_string())?;
            let set = voxcast_core::rays::camera::virtual_camera_rays(&scene, &camera, w, h);
            let data = RayData {
                description: label.clone(),
                scene: TriangleScene::default(),
                traces: vec![set.clone()],
            };
            // The counts in slices (a page's frames go on between them).
            let params = grid_for(&data, &set, params)?;
            let mut slices = DensitySlices::within(voxcast_core::rays::density::MAX_BYTES, &params);
            let report = |done, total| progress.set(done, total);
            let (density, _) = crate::sandbox::shared::tasks::in_slices(|deadline| {
                density_in(&set, &params, &mut slices, &report, &cancel, deadline)
            })
            .await
            .map_err(|_| "cancelled".to_string())?;
            let d = finish_set(data, set, &label, params, density)?;
            let facts = RayDensityFacts {
                source: "camera".into(),
                trace: None,
                side: w,
            };
            Ok(Computed::outcome(d, Some(camera), facts))
        });
    }
}

pub(crate) fn plugin(app: &mut App) {
    app.init_resource::<RayChoices>()
        .add_systems(Update, go_back.in_set(Frame::SwapVolume));
}

/// Brings back the volume (and its settings) the densities replaced.
fn go_back(
    mut choices: ResMut<RayChoices>,
    mut rays: ResMut<RayScene>,
    mut volume: ResMut<VolumeState>,
    mut change: MessageWriter<ChangeRender>,
) {
    if !choices.back {
        return;
    }
    choices.back = false;
    if let Some(b) = rays.before.take() {
        *volume = b.volume;
        change.write(ChangeRender::whole(Author::RayData, b.render));
        rays.current = None;
    }
}

/// What the views show, for the panel: lines and arrows drawn, rays left out.
#[derive(Resource, Default, Clone, Debug, PartialEq)]
pub struct ViewReport {
    pub lines: usize,
    pub arrows: usize,
    /// Rays of the filter that never entered the drawn box, or were malformed.
    pub left_out: usize,
    /// Why the vector field is not drawn.
    pub field_error: Option<String>,
    /// The line lists are being built.
    pub building: bool,
    /// Some line list is in the scene (as meshes the GPU's cameras draw).
    pub drawn: bool,
    /// While the view moves with the CPU live view, every n-th ray and arrow is drawn
    /// (`cpu_lines`).
    pub moving_every: Option<usize>,
}
