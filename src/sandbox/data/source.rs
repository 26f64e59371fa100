//! RayVis in the sandbox: the ray data set behind the density on show (its scene, its rays,
//! the sparse grid with the mean directions) and the volume it replaced. The density itself is
//! loaded like any volume (`data/loading.rs`); this keeps what it came from, so the scene, the
//! ray mesh and the vector field (`data/views.rs`) can be drawn around it, and the volume it
//! replaced can come back.

use crate::sandbox::shared::state::{RenderState, VolumeState};
use bevy::prelude::*;
use std::sync::Arc;
use voxcast_core::camera::Camera as CoreCamera;
use voxcast_core::io::Loaded;
use voxcast_core::level::RayDensityFacts;
use voxcast_core::rays::as_volume::{RayDensity, is_density};
use voxcast_core::rays::data::RayData;
use voxcast_core::rays::density::Density;
use voxcast_core::rays::set::RaySet;

/// What a density was computed from.
pub struct Computed {
    pub data: RayData,
    /// The rays of the chosen trace (or all), before the filter.
    pub set: RaySet,
    pub density: Density,
    /// Where the volume's voxel `(0, 0, 0)` lies in the rays' world.
    pub origin: Vec3,
    /// For the virtual camera's rays: the camera they were shot from.
    pub camera: Option<CoreCamera>,
    /// Where the rays came from, as the levels see it.
    pub facts: RayDensityFacts,
}

impl Computed {
    /// A finished density as a load's outcome: the volume to show and what it came from.
    pub fn outcome(d: RayDensity, camera: Option<CoreCamera>, facts: RayDensityFacts) -> Outcome {
        let RayDensity {
            data,
            set,
            density,
            origin,
            volume,
            words,
        } = d;
        Outcome {
            loaded: Loaded {
                volume,
                notes: vec![words],
            },
            rays: Some(Self {
                data,
                set,
                density,
                origin,
                camera,
                facts,
            }),
        }
    }
}

/// Computes the density a `density:…` source names, keeping what it came from: `None` when
/// `source` is not one, else the outcome or why not (the source's text first). Progress and
/// cancel as [`voxcast_core::rays::density::compute`].
pub fn compute_source(
    source: &str,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &std::sync::atomic::AtomicBool,
) -> Option<Result<Outcome, String>> {
    let parsed = voxcast_core::rays::as_volume::parse(source)?;
    Some(
        (|| {
            let spec = parsed?;
            let d = voxcast_core::rays::as_volume::compute_spec(&spec, progress, cancel)?;
            let facts = RayDensityFacts {
                source: spec.source.clone(),
                trace: spec.trace,
                side: 0,
            };
            Ok(Computed::outcome(d, None, facts))
        })()
        .map_err(|e: String| density_error(source, &e)),
    )
}

/// Why the density `source` could not be made, in words: "Ray density of r.rayvis: the file
/// ends inside …" — the reader's own error names the file, which is not said twice. A source
/// that does not parse leads with its text, which is what is wrong.
fn density_error(source: &str, e: &str) -> String {
    match voxcast_core::rays::as_volume::parse(source) {
        Some(Ok(spec)) => {
            let why = e.strip_prefix(&format!("{}: ", spec.source)).unwrap_or(e);
            format!("Ray density of {}: {why}", spec.source)
        }
        _ => format!("{source}: {e}"),
    }
}

/// [`compute_source`] in slices, yielding to the page between them (`crate::sandbox::shared::tasks`).
pub async fn compute_source_in_slices(
    source: &str,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &std::sync::atomic::AtomicBool,
) -> Option<Result<Outcome, String>> {
    let parsed = voxcast_core::rays::as_volume::parse(source)?;
    let computed = async {
        let spec = parsed?;
        let mut slices = voxcast_core::rays::as_volume::SpecSlices::default();
        let (d, _) = crate::sandbox::shared::tasks::in_slices(|deadline| {
            voxcast_core::rays::as_volume::compute_spec_in(
                &spec,
                &mut slices,
                progress,
                cancel,
                deadline,
            )
        })
        .await?;
        let facts = RayDensityFacts {
            source: spec.source.clone(),
            trace: spec.trace,
            side: 0,
        };
        Ok(Computed::outcome(d, None, facts))
    };
    Some(
        computed
            .await
            .map_err(|e: String| density_error(source, &e)),
    )
}

/// A density on show: what it came from, and its volume (the one [`VolumeState`] holds).
pub struct Shown {
    pub computed: Computed,
    pub volume: Arc<voxcast_core::Prepared>,
}

