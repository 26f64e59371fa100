//! Before computing a density: the memory it would take ([`Estimator`]) and the value range
//! that fits the rays' counts ([`RangeFit`]), both worked out on the background pool.

use crate::sandbox::data::choices::RayChoices;
use crate::sandbox::data::source::RayScene;
use crate::sandbox::shared::render_change::{Author, Change, RenderChanges};
use crate::sandbox::shared::schedule::Frame;
use crate::sandbox::shared::state::VolumeState;
use bevy::prelude::*;
use bevy::tasks::{Task, futures::check_ready};
use std::sync::Arc;
use voxcast_core::camera::Camera as CoreCamera;
use voxcast_core::rays::as_volume::DensitySpec;
use voxcast_core::rays::data::RayData;
use voxcast_core::scene::Scene;

pub(crate) fn plugin(app: &mut App) {
    app.init_resource::<Estimator>()
        .init_resource::<RangeFit>()
        .add_systems(Update, (estimate, fit_range).in_set(Frame::Results));
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
    /// Set by the panel that shows the estimate, the first time it is drawn: until then none
    /// is made (the default source's rays take half a second to trace on a page's one thread,
    /// at its start, for a section most never open).
    wanted: std::sync::atomic::AtomicBool,
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
    /// Asks for estimates from now on (the panel showing them is on screen).
    pub fn want(&self) {
        self.wanted
            .store(true, std::sync::atomic::Ordering::Relaxed);
    }

    /// Forgets the data set read from `source` (a file of that name came anew) and the
    /// estimate made of it.
    pub fn forget(&mut self, source: &str) {
        if self.data.as_ref().is_some_and(|(s, _)| s == source) {
            self.data = None;
        }
        if self.key.as_ref().is_some_and(|k| k.source == source) {
            self.key = None;
        }
    }

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
    if !est.wanted.load(std::sync::atomic::Ordering::Relaxed) {
        return;
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
    est.task = Some(crate::sandbox::shared::tasks::spawn(async move {
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
    mut render: RenderChanges,
    choices: Res<RayChoices>,
    views: Query<
        (&crate::sandbox::shared::state::View, &Camera),
        With<crate::sandbox::shared::state::MainCamera>,
    >,
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
            && render.now.settings.method == voxcast_core::composite::Method::Sum
        {
            render.ask(Author::RangeFit, Change::SumRange(Some(r)));
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
    let (render, shading, view) = (render.now.clone(), choices.view.shading, view.0);
    fit.task = Some(crate::sandbox::shared::tasks::spawn(async move {
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

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::tasks::{AsyncComputeTaskPool, TaskPool};

    /// No estimate is made (and no ray traced or read) until the panel showing it asks; then
    /// one is, for the chosen source.
    #[test]
    fn no_estimate_until_the_panel_asks_for_one() {
        AsyncComputeTaskPool::get_or_init(TaskPool::new);
        let choices = RayChoices {
            source: crate::sandbox::data::source::SourceKind::File,
            path: concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/two_level.rayvis").into(),
            ..default()
        };
        let mut app = App::new();
        app.init_resource::<Estimator>()
            .insert_resource(choices)
            .add_systems(Update, estimate);
        for _ in 0..5 {
            app.update();
        }
        let est = app.world().resource::<Estimator>();
        assert!(!est.busy() && est.result.is_none() && est.key.is_none());
        est.want();
        for _ in 0..2000 {
            app.update();
            if app.world().resource::<Estimator>().result.is_some() {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
        let words = app.world().resource::<Estimator>().result.clone();
        let words = words
            .expect("an estimate once asked")
            .expect("the file reads");
        assert!(words.rays > 0 && words.chunks > 0, "{words:?}");
    }
}
