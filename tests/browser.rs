//! The web page in a real browser: Debian's headless `chromium`, driven over WebDriver by
//! `chromedriver`, against the page `web/build.sh` built (`dist/`, or `$VOXCAST_WEB_DIR`)
//! served on 127.0.0.1. Once with WebGL2 (what every browser has; here SwiftShader) and once
//! with WebGPU (SwiftShader's Vulkan through Dawn: the browser's fallback adapter, which the
//! page gives the CPU live view, checked first; the run then asks for the GPU preview). Each
//! run waits for the first frame, checks that the bunny is drawn where the desktop's
//! `--screenshot` draws it, orbits with a drag,
//! renders the exact image while the page keeps drawing, opens a dropped NRRD file (and a
//! damaged one, which leaves it), computes a dropped `.rayvis` file's density, reads a 512³ 16-bit volume with its progress (and Cancel)
//! and draws it, refuses a file over the page's limit in words, starts level 1 with a click and reads its first step,
//! opens a level on a dataset the page fetches when first opened, checks
//! that the scene keeps at least half the page in every layout at 1024×576, and fails on any
//! error in the browser's console. Where chromium, chromedriver or the built page is missing
//! the test is reported as ignored with the reason, unless `VOXCAST_REQUIRE_BROWSER=1` (as
//! `.ci/run` sets it). The page's figures for BENCHMARKS.md (Render image five times, 40 frames
//! orbiting and resting) are taken with `VOXCAST_PAGE_FIGURES=1`, as `benches/web.sh` sets it;
//! without it, once and over a few frames, which checks the same paths.

mod support;

use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use support::webdriver::{Browser, CHROMEDRIVER, CHROMIUM, serve};
use support::{Completion, Outcome};

fn main() {
    support::run(&[
        ("the_page_works_in_chromium_with_webgl2", || page("webgl2")),
        ("the_page_works_in_chromium_with_webgpu", || page("webgpu")),
        (
            "a_page_whose_webgpu_cannot_draw_falls_back_to_webgl2",
            falls_back,
        ),
        (
            "the_loader_fetches_every_real_dataset_the_module_leaves_out",
            loader_fetches_datasets,
        ),
    ])
}

/// The page's module carries no real dataset's file (`embedded-files` is the desktop's): the
/// loader must fetch each of the core's `builtin::FILES`, and `web/build.sh` put them beside it.
fn loader_fetches_datasets() -> Outcome {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let loader = std::fs::read_to_string(root.join("web/voxcast.js")).unwrap();
    let listed = loader
        .lines()
        .find_map(|l| l.strip_prefix("const VOLUME_FILES = "))
        .expect("VOLUME_FILES in web/voxcast.js");
    let build = std::fs::read_to_string(root.join("web/build.sh")).unwrap();
    for (dataset, file) in voxcast_core::builtin::FILES {
        assert!(
            listed.contains(&format!("['{dataset}', '{file}']")),
            "web/voxcast.js does not fetch {file} ({dataset}): {listed}"
        );
        assert!(root.join("assets/volumes").join(file).is_file(), "{file}");
    }
    assert!(
        build.contains("assets/volumes/*.nrrd"),
        "web/build.sh does not copy the datasets"
    );
    let count = listed.matches(".nrrd'").count();
    assert_eq!(count, voxcast_core::builtin::FILES.len(), "{listed}");
    Ok(Completion::Completed)
}

/// The flags under which chromium offers a WebGPU adapter that cannot draw (SwiftShader's
/// WebGPU adapter without its Vulkan): the page stayed blank at its second frame, with no
/// message, until the loader watched for frames.
const BROKEN_WEBGPU_FLAGS: [&str; 2] =
    ["--enable-unsafe-webgpu", "--use-webgpu-adapter=swiftshader"];

/// Where WebGPU stops drawing, the loader notices within seconds and opens the page again with
/// the WebGL2 build, saying so; where WebGL2 then loses its context (as a 1 GB volume texture
/// made it, BENCHMARKS "Large files on the page"; here asked for with `WEBGL_lose_context`),
/// the page says so instead of staying blank.
fn falls_back() -> Outcome {
    let dir = page_dir();
    if let Some(skip) = unavailable(&dir, &["webgl2", "webgpu"]) {
        return Ok(skip);
    }
    let out = out_dir().join("fallback");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();
    let port = serve(&dir);
    let browser =
        Browser::start(&BROKEN_WEBGPU_FLAGS, &out).map_err(|e| format!("chromium: {e}"))?;
    browser.set_viewport(1024, 576)?;
    let started = Instant::now();
    browser.open(&format!("http://127.0.0.1:{port}/?no-rays"))?;
    let first = browser.wait_for("return window.voxcastGraphics", FIRST_FRAME)?;
    let drawn = browser
        .wait_for(
            "return window.voxcastGraphics === 'webgl2' && window.voxcastStatus \
             && window.voxcastStatus().frames >= 2 && location.search",
            FIRST_FRAME + Duration::from_secs(30),
        )
        .map_err(|e| format!("{e}\nthe browser's log: {:#?}", browser.log()))?;
    let notice = browser.run(
        "const n = document.getElementById('voxcast-switched'); return n.hidden ? '' : n.textContent",
        json!([]),
    )?;
    let png = browser.screenshot()?;
    std::fs::write(out.join("fallback.png"), &png).map_err(|e| e.to_string())?;
    println!(
        "chromium {BROKEN_WEBGPU_FLAGS:?}: the loader chose {first} first; drawing with WebGL2 \
         after {:.1} s at {drawn}; the page says: {notice}",
        started.elapsed().as_secs_f64()
    );
    if first == json!("webgpu") {
        let search = drawn.as_str().unwrap_or_default();
        assert!(
            search.contains("gpu=webgl2") && search.contains("fallback=webgpu"),
            "the page did not reopen with WebGL2: {search}"
        );
        assert!(
            notice
                .as_str()
                .unwrap_or_default()
                .contains("switched to WebGL2"),
            "the page does not say why it switched: {notice}"
        );
    } else {
        println!(
            "note: this chromium offers no WebGPU adapter under these flags: no fallback needed"
        );
    }
    browser.run(
        "document.getElementById('voxcast-canvas').getContext('webgl2') \
           .getExtension('WEBGL_lose_context').loseContext();",
        json!([]),
    )?;
    let said = browser.wait_for(
        "const e = document.getElementById('voxcast-error'); return !e.hidden && e.textContent",
        Duration::from_secs(30),
    )?;
    println!("WebGL2's context lost: the page says {said}");
    assert!(
        said.as_str()
            .unwrap_or_default()
            .contains("lost its context"),
        "{said}"
    );
    Ok(Completion::Completed)
}

