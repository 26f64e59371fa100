//! A ray density as a volume source, so every path that opens a volume — the sandbox's loader,
//! `voxcast render`, `trace`, `info` — opens one: `density:SOURCE[@key=value,…]`, where
//! `SOURCE` is a ray data source (`builtin:cornell` or a `.rayvis` file) and the keys are
//! `cell` (edge S, world units), `chunk` (N), `trace` (an id; every trace when left out),
//! `filter` (all, hit, miss) and `tolerance` (RayVis's miss-detection tolerance), e.g.
//! `density:builtin:cornell@cell=20,trace=1,filter=hit`. Without `cell` the grid has
//! [`DEFAULT_CELLS`] cells along the longest side of the scene (or, without one, of the
//! rays' origins).
//!
//! The volume is the counts of [`super::grid::DenseDensity`], named [`NAME_PREFIX`]`…`: its
//! voxel `(0, 0, 0)` is the first cell's centre, so its coordinates are the world's shifted by
//! that point (the loader's note says where it is).

use super::data::RayData;
use super::density::{Density, DensityParams, DensitySlices, MAX_BYTES, density_in};
use super::effects::TraceSlices;
use super::grid::{DenseDensity, NAME_PREFIX};
use super::set::{Filter, RaySet};
use crate::slices::{Deadline, Step};
use crate::volume::Volume;
use glam::Vec3;
use std::sync::atomic::AtomicBool;

/// What starts a density source.
pub const PREFIX: &str = "density:";

/// Cells along the longest side when no `cell` is given (the 128³ grid).
pub const DEFAULT_CELLS: f32 = 128.0;

/// A parsed `density:` source.
#[derive(Clone, Debug, PartialEq)]
pub struct DensitySpec {
    /// The ray data source.
    pub source: String,
    pub trace: Option<u32>,
    /// The grid and filter; `cell` is 0 when it is to be chosen from the scene.
    pub params: DensityParams,
}

impl DensitySpec {
    /// The source text that parses back to this spec (`cell` left out when it is to be
    /// chosen from the scene).
    pub fn to_text(&self) -> String {
        let p = &self.params;
        let mut keys = Vec::new();
        if p.cell != 0.0 {
            keys.push(format!("cell={}", p.cell));
        }
        if let Some(id) = self.trace {
            keys.push(format!("trace={id}"));
        }
        if p.filter != Filter::All {
            keys.push(format!("filter={}", p.filter.name()));
        }
        if p.chunk != DensityParams::default().chunk {
            keys.push(format!("chunk={}", p.chunk));
        }
        if p.tolerance != 0.0 {
            keys.push(format!("tolerance={}", p.tolerance));
        }
        match keys.is_empty() {
            true => format!("{PREFIX}{}", self.source),
            false => format!("{PREFIX}{}@{}", self.source, keys.join(",")),
        }
    }
}

/// `Some` when `spec` is a `density:` source: the parsed spec, or why it is not one.
pub fn parse(spec: &str) -> Option<Result<DensitySpec, String>> {
    let rest = spec.strip_prefix(PREFIX)?;
    Some(parse_rest(rest))
}

