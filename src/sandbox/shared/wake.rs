//! Waking the window from outside its frames: a background task that ends, or the page handing
//! over files a student picked, changes what the window shows while it may be waiting between
//! frames (`pacing.rs`); [`wake`] asks for the next frame at once. The window gives its way of
//! waking (winit's event-loop proxy) with [`set`]; without a window (tests, the command line)
//! waking does nothing.

use std::sync::OnceLock;

/// What [`set`] was given.
static WAKE: OnceLock<Box<dyn Fn() + Send + Sync>> = OnceLock::new();

/// Sets how to wake the window; the first call sets it for the process.
pub fn set(wake: impl Fn() + Send + Sync + 'static) {
    let _ = WAKE.set(Box::new(wake));
}

/// Asks the window for its next frame now (from any thread).
pub fn wake() {
    if let Some(wake) = WAKE.get() {
        wake();
    }
}
