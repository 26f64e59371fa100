//! Exports of a ray's breakdown ([`crate::trace::RayTrace`]): JSON and CSV, the same numbers
//! `voxcast trace` prints and the sandbox's inspector saves.
//!
//! Numbers are written with Rust's shortest round-trip formatting, so every `f32` reads back to
//! the identical value: a student can redo each step by hand from the file.

use crate::trace::RayTrace;
use std::fmt::Write;

/// Pretty JSON of the whole breakdown.
pub fn to_json(trace: &RayTrace) -> String {
    serde_json::to_string_pretty(trace).expect("a breakdown always serialises")
}

/// The CSV header: one row per sample.
pub const CSV_HEADER: &str = "index,t,ds,x,y,z,u,v,w,value,value_normalized,\
tf_r,tf_g,tf_b,tf_a,alpha,alpha_corrected,grad_x,grad_y,grad_z,lit,n_dot_l,\
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
                opt(s.shading.map(|t| t.n_dot_l)),
            ])
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
