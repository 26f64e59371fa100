//! Long work a slice at a time. A browser gives a page one thread, the one that draws its frames:
//! a render, a measurement or a ray density that takes seconds would freeze the page. So such
//! work can be done in slices: each call works until a [`Deadline`], keeps what it finished in
//! its state (a [`crate::render::TileSlices`], …), and answers [`Step::Paused`]; the caller lets
//! the page draw a frame and calls again with the same state, which carries on where it
//! stopped. The result is the one a single call gives, bit for bit (tested). Without a deadline
//! (the desktop, where the work has threads of its own) one call does the whole.

pub use web_time::Duration;
use web_time::Instant;

/// When a slice of work stops taking new pieces (a tile, a block of rays).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Deadline(Option<Instant>);

impl Deadline {
    /// No deadline: the whole work in one call.
    pub const NONE: Self = Self(None);

    /// `slice` from now.
    pub fn after(slice: Duration) -> Self {
        Self(Some(Instant::now() + slice))
    }

    /// Whether the slice is over.
    pub fn passed(&self) -> bool {
        self.0.is_some_and(|d| Instant::now() >= d)
    }
}

/// What a call of work done in slices gives.
#[derive(Clone, Debug, PartialEq)]
pub enum Step<T> {
    /// The work is finished.
    Done(T),
    /// The deadline came first: call again with the same state.
    Paused,
}

impl<T> Step<T> {
    /// The result of work run without a deadline, which never pauses.
    pub fn whole(self) -> T {
        match self {
            Step::Done(t) => t,
            Step::Paused => unreachable!("work without a deadline runs to its end"),
        }
    }
}

/// Runs `slice` with a fresh deadline `every` apart until it is done, doing nothing between
/// slices: what a page does with frames drawn between them, for tests and measurements.
pub fn until_done<T, E>(
    every: Duration,
    mut slice: impl FnMut(Deadline) -> Result<Step<T>, E>,
) -> Result<(T, usize), E> {
    let mut calls = 0;
    loop {
        calls += 1;
        if let Step::Done(t) = slice(Deadline::after(every))? {
            return Ok((t, calls));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_deadline_never_passes_and_a_past_one_has() {
        assert!(!Deadline::NONE.passed());
        assert!(Deadline::after(Duration::ZERO).passed());
        assert!(!Deadline::after(Duration::from_secs(3600)).passed());
        assert_eq!(Step::Done(3).whole(), 3);
    }
}