fn parse_rest(rest: &str) -> Result<DensitySpec, String> {
    let (source, keys) = match rest.rsplit_once('@') {
        Some((s, k)) => (s, k),
        None => (rest, ""),
    };
    if source.is_empty() {
        return Err(format!(
            "{PREFIX} needs a ray data source: {PREFIX}builtin:cornell or {PREFIX}FILE.rayvis"
        ));
    }
    let mut out = DensitySpec {
        source: source.into(),
        trace: None,
        params: DensityParams {
            cell: 0.0,
            ..DensityParams::default()
        },
    };
    for pair in keys.split(',').filter(|p| !p.trim().is_empty()) {
        let (k, v) = pair
            .split_once('=')
            .ok_or_else(|| format!("'{pair}': expected key=value"))?;
        let (k, v) = (k.trim(), v.trim());
        let number = || {
            v.parse::<f32>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| format!("{k}={v}: not a number"))
        };
        match k {
            "cell" => out.params.cell = number()?,
            "chunk" => {
                out.params.chunk = v
                    .parse()
                    .map_err(|_| format!("chunk={v}: not a whole number"))?
            }
            "trace" => out.trace = Some(v.parse().map_err(|_| format!("trace={v}: not an id"))?),
            "filter" => {
                out.params.filter =
                    Filter::parse(v).ok_or_else(|| format!("filter={v}: all, hit or miss"))?
            }
            "tolerance" => out.params.tolerance = number()?,
            other => {
                return Err(format!(
                    "'{other}': the keys are cell, chunk, trace, filter and tolerance"
                ));
            }
        }
    }
    if out.params.cell != 0.0 {
        out.params.check()?;
    }
    Ok(out)
}

/// A computed ray density and everything it came from: the data set (its scene and every
/// trace), the rays counted, the sparse density (counts and directions) and its volume.
pub struct RayDensity {
    pub data: RayData,
    /// The rays of the chosen trace (or of all), before the filter.
    pub set: RaySet,
    pub density: super::density::Density,
    /// Where the volume's voxel `(0, 0, 0)` lies in the scene.
    pub origin: Vec3,
    pub volume: Volume,
    /// What was done, in words (rays, grid, where the volume sits).
    pub words: String,
}