/// The seconds of work in Render image's "done in … s of work, … s on the clock".
fn work_seconds(said: &Value) -> f64 {
    said.as_str()
        .and_then(|s| s.strip_prefix("done in "))
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or(f64::NAN)
}

/// The test reported as ignored where the page cannot be tested here (chromium, chromedriver
/// or a build missing), unless `VOXCAST_REQUIRE_BROWSER=1` makes that a failure.
fn unavailable(dir: &Path, builds: &[&str]) -> Option<Completion> {
    let why = missing(dir, builds)?;
    assert!(!browser_required(), "{why}");
    Some(Completion::ignored_with(format!(
        "{why}; VOXCAST_REQUIRE_BROWSER=1 makes this a failure"
    )))
}

/// Why the page cannot be tested here, if it cannot: chromium, chromedriver or a build missing.
fn missing(dir: &Path, builds: &[&str]) -> Option<String> {
    [
        (!Path::new(CHROMIUM).exists()).then(|| format!("no {CHROMIUM} (package chromium)")),
        (!Path::new(CHROMEDRIVER).exists())
            .then(|| format!("no {CHROMEDRIVER} (package chromium-driver)")),
    ]
    .into_iter()
    .flatten()
    .chain(
        builds
            .iter()
            .filter(|graphics| !dir.join(graphics).join("voxcast_bg.wasm").exists())
            .map(|_| {
                format!(
                    "no page built in {} (bash web/build.sh {})",
                    dir.display(),
                    dir.display()
                )
            }),
    )
    .next()
}

/// Whether `VOXCAST_REQUIRE_BROWSER=1` makes a missing browser or page a failure.
fn browser_required() -> bool {
    std::env::var_os("VOXCAST_REQUIRE_BROWSER").is_some_and(|v| v == "1")
}

/// The built page, if there is one.
fn page_dir() -> PathBuf {
    std::env::var_os("VOXCAST_WEB_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("dist"))
}

fn out_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/out/browser")
}

/// Whether to take the page's figures for BENCHMARKS.md (`benches/web.sh` asks): Render image
/// five times for a median and 40 frames orbiting and resting, some 40 s a build on 2 cores;
/// otherwise once, and 8 frames orbiting.
fn figures_asked() -> bool {
    std::env::var_os("VOXCAST_PAGE_FIGURES").is_some_and(|v| v == "1")
}

/// How long the page may take to show its first frame in headless chromium on 2 cores.
const FIRST_FRAME: Duration = Duration::from_secs(120);

/// The WebGPU run's flags: chromium offers WebGPU on SwiftShader's Vulkan only when asked.
const WEBGPU_FLAGS: [&str; 4] = [
    "--enable-unsafe-webgpu",
    "--enable-features=Vulkan",
    "--use-vulkan=swiftshader",
    "--use-webgpu-adapter=swiftshader",
];

/// The WebGPU build on chromium's fallback adapter: the adapter named as the browser names it,
/// and the volume drawn by the CPU live view (as a visitor without a graphics card gets it).
fn software_adapter_gets_the_cpu(browser: &Browser, port: u16) -> Result<(), String> {
    let started = Instant::now();
    browser.open(&format!("http://127.0.0.1:{port}/?gpu=webgpu&no-rays"))?;
    let chosen = browser.wait_for(
        "const s = window.voxcastStatus && window.voxcastStatus(); \
         return s && s.frames >= 2 && s.adapter !== '' && s.backend === 'cpu' && s",
        FIRST_FRAME,
    )?;
    println!(
        "webgpu as a visitor gets it: the adapter \"{}\", the volume drawn by the CPU live \
         view; {} frames after {:.1} s",
        chosen["adapter"].as_str().unwrap_or_default(),
        chosen["frames"],
        started.elapsed().as_secs_f64()
    );
    assert!(
        chosen["adapter"]
            .as_str()
            .is_some_and(|a| a.contains("swiftshader")),
        "{chosen}"
    );
    Ok(())
}

