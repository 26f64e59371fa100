//! What the sandbox starts with: the volume, its settings, the camera and any ray density the
//! command line names, loaded before the app is built.

use super::args::SandboxArgs;
use crate::cli::CliError;
use crate::sandbox::data::source;
use crate::sandbox::shared::state::{RenderState, VolumeState};
use bevy::prelude::*;
use std::sync::Arc;

/// What every sandbox starts with, from the command line.
pub(super) struct Start {
    pub(super) volume: VolumeState,
    pub(super) render: RenderState,
    pub(super) camera: voxcast_core::camera::Camera,
    pub(super) rays: source::RayScene,
}

impl Start {
    pub(super) fn from_args(args: &SandboxArgs) -> Result<Self, CliError> {
        // A ray density keeps what it was computed from, for RayVis's views.
        let never = std::sync::atomic::AtomicBool::new(false);
        let (loaded, computed) =
            match source::compute_source(&args.volume.volume, &|_, _| {}, &never) {
                Some(outcome) => {
                    let outcome = outcome.map_err(CliError::failed)?;
                    (outcome.loaded.into(), outcome.rays)
                }
                None => (args.volume.load()?, None),
            };
        let resolved = args.settings.resolve(&loaded)?;
        for note in &resolved.notes {
            eprintln!("note: {note}");
        }
        let camera = args.camera.camera(&loaded, resolved.preset.as_ref())?;
        let volume = VolumeState {
            volume: Arc::new(loaded.volume),
            source: args.volume.volume.clone(),
            preset: resolved.preset,
        };
        let rays = source::RayScene {
            current: computed.map(|computed| {
                Arc::new(source::Shown {
                    computed,
                    volume: volume.volume.clone(),
                })
            }),
            before: None,
        };
        Ok(Self {
            rays,
            volume,
            render: RenderState {
                transfer: resolved.transfer,
                settings: resolved.settings,
                depth_termination: !args.no_depth_termination,
            },
            camera,
        })
    }
}
