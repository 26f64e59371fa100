//! A ray data set: a scene and the traces cast through it, wherever it came from (a `.rayvis`
//! file, `rayvis`; the built-in Cornell box, `source`).

use super::mesh::TriangleScene;
use super::set::RaySet;

/// A scene and the traces cast through it.
#[derive(Clone, Debug, PartialEq)]
pub struct RayData {
    /// What it is, in words.
    pub description: String,
    pub scene: TriangleScene,
    pub traces: Vec<RaySet>,
}

impl RayData {
    /// The trace with id `id`.
    pub fn trace(&self, id: u32) -> Option<&RaySet> {
        self.traces.iter().find(|t| t.trace_id == id)
    }

    /// Every trace's rays in one set (trace id 0; ray ids as in their own traces).
    pub fn all_rays(&self) -> RaySet {
        RaySet {
            trace_id: 0,
            rays: self
                .traces
                .iter()
                .flat_map(|t| t.rays.iter().copied())
                .collect(),
        }
    }
}
