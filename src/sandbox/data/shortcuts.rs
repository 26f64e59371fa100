//! Keyboard shortcuts for RayVis's common view toggles (RayVis's users asked for them): V the
//! density volume, M the ray mesh, G its start and end glyphs, F the vector field, S the
//! scene's shading in turn. Keys egui
//! wants (a text field being typed in) are left to egui. The Ray data panel lists them
//! ([`SHORTCUTS`]).

use crate::sandbox::data::choices::RayChoices;
use bevy::prelude::*;
use bevy_egui::input::EguiWantsInput;
use voxcast_core::rays::layered::SceneShading;

/// The shortcuts, in words, for the panel.
pub const SHORTCUTS: &str = "Keys: V the density volume, M the ray mesh, G its glyphs, F the vector field, S the \
     scene's shading";

/// What a key toggles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Toggle {
    Volume,
    Mesh,
    Glyphs,
    Field,
    Shading,
}

const KEYS: [(KeyCode, Toggle); 5] = [
    (KeyCode::KeyV, Toggle::Volume),
    (KeyCode::KeyM, Toggle::Mesh),
    (KeyCode::KeyG, Toggle::Glyphs),
    (KeyCode::KeyF, Toggle::Field),
    (KeyCode::KeyS, Toggle::Shading),
];

pub(crate) fn plugin(app: &mut App) {
    app.add_systems(
        Update,
        toggle_views.in_set(crate::sandbox::shared::schedule::Frame::Input),
    );
}

/// Applies the keys pressed this frame to the view choices.
fn toggle_views(
    keys: Option<Res<ButtonInput<KeyCode>>>,
    egui: Option<Res<EguiWantsInput>>,
    choices: Option<ResMut<RayChoices>>,
) {
    let (Some(keys), Some(mut choices)) = (keys, choices) else {
        return;
    };
    if egui.is_some_and(|e| e.wants_any_keyboard_input()) {
        return;
    }
    for (key, toggle) in KEYS {
        if keys.just_pressed(key) {
            apply(&mut choices, toggle);
        }
    }
}

fn apply(c: &mut RayChoices, toggle: Toggle) {
    let v = &mut c.view;
    match toggle {
        Toggle::Volume => v.volume = !v.volume,
        Toggle::Mesh => v.mesh = !v.mesh,
        Toggle::Glyphs => v.glyphs = !v.glyphs,
        Toggle::Field => v.field = !v.field,
        Toggle::Shading => {
            let all = SceneShading::ALL;
            let i = all.iter().position(|s| *s == v.shading).unwrap_or(0);
            v.shading = all[(i + 1) % all.len()];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each key flips its view (twice: back), S walks through the shadings; a key held down
    /// acts once.
    #[test]
    fn keys_toggle_the_views() {
        let mut app = App::new();
        app.init_resource::<ButtonInput<KeyCode>>()
            .init_resource::<RayChoices>()
            .add_systems(Update, toggle_views);
        let press = |app: &mut App, key: KeyCode| {
            app.world_mut()
                .resource_mut::<ButtonInput<KeyCode>>()
                .press(key);
            app.update();
            let mut keys = app.world_mut().resource_mut::<ButtonInput<KeyCode>>();
            keys.release(key);
            keys.clear();
        };
        let view = |app: &App| app.world().resource::<RayChoices>().view.clone();
        let before = view(&app);
        press(&mut app, KeyCode::KeyM);
        assert!(view(&app).mesh != before.mesh);
        press(&mut app, KeyCode::KeyF);
        assert!(view(&app).field != before.field);
        press(&mut app, KeyCode::KeyG);
        assert!(view(&app).glyphs != before.glyphs);
        press(&mut app, KeyCode::KeyV);
        assert!(view(&app).volume != before.volume);
        let mut seen = vec![view(&app).shading];
        for _ in 0..SceneShading::ALL.len() {
            press(&mut app, KeyCode::KeyS);
            seen.push(view(&app).shading);
        }
        assert_eq!(seen.first(), seen.last(), "round the shadings");
        assert_eq!(seen.len(), SceneShading::ALL.len() + 1);
        for k in [KeyCode::KeyM, KeyCode::KeyF, KeyCode::KeyV, KeyCode::KeyG] {
            press(&mut app, k);
        }
        assert_eq!(view(&app), before);
        // Held down, a key acts once.
        app.world_mut()
            .resource_mut::<ButtonInput<KeyCode>>()
            .press(KeyCode::KeyM);
        app.update();
        app.world_mut()
            .resource_mut::<ButtonInput<KeyCode>>()
            .clear();
        app.update();
        assert!(view(&app).mesh != before.mesh);
    }
}
