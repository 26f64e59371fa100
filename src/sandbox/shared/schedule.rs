//! The order of a frame, in one place: [`Frame`] for the sandbox's work in `Update` and then in
//! `PostUpdate`, [`Paint`] for the egui pass that paints the window. Features put their systems
//! in these sets and never order themselves after another file's function.

use bevy::prelude::*;
use bevy_egui::EguiPrimaryContextPass;

/// The order of a frame's work (as bevy_new_2d orders its frame). In `Update`: who holds the
/// mouse, the player's input, a volume replaced, the rules that react to what changed, the
/// settings' changes applied, what stands beside the main camera, the virtual camera's rays,
/// what is worked out from it all, the checks of the level's objective, the scripted players,
/// then what is shown. In `PostUpdate`, once the engine has placed the cameras (their
/// transforms propagated, their projections updated for this frame): the GPU's material
/// synced, then the views that read it.
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Frame {
    /// Who holds the mouse this frame: the light's drag and the cut's drag take it before the
    /// orbit reads it.
    Grab,
    /// Mouse, keyboard and dropped files: the orbit, the shortcuts, files to load.
    Input,
    /// The systems that replace the volume (a load finishing, going back from a ray density).
    /// Whatever reacts to a new volume runs after them: it must see the new volume in the same
    /// frame as every other reaction, or it frames one of them for the old volume.
    SwapVolume,
    /// The sandbox's rules: the main camera's framing, levels' commands and presets, the
    /// editor's commands, a transfer function file handed over.
    Rules,
    /// The changes of the render state and the preview's settings asked for so far, applied
    /// by their one writer (`render_change.rs`): what follows sees this frame's settings.
    Settings,
    /// What stands beside the main camera once it is framed: the virtual camera.
    Follow,
    /// The virtual camera's rays traced (or collected from their task) and their samples
    /// placed and shown.
    Trace,
    /// What is worked out from this frame's settled state, which the check reads: the step's
    /// trade timed, the selected ray's breakdown, a density's memory estimate and its range
    /// fitted to the view.
    Results,
    /// The level's objective, checked once the rules have settled this frame's state.
    Check,
    /// Scripted players (the levels' play-through, measurements): they act on what the check
    /// saw.
    Drive,
    /// What is shown: the preview's target and quality, the live view, gizmos and lines.
    Show,
    /// `PostUpdate`: the material written from the settings, the view and the volume (the
    /// uniform's rays use this frame's view and target size).
    Sync,
    /// `PostUpdate`: what reads the written material and the placed cameras: Render image's
    /// capture, the CPU live view, the CPU-drawn lines.
    Views,
}

impl Frame {
    /// The sets of `Update`, in the order a frame runs them.
    pub const UPDATE: [Frame; 11] = [
        Frame::Grab,
        Frame::Input,
        Frame::SwapVolume,
        Frame::Rules,
        Frame::Settings,
        Frame::Follow,
        Frame::Trace,
        Frame::Results,
        Frame::Check,
        Frame::Drive,
        Frame::Show,
    ];
    /// The sets of `PostUpdate`, in order.
    pub const POST_UPDATE: [Frame; 2] = [Frame::Sync, Frame::Views];
}

/// The order of the egui pass: the panels lay themselves out around the viewport, the preview
/// is painted into what is left, then what is drawn over it.
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Paint {
    /// The docked panels and windows, and the viewport they leave.
    Panels,
    /// The preview's image in the viewport.
    Preview,
    /// Over the preview: overlay lines and the rays' overlay.
    Over,
    /// Over those: the compiling note, the page's status.
    Notes,
}

impl Paint {
    /// Every set in the order the pass runs them.
    pub const ALL: [Paint; 4] = [Paint::Panels, Paint::Preview, Paint::Over, Paint::Notes];
}

/// Orders the sets of all three schedules, and names the messages whose writers need no order
/// between them (and `render_change.rs` its own); every app of the sandbox (and the tests that build one) calls this once.
pub fn configure(app: &mut App) {
    // Any feature may ask for frames; only whether one did counts.
    app.allow_ambiguous_resource::<Messages<super::pacing::KeepDrawing>>();
    // Files chosen are read by the feature each is for: one written after its reader ran this
    // frame is read the next.
    app.allow_ambiguous_resource::<Messages<super::files::FilesChosen>>();
    let [a, b, c, d, e, f, g, h, i, j, k] = Frame::UPDATE;
    app.configure_sets(Update, (a, b, c, d, e, f, g, h, i, j, k).chain());
    let [p, q, r, n] = Paint::ALL;
    app.configure_sets(EguiPrimaryContextPass, (p, q, r, n).chain());
    let [s, v] = Frame::POST_UPDATE;
    app.configure_sets(
        PostUpdate,
        (s, v)
            .chain()
            .after(bevy::camera::CameraUpdateSystems)
            .after(bevy::transform::TransformSystems::Propagate),
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::ecs::schedule::ScheduleLabel;

    #[derive(Resource, Default)]
    struct Ran(Vec<String>);

    /// A system that notes its set's name.
    fn note(name: String) -> impl FnMut(ResMut<Ran>) {
        move |mut ran: ResMut<Ran>| ran.0.push(name.clone())
    }

    /// Runs `schedule` once with one noting system per set, added in reverse order so that
    /// only the sets' configuration can put them in order.
    fn order<S: SystemSet + Copy + std::fmt::Debug>(
        schedule: impl ScheduleLabel + Clone,
        sets: &[S],
    ) -> Vec<String> {
        let mut app = App::new();
        app.init_resource::<Ran>();
        configure(&mut app);
        for set in sets.iter().rev() {
            app.add_systems(schedule.clone(), note(format!("{set:?}")).in_set(*set));
        }
        app.world_mut().run_schedule(schedule);
        app.world_mut().remove_resource::<Ran>().unwrap().0
    }

    #[test]
    fn a_frame_runs_its_sets_in_the_enums_order() {
        let want: Vec<String> = Frame::UPDATE.iter().map(|s| format!("{s:?}")).collect();
        assert_eq!(order(Update, &Frame::UPDATE), want);
        let want: Vec<String> = Paint::ALL.iter().map(|s| format!("{s:?}")).collect();
        assert_eq!(order(EguiPrimaryContextPass, &Paint::ALL), want);
        let want: Vec<String> = Frame::POST_UPDATE
            .iter()
            .map(|s| format!("{s:?}"))
            .collect();
        assert_eq!(order(PostUpdate, &Frame::POST_UPDATE), want);
    }
}
