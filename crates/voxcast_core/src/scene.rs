//! The scene of one render: what every ray shares, resolved once from the volume, the transfer
//! function and the settings — the baked table, step lengths in world units, the light for this
//! view, and the acceleration structures ([`crate::skip`], precomputed gradients).

use crate::bricks::{BrickRanges, Superblocks};
use crate::classify::Classifier;
use crate::clip::ResolvedClip;
use crate::composite::{Method, Order};
use crate::error::SettingsError;
use crate::hash::jitter_fraction;
use crate::prepared::Prepared;
use crate::settings::RenderSettings;
use crate::shade::ResolvedLights;
use crate::skip::BlockRanges;
use crate::transfer::{Lut, TransferFunction};
use crate::volume::Volume;
use glam::Vec3;

/// The share of a volume's 8³ blocks that must hold only zeros for Sum to walk the blocks and
/// pass over those; below it, walking costs more than it passes over. Measured (AMD EPYC, 2
/// threads, step ½ voxel; the same images either way): with 71 % and 60 % zero blocks,
/// mni152 and the bunny (512²) rendered 30 % and 8 % faster walking; the Cornell box's
/// shadow-ray density (128 cells across, 256², scene hidden), 44 %, 20 % faster; ch2 (512²),
/// 33 %, 18 % slower; the CT, none, 57 % slower.
pub const ZERO_SHARE_TO_SKIP: f32 = 0.4;

/// Whether at least [`ZERO_SHARE_TO_SKIP`] of the blocks hold only zeros: where Sum passes over
/// them (if it may, [`Scene::may_skip_zeros`]).
pub fn enough_zeros(ranges: &BlockRanges) -> bool {
    let zeros = ranges.ranges.iter().filter(|&&r| r == (0.0, 0.0)).count();
    zeros as f32 >= ZERO_SHARE_TO_SKIP * ranges.ranges.len() as f32
}

/// What a render's rays share, resolved once: world-unit step lengths, the baked table, the
/// light for this view.
#[derive(Clone, Debug)]
pub struct Scene<'a> {
    pub volume: &'a Volume,
    pub lut: Lut,
    pub settings: RenderSettings,
    pub classifier: Classifier,
    pub lights: ResolvedLights,
    /// Step between samples, world units.
    pub dt: f32,
    /// Reference step of the transfer function's opacity, world units.
    pub dt_ref: f32,
    /// The opacity correction's power for a sample standing for one whole step, `dt/dt_ref`,
    /// prepared (where correction is on and the power is one the tables serve).
    pub step_power: Option<Box<crate::power::StepPower>>,
    /// First-hit target value, data units.
    pub target: f32,
    /// Sum's range (value × voxels), resolved ([`RenderSettings::sum_range`]).
    pub sum_range: (f32, f32),
    pub bounds: (Vec3, Vec3),
    /// The crop box and clip plane in world units ([`crate::clip`]).
    pub clip: ResolvedClip,
    /// Blocks and cells the transfer function makes transparent, where skipping them is exact.
    pub empty: Option<crate::prepared::EmptySpace>,
    /// Whether Maximum, Minimum and First may skip blocks that cannot change their result.
    pub block_skipping: bool,
    /// Whether Sum may pass over blocks of exact zeros (CPU only: the GPU marches them, to
    /// the same sums).
    pub sum_skipping: bool,
    /// Precomputed lattice differences, when gradients are needed and they exist.
    pub differences: Option<&'a [crate::sample::Differences]>,
    /// The blocks' value ranges, where block or zero skipping uses them.
    pub blocks: Option<&'a BlockRanges>,
    /// The bricks' raw value ranges, where Maximum and Minimum test their samples against them.
    pub bricks: Option<&'a BrickRanges>,
    /// The superblocks' ranges, where Maximum and Minimum choose what to sample first.
    pub superblocks: Option<&'a Superblocks>,
    /// The widest vectors the CPU renderer may use to locate and evaluate eight samples at once
    /// where the CPU has the instructions for it (AVX2, SSE 4.1, NEON) — the same pixels, bit for bit
    /// (`crate::trace`'s lanes); the widest by default (unless [`crate::trace::set_vectors`]
    /// said otherwise), narrower or off to compare.
    pub simd: crate::vectors::Vectors,
}

/// Sum's default range: from 0 to twice what a ray along the longest side gathers through
/// data of the volume's mean value, `2·mean·side` (side in voxels) — so an average ray lands
/// near the middle of the transfer function (ends swapped for a negative mean; `(0, 1)` when
/// the mean is 0).
pub fn default_sum_range(volume: &Volume) -> (f32, f32) {
    let side = (volume.dims().max_element().max(2) - 1) as f32;
    let top = 2.0 * volume.mean_value() * side;
    if !top.is_finite() || top == 0.0 {
        (0.0, 1.0)
    } else {
        (top.min(0.0), top.max(0.0))
    }
}

