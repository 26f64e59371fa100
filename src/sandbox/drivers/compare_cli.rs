//! `voxcast --compare FILE.png`: what the "Render image" button does, without a window: the
//! preview of the view is captured and the CPU renders the same view; both and the heat-map are
//! saved (`FILE.png`, `FILE_preview.png`, `FILE_diff.png`), the differences printed, and the
//! program exits.

use crate::sandbox::checks::compare::{Comparison, save_pngs};
use crate::sandbox::drivers::screenshot::WARM_UP_FRAMES;
use bevy::prelude::*;
use std::path::PathBuf;

/// Where the render goes (the other two pictures go beside it).
#[derive(Resource, Clone)]
pub struct CompareRequest(pub PathBuf);

pub(crate) fn plugin(app: &mut App) {
    app.add_systems(
        Update,
        run_comparison.in_set(crate::sandbox::shared::schedule::Frame::Drive),
    );
}

fn run_comparison(
    mut frames: Local<u32>,
    mut comparison: ResMut<Comparison>,
    request: Res<CompareRequest>,
    mut exit: MessageWriter<AppExit>,
    cells: Res<crate::sandbox::preview::sync::CellsUpload>,
    compiling: Res<crate::sandbox::gpu::pipelines::Compiling>,
) {
    if cells.pending() || compiling.now() {
        return; // the preview as it will be: cells uploaded, its pipeline compiled
    }
    *frames += 1;
    if *frames == WARM_UP_FRAMES {
        comparison.start();
    }
    if let Some(result) = &comparison.result {
        let code = match (
            &result.diff,
            save_pngs(result, &request.0.to_string_lossy()),
        ) {
            (_, Err(e)) => {
                eprintln!("error: {e}");
                1
            }
            (None, Ok(_)) => {
                let why = result.gpu.as_ref().err().map_or("", |e| e.as_str());
                eprintln!("error: no preview to compare with: {why}");
                1
            }
            (Some((d, _)), Ok(written)) => {
                let s = &result.stats;
                println!(
                    "{}×{}: render {:.3} s, {} sample positions, {} interpolated; preview − render: max {:.2}/255, mean \
                     {:.4}/255, RMSE {:.4}/255",
                    result.snapshot.size.x,
                    result.snapshot.size.y,
                    result.seconds,
                    s.positions,
                    s.samples,
                    d.max_abs * 255.0,
                    d.mean_abs * 255.0,
                    d.rmse * 255.0
                );
                for p in written {
                    println!("wrote {}", p.display());
                }
                0
            }
        };
        comparison.result = None;
        exit.write(if code == 0 {
            AppExit::Success
        } else {
            AppExit::from_code(code)
        });
    } else if let Some(message) = comparison.message.take() {
        eprintln!("error: {message}");
        exit.write(AppExit::from_code(1));
    }
}
