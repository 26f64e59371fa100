//! The knobs that trade speed for accuracy: for each, the values a measurement tries and the
//! exact setting it is measured against ([`crate::trade`] renders and times them).
//!
//! Each knob is measured against the same settings with only that knob at its exact value, so a
//! row's error is that knob's alone: the step against a sixteenth of a voxel (trilinear, no
//! jitter), the cutoff against no early termination, supersampling against 8×8 rays a pixel, a
//! preview resolution against the full one, a preview step multiplier against ×1. Preview
//! resolutions are rendered small and stretched bilinearly, as the GPU preview's target is.

use crate::sample::Interpolation;
use crate::settings::RenderSettings;
use crate::step::Length;
use crate::tunables as t;

/// A setting that trades speed for accuracy.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Knob {
    #[default]
    Step,
    Interpolation,
    Cutoff,
    Jitter,
    Supersampling,
    PreviewScale,
    PreviewStepMultiplier,
    /// The preview's frame while the camera moves: resolution and step multiplier together.
    AdaptiveQuality,
}

/// One setting a measurement renders: its words, the settings, and the fraction of the image's
/// width and height it is rendered at (then stretched to the full size).
#[derive(Clone, Debug, PartialEq)]
pub struct Try {
    pub label: String,
    pub settings: RenderSettings,
    pub scale: f32,
}

/// The moving frames adaptive quality is measured at, cheapest first: (resolution fraction,
/// step multiplier); the sandbox's defaults ([`t::MOVING_SCALE`], [`t::MOVING_STEP_MULTIPLIER`])
/// are the second.
pub const MOVING_FRAMES: [(f32, f32); 4] = [(0.125, 4.0), (0.25, 2.0), (0.5, 2.0), (0.5, 1.0)];

/// The step (voxels) the exact reference of the step, interpolation and jitter uses.
pub const REFERENCE_STEP: f32 = 1.0 / 16.0;
/// Rays per pixel side of supersampling's reference.
pub const REFERENCE_SUPERSAMPLING: u32 = 8;

impl Knob {
    pub const ALL: [Knob; 8] = [
        Knob::Step,
        Knob::Interpolation,
        Knob::Cutoff,
        Knob::Jitter,
        Knob::Supersampling,
        Knob::PreviewScale,
        Knob::PreviewStepMultiplier,
        Knob::AdaptiveQuality,
    ];

    /// Whether it is one of the preview's: its cost is the frame the preview draws, and the
    /// core's render only stands in for it.
    pub const fn is_preview(self) -> bool {
        matches!(
            self,
            Knob::PreviewScale | Knob::PreviewStepMultiplier | Knob::AdaptiveQuality
        )
    }

