//! Every tunable parameter, documented once: meaning, unit, effect of raising it, default, range.
//!
//! The same text is the CLI's `--help` for the flag and (in the sandbox) the control's tooltip,
//! so the documentation is the lesson. [`crate::settings::RenderSettings::default`] takes its
//! defaults from here and [`crate::settings::RenderSettings::validate`] its ranges.

/// One documented parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tunable {
    /// Stable key: CLI flag name and JSON field.
    pub key: &'static str,
    /// Short label for a UI control.
    pub label: &'static str,
    /// The one description: what it means, its unit, what raising it does.
    pub doc: &'static str,
    /// Default value (1 / 0 for switches).
    pub default: f32,
    /// Smallest accepted value.
    pub min: f32,
    /// Largest accepted value.
    pub max: f32,
}

pub const STEP: Tunable = Tunable {
    key: "step",
    label: "Step size (voxels)",
    doc: "Distance between two samples along a ray, in voxels of the smallest spacing. \
          Smaller steps follow thin structures and sharp transfer functions more faithfully \
          but take proportionally more samples (time). Default 0.5 voxel (twice per voxel, \
          the Nyquist rate of the lattice).",
    default: 0.5,
    min: 1e-6,
    max: 1e6,
};

pub const REFERENCE_STEP: Tunable = Tunable {
    key: "reference-step",
    label: "Reference step (voxels)",
    doc: "The path length a transfer-function opacity is defined for, in voxels of the smallest \
          spacing. With opacity correction each sample's opacity is rescaled to its own length: \
          α' = 1 − (1 − α)^(Δs/Δs_ref). Raising it makes the same transfer function more \
          transparent. Default 1 voxel.",
    default: 1.0,
    min: 1e-6,
    max: 1e6,
};

pub const OPACITY_CORRECTION: Tunable = Tunable {
    key: "opacity-correction",
    label: "Opacity correction",
    doc: "Rescale each sample's opacity to the length of ray it stands for, so the image keeps its \
          brightness when the step changes (and constant density gives Beer–Lambert's \
          1 − e^(−σL) exactly). Turn it off to see why it is needed: halving the step then \
          doubles the number of samples and the volume turns more opaque. Default on.",
    default: 1.0,
    min: 0.0,
    max: 1.0,
};

pub const EARLY_TERMINATION: Tunable = Tunable {
    key: "early-termination",
    label: "Early ray termination",
    doc: "Stop a ray once its accumulated opacity reaches the cutoff: what lies behind can change \
          the pixel by at most (1 − cutoff). Saves time in dense volumes. Default on.",
    default: 1.0,
    min: 0.0,
    max: 1.0,
};

pub const SKIPPING: Tunable = Tunable {
    key: "skipping",
    label: "Empty-space skipping",
    doc: "Pass over space that cannot change the pixel without sampling it: 8×8×8-voxel blocks \
          (and, on the CPU, cells) the transfer function makes transparent under Accumulate, \
          blocks whose values cannot hold the First hit or beat the running Maximum or \
          Minimum, and, for Sum on the CPU, blocks of zeros (where at least 40 % of the blocks \
          are). It never changes a pixel, only the time. Default on.",
    default: 1.0,
    min: 0.0,
    max: 1.0,
};

pub const CUTOFF: Tunable = Tunable {
    key: "cutoff",
    label: "Opacity cutoff",
    doc: "Accumulated opacity at which early termination stops a ray, in [0, 1]. Lower values are \
          faster and less exact (each pixel may be off by up to 1 − cutoff); 1 never stops \
          early unless the ray becomes fully opaque. Default 0.99.",
    default: 0.99,
    min: 0.0,
    max: 1.0,
};

pub const JITTER: Tunable = Tunable {
    key: "jitter",
    label: "Jitter",
    doc: "Offset each ray's first sample by a pseudo-random fraction of the step (the same for a \
          pixel every time). Trades the wood-grain banding of a coarse step for fine noise. \
          Default off.",
    default: 0.0,
    min: 0.0,
    max: 1.0,
};

