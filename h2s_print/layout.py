"""Layout stage (DESIGN.md §2.9): steps + templates + paper -> pages, every coordinate in mm.

Nothing here draws: each page is a frozen :class:`Page` holding frozen items (:class:`Polyline`,
:class:`Text`, :class:`Rect`, :class:`Circle`) in page millimetres, origin at the page's
bottom-left corner, x to the right, y up (the sheet's own convention).  ``render.py`` turns
pages into PDF/SVG/PNG.

Public verbs: :func:`lay_out_workbook`, :func:`lay_out_sheet`, :func:`lay_out_book`, and
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
  wording (``cover.how_basic``), a key without guide styles (no step has guides), and the
  level is shown as plain "basic", so the control workbook never mentions guides.
* **Book outline**: a workbook label ``"Camera > front-left > novice"`` (parts joined by
  :data:`OUTLINE_SEP`) gives outline levels tutorial > view > level; the workbook's own
  bookmarks (cover, primer, steps ...) sit one level below.
"""

from __future__ import annotations

import logging
import math
import re
from dataclasses import dataclass, replace
from typing import Callable, Iterable, Sequence

import numpy as np

from . import templates
from .config import MIN_MARGIN_MM, PaperSpec, ViewSpec
from .constructions import Face, construct, ellipse_on_face
from .errors import RenderError
from . import fonts
from .glyphs import ascii_font, printable, spelled
from .project import edge_exit, horizon_mm, make_camera, vp_side
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
    "vanishing": LineStyle("lightgrey", 0.2, (5.0, 2.0)),
    "corner": LineStyle("green", 0.8),
    "frame": LineStyle("lightgrey", 0.2),
    "final": LineStyle("black", 0.4),
    "face": LineStyle("black", 0.4),
    "construction": LineStyle("orange", 0.25, (1.6, 1.0)),
    "result": LineStyle("orange", 0.6),
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
    return "".join(spelled(ch) if printable(ch) else "?" for ch in text)


def text_width_mm(string: str, size_pt: float, font: str = "Helvetica") -> float:
    """Advance width of ``string`` (already plain) set in style ``font`` of the current page
    font at ``size_pt``, mm."""
    return fonts.width_mm(string, size_pt, font)


def wrap(string: str, width_mm: float, size_pt: float, font: str = "Helvetica") -> list[str]:
    """Greedy word wrap of ``string`` into lines no wider than ``width_mm`` (long words split);
    lines break at plain spaces only, never at a no-break space (French « : », Russian
    «с. 3»)."""
    words = [w for w in re.split(r"[ \t\n\r]+", plain_text(string)) if w]
    lines: list[str] = []
    line = ""
    for word in words:
        while text_width_mm(word, size_pt, font) > width_mm and len(word) > 1:
            cut = len(word) - 1
            while cut > 1 and text_width_mm(word[:cut], size_pt, font) > width_mm:
                cut -= 1
            if line:
                lines.append(line)
                line = ""
            lines.append(word[:cut])
            word = word[cut:]
        trial = f"{line} {word}" if line else word
        if text_width_mm(trial, size_pt, font) <= width_mm:
            line = trial
        else:
            lines.append(line)
            line = word
    if line:
        lines.append(line)
    return lines


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

    def lines(self, points: Sequence[Pt], style: LineStyle, role: str,
              closed: bool = False) -> list[Polyline]:
        mapped = [self.map(p) for p in points]
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


def _arrow(tip: Pt, direction: Pt, length: float, colour: str, width: float, role: str) -> list[Polyline]:
    """A shaft ending at ``tip`` pointing along ``direction`` with a two-stroke head."""
    dx, dy = direction
    n = math.hypot(dx, dy) or 1.0
    dx, dy = dx / n, dy / n
    tail = (tip[0] - dx * length, tip[1] - dy * length)
    head = min(2.5, length / 2)
    left = (tip[0] - head * (dx * 0.87 - dy * 0.5), tip[1] - head * (dy * 0.87 + dx * 0.5))
    right = (tip[0] - head * (dx * 0.87 + dy * 0.5), tip[1] - head * (dy * 0.87 - dx * 0.5))
    return [Polyline((tail, tip), colour, width, (), False, role),
            Polyline((left, tip, right), colour, width, (), False, role)]


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
        out.append((g, "guide_new" if g.status == "new" else "guide_reused"))
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
    order = {"guide_idle": 0, "guide_reused": 1, "guide_new": 2}
    return sorted(out, key=lambda gs: order[gs[1]])


def _erasable(plan: ViewPlan, i: int) -> int:
    """Guide lines shown at step ``i`` that are no longer shown at step ``i + 1``."""
    if i + 1 >= len(plan.steps):
        return 0
    shown = {g.id for g, _ in _step_guides(plan, i)}
    later = {g.id for g, _ in _step_guides(plan, i + 1)}
    return len(shown - later)


def _stroke_points(strokes: Iterable[Stroke]) -> list[Pt]:
    return [tuple(p) for s in strokes for p in s.points_mm]  # type: ignore[misc]


def _vanishing_lines(view: _View, plan: ViewPlan, strokes: Sequence[Stroke]) -> list[Item]:
    """Two lines per finite VP enclosing ``strokes``, clipped to the panel; VP marks inside it."""
    box = _bbox(_stroke_points(strokes))
    items: list[Item] = []
    style = STYLES["vanishing"]
    names = vp_names(plan)
    for vp in sorted(plan.vanishing_points, key=lambda v: v.axis):
        if vp.at_infinity or vp.xy_mm is None:
            continue
        v = (float(vp.xy_mm[0]), float(vp.xy_mm[1]))
        if box is not None:
            corners = [(box[0], box[1]), (box[2], box[1]), (box[2], box[3]), (box[0], box[3])]
            ref = math.atan2(((box[1] + box[3]) / 2) - v[1], ((box[0] + box[2]) / 2) - v[0])
            def rel(c: Pt) -> float:
                a = math.atan2(c[1] - v[1], c[0] - v[0]) - ref
                return (a + math.pi) % (2 * math.pi) - math.pi
            spread = sorted(corners, key=rel)
            for corner in (spread[0], spread[-1]):
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