fn page(graphics: &str) -> Outcome {
    let dir = page_dir();
    if let Some(skip) = unavailable(&dir, &[graphics]) {
        return Ok(skip);
    }
    let out = out_dir().join(graphics);
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();
    let port = serve(&dir);
    let flags: &[&str] = if graphics == "webgpu" {
        &WEBGPU_FLAGS
    } else {
        &[]
    };
    let downloads = out.join("downloads");
    std::fs::create_dir_all(&downloads).unwrap();
    let browser = Browser::start(flags, &downloads).map_err(|e| format!("chromium: {e}"))?;
    let page = Page {
        browser: &browser,
        out: &out,
    };
    browser.set_viewport(1280, 720)?;

    // WebGPU here is chromium's fallback adapter (SwiftShader: no graphics card), which the
    // page treats as the software rasterizer it is: the CPU live view draws the volume, as in
    // the WebGL2 build. The rest of this run asks for the GPU preview, the WebGPU path of a
    // visitor with a graphics card.
    let forced = if graphics == "webgpu" {
        software_adapter_gets_the_cpu(&browser, port)?;
        "&preview-backend=gpu"
    } else {
        ""
    };

    // The first frame, and the graphics the page chose.
    let started = Instant::now();
    browser.open(&format!(
        "http://127.0.0.1:{port}/?gpu={graphics}&no-rays{forced}"
    ))?;
    browser
        .wait_for(
            "return window.voxcastStatus && window.voxcastStatus().frames >= 2",
            FIRST_FRAME,
        )
        .map_err(|e| format!("{e}\nthe browser's log: {:#?}", browser.log()))?;
    let first_frame = started.elapsed();
    let chosen = browser.run("return window.voxcastGraphics", json!([]))?;
    assert_eq!(chosen, json!(graphics), "the page runs the build asked for");

    // The bunny, where the desktop draws it.
    let bunny = page.wait_for_picture("bunny", |s| s.drawn > 0.05)?;
    println!(
        "{graphics}: first frame after {:.1} s; the volume drawn by the {} ({}, {}); {:.0} % \
         of the scene differs from the background",
        first_frame.as_secs_f64(),
        page.status()?["backend"],
        page.status()?["live"],
        page.status()?["adapter"],
        100.0 * bunny.drawn
    );
    if let Some(desktop) = desktop_silhouette(&bunny, &out, &[])? {
        let overlap = bunny.overlap(&desktop);
        println!("{graphics}: the silhouette overlaps the desktop's by {overlap:.3} (IoU)");
        // The page also draws the volume's box in thin lines, which the desktop's capture of
        // the preview alone has not: a few per cent of the bunny's area.
        assert!(
            overlap > 0.9,
            "the bunny is not where the desktop draws it: IoU {overlap}"
        );
    }

    // Orbit: a drag across the scene turns the view.
    let scene = page.scene_css()?;
    let (cx, cy) = (scene[0] + scene[2] / 2.0, scene[1] + scene[3] / 2.0);
    browser.drag((cx, cy), &[(cx + 60.0, cy + 10.0), (cx + 160.0, cy + 20.0)])?;
    let turned = page.wait_for_picture("orbited", |s| s.differs_from(&bunny) > 0.05)?;
    println!(
        "{graphics}: the drag changed {:.0} % of the scene",
        100.0 * turned.differs_from(&bunny)
    );

    // Render image: the exact render, while the page keeps drawing frames.
    page.click("render image")?;
    let frames_before = page.status()?["frames"].as_u64().unwrap_or(0);
    let rendered = browser.wait_for(
        "const s = window.voxcastStatus(); return s.render.startsWith('done') && s.render",
        Duration::from_secs(300),
    )?;
    let frames_after = page.status()?["frames"].as_u64().unwrap_or(0);
    println!(
        "{graphics}: Render image {}, {} frames drawn meanwhile",
        rendered.as_str().unwrap_or_default(),
        frames_after - frames_before
    );
    assert!(
        frames_after > frames_before + 2,
        "the page froze while rendering"
    );
    page.save_screenshot("render_image")?;
    // Four more renders of the same view, for the figures: one render's time of work varies
    // by half from run to run, the median of five is the figure to compare (benches/web.sh).
    // (Render image runs again below, at 1024×576.)
    if figures_asked() {
        let mut works = vec![work_seconds(&rendered)];
        for _ in 0..4 {
            works.push(work_seconds(&page.render_again()?));
        }
        let shown: Vec<String> = works.iter().map(|w| format!("{w:.3}")).collect();
        works.sort_by(f64::total_cmp);
        println!(
            "{graphics}: Render image's work, median of 5: {:.3} s ({} s)",
            works[2],
            shown.join(", ")
        );
    }
    // Saving: one download a button (a browser asks before a page downloads several files
    // at once); each image is the scene's size (the status gives it in fractional pixels).
    let scene = page.status()?["scene"].clone();
    let scene = [
        scene[2].as_f64().unwrap_or(0.0),
        scene[3].as_f64().unwrap_or(0.0),
    ];
    for (button, file) in [
        ("save render png", "voxcast_render.png"),
        ("save preview png", "voxcast_render_preview.png"),
        ("save difference png", "voxcast_render_diff.png"),
    ] {
        page.click(button)?;
        let saved = downloads.join(file);
        let started = Instant::now();
        while !saved.exists() && started.elapsed() < Duration::from_secs(30) {
            std::thread::sleep(Duration::from_millis(200));
        }
        let png = image::open(&saved).map_err(|e| format!("{}: {e}", saved.display()))?;
        let size = [png.width() as f64, png.height() as f64];
        assert!(
            (0..2).all(|i| (size[i] - scene[i]).abs() <= 1.0),
            "{file} is {size:?}, the scene {scene:?}"
        );
    }

    // A dropped NRRD opens; a damaged one says why and leaves it.
    let tiny = b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n\
                \x00\x10\x20\x30\x40\x50\x60\x70";
    page.drop_file("tiny.nrrd", tiny)?;
    browser.wait_for(
        "const s = window.voxcastStatus(); return !s.loading && s.volume == 'tiny.nrrd'",
        Duration::from_secs(60),
    )?;
    page.drop_file("damaged.nrrd", &tiny[..tiny.len() - 3])?;
    let error = browser.wait_for(
        "const s = window.voxcastStatus(); return (!s.loading && s.load_error) || null",
        Duration::from_secs(60),
    )?;
    let error = error.as_str().unwrap_or_default().to_string();
    assert!(error.starts_with("damaged.nrrd"), "{error}");
    assert_eq!(
        page.status()?["volume"],
        "tiny.nrrd",
        "the damaged file left the volume"
    );
    page.save_screenshot("dropped")?;
    rayvis_files(&page)?;
    large_files(&page, graphics)?;
    // Nothing moves and nothing is under way: the page comes to rest (it draws only on input
    // or now and then); the clicks below wake it.
    let rested = browser.wait_for(
        "return window.voxcastStatus().resting || null",
        Duration::from_secs(60),
    );
    assert!(rested.is_ok(), "the page did not rest: {}", page.status()?);

    // Level 1, started with a click (from the levels menu where the list is folded), shows its
    // first step.
    if !page.has("level 1")? {
        page.click("levels menu")?;
        page.settle(3)?;
    }
    page.click("level 1")?;
    let first_step = &voxcast_core::level::Level::all()[0].steps[0].text;
    browser.wait_for(
        "const s = window.voxcastStatus(); return (s.mode == 'level 1' && s.step_text) || null",
        Duration::from_secs(60),
    )?;
    assert_eq!(&page.status()?["step_text"], first_step);
    let spoken = browser.run(
        "return document.getElementById('voxcast-step').textContent",
        json!([]),
    )?;
    assert_eq!(&spoken, first_step, "what a screen reader speaks");
    page.save_screenshot("level_1")?;
    // Its step done, the progress is kept in the browser's local storage.
    page.click("next")?;
    browser.wait_for(
        "const kept = JSON.parse(localStorage.getItem('voxcast-progress') || '{}'); \
         return Object.values(kept.completed || {}).some(n => n >= 1) || null",
        Duration::from_secs(30),
    )?;

    // On a small laptop's tab the scene keeps at least half the page in every layout, and
    // Render image opens inside it.
    browser.set_viewport(1024, 576)?;
    page.settle(10)?;
    page.check_layout("a level's step")?;
    page.save_screenshot("level_1_1024x576")?;
    if !page.has("pixel grid")? {
        page.click("rays panel")?;
        page.settle(3)?;
    }
    page.click("pixel grid")?;
    browser.wait_for(
        "return window.voxcastStatus().targets.some(t => t[0] == 'breakdown')",
        Duration::from_secs(60),
    )?;
    page.settle(3)?;
    page.save_screenshot("breakdown_1024x576")?;
    page.check_layout("the breakdown open")?;
    page.click("free play")?;
    page.settle(10)?;
    page.check_layout("free play, the levels list")?;
    if !page.has("render image")? {
        page.click("settings panel")?;
        page.settle(3)?;
    }
    page.click("render image")?;
    // The window with its result: the widest it gets (the images, the save buttons).
    browser.wait_for(
        "const s = window.voxcastStatus(); return s.render.startsWith('done') && s.render",
        Duration::from_secs(300),
    )?;
    page.settle(5)?;
    page.save_screenshot("render_image_1024x576")?;
    page.check_layout("Render image open")?;
    let window = page.target("render image window")?;
    let scene = page.status()?["scene"].clone();
    let f = |v: &Value, i: usize| v[i].as_f64().unwrap_or(0.0);
    assert!(
        f(&window, 0) >= f(&scene, 0) - 1.0
            && f(&window, 1) >= f(&scene, 1) - 1.0
            && f(&window, 0) + f(&window, 2) <= f(&scene, 0) + f(&scene, 2) + 1.0
            && f(&window, 1) + f(&window, 3) <= f(&scene, 1) + f(&scene, 3) + 1.0,
        "Render image {window} lies outside the scene {scene}"
    );

    // Progress damaged in the browser's storage: the page starts afresh and says so.
    if graphics == "webgl2" {
        browser.run(
            "localStorage.setItem('voxcast-progress', '{\"completed\": {damaged')",
            json!([]),
        )?;
        browser.open(&format!("http://127.0.0.1:{port}/?gpu=webgl2&no-rays"))?;
        let said = browser.wait_for(
            "const s = window.voxcastStatus && window.voxcastStatus(); \
             return (s && s.frames >= 2 && s.levels_message) || null",
            FIRST_FRAME,
        )?;
        let said = said.as_str().unwrap_or_default();
        assert!(
            said.contains("is damaged") && said.contains("starting afresh"),
            "{said}"
        );
        page.save_screenshot("progress_damaged")?;
    }

    // WebGL2's own GPU preview (the WebGPU run's is the default there): compiled without the
    // depth prepass, it draws the bunny where the desktop does, for two methods.
    if graphics == "webgl2" {
        browser.set_viewport(1280, 720)?;
        for method in ["accumulate", "maximum"] {
            browser.open(&format!(
                "http://127.0.0.1:{port}/?gpu=webgl2&no-rays&preview-backend=gpu&method={method}"
            ))?;
            browser.wait_for(
                "return window.voxcastStatus && window.voxcastStatus().frames >= 2",
                FIRST_FRAME,
            )?;
            let name = format!("webgl2_gpu_{method}");
            let picture = page.wait_for_picture(&name, |s| s.drawn > 0.05)?;
            assert_eq!(
                page.status()?["backend"],
                "gpu",
                "WebGL2 runs the GPU preview"
            );
            if let Some(desktop) = desktop_silhouette(&picture, &out, &["--method", method])? {
                let overlap = picture.overlap(&desktop);
                println!(
                    "{graphics}: the GPU preview ({method}) overlaps the desktop's by {overlap:.3}"
                );
                assert!(overlap > 0.9, "{method}: IoU {overlap}");
            }
        }
    }

    // A teacher's side: levels from ?levels= with their data set, a level's link in a fresh
    // browser, a class's answer files dropped.
    if graphics == "webgl2" {
        teachers_side(&page, port, &dir, &downloads)?;
    }

    // A level on the MRI head, opened from the address (`?study=`): the page fetches that
    // dataset's file the first time it is opened (the module carries none; the loader fetched
    // only the bunny, which the address does not name).
    let study = voxcast_core::level::Level::all()
        .into_iter()
        .enumerate()
        .find(|(_, l)| l.scene.volume == "builtin:brainsmall")
        .expect("a level on brainsmall");
    browser.open(&format!(
        "http://127.0.0.1:{port}/?gpu={graphics}&no-rays&study={}",
        study.1.id
    ))?;
    let opened = browser.wait_for(
        &format!(
            "const s = window.voxcastStatus && window.voxcastStatus(); \
             return (s && s.mode == 'level {}' && !s.loading && (s.load_error || s.volume)) \
               || null",
            study.0 + 1
        ),
        FIRST_FRAME,
    )?;
    assert_eq!(
        opened, "builtin:brainsmall",
        "the level's dataset was fetched"
    );
    page.save_screenshot("fetched_dataset")?;

    // The page's frame times at 1280×720, orbiting and resting (`--measure-frames`, as the
    // desktop's `benches/frames.sh` measures them): printed for BENCHMARKS.md, not judged.
    browser.set_viewport(1280, 720)?;
    let measures: &[(&str, &str)] = if figures_asked() {
        &[
            ("orbiting", "measure-frames=40&auto-orbit=5"),
            ("resting", "measure-frames=40"),
        ]
    } else {
        &[("orbiting", "measure-frames=8&auto-orbit=5")]
    };
    for (what, query) in measures {
        browser.open(&format!(
            "http://127.0.0.1:{port}/?gpu={graphics}&no-rays&{query}"
        ))?;
        let measured = browser.wait_for(
            "const s = window.voxcastStatus && window.voxcastStatus(); \
             return (s && s.measured) || null",
            Duration::from_secs(300),
        )?;
        println!(
            "{graphics}: {what}: {}",
            measured.as_str().unwrap_or_default()
        );
    }

    // Nothing went wrong in the console.
    let errors = browser.run("return window.voxcastErrors", json!([]))?;
    assert_eq!(errors, json!([]), "errors in the page");
    let severe: Vec<String> = browser
        .log()?
        .into_iter()
        .filter(|(level, m)| level == "SEVERE" || m.contains("%cERROR") || m.contains("panicked"))
        .map(|(_, m)| m)
        .collect();
    assert!(severe.is_empty(), "the console says: {severe:#?}");
    Ok(Completion::Completed)
}

