//! A level in a link: its file, deflated and written in base64url after `#level=` in the page's
//! address, so a teacher shares a level without hosting anything. The fragment never reaches a
//! server; the page reads it and plays the level. A link too long for browsers and the
//! programs links travel through is refused with a sentence that offers the file instead.

use super::Level;
use std::io::{Read, Write};

/// What follows `#` in a level's link.
pub const FRAGMENT: &str = "level=";

/// The longest link offered: browsers take longer addresses, but mail and chat programs and
/// learning platforms cut or refuse links much past this length.
pub const LONGEST_LINK: usize = 8_000;

/// The link to `level` on the page at `page` (its address without a fragment), or why there
/// is none.
pub fn link(level: &Level, page: &str) -> Result<String, String> {
    let text = super::to_text(level);
    let mut deflate = flate2::write::DeflateEncoder::new(Vec::new(), flate2::Compression::best());
    deflate
        .write_all(text.as_bytes())
        .map_err(|e| e.to_string())?;
    let packed = deflate.finish().map_err(|e| e.to_string())?;
    let page = page.split('#').next().unwrap_or(page);
    let link = format!("{page}#{FRAGMENT}{}", base64url(&packed));
    if link.len() > LONGEST_LINK {
        return Err(format!(
            "This level's link would be {} characters long, more than the {LONGEST_LINK} that \
             mail, chat and learning platforms pass on whole (its data set, transfer functions \
             and steps make it large): share the level's file instead (Save).",
            link.len()
        ));
    }
    Ok(link)
}

/// The level file a link's fragment holds (`level=…`, with or without the `#`).
pub fn from_fragment(fragment: &str) -> Result<String, String> {
    let data = fragment
        .trim_start_matches('#')
        .strip_prefix(FRAGMENT)
        .ok_or("the link holds no level (its address has no #level=…)")?;
    let packed = from_base64url(data).ok_or("the link's level is damaged (cut short?)")?;
    let mut text = String::new();
    flate2::read::DeflateDecoder::new(&packed[..])
        .take(4 << 20)
        .read_to_string(&mut text)
        .map_err(|_| "the link's level is damaged (cut short?)".to_string())?;
    Ok(text)
}

const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_";

/// RFC 4648 base64url without padding: safe in an address as it is.
fn base64url(bytes: &[u8]) -> String {
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let n = chunk.iter().fold(0u32, |n, b| (n << 8) | u32::from(*b)) << (8 * (3 - chunk.len()));
        for i in 0..=chunk.len() {
            out.push(ALPHABET[(n >> (18 - 6 * i) & 63) as usize] as char);
        }
    }
    out
}

fn from_base64url(text: &str) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(text.len() * 3 / 4);
    let digits: Vec<u32> = text
        .trim_end_matches('=')
        .bytes()
        .map(|c| ALPHABET.iter().position(|a| *a == c).map(|p| p as u32))
        .collect::<Option<_>>()?;
    for chunk in digits.chunks(4) {
        if chunk.len() == 1 {
            return None;
        }
        let n = chunk.iter().fold(0u32, |n, d| (n << 6) | d) << (6 * (4 - chunk.len()));
        for i in 0..chunk.len() - 1 {
            out.push((n >> (16 - 8 * i)) as u8);
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64url_round_trips_every_length() {
        for n in 0..40usize {
            let bytes: Vec<u8> = (0..n).map(|i| (i * 37 + 5) as u8).collect();
            let text = base64url(&bytes);
            assert!(text.bytes().all(|c| ALPHABET.contains(&c)));
            assert_eq!(from_base64url(&text), Some(bytes));
        }
        assert_eq!(base64url(b"Man"), "TWFu");
        assert_eq!(base64url(b"Ma"), "TWE");
        assert_eq!(from_base64url("a"), None);
        assert_eq!(from_base64url("a+b="), None);
    }

    /// Every built-in level fits a link and comes back as the same level; a damaged or cut
    /// link says so; a level too large for a link is refused with a sentence.
    #[test]
    fn a_level_travels_in_a_link() {
        for level in Level::all() {
            let link = link(&level, "http://127.0.0.1:8000/index.html#old").unwrap();
            assert!(
                link.starts_with("http://127.0.0.1:8000/index.html#level="),
                "{link}"
            );
            assert!(link.len() < LONGEST_LINK, "{}: {}", level.id, link.len());
            let text = from_fragment(link.split('#').nth(1).unwrap()).unwrap();
            assert_eq!(text, super::super::to_text(&level));
        }
        let level = &Level::all()[0];
        let link = link(level, "page").unwrap();
        let cut = &link[..link.len() / 2];
        assert!(from_fragment(cut.split('#').nth(1).unwrap()).is_err());
        assert!(from_fragment("#volume=x").is_err());
        let mut big = level.clone();
        // Text that does not compress: letters from a linear congruential generator.
        let mut x = 1u64;
        big.concept = (0..20_000)
            .map(|_| {
                x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
                char::from(b'a' + (x >> 59) as u8 % 26)
            })
            .collect();
        let refused = super::link(&big, "page").unwrap_err();
        assert!(
            refused.contains("share the level's file instead"),
            "{refused}"
        );
    }
}