def _step_panel(view: _View, plan: ViewPlan, i: int, margin: float) -> list[Item]:
    """The cumulative drawing at step ``i`` (0-based) in ``view``, lettered; crowded letters
    go in a close-up (:func:`_close_up`) drawn in a corner of the picture."""
    step = plan.steps[i]
    items: list[Item] = _sheet_background(view, plan.paper_mm, margin)
    drawing = _drawing(view, plan, i)
    items += drawing
    zoom = _close_up(view, step, _segments(items), _segments(
        [it for it in drawing if isinstance(it, Polyline) and it.role.startswith("stroke")]))
    if zoom is None:
        return items + place_labels(view, step.labels, items)
    region, zview = zoom
    items += place_labels(view, [lb for lb in step.labels if lb.kind == "part"], items)
    items.append(Rect(region[0], region[1], region[2] - region[0], region[3] - region[1],
                      "grey", 0.25, None, "close_up_region"))
    x0, y0, x1, y1 = zview.rect
    items.append(Rect(x0, y0, x1 - x0, y1 - y0, "grey", 0.35, "white", "close_up"))
    # its caption outside it, on the side toward the middle of the picture
    size, cap = CLOSE_UP_CAPTION_PT, 0.72 * CLOSE_UP_CAPTION_PT * PT_MM
    below = (y0 + y1) / 2 > (view.rect[1] + view.rect[3]) / 2
    items.append(Text(x0, y0 - 1.0 - cap if below else y1 + 1.0, _t("step.close_up"), size,
                      "Helvetica-Oblique", "start", "grey", "close_up_caption"))
    lines = _drawing(zview, plan, i)
    return items + lines + place_labels(zview, [lb for lb in step.labels
                                                if lb.kind == "point"], lines)


#: A step's lettered points get a close-up when two of them lie closer than this on the
#: picture (page mm; about two letter heights) ...
CLOSE_UP_CROWDED_MM = 5.0
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
CLOSE_UP_CAPTION_PT = 6.5


def _close_up(view: _View, step: Step, segs: np.ndarray, drawn: np.ndarray
              ) -> tuple[Box2, _View] | None:
    """Where a crowded step's letters go: the region round its lettered points (page mm) and
    the view that magnifies it into a corner (or the middle of an edge) of the picture, or
    None when the letters have room (no two points closer than :data:`CLOSE_UP_CROWDED_MM`)
    or no place can take the close-up without covering the region or a part's name.  Of the
    places that can, the one hiding the fewest lines of the object (``drawn``, segments of
    its strokes), then the most magnified (a smaller close-up is tried where the largest
    covers the object), then the one hiding the fewest lines of any kind (``segs``)."""
    pts = [view.map(lb.at_mm) for lb in step.labels if lb.kind == "point"]
    if len(pts) < 2:
        return None
    closest = min(math.dist(a, b) for k, a in enumerate(pts) for b in pts[k + 1:])
    if closest >= CLOSE_UP_CROWDED_MM:
        return None
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    pad = CLOSE_UP_PAD_MM
    region = (min(xs) - pad, min(ys) - pad, max(xs) + pad, max(ys) + pad)
    rw, rh = region[2] - region[0], region[3] - region[1]
    x0, y0, x1, y1 = view.rect
    zoom = min(CLOSE_UP_MAX_ZOOM, CLOSE_UP_SPACING_MM / max(closest, 1e-9),
               CLOSE_UP_SHARE * (x1 - x0) / rw, CLOSE_UP_SHARE * (y1 - y0) / rh)
    if zoom < CLOSE_UP_MIN_ZOOM:
        return None
    m = CLOSE_UP_INSET_MM
    names = [view.map(lb.at_mm) for lb in step.labels if lb.kind == "part"]
    best: tuple[tuple[int, float, int], Box2] | None = None
    # largest first, smaller (down to the least zoom) where a larger one covers the object
    for z in (zoom * f for f in (1.0, 0.85, 0.7, 0.55)):
        if z < CLOSE_UP_MIN_ZOOM:
            break
        w, h = rw * z, rh * z
        cx, cy = (x0 + x1 - w) / 2, (y0 + y1 - h) / 2
        for bx, by in ((x1 - m - w, y1 - m - h), (x0 + m, y1 - m - h),
                       (x1 - m - w, y0 + m), (x0 + m, y0 + m),
                       (cx, y1 - m - h), (cx, y0 + m), (x0 + m, cy), (x1 - m - w, cy)):
            box = (bx, by, bx + w, by + h)
            if _boxes_overlap(box, region) or any(
                    box[0] <= q[0] <= box[2] and box[1] <= q[1] <= box[3] for q in names):
                continue
            score = (_crossings(drawn, box), -z, _crossings(segs, box))
            if best is None or score < best[0]:
                best = (score, box)
        if best is not None and best[0][0] == 0:
            break
    if best is None:
        return None
    s = view.scale
    window = (view.window[0] + (region[0] - x0) / s, view.window[1] + (region[1] - y0) / s,
              view.window[0] + (region[2] - x0) / s, view.window[1] + (region[3] - y0) / s)
    return region, _View(window, best[1])


def _drawing(view: _View, plan: ViewPlan, i: int) -> list[Item]:
    """The lines of the picture at step ``i`` in ``view`` (no sheet, no letters)."""
    step = plan.steps[i]
    items: list[Item] = _vanishing_lines(view, plan, step.strokes)
    # Earlier lines: the scaffold grey (its hidden edges dotted, fainter), contours already
    # drawn in ink, so the object emerges from its scaffold as in the paper's figures.
    for earlier in plan.steps[:i]:
        for s in earlier.strokes:
            key = {"contour": "ink", "scaffold_hidden": "earlier_hidden",
                   "ellipse_hidden": "earlier_hidden"}.get(s.kind, "earlier")
            items += view.lines(s.points_mm, STYLES[key], f"stroke_{key}")
    for g, key in _step_guides(plan, i):
        items += view.lines([g.from_mm, g.to_mm], STYLES[key], key)
    for s in step.strokes:
        key = "new_hidden" if s.kind in ("scaffold_hidden", "ellipse_hidden") else "new"
        items += view.lines(s.points_mm, STYLES[key], "stroke_new")
    return items


#: Letters on a step's picture: size (pt), dot radius (mm), distances from the dot tried (mm).
LABEL_PT = 7.5
LABEL_DOT_MM = 0.45
LABEL_RADII_MM = (1.0, 1.8, 2.8, 4.0, 5.5, 7.5)
#: Further rings, tried only for a label that finds no room on the rings above (a crowded
#: picture of a big assembly): farther from its dot, but never on another label.
LABEL_RADII_FAR_MM = (10.0, 13.0, 17.0, 22.0)
#: Directions tried round a point, in order of preference (right, up, left, down, diagonals).
_LABEL_DIRS = ((1, 0), (0, 1), (-1, 0), (0, -1), (1, 1), (-1, 1), (-1, -1), (1, -1))


def _segments(items: Sequence[Item]) -> np.ndarray:
    """(n, 4) segments ``x0 y0 x1 y1`` of every polyline among ``items``, page mm."""
    segs = []
    for it in items:
        if isinstance(it, Polyline) and len(it.points_mm) > 1:
            pts = np.asarray(it.points_mm, dtype=float)
            if it.closed:
                pts = np.vstack([pts, pts[:1]])
            segs.append(np.hstack([pts[:-1], pts[1:]]))
    return np.vstack(segs) if segs else np.zeros((0, 4))


