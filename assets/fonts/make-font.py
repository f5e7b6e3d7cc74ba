#!/usr/bin/env python3
"""Makes DejaVuSans-subset.ttf, the font embedded in swarf's PNG plots (host/plot), from Debian's
fonts-dejavu-core DejaVuSans.ttf (2.37) with fontTools:

1. subset to Latin-1, Greek and the math symbols plot labels use (48 kB instead of 760 kB), without hinting
   (plotters' ab_glyph rasteriser ignores it), keeping the legacy `kern` table (the one ab_glyph reads);
2. add to every simple glyph whose outline starts right of the origin (left side bearing > 0) a one-point contour
   at x = 0, which draws nothing. plotters 0.3.7's ab_glyph text renderer places each glyph's bitmap at the pen
   position, ignoring the bitmap's offset (the left side bearing), so letters drift by their bearings
   ("Degen erate"); with the glyph's bounds starting at x = 0 the offset is 0 and the spacing is the font's.

Usage: python3 make-font.py [/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf]
The licence (Bitstream Vera + Arev; DejaVu changes public domain) allows modification under a name without
"Bitstream", "Vera", "Arev" or "Tavmjong Bah"; see LICENSE-DejaVu.txt.
"""
import os
import sys

from fontTools import subset
from fontTools.ttLib import TTFont
from fontTools.ttLib.tables._g_l_y_f import GlyphCoordinates

SOURCE = sys.argv[1] if len(sys.argv) > 1 else "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
TARGET = os.path.join(os.path.dirname(os.path.abspath(__file__)), "DejaVuSans-subset.ttf")
UNICODES = (
    "U+0020-007E,U+00A0-00FF,U+0391-03A9,U+03B1-03C9,U+03D1,U+03D5,U+2010-2027,U+2030-2033,U+2070-209F,"
    "U+2190-2193,U+2202,U+2206,U+2207,U+2211,U+2212,U+2219,U+221A,U+221D,U+221E,U+2248,U+2260,U+2264,U+2265,"
    "U+22C5,U+FFFD"
)

options = subset.Options()
options.hinting = False
options.legacy_kern = True
options.layout_features = ["kern"]
options.drop_tables += ["MATH", "FFTM"]
options.name_IDs = ["*"]
options.name_languages = ["*"]
font = subset.load_font(SOURCE, options)
subsetter = subset.Subsetter(options)
subsetter.populate(unicodes=subset.parse_unicodes(UNICODES))
subsetter.subset(font)

glyf, hmtx = font["glyf"], font["hmtx"]
anchored = 0
for name in font.getGlyphOrder():
    g = glyf[name]
    if g.isComposite() or g.numberOfContours <= 0:
        continue
    g.recalcBounds(glyf)
    if g.xMin <= 0:
        continue
    coords = list(g.coordinates) + [(0, g.yMin)]
    g.coordinates = GlyphCoordinates(coords)
    g.flags = bytearray(g.flags) + bytearray([1])  # on-curve
    g.endPtsOfContours = list(g.endPtsOfContours) + [len(coords) - 1]
    g.numberOfContours += 1
    anchored += 1
# Keep every left side bearing equal to the glyph's xMin (composites built on an anchored glyph moved too).
for name in font.getGlyphOrder():
    g = glyf[name]
    if g.numberOfContours != 0:
        g.recalcBounds(glyf)
        hmtx[name] = (hmtx[name][0], g.xMin)
font.save(TARGET)
print(f"{TARGET}: {os.path.getsize(TARGET)} bytes, {len(font.getGlyphOrder())} glyphs, {anchored} anchored at x = 0")
