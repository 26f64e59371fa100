//! Tests under `libtest-mimic`, so one that cannot run here is reported as *ignored*, with the
//! reason, instead of passing silently. Shared by the core's tests and the sandbox's (which
//! include this file by path).

pub use libtest_mimic::{Completion, Failed};

/// What a test returns: completed, ignored (with why), or failed.
pub type Outcome = Result<Completion, Failed>;

/// A test: its name and its function.
pub type Test = (&'static str, fn() -> Outcome);

/// Runs the named tests as `cargo test` would, with its filters and flags.
pub fn run(tests: &[Test]) -> ! {
    let args = libtest_mimic::Arguments::from_args();
    let trials = tests
        .iter()
        .map(|&(name, f)| libtest_mimic::Trial::ignorable_test(name, f))
        .collect();
    libtest_mimic::run(&args, trials).exit()
}
