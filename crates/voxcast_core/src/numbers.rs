//! Numbers for people: values rounded to what they mean, as the sandbox shows them and
//! `voxcast trace` prints them (the exported JSON and CSV keep every digit); and
//! [`capitalised`], for the words around them.
//!
//! The rule, in one place: four significant digits, trailing zeros dropped (`0.5`, `0.3307`,
//! `4.909`); values of a thousand or more to the nearest whole number (`2588`); values below
//! 0.001 in scientific notation (`1.5e-5`); zero as `0`. A reader can therefore bound the
//! value behind any printed number: [`half_width`] gives how far it may be from it.

/// `x` with four significant digits (see the module's rule).
pub fn sig(x: f32) -> String {
    sig64(x as f64)
}

/// [`sig`] for an `f64` (sums of many samples are kept in double precision).
pub fn sig64(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    if !x.is_finite() {
        return if x.is_nan() {
            "no value".into()
        } else if x > 0.0 {
            "∞".into()
        } else {
            "-∞".into()
        };
    }
    let a = x.abs();
    if a >= 1000.0 {
        return format!("{}", x.round());
    }
    if a < 1e-3 {
        let s = format!("{x:.3e}");
        let (mantissa, exp) = s.split_once('e').unwrap_or((&s, "0"));
        return format!("{}e{exp}", trim_zeros(mantissa));
    }
    with_digits(x, 4)
}

/// `x` (finite, not zero) with `n` significant digits as decimals, trailing zeros dropped.
fn with_digits(x: f64, n: usize) -> String {
    let decimals = (n as i32 - 1 - x.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{x:.decimals$}");
    // Rounding can carry into a new digit (999.96 → "1000.0"): trim as usual.
    let s = trim_zeros(&s);
    if s == "-0" { "0".into() } else { s }
}

/// A 3-vector as `(x, y, z)`, each with [`sig`].
pub fn sig3(v: [f32; 3]) -> String {
    format!("({}, {}, {})", sig(v[0]), sig(v[1]), sig(v[2]))
}

/// A percentage for progress: `63 %` (whole percent; `100 %` only when done).
pub fn percent(fraction: f32) -> String {
    let p = (fraction.clamp(0.0, 1.0) * 100.0).floor();
    format!("{p:.0} %")
}

/// A size in memory for people, in binary units as files are sized (`256 MB` is 256 × 2²⁰
/// bytes): whole below ten, one decimal below ten units (`1.5 GB`, `812 KB`, `40 bytes`).
pub fn bytes(n: u64) -> String {
    if n < 1024 {
        return format!("{n} bytes");
    }
    let mut v = n as f64 / 1024.0;
    let mut unit = "KB";
    for next in ["MB", "GB", "TB"] {
        if v < 1024.0 {
            break;
        }
        v /= 1024.0;
        unit = next;
    }
    let decimals = if v < 10.0 { 1 } else { 0 };
    format!("{} {unit}", trim_zeros(&format!("{v:.decimals$}")))
}

/// A count of things for people: exact below ten thousand, else to two or three significant
/// digits in thousands, millions or billions (`9.9 million`, `502 thousand`).
pub fn count(n: u64) -> String {
    if n < 10_000 {
        return n.to_string();
    }
    let x = n as f64;
    let (v, unit) = if x < 1e6 {
        (x / 1e3, "thousand")
    } else if x < 1e9 {
        (x / 1e6, "million")
    } else {
        (x / 1e9, "billion")
    };
    let decimals = if v < 10.0 { 1 } else { 0 };
    format!("{} {unit}", trim_zeros(&format!("{v:.decimals$}")))
}

/// The median of `values` (the mean of the middle two where their count is even), `None`
/// for none: the one every timing, report and benchmark in Voxcast takes.
pub fn median(values: &[f64]) -> Option<f64> {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => Some(v[n / 2]),
        _ => Some(0.5 * (v[n / 2 - 1] + v[n / 2])),
    }
}

/// A time for people: milliseconds below a second (one decimal below ten), else seconds
/// with one decimal (`4.2 ms`, `192 ms`, `1.4 s`).
pub fn duration(seconds: f64) -> String {
    let ms = seconds * 1e3;
    if ms < 10.0 {
        format!("{ms:.1} ms")
    } else if seconds < 1.0 {
        format!("{ms:.0} ms")
    } else {
        format!("{seconds:.1} s")
    }
}

/// A run of values (a search's steps along a ray) each with [`sig`]'s four significant
/// digits, or as many more (up to nine, and then past the decimal point whatever the size)
/// as it takes for neighbours that differ to print differently: a bisection's last steps
/// read "178.6, then 178.6" at four digits, "178.58, then 178.64" here.
pub fn sig_apart(xs: &[f32]) -> Vec<String> {
    let print = |n: usize| -> Vec<String> { xs.iter().map(|&x| sig_digits(x as f64, n)).collect() };
    for n in 4..9 {
        let printed = print(n);
        let apart = printed
            .windows(2)
            .zip(xs.windows(2))
            .all(|(p, x)| p[0] != p[1] || x[0] == x[1]);
        if apart {
            return printed;
        }
    }
    print(9)
}