/// The teacher's side of the page: a level file and the data set it names, served beside the
/// page, added with `?levels=` and played; a level's link (the editor's Copy link) opened in a
/// fresh browser plays its level; a class's answer file dropped on the page comes back as the
/// report's download.
fn teachers_side(page: &Page, port: u16, dir: &Path, downloads: &Path) -> Result<(), String> {
    let browser = page.browser;
    let served = dir.join("levels-test");
    std::fs::create_dir_all(&served).map_err(|e| e.to_string())?;
    let tiny = b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n\
                \x00\x10\x20\x30\x40\x50\x60\x70";
    std::fs::write(served.join("tiny.nrrd"), tiny).map_err(|e| e.to_string())?;
    let first = "A volume of 2×2×2 voxels, served beside this level.";
    let level = json!({
        "id": "tiny", "title": "A tiny volume", "concept": "A level on a file beside it.",
        "scene": {"volume": "tiny.nrrd", "preview": true, "rays": 2},
        "steps": [
            {"text": first, "objective": {"kind": "read"}},
            {"text": "Set the step to 0.25 voxel or less.", "control": "step",
             "objective": {"kind": "step-at-most", "voxels": 0.25}}
        ]
    });
    std::fs::write(served.join("tiny_level.json"), level.to_string()).map_err(|e| e.to_string())?;
    browser.open(&format!(
        "http://127.0.0.1:{port}/?gpu=webgl2&no-rays&levels=levels-test/tiny_level.json"
    ))?;
    let said = browser.wait_for(
        "const s = window.voxcastStatus && window.voxcastStatus(); \
         return (s && s.levels_message.includes('Added') && s.levels_message) || null",
        FIRST_FRAME,
    )?;
    println!("?levels=: {}", said.as_str().unwrap_or_default());
    let n = voxcast_core::level::Level::all().len() + 1;
    let button = format!("level {n}");
    if !page.has(&button)? {
        page.click("levels menu")?;
        page.settle(3)?;
    }
    page.click(&button)?;
    let volume = format!("http://127.0.0.1:{port}/levels-test/tiny.nrrd");
    browser.wait_for(
        &format!(
            "const s = window.voxcastStatus(); return (s.mode == 'level {n}' && \
             s.step_text == {first:?} && s.volume == {volume:?} && !s.loading) || null"
        ),
        Duration::from_secs(60),
    )?;
    page.save_screenshot("added_level")?;

    // The teacher edits it in the page's level editor: a step added (a snapshot of the view),
    // saved (a download) and shared as a link.
    if !page.has("level editor")? {
        page.click("fold")?;
        page.settle(3)?;
    }
    page.click("level editor")?;
    page.settle(3)?;
    // A window just opened may still be finding its place: the click is made again until the
    // draft has its step.
    for _ in 0..3 {
        page.click("add step")?;
        page.settle(3)?;
        if page.status()?["editor_steps"] == 3 {
            break;
        }
    }
    page.click("save level")?;
    let saved = downloads.join("tiny.json");
    let started = Instant::now();
    while !saved.exists() && started.elapsed() < Duration::from_secs(30) {
        std::thread::sleep(Duration::from_millis(200));
    }
    let text = std::fs::read_to_string(&saved).map_err(|e| format!("{}: {e}", saved.display()))?;
    let written = voxcast_core::level::Level::from_json(&text).map_err(|e| e.to_string())?;
    assert_eq!(written.steps.len(), 3, "{text}");
    assert_eq!(written.scene.volume, "tiny.nrrd", "named beside the level");
    page.click("copy link")?;
    let url = browser.wait_for(
        "const s = window.voxcastStatus(); return s.editor_link || null",
        Duration::from_secs(30),
    )?;
    let url = url.as_str().unwrap_or_default().to_string();
    assert!(url.contains("#level=") && !url.contains("levels="), "{url}");
    page.save_screenshot("level_editor")?;

    // The link, opened where nothing of the teacher's is: the level plays on its data set,
    // found where the teacher's page found it.
    let fresh = Browser::start(&[], downloads).map_err(|e| format!("chromium: {e}"))?;
    fresh.set_viewport(1280, 720)?;
    fresh.open(&url)?;
    let played = fresh.wait_for(
        &format!(
            "const s = window.voxcastStatus && window.voxcastStatus(); \
             return (s && s.mode.startsWith('level') && s.step_text == {first:?} && \
             s.volume == {volume:?} && !s.loading) || null"
        ),
        FIRST_FRAME,
    );
    if let Err(e) = played {
        let _ = std::fs::write(page.out.join("linked_level.png"), fresh.screenshot()?);
        let status = fresh.run(
            "const s = window.voxcastStatus && window.voxcastStatus(); \
             return s && [s.mode, s.step_text, s.volume, s.loading, s.load_error, \
             s.levels_message]",
            json!([]),
        );
        return Err(format!("{e}\nthe linked page: {status:?}\nthe link: {url}"));
    }
    std::fs::write(page.out.join("linked_level.png"), fresh.screenshot()?)
        .map_err(|e| e.to_string())?;
    drop(fresh);

    // A student's answers dropped: the class's report comes back as a download.
    let answers = "level,step,question,answer,expected,correct,time (UTC),run,try,seconds\n\
                   trilinear,2,\"the value at (0.5, 0.5, 0.5)\",5.1,4.988,no,\
                   2026-12-07T09:00:00Z,,1,20\n";
    page.drop_file("student1.csv", answers.as_bytes())?;
    let report = downloads.join("class_report.html");
    let started = Instant::now();
    while !report.exists() && started.elapsed() < Duration::from_secs(30) {
        std::thread::sleep(Duration::from_millis(200));
    }
    let html =
        std::fs::read_to_string(&report).map_err(|e| format!("{}: {e}", report.display()))?;
    assert!(
        html.contains("Trilinear interpolation") && html.contains("5.1 ×1"),
        "{html}"
    );
    let _ = std::fs::remove_dir_all(&served);
    Ok(())
}

