"""The calibrated drawing sheet (DESIGN.md §2.9): the page a person draws on, at true scale.

:func:`lay_out_sheet` places the frame and its green corners, the vanishing points (or arrows
toward them, with their distances), the horizon, the first box's footprint and nearest upright
edge, an optional perspective grid, registration marks and a scale bar, and their labels off
the drawing wherever the frame has room.  Split from :mod:`h2s_print.layout` (whose page
values and drawing helpers it uses) when that module outgrew one reader; the decisions are
in :mod:`h2s_print.layout`'s docstring (*Calibrated sheet*).
"""

from __future__ import annotations

import itertools
import logging
import math
from collections import Counter
from dataclasses import replace
from typing import Any, Iterable, Iterator, Sequence

import numpy as np

from . import templates
from .errors import RenderError
from .config import MIN_MARGIN_MM
from .layout import (Bookmark, Box2, Circle, Item, LineStyle, Page, Polyline, Pt, Rect, Text,
                     PT_MM, _arrow, _boxes_overlap, _clip_segment, _crossings, _crossings_many,
                     _frame_box,
                     _green_corners, _level_name,
                     _segments, _t, clip_polyline, fit_line, plain_text, text_width_mm,
                     vp_names)
from .project import FirstBoxLines, edge_exit, first_scaffold_lines, horizon_mm, vp_side
from .types import ViewPlan

log = logging.getLogger(__name__)


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


def _first_lines(plan: ViewPlan) -> tuple[str, FirstBoxLines] | None:
    """The first scaffold step's part and what the sheet prints of its box
    (:func:`h2s_print.project.first_scaffold_lines`, the definition step 1's sheet guides
    share)."""
    found = first_scaffold_lines(plan)
    if found is None:
        return None
    step = plan.steps[found[0]]
    return step.part or step.strokes[0].part, found[1]


def first_ground_quad(plan: ViewPlan) -> tuple[str, tuple[Pt, ...]] | None:
    """The first scaffold step's bottom face projected on the sheet: ``(part, 4 corners mm)``.

    The face is the bottom (lowest z) face of the 3D box around that step's stroke points.
    """
    found = _first_lines(plan)
    if found is None:
        return None
    proj = plan.camera.project(found[1].footprint)
    return found[0], tuple((float(x), float(y)) for x, y in proj)


def first_floor_line(plan: ViewPlan) -> tuple[Pt, Pt] | None:
    """The floor under the first box's nearest bottom corner, projected on the sheet
    ``(corner, foot)`` mm, when the first box stands above the floor
    (:class:`h2s_print.project.FirstBoxLines`)."""
    found = _first_lines(plan)
    if found is None or found[1].floor is None:
        return None
    (ax, ay), (bx, by) = plan.camera.project(found[1].floor)
    return (float(ax), float(ay)), (float(bx), float(by))


def first_near_edge(plan: ViewPlan) -> tuple[Pt, Pt] | None:
    """The first scaffold step's upright edge nearest the camera, projected on the sheet
    ``(bottom, top)`` mm: with the footprint it fixes the first box's height, which every
    later size is measured against (the read-through: step 1 never said how tall)."""
    found = _first_lines(plan)
    if found is None or found[1].height is None:
        return None
    (bx, by), (tx, ty) = plan.camera.project(found[1].height)
    return (float(bx), float(by)), (float(tx), float(ty))


#: A vanishing point's arrow keeps this far from the printed first box's lines, mm.
ARROW_CLEAR_MM = 6.0
#: The arrow's shaft, mm (``_arrow``'s length in :func:`lay_out_sheet`).
ARROW_MM = 12.0
#: Where no arrow from the middle finds its label room off the finished drawing, arrows moved
#: along the frame's edge are tried, by these multiples of ARROW_SHIFT_MM, nearest first.
ARROW_SHIFT_MM = 8.0
ARROW_SHIFTS = tuple(k for j in range(1, 16) for k in (j, -j))
#: A label within this much of its place beside its arrow reads as the arrow's (mm).
LABEL_NEAR_MM = 12.0


def _shaft_near(exit_: Any, segs: np.ndarray, clear: float) -> bool:
    """Does the arrow at ``exit_`` (its tip, and a shaft of :data:`ARROW_MM` back along its
    direction) come within ``clear`` mm of one of ``segs`` (rows ``x0 y0 x1 y1``)?"""
    tip = np.asarray(exit_.point_mm, dtype=float)
    d = np.asarray(exit_.direction_mm, dtype=float)
    d = d / float(np.linalg.norm(d))
    pts = tip[None, :] - np.linspace(0.0, ARROW_MM, 7)[:, None] * d[None, :]  # along the shaft
    a, b = segs[:, :2], segs[:, 2:]
    ab = b - a
    t = np.clip(np.einsum("kij,ij->ki", pts[:, None, :] - a[None], ab)
                / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-12)[None], 0.0, 1.0)
    near = a[None] + t[..., None] * ab[None]
    return bool((np.linalg.norm(pts[:, None, :] - near, axis=2) < clear).any())


