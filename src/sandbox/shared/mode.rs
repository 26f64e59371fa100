//! What the sandbox is playing — free play or one level — as a Bevy state, and what that mode's
//! scene holds. Entities a mode spawns carry `DespawnOnExit(mode)`, so everything a level set
//! up leaves with it; the spawners run when the mode changes (and when a new volume needs them
//! resized).

use bevy::prelude::*;

/// Free play (everything on) or level `i` of the embedded levels.
#[derive(States, Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Mode {
    #[default]
    FreePlay,
    Level(usize),
}

/// What the current mode's scene holds: only what it teaches. Set together with the next
/// [`Mode`], read by the spawners once the mode has changed.
#[derive(Resource, Clone, Copy, Debug, PartialEq)]
pub struct Stage {
    /// The virtual camera's pixels across and down; `None`: no virtual camera.
    pub rays: Option<u32>,
    /// Whether the virtual camera is drawn at first (free play's `--no-rays` hides it).
    pub rays_shown: bool,
    /// Whether the light's marker sphere is in the scene.
    pub light_marker: bool,
    /// Whether the live GPU preview is drawn.
    pub preview: bool,
    /// Whether the virtual camera shoots the lecture's worked ray (one pixel, from P3 to P1).
    pub lecture_ray: bool,
}

/// The mode on screen and what its scene holds, which the spawners read together.
#[derive(bevy::ecs::system::SystemParam)]
pub struct Staged<'w> {
    pub mode: Res<'w, State<Mode>>,
    pub stage: Res<'w, Stage>,
}

impl Default for Stage {
    /// Free play: everything on, at the default virtual-camera resolution.
    fn default() -> Self {
        Self {
            rays: Some(voxcast_core::tunables::VIRTUAL_RESOLUTION.default as u32),
            rays_shown: true,
            light_marker: true,
            preview: true,
            lecture_ray: false,
        }
    }
}

impl Stage {
    /// What level scene `s` holds.
    pub fn of(s: &voxcast_core::level::LevelScene) -> Self {
        Self {
            rays: s.rays,
            rays_shown: true,
            light_marker: s.light,
            preview: s.preview,
            lecture_ray: s.lecture_ray,
        }
    }
}

/// Free play's stage (the command line sets its virtual camera: `--rays`, `--no-rays`).
#[derive(Resource, Clone, Copy, Debug, Default)]
pub struct FreePlay(pub Stage);

/// The state and the stage, in the window and headless alike (`DefaultPlugins` brings the
/// state machinery).
pub(crate) fn plugin(app: &mut App) {
    app.init_state::<Mode>()
        .init_resource::<Stage>()
        .init_resource::<FreePlay>();
}