def _crossings(segs: np.ndarray, box: Box2) -> int:
    """How many of ``segs`` meet the rectangle ``box`` (separating axes: x, y, the segment's
    normal)."""
    if not len(segs):
        return 0
    x0, y0, x1, y1 = box
    sx0, sy0, sx1, sy1 = segs.T
    near = ((np.minimum(sx0, sx1) <= x1) & (np.maximum(sx0, sx1) >= x0)
            & (np.minimum(sy0, sy1) <= y1) & (np.maximum(sy0, sy1) >= y0))
    if not near.any():
        return 0
    s = segs[near]
    dx, dy = s[:, 2] - s[:, 0], s[:, 3] - s[:, 1]
    sides = np.stack([dx * (cy - s[:, 1]) - dy * (cx - s[:, 0])
                      for cx, cy in ((x0, y0), (x1, y0), (x1, y1), (x0, y1))])
    return int(np.count_nonzero(~((sides > 0).all(axis=0) | (sides < 0).all(axis=0))))


def _boxes_overlap(a: Box2, b: Box2) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def place_labels(view: _View, labels: Sequence[Label], items: Sequence[Item]) -> list[Item]:
    """A dot at each label's point and its letters beside it (roles ``label_point`` and
    ``label``; a part's short name, kind ``part``, in blue without a dot, on the part if there
    is room: role ``part_label``), placed so that no two labels overlap each other or another label's dot, every
    label stays inside the picture, each label is nearer its own dot than any other dot when
    possible, and then as few drawn lines as possible cross it, each ring further from the dot
    counting as one line crossed (then the preferred direction).

    Raises:
        RenderError: no place is free for a label (more labels than the picture can hold).
    """
    segs = _segments(items)
    dots = [view.map(lb.at_mm) for lb in labels]
    x0, y0, x1, y1 = view.rect
    taken: list[Box2] = [(dx - LABEL_DOT_MM, dy - LABEL_DOT_MM, dx + LABEL_DOT_MM,
                          dy + LABEL_DOT_MM) if lb.kind == "point" else (dx, dy, dx, dy)
                         for lb, (dx, dy) in zip(labels, dots)]
    out: list[Item] = []
    pad = 0.25
    for k, (lb, (dx, dy)) in enumerate(zip(labels, dots)):
        part = lb.kind == "part"  # a part's short name: centred on the part, no dot
        if not part:
            out.append(Circle(dx, dy, LABEL_DOT_MM, None, 0.0, "black", "label_point"))
        w = text_width_mm(lb.name, LABEL_PT, "Helvetica-Bold")
        cap, desc = 0.72 * LABEL_PT * PT_MM, 0.21 * LABEL_PT * PT_MM
        best: tuple[tuple, Text] | None = None
        rings = ((0.0,) if part else ()) + LABEL_RADII_MM + LABEL_RADII_FAR_MM
        for ri, r in enumerate(rings):
            if best is not None and r in LABEL_RADII_FAR_MM:
                break  # the far rings only when nothing nearer is free
            for di, (ux, uy) in enumerate(_LABEL_DIRS if r else ((0, 0),)):  # r 0: centred
                norm = math.hypot(ux, uy) or 1.0
                cx, cy = dx + r * ux / norm, dy + r * uy / norm
                # the label's box touches (cx, cy) on the side facing the dot
                bx0 = cx if ux > 0 else (cx - w if ux < 0 else cx - w / 2)
                by0 = cy if uy > 0 else (cy - cap - desc if uy < 0 else cy - (cap + desc) / 2)
                box = (bx0 - pad, by0 - pad, bx0 + w + pad, by0 + cap + desc + pad)
                if box[0] < x0 or box[1] < y0 or box[2] > x1 or box[3] > y1:
                    continue
                if any(_boxes_overlap(box, t) for j, t in enumerate(taken) if j != k):
                    continue
                # a label must read as its own dot's: nearer to it than to any other dot; then
                # few lines across it, then near its dot (a line crossed costs a ring)
                mx, my = (box[0] + box[2]) / 2, (box[1] + box[3]) / 2
                own = math.hypot(mx - dx, my - dy)
                ambiguous = any(math.hypot(mx - ox, my - oy) < own
                                for j, (ox, oy) in enumerate(dots)
                                if j != k and labels[j].kind == "point")
                score = (ambiguous, _crossings(segs, box) + ri, di)
                if best is None or score < best[0]:
                    best = (score, Text(bx0, by0 + desc, lb.name, LABEL_PT, "Helvetica-Bold",
                                        "start", "blue" if part else "black",
                                        "part_label" if part else "label"))
            if best is not None and not best[0][0] and best[0][1] <= ri:
                break  # nothing further out can score better
        if best is None:
            raise RenderError(f"no room on the picture for the label {lb.name!r}")
        text = best[1]
        out.append(text)
        b = text.box_mm
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


def primer_diagrams() -> tuple[PrimerDiagram, ...]:
    """The primer's constructions, built in 3D on one box face and projected (two-point view).

    Each diagram is the face ``x in [0, 1], z in [0, 1.25]`` at ``y = 0`` seen from the
    front-right, with the lines of ``h2s_print.constructions.construct`` for its ratios (shared
    lines once), projected by a camera from ``h2s_print.project.make_camera``; so every crossing
    the diagram shows is where a ruler construction on paper lands.  Extensions also show the
    new face's top and bottom edges as results.  Coordinates are that camera's sheet mm (the
    page fits them into a cell).
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


def _primer_page(f: _Frame, title: str, header_right: str,
                 diagrams: Sequence[PrimerDiagram]) -> Page:
    items: list[Item] = []
    head, top = _header(f, _t("primer.heading"), header_right)
    items += head
    x0, y0, x1, _ = f.box
    intro, top = _paragraph(x0, top, x1 - x0, _t("primer.intro"), 9.5, role="intro")
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
                how: Sequence[str] | None = None) -> Page:
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
             _t("cover.time", minutes=estimate_minutes(plan))]
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
    for line in how if how is not None else templates.lookup("pages", how_key):
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
        for label, name in plan.part_names:
            para, top = _paragraph(x0 + 4, top, text_w - 4, _t("parts.entry", label=label,
                                                                full=name), 9, role="part_name")
            items += para
            top -= 1
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
    """Every step's :func:`_erase_hint`, the scaffold edges gathered once as the steps go."""
    out: list[str] = []
    edges: list[np.ndarray] = []
    for i, step in enumerate(plan.steps):
        edges.append(_step_edges(step))
        out.append(_erase_hint(plan, i, np.vstack(edges)))
    return out


