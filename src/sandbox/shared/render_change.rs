//! The one writer of how the volume is rendered: the render state ([`RenderState`]) and the
//! preview's settings ([`PreviewSettings`]). Every feature that changes them (the panels, the
//! scene's drags, a load, a level, the ray data, the step's trade, the adapter's backend, the
//! scripted players) sends a [`ChangeRender`] or [`ChangePreview`] message, and [`apply`] and
//! [`apply_preview`] make the changes at one point of the frame, [`Frame::Settings`] (after the
//! rules, before the objective is checked), in the order of [`Author`]. So this file says what
//! can change a setting, and in which order; a change that would make the render settings
//! invalid is refused here, the settings kept.

use super::quality::{Backend, PreviewSettings};
use super::schedule::Frame;
use super::state::RenderState;
use bevy::prelude::*;
use voxcast_core::clip::Clip;
use voxcast_core::settings::RenderSettings;
use voxcast_core::shade::Light;
use voxcast_core::transfer::TransferFunction;

/// Who asked for a change. Changes are applied in this order (a later one wins where two touch
/// the same setting), whatever order the systems that sent them ran in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Author {
    /// The settings panel, as the student edited it (in the last frame's panels).
    Panel,
    /// A transfer function file opened in the editor (on the page, handed over by the browser).
    TransferFile,
    /// The levels' play-through and the scripted measurements: they act as a student's hands.
    Script,
    /// `--screenshot --sweep`: each shot's settings.
    Screenshot,
    /// The cut's handles dragged in the scene.
    CutDrag,
    /// A light's marker dragged in the scene.
    LightDrag,
    /// Going back from a ray density to the volume it replaced.
    RayData,
    /// A new volume's defaults.
    Loading,
    /// A level's scene, over the volume's defaults.
    Level,
    /// The step's trade, timing the preview's own images (and putting the player's back).
    Trade,
    /// The range a ray density's sum is shown over, fitted to the view once computed.
    RangeFit,
    /// The CPU live view chosen where the GPU is a software renderer or cannot run the preview.
    Adapter,
}

/// What changes.
#[derive(Clone, Debug, PartialEq)]
pub enum Change {
    /// Everything: a volume's defaults, a level's scene, going back from a ray density, an
    /// edit in the settings panel.
    Whole(Box<RenderState>),
    /// The settings, the transfer function kept.
    Settings(Box<RenderSettings>),
    /// The transfer function.
    Transfer(TransferFunction),
    /// The cut: clip plane and crop box.
    Clip(Clip),
    /// Where one light stands (or points), by its place in the list (ignored if it is no
    /// longer there).
    Light(usize, Light),
    /// The range a sum is shown over.
    SumRange(Option<(f32, f32)>),
}

/// A change asked of the render state's owner.
#[derive(Message, Clone, Debug, PartialEq)]
pub struct ChangeRender {
    pub by: Author,
    pub change: Change,
}

impl ChangeRender {
    pub fn new(by: Author, change: Change) -> Self {
        Self { by, change }
    }

    /// The whole state, as `by` edited a copy of it.
    pub fn whole(by: Author, render: RenderState) -> Self {
        Self::new(by, Change::Whole(Box::new(render)))
    }
}

/// The render state as it is now, and the way to ask for a change of it.
#[derive(bevy::ecs::system::SystemParam)]
pub struct RenderChanges<'w> {
    pub now: Res<'w, RenderState>,
    asked: MessageWriter<'w, ChangeRender>,
}

impl RenderChanges<'_> {
    /// Asks for `change`.
    pub fn ask(&mut self, by: Author, change: Change) {
        self.asked.write(ChangeRender::new(by, change));
    }

    /// Asks for `edited`, a copy of the state as `by` edited it, where it differs from now.
    pub fn edited(&mut self, by: Author, edited: RenderState) {
        if edited != *self.now {
            self.asked.write(ChangeRender::whole(by, edited));
        }
    }
}

/// What changes in the preview's settings.
#[derive(Clone, Debug, PartialEq)]
pub enum PreviewChange {
    /// Everything, as an author edited a copy.
    Whole(Box<PreviewSettings>),
    /// Who draws the volume.
    Backend(Backend),
}

/// A change asked of the preview settings' owner.
#[derive(Message, Clone, Debug, PartialEq)]
pub struct ChangePreview {
    pub by: Author,
    pub change: PreviewChange,
}

/// The preview's settings as they are now (none in a window-less app), and the way to ask for
/// a change of them.
#[derive(bevy::ecs::system::SystemParam)]
pub struct PreviewChanges<'w> {
    pub now: Option<Res<'w, PreviewSettings>>,
    asked: MessageWriter<'w, ChangePreview>,
}

impl PreviewChanges<'_> {
    /// Asks for `change`.
    pub fn ask(&mut self, by: Author, change: PreviewChange) {
        self.asked.write(ChangePreview { by, change });
    }

    /// Asks for `edited`, a copy of the settings as `by` edited it, where it differs from now
    /// (nothing where there are no preview settings to change).
    pub fn edited(&mut self, by: Author, edited: PreviewSettings) {
        if self.now.as_deref().is_some_and(|now| *now != edited) {
            self.ask(by, PreviewChange::Whole(Box::new(edited)));
        }
    }
}

pub fn plugin(app: &mut App) {
    app.add_message::<ChangeRender>()
        .add_message::<ChangePreview>()
        // Many features ask for changes, in any order: they are ordered by author here.
        .allow_ambiguous_resource::<Messages<ChangeRender>>()
        .allow_ambiguous_resource::<Messages<ChangePreview>>()
        .add_systems(Update, (apply, apply_preview).in_set(Frame::Settings));
}

