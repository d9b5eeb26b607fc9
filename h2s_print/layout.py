"""Layout stage (DESIGN.md §2.9): steps + templates + paper -> pages, every coordinate in mm.

Nothing here draws: each page is a frozen :class:`Page` holding frozen items (:class:`Polyline`,
:class:`Text`, :class:`Rect`, :class:`Circle`) in page millimetres, origin at the page's
bottom-left corner, x to the right, y up (the sheet's own convention).  ``render.py`` turns
pages into PDF/SVG/PNG.

Public verbs: :func:`lay_out_workbook` (its last page from :mod:`h2s_print.sheet`),
:func:`lay_out_book`, and
:func:`primer_diagrams` (the primer's figures: ``h2s_print.constructions`` built in 3D on one
face and projected by a ``h2s_print.project`` camera, isolated in one function).

Decisions where the brief is silent (documented here, kept in one place):

* **Steps per page**: novice workbooks show one step per page (bigger panel, more guides to
  read); every other level two, side by side on a landscape page, stacked on a portrait page.
* **Colours and greyscale**: each line style differs in weight *and* dash pattern so a greyscale
  print stays readable (see :data:`STYLES` and the legend on every step page): earlier strokes
  thin grey solid; this step's strokes thick orange solid; new guides orange dashed; guides
  reused in this step blue dash-dot; guides still on the paper but idle in this step (alive,
  waiting for a later use, paper §5 "guide lifetime") thin blue dotted; vanishing lines thin
  light-grey long dashes.  A guide disappears after its last use (``Step.alive``).
* **Vanishing lines** in a step panel: for each finite vanishing point, the two lines from the
  VP that just enclose this step's new strokes (the outermost of the strokes' box corners as
  seen from the VP), clipped to the panel; VPs inside the panel get a mark and a label.
* **Frame and green corners**: the sheet's frame is the drawing area inside the paper margins;
  its corners are green in every panel and on the calibrated sheet, so the two correspond.
* **Estimated time**: :func:`estimate_minutes` counts what the pages make the reader draw, at
  a beginner's pace: half a minute to read a step, 10 s per ruler line, a minute per scaffold
  box and per part outlined, half a minute per ellipse; rounded up to 5 minutes (the paper
  reports 15-45 minutes per tutorial of its four objects).
* **Text**: one embedded Unicode font (:mod:`h2s_print.fonts`: DejaVu Sans, or the config's
  ``font:``), measured in its own advance widths, so wrapped widths equal printed widths;
  ``Text.font`` names a style (``Helvetica``, ``-Bold``, ``-Oblique``) of the page's font.
* **Calibrated sheet**: an off-sheet vanishing point is an arrow on the frame (along the
  horizon when the VP lies on it, else from the frame's centre) labelled with its distance from
  the arrow's tip and its offset from the nearest green corner ("603 mm left, 48 mm down from
  the top-left green corner"), so it can be found with a ruler on a larger surface.  Labels
  that could collide (horizon, ground plane) take the first of a few positions that overlaps
  no other text.  Vanishing points are named as the step texts name them (:func:`vp_names`:
  "right vanishing point", "vanishing point above" ..., by :func:`h2s_print.project.vp_side`
  from the sheet's centre), on the sheet and in the step panels; part names print with
  spaces ("shutter_button" -> "shutter button").  Horizon and arrow tips come from
  :func:`h2s_print.project.horizon_mm` and :func:`h2s_print.project.edge_exit`.
* **Control condition** (level ``basic``): no primer page, a cover without guide or erasing
  wording (``cover.how_basic``), a key without guide styles (no step has guides) but the
  sheet's printed lines, which its step 1 draws on as the guided tutorial's does
  (:func:`_control_printed`), and the level is shown as plain "basic", so the control
  workbook never mentions guides.
* **Book outline**: a workbook label ``"Camera > front-left > novice"`` (parts joined by
  :data:`OUTLINE_SEP`) gives outline levels tutorial > view > level; the workbook's own
  bookmarks (cover, primer, steps ...) sit one level below.
"""

from __future__ import annotations

import functools
import itertools
import logging
import math
import re
from dataclasses import dataclass, replace
from typing import Any, Callable, Iterable, Sequence

import numpy as np

from . import fonts, templates
from .config import MIN_MARGIN_MM, PaperSpec, ViewSpec
from .constructions import Face, construct, ellipse_on_face
from .errors import RenderError
from .glyphs import ascii_font, printable, spelled
from .project import first_scaffold_lines, make_camera, vp_side
from .sequence.geometry import ALONG_MM
from .types import Guide, Label, Step, Stroke, ViewPlan

log = logging.getLogger(__name__)

PT_MM = 25.4 / 72.0  #: millimetres per PostScript point
OUTLINE_SEP = " > "
#: The time estimate (:func:`estimate_minutes`), a beginner's pace: reading a step (15 s: a
#: headline and sub-steps of about 35 words), one ruler line toward a vanishing point (10 s),
#: a part's scaffold box (45 s), one ellipse (30 s), one part's outlines (45 s).  Calibrated
#: on the paper's four objects (§6: "each tutorial takes between 15 and 45 minutes"): with
#: these, the camera, mixer, train and roller examples come out at 20-45 minutes novice and
#: 15-30 master, every view; the earlier 30 s a step and a minute a box and an outline put the
#: train at 55 minutes (test_layout.test_the_papers_objects_take_15_to_45_minutes).
READ_MINUTES = 0.25
GUIDE_MINUTES = 1.0 / 6.0
BOX_MINUTES = 0.75
ELLIPSE_MINUTES = 0.5
OUTLINE_MINUTES = 0.75

#: Colour roles used by items, as RGB in 0..1 (the renderer's palette).
COLOURS: dict[str, tuple[float, float, float]] = {
    "black": (0.0, 0.0, 0.0),
    "grey": (0.55, 0.55, 0.55),
    "lightgrey": (0.72, 0.72, 0.72),
    "orange": (0.93, 0.45, 0.0),
    "blue": (0.05, 0.33, 0.85),
    "green": (0.0, 0.62, 0.23),
    "white": (1.0, 1.0, 1.0),
}


@dataclass(frozen=True, slots=True)
class LineStyle:
    """How one kind of line is drawn: colour role, width in mm, dash pattern in mm."""

    colour: str
    width_mm: float
    dash_mm: tuple[float, ...] = ()


#: Line styles by meaning (legend keys of ``templates/pages.yaml``).
STYLES: dict[str, LineStyle] = {
    "earlier": LineStyle("grey", 0.3),
    "earlier_hidden": LineStyle("lightgrey", 0.2, (1.0, 1.0)),
    "ink": LineStyle("black", 0.45),
    "new": LineStyle("orange", 0.7),
    "new_hidden": LineStyle("orange", 0.3, (1.0, 1.0)),
    "guide_new": LineStyle("orange", 0.35, (2.4, 1.2)),
    "guide_reused": LineStyle("blue", 0.35, (2.4, 0.9, 0.5, 0.9)),
    "guide_idle": LineStyle("blue", 0.2, (0.4, 1.0)),
    "guide_sheet": LineStyle("blue", 0.3, (2.0, 1.0)),  # as the sheet prints them
    "vanishing": LineStyle("lightgrey", 0.2, (5.0, 2.0)),
    "corner": LineStyle("green", 0.8),
    "frame": LineStyle("lightgrey", 0.2),
    "final": LineStyle("black", 0.4),
    "face": LineStyle("black", 0.4),
    "construction": LineStyle("orange", 0.25, (1.6, 1.0)),
    "result": LineStyle("orange", 0.6),
    # a close-up's frames (the small one and the enlargement): no line of the drawing
    "close_up": LineStyle("green", 0.25, (1.5, 1.0)),
}


# ----------------------------------------------------------------------------- page items


@dataclass(frozen=True, slots=True)
class Polyline:
    """An open or closed polyline.

    Attributes:
        points_mm: vertices on the page, mm.
        colour: a key of :data:`COLOURS`.
        width_mm: stroke width, mm.
        dash_mm: dash pattern (on, off, ...) in mm; empty for solid.
        closed: join the last vertex to the first.
        role: what it shows (``stroke``, ``guide``, ``scale_bar`` ...), for tests and exports.
    """

    points_mm: tuple[tuple[float, float], ...]
    colour: str = "black"
    width_mm: float = 0.3
    dash_mm: tuple[float, ...] = ()
    closed: bool = False
    role: str = ""


@dataclass(frozen=True, slots=True)
class Text:
    """One line of text (already :func:`plain_text`) in the page's font.

    Attributes:
        x_mm, y_mm: anchor point on the baseline, mm.
        string: the text.
        size_pt: font size, points.
        font: the style: ``Helvetica`` (regular), ``Helvetica-Bold`` or ``Helvetica-Oblique``
            (names of old; the face is the page font's: :data:`h2s_print.fonts.STYLES`).
        anchor: ``start``, ``middle`` or ``end`` (which point of the line sits at ``x_mm``).
        colour: a key of :data:`COLOURS`.
        role: what it shows (``instruction``, ``title`` ...).
    """

    x_mm: float
    y_mm: float
    string: str
    size_pt: float
    font: str = "Helvetica"
    anchor: str = "start"
    colour: str = "black"
    role: str = ""

    @property
    def box_mm(self) -> tuple[float, float, float, float]:
        """(x0, y0, x1, y1) of the inked area, from descender to cap height, mm."""
        return self.box_at(self.x_mm, self.y_mm)

    def box_at(self, x_mm: float, y_mm: float) -> tuple[float, float, float, float]:
        """:attr:`box_mm` of this text anchored at ``(x_mm, y_mm)`` instead."""
        width = text_width_mm(self.string, self.size_pt, self.font)
        x0 = x_mm - {"start": 0.0, "middle": width / 2, "end": width}[self.anchor]
        size = self.size_pt * PT_MM
        return (x0, y_mm - 0.21 * size, x0 + width, y_mm + 0.72 * size)


@dataclass(frozen=True, slots=True)
class Rect:
    """An axis-aligned rectangle: lower-left corner and size in mm, optional fill."""

    x_mm: float
    y_mm: float
    w_mm: float
    h_mm: float
    colour: str | None = "black"
    line_mm: float = 0.2
    fill: str | None = None
    role: str = ""


@dataclass(frozen=True, slots=True)
class Circle:
    """A circle: centre and radius in mm, optional fill."""

    cx_mm: float
    cy_mm: float
    r_mm: float
    colour: str | None = "black"
    line_mm: float = 0.2
    fill: str | None = None
    role: str = ""


Item = Polyline | Text | Rect | Circle


@dataclass(frozen=True, slots=True)
class Bookmark:
    """A PDF outline entry pointing at its page; ``level`` 0 is the top."""

    title: str
    level: int = 0


@dataclass(frozen=True, slots=True)
class Page:
    """One laid-out page.

    Attributes:
        width_mm, height_mm: the page (= PDF MediaBox), mm.
        items: drawn in order (later on top).
        bookmarks: outline entries that point at this page, in outline order.
        kind: ``cover``, ``primer``, ``steps``, ``final``, ``sheet``, ``title``, ``contents``.
        title: the document title this page belongs to (PDF metadata).
        margin_mm: the blank border the page was laid out with, mm.
        font: the font its texts were measured in and are drawn in (:mod:`h2s_print.fonts`);
            ``None``: the current one when rendered.
    """

    width_mm: float
    height_mm: float
    items: tuple[Item, ...]
    bookmarks: tuple[Bookmark, ...] = ()
    kind: str = ""
    title: str = ""
    margin_mm: float = 12.0
    font: fonts.FontSpec | None = None


# ----------------------------------------------------------------------------- text


def plain_text(string: str) -> str:
    """``string`` as the current page font (:mod:`h2s_print.fonts`) prints it: a character
    the font lacks is spelled when :data:`h2s_print.glyphs.SPELL` knows a spelling it has
    (``⅓`` -> ``1/3`` in a font without the fraction), and as a last resort ``?`` (user text
    and templates are checked against the font before any layout, so that does not happen
    silently: :func:`h2s_print.glyphs.unprintable`)."""
    text = str(string)
    if text.isascii() and "\t" not in text and "\n" not in text and ascii_font():
        return text  # nearly every text on a page: nothing to spell (measured: 1.2 s a book)
    return text.translate(_printed_as(fonts.current(), text))


#: Per font: code point -> how :func:`plain_text` prints it, each worked out once.
_PRINTED_AS: dict[fonts.FontSpec, dict[int, str]] = {}


def _printed_as(spec: fonts.FontSpec, text: str) -> dict[int, str]:
    """The table ``str.translate`` prints ``text`` by in ``spec`` (the current font): each of
    its characters ``spelled(ch) if printable(ch) else "?"``, worked out the first time the
    font meets the character: three glyph checks a character, on every text that is not
    plain ASCII (book, --jobs 1: plain_text 0.06 -> 0.02 s, bytes identical)."""
    table = _PRINTED_AS.setdefault(spec, {})
    for code in set(map(ord, text)).difference(table):
        ch = chr(code)
        table[code] = spelled(ch) if printable(ch) else "?"
    return table


def text_width_mm(string: str, size_pt: float, font: str = "Helvetica") -> float:
    """Advance width of ``string`` (already plain) set in style ``font`` of the current page
    font at ``size_pt``, mm."""
    return fonts.width_mm(string, size_pt, font)


def wrap(string: str, width_mm: float, size_pt: float, font: str = "Helvetica") -> list[str]:
    """Greedy word wrap of ``string`` into lines no wider than ``width_mm`` (long words split);
    lines break at plain spaces only, never at a no-break space (French « : », Russian
    «с. 3»)."""
    return list(_wrapped(plain_text(string), width_mm, size_pt, font, fonts.current()))


