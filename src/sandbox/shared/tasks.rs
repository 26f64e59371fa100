//! Background work, one code for the desktop and the browser. On the desktop a task runs on
//! Bevy's `AsyncComputeTaskPool`, on threads of its own, and the core's work in it runs whole.
//! A browser gives the page one thread, which also draws its frames: there a task's core work
//! runs in slices of [`SLICE`] to [`LONGEST_SLICE`] ([`voxcast_core::slices`]), and between
//! two slices the task yields to the page, which draws a frame and answers the student, so the
//! page never freezes (Render image's progress and Cancel work as on the desktop).

use bevy::platform::time::Instant;
use bevy::tasks::{AsyncComputeTaskPool, ConditionalSend, Task};
use std::sync::atomic::{AtomicUsize, Ordering};
use voxcast_core::slices::{Deadline, Step};

/// Tasks [`spawn`]ed and not yet finished or dropped.
static IN_FLIGHT: AtomicUsize = AtomicUsize::new(0);

/// One task counted in [`IN_FLIGHT`] while it lives.
struct Counted;

impl Counted {
    fn new() -> Self {
        IN_FLIGHT.fetch_add(1, Ordering::Relaxed);
        Counted
    }
}

impl Drop for Counted {
    fn drop(&mut self) {
        IN_FLIGHT.fetch_sub(1, Ordering::Relaxed);
        // The window may be waiting between frames: the result shows at once.
        super::wake::wake();
    }
}

/// Starts `work` on Bevy's `AsyncComputeTaskPool`, counted while it runs: the window draws its
/// progress while any task is under way and wakes when it ends, so its result shows the frame
/// it is ready (`pacing.rs`).
pub fn spawn<T: ConditionalSend + 'static>(
    work: impl Future<Output = T> + ConditionalSend + 'static,
) -> Task<T> {
    let counted = Counted::new();
    AsyncComputeTaskPool::get().spawn(async move {
        let _counted = counted;
        work.await
    })
}

/// How many [`spawn`]ed tasks are under way.
pub fn in_flight() -> usize {
    IN_FLIGHT.load(Ordering::Relaxed)
}

/// The shortest slice of work in a browser before the page may draw a frame: short enough
/// that the page answers a click within a frame or two.
pub const SLICE: std::time::Duration = std::time::Duration::from_millis(20);

/// The longest slice of work in a browser: where the page's frames are slow (a software
/// renderer draws a frame of the page in 100–200 ms on 2 cores), a slice lasts as long as the
/// page took between the last two slices, up to this, so that the work keeps about half of the
/// time and draws on fewer frames (each frame's drawing competes with it for the cores);
/// the page still answers a click within a quarter of a second.
pub const LONGEST_SLICE: std::time::Duration = std::time::Duration::from_millis(100);

/// The next slice's length, given how long the page took since the last one.
pub fn slice_after(gap: std::time::Duration) -> std::time::Duration {
    gap.clamp(SLICE, LONGEST_SLICE)
}

/// The deadline of a slice of `length`: none on the desktop.
pub fn deadline(length: std::time::Duration) -> Deadline {
    if cfg!(target_arch = "wasm32") {
        Deadline::after(length)
    } else {
        Deadline::NONE
    }
}

/// Lets the page draw a frame before the task goes on (a new task of the browser's event
/// loop, after its frames; on the desktop, nothing).
pub async fn yield_to_page() {
    #[cfg(target_arch = "wasm32")]
    {
        let promise = js_sys::Promise::new(&mut |resolve, _| {
            if let Some(window) = web_sys::window() {
                let _ = window.set_timeout_with_callback(&resolve);
            }
        });
        let _ = wasm_bindgen_futures::JsFuture::from(promise).await;
    }
}

/// Runs `slice` until it is done, yielding to the page between slices; gives the result and
/// the time the slices themselves took (not the frames drawn between them).
pub async fn in_slices<T, E>(
    mut slice: impl FnMut(Deadline) -> Result<Step<T>, E>,
) -> Result<(T, f64), E> {
    let mut busy = 0.0;
    let mut length = SLICE;
    loop {
        let started = Instant::now();
        let step = slice(deadline(length))?;
        busy += started.elapsed().as_secs_f64();
        match step {
            Step::Done(t) => return Ok((t, busy)),
            Step::Paused => {
                let paused = Instant::now();
                yield_to_page().await;
                length = slice_after(paused.elapsed());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn a_slice_lasts_as_long_as_the_page_took_within_its_bounds() {
        assert_eq!(
            slice_after(Duration::ZERO),
            SLICE,
            "a quick page: the shortest"
        );
        assert_eq!(
            slice_after(Duration::from_millis(60)),
            Duration::from_millis(60)
        );
        assert_eq!(
            slice_after(Duration::from_secs(3)),
            LONGEST_SLICE,
            "a stalled page"
        );
        assert_eq!(
            deadline(LONGEST_SLICE),
            Deadline::NONE,
            "the desktop runs whole"
        );
    }
}
