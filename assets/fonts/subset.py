#!/usr/bin/env python3
"""Makes the sandbox's two fonts (assets/fonts/*.ttf) from egui's: Ubuntu Light and Hack, kept
to the scripts and symbols below and without their hinting instructions. Text looks the same
(glyph edges antialiased a little differently); a visitor of the page downloads 0.17 MB less
with gzip (BENCHMARKS.md, "In a browser").

egui renders text with skrifa, whose autohinter fits a font that carries no instructions to the
pixel grid (Hack's own were made by ttfautohint). The licences ask a changed font to carry a new
name: each is renamed "... derivative Voxcast" (the Ubuntu Font Licence, 2c).

    python3 assets/fonts/subset.py <epaint_default_fonts-0.36.2/fonts>

Needs fontTools (Debian: python3-fonttools). The glyph test in src/sandbox/ui/fonts.rs checks
that every character our texts use is still drawn.
"""
import pathlib
import sys

from fontTools import subset
from fontTools.ttLib import TTFont

# Latin, IPA, Greek, Cyrillic, Armenian, Hebrew; Thai; Georgian; Latin and Greek extended;
# punctuation, super- and subscripts, currency, letterlike, numbers, arrows, mathematics,
# technical, box drawing, blocks, shapes, symbols, dingbats, more arrows; ligatures; the
# replacement character.
RANGES = [(0x0000, 0x05FF), (0x0E00, 0x0E7F), (0x10A0, 0x10FF), (0x1E00, 0x1FFF),
          (0x2000, 0x2BFF), (0xFB00, 0xFB4F), (0xFFFD, 0xFFFD)]
FONTS = [("Ubuntu-Light.ttf", "Ubuntu Light"), ("Hack-Regular.ttf", "Hack")]


def main(source: pathlib.Path, out: pathlib.Path) -> None:
    for file, family in FONTS:
        # The source's own timestamp kept, so that a second run writes the same bytes.
        font = TTFont(source / file, recalcTimestamp=False)
        options = subset.Options()
        options.hinting = False
        options.layout_features = ["*"]
        options.name_IDs = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14]
        subsetter = subset.Subsetter(options)
        subsetter.populate(unicodes=[c for lo, hi in RANGES for c in range(lo, hi + 1)])
        subsetter.subset(font)
        new = f"{family} derivative Voxcast"
        names = font["name"]
        for record in list(names.names):
            if record.nameID in (1, 4, 16):
                names.setName(new, record.nameID, record.platformID, record.platEncID, record.langID)
            elif record.nameID == 6:
                names.setName(new.replace(" ", ""), 6, record.platformID, record.platEncID,
                              record.langID)
            elif record.nameID == 3:
                names.setName(f"{new}: subset", 3, record.platformID, record.platEncID,
                              record.langID)
        target = out / file.replace(".ttf", "-Voxcast.ttf")
        font.save(target)
        print(f"{target}: {target.stat().st_size} bytes, "
              f"{len(font.getBestCmap())} characters")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(pathlib.Path(sys.argv[1]), pathlib.Path(__file__).parent)