@functools.lru_cache(maxsize=1 << 12)
def _wrapped(text: str, width_mm: float, size_pt: float, font: str,
             spec: fonts.FontSpec) -> tuple[str, ...]:
    """:func:`wrap` of plain ``text`` measured in ``spec``, remembered: layout wraps the same
    texts at the same widths again and again while it fits them (the example book: 6119
    wraps of 1192 distinct ones, 155 000 widths measured)."""
    def width(s: str) -> float:
        return fonts.width_mm(s, size_pt, font, spec)

    words = [w for w in re.split(r"[ \t\n\r]+", text) if w]
    lines: list[str] = []
    line = ""
    for word in words:
        while width(word) > width_mm and len(word) > 1:
            cut = len(word) - 1
            while cut > 1 and width(word[:cut]) > width_mm:
                cut -= 1
            if line:
                lines.append(line)
                line = ""
            lines.append(word[:cut])
            word = word[cut:]
        trial = f"{line} {word}" if line else word
        if width(trial) <= width_mm:
            line = trial
        else:
            lines.append(line)
            line = word
    if line:
        lines.append(line)
    return tuple(lines)


def fit_line(string: str, width_mm: float, size_pt: float, font: str = "Helvetica",
             smallest_pt: float = 5.0) -> float:
    """The largest size, from ``size_pt`` down to ``smallest_pt`` in half points, at which
    ``string`` fits on one line ``width_mm`` wide: a one-line text (a header, a stamp) is set
    smaller rather than cut.

    Raises:
        RenderError: it does not fit even at ``smallest_pt`` (never cut silently).
    """
    size = size_pt
    while size >= smallest_pt:
        if text_width_mm(string, size, font) <= width_mm:
            return size
        size -= 0.5
    raise RenderError(f"text does not fit on one line of {width_mm:.0f} mm even at "
                      f"{smallest_pt:g} pt: {string!r}")


def _leading(size_pt: float) -> float:
    """Baseline-to-baseline distance for ``size_pt`` text, mm."""
    return 1.25 * size_pt * PT_MM


def _paragraph(x: float, top: float, width: float, string: str, size: float, *,
               font: str = "Helvetica", role: str = "", colour: str = "black",
               anchor: str = "start") -> tuple[list[Text], float]:
    """Wrapped text whose first line's cap height touches ``top``; returns items and the
    y of the paragraph's bottom (last baseline's descender), mm."""
    lines = wrap(string, width, size, font)
    lead = _leading(size)
    y = top - 0.72 * size * PT_MM
    items = []
    for line in lines:
        items.append(Text(x, y, line, size, font, anchor, colour, role))
        y -= lead
    bottom = (y + lead) - 0.21 * size * PT_MM if lines else top
    return items, bottom


def _paragraph_height(string: str, width: float, size: float, font: str = "Helvetica") -> float:
    n = len(wrap(string, width, size, font))
    return 0.0 if n == 0 else (n - 1) * _leading(size) + 0.93 * size * PT_MM


def _t(key: str, **fields) -> str:
    return plain_text(templates.text("pages", key, **fields))


# ----------------------------------------------------------------------------- geometry

Pt = tuple[float, float]
Box2 = tuple[float, float, float, float]  # x0, y0, x1, y1


def _clip_segment(p: Pt, q: Pt, box: Box2) -> tuple[Pt, Pt] | None:
    """Liang-Barsky: the part of segment pq inside ``box``, or None."""
    x0, y0, x1, y1 = box
    dx, dy = q[0] - p[0], q[1] - p[1]
    t0, t1 = 0.0, 1.0
    for pk, qk in ((-dx, p[0] - x0), (dx, x1 - p[0]), (-dy, p[1] - y0), (dy, y1 - p[1])):
        if pk == 0:
            if qk < 0:
                return None
            continue
        t = qk / pk
        if pk < 0:
            t0 = max(t0, t)
        else:
            t1 = min(t1, t)
        if t0 > t1:
            return None
    return ((p[0] + t0 * dx, p[1] + t0 * dy), (p[0] + t1 * dx, p[1] + t1 * dy))


def clip_polyline(points: Sequence[Pt], box: Box2, closed: bool = False) -> list[list[Pt]]:
    """Pieces of a polyline inside ``box`` (each piece a list of >= 2 points)."""
    pts = list(points)
    if closed and len(pts) > 2:
        pts = pts + [pts[0]]
    if len(pts) >= 2 and all(box[0] <= x <= box[2] and box[1] <= y <= box[3] for x, y in pts):
        return [pts]  # inside whole: one piece, its own points (the clipping would recompute them)
    pieces: list[list[Pt]] = []
    current: list[Pt] = []
    for p, q in zip(pts, pts[1:]):
        seg = _clip_segment(p, q, box)
        if seg is None:
            if len(current) >= 2:
                pieces.append(current)
            current = []
            continue
        a, b = seg
        if current and math.dist(current[-1], a) < 1e-9:
            current.append(b)
        else:
            if len(current) >= 2:
                pieces.append(current)
            current = [a, b]
        if math.dist(b, q) > 1e-9:  # left the box: the piece ends here
            pieces.append(current)
            current = []
    if len(current) >= 2:
        pieces.append(current)
    return pieces


def _bbox(points: Iterable[Pt]) -> Box2 | None:
    pts = list(points)
    if not pts:
        return None
    xs = [p[0] for p in pts]
    ys = [p[1] for p in pts]
    return (min(xs), min(ys), max(xs), max(ys))


@dataclass(frozen=True, slots=True)
class _View:
    """Maps a window of sheet mm onto a page rectangle (uniform scale), clipping to it."""

    window: Box2  # sheet mm
    rect: Box2  # page mm, same aspect as window

    @property
    def scale(self) -> float:
        return (self.rect[2] - self.rect[0]) / (self.window[2] - self.window[0])

    def map(self, p: Pt) -> Pt:
        s = self.scale
        return (self.rect[0] + (p[0] - self.window[0]) * s, self.rect[1] + (p[1] - self.window[1]) * s)

    def map_all(self, points: Iterable[Pt]) -> list[Pt]:
        """:meth:`map` of each of ``points`` (the same arithmetic, the scale worked out once:
        a book maps 150 000 points)."""
        s = self.scale
        rx, ry = self.rect[0], self.rect[1]
        wx, wy = self.window[0], self.window[1]
        return [(rx + (p[0] - wx) * s, ry + (p[1] - wy) * s) for p in points]

    def lines(self, points: Sequence[Pt], style: LineStyle, role: str,
              closed: bool = False) -> list[Polyline]:
        mapped = self.map_all(points)
        # A hair of slack so lines lying exactly on the rectangle's edge survive rounding.
        x0, y0, x1, y1 = self.rect
        box = (x0 - 1e-7, y0 - 1e-7, x1 + 1e-7, y1 + 1e-7)
        return [Polyline(tuple(piece), style.colour, style.width_mm, style.dash_mm, False, role)
                for piece in clip_polyline(mapped, box, closed)]


def _fit(window: Box2, area: Box2, top: bool = False) -> _View:
    """The largest rectangle of ``window``'s aspect in ``area``: centred, or (``top``) centred
    horizontally and touching the area's top."""
    ww, wh = window[2] - window[0], window[3] - window[1]
    aw, ah = area[2] - area[0], area[3] - area[1]
    s = min(aw / ww, ah / wh)
    x0 = area[0] + (aw - ww * s) / 2
    y0 = area[3] - wh * s if top else area[1] + (ah - wh * s) / 2
    return _View(window, (x0, y0, x0 + ww * s, y0 + wh * s))


def _green_corners(frame: Box2, arm: float, style: LineStyle = STYLES["corner"]) -> list[Polyline]:
    x0, y0, x1, y1 = frame
    out = []
    for cx, cy, sx, sy in ((x0, y0, 1, 1), (x1, y0, -1, 1), (x1, y1, -1, -1), (x0, y1, 1, -1)):
        out.append(Polyline(((cx + sx * arm, cy), (cx, cy), (cx, cy + sy * arm)),
                            style.colour, style.width_mm, (), False, "corner"))
    return out


def _arrow(tip: Pt, direction: Pt, length: float, colour: str, width: float, role: str,
           *, both: bool = False) -> list[Polyline]:
    """A shaft ending at ``tip`` pointing along ``direction`` with a two-stroke head (and one
    at its tail too, pointing back, when ``both``: a direction, not a point)."""
    dx, dy = direction
    n = math.hypot(dx, dy) or 1.0
    dx, dy = dx / n, dy / n
    tail = (tip[0] - dx * length, tip[1] - dy * length)
    head = min(2.5, length / 2)

    def barbs(at: Pt, ux: float, uy: float) -> Polyline:
        left = (at[0] - head * (ux * 0.87 - uy * 0.5), at[1] - head * (uy * 0.87 + ux * 0.5))
        right = (at[0] - head * (ux * 0.87 + uy * 0.5), at[1] - head * (uy * 0.87 - ux * 0.5))
        return Polyline((left, at, right), colour, width, (), False, role)

    return [Polyline((tail, tip), colour, width, (), False, role), barbs(tip, dx, dy)] + (
        [barbs(tail, -dx, -dy)] if both else [])


# ----------------------------------------------------------------------------- drawing panels


def _frame_box(sheet: tuple[float, float], margin: float) -> Box2:
    return (margin, margin, sheet[0] - margin, sheet[1] - margin)


def _window(sheet: tuple[float, float]) -> Box2:
    """The whole sheet: panels clip to the paper, so vanishing lines end where they leave it."""
    return (0.0, 0.0, float(sheet[0]), float(sheet[1]))


def _sheet_background(view: _View, sheet: tuple[float, float], margin: float) -> list[Item]:
    """Paper outline (light) and the frame with green corners, in a panel."""
    s = view.scale
    p0, p1 = view.map((0.0, 0.0)), view.map(sheet)
    f = _frame_box(sheet, margin)
    f0, f1 = view.map((f[0], f[1])), view.map((f[2], f[3]))
    items: list[Item] = [Rect(p0[0], p0[1], p1[0] - p0[0], p1[1] - p0[1], "lightgrey", 0.2,
                              None, "paper")]
    arm = max(3.0, 0.08 * min(sheet) * s)
    items += _green_corners((f0[0], f0[1], f1[0], f1[1]), arm)
    return items


def _step_guides(plan: ViewPlan, i: int) -> list[tuple[Guide, str]]:
    """Guides drawn at step ``i`` (0-based) with their style key, in a stable order.

    This step's guides (new / reused) plus guides still alive from earlier steps that this step
    does not use (idle, waiting for a later step): their geometry is their latest earlier use.
    """
    step = plan.steps[i]
    out: list[tuple[Guide, str]] = []
    used = set()
    for g in step.guides:
        out.append((g, "guide_sheet" if g.role == "sheet"
                    else "guide_new" if g.status == "new" else "guide_reused"))
        used.add(g.id)
    for gid in step.alive:
        if gid in used:
            continue
        for earlier in reversed(plan.steps[:i]):
            match = next((g for g in earlier.guides if g.id == gid), None)
            if match is not None:
                out.append((match, "guide_idle"))
                used.add(gid)
                break
    # Draw idle first (under), then reused, then new on top.
    order = {"guide_sheet": 0, "guide_idle": 1, "guide_reused": 2, "guide_new": 3}
    return sorted(out, key=lambda gs: order[gs[1]])


def _stroke_points(strokes: Iterable[Stroke]) -> list[Pt]:
    return [tuple(p) for s in strokes for p in s.points_mm]  # type: ignore[misc]


def _vanishing_lines(view: _View, plan: ViewPlan, strokes: Sequence[Stroke]) -> list[Item]:
    """Two lines per finite VP enclosing ``strokes``, clipped to the panel; VP marks inside it.

    Each line runs through a point of ``strokes`` (the outermost seen from the VP, mostly a
    corner of the new box), so that it lies along a line the step draws: through the
    corners of the strokes' bounding box they ran past the box, beside its edges (a
    read-through: "they don't pass through the handle's corners, so I couldn't use them")."""
    points = list(dict.fromkeys(_stroke_points(strokes)))
    box = _bbox(points)
    items: list[Item] = []
    style = STYLES["vanishing"]
    names = vp_names(plan)
    for vp in sorted(plan.vanishing_points, key=lambda v: v.axis):
        if vp.at_infinity or vp.xy_mm is None:
            continue
        v = (float(vp.xy_mm[0]), float(vp.xy_mm[1]))
        if box is not None:
            ref = math.atan2(((box[1] + box[3]) / 2) - v[1], ((box[0] + box[2]) / 2) - v[0])
            def rel(c: Pt) -> float:
                a = math.atan2(c[1] - v[1], c[0] - v[0]) - ref
                return (a + math.pi) % (2 * math.pi) - math.pi
            # each point's angle once; the first point of the least and of the greatest, as
            # min() and max() with key=rel pick them
            angles = [rel(c) for c in points]
            for corner in (points[angles.index(min(angles))], points[angles.index(max(angles))]):
                if math.dist(corner, v) < 1e-6:
                    continue
                # From beyond the corner (a quarter of the way back past it) to the VP.
                start = (corner[0] + 0.25 * (corner[0] - v[0]), corner[1] + 0.25 * (corner[1] - v[1]))
                items += view.lines([start, v], style, "vanishing")
        p = view.map(v)
        r = view.rect
        if r[0] <= p[0] <= r[2] and r[1] <= p[1] <= r[3]:
            items.append(Circle(p[0], p[1], 0.9, "black", 0.25, None, "vp"))
            label = _t("sheet.vp", vp=names[vp.axis])
            anchor = "end" if p[0] > (r[0] + r[2]) / 2 else "start"
            dx = -1.6 if anchor == "end" else 1.6
            ty = p[1] + 1.2 if p[1] + 4 < r[3] else p[1] - 3.2
            items.append(Text(p[0] + dx, ty, label, 7, "Helvetica", anchor, "black", "vp_label"))
    return items


