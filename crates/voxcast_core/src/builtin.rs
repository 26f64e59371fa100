//! Embedded datasets, so nothing needs a file: three procedural test volumes and two small real
//! ones (sources and licences in `assets/volumes/NOTICE.md`).
//!
//! * `bunny` — the Stanford bunny as a smooth density, surface at 128 (128×126×101, u8).
//! * `brainsmall` — VolPack's MRI head (128×128×84, u8).
//! * `shells` — concentric spherical shells, `255·(½ − ½·cos(2πr/10))` inside r < 30 voxels
//!   (64³, u8): nested surfaces for First and Accumulate.
//! * `marschner-lobb` — the Marschner–Lobb test signal (Marschner & Lobb, "An evaluation of
//!   reconstruction filters for volume rendering", 1994) with f_M = 6, α = 0.25 on [−1, 1]³
//!   (41³, f32): nearly all its energy is near the Nyquist limit, so it shows every
//!   reconstruction and step-size artefact.
//! * `bucky` — a buckminsterfullerene-like cage: Gaussian blobs on the 60 vertices of a
//!   truncated icosahedron (32³, u8).
//! * `blobs` — two Gaussian blobs, one brighter, on an 8³ grid (u8): small enough that every
//!   voxel, ray and sample can be seen and counted.
//! * `head` — a CT-like head phantom: nested ellipsoids of scalp, skull, brain and two
//!   ventricles at CT-like levels ([`HEAD_SKIN`] … [`HEAD_BONE`]) with soft edges 1.5 voxels wide
//!   (64³, u8): a low isovalue shows the skin, one between skin and bone the skull.

use crate::error::LoadError;
use crate::io::{Loaded, load, nrrd};
use crate::volume::{Volume, VoxelData};
use glam::{UVec3, Vec3};
use std::f32::consts::PI;
use std::path::Path;

/// Every embedded dataset's name, with a one-line description.
pub const DATASETS: &[(&str, &str)] = &[
    (
        "bunny",
        "Stanford bunny as a smooth density, surface at 128 (128×126×101, uint8)",
    ),
    (
        "brainsmall",
        "MRI of a head, VolPack example (128×128×84, uint8)",
    ),
    ("shells", "concentric spherical shells (64³, uint8)"),
    (
        "marschner-lobb",
        "Marschner–Lobb test signal, f_M = 6, α = 0.25 (41³, float32)",
    ),
    (
        "bucky",
        "buckyball-like cage of 60 Gaussian atoms (32³, uint8)",
    ),
    (
        "blobs",
        "two Gaussian blobs on an 8³ grid, small enough to see every voxel and sample (uint8)",
    ),
    (
        "head",
        "CT-like head phantom: scalp, skull, brain, ventricles (64³, uint8)",
    ),
    (
        "voxel",
        "one unit voxel with the lecture's 8 corner values, for trilinear interpolation (2³, float32)",
    ),
    (
        "masked",
        "a ball with one octant of no data (NaN, as a masked scan stores it) and a few ±∞ voxels (32³, float32)",
    ),
];

/// The real datasets' files (in `assets/volumes/`), by the dataset names they open as.
pub const FILES: &[(&str, &str)] = &[
    ("bunny", "bunny_sdf.nrrd"),
    ("brainsmall", "mri_brainsmall.nrrd"),
];

/// [`FILES`]' bytes compiled in, by file (the desktop's `embedded-files` feature).
#[cfg(feature = "embedded-files")]
const EMBEDDED: &[(&str, &[u8])] = &[
    (
        "bunny_sdf.nrrd",
        include_bytes!("../../../assets/volumes/bunny_sdf.nrrd"),
    ),
    (
        "mri_brainsmall.nrrd",
        include_bytes!("../../../assets/volumes/mri_brainsmall.nrrd"),
    ),
];
/// None compiled in: the web page fetches them beside its module (0.8 MB a visitor would
/// otherwise download inside it, uncompressible) and hands them over with [`provide`].
#[cfg(not(feature = "embedded-files"))]
const EMBEDDED: &[(&str, &[u8])] = &[];