/// Makes the preview's changes asked since the last `Settings` point, in the order of their
/// authors.
fn apply_preview(
    mut changes: MessageReader<ChangePreview>,
    preview: Option<ResMut<PreviewSettings>>,
) {
    let mut asked: Vec<&ChangePreview> = changes.read().collect();
    let Some(mut preview) = preview else { return };
    asked.sort_by_key(|c| c.by);
    let mut next = preview.clone();
    for c in asked {
        match &c.change {
            PreviewChange::Whole(p) => next = (**p).clone(),
            PreviewChange::Backend(b) => next.backend = *b,
        }
    }
    if next != *preview {
        *preview = next;
    }
}

/// Makes this frame's changes (and those sent since the last `Settings` point: the panels'
/// and the scripted players'), in the order of their authors.
fn apply(mut changes: MessageReader<ChangeRender>, render: Option<ResMut<RenderState>>) {
    let mut asked: Vec<&ChangeRender> = changes.read().collect();
    let Some(mut render) = render else { return };
    asked.sort_by_key(|c| c.by); // stable: one author's changes keep their order
    let mut next = render.clone();
    for c in asked {
        changed(&mut next, &c.change);
    }
    if next != *render {
        *render = next;
    }
}

/// `render` after `change`; a change that would leave the settings invalid is refused.
pub fn changed(render: &mut RenderState, change: &Change) {
    let mut next = render.clone();
    match change {
        Change::Whole(r) => next = (**r).clone(),
        Change::Settings(s) => next.settings = (**s).clone(),
        Change::Transfer(t) => next.transfer = t.clone(),
        Change::Clip(c) => next.settings.clip = c.clone(),
        Change::Light(i, l) => {
            if let Some(slot) = next.settings.phong.lights.get_mut(*i) {
                slot.light = *l;
            }
        }
        Change::SumRange(r) => next.settings.sum_range = *r,
    }
    if next.settings.validate().is_ok() {
        *render = next;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use voxcast_core::composite::Method;
    use voxcast_core::step::Length;

    fn app() -> App {
        let mut app = App::new();
        super::super::schedule::configure(&mut app);
        app.add_plugins(plugin).insert_resource(RenderState {
            transfer: TransferFunction::ramp(0.0, 1.0, 0.5).unwrap(),
            settings: RenderSettings::default(),
            depth_termination: true,
        });
        app
    }

    fn send(app: &mut App, by: Author, change: Change) {
        app.world_mut().write_message(ChangeRender::new(by, change));
    }

    #[test]
    fn changes_are_applied_in_the_order_of_their_authors() {
        let mut app = app();
        let level = RenderSettings {
            method: Method::Maximum,
            sum_range: Some((0.0, 1.0)),
            ..Default::default()
        };
        // Sent in the "wrong" order: the range fit first, the level's whole scene after.
        send(
            &mut app,
            Author::RangeFit,
            Change::SumRange(Some((2.0, 3.0))),
        );
        send(
            &mut app,
            Author::Level,
            Change::Settings(Box::new(level.clone())),
        );
        send(&mut app, Author::Panel, Change::Settings(Box::default()));
        app.update();
        let s = &app.world().resource::<RenderState>().settings;
        assert_eq!(s.method, Method::Maximum, "the level's over the panel's");
        assert_eq!(s.sum_range, Some((2.0, 3.0)), "the fit over the level's");
    }

    #[test]
    fn the_adapters_backend_stands_over_a_levels_whole_preview() {
        let mut app = app();
        app.init_resource::<PreviewSettings>();
        let level = PreviewSettings {
            enabled: false,
            scale: 0.5,
            ..Default::default()
        };
        let world = app.world_mut();
        world.write_message(ChangePreview {
            by: Author::Adapter,
            change: PreviewChange::Backend(Backend::Cpu),
        });
        world.write_message(ChangePreview {
            by: Author::Level,
            change: PreviewChange::Whole(Box::new(level)),
        });
        app.update();
        let p = app.world().resource::<PreviewSettings>();
        assert_eq!((p.enabled, p.scale, p.backend), (false, 0.5, Backend::Cpu));
    }

    #[test]
    fn a_change_that_makes_the_settings_invalid_is_refused() {
        let mut app = app();
        let bad = RenderSettings {
            step: Length::Voxels(-1.0),
            ..Default::default()
        };
        send(&mut app, Author::Panel, Change::Settings(Box::new(bad)));
        send(&mut app, Author::Script, Change::SumRange(Some((0.0, 4.0))));
        app.update();
        let s = &app.world().resource::<RenderState>().settings;
        assert_eq!(s.step, RenderSettings::default().step, "kept");
        assert_eq!(s.sum_range, Some((0.0, 4.0)), "the valid one applied");
    }

    #[test]
    fn an_unchanged_state_is_not_marked_changed_and_a_missing_light_is_ignored() {
        let mut app = app();
        app.update();
        let lights = app
            .world()
            .resource::<RenderState>()
            .settings
            .phong
            .lights
            .len();
        let light = Light::Point(Vec3::ONE);
        send(
            &mut app,
            Author::LightDrag,
            Change::Light(lights + 3, light),
        );
        let before = app.world().resource_ref::<RenderState>().last_changed();
        app.update();
        let after = app.world().resource_ref::<RenderState>().last_changed();
        assert_eq!(before, after);
    }
}
