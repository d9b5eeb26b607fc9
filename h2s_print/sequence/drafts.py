"""Steps before guide ids: lines, drafts, units of construction, citations of earlier lines."""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any, Callable, Sequence

import numpy as np

from ..instructions import Many, Pts, Spec, line_runs, spec, unique_specs
from ..project import FirstBoxLines, first_box_lines
from ..types import Camera, Guide, Stroke, Vec3
from .geometry import _Line, _same_segment
from .words import _cap, _join, _t, _the

#: A step's text (headline and numbered sub-steps) longer than this many words is split: its
#: constructions go to steps of their own (kind ``guides``) before the part's step.
MAX_STEP_WORDS = 70


#: Sub-steps that only point at lines already drawn (:meth:`_Context.uncited`).
_CITES = ("reuse", "reuse_for", "edge", "edge_two", "edge_for", "edge_for_two")


@dataclass(frozen=True, slots=True)
class _Draft:
    """A step before guide ids, statuses and level filtering."""

    part: str | None
    kind: str
    eyeball: bool
    lines: tuple[_Line, ...]
    strokes: tuple[Stroke, ...]
    headline: str
    specs: tuple[Spec, ...] = ()  # sub-steps before letters (:mod:`h2s_print.instructions`)
    summary: str = ""
    substeps: tuple[str, ...] = ()  # the sub-steps with letters (:meth:`_Context.letter`)
    labels: tuple[tuple[str, Vec3], ...] = ()
    group: tuple[str, ...] = ()  # identical parts drawn in this step (their first is ``part``)


def _first_lines(strokes: Sequence[Stroke], camera: Camera,
                 floor_z: float | None = None) -> FirstBoxLines | None:
    """What the sheet prints of the box of the first step's ``strokes`` above the floor
    ``floor_z`` (:func:`h2s_print.project.first_box_lines`; the sheet reads the same)."""
    return first_box_lines(camera, [p for s in strokes for p in s.points3d], floor_z)


def _first_specs(lines: FirstBoxLines | None) -> list[Spec]:
    """The first box's sub-steps: its footprint on the sheet, and its nearest upright edge
    (printed on the sheet too) when it has a height, the floor below it when it stands above
    the floor, then its edges.  A flat first part (no height: the IVAR box's base) *is* its
    footprint, whose edges are gone over ("Its bottom is the blue footprint" then "Draw its
    edges" asked for a box the footprint already is).  The printed footprint places the box:
    "Place it by the green paper corners, as pictured" is said only where the sheet prints
    none (a read-through, with the footprint printed: "confusing").  Above the floor, the
    height and the floor line are one upright line through the footprint's corner: the height
    is the part above it, named so on the sheet (a read-through: "a beginner will make the
    desktop as tall as the whole desk")."""
    if lines is None:
        return [spec("first_edges"), spec("first_corners")]
    tall = lines.height is not None
    floor = lines.floor is not None
    flat = "_flat" if lines.flat else ""
    return [spec("first_footprint" + flat),
            *([spec("first_height_floor" if floor else "first_height")] if tall else []),
            *([spec("first_floor")] if floor else []), spec("first_edges" + flat)]


#: Guide ids of the sheet's printed lines on the first step (:func:`_sheet_guides`), and of
#: the floor line below the first box.
SHEET_GUIDE = "sheet"
SHEET_FLOOR = "sheet_floor"


def _sheet_guides(lines: FirstBoxLines | None, camera: Camera) -> tuple[Guide, ...]:
    """The first step's guides that the calibrated sheet prints (role ``sheet``): the first
    box's footprint, edge by edge, and its nearest upright edge.  The first box is drawn on
    them, not by eye; they are new in that step (status ``new``) and shown only there (the
    box's own edges cover them after).  Novice and apprentice only: a master sees no guides
    (DESIGN.md §2.6)."""
    if lines is None:
        return ()
    foot = lines.footprint
    segs = [(foot[k], foot[(k + 1) % 4]) for k in range(4)]
    if lines.height is not None:
        segs.append(lines.height)
    ids = [f"{SHEET_GUIDE}{k}" for k in range(1, len(segs) + 1)]
    if lines.floor is not None:  # shown while a step stands a part on the floor
        segs.append(lines.floor)
        ids.append(SHEET_FLOOR)
    out = []
    for gid, (a, b) in zip(ids, segs):
        mm = camera.project(np.array([a, b], dtype=float))
        out.append(Guide(gid, "new", a, b, (float(mm[0, 0]), float(mm[0, 1])),
                         (float(mm[1, 0]), float(mm[1, 1])), "sheet"))
    return tuple(out)


