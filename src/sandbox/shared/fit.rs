//! The window fits the screen: without `--size`, a window larger than its monitor's usable part
//! (a small laptop screen, or a large one scaled up) is made smaller once the monitor is known,
//! so that no panel starts off screen.

use bevy::prelude::*;
use bevy::window::{Monitor, PrimaryMonitor, PrimaryWindow};

/// The window's size when none is asked for (logical pixels).
pub const DEFAULT_SIZE: (u32, u32) = (1280, 720);

/// The share of the monitor's width and height a window may take at most: the rest is left to
/// the title bar, a task bar or dock, and the window manager's margins.
const USABLE: (f32, f32) = (0.95, 0.88);

/// Smaller than this the panels no longer fit side by side: a window is never made smaller.
const SMALLEST: (f32, f32) = (800.0, 500.0);

/// Frames to wait for the monitor to be reported before leaving the window as it is.
const PATIENCE: u32 = 120;

/// Fits the window to the screen (only where no size was asked for).
pub(crate) fn plugin(app: &mut App) {
    app.add_systems(Update, fit_window.in_set(super::schedule::Frame::Input));
}

/// The logical size a window of `window` logical pixels should take on a monitor of
/// `monitor` logical pixels: as it is where it fits, else the usable part, never below
/// [`SMALLEST`] nor above what it was.
pub fn fitted((w, h): (f32, f32), (mw, mh): (f32, f32)) -> (f32, f32) {
    let fit = |size: f32, screen: f32, share: f32, least: f32| {
        size.min((screen * share).max(least)).round()
    };
    (
        fit(w, mw, USABLE.0, SMALLEST.0),
        fit(h, mh, USABLE.1, SMALLEST.1),
    )
}

fn fit_window(
    mut windows: Query<&mut Window, With<PrimaryWindow>>,
    monitors: Query<&Monitor, With<PrimaryMonitor>>,
    mut frames: Local<u32>,
) {
    if *frames > PATIENCE {
        return;
    }
    *frames += 1;
    let (Ok(mut window), Ok(monitor)) = (windows.single_mut(), monitors.single()) else {
        return;
    };
    *frames = PATIENCE + 1; // once
    let scale = monitor.scale_factor.max(1e-3) as f32;
    let screen = monitor.physical_size().as_vec2() / scale;
    let size = (window.resolution.width(), window.resolution.height());
    let (w, h) = fitted(size, (screen.x, screen.y));
    if (w, h) != size {
        info!(
            "the screen is {:.0}×{:.0}: the window is made {w:.0}×{h:.0} to fit",
            screen.x, screen.y
        );
        window.resolution.set(w, h);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_window_that_fits_stays_and_one_that_does_not_shrinks() {
        // A full-HD screen: the default window fits.
        assert_eq!(fitted((1280.0, 720.0), (1920.0, 1080.0)), (1280.0, 720.0));
        // Full HD at 150 %: 1280×720 logical, with no room for a title bar.
        assert_eq!(fitted((1280.0, 720.0), (1280.0, 720.0)), (1216.0, 634.0));
        // A 1024×600 netbook.
        assert_eq!(fitted((1280.0, 720.0), (1024.0, 600.0)), (973.0, 528.0));
        // Never below the smallest that works, however small the screen.
        assert_eq!(fitted((1280.0, 720.0), (640.0, 480.0)), (800.0, 500.0));
    }

    /// In an app: the primary window shrinks to its primary monitor, once it is reported.
    #[test]
    fn the_window_shrinks_once_the_monitor_is_known() {
        let mut app = App::new();
        app.add_plugins(plugin);
        let window =
            crate::sandbox::shared::viewport::spawn_test_window(app.world_mut(), 1280, 720);
        app.update();
        let size = |app: &App| {
            let w = app.world().get::<Window>(window).unwrap();
            (w.resolution.width(), w.resolution.height())
        };
        assert_eq!(size(&app), (1280.0, 720.0), "no monitor yet: as it was");
        app.world_mut().spawn((
            Monitor {
                name: None,
                physical_height: 1200,
                physical_width: 2048,
                physical_position: IVec2::ZERO,
                refresh_rate_millihertz: None,
                scale_factor: 2.0,
                video_modes: Vec::new(),
            },
            PrimaryMonitor,
        ));
        app.update();
        assert_eq!(size(&app), (973.0, 528.0));
    }
}