pub const TARGET: Tunable = Tunable {
    key: "target",
    label: "Target value (First hit)",
    doc: "First hit: the value whose first crossing along the ray is shown, in data units (an \
          isosurface). The crossing is located between two samples and refined, then coloured \
          with the transfer function at this value and shaded. Default: the preset's isovalue, \
          else the middle of the value range.",
    default: 0.0,
    min: -3.4e38,
    max: 3.4e38,
};

pub const SUM_RANGE: Tunable = Tunable {
    key: "sum-range",
    label: "Sum range",
    doc: "Sum: the sums (value × voxels of path) stretched over the transfer function, from \
          the low end (the table's lowest value) to the high end (its highest); sums outside \
          are clamped. Narrow it to see faint rays, widen it to see the densest ones apart. \
          Default: from 0 to twice what a ray along the longest side gathers through data of \
          the volume's mean value, so an average ray lands near the middle.",
    default: 0.0,
    min: -3.4e38,
    max: 3.4e38,
};

pub const RAY_CELL: Tunable = Tunable {
    key: "cell",
    label: "Cell size",
    doc: "Ray density: the cell edge S in world units; cell (i, j, k) spans [iS, (i+1)S) on \
          each axis from the world's origin. Smaller cells show finer paths but need more \
          rays to fill and more memory. Default 0: the scene's longest side over 128 (the \
          volume's voxel for the virtual camera's rays).",
    default: 0.0,
    min: 0.0,
    max: 3.4e38,
};

pub const RAY_CHUNK: Tunable = Tunable {
    key: "chunk",
    label: "Chunk size (cells)",
    doc: "Ray density: cells per chunk edge N. Only chunks a counted ray passes through are \
          stored (RayVis's sparse grid): smaller chunks store less empty space, larger ones \
          cost less to look up. The vector field's sample cube must divide it. Default 16.",
    default: 16.0,
    min: 1.0,
    max: 64.0,
};

pub const MISS_TOLERANCE: Tunable = Tunable {
    key: "miss-tolerance",
    label: "Miss tolerance",
    doc: "A ray is a hit when 0 ≤ t_hit < t_max − tolerance (t in units of its direction's \
          length). Raise it when a renderer reports misses as hits at t_max. Default 0.",
    default: 0.0,
    min: 0.0,
    max: 3.4e38,
};

pub const RAY_STRIDE: Tunable = Tunable {
    key: "stride",
    label: "Stride",
    doc: "The ray mesh draws every n-th ray the filter passes: raise it to see single paths \
          in a dense set, and to draw faster. Default 16.",
    default: 16.0,
    min: 1.0,
    max: 1_000_000.0,
};

pub const RAY_CAMERA_SIDE: Tunable = Tunable {
    key: "camera-rays",
    label: "Rays across",
    doc: "The virtual camera's rays across its image (down by its aspect) whose density is \
          computed; at most 512. Raise it until every voxel is crossed by some ray. \
          Default 32.",
    default: 32.0,
    min: 1.0,
    max: 512.0,
};

pub const FIELD_MIN_COUNT: Tunable = Tunable {
    key: "field-min-count",
    label: "Count threshold",
    doc: "The vector field draws no arrow for a cube whose rays' cell visits number fewer than \
          this (RayVis's count threshold): the sparse fringes stop hiding the main streams. \
          Default 0 (every cube some ray crossed).",
    default: 0.0,
    min: 0.0,
    max: 1e9,
};

pub const SAMPLE_CUBE: Tunable = Tunable {
    key: "sample-cube",
    label: "Sample cube (cells)",
    doc: "The vector field draws one arrow per cube of this many cells a side, along the mean \
          direction of the rays that crossed it, coloured by their count. It must divide the \
          chunk size. Default 4.",
    default: 4.0,
    min: 1.0,
    max: 64.0,
};

pub const REFINE_STEPS: Tunable = Tunable {
    key: "refine-steps",
    label: "Refinement steps (First hit)",
    doc: "First hit: bisection steps that narrow the interval holding the crossing before the final \
          linear interpolation; each halves the error. 0 interpolates linearly between the two \
          samples only. Default 8.",
    default: 8.0,
    min: 0.0,
    max: 32.0,
};

