//! `voxcast --measure-frames N [--auto-orbit DEG]`: the sandbox measures its own frame time —
//! optionally while orbiting the camera, which engages adaptive quality — prints the mean and
//! median over N frames after a warm-up, and exits. BENCHMARKS.md's preview figures come from it.
//! The virtual camera's rays are shown whole (no growing animation), with all their samples.
//!
//! `voxcast --measure-knob KNOB` measures one knob's trade as the panel's Measure does (a
//! preview's knob timed as the preview's own images), prints its table and exits.
//!
//! With the CPU live view it also reports how many new volume images arrived a second while
//! measuring, at what size, and (resting) how long after start the exact render was on screen.

use crate::sandbox::scene::orbit::Orbit;
use crate::sandbox::shared::state::{MainCamera, View};
use bevy::prelude::*;

/// What to measure.
#[derive(Resource, Clone)]
pub struct MeasureRequest {
    pub frames: u32,
    /// Degrees of orbit per frame (0: a resting camera).
    pub orbit_degrees: f32,
    /// A label printed with the figures.
    pub label: String,
}

/// When the measured frames ended, the live view's images a second and size until then, and
/// the CPU's pictures of a ray density's lines a second and their thinning.
struct Stopped {
    at: f64,
    live: Option<(f64, UVec2)>,
    lines: Option<(f64, usize)>,
    /// Where the measured frames went, in words (`frame_parts`).
    parts: Option<String>,
}

/// Frames drawn before measuring (pipelines compiled, textures uploaded, quality settled).
const WARM_UP: u32 = 15;

pub(crate) fn plugin(app: &mut App) {
    app.add_systems(
        Update,
        measure_frames.in_set(crate::sandbox::shared::schedule::Frame::Drive),
    );
}

/// What the measurement has seen so far.
#[derive(Default)]
struct Measured {
    /// Frames drawn.
    seen: u32,
    /// Frame times after the warm-up, ms.
    samples: Vec<f32>,
    /// The live view's generation and the time when measuring began.
    live_start: Option<(u64, f64)>,
    /// The same for the CPU's pictures of the lines.
    lines_start: Option<(u64, f64)>,
    stopped: Option<Stopped>,
    /// The figures were given (a page reports them once and goes on).
    #[cfg(target_arch = "wasm32")]
    reported: bool,
}

/// The preview's settings, the CPU live view (and its lines) and the GPU's progressive pass,
/// where there are.
#[derive(bevy::ecs::system::SystemParam)]
struct Previews<'w> {
    live: Option<Res<'w, crate::sandbox::preview::live::LiveView>>,
    preview: Option<Res<'w, crate::sandbox::shared::quality::PreviewSettings>>,
    progressive: Option<Res<'w, crate::sandbox::preview::progressive::Progressive>>,
    motion: Option<Res<'w, crate::sandbox::shared::quality::Motion>>,
    lines: Option<Res<'w, crate::sandbox::data::cpu_lines::CpuLines>>,
}

impl Previews<'_> {
    /// The CPU live view, where it draws the volume.
    fn live(&self) -> Option<&crate::sandbox::preview::live::LiveView> {
        let cpu = self.preview.as_ref().is_some_and(|p| p.cpu_live());
        self.live.as_deref().filter(|_| cpu)
    }

    /// Whether the GPU preview draws the volume.
    fn gpu(&self) -> bool {
        self.preview.as_ref().is_some_and(|p| p.gpu_live())
    }

    /// The CPU's pictures of a ray density's lines, where they are on screen.
    fn lines(&self) -> Option<&crate::sandbox::data::cpu_lines::CpuLines> {
        self.lines.as_deref().filter(|l| l.on_screen().is_some())
    }

    /// Whether the GPU preview is at full quality: the view rests and its pass (if it draws
    /// in strips) has finished.
    fn gpu_full(&self) -> bool {
        self.gpu()
            && !self.motion.as_ref().is_some_and(|m| m.moving)
            && self
                .progressive
                .as_ref()
                .is_some_and(|p| p.full_quality_shown())
    }
}

