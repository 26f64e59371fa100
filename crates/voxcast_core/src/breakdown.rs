//! A ray's breakdown: the record of every sample ([`SampleRecord`]), of the First hit, and of
//! the whole ray ([`RayTrace`]) and why it stopped ([`StopReason`]), the [`Recorder`] the march
//! writes them to, and their exports as JSON and CSV — the same numbers `voxcast trace` prints
//! and the sandbox's inspector saves.
//!
//! Numbers are written with Rust's shortest round-trip formatting, so every `f32` reads back to
//! the identical value: a student can redo each step by hand from the file.

use crate::composite::{Method, Order, ValueStats};
use crate::sample::SampleDetail;
use crate::shade::ShadeTerms;
use crate::step::StepPlan;
use serde::Serialize;

use std::fmt::Write;

/// Why a ray stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum StopReason {
    /// The ray never entered the volume's box.
    Missed,
    /// It crossed the box, but the crop box or clip plane had cut away all of it on its way.
    CutAway,
    /// It crossed the box (or took no sample, when jitter pushed the only one out).
    LeftVolume,
    /// Early ray termination: the accumulated opacity reached the cutoff.
    Cutoff,
    /// First: a value at or above the target was found.
    FirstHit,
    /// The sample cap was reached before the ray left the box.
    SampleCap,
}

impl StopReason {
    /// Why the ray stopped, in words.
    pub const fn words(self) -> &'static str {
        match self {
            StopReason::Missed => "missed the volume",
            StopReason::CutAway => "the crop box or clip plane cut away everything on its way",
            StopReason::LeftVolume => "left the volume",
            StopReason::Cutoff => "early termination: the opacity reached the cutoff",
            StopReason::FirstHit => "found the target value",
            StopReason::SampleCap => "the sample cap was reached before the ray left the volume",
        }
    }
}

/// Everything about one sample, for the inspector and `voxcast trace --json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SampleRecord {
    /// Sample number `k` along the ray (from the entry point).
    pub index: u32,
    /// Distance along the ray, world units.
    pub t: f32,
    /// Length of ray this sample stands for, world units.
    pub ds: f32,
    pub p_world: [f32; 3],
    pub p_voxel: [f32; 3],
    /// The 8 corners, their values and weights, and the interpolated value (data units).
    pub reconstruction: SampleDetail,
    /// The value normalised to the volume's range, in [0, 1].
    pub value_normalized: f32,
    /// Transfer-function colour and opacity at the value (the table's, before classification).
    pub tf_rgba: [f32; 4],
    /// Opacity after classification, before correction.
    pub alpha: f32,
    /// Opacity actually composited (after correction, if on).
    pub alpha_corrected: f32,
    /// Gradient (data units per world unit), where it was computed.
    pub gradient: Option<[f32; 3]>,
    /// Shading terms, where the sample was shaded.
    pub shading: Option<ShadeTerms>,
    /// The sample's colour as composited (after shading).
    pub color: [f32; 3],
    /// Composited colour (premultiplied) and opacity after this sample (Accumulate).
    pub composite_after: [f32; 4],
    /// Running statistics of values (Average, Maximum, Minimum).
    pub stats_after: Option<ValueStats>,
}

/// One step of the First method's refinement.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RefineStep {
    pub t: f32,
    pub value: f32,
}

/// Where and how the First method found its crossing.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FirstHit {
    pub t: f32,
    pub p_world: [f32; 3],
    pub p_voxel: [f32; 3],
    /// The reconstructed value at the hit (≈ the target).
    pub value: f32,
    /// The two sample distances that bracketed the crossing.
    pub bracket: [f32; 2],
    /// Bisection midpoints, in order, then the final interpolation.
    pub refinement: Vec<RefineStep>,
    pub tf_rgba: [f32; 4],
    pub shading: Option<ShadeTerms>,
    pub color: [f32; 3],
}

