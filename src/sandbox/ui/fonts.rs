//! The window's two fonts: Ubuntu Light for text and Hack for numbers laid out in columns, each
//! the other's fallback (Hack draws the arrows and shapes Ubuntu lacks: ≡ ⇶ ● ▶).
//!
//! egui's own default adds two emoji fonts, 0.46 MB of the page's download with gzip (of 8.1 MB
//! then) for three glyphs our texts used; our texts keep to what these two fonts draw (the
//! test below lists any character of ours they lack). The two are egui's, kept to the scripts
//! and symbols a level may use and without hinting instructions (`assets/fonts/subset.py`,
//! 0.17 MB less with gzip); egui's renderer hints them itself.

use bevy::prelude::*;
use bevy_egui::{EguiContext, egui};
use std::sync::Arc;

/// Ubuntu Light, as `assets/fonts/subset.py` makes it (licence: `assets/fonts/NOTICE.md`).
const UBUNTU_LIGHT: &[u8] = include_bytes!("../../../assets/fonts/Ubuntu-Light-Voxcast.ttf");
/// Hack, as `assets/fonts/subset.py` makes it.
const HACK: &[u8] = include_bytes!("../../../assets/fonts/Hack-Regular-Voxcast.ttf");

/// The fonts every egui context of the sandbox draws with, the window's and the tests'.
pub(crate) fn definitions() -> egui::FontDefinitions {
    let mut fonts = egui::FontDefinitions::empty();
    for (name, bytes) in [("Ubuntu-Light", UBUNTU_LIGHT), ("Hack", HACK)] {
        fonts.font_data.insert(
            name.to_owned(),
            Arc::new(egui::FontData::from_static(bytes)),
        );
    }
    let family = |names: [&str; 2]| names.map(str::to_owned).to_vec();
    fonts.families.insert(
        egui::FontFamily::Proportional,
        family(["Ubuntu-Light", "Hack"]),
    );
    fonts.families.insert(
        egui::FontFamily::Monospace,
        family(["Hack", "Ubuntu-Light"]),
    );
    fonts
}

/// An egui context that draws with [`definitions`] from its first pass (the panels' tests).
#[cfg(test)]
pub(crate) fn context() -> egui::Context {
    let ctx = egui::Context::default();
    ctx.set_fonts(definitions());
    ctx
}

/// Whether a font of `family` in [`definitions`] has a glyph for `c` (read from the fonts'
/// character maps: egui's own `has_glyph` calls every character of the font that draws its
/// replacement box, Hack here, missing).
#[cfg(test)]
pub(crate) fn has_glyph(family: &egui::FontFamily, c: char) -> bool {
    use skrifa::MetadataProvider;
    let fonts = definitions();
    fonts.families[family].iter().any(|name| {
        let font = skrifa::FontRef::new(&fonts.font_data[name].font).expect("a TrueType font");
        font.charmap().map(c).is_some()
    })
}

/// Gives each egui context the sandbox creates its fonts as it is added, before its first pass.
pub(super) fn plugin(app: &mut App) {
    app.add_observer(
        |add: On<Add, EguiContext>, mut contexts: Query<&mut EguiContext>| {
            if let Ok(mut ctx) = contexts.get_mut(add.entity) {
                ctx.get_mut().set_fonts(definitions());
            }
        },
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every character outside ASCII that a text of ours may show — in the sandbox's and the
    /// core's code outside comments (labels, tooltips, tunables' documentation, messages), the
    /// levels and the presets — has a glyph in both families: a missing one is drawn as a box.
    #[test]
    fn every_character_our_texts_use_has_a_glyph() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut used = std::collections::BTreeMap::<char, String>::new();
        let mut folders = vec![root.join("src"), root.join("crates/voxcast_core/src")];
        folders.extend(["levels", "presets"].map(|f| root.join("assets").join(f)));
        let mut files = 0;
        while let Some(folder) = folders.pop() {
            for entry in std::fs::read_dir(&folder).unwrap() {
                let path = entry.unwrap().path();
                let ext = path.extension().and_then(|e| e.to_str());
                if path.is_dir() {
                    folders.push(path);
                } else if matches!(ext, Some("rs" | "json")) {
                    files += 1;
                    let text = std::fs::read_to_string(&path).unwrap();
                    for line in text.lines().filter(|l| !l.trim_start().starts_with("//")) {
                        for c in line.chars().filter(|c| !c.is_ascii() && !c.is_whitespace()) {
                            used.entry(c).or_insert_with(|| path.display().to_string());
                        }
                    }
                }
            }
        }
        assert!(
            files > 100 && used.len() > 20,
            "{files} files, {} characters",
            used.len()
        );
        let missing: Vec<_> = used
            .iter()
            .filter(|&(&c, _)| {
                [egui::FontFamily::Proportional, egui::FontFamily::Monospace]
                    .iter()
                    .any(|family| !has_glyph(family, c))
            })
            .collect();
        assert!(
            missing.is_empty(),
            "no glyph for (character, first file): {missing:?}"
        );
    }
}