/// The page under test, and where its screenshots go.
struct Page<'b> {
    browser: &'b Browser,
    out: &'b Path,
}

/// The scene's part of a screenshot: which pixels differ from the background.
struct Picture {
    width: u32,
    height: u32,
    /// Per pixel: not the background (any channel more than 10/255 away).
    mask: Vec<bool>,
    rgb: Vec<[u8; 3]>,
    /// The share of pixels not the background.
    drawn: f64,
}

impl Picture {
    fn new(image: &image::RgbImage, background: [u8; 3]) -> Self {
        let rgb: Vec<[u8; 3]> = image.pixels().map(|p| p.0).collect();
        let mask: Vec<bool> = rgb
            .iter()
            .map(|p| (0..3).any(|c| p[c].abs_diff(background[c]) > 10))
            .collect();
        let drawn = mask.iter().filter(|m| **m).count() as f64 / mask.len().max(1) as f64;
        Self {
            width: image.width(),
            height: image.height(),
            mask,
            rgb,
            drawn,
        }
    }

    /// Intersection over union of the two silhouettes.
    fn overlap(&self, other: &Picture) -> f64 {
        let both = self
            .mask
            .iter()
            .zip(&other.mask)
            .filter(|(a, b)| **a && **b);
        let either = self
            .mask
            .iter()
            .zip(&other.mask)
            .filter(|(a, b)| **a || **b);
        both.count() as f64 / either.count().max(1) as f64
    }

