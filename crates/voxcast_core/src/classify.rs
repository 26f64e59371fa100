//! Classification: the opacity of a sample, from its value and (in Levoy's modes) its gradient.
//!
//! Twin: `shaders/classify.wgsl` (`classify`).
//!
//! * **Table** — the transfer function's opacity at the value: `α = TF_α(f)`.
//! * **Isovalue contours** (Levoy 1988, "Display of surfaces from volume data", §3; lecture
//!   "Classification based on isovalues"). For each isovalue `f_v` with opacity `α_v = TF_α(f_v)`
//!   and a transition thickness `r` (world units):
//!
//!   ```text
//!   α_v(x) = α_v · 1                                 if |∇f| = 0 and f(x) = f_v
//!            α_v · (1 − |f_v − f(x)| / (r·|∇f|))     if |∇f| > 0 and |f(x) − f_v| ≤ r·|∇f|
//!            0                                       otherwise
//!   ```
//!
//!   Dividing by the gradient makes the surface equally thick wherever it is steep or shallow.
//!   Several isovalues combine as `α = 1 − Π(1 − α_v(x))`.
//! * **Region boundaries** (Levoy 1988, §3; lecture "Classification based on boundaries"): the
//!   table's opacity (piecewise linear between region values, as Levoy's formula) scaled by the
//!   gradient magnitude, `α = min(1, TF_α(f) · |∇f| / g_full)`, so the insides of homogeneous
//!   regions vanish and the boundaries between them remain. `g_full` is the gradient at which a
//!   boundary reaches the table's opacity.
//!
//! * **Value and gradient** (the lecture's "classification based on scalar value and gradient
//!   magnitude"; the 2-D transfer functions of Kindlmann and Durkin 1998 and Kniss et al. 2001):
//!   rectangles in the plane of value × gradient magnitude, each with an opacity, drawn over
//!   that plane's histogram ([`crate::histogram2d`]). A sample whose `(f, |∇f|)` lies in a
//!   rectangle takes its opacity (the highest, where rectangles overlap), elsewhere 0:
//!   `α = max{α_r : f ∈ [f0_r, f1_r], |∇f| ∈ [g0_r, g1_r]}`. A boundary between two materials
//!   crosses every value between theirs with a high gradient, while a material of one of
//!   those values inside has a low one: a rectangle at high gradient keeps the boundary and
//!   drops the material, which no 1-D table can do.
//!
//! The colour is always the transfer function's colour at the value.

use crate::error::SettingsError;
use crate::transfer::Lut;

/// The most isovalues a classification may have: the GPU preview's uniform holds this many.
pub const MAX_ISOVALUES: usize = 4;

/// The most rectangles a value-and-gradient classification may have (the uniform's room).
pub const MAX_REGIONS: usize = 4;

/// One rectangle of a value-and-gradient classification.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Region {
    /// `[f0, f1]`: the values it covers (data units).
    pub value: [f32; 2],
    /// `[g0, g1]`: the gradient magnitudes it covers (data units per world unit).
    pub gradient: [f32; 2],
    /// The opacity of a sample inside it.
    pub opacity: f32,
}

impl Region {
    /// Whether `(f, g)` lies in it (edges included).
    #[inline]
    pub fn contains(&self, f: f32, g: f32) -> bool {
        f >= self.value[0] && f <= self.value[1] && g >= self.gradient[0] && g <= self.gradient[1]
    }
}

/// How opacity is assigned (see the module docs for the formulas).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case", tag = "mode")]
pub enum Classification {
    /// The transfer function's opacity.
    #[default]
    Table,
    /// Levoy's isovalue contours around each value in `isovalues` (data units).
    IsoContours {
        isovalues: Vec<f32>,
        /// Transition thickness `r`, in voxels of the smallest spacing.
        thickness_voxels: f32,
    },
    /// Levoy's region boundaries: table opacity scaled by `|∇f| / full_gradient`.
    Boundaries {
        /// Gradient magnitude (data units per world unit) at which opacity reaches the table's;
        /// `None`: a tenth of the value range per voxel.
        full_gradient: Option<f32>,
    },
    /// Rectangles over value × gradient magnitude, each with an opacity.
    ValueGradient { regions: Vec<Region> },
}

impl Classification {
    /// Whether the opacity depends on the gradient (which then must be computed per sample).
    pub fn needs_gradient(&self) -> bool {
        !matches!(self, Classification::Table)
    }

