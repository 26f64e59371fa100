//! The part of the window the scene is shown in, as the panels leave it: what the cursor's ray,
//! the overlays and the preview's images are measured against.

use bevy::prelude::*;
use bevy_egui::egui;

/// The part of the window the scene is shown in: what the docked panels leave free (the
/// whole window before the panels are laid out, and without them). Logical points, as egui
/// lays out, and the window's pixels per point.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct Viewport {
    pub rect: egui::Rect,
    pub pixels_per_point: f32,
}

impl Viewport {
    /// The viewport in the window's physical pixels: top-left corner and size.
    pub fn physical(&self) -> (Vec2, UVec2) {
        let min = Vec2::new(self.rect.min.x, self.rect.min.y) * self.pixels_per_point;
        let size = Vec2::new(self.rect.width(), self.rect.height()) * self.pixels_per_point;
        (min, size.round().as_uvec2().max(UVec2::ONE))
    }

    /// The viewport in egui's points (the whole window when `viewport` is not known yet).
    pub fn rect(viewport: Option<&Viewport>, ctx: &egui::Context) -> egui::Rect {
        viewport.map_or(ctx.viewport_rect(), |v| v.rect)
    }

    /// The cursor in the viewport of `window` (physical pixels from its top-left corner, with
    /// the viewport's size), where the cursor is inside it.
    pub fn cursor(viewport: Option<&Viewport>, window: &Window) -> Option<(Vec2, UVec2)> {
        let (min, size) = Self::of(viewport, window);
        let cursor = window.physical_cursor_position()? - min;
        let inside = cursor.cmpge(Vec2::ZERO).all() && cursor.cmplt(size.as_vec2()).all();
        inside.then_some((cursor, size))
    }

    /// The viewport of `window` (its whole area when `viewport` is not known yet).
    pub fn of(viewport: Option<&Viewport>, window: &Window) -> (Vec2, UVec2) {
        match viewport {
            Some(v) => v.physical(),
            None => (
                Vec2::ZERO,
                UVec2::new(window.physical_width(), window.physical_height()).max(UVec2::ONE),
            ),
        }
    }
}

/// Where the scene is seen in and from: the primary window, the part of it the scene is shown
/// in (once the panels are laid out) and the main camera's view.
#[derive(bevy::ecs::system::SystemParam)]
pub struct SceneOnScreen<'w, 's> {
    pub window: Query<'w, 's, &'static Window, With<bevy::window::PrimaryWindow>>,
    pub viewport: Option<Res<'w, Viewport>>,
    pub views: Query<
        'w,
        's,
        &'static crate::sandbox::shared::state::View,
        With<crate::sandbox::shared::state::MainCamera>,
    >,
}

/// A test's primary window of `w` × `h` pixels at one pixel per point (no display needed):
/// what the features that read the window's size and cursor are tested against.
#[cfg(test)]
pub fn spawn_test_window(world: &mut World, w: u32, h: u32) -> Entity {
    world
        .spawn((
            Window {
                resolution: bevy::window::WindowResolution::new(w, h)
                    .with_scale_factor_override(1.0),
                ..default()
            },
            bevy::window::PrimaryWindow,
        ))
        .id()
}