/// The counts of `spec`'s rays as a volume, with what was done in words (rays, grid, where
/// the volume sits). Progress and cancel as [`compute_spec`].
pub fn load(
    spec: &DensitySpec,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<(Volume, String), String> {
    compute_spec(spec, progress, cancel).map(|d| (d.volume, d.words))
}

/// [`load`], keeping everything the density came from.
pub fn compute_spec(
    spec: &DensitySpec,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<RayDensity, String> {
    let mut slices = SpecSlices::default();
    compute_spec_in(spec, &mut slices, progress, cancel, Deadline::NONE).map(Step::whole)
}

/// A density's work from its spec, kept between slices ([`crate::slices`]): the rays traced
/// (a builtin's), then the grid's counts.
#[derive(Default)]
pub struct SpecSlices {
    trace: TraceSlices,
    rays: Option<(RayData, RaySet, DensityParams, DensitySlices)>,
}

/// [`compute_spec`] in slices up to `deadline`: the builtin's tracing and the density a block
/// at a time (a file's rays are read whole, and the volume is made in one piece at the end).
pub fn compute_spec_in(
    spec: &DensitySpec,
    slices: &mut SpecSlices,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
    deadline: Deadline,
) -> Result<Step<RayDensity>, String> {
    if slices.rays.is_none() {
        let step = super::source::load_in(&spec.source, &mut slices.trace, deadline)
            .map_err(|e| e.to_string())?;
        let Step::Done(data) = step else {
            return Ok(Step::Paused);
        };
        let set = select(&data, spec)?;
        let params = grid_for(&data, &set, spec.params)?;
        let density = DensitySlices::within(MAX_BYTES, &params);
        slices.rays = Some((data, set, params, density));
        if deadline.passed() {
            return Ok(Step::Paused);
        }
    }
    let (_, set, params, density) = slices.rays.as_mut().expect("traced");
    let step = density_in(set, params, density, progress, cancel, deadline)
        .map_err(|_| "cancelled".to_string())?;
    let Step::Done(density) = step else {
        return Ok(Step::Paused);
    };
    let (data, set, params, _) = slices.rays.take().expect("traced");
    let what = match spec.trace {
        Some(id) => format!("{} (trace {id})", spec.source),
        None => spec.source.clone(),
    };
    finish_set(data, set, &what, params, density).map(Step::Done)
}

/// `params` with the cell chosen from the scene where it is 0, checked.
pub fn grid_for(
    data: &RayData,
    set: &RaySet,
    mut params: DensityParams,
) -> Result<DensityParams, String> {
    if params.cell == 0.0 {
        params.cell = default_cell(data, set);
    }
    params.check()?;
    Ok(params)
}

/// The density of `set` (what [`density_in`] computed under `params`, `None`: more than
/// [`MAX_BYTES`]) as a volume, with what was done in words.
pub fn finish_set(
    data: RayData,
    set: RaySet,
    what: &str,
    params: DensityParams,
    density: Option<Density>,
) -> Result<RayDensity, String> {
    let density = density.ok_or_else(|| {
        format!(
            "these rays through cells of {} would take more than {} MiB: choose a larger cell",
            crate::numbers::sig(params.cell),
            MAX_BYTES >> 20
        )
    })?;
    let dense = DenseDensity::new(&density)?
        .ok_or_else(|| "no ray passed the filter: the density is empty".to_string())?;
    let volume = dense
        .to_volume()
        .map_err(|e| e.to_string())?
        .with_name(format!("{NAME_PREFIX} of {what}"));
    let o = dense.origin();
    let words = format!(
        "{} rays through cells of {} ({} × {} × {}); voxel (0, 0, 0) is the cell centred at \
         ({}, {}, {}) in the scene",
        density.report.rays,
        crate::numbers::sig(params.cell),
        dense.dims.x,
        dense.dims.y,
        dense.dims.z,
        crate::numbers::sig(o.x),
        crate::numbers::sig(o.y),
        crate::numbers::sig(o.z)
    );
    Ok(RayDensity {
        data,
        set,
        density,
        origin: o,
        volume,
        words,
    })
}

/// Whether `volume` is a ray density (by its name).
pub fn is_density(volume: &Volume) -> bool {
    volume.name().starts_with(NAME_PREFIX)
}

fn select(data: &RayData, spec: &DensitySpec) -> Result<RaySet, String> {
    match spec.trace {
        Some(id) => data.trace(id).cloned().ok_or_else(|| {
            let ids: Vec<String> = data.traces.iter().map(|t| t.trace_id.to_string()).collect();
            format!("trace={id}: {} has traces {}", spec.source, ids.join(", "))
        }),
        None => Ok(data.all_rays()),
    }
}

/// The longest side of the scene (else of the rays' origins) over [`DEFAULT_CELLS`].
pub fn default_cell(data: &RayData, set: &RaySet) -> f32 {
    let bounds = data.scene.bounds().or_else(|| {
        let mut points = set.rays.iter().map(|r| r.origin).filter(|p| p.is_finite());
        let first = points.next()?;
        Some(points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
    });
    let side = bounds.map_or(0.0, |(lo, hi): (Vec3, Vec3)| (hi - lo).max_element());
    if side.is_finite() && side > 0.0 {
        side / DEFAULT_CELLS
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rays::density::compute;

    /// From its spec in slices (the tracing and the counts a block at a time), the density
    /// is the one computed whole.
    #[test]
    fn a_spec_in_slices_gives_the_same_density() {
        let spec = parse("density:builtin:cornell@trace=2").unwrap().unwrap();
        let never = AtomicBool::new(false);
        let whole = compute_spec(&spec, &|_, _| {}, &never).unwrap();
        let mut slices = SpecSlices::default();
        let (sliced, calls) = crate::slices::until_done(crate::slices::Duration::ZERO, |d| {
            compute_spec_in(&spec, &mut slices, &|_, _| {}, &never, d)
        })
        .unwrap();
        assert!(calls > 10, "{calls} slices");
        assert!(sliced.density == whole.density);
        assert_eq!(sliced.volume.data(), whole.volume.data());
        assert_eq!(sliced.words, whole.words);
    }

    #[test]
    fn specs_parse_and_bad_ones_say_why() {
        assert!(parse("builtin:bunny").is_none());
        let s = parse("density:builtin:cornell@cell=20, trace=1,filter=hit")
            .unwrap()
            .unwrap();
        assert_eq!(s.source, "builtin:cornell");
        assert_eq!(s.trace, Some(1));
        assert_eq!(s.params.cell, 20.0);
        assert_eq!(s.params.filter, Filter::Hit);
        let plain = parse("density:/data/a@b.rayvis@chunk=8").unwrap().unwrap();
        assert_eq!(
            plain.source, "/data/a@b.rayvis",
            "the last @ starts the keys"
        );
        assert_eq!(plain.params.chunk, 8);
        assert_eq!(plain.params.cell, 0.0, "chosen from the scene");
        for (bad, words) in [
            ("density:", "needs a ray data source"),
            ("density:builtin:cornell@cell", "key=value"),
            ("density:builtin:cornell@cell=x", "not a number"),
            ("density:builtin:cornell@cell=-2", "cell size"),
            ("density:builtin:cornell@colour=red", "the keys are"),
            ("density:builtin:cornell@filter=some", "all, hit or miss"),
            ("density:builtin:cornell@chunk=0,cell=1", "chunk size 0"),
        ] {
            let e = parse(bad).unwrap().unwrap_err();
            assert!(e.contains(words), "{bad}: {e}");
        }
    }

    /// A spec written as text parses back to itself, keys left at their defaults left out.
    #[test]
    fn specs_round_trip_through_text() {
        for text in [
            "density:builtin:cornell",
            "density:builtin:cornell@cell=12.5,trace=3,filter=miss,chunk=8,tolerance=0.25",
            "density:/data/a@b.rayvis@filter=hit",
        ] {
            let spec = parse(text).unwrap().unwrap();
            assert_eq!(spec.to_text(), text);
            assert_eq!(parse(&spec.to_text()).unwrap().unwrap(), spec);
        }
    }

    #[test]
    fn the_cornell_shadow_rays_load_as_a_volume_of_their_counts() {
        let spec = parse("density:builtin:cornell@cell=40,trace=1")
            .unwrap()
            .unwrap();
        let (v, words) = load(&spec, &|_, _| {}, &AtomicBool::new(false)).unwrap();
        assert!(is_density(&v), "{}", v.name());
        assert_eq!(v.spacing(), Vec3::splat(40.0));
        assert!(words.contains("rays through cells of 40"), "{words}");
        let data = super::super::source::load("builtin:cornell").unwrap();
        let set = data.trace(1).unwrap();
        let p = DensityParams {
            cell: 40.0,
            ..DensityParams::default()
        };
        let d = compute(set, &p, &|_, _| {}, &AtomicBool::new(false)).unwrap();
        let total: f64 = match v.data() {
            crate::volume::VoxelData::F32(c) => c.iter().map(|&x| x as f64).sum(),
            _ => panic!("counts are floats"),
        };
        assert_eq!(
            total, d.report.visits as f64,
            "every visit is in the volume"
        );
        // Without a cell: 128 along the scene's longest side.
        let spec = parse("density:builtin:cornell@trace=1").unwrap().unwrap();
        let data_side = {
            let (lo, hi) = data.scene.bounds().unwrap();
            (hi - lo).max_element()
        };
        let (v, _) = load(&spec, &|_, _| {}, &AtomicBool::new(false)).unwrap();
        assert_eq!(v.spacing().x, data_side / DEFAULT_CELLS);
        let e = load(
            &parse("density:builtin:cornell@trace=7").unwrap().unwrap(),
            &|_, _| {},
            &AtomicBool::new(false),
        )
        .unwrap_err();
        assert!(e.contains("has traces 0, 1, 2, 3"), "{e}");
        let cancelled = AtomicBool::new(true);
        assert_eq!(
            load(&spec, &|_, _| {}, &cancelled).unwrap_err(),
            "cancelled"
        );
    }
}