/// What was on show before the first density, to go back to (and, for the virtual camera's
/// rays, what they are shot through).
#[derive(Clone)]
pub struct Before {
    pub volume: VolumeState,
    pub render: RenderState,
    /// The virtual camera the first camera density was shot from.
    pub camera: Option<CoreCamera>,
}

/// The density on show and the volume before it.
#[derive(Resource, Default)]
pub struct RayScene {
    pub current: Option<Arc<Shown>>,
    pub before: Option<Before>,
}

impl RayScene {
    /// A load finished: `now` is on show, `before` was. A density keeps what it came from and,
    /// the first time, what was on show before it; any other volume forgets both.
    pub fn shown(&mut self, computed: Option<Computed>, now: &VolumeState, before: Before) {
        match computed {
            Some(c) => {
                if !is_density(&before.volume.volume) {
                    self.before = Some(Before {
                        camera: c.camera,
                        ..before
                    });
                }
                self.current = Some(Arc::new(Shown {
                    computed: c,
                    volume: now.volume.clone(),
                }));
            }
            None => *self = Self::default(),
        }
    }

    /// What the volume on show was computed from, when it is a density computed here.
    pub fn on_show(&self, volume: &VolumeState) -> Option<&Arc<Shown>> {
        self.current
            .as_ref()
            .filter(|s| Arc::ptr_eq(&s.volume, &volume.volume))
    }
}

/// Where the rays come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SourceKind {
    /// The embedded Cornell box and the rays Voxcast traces through it.
    #[default]
    Cornell,
    /// The same at 400 × 400 primary rays: about a million rays.
    CornellMillion,
    /// A `.rayvis` file.
    File,
    /// The virtual camera's rays through the volume.
    Camera,
}

impl SourceKind {
    pub const ALL: [SourceKind; 4] = [
        Self::Cornell,
        Self::CornellMillion,
        Self::Camera,
        Self::File,
    ];

    /// The embedded ray data this kind loads (`builtin:…`), if it is one.
    pub const fn builtin(self) -> Option<&'static str> {
        match self {
            Self::Cornell => Some("builtin:cornell"),
            Self::CornellMillion => Some("builtin:cornell-1m"),
            Self::File | Self::Camera => None,
        }
    }

    pub const fn words(self) -> &'static str {
        match self {
            Self::Cornell => "Cornell box (embedded)",
            Self::CornellMillion => "Cornell box, a million rays",
            Self::File => ".rayvis file",
            Self::Camera => "the virtual camera's rays",
        }
    }

    pub const fn doc(self) -> &'static str {
        match self {
            Self::Cornell => {
                "The Cornell box with RayVis's study's five traces, which Voxcast traces through \
                 it (seeded: the same every time): primary rays of two cameras, reflection, \
                 ambient-occlusion and shadow rays"
            }
            Self::CornellMillion => {
                "The Cornell box traced with 400 × 400 primary rays instead of 256 × 256: \
                 about 1.2 million rays in all, the scale RayVis's study drew (the density \
                 takes about a second)"
            }
            Self::File => "A ray data set saved by RayVis (or by voxcast rays export)",
            Self::Camera => {
                "The virtual camera's rays through the volume, with the settings on show: a \
                 ray 'hits' where it stopped early (opacity cutoff, or First's crossing), so \
                 the density shows how densely each method samples the grid"
            }
        }
    }
}

/// What a finished load brings: the volume, and for a ray density what it was computed from.
pub struct Outcome {
    pub loaded: Loaded,
    pub rays: Option<Computed>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_damaged_ray_file_is_named_once_in_words() {
        let dir = std::env::temp_dir().join(format!("voxcast-density-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let whole = std::fs::read(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/two_level.rayvis"),
        )
        .unwrap();
        let file = dir.join("damaged.rayvis");
        std::fs::write(&file, &whole[..whole.len() / 2]).unwrap();
        let file = file.display().to_string();
        let cancel = std::sync::atomic::AtomicBool::new(false);
        let said = compute_source(&format!("density:{file}"), &|_, _| {}, &cancel)
            .expect("a density source")
            .err()
            .expect("the half file fails");
        std::fs::remove_dir_all(&dir).unwrap();
        assert!(
            said.starts_with(&format!("Ray density of {file}: ")),
            "{said}"
        );
        assert_eq!(said.matches(&file).count(), 1, "{said}");
        // A source whose text is wrong leads with it.
        let said = compute_source("density:r.rayvis@trace=x", &|_, _| {}, &cancel)
            .expect("a density source")
            .err()
            .expect("a bad trace");
        assert!(said.starts_with("density:r.rayvis@trace=x: "), "{said}");
    }
}
