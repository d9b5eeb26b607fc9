"""Render stage (DESIGN.md §2.9): laid-out pages -> PDF (reportlab), SVG and PNG (cairosvg).

Everything was placed by ``layout.py`` in page millimetres; this module only converts units
(1 mm = 72 / 25.4 pt) and draws.  PDFs are vector (real lines, real text in the page's
embedded font, :mod:`h2s_print.fonts`: only the glyphs used are embedded), written
with reportlab's ``invariant=1`` so the same pages give the same bytes, with a PDF outline from
the pages' bookmarks and the viewer preference ``/PrintScaling /None`` so print dialogs default
to actual size (the calibrated drawing sheet must not be scaled).  Each page's MediaBox is
exactly its size in points.
"""

from __future__ import annotations

import functools
import io
import logging
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Sequence
from xml.sax.saxutils import escape

from . import fonts
from .errors import RenderError
from .files import write_bytes_atomic
from .layout import COLOURS, PT_MM, Circle, Page, Polyline, Rect, Text, text_width_mm

log = logging.getLogger(__name__)

MM_PT = 72.0 / 25.4  #: points per millimetre
PRODUCER = "h2s-print"


def _pt(mm: float) -> float:
    return mm * MM_PT


def _rgb(name: str) -> tuple[float, float, float]:
    try:
        return COLOURS[name]
    except KeyError:
        raise RenderError(f"unknown colour role {name!r} in a laid-out page") from None


# ----------------------------------------------------------------------------- PDF


@functools.lru_cache(maxsize=256)
def _stroke_style_ops(colour: str, width_mm: float, dash_mm: tuple[float, ...]) -> str:
    """The operators that set a polyline's stroke, exactly as reportlab's canvas writes them.

    ``setStrokeColorRGB``, ``setLineWidth`` and ``setDash([...], 0)`` each append one line
    (``r g b RG``, ``w w``, ``[d ...] 0 d``) that depends on nothing but these values, so a
    style's lines are made once (a book has about twenty styles and 40 000 polylines).
    """
    from reportlab.lib.rl_accel import fp_str

    return (f"{fp_str(_rgb(colour))} RG\n{fp_str(_pt(width_mm))} w\n"
            f"[{fp_str([_pt(d) for d in dash_mm])}] 0 d")


@functools.lru_cache(maxsize=512)
def _path_template(n_points: int, closed: bool) -> str:
    """``n {} {} m {} {} l ... [h]``: a polyline's path with a slot per coordinate."""
    return "n {} {} m" + " {} {} l" * (n_points - 1) + (" h" if closed else "")


def _path_ops(points_mm: Sequence[tuple[float, float]], closed: bool,
              numbers: dict[float, str]) -> str:
    """A polyline's path, ``n x0 y0 m x1 y1 l ... [h]``, exactly as reportlab's path object
    writes it (``beginPath``, ``moveTo``, ``lineTo``..., ``close``, then ``drawPath``).

    Each coordinate is written by ``fp_str`` of it in pt, which formats each number on its
    own, so numbers met before are not formatted again: ``numbers`` (mm -> that text) is
    filled as they are met, with one ``fp_str`` call a polyline for its new ones (a book's
    lines meet their 360 000 coordinates' 53 000 values again and again: shared corners,
    guides through them).  Equal mm give the same text: the one pair of equal floats that
    differ, 0.0 and -0.0, both print ``0``.
    """
    from reportlab.lib.rl_accel import fp_str

    flat = [v for point in points_mm for v in point]
    texts = list(map(numbers.get, flat))
    if None in texts:
        new = [i for i, text in enumerate(texts) if text is None]
        for i, text in zip(new, fp_str([flat[i] * MM_PT for i in new]).split(" ")):
            texts[i] = numbers[flat[i]] = text
    return _path_template(len(points_mm), closed).format(*texts)


@functools.lru_cache(maxsize=64)
def _fill_colour_op(colour: str) -> str:
    """``r g b rg``: the line ``setFillColorRGB`` appends for a colour role."""
    from reportlab.lib.rl_accel import fp_str

    return f"{fp_str(_rgb(colour))} rg"


#: Per document: (font key, size in pt, string) -> (its width in pt, the end of its text line).
_TextLines = dict[tuple[str, float, str], tuple[float, str]]


