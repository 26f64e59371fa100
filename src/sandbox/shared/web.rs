//! The page around the sandbox in a browser (wasm32): the canvas it draws in, files chosen or dropped on the page, downloads for what it saves, the
//! browser's local storage for the levels' progress, a line of the page for what a student
//! should know about the graphics, and what the page's own test reads of the sandbox's state.
//!
//! Everything here talks to the page through `web-sys`; the rest of the sandbox sees plain Rust
//! (bytes, strings, messages) and works the same on the desktop.

use bevy::prelude::*;
use std::cell::RefCell;
use wasm_bindgen::JsCast;
use wasm_bindgen::prelude::*;

/// The canvas the page gives the sandbox (`web/index.html`).
pub const CANVAS: &str = "#voxcast-canvas";

/// Shows `text` in the page's error box (`#voxcast-error`) and the console.
pub fn show_error(text: &str) {
    web_sys::console::error_1(&JsValue::from_str(text));
    set_text("voxcast-error", text);
}

/// Writes the page's one line about the graphics (`#voxcast-notice`), or clears it.
pub fn set_notice(text: &str) {
    set_text("voxcast-notice", text);
}

fn set_text(id: &str, text: &str) {
    let element = web_sys::window()
        .and_then(|w| w.document())
        .and_then(|d| d.get_element_by_id(id));
    if let Some(element) = element {
        element.set_text_content(Some(text));
        if let Some(html) = element.dyn_ref::<web_sys::HtmlElement>() {
            html.set_hidden(text.is_empty());
        }
    }
}

/// Offers `bytes` to the student as a download named `name` (the browser's own save, into
/// their downloads folder).
pub fn download(name: &str, bytes: &[u8], mime: &str) -> Result<(), String> {
    let fail = |what: &str| format!("the browser did not save {name}: {what}");
    let window = web_sys::window().ok_or_else(|| fail("no window"))?;
    let document = window.document().ok_or_else(|| fail("no document"))?;
    let array = js_sys::Uint8Array::from(bytes);
    let parts = js_sys::Array::of1(&array);
    let options = web_sys::BlobPropertyBag::new();
    options.set_type(mime);
    let blob = web_sys::Blob::new_with_u8_array_sequence_and_options(&parts, &options)
        .map_err(|_| fail("could not make the file"))?;
    let url = web_sys::Url::create_object_url_with_blob(&blob)
        .map_err(|_| fail("could not make its address"))?;
    let link: web_sys::HtmlAnchorElement = document
        .create_element("a")
        .map_err(|_| fail("no link"))?
        .unchecked_into();
    link.set_href(&url);
    link.set_download(name);
    link.click();
    // The download reads the address after this returns: let it go a minute later.
    let revoke = Closure::once_into_js(move || {
        let _ = web_sys::Url::revoke_object_url(&url);
    });
    let _ = window
        .set_timeout_with_callback_and_timeout_and_arguments_0(revoke.unchecked_ref(), 60_000);
    Ok(())
}

/// Puts `text` on the clipboard (the browser asks nothing for a click's copy).
pub fn copy_text(text: &str) -> Result<(), String> {
    let window = web_sys::window().ok_or("no window")?;
    let _ = window.navigator().clipboard().write_text(text);
    Ok(())
}

/// The page's own address, without its fragment: what a level's link is made on.
pub fn page_address() -> String {
    web_sys::window()
        .and_then(|w| w.location().href().ok())
        .map(|href| href.split('#').next().unwrap_or_default().to_string())
        .unwrap_or_default()
}

/// The browser's local storage of this page's origin.
fn storage() -> Option<web_sys::Storage> {
    web_sys::window()?.local_storage().ok()?
}

/// The text stored under `key`, if any.
pub fn stored(key: &str) -> Option<String> {
    storage()?.get_item(key).ok()?
}

/// Stores `text` under `key`.
pub fn store(key: &str, text: &str) -> Result<(), String> {
    storage()
        .ok_or_else(|| "this browser keeps no local storage for the page".to_string())?
        .set_item(key, text)
        .map_err(|_| "the browser's local storage refused it (full, or private browsing)".into())
}