/// `x` with `n` significant digits, decimals kept at any size (`n` ≤ 4: [`sig64`]).
fn sig_digits(x: f64, n: usize) -> String {
    if n <= 4 || x == 0.0 || !x.is_finite() {
        return sig64(x);
    }
    with_digits(x, n)
}

/// `text` with its first letter a capital (a description or question that opens a sentence).
pub fn capitalised(text: &str) -> String {
    let mut chars = text.chars();
    chars
        .next()
        .map_or(String::new(), |c| c.to_uppercase().chain(chars).collect())
}

/// How far the value behind a number printed by [`sig`] may lie from it: half a unit of its
/// last significant place (0 for `0`, which is printed only for an exact zero).
pub fn half_width(printed: f64) -> f64 {
    let a = printed.abs();
    if a == 0.0 {
        0.0
    } else if a >= 1000.0 {
        0.5
    } else {
        0.5 * 10f64.powi(a.log10().floor() as i32 - 3)
    }
}

fn trim_zeros(s: &str) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_median_of_odd_even_and_no_values() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), Some(2.5));
        assert_eq!(median(&[7.0]), Some(7.0));
        assert_eq!(median(&[]), None);
    }

    #[test]
    fn a_run_of_values_prints_neighbours_apart() {
        // Four digits where they tell the steps apart.
        assert_eq!(
            sig_apart(&[178.1, 178.4, 178.9]),
            ["178.1", "178.4", "178.9"]
        );
        // More where a bisection's steps crowd together; equal values may print equal.
        assert_eq!(
            sig_apart(&[178.44, 178.58, 178.58, 178.64]),
            ["178.44", "178.58", "178.58", "178.64"]
        );
        // Past the decimal point above a thousand, where sig rounds to whole numbers.
        assert_eq!(sig_apart(&[2588.2, 2588.4]), ["2588.2", "2588.4"]);
        // Neighbouring f32 values are told apart too.
        let close = [1.0, 1.0 + f32::EPSILON];
        assert_eq!(sig_apart(&close), ["1", "1.0000001"]);
        assert!(sig_apart(&[]).is_empty());
    }

    #[test]
    fn rounds_to_four_significant_digits() {
        assert_eq!(sig(0.111_999_996), "0.112");
        assert_eq!(sig(4.909_199_7), "4.909");
        assert_eq!(sig64(2_588.123_351_573_944), "2588");
        assert_eq!(sig(0.5), "0.5");
        assert_eq!(sig(-0.330_74), "-0.3307");
        assert_eq!(sig(1.5e-5), "1.5e-5");
        assert_eq!(sig(0.0), "0");
        assert_eq!(sig(-0.0), "0");
        assert_eq!(sig(999.96), "1000");
        assert_eq!(sig(1.0), "1");
        assert_eq!(sig(f32::NAN), "no value");
        assert_eq!(sig3([0.25, 1.0, 12.345_6]), "(0.25, 1, 12.35)");
        assert_eq!(percent(0.634), "63 %");
        assert_eq!(percent(1.0), "100 %");
    }

    /// Every printed number is within `half_width` of the value it stands for.
    #[test]
    fn counts_and_times_read_as_people_say_them() {
        assert_eq!(count(0), "0");
        assert_eq!(count(9_999), "9999");
        assert_eq!(count(502_350), "502 thousand");
        assert_eq!(count(934_511), "935 thousand");
        assert_eq!(count(9_911_921), "9.9 million");
        assert_eq!(count(51_690_000), "52 million");
        assert_eq!(count(3_000_000), "3 million");
        assert_eq!(count(2_500_000_000), "2.5 billion");
        assert_eq!(duration(0.0042), "4.2 ms");
        assert_eq!(duration(0.1918), "192 ms");
        assert_eq!(duration(1.44), "1.4 s");
        assert_eq!(bytes(40), "40 bytes");
        assert_eq!(bytes(812 << 10), "812 KB");
        assert_eq!(bytes(256 << 20), "256 MB");
        assert_eq!(bytes(3 << 29), "1.5 GB");
        assert_eq!(bytes(1 << 40), "1 TB");
    }

    #[test]
    fn the_half_width_bounds_the_rounding() {
        let mut x = 1.234_567e-3f64;
        while x < 1e5 {
            for v in [x, -x, x * 1.7, x * 9.99] {
                let printed: f64 = sig64(v).parse().unwrap();
                let hw = half_width(printed);
                assert!(
                    (printed - v).abs() <= hw * (1.0 + 1e-9),
                    "{v} → {printed} ± {hw}"
                );
            }
            x *= 1.37;
        }
    }
}