def _erase_hint(plan: ViewPlan, i: int, edges: np.ndarray | None = None) -> str:
    """The step's "you may erase ..." line (empty when nothing retires): the lines by their
    letters ("Afterwards you may erase AC, BD and FG.") when the ends of each are lettered on
    this step's picture, else their number and where to see which (the next picture no
    longer shows them).  A guide that runs along an edge of the scaffold is erased only
    beyond it (the mixer's KU along the column's edge KL is "LU"), and not at all when it
    lies on the edge whole (:func:`_off_edges`)."""
    if _erasable(plan, i) == 0:
        return ""
    later = {g.id for g, _ in _step_guides(plan, i + 1)}
    if edges is None:
        edges = np.vstack([_step_edges(st) for st in plan.steps[:i + 1]])
    names: list[str | None] = []
    for g, _ in _step_guides(plan, i):
        if g.id in later:
            continue
        pieces = _off_edges(g, edges)
        if not pieces:
            continue  # an edge of the drawing itself: nothing to erase
        name = _letters_at(plan.steps[i], pieces[0]) if len(pieces) == 1 else None
        if name not in names or name is None:
            names.append(name)
    if not names:
        return ""
    if None in names:
        return plain_text(templates.plural("pages", "step.erase", len(names)))
    join, last = templates.lookup("steps", "join"), templates.lookup("steps", "join_last")
    said = [n for n in names if n is not None]
    lines = said[0] if len(said) == 1 else join.join(said[:-1]) + last + said[-1]
    return plain_text(templates.text("pages", "step.erase_named", lines=lines))


#: A guide's piece lies along a scaffold edge when both ends of the edge's segment are this
#: close to the guide's line (sheet mm) ...
ON_EDGE_MM = 0.05
#: ... and a piece left over shorter than this is not a line to erase (sheet mm).
ERASE_MIN_MM = 0.5


def _step_edges(step: Step) -> np.ndarray:
    """(n, 4) segments of the scaffold edges ``step`` draws, sheet mm."""
    segs = [np.hstack([p[:-1], p[1:]]) for s in step.strokes
            if s.kind in ("scaffold", "scaffold_hidden")
            for p in (np.asarray(s.points_mm, dtype=float),) if len(p) > 1]
    return np.vstack(segs) if segs else np.zeros((0, 4))


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
                    if lb.kind == "point" and math.dist(lb.at_mm, end) <= ON_EDGE_MM), None)
        if hit is None:
            return None
        out += hit
    return out


def _steps_per_page(plan: ViewPlan) -> int:
    return 1 if plan.level == "novice" else 2


def _legend_keys(plan: ViewPlan) -> list[str]:
    # the new part's hidden edges have a key of their own: dotted orange read as "new guide"
    keys = ["earlier", "earlier_hidden", "ink", "new", "new_hidden", "guide_new", "guide_reused",
            "guide_idle", "vanishing", "corner"]
    if not any(step.guides for step in plan.steps):  # master and basic: no guide styles to explain
        keys = [k for k in keys if not k.startswith("guide_")]
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
                hints: Sequence[str]) -> list[Page]:
    n = len(plan.steps)
    per = _steps_per_page(plan)
    size = 11.0 if per == 1 else 10.0
    pages = []
    legend_keys = _legend_keys(plan)
    slots, views, _ = _step_geometry(f, plan, hints)
    margin_sheet = f.margin  # the tutorial's sheet has the same margins as the workbook paper
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
            items += _step_panel(view, plan, i, margin_sheet)
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
                final: Sequence[Stroke], hints: Sequence[str]) -> Page:
    items: list[Item] = []
    head, top = _header(f, _t("final.heading"),
                        _t("step.header", title=title, view=view_label, level=level))
    items += head
    x0, _, x1, _ = f.box
    view = _step_geometry(f, plan, hints)[1][0]  # the step pages' picture: same place
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
                     cover_level: bool = True) -> tuple[Page, ...]:
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
                                     level if cover_level else None, how)]
    if plan.level != "basic":  # the control condition gets no How2Sketch constructions
        pages.append(_primer_page(f, title, right, primer_diagrams()))
    hints = _erase_hints(plan)
    pages += _step_pages(f, title, plan, view_label, level, hints)
    pages.append(_final_page(f, title, plan, view_label, level, final, hints))
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


def _horizon(plan: ViewPlan) -> tuple[float, float, float] | None:
    """:func:`h2s_print.project.horizon_mm` as ``(a, b, c)``: ``a x + b y + c = 0`` on the
    sheet (mm) with ``(a, b)`` a unit normal; ``None`` when the horizon is at infinity."""
    ends = horizon_mm(plan.camera)
    if ends is None:
        return None
    (x0, y0), (x1, y1) = ends
    a, b = y0 - y1, x1 - x0  # normal of the direction (x1 - x0, y1 - y0)
    n = math.hypot(a, b)
    if not n > 0.0:
        return None
    a, b = a / n, b / n
    return (a, b, -(a * x0 + b * y0))


def _first_box(plan: ViewPlan) -> tuple[str, np.ndarray, np.ndarray] | None:
    """The first scaffold step's part and the 3D box ``(lo, hi)`` around its stroke points."""
    for step in plan.steps:
        if step.kind not in ("primitive", "basic") or not step.strokes:
            continue
        pts = np.array([p for s in step.strokes for p in s.points3d], dtype=float)
        if len(pts) == 0:
            continue
        part = step.part or (step.strokes[0].part if step.strokes else "")
        return part, pts.min(axis=0), pts.max(axis=0)
    return None


def first_ground_quad(plan: ViewPlan) -> tuple[str, tuple[Pt, ...]] | None:
    """The first scaffold step's bottom face projected on the sheet: ``(part, 4 corners mm)``.

    The face is the bottom (lowest z) face of the 3D box around that step's stroke points.
    """
    found = _first_box(plan)
    if found is None:
        return None
    part, lo, hi = found
    z = lo[2]
    corners = [(lo[0], lo[1], z), (hi[0], lo[1], z), (hi[0], hi[1], z), (lo[0], hi[1], z)]
    if np.any(plan.camera.depth(corners) <= 0):
        return None
    proj = plan.camera.project(corners)
    return part, tuple((float(x), float(y)) for x, y in proj)