/// A real dataset's file: compiled in, or handed over with [`provide`].
fn file_bytes(file: &str) -> Option<std::sync::Arc<[u8]>> {
    if let Some((_, bytes)) = EMBEDDED.iter().find(|(name, _)| *name == file) {
        return Some((*bytes).into());
    }
    let provided = PROVIDED.lock().unwrap_or_else(|e| e.into_inner());
    provided
        .iter()
        .find(|(name, _)| name == file)
        .map(|(_, bytes)| bytes.clone())
}

static PROVIDED: std::sync::Mutex<Vec<(String, std::sync::Arc<[u8]>)>> =
    std::sync::Mutex::new(Vec::new());

/// Hands over one of [`FILES`]' files where it is not compiled in; a second copy replaces the first.
pub fn provide(file: &str, bytes: Vec<u8>) {
    let mut provided = PROVIDED.lock().unwrap_or_else(|e| e.into_inner());
    provided.retain(|(name, _)| name != file);
    provided.push((file.to_string(), bytes.into()));
}

/// The file of the real dataset `source` names (`builtin:NAME`) where it is neither compiled
/// in nor handed over yet: what a page must fetch before opening it.
pub fn missing_file(source: &str) -> Option<&'static str> {
    let name = source.strip_prefix("builtin:")?.replace('_', "-");
    let (_, file) = FILES.iter().find(|f| f.0 == name)?;
    file_bytes(file).is_none().then_some(*file)
}

/// Decodes a real dataset from its file, as `bytes_of` finds it (compiled in or provided).
fn load_file(
    name: &str,
    bytes_of: impl Fn(&str) -> Option<std::sync::Arc<[u8]>>,
) -> Result<Loaded, LoadError> {
    let file = FILES.iter().find(|f| f.0 == name).map_or(name, |f| f.1);
    let stem = file.trim_end_matches(".nrrd");
    match bytes_of(file) {
        Some(bytes) => nrrd::load_bytes(stem, &bytes),
        None => Err(LoadError::new(
            format!("builtin:{name}"),
            crate::error::LoadProblem::NotProvided(file.to_string()),
        )),
    }
}

/// Opens `builtin:NAME`, a ray density (`density:…`, [`crate::rays::as_volume`]) or a file
/// path.
pub fn load_source(spec: &str) -> Result<Loaded, LoadError> {
    if let Some(parsed) = crate::rays::as_volume::parse(spec) {
        let fail = |why: String| LoadError::new(spec, crate::error::LoadProblem::RayDensity(why));
        let density = parsed.map_err(fail)?;
        let never = std::sync::atomic::AtomicBool::new(false);
        let (volume, words) =
            crate::rays::as_volume::load(&density, &|_, _| {}, &never).map_err(fail)?;
        return Ok(Loaded {
            volume,
            notes: vec![words],
        });
    }
    match spec.strip_prefix("builtin:") {
        Some(name) => load_builtin(name),
        None => load(Path::new(spec)),
    }
}

/// Builds or decodes an embedded dataset by name.
pub fn load_builtin(name: &str) -> Result<Loaded, LoadError> {
    let generated = |volume: Volume| Loaded {
        volume,
        notes: Vec::new(),
    };
    match name.replace('_', "-").as_str() {
        real @ ("bunny" | "brainsmall") => load_file(real, file_bytes),
        "shells" => Ok(generated(shells())),
        "marschner-lobb" => Ok(generated(marschner_lobb())),
        "bucky" => Ok(generated(bucky())),
        "voxel" => Ok(generated(worked_voxel())),
        "head" => Ok(generated(head())),
        "blobs" => Ok(generated(blobs())),
        "masked" => Ok(generated(masked())),
        other => {
            let names: Vec<&str> = DATASETS.iter().map(|d| d.0).collect();
            Err(LoadError::new(
                format!("builtin:{other}"),
                crate::error::LoadProblem::UnknownBuiltin(names.join(", ")),
            ))
        }
    }
}

/// Samples `f(i, j, k)` over an `n³` lattice, x fastest.
fn lattice<T>(n: u32, f: impl Fn(u32, u32, u32) -> T) -> Vec<T> {
    let mut out = Vec::with_capacity((n * n * n) as usize);
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                out.push(f(i, j, k));
            }
        }
    }
    out
}

