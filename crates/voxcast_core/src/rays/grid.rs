//! A ray density laid out densely over the box of its stored chunks, and written as NRRD files
//! that Slicer, ParaView and Voxcast itself open: the counts as a scalar volume, the mean unit
//! directions as a 3-vector per cell. Cell `(i, j, k)` of the whole grid spans
//! `[iS, (i+1)S)` on each axis, so the file's `space origin` is the centre of its first cell and
//! its `space directions` are `S` along each axis.
//!
//! Counts are written as 32-bit floats (what Voxcast's volume readers take), exact up to
//! 2²⁴ = 16 777 216 rays in one cell; [`DenseDensity::inexact_counts`] says when a count is
//! larger.

use super::density::Density;
use glam::{IVec3, UVec3, Vec3};

/// How a density volume's name begins (the sandbox picks Sum and inferno for it).
pub const NAME_PREFIX: &str = "ray density";

/// The most cells a dense grid may hold (a sparse density with chunks far apart can span a
/// box far larger than what it stores).
pub const MAX_DENSE_CELLS: u64 = 1 << 28;

/// A density over a dense box of cells, x fastest.
#[derive(Clone, Debug, PartialEq)]
pub struct DenseDensity {
    /// The whole grid's coordinates of the box's first cell.
    pub first_cell: IVec3,
    pub dims: UVec3,
    /// Cell edge, world units.
    pub cell: f32,
    pub counts: Vec<u32>,
    /// Mean unit direction per cell (zero where no ray passed).
    pub directions: Vec<Vec3>,
}

impl DenseDensity {
    /// The dense box of `density`'s stored chunks; `Ok(None)` when no ray was counted, an
    /// error when the box holds more than [`MAX_DENSE_CELLS`].
    pub fn new(density: &Density) -> Result<Option<Self>, String> {
        let Some((lo, hi)) = density.chunk_bounds() else {
            return Ok(None);
        };
        let n = density.params.chunk as i64;
        let chunks = (hi - lo + IVec3::ONE).as_i64vec3();
        let cells = chunks * n;
        let total = cells.x as u64 * cells.y as u64 * cells.z as u64;
        if total > MAX_DENSE_CELLS {
            return Err(format!(
                "the stored chunks span {} × {} × {} cells, more than the {} a dense file may \
                 hold: choose larger cells or filter the rays",
                cells.x, cells.y, cells.z, MAX_DENSE_CELLS
            ));
        }
        let dims = cells.as_uvec3();
        let first_cell = lo * density.params.chunk as i32;
        let mut counts = vec![0u32; total as usize];
        let mut directions = vec![Vec3::ZERO; total as usize];
        let index = |c: IVec3| {
            let r = (c - first_cell).as_uvec3();
            (r.x + dims.x * (r.y + dims.y * r.z)) as usize
        };
        for key in density.chunks.keys() {
            let base = IVec3::from_array(*key) * density.params.chunk as i32;
            for z in 0..n as i32 {
                for y in 0..n as i32 {
                    for x in 0..n as i32 {
                        let c = base + IVec3::new(x, y, z);
                        let i = index(c);
                        counts[i] = density.count(c);
                        directions[i] = density.mean_direction(c);
                    }
                }
            }
        }
        Ok(Some(Self {
            first_cell,
            dims,
            cell: density.params.cell,
            counts,
            directions,
        }))
    }

    /// The centre of the box's first cell, world units.
    pub fn origin(&self) -> Vec3 {
        (self.first_cell.as_vec3() + 0.5) * self.cell
    }

    /// The counts as a float volume every path of Voxcast renders: voxel `(i, j, k)` is cell
    /// `first_cell + (i, j, k)` and sits at its centre, `origin() + (i, j, k)·S` in the world,
    /// so the volume's own coordinates are the world's shifted by [`DenseDensity::origin`].
    /// Between cell centres it is interpolated like any volume; its box reaches from the first
    /// cell's centre to the last's (half a cell short of the chunks' faces).
    pub fn to_volume(&self) -> Result<crate::volume::Volume, crate::error::VolumeError> {
        crate::volume::Volume::new(
            NAME_PREFIX,
            self.dims,
            Vec3::splat(self.cell),
            crate::volume::VoxelData::F32(self.counts.iter().map(|&c| c as f32).collect()),
        )
    }

    /// Whether some count is too large for a float to hold exactly.
    pub fn inexact_counts(&self) -> bool {
        self.counts.iter().any(|&c| c > 1 << 24)
    }

    /// The counts as an NRRD file (header and raw little-endian floats).
    pub fn counts_nrrd(&self) -> Vec<u8> {
        let d = self.dims;
        let mut out = self
            .header(
                "rays per cell",
                3,
                &format!("{} {} {}", d.x, d.y, d.z),
                "",
                "domain domain domain",
            )
            .into_bytes();
        for &c in &self.counts {
            out.extend_from_slice(&(c as f32).to_le_bytes());
        }
        out
    }