def first_near_edge(plan: ViewPlan) -> tuple[Pt, Pt] | None:
    """The first scaffold step's upright edge nearest the camera, projected on the sheet
    ``(bottom, top)`` mm: with the footprint it fixes the first box's height, which every
    later size is measured against (the read-through: step 1 never said how tall)."""
    found = _first_box(plan)
    if found is None:
        return None
    _, lo, hi = found
    if not hi[2] > lo[2]:
        return None  # a flat first part: its footprint is all of it
    eye = np.asarray(plan.camera.position, dtype=float)
    x, y = min(((x, y) for x in (lo[0], hi[0]) for y in (lo[1], hi[1])),
               key=lambda c: (math.hypot(c[0] - eye[0], c[1] - eye[1]), c))
    ends = [(x, y, lo[2]), (x, y, hi[2])]
    if np.any(plan.camera.depth(ends) <= 0):
        return None
    (bx, by), (tx, ty) = plan.camera.project(ends)
    return (float(bx), float(by)), (float(tx), float(ty))


#: Perspective grid (:func:`perspective_grid`): about this far apart where the lines leave the
#: frame, mm, and drawn like this.
GRID_SPACING_MM = 12.0
GRID_STYLE = LineStyle("lightgrey", 0.15)


def perspective_grid(plan: ViewPlan, frame: Box2) -> list[Polyline]:
    """Lines converging toward each vanishing point across ``frame`` (sheet mm), as printed
    perspective grids have (role ``grid``): from a finite vanishing point, rays at equal angles
    over the frame's span as seen from it, about :data:`GRID_SPACING_MM` apart where they
    leave the frame; toward one at infinity, parallels that far apart.  Every line lies on a
    line through its vanishing point (or along its direction)."""
    x0, y0, x1, y1 = frame
    corners = np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], dtype=float)
    reach = float(np.hypot(x1 - x0, y1 - y0))
    out: list[Polyline] = []

    def add(p: Pt, q: Pt) -> None:
        for piece in clip_polyline([p, q], frame):
            if math.hypot(piece[-1][0] - piece[0][0], piece[-1][1] - piece[0][1]) > 1.0:
                out.append(Polyline(tuple(piece), GRID_STYLE.colour, GRID_STYLE.width_mm, (),
                                    False, "grid"))

    for vp in sorted(plan.vanishing_points, key=lambda v: v.axis):
        if vp.at_infinity or vp.xy_mm is None:
            d = np.asarray(vp.direction_mm, dtype=float)
            d = d / np.linalg.norm(d)
            nrm = np.array([-d[1], d[0]])
            offs = corners @ nrm
            centre = corners.mean(axis=0)
            c0 = float(centre @ nrm)
            k0 = math.ceil((offs.min() - c0) / GRID_SPACING_MM)
            k1 = math.floor((offs.max() - c0) / GRID_SPACING_MM)
            for k in range(k0, k1 + 1):
                p = centre + (k * GRID_SPACING_MM) * nrm
                add(tuple(p - reach * d), tuple(p + reach * d))
            continue
        v = np.asarray(vp.xy_mm, dtype=float)
        rel = corners - v
        dist = np.hypot(rel[:, 0], rel[:, 1])
        far = float(dist.max())
        inside = x0 < v[0] < x1 and y0 < v[1] < y1
        if inside:
            lo, hi = 0.0, 2 * math.pi
        else:  # the frame's span seen from the VP (under half a turn: the frame is convex)
            mid = math.atan2(*(corners.mean(axis=0) - v)[::-1])
            ang = [(math.atan2(r[1], r[0]) - mid + math.pi) % (2 * math.pi) - math.pi
                   for r in rel]
            lo, hi = mid + min(ang), mid + max(ang)
        n = max(8, min(90, int(math.ceil((hi - lo) * far / GRID_SPACING_MM))))
        for k in range(1, n) if not inside else range(n):
            t = lo + (hi - lo) * k / n
            add((float(v[0]), float(v[1])),
                (float(v[0] + (far + reach) * math.cos(t)), float(v[1] + (far + reach) * math.sin(t))))
    return out


def _clear_of_texts(block: list[Text], items: Sequence[Item], frame: Box2,
                    vertical: bool, avoid: np.ndarray | None = None,
                    inside: np.ndarray | None = None) -> list[Text] | None:
    """``block`` moved along the frame's edge (``vertical``: up or down, else sideways) by the
    smallest step that keeps it clear of every text and line of :data:`_SHEET_LINES` in
    ``items``, of the segments ``avoid`` and of the convex polygon ``inside``, inside
    ``frame``; None when no such place is within 60 mm."""
    placed = [t.box_mm for t in items if isinstance(t, Text)]
    arrows = _segments([it for it in items if isinstance(it, Polyline)
                        and it.role in _SHEET_LINES])
    if avoid is not None and len(avoid):
        # only the segments the search can reach (60 mm along the edge, 20 mm across)
        bx = [t.box_mm for t in block]
        reach = (20.0 + 2.0, 60.0 + 2.0) if vertical else (60.0 + 2.0, 20.0 + 2.0)
        x0 = min(b[0] for b in bx) - reach[0]
        x1 = max(b[2] for b in bx) + reach[0]
        y0 = min(b[1] for b in bx) - reach[1]
        y1 = max(b[3] for b in bx) + reach[1]
        near = ((np.minimum(avoid[:, 0], avoid[:, 2]) <= x1)
                & (np.maximum(avoid[:, 0], avoid[:, 2]) >= x0)
                & (np.minimum(avoid[:, 1], avoid[:, 3]) <= y1)
                & (np.maximum(avoid[:, 1], avoid[:, 3]) >= y0))
        arrows = np.vstack([arrows, avoid[near]])

    def clear(dx: float, dy: float) -> bool:
        for t in block:
            b = t.box_at(t.x_mm + dx, t.y_mm + dy)
            if b[0] < frame[0] or b[2] > frame[2] or b[1] < frame[1] or b[3] > frame[3]:
                return False
            if any(b[0] < p[2] + 3.0 and p[0] < b[2] + 3.0 and b[1] < p[3] + 1.0
                   and p[1] < b[3] + 1.0 for p in placed):  # 3 mm apart along a line, 1 mm across
                return False
            if _crossings(arrows, (b[0] - 1.0, b[1] - 0.5, b[2] + 1.0, b[3] + 0.5)):
                return False
        return True

    # along the edge first, then also away from it, nearest first (2 mm steps, up to 60 mm)
    shifts = sorted(((a, c) for a in range(-30, 31) for c in range(-10, 11)),
                    key=lambda s: (abs(s[0]) + 2 * abs(s[1]), abs(s[1]), s))
    offsets = np.array([(2.0 * c, 2.0 * a) if vertical else (2.0 * a, 2.0 * c)
                        for a, c in shifts])
    free = np.ones(len(offsets), dtype=bool)
    if inside is not None and len(inside) >= 3:  # places whose texts' middles are all outside
        middles = np.array([((b[0] + b[2]) / 2, (b[1] + b[3]) / 2)
                            for b in (t.box_mm for t in block)])
        at = (offsets[:, None, :] + middles[None, :, :]).reshape(-1, 2)
        free = ~_in_convex_all(inside, at).reshape(len(offsets), len(block)).any(axis=1)
    for (dx, dy), ok in zip(offsets.tolist(), free.tolist()):
        if not ok:
            continue
        if clear(dx, dy):
            return [replace(t, x_mm=t.x_mm + dx, y_mm=t.y_mm + dy) for t in block]
    return None