fn to_u8(x: f32) -> u8 {
    (x.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// Concentric shells (see module docs).
pub fn shells() -> Volume {
    let n = 64;
    let c = Vec3::splat((n - 1) as f32 * 0.5);
    let data = lattice(n, |i, j, k| {
        let r = (Vec3::new(i as f32, j as f32, k as f32) - c).length();
        if r < 30.0 {
            to_u8(0.5 - 0.5 * (2.0 * PI * r / 10.0).cos())
        } else {
            0
        }
    });
    Volume::new("shells", UVec3::splat(n), Vec3::ONE, VoxelData::U8(data))
        .expect("valid by construction")
}

/// The blobs (see module docs): peaks 1 and 0.6 of the full range, σ = 1.2 voxels.
pub fn blobs() -> Volume {
    let (a, b) = (Vec3::new(2.5, 3.5, 3.5), Vec3::new(5.5, 4.0, 3.0));
    let g = |p: Vec3, c: Vec3| (-(p - c).length_squared() / (2.0 * 1.2f32 * 1.2)).exp();
    let data = lattice(8, |i, j, k| {
        let p = Vec3::new(i as f32, j as f32, k as f32);
        to_u8(g(p, a) + 0.6 * g(p, b))
    });
    Volume::new("blobs", UVec3::splat(8), Vec3::ONE, VoxelData::U8(data))
        .expect("valid by construction")
}

/// A ball of density 1 − r/12 (float) on a 32³ lattice whose octant beyond the centre on
/// every axis holds no data (NaN), with ±∞ at two voxels inside the ball: what a scan masked
/// to a region stores outside it. Every method passes over the missing octant.
pub fn masked() -> Volume {
    let n = 32;
    let c = Vec3::splat((n - 1) as f32 * 0.5);
    let mut data = lattice(n, |i, j, k| {
        let p = Vec3::new(i as f32, j as f32, k as f32);
        if p.cmpgt(c).all() {
            f32::NAN
        } else {
            (1.0 - (p - c).length() / 12.0).max(0.0)
        }
    });
    let at = |i: u32, j: u32, k: u32| (i + n * (j + n * k)) as usize;
    data[at(10, 16, 12)] = f32::INFINITY;
    data[at(12, 10, 16)] = f32::NEG_INFINITY;
    Volume::new("masked", UVec3::splat(n), Vec3::ONE, VoxelData::F32(data))
        .expect("valid by construction")
}

/// The head phantom's levels (u8, CT-like order: CSF < scalp < brain < bone).
pub const HEAD_CSF: f32 = 60.0;
pub const HEAD_SKIN: f32 = 80.0;
pub const HEAD_BRAIN: f32 = 110.0;
pub const HEAD_BONE: f32 = 220.0;
/// The head phantom's ellipsoids, semi-axes as fractions of the half-size: the scalp's outside,
/// the skull's outside and inside (the brain's surface); the ventricles' centres and semi-axes.
pub const HEAD_SCALP: Vec3 = Vec3::new(0.80, 0.92, 0.85);
pub const HEAD_SKULL: Vec3 = Vec3::new(0.72, 0.84, 0.77);
pub const HEAD_BRAIN_AXES: Vec3 = Vec3::new(0.64, 0.76, 0.69);
const HEAD_VENTRICLE: Vec3 = Vec3::new(0.07, 0.2, 0.12);
const HEAD_VENTRICLE_X: f32 = 0.12;
/// The width of the head phantom's soft edges, in voxels (a sharper edge shows rings).
const HEAD_EDGE: f32 = 3.0;
/// The head phantom's size in voxels.
const HEAD_N: u32 = 64;

/// The head phantom's value at `p` (voxel coordinates of the 64³ lattice).
pub fn head_at(p: Vec3) -> f32 {
    let half = (HEAD_N - 1) as f32 * 0.5;
    let u = (p - Vec3::splat(half)) / half;
    // Inside-ness of an ellipsoid, 1 inside and 0 outside, over HEAD_EDGE voxels.
    let inside = |centre: Vec3, axes: Vec3| {
        let r = ((u - centre) / axes).length();
        let voxels = (r - 1.0) * axes.min_element() * half;
        (0.5 - voxels / HEAD_EDGE).clamp(0.0, 1.0)
    };
    let ventricles = inside(Vec3::new(-HEAD_VENTRICLE_X, 0.05, 0.0), HEAD_VENTRICLE)
        + inside(Vec3::new(HEAD_VENTRICLE_X, 0.05, 0.0), HEAD_VENTRICLE);
    HEAD_SKIN * inside(Vec3::ZERO, HEAD_SCALP)
        + (HEAD_BONE - HEAD_SKIN) * inside(Vec3::ZERO, HEAD_SKULL)
        + (HEAD_BRAIN - HEAD_BONE) * inside(Vec3::ZERO, HEAD_BRAIN_AXES)
        + (HEAD_CSF - HEAD_BRAIN) * ventricles
}

/// The head phantom (see module docs).
pub fn head() -> Volume {
    // Floats, not bytes: rounding the soft edges to whole numbers terraced them, and the
    // terraces showed as rings on the skin.
    let data = lattice(HEAD_N, |i, j, k| {
        head_at(Vec3::new(i as f32, j as f32, k as f32))
    });
    Volume::new(
        "head",
        UVec3::splat(HEAD_N),
        Vec3::ONE,
        VoxelData::F32(data),
    )
    .expect("valid by construction")
}

/// The Marschner–Lobb signal at a point of [−1, 1]³, in [0, 1].
pub fn marschner_lobb_at(p: Vec3) -> f32 {
    const F_M: f32 = 6.0;
    const ALPHA: f32 = 0.25;
    let r = (p.x * p.x + p.y * p.y).sqrt();
    let rho_r = (2.0 * PI * F_M * (PI * r / 2.0).cos()).cos();
    (1.0 - (PI * p.z / 2.0).sin() + ALPHA * (1.0 + rho_r)) / (2.0 * (1.0 + ALPHA))
}

/// The Marschner–Lobb volume (see module docs).
pub fn marschner_lobb() -> Volume {
    let n = 41;
    let h = 2.0 / (n - 1) as f32;
    let data = lattice(n, |i, j, k| {
        marschner_lobb_at(Vec3::new(i as f32, j as f32, k as f32) * h - 1.0)
    });
    Volume::new(
        "marschner-lobb",
        UVec3::splat(n),
        Vec3::splat(h),
        VoxelData::F32(data),
    )
    .expect("valid by construction")
}

/// The 60 vertices of a truncated icosahedron with edge length 2 (circumradius √(9φ + 10)).
pub fn truncated_icosahedron() -> Vec<Vec3> {
    let phi = (1.0 + 5f32.sqrt()) / 2.0;
    let bases = [
        Vec3::new(0.0, 1.0, 3.0 * phi),
        Vec3::new(1.0, 2.0 + phi, 2.0 * phi),
        Vec3::new(phi, 2.0, 2.0 * phi + 1.0),
    ];
    let mut out = Vec::with_capacity(60);
    for b in bases {
        for signs in 0..8u32 {
            let s = Vec3::new(
                if signs & 1 == 0 { 1.0 } else { -1.0 },
                if signs & 2 == 0 { 1.0 } else { -1.0 },
                if signs & 4 == 0 { 1.0 } else { -1.0 },
            );
            let v = b * s;
            // Skip duplicate sign patterns on zero components.
            if b.x == 0.0 && s.x < 0.0 {
                continue;
            }
            // The three cyclic (even) permutations.
            for p in [v, Vec3::new(v.y, v.z, v.x), Vec3::new(v.z, v.x, v.y)] {
                out.push(p);
            }
        }
    }
    out
}

/// The bucky-like cage (see module docs).
/// The worked example of the ray-casting lecture (seed 003): a unit voxel whose corners hold
/// f1 … f8 = 5.0, 5.1, 5.2, 4.6, 4.9, 5.1, 5.3, 4.7, numbered as the lecture's trilinear
/// formula numbers them (f1 at the origin, f2 along x, f3 along x and y, f4 along y, then the
/// same four one unit along z).
pub fn worked_voxel() -> Volume {
    // x fastest: (0,0,0) (1,0,0) (0,1,0) (1,1,0) (0,0,1) (1,0,1) (0,1,1) (1,1,1).
    let data = vec![5.0, 5.1, 4.6, 5.2, 4.9, 5.1, 4.7, 5.3];
    Volume::new("voxel", UVec3::splat(2), Vec3::ONE, VoxelData::F32(data))
        .expect("valid by construction")
}

pub fn bucky() -> Volume {
    let n = 32;
    let c = Vec3::splat((n - 1) as f32 * 0.5);
    let atoms = truncated_icosahedron();
    let radius = atoms[0].length();
    let scale = 12.0 / radius;
    let atoms: Vec<Vec3> = atoms.into_iter().map(|a| c + a * scale).collect();
    let sigma2 = 2.0 * 1.1f32 * 1.1;
    let data = lattice(n, |i, j, k| {
        let p = Vec3::new(i as f32, j as f32, k as f32);
        let d: f32 = atoms
            .iter()
            .map(|a| (-(p - *a).length_squared() / sigma2).exp())
            .sum();
        to_u8(d)
    });
    Volume::new("bucky", UVec3::splat(n), Vec3::ONE, VoxelData::U8(data))
        .expect("valid by construction")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At P2 = (0.5, 0.5, 0.5) every weight is 1/8: the mean of the corners. (The lecture's
    /// formula at P1, P2, P3 is checked on this volume in tests/closed_forms.rs.)
    #[test]
    fn the_worked_voxels_centre_is_the_mean_of_its_corners() {
        let mid = crate::sample::detail_at(
            &worked_voxel(),
            Vec3::splat(0.5),
            crate::sample::Interpolation::Trilinear,
        );
        assert!((mid.value - 4.9875).abs() < 1e-5);
        assert!(mid.weights.iter().all(|w| (*w - 0.125).abs() < 1e-6));
    }

    #[test]
    fn every_builtin_loads() {
        for (name, _) in DATASETS {
            let l = load_builtin(name).unwrap();
            assert!(l.volume.voxel_count() > 0, "{name}");
            let (lo, hi) = l.volume.value_range();
            assert!(hi > lo, "{name} is not constant");
        }
        assert!(
            load_builtin("nope")
                .unwrap_err()
                .to_string()
                .contains("bunny")
        );
    }

    #[test]
    fn truncated_icosahedron_has_60_equidistant_vertices_with_edge_2() {
        let v = truncated_icosahedron();
        assert_eq!(v.len(), 60);
        let r = v[0].length();
        assert!(v.iter().all(|p| (p.length() - r).abs() < 1e-4));
        let phi = (1.0 + 5f32.sqrt()) / 2.0;
        assert!((r - (9.0 * phi + 10.0).sqrt()).abs() < 1e-4);
        // Every vertex has exactly three neighbours at distance 2.
        for a in &v {
            let near = v
                .iter()
                .filter(|b| ((**b - *a).length() - 2.0).abs() < 1e-3)
                .count();
            assert_eq!(near, 3);
        }
    }

    #[test]
    fn marschner_lobb_stays_in_range() {
        let v = marschner_lobb();
        let (lo, hi) = v.value_range();
        assert!(lo >= 0.0 && hi <= 1.0, "{lo} {hi}");
    }

    #[test]
    fn a_real_dataset_opens_from_handed_bytes_and_says_when_none_came() {
        let brain = file_bytes("mri_brainsmall.nrrd").expect("compiled in for the tests");
        let handed = load_file("bunny", |file| {
            (file == "bunny_sdf.nrrd").then(|| brain.clone())
        })
        .unwrap();
        assert_eq!(handed.volume.dims(), UVec3::new(128, 128, 84));
        // Compiled in here: nothing to fetch; not a real dataset's: nothing either.
        assert_eq!(missing_file("builtin:brainsmall"), None);
        assert_eq!(missing_file("builtin:shells"), None);
        assert_eq!(missing_file("brain.nrrd"), None);
        let missing = load_file("brainsmall", |_| None).unwrap_err().to_string();
        assert!(
            missing.contains("mri_brainsmall.nrrd did not come with this page")
                && missing.contains("volumes/"),
            "{missing}"
        );
    }
}
