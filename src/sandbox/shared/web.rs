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

/// The browser's WebGPU adapter as the loader read it (`voxcastAdapter`, `web/voxcast.js`): its
/// name in words and whether it is the browser's fallback adapter, a software rasterizer.
/// wgpu names neither in a browser. None in the WebGL2 build.
pub fn webgpu_adapter() -> Option<(String, bool)> {
    let adapter = js_sys::Reflect::get(&js_sys::global(), &JsValue::from_str("voxcastAdapter"))
        .ok()
        .filter(|a| a.is_object())?;
    let field = |name: &str| js_sys::Reflect::get(&adapter, &JsValue::from_str(name)).ok();
    let name = field("name")
        .and_then(|n| n.as_string())
        .unwrap_or_default();
    let fallback = field("fallback").and_then(|f| f.as_bool()).unwrap_or(false);
    Some((name, fallback))
}

/// Hands the core the real datasets' files the page fetched beside the module
/// (`voxcastVolumes`, `web/voxcast.js`) and lets the page's copy go.
pub fn take_fetched_volumes() {
    let global = js_sys::global();
    let key = JsValue::from_str("voxcastVolumes");
    let Ok(fetched) = js_sys::Reflect::get(&global, &key) else {
        return;
    };
    for (_, file) in voxcast_core::builtin::FILES {
        let bytes = js_sys::Reflect::get(&fetched, &JsValue::from_str(file));
        if let Some(bytes) = bytes
            .ok()
            .and_then(|b| b.dyn_into::<js_sys::Uint8Array>().ok())
        {
            voxcast_core::builtin::provide(file, bytes.to_vec());
        }
    }
    let _ = js_sys::Reflect::delete_property(global.unchecked_ref::<js_sys::Object>(), &key);
}

