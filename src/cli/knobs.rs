//! `voxcast bench --knobs`: the speed/accuracy trade of every knob (`voxcast_core::knob`) for
//! one view, as markdown tables — the numbers the sandbox's "Speed against accuracy" shows.

use super::CliError;
use super::progress::Progress;
use std::fmt::Write as _;
use std::sync::atomic::AtomicBool;
use voxcast_core::camera::Camera;
use voxcast_core::knob::Knob;
use voxcast_core::settings::RenderSettings;
use voxcast_core::trade::{STEPS, View, trade};

/// Every knob's table for `view` with `settings`, each setting timed as the core's trade
/// times (a median of alternating runs after an untimed one) on the global pool.
pub fn tables(
    view: &View<'_>,
    settings: &RenderSettings,
    camera_words: &str,
) -> Result<String, CliError> {
    let mut out = String::new();
    let cpu = cpu_model();
    let _ = writeln!(
        out,
        "{}×{} pixels, {camera_words}, {cpu}, {} threads; each time the median of {} renders \
         after an untimed one, the settings in alternating order, with the fastest and slowest \
         beside it.\n",
        view.size.0,
        view.size.1,
        rayon::current_num_threads(),
        voxcast_core::trade::TIMED_RUNS
    );
    let cancel = AtomicBool::new(false);
    for knob in Knob::ALL {
        let progress = Progress::new(knob.name());
        let t = trade(
            view,
            settings,
            knob,
            &STEPS,
            &|d, n| progress.update(d, n),
            &cancel,
        )
        .map_err(|e| CliError::failed(e.to_string()))?;
        progress.finish();
        out.push_str(&t.markdown());
        if knob.is_preview() {
            let _ = writeln!(
                out,
                "Timed here as the core's renders of the image above, stretched; the window's \
                 Measure, and `voxcast --measure-knob {}`, time them as the preview's own images \
                 at the window's size.\n",
                knob.name()
            );
        }
    }
    Ok(out)
}

/// The CPU's model name (`lscpu`'s "Model name", from /proc/cpuinfo), or "an unnamed CPU",
/// with its family and model and whether it has AVX-512: a virtual machine often names only
/// the vendor's line ("AMD EPYC" for a Zen 1 and a Zen 4 alike), and the two run the lanes
/// at different speeds.
pub fn cpu_model() -> String {
    cpu_words(&std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default())
}

/// [`cpu_model`] from the text of /proc/cpuinfo.
fn cpu_words(info: &str) -> String {
    let field = |key| cpuinfo_field(info, key);
    let Some(name) = field("model name") else {
        return "an unnamed CPU".into();
    };
    let (Some(family), Some(model)) = (field("cpu family"), field("model")) else {
        return name.into();
    };
    let wide = field("flags").is_some_and(|f| f.split_whitespace().any(|x| x == "avx512f"));
    let avx512 = if wide { "AVX-512" } else { "no AVX-512" };
    format!("{name} (family {family}, model {model}, {avx512})")
}

/// The value of the first line of /proc/cpuinfo's text whose key is `key` (the first core's),
/// if it has one.
fn cpuinfo_field<'a>(info: &'a str, key: &str) -> Option<&'a str> {
    info.lines()
        .filter_map(|l| l.split_once(':'))
        .find(|(k, _)| k.trim() == key)
        .map(|(_, v)| v.trim())
        .filter(|v| !v.is_empty())
}

/// The clock /proc/cpuinfo reports for the first core, GHz (a virtual machine shows its
/// nominal clock; no boost), if it reports one.
pub fn cpu_ghz() -> Option<f64> {
    let info = std::fs::read_to_string("/proc/cpuinfo").ok()?;
    let mhz: f64 = cpuinfo_field(&info, "cpu MHz")?.parse().ok()?;
    (mhz > 0.0).then_some(mhz / 1000.0)
}

/// The camera in words for the tables' heading.
pub fn camera_words(c: &Camera) -> String {
    format!(
        "camera at ({:.3}, {:.3}, {:.3}) looking at ({:.3}, {:.3}, {:.3})",
        c.eye.x, c.eye.y, c.eye.z, c.target.x, c.target.y, c.target.z
    )
}

#[cfg(test)]
mod tests {
    use super::cpu_words;

    #[test]
    fn a_cpu_is_named_with_its_family_model_and_widest_vectors() {
        let zen1 = "processor\t: 0\nvendor_id\t: AuthenticAMD\ncpu family\t: 23\nmodel\t\t: 1\n\
                    model name\t: AMD EPYC\nflags\t\t: fpu sse avx2\n";
        assert_eq!(cpu_words(zen1), "AMD EPYC (family 23, model 1, no AVX-512)");
        let zen4 = zen1.replace(": 23", ": 25").replace("avx2", "avx2 avx512f");
        assert_eq!(cpu_words(&zen4), "AMD EPYC (family 25, model 1, AVX-512)");
        assert_eq!(cpu_words("model name : Some CPU\n"), "Some CPU");
        assert_eq!(cpu_words(""), "an unnamed CPU");
    }
}