def _in_plane(line: Sequence[Any], anchor: Any, box: Any) -> bool:
    """Does the line (two 3D points) lie in the plane ``anchor`` puts the part's side on (its
    end's plane of ``box``, or its mid-plane)?  Then the line places that side."""
    ax = anchor.axis
    lo, hi = float(box[0][ax]), float(box[1][ax])
    at = lo if anchor.end == "lo" else hi if anchor.end == "hi" else 0.5 * (lo + hi)
    tol = 1e-9 * max(1.0, abs(lo), abs(hi))
    return all(abs(float(p[ax]) - at) <= tol for p in line)


def _edge_for(edge: Spec, anchors: Sequence[Any], side_of: Callable[[Any], str],
              box: Any = None) -> Spec:
    """"Use the edge DC for its back.": an edge of a drawn part cited with the sides of the
    part it places (of ``anchors``, those whose plane the edge lies in, given the part's
    ``box``; a read-through: the mixer's column read "Use the edge DC." and nothing said its
    back stands on DC).  ``edge`` itself when it places none."""
    line = dict(edge.fields)["line"]
    said = list(dict.fromkeys(side_of(a) for a in anchors
                              if box is None or _in_plane(line.points, a, box)))
    return (spec("edge_for", edge.same, line=line, sides=_join(said), each=tuple(said))
            if said else edge)


def _edges_together(specs: Sequence[Spec]) -> list[Spec]:
    """Edges cited for one side each said in one sentence, in order: "Use the edges AD and
    AB for its left side and bottom." (two sentences cost four words more).  Only when each
    edge places one side, the edges are distinct and so are the sides: else each is said on
    its own (lines and sides could not be paired)."""
    fors = [x for x in specs if x.key == "edge_for"]
    sides = [dict(x.fields)["each"] for x in fors]
    lines = [frozenset(dict(x.fields)["line"].points) for x in fors]
    if (len(fors) < 2 or any(len(e) != 1 for e in sides) or len(set(sides)) < len(sides)
            or len(set(lines)) < len(lines)
            or any(len(dict(x.fields)["line"].points) != 2 for x in fors)):
        return list(specs)
    each = tuple(e[0] for e in sides)
    both = spec("edge_for_two", ("edges",) + tuple(x.same for x in fors),
                line=Many(tuple(dict(x.fields)["line"] for x in fors)), sides=_join(each),
                each=each)  # each line's side, for a sentence that keeps only some
    return [both if x is fors[0] else x for x in specs if x.key != "edge_for" or x is fors[0]]