def _step_panel(view: _View, plan: ViewPlan, i: int, margin: float,
                room: Box2 | None = None,
                memo: dict[Any, Any] | None = None
                ) -> list[Item]:
    """The cumulative drawing at step ``i`` (0-based) in ``view``, lettered; crowded letters,
    or a part too small to follow, go in a close-up (:func:`_close_up`), beside the picture
    within ``room`` or in it.  ``memo``: :func:`_drawing`'s."""
    step = plan.steps[i]
    items: list[Item] = _sheet_background(view, plan.paper_mm, margin)
    drawing = _drawing(view, plan, i, memo)
    items += drawing
    # the segments of every line at once: all of them, the object's lines and the paper
    # corners (what a close-up must not hide), the step's new lines (what a letter keeps off)
    lines = [it for it in items if isinstance(it, Polyline)]
    segs, owner = _line_segments(lines)
    kept = segs[np.array([ln.role.startswith("stroke") or ln.role == "corner"
                          for ln in lines], dtype=bool)[owner]]
    new = segs[np.array([ln.role == "stroke_new" for ln in lines], dtype=bool)[owner]]
    zoom = _close_up(view, step, segs, kept, room)
    if zoom is None:
        return items + place_labels(view, step.labels, items, segs=segs, new=new)
    region, zview, small = zoom

    def inside(lb: Label) -> bool:  # labels of what the close-up shows go there
        x, y = view.map(lb.at_mm)
        return region[0] <= x <= region[2] and region[1] <= y <= region[3]

    # crowded letters: the letters in the close-up's region there, the parts' names and the
    # other letters on the picture; a small part: every label it shows in the close-up
    there = [lb for lb in step.labels if inside(lb) and (small or lb.kind == "point")]
    x0, y0, x1, y1 = zview.rect
    style = STYLES["close_up"]
    frames = [Polyline(((a, b), (c, b), (c, d), (a, d)), style.colour, style.width_mm,
                       style.dash_mm, True, "close_up_frame") for a, b, c, d in (region, zview.rect)]
    zlines = _drawing(zview, plan, i)
    try:
        close = place_labels(zview, there, zlines + [frames[1]])
    except RenderError:
        if not small:
            raise
        # the names do not fit the close-up (the oven's five buttons): on the picture
        there = [lb for lb in there if lb.kind == "point"]
        close = place_labels(zview, there, zlines + [frames[1]])
    items += place_labels(view, [lb for lb in step.labels if lb not in there], items,
                          segs=segs, new=new)
    items += [Rect(region[0], region[1], region[2] - region[0], region[3] - region[1],
                   None, 0.0, None, "close_up_region"), frames[0],
              Rect(x0, y0, x1 - x0, y1 - y0, None, 0.0, "white", "close_up")]
    # its caption outside it, on the side toward the middle of the picture
    size, cap = CLOSE_UP_CAPTION_PT, CLOSE_UP_CAPTION_MM
    caption = _t("step.close_up")
    if x0 > view.rect[2] or x1 < view.rect[0]:
        # beside the picture: wrapped to the close-up's column, so that it never runs into
        # the picture (a read-through: the roller's and the desk's ran across its border)
        width = max(x1 - x0, CLOSE_UP_CAPTION_MIN_MM)
        rows = wrap(caption, width, size, "Helvetica-Oblique")
        left = x1 < view.rect[0]  # left of the picture: the column ends at the close-up's edge
        step_y = cap + 1.0
        below = _caption_below(view.rect, (x0, y0, x1, y1), len(rows) * step_y)
        for k, row in enumerate(rows):
            y = y0 - 1.0 - cap - k * step_y if below else y1 + 1.0 + (len(rows) - 1 - k) * step_y
            items.append(Text(x1 if left else x0, y, row, size, "Helvetica-Oblique",
                              "end" if left else "start", "green", "close_up_caption"))
        return items + zlines + [frames[1]] + close
    items.append(_close_up_caption(view.rect, zview.rect))
    return items + zlines + [frames[1]] + close


def _caption_below(picture: Box2, box: Box2, need: float) -> bool:
    """Does a close-up's caption, ``need`` mm tall with its gap, go below the close-up
    ``box`` (page y up)?  Toward the middle of the picture, unless only the other side keeps
    it level with the picture (a read-through: a close-up beside the picture, about as tall
    as it, had its caption over the page's header)."""
    fits_below = box[1] - need >= picture[1] - 1e-9
    fits_above = box[3] + need <= picture[3] + 1e-9
    if fits_below != fits_above:
        return fits_below
    return (box[1] + box[3]) / 2 > (picture[1] + picture[3]) / 2


def _beside_caption_rows() -> list[str]:
    """The caption of a close-up beside the picture, wrapped to its narrowest column (the
    most rows it can take)."""
    return wrap(_t("step.close_up"), CLOSE_UP_CAPTION_MIN_MM, CLOSE_UP_CAPTION_PT,
                "Helvetica-Oblique")


def _close_up_caption(picture: Box2, box: Box2) -> Text:
    """A close-up's caption in the picture, outside the close-up ``box``: above it in the
    picture's lower half, else below, unless only the other side keeps it level with the
    picture (a read-through: a close-up beside the picture, as tall as it, had its caption
    over the page's header); running right from its left edge, or, too long for the picture
    that way (a German caption ran off the page), ending at its right edge."""
    x0, y0, x1, y1 = box
    size, cap = CLOSE_UP_CAPTION_PT, CLOSE_UP_CAPTION_MM
    below = _caption_below(picture, box, 1.0 + cap)
    caption = _t("step.close_up")
    right = x0 + text_width_mm(caption, size, "Helvetica-Oblique") > picture[2]
    return Text(x1 if right else x0, y0 - 1.0 - cap if below else y1 + 1.0, caption, size,
                "Helvetica-Oblique", "end" if right else "start", "green", "close_up_caption")


#: A step's lettered points get a close-up when two of them lie closer than this on the
#: picture (page mm; about two letter heights), or when at least
#: :data:`CLOSE_UP_DENSE_LETTERS` share their bounding box at less than
#: :data:`CLOSE_UP_ROOM_MM2` each (nine letters on a 12 mm ellipse) ...
CLOSE_UP_CROWDED_MM = 5.0
CLOSE_UP_DENSE_LETTERS = 5
CLOSE_UP_ROOM_MM2 = 40.0
#: ... magnified so that those two lie this far apart, at most :data:`CLOSE_UP_MAX_ZOOM`
#: times, and only if at least :data:`CLOSE_UP_MIN_ZOOM` times fits (less is not worth the
#: part of the picture it covers).
CLOSE_UP_SPACING_MM = 9.0
CLOSE_UP_MAX_ZOOM = 3.0
CLOSE_UP_MIN_ZOOM = 1.6
#: The close-up is at most this share of the picture's width and of its height, ...
CLOSE_UP_SHARE = 0.45
#: ... shows this much round the points (page mm, before magnifying) ...
CLOSE_UP_PAD_MM = 3.0
#: ... and sits this far inside a corner of the picture, with a caption of this size beside it
#: (the room for it is kept, :func:`_close_up`).
CLOSE_UP_INSET_MM = 1.5
#: In the picture, a close-up is also tried on a grid of this many steps each way.
CLOSE_UP_GRID = 6
CLOSE_UP_CAPTION_PT = 6.5
#: ... whose capitals are this tall (mm).
CLOSE_UP_CAPTION_MM = 0.72 * CLOSE_UP_CAPTION_PT * PT_MM
#: A caption beside the picture is wrapped to its close-up's width, but no narrower than this.
CLOSE_UP_CAPTION_MIN_MM = 24.0
#: A step whose new lines all fit in a square this wide on the picture (page mm) draws a part
#: too small to follow (the oven's five buttons, one orange blob 8 mm wide): it gets a
#: close-up too, magnified toward :data:`CLOSE_UP_SMALL_TARGET_MM` across.
CLOSE_UP_SMALL_MM = 12.0
CLOSE_UP_SMALL_TARGET_MM = 36.0


def _close_up(view: _View, step: Step, segs: np.ndarray, drawn: np.ndarray,
              room: Box2 | None = None) -> tuple[Box2, _View, bool] | None:
    """Where a crowded step's letters go: the region round its lettered points (page mm) and
    the view that magnifies it into a corner (or the middle of an edge) of the picture, or
    None when the letters have room (no two points closer than :data:`CLOSE_UP_CROWDED_MM`)
    or no place can take the close-up without covering the region or a label the picture
    keeps.  A step whose letters have room but whose new lines are small (within
    :data:`CLOSE_UP_SMALL_MM`) gets a close-up of those lines instead (the third value True).

    The region, first that can be placed: the letters with the part the step draws, when
    that adds at most half again to the region each way (a read-through: the shutter
    button's box was cut off at the close-up's edge, its letters shown whole); the letters
    alone; then only the letters that crowd each other (a read-through: the roller's V and
    X, 1.4 mm apart, got no close-up because all the step's letters spanned the picture),
    the others staying on the picture.  Placing: :func:`_place_close_up`."""
    pts = [view.map(lb.at_mm) for lb in step.labels if lb.kind == "point"]
    crowded = dense = False
    if len(pts) >= 2:
        closest = min(math.dist(a, b) for k, a in enumerate(pts) for b in pts[k + 1:])
        xs, ys = [p[0] for p in pts], [p[1] for p in pts]
        each = (max(xs) - min(xs)) * (max(ys) - min(ys)) / len(pts)  # room per letter, mm²
        dense = len(pts) >= CLOSE_UP_DENSE_LETTERS and each < CLOSE_UP_ROOM_MM2
        crowded = closest < CLOSE_UP_CROWDED_MM or dense
    pad = CLOSE_UP_PAD_MM

    def around(ps: Sequence[Pt]) -> Box2:
        return (min(p[0] for p in ps) - pad, min(p[1] for p in ps) - pad,
                max(p[0] for p in ps) + pad, max(p[1] for p in ps) + pad)

    new = view.map_all(p for st in step.strokes for p in st.points_mm)
    tries: list[tuple[Box2, float]] = []
    if crowded:
        wanted = max(CLOSE_UP_SPACING_MM / max(closest, 1e-9),
                     math.sqrt(2.0 * CLOSE_UP_ROOM_MM2 / max(each, 1e-9)) if dense else 0.0)
        letters = around(pts)
        if new:
            a, b = letters, around(new)
            both = (min(a[0], b[0]), min(a[1], b[1]), max(a[2], b[2]), max(a[3], b[3]))
            if (both[2] - both[0] <= 1.5 * (a[2] - a[0])
                    and both[3] - both[1] <= 1.5 * (a[3] - a[1])):
                tries.append((both, wanted))
        tries.append((letters, wanted))
        # the letters that crowd each other, in groups (each letter with every letter closer
        # than CLOSE_UP_CROWDED_MM to one of its group): the largest group, if not all
        group = list(range(len(pts)))
        for k, p in enumerate(pts):
            for j in range(k):
                if math.dist(p, pts[j]) < CLOSE_UP_CROWDED_MM:
                    old, to = group[k], group[j]
                    group = [to if g == old else g for g in group]
        sizes = {g: group.count(g) for g in group}
        biggest = max(sizes, key=lambda g: (sizes[g], -g))
        near = [p for p, g in zip(pts, group) if g == biggest]
        if not dense and 1 < len(near) < len(pts):
            gap = min(math.dist(a, b) for k, a in enumerate(near) for b in near[k + 1:])
            tries.append((around(near), CLOSE_UP_SPACING_MM / max(gap, 1e-9)))
    else:
        if not new:
            return None
        xs, ys = [p[0] for p in new], [p[1] for p in new]
        side = max(max(xs) - min(xs), max(ys) - min(ys))
        if side >= CLOSE_UP_SMALL_MM:
            return None
        tries.append((around(new), CLOSE_UP_SMALL_TARGET_MM / max(side, 1e-9)))
    for region, wanted in tries:
        placed = _place_close_up(view, step, region, wanted, crowded, segs, drawn, room)
        if placed is not None:
            return region, placed, not crowded
    return None


def _place_close_up(view: _View, step: Step, region: Box2, wanted: float, crowded: bool,
                    segs: np.ndarray, drawn: np.ndarray, room: Box2 | None) -> _View | None:
    """The view magnifying ``region`` (about ``wanted`` times, within the limits) where it
    goes, or None.  Of the places that can, the one hiding the fewest lines of the object
    (``drawn``, segments of its strokes), then the most magnified (a smaller close-up is
    tried where the largest covers the object), then the one hiding the fewest lines of any
    kind (``segs``).  First of all, beside the picture within ``room`` (its slot on the
    page), level with the frame, on the side nearer the frame that leaves room for the least
    zoom: there it hides nothing.  In the picture it never covers the region or a label the
    picture keeps (the parts' names, and every label outside the region)."""
    rw, rh = region[2] - region[0], region[3] - region[1]
    x0, y0, x1, y1 = view.rect
    s = view.scale
    window = (view.window[0] + (region[0] - x0) / s, view.window[1] + (region[1] - y0) / s,
              view.window[0] + (region[2] - x0) / s, view.window[1] + (region[3] - y0) / s)
    if room is not None:  # beside the picture, level with the frame: it hides nothing there
        gap = CLOSE_UP_INSET_MM
        sides = [(room[0], x0 - gap), (x1 + gap, room[2])]
        if region[0] + region[2] > x0 + x1:  # the side nearer the frame first
            sides.reverse()
        for lo, hi in sides:
            # (its caption above or below it, level with the picture too)
            need = len(_beside_caption_rows()) * (CLOSE_UP_CAPTION_MM + 1.0)
            z = min(CLOSE_UP_MAX_ZOOM, wanted, (hi - lo) / rw, (y1 - y0 - need) / rh)
            if z >= CLOSE_UP_MIN_ZOOM:
                w, h = rw * z, rh * z
                bx = lo if lo > x1 else hi - w  # against the picture
                by = min(max(0.5 * (region[1] + region[3]) - h / 2, y0), y1 - h)
                return _View(window, (bx, by, bx + w, by + h))
    zoom = min(CLOSE_UP_MAX_ZOOM, wanted,
               CLOSE_UP_SHARE * (x1 - x0) / rw, CLOSE_UP_SHARE * (y1 - y0) / rh)
    if zoom < CLOSE_UP_MIN_ZOOM:
        return None
    m = CLOSE_UP_INSET_MM
    # the labels the picture keeps, which the close-up must not cover: the parts' names, and
    # every label outside the region it magnifies
    names = [q for q, kind in ((view.map(lb.at_mm), lb.kind) for lb in step.labels)
             if (crowded and kind == "part")
             or not (region[0] <= q[0] <= region[2] and region[1] <= q[1] <= region[3])]
    best: tuple[tuple[int, float, int], Box2] | None = None
    # largest first, smaller (down to the least zoom) where a larger one covers the object;
    # the corners and the sides' middles first, then places on a grid between them (the
    # camera's close-up sat on its body's lines, with room below the body: a read-through)
    for z in (zoom * f for f in (1.0, 0.85, 0.7, 0.55)):
        if z < CLOSE_UP_MIN_ZOOM:
            break
        w, h = rw * z, rh * z
        cx, cy = (x0 + x1 - w) / 2, (y0 + y1 - h) / 2
        xs = [x0 + m + (x1 - x0 - 2 * m - w) * k / CLOSE_UP_GRID for k in range(CLOSE_UP_GRID + 1)]
        ys = [y0 + m + (y1 - y0 - 2 * m - h) * k / CLOSE_UP_GRID for k in range(CLOSE_UP_GRID + 1)]
        places = [(x1 - m - w, y1 - m - h), (x0 + m, y1 - m - h),
                  (x1 - m - w, y0 + m), (x0 + m, y0 + m),
                  (cx, y1 - m - h), (cx, y0 + m), (x0 + m, cy), (x1 - m - w, cy)]
        places += [(bx, by) for by in ys for bx in xs if (bx, by) not in places]
        boxes, texts = [], []
        for bx, by in places:
            box = (bx, by, bx + w, by + h)
            if _boxes_overlap(box, region) or any(
                    box[0] <= q[0] <= box[2] and box[1] <= q[1] <= box[3] for q in names):
                continue
            # its caption is read over what it crosses too (a read-through: "the small
            # frame, enlarged" printed across the roller's frame arm)
            text = _close_up_caption(view.rect, box).box_mm
            if text[0] < x0 or text[2] > x1 or text[1] < y0 or text[3] > y1:
                continue
            boxes.append(box)
            texts.append(text)
        if boxes:  # every place's crossings at once, in bulk
            on_drawn = _crossings_many(drawn, boxes) + _crossings_many(drawn, texts)
            on_any = _crossings_many(segs, boxes) + _crossings_many(segs, texts)
            for box, a, b in zip(boxes, on_drawn.tolist(), on_any.tolist()):
                score = (a, -z, b)
                if best is None or score < best[0]:
                    best = (score, box)
        if best is not None and best[0][0] == 0:
            break
    if best is None:
        return None
    return _View(window, best[1])