@dataclass(slots=True)
class _Drawn:
    """What a document has drawn so far, for its later pages to reuse (:func:`_draw_text`,
    :func:`_path_ops`)."""

    texts: _TextLines = field(default_factory=dict)
    numbers: dict[float, str] = field(default_factory=dict)  #: mm -> its text in pt
    #: (points, closed) -> the path's operators (:func:`_path_ops`): a book draws 42 000
    #: polylines, 7 000 different (an earlier stroke again at every later step); looked up
    #: by the points, a path drawn before is not written again (book, --jobs 1: render
    #: 0.58 -> 0.50 s, bytes identical)
    paths: dict[tuple[tuple[tuple[float, float], ...], bool], str] = field(default_factory=dict)


def _text_x(anchor: str, x: float, width: float) -> float:
    """Where a line of ``width`` pt anchored at ``x`` starts, as drawString, drawCentredString
    and drawRightString work it out (the same float operations)."""
    return x if anchor == "start" else x - 0.5 * width if anchor == "middle" else x - width


def _draw_text(c, known: _TextLines, font_key: str, size_pt: float, anchor: str,
               x: float, y: float, string: str) -> None:
    """Draw ``string`` at ``(x, y)`` pt as reportlab's drawString (Centred, Right) does.

    A string's text line is ``BT 1 0 0 1 x0 y Tm <glyphs in subsets> T* ET``: only ``x0 y``
    depends on where it stands.  The rest depends on the font, size and the document's glyph
    subsets, where a character keeps the slot it got when first drawn; so a string drawn
    before in the same document (a book draws 11 000 texts, 2 000 different) gets the rest
    of its first line.  The canvas's current font is left as the first drawing set it: only
    that first drawing reads it, and setting a TrueType font (every page font is one,
    :func:`h2s_print.fonts.face`) writes nothing to the page.
    """
    from reportlab.lib.rl_accel import fp_str

    seen = known.get((font_key, size_pt, string))
    if seen is not None:
        width, rest = seen
        c._code.append(f"BT 1 0 0 1 {fp_str(_text_x(anchor, x, width), y)} Tm {rest}")
        return
    c.setFont(font_key, size_pt)
    draw = {"start": c.drawString, "middle": c.drawCentredString,
            "end": c.drawRightString}[anchor]
    draw(x, y, string)
    width = c.stringWidth(string, font_key, size_pt)
    head = f"BT 1 0 0 1 {fp_str(_text_x(anchor, x, width), y)} Tm "
    if c._code[-1].startswith(head):  # else drawn some other way: not reused
        known[font_key, size_pt, string] = (width, c._code[-1][len(head):])


def _draw_page(c, page: Page, drawn: _Drawn) -> None:
    spec = page.font or fonts.current()
    c.setLineJoin(1)
    c.setLineCap(0)
    code = c._code  # the page's content stream, one line per entry
    for item in page.items:
        if isinstance(item, Polyline):
            if len(item.points_mm) < 2:
                continue
            # The lines the canvas methods would append (setStrokeColorRGB, setLineWidth,
            # setDash, beginPath ... drawPath(stroke=1, fill=0)), written directly: the same
            # bytes at a fraction of the calls.  The canvas's remembered stroke colour and
            # width are not updated; only saveState/restoreState read them, never used here.
            code.append(_stroke_style_ops(item.colour, item.width_mm, item.dash_mm))
            key = (item.points_mm, item.closed)
            path = drawn.paths.get(key)
            if path is None:
                path = drawn.paths[key] = _path_ops(item.points_mm, item.closed, drawn.numbers)
            code.append(path)
            code.append("S")
        elif isinstance(item, Text):
            if not item.string:
                continue
            # setFillColorRGB's line; the canvas's remembered fill colour is not updated
            # (see above), and rects and circles set theirs through the canvas
            code.append(_fill_colour_op(item.colour))
            _draw_text(c, drawn.texts, fonts.face(spec.path(item.font)).key, item.size_pt,
                       item.anchor, _pt(item.x_mm), _pt(item.y_mm), item.string)
        elif isinstance(item, Rect):
            _style_area(c, item.colour, item.line_mm, item.fill)
            c.rect(_pt(item.x_mm), _pt(item.y_mm), _pt(item.w_mm), _pt(item.h_mm),
                   stroke=int(item.colour is not None), fill=int(item.fill is not None))
        elif isinstance(item, Circle):
            _style_area(c, item.colour, item.line_mm, item.fill)
            c.circle(_pt(item.cx_mm), _pt(item.cy_mm), _pt(item.r_mm),
                     stroke=int(item.colour is not None), fill=int(item.fill is not None))
        else:
            raise RenderError(f"cannot draw a {type(item).__name__} item")