class _Remembered:
    """The values of an iterator, each worked out when a loop first reaches it and kept for
    the loops after: :func:`lay_out_sheet` tries a vanishing point's arrows in up to four
    passes, each stopping at the first that fits (nearly always one of the first few)."""

    def __init__(self, values: Iterable[Any]) -> None:
        self._values = iter(values)
        self._kept: list[Any] = []

    def __iter__(self) -> Iterator[Any]:
        k = 0
        while True:
            if k == len(self._kept):
                try:
                    self._kept.append(next(self._values))
                except StopIteration:
                    return
            yield self._kept[k]
            k += 1


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
        lo, hi = (0.0, 2 * math.pi) if inside else _seen_span(v, corners)
        n = max(8, min(90, int(math.ceil((hi - lo) * far / GRID_SPACING_MM))))
        for k in range(1, n) if not inside else range(n):
            t = lo + (hi - lo) * k / n
            add((float(v[0]), float(v[1])),
                (float(v[0] + (far + reach) * math.cos(t)), float(v[1] + (far + reach) * math.sin(t))))
    return out


def _seen_span(v: np.ndarray, corners: np.ndarray) -> tuple[float, float]:
    """The directions (radians, ``lo`` < ``hi``) from ``v``, a point outside the frame with
    ``corners``, that cross the frame: under half a turn, the frame being convex."""
    rel = corners - v
    mid = math.atan2(*(corners.mean(axis=0) - v)[::-1])
    ang = [(math.atan2(r[1], r[0]) - mid + math.pi) % (2 * math.pi) - math.pi for r in rel]
    return mid + min(ang), mid + max(ang)


def _clear_of_texts(block: list[Text], items: Sequence[Item], frame: Box2,
                    vertical: bool, avoid: np.ndarray | None = None,
                    inside: np.ndarray | None = None,
                    within: float | None = None) -> list[Text] | None:
    """``block`` moved along the frame's edge (``vertical``: up or down, else sideways) by the
    smallest step that keeps it clear of every text and line of :data:`_SHEET_LINES` in
    ``items``, of the segments ``avoid`` and of the convex polygon ``inside``, inside
    ``frame``; None when no such place is within 60 mm (within ``within`` mm, if given)."""
    placed = [t.box_mm for t in items if isinstance(t, Text)]
    others = np.asarray(placed, dtype=float).reshape(-1, 4)  # the same boxes, as rows
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

    def clear(offs: np.ndarray) -> np.ndarray:
        """For each shift ``(dx, dy)`` of ``offs``: does the block fit there?  (Each text's
        box as :meth:`Text.box_at` computes it, the same floating-point operations.)"""
        ok = np.ones(len(offs), dtype=bool)
        for t in block:
            width = text_width_mm(t.string, t.size_pt, t.font)
            size = t.size_pt * PT_MM
            b0 = (t.x_mm + offs[:, 0]) - {"start": 0.0, "middle": width / 2, "end": width}[t.anchor]
            y = t.y_mm + offs[:, 1]
            b1, b2, b3 = y - 0.21 * size, b0 + width, y + 0.72 * size
            ok &= ~((b0 < frame[0]) | (b2 > frame[2]) | (b1 < frame[1]) | (b3 > frame[3]))
            if len(others):  # 3 mm apart along a line, 1 mm across (every text at once)
                ok &= ~((b0[:, None] < others[:, 2] + 3.0) & (others[:, 0] < b2[:, None] + 3.0)
                        & (b1[:, None] < others[:, 3] + 1.0)
                        & (others[:, 1] < b3[:, None] + 1.0)).any(axis=1)
            if ok.any():
                boxes = np.stack([b0 - 1.0, b1 - 0.5, b2 + 1.0, b3 + 0.5], axis=1)
                ok[ok] = _crossings_many(arrows, boxes[ok]) == 0
        return ok

    offsets = _LABEL_SHIFTS[vertical]
    if within is not None:  # (a test of each shift alone: first, it leaves the fewest to try)
        offsets = offsets[np.hypot(offsets[:, 0], offsets[:, 1]) <= within]
    middles = None
    if inside is not None and len(inside) >= 3:  # places whose texts' middles are all outside
        middles = np.array([((b[0] + b[2]) / 2, (b[1] + b[3]) / 2)
                            for b in (t.box_mm for t in block)])

    def usable(shifts: np.ndarray) -> np.ndarray:
        """The shifts (in order) the search may try: outside ``inside`` (those within
        ``within`` are ``offsets`` already)."""
        if middles is not None:
            at = (shifts[:, None, :] + middles[None, :, :]).reshape(-1, 2)
            shifts = shifts[~_in_convex_all(inside, at).reshape(len(shifts), len(block))
                            .any(axis=1)]
        return shifts

    # the places tried, made as far as the search reaches (nearly every block fits among the
    # first few): each shift's test is its own, so the places are those of all at once
    made: list[np.ndarray] = []
    n_made, done = 0, 0

    def tried(stop: int | None) -> np.ndarray:
        """The first ``stop`` places tried (None: all of them)."""
        nonlocal n_made, done
        while done < len(offsets) and (stop is None or n_made < stop):
            more = usable(offsets[done:done + _SHIFTS_AT_ONCE])
            made.append(more)
            n_made += len(more)
            done += _SHIFTS_AT_ONCE
        return np.concatenate(made) if len(made) != 1 else made[0]

    start = 0
    for size in (64, 256, None):  # nearest first, the nearest few places alone first
        places = tried(None if size is None else start + size)
        fit = np.flatnonzero(clear(places[start:] if size is None
                                   else places[start:start + size]))
        if len(fit):
            dx, dy = places[start + int(fit[0])].tolist()
            return [replace(t, x_mm=t.x_mm + dx, y_mm=t.y_mm + dy) for t in block]
        if size is None:
            break
        start += size
        if done >= len(offsets) and start >= n_made:
            break
    return None