def _drawing(view: _View, plan: ViewPlan, i: int,
             memo: dict[Any, Any] | None = None
             ) -> list[Item]:
    """The lines of the picture at step ``i`` in ``view`` (no sheet, no letters).

    ``memo`` (one per workbook, :func:`_step_pages`) keeps each earlier stroke's lines in a
    view: every later step of the workbook draws them again, the same (the train's novice
    workbook mapped its first strokes 19 times)."""
    step = plan.steps[i]
    items: list[Item] = _vanishing_lines(view, plan, step.strokes)
    # Earlier lines: the scaffold grey (its hidden edges dotted, fainter), contours already
    # drawn in ink, so the object emerges from its scaffold as in the paper's figures.
    for earlier in plan.steps[:i]:
        for s in earlier.strokes:
            known = memo.get((view, id(s))) if memo is not None else None
            if known is not None and known[0] is s:
                items += known[1]
                continue
            key = {"contour": "ink", "scaffold_hidden": "earlier_hidden",
                   "ellipse_hidden": "earlier_hidden"}.get(s.kind, "earlier")
            lines = view.lines(s.points_mm, STYLES[key], f"stroke_{key}")
            if memo is not None:  # the stroke kept with its lines: its id stays its own
                memo[(view, id(s))] = (s, lines)
            items += lines
    guides = _step_guides(plan, i)
    for g, key in guides:
        if key != "guide_sheet":
            items += view.lines([g.from_mm, g.to_mm], STYLES[key], key)
    for s in step.strokes:
        key = "new_hidden" if s.kind in ("scaffold_hidden", "ellipse_hidden") else "new"
        items += view.lines(s.points_mm, STYLES[key], "stroke_new")
    # the sheet's printed lines over the box drawn on them: they are the box's own edges
    for g, key in guides:
        if key == "guide_sheet":
            items += view.lines([g.from_mm, g.to_mm], STYLES[key], key)
    printed = _control_printed(plan)
    if printed is not None and printed[0] == i:
        for a, b in printed[1]:
            items += view.lines([a, b], STYLES["guide_sheet"], "printed")  # not a guide
    return items


def _control_printed(plan: ViewPlan) -> tuple[int, list[tuple[Pt, Pt]]] | None:
    """For the control tutorial (level ``basic``): its first box's step and the lines the
    calibrated sheet prints of that box (:func:`h2s_print.project.first_scaffold_lines`, as
    :mod:`h2s_print.sheet` prints them), sheet mm; else None.  Its steps carry no guides (the
    plan.json contract), but its sheet prints the footprint, the nearest upright edge and the
    floor line as every sheet does, and step 1 says to draw on them: the picture shows them
    as the guided tutorial's does (a study designer's review: "Its bottom is the blue
    footprint on your sheet" beside a picture with no blue line, and no key for it)."""
    if plan.level != "basic":
        return None
    found = first_scaffold_lines(plan)
    if found is None:
        return None
    k, lines = found
    pts = list(lines.footprint)
    segs3 = [(pts[j], pts[(j + 1) % 4]) for j in range(4)]
    segs3 += [seg for seg in (lines.height, lines.floor) if seg is not None]
    out = []
    for a, b in segs3:
        pa, pb = plan.camera.project(np.array([a, b], dtype=float))
        out.append(((float(pa[0]), float(pa[1])), (float(pb[0]), float(pb[1]))))
    return k, out


#: Letters on a step's picture: size (pt), dot radius (mm), distances from the dot tried (mm).
LABEL_PT = 7.5
LABEL_DOT_MM = 0.45
#: A part's short name keeps this far from every other label (mm) where a place on the
#: near rings allows: two names 0.25 mm apart read as one ("wheel 5wheel 7" on the train's
#: wheel ellipses, a read-through of stop 27).
PART_LABEL_GAP_MM = 1.2
LABEL_RADII_MM = (1.0, 1.8, 2.8, 4.0, 5.5, 7.5)
#: Further rings, tried only for a label that finds no room on the rings above (a crowded
#: picture of a big assembly): farther from its dot, but never on another label.
LABEL_RADII_FAR_MM = (10.0, 13.0, 17.0, 22.0)
#: Directions tried round a point, in order of preference (right, up, left, down, diagonals,
#: then the eight between: a crowded close-up's letter found a place off the step's new
#: lines there, the roller's ferrule's D').
_LABEL_DIRS = ((1, 0), (0, 1), (-1, 0), (0, -1), (1, 1), (-1, 1), (-1, -1), (1, -1),
               (2, 1), (1, 2), (-1, 2), (-2, 1), (-2, -1), (-1, -2), (1, -2), (2, -1))


def _segments(items: Sequence[Item]) -> np.ndarray:
    """(n, 4) segments ``x0 y0 x1 y1`` of every polyline among ``items``, page mm."""
    return _line_segments([it for it in items if isinstance(it, Polyline)])[0]


def _line_segments(lines: Sequence[Polyline]) -> tuple[np.ndarray, np.ndarray]:
    """The segments of ``lines``, in order (n, 4: ``x0 y0 x1 y1``, page mm: each line's
    consecutive points, a closed line's last back to its first; none for a line of one
    point), and the index in ``lines`` of each segment's line (n,).

    Every coordinate goes into one array, and a segment is a point with the next but at a
    line's last point: one array a picture, where an array a line (each earlier stroke's
    kept in a memo) took twice as long (book, --jobs 1: 0.10 -> 0.05 s, bytes identical)."""
    paths = [(k, ln.points_mm + ln.points_mm[:1] if ln.closed else ln.points_mm)
             for k, ln in enumerate(lines) if len(ln.points_mm) > 1]
    if not paths:
        return np.zeros((0, 4)), np.zeros(0, dtype=int)
    flat = itertools.chain.from_iterable
    pts = np.fromiter(flat(flat(path for _, path in paths)), dtype=float).reshape(-1, 2)
    sizes = np.array([len(path) for _, path in paths])
    first = np.ones(len(pts), dtype=bool)  # the points a segment starts at
    first[np.cumsum(sizes) - 1] = False
    at = np.flatnonzero(first)
    owner = np.repeat(np.array([k for k, _ in paths]), sizes - 1)
    return np.hstack([pts[at], pts[at + 1]]), owner


def _crossings(segs: np.ndarray, box: Box2) -> int:
    """How many of ``segs`` meet the rectangle ``box`` (separating axes: x, y, the segment's
    normal)."""
    return int(_crossings_many(segs, [box])[0])


def _crossings_many(segs: np.ndarray, boxes: Sequence[Box2]) -> np.ndarray:
    """:func:`_crossings` of each of ``boxes``, at once: an int array, one count a box (a
    segment meets a box when their x and y ranges overlap and the box's corners are not all
    on one side of the segment's line).

    Only the segments that reach the boxes' common extent are compared with each box, and
    the corners' sides are worked out only for the (box, segment) pairs whose ranges
    overlap: a picture's hundreds of segments against a label's hundred places round one dot.
    Each side is ``dx * (cy - sy0) - dy * (cx - sx0)`` as one corner at a time computed it,
    the two products of a box edge shared by its two corners, and "all four on one side" is
    their least above 0 or their greatest below 0: half the array operations of a side at a
    time, this being some 50 of them on small arrays 5 000 times a book (book, --jobs 1:
    0.33 -> 0.24 s, bytes identical)."""
    if not len(boxes):
        return np.zeros(0, dtype=int)
    if not len(segs):
        return np.zeros(len(boxes), dtype=int)
    x0, y0, x1, y1 = np.asarray(boxes, dtype=float).T
    sx0, sy0, sx1, sy1 = segs.T
    lo_x, hi_x = np.minimum(sx0, sx1), np.maximum(sx0, sx1)
    lo_y, hi_y = np.minimum(sy0, sy1), np.maximum(sy0, sy1)
    reach = np.flatnonzero((lo_x <= x1.max()) & (hi_x >= x0.min())
                           & (lo_y <= y1.max()) & (hi_y >= y0.min()))
    if not len(reach):
        return np.zeros(len(boxes), dtype=int)
    near = ((lo_x[reach] <= x1[:, None]) & (hi_x[reach] >= x0[:, None])
            & (lo_y[reach] <= y1[:, None]) & (hi_y[reach] >= y0[:, None]))  # (k, n)
    k, n = np.nonzero(near)
    if not len(k):
        return np.zeros(len(boxes), dtype=int)
    n = reach[n]
    ax, ay = sx0[n], sy0[n]  # (pairs,)
    dx, dy = sx1[n] - ax, sy1[n] - ay
    x0, y0, x1, y1 = x0[k], y0[k], x1[k], y1[k]
    below, above = dx * (y0 - ay), dx * (y1 - ay)
    left, right = dy * (x0 - ax), dy * (x1 - ax)
    # the corners (x0, y0), (x1, y0), (x1, y1), (x0, y1)
    c1, c2, c3, c4 = below - left, below - right, above - right, above - left
    one_side = ((np.minimum(np.minimum(c1, c2), np.minimum(c3, c4)) > 0)
                | (np.maximum(np.maximum(c1, c2), np.maximum(c3, c4)) < 0))
    return np.bincount(k[~one_side], minlength=len(boxes))


def _boxes_overlap(a: Box2, b: Box2) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


#: How a label of each kind is printed: font, colour, role.  A face's name (the first
#: step's "front", "left side", "top": the words the steps use for the sides) is grey and
#: slanted, so that it reads as a name for the face, not a point to construct.
_LABEL_LOOK: dict[str, tuple[str, str, str]] = {
    "point": ("Helvetica-Bold", "black", "label"),
    "part": ("Helvetica-Bold", "blue", "part_label"),
    "face": ("Helvetica-Oblique", "grey", "face_label"),
}


#: A label crossing one of the step's new (thick, coloured) lines counts as crossing this
#: many drawn lines (:func:`place_labels`).
NEW_LINE_WEIGHT = 3
#: A corner of a drawn line within this of a label's own dot is the dot's own point (page mm);
#: a place for the letter nearer any other corner than its dot counts one line more.
CORNER_OWN_MM = 0.3


def _rows(values: Sequence[Sequence[float]], width: int) -> np.ndarray:
    """``values`` as a float array (n, ``width``), also when empty."""
    return np.asarray(values, dtype=float).reshape(-1, width)


@functools.cache
def _ring_steps(rings: tuple[float, ...]) -> tuple[np.ndarray, ...]:
    """For every place :func:`place_labels` tries on ``rings`` (radii, mm), in its order (ring
    by ring, each in :data:`_LABEL_DIRS`' order; a ring of radius 0 is one place, centred):
    its ring's and direction's indices, the direction's signs (x, y), and its step from the
    dot (x, y), mm, worked out as place_labels did place by place (``r * ux / norm``)."""
    rows = [(i, di, ux, uy, r * ux / (math.hypot(ux, uy) or 1.0),
             r * uy / (math.hypot(ux, uy) or 1.0))
            for i, r in enumerate(rings)
            for di, (ux, uy) in enumerate(_LABEL_DIRS if r else ((0, 0),))]
    cols = list(zip(*rows))
    return (np.array(cols[0]), np.array(cols[1]), np.array(cols[2]), np.array(cols[3]),
            np.array(cols[4], dtype=float), np.array(cols[5], dtype=float))


