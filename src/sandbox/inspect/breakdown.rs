//! The selected ray's breakdown, as the game state holds it: the core's trace of the virtual
//! camera's pixel the player selected (taken from the inspection when it was traced there),
//! the sample opened in it, and the cells of the lattice it crosses. The breakdown panel
//! (`ui/breakdown_panel.rs`) shows it; the levels' objectives read it.

use crate::sandbox::inspect::rays::{Inspection, RaySelection};
use crate::sandbox::inspect::virtual_camera::VirtualCamera;
use crate::sandbox::shared::state::{RenderState, VolumeState};
use bevy::prelude::*;
use voxcast_core::cells::{CellsCrossed, cells_crossed};
use voxcast_core::trace::{RayTrace, Scene, trace_ray};

/// The selected ray's trace and the opened sample.
#[derive(Resource, Default)]
pub struct BreakdownState {
    /// The pixel and the inspection generation the trace belongs to.
    key: Option<(UVec2, u64)>,
    pub trace: Option<RayTrace>,
    pub opened: Option<usize>,
    /// The cells of the lattice the traced ray crosses (the core's walk), for the panel and
    /// the scene.
    pub cells: Option<CellsCrossed>,
    /// Draw those cells in the scene (`inspect/cells.rs`).
    pub show_cells: bool,
}

pub(crate) fn plugin(app: &mut App) {
    app.init_resource::<BreakdownState>().add_systems(
        Update,
        follow_selection.in_set(crate::sandbox::shared::schedule::Frame::Results),
    );
}

/// The trace of the virtual camera's pixel `p`: the core's `trace_ray` of that pixel's ray.
pub fn pixel_trace(
    volume: &VolumeState,
    render: &RenderState,
    vc: &VirtualCamera,
    p: UVec2,
) -> Option<RayTrace> {
    let (w, h) = (vc.width.max(1), vc.height.max(1));
    // A recorded ray visits every sample: the scene needs none of the skipping structures
    // (the cells' visibility of a CT is tens of milliseconds, and this runs in a frame).
    let scene = Scene::plain(
        &volume.volume,
        &render.transfer,
        &render.settings,
        vc.view.forward(),
    )
    .ok()?;
    Some(trace_ray(
        &scene,
        &vc.view.pixel_ray(p.x, p.y, w, h),
        [p.x, p.y],
    ))
}

/// Keeps the breakdown's trace in step with the selection and the settings.
pub fn follow_selection(
    selection: Res<RaySelection>,
    inspection: Res<Inspection>,
    volume: Res<VolumeState>,
    render: Res<RenderState>,
    cameras: Query<&VirtualCamera>,
    mut state: ResMut<BreakdownState>,
) {
    let key = selection.selected.map(|p| (p, inspection.generation));
    if key == state.key {
        return;
    }
    state.key = key;
    let previous_len = state.trace.as_ref().map(|t| t.samples.len());
    state.trace = match (selection.selected, cameras.single()) {
        (Some(p), Ok(vc)) => {
            let index = selection.selected_index(inspection.size);
            inspection
                .traces
                .as_ref()
                .and_then(|ts| index.and_then(|i| ts.get(i)))
                .cloned()
                .or_else(|| pixel_trace(&volume, &render, vc, p))
        }
        _ => None,
    };
    state.cells = state.trace.as_ref().and_then(|t| {
        let interval = t.interval?;
        Some(cells_crossed(
            &volume.volume,
            Vec3::from(t.origin),
            Vec3::from(t.dir),
            interval,
        ))
    });
    if state.trace.as_ref().map(|t| t.samples.len()) != previous_len {
        state.opened = None;
    }
}