    /// The mean directions as an NRRD file: a 3-vector axis first, then the cells.
    pub fn directions_nrrd(&self) -> Vec<u8> {
        let d = self.dims;
        let mut out = self
            .header(
                "mean unit direction of the rays per cell (zero where none passed)",
                4,
                &format!("3 {} {} {}", d.x, d.y, d.z),
                "none ",
                "vector domain domain domain",
            )
            .into_bytes();
        for v in &self.directions {
            for c in v.to_array() {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
        out
    }

    fn header(&self, what: &str, dimension: u32, sizes: &str, lead: &str, kinds: &str) -> String {
        let s = self.cell;
        let o = self.origin();
        format!(
            "NRRD0004\n# {what}, written by Voxcast\ntype: float\ndimension: {dimension}\n\
             space: 3D-right-handed\nsizes: {sizes}\n\
             space directions: {lead}({s},0,0) (0,{s},0) (0,0,{s})\nkinds: {kinds}\n\
             space origin: ({},{},{})\nendian: little\nencoding: raw\n\n",
            o.x, o.y, o.z
        )
    }
}

#[cfg(test)]
mod tests {
    use super::super::density::{DensityParams, compute};
    use super::super::set::{RayRecord, RaySet};
    use super::*;
    use std::sync::atomic::AtomicBool;

    fn density() -> Density {
        // Two rays along +x at y = z = 0.5 and 2.5 (cells of edge 1), from x = −3 to x = 5.
        let rays = [0.5f32, 2.5]
            .iter()
            .enumerate()
            .map(|(id, &y)| RayRecord {
                id: id as u32,
                origin: Vec3::new(-3.0, y, 0.5),
                direction: Vec3::X,
                t_min: 0.0,
                t_max: 8.0,
                t_hit: -1.0,
            })
            .collect();
        let set = RaySet { trace_id: 0, rays };
        let p = DensityParams {
            cell: 1.0,
            chunk: 4,
            ..Default::default()
        };
        compute(&set, &p, &|_, _| {}, &AtomicBool::new(false)).unwrap()
    }

    #[test]
    fn the_dense_box_holds_every_count_where_the_chunks_put_it() {
        let d = density();
        let dense = DenseDensity::new(&d).unwrap().unwrap();
        // Cells x = −3 … 4 lie in chunks x = −1, 0 and 1: the box spans cells −4 … 7.
        assert_eq!(dense.first_cell, IVec3::new(-4, 0, 0));
        assert_eq!(dense.dims, UVec3::new(12, 4, 4));
        assert_eq!(dense.origin(), Vec3::new(-3.5, 0.5, 0.5));
        let total: u64 = dense.counts.iter().map(|&c| u64::from(c)).sum();
        assert_eq!(total, d.report.visits);
        for x in -4..8 {
            for y in 0..4 {
                let c = IVec3::new(x, y, 0);
                let i = (x + 4) as usize + 12 * y as usize;
                assert_eq!(dense.counts[i], d.count(c), "{c}");
                let want = u32::from((-3..=4).contains(&x) && (y == 0 || y == 2));
                assert_eq!(dense.counts[i], want, "{c}");
                if want == 1 {
                    assert_eq!(dense.directions[i], Vec3::X);
                }
            }
        }
        assert!(!dense.inexact_counts());
    }

    #[test]
    fn the_counts_file_opens_as_a_volume_with_the_counts() {
        let dense = DenseDensity::new(&density()).unwrap().unwrap();
        let bytes = dense.counts_nrrd();
        let text = String::from_utf8_lossy(&bytes[..400.min(bytes.len())]).to_string();
        assert!(text.contains("space origin: (-3.5,0.5,0.5)"), "{text}");
        assert!(text.contains("space directions: (1,0,0) (0,1,0) (0,0,1)"));
        let loaded = crate::io::nrrd::load_bytes("counts", &bytes).unwrap();
        let v = loaded.volume;
        assert_eq!(v.dims(), dense.dims);
        assert_eq!(v.spacing(), Vec3::ONE);
        assert_eq!(v.value_range(), (0.0, 1.0));
        let dirs = dense.directions_nrrd();
        let header_end = dirs.windows(2).position(|w| w == b"\n\n").unwrap() + 2;
        assert_eq!(dirs.len() - header_end, 3 * 4 * dense.counts.len());
        let head = String::from_utf8_lossy(&dirs[..header_end]);
        assert!(head.contains("sizes: 3 12 4 4") && head.contains("kinds: vector domain"));
        // The volume in memory is the file's.
        let direct = dense.to_volume().unwrap();
        assert_eq!(direct.dims(), v.dims());
        assert_eq!(direct.spacing(), v.spacing());
        for x in 0..12 {
            assert_eq!(direct.value_at(x, 2, 0), v.value_at(x, 2, 0));
            assert_eq!(
                direct.value_at(x, 2, 0),
                Some(dense.counts[x as usize + 24] as f32)
            );
        }
    }

    #[test]
    fn an_empty_density_has_no_box_and_a_huge_one_is_refused() {
        let mut d = density();
        d.chunks.clear();
        assert_eq!(DenseDensity::new(&d).unwrap(), None);
        let mut far = density();
        let chunk = far.chunks.values().next().unwrap().clone();
        far.chunks.insert([100_000, 100_000, 0], chunk);
        match DenseDensity::new(&far) {
            Err(e) => assert!(e.contains("choose larger cells"), "{e}"),
            Ok(_) => panic!("a box of 400 008² × 4 cells was accepted"),
        }
    }
}
