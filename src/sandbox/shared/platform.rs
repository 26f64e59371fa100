//! What the sandbox needs from the machine before Bevy starts: a display to open a window on
//! (or a clear error that says how to work without one), a runtime directory for the window
//! system's client libraries, and a log that carries colour codes only to a terminal. In a
//! browser there is none of this: the page is the window and the console the log.

use crate::cli::CliError;
use bevy::log::LogPlugin;
#[cfg(target_os = "linux")]
use std::path::{Path, PathBuf};

/// The error when no window can be opened, with what to do instead.
#[cfg(target_os = "linux")]
pub fn no_display(why: &str) -> CliError {
    CliError::failed(format!(
        "{why}: the sandbox needs a window. Run it on a desktop, or under a virtual display \
         (`xvfb-run -a voxcast`); without one, `voxcast --screenshot preview.png` saves the \
         preview, `voxcast --compare cmp.png` the preview beside the exact render, and \
         `voxcast render --out out.png` the exact CPU image"
    ))
}

/// Checks, before winit tries (and panics), that a display server can be reached: Wayland's
/// socket, or X11's (local displays by their socket file; a remote `host:N` is left to the
/// X library).
pub fn check_display() -> Result<(), CliError> {
    #[cfg(target_os = "linux")]
    check_linux_display()?;
    Ok(())
}

#[cfg(target_os = "linux")]
fn check_linux_display() -> Result<(), CliError> {
    let runtime = std::env::var_os("XDG_RUNTIME_DIR").map(PathBuf::from);
    if let (Some(name), Some(dir)) = (std::env::var_os("WAYLAND_DISPLAY"), &runtime) {
        let socket = Path::new(&name);
        let socket = if socket.is_absolute() {
            socket.to_path_buf()
        } else {
            dir.join(socket)
        };
        if socket.exists() {
            return Ok(());
        }
    }
    let Some(display) = std::env::var("DISPLAY").ok().filter(|d| !d.is_empty()) else {
        return Err(no_display("no display (DISPLAY is not set)"));
    };
    match local_x_socket(&display) {
        Some(socket) if !socket.exists() => Err(no_display(&format!(
            "no X server answers on display {display} ({} does not exist)",
            socket.display()
        ))),
        _ => Ok(()),
    }
}

/// The socket file of a local X display (`:1`, `:1.0`, `unix:1`), `None` for a remote one.
#[cfg(target_os = "linux")]
fn local_x_socket(display: &str) -> Option<PathBuf> {
    let (host, rest) = display.rsplit_once(':')?;
    if !(host.is_empty() || host == "unix") {
        return None;
    }
    let number = rest.split('.').next()?;
    number.parse::<u32>().ok()?;
    Some(PathBuf::from(format!("/tmp/.X11-unix/X{number}")))
}

/// Gives the window system's client libraries a private runtime directory when the
/// environment has none (they print "XDG_RUNTIME_DIR is invalid or not set" otherwise).
/// Called first thing in `main`, before any thread starts.
#[cfg(not(target_arch = "wasm32"))]
pub fn ensure_runtime_dir() {
    #[cfg(target_os = "linux")]
    ensure_linux_runtime_dir();
}

#[cfg(target_os = "linux")]
fn ensure_linux_runtime_dir() {
    let ok = std::env::var_os("XDG_RUNTIME_DIR")
        .map(PathBuf::from)
        .is_some_and(|d| d.is_dir());
    if ok {
        return;
    }
    let uid = std::fs::metadata("/proc/self").map_or(0, |m| {
        use std::os::unix::fs::MetadataExt;
        m.uid()
    });
    let dir = std::env::temp_dir().join(format!("voxcast-runtime-{uid}"));
    let made = std::fs::create_dir_all(&dir).and_then(|_| {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o700))
    });
    if made.is_ok() {
        // SAFETY: called at the start of `main`, before any other thread exists.
        unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
    }
}

/// Bevy's log, with colour codes only when standard error is a terminal (and `NO_COLOR`
/// unset), so a log saved to a file reads as plain text; in a browser, its console.
pub fn log_plugin() -> LogPlugin {
    #[cfg(target_arch = "wasm32")]
    return LogPlugin::default();
    #[cfg(not(target_arch = "wasm32"))]
    LogPlugin {
        fmt_layer: |_| {
            use std::io::IsTerminal;
            let colour = std::io::stderr().is_terminal() && std::env::var_os("NO_COLOR").is_none();
            Some(Box::new(
                bevy::log::tracing_subscriber::fmt::Layer::default()
                    .with_writer(std::io::stderr)
                    .with_ansi(colour),
            ))
        },
        ..Default::default()
    }
}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    use super::*;

    #[test]
    fn local_displays_map_to_their_socket() {
        assert_eq!(
            local_x_socket(":91"),
            Some(PathBuf::from("/tmp/.X11-unix/X91"))
        );
        assert_eq!(
            local_x_socket("unix:0.0"),
            Some(PathBuf::from("/tmp/.X11-unix/X0"))
        );
        assert_eq!(local_x_socket("remote.example:0"), None);
        assert_eq!(local_x_socket("garbage"), None);
    }
}
