//! The top of the sandbox: its command-line options, what it starts with, and the app built from
//! every layer below (the window's or a headless one); in a browser, the page's start. May
//! import every layer.

pub mod args;
mod engine;
#[cfg(target_arch = "wasm32")]
pub mod page;
pub mod run;
mod start;
mod window;