    /// The share of pixels that changed by more than 10/255 in a channel.
    fn differs_from(&self, other: &Picture) -> f64 {
        if (self.width, self.height) != (other.width, other.height) {
            return 1.0;
        }
        let changed = self
            .rgb
            .iter()
            .zip(&other.rgb)
            .filter(|(a, b)| (0..3).any(|c| a[c].abs_diff(b[c]) > 10))
            .count();
        changed as f64 / self.rgb.len().max(1) as f64
    }
}

impl Page<'_> {
    fn status(&self) -> Result<Value, String> {
        self.browser.run("return window.voxcastStatus()", json!([]))
    }

    /// CSS pixels per UI point, and the canvas's top-left corner in the page.
    fn scale(&self) -> Result<(f64, f64, f64), String> {
        let v = self.browser.run(
            "const r = document.getElementById('voxcast-canvas').getBoundingClientRect(); \
             return [r.left, r.top, r.width, window.voxcastStatus().canvas[0]]",
            json!([]),
        )?;
        let f = |i: usize| v[i].as_f64().unwrap_or(0.0);
        Ok((f(2) / f(3).max(1.0), f(0), f(1)))
    }

    /// A rectangle of the status (UI points) in CSS pixels of the page.
    fn css(&self, r: &Value) -> Result<[f64; 4], String> {
        let (k, left, top) = self.scale()?;
        let f = |i: usize| r[i].as_f64().unwrap_or(0.0);
        Ok([left + f(0) * k, top + f(1) * k, f(2) * k, f(3) * k])
    }

    fn scene_css(&self) -> Result<[f64; 4], String> {
        self.css(&self.status()?["scene"])
    }

    /// Whether the page shows the control named `name`.
    fn has(&self, name: &str) -> Result<bool, String> {
        let status = self.status()?;
        Ok(status["targets"]
            .as_array()
            .is_some_and(|t| t.iter().any(|t| t[0] == name)))
    }

    /// The rectangle (UI points) of the control the page names `name`.
    fn target(&self, name: &str) -> Result<Value, String> {
        let status = self.status()?;
        status["targets"]
            .as_array()
            .and_then(|t| t.iter().find(|t| t[0] == name))
            .map(|t| t[1].clone())
            .ok_or_else(|| format!("no control '{name}' on the page: {}", status["targets"]))
    }

    /// Clicks the control the page names `name`.
    fn click(&self, name: &str) -> Result<(), String> {
        let r = self.css(&self.target(name)?)?;
        self.browser
            .drag((r[0] + r[2] / 2.0, r[1] + r[3] / 2.0), &[])
    }

    /// Renders the view again with Render image (clicked again where a click was lost) and
    /// gives what the page says when it is done.
    fn render_again(&self) -> Result<Value, String> {
        let rendering = "return window.voxcastStatus().render === 'rendering'";
        let mut started = false;
        for _ in 0..3 {
            self.click("render image")?;
            if self
                .browser
                .wait_for(rendering, Duration::from_secs(5))
                .is_ok()
            {
                started = true;
                break;
            }
        }
        if !started {
            return Err("Render image did not start again".into());
        }
        self.browser.wait_for(
            "const s = window.voxcastStatus(); return s.render.startsWith('done') && s.render",
            Duration::from_secs(300),
        )
    }

    /// Waits for `frames` more frames.
    fn settle(&self, frames: u64) -> Result<(), String> {
        let now = self.status()?["frames"].as_u64().unwrap_or(0);
        self.browser.wait_for(
            &format!("return window.voxcastStatus().frames >= {}", now + frames),
            Duration::from_secs(120),
        )?;
        Ok(())
    }

    fn save_screenshot(&self, name: &str) -> Result<image::RgbImage, String> {
        let png = self.browser.screenshot()?;
        std::fs::write(self.out.join(format!("{name}.png")), &png).map_err(|e| e.to_string())?;
        image::load_from_memory(&png)
            .map(|i| i.to_rgb8())
            .map_err(|e| e.to_string())
    }

    /// The scene's part of a screenshot.
    fn scene_picture(&self, name: &str) -> Result<Picture, String> {
        let shot = self.save_screenshot(name)?;
        let [x, y, w, h] = self.scene_css()?;
        let crop = image::imageops::crop_imm(
            &shot,
            x.round() as u32,
            y.round() as u32,
            w.round() as u32,
            h.round() as u32,
        )
        .to_image();
        crop.save(self.out.join(format!("{name}_scene.png")))
            .map_err(|e| e.to_string())?;
        Ok(Picture::new(&crop, [0, 0, 0]))
    }

    /// Screenshots until the scene shows what `done` asks for and has settled: drawn at full
    /// quality (the GPU's whole frame, or the CPU's exact render at the scene's size, the same
    /// frame before and after the screenshot), as a second before. Two minutes at most.
    fn wait_for_picture(
        &self,
        name: &str,
        done: impl Fn(&Picture) -> bool,
    ) -> Result<Picture, String> {
        let started = Instant::now();
        let mut last: Option<Picture> = None;
        let settled = |page: &Self| -> Result<Option<String>, String> {
            let s = page.status()?;
            let size = format!(
                "{:.0}×{:.0} ",
                s["scene"][2].as_f64().unwrap_or(0.0),
                s["scene"][3].as_f64().unwrap_or(0.0)
            );
            let live = s["live"].as_str().unwrap_or_default().to_string();
            let exact =
                s["backend"] != "cpu" || (live.starts_with(&size) && live.contains("exact"));
            Ok((s["settled"] == json!(true) && exact).then_some(live))
        };
        loop {
            let before = settled(self)?;
            let p = self.scene_picture(name)?;
            let same = last.as_ref().is_some_and(|l| p.differs_from(l) == 0.0);
            if before.is_some() && settled(self)? == before && done(&p) && same {
                return Ok(p);
            }
            last = Some(p);
            if started.elapsed() > Duration::from_secs(120) {
                return Err(format!(
                    "the scene never showed '{name}' (tests/out/browser): {}",
                    self.status()?
                ));
            }
            std::thread::sleep(Duration::from_millis(1000));
        }
    }

    /// Drops a file named `name` holding `bytes` on the page, as a student drags one onto it.
    fn drop_file(&self, name: &str, bytes: &[u8]) -> Result<(), String> {
        self.drop_made_file(
            "const [name, bytes] = arguments; return new File([new Uint8Array(bytes)], name);",
            json!([name, bytes]),
        )
    }

    /// Drops the file the script `make` returns (given `args`), made in the page: a file too
    /// large to send over WebDriver.
    fn drop_made_file(&self, make: &str, args: Value) -> Result<(), String> {
        self.browser
            .run(
                &format!(
                    "const file = (function () {{ {make} }}).apply(null, arguments); \
                     const data = new DataTransfer(); data.items.add(file); \
                     const canvas = document.getElementById('voxcast-canvas'); \
                     for (const type of ['dragenter', 'dragover', 'drop']) {{ \
                       canvas.dispatchEvent(new DragEvent(type, \
                         {{dataTransfer: data, bubbles: true, cancelable: true}})); }}"
                ),
                args,
            )
            .map(drop)
    }

    /// The scene keeps at least half the page's width and most of its height.
    fn check_layout(&self, layout: &str) -> Result<(), String> {
        let s = self.status()?;
        let f = |v: &Value, i: usize| v[i].as_f64().unwrap_or(0.0);
        let (w, h) = (f(&s["canvas"], 0), f(&s["canvas"], 1));
        let (sw, sh) = (f(&s["scene"], 2), f(&s["scene"], 3));
        println!(
            "{layout}: the scene {sw:.0}×{sh:.0} of the page's {w:.0}×{h:.0} points ({:.0} % × {:.0} %)",
            100.0 * sw / w,
            100.0 * sh / h
        );
        if sw < 0.5 * w || sh < 0.6 * h {
            return Err(format!(
                "{layout}: the scene is {sw:.0}×{sh:.0} of {w:.0}×{h:.0}: less than half the \
                 width or 60 % of the height"
            ));
        }
        Ok(())
    }
}