#: Lines of the drawing sheet that no label may cross: arrows, the horizon, the footprint (and,
#: where there is room, the finished drawing: ``lay_out_sheet(drawing=...)``).
_SHEET_LINES = ("vp_arrow", "horizon", "ground", "ground_edge")


def _fits(texts: Sequence[Text], items: Sequence[Item], frame: Box2,
          avoid: np.ndarray | None = None, inside: np.ndarray | None = None) -> bool:
    """True when ``texts`` lie inside ``frame``, overlap no text already in ``items``, cross
    none of the sheet's lines there (:data:`_SHEET_LINES`) nor ``avoid``, and do not lie in
    the convex polygon ``inside``."""
    placed = [it.box_mm for it in items if isinstance(it, Text) and it.string]
    lines = _segments([it for it in items if isinstance(it, Polyline)
                       and it.role in _SHEET_LINES])
    if avoid is not None and len(avoid):
        lines = np.vstack([lines, avoid])
    for t in texts:
        x0, y0, x1, y1 = t.box_mm
        if x0 < frame[0] or y0 < frame[1] or x1 > frame[2] or y1 > frame[3]:
            return False
        if any(min(x1, b[2]) > max(x0, b[0]) and min(y1, b[3]) > max(y0, b[1]) for b in placed):
            return False
        if inside is not None and _in_convex(inside, ((x0 + x1) / 2, (y0 + y1) / 2)):
            return False
        if _crossings(lines, t.box_mm):
            return False
    return True


def _hull(points: Sequence[Pt]) -> np.ndarray:
    """The convex hull of ``points``, counter-clockwise (n, 2); empty when degenerate."""
    from scipy.spatial import ConvexHull, QhullError

    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    if len(pts) < 3:
        return np.zeros((0, 2))
    try:
        return pts[ConvexHull(pts).vertices]
    except (QhullError, ValueError):
        return np.zeros((0, 2))


def _in_convex(poly: np.ndarray, p: Pt) -> bool:
    """Is ``p`` inside the counter-clockwise convex polygon ``poly`` (n >= 3)?"""
    return bool(_in_convex_all(poly, np.asarray([p], dtype=float))[0])