def _label_places(dot: Pt, w: float, cap: float, desc: float, rings: tuple[float, ...],
                  rect: Box2, pad: float) -> tuple[np.ndarray, ...]:
    """The places on ``rings`` round ``dot`` for a label ``w`` mm wide (``cap`` above its
    baseline, ``desc`` below) that lie inside ``rect``, in :func:`place_labels`' order: their
    ring indices, direction indices, the label's lower-left corner (x, y) and its box grown
    by ``pad`` (k, 4), page mm.  The box touches the point on its ring on the side facing the
    dot; the same floating-point operations as one place at a time."""
    ring, di, ux, uy, step_x, step_y = _ring_steps(rings)
    cx, cy = dot[0] + step_x, dot[1] + step_y
    bx0 = np.where(ux > 0, cx, np.where(ux < 0, cx - w, cx - w / 2))
    by0 = np.where(uy > 0, cy, np.where(uy < 0, cy - cap - desc, cy - (cap + desc) / 2))
    box = np.stack([bx0 - pad, by0 - pad, bx0 + w + pad, by0 + cap + desc + pad], axis=1)
    inside = ~((box[:, 0] < rect[0]) | (box[:, 1] < rect[1]) | (box[:, 2] > rect[2])
               | (box[:, 3] > rect[3]))
    return ring[inside], di[inside], bx0[inside], by0[inside], box[inside]


def _overlaps_any(boxes: np.ndarray, others: np.ndarray) -> np.ndarray:
    """For each of ``boxes`` (k, 4): does it overlap one of ``others`` (n, 4)
    (:func:`_boxes_overlap`, the same comparisons)?"""
    if not len(others) or not len(boxes):
        return np.zeros(len(boxes), dtype=bool)
    b, o = boxes[:, None, :], others[None, :, :]
    return ((b[..., 0] < o[..., 2]) & (o[..., 0] < b[..., 2]) & (b[..., 1] < o[..., 3])
            & (o[..., 1] < b[..., 3])).any(axis=1)


def _nearer_other(points: np.ndarray, own: Sequence[float], dots: np.ndarray) -> np.ndarray:
    """For each of ``points`` (k, 2): is one of ``dots`` (n, 2) nearer to it than ``own`` (its
    own dot's distance), measured with :func:`math.hypot` as :func:`place_labels` measured?
    Only the pairs whose longer coordinate difference is at most ``own`` are measured: a
    hypotenuse is never shorter than its longer side (math.hypot rounds to a neighbour of the
    exact value, and that side is a float at or below it), so no other dot can be nearer."""
    out = np.zeros(len(points), dtype=bool)
    if not len(dots) or not len(points):
        return out
    ddx = points[:, None, 0] - dots[None, :, 0]
    ddy = points[:, None, 1] - dots[None, :, 1]
    maybe = np.maximum(np.abs(ddx), np.abs(ddy)) <= np.asarray(own, dtype=float)[:, None]
    for i, j in zip(*np.nonzero(maybe)):
        if math.hypot(ddx[i, j], ddy[i, j]) < own[i]:
            out[i] = True
    return out


#: A label's box on a picture: its letters' cap height and descender, and the room kept round
#: them, mm (:func:`place_labels`).
_LABEL_CAP_MM = 0.72 * LABEL_PT * PT_MM
_LABEL_DESC_MM = 0.21 * LABEL_PT * PT_MM
_LABEL_PAD_MM = 0.25


@dataclass(frozen=True, slots=True)
class _LabelSurroundings:
    """What a place for one label on a picture is tested against (:func:`place_labels`), page
    mm.

    Attributes:
        rest: the boxes of every other label and dot (n, 4).
        gapped: those a place keeps :data:`PART_LABEL_GAP_MM` from (n, 4).
        dots: the other letters' dots (n, 2).
        corners: the corners of straight lines near the dot, not the dot's own (n, 2).
        segs: every drawn line's segments; ``new``: the step's new lines' (n, 4).
        rect: the picture.
    """

    rest: np.ndarray
    gapped: np.ndarray
    dots: np.ndarray
    corners: np.ndarray
    segs: np.ndarray
    new: np.ndarray
    rect: Box2


def _scored_places(dot: Pt, w: float, rings: tuple[float, ...], near: _LabelSurroundings
                   ) -> dict[int, tuple[int, float, float, bool, bool, int]]:
    """The best free place for a label ``w`` mm wide round ``dot`` on each of ``rings``, by
    ring index: ``(direction, x, y, ambiguous, crowded, lines crossed)`` (the lower-left
    corner of its letters, and the terms of :func:`place_labels`' score but the ring).

    The places of several rings at once, each tested on its own as place_labels tested them
    one by one; a ring's best is its first place of the fewest (ambiguous, crowded, lines
    crossed), which is what place_labels' scan of the ring in order keeps: the ring and the
    direction are the rest of its score, and a ring's directions differ."""
    pad, cap, desc = _LABEL_PAD_MM, _LABEL_CAP_MM, _LABEL_DESC_MM
    ring, di, bx0, by0, box = _label_places(dot, w, cap, desc, rings, near.rect, pad)
    # not on another label or dot
    free = ~_overlaps_any(box, near.rest)
    ring, di, bx0, by0, box = ring[free], di[free], bx0[free], by0[free], box[free]
    if not len(box):
        return {}
    # a part's name closer than PART_LABEL_GAP_MM to another label (or a label to a part's
    # name) only where no place on the near rings keeps the gap
    g = PART_LABEL_GAP_MM
    crowded = _overlaps_any(np.stack([box[:, 0] - g, box[:, 1] - g, box[:, 2] + g,
                                      box[:, 3] + g], axis=1), near.gapped)
    # a label must read as its own dot's: nearer to it than to any other dot; then few lines
    # across it, then near its dot (a line crossed costs a ring)
    mid = np.stack([(box[:, 0] + box[:, 2]) / 2, (box[:, 1] + box[:, 3]) / 2], axis=1)
    # (math.hypot, which rounds unlike np.hypot, of the differences numpy takes as Python would)
    own = list(map(math.hypot, (mid[:, 0] - dot[0]).tolist(), (mid[:, 1] - dot[1]).tolist()))
    ambiguous = _nearer_other(mid, own, near.dots)
    crossed = _crossings_many(near.segs, box)
    corners = near.corners
    if len(corners):  # nearer another corner than the dot: one line more
        gap = np.hypot(mid[:, None, 0] - corners[None, :, 0],
                       mid[:, None, 1] - corners[None, :, 1]).min(axis=1)
        crossed = crossed + (gap < np.array(own))
    if len(near.new):  # the box grown by the thick line's half width: touching counts
        grow = STYLES["new"].width_mm / 2 + pad
        crossed = crossed + (NEW_LINE_WEIGHT - 1) * _crossings_many(
            near.new, np.stack([box[:, 0] - grow, box[:, 1] - grow, box[:, 2] + grow,
                                box[:, 3] + grow], axis=1))
    # each ring's first place of the least (ambiguous, crowded, crossed): sorted by ring,
    # then by those, then by place (the places are in ring order, each ring's in direction
    # order)
    order = np.lexsort((np.arange(len(ring)), crossed, crowded, ambiguous, ring))
    rings_seen, first = np.unique(ring[order], return_index=True)
    best = order[first]
    return {r: (d, x, y, a, c, n) for r, d, x, y, a, c, n in zip(
        rings_seen.tolist(), di[best].tolist(), bx0[best].tolist(), by0[best].tolist(),
        ambiguous[best].tolist(), crowded[best].tolist(), crossed[best].tolist())}


def place_labels(view: _View, labels: Sequence[Label], items: Sequence[Item], *,
                 segs: np.ndarray | None = None, new: np.ndarray | None = None) -> list[Item]:
    """A dot at each label's point and its letters beside it (roles ``label_point`` and
    ``label``; a part's short name, kind ``part``, in blue without a dot, on the part if there
    is room: role ``part_label``; a face's name, kind ``face``, the same way in grey and
    slanted: role ``face_label``), placed so that no two labels overlap each other or another
    label's dot, every label stays inside the picture, each label is nearer its own dot than any other dot when
    possible, and then as few drawn lines as possible cross it (one of the step's new lines
    counting :data:`NEW_LINE_WEIGHT`), each ring further from the dot counting as one line
    crossed, and so does a place nearer a corner of a straight line than the dot (then the
    preferred direction).

    ``segs`` and ``new``: the segments of ``items``' lines and of the step's new lines
    (``stroke_new``), when the caller has them already (:func:`_segments`).

    Raises:
        RenderError: no place is free for a label (more labels than the picture can hold).
    """
    if segs is None:
        segs = _segments(items)
    # the step's new lines are drawn thick, in colour: a letter across one is lost in it (the
    # train's J under the boiler's new edge), so crossing one counts NEW_LINE_WEIGHT lines
    if new is None:
        new = _segments([it for it in items
                         if isinstance(it, Polyline) and it.role == "stroke_new"])
    dots = [view.map(lb.at_mm) for lb in labels]
    # the corners of the drawing's straight lines (a box's edges, guides): a letter nearer
    # one of them than its own dot reads as that corner's (a read-through put the roller's
    # handle's top corner at S, whose dot was the top face's centre)
    ends = [p for it in items if isinstance(it, Polyline) and len(it.points_mm) == 2
            for p in it.points_mm]
    # (a corner met twice is left twice: only the nearest counts)
    corners = np.round(np.asarray(ends, dtype=float).reshape(-1, 2), 3)
    taken: list[Box2] = [(dx - LABEL_DOT_MM, dy - LABEL_DOT_MM, dx + LABEL_DOT_MM,
                          dy + LABEL_DOT_MM) if lb.kind == "point" else (dx, dy, dx, dy)
                         for lb, (dx, dy) in zip(labels, dots)]
    out: list[Item] = []
    pad = _LABEL_PAD_MM
    names: set[int] = set()  # indices in ``taken`` of parts' names placed
    for k, (lb, (dx, dy)) in enumerate(zip(labels, dots)):
        # a part's short name or a face's: centred on the part (the face), no dot
        part = lb.kind in ("part", "face")
        font, colour, role = _LABEL_LOOK[lb.kind]
        if not part:
            out.append(Circle(dx, dy, LABEL_DOT_MM, None, 0.0, "black", "label_point"))
        w = text_width_mm(lb.name, LABEL_PT, font)
        # the corners a place for the letter may be nearer than its dot: not its own point,
        # and only those within reach of the rings (a picture has hundreds)
        reach = LABEL_RADII_FAR_MM[-1] + w + 2.0
        others = np.zeros((0, 2)) if part or not len(corners) else corners[
            (np.abs(corners[:, 0] - dx) <= reach) & (np.abs(corners[:, 1] - dy) <= reach)
            & (np.hypot(corners[:, 0] - dx, corners[:, 1] - dy) > CORNER_OWN_MM)]
        # what a place is tested against: every other label (and dot), the labels a part's
        # name keeps PART_LABEL_GAP_MM from (all, for a part's name), the other letters' dots
        near_of = _LabelSurroundings(
            rest=_rows([t for j, t in enumerate(taken) if j != k], 4),
            gapped=_rows([t for j, t in enumerate(taken) if j != k and (part or j in names)], 4),
            dots=_rows([p for j, p in enumerate(dots) if j != k and labels[j].kind == "point"],
                       2),
            corners=others, segs=segs, new=new, rect=view.rect)
        best: tuple[tuple, Text] | None = None
        rings = ((0.0,) if part else ()) + LABEL_RADII_MM + LABEL_RADII_FAR_MM
        near = len(rings) - len(LABEL_RADII_FAR_MM)
        places: dict[int, tuple[int, float, float, bool, bool, int]] = {}
        for ri, r in enumerate(rings):
            if best is not None and r in LABEL_RADII_FAR_MM:
                break  # the far rings only when nothing nearer is free
            if ri in (0, near):  # the near rings' places at once, then the far rings'
                group = rings[:near] if ri == 0 else rings[near:]
                places = {ri + j: place for j, place in _scored_places((dx, dy), w, group,
                                                                       near_of).items()}
            if ri in places:  # the ring's best place against the best so far
                di, bx0, by0, ambiguous, crowded, n = places[ri]
                score = (ambiguous, crowded, n + ri, di)
                if best is None or score < best[0]:
                    best = (score, Text(bx0, by0 + _LABEL_DESC_MM, lb.name, LABEL_PT, font,
                                        "start", colour, role))
            if best is not None and not best[0][0] and not best[0][1] and best[0][2] <= ri:
                break  # nothing further out can score better
        if best is None:
            raise RenderError(f"no room on the picture for the label {lb.name!r}")
        text = best[1]
        out.append(text)
        b = text.box_mm
        if part:
            names.add(len(taken))
        taken.append((b[0] - pad, b[1] - pad, b[2] + pad, b[3] + pad))
    return out


# ----------------------------------------------------------------------------- page furniture


@dataclass(frozen=True, slots=True)
class _Frame:
    """The page's content area inside its margins, mm."""

    width: float
    height: float
    margin: float

    @property
    def box(self) -> Box2:
        return (self.margin, self.margin, self.width - self.margin, self.height - self.margin)


def _header(f: _Frame, left: str, right: str = "") -> tuple[list[Item], float]:
    """Title line at the top of the content area; returns items and the y below it, mm."""
    x0, _, x1, y1 = f.box
    size = 11.0
    base = y1 - 0.72 * size * PT_MM
    items: list[Item] = []
    right_w = text_width_mm(right, 9, "Helvetica") if right else 0.0
    avail = x1 - x0 - right_w - 6
    left = plain_text(left)
    if left:
        items.append(Text(x0, base, left, fit_line(left, avail, size, "Helvetica-Bold", 6.0),
                          "Helvetica-Bold", "start", "black", "header"))
    if right:
        items.append(Text(x1, base, right, 9, "Helvetica", "end", "black", "header"))
    rule_y = base - 2.6
    items.append(Polyline(((x0, rule_y), (x1, rule_y)), "lightgrey", 0.3, (), False, "rule"))
    return items, rule_y - 3.0


