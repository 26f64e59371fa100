//! The mouse over the scene, as the features that drag in it read it: the buttons, the cursor
//! in the viewport, whether a panel has the pointer, and who holds a drag this frame. The orbit,
//! the light's drag and the cut's drag read this instead of each other's state.

use crate::sandbox::shared::state::View;
use crate::sandbox::shared::viewport::Viewport;
use bevy::ecs::system::SystemParam;
use bevy::prelude::*;
use bevy::window::PrimaryWindow;
use bevy_egui::input::EguiWantsInput;
use voxcast_core::ray::Ray;

/// Who holds a drag of the mouse this frame, by name. A feature whose handle was grabbed says
/// so in [`crate::sandbox::shared::schedule::Frame::Grab`]; the orbit, in [`crate::sandbox::shared::schedule::Frame::Input`], leaves the view alone
/// while anyone holds one.
#[derive(Resource, Default, Debug)]
pub struct MouseHeld(Vec<&'static str>);

impl MouseHeld {
    /// Records whether `who` holds a drag now.
    pub fn hold(&mut self, who: &'static str, held: bool) {
        self.0.retain(|w| *w != who);
        if held {
            self.0.push(who);
        }
    }

    /// Whether any feature holds a drag.
    pub fn by_anyone(&self) -> bool {
        !self.0.is_empty()
    }
}

/// The mouse's buttons and the cursor over the window's viewport.
#[derive(SystemParam)]
pub struct Pointer<'w, 's> {
    pub buttons: Res<'w, ButtonInput<MouseButton>>,
    windows: Query<'w, 's, &'static Window, With<PrimaryWindow>>,
    viewport: Option<Res<'w, Viewport>>,
    egui: Option<Res<'w, EguiWantsInput>>,
}

impl Pointer<'_, '_> {
    /// The cursor in the window, in logical pixels (None off the window or without one).
    pub fn cursor(&self) -> Option<Vec2> {
        self.windows.single().ok()?.cursor_position()
    }

    /// Whether the cursor is over the part of the window the panels leave to the scene.
    pub fn over_scene(&self) -> bool {
        self.windows
            .single()
            .is_ok_and(|w| Viewport::cursor(self.viewport.as_deref(), w).is_some())
    }

    /// Whether a panel (egui) wants the pointer: a click there is the panel's.
    pub fn panel_has_it(&self) -> bool {
        self.egui
            .as_ref()
            .is_some_and(|e| e.wants_any_pointer_input())
    }

    /// The ray under the cursor, from the main camera's `view` (shown in the viewport).
    pub fn ray(&self, view: &View) -> Option<Ray> {
        let window = self.windows.single().ok()?;
        let (cursor, size) = Viewport::cursor(self.viewport.as_deref(), window)?;
        Some(view.0.ray(cursor.x, cursor.y, size.x, size.y))
    }
}
