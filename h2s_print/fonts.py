"""The page font: an embedded Unicode TrueType font, measured as it is drawn (issue 15).

Pages are set in **DejaVu Sans** by default (regular, bold, oblique): Latin, Greek, Cyrillic
and many more scripts, taken from matplotlib's package data (a well-kept package that ships
the DejaVu files and their licence), never copied into this repository.  A config's ``font:``
names a TrueType/OpenType file of the user's instead (a CJK font, say), for every style or
one file per style.  PDFs embed the glyphs they use (ReportLab subsets TrueType fonts); PNGs
are drawn by cairosvg in the same font (the file is added to fontconfig's application fonts),
so text widths match; SVGs name the font's family and carry the width it was laid out at.

A :class:`FontSpec` is plain paths, so it pickles to worker processes.  Layout measures text
in the **current** font (:func:`using`, :func:`current`): a context variable set around the
layout of one workbook, so measuring and drawing agree without threading the font through
every layout helper.  ``Text.font`` keeps naming a *style* with the names of old
(``Helvetica``, ``Helvetica-Bold``, ``Helvetica-Oblique``: :data:`STYLES`), resolved in the
page's font.
"""

from __future__ import annotations

import contextlib
import contextvars
import functools
import hashlib
import importlib.util
import itertools
import struct
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from .errors import H2SError

#: The style keys ``Text.font`` holds, and the attribute of :class:`FontSpec` each selects.
STYLES = {"Helvetica": "regular", "Helvetica-Bold": "bold", "Helvetica-Oblique": "oblique"}
#: The default font's files inside matplotlib's package data.
DEJAVU = {"regular": "DejaVuSans.ttf", "bold": "DejaVuSans-Bold.ttf",
          "oblique": "DejaVuSans-Oblique.ttf"}


class FontError(H2SError):
    """A font file that cannot be read, or text it cannot draw."""


@dataclass(frozen=True, slots=True)
class FontSpec:
    """The three faces pages are set in.

    Attributes:
        regular, bold, oblique: TrueType/OpenType files (one file may serve several).
        name: how messages call it ("DejaVu Sans", or the config's file name).
    """

    regular: Path
    bold: Path
    oblique: Path
    name: str

    def path(self, style: str) -> Path:
        """The file of a ``Text.font`` style (:data:`STYLES`)."""
        return getattr(self, STYLES.get(style, "regular"))

    def __hash__(self) -> int:
        # The name's alone (equal specs have equal names): a str keeps its hash, where the
        # generated hash hashes three paths each time, and the font caches (widths, glyph
        # checks, wraps) look a spec up some 200 000 times in a book.
        return hash(self.name)


@dataclass(frozen=True, slots=True)
class Face:
    """One loaded font file.

    Attributes:
        path: the file.
        key: the name it is registered under with ReportLab (stable for a file).
        family: its family name (SVG ``font-family``).
        bold, italic: its own weight and slant (SVG says them only when the file has them).
        widths: advance width per code point, in 1/1000 em.
        default_width: the advance of a code point it lacks (never drawn: checked first).
    """

    path: Path
    key: str
    family: str
    bold: bool
    italic: bool
    widths: dict[int, float]
    default_width: float

    def has(self, ch: str) -> bool:
        return ord(ch) in self.widths


def _matplotlib_fonts() -> Path:
    spec = importlib.util.find_spec("matplotlib")
    if spec is None or not spec.submodule_search_locations:
        raise FontError("the default page font (DejaVu Sans) comes with matplotlib, which is "
                        "not installed: pip install matplotlib, or give a config 'font:'")
    return Path(list(spec.submodule_search_locations)[0]) / "mpl-data" / "fonts" / "ttf"


@functools.lru_cache(maxsize=1)
def default_spec() -> FontSpec:
    """DejaVu Sans from matplotlib's package data."""
    folder = _matplotlib_fonts()
    return FontSpec(*(folder / DEJAVU[s] for s in ("regular", "bold", "oblique")),
                    name="DejaVu Sans")


