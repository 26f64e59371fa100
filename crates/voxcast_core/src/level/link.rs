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
/// is none. A link has no folder: the data sets and transfer-function files the level names
/// beside itself go into it named where the level found them (its URL's folder, or its
/// file's), so the link opens them from there.
pub fn link(level: &Level, page: &str) -> Result<String, String> {
    let text = super::to_text(&named_where_found(level));
    let mut deflate = flate2::write::DeflateEncoder::new(Vec::new(), flate2::Compression::best());
    deflate
        .write_all(text.as_bytes())
        .map_err(|e| e.to_string())?;
    let packed = deflate.finish().map_err(|e| e.to_string())?;
    let page = page_for_link(page);
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

/// The page's address as a link carries it: without its fragment, and without a `levels=`
/// query parameter (the course the teacher opened; the link carries its own level).
pub fn page_for_link(address: &str) -> String {
    let address = address.split('#').next().unwrap_or(address);
    let Some((page, query)) = address.split_once('?') else {
        return address.to_string();
    };
    let kept: Vec<&str> = query
        .split('&')
        .filter(|p| !p.is_empty() && *p != "levels" && !p.starts_with("levels="))
        .collect();
    if kept.is_empty() {
        page.to_string()
    } else {
        format!("{page}?{}", kept.join("&"))
    }
}

/// `level` with each data set and transfer-function file it names beside itself named where
/// it was found ([`super::Origin::resolve`]); built-ins, presets and full names as they are.
pub fn named_where_found(level: &Level) -> Level {
    let mut out = level.clone();
    let found = |name: &mut String| *name = level.resolve(name);
    let file = |t: &mut Option<super::TransferChoice>| {
        if let Some(super::TransferChoice::Named(name)) = t
            && name.to_ascii_lowercase().ends_with(".json")
        {
            found(name);
        }
    };
    found(&mut out.scene.volume);
    file(&mut out.scene.transfer);
    for step in &mut out.steps {
        if let Some(scene) = step.scene.as_mut() {
            if let Some(v) = scene.volume.as_mut() {
                found(v);
            }
            file(&mut scene.transfer);
        }
    }
    out
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

    /// A link opens the page without the course the teacher opened, keeping the rest.
    #[test]
    fn a_link_leaves_the_teacher_s_course_out() {
        let cases = [
            ("http://h/#x", "http://h/"),
            ("http://h/?levels=c/l.json", "http://h/"),
            (
                "http://h/?gpu=webgl2&levels=c/l.json&no-rays#level=abc",
                "http://h/?gpu=webgl2&no-rays",
            ),
            (
                "http://h/index.html?levelsx=1",
                "http://h/index.html?levelsx=1",
            ),
            ("page", "page"),
        ];
        for (address, page) in cases {
            assert_eq!(page_for_link(address), page, "{address}");
        }
    }

    /// A level read from a URL goes into its link with its data set and transfer file named
    /// beside that URL (a link has no folder of its own); built-ins and presets stay names.
    #[test]
    fn a_link_names_the_files_where_the_level_found_them() {
        use super::super::{Origin, StepScene, TransferChoice};
        let mut level = Level::all()[0].clone();
        level.origin = Origin::Url("https://school.example/course/week1.json?x=1".into());
        level.scene.volume = "data/ct.nrrd".into();
        level.scene.transfer = Some(TransferChoice::Named("bone.json".into()));
        level.steps[1].scene = Some(StepScene {
            volume: Some("builtin:bucky".into()),
            transfer: Some(TransferChoice::Named("ct-bone".into())),
            ..Default::default()
        });
        level.steps[2].scene = Some(StepScene {
            volume: Some("mri.nii.gz".into()),
            ..Default::default()
        });
        let url = link(&level, "https://school.example/voxcast/").unwrap();
        let text = from_fragment(url.split('#').nth(1).unwrap()).unwrap();
        let back = Level::from_json(&text).unwrap();
        assert_eq!(
            back.scene.volume,
            "https://school.example/course/data/ct.nrrd"
        );
        assert_eq!(
            back.scene.transfer,
            Some(TransferChoice::Named(
                "https://school.example/course/bone.json".into()
            ))
        );
        let step = |k: usize| back.steps[k].scene.clone().unwrap();
        assert_eq!(step(1).volume.as_deref(), Some("builtin:bucky"));
        assert_eq!(
            step(1).transfer,
            Some(TransferChoice::Named("ct-bone".into()))
        );
        assert_eq!(
            step(2).volume.as_deref(),
            Some("https://school.example/course/mri.nii.gz")
        );
    }
}