pub const MAX_SAMPLES: Tunable = Tunable {
    key: "max-samples",
    label: "Sample cap per ray",
    doc: "The most samples one ray may take; a ray that would need more stops there and says so. \
          Keeps a tiny step from hanging the program. Default 65536.",
    default: 65536.0,
    min: 1.0,
    max: 16_777_216.0,
};

pub const SUPERSAMPLING: Tunable = Tunable {
    key: "supersampling",
    label: "Supersampling (n×n rays)",
    doc: "Cast n×n rays per pixel on a regular grid and average them, smoothing edges at n² the \
          cost. Default 1 (one ray through each pixel centre).",
    default: 1.0,
    min: 1.0,
    max: 8.0,
};

pub const SHADING: Tunable = Tunable {
    key: "shading",
    label: "Shading",
    doc: "Light each sample with the Phong model, using the normalised gradient (central \
          differences) as the surface normal. Shows surfaces inside the volume; costs six extra \
          lattice reads per lit sample. Default off (on in presets that call for it).",
    default: 0.0,
    min: 0.0,
    max: 1.0,
};

pub const AMBIENT: Tunable = Tunable {
    key: "ka",
    label: "Ambient (ka)",
    doc: "Fraction of the sample's colour seen without any light (times the global ambient G_a): \
          lifts shadowed sides. \
          In [0, 1]; default 0.2.",
    default: 0.2,
    min: 0.0,
    max: 1.0,
};

pub const DIFFUSE: Tunable = Tunable {
    key: "kd",
    label: "Diffuse (kd)",
    doc: "Weight of Lambert's term kd·max(N·L, 0): brightness of surfaces facing the light. \
          In [0, 1]; default 0.7.",
    default: 0.7,
    min: 0.0,
    max: 1.0,
};

pub const SPECULAR: Tunable = Tunable {
    key: "ks",
    label: "Specular (ks)",
    doc: "Weight of the white highlight ks·max(N·H, 0)^n (Blinn–Phong) or ks·max(R·V, 0)^n \
          (Phong). In [0, 1]; default 0.3.",
    default: 0.3,
    min: 0.0,
    max: 1.0,
};

pub const SHININESS: Tunable = Tunable {
    key: "shininess",
    label: "Shininess (n)",
    doc: "Specular exponent n: higher values give smaller, sharper highlights. Default 10.",
    default: 10.0,
    min: 1.0,
    max: 1024.0,
};

pub const ATTENUATION_CONSTANT: Tunable = Tunable {
    key: "kc",
    label: "Attenuation kc",
    doc: "Constant term of a point or spot light's attenuation f = 1/(kc + kl·d + kq·d²), d the \
          distance to the light in world units. Default 1 (no falloff with kl = kq = 0).",
    default: 1.0,
    min: 0.0,
    max: 1e6,
};

pub const ATTENUATION_LINEAR: Tunable = Tunable {
    key: "kl",
    label: "Attenuation kl",
    doc: "Linear term of a point or spot light's attenuation, per world unit: raising it darkens \
          samples far from the light. Default 0.",
    default: 0.0,
    min: 0.0,
    max: 1e6,
};

pub const ATTENUATION_QUADRATIC: Tunable = Tunable {
    key: "kq",
    label: "Attenuation kq",
    doc: "Quadratic term of a point or spot light's attenuation, per squared world unit (physical \
          inverse-square falloff). Default 0.",
    default: 0.0,
    min: 0.0,
    max: 1e6,
};

pub const GRADIENT_THRESHOLD: Tunable = Tunable {
    key: "gradient-threshold",
    label: "Gradient threshold",
    doc: "Samples whose gradient magnitude (data units per world unit) is below this keep their \
          unshaded colour: in flat regions the normal is undefined. Default 1e-3.",
    default: 1e-3,
    min: 0.0,
    max: 3.4e38,
};

pub const TWO_SIDED: Tunable = Tunable {
    key: "two-sided",
    label: "Two-sided lighting",
    doc: "Flip normals that face away from the viewer, so a surface is lit from both sides (what \
          you want inside a volume, where a 'surface' has no outside). Default on.",
    default: 1.0,
    min: 0.0,
    max: 1.0,
};

