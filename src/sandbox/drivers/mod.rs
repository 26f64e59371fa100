//! The sandbox driven from the command line instead of by a person: a screenshot of the
//! preview, a comparison without a window, the frame time measured, every level played.
//! Imports the layers below (`shared/` to `levels/`).

pub mod ambiguities;
pub mod compare_cli;
pub mod frame_parts;
pub mod measure;
pub mod screenshot;
pub mod script;