/// A 512³ volume of 16-bit values (256 MB, the page's limit; made in the page: a ball of value
/// 1000 in zeros), dropped on the page: it is read with its share shown, Cancel stops it (the
/// volume before stays), dropped again it loads and is drawn; a 600 MB file is refused before
/// it is read, in words that give the page's limit, and the ball stays.
/// A dropped `.rayvis` file's density is computed and shown, as `--volume density:FILE` does
/// on the desktop; a damaged one says why and leaves it.
fn rayvis_files(page: &Page) -> Result<(), String> {
    let browser = page.browser;
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/two_level.rayvis");
    let bytes = std::fs::read(&data).map_err(|e| e.to_string())?;
    // What the page says next: a new error, or the density on show.
    let next = |before: &Value| {
        format!(
            "const s = window.voxcastStatus(); \
             return (!s.loading && (s.load_error != {before} && s.load_error \
               || s.volume.startsWith('density:') && s.volume)) || null"
        )
    };
    let before = page.status()?["load_error"].clone();
    page.drop_file("two_level.rayvis", &bytes)?;
    let shown = browser.wait_for(&next(&before), Duration::from_secs(60))?;
    let shown = shown.as_str().unwrap_or_default().to_string();
    assert!(
        shown.starts_with("density:two_level.rayvis"),
        "the dropped ray file's density is not on show: {shown}"
    );
    page.save_screenshot("rayvis")?;
    let before = page.status()?["load_error"].clone();
    page.drop_file("damaged.rayvis", &bytes[..bytes.len() / 2])?;
    let error = browser.wait_for(
        &format!(
            "const s = window.voxcastStatus(); \
             return (!s.loading && s.load_error != {before} && s.load_error) || null"
        ),
        Duration::from_secs(60),
    )?;
    let error = error.as_str().unwrap_or_default().to_string();
    assert!(error.contains("damaged.rayvis: "), "{error}");
    assert_eq!(
        page.status()?["volume"],
        shown,
        "the damaged file left the density"
    );
    println!("a dropped .rayvis file: {shown}; a damaged one: {error}");
    Ok(())
}