pub const EMISSION: Tunable = Tunable {
    key: "ke",
    label: "Emission (ke)",
    doc: "The lecture's M_e: the sample glows with ke times its own colour, lit or not (added \
          before the ambient term). In [0, 1]; default 0.",
    default: 0.0,
    min: 0.0,
    max: 1.0,
};

pub const GLOBAL_AMBIENT: Tunable = Tunable {
    key: "global-ambient",
    label: "Global ambient (G_a)",
    doc: "The lecture's G_a: the grey level of the scene-wide ambient light, which multiplies the \
          ambient term to give G_a·ka·c. In [0, 1]; default 1.",
    default: 1.0,
    min: 0.0,
    max: 1.0,
};

pub const LIGHT_AMBIENT: Tunable = Tunable {
    key: "light-ambient",
    label: "Light's ambient",
    doc: "The lecture's I_a,i: this light's own ambient intensity as a share of its colour; it \
          adds f·s·I_a·ka·c, so it falls off with the light's distance and cone. In [0, 1]; \
          default 0.",
    default: 0.0,
    min: 0.0,
    max: 1.0,
};

pub const SPOT_CUTOFF: Tunable = Tunable {
    key: "spot-cutoff",
    label: "Spot cutoff (degrees)",
    doc: "Half the opening angle of a spot light's cone: samples further off its axis get no \
          light from it (s = 0). Default 30.",
    default: 30.0,
    min: 0.0,
    max: 90.0,
};

pub const SPOT_EXPONENT: Tunable = Tunable {
    key: "spot-exponent",
    label: "Spot exponent",
    doc: "How fast a spot light dims away from its axis inside the cone: the spotlight factor is \
          s = (cos of the angle to the axis)^exponent; 0 lights the cone evenly. Default 4.",
    default: 4.0,
    min: 0.0,
    max: 128.0,
};

pub const DEPTH_CUE: Tunable = Tunable {
    key: "depth-cue",
    label: "Depth cue (Levoy)",
    doc: "Levoy's depth cueing: every light's falloff becomes f = 1/(k1 + k2·d) with d the \
          sample's distance from the picture plane, so farther parts of the volume are dimmer \
          (instead of each point light's own falloff with its distance). Default off.",
    default: 0.0,
    min: 0.0,
    max: 1.0,
};

pub const DEPTH_CUE_CONSTANT: Tunable = Tunable {
    key: "depth-k1",
    label: "Depth cue k1",
    doc: "Constant term k1 of Levoy's depth cue 1/(k1 + k2·d). Default 1.",
    default: 1.0,
    min: 0.0,
    max: 1e6,
};

pub const DEPTH_CUE_LINEAR: Tunable = Tunable {
    key: "depth-k2",
    label: "Depth cue k2",
    doc: "Linear term k2 of Levoy's depth cue 1/(k1 + k2·d), per world unit of distance from the \
          picture plane: raising it darkens the far side. Default 0.002.",
    default: 0.002,
    min: 0.0,
    max: 1e6,
};

pub const ISO_THICKNESS: Tunable = Tunable {
    key: "iso-thickness",
    label: "Isovalue thickness (voxels)",
    doc: "Levoy isovalue classification: the width r of the transition region around each \
          isovalue, in voxels. Opacity falls linearly from the isovalue's to 0 over |f − f_v| ≤ \
          r·|grad f|, so surfaces look equally thick whatever the local gradient. Default 1.",
    default: 1.0,
    min: 1e-3,
    max: 1e3,
};

pub const BOUNDARY_GRADIENT: Tunable = Tunable {
    key: "boundary-gradient",
    label: "Full-opacity gradient",
    doc: "Levoy boundary classification: the gradient magnitude (data units per world unit) at \
          which a boundary reaches the transfer function's opacity; opacity is scaled by \
          |grad f| / this and clamped, so homogeneous regions vanish and boundaries remain. \
          Default: a tenth of the value range per voxel.",
    default: 0.0,
    min: 0.0,
    max: 3.4e38,
};