@functools.lru_cache(maxsize=32)
def face(path: Path) -> Face:
    """The font file at ``path``, loaded and registered with ReportLab (cached).

    Raises:
        FontError: not a TrueType/OpenType font ReportLab can embed.
    """
    from reportlab.pdfbase import pdfmetrics
    from reportlab.pdfbase.ttfonts import TTFont, TTFError

    key = "h2s-" + hashlib.sha1(str(path).encode("utf-8")).hexdigest()[:12]
    try:
        font = TTFont(key, str(path))
    except (TTFError, OSError, ValueError) as exc:
        raise FontError(f"{path}: cannot be used as the page font ({exc})") from None
    pdfmetrics.registerFont(font)
    f = font.face
    family = f.familyName.decode("utf-8", "replace") if isinstance(f.familyName, bytes) \
        else str(f.familyName)
    flags = int(getattr(f, "flags", 0))
    name = f.name.decode("latin-1", "replace") if isinstance(f.name, bytes) else str(f.name)
    bold = "bold" in name.lower()
    italic = bool(flags & 64) or "oblique" in name.lower() or "italic" in name.lower()
    return Face(path, key, family, bold, italic, dict(f.charWidths), float(f.defaultWidth))


_current: contextvars.ContextVar[FontSpec | None] = contextvars.ContextVar("h2s_font",
                                                                            default=None)


def current() -> FontSpec:
    """The font layout measures in now (the default outside :func:`using`)."""
    return _current.get() or default_spec()


@contextlib.contextmanager
def using(spec: FontSpec | None) -> Iterator[FontSpec]:
    """Lay out (measure) in ``spec`` inside the ``with`` block (``None``: the default)."""
    token = _current.set(spec)
    try:
        yield current()
    finally:
        _current.reset(token)


def width_mm(text: str, size_pt: float, style: str = "Helvetica",
             spec: FontSpec | None = None) -> float:
    """Advance width of ``text`` set in ``style`` of ``spec`` (default: current) at
    ``size_pt``, mm."""
    return _em_width(spec or current(), style, text) / 1000.0 * size_pt * 25.4 / 72.0


@functools.lru_cache(maxsize=1 << 16)
def _em_width(spec: FontSpec, style: str, text: str) -> float:
    """Advance of ``text`` in 1/1000 em (cached: layout measures the same labels and lines
    again and again while it places them; a book asks 160 000 times)."""
    f = face(spec.path(style))
    # the same advances added in the same order as one by one, without a Python step each
    return sum(map(f.widths.get, map(ord, text), itertools.repeat(f.default_width)))


def missing(text: str, spec: FontSpec | None = None) -> str | None:
    """The first character of ``text`` that a face of ``spec`` (default: current) cannot
    draw, or None (line breaks and tabs are spaces on a page)."""
    have = coverage(spec or current())
    for ch in str(text):
        if ord(ch) not in have and ch not in "\n\t":
            return ch
    return None


@functools.lru_cache(maxsize=32)
def coverage(spec: FontSpec) -> frozenset[int]:
    """The code points every face of ``spec`` draws."""
    return frozenset.intersection(*(code_points(spec.path(style)) for style in STYLES))


@functools.lru_cache(maxsize=32)
def code_points(path: Path) -> frozenset[int]:
    """The code points the font file at ``path`` draws: the keys of its :func:`face`'s
    ``widths``, read from its ``cmap`` and ``maxp`` tables alone (:func:`_cmap_points`) when
    it is a plain TrueType file with a cmap subtable of format 4, 12 or 13, else from
    :func:`face`.

    Why: ``h2s plan`` checks the wording's characters against the font (``templates.
    check_font``) but never measures text, and loading the three DejaVu faces with ReportLab
    (every table, every glyph's width) and importing it took some 0.05 s of a 1.2 s plan.  A
    file :func:`face` refuses never gets here with a set of its own: a config's ``font:`` is
    loaded by :func:`face` when the config is read, the default is matplotlib's DejaVu Sans.
    tests/test_fonts.py compares the two on every font matplotlib ships.
    """
    try:
        points = _cmap_points(path.read_bytes())
    except (OSError, struct.error, ValueError, IndexError):
        points = None
    return points if points is not None else frozenset(face(path).widths)


