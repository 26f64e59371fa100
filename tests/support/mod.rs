//! The harness of the tests that need something a machine may lack (a Vulkan device, an X
//! display): they run under `libtest-mimic`, so a test that cannot run here is reported as
//! *ignored*, with the reason, instead of passing silently.
#![allow(dead_code)]

#[path = "../../crates/voxcast_core/tests/support/harness.rs"]
mod harness;
pub use harness::*;
pub mod webdriver;

/// Whether `VOXCAST_REQUIRE_GPU=1` (as `.ci/run` sets it) makes a missing device a failure.
pub fn gpu_required() -> bool {
    std::env::var_os("VOXCAST_REQUIRE_GPU").is_some_and(|v| v == "1")
}

/// `Some(ignored)` when a failed run's error output says it found no Vulkan device and that
/// is allowed here; `None` when the failure is the test's to report.
pub fn skipped_for_want_of_a_gpu(stderr: &str) -> Option<Outcome> {
    let missing = stderr.contains("Unable to find a GPU") || stderr.contains("adapter");
    (missing && !gpu_required()).then(|| {
        Ok(Completion::ignored_with(
            "no Vulkan device here (VOXCAST_REQUIRE_GPU=1 makes this a failure)",
        ))
    })
}

/// Runs the sandbox `command`: its standard output and error once it succeeded; `Err` with the
/// *ignored* outcome where it failed for want of a Vulkan device that may be missing here. Any
/// other failure fails the test, with both outputs.
pub fn run_or_skip(command: &mut std::process::Command) -> Result<(String, String), Outcome> {
    let output = command.output().expect("the binary runs");
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    if !output.status.success()
        && let Some(skip) = skipped_for_want_of_a_gpu(&stderr)
    {
        return Err(skip);
    }
    assert!(output.status.success(), "{stdout}\n{stderr}");
    Ok((stdout, stderr))
}

/// The sandbox `exe`'s command, inside `xvfb-run` when there is no display; `None` without
/// either.
pub fn windowed(exe: &str) -> Option<std::process::Command> {
    use std::process::Command;
    if std::env::var_os("DISPLAY").is_some() {
        return Some(Command::new(exe));
    }
    let has_xvfb = Command::new("xvfb-run").arg("--help").output().is_ok();
    has_xvfb.then(|| {
        let mut c = Command::new("xvfb-run");
        c.args(["-a", "-s", "-screen 0 1280x800x24", exe]);
        c
    })
}