    pub fn validate(&self) -> Result<(), SettingsError> {
        match self {
            Classification::Table => Ok(()),
            Classification::IsoContours {
                isovalues,
                thickness_voxels,
            } => {
                if isovalues.is_empty() {
                    return Err(SettingsError::Invalid(
                        "isovalue classification needs at least one isovalue".into(),
                    ));
                }
                if isovalues.len() > MAX_ISOVALUES {
                    return Err(SettingsError::Invalid(format!(
                        "at most {MAX_ISOVALUES} isovalues (the GPU preview classifies with no \
                         more, and the render must show what the preview shows); {} given",
                        isovalues.len()
                    )));
                }
                if let Some(v) = isovalues.iter().find(|v| !v.is_finite()) {
                    return Err(SettingsError::Invalid(format!(
                        "isovalue {v} is not finite"
                    )));
                }
                SettingsError::check_positive("iso-thickness", *thickness_voxels)
            }
            Classification::Boundaries { full_gradient } => match full_gradient {
                Some(g) => SettingsError::check_positive("boundary-gradient", *g),
                None => Ok(()),
            },
            Classification::ValueGradient { regions } => validate_regions(regions),
        }
    }
}

fn validate_regions(regions: &[Region]) -> Result<(), SettingsError> {
    if regions.len() > MAX_REGIONS {
        return Err(SettingsError::Invalid(format!(
            "at most {MAX_REGIONS} rectangles (the GPU preview classifies with no more); {} given",
            regions.len()
        )));
    }
    for (i, r) in regions.iter().enumerate() {
        let [f0, f1] = r.value;
        let [g0, g1] = r.gradient;
        let finite = [f0, f1, g0, g1, r.opacity].iter().all(|x| x.is_finite());
        if !finite || f0 > f1 || g0 > g1 || g0 < 0.0 || !(0.0..=1.0).contains(&r.opacity) {
            return Err(SettingsError::Invalid(format!(
                "rectangle {}: values {f0} … {f1} and gradients {g0} … {g1} must be finite and \
                 in order, gradients not negative, and the opacity {} within 0 … 1",
                i + 1,
                r.opacity
            )));
        }
    }
    Ok(())
}

/// One isovalue's contour opacity (Levoy's formula) for value `f` with gradient magnitude `g`.
#[inline]
pub fn iso_contour_alpha(f: f32, g: f32, f_v: f32, alpha_v: f32, r: f32) -> f32 {
    let d = (f_v - f).abs();
    if g <= 0.0 {
        return if d == 0.0 { alpha_v } else { 0.0 };
    }
    if d <= r * g {
        alpha_v * (1.0 - d / (r * g))
    } else {
        0.0
    }
}

/// The classification resolved for one volume: world-unit thickness, isovalue opacities.
#[derive(Clone, Debug, PartialEq)]
pub enum Classifier {
    Table,
    IsoContours { isovalues: Vec<(f32, f32)>, r: f32 },
    Boundaries { inv_full_gradient: f32 },
    ValueGradient { regions: Vec<Region> },
}

impl Classifier {
    /// Resolves `c` for a volume whose smallest spacing is `voxel` (world units), with `lut`
    /// baked over the volume's value range.
    pub fn new(c: &Classification, lut: &Lut, voxel: f32) -> Self {
        match c {
            Classification::Table => Classifier::Table,
            Classification::IsoContours {
                isovalues,
                thickness_voxels,
            } => Classifier::IsoContours {
                isovalues: isovalues.iter().map(|&v| (v, lut.lookup(v).w)).collect(),
                r: thickness_voxels * voxel,
            },
            Classification::Boundaries { full_gradient } => Classifier::Boundaries {
                inv_full_gradient: 1.0 / full_gradient.unwrap_or(0.1 * (lut.hi - lut.lo) / voxel),
            },
            Classification::ValueGradient { regions } => Classifier::ValueGradient {
                regions: regions.iter().take(MAX_REGIONS).copied().collect(),
            },
        }
    }

    /// Whether a sample may be opaque where the table's opacity is 0: isovalue contours (any
    /// value near an isovalue) and the value-and-gradient rectangles (their own opacities).
    /// Skipping by the table's visibility is then not exact.
    pub fn beyond_table(&self) -> bool {
        matches!(
            self,
            Classifier::IsoContours { .. } | Classifier::ValueGradient { .. }
        )
    }

