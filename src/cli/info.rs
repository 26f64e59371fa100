//! `voxcast info`: what a volume file holds.

use super::CliError;
use super::args::VolumeArgs;
use clap::Args;
use voxcast_core::histogram::{Histogram, HistogramScale, percentiles};
use voxcast_core::numbers::sig;
use voxcast_core::preset;

#[derive(Args, Debug)]
pub struct InfoArgs {
    /// The volume (file path or builtin:NAME).
    #[arg(value_name = "PATH")]
    pub path: String,
    #[command(flatten)]
    pub raw: RawOnly,
}

/// The raw-file options of [`VolumeArgs`] without its --volume.
#[derive(Args, Debug)]
pub struct RawOnly {
    /// Raw files: dimensions NXxNYxNZ (overrides the file name).
    #[arg(long, value_name = "NXxNYxNZ")]
    pub dims: Option<String>,
    /// Raw files: scalar type (uint8, int16, uint16, float32, …; overrides the file name).
    #[arg(long = "type", value_name = "TYPE")]
    pub scalar_type: Option<String>,
    /// Raw files: byte order.
    #[arg(long, value_parser = ["little", "big"])]
    pub endian: Option<String>,
    /// Raw files: spacing sx,sy,sz in world units.
    #[arg(long, value_name = "SX,SY,SZ", value_parser = super::args::parse_vec3)]
    pub spacing: Option<voxcast_core::glam::Vec3>,
    /// Raw files: bytes to skip before the data.
    #[arg(long, default_value_t = 0)]
    pub header_bytes: u64,
}

pub fn run(a: &InfoArgs) -> Result<(), CliError> {
    let args = VolumeArgs {
        volume: a.path.clone(),
        dims: a.raw.dims.clone(),
        scalar_type: a.raw.scalar_type.clone(),
        endian: a.raw.endian.clone(),
        spacing: a.raw.spacing,
        header_bytes: a.raw.header_bytes,
    };
    let loaded = args.load()?;
    let v = &loaded.volume;
    let d = v.dims();
    let s = v.spacing();
    let (lo, hi) = v.bounds();
    let (min, max) = v.value_range();
    let (slope, intercept) = v.rescale();
    println!("name:       {}", v.name());
    println!(
        "dims:       {} × {} × {} = {} voxels",
        d.x,
        d.y,
        d.z,
        v.voxel_count()
    );
    println!(
        "type:       {} ({:.1} MiB in memory)",
        v.scalar_type().name(),
        (v.voxel_count() * v.scalar_type().bytes()) as f64 / (1 << 20) as f64
    );
    println!("spacing:    {} × {} × {}", s.x, s.y, s.z);
    println!(
        "box:        [{}, {}] × [{}, {}] × [{}, {}] (world units)",
        lo.x, hi.x, lo.y, hi.y, lo.z, hi.z
    );
    println!("range:      {min} .. {max} (data units)");
    if v.no_data_count() > 0 {
        println!(
            "no data:    {} voxels ({}) are NaN or ±∞: every method passes over them",
            v.no_data_count(),
            voxcast_core::numbers::percent(v.no_data_count() as f32 / v.voxel_count() as f32)
        );
    }
    if (slope, intercept) != (1.0, 0.0) {
        println!("rescale:    data = raw × {slope} + {intercept}");
    }
    let h = Histogram::of(v, 64);
    let p = percentiles(v, &[0.01, 0.25, 0.5, 0.75, 0.99]);
    println!(
        "percentiles: 1% {}, 25% {}, 50% {}, 75% {}, 99% {} (exact, data units)",
        sig(p[0]),
        sig(p[1]),
        sig(p[2]),
        sig(p[3]),
        sig(p[4])
    );
    const BARS: [char; 8] = ['▁', '▂', '▃', '▄', '▅', '▆', '▇', '█'];
    // A height in [0, 1] as one of eight bars (a blank for none).
    let bar = |x: f32| {
        if x == 0.0 {
            ' '
        } else {
            BARS[((x * 7.0).round() as usize).min(7)]
        }
    };
    let bars: String = h
        .heights(HistogramScale::Log)
        .into_iter()
        .map(bar)
        .collect();
    println!("histogram (64 bins, log): |{bars}|");
    // Value across, gradient magnitude up: where --classify rects:… draws its rectangles.
    let joint = voxcast_core::histogram2d::JointHistogram::of(v, [64, 10], 1 << 20);
    let shades = joint.shades();
    println!(
        "value × gradient magnitude (log; gradient 0 … {} data units per world unit, up):",
        sig(joint.gradient[1])
    );
    for row in (0..joint.bins[1]).rev() {
        let line: String = (0..joint.bins[0])
            .map(|col| bar(shades[row * joint.bins[0] + col]))
            .collect();
        println!("  |{line}|");
    }
    if let Some(p) = preset::for_loaded(v) {
        println!("preset:     {} — {}", p.name, p.description);
    }
    for note in &loaded.notes {
        println!("note:       {note}");
    }
    Ok(())
}