/// Real time (virtual time clamps a frame at 250 ms), and the clock of each frame's parts.
#[derive(bevy::ecs::system::SystemParam)]
struct Clocks<'w> {
    time: Res<'w, Time<Real>>,
    parts: Option<Res<'w, super::frame_parts::FrameClock>>,
}

fn measure_frames(
    request: Res<MeasureRequest>,
    clocks: Clocks,
    mut m: Local<Measured>,
    mut cameras: Query<(&mut Orbit, &mut Transform, &mut View), With<MainCamera>>,
    mut exit: MessageWriter<AppExit>,
    animation: Option<ResMut<crate::sandbox::inspect::rays::RayAnimation>>,
    previews: Previews,
) {
    m.seen += 1;
    let now = clocks.time.elapsed_secs_f64();
    // Every ray and sample on screen from the start: the cost of the whole scene.
    if let Some(mut a) = animation
        && a.distance.is_finite()
    {
        a.skip();
    }
    // Once the frames are measured the orbit stops, and (with the CPU live view) the time
    // until the exact render of the resting view is on screen is measured too.
    let measured = m.samples.len() as u32 >= request.frames;
    if request.orbit_degrees != 0.0 && !measured {
        orbit(&mut cameras, request.orbit_degrees);
    }
    if m.seen <= WARM_UP {
        return;
    }
    let (live, lines) = (previews.live(), previews.lines());
    if m.live_start.is_none() {
        m.live_start = live.map(|l| (l.generation, now));
    }
    if m.lines_start.is_none() {
        m.lines_start = lines.map(|l| (l.pictures(), now));
    }
    if !measured {
        m.samples.push(clocks.time.delta_secs() * 1000.0);
        if m.samples.len() as u32 == request.frames {
            let parts = clocks
                .parts
                .as_ref()
                .and_then(|c| super::frame_parts::words(c, request.frames as usize));
            m.stopped = Some(m.stop(now, live, lines, parts));
        }
        return;
    }
    let view = cameras.single().ok().map(|(_, _, v)| v.0);
    let Some(text) = m.report(&request, &previews, view, now) else {
        return; // the preview is still refining the resting view
    };
    // A page has no standard output and goes on: the figures go to its console and status
    // (`voxcast_status().measured`), once.
    #[cfg(target_arch = "wasm32")]
    {
        let _ = &mut exit;
        if !m.reported {
            m.reported = true;
            info!("{text}");
            crate::sandbox::shared::web::publish(|s| s.measured = text);
        }
    }
    #[cfg(not(target_arch = "wasm32"))]
    {
        println!("{text}");
        exit.write(AppExit::Success);
    }
}

/// Turns the main camera `degrees` further round its orbit.
fn orbit(
    cameras: &mut Query<(&mut Orbit, &mut Transform, &mut View), With<MainCamera>>,
    degrees: f32,
) {
    for (mut orbit, mut transform, mut view) in cameras {
        orbit.yaw += degrees.to_radians();
        orbit.place(&mut transform, &mut view);
    }
}

impl Measured {
    /// The measured frames end `now`: the live view's images and the lines' pictures a second
    /// since measuring began.
    fn stop(
        &self,
        now: f64,
        live: Option<&crate::sandbox::preview::live::LiveView>,
        lines: Option<&crate::sandbox::data::cpu_lines::CpuLines>,
        parts: Option<String>,
    ) -> Stopped {
        Stopped {
            parts,
            at: now,
            live: live.zip(self.live_start).map(|(l, (g0, t0))| {
                let size = l.shown.as_ref().map_or(UVec2::ZERO, |f| f.size);
                ((l.generation - g0) as f64 / (now - t0).max(1e-6), size)
            }),
            lines: lines.zip(self.lines_start).map(|(l, (g0, t0))| {
                let every = l.on_screen().map_or(1, |(_, every)| every);
                ((l.pictures() - g0) as f64 / (now - t0).max(1e-6), every)
            }),
        }
    }

