//! The check of the current step's objective: what the player has done, gathered as the core's
//! `Situation`, against `Objective::met`; and the answers the code computes for the questions
//! a step asks (a predicted value, a study question).

use super::*;

/// What the player has done that an objective can ask about, each feature's state as it
/// publishes it (the ray data and the panels' are absent in tests without their plugins).
#[derive(bevy::ecs::system::SystemParam)]
pub(crate) struct Done<'w, 's> {
    render: Res<'w, RenderState>,
    volume: Res<'w, VolumeState>,
    cameras: Query<'w, 's, &'static VirtualCamera>,
    selection: Res<'w, RaySelection>,
    breakdown: Res<'w, BreakdownState>,
    comparison: Res<'w, Comparison>,
    views: Query<'w, 's, &'static View, With<MainCamera>>,
    preview: Option<Res<'w, PreviewSettings>>,
    inspect: Option<Res<'w, crate::sandbox::inspect::rays::InspectSettings>>,
    rays: Option<Res<'w, crate::sandbox::data::source::RayScene>>,
    loading: Res<'w, Loading>,
    ray_choices: Option<Res<'w, crate::sandbox::data::choices::RayChoices>>,
    ray_report: Option<Res<'w, crate::sandbox::data::choices::ViewReport>>,
}

/// Checks the current step's objective against what the player has done.
pub(crate) fn check_objective(
    mode: Res<State<Mode>>,
    mut lessons: ResMut<Lessons>,
    mut trade: ResMut<StepTrade>,
    done: Done,
) {
    let step = lessons.step_in(*mode.get()).cloned();
    // A step about the step's trade measures the step, whatever knob was picked before.
    if step
        .as_ref()
        .is_some_and(|s| s.objective == Objective::TradeMeasured)
        && trade.knob != voxcast_core::knob::Knob::Step
        && trade.progress().is_none()
    {
        trade.knob = voxcast_core::knob::Knob::Step;
    }
    let spot = step.as_ref().and_then(|s| s.control);
    let (detail, composite) = done.predicted(step.as_ref());
    let here = Some((*mode.get(), lessons.step));
    // The step's scene is on screen: nothing waits to be opened or loaded.
    let ready = lessons.scene_ready() && done.loading.under_way().is_none();
    // What the player has done, every frame (the editor judges a draft's objective on it too).
    let mut sit = done.situation(&trade);
    sit.named_effect = lessons.named_effect;
    sit.studied = lessons.studied.clone();
    // A question about the selected ray: answered for the ray selected now.
    let ray_answer = step.as_ref().and_then(|s| {
        let trace = done.breakdown.trace.as_ref()?;
        voxcast_core::level::ray_answer(&s.objective, trace, &done.volume.volume)
    });
    // Only a submitted prediction is judged, never one half typed.
    let truth = prediction_truth(detail.as_ref(), composite.as_deref(), ray_answer.as_ref());
    sit.prediction = truth
        .zip(lessons.tried)
        .map(|(truth, tried)| (tried, truth));
    lessons.now = sit.clone();
    let met = step.is_some_and(|step| {
        // The state the step opened in: taken on the first frame its scene is on screen;
        // until then nothing is met (a load under way still shows the last level's settings).
        if lessons
            .at_open
            .as_ref()
            .is_none_or(|(at, _)| Some(*at) != here)
        {
            if !ready {
                return false;
            }
            lessons.at_open = here.map(|h| (h, sit.clone()));
        }
        sit.at_open = lessons.at_open.as_ref().map(|(_, o)| Box::new(o.clone()));
        step.objective.met(&sit)
    });
    lessons.on_show = done
        .rays
        .as_ref()
        .and_then(|r| r.on_show(&done.volume))
        .cloned();
    let met = met || (lessons.met_for == here && lessons.met);
    if met {
        lessons.met_for = here;
    }
    (lessons.met, lessons.spot) = (met, spot);
    (lessons.detail, lessons.composite) = (detail, composite);
    lessons.ray_answer = ray_answer;
}

/// The code's answer to study question `q` from the density on show (see
/// [`Lessons::study_shown`]).
pub fn study_truth(
    shown: &crate::sandbox::data::source::Shown,
    q: voxcast_core::rays::study::Question,
) -> Option<String> {
    let c = &shown.computed;
    q.answer(&c.data.scene, &c.set, Some(&c.density))
}