/// Fetches the file of the real dataset `source` names from the page's `volumes/` folder and
/// hands it to the core, where the page has not yet (the loader fetches only what the page
/// opens with); nothing for any other source.
pub async fn fetch_dataset(source: &str) -> Result<(), String> {
    let Some(file) = voxcast_core::builtin::missing_file(source) else {
        return Ok(());
    };
    let fail = |why: &str| format!("{source}: the page could not fetch volumes/{file} ({why})");
    let window = web_sys::window().ok_or_else(|| fail("no window"))?;
    let response =
        wasm_bindgen_futures::JsFuture::from(window.fetch_with_str(&format!("volumes/{file}")))
            .await
            .map_err(|_| fail("no connection"))?;
    let response: web_sys::Response = response.dyn_into().map_err(|_| fail("no response"))?;
    if !response.ok() {
        return Err(fail(&format!("HTTP {}", response.status())));
    }
    let buffer = response.array_buffer().map_err(|_| fail("unreadable"))?;
    let buffer = wasm_bindgen_futures::JsFuture::from(buffer)
        .await
        .map_err(|_| fail("cut off"))?;
    voxcast_core::builtin::provide(file, js_sys::Uint8Array::new(&buffer).to_vec());
    Ok(())
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
    /// The volume shown, whether another is loading (and the share of it read, 0 to 1; -1
    /// when the load does not say), and the last load's error.
    pub volume: String,
    pub loading: bool,
    pub load_progress: f32,
    pub load_error: String,
    /// The bytes the page's WebAssembly memory holds (it only grows, up to 4 GB).
    pub memory: u64,
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
    /// Only background work runs: the page draws its progress now and then (`pacing.rs`).
    pub working: bool,
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

/// Volume files the page handed over as the browser's file handles, not yet read (a volume may
/// be hundreds of megabytes): their names and sizes, and the number under which
/// [`take_volume_files`] gives the handles. Read by the data feature, with progress and Cancel.
#[derive(Message, Clone, Debug)]
pub struct VolumeHanded {
    pub id: u64,
    pub files: Vec<(String, u64)>,
}

thread_local! {
    static HANDED: RefCell<Vec<FilesHanded>> = const { RefCell::new(Vec::new()) };
    static VOLUMES: RefCell<Vec<VolumeHanded>> = const { RefCell::new(Vec::new()) };
    static HANDLES: RefCell<Vec<(u64, Vec<web_sys::Blob>)>> = const { RefCell::new(Vec::new()) };
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
    super::wake::wake();
}

/// The page hands over a volume's files (picked or dropped): their names and the browser's
/// handles on them, read later in pieces ([`read_file`]).
#[wasm_bindgen]
pub fn voxcast_receive_volume(names: Vec<String>, files: Vec<web_sys::Blob>) {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let id = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let sized = names
        .into_iter()
        .zip(&files)
        .map(|(name, file)| (name, file.size() as u64))
        .collect();
    HANDLES.with(|h| h.borrow_mut().push((id, files)));
    VOLUMES.with(|v| v.borrow_mut().push(VolumeHanded { id, files: sized }));
    super::wake::wake();
}

/// The handles of the volume files handed over as `id`, in their order (once; none after).
pub fn take_volume_files(id: u64) -> Vec<web_sys::Blob> {
    HANDLES.with(|h| {
        let mut h = h.borrow_mut();
        let at = h.iter().position(|(i, _)| *i == id);
        at.map(|i| h.swap_remove(i).1).unwrap_or_default()
    })
}

/// How much of a file [`read_file`] reads a frame: a piece copied into the page's memory in a
/// few milliseconds; a 256 MB file is read over 16 frames, so its share read moves on screen
/// and Cancel is heard between pieces.
const PIECE: u64 = 16 << 20;

/// Resolves when the page draws its next frame.
async fn next_frame() {
    let promise = js_sys::Promise::new(&mut |resolve, _| {
        if let Some(window) = web_sys::window() {
            let _ = window.request_animation_frame(&resolve);
        }
    });
    let _ = wasm_bindgen_futures::JsFuture::from(promise).await;
}

/// Reads `file` into memory a piece a frame, the page drawing between pieces; `progress` is
/// told the bytes read so far after each piece. `Ok(None)` when `cancel` was set.
pub async fn read_file(
    file: &web_sys::Blob,
    mut progress: impl FnMut(u64),
    cancel: &std::sync::atomic::AtomicBool,
) -> Result<Option<Vec<u8>>, String> {
    let size = file.size() as u64;
    let mut bytes = Vec::new();
    bytes
        .try_reserve_exact(size as usize)
        .map_err(|_| "the page has no room left to read it".to_string())?;
    let mut at = 0;
    while at < size {
        next_frame().await;
        if cancel.load(std::sync::atomic::Ordering::Relaxed) {
            return Ok(None);
        }
        let end = (at + PIECE).min(size);
        let piece = file
            .slice_with_f64_and_f64(at as f64, end as f64)
            .map_err(|_| "the browser could not cut the file into pieces".to_string())?;
        let buffer = wasm_bindgen_futures::JsFuture::from(piece.array_buffer())
            .await
            .map_err(|_| "the browser could not read the file (was it moved or deleted?)")?;
        let start = bytes.len();
        bytes.resize(start + (end - at) as usize, 0);
        js_sys::Uint8Array::new(&buffer).copy_to(&mut bytes[start..]);
        at = end;
        progress(at);
    }
    Ok(Some(bytes))
}

/// The bytes the page's WebAssembly memory holds now.
fn memory_bytes() -> u64 {
    wasm_bindgen::memory()
        .dyn_into::<js_sys::WebAssembly::Memory>()
        .map(|m| {
            m.buffer()
                .unchecked_into::<js_sys::ArrayBuffer>()
                .byte_length() as u64
        })
        .unwrap_or(0)
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
        .add_message::<VolumeHanded>()
        .add_systems(First, hand_over_files)
        .add_systems(Last, count_frames);
}

/// Turns the files the page handed over into messages.
fn hand_over_files(
    mut handed: MessageWriter<FilesHanded>,
    mut volumes: MessageWriter<VolumeHanded>,
) {
    for files in HANDED.with(|h| std::mem::take(&mut *h.borrow_mut())) {
        handed.write(files);
    }
    for volume in VOLUMES.with(|v| std::mem::take(&mut *v.borrow_mut())) {
        volumes.write(volume);
    }
}

fn count_frames() {
    let memory = memory_bytes();
    publish(|s| {
        s.frames += 1;
        s.memory = memory;
    });
}