pub const VIRTUAL_RESOLUTION: Tunable = Tunable {
    key: "virtual-resolution",
    label: "Virtual camera pixels",
    doc: "Pixels across each edge of the virtual camera's image: one ray per pixel, drawn in the \
          scene and traced in the inspector. Small, so every ray and sample stays visible \
          (and the scene light: each sample is a sphere). Default 4.",
    default: 4.0,
    min: 1.0,
    max: 64.0,
};

pub const SAMPLE_BUDGET: Tunable = Tunable {
    key: "sample-budget",
    label: "Sample budget",
    doc: "The most sample spheres the scene shows for the virtual camera's rays; beyond it the \
          rays are drawn without their samples and a message says so. Default 20000.",
    default: 20000.0,
    min: 100.0,
    max: 200000.0,
};

pub const RAY_SPEED: Tunable = Tunable {
    key: "ray-speed",
    label: "Ray speed",
    doc: "How fast the virtual camera's rays grow outwards, in volume diagonals per second; \
          samples appear as a ray passes them. Default 0.5.",
    default: 0.5,
    min: 0.02,
    max: 10.0,
};

pub const PREVIEW_SCALE: Tunable = Tunable {
    key: "preview-scale",
    label: "Preview resolution",
    doc: "Fraction of the window's pixels the preview renders at rest (then stretched to fill \
          it). Halving it quarters the rays: the way to keep slow hardware interactive. \
          Default 1.",
    default: 1.0,
    min: 0.05,
    max: 1.0,
};

pub const PREVIEW_BACKEND: Tunable = Tunable {
    key: "preview-backend",
    label: "Preview drawn by",
    doc: "Who draws the live view of the volume. GPU: the preview shaders, the twin of the core, \
          on the graphics card. CPU: the core itself on background threads, coarse while the \
          view moves and refined to the exact render at rest; the window never waits for it. \
          The step multipliers below apply to the GPU only. Default: the CPU on a software \
          rasterizer (lavapipe, llvmpipe, WARP: a machine without a real GPU), else the GPU.",
    default: 0.0,
    min: 0.0,
    max: 1.0,
};

pub const PREVIEW_STEP_MULTIPLIER: Tunable = Tunable {
    key: "preview-step-multiplier",
    label: "Preview step ×",
    doc: "The GPU preview samples this many times farther apart than the step setting (the CPU \
          render always uses the step itself). Raising it speeds the preview up and makes it \
          coarser. Default 1.",
    default: 1.0,
    min: 1.0,
    max: 16.0,
};

pub const ADAPTIVE_QUALITY: Tunable = Tunable {
    key: "adaptive-quality",
    label: "Adaptive quality",
    doc: "While the camera moves, the GPU preview lowers its resolution (as far as its measured \
          speed needs) and raises its step multiplier, and returns to full quality once it \
          rests; a resting view too slow for one frame is drawn a few rows a frame. Default on.",
    default: 1.0,
    min: 0.0,
    max: 1.0,
};

pub const MOVING_SCALE: Tunable = Tunable {
    key: "moving-scale",
    label: "Resolution while moving",
    doc: "With adaptive quality: the lowest resolution fraction the GPU preview drops to while \
          the camera moves (0.25: one ray in 16 of the resting frame). It drops only as far as \
          the measured frame time needs: a GPU fast enough keeps the resting resolution. \
          Default 0.25.",
    default: 0.25,
    min: 0.05,
    max: 1.0,
};

pub const MOVING_STEP_MULTIPLIER: Tunable = Tunable {
    key: "moving-step-multiplier",
    label: "Step × while moving",
    doc: "With adaptive quality: the preview's step multiplier while the camera moves. Default 2.",
    default: 2.0,
    min: 1.0,
    max: 16.0,
};

pub const CROP: Tunable = Tunable {
    key: "crop",
    label: "Crop box",
    doc: "Keep only a sub-box of the volume, per axis from a lower to an upper side given as \
          fractions of the volume's extent (0 to 1): rays start sampling where they enter the \
          cropped box, so what it removes is not drawn and not paid for. Equal sides keep a \
          single slice. Default: the whole volume (0 to 1 on every axis).",
    default: 0.0,
    min: 0.0,
    max: 1.0,
};