impl<'a> Scene<'a> {
    /// Validates the settings and resolves them for `volume`, with the headlight (if any) along
    /// `view_forward`; the acceleration structures come from (and are kept in) `volume`.
    pub fn new(
        volume: &'a Prepared,
        tf: &TransferFunction,
        settings: &RenderSettings,
        view_forward: Vec3,
    ) -> Result<Self, SettingsError> {
        let mut scene = Self::plain(volume.volume(), tf, settings, view_forward)?;
        let lut = &scene.lut;
        scene.empty = scene.skips_empty().then(|| volume.empty_space(lut));
        let needs_gradient = settings.shading || scene.classifier != Classifier::Table;
        if needs_gradient {
            scene.differences = volume.lattice_differences();
        }
        scene.block_skipping = scene.skips_by_ranges();
        scene.sum_skipping = scene.may_skip_zeros() && enough_zeros(volume.block_ranges());
        if scene.block_skipping || scene.sum_skipping {
            scene.blocks = Some(volume.block_ranges());
        }
        if scene.block_skipping && matches!(settings.method, Method::Maximum | Method::Minimum) {
            scene.bricks = volume.brick_ranges();
            scene.superblocks = Some(volume.superblocks());
        }
        Ok(scene)
    }

    /// As [`Scene::new`] without the acceleration structures: what the GPU preview's uniform
    /// needs, cheap to rebuild on every change. Renders the same image, more slowly.
    pub fn plain(
        volume: &'a Volume,
        tf: &TransferFunction,
        settings: &RenderSettings,
        view_forward: Vec3,
    ) -> Result<Self, SettingsError> {
        settings.validate()?;
        let voxel = volume.spacing().min_element();
        let (lo, hi) = volume.value_range();
        let lut = tf.bake(lo, hi);
        let classifier = Classifier::new(&settings.classification, &lut, voxel);
        let (dt, dt_ref) = (
            settings.step.world(voxel),
            settings.reference_step.world(voxel),
        );
        Ok(Self {
            empty: None,
            block_skipping: false,
            sum_skipping: false,
            differences: None,
            blocks: None,
            bricks: None,
            superblocks: None,
            simd: crate::vectors::vectors(),
            volume,
            classifier,
            lights: settings.phong.resolve(view_forward),
            dt,
            dt_ref,
            step_power: settings
                .opacity_correction
                .then(|| crate::power::StepPower::new(dt / dt_ref))
                .flatten(),
            target: settings.target.unwrap_or(0.5 * (lo + hi)),
            // The default needs the volume's mean (a pass over the data): only for Sum.
            sum_range: match settings.sum_range {
                Some(r) => r,
                None if settings.method == Method::Sum => default_sum_range(volume),
                None => (0.0, 1.0),
            },
            bounds: volume.bounds(),
            clip: settings.clip.resolve(volume.bounds()),
            lut,
            settings: settings.clone(),
        })
    }

    /// Whether empty space is skipped by the transfer function's visibility: on, for
    /// Accumulate front to back, unless a classification may show what the table hides
    /// (Levoy's isovalue contours, the value-and-gradient rectangles).
    pub fn skips_empty(&self) -> bool {
        let s = &self.settings;
        s.skipping
            && s.method == Method::Accumulate
            && s.order == Order::FrontToBack
            && !self.classifier.beyond_table()
    }

    /// Whether First, Maximum and Minimum pass blocks that cannot change their result, by the
    /// blocks' value ranges (when skipping is on).
    pub fn skips_by_ranges(&self) -> bool {
        self.settings.skipping
            && matches!(
                self.settings.method,
                Method::Maximum | Method::Minimum | Method::First
            )
    }

    /// Whether Sum may pass over blocks of zeros (when skipping is on): exact only where a
    /// block whose values are all 0 interpolates to exactly 0 everywhere — no voxel without
    /// data (a NaN would make its neighbours no data, not zeros) and a rescale without
    /// intercept (stored 0 is value 0, and a weighted sum of zeros is zero).
    pub fn may_skip_zeros(&self) -> bool {
        self.settings.skipping
            && self.settings.method == Method::Sum
            && self.volume.no_data_count() == 0
            && self.volume.rescale().1 == 0.0
    }

    /// The jitter fraction for image position `key` (pixel, or sub-pixel with supersampling).
    pub fn jitter(&self, key: [u32; 2]) -> f32 {
        if self.settings.jitter {
            jitter_fraction(key[0], key[1], self.settings.jitter_seed)
        } else {
            0.0
        }
    }
}
