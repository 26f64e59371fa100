//! A small log–log line plot written straight to PNG (no plotting dependency): the speed/accuracy
//! figure of `voxcast bench`. Text uses a built-in 5×7 bitmap font (upper case, digits, a few signs).

use image::{Rgb, RgbImage};

/// One line of the plot: points `(x, y, label)`, joined in order.
pub struct Series {
    pub name: String,
    pub color: [u8; 3],
    pub points: Vec<(f64, f64, String)>,
}

const W: u32 = 900;
const H: u32 = 560;
const LEFT: u32 = 110;
const RIGHT: u32 = 40;
const TOP: u32 = 84;
const BOTTOM: u32 = 80;

/// Draws `series` on log₁₀ axes with decade grid lines, point labels and a legend.
pub fn log_log(series: &[Series], title: &str, x_label: &str, y_label: &str) -> RgbImage {
    let mut img = RgbImage::from_pixel(W, H, Rgb([255, 255, 255]));
    let pts = || {
        series
            .iter()
            .flat_map(|s| s.points.iter())
            .filter(|p| p.0 > 0.0 && p.1 > 0.0)
    };
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for p in pts() {
        x0 = x0.min(p.0.log10());
        x1 = x1.max(p.0.log10());
        y0 = y0.min(p.1.log10());
        y1 = y1.max(p.1.log10());
    }
    if x0 > x1 {
        (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
    }
    let (x0, x1) = (x0.floor(), x1.ceil().max(x0.floor() + 1.0));
    let (y0, y1) = (y0.floor(), y1.ceil().max(y0.floor() + 1.0));
    let px = |x: f64| LEFT as f64 + (x.log10() - x0) / (x1 - x0) * (W - LEFT - RIGHT) as f64;
    let py =
        |y: f64| (H - BOTTOM) as f64 - (y.log10() - y0) / (y1 - y0) * (H - TOP - BOTTOM) as f64;
    let grey = Rgb([215, 215, 215]);
    let black = Rgb([0, 0, 0]);
    for d in x0 as i32..=x1 as i32 {
        let x = px(10f64.powi(d)) as i32;
        line(&mut img, x, TOP as i32, x, (H - BOTTOM) as i32, grey);
        let label = format!("1E{d}");
        text(
            &mut img,
            x - text_width(&label) as i32 / 2,
            (H - BOTTOM + 10) as i32,
            &label,
            black,
        );
    }
    for d in y0 as i32..=y1 as i32 {
        let y = py(10f64.powi(d)) as i32;
        line(&mut img, LEFT as i32, y, (W - RIGHT) as i32, y, grey);
        let label = format!("1E{d}");
        text(
            &mut img,
            LEFT as i32 - 10 - text_width(&label) as i32,
            y - 7,
            &label,
            black,
        );
    }
    line(
        &mut img,
        LEFT as i32,
        TOP as i32,
        LEFT as i32,
        (H - BOTTOM) as i32,
        black,
    );
    line(
        &mut img,
        LEFT as i32,
        (H - BOTTOM) as i32,
        (W - RIGHT) as i32,
        (H - BOTTOM) as i32,
        black,
    );
    text(
        &mut img,
        (W / 2) as i32 - text_width(title) as i32 / 2,
        20,
        title,
        black,
    );
    text(
        &mut img,
        (W / 2) as i32 - text_width(x_label) as i32 / 2,
        (H - 35) as i32,
        x_label,
        black,
    );
    // The y axis's label above the axis, clear of the title (y 20) and the top tick label
    // (y TOP − 7): glyphs are 7 × SCALE high.
    text(&mut img, 10, TOP as i32 - 7 - 7 * SCALE - 8, y_label, black);
    for (i, s) in series.iter().enumerate() {
        let c = Rgb(s.color);
        let valid: Vec<_> = s.points.iter().filter(|p| p.0 > 0.0 && p.1 > 0.0).collect();
        for w in valid.windows(2) {
            line(
                &mut img,
                px(w[0].0) as i32,
                py(w[0].1) as i32,
                px(w[1].0) as i32,
                py(w[1].1) as i32,
                c,
            );
        }
        for p in &valid {
            let (x, y) = (px(p.0) as i32, py(p.1) as i32);
            for dy in -3..=3 {
                for dx in -3..=3 {
                    put(&mut img, x + dx, y + dy, c);
                }
            }
            text(&mut img, x + 6, y + 4, &p.2, c);
        }
        let ly = TOP as i32 + 10 + 22 * i as i32;
        let lx = (W - RIGHT) as i32 - 260;
        line(&mut img, lx, ly + 7, lx + 30, ly + 7, c);
        text(&mut img, lx + 40, ly, &s.name, c);
    }
    img
}

fn put(img: &mut RgbImage, x: i32, y: i32, c: Rgb<u8>) {
    if x >= 0 && y >= 0 && (x as u32) < img.width() && (y as u32) < img.height() {
        img.put_pixel(x as u32, y as u32, c);
    }
}

/// Bresenham's line, two pixels thick.
fn line(img: &mut RgbImage, mut x0: i32, mut y0: i32, x1: i32, y1: i32, c: Rgb<u8>) {
    let dx = (x1 - x0).abs();
    let dy = -(y1 - y0).abs();
    let sx = if x0 < x1 { 1 } else { -1 };
    let sy = if y0 < y1 { 1 } else { -1 };
    let mut err = dx + dy;
    loop {
        put(img, x0, y0, c);
        put(img, x0 + 1, y0, c);
        if x0 == x1 && y0 == y1 {
            break;
        }
        let e2 = 2 * err;
        if e2 >= dy {
            err += dy;
            x0 += sx;
        }
        if e2 <= dx {
            err += dx;
            y0 += sy;
        }
    }
}

const SCALE: i32 = 2;

fn text_width(s: &str) -> u32 {
    s.chars().count() as u32 * 6 * SCALE as u32
}

/// Writes `s` (upper-cased) at `(x, y)`; characters without a glyph are left blank.
fn text(img: &mut RgbImage, x: i32, y: i32, s: &str, c: Rgb<u8>) {
    for (i, ch) in s.to_ascii_uppercase().chars().enumerate() {
        let rows = glyph(ch);
        for (r, bits) in rows.iter().enumerate() {
            for col in 0..5 {
                if bits & (0b10000 >> col) != 0 {
                    for sy in 0..SCALE {
                        for sx in 0..SCALE {
                            put(
                                img,
                                x + (i as i32 * 6 + col) * SCALE + sx,
                                y + r as i32 * SCALE + sy,
                                c,
                            );
                        }
                    }
                }
            }
        }
    }
}

/// 5×7 glyphs, one byte per row, the low five bits left to right.
fn glyph(c: char) -> [u8; 7] {
    match c {
        '0' => [0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E],
        '1' => [0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E],
        '2' => [0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F],
        '3' => [0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E],
        '4' => [0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02],
        '5' => [0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E],
        '6' => [0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E],
        '7' => [0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08],
        '8' => [0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E],
        '9' => [0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C],
        'A' => [0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11],
        'B' => [0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E],
        'C' => [0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E],
        'D' => [0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C],
        'E' => [0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F],
        'F' => [0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10],
        'G' => [0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F],
        'H' => [0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11],
        'I' => [0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E],
        'J' => [0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C],
        'K' => [0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11],
        'L' => [0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F],
        'M' => [0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11],
        'N' => [0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11],
        'O' => [0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E],
        'P' => [0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10],
        'Q' => [0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D],
        'R' => [0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11],
        'S' => [0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E],
        'T' => [0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04],
        'U' => [0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E],
        'V' => [0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04],
        'W' => [0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A],
        'X' => [0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11],
        'Y' => [0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04],
        'Z' => [0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F],
        '.' => [0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C],
        ',' => [0x00, 0x00, 0x00, 0x00, 0x0C, 0x04, 0x08],
        '-' => [0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00],
        '+' => [0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00],
        '=' => [0x00, 0x00, 0x1F, 0x00, 0x1F, 0x00, 0x00],
        '(' => [0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02],
        ')' => [0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08],
        '/' => [0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00],
        ':' => [0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00],
        _ => [0; 7],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plot_draws_series_in_their_colours() {
        let s = Series {
            name: "a".into(),
            color: [200, 0, 0],
            points: vec![
                (0.1, 0.01, "4".into()),
                (1.0, 0.001, "0.5".into()),
                (0.0, 1.0, "skipped".into()),
            ],
        };
        let img = log_log(&[s], "T", "X", "Y");
        assert_eq!(img.dimensions(), (W, H));
        assert!(img.pixels().any(|p| p.0 == [200, 0, 0]));
    }
}