    /// The figures, once the preview has finished refining the view the camera rests at (or
    /// 30 s after the measured frames, whichever comes first); `None` before.
    fn report(
        &self,
        request: &MeasureRequest,
        previews: &Previews,
        view: Option<voxcast_core::camera::Camera>,
        now: f64,
    ) -> Option<String> {
        let live = previews.live();
        let exact_now = live.is_some_and(|l| {
            l.showing_exact() && l.shown.as_ref().is_some_and(|f| Some(f.key.camera) == view)
        });
        let gpu_full = previews.gpu_full();
        let waited = now - self.stopped.as_ref().map_or(now, |s| s.at);
        let refining = (live.is_some() && !exact_now) || (previews.gpu() && !gpu_full);
        if refining && waited < 30.0 {
            return None;
        }
        let mean = self.samples.iter().sum::<f32>() / self.samples.len() as f32;
        let samples: Vec<f64> = self.samples.iter().map(|&s| s as f64).collect();
        let median = voxcast_core::numbers::median(&samples).unwrap_or_default() as f32;
        // How long after the camera stopped the best image was on screen.
        let reached = |on: bool| match (on, request.orbit_degrees != 0.0) {
            (false, _) => "not reached".to_string(),
            (true, true) => format!("{:.0} ms after the camera stopped", waited * 1000.0),
            (true, false) => "on screen".to_string(),
        };
        let stopped = self.stopped.as_ref();
        let live_text = match stopped.and_then(|s| s.live) {
            Some((rate, size)) => format!(
                "; CPU live view: {rate:.1} images/s at {}×{}, exact render {}",
                size.x,
                size.y,
                reached(exact_now)
            ),
            None if previews.gpu() => {
                let strips = previews
                    .progressive
                    .as_ref()
                    .filter(|p| p.active())
                    .map_or(String::new(), |p| {
                        format!(" (drawn in {} strips)", p.strips())
                    });
                format!("; GPU preview: full quality {}{strips}", reached(gpu_full))
            }
            None => String::new(),
        };
        let lines_text = stopped
            .and_then(|s| s.lines)
            .map_or(String::new(), |(rate, every)| {
                format!(
                    "; lines drawn by the CPU: {rate:.1} pictures/s, 1 in {every} of the rays and \
                 arrows"
                )
            });
        let parts_text = stopped
            .and_then(|s| s.parts.as_ref())
            .map_or(String::new(), |w| format!("; {w}"));
        Some(format!(
            "{}: frame time mean {mean:.1} ms, median {median:.1} ms ({:.1} fps) over {} \
             frames{live_text}{lines_text}{parts_text}",
            request.label,
            1000.0 / median,
            self.samples.len()
        ))
    }
}

/// `--measure-knob`: the knob to measure.
#[derive(Resource, Clone, Copy)]
pub struct KnobRequest(pub voxcast_core::knob::Knob);

/// Asks for the knob's trade once the window has settled, prints its table when it is there
/// (or why there is none) and exits.
pub(crate) fn measure_knob(
    request: Res<KnobRequest>,
    mut trade: ResMut<crate::sandbox::checks::trade::StepTrade>,
    mut seen: Local<u32>,
    mut exit: MessageWriter<AppExit>,
) {
    *seen += 1;
    if *seen == WARM_UP {
        trade.knob = request.0;
        trade.request();
    }
    if *seen <= WARM_UP || trade.progress().is_some() {
        return;
    }
    if let Some(why) = &trade.error {
        eprintln!("error: {why}");
        exit.write(AppExit::from_code(1));
        return;
    }
    let Some((t, _)) = &trade.result else {
        return;
    };
    let how = match &trade.timed_frames {
        Some(f) => f.words(t.runs),
        None => format!(
            "{}time: the core's render at {}×{} on {} threads, the median of {} after an \
             untimed one, the settings in alternating order",
            trade.stand_in.map_or(String::new(), |w| format!("{w}\n")),
            crate::sandbox::checks::trade::TRADE_SIZE.0,
            crate::sandbox::checks::trade::TRADE_SIZE.1,
            t.threads,
            t.runs
        ),
    };
    println!("{how}.\n\n{}", t.markdown());
    exit.write(AppExit::Success);
}
