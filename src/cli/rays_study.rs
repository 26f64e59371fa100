//! `voxcast rays study SOURCE [--trace ID] [--cell S]`: RayVis's study questions (its Table
//! 4.1) about each trace, with the answer the code finds in the trace — what the which-effect level checks a
//! student's answer against (`voxcast_core::rays::study`).

use super::CliError;
use super::rays_input::{SourceArg, source, trace_named, trace_words};
use clap::Args;
use std::sync::atomic::AtomicBool;
use voxcast_core::rays::density::{DensityParams, MAX_BYTES, compute, estimate_within};
use voxcast_core::rays::set::RaySet;
use voxcast_core::rays::study::Question;

#[derive(Args, Debug)]
pub struct StudyArgs {
    #[command(flatten)]
    pub source: SourceArg,
    /// Ask about this trace only (see `voxcast rays info`); every trace when left out.
    #[arg(long, value_name = "ID")]
    pub trace: Option<u32>,
    /// Cell edge S (world units) of the densities the density questions read (the densest
    /// cell of the hitting rays).
    #[arg(long, value_name = "S", default_value_t = 20.0)]
    pub cell: f32,
}

pub fn study(a: &StudyArgs) -> Result<(), CliError> {
    let data = source(&a.source)?;
    let name = &a.source.source;
    let sets: Vec<&RaySet> = match a.trace {
        Some(id) => vec![trace_named(&data, name, id)?],
        None => data.traces.iter().collect(),
    };
    for set in sets {
        let id = set.trace_id;
        println!("{}:", trace_words(name, id));
        for q in Question::ALL {
            let density = match q.density_filter().filter(|_| q.reads_density()) {
                Some(filter) => {
                    let params = DensityParams {
                        cell: a.cell,
                        filter,
                        tolerance: a.source.miss_tolerance,
                        ..Default::default()
                    };
                    params.check().map_err(CliError::usage)?;
                    if estimate_within(set, &params, MAX_BYTES).is_none_or(|e| e.bytes > MAX_BYTES)
                    {
                        return Err(CliError::usage(format!(
                            "cells of {} would take more than {} MiB for trace {id}: choose \
                             larger cells (--cell)",
                            a.cell,
                            MAX_BYTES >> 20
                        )));
                    }
                    let d = compute(set, &params, &|_, _| {}, &AtomicBool::new(false))
                        .map_err(|_| CliError::failed("cancelled"))?;
                    Some(d)
                }
                None => None,
            };
            let answer = q
                .answer(&data.scene, set, density.as_ref())
                .unwrap_or_else(|| "no answer in this trace".into());
            println!(
                "  {}? {answer}",
                voxcast_core::numbers::capitalised(&q.words(id))
            );
        }
    }
    Ok(())
}