def _legend(f: _Frame, y: float, keys: Sequence[str]) -> tuple[list[Item], float]:
    """A key of line styles starting at baseline ``y`` (wrapping rows upward); returns the top."""
    x0, _, x1, _ = f.box
    size = 7.0
    swatch, gap = 9.0, 4.0
    entries = [(k, _t(f"legend.{k}")) for k in keys]
    rows: list[list[tuple[str, str, float]]] = [[]]
    head = _t("legend.heading")
    x = x0 + text_width_mm(head, size, "Helvetica-Bold") + 2
    for k, label in entries:
        w = swatch + 1.5 + text_width_mm(label, size)
        if x + w > x1 and rows[-1]:
            rows.append([])
            x = x0
        rows[-1].append((k, label, x))
        x += w + gap
    items: list[Item] = [Text(x0, y + (len(rows) - 1) * 4.0, head, size, "Helvetica-Bold", "start",
                              "black", "legend")]
    for r, row in enumerate(rows):
        yy = y + (len(rows) - 1 - r) * 4.0
        for k, label, xx in row:
            st = STYLES[k]
            mid = yy + 0.9
            if k == "corner":
                items.append(Polyline(((xx + 2.5, mid + 1.3), (xx + 2.5, mid - 1.3), (xx + 6.5, mid - 1.3)),
                                      st.colour, st.width_mm, (), False, "legend"))
            else:
                items.append(Polyline(((xx, mid), (xx + swatch, mid)), st.colour, st.width_mm,
                                      st.dash_mm, False, "legend"))
            items.append(Text(xx + swatch + 1.5, yy, label, size, "Helvetica", "start", "black", "legend"))
    return items, y + (len(rows) - 1) * 4.0 + 0.72 * size * PT_MM


def _footer_y(f: _Frame) -> float:
    return f.margin + 0.8


def _with_footers(pages: Sequence[Page], make: Callable[[int, int], str]) -> tuple[Page, ...]:
    """Replace every page-number footer with ``make(page_no, total)`` (sheets have none);
    pages without a font are given the current one (the one they were measured in)."""
    out = []
    here = fonts.current()
    total = len(pages)
    for n, page in enumerate(pages, start=1):
        items = tuple(it for it in page.items if getattr(it, "role", "") != "page_number")
        if page.kind != "sheet":
            f = _Frame(page.width_mm, page.height_mm, page.margin_mm)
            items += (Text(f.box[2], _footer_y(f), make(n, total), 7, "Helvetica", "end", "grey",
                           "page_number"),)
        out.append(replace(page, items=items, font=page.font or here))
    return tuple(out)


# ----------------------------------------------------------------------------- primer


@dataclass(frozen=True, slots=True)
class PrimerDiagram:
    """One primer construction: segments in an arbitrary diagram frame (y up).

    Attributes:
        key: ``half``, ``quarter``, ``third``, ``extend``, ``extend_half`` or ``ellipse`` (the
            template key under ``primer.diagrams``).
        segments: ``((x0, y0), (x1, y1), role)``; role ``face`` (the given face), ``construction``
            (helper lines) or ``result`` (the line the construction yields).
    """

    key: str
    segments: tuple[tuple[Pt, Pt, str], ...]


#: Primer diagrams: template key -> ratios constructed on one face (``h2s_print.constructions``).
PRIMER_RATIOS: tuple[tuple[str, tuple[float, ...]], ...] = (
    ("half", (0.5,)), ("quarter", (0.25, 0.75)), ("third", (1 / 3, 2 / 3)),
    ("extend", (2.0,)), ("extend_half", (1.5,)),
)


@functools.lru_cache(maxsize=1)
def primer_diagrams() -> tuple[PrimerDiagram, ...]:
    """The primer's constructions, built in 3D on one box face and projected (two-point view).

    Each diagram is the face ``x in [0, 1], z in [0, 1.25]`` at ``y = 0`` seen from the
    front-right, with the lines of ``h2s_print.constructions.construct`` for its ratios (shared
    lines once), projected by a camera from ``h2s_print.project.make_camera``; so every crossing
    the diagram shows is where a ruler construction on paper lands.  Extensions also show the
    new face's top and bottom edges as results.  Coordinates are that camera's sheet mm (the
    page fits them into a cell).  They depend on nothing but constants: made once (every
    workbook's primer shows them).
    """
    face = Face(((0.0, 0.0, 0.0), (1.0, 1.0, 1.25)), 1, "lo")
    frame = [face.point(u, v) for u in (0.0, 2.0) for v in (0.0, 1.0)]
    view = ViewSpec("primer", azimuth_deg=40.0, elevation_deg=4.0, distance=2.2,
                    perspective="two-point")
    camera = make_camera(view, frame, PaperSpec("A4", "landscape", 12.0))

    def mm(p) -> Pt:
        x, y = camera.project([p])[0]
        return (round(float(x), 6), round(float(y), 6))

    out = []
    for key, ratios in PRIMER_RATIOS:
        a, b, c, d = face.corners
        segs: list[tuple[Pt, Pt, str]] = [(mm(a), mm(b), "face"), (mm(b), mm(c), "face"),
                                          (mm(c), mm(d), "face"), (mm(d), mm(a), "face")]
        seen = {frozenset((s[0], s[1])) for s in segs}
        for ratio in ratios:
            con = construct(face, 0, ratio)
            lines = [(ln.start, ln.end, "result" if ln.role == "guide" else "construction")
                     for ln in con.lines]
            if ratio > 1:
                lines += [(face.point(1, 0), face.point(ratio, 0), "result"),
                          (face.point(1, 1), face.point(ratio, 1), "result")]
            for p, q, role in lines:
                seg = (mm(p), mm(q), role)
                if frozenset(seg[:2]) not in seen:
                    seen.add(frozenset(seg[:2]))
                    segs.append(seg)
        out.append(PrimerDiagram(key, tuple(segs)))
    # the ellipse of a round part's end face: diagonals, middle lines, the inscribed ellipse
    # (h2s_print.constructions.ellipse_on_face, as the ellipse steps draw it)
    a, b, c, d = face.corners
    fe = ellipse_on_face(face, camera)
    segs = [(mm(a), mm(b), "face"), (mm(b), mm(c), "face"), (mm(c), mm(d), "face"),
            (mm(d), mm(a), "face")]
    segs += [(mm(ln.start), mm(ln.end), "construction") for ln in fe.lines]
    ring = [mm(p) for p in fe.points3d]
    segs += [(ring[k], ring[(k + 1) % len(ring)], "result") for k in range(len(ring))]
    out.append(PrimerDiagram("ellipse", tuple(segs)))
    return tuple(out)


def _compares_sizes(plan: ViewPlan) -> bool:
    """Does a sub-step of ``plan`` compare a size with a part drawn before ("Make its width
    about three quarters of the engine's") or with another of its own ("Make its height the
    same as its depth", a read-through: a guess not said to be one): ``steps.yaml``'s
    ``substep.size*``; or do a master's ratio words place a part at a fraction or a multiple of
    another's size ("at a quarter of the body's width")?"""
    def said(keys: Sequence[str]) -> re.Pattern[str]:
        return re.compile("|".join(re.sub(r"\\\{[a-z_0-9]+\\\}", ".+",
                                          re.escape(templates.lookup("steps", k)))
                                   for k in keys), re.IGNORECASE)

    sizes = said([f"substep.{k}" for k in ("size", "size_many", "size_round", "size_same")])
    # a master's ratio words: fractions and multiples of a part's size (a read-through of
    # the master workbooks found the primer's warning missing there)
    ratios = said([f"ratio_words.{k}" for k in ("inside", "inside_both", "middle", "extend",
                                                "extend_both", "outside")])
    return any(sizes.search(x) for st in plan.steps for x in st.substeps) or any(
        ratios.search(st.summary) for st in plan.steps if st.summary)


def _primer_intro(plan: ViewPlan) -> str:
    """The primer's introduction for ``plan``'s view: what "away from" a vanishing point
    means, and, where upright edges run toward a vanishing point of their own (a view from
    high or low), that they do, in the words the steps use (a read-through of the high
    views met "toward the vanishing point below" and "away from" nowhere explained); where
    step 1's picture names the first box's faces (labels of kind ``face``), that it does, and
    which way a width, a depth and a height run (a read-through could not tell which edge of
    the mixer's base was its width); where a step compares a size with another part's, that
    it compares the real parts, not lengths on the paper (a read-through measured the train's
    wagon, "about three quarters of the engine's", with a ruler on the page, where the nearer
    wagon is drawn longer than the engine)."""
    text = _t("primer.intro") + " " + _t("primer.away")
    if any(lb.kind == "face" for st in plan.steps for lb in st.labels):
        text += " " + _t("primer.sides")
    if _compares_sizes(plan):
        text += " " + _t("primer.sizes")
    centre = (plan.camera.paper_mm[0] / 2.0, plan.camera.paper_mm[1] / 2.0)
    up = next((side for vp in plan.vanishing_points if vp.axis == 2
               and (side := vp_side(vp, centre)) is not None), None)
    if up is not None:
        text += " " + _t("primer.upright",
                         vp=plain_text(templates.lookup("steps", f"vp.{up}")))
    return text


def _primer_page(f: _Frame, title: str, header_right: str,
                 diagrams: Sequence[PrimerDiagram], intro_text: str) -> Page:
    items: list[Item] = []
    head, top = _header(f, _t("primer.heading"), header_right)
    items += head
    x0, y0, x1, _ = f.box
    intro, top = _paragraph(x0, top, x1 - x0, intro_text, 9.5, role="intro")
    items += intro
    legend, legend_top = _legend(f, _footer_y(f) + 5.0, ["face", "construction", "result"])
    items += legend
    cols = 3 if f.width > f.height else 2
    rows = math.ceil(len(diagrams) / cols)
    gap = 6.0
    area_top = top - 4.0
    area_bottom = legend_top + 4.0
    cw = (x1 - x0 - gap * (cols - 1)) / cols
    ch = (area_top - area_bottom - gap * (rows - 1)) / rows
    size = 8.0
    for k, d in enumerate(diagrams):
        r, c = divmod(k, cols)
        cx0 = x0 + c * (cw + gap)
        ctop = area_top - r * (ch + gap)
        title_items, below = _paragraph(cx0, ctop, cw, _t(f"primer.diagrams.{d.key}.title"), 9,
                                        font="Helvetica-Bold", role="primer_title")
        items += title_items
        steps = templates.lookup("pages", f"primer.diagrams.{d.key}.steps")
        texts = [plain_text(f"{n}. {s}") for n, s in enumerate(steps, start=1)]
        text_h = sum(_paragraph_height(s, cw, size) + 1.0 for s in texts)
        diagram_area = (cx0, ctop - ch + text_h + 2.0, cx0 + cw, below - 2.0)
        pts = [p for a, b, _ in d.segments for p in (a, b)]
        box = _bbox(pts)
        if box is not None and diagram_area[3] - diagram_area[1] > 5:
            view = _fit(box, diagram_area)
            for a, b, role in sorted(d.segments, key=lambda s: ("face", "construction", "result").index(s[2])):
                items += view.lines([a, b], STYLES[role], f"primer_{role}")
        y = ctop - ch + text_h
        for s in texts:
            para, bottom = _paragraph(cx0, y, cw, s, size, role="primer_step")
            items += para
            y = bottom - 1.0
    return Page(f.width, f.height, tuple(items), (Bookmark(_t("primer.bookmark")),), "primer", title, f.margin)


# ----------------------------------------------------------------------------- workbook


def estimate_minutes(plan: ViewPlan) -> int:
    """Estimated time to work through ``plan``, at a beginner's pace, rounded up to 5 minutes
    (at least 5): :data:`READ_MINUTES` to read each step, :data:`GUIDE_MINUTES` per new guide
    line drawn with the ruler, :data:`BOX_MINUTES` per part's scaffold, :data:`ELLIPSE_MINUTES`
    per ellipse and :data:`OUTLINE_MINUTES` per part outlined.  Each term counts what the
    pages make the reader draw, so a master (no guides shown) is quicker than a novice."""
    boxes = {st.part for s in plan.steps if s.kind in ("primitive", "basic")
             for st in s.strokes}
    ellipses = len({_ellipse_key(st) for s in plan.steps for st in s.strokes
                    if st.kind in ("ellipse", "ellipse_hidden")})
    outlined = {st.part for s in plan.steps if s.kind == "contour" for st in s.strokes
                if st.kind == "contour"}
    guides = sum(1 for s in plan.steps for g in s.guides if g.status == "new")
    total = (READ_MINUTES * len(plan.steps) + GUIDE_MINUTES * guides + BOX_MINUTES * len(boxes)
             + ELLIPSE_MINUTES * ellipses + OUTLINE_MINUTES * len(outlined))
    return max(5, int(math.ceil(total / 5.0 - 1e-9)) * 5)


def _ellipse_key(stroke: Stroke) -> tuple:
    """One ellipse's identity across the runs it is cut into (seen, hidden): its part and the
    plane it lies in (the coordinate its points share)."""
    pts = np.asarray(stroke.points3d, dtype=float)
    axis = int(np.argmin(np.ptp(pts, axis=0)))
    return stroke.part, axis, round(float(pts[0, axis]), 9)


def _level_name(level: str) -> str:
    try:
        return _t(f"levels.{level}")
    except KeyError:
        return plain_text(level)


def _final_strokes(plan: ViewPlan, final: Sequence[Stroke]) -> tuple[Stroke, ...]:
    return tuple(final) if final else tuple(s for st in plan.steps for s in st.strokes)