    /// Opacity for value `f` with table opacity `table_alpha` and gradient magnitude `g`
    /// (ignored by [`Classifier::Table`]).
    #[inline]
    pub fn classify(&self, f: f32, table_alpha: f32, g: f32) -> f32 {
        match self {
            Classifier::Table => table_alpha,
            Classifier::IsoContours { isovalues, r } => {
                let transparency = isovalues.iter().fold(1.0, |t, &(f_v, a_v)| {
                    t * (1.0 - iso_contour_alpha(f, g, f_v, a_v, *r))
                });
                1.0 - transparency
            }
            Classifier::Boundaries { inv_full_gradient } => {
                (table_alpha * g * inv_full_gradient).min(1.0)
            }
            Classifier::ValueGradient { regions } => regions
                .iter()
                .filter(|r| r.contains(f, g))
                .fold(0.0, |a, r| a.max(r.opacity)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levoy_iso_contour_closed_form() {
        // f_v = 100, α_v = 0.8, r = 2, |∇f| = 5: full at 100, zero beyond ±10, linear between.
        assert_eq!(iso_contour_alpha(100.0, 5.0, 100.0, 0.8, 2.0), 0.8);
        assert!((iso_contour_alpha(105.0, 5.0, 100.0, 0.8, 2.0) - 0.4).abs() < 1e-6);
        assert_eq!(iso_contour_alpha(110.5, 5.0, 100.0, 0.8, 2.0), 0.0);
        assert_eq!(iso_contour_alpha(100.0, 0.0, 100.0, 0.8, 2.0), 0.8);
        assert_eq!(iso_contour_alpha(100.1, 0.0, 100.0, 0.8, 2.0), 0.0);
    }

    #[test]
    fn several_isovalues_combine_as_transparencies() {
        let c = Classifier::IsoContours {
            isovalues: vec![(10.0, 0.5), (12.0, 0.5)],
            r: 1.0,
        };
        // At f = 11 with |∇f| = 2: each contributes 0.5·(1 − 1/2) = 0.25.
        let a = c.classify(11.0, 0.0, 2.0);
        assert!((a - (1.0 - 0.75 * 0.75)).abs() < 1e-6);
    }

    #[test]
    fn boundaries_scale_by_gradient_and_clamp() {
        let c = Classifier::Boundaries {
            inv_full_gradient: 0.1,
        };
        assert_eq!(c.classify(0.0, 0.5, 0.0), 0.0);
        assert!((c.classify(0.0, 0.5, 10.0) - 0.5).abs() < 1e-6);
        assert_eq!(c.classify(0.0, 0.5, 1000.0), 1.0);
    }

    /// A sample takes the opacity of the rectangle it lies in (the highest where two overlap),
    /// whatever the table says; outside every rectangle it is transparent.
    #[test]
    fn value_gradient_rectangles_set_the_opacity() {
        let c = Classifier::ValueGradient {
            regions: vec![
                Region {
                    value: [10.0, 20.0],
                    gradient: [5.0, 50.0],
                    opacity: 0.4,
                },
                Region {
                    value: [15.0, 30.0],
                    gradient: [0.0, 8.0],
                    opacity: 0.9,
                },
            ],
        };
        assert_eq!(c.classify(12.0, 0.0, 6.0), 0.4);
        assert_eq!(c.classify(16.0, 1.0, 6.0), 0.9, "both: the higher");
        assert_eq!(c.classify(16.0, 1.0, 9.0), 0.4);
        assert_eq!(c.classify(25.0, 1.0, 9.0), 0.0);
        assert_eq!(c.classify(20.0, 0.0, 50.0), 0.4, "edges are inside");
        assert_eq!(c.classify(9.99, 1.0, 6.0), 0.0);
        let none = Classifier::ValueGradient { regions: vec![] };
        assert_eq!(none.classify(12.0, 1.0, 6.0), 0.0);
    }

    #[test]
    fn validation() {
        assert!(
            Classification::IsoContours {
                isovalues: vec![],
                thickness_voxels: 1.0
            }
            .validate()
            .is_err()
        );
        let iso = |n: usize| Classification::IsoContours {
            isovalues: (0..n).map(|i| i as f32).collect(),
            thickness_voxels: 1.0,
        };
        assert!(iso(MAX_ISOVALUES).validate().is_ok());
        let e = iso(MAX_ISOVALUES + 1).validate().unwrap_err().to_string();
        assert!(
            e.contains("at most 4 isovalues") && e.contains("5 given"),
            "{e}"
        );
        assert!(
            Classification::Boundaries {
                full_gradient: Some(0.0)
            }
            .validate()
            .is_err()
        );
        assert!(
            Classification::Boundaries {
                full_gradient: None
            }
            .validate()
            .is_ok()
        );
        assert!(Classification::Table.validate().is_ok());
        let r = Region {
            value: [0.0, 1.0],
            gradient: [0.0, 1.0],
            opacity: 0.5,
        };
        let vg = |regions: Vec<Region>| Classification::ValueGradient { regions };
        assert!(vg(vec![r; MAX_REGIONS]).validate().is_ok());
        assert!(vg(vec![r; MAX_REGIONS + 1]).validate().is_err());
        for bad in [
            Region {
                value: [2.0, 1.0],
                ..r
            },
            Region {
                gradient: [-1.0, 1.0],
                ..r
            },
            Region { opacity: 1.5, ..r },
            Region {
                value: [f32::NAN, 1.0],
                ..r
            },
        ] {
            let e = vg(vec![r, bad]).validate().unwrap_err().to_string();
            assert!(e.contains("rectangle 2"), "{e}");
        }
    }
}