/// How Sum turned its samples into a table value.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SumDetail {
    /// The length each sample stands for, in voxels (the step along this ray's direction).
    pub ds_voxels: f32,
    /// `Σ v` over the samples with a value.
    pub values: f64,
    /// `S = Σ v · Δs`.
    pub sum: f32,
    /// The sum range `[a, b]` stretched over the table.
    pub range: [f32; 2],
    /// The table's values `[lo, hi]`.
    pub table: [f32; 2],
    /// Where `S` falls in the range, clamped to `[0, 1]`.
    pub fraction: f32,
    /// The value looked up: `lo + (hi − lo)·fraction`.
    pub table_value: f32,
}

/// The full breakdown of one ray.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RayTrace {
    pub origin: [f32; 3],
    pub dir: [f32; 3],
    pub method: Method,
    /// The compositing order (Accumulate): the order the samples were visited and recorded in.
    pub order: Order,
    /// `[t_enter, t_exit]` where the ray samples: in the box, cut by the crop box and clip
    /// plane; `None` if nothing of the volume was left on its way.
    pub interval: Option<[f32; 2]>,
    /// `[t_enter, t_exit]` in the whole box, before any cut (equal to `interval` when nothing
    /// was cut).
    pub box_interval: Option<[f32; 2]>,
    pub plan: Option<StepPlan>,
    pub samples: Vec<SampleRecord>,
    pub first_hit: Option<FirstHit>,
    /// The value Average/Maximum/Minimum/Sum projected.
    pub projected_value: Option<f32>,
    /// Sum's arithmetic, for Sum.
    pub sum: Option<SumDetail>,
    pub stop: StopReason,
    /// Composited colour (premultiplied) and opacity.
    pub color: [f32; 3],
    pub opacity: f32,
    /// The background the pixel is blended over.
    pub background: [f32; 3],
    /// The final pixel over the background.
    pub pixel: [f32; 3],
}

impl RayTrace {
    /// What the crop box or clip plane cut from this ray, in words; `None` when nothing was.
    pub fn cut_words(&self) -> Option<String> {
        use crate::numbers::sig;
        let [a, b] = self.box_interval?;
        let span = format!("the box spans t = {} to {}", sig(a), sig(b));
        let Some([c, d]) = self.interval else {
            return Some(format!("the cut removed all of it ({span})"));
        };
        let mut parts = Vec::new();
        if c > a {
            parts.push(format!("t = {} to {} in front", sig(a), sig(c)));
        }
        if d < b {
            parts.push(format!("t = {} to {} behind", sig(d), sig(b)));
        }
        (!parts.is_empty()).then(|| format!("the cut removed {} ({span})", parts.join(" and ")))
    }
}

/// Receives each sample's record; [`NoRecord`] compiles to nothing.
pub trait Recorder {
    const ACTIVE: bool;
    fn sample(&mut self, record: SampleRecord);
    fn plan(&mut self, _plan: &StepPlan) {}
    fn first_hit(&mut self, _hit: FirstHit) {}
    fn projected(&mut self, _value: f32) {}
    fn sum(&mut self, _detail: SumDetail) {}
}

/// The renderer's recorder: records nothing.
pub struct NoRecord;

impl Recorder for NoRecord {
    const ACTIVE: bool = false;
    #[inline(always)]
    fn sample(&mut self, _: SampleRecord) {}
}

/// The recorder of [`crate::trace::trace_ray`]: keeps everything.
#[derive(Default)]
pub(crate) struct Breakdown {
    pub(crate) plan: Option<StepPlan>,
    pub(crate) samples: Vec<SampleRecord>,
    pub(crate) first_hit: Option<FirstHit>,
    pub(crate) projected: Option<f32>,
    pub(crate) sum: Option<SumDetail>,
}