def _cover_page(f: _Frame, title: str, plan: ViewPlan, view_label: str,
                final: Sequence[Stroke], level: str | None,
                how: Sequence[str] | None = None, time: bool = True) -> Page:
    items: list[Item] = []
    x0, y0, x1, y1 = f.box
    landscape = f.width > f.height
    text_w = (x1 - x0) * (0.45 if landscape else 1.0)
    top = y1
    kick, top = _paragraph(x0, top, text_w, _t("cover.kicker"), 11, role="kicker", colour="grey")
    items += kick
    heading, top = _paragraph(x0, top - 4, text_w, title, 26, font="Helvetica-Bold", role="title")
    items += heading
    top -= 6
    facts = [_t("cover.view", view=view_label),
             *([_t("cover.level", level=level)] if level is not None else []),
             _t("cover.steps", n=len(plan.steps)),
             *([_t("cover.time", minutes=estimate_minutes(plan))] if time else [])]
    for fact in facts:
        para, top = _paragraph(x0, top, text_w, fact, 12, role="cover_fact")
        items += para
        top -= 2.5
    top -= 5
    how_h, top = _paragraph(x0, top, text_w, _t("cover.how_heading"), 11, font="Helvetica-Bold",
                            role="how")
    items += how_h
    top -= 2
    how_key = "cover.how_basic" if plan.level == "basic" else "cover.how"
    lines = list(how if how is not None else templates.lookup("pages", how_key))
    if how is None and plan.level == "apprentice":  # its pictures show no construction lines
        lines.insert(3, _t("cover.how_apprentice"))  # after "Orange shows what to draw ..."
    for line in lines:
        para, top = _paragraph(x0 + 4, top, text_w - 4, plain_text(line), 9.5, role="how")
        items.append(Circle(x0 + 1.2, para[0].y_mm + 1.1, 0.6, None, 0.0, "black", "bullet"))
        items += para
        top -= 2
    if plan.part_names:  # parts called by a short label: their full names
        top -= 3
        head, top = _paragraph(x0, top, text_w, _t("parts.heading"), 11, font="Helvetica-Bold",
                               role="part_names")
        items += head
        top -= 1.5
        items += _name_columns(x0 + 4, top, text_w - 4, y0, [
            _t("parts.entry", label=label, full=name) for label, name in plan.part_names])
    # The finished drawing, zoomed on its own extent.
    if landscape:
        area = (x0 + text_w + 12, y0 + 14, x1, y1 - 8)
    else:
        area = (x0, y0 + 14, x1, top - 14)
    strokes = _final_strokes(plan, final)
    box = _bbox(_stroke_points(strokes))
    if box is not None and area[3] - area[1] > 10:
        pad = 0.06 * max(box[2] - box[0], box[3] - box[1], 1e-6)
        window = (box[0] - pad, box[1] - pad, box[2] + pad, box[3] + pad)
        view = _fit(window, area)
        items.append(Rect(view.rect[0], view.rect[1], view.rect[2] - view.rect[0],
                          view.rect[3] - view.rect[1], "lightgrey", 0.3, None, "image_frame"))
        for s in strokes:
            items += view.lines(s.points_mm, STYLES["final"], "stroke_final")
        items.append(Text(view.rect[0], view.rect[3] + 2.0, _t("cover.image_caption"), 9,
                          "Helvetica-Oblique", "start", "grey", "image_caption"))
    return Page(f.width, f.height, tuple(items), (Bookmark(_t("cover.bookmark")),), "cover", title, f.margin)


#: Columns the cover's list of part names may take, at most (:func:`_name_columns`).
NAME_COLUMNS = 4


