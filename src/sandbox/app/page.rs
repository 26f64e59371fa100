//! The sandbox in a browser: its options from the page's address, then [`run`](super::run).

use super::args::SandboxArgs;
use crate::sandbox::shared;

/// The sandbox's options as the page's address gives them: `?volume=builtin:head&no-rays` is
/// `--volume builtin:head --no-rays`, the same names as the command line's.
#[derive(clap::Parser, Debug)]
#[command(name = "voxcast", no_binary_name = true)]
struct PageOptions {
    #[command(flatten)]
    sandbox: SandboxArgs,
}

/// Starts the sandbox in the page (the wasm module's `main`).
pub fn run() {
    shared::web::take_fetched_volumes();
    let args = address_options();
    let options = match <PageOptions as clap::Parser>::try_parse_from(&args) {
        Ok(o) => o,
        Err(e) => {
            let text = e.to_string();
            shared::web::show_error(&format!(
                "The page's address has options the sandbox does not know: {text}"
            ));
            return;
        }
    };
    if let Err(e) = super::run::run(&options.sandbox) {
        shared::web::show_error(&e.to_string());
    }
}

/// The page's query string as command-line options.
fn address_options() -> Vec<String> {
    let Some(search) = web_sys::window().and_then(|w| w.location().search().ok()) else {
        return Vec::new();
    };
    crate::cli::args::query_to_args(&search, |s| {
        js_sys::decode_uri_component(s)
            .ok()
            .and_then(|v| v.as_string())
            .unwrap_or_else(|| s.to_owned())
    })
}