impl Recorder for Breakdown {
    const ACTIVE: bool = true;
    fn sample(&mut self, record: SampleRecord) {
        self.samples.push(record);
    }
    fn plan(&mut self, plan: &StepPlan) {
        self.plan = Some(*plan);
    }
    fn first_hit(&mut self, hit: FirstHit) {
        self.first_hit = Some(hit);
    }
    fn projected(&mut self, value: f32) {
        self.projected = Some(value);
    }
    fn sum(&mut self, detail: SumDetail) {
        self.sum = Some(detail);
    }
}

/// Pretty JSON of the whole breakdown.
pub fn to_json(trace: &RayTrace) -> String {
    serde_json::to_string_pretty(trace).expect("a breakdown always serialises")
}

/// The CSV header: one row per sample.
pub const CSV_HEADER: &str = "index,t,ds,x,y,z,u,v,w,value,value_normalized,\
tf_r,tf_g,tf_b,tf_a,alpha,alpha_corrected,grad_x,grad_y,grad_z,lit,lights,\
ambient_r,ambient_g,ambient_b,diffuse_r,diffuse_g,diffuse_b,specular_r,specular_g,specular_b,\
color_r,color_g,color_b,C_r,C_g,C_b,O,\
corner0_value,corner1_value,corner2_value,corner3_value,corner4_value,corner5_value,corner6_value,corner7_value,\
weight0,weight1,weight2,weight3,weight4,weight5,weight6,weight7";

/// CSV with one row per sample, then `#` comment lines for the stop reason, the first hit and
/// the final pixel.
pub fn to_csv(trace: &RayTrace) -> String {
    let mut out = String::new();
    out.push_str(CSV_HEADER);
    out.push('\n');
    let opt = |v: Option<f32>| v.map_or(String::new(), |v| v.to_string());
    for s in &trace.samples {
        let g = s.gradient;
        let lit = s.shading.map(|t| t.lit);
        let row: Vec<String> = [s.index as f32, s.t, s.ds]
            .iter()
            .chain(&s.p_world)
            .chain(&s.p_voxel)
            .chain(&[s.reconstruction.value, s.value_normalized])
            .chain(&s.tf_rgba)
            .chain(&[s.alpha, s.alpha_corrected])
            .map(|v| v.to_string())
            .chain((0..3).map(|i| opt(g.map(|g| g[i]))))
            .chain([
                lit.map_or(String::new(), |l| l.to_string()),
                s.shading
                    .filter(|t| t.lit)
                    .map_or(String::new(), |t| t.light_count.to_string()),
            ])
            .chain(
                [
                    s.shading.map(|t| t.ambient),
                    s.shading.map(|t| t.diffuse),
                    s.shading.map(|t| t.specular),
                ]
                .into_iter()
                .flat_map(|term| (0..3).map(move |i| opt(term.map(|v| v[i])))),
            )
            .chain(s.color.iter().map(|v| v.to_string()))
            .chain(s.composite_after.iter().map(|v| v.to_string()))
            .chain(s.reconstruction.values.iter().map(|v| v.to_string()))
            .chain(s.reconstruction.weights.iter().map(|v| v.to_string()))
            .collect();
        out.push_str(&row.join(","));
        out.push('\n');
    }
    let _ = writeln!(
        out,
        "# stop: {}",
        serde_json::to_string(&trace.stop)
            .unwrap_or_default()
            .trim_matches('"')
    );
    if let Some(h) = &trace.first_hit {
        let _ = writeln!(
            out,
            "# first hit: t = {}, position = ({}, {}, {}), value = {}",
            h.t, h.p_world[0], h.p_world[1], h.p_world[2], h.value
        );
    }
    if let Some(v) = trace.projected_value {
        let _ = writeln!(out, "# projected value: {v}");
    }
    let _ = writeln!(
        out,
        "# pixel: ({}, {}, {}), opacity {}",
        trace.pixel[0], trace.pixel[1], trace.pixel[2], trace.opacity
    );
    out
}