def _cmap_points(data: bytes) -> frozenset[int] | None:
    """The code points ReportLab's ``TTFontFile.extractInfo`` gives a width, from the file's
    bytes: the cmap subtable it picks (the last record for platform 3, for platform 0 but
    encoding 5, for Macintosh Roman; Macintosh 0 only before any other), every code point
    mapped to a glyph below ``maxp``'s count (glyph 0 included, as there), and U+00A0 with
    U+0020 (each stands for the other).  None for a file or subtable it does not read
    (a collection, PostScript outlines, cmap formats other than 4, 12 and 13)."""
    u16, u32 = struct.Struct(">H"), struct.Struct(">L")
    if u32.unpack_from(data, 0)[0] not in (0x00010000, 0x74727565):
        return None
    tables = {}
    for i in range(u16.unpack_from(data, 4)[0]):
        tag, _, offset, _ = struct.unpack_from(">4sLLL", data, 12 + 16 * i)
        tables[tag] = offset
    if b"cmap" not in tables or b"maxp" not in tables:
        return None
    n_glyphs = u16.unpack_from(data, tables[b"maxp"] + 4)[0]
    cmap = tables[b"cmap"]
    version, count = u16.unpack_from(data, cmap)[0], u16.unpack_from(data, cmap + 2)[0]
    if count == 0 and version != 0:
        count = version
    chosen, enc = None, 0
    for i in range(count):
        platform, encoding, offset = struct.unpack_from(">HHL", data, cmap + 4 + 8 * i)
        if platform == 3 or (platform == 1 and encoding == 1) or (platform == 0
                                                                  and encoding != 5):
            chosen, enc = offset, 1
        elif platform == 1 and encoding == 0 and enc != 1:
            chosen, enc = offset, 2
    if chosen is None:
        return None
    at = cmap + chosen
    fmt = u16.unpack_from(data, at)[0]
    points: set[int] = set()
    if fmt in (12, 13):
        for k in range(u32.unpack_from(data, at + 12)[0]):
            start, end, glyph = struct.unpack_from(">LLL", data, at + 16 + 12 * k)
            if fmt == 13:  # every code point of the group maps to one glyph
                if glyph < n_glyphs:
                    points.update(range(start, end + 1))
            else:  # consecutive glyphs from ``glyph``: those below the count
                points.update(range(start, min(end, start + n_glyphs - 1 - glyph) + 1))
    elif fmt == 4:
        limit = at + u16.unpack_from(data, at + 2)[0]
        segs = u16.unpack_from(data, at + 6)[0] // 2
        ends = struct.unpack_from(f">{segs}H", data, at + 14)
        starts = struct.unpack_from(f">{segs}H", data, at + 16 + 2 * segs)
        deltas = struct.unpack_from(f">{segs}h", data, at + 16 + 4 * segs)
        range_at = at + 16 + 6 * segs
        ranges = struct.unpack_from(f">{segs}H", data, range_at)
        for n, (start, end, delta, ro) in enumerate(zip(starts, ends, deltas, ranges)):
            for ch in range(start, end + 1):
                if ro == 0:
                    glyph = (ch + delta) & 0xFFFF
                else:
                    offset = range_at + 2 * n + (ch - start) * 2 + ro
                    glyph = 0 if offset >= limit else u16.unpack_from(data, offset)[0]
                    if glyph != 0:
                        glyph = (glyph + delta) & 0xFFFF
                if glyph < n_glyphs:
                    points.add(ch)
    else:
        return None
    if 0x20 in points or 0xA0 in points:
        points |= {0x20, 0xA0}
    return frozenset(points)


@functools.lru_cache(maxsize=32)
def fontconfig_add(path: Path) -> bool:
    """Make ``path`` known to fontconfig (as an application font), so cairo (cairosvg's PNG
    pages) draws in it; True when fontconfig took it."""
    import ctypes
    import ctypes.util

    lib = ctypes.util.find_library("fontconfig")
    if not lib:
        return False
    try:
        fc = ctypes.CDLL(lib)
        fc.FcConfigAppFontAddFile.argtypes = [ctypes.c_void_p, ctypes.c_char_p]
        fc.FcConfigAppFontAddFile.restype = ctypes.c_int
        return bool(fc.FcConfigAppFontAddFile(None, str(path).encode("utf-8")))
    except (OSError, AttributeError):
        return False
