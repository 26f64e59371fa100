//! RayVis in the sandbox: the ray data set behind the density on show (its scene, its rays,
//! the sparse grid with the mean directions), what the Ray data section computes next, and
//! how the views are drawn. The density itself is loaded like any volume
//! ([`super::loading`]); this keeps what it came from, so the scene, the ray mesh and the
//! vector field ([`super::rayviews`]) can be drawn around it, and the volume it replaced can
//! come back.

use super::loading::{Loading, Outcome};
use super::state::{RenderState, VolumeState};
use bevy::prelude::*;
use bevy::tasks::{AsyncComputeTaskPool, Task, futures::check_ready};
use std::sync::Arc;
use voxcast_core::camera::Camera as CoreCamera;
use voxcast_core::io::Loaded;
use voxcast_core::level::RayDensityFacts;
use voxcast_core::rays::as_volume::{DensitySpec, RayDensity, finish_set, grid_for, is_density};
use voxcast_core::rays::density::{Density, DensityParams, DensitySlices, density_in};
use voxcast_core::rays::field::ArrowScale;
use voxcast_core::rays::layered::SceneShading;
use voxcast_core::rays::mesh::TriangleScene;
use voxcast_core::rays::set::RaySet;
use voxcast_core::rays::source::RayData;
use voxcast_core::scene::Scene;
use voxcast_core::tunables as t;

/// What a density was computed from.
pub struct Computed {
    pub data: RayData,
    /// The rays of the chosen trace (or all), before the filter.
    pub set: RaySet,
    pub density: Density,
    /// Where the volume's voxel `(0, 0, 0)` lies in the rays' world.
    pub origin: Vec3,
    /// For the virtual camera's rays: the camera they were shot from.
    pub camera: Option<CoreCamera>,
    /// Where the rays came from, as the levels see it.
    pub facts: RayDensityFacts,
}

impl Computed {
    /// A finished density as a load's outcome: the volume to show and what it came from.
    pub fn outcome(d: RayDensity, camera: Option<CoreCamera>, facts: RayDensityFacts) -> Outcome {
        let RayDensity {
            data,
            set,
            density,
            origin,
            volume,
            words,
        } = d;
        Outcome {
            loaded: Loaded {
                volume,
                notes: vec![words],
            },
            rays: Some(Self {
                data,
                set,
                density,
                origin,
                camera,
                facts,
            }),
        }
    }
}

/// Computes the density a `density:…` source names, keeping what it came from: `None` when
/// `source` is not one, else the outcome or why not (the source's text first). Progress and
/// cancel as [`voxcast_core::rays::density::compute`].
pub fn compute_source(
    source: &str,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &std::sync::atomic::AtomicBool,
) -> Option<Result<Outcome, String>> {
    let parsed = voxcast_core::rays::as_volume::parse(source)?;
    Some(
        (|| {
            let spec = parsed?;
            let d = voxcast_core::rays::as_volume::compute_spec(&spec, progress, cancel)?;
            let facts = RayDensityFacts {
                source: spec.source.clone(),
                trace: spec.trace,
                side: 0,
            };
            Ok(Computed::outcome(d, None, facts))
        })()
        .map_err(|e: String| format!("{source}: {e}")),
    )
}

/// [`compute_source`] in slices, yielding to the page between them (`super::tasks`).
pub async fn compute_source_in_slices(
    source: &str,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &std::sync::atomic::AtomicBool,
) -> Option<Result<Outcome, String>> {
    let parsed = voxcast_core::rays::as_volume::parse(source)?;
    let computed = async {
        let spec = parsed?;
        let mut slices = voxcast_core::rays::as_volume::SpecSlices::default();
        let (d, _) = super::tasks::in_slices(|deadline| {
            voxcast_core::rays::as_volume::compute_spec_in(
                &spec,
                &mut slices,
                progress,
                cancel,
                deadline,
            )
        })
        .await?;
        let facts = RayDensityFacts {
            source: spec.source.clone(),
            trace: spec.trace,
            side: 0,
        };
        Ok(Computed::outcome(d, None, facts))
    };
    Some(computed.await.map_err(|e: String| format!("{source}: {e}")))
}

/// A density on show: what it came from, and its volume (the one [`VolumeState`] holds).
pub struct Shown {
    pub computed: Computed,
    pub volume: Arc<voxcast_core::Prepared>,
}

/// What was on show before the first density, to go back to (and, for the virtual camera's
/// rays, what they are shot through).
#[derive(Clone)]
pub struct Before {
    pub volume: VolumeState,
    pub render: RenderState,
    /// The virtual camera the first camera density was shot from.
    pub camera: Option<CoreCamera>,
}

/// The density on show and the volume before it.
#[derive(Resource, Default)]
pub struct RayScene {
    pub current: Option<Arc<Shown>>,
    pub before: Option<Before>,
}