/// What a prediction step's answer should be: the reconstructed value at its point, the red of
/// the worked composite after its last point, or the number asked about the selected ray.
pub(super) fn prediction_truth(
    detail: Option<&SampleDetail>,
    composite: Option<&[voxcast_core::worked::WorkedPoint]>,
    ray: Option<&voxcast_core::level::RayAnswer>,
) -> Option<f32> {
    detail
        .map(|d| d.value)
        .or_else(|| composite?.last().map(|r| r.after[0]))
        .or_else(|| ray.map(|r| r.truth))
}

/// A number as a player types it: spaces around it and a decimal comma allowed.
pub fn parse_typed(typed: &str) -> Result<f32, std::num::ParseFloatError> {
    typed.trim().replace(',', ".").parse::<f32>()
}

impl Done<'_, '_> {
    /// A prediction step's answer: the reconstruction at its point, or the worked composite.
    fn predicted(
        &self,
        step: Option<&voxcast_core::level::Step>,
    ) -> (
        Option<SampleDetail>,
        Option<Vec<voxcast_core::worked::WorkedPoint>>,
    ) {
        let volume = &self.volume.volume;
        match step.map(|s| &s.objective) {
            Some(Objective::PredictValue { point, .. }) => {
                let point = Vec3::from_array(*point);
                (
                    Some(detail_at(volume, point, Interpolation::Trilinear)),
                    None,
                )
            }
            Some(Objective::PredictComposite { points, .. }) => {
                let tf = &self.render.transfer;
                (
                    None,
                    Some(voxcast_core::worked::back_to_front(volume, tf, points)),
                )
            }
            _ => (None, None),
        }
    }

    /// What the player has done, as the objectives see it (the effect named, the study and the
    /// prediction are the levels' own, filled in by the caller).
    fn situation(&self, trade: &StepTrade) -> Situation {
        let (render, volume, breakdown) = (&*self.render, &*self.volume, &*self.breakdown);
        let view = self.views.single().ok();
        let preview = self.preview.as_deref();
        let current = self
            .comparison
            .result
            .as_ref()
            .filter(|r| r.snapshot.is_current(view, render, volume));
        let measured = trade.current(view, render, volume).map(|t| t.knob);
        let opened_sample_lights = breakdown
            .opened
            .and_then(|i| breakdown.trace.as_ref()?.samples.get(i)?.shading)
            .filter(|t| t.lit)
            .map(|t| t.lights_reaching());
        let v = &volume.volume;
        let settled = Situation::from_settings(
            &render.settings,
            &render.transfer,
            v.bounds(),
            v.spacing().min_element(),
        );
        let sit = Situation {
            virtual_pixels_across: self.cameras.single().map_or(0, |v| v.width),
            ray_selected: self.selection.selected.is_some(),
            ray_clicks: self.selection.clicks,
            ray_values: breakdown
                .trace
                .as_ref()
                .map(|t| t.samples.iter().map(|s| s.reconstruction.value).collect())
                .unwrap_or_default(),
            opened_sample: breakdown.opened,
            compared_max: current.and_then(|r| r.diff.as_ref().map(|(d, _)| d.max_abs * 255.0)),
            opened_sample_lights,
            // The sampling levels measure the step's trade.
            trade_measured: measured == Some(voxcast_core::knob::Knob::Step),
            measured_knob: measured.map(|k| k.name()),
            preview_on: preview.is_some_and(|p| p.enabled),
            preview_scale: preview.map_or(1.0, |p| p.scale),
            preview_cost_view: preview.and_then(|p| p.cost_view).map(|v| v.name()),
            skip_blocks_shown: self.inspect.as_ref().is_some_and(|i| i.show_blocks),
            cost_view: current.and(self.comparison.cost_view).map(|v| v.name()),
            ray_cut: breakdown
                .trace
                .as_ref()
                .is_some_and(|t| t.cut_words().is_some()),
            ..settled
        };
        self.with_ray_data(sit)
    }

    /// `sit` with the ray data on show: its density's facts and the views drawn.
    fn with_ray_data(&self, mut sit: Situation) -> Situation {
        let Some(shown) = self.rays.as_ref().and_then(|r| r.on_show(&self.volume)) else {
            return sit;
        };
        sit.ray_density = Some(shown.computed.facts.clone());
        let drawn = self.ray_report.as_ref().is_some_and(|r| r.drawn);
        let view = self
            .ray_choices
            .as_ref()
            .map(|c| c.view.clone())
            .unwrap_or_default();
        sit.ray_views = [
            ("volume", sit.preview_on),
            ("mesh", view.mesh && drawn),
            ("field", view.field && drawn),
        ]
        .into_iter()
        .filter_map(|(name, on)| on.then_some(name))
        .collect();
        sit
    }
}