def _style_area(c, colour: str | None, line_mm: float, fill: str | None) -> None:
    c.setDash([], 0)
    if colour is not None:
        c.setStrokeColorRGB(*_rgb(colour))
        c.setLineWidth(_pt(line_mm))
    if fill is not None:
        c.setFillColorRGB(*_rgb(fill))


def pdf_bytes(pages: Sequence[Page]) -> bytes:
    """The PDF of ``pages``: one PDF page per page, MediaBox = page size, outline, no scaling.

    Raises:
        RenderError: no pages, or an item the renderer does not know.
    """
    from reportlab.pdfgen import canvas

    if not pages:
        raise RenderError("nothing to render: no pages")
    buf = io.BytesIO()
    first = pages[0]
    c = canvas.Canvas(buf, pagesize=(_pt(first.width_mm), _pt(first.height_mm)), invariant=1,
                      pageCompression=1)
    c.setTitle(first.title or "h2s workbook")
    c.setCreator(PRODUCER)
    c.setProducer(PRODUCER)
    c.setViewerPreference("PrintScaling", "None")
    level = -1
    has_outline = False
    drawn = _Drawn()
    for n, page in enumerate(pages):
        c.setPageSize((_pt(page.width_mm), _pt(page.height_mm)))
        _draw_page(c, page, drawn)
        for j, mark in enumerate(page.bookmarks):
            key = f"p{n}b{j}"
            c.bookmarkPage(key, fit="Fit")
            # An outline can only go one level deeper at a time.
            level = max(0, min(mark.level, level + 1))
            c.addOutlineEntry(mark.title, key, level=level, closed=level >= 2)
            has_outline = True
        c.showPage()
    if has_outline:
        c.showOutline()
    c.save()
    return buf.getvalue()


def render_pdf(pages: Sequence[Page], path: Path) -> None:
    """Write ``pages`` as a PDF at ``path`` atomically (temp file in the same folder, then
    ``os.replace``), so a failed run never leaves a half-written PDF.

    Raises:
        RenderError: naming ``path``, when it cannot be written (or nothing to render).
    """
    path = Path(path)
    data = pdf_bytes(pages)
    write_bytes_atomic(path, data)
    log.debug("%s: %d pages, %d bytes", path, len(pages), len(data))


# ----------------------------------------------------------------------------- SVG / PNG


def _num(v: float) -> str:
    s = f"{v:.3f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def _svg_colour(name: str | None) -> str:
    if name is None:
        return "none"
    r, g, b = _rgb(name)
    return f"rgb({round(r * 255)},{round(g * 255)},{round(b * 255)})"


def render_svg(page: Page, *, measure: Callable[[Text], float] | None = None) -> str:
    """One page as a standalone SVG (size in mm, ``viewBox`` in mm, y flipped to point down).

    Every :class:`~h2s_print.layout.Polyline` becomes one ``<polyline>`` (or ``<polygon>`` when
    closed), every text one ``<text>``; a white background ``<rect>`` comes first.

    Texts name the page font's family (:mod:`h2s_print.fonts`) and carry the width the
    layout measured in it as ``textLength``.  ``measure`` (text item -> width in mm in the
    font the rasteriser will really use) makes each text also scaled horizontally to that
    width, for rasterisers that ignore ``textLength`` (cairosvg) and may substitute a font.
    """
    spec = page.font or fonts.current()
    with fonts.using(spec):
        return _svg(page, spec, measure)