impl RayScene {
    /// A load finished: `now` is on show, `before` was. A density keeps what it came from and,
    /// the first time, what was on show before it; any other volume forgets both.
    pub fn shown(&mut self, computed: Option<Computed>, now: &VolumeState, before: Before) {
        match computed {
            Some(c) => {
                if !is_density(&before.volume.volume) {
                    self.before = Some(Before {
                        camera: c.camera,
                        ..before
                    });
                }
                self.current = Some(Arc::new(Shown {
                    computed: c,
                    volume: now.volume.clone(),
                }));
            }
            None => *self = Self::default(),
        }
    }

    /// What the volume on show was computed from, when it is a density computed here.
    pub fn on_show(&self, volume: &VolumeState) -> Option<&Arc<Shown>> {
        self.current
            .as_ref()
            .filter(|s| Arc::ptr_eq(&s.volume, &volume.volume))
    }
}

/// Where the rays come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SourceKind {
    /// The embedded Cornell box and the rays Voxcast traces through it.
    #[default]
    Cornell,
    /// The same at 400 × 400 primary rays: about a million rays.
    CornellMillion,
    /// A `.rayvis` file.
    File,
    /// The virtual camera's rays through the volume.
    Camera,
}

impl SourceKind {
    pub const ALL: [SourceKind; 4] = [
        Self::Cornell,
        Self::CornellMillion,
        Self::Camera,
        Self::File,
    ];