def _name_columns(x: float, top: float, width: float, bottom: float,
                  entries: Sequence[str]) -> list[Item]:
    """The cover's list of part names from ``top`` down, in as few columns side by side (up
    to :data:`NAME_COLUMNS`) as keep it above ``bottom`` (a read-through of the oven's cover:
    its eleven names ran off the page, the last one lost), filled top to bottom; in the most
    columns where none fits."""
    items: list[Item] = []
    for cols in range(1, NAME_COLUMNS + 1):
        per = -(-len(entries) // cols)
        col_w = (width - 3.0 * (cols - 1)) / cols
        items, low = [], top
        for c in range(cols):
            y = top
            for entry in entries[c * per:(c + 1) * per]:
                para, y = _paragraph(x + c * (col_w + 3.0), y, col_w, entry, 9,
                                     role="part_name")
                items += para
                y -= 1
            low = min(low, y + 1)
        if low >= bottom:
            break
    return items


#: Indent of a sub-step's text after its number, mm.
SUBSTEP_INDENT_MM = 5.0


def _instruction_parts(step: Step) -> list[tuple[str, str]]:
    """The step's text as ``(number, paragraph)`` pairs: the headline (bold, no number), then
    the numbered sub-steps, or (master) the summary."""
    out = [("", plain_text(step.headline or step.text))]
    if step.substeps:
        out += [(f"{k + 1}.", plain_text(x)) for k, x in enumerate(step.substeps)]
    elif step.summary:
        out.append(("", plain_text(step.summary)))
    return out


def _instruction_height(step: Step, width: float, size: float) -> float:
    """Height of :func:`_instruction` for ``step``, mm."""
    h = 0.0
    for k, (num, para) in enumerate(_instruction_parts(step)):
        font = "Helvetica-Bold" if k == 0 else "Helvetica"
        w = width - (SUBSTEP_INDENT_MM if num else 0.0)
        h += _paragraph_height(para, w, size, font) + (1.2 if k else 0.0)
    return h


def _instruction(x: float, top: float, width: float, step: Step, size: float
                 ) -> tuple[list[Item], float]:
    """The headline (bold) and the sub-steps, each a paragraph with a hanging number."""
    items: list[Item] = []
    y = top
    for k, (num, para) in enumerate(_instruction_parts(step)):
        font = "Helvetica-Bold" if k == 0 else "Helvetica"
        if k:
            y -= 1.2
        if num:
            items.append(Text(x, y - 0.72 * size * PT_MM, num, size, "Helvetica-Bold", "start",
                              "black", "substep_number"))
            lines, y = _paragraph(x + SUBSTEP_INDENT_MM, y, width - SUBSTEP_INDENT_MM, para,
                                  size, role="substep")
        else:
            lines, y = _paragraph(x, y, width, para, size, font=font,
                                  role="headline" if k == 0 else "summary")
        items += lines
    return items, y


def _erase_hints(plan: ViewPlan) -> list[str]:
    """Every step's :func:`_erase_hint`, the scaffold edges gathered once as the steps go:
    those drawn by the step and before, and by the next step too (a guide the next step's box
    is drawn on is not erased only to be drawn again: the roller's "2 guide lines" after
    step 8 ran where step 9 draws the riser's edges, a read-through)."""
    out: list[str] = []
    edges = [_step_edges(step) for step in plan.steps]
    for i in range(len(plan.steps)):
        out.append(_erase_hint(plan, i, np.vstack(edges[:i + 2])))
    return out


def _erase_hint(plan: ViewPlan, i: int, edges: np.ndarray) -> str:
    """The step's "you may erase ..." line (empty when nothing retires): the lines by their
    letters ("Afterwards you may erase AC, BD and FG.") when the ends of each are lettered on
    this step's picture (the reader points at each); else, where they are all the guide lines
    some steps drew, by those steps ("Afterwards you may erase this step's guide lines.",
    "... the guide lines of steps 7 and 8.", :func:`_whole_steps`); else the lettered ones by
    name and the others by their number and where to see which ("... AC and 2 more guide
    lines: the next picture no longer shows them.").  The floor line printed on the sheet is
    never among them (no one erases print; the count took it for a line to erase).  A guide that runs along an
    edge of the scaffold is erased only beyond it (the mixer's KU along the column's edge KL
    is "LU"), and not at all when it lies on the edge whole (:func:`_off_edges`).  ``edges``:
    the scaffold edges drawn by step ``i`` and the next (:func:`_erase_hints` gathers
    them)."""
    if i + 1 >= len(plan.steps):
        return ""
    later = {g.id for g, _ in _step_guides(plan, i + 1)}
    shown = [g for g, _ in _step_guides(plan, i)]
    names: list[str | None] = []
    retired: set[str] = set()  # the guides erased whole (no scaffold edge along them)
    on_edges: set[str] = set()  # those along scaffold edges whole: never erased
    for g in shown:
        if g.id in later or g.role == "sheet":  # (printed on the sheet: no one erases it)
            continue
        pieces = _off_edges(g, edges)
        if not pieces:
            on_edges.add(g.id)
            continue  # an edge of the drawing itself: nothing to erase
        whole = (len(pieces) == 1 and math.dist(pieces[0][0], g.from_mm) <= 1e-6
                 and math.dist(pieces[0][1], g.to_mm) <= 1e-6)
        retired.add(g.id if whole else "")  # (a piece beyond an edge: named, not a step's)
        name = _letters_at(plan.steps[i], pieces[0]) if len(pieces) == 1 else None
        if name not in names or name is None:
            names.append(name)
    if not names:
        return ""
    said = [n for n in names if n is not None]
    steps = (_whole_steps(plan, i, retired, on_edges, {g.id for g in shown})
             if None in names else None)
    if steps == [i + 1]:
        return plain_text(templates.text("pages", "step.erase_this"))
    if steps:
        return plain_text(templates.plural("pages", "step.erase_steps", len(steps),
                                           steps=_listed([str(n) for n in steps])))
    if not said:
        return plain_text(templates.plural("pages", "step.erase", len(names)))
    if None in names:  # the lettered ones by name (the template joins the count last)
        return plain_text(templates.plural("pages", "step.erase_more", names.count(None),
                                           lines=templates.lookup("steps", "join").join(said)))
    return plain_text(templates.text("pages", "step.erase_named", lines=_listed(said)))


def _listed(items: Sequence[str]) -> str:
    """``items`` as the wording lists them ("AC, BD and FG"; ``steps.join`` and
    ``steps.join_last``)."""
    join, last = templates.lookup("steps", "join"), templates.lookup("steps", "join_last")
    return items[0] if len(items) == 1 else join.join(items[:-1]) + last + items[-1]


#: A guide's piece lies along a scaffold edge when both ends of the edge's segment are
#: within a pencil's width of the guide's line on the sheet (the sequence's "along the
#: column's edge" uses the same width: a line said to run along an edge is never erased) ...
ON_EDGE_MM = ALONG_MM
#: ... and a lettered point names a piece's end within this (sheet mm).
AT_POINT_MM = 0.05
#: ... and a piece left over shorter than this is not a line to erase (sheet mm).
ERASE_MIN_MM = 0.5


def _step_edges(step: Step) -> np.ndarray:
    """(n, 4) segments of the scaffold edges ``step`` draws, sheet mm."""
    segs = [np.hstack([p[:-1], p[1:]]) for s in step.strokes
            if s.kind in ("scaffold", "scaffold_hidden")
            for p in (np.asarray(s.points_mm, dtype=float),) if len(p) > 1]
    return np.vstack(segs) if segs else np.zeros((0, 4))


def _whole_steps(plan: ViewPlan, i: int, retired: set[str], on_edges: set[str],
                 shown: set[str]) -> list[int] | None:
    """The steps (numbers, in order) whose guide lines still on the paper are exactly the
    guides retiring after step ``i`` (``retired``: their ids, each erased whole, or "" for
    one erased only beyond a scaffold edge, which makes it None; ``on_edges``: retiring
    guides that lie along scaffold edges whole, which no one erases; ``shown``: the ids of
    the guides step ``i``'s picture shows), or None when they are
    not: "Afterwards you may erase the guide lines of steps 7 and 8." says which lines as the
    pictures show them (each step's picture draws its new guides in their own style), where
    "... ED, FC and 11 more guide lines" left the reader counting (a read-through).  Every
    guide those steps drew that is still drawn at step ``i`` must retire now, so that none
    still needed is erased, and every retiring guide must be one of theirs."""
    if not retired or "" in retired:
        return None
    first: dict[str, int] = {}  # each guide's step (number) that drew it
    for k, step in enumerate(plan.steps[:i + 1]):
        for g in step.guides:
            if g.status == "new" and g.role != "sheet":
                first.setdefault(g.id, k + 1)
    if not retired <= first.keys():
        return None
    steps = sorted({first[g] for g in retired})
    drew = {g for g, n in first.items() if n in steps and g in shown} - on_edges
    return steps if drew == retired else None


def _off_edges(guide: Guide, edges: np.ndarray) -> list[tuple[Pt, Pt]]:
    """The pieces of ``guide`` (sheet mm) that no scaffold edge covers, in order."""
    a, b = np.asarray(guide.from_mm, dtype=float), np.asarray(guide.to_mm, dtype=float)
    d = b - a
    length = float(math.hypot(*d))
    if length < ERASE_MIN_MM:
        return []
    n = np.array([-d[1], d[0]]) / length
    spans = []
    if len(edges):
        p, q = edges[:, :2], edges[:, 2:]
        on = (np.abs((p - a) @ n) <= ON_EDGE_MM) & (np.abs((q - a) @ n) <= ON_EDGE_MM)
        tp, tq = ((p[on] - a) @ d) / length ** 2, ((q[on] - a) @ d) / length ** 2
        spans = sorted((max(min(x, y), 0.0), min(max(x, y), 1.0)) for x, y in zip(tp, tq)
                       if max(x, y) > 0.0 and min(x, y) < 1.0)
    pieces, at = [], 0.0
    for lo, hi in spans + [(1.0, 1.0)]:
        if (lo - at) * length >= ERASE_MIN_MM:
            pieces.append(((float(a[0] + at * d[0]), float(a[1] + at * d[1])),
                           (float(a[0] + lo * d[0]), float(a[1] + lo * d[1]))))
        at = max(at, hi)
    return pieces


def _letters_at(step: Step, piece: tuple[Pt, Pt]) -> str | None:
    """The piece's name on the step's picture ("AC"): the letters at its two ends, or None
    when an end is not a lettered point there."""
    out = ""
    for end in piece:
        hit = next((lb.name for lb in step.labels
                    if lb.kind == "point" and math.dist(lb.at_mm, end) <= AT_POINT_MM), None)
        if hit is None:
            return None
        out += hit
    return out


def _steps_per_page(plan: ViewPlan) -> int:
    return 1 if plan.level == "novice" else 2


def _legend_keys(plan: ViewPlan) -> list[str]:
    # the new part's hidden edges have a key of their own: dotted orange read as "new guide"
    keys = ["earlier", "earlier_hidden", "ink", "new", "new_hidden", "guide_sheet", "guide_new",
            "guide_reused", "guide_idle", "vanishing", "corner"]
    roles = {g.role for step in plan.steps for g in step.guides}
    if not roles - {"sheet"}:  # master and basic: no constructed guide to explain
        keys = [k for k in keys if not k.startswith("guide_") or k == "guide_sheet"]
    if "sheet" not in roles and _control_printed(plan) is None:
        keys.remove("guide_sheet")
    return keys


def _step_geometry(f: _Frame, plan: ViewPlan, hints: Sequence[str]
                   ) -> tuple[list[Box2], list[_View], float]:
    """Where a workbook's step pages put their pictures: the slots (one per step on a page),
    the picture in each, and the text height below it.  One text height for every step page
    of the workbook, so the picture keeps one scale and place from page to page (a scaffold
    that grows and shrinks while one copies it misleads); the finished drawing uses it too."""
    per = _steps_per_page(plan)
    size = 11.0 if per == 1 else 10.0
    _, top = _header(f, "")
    _, legend_top = _legend(f, _footer_y(f) + 5.0, _legend_keys(plan))
    x0, _, x1, _ = f.box
    bottom = legend_top + 4.0
    gap = 8.0
    slots: list[Box2] = []
    for k in range(per):
        if f.width > f.height:  # side by side
            w = (x1 - x0 - gap * (per - 1)) / per
            slots.append((x0 + k * (w + gap), bottom, x0 + k * (w + gap) + w, top))
        else:
            h = (top - bottom - gap * (per - 1)) / per
            slots.append((x0, top - k * (h + gap) - h, x1, top - k * (h + gap)))
    sw = slots[0][2] - slots[0][0]
    text_h = max(
        6.5 + _instruction_height(step, sw, size)
        + (_paragraph_height(hint, sw, 8.5) + 2.0 if hint else 0.0)
        for step, hint in zip(plan.steps, hints))
    views = [_fit(_window(plan.paper_mm), (sx0, sy0 + text_h + 4.0, sx1, sy1), top=True)
             for sx0, sy0, sx1, sy1 in slots]
    return slots, views, text_h


def _step_pages(f: _Frame, title: str, plan: ViewPlan, view_label: str, level: str,
                hints: Sequence[str],
                geometry: tuple[list[Box2], list[_View], float]) -> list[Page]:
    """The step pages; ``geometry``: :func:`_step_geometry`'s."""
    n = len(plan.steps)
    per = _steps_per_page(plan)
    size = 11.0 if per == 1 else 10.0
    pages = []
    legend_keys = _legend_keys(plan)
    slots, views, _ = geometry
    margin_sheet = f.margin  # the tutorial's sheet has the same margins as the workbook paper
    memo: dict[Any, Any] = {}  # _drawing's
    for first in range(0, n, per):
        idx = list(range(first, min(n, first + per)))
        if len(idx) == 1:
            rng = _t("step.range_one", first=idx[0] + 1, n=n)
            mark = _t("step.bookmark_one", first=idx[0] + 1)
        else:
            rng = _t("step.range_many", first=idx[0] + 1, last=idx[-1] + 1, n=n)
            mark = _t("step.bookmark_many", first=idx[0] + 1, last=idx[-1] + 1)
        items: list[Item] = []
        head, top = _header(f, _t("step.header", title=title, view=view_label, level=level), rng)
        items += head
        legend, _ = _legend(f, _footer_y(f) + 5.0, legend_keys)
        items += legend
        texts = []
        for i in idx:
            texts.append((plan.steps[i], hints[i]))
        sw = slots[0][2] - slots[0][0]
        for (step, hint), slot, view, i in zip(texts, slots, views, idx):
            sx0 = slot[0]
            items += _step_panel(view, plan, i, margin_sheet, (slot[0], view.rect[1],
                                                               slot[2], view.rect[3]), memo)
            ttop = view.rect[1] - 3.0
            items.append(Text(sx0, ttop - 0.72 * 12 * PT_MM, _t("step.number", index=step.index),
                              12, "Helvetica-Bold", "start", "black", "step_number"))
            para, below = _instruction(sx0, ttop - 6.5, sw, step, size)
            items += para
            if hint:
                para, _ = _paragraph(sx0, below - 2.0, sw, hint, 8.5, font="Helvetica-Oblique",
                                     role="erase_hint", colour="grey")
                items += para
        pages.append(Page(f.width, f.height, tuple(items), (Bookmark(mark),), "steps", title, f.margin))
    return pages


def _final_page(f: _Frame, title: str, plan: ViewPlan, view_label: str, level: str,
                final: Sequence[Stroke], view: _View) -> Page:
    """The finished drawing, in ``view``: the step pages' first picture, same place."""
    items: list[Item] = []
    head, top = _header(f, _t("final.heading"),
                        _t("step.header", title=title, view=view_label, level=level))
    items += head
    x0, _, x1, _ = f.box
    items += _sheet_background(view, plan.paper_mm, f.margin)
    for s in _final_strokes(plan, final):
        items += view.lines(s.points_mm, STYLES["final"], "stroke_final")
    para, _ = _paragraph(x0, view.rect[1] - 3.0, x1 - x0, _t("final.caption"), 9.5, role="caption")
    items += para
    return Page(f.width, f.height, tuple(items), (Bookmark(_t("final.bookmark")),), "final", title, f.margin)


def _check_paper(paper: PaperSpec) -> float:
    if not (paper.margin_mm >= MIN_MARGIN_MM):
        raise RenderError(f"paper.margin_mm: {paper.margin_mm} mm is below the {MIN_MARGIN_MM} mm "
                          "printers need")
    if min(paper.width_mm, paper.height_mm) < 4 * paper.margin_mm + 60:
        raise RenderError(f"paper.margin_mm: {paper.margin_mm} mm leaves no room on "
                          f"{paper.size} paper")
    return float(paper.margin_mm)


def lay_out_workbook(title: str, plan: ViewPlan, paper: PaperSpec, *, view_label: str,
                     grid: bool = False,
                     final: tuple[Stroke, ...] = (), margin_mm: float | None = None,
                     level_label: str | None = None, how: Sequence[str] | None = None,
                     cover_level: bool = True, cover_time: bool = True) -> tuple[Page, ...]:
    """Every page of one workbook (one model, view and level), laid out in mm.

    Pages: cover, primer, step pages (1 step per page for novices, else 2), the finished
    drawing, and the calibrated drawing sheet (:func:`lay_out_sheet`, at ``plan.paper_mm``).
    Level ``basic`` (a study's control condition) gets no primer and a cover whose "how to
    use" text (``cover.how_basic``) says nothing of guides.

    Args:
        title: the tutorial's title (config ``title``).
        plan: the view's steps, camera and vanishing points.
        paper: the workbook's paper size, orientation and margins.
        view_label: the view's name as shown to the reader.
        final: the finished drawing's strokes (sheet mm); default: every step's strokes.
        margin_mm: margin of the drawing sheet's frame, mm; default ``paper.margin_mm``.
        grid: a perspective grid on the drawing sheet (:func:`lay_out_sheet`).
        level_label: the level as the reader sees it (default ``templates/pages.yaml``
            ``levels``): a study's packets name conditions neutrally, never "novice".
        how: the cover's "how to use" lines, replacing ``cover.how`` (a study packet's
            sheet is not the workbook's last page).
        cover_level: the cover says the level ("Level: novice"); a study packet's does not
            (its condition is in the headers, in neutral words).
        cover_time: the cover gives the estimated time; a study packet's does not (it
            differed between conditions, 25-30 against 15 minutes, a cue to which tutorial is
            the fuller one and a pace to keep: a study designer's review).

    Returns:
        The pages in print order, page numbers in the footers, bookmarks attached.

    Raises:
        RenderError: margins below 5 mm or leaving no room, or a plan without steps.
    """
    margin = _check_paper(paper)
    if not plan.steps:
        raise RenderError(f"view {plan.name!r} ({plan.level}): no steps to lay out")
    sheet_margin = margin if margin_mm is None else float(margin_mm)
    f = _Frame(paper.width_mm, paper.height_mm, margin)
    title = plain_text(title)
    view_label = plain_text(view_label)
    level = plain_text(level_label) if level_label is not None else _level_name(plan.level)
    right = _t("step.header", title=title, view=view_label, level=level)
    pages: list[Page] = [_cover_page(f, title, plan, view_label, final,
                                     level if cover_level else None, how, cover_time)]
    if plan.level != "basic":  # the control condition gets no How2Sketch constructions
        pages.append(_primer_page(f, title, right, primer_diagrams(), _primer_intro(plan)))
    hints = _erase_hints(plan)
    geometry = _step_geometry(f, plan, hints)  # the step pages' and the finished drawing's
    pages += _step_pages(f, title, plan, view_label, level, hints, geometry)
    pages.append(_final_page(f, title, plan, view_label, level, final, geometry[1][0]))
    from .sheet import lay_out_sheet  # (the sheet's module builds on this one)

    pages.append(lay_out_sheet(title, plan, margin_mm=sheet_margin, view_label=view_label,
                               grid=grid, drawing=[s.points_mm for s in
                                                   _final_strokes(plan, final)]))
    return _with_footers(pages, lambda n, total: _t("footer", title=title, view=view_label,
                                                    level=level, page=n, pages=total))



# ----------------------------------------------------------------------------- calibrated sheet


def vp_names(plan: ViewPlan) -> dict[int, str]:
    """How the sheet and the step panels name each vanishing point, by axis.

    The words of the step instructions: :func:`h2s_print.project.vp_side` seen from the sheet's
    centre gives "right/left vanishing point" or "vanishing point above/below"
    (``sheet.vp_names.<side>``); when two VPs share a side both add their edges ("... of the
    left-right edges", ``<side>_of``, edges from ``templates/steps.yaml`` ``edges``).  A VP at
    infinity is named by its edges (``sheet.vp_names.infinite``).
    """
    centre = (plan.paper_mm[0] / 2.0, plan.paper_mm[1] / 2.0)
    edges = templates.lookup("steps", "edges")
    sides = {vp.axis: vp_side(vp, centre) for vp in plan.vanishing_points}
    names: dict[int, str] = {}
    for axis, side in sides.items():
        if side is None:
            names[axis] = _t("sheet.vp_names.infinite", edges=edges[axis])
        elif sum(1 for other in sides.values() if other == side) > 1:
            names[axis] = _t(f"sheet.vp_names.{side}_of", edges=edges[axis])
        else:
            names[axis] = _t(f"sheet.vp_names.{side}")
    return names


# ----------------------------------------------------------------------------- book


def lay_out_book(title: str, workbooks: Sequence[tuple[str, tuple[Page, ...]]]) -> tuple[Page, ...]:
    """Many workbooks in one document: a title page, contents, then each workbook's pages.

    Args:
        title: the book's title.
        workbooks: ``(label, pages)``; ``label`` is ``"tutorial > view > level"`` (parts joined by
            :data:`OUTLINE_SEP`; fewer parts are fine), ``pages`` from :func:`lay_out_workbook`.

    Returns:
        All pages; outline: each label part once per run of workbooks sharing it (tutorial at
        level 0, view 1, level 2), the workbook's own bookmarks below; footers renumbered.
    """
    if not workbooks:
        raise RenderError(f"book {title!r}: no workbooks to lay out")
    title = plain_text(title)
    first = workbooks[0][1][0]
    w, h = first.width_mm, first.height_mm
    m = first.margin_mm
    f = _Frame(w, h, m)
    x0, y0, x1, y1 = f.box
    # Contents lines: one per workbook (label parts joined), dotted to the page number.
    size, lead = 10.0, 6.0
    head_h = 30.0
    per_page = max(1, int((y1 - y0 - head_h - 8.0) // lead))
    n_contents = math.ceil(len(workbooks) / per_page)
    start = 1 + n_contents + 1  # title page, contents pages, then the first workbook page
    starts = []
    for _, pages in workbooks:
        starts.append(start)
        start += len(pages)
    # Title page.
    items: list[Item] = []
    top = y1 - 0.3 * (y1 - y0)
    para, top = _paragraph(x0, top, x1 - x0, _t("book.kicker"), 12, role="kicker", colour="grey")
    items += para
    para, top = _paragraph(x0, top - 4, x1 - x0, title, 30, font="Helvetica-Bold", role="title")
    items += para
    count = plain_text(templates.plural("pages", "book.count", len(workbooks)))
    para, _ = _paragraph(x0, top - 6, x1 - x0, count, 12, role="count")
    items += para
    out: list[Page] = [Page(w, h, tuple(items), (Bookmark(_t("book.bookmark_title")),), "title", title, m)]
    for c in range(n_contents):
        items = []
        head, top = _header(f, _t("book.contents") if c == 0 else _t("book.contents_more"), title)
        items += head
        y = top - 6.0
        for k in range(c * per_page, min(len(workbooks), (c + 1) * per_page)):
            label = plain_text(workbooks[k][0])
            parts = [p.strip() for p in label.split(OUTLINE_SEP.strip())]
            shown = "  -  ".join(parts)
            num = str(starts[k])
            nw = text_width_mm(num, size)
            line = wrap(shown, x1 - x0 - nw - 12, size)[0]
            items.append(Text(x0, y, line, size, "Helvetica", "start", "black", "contents_entry"))
            lw = text_width_mm(line, size)
            items.append(Polyline(((x0 + lw + 2, y + 0.3), (x1 - nw - 2, y + 0.3)), "lightgrey",
                                  0.3, (0.3, 1.2), False, "contents_dots"))
            items.append(Text(x1, y, num, size, "Helvetica", "end", "black", "contents_page"))
            y -= lead
        marks = (Bookmark(_t("book.bookmark_contents")),) if c == 0 else ()
        out.append(Page(w, h, tuple(items), marks, "contents", title, m))
    previous: list[str] = []
    for label, pages in workbooks:
        parts = [plain_text(p.strip()) for p in label.split(OUTLINE_SEP.strip())]
        common = 0
        while common < min(len(parts), len(previous)) and parts[common] == previous[common]:
            common += 1
        heads = tuple(Bookmark(p, lvl) for lvl, p in enumerate(parts) if lvl >= common)
        previous = parts
        depth = len(parts)
        for j, page in enumerate(pages):
            marks = tuple(Bookmark(b.title, b.level + depth) for b in page.bookmarks)
            if j == 0:
                marks = heads + marks
            out.append(replace(page, bookmarks=marks, title=title))
    return _with_footers(out, lambda n, total: _t("book.footer", title=title, page=n, pages=total))