def _citations(groups: Sequence[Sequence[_Unit]], step: int,
               side_of: Callable[[Any], str] | None = None, box: Any = None) -> list[Spec]:
    """"Use KL from step 2 for its back.": every line the units of ``groups`` (the guides
    steps numbered from ``step``) draw, cited with the step that drew it (an earlier one for a
    line reused) and, with ``side_of`` (an anchor's side of the part, "back", "middle (front
    to back)"), what the lines place (a read-through: "Use MP from step 8" did not say MP is
    the flash's back, and a reader who had just centred the lens on PQ centred the flash).
    With the part's ``box``, an edge places only the sides whose plane it lies in."""
    cited: dict[int, list[Pts]] = {}
    sides: dict[int, list[str]] = {}
    carried: dict[int, bool] = {}  # step -> carried (True) or only extended (False)
    moved_sides: dict[int, list[str]] = {}  # step -> the sides its carried lines place
    moved_mids: dict[int, list[str]] = {}  # ... those of them that are middles
    moved = _carried(groups)
    edges: list[Spec] = []  # edges of drawn parts: no step drew them ("Use the edge AD")
    floor: list[Spec] = []  # "Its bottom corner is G, on EG from step 3."
    for k, g in enumerate(groups):
        for u in g:
            for i, r in enumerate(u.results):
                if tuple(r) in moved:
                    continue
                if u.floor:
                    floor.append(spec("floor_reuse_middle" if u.floor_middle else "floor_reuse",
                                      line=Pts(r), point=Pts((r[1],)), step=step + k))
                    continue
                edge = next((x for x in u.specs if x.key == "edge"
                             and dict(x.fields)["line"].points == tuple(r)), None)
                if edge is not None:
                    edges.append(_edge_for(edge, u.anchors, side_of, box) if side_of else edge)
                else:
                    n = u.origin.get(i, step + k)
                    cited.setdefault(n, []).append(Pts(r))
                    if side_of is not None:
                        sides.setdefault(n, []).extend(side_of(a) for a in u.anchors)
            if any(x.key in _CARRIES for x in u.specs):
                carried[step + k] = carried.get(step + k, False) or any(
                    x.key in _CARRIES and not x.key.startswith("extend_to") for x in u.specs)
                if side_of is not None:
                    moved_sides.setdefault(step + k, []).extend(side_of(a) for a in u.carried_for)
                    moved_mids.setdefault(step + k, []).extend(
                        side_of(a) for a in u.carried_for if a.end == "mid")
    out = _edges_together(edges)
    for n, lines in sorted(cited.items()):
        said = list(dict.fromkeys(sides.get(n, ())))
        out.append(spec("reuse_for", line=Many(tuple(lines)), step=n, sides=_join(said))
                   if said else spec("reuse", line=Many(tuple(lines)), step=n))
    # lines only extended are said so (a read-through: "the lines carried in step 4" where
    # step 4 had extended them)
    # and, as for lines cited, what they place (a read-through: "Use the lines extended in
    # step 4" did not say they place the bowl's front and bottom)
    for n, moved_too in carried.items():
        key = "reuse_carried" if moved_too else "reuse_extended"
        said = list(dict.fromkeys(moved_sides.get(n, ())))
        out.append(spec(f"{key}_for", step=n, sides=_join(said), each=tuple(said),
                        mids=tuple(dict.fromkeys(moved_mids.get(n, ()))))
                   if said else spec(key, step=n))
    return out + floor


def _carried(groups: Sequence[Sequence[_Unit]]) -> set[tuple]:
    """The lines (end points, both ways round) that the units of ``groups`` carry to the
    part.  Such a line is cited as carried ("Use the lines carried in step 9"), not also as
    itself ("Use FG from step 2"): the part sits on the carried copy, which the step names
    (:func:`_citations`, and the placing step's own citations)."""
    out: set[tuple] = set()
    for g in groups:
        for u in g:
            for x in u.specs:
                if x.key in _CARRIES:
                    # (a line carried from a crossing on it is its ``other``: "Extend GF to
                    # NP, meeting it at R; from R, draw RS ...")
                    carried = ("other",) if x.key.startswith("cross_") else ("lines", "lines2")
                    for name, v in x.fields:
                        if name in carried:
                            for run in line_runs(v):
                                out.update((tuple(run.points), tuple(run.points)[::-1]))
    return out


#: Sub-steps that carry lines to the part (the carry unit's).
_CARRIES = tuple(key + suffix for key in (
    "carry", "carry_to", "carry_two", "carry_turn", "carry_turn_eye", "carry_turn_to",
    "carry_turn_eye_to", "carry_walk", "carry_walk_to", "extend_turn", "extend_turn_to", "extend_walk",
    "extend_walk_to", "carry_from", "carry_from_to", "carry_from_walk", "carry_from_walk_to",
    "carry_on", "carry_on_to", "carry_on_walk", "carry_on_walk_to",
    "extend_to", "carry_meet", "carry_meet_on", "carry_meet_edge",
    "carry_two_meet",
    "cross_carry", "cross_on") for suffix in ("", "_for"))