/// What the page's test reads of the sandbox (`voxcast_status()` in the page's console).
#[derive(Default, Clone, serde::Serialize)]
pub struct PageStatus {
    /// Frames drawn since the start.
    pub frames: u64,
    /// What the sandbox shows: the levels list, a level's step, free play.
    pub mode: String,
    /// The current step's text, when a level is played.
    pub step_text: String,
    /// What the levels say about the progress kept (damaged, not saved), if anything.
    pub levels_message: String,
    /// The level editor's draft's steps (0: no draft), its last link (Copy link) and what it
    /// said last (saved, copied).
    pub editor_steps: usize,
    pub editor_link: String,
    pub editor_message: String,
    /// Where the named controls a test clicks are: x, y, width, height in the UI's points
    /// (the canvas is `canvas` points across).
    pub targets: Vec<(String, [f32; 4])>,
    /// The 3-D view's rectangle, in the UI's points.
    pub scene: [f32; 4],
    /// The canvas's size in the UI's points.
    pub canvas: [f32; 2],
    /// The volume shown, whether another is loading, and the last load's error.
    pub volume: String,
    pub loading: bool,
    pub load_error: String,
    /// Render image's state: "open", "rendering", "done in … s".
    pub render: String,
    /// `--measure-frames`' figures, once measured.
    pub measured: String,
    /// The browser's graphics adapter, as it names itself.
    pub adapter: String,
    /// Who draws the volume: "gpu", "cpu" or "off".
    pub backend: String,
    /// What the CPU live view shows, in words (its frame's size and time).
    pub live: String,
    /// The volume is drawn at full quality for the view (the CPU's exact render, the GPU's
    /// whole frame), not a coarse frame or a refinement under way.
    pub settled: bool,
    /// The page rests: nothing moves or is under way, so it draws only on input or now and
    /// then (`pacing.rs`).
    pub resting: bool,
    /// What last kept it drawing, in words.
    pub woken_by: String,
}

thread_local! {
    static STATUS: RefCell<PageStatus> = RefCell::new(PageStatus::default());
}

/// Updates what the page's test reads.
pub fn publish(update: impl FnOnce(&mut PageStatus)) {
    STATUS.with(|s| update(&mut s.borrow_mut()));
}

/// The sandbox's state as JSON, for the page's test (and a curious student's console).
#[wasm_bindgen]
pub fn voxcast_status() -> String {
    STATUS.with(|s| serde_json::to_string(&*s.borrow()).unwrap_or_default())
}

/// Files the page handed over: what they are for, as the page names it (the name the picker
/// was asked with), and each file's name and bytes. Written at the start of a frame; the files
/// feature turns them into its own messages.
#[derive(Message, Clone, Debug)]
pub struct FilesHanded {
    pub purpose: String,
    pub files: Vec<(String, Vec<u8>)>,
}

thread_local! {
    static HANDED: RefCell<Vec<FilesHanded>> = const { RefCell::new(Vec::new()) };
}

/// The page hands over files a student picked or dropped (`web/voxcast.js`): their names and
/// bytes, and what they are for (`volume`, `transfer`, `rays`).
#[wasm_bindgen]
pub fn voxcast_receive_files(purpose: String, names: Vec<String>, files: Vec<js_sys::Uint8Array>) {
    let files = names
        .into_iter()
        .zip(files)
        .map(|(name, bytes)| (name, bytes.to_vec()))
        .collect();
    HANDED.with(|h| h.borrow_mut().push(FilesHanded { purpose, files }));
}

/// Asks the page for files: the browser's file picker, offering `accept` (`.nrrd,.nii,…`);
/// what the student chooses arrives as a [`FilesHanded`] message with this `purpose`.
pub fn pick_files(purpose: &str, accept: &str) {
    let Some(window) = web_sys::window() else {
        return;
    };
    let pick = js_sys::Reflect::get(&window, &JsValue::from_str("voxcastPick"))
        .ok()
        .and_then(|f| f.dyn_into::<js_sys::Function>().ok());
    match pick {
        Some(pick) => {
            let _ = pick.call2(
                &JsValue::NULL,
                &JsValue::from_str(purpose),
                &JsValue::from_str(accept),
            );
        }
        None => show_error("this page has no file picker (voxcast.js did not load)"),
    }
}

pub(crate) fn plugin(app: &mut App) {
    app.add_message::<FilesHanded>()
        .add_systems(First, hand_over_files)
        .add_systems(Last, count_frames);
}

/// Turns the files the page handed over into messages.
fn hand_over_files(mut handed: MessageWriter<FilesHanded>) {
    for files in HANDED.with(|h| std::mem::take(&mut *h.borrow_mut())) {
        handed.write(files);
    }
}

fn count_frames() {
    publish(|s| s.frames += 1);
}