pub const CLIP_PLANE: Tunable = Tunable {
    key: "clip-plane",
    label: "Clip plane",
    doc: "Cut the volume with a plane and remove the side its normal points to, to look inside \
          (the ventricles behind the skull). Rays sample only the kept side, starting at the cut \
          face where they cross it. Default off.",
    default: 0.0,
    min: 0.0,
    max: 1.0,
};

pub const CLIP_POSITION: Tunable = Tunable {
    key: "clip-position",
    label: "Plane position",
    doc: "Where the clip plane sits along its normal, as a fraction of the volume's half-size in \
          that direction: 0 cuts through the centre, 1 touches the farthest corner (keeps all), \
          −1 the nearest (keeps nothing). Default 0.",
    default: 0.0,
    min: -1.0,
    max: 1.0,
};

/// Every tunable, for listing and for the UI.
pub const ALL: &[Tunable] = &[
    VIRTUAL_RESOLUTION,
    SAMPLE_BUDGET,
    RAY_SPEED,
    STEP,
    REFERENCE_STEP,
    OPACITY_CORRECTION,
    EARLY_TERMINATION,
    CUTOFF,
    JITTER,
    TARGET,
    SUM_RANGE,
    REFINE_STEPS,
    MAX_SAMPLES,
    SUPERSAMPLING,
    SHADING,
    AMBIENT,
    DIFFUSE,
    SPECULAR,
    SHININESS,
    ATTENUATION_CONSTANT,
    ATTENUATION_LINEAR,
    ATTENUATION_QUADRATIC,
    GRADIENT_THRESHOLD,
    TWO_SIDED,
    EMISSION,
    GLOBAL_AMBIENT,
    LIGHT_AMBIENT,
    SPOT_CUTOFF,
    SPOT_EXPONENT,
    DEPTH_CUE,
    DEPTH_CUE_CONSTANT,
    DEPTH_CUE_LINEAR,
    ISO_THICKNESS,
    BOUNDARY_GRADIENT,
    PREVIEW_SCALE,
    PREVIEW_BACKEND,
    PREVIEW_STEP_MULTIPLIER,
    ADAPTIVE_QUALITY,
    MOVING_SCALE,
    MOVING_STEP_MULTIPLIER,
    SKIPPING,
    CROP,
    CLIP_PLANE,
    CLIP_POSITION,
    RAY_CELL,
    RAY_CHUNK,
    MISS_TOLERANCE,
    RAY_STRIDE,
    RAY_CAMERA_SIDE,
    SAMPLE_CUBE,
    FIELD_MIN_COUNT,
];

#[cfg(test)]
mod tests {
    use super::*;

    /// The text never contradicts the code: a default quoted in a doc is the default.
    #[test]
    fn quoted_defaults_match_the_values() {
        for t in ALL {
            let doc = t.doc.to_lowercase();
            let Some(pos) = doc.rfind("default") else {
                panic!("{} does not state its default", t.key);
            };
            let quoted = &doc[pos + "default".len()..];
            let word = quoted
                .split_whitespace()
                .next()
                .unwrap_or("")
                .trim_end_matches(['.', ',', ')']);
            match word {
                "on" => assert_eq!(t.default, 1.0, "{}", t.key),
                "off" => assert_eq!(t.default, 0.0, "{}", t.key),
                _ => match word.parse::<f32>() {
                    Ok(v) => assert_eq!(v, t.default, "{}: doc says {v}", t.key),
                    // Defaults that depend on the volume or preset are described in words.
                    Err(_) => assert!(t.default == 0.0, "{}: unparsed default '{word}'", t.key),
                },
            }
        }
    }

    #[test]
    fn every_tunable_is_documented_and_its_default_in_range() {
        let mut keys = std::collections::HashSet::new();
        for t in ALL {
            assert!(keys.insert(t.key), "duplicate key {}", t.key);
            assert!(t.doc.len() > 40, "{} is under-documented", t.key);
            assert!(t.min <= t.max, "{}", t.key);
            assert!(
                t.default >= t.min && t.default <= t.max,
                "{} default out of range",
                t.key
            );
        }
    }
}