    /// Its key on the command line.
    pub const fn name(self) -> &'static str {
        match self {
            Knob::Step => "step",
            Knob::Interpolation => "interpolation",
            Knob::Cutoff => "cutoff",
            Knob::Jitter => "jitter",
            Knob::Supersampling => "supersampling",
            Knob::PreviewScale => "preview-scale",
            Knob::PreviewStepMultiplier => "preview-step-multiplier",
            Knob::AdaptiveQuality => "adaptive-quality",
        }
    }

    /// Its name for people (the control's label).
    pub const fn label(self) -> &'static str {
        match self {
            Knob::Step => "Step size",
            Knob::Interpolation => "Interpolation",
            Knob::Cutoff => "Opacity cutoff",
            Knob::Jitter => "Jitter",
            Knob::Supersampling => "Supersampling",
            Knob::PreviewScale => "Preview resolution",
            Knob::PreviewStepMultiplier => "Preview step ×",
            Knob::AdaptiveQuality => "Adaptive quality (the moving frame)",
        }
    }

    /// What the knob trades, and what it is measured against.
    pub fn doc(self) -> String {
        let (what, against) = match self {
            Knob::Step => (t::STEP.doc, "Against a step of 1/16 voxel."),
            Knob::Interpolation => (
                "Nearest takes the closest lattice point's value (one read a sample), trilinear \
                 blends the 8 around it.",
                "Against trilinear at 1/16 voxel: nearest's staircase stays at every step.",
            ),
            Knob::Cutoff => (t::CUTOFF.doc, "Against no early termination."),
            Knob::Jitter => (
                t::JITTER.doc,
                "Against a step of 1/16 voxel without jitter.",
            ),
            Knob::Supersampling => (t::SUPERSAMPLING.doc, "Against 8×8 rays a pixel."),
            Knob::PreviewScale => (
                t::PREVIEW_SCALE.doc,
                "Rendered small and stretched bilinearly; against the full resolution.",
            ),
            Knob::PreviewStepMultiplier => (t::PREVIEW_STEP_MULTIPLIER.doc, "Against ×1."),
            Knob::AdaptiveQuality => (
                t::ADAPTIVE_QUALITY.doc,
                "Each try is a moving frame as a whole — a lower resolution stretched bilinearly \
                 and a longer step together, the defaults among them — against the resting \
                 frame (full resolution, ×1).",
            ),
        };
        format!("{what} {against}")
    }

    /// The knob named `name`, if any.
    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// The exact setting the knob's tries are measured against.
    pub fn reference(self, s: &RenderSettings) -> Try {
        let mut r = s.clone();
        let label = match self {
            Knob::Step | Knob::Interpolation | Knob::Jitter => {
                r.step = Length::Voxels(REFERENCE_STEP);
                r.interpolation = Interpolation::Trilinear;
                r.jitter = false;
                format!("step {REFERENCE_STEP} voxel, trilinear")
            }
            Knob::Cutoff => {
                r.early_termination = false;
                "no early termination".into()
            }
            Knob::Supersampling => {
                r.supersampling = REFERENCE_SUPERSAMPLING;
                format!("{0}×{0} rays a pixel", REFERENCE_SUPERSAMPLING)
            }
            Knob::PreviewScale => "full resolution".into(),
            Knob::PreviewStepMultiplier => "×1".into(),
            Knob::AdaptiveQuality => "the resting frame: full resolution, ×1".into(),
        };
        Try {
            label,
            settings: r,
            scale: 1.0,
        }
    }

    /// The settings a measurement tries, cheapest first; `steps` are the step knob's (voxels).
    pub fn tries(self, s: &RenderSettings, voxel: f32, steps: &[f32]) -> Vec<Try> {
        let with = |label: String, f: &dyn Fn(&mut RenderSettings), scale: f32| {
            let mut r = s.clone();
            f(&mut r);
            Try {
                label,
                settings: r,
                scale,
            }
        };
        match self {
            Knob::Step => {
                let mut steps = steps.to_vec();
                steps.sort_by(|a, b| b.total_cmp(a));
                steps.dedup();
                steps
                    .into_iter()
                    .map(|v| {
                        with(
                            format!("{v}"),
                            &|r| {
                                r.step = Length::Voxels(v);
                                // Jitter adds noise the reference does not share.
                                r.jitter = false;
                            },
                            1.0,
                        )
                    })
                    .collect()
            }
            Knob::Interpolation => [Interpolation::Nearest, Interpolation::Trilinear]
                .into_iter()
                .map(|i| {
                    let words = match i {
                        Interpolation::Nearest => "nearest",
                        Interpolation::Trilinear => "trilinear",
                    };
                    with(
                        words.into(),
                        &|r| {
                            r.interpolation = i;
                            r.jitter = false;
                        },
                        1.0,
                    )
                })
                .collect(),
            Knob::Cutoff => [0.8f32, 0.9, 0.95, 0.99]
                .into_iter()
                .map(|c| {
                    with(
                        format!("{c}"),
                        &|r| {
                            r.early_termination = true;
                            r.cutoff = c;
                        },
                        1.0,
                    )
                })
                .collect(),
            Knob::Jitter => {
                // At the player's step and at twice it: jitter matters most when coarse.
                let step = s.step.voxels(voxel);
                let mut out = Vec::new();
                for v in [2.0 * step, step] {
                    for on in [false, true] {
                        let words = if on { "on" } else { "off" };
                        out.push(with(
                            format!("{words} at step {}", crate::numbers::sig(v)),
                            &|r| {
                                r.step = Length::Voxels(v);
                                r.jitter = on;
                            },
                            1.0,
                        ));
                    }
                }
                out
            }
            Knob::Supersampling => (1u32..=4)
                .map(|n| with(format!("{n}×{n}"), &|r| r.supersampling = n, 1.0))
                .collect(),
            Knob::PreviewScale => [0.25f32, 0.5, 0.75]
                .into_iter()
                .map(|f| with(format!("{f}"), &|_| {}, f))
                .collect(),
            Knob::PreviewStepMultiplier => [8.0f32, 4.0, 2.0]
                .into_iter()
                .map(|m| with(format!("×{m}"), &|r| r.step = r.step.scaled(m), 1.0))
                .collect(),
            Knob::AdaptiveQuality => MOVING_FRAMES
                .into_iter()
                .map(|(f, m)| with(format!("{f} and ×{m}"), &|r| r.step = r.step.scaled(m), f))
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_knob_has_a_name_words_a_reference_and_tries() {
        let s = RenderSettings::default();
        for k in Knob::ALL {
            assert_eq!(Knob::parse(k.name()), Some(k));
            assert!(k.doc().len() > 60, "{k:?}");
            let tries = k.tries(&s, 1.0, &[2.0, 1.0]);
            assert!(tries.len() >= 2, "{k:?}");
            assert!(tries.iter().all(|t| t.settings.validate().is_ok()));
            assert!(k.reference(&s).settings.validate().is_ok());
            // Only the knob moves: everything else is the player's.
            for t in &tries {
                assert_eq!(t.settings.method, s.method);
            }
        }
        assert_eq!(Knob::parse("volume"), None);
    }

    #[test]
    fn references_are_the_exact_ends() {
        let s = RenderSettings::default();
        assert_eq!(
            Knob::Step.reference(&s).settings.step,
            Length::Voxels(REFERENCE_STEP)
        );
        assert!(!Knob::Cutoff.reference(&s).settings.early_termination);
        assert_eq!(Knob::Supersampling.reference(&s).settings.supersampling, 8);
        assert_eq!(Knob::PreviewScale.reference(&s).scale, 1.0);
        let x4 = &Knob::PreviewStepMultiplier.tries(&s, 1.0, &[])[1];
        assert_eq!(x4.settings.step, Length::Voxels(2.0), "0.5 voxel ×4");
        // Adaptive quality tries the sandbox's own moving frame among others.
        let defaults = (t::MOVING_SCALE.default, t::MOVING_STEP_MULTIPLIER.default);
        assert_eq!(MOVING_FRAMES[1], defaults);
        let moving = &Knob::AdaptiveQuality.tries(&s, 1.0, &[])[1];
        assert_eq!(moving.scale, 0.25);
        assert_eq!(moving.settings.step, Length::Voxels(1.0), "0.5 voxel ×2");
        assert_eq!(Knob::AdaptiveQuality.reference(&s).scale, 1.0);
    }
}