fn large_files(page: &Page, graphics: &str) -> Result<(), String> {
    let browser = page.browser;
    let make_ball = "const n = 512; \
        const header = new TextEncoder().encode('NRRD0004\\ntype: uint16\\ndimension: 3\\n' \
          + 'sizes: 512 512 512\\nendian: little\\nencoding: raw\\n\\n'); \
        const data = new Uint16Array(n * n * n); \
        for (let z = 0; z < n; z++) for (let y = 0; y < n; y++) { \
          const dz = z - 256, dy = y - 256, row = (z * n + y) * n; \
          for (let x = 0; x < n; x++) { const dx = x - 256; \
            if (dx * dx + dy * dy + dz * dz < 40000) data[row + x] = 1000; } } \
        return new File([header, data], 'ball512.nrrd');";
    let before = page.status()?;
    let volume_before = before["volume"].clone();
    // A slow drive (a school's network folder, a USB stick): each piece the page reads comes
    // a quarter of a second late, so a click lands while the file is read.
    browser.run(
        "window.fastRead = Blob.prototype.arrayBuffer; \
         Blob.prototype.arrayBuffer = function () { \
           return new Promise((r) => setTimeout(r, 250)).then(() => window.fastRead.call(this)); };",
        json!([]),
    )?;
    page.drop_made_file(make_ball, json!([]))?;
    // Cancel, clicked while it is read (a piece a frame), keeps the volume.
    browser.wait_for(
        "return window.voxcastStatus().loading",
        Duration::from_secs(60),
    )?;
    // Clicked again where a click was lost (as Render image's is, `render_again`).
    for _ in 0..3 {
        page.click("Cancel loading")?;
        if browser
            .wait_for(
                "return !window.voxcastStatus().loading",
                Duration::from_secs(1),
            )
            .is_ok()
        {
            break;
        }
    }
    let after = page.status()?;
    assert_eq!(after["volume"], volume_before, "Cancel kept the volume");
    assert_eq!(after["load_error"], "", "a cancelled load is no error");

    // Again, to the end: its share read shows on the way; loaded, and drawn.
    let started = Instant::now();
    page.drop_made_file(make_ball, json!([]))?;
    let mut shares = Vec::new();
    while started.elapsed() < Duration::from_secs(300) {
        let s = page.status()?;
        if let Some(share) = s["load_progress"].as_f64().filter(|f| *f > 0.0 && *f < 1.0) {
            let share = format!("{:.0} %", 100.0 * share);
            if shares.last() != Some(&share) {
                shares.push(share);
            }
        }
        if s["load_error"] != "" || (s["loading"] == false && s["volume"] == "ball512.nrrd") {
            break;
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    let loaded = started.elapsed();
    browser.run("Blob.prototype.arrayBuffer = window.fastRead;", json!([]))?;
    println!(
        "{graphics}: the share read, as the page showed it: {}",
        shares.join(", ")
    );
    assert!(!shares.is_empty(), "the load showed no share read");
    assert_eq!(page.status()?["load_error"], "", "the 512³ volume loads");
    let ball = page.wait_for_picture("ball512", |p| p.drawn > 0.02)?;
    let memory = page.status()?["memory"].as_f64().unwrap_or(0.0) / f64::from(1 << 20);
    println!(
        "{graphics}: the 512³ 16-bit volume (256 MB) loaded {:.1} s after the drop (made in the \
         page, read a piece every quarter of a second at the least); drawn on {:.0} % of the scene; the page's memory {memory:.0} MB (before it \
         {:.0} MB)",
        loaded.as_secs_f64(),
        100.0 * ball.drawn,
        before["memory"].as_f64().unwrap_or(0.0) / f64::from(1 << 20),
    );

    // Over the limit: refused before it is read, the ball kept.
    page.drop_made_file(
        "return new File([new Uint8Array(600 * 1024 * 1024)], 'huge.raw');",
        json!([]),
    )?;
    let refused = browser.wait_for(
        "const s = window.voxcastStatus(); return s.load_error || null",
        Duration::from_secs(60),
    )?;
    assert_eq!(
        refused,
        "huge.raw: the file takes 600 MB, more than the 256 MB of voxel data this page can \
         hold; Voxcast's desktop app opens larger volumes."
    );
    assert_eq!(page.status()?["volume"], "ball512.nrrd", "the ball stayed");
    page.save_screenshot("refused")?;
    Ok(())
}

/// The silhouette the desktop's `--screenshot` draws of the same view at the scene's size, if
/// this machine can run it (a Vulkan device).
fn desktop_silhouette(
    page: &Picture,
    out: &Path,
    args: &[&str],
) -> Result<Option<Picture>, String> {
    let path = out.join(format!("desktop{}.png", args.join("_")));
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_voxcast"))
        .args(["--volume", "builtin:bunny", "--no-rays"])
        .args(args)
        .args(["--size", &format!("{}x{}", page.width, page.height)])
        .arg("--screenshot")
        .arg(&path)
        .env("XDG_RUNTIME_DIR", std::env::temp_dir())
        .output()
        .map_err(|e| e.to_string())?;
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        if support::skipped_for_want_of_a_gpu(&stderr).is_some() {
            println!("no Vulkan device: the silhouette is not compared with the desktop's");
            return Ok(None);
        }
        return Err(format!("voxcast --screenshot: {stderr}"));
    }
    let image = image::open(&path).map_err(|e| e.to_string())?.to_rgb8();
    Ok(Some(Picture::new(&image, [0, 0, 0])))
}