#: Shifts :func:`_clear_of_texts` tests against ``inside`` at a time.
_SHIFTS_AT_ONCE = 320


def _label_shifts(vertical: bool) -> np.ndarray:
    """The shifts :func:`_clear_of_texts` tries, nearest first: along the frame's edge first,
    then also away from it (2 mm steps, up to 60 mm along and 20 mm across)."""
    shifts = sorted(((a, c) for a in range(-30, 31) for c in range(-10, 11)),
                    key=lambda s: (abs(s[0]) + 2 * abs(s[1]), abs(s[1]), s))
    return np.array([(2.0 * c, 2.0 * a) if vertical else (2.0 * a, 2.0 * c) for a, c in shifts])


_LABEL_SHIFTS = {v: _label_shifts(v) for v in (False, True)}


#: Lines of the drawing sheet that no label may cross: arrows, the horizon, the footprint (and,
#: where there is room, the finished drawing: ``lay_out_sheet(drawing=...)``).
_SHEET_LINES = ("vp_arrow", "horizon", "ground", "ground_edge", "height_tick")


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


def _on_texts(lines: Sequence[Polyline], items: Sequence[Item]) -> bool:
    """Does any of ``lines`` (a label's arrow) cross a text already in ``items``?  (The desk's
    horizon arrow ran through the left vanishing point's label.)"""
    segs = _segments(list(lines))
    boxes = [it.box_mm for it in items if isinstance(it, Text) and it.string]
    return bool(len(segs) and boxes and _crossings_many(segs, boxes).any())


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
                  drawing: Sequence[Sequence[Pt]] = (), labels_near: bool = True) -> Page:
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
        labels_near: a vanishing point's label goes beside its arrow (within
            :data:`LABEL_NEAR_MM`) where some arrow's allows, before one moved further; the
            sheet is laid out again without that preference where it leaves a far vanishing
            point without ticks (the roller's high view).
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
    # labels that name a line beside them, where the drawing will be: the first of their
    # places clear of the drawing's lines, else of the sheet's lines and labels only (in the
    # footprint if need be: beside a short upright line over a footprint seen from above
    # there is no other room); never moved away (a label 40 mm off names nothing, and one
    # moved down the height line names the floor line).  With no room, a label that must be
    # printed (the flag) is placed as the deferred ones are; the others are left out
    beside: list[tuple[list[Text], bool]] = []
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
            # its top end marked across it: it runs on past the footprint's far edge in the
            # picture, where a reader stopped (a read-through of the train, front-left)
            (bx, by), (tx, ty) = edge
            n = math.hypot(tx - bx, ty - by)
            if n > 0 and _on_frame(frame, tx, ty):
                ux, uy = (ty - by) / n * 1.2, -(tx - bx) / n * 1.2  # across, 1.2 mm each way
                items.append(Polyline(((tx - ux, ty - uy), (tx + ux, ty + uy)), "blue", 0.3,
                                      (), False, "height_tick"))
        drop = first_floor_line(plan) if ground_mm is None else None
        if drop is not None and edge is not None:
            # the height and the floor line are one upright line through the footprint's
            # corner: the part above it is named, so that it is not taken for the height of
            # the whole line (a read-through of the desk: "a beginner will make the desktop as
            # tall as the whole desk"); with no room the step's words say which line it is
            mx, my = 0.5 * (bx + tx), 0.5 * (by + ty)
            height = _t("sheet.height")
            beside.append(([Text(x, y, height, 7, "Helvetica", anchor, "blue", "height_label")
                            for x, y, anchor in ((mx + 2.0, my - 1.0, "start"),
                                                 (mx - 2.0, my - 1.0, "end"),
                                                 (tx, ty + 1.5, "middle"),
                                                 (tx + 2.0, ty - 1.0, "start"),
                                                 (tx - 2.0, ty - 1.0, "end"))], False))
        if drop is not None:  # the floor below it: the object's whole height
            for piece in clip_polyline(drop, frame):
                items.append(Polyline(tuple(piece), "blue", 0.3, (2.0, 1.0), False,
                                      "ground_edge"))
            fx, fy = drop[1]
            # its foot, where later steps start lines along the floor, as a dot: a short
            # floor line can end in a gap of its dashes (a read-through of the train,
            # high-right: "the foot P is hard to find")
            if _on_frame(frame, fx, fy):
                items.append(Circle(fx, fy, 0.6, "blue", 0.2, "blue", "floor_foot"))
            floor = _t("sheet.floor")
            deferred.append([([Text(x, y, floor, 7, "Helvetica", anchor, "blue",
                                    "floor_label")], [])
                             for x, y, anchor in ((fx, fy - 3.5, "middle"),
                                                  (fx + 2.0, fy - 1.0, "start"),
                                                  (fx - 2.0, fy - 1.0, "end"))])
        called = dict((full, label) for label, full in plan.part_names)  # renamed parts
        name = called.get(part or "", (part or "?").replace("_", " "))
        label = _t("sheet.ground", the_part=plain_text(templates.the(name)))
        low = min(quad, key=lambda p: (p[1], p[0]))
        high = max(quad, key=lambda p: (p[1], p[0]))
        lft = min(quad, key=lambda p: (p[0], p[1]))
        rgt = max(quad, key=lambda p: (p[0], p[1]))
        places = [(low[0], low[1] - 3.5, "middle"), (high[0], high[1] + 1.5, "middle"),
                  (rgt[0] + 2.0, rgt[1] - 1.0, "start"), (lft[0] - 2.0, lft[1] - 1.0, "end")]
        if drop is not None:
            # above the floor the floor line hangs from the lowest corner, and a label below it
            # read as naming that line (a read-through of the desk and the train): in the
            # footprint first, below it last, and never moved away from it
            cx = sum(p[0] for p in quad) / len(quad)
            cy = sum(p[1] for p in quad) / len(quad)
            places = [(cx, cy - 1.0, "middle"), *places[1:], places[0]]
        grounds = [Text(x, y, label, 7, "Helvetica", anchor, "blue", "ground_label")
                   for x, y, anchor in places]
        if drop is not None:
            beside.append((grounds, True))
        else:
            deferred.append([([t], []) for t in grounds])
    # Vanishing points, named as the step texts name them.
    centre = (w / 2, h / 2)
    inner = (m + 2.0, m + 2.0, w - m - 2.0, h - m - 2.0)  # arrow tips end 2 mm inside the frame
    names = vp_names(plan)
    ground = _segments([it for it in items if isinstance(it, Polyline)
                        and it.role in ("ground", "ground_edge")])
    foot = _segments([it for it in items if isinstance(it, Polyline) and it.role == "ground"])
    footprint = _hull(foot.reshape(-1, 2).tolist()) if len(foot) else None
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
        # The arrow's tip: where the ray toward the VP leaves ``inner``; moved across the ray
        # (still toward the VP) where its shaft would run beside the printed first box, whose
        # upright line it was taken for (the mixer's high-right sheet)
        exit_ = edge_exit(plan.camera, vp, inset_mm=m + 2.0, origin_mm=origin)
        if exit_ is None:
            continue
        # parallels (a point at infinity) run both ways: the arrow may point either way
        # (the desk's upward arrow crossed its printed top, all across the sheet's top)
        ways = [vp] + ([replace(vp, direction_mm=(-vp.direction_mm[0], -vp.direction_mm[1]))]
                       if vp.at_infinity else [])
        n = math.hypot(*exit_.direction_mm)
        across = (-exit_.direction_mm[1] / n, exit_.direction_mm[0] / n)

        def shifted(way: Any, k: int, origin: Pt = origin, across: Pt = across) -> Any:
            """The exit toward ``way`` from the origin moved ``k`` shifts across the ray
            (ARROW_SHIFT_MM each), if that origin is inside the frame and the arrow's shaft
            clear of the printed first box; else None."""
            moved = (origin[0] + ARROW_SHIFT_MM * k * across[0],
                     origin[1] + ARROW_SHIFT_MM * k * across[1])
            if not (inner[0] < moved[0] < inner[2] and inner[1] < moved[1] < inner[3]):
                return None
            other = edge_exit(plan.camera, way, inset_mm=m + 2.0, origin_mm=moved)
            if other is None or (len(ground) and _shaft_near(other, ground, ARROW_CLEAR_MM)):
                return None
            return other

        if len(ground) and _shaft_near(exit_, ground, ARROW_CLEAR_MM):
            exit_ = next((x for way in ways for k in (0, 1, -1, 2, -2, 3, -3, 4, -4, 5, -5, 6, -6)
                          if (x := shifted(way, k)) is not None), exit_)

        def labelled(ex: Any, detail: str = detail, name: str = name, finite: bool = finite
                     ) -> tuple[list[Polyline], list[Text], bool]:
            """The arrow at exit ``ex``, its label block, and whether it sits on a side edge."""
            tip, edge, direction = ex.point_mm, ex.side, ex.direction_mm
            label = (_t("sheet.vp_far", vp=name, distance=f"{ex.distance_mm:.0f}") if finite
                     else _t("sheet.vp_infinite", vp=name))
            # toward parallels, a double-headed arrow: a direction, where a single head read
            # as pointing at a vanishing point (a read-through)
            arrow = _arrow(tip, direction, ARROW_MM, "black", 0.35, "vp_arrow",
                           both=not finite)
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
            return arrow, block, vertical

        # an arrow toward parallels may point either way: the way whose label finds room off
        # the drawing, and whose arrow is not inside it, first (the roller's "vertical edges"
        # label sat where its front face is drawn, a read-through of stop 27)
        # then, each way, arrows moved along the frame's edge (across the ray; each still
        # points at its vanishing point): the arrow toward parallels at the sheet's middle lay
        # in the drawing of any object drawn there top to bottom (the bottle's lid, the oven),
        # the train's left-VP label in its chimney
        n = math.hypot(*exit_.direction_mm)  # (across the ray as it is now)
        across = (-exit_.direction_mm[1] / n, exit_.direction_mm[0] / n)

        def in_turn(ways: list[Any] = ways, shifted: Any = shifted, across: Pt = across
                    ) -> Iterator[Any]:
            """The arrows in the order they are tried, the first (``exit_``) left out."""
            for way in ways[1:]:
                if (other := shifted(way, 0)) is not None:
                    yield other
            for k in ARROW_SHIFTS:
                for way in ways:
                    if (other := shifted(way, k, across=across)) is not None:
                        yield other

        # each arrow made when the search first reaches it (it nearly always stops at one of
        # the first few): an arrow is the same whenever it is made
        exits = _Remembered(itertools.chain([exit_], in_turn()))
        chosen = None
        # the label off the drawing; else off its lines only (the train fills its frame: the
        # arrow toward its left vanishing point sat in the chimney), the arrow never inside
        # it here (only the fallback below, where no arrow finds room, may put it there)
        # ... and, each way, first beside its arrow: an arrow moved along the frame whose label
        # fits next to it before a label moved far from its arrow (a read-through: the
        # bottle's "vanishing point below" 47 mm from its arrow, read as naming a tick)
        for avoid, inside in ((area, hull), (shadow, footprint)):
            for within in ((LABEL_NEAR_MM, None) if labels_near else (None,)):
                for ex in exits:
                    arrow, block, vertical = labelled(ex)
                    ends = np.array([q for a in arrow for q in a.points_mm], dtype=float)
                    if len(hull) >= 3 and _in_convex_all(hull, ends).any():
                        continue
                    placed = _clear_of_texts(block, [*items, *arrow], frame, vertical, avoid,
                                             inside, within)
                    if placed is not None:
                        chosen = arrow + placed
                        break
                if chosen is not None:
                    break
            if chosen is not None:
                break
        if chosen is not None:
            items += chosen
            continue
        arrow, block, vertical = labelled(exit_)
        items += arrow
        # the loop above tried this arrow's label off the drawing, and off its lines, unless
        # the arrow lies inside the drawing
        ends = np.array([q for a in arrow for q in a.points_mm], dtype=float)
        placed = None
        if len(hull) >= 3 and _in_convex_all(hull, ends).any():
            placed = _clear_of_texts(block, items, frame, vertical, area, hull)
            if placed is None:  # no room off the drawing: at least off its lines, and never
                # in the printed first box's footprint, where the first box is drawn (the desk's)
                placed = _clear_of_texts(block, items, frame, vertical, shadow, footprint)
        if placed is None:  # nor that: at least clear of the other labels
            placed = _clear_of_texts(block, items, frame, vertical, None, footprint)
        items += placed or block
    def place(options: list[tuple[list[Text], list[Polyline]]]) -> None:
        # the first position off the drawing; else the first one moved off it; else the same
        # off its lines only; else clear of the other labels only; else the first
        texts, extra = options[0]
        for avoid, inside in ((area, hull), (shadow, None), (None, None)):
            fit = next((o for o in options if _fits(o[0], items, frame, avoid, inside)
                        and not _on_texts(o[1], items)), None)
            if fit is not None:
                texts, extra = fit
                break
            moved = _clear_of_texts(options[0][0], items, frame, False, avoid, inside)
            if moved is not None:  # moved off its arrow: the words say where without it
                texts, extra = moved, []
                break
        if _on_texts(extra, items):  # nor an arrow through another label (the desk's horizon)
            extra = []
        items.extend(extra)
        items.extend(texts)

    for options in deferred:
        place(options)
    for texts, keep in beside:
        fit = next((t for avoid in (shadow, None) for t in texts
                    if _fits([t], items, frame, avoid)), None)
        if fit is not None:
            items.append(fit)
        elif keep:  # the footprint's name is never left out
            place([([t], []) for t in texts])
    ticks = vp_ticks(plan, frame, items, shadow)
    if labels_near and (_unticked(plan, frame, ticks)
                        or _unticked(plan, frame, ticks, 2, TAPE_REACH_MM)):
        # the labels beside their arrows took the room of a far point's ticks (or of all but
        # one pair, and one line is none to aim between: the train's front-left sheet had R1
        # alone, below its drawing, and its right vanishing point 649 mm off, a
        # read-through): a ruler through ticks matters more, where the labels elsewhere
        # leave room for more; for a point paper taped on reaches, the labels stay beside
        # their arrows (one far from its arrow read as naming a tick: the mixer's "vertical
        # edges" 51 mm from its arrow, for its right point 208 mm off)
        other = lay_out_sheet(title, plan, margin_mm=margin_mm, view_label=view_label,
                              ground_mm=ground_mm, grid=grid, drawing=drawing,
                              labels_near=False)
        if _unticked(plan, frame, ticks) or not _unticked(
                plan, frame, [it for it in other.items if isinstance(it, Text)], 2,
                TAPE_REACH_MM):
            return other
    items += _beside_heading(ticks, items)
    if grid:  # the grid stops short of every label, so no text is read through its lines
        boxes = [it.box_mm for it in items if isinstance(it, Text) and it.string]
        items = [piece for it in items for piece in (
            _knocked_out(it, boxes, GRID_KNOCKOUT_MM)
            if isinstance(it, Polyline) and it.role == "grid" else [it])]
    return Page(w, h, tuple(items), (Bookmark(_t("sheet.bookmark")),), "sheet", title, m)


#: Ticks toward a vanishing point off the sheet (:func:`vp_ticks`): pairs tried, tick length
#: and label size, and how far a tick stays from the frame's corners (the green corners), mm.
TICK_PAIRS = 7
#: ... a pair's two ticks at least this share of the frame's shorter side apart
TICK_CHORD = 0.6
TICK_MM = 4.0
TICK_PT = 6.0
TICK_CORNER_MM = 20.0
#: ... at most this many pairs a vanishing point, ...
TICK_PAIRS_KEPT = 4
#: ... and from every other tick on the frame (a read-through found the camera's L1 and R5
#: ticks 3 mm apart, each name beside the other's tick)
TICK_GAP_MM = 6.0
#: The first lines tried pass this far (mm, at the drawing's middle) outside the drawing on
#: either side, then twice, three times ... as far where a tick is in the way
#: (:func:`vp_ticks`).
TICK_BRACKET_MM = 4.0
TICK_BRACKET_TRIES = 40
#: ... and a line is not tried within this share of the drawing's angle (the frame's without
#: one) of a line kept toward the same point: the camera's L1 and L2 ran 8 mm apart below
#: its drawing, where one above it was wanted
TICK_SPREAD = 0.2


def vp_ticks(plan: ViewPlan, frame: Box2, items: Sequence[Item],
             drawing: np.ndarray | None = None) -> list[Item]:
    """Ticks on the frame toward each vanishing point that lies off the sheet, in named pairs.

    A line through a far vanishing point crosses the frame twice; a short tick marks both
    crossings, inside the frame, each named alike ("L3" … "L3"): a ruler laid through two
    ticks of one name runs toward that vanishing point, which no taped-on paper then needs
    (the read-throughs: the camera's right vanishing point is 392 mm off the sheet, the
    roller's left one 859 mm).  The lines are spread evenly in angle over the frame as seen
    from the point; a pair is left out where a tick or its name would touch a text, an arrow,
    the printed first box, the drawing's lines (``drawing``, segments) or a green corner, and
    the pairs kept are numbered along the frame.
    Names: ``sheet.tick_names.<side>`` (the side as :func:`h2s_print.project.vp_side` says).
    """
    w, h = float(plan.paper_mm[0]), float(plan.paper_mm[1])
    centre = (w / 2, h / 2)
    boxes = [it.box_mm for it in items if isinstance(it, Text) and it.string]
    lines = _segments([it for it in items if isinstance(it, Polyline)
                       and it.role in ("vp_arrow", "ground", "ground_edge", "horizon")])
    if drawing is not None and len(drawing):
        lines = np.vstack([lines, drawing]) if len(lines) else drawing
    taken = list(boxes)
    corners = [(frame[0], frame[1]), (frame[2], frame[1]), (frame[2], frame[3]),
               (frame[0], frame[3])]
    out: list[Item] = []
    example = ""  # the first pair's name, for the legend
    marks: list[tuple[float, float, float, float]] = []  # the ticks so far, as segments
    # ... and every arrow's tip, from which a tick keeps TICK_GAP_MM too: a tick running
    # beside an arrow toward the same point hid where "beyond the arrow's tip" starts (the
    # bottle's, the chair's and the train's arrows toward their points below, a read-through)
    tips = [it.points_mm[-1] for it in items if isinstance(it, Polyline)
            and it.role == "vp_arrow" and len(it.points_mm) == 2]
    marks += [(p[0], p[1], p[0], p[1]) for p in tips]
    # Per vanishing point off the sheet: the lines to try, in order.  The evenly spread lines
    # come middle first, then spreading out; where fewer than two pairs fit, the lines
    # half-way between them too (the desk's point below: each of the first seven had a tick
    # on that point's own label or arrow).  At most TICK_PAIRS_KEPT pairs a point, taken in
    # turns, one a point a round: enough to aim by, and room for every point's ticks (the
    # camera's high-right sheet: seven pairs of the side points left none for the one below).
    # Bracketing first: the sheet says a line from a corner "runs between its two nearest
    # faint lines", so the first lines tried pass just outside the drawing on either side
    # (a few tries further out each, where a tick is in the way), then through its middle;
    # evenly spread over the frame, both of the camera's L lines passed below its whole
    # drawing and every line toward that point had to be guessed beyond the last (a
    # read-through).
    far: list[tuple[Any, Pt, str, list[list[float]], list[float], float, float]] = []
    ends = (np.asarray(drawing, dtype=float).reshape(-1, 2) if drawing is not None
            else np.zeros((0, 2)))
    for vp in sorted(plan.vanishing_points, key=lambda v: v.axis):
        if not _off_frame(vp, frame):  # at infinity, or on the sheet: a ruler reaches it
            continue
        v = (float(vp.xy_mm[0]), float(vp.xy_mm[1]))
        lo, hi = _seen_span(np.asarray(v), np.asarray(corners, dtype=float))
        first = [[a] for a in (lo + (k + 0.5) / TICK_PAIRS * (hi - lo)
                               for k in _spread(TICK_PAIRS))]
        sep = TICK_SPREAD * (hi - lo)
        if len(ends):
            d_lo, d_hi = _seen_span(np.asarray(v), ends)
            step = TICK_BRACKET_MM / float(np.linalg.norm(ends.mean(axis=0) - v))
            first = [[d_lo - k * step for k in range(1, TICK_BRACKET_TRIES + 1)],
                     [d_hi + k * step for k in range(1, TICK_BRACKET_TRIES + 1)],
                     [(d_lo + d_hi) / 2]] + first
            sep = TICK_SPREAD * (d_hi - d_lo)
        between = [lo + (k + 1) / TICK_PAIRS * (hi - lo) for k in _spread(TICK_PAIRS - 1)]
        far.append((vp, v, _t(f"sheet.tick_names.{vp_side(vp, centre)}"), first, between,
                    max(math.dist(v, c) for c in corners), sep))
    kept: dict[int, list[tuple[float, list[tuple[Pt, Pt, Text]]]]] = {
        vp.axis: [] for vp, *_ in far}
    moved = True
    while moved:
        moved = False
        for vp, v, prefix, first, between, reach, sep in far:
            mine = kept[vp.axis]
            if len(mine) >= TICK_PAIRS_KEPT:
                continue
            found = False
            while not found and (first or (len(mine) < 2 and between)):
                group = first.pop(0) if first else [between.pop(0)]
                for a in group:  # (a bracket's tries, nearest the drawing first)
                    if any(abs((a - b + math.pi) % (2 * math.pi) - math.pi) < sep
                           for b, _ in mine):
                        continue  # beside a line kept: it would add little to aim by
                    made = _tick_pair(v, a, reach, frame, corners, centre, taken,
                                      np.vstack([lines, np.asarray(marks).reshape(-1, 4)]),
                                      prefix)
                    # a tick keeps TICK_GAP_MM from every other, so no name sits by the
                    # wrong one
                    if made is not None and all(math.dist(p, (m[0], m[1])) >= TICK_GAP_MM
                                                for p, _, _ in made for m in marks):
                        mine.append((a, made))
                        taken += [tx.box_mm for _, _, tx in made]
                        marks += [(p[0], p[1], q[0], q[1]) for p, q, _ in made]
                        moved = found = True
                        break
    for vp, _, prefix, *_ in far:
        n = 0
        for _, made in sorted(kept[vp.axis], key=lambda am: am[0]):  # numbered along the frame
            n += 1
            for p, q, tx in made:
                out.append(Polyline((p, q), "black", 0.3, (), False, "vp_tick"))
                out.append(replace(tx, string=f"{prefix}{n}"))
        if n and not example:
            example = f"{prefix}1"
    if example:  # what the ticks are for, in the top band at the right, by one pair's name
        # (a read-through took a list "R1-R2, L1-L2" for lines to draw from R1 to R2)
        m = frame[1]
        line = _t("sheet.ticks", example=example)
        out.append(Text(frame[2], h - m / 2 - 0.9, line, fit_line(line, 0.5 * w, 7),
                        "Helvetica", "end", "black", "vp_tick_legend"))
    return out


def _spread(n: int) -> list[int]:
    """``0 .. n-1`` middle first, then the halves' middles, and so on: the first few spread
    over the range (7: 3, 1, 5, 0, 2, 4, 6)."""
    out: list[int] = []
    spans = [(0, n)]
    while spans:
        nxt = []
        for lo, hi in spans:
            if lo < hi:
                mid = (lo + hi - 1) // 2
                out.append(mid)
                nxt += [(lo, mid), (mid + 1, hi)]
        spans = nxt
    return out


def _tick_pair(v: Pt, angle: float, reach: float, frame: Box2, corners: Sequence[Pt],
               centre: Pt, taken: Sequence[Box2], lines: np.ndarray, prefix: str
               ) -> list[tuple[Pt, Pt, Text]] | None:
    """The two ticks (and their names) where the line from ``v`` at ``angle`` crosses the
    frame, or None where it cannot be marked (:func:`vp_ticks`): a chord too short for the
    ruler, a tick near a green corner, or a tick or its name on a text or a line.  A name
    sits just inside its tick's inner end, toward the frame's middle, or else on the tick's
    other side, always inside the frame."""
    d = (math.cos(angle), math.sin(angle))
    # where the line through the point crosses the frame: in, then out
    hit = _clip_segment(v, (v[0] + reach * d[0], v[1] + reach * d[1]), frame)
    if hit is None or math.dist(*hit) < TICK_CHORD * min(frame[2] - frame[0],
                                                          frame[3] - frame[1]):
        return None  # across a corner: too short a baseline for the ruler
    (p0, q0) = hit
    made: list[tuple[Pt, Pt, Text]] = []
    for p, q in ((p0, (p0[0] + TICK_MM * d[0], p0[1] + TICK_MM * d[1])),
                 (q0, (q0[0] - TICK_MM * d[0], q0[1] - TICK_MM * d[1]))):
        if min(math.dist(p, c) for c in corners) < TICK_CORNER_MM:
            return None
        seg = np.array([[p[0], p[1], q[0], q[1]]])
        if _crossings_many(seg, taken).any():
            return None
        inward = q[0] < centre[0]
        iy = q[1] + (1.0 if q[1] < centre[1] else -3.0)
        for right in (inward, not inward):
            # named when numbered; the digits are equally wide, so the box is the name's
            text = Text(q[0] + (1.5 if right else -1.5), iy, f"{prefix}1", TICK_PT,
                        "Helvetica", "start" if right else "end", "black", "vp_tick_label")
            b = text.box_mm
            pad = (b[0] - 1.0, b[1] - 0.8, b[2] + 1.0, b[3] + 0.8)
            inside = frame[0] < pad[0] and pad[2] < frame[2] and frame[1] < pad[1] and \
                pad[3] < frame[3]
            if inside and not (any(_boxes_overlap(pad, o) for o in taken) or _crossings(lines, pad)):
                made.append((p, q, text))
                break
        else:
            return None
    return made


def _on_frame(frame: Box2, x: float, y: float) -> bool:
    """Is the sheet point (x, y) within ``frame``, its edge included (a point the camera's
    framing put on the edge may lie a rounding error outside it)?"""
    return frame[0] - 1e-6 <= x <= frame[2] + 1e-6 and frame[1] - 1e-6 <= y <= frame[3] + 1e-6


def _off_frame(vp: Any, frame: Box2) -> bool:
    """Is the vanishing point ``vp`` a point (not at infinity) off the frame, where the frame
    gets ticks toward it (:func:`vp_ticks`)?"""
    if vp.at_infinity or vp.xy_mm is None:
        return False
    x, y = float(vp.xy_mm[0]), float(vp.xy_mm[1])
    return not (frame[0] <= x <= frame[2] and frame[1] <= y <= frame[3])


#: A vanishing point this far off the frame (mm) is beyond a sheet of paper taped on (an A4
#: sheet's length): its ticks are the only way to aim at it (:func:`lay_out_sheet`).
TAPE_REACH_MM = 297.0


def _unticked(plan: ViewPlan, frame: Box2, ticks: Sequence[Item], pairs: int = 1,
              beyond_mm: float = 0.0) -> bool:
    """Does a vanishing point off the frame (not at infinity), more than ``beyond_mm`` from
    it, have fewer than ``pairs`` tick pairs (:func:`vp_ticks`) among ``ticks``?"""
    w, h = float(plan.paper_mm[0]), float(plan.paper_mm[1])
    centre = (w / 2, h / 2)

    def off(vp: Any) -> float:
        x, y = float(vp.xy_mm[0]), float(vp.xy_mm[1])
        return math.hypot(max(frame[0] - x, 0.0, x - frame[2]),
                          max(frame[1] - y, 0.0, y - frame[3]))

    want = {_t(f"sheet.tick_names.{vp_side(vp, centre)}") for vp in plan.vanishing_points
            if _off_frame(vp, frame) and off(vp) > beyond_mm}
    have = Counter(it.string.rstrip("0123456789") for it in ticks
                   if isinstance(it, Text) and it.role == "vp_tick_label")
    return any(have[name] < 2 * pairs for name in want)  # (two ticks a pair)


def _beside_heading(ticks: list[Item], items: list[Item]) -> list[Item]:
    """``ticks`` with their line in the top band set beside the heading (``items``' text of
    role ``sheet_title``, shrunk in place when it is long), or none of them when the two do
    not fit one band even at the smallest size: ticks nobody explains would only puzzle."""
    legend = next((it for it in ticks if isinstance(it, Text) and it.role == "vp_tick_legend"),
                  None)
    k, head = next(((k, it) for k, it in enumerate(items)
                    if isinstance(it, Text) and it.role == "sheet_title"), (None, None))
    if legend is None or head is None or k is None:
        return ticks
    try:
        items[k] = replace(head, size_pt=fit_line(head.string, legend.box_mm[0] - 4.0
                                                  - head.x_mm, head.size_pt, head.font))
        return ticks
    except RenderError:  # a long heading: the ticks' line smaller, after it
        pass
    try:
        size = fit_line(legend.string, legend.x_mm - head.box_mm[2] - 4.0, legend.size_pt,
                        legend.font)
    except RenderError:
        log.info("sheet: no room in the top band to explain the vanishing-point ticks; "
                 "left out")
        return []
    return [replace(it, size_pt=size) if it is legend else it for it in ticks]


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