def _svg(page: Page, spec: fonts.FontSpec, measure: Callable[[Text], float] | None) -> str:
    w, h = page.width_mm, page.height_mm
    out = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{_num(w)}mm" '
        f'height="{_num(h)}mm" viewBox="0 0 {_num(w)} {_num(h)}">',
        f'<rect x="0" y="0" width="{_num(w)}" height="{_num(h)}" fill="white"/>',
    ]
    for item in page.items:
        if isinstance(item, Polyline):
            if len(item.points_mm) < 2:
                continue
            pts = " ".join(f"{_num(x)},{_num(h - y)}" for x, y in item.points_mm)
            tag = "polygon" if item.closed else "polyline"
            dash = (f' stroke-dasharray="{" ".join(_num(d) for d in item.dash_mm)}"'
                    if item.dash_mm else "")
            out.append(f'<{tag} points="{pts}" fill="none" stroke="{_svg_colour(item.colour)}" '
                       f'stroke-width="{_num(item.width_mm)}" stroke-linejoin="round"{dash}/>')
        elif isinstance(item, Text):
            if not item.string:
                continue
            family = fonts.face(spec.path(item.font)).family
            weight = ' font-weight="bold"' if item.font.endswith("Bold") else ""
            style = ' font-style="oblique"' if item.font.endswith("Oblique") else ""
            want = text_width_mm(item.string, item.size_pt, item.font)
            fit = ""
            if measure is not None:
                got = measure(item)
                if got > 0 and abs(want / got - 1) > 1e-3:
                    x, y = _num(item.x_mm), _num(h - item.y_mm)
                    fit = (f' transform="translate({x} {y}) scale({want / got:.4f} 1) '
                           f'translate(-{x} -{y})"')
            out.append(f'<text x="{_num(item.x_mm)}" y="{_num(h - item.y_mm)}"{fit} '
                       f'font-family="\'{escape(family.replace(chr(39), ""), {chr(34): "&quot;"})}\', sans-serif" '
                       f'font-size="{_num(item.size_pt * PT_MM)}"{weight}{style} '
                       f'text-anchor="{item.anchor}" fill="{_svg_colour(item.colour)}" '
                       # the layout measured the text in the page font; a viewer without
                       # it (a substitute font) is told to keep that width
                       f'textLength="{_num(want)}" '
                       f'lengthAdjust="spacingAndGlyphs">'
                       f'{escape(item.string)}</text>')
        elif isinstance(item, Rect):
            out.append(f'<rect x="{_num(item.x_mm)}" y="{_num(h - item.y_mm - item.h_mm)}" '
                       f'width="{_num(item.w_mm)}" height="{_num(item.h_mm)}" '
                       f'fill="{_svg_colour(item.fill)}" stroke="{_svg_colour(item.colour)}" '
                       f'stroke-width="{_num(item.line_mm)}"/>')
        elif isinstance(item, Circle):
            out.append(f'<circle cx="{_num(item.cx_mm)}" cy="{_num(h - item.cy_mm)}" '
                       f'r="{_num(item.r_mm)}" fill="{_svg_colour(item.fill)}" '
                       f'stroke="{_svg_colour(item.colour)}" stroke-width="{_num(item.line_mm)}"/>')
        else:
            raise RenderError(f"cannot draw a {type(item).__name__} item")
    out.append("</svg>")
    return "\n".join(out) + "\n"


def render_png(page: Page, dpi: float = 150.0) -> bytes:
    """One page as PNG bytes at ``dpi`` (rasterised from :func:`render_svg` by cairosvg, in
    the page font: its files are added to fontconfig first)."""
    import cairosvg

    if not dpi > 0:
        raise RenderError(f"png dpi must be positive, got {dpi}")
    spec = page.font or fonts.current()
    for style in fonts.STYLES:
        fonts.fontconfig_add(spec.path(style))
    svg = render_svg(page, measure=lambda item: _cairo_width_mm(item, spec))
    return cairosvg.svg2png(bytestring=svg.encode("utf-8"), dpi=dpi)


def _cairo_width_mm(item: Text, spec: fonts.FontSpec | None = None) -> float:
    """Width of a text item in the font cairo really picks for the page font's family
    (fontconfig may substitute another face), mm; measured the way cairosvg selects it."""
    import cairocffi as cairo

    ctx = _cairo_context()
    family = fonts.face((spec or fonts.current()).path(item.font)).family
    slant = cairo.FONT_SLANT_OBLIQUE if item.font.endswith("Oblique") else cairo.FONT_SLANT_NORMAL
    weight = cairo.FONT_WEIGHT_BOLD if item.font.endswith("Bold") else cairo.FONT_WEIGHT_NORMAL
    ctx.select_font_face(family, slant, weight)
    # measured at 100 units and scaled: at a few units cairo rounds (hints) each advance
    ctx.set_font_size(100.0)
    return float(ctx.text_extents(item.string)[4]) * item.size_pt * PT_MM / 100.0


@functools.lru_cache(maxsize=1)
def _cairo_context():
    import cairocffi as cairo

    return cairo.Context(cairo.ImageSurface(cairo.FORMAT_ARGB32, 1, 1))