def _touch(a: "_Unit", b: "_Unit", tol: float) -> bool:
    """Do two units of construction share a point (a line's end, a result's end)?  Then one
    may use what the other draws, and their order stays."""
    def points(u: _Unit) -> np.ndarray:
        pts = [p for ln in u.lines for p in (ln.start, ln.end)] + [p for r in u.results for p in r]
        return np.asarray(pts, dtype=float).reshape(-1, 3)

    pa, pb = points(a), points(b)
    return bool(len(pa) and len(pb)
                and (np.abs(pa[:, None, :] - pb[None, :, :]).max(axis=2) <= tol).any())


@dataclass
class _Unit:
    """The constructions of one primitive step on one parent face: sub-steps, lines, results."""

    parent: str
    specs: list[Spec] = field(default_factory=list)
    lines: list[_Line] = field(default_factory=list)
    results: list[tuple[Vec3, Vec3]] = field(default_factory=list)
    room: bool = False  # a construction that needs room on the face (not only edges)
    anchors: list[Any] = field(default_factory=list)
    origin: dict[int, int] = field(default_factory=dict)  # result index -> step that drew it
    carried_for: list[Any] = field(default_factory=list)  # anchors whose lines it carries
    floor: bool = False  # finds the part's bottom corner on the floor (its result's end)
    floor_middle: bool = False  # ... the middle of its bottom instead


def _names_lines_of(u: _Unit, group: Sequence[_Unit], tol: float) -> bool:
    """Does a sentence of another unit of ``group`` name a line of ``u`` ("Extend NQ as
    pictured" names the edge NQ that ``u`` cites)?"""
    runs = [r.points for v in group if v is not u for x in v.specs for _, val in x.fields
            if isinstance(val, (Pts, Many)) for r in line_runs(val) if len(r.points) == 2]
    return any(_same_segment(ln.start, ln.end, a, b, tol) for ln in u.lines for a, b in runs)


def _merged_outlines(prev: _Draft, d: _Draft, say: Any) -> _Draft:
    """Two outline drafts as one step: small ellipses first (one sentence for all the parts'
    ellipses sketched by eye), then one tracing sub-step; named after all its parts."""
    members = prev.group + d.group
    both = list(prev.specs) + list(d.specs)
    small = [x for x in both if x.key in ("ellipse_by_eye_part", "ellipse_by_eye_parts")]
    if len(small) > 1:
        names = [n for x in small for n in (
            [dict(x.fields)["part"]] if x.key == "ellipse_by_eye_part"
            else list(dict(x.fields)["parts"]))]
        one = spec("ellipse_by_eye_parts", parts=tuple(names),
                   the_parents=_join([_the(n) for n in names]))
        both = [one] + [x for x in both if x not in small]
    both = ([x for x in both if not x.key.startswith("contour")]
            + [x for x in both if x.key.startswith("contour")][:1])
    return replace(prev, strokes=prev.strokes + d.strokes, lines=prev.lines + d.lines,
                   specs=tuple(unique_specs(both)), eyeball=prev.eyeball or d.eyeball,
                   group=members,
                   headline=_t("headline.contour_many", Parts=_cap(_join([say(q)
                                                                        for q in members]))))


#: The lines a sub-step draws, by template key (fields holding two points each).
_DRAWS: dict[str, tuple[str, ...]] = {
    "diagonals": ("first", "second"), "diagonals_box": ("first", "second"),
    "half_diagonals": ("first", "second"),
    "through": ("line",), "cross": ("line",), "from": ("line",),
    "ellipse_diagonals": ("first", "second"), "ellipse_diagonals_plate": ("first", "second"),
}


def _draws_known(s: Spec, known: Sequence[tuple[Vec3, Vec3]], tol: float) -> bool:
    """Does sub-step ``s`` only draw a line already on the sheet (one of ``known``)?"""
    if s.key not in ("cross", "through", "from", "edge"):
        return False
    line = dict(s.fields).get("line")
    if not isinstance(line, Pts) or len(line.points) != 2:
        return False
    return any(_same_segment(line.points[0], line.points[1], p, q, tol) for p, q in known)


def _carry_key(item: tuple[tuple[int, int | None], Any]) -> tuple[int, int]:
    """Sort key of a carry group ``((axis, turn or None), runs)``."""
    (axis, turn), _ = item
    return (axis, -1 if turn is None else turn)