    pub const fn words(self) -> &'static str {
        match self {
            Self::Cornell => "Cornell box (embedded)",
            Self::CornellMillion => "Cornell box, a million rays",
            Self::File => ".rayvis file",
            Self::Camera => "the virtual camera's rays",
        }
    }

    pub const fn doc(self) -> &'static str {
        match self {
            Self::Cornell => {
                "The Cornell box with RayVis's study's five traces, which Voxcast traces through \
                 it (seeded: the same every time): primary rays of two cameras, reflection, \
                 ambient-occlusion and shadow rays"
            }
            Self::CornellMillion => {
                "The Cornell box traced with 400 × 400 primary rays instead of 256 × 256: \
                 about 1.2 million rays in all, the scale RayVis's study drew (the density \
                 takes about a second)"
            }
            Self::File => "A ray data set saved by RayVis (or by voxcast rays export)",
            Self::Camera => {
                "The virtual camera's rays through the volume, with the settings on show: a \
                 ray 'hits' where it stopped early (opacity cutoff, or First's crossing), so \
                 the density shows how densely each method samples the grid"
            }
        }
    }
}

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
        let source = match self.source {
            SourceKind::Cornell => "builtin:cornell".to_string(),
            SourceKind::CornellMillion => "builtin:cornell-1m".to_string(),
            SourceKind::File => self.path.trim().to_string(),
            SourceKind::Camera => return None,
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
        virtual_camera: Option<&super::virtual_camera::VirtualCamera>,
    ) {
        if let Some(spec) = self.spec() {
            if spec.source.is_empty() {
                loading.error = Some("give the path of a .rayvis file".into());
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
            let (density, _) = super::tasks::in_slices(|deadline| {
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

pub(super) fn plugin(app: &mut App) {
    app.init_resource::<RayChoices>()
        .init_resource::<Estimator>()
        .init_resource::<RangeFit>()
        .add_systems(
            Update,
            (
                go_back.in_set(super::Frame::SwapVolume),
                (estimate, fit_range).in_set(super::Frame::Rules),
            ),
        );
}

/// Brings back the volume (and its settings) the densities replaced.
fn go_back(
    mut choices: ResMut<RayChoices>,
    mut rays: ResMut<RayScene>,
    mut volume: ResMut<VolumeState>,
    mut render: ResMut<RenderState>,
) {
    if !choices.back {
        return;
    }
    choices.back = false;
    if let Some(b) = rays.before.take() {
        *volume = b.volume;
        *render = b.render;
        rays.current = None;
    }
}

/// The memory a density would take, estimated before computing it (the rays are walked
/// through chunk-sized cells: which chunks would be stored). The data set is read once per
/// source and kept.
#[derive(Resource, Default)]
pub struct Estimator {
    /// The source, trace and grid the estimate is (or is being made) for.
    key: Option<DensitySpec>,
    /// The last data set read, by source.
    data: Option<(String, Arc<RayData>)>,
    task: Option<Task<EstimateResult>>,
    /// The last estimate, or why there is none.
    pub result: Option<Result<EstimateWords, String>>,
}

/// A finished estimate and the data set it read, or why there is none.
type EstimateResult = Result<(Arc<RayData>, EstimateWords), String>;

/// An estimate as the panel shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct EstimateWords {
    pub rays: usize,
    pub cell: f32,
    pub chunks: usize,
    pub bytes: usize,
}

impl Estimator {
    /// Whether an estimate is being made.
    pub fn busy(&self) -> bool {
        self.task.is_some()
    }
}

/// Starts an estimate when the chosen source or grid changes, and picks up finished ones.
fn estimate(choices: Res<RayChoices>, mut est: ResMut<Estimator>) {
    if let Some(task) = est.task.as_mut()
        && let Some(result) = check_ready(task)
    {
        est.task = None;
        est.result = Some(result.map(|(data, words)| {
            let source = est
                .key
                .as_ref()
                .map(|k| k.source.clone())
                .unwrap_or_default();
            est.data = Some((source, data));
            words
        }));
    }
    let Some(spec) = choices.spec() else {
        est.key = None;
        est.result = None;
        return;
    };
    if spec.source.is_empty() || est.key.as_ref() == Some(&spec) {
        return;
    }
    est.key = Some(spec.clone());
    let cached = est
        .data
        .as_ref()
        .filter(|(s, _)| *s == spec.source)
        .map(|(_, d)| d.clone());
    est.task = Some(AsyncComputeTaskPool::get().spawn(async move {
        let data = match cached {
            Some(d) => d,
            None => {
                Arc::new(voxcast_core::rays::source::load(&spec.source).map_err(|e| e.to_string())?)
            }
        };
        let set = match spec.trace {
            Some(id) => data
                .trace(id)
                .cloned()
                .ok_or_else(|| format!("{} has no trace {id}", spec.source))?,
            None => data.all_rays(),
        };
        let mut p = spec.params;
        if p.cell == 0.0 {
            p.cell = voxcast_core::rays::as_volume::default_cell(&data, &set);
        }
        p.check()?;
        let e = voxcast_core::rays::density::estimate_within(
            &set,
            &p,
            voxcast_core::rays::density::MAX_BYTES,
        )
        .ok_or_else(|| {
            format!(
                "more than {} MiB: choose a larger cell",
                voxcast_core::rays::density::MAX_BYTES >> 20
            )
        })?;
        let rays = set.selected(p.filter, p.tolerance, 1).count();
        Ok((
            data.clone(),
            EstimateWords {
                rays,
                cell: p.cell,
                chunks: e.chunks,
                bytes: e.bytes,
            },
        ))
    }));
}

/// The Sum range fitted to the view (`voxcast_core::rays::layered::DensityView::fit_sum_range`),
/// on the background pool: once for every new density, and when the panel asks.
#[derive(Resource, Default)]
pub struct RangeFit {
    /// The density the range was (or is being) fitted for.
    fitted_for: Option<usize>,
    task: Option<Task<Option<(f32, f32)>>>,
    /// The panel asked for a fit of the view on screen.
    pub asked: bool,
}

impl RangeFit {
    pub fn busy(&self) -> bool {
        self.task.is_some()
    }
}

/// Starts a fit for a new density (or when asked) and sets the range when it arrives.
fn fit_range(
    rays: Res<RayScene>,
    volume: Res<VolumeState>,
    mut render: ResMut<RenderState>,
    choices: Res<RayChoices>,
    views: Query<(&super::state::View, &Camera), With<super::state::MainCamera>>,
    mut fit: ResMut<RangeFit>,
) {
    let Some(shown) = rays.on_show(&volume).cloned() else {
        *fit = RangeFit::default();
        return;
    };
    let id = Arc::as_ptr(&shown) as usize;
    if let Some(task) = fit.task.as_mut()
        && let Some(range) = check_ready(task)
    {
        fit.task = None;
        if fit.fitted_for == Some(id)
            && let Some(r) = range
            && render.settings.method == voxcast_core::composite::Method::Sum
        {
            render.settings.sum_range = Some(r);
        }
    }
    // A new volume is framed this frame: fit the view it is framed in, the next.
    if fit.task.is_some() || (fit.fitted_for == Some(id) && !fit.asked) || volume.is_changed() {
        return;
    }
    let Ok((view, camera)) = views.single() else {
        return;
    };
    let size = camera
        .physical_target_size()
        .unwrap_or(UVec2::new(640, 360));
    fit.asked = false;
    fit.fitted_for = Some(id);
    let (render, shading, view) = (render.clone(), choices.view.shading, view.0);
    fit.task = Some(AsyncComputeTaskPool::get().spawn(async move {
        let c = &shown.computed;
        let mut settings = render.settings.clone();
        settings.sum_range = None;
        let scene =
            Scene::plain(&shown.volume, &render.transfer, &settings, view.forward()).ok()?;
        // The view is in the volume's coordinates; the fit takes the world's.
        let world = CoreCamera {
            eye: view.eye + c.origin,
            target: view.target + c.origin,
            ..view
        };
        voxcast_core::rays::layered::DensityView {
            volume_scene: &scene,
            origin: c.origin,
            triangles: &c.data.scene,
            shading,
            camera: &world,
        }
        .fit_sum_range((size.x.max(1), size.y.max(1)))
    }));
}