def _in_convex_all(poly: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """Which of the points ``pts`` (m, 2) lie inside the counter-clockwise convex polygon
    ``poly`` (n >= 3; on its edge counts as inside)."""
    if len(poly) < 3:
        return np.zeros(len(pts), dtype=bool)
    a, b = poly, np.roll(poly, -1, axis=0)
    cross = ((b[:, 0] - a[:, 0])[None, :] * (pts[:, 1:2] - a[None, :, 1])
             - (b[:, 1] - a[:, 1])[None, :] * (pts[:, 0:1] - a[None, :, 0]))
    return (cross >= 0).all(axis=1)


def _corner_offset(v: Pt, frame: Box2) -> str:
    """Where ``v`` lies from the nearest green frame corner, in words (mm along x and y)."""
    corners = {"bottom_left": (frame[0], frame[1]), "bottom_right": (frame[2], frame[1]),
               "top_right": (frame[2], frame[3]), "top_left": (frame[0], frame[3])}
    key = min(corners, key=lambda k: (math.dist(corners[k], v), k))
    c = corners[key]
    dx, dy = v[0] - c[0], v[1] - c[1]
    return _t("sheet.vp_offset", dx=f"{abs(dx):.0f}", dy=f"{abs(dy):.0f}",
              hdir=_t("sheet.right" if dx >= 0 else "sheet.left"),
              vdir=_t("sheet.up" if dy >= 0 else "sheet.down"),
              corner=_t(f"sheet.corners.{key}"))


def registration_marks(paper_mm: tuple[float, float], margin_mm: float
                       ) -> tuple[tuple[Pt, Pt, Pt, Pt], float]:
    """The calibrated sheet's four registration marks: their centres, in the middle of the
    margin band at each corner (bottom-left, bottom-right, top-right, top-left), and their
    circles' radius, mm (the crosses reach half a millimetre beyond)."""
    w, h = float(paper_mm[0]), float(paper_mm[1])
    band = float(margin_mm) / 2
    r = min(2.5, max(1.0, band - 1.0))
    return ((band, band), (w - band, band), (w - band, h - band), (band, h - band)), r


def lay_out_sheet(title: str, plan: ViewPlan, *, margin_mm: float = 12.0, view_label: str = "",
                  ground_mm: Sequence[Pt] | None = None, grid: bool = False,
                  drawing: Sequence[Sequence[Pt]] = ()) -> Page:
    """The calibrated drawing sheet at true scale: 1 sheet mm is 1 page mm.

    The page is ``plan.paper_mm``.  It shows the frame (the paper margins) with green corners,
    each vanishing point (a mark when on the paper; otherwise an arrow on the frame pointing at
    it with its distance from the arrow's tip), the horizon, the ground plane of the first
    primitive (``ground_mm`` or :func:`first_ground_quad`), four registration marks in the
    margin band and a 100 mm scale bar with "print at 100% (actual size)".

    Args:
        title: the tutorial's title.
        plan: the view (camera, vanishing points, steps).
        margin_mm: the frame's inset from the paper edge, mm.
        view_label: the view's name for the heading (default ``plan.name``).
        ground_mm: four sheet points (mm) of the ground quad, overriding the computed one.
        grid: also a light perspective grid (config ``sheet.grid``): lines converging toward
            each vanishing point across the frame (:func:`perspective_grid`), so a ruler line
            toward a vanishing point far off the sheet can be drawn anywhere.
        drawing: the finished drawing's polylines (sheet mm), not printed: labels are placed
            where they cross none of its lines, so nothing is printed where the person draws
            (and where scoring a scan could not see the pencil).
    """
    w, h = float(plan.paper_mm[0]), float(plan.paper_mm[1])
    m = float(margin_mm)
    if m < MIN_MARGIN_MM or min(w, h) < 2 * m + 20:
        raise RenderError(f"drawing sheet {w:g} x {h:g} mm: margin {m:g} mm does not fit")
    if tuple(map(float, plan.camera.paper_mm)) != (w, h):
        raise RenderError(f"view {plan.name!r}: camera sheet {plan.camera.paper_mm} mm is not "
                          f"the plan's paper {plan.paper_mm} mm")
    title = plain_text(title)
    frame = _frame_box((w, h), m)
    items: list[Item] = []
    items.append(Rect(frame[0], frame[1], frame[2] - frame[0], frame[3] - frame[1], "lightgrey",
                      0.2, None, "frame"))
    if grid:
        items += perspective_grid(plan, frame)
    items += _green_corners(frame, 15.0)
    band = m / 2  # centre line of the margin band
    # Registration marks: a circle and cross centred in the margin band at each corner.
    centres, r = registration_marks((w, h), m)
    for cx, cy in centres:
        items.append(Circle(cx, cy, r, "black", 0.2, None, "registration"))
        arm = r + 0.5  # at a 15 mm margin the cross ends 4.5 mm from the edge: printers print it
        items.append(Polyline(((cx - arm, cy), (cx + arm, cy)), "black", 0.2, (), False, "registration"))
        items.append(Polyline(((cx, cy - arm), (cx, cy + arm)), "black", 0.2, (), False, "registration"))
    # Heading in the top band, scale bar in the bottom band.
    head = _t("sheet.heading", title=title, view=plain_text(view_label or plan.name),
              level=_level_name(plan.level))
    hx0, hx1 = band + r + 3, w - band - r - 3
    items.append(Text(hx0, h - band - 0.9, head, fit_line(head, hx1 - hx0, 7), "Helvetica",
                      "start", "grey", "sheet_title"))
    bar_x0 = band + r + 5
    bar_y = band - 0.5
    items.append(Polyline(((bar_x0, bar_y), (bar_x0 + 100.0, bar_y)), "black", 0.3, (), False, "scale_bar"))
    for k in range(11):
        tick = 1.6 if k % 5 == 0 else 0.9
        x = bar_x0 + 10.0 * k
        items.append(Polyline(((x, bar_y), (x, bar_y + tick)), "black", 0.2, (), False, "scale_tick"))
    items.append(Text(bar_x0 + 103.0, bar_y, _t("sheet.scale"), 7, "Helvetica", "start", "black",
                      "scale_label"))
    # Labels placed after the VP labels, at the first option that collides with no text.
    shadow = _segments([Polyline(tuple(p)) for p in drawing if len(p) >= 2])
    # where the learner will draw: the finished drawing's convex outline, its edges and its
    # inside (a label between the drawing's lines still sits on a surface to be drawn)
    hull = _hull([q for p in drawing for q in p])
    area = (np.vstack([shadow, np.hstack([hull, np.roll(hull, -1, axis=0)])])
            if len(hull) >= 3 else shadow)
    deferred: list[list[tuple[list[Text], list[Polyline]]]] = []
    # Horizon.
    hl = _horizon(plan)
    if hl is not None:
        a, b, c = hl
        # Two far points on the line, then clip to the frame.
        p0 = (-a * c, -b * c)
        d = (-b, a)
        far = 10 * (w + h)
        seg = _clip_segment((p0[0] - far * d[0], p0[1] - far * d[1]),
                            (p0[0] + far * d[0], p0[1] + far * d[1]), frame)
        if seg is not None and math.dist(*seg) > 1.0:
            left, right = sorted(seg)
            items.append(Polyline((left, right), "black", 0.25, (4.0, 1.5), False, "horizon"))
            # Label along the line, away from the VP labels (placed after them).
            options = []
            for t in (0.5, 0.35, 0.65, 0.2, 0.8):
                at = (left[0] + t * (right[0] - left[0]), left[1] + t * (right[1] - left[1]))
                for dy in (1.2, -3.2):
                    options.append(([Text(at[0], at[1] + dy, _t("sheet.horizon"), 7, "Helvetica",
                                          "middle", "black", "horizon_label")], []))
            deferred.append(options)
        else:
            cx = w / 2
            y_at = (-c - a * cx) / b if abs(b) > 1e-9 else None
            if y_at is not None:
                above = y_at > frame[3]
                dist = abs(y_at - (frame[3] if above else frame[1]))
                key = "sheet.horizon_above" if above else "sheet.horizon_below"
                ty = frame[3] - 5.0 if above else frame[1] + 3.0
                tip_y = frame[3] - 1.0 if above else frame[1] + 1.0
                up = (0.0, 1.0 if above else -1.0)
                note = _t(key, distance=f"{dist:.0f}")
                options = []
                for ax, tx, anchor in ((frame[0] + 4.0, frame[0] + 7.0, "start"),
                                       (frame[2] - 4.0, frame[2] - 7.0, "end"),
                                       (frame[0] + 0.3 * (frame[2] - frame[0]),
                                        frame[0] + 0.3 * (frame[2] - frame[0]) + 3.0, "start")):
                    options.append(([Text(tx, ty, note, 7, "Helvetica", anchor, "black",
                                          "horizon_label")],
                                    _arrow((ax, tip_y), up, 6.0, "black", 0.25, "horizon_arrow")))
                deferred.append(options)
    # Ground plane of the first primitive.
    quad: tuple[Pt, ...] | None
    part = ""
    if ground_mm is not None:
        quad = tuple((float(x), float(y)) for x, y in ground_mm)
    else:
        found = first_ground_quad(plan)
        quad = None if found is None else found[1]
        part = "" if found is None else found[0]
    if quad:
        for piece in clip_polyline(quad, frame, closed=True):
            items.append(Polyline(tuple(piece), "blue", 0.3, (2.0, 1.0), False, "ground"))
        edge = first_near_edge(plan) if ground_mm is None else None
        if edge is not None:  # the first box's height: its nearest upright edge
            for piece in clip_polyline(edge, frame):
                items.append(Polyline(tuple(piece), "blue", 0.3, (2.0, 1.0), False,
                                      "ground_edge"))
        called = dict((full, label) for label, full in plan.part_names)  # renamed parts
        name = called.get(part or "", (part or "?").replace("_", " "))
        label = _t("sheet.ground", the_part=plain_text(templates.the(name)))
        low = min(quad, key=lambda p: (p[1], p[0]))
        high = max(quad, key=lambda p: (p[1], p[0]))
        lft = min(quad, key=lambda p: (p[0], p[1]))
        rgt = max(quad, key=lambda p: (p[0], p[1]))
        deferred.append([([Text(x, y, label, 7, "Helvetica", anchor, "blue", "ground_label")], [])
                         for x, y, anchor in ((low[0], low[1] - 3.5, "middle"),
                                              (high[0], high[1] + 1.5, "middle"),
                                              (rgt[0] + 2.0, rgt[1] - 1.0, "start"),
                                              (lft[0] - 2.0, lft[1] - 1.0, "end"))])
    # Vanishing points, named as the step texts name them.
    centre = (w / 2, h / 2)
    inner = (m + 2.0, m + 2.0, w - m - 2.0, h - m - 2.0)  # arrow tips end 2 mm inside the frame
    names = vp_names(plan)
    for vp in sorted(plan.vanishing_points, key=lambda v: v.axis):
        name = names[vp.axis]
        finite = not vp.at_infinity and vp.xy_mm is not None
        if finite:
            v = (float(vp.xy_mm[0]), float(vp.xy_mm[1]))
            if 0.0 <= v[0] <= w and 0.0 <= v[1] <= h:
                items.append(Circle(v[0], v[1], 1.2, "black", 0.3, None, "vp"))
                items.append(Polyline(((v[0] - 3, v[1]), (v[0] + 3, v[1])), "black", 0.2, (), False, "vp"))
                items.append(Polyline(((v[0], v[1] - 3), (v[0], v[1] + 3)), "black", 0.2, (), False, "vp"))
                anchor = "end" if v[0] > w / 2 else "start"
                dx = -2.5 if anchor == "end" else 2.5
                items.append(Text(v[0] + dx, v[1] + 2.0, _t("sheet.vp", vp=name), 8, "Helvetica-Bold",
                                  anchor, "black", "vp_label"))
                continue
            detail = _corner_offset(v, frame)
        else:
            detail = ""
        origin = centre
        if finite and hl is not None:
            # A VP on the horizon (two-point views): run the arrow along the horizon, from the
            # frame centre's foot on it, so the arrow lies on the line the VP sits on.
            a, b, c = hl
            off = a * centre[0] + b * centre[1] + c
            foot = (centre[0] - a * off, centre[1] - b * off)
            if abs(a * v[0] + b * v[1] + c) < 1e-6 * (1.0 + math.hypot(*v)) and \
                    inner[0] < foot[0] < inner[2] and inner[1] < foot[1] < inner[3]:
                origin = foot
        # The arrow's tip: where the ray toward the VP leaves ``inner``.
        exit_ = edge_exit(plan.camera, vp, inset_mm=m + 2.0, origin_mm=origin)
        if exit_ is None:
            continue
        tip, edge, direction = exit_.point_mm, exit_.side, exit_.direction_mm
        label = (_t("sheet.vp_far", vp=name, distance=f"{exit_.distance_mm:.0f}") if finite
                 else _t("sheet.vp_infinite", vp=name))
        items += _arrow(tip, direction, 12.0, "black", 0.35, "vp_arrow")
        tw = text_width_mm(label, 8, "Helvetica-Bold")
        n = math.hypot(*direction)
        ux, uy = direction[0] / n, direction[1] / n
        # Label just inside the frame next to the arrow's shaft.
        # Side edges: the label block goes above the tip when the shaft comes from below,
        # else below it, so neither the shaft nor a horizon through the tip crosses the text.
        ly = tip[1] + 5.5 if uy > 0 else tip[1] - 5.0
        ly = min(max(ly, inner[1] + 5.0), inner[3] - 3.0)
        if edge == "right":
            anchor, lx = "end", tip[0] - 3.0
        elif edge == "left":
            anchor, lx = "start", tip[0] + 3.0
        else:
            # Top/bottom edges: the block sits beside the shaft, toward the sheet's middle,
            # within the shaft's 12 mm from the edge.
            tail = (tip[0] - ux * 12.0, tip[1] - uy * 12.0)
            block = max(tw, text_width_mm(detail, 7))
            if tip[0] < (frame[0] + frame[2]) / 2:
                anchor, lx = "start", min(max(tip[0], tail[0]) + 3.0, inner[2] - block)
            else:
                anchor, lx = "end", max(min(tip[0], tail[0]) - 3.0, inner[0] + block)
            ly = tip[1] - 4.5 if edge == "top" else tip[1] + 8.5
        block = [Text(lx, ly, label, 8, "Helvetica-Bold", anchor, "black", "vp_label")]
        if detail:
            block.append(Text(lx, ly - 3.6, detail, 7, "Helvetica", anchor, "black", "vp_detail"))
        vertical = edge in ("left", "right")
        placed = _clear_of_texts(block, items, frame, vertical, area, hull)
        if placed is None:  # no room off the drawing: at least off its lines
            placed = _clear_of_texts(block, items, frame, vertical, shadow)
        if placed is None:  # nor that: at least clear of the other labels
            placed = _clear_of_texts(block, items, frame, vertical)
        items += placed or block
    for options in deferred:
        # the first position off the drawing; else the first one moved off it; else the same
        # off its lines only; else clear of the other labels only; else the first
        texts, extra = options[0]
        for avoid, inside in ((area, hull), (shadow, None), (None, None)):
            fit = next((o for o in options if _fits(o[0], items, frame, avoid, inside)), None)
            if fit is not None:
                texts, extra = fit
                break
            moved = _clear_of_texts(options[0][0], items, frame, False, avoid, inside)
            if moved is not None:
                texts = moved
                break
        items += extra
        items += texts
    if grid:  # the grid stops short of every label, so no text is read through its lines
        boxes = [it.box_mm for it in items if isinstance(it, Text) and it.string]
        items = [piece for it in items for piece in (
            _knocked_out(it, boxes, GRID_KNOCKOUT_MM)
            if isinstance(it, Polyline) and it.role == "grid" else [it])]
    return Page(w, h, tuple(items), (Bookmark(_t("sheet.bookmark")),), "sheet", title, m)


#: The perspective grid leaves this much room around each label on the sheet, mm.
GRID_KNOCKOUT_MM = 1.0


def _knocked_out(line: Polyline, boxes: Sequence[Box2], pad: float) -> list[Polyline]:
    """A straight two-point ``line`` without the stretches inside any of ``boxes`` grown by
    ``pad`` (pieces under 1 mm dropped)."""
    (ax, ay), (bx, by) = line.points_mm[0], line.points_mm[-1]
    cuts = []
    for x0, y0, x1, y1 in boxes:
        hit = _clip_segment((ax, ay), (bx, by), (x0 - pad, y0 - pad, x1 + pad, y1 + pad))
        if hit is None:
            continue
        length = math.hypot(bx - ax, by - ay) or 1.0
        t = sorted(math.hypot(q[0] - ax, q[1] - ay) / length for q in hit)
        cuts.append((t[0], t[1]))
    if not cuts:
        return [line]
    out: list[Polyline] = []
    start = 0.0
    for t0, t1 in sorted(cuts) + [(1.0, 1.0)]:
        if t0 > start:
            p = (ax + start * (bx - ax), ay + start * (by - ay))
            q = (ax + t0 * (bx - ax), ay + t0 * (by - ay))
            if math.dist(p, q) > 1.0:
                out.append(replace(line, points_mm=(p, q)))
        start = max(start, t1)
    return out


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
