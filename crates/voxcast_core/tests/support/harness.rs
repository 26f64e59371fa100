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
    run_side_by_side(tests, None)
}

/// [`run`], with `threads` tests at a time unless `--test-threads` says otherwise (by default
/// as many as the machine has cores): for tests that spend their time waiting on other
/// processes (a window on a software GPU, a browser), which leave the cores partly idle.
pub fn run_side_by_side(tests: &[Test], threads: Option<usize>) -> ! {
    let mut args = libtest_mimic::Arguments::from_args();
    if args.test_threads.is_none() {
        args.test_threads = threads;
    }
    let trials = tests
        .iter()
        .map(|&(name, f)| libtest_mimic::Trial::ignorable_test(name, f))
        .collect();
    libtest_mimic::run(&args, trials).exit()
}
