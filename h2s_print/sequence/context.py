"""The view context: everything a view needs, computed once; the steps of each level."""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field, replace
from typing import Any, Callable, Iterable, Mapping, Sequence

import numpy as np

from .. import templates
from ..candidates import Anchor, relation_holds
from ..config import PaperSpec, SequenceSettings, ViewSpec
from ..constructions import Face
from ..contours import final_contours
from ..errors import SelectionError
from ..instructions import (
    Many,
    Pts,
    Spec,
    brief_specs,
    construction_specs,
    letter_steps,
    line_runs,
    points_key,
    points_of,
    spec,
    unique_specs,
)
from ..names import PartName, display_names, natural_key, stem
from ..occlude import Solid
from ..order import drawing_order, part_size, start_part
from ..project import raised, vanishing_points
from ..ratios import entry_for
from ..types import (
    Box,
    Camera,
    Guide,
    Label,
    Part,
    Step,
    Stroke,
    VanishingPoint,
    Vec3,
    ViewPlan,
)
from .camera import _adjusted_parts, _fit_camera, _tolerance
from .drafts import (
    _CARRIES,
    _CITES,
    _DRAWS,
    MAX_STEP_WORDS,
    SHEET_FLOOR,
    _carried,
    _carry_key,
    _citations,
    _Draft,
    _draws_known,
    _edge_for,
    _edges_together,
    _first_lines,
    _first_specs,
    _names_lines_of,
    _sheet_guides,
    _touch,
    _Unit,
)
from .ellipses import _Ellipses
from .geometry import (
    ALONG_MM,
    TINY_CARRY_MM,
    TINY_LOOP_MM,
    _anchor_lines,
    _box_corners,
    _carry_ways,
    _contour_strokes,
    _covers,
    _Crossing,
    _crossing_carry,
    _drawn_box,
    _extent,
    _floor_corner,
    _floor_under,
    _front_facing,
    _walk_carry,
    _Line,
    _Meeting,
    _meeting_carries,
    _mostly_on,
    _moving_axis,
    _on_face,
    _on_line,
    _near_segment,
    _on_segment,
    _placed_planes,
    _polygon_area_mm2,
    _round,
    _runs_along,
    _same_point,
    _same_segment,
    _segments_cross,
    _scaffold,
    _Segments,
    _sheet_length,
    _sheet_polygon,
    _too_small,
    _touching,
    _vec,
)
from .repeats import _Repeats
from .words import (
    _cap,
    drawn_fields,
    _guides_of,
    _join,
    _plural,
    _positions,
    _ratio_phrases,
    _ratio_words,
    _raw,
    _substep,
    _t,
    _the,
    _unique,
    _Words,
)

log = logging.getLogger(__name__)


#: Positions said for a part placed by eye, at most (:meth:`_Context.free_positions`).
FREE_POSITIONS = 3


#: Sizes a part judged by eye is compared with (:meth:`_Context.size_specs`): the ratio of its
#: extent to a drawn part's along the same axis, named by the key of ``size_amounts``.
SIZE_RATIOS = ((0.25, "quarter"), (1 / 3, "third"), (0.5, "half"), (2 / 3, "two-thirds"),
               (0.75, "three-quarters"), (1.0, "same"), (1.5, "one-and-half"), (2.0, "twice"),
               (3.0, "three-times"), (4.0, "four-times"))


#: A size is said when the ratio is within this fraction of an easy one ...
SIZE_TOLERANCE = 0.12


#: ... in at most this many sentences a step.
SIZE_SENTENCES = 2

#: A round part's box is square across its axis within this fraction: its other size is
#: said to equal the one a size sentence gives (:meth:`_Context.round_sizes`).
ROUND_SIZES = 0.01
#: The first box's faces are named on its picture where they are at least this wide on the
#: sheet (mm: projected area over the longest projected side; the step pages show the sheet
#: at about half size), room for the word.
FACE_LABEL_MM = 16.0


def _easy_ratio(ratio: float) -> str | None:
    """The name of the :data:`SIZE_RATIOS` entry ``ratio`` lies within
    :data:`SIZE_TOLERANCE` of (the nearest), or None."""
    value, name = min(SIZE_RATIOS, key=lambda vn: abs(ratio / vn[0] - 1.0))
    return name if abs(ratio / value - 1.0) <= SIZE_TOLERANCE else None


#: Roles shown at each level.
LEVEL_ROLES: dict[str, frozenset[str]] = {
    "novice": frozenset({"construction", "guide", "vanishing"}),
    "apprentice": frozenset({"guide", "vanishing"}),
    "master": frozenset(),
    "basic": frozenset(),
}


_ROLE_RANK = {"construction": 0, "vanishing": 1, "guide": 2}


def _by_eye_ellipses(d: _Draft) -> str:
    """An outline step's sentence sketching ellipses by eye, or "": a master reads only the
    headline and this (a read-through: the master's roller parts were "Ellipses come later"
    and no step said more than "Handle: its outlines.")."""
    if d.kind != "contour" or len(d.specs) != len(d.substeps):
        return ""
    return next((x for s, x in zip(d.specs, d.substeps) if s.key.startswith("ellipse_by_eye")),
                "")


def _unsaid(x: Spec) -> Spec:
    """A carry sentence without what its lines place ("Carry XY vertically, as pictured.")."""
    if x.key not in _CARRIES:
        return x
    f = {k: Many(tuple(Pts(r.points) for r in line_runs(v))) if k in ("lines", "lines2")
         and any(r.places for r in line_runs(v)) else v
         for k, v in x.fields if k != "sides"}
    return spec(x.key.removesuffix("_for"), x.same, x.pair, **f)


def _stands_on_floor(d: _Draft) -> bool:
    """Does draft ``d`` stand a part on the floor the sheet prints ("Its bottom stands on the
    floor")?"""
    return any(x.key in ("on_floor", "on_floor_eye", "on_floor_line", "floor_side",
                         "floor_side_through",
                         "floor_line", "floor_line_end", "floor_back")
               for x in d.specs)


def _floor_span(drafts: Sequence[_Draft]) -> tuple[int | None, int]:
    """The first scaffold draft (the first box, whose floor line the sheet prints) and the
    last draft standing a part on the floor (-1 when none): the floor line's life."""
    start = next((i for i, d in enumerate(drafts) if d.kind == "primitive" and d.strokes), None)
    until = max((i for i, d in enumerate(drafts) if _stands_on_floor(d)), default=-1)
    return start, until


#: Citations of an edge of a drawn part.
_EDGE_CITES = ("edge", "edge_two", "edge_for", "edge_for_two")
def _fewest_longest(items: Sequence[str], fits: Callable[[list[str]], bool],
                    least: int) -> list[str]:
    """``items`` without their longest (in words; ties: the later), one at a time, until
    ``fits`` them or ``least`` are left: what a step over the word limit still says, the rest
    left to the picture."""
    kept = list(items)
    while len(kept) > least and not fits(kept):
        kept.remove(max(reversed(kept), key=lambda x: len(x.split())))
    return kept


#: Centring sentences said of two crossing lines in one (:meth:`_Context.centred_together`).
_CROSS_CENTRED = {"centred": "centred_cross", "centred_reuse": "centred_cross_reuse",
                  "centred_carried": "centred_cross_carried",
                  "centred_extended": "centred_cross_extended"}

#: Citations of the lines an earlier step carried or extended (no line named).
_MOVED_CITES = ("reuse_carried", "reuse_carried_for", "reuse_extended", "reuse_extended_for")



def _paired(s: Spec) -> Spec:
    """Twin lines each crossing a line, said pair by pair: "Draw QT and NS; QT crosses GN at
    X, NS crosses LQ at Y." ("they cross GN and LQ at X and Y" left which crosses which to
    the picture, a read-through); other specs as they are."""
    if s.key != "connect_two":
        return s
    f = dict(s.fields)
    runs = {k: (f[k].items if isinstance(f[k], Many) else (f[k], f[k]))
            for k in ("line", "other", "point")}
    if any(len(v) != 2 for v in runs.values()) or not isinstance(f["line"], Many):
        return s
    rest = {k: v for k, v in f.items() if k not in runs}
    return spec("connect_pair", s.same, s.pair, line=runs["line"][0], line2=runs["line"][1],
                other=runs["other"][0], other2=runs["other"][1], point=runs["point"][0],
                point2=runs["point"][1], **rest)


def _edge_cite(key: str) -> bool:
    """Does sub-step ``key`` cite a drawn box's edge ("Put its bottom on the edge AB.")?"""
    return key.startswith("edge")


@dataclass(eq=False)
class _Context(_Repeats, _Ellipses):
    """Everything a view needs, computed once and shared by its levels (never escapes)."""

    plan: Any
    camera: Camera
    settings: SequenceSettings
    vps: tuple[VanishingPoint, ...]
    words: _Words
    tol: float
    by_id: dict[str, Any]
    chosen: dict[str, Any]
    adjusted: dict[str, Part]
    originals: dict[str, Part]
    _guided: tuple[_Draft, ...] | None = None
    _unlettered: tuple[_Draft, ...] = ()  # the guided drafts before letters
    _apprentice: tuple[_Draft, ...] | None = None
    _basic: tuple[_Draft, ...] | None = None
    _ids: tuple[tuple[tuple[str, str], ...], ...] | None = None
    _canon: dict[str, tuple[Vec3, Vec3]] = field(default_factory=dict)
    _finals: dict[str, dict[str, tuple[Stroke, ...]]] = field(default_factory=dict)
    _box_steps: dict[str, int] = field(default_factory=dict)
    _walked: bool = False  # the last drafts_of walked a carry (primitive_drafts)
    _merged: dict[int, int] = field(default_factory=dict)  # walk_carries: said with another
    _far: set[int] = field(default_factory=set)  # walk_carries: from the line's farther end
    _solids: dict[str, list[tuple[str, Solid]]] = field(default_factory=dict)
    _hide_depth: float | None = None
    _reach: dict[tuple[str, bool], tuple[np.ndarray, np.ndarray, float]] = field(
        default_factory=dict)
    # each part's visible scaffold edges on the sheet: ends and box (x0, y0, x1, y1), mm
    _edges: dict[str, list[tuple[np.ndarray, np.ndarray, tuple[float, float, float, float]]]] = \
        field(default_factory=dict)
    _scaffolds: dict[str, tuple[Stroke, ...]] = field(default_factory=dict)
    # the anchors' lines the camera fit worked out with this camera, by (candidate, anchor)
    _anchor_memo: dict[tuple[str, int], tuple] = field(default_factory=dict)
    _scaffold_ends: dict[str, list[tuple[np.ndarray, np.ndarray]]] = field(default_factory=dict)
    _floor_lines: dict[str, tuple[Vec3, Vec3] | None] = field(default_factory=dict)
    _parts: tuple[list[list[str]], set[str]] | None = None
    _drawn: list[tuple[Vec3, Vec3, int]] = field(default_factory=list)  # guide lines, by step
    _drawn_segs: _Segments | None = None  # _drawn, to look lines up in (drawn_like)
    _step_words: dict[tuple[tuple[Spec, ...], str], int] = field(default_factory=dict)
    _step_subs: dict[tuple[Spec, ...], int] = field(default_factory=dict)  # their words
    _box_pictures: dict[tuple, np.ndarray] = field(default_factory=dict)  # box_picture
    names: dict[str, PartName] = field(default_factory=dict)


    def guided_order(self, keep: Iterable[str] | None = None) -> list[str]:
        """Drawing order of the kept primitives (all selected ones when ``keep`` is None):
        :func:`h2s_print.order.drawing_order` on the selected boxes (module docstring,
        "drawing order").

        Raises:
            SelectionError: the anchoring graph has a cycle.
        """
        names = sorted(self.chosen if keep is None else set(keep))
        kept = set(names)
        parents = {p: sorted({self.by_id[pid].part for pid in self.chosen[p].parents} & kept)
                   for p in names}
        rests_on = {p: [q for q in _touching(p, self.chosen, 100.0 * self.tol) if q in kept]
                    for p in names if not self.chosen[p].anchors}
        cam = np.asarray(self.camera.position, dtype=float)
        dist = {p: float(np.linalg.norm(np.mean(np.asarray(self.chosen[p].box, dtype=float),
                                                axis=0) - cam)) for p in names}
        sizes = {p: part_size(self.chosen[p].box) for p in names}
        first = self.start(kept)
        if first is not None and self.chosen[first].anchors:
            log.info("start part %s hangs off %s (not a root): its ancestors are drawn first",
                     first, ", ".join(parents[first]))
        try:
            return drawing_order(sizes, parents, dist, first, rests_on)
        except ValueError as err:
            raise SelectionError(str(err)) from None

    def start(self, keep: set[str]) -> str | None:
        """The start part (:func:`h2s_print.order.start_part` of the fitted primitives); when
        it is left out (hidden, anchoring nothing visible), the start part of the kept ones."""
        first = start_part(self.plan.primitives)
        if first is not None and first not in keep:
            fallback = start_part([self.plan.primitive(p) for p in sorted(keep)])
            log.info("start part %s is not drawn (hidden); starting from %s", first, fallback)
            first = fallback
        return first

    def floor_z(self, basic: bool) -> float:
        """The floor the object stands on: the lowest z of the selected boxes (``basic``: of
        the fitted ones, the control tutorial's)."""
        boxes = ([p.box for p in self.plan.primitives] if basic
                 else [c.box for c in self.chosen.values()])
        return float(min(b[0][2] for b in boxes))

    def on_floor(self, part: str, drawn: Sequence[str]) -> bool:
        """Does ``part`` stand on the floor that the sheet prints under the first box (one
        above the floor: a table's top, :class:`h2s_print.project.FirstBoxLines`), its bottom
        placed by no anchor?  Then its step says so, and its bottom is no longer judged by
        eye (a read-through: the table's legs were "width, depth and height by eye")."""
        if not drawn or part == drawn[0]:
            return False
        floor = self.floor_z(False)
        first, box = self.chosen[drawn[0]].box, self.chosen[part].box
        return (raised(*first, floor) and abs(box[0][2] - floor) <= self.tol
                and not any(a.axis == 2 and a.end == "lo" for a in self.chosen[part].anchors))

    def floor_unit(self, part: str, drawn: Sequence[str]) -> _Unit | None:
        """The floor under ``part``'s nearest bottom corner, constructed from the floor
        line's foot F (printed on the sheet under the first box's nearest corner C), for a
        part standing on the floor (:meth:`on_floor`) whose top lies in the first box's
        bottom face, anchored: from its top corner Q a line toward one vanishing point to
        the first box's bottom edge through C (R), from F the floor line toward the other
        (S, under R), R dropped to S, and from S back toward the first vanishing point to T,
        under Q: its bottom corner.  Lines along which Q and C agree are left out.  None
        otherwise (the part is said to stand on the floor, ``on_floor``).  A
        read-through of stop 30: the table's leg and the desk's foot "carried the floor
        line's foot" with no line drawn and no direction said."""
        if not self.on_floor(part, drawn):
            return None
        cand = self.chosen[part]
        if not any(a.axis == 2 and a.end == "hi" for a in cand.anchors):
            return None
        first = drawn[0]
        floor_line = self.floor_line(first)
        if floor_line is None:
            return None
        eye = np.asarray(self.camera.position, dtype=float)
        placed = [(a.axis, float(cand.box[0 if a.end == "lo" else 1][a.axis]))
                  for a in cand.anchors if a.axis in (0, 1) and a.end in ("lo", "hi")]
        corner = _floor_corner(self.chosen[first].box, cand.box, *floor_line, eye, self.tol,
                               placed)
        return None if corner is None else self.floor_construction(first, corner)

    def floor_middle_unit(self, part: str, drawn: Sequence[str], meet: Vec3,
                          known: Sequence[tuple[Vec3, Vec3]] = ()) -> _Unit | None:
        """The floor under the middle of ``part``'s bottom, for a part standing on the floor
        (:meth:`on_floor`) whose top is anchored below the first box and whose centring
        lines meet at ``meet`` on that box's bottom face (the roller's handle: "Its bottom
        stands on the floor: judge where by eye" under a point the page has): the
        construction of :meth:`floor_unit` under ``meet`` (:func:`~.geometry._floor_under`),
        ending at the middle of its bottom; a line of it
        among ``known`` (the carries that meet there) is not drawn again.  None otherwise."""
        if not self.on_floor(part, drawn):
            return None
        cand, first = self.chosen[part], drawn[0]
        fbox = self.chosen[first].box
        if (not any(a.axis == 2 and a.end == "hi" for a in cand.anchors)
                or abs(meet[2] - fbox[0][2]) > self.tol
                or cand.box[1][2] > fbox[0][2] + self.tol):
            return None
        middle = [0.5 * (cand.box[0][k] + cand.box[1][k]) for k in (0, 1)]
        if any(abs(meet[k] - middle[k]) > 10.0 * self.tol for k in (0, 1)):
            return None
        floor_line = self.floor_line(first)
        if floor_line is None:
            return None
        corner = _floor_under(fbox, (float(meet[0]), float(meet[1])), *floor_line, self.tol)
        return None if corner is None else self.floor_construction(first, corner, True, known)

    def floor_construction(self, first: str, corner: Any, middle: bool = False,
                           known: Sequence[tuple[Vec3, Vec3]] = ()) -> _Unit:
        """The unit drawing ``corner`` (:class:`~.geometry._FloorCorner`) under the first box
        ``first``: its bottom corner found (:meth:`floor_unit`), or with ``middle`` the middle
        of its bottom (:meth:`floor_middle_unit`)."""
        Q, R, F, S, T = corner.Q, corner.R, corner.F, corner.S, corner.T
        a, b, moved_a, moved_b = corner.a, 1 - corner.a, corner.moved_a, corner.moved_b
        owner = self.say(first)
        specs: list[Spec] = []
        out: list[_Line] = []
        words = self.words
        # Q on the first box's bottom edge (its sides flush with the first box's): QR runs
        # along that edge, already drawn, and R is the box's corner (a line along a drawn
        # edge draws nothing new)
        fbox = self.chosen[first].box
        along = moved_a and any(abs(Q[b] - fbox[e][b]) <= self.tol for e in (0, 1))
        # (a line a carry drew already: the roller's handle's centring carry from L to Q)
        drawn = any(_same_segment(Q, R, p, q, self.tol) for p, q in known)
        if moved_a and not along and not drawn:
            specs.append(spec("floor_over_point" if middle else "floor_over", line=Pts((Q, R)),
                              point=Pts((Q,)), vp=words.vp(a, Q, R), parent=owner))
            out.append(_Line("vanishing", Q, R))
        result = (F, S)  # the line whose end is the bottom corner
        if moved_b:
            # (its end under Q when no line follows: "its nearest upright edge ends at C" was
            # wrong once Q was the corner its placed sides meet, not the nearest one)
            specs.append(spec("floor_line", line=Pts((F, S)), point=Pts((F,)),
                              vp=words.vp(b, F, S), end=Pts((S,))) if moved_a else
                         spec("floor_line_end" + ("_middle" if middle else ""),
                              line=Pts((F, S)), point=Pts((F,)), vp=words.vp(b, F, S),
                              end=Pts((S,)), through=Pts((Q,)),
                              **({"vp2": words.vp(2, Q, S)} if middle else {})))
            out.append(_Line("vanishing", F, S))
            if middle and not moved_a:  # the line down from Q that finds it (below)
                out.append(_Line("vanishing", Q, S))
            if moved_a:
                specs.append(spec("floor_drop_corner" if along else "floor_drop",
                                  line=Pts((R, S)), point=Pts((R,)), other=Pts((F, S)),
                                  **({"parent": owner} if along else {})))
                out.append(_Line("vanishing", R, S))
        if moved_a:
            start = S if moved_b else F
            specs.append(spec("floor_back" + ("_middle" if middle else ""),
                              line=Pts((start, T)), point=Pts((start,)),
                              vp=words.vp(a, start, T), end=Pts((T,)), through=Pts((Q,)),
                              **({"vp2": words.vp(2, Q, T)} if middle else {})))
            out.append(_Line("vanishing", start, T))
            if middle:  # the middle of the bottom is no corner a box edge drops to: the line
                # down from the meeting point finds it ("V, below Q" named a point no line
                # gave, a read-through of the roller's handle); in space, as the floor's
                # other lines (the role the picture shows every level that draws lines)
                out.append(_Line("vanishing", Q, T))
            result = (start, T)
        return _Unit(first, specs, out, [result], floor=True, floor_middle=middle)

    def floor_leg(self, carry: Sequence[_Line], floor: float, foot: Vec3 | None
                  ) -> tuple[Vec3, Vec3] | None:
        """The line along the floor from the floor line's ``foot`` to where ``carry`` turns,
        when it turns on the ``floor`` in line with the foot along one of the floor's axes
        (one line toward a vanishing point finds it); None otherwise."""
        if foot is None or len(carry) < 2:
            return None
        turn = carry[0].end
        if abs(turn[2] - floor) > 10.0 * self.tol or _same_point(turn, foot, 10.0 * self.tol):
            return None
        if not any(abs(turn[b] - foot[b]) <= 10.0 * self.tol for b in (0, 1)):
            return None
        return (foot[0], foot[1], floor), turn

    def floor_line(self, first: str) -> tuple[Vec3, Vec3] | None:
        """The floor line the sheet prints under the first box ``first``'s nearest corner:
        ``(corner, foot)``, or None (a first box on the floor); worked out once (every part
        on the floor asks)."""
        if first not in self._floor_lines:
            lines = _first_lines(self.scaffold(first), self.camera, self.floor_z(False))
            self._floor_lines[first] = None if lines is None else lines.floor
        return self._floor_lines[first]

    def floor_foot(self, part: str, drawn: Sequence[str]) -> Vec3 | None:
        """The floor line's foot, for a part standing on the floor (:meth:`on_floor`)."""
        found = self.floor_line(drawn[0]) if self.on_floor(part, drawn) else None
        return None if found is None else found[1]

    def floor_size(self, part: str, drawn: Sequence[str]) -> list[tuple[Spec, list[int]]]:
        """"Its bottom stands on the floor" (:meth:`on_floor`) as the first of the part's
        size sentences (said when the step has room for it, :meth:`sized`): with its top
        anchored, it gives the height, which is then not left to the eye.  "... where the
        blue floor line ends" only where an upright edge of the part's box is the floor
        line's; elsewhere the floor under the part is not where the line ends (the picture is
        in perspective), and the sentence says to judge it by eye (a read-through: the
        roller's handle, drawn to the floor line's foot, came out far too long)."""
        if not self.on_floor(part, drawn):
            return []
        top = any(a.axis == 2 and a.end == "hi" for a in self.chosen[part].anchors)
        floor_line = self.floor_line(drawn[0])
        box = self.chosen[part].box
        at_foot = floor_line is not None and any(
            abs(float(box[i][0]) - float(floor_line[1][0])) <= self.tol
            and abs(float(box[j][1]) - float(floor_line[1][1])) <= self.tol
            for i in (0, 1) for j in (0, 1))
        side = None if at_foot else self.floor_side(part, drawn)
        return [(side[0] if side is not None else spec("on_floor" if at_foot else "on_floor_eye"),
                 [2] if top else [])]

    def floor_side(self, part: str, drawn: Sequence[str], copies: Sequence[str] = ()
                   ) -> tuple[Spec, _Line, tuple[int, str], bool] | None:
        """For a part standing on the floor (:meth:`on_floor`) with a side in line with the
        floor line's foot F: the line along the floor from F under that side, to the side's
        far end, and the sentence drawing it ("From F, the blue floor line's foot, draw FG
        toward the right vanishing point: its back stands on it."; the train's wheels, whose
        backs are in line with the engine's front, read "Its bottom stands on the floor:
        judge where by eye", a read-through), the side's (axis, end), and whether every one
        of ``copies`` (identical parts drawn with it) has that side on the line too: then
        the line runs under them all.  None otherwise."""
        foot = self.floor_foot(part, drawn)
        if foot is None:
            return None
        box = self.chosen[part].box
        for k in (0, 1):
            for e in (0, 1):
                if abs(box[e][k] - foot[k]) > self.tol:
                    continue
                o = 1 - k
                boxes = [box] + [self.chosen[q].box for q in copies]
                along = all(abs(b[e][k] - foot[k]) <= self.tol for b in boxes[1:])
                ends = [b[j][o] for b in (boxes if along else boxes[:1]) for j in (0, 1)]
                far = max(ends, key=lambda v: abs(v - foot[o]))
                if abs(far - foot[o]) <= self.tol:
                    continue
                end = [float(foot[0]), float(foot[1]), float(foot[2])]
                end[o] = float(far)
                stop: Vec3 = (end[0], end[1], end[2])
                side = self.words.side(k, "lo" if e == 0 else "hi")
                # parts on both sides of the foot (a read-through: the train's wheels 5 and 7
                # stood on "JP" beyond J, where no line was): the line runs under them all,
                # drawn through the foot
                behind = [v for v in ends if (v - foot[o]) * (far - foot[o]) < 0
                          and abs(v - foot[o]) > self.tol]
                if behind:
                    back = max(behind, key=lambda v: abs(v - foot[o]))
                    start = list(end)
                    start[o] = float(back)
                    begin: Vec3 = (start[0], start[1], start[2])
                    return (spec("floor_side_through", line=Pts((begin, stop)),
                                 point=Pts((foot,)), vp=self.words.vp(o, begin, stop),
                                 sides=side),
                            _Line("vanishing", begin, stop), (k, "lo" if e == 0 else "hi"),
                            bool(copies) and along)
                return (spec("floor_side", line=Pts((foot, stop)), point=Pts((foot,)),
                             vp=self.words.vp(o, foot, stop), sides=side),
                        _Line("vanishing", foot, stop), (k, "lo" if e == 0 else "hi"),
                        bool(copies) and along)
        return None

    def floor_side_lines(self, specs: Sequence[Spec]) -> list[_Line]:
        """The lines the ``floor_side`` sentences among ``specs`` draw."""
        return [_Line("vanishing", *dict(x.fields)["line"].points) for x in specs
                if x.key in ("floor_side", "floor_side_through")]

    def basic_order(self, keep: set[str]) -> list[str]:
        """The control tutorial's order of the kept parts (fitted boxes, no anchoring): the
        start part (:meth:`start`), then the others from largest to smallest
        :func:`h2s_print.order.part_size` of the fitted box (ties: name)."""
        first = self.start(keep)
        return sorted(keep, key=lambda n: (n != first, -part_size(self.plan.primitive(n).box), n))

    def finals(self, parts: dict[str, Part]) -> dict[str, tuple[Stroke, ...]]:
        """Each part's strokes in the finished drawing (:func:`final_strokes`), by name."""
        key = "basic" if parts is self.originals else "guided"
        if key not in self._finals:
            sets = final_contours([parts[p.name] for p in self.plan.model.parts], self.camera,
                                  crease_deg=self.settings.crease_deg,
                                  suggestive=self.settings.suggestive)
            self._finals[key] = {cs.part: _contour_strokes(cs, self.camera) for cs in sets}
        return self._finals[key]

    def visible(self, parts: dict[str, Part]) -> set[str]:
        """Parts with at least one line in the finished drawing (:meth:`finals`)."""
        finals = self.finals(parts)
        return {p.name for p in self.plan.model.parts if finals[p.name]}

    def closure(self, visible: set[str], uses: dict[str, set[str]]) -> set[str]:
        """``visible`` and every part reached from it through ``uses`` (part -> the parts its
        construction is drawn from)."""
        keep = set(visible)
        stack = sorted(visible)
        while stack:
            for pp in sorted(uses.get(stack.pop(), ())):
                if pp not in keep:
                    keep.add(pp)
                    stack.append(pp)
        return keep

    def free_positions(self, part: str, drawn: Sequence[str],
                       axes: Sequence[int] = (0, 1, 2)) -> list[tuple[str, Any]]:
        """Where a part placed by eye lines up with the parts drawn before it, as (part,
        anchor-like position) pairs for :func:`_position`: its preserved relations with them
        that its selected box keeps (a shared face plane: "its back in line with the base's
        back"; a common mid-plane or axis: "its middle ... half of the way ..."), the biggest
        drawn part first, at most one per axis and :data:`FREE_POSITIONS` in all.  They are
        not constructed (the selection found anchoring it dearer than judging it), only
        said, so the eye has something to go by."""
        drawn_set = set(drawn)
        used: set[int] = set(range(3)) - set(axes)  # only ``axes`` are said
        ends: dict[int, set[str]] = {}  # faces already lined up, per axis
        rels = [(r.b if r.a == part else r.a, r) for r in self.plan.relations
                if part in (r.a, r.b)]
        # the biggest drawn part first; faces in line before mid-planes (extending an edge is
        # easier than finding a middle: the train's wagon has the engine's front and back)
        rels = sorted(((q, r) for q, r in rels if q in drawn_set),
                      key=lambda qr: (-part_size(self.chosen[qr[0]].box), qr[0],
                                      qr[1].type != "coplanar", qr[1].type, qr[1].axis,
                                      str(qr[1].detail.get("a_end" if qr[1].a == part
                                                           else "b_end", ""))))
        out: list[tuple[str, Any]] = []
        for other, r in rels:
            box, obox = self.chosen[part].box, self.chosen[other].box
            if not relation_holds(r, *((box, obox) if r.a == part else (obox, box))):
                continue
            axes = ((r.axis,) if r.type != "coaxial"
                    else tuple(a for a in range(3) if a != r.axis))
            for axis in axes:
                if len(out) >= FREE_POSITIONS:
                    continue
                if r.type == "coplanar":  # both faces of an axis may line up, one each
                    mine_end = r.detail.get("a_end" if r.a == part else "b_end", "lo")
                    said = ends.get(axis)  # None: the axis was said otherwise, or not asked
                    if axis in used and (said is None or mine_end in said):
                        continue
                    ends.setdefault(axis, set()).add(mine_end)
                elif axis in used:
                    continue
                flat = _extent(obox, axis) <= 1e-9 * max(_extent(obox, a) for a in range(3))
                if r.type == "coplanar":
                    mine = r.detail.get("a_end" if r.a == part else "b_end", "lo")
                    theirs = r.detail.get("b_end" if r.a == part else "a_end", "lo")
                    pos = Anchor(axis, mine, self.chosen[other].id,
                                 0.0 if theirs == "lo" or flat else 1.0, 1,
                                 axis if flat else (axis + 1) % 3)
                else:  # a common mid-plane
                    if flat:
                        continue
                    pos = Anchor(axis, "mid", self.chosen[other].id, 0.5, 3, (axis + 1) % 3)
                out.append((other, pos))
                used.add(axis)
        return out

    def free_specs(self, positions: Sequence[tuple[str, Any]]) -> list[Spec]:
        """:meth:`free_positions` said briefly, per part drawn before: "Centre it left to
        right on the base." and "Line up its back and bottom with the base's back and top."."""
        out: list[Spec] = []
        for other in _unique(q for q, _ in positions):
            mine = [a for q, a in positions if q == other]
            mids = [a.axis for a in mine if a.end == "mid"]
            if mids:
                out.append(spec("free_centre", parent=self.say(other),
                                directions=_join([_raw("directions")[ax] for ax in mids])))
            ends = [a for a in mine if a.end != "mid"]
            if ends:
                out.append(spec("free_align", parent=self.say(other),
                                sides=_join([self.words.side(a.axis, a.end) for a in ends]),
                                psides=_join([self.words.side(a.axis, "lo" if a.ratio < 0.5
                                                              else "hi") for a in ends])))
        return out

    def size_ratios(self, part: str, axes: Sequence[int], refs: Sequence[str]
                    ) -> list[tuple[str, str, list[int]]]:
        """What a part's sizes judged by eye compare with, as ``(drawn part, ratio name,
        axes)``: per axis of ``axes``, the first part of ``refs`` whose extent along the same
        axis makes an easy ratio with the part's own (:data:`SIZE_RATIOS`, within
        :data:`SIZE_TOLERANCE`); axes with the same part and ratio together; the biggest axes
        first, at most :data:`SIZE_SENTENCES` entries.  A drawing teacher gives the proportion
        to look for ("about as tall as the column is wide") rather than "by eye" alone."""
        box = self.chosen[part].box
        found: dict[tuple[str, str], list[int]] = {}
        for axis in sorted(axes, key=lambda a: (-_extent(box, a), a)):
            mine = _extent(box, axis)
            for ref in refs:
                rbox = self.chosen[ref].box
                theirs = _extent(rbox, axis)
                if mine <= 0 or theirs <= 1e-9 * max(_extent(rbox, a) for a in range(3)):
                    continue
                name = _easy_ratio(mine / theirs)
                if name is not None:
                    found.setdefault((ref, name), []).append(axis)
                    break
        return [(ref, name, sorted(group))
                for (ref, name), group in list(found.items())[:SIZE_SENTENCES]]

    def taper_specs(self, part: str) -> list[Spec]:
        """A tapered part's smaller end compared with its larger one, when both its sides
        narrow by the same easy ratio (:data:`SIZE_RATIOS` within :data:`SIZE_TOLERANCE`):
        "Its bottom face is about half its top face's size, centred on it."  The lines drawn
        place the box around it; without this the smaller end was guessed (the read-through:
        the mixer's bowl)."""
        prim = self.plan.primitive(part)
        detail = prim.detail or {}
        if prim.type != "frustum" or prim.axis is None or not {"lo_half", "hi_half"} <= set(detail):
            return []
        lo, hi = (tuple(float(x) for x in detail[k]) for k in ("lo_half", "hi_half"))
        small, large = ("lo", "hi") if max(lo) < max(hi) else ("hi", "lo")
        s_half, l_half = (lo, hi) if small == "lo" else (hi, lo)
        if min(l_half) <= 0.0:
            return []
        names = {_easy_ratio(a / b) for a, b in zip(s_half, l_half)}
        narrower = {name for value, name in SIZE_RATIOS if value < 1.0}
        if len(names) != 1 or not names <= narrower:  # one easy ratio, a real taper
            return []
        return [spec("taper", small=self.words.face(prim.axis, small),
                     large=self.words.face(prim.axis, large),
                     amount=_raw("size_amounts")[names.pop()])]

    def size_specs(self, part: str, axes: Sequence[int], refs: Sequence[str]
                   ) -> list[tuple[Spec, list[int]]]:
        """:meth:`size_ratios` said ("Make its height about a third of the base's."), each
        with the axes it sizes."""
        amounts = _raw("size_amounts")
        return [(spec("size" if len(group) == 1 else "size_many",
                      dims=_join([self.words.dim(a) for a in group]),
                      amount=amounts[name], parent=self.say(ref)), group)
                for ref, name, group in self.size_ratios(part, axes, refs)]

    def round_sizes(self, part: str, sizes: list[tuple[Spec, list[int]]], axes: Sequence[int]
                    ) -> list[tuple[Spec, list[int]]] | None:
        """``sizes`` (:meth:`size_specs`) with a round part's other size across its axis said
        with the one a sentence gives ("Make its width and height about a quarter of the
        engine's width."; the train's wheel read a width and nothing of its height, a
        read-through), that other size's own sentence left out; or, where one size across
        its axis is constructed and the other by eye, the other said the same ("Make its
        height the same as its width."); None when nothing is to add."""
        prim, box = self.plan.primitive(part), self.chosen[part].box
        if prim.type not in ("cylinder", "frustum") or prim.axis is None:
            return None
        u, v = (a for a in range(3) if a != prim.axis)
        if abs(_extent(box, u) - _extent(box, v)) > ROUND_SIZES * max(_extent(box, u),
                                                                     _extent(box, v)):
            return None
        for said, group in sizes:
            if said.key not in ("size", "size_many"):
                continue
            for mine, other in ((u, v), (v, u)):
                if group != [mine] or other not in axes:  # its own sentence: {dims} is it
                    continue
                rest = [(x, g) for x, g in sizes if other not in g or x is said]
                if len(rest) < len(sizes) - 1 or any(
                        other in g and len(g) > 1 for x, g in sizes if x is not said):
                    continue  # the other size said with a third: keep that sentence
                fields = {**dict(said.fields), "dims": _join([self.words.dim(mine),
                                                              self.words.dim(other)])}
                merged = (spec("size_round", dim=self.words.dim(mine), **fields),
                          sorted(group + [other]))
                return [merged if x is said else (x, g) for x, g in rest]
        # one size across its axis constructed (both ends anchored), the other by eye: the
        # same ("Make its height the same as its width."; the camera's lens read "its depth
        # and height by eye" under a width drawn on two lines, a read-through)
        # (exact, where a sentence of its own compares that size with another part's)
        for mine, other in ((u, v), (v, u)):
            if mine in axes or other not in axes or any(
                    other in g and len(g) > 1 for _, g in sizes):
                continue
            same = (spec("size_same", dims=self.words.dim(other), dim=self.words.dim(mine)),
                    [other])
            return [same, *((x, g) for x, g in sizes if other not in g)]
        return None

    def step_words(self, specs: Sequence[Spec], headline: str) -> int:
        """Words of a step's text with ``headline`` and these sub-steps, lettered and
        numbered as the page says them.

        Remembered per step text: packing parts into steps asks again for groups it tried
        before (the book's four tutorials: 793 counts of 437 distinct steps); the count
        depends on the specs and headline alone (specs are frozen values).  The sentences,
        lettered alone, depend on the lettered sub-steps alone: their words are remembered
        apart, for other headlines and for specs that come out alike (the book: 470
        letterings, 363 distinct).  The text joins the headline and the numbered sentences
        with spaces, so its words are the headline's and theirs (``str.split``)."""
        key = (tuple(specs), headline)
        if key in self._step_words:
            return self._step_words[key]
        lettered = self.lettered(specs)
        subs = self._step_subs.get(lettered)
        if subs is None:  # one step lettered alone: the same sentences under any headline
            (said, _), = letter_steps([lettered], self.tol, _substep, _join)
            subs = self._step_subs[lettered] = sum(
                len(_t("step_text.number", n=k + 1, text=x).split()) for k, x in enumerate(said))
        words = self._step_words[key] = len(headline.split()) + subs
        return words

    def said_lines(self, specs: Sequence[Spec]) -> set[frozenset]:
        """The lines (:func:`points_key`) sub-steps draw (:func:`drawn_fields`) or cite
        ("Use diagonals CB and DA from step 3"): a step names them again without a step
        ("Draw DV; it crosses CB at K.")."""
        out: set[frozenset] = set()
        for x in specs:
            f = dict(x.fields)
            names = f if "step" in f else drawn_fields(x.key)
            for name in names:
                v = f.get(name)
                if isinstance(v, (Pts, Many)):
                    out.update(points_key(r.points, self.tol) for r in line_runs(v)
                               if len(r.points) == 2)
        return out

    def sized(self, headline: str, build: Callable[[list[tuple[Spec, list[int]]]], list[Spec]],
              sizes: list[tuple[Spec, list[int]]], part: str | None = None,
              loose: Sequence[int] = ()) -> list[Spec]:
        """``build(sizes[:n])``, the sub-steps with the most size sentences (biggest axes
        first) that keep the step within :data:`MAX_STEP_WORDS`: sizes help the eye, but
        never make a step longer than the limit or split it (they are not counted when
        constructions are packed into steps), at novice nor at apprentice, whose sub-step
        naming a construction can be longer than the novice's last line of it
        (:func:`~h2s_print.instructions.brief_specs`).  With ``part`` and its ``loose``
        axes, a round part's version of each choice (:meth:`round_sizes`) is tried first."""
        for n in range(len(sizes), -1, -1):
            merged = self.round_sizes(part, sizes[:n], loose) if part is not None else None
            for chosen in ([merged] if merged is not None else []) + [sizes[:n]] * (n > 0):
                specs = build(chosen)
                if self.fits_levels(specs, headline):
                    return specs
        return build([])

    def copies_pictured(self, specs: Sequence[Spec], headline: str) -> list[Spec]:
        """``specs`` with copies placed on some axes only by their words said to be placed
        otherwise as pictured ("Part 7: the same box, its middle (front to back) at half of
        part 1's depth, otherwise as pictured."; a read-through found nothing saying where
        along the desk), where the step has room: a size sentence is worth more.  Where the
        copies' words do not fit the step at all, they lie where the picture shows them."""
        def mirrored(chosen: list[Spec], short: bool = False) -> list[Spec]:
            # copies mirrored across a part's middle said so where the step has room: those
            # placed where the picture shows them, and those whose words leave an axis to the
            # picture (a read-through: the desk's second foot, said only where it lies front
            # to back; the IVAR box's second side "where the picture shows it"); from the
            # part's sides (repeats.mirror_words), or, ``short``, as mirrored across its middle
            def said(m: tuple) -> tuple[str, dict]:
                return ("repeat_mirror_short", dict(m[2])) if short else (m[0], dict(m[1]))

            out: list[Spec] = []
            for x in chosen:
                f = dict(x.fields)
                if x.key.startswith(("repeat_free", "repeat")) and f.get("mirror") and (
                        x.key.startswith("repeat_pictured") or f.get("pictured")):
                    key, fields = said(f["mirror"])
                    out.append(spec(key, x.same, x.pair, parts=f["parts"], shape=f["shape"],
                                    names=f["names"], **fields))
                elif x.key.startswith("repeat_free") and any(f.get("mirrors", ())):
                    rest = [n for n, m in zip(f["names"], f["mirrors"]) if m is None]
                    out += [spec(said(m)[0], x.same, x.pair, parts=_cap(n), shape=f["shape"],
                                 names=(n,), **said(m)[1])
                            for n, m in zip(f["names"], f["mirrors"]) if m is not None]
                    if rest:
                        out.append(spec("repeat_free" if len(rest) > 1 else "repeat_free_one",
                                        x.same, x.pair, parts=_cap(_join(rest)),
                                        shape=f["shape"], names=tuple(rest),
                                        mirrors=(None,) * len(rest)))
                else:
                    out.append(x)
            return out

        def best(chosen: list[Spec]) -> list[Spec]:
            for short in (False, True):
                up = mirrored(chosen, short)
                if up != chosen and self.fits_levels(up, headline):
                    return up
            return chosen

        said = [spec(dict(x.fields)["pictured"], x.same, x.pair, **dict(x.fields))
                if x.key == "repeat" and dict(x.fields).get("pictured") else x for x in specs]
        if said != list(specs) and self.fits_levels(said, headline):
            return best(said)
        if self.fits_levels(specs, headline):
            return best(list(specs))
        # over the step's words with where the copies lie: where the picture shows them, or
        # mirrored across a part's middle where they are and the step has room
        free = [spec("repeat_free" if f["many"] else "repeat_free_one", x.same, x.pair,
                     parts=f["parts"], shape=f["shape"], names=f["names"],
                     mirrors=(f["mirror"] or None,) if len(f["names"]) == 1
                     else (None,) * len(f["names"]))
                if x.key == "repeat" else x for x in specs for f in (dict(x.fields),)]
        if self.fits_levels(free, headline):
            return best(free)

        def counted(specs: list[Spec]) -> list[Spec]:
            # many copies named by the first and a count ("Wheel 2 and 5 more: the same box,
            # where the picture shows them": the train's wheels placed by eye from the
            # right, 77 words a step)
            return [spec(x.key, x.same, x.pair, **{**dict(x.fields), "parts": _cap(
                        templates.plural("steps", "headline.and_more",
                                         len(dict(x.fields)["names"]) - 1,
                                         Part=dict(x.fields)["names"][0]))})
                    if x.key == "repeat_free" and len(dict(x.fields)["names"]) > 2 else x
                    for x in specs]

        out = counted(free)
        loose = [x for x in out if x.key in ("repeat_free", "repeat_free_one")
                 or x.key.startswith("repeat_mirror")]
        if self.fits_levels(out, headline) or len(loose) < 2:
            return out
        # ... and over it still: the mirrored copies too where the picture shows them, with
        # the others (the train's wheel 5 from the right: 78 words with two mirrored wheels)
        names = sorted({n for x in loose for n in dict(x.fields)["names"]}, key=natural_key)
        at = out.index(loose[0])
        merged = spec("repeat_free", parts=_cap(_join(names)), shape=dict(loose[0].fields)["shape"],
                      names=tuple(names))
        return counted(out[:at] + [merged] + [x for x in out[at:] if x not in loose])

    def fits_levels(self, specs: Sequence[Spec], headline: str) -> bool:
        """Does a step of these sub-steps keep within :data:`MAX_STEP_WORDS` at novice and at
        apprentice (:func:`~h2s_print.instructions.brief_specs`)?"""
        return max(self.step_words(specs, headline),
                   self.step_words(brief_specs(specs, self.brief_where), headline)
                   ) <= MAX_STEP_WORDS

    def lined_up(self, positions: Sequence[tuple[str, Any]]) -> list[str]:
        """:meth:`free_positions` in a master's ratio words ("its back in line with the
        base's back")."""
        return [_ratio_words(self.words, a, self.say(q)) for q, a in positions]

    def parents_of(self, part: str) -> set[str]:
        """The parts ``part``'s selected candidate hangs off."""
        return {self.by_id[pid].part for pid in self.chosen[part].parents}

    def guided_parts(self) -> tuple[list[list[str]], set[str]]:
        """The guided tutorial's parts: repeat groups in drawing order (:meth:`repeat_groups`)
        and the set of parts kept (module docstring, *Left out*).

        A hidden part stays only when a kept part's construction is drawn from it: the first
        part of a group is constructed from its parents, a copy only when its sentence places
        it by them (:meth:`copy_places`); a copy drawn "where the picture shows it" needs none.
        Leaving a part out changes the groups, so this runs to a fixed point (every part a kept
        part is drawn from is kept, and nothing else hidden), starting from every ancestor of a
        visible part; without one within a round per part, every ancestor is kept (valid: no
        part is drawn from a part left out, though a hidden one may be drawn for nothing).
        """
        if self._parts is not None:
            return self._parts
        names = [p.name for p in self.plan.model.parts]
        # a part showing under BARELY_MM of line (the train's coupling behind its engine: a
        # sliver 0.6 mm wide) counts as hidden here: it gets no construction of its own, only
        # its lines in the outline steps (:meth:`traced_only`); not a copy of a part that
        # shows more (a copy costs one sentence in its first's step: the plate's dowels)
        finals = self.finals(self.adjusted)
        shown = self.visible(self.adjusted)
        boxes = {p: self.chosen[p].box for p in names}
        clear = {p for p in shown if _ink_mm(finals[p]) >= BARELY_MM}
        visible = clear | {p for p in shown - clear if _ink_mm(finals[p]) >= TINY_LOOP_MM
                           and any(self.congruent(p, q, boxes) for q in sorted(clear))}
        everything = self.closure(visible, {p: self.parents_of(p) for p in names})
        keep = everything
        for _ in range(len(names) + 1):
            groups = self.groups_of(keep, visible)
            uses = self.uses(groups, keep)
            need = self.closure(visible, uses)
            if need == keep:
                break
            keep = need
        else:
            keep = everything
            groups = self.groups_of(keep, visible)
            uses = self.uses(groups, keep)
        left_out = sorted(set(names) - keep)
        if left_out:
            log.info("left out (hidden or barely seen, anchoring nothing visible): %s",
                     ", ".join(left_out))
        for part in sorted(keep - visible):
            users = sorted(q for q in keep if part in uses.get(q, ()))
            log.info("kept though hidden: %s (anchors %s)", part, ", ".join(users) or "nothing")
        self._parts = (groups, keep)
        return self._parts

    def traced_only(self) -> list[str]:
        """Parts left out of the constructions that still show some line: traced in the
        outline steps only, so that the steps add up to the finished drawing."""
        keep = self.guided_parts()[1]
        finals = self.finals(self.adjusted)
        out = sorted(p for p in self.visible(self.adjusted) if p not in keep)
        for p in out:
            log.info("traced only (%.1f mm of line on the sheet): %s", _ink_mm(finals[p]), p)
        return out

    def uses(self, groups: Sequence[Sequence[str]], keep: set[str]) -> dict[str, set[str]]:
        """Per part, the parts its construction is drawn from (:meth:`guided_parts`)."""
        uses: dict[str, set[str]] = {}
        for group in groups:
            uses[group[0]] = self.parents_of(group[0])
            placed = self.copy_places(group[1:], keep, group[0])
            for q in group[1:]:
                uses[q] = self.copy_parents(q, group[0]) if placed.get(q) else set()
        return uses

    def groups_of(self, keep: set[str], visible: set[str]) -> list[list[str]]:
        """:meth:`repeat_groups` of the kept parts in :meth:`guided_order`, each group led by a
        part that can be constructed and is seen: when its first part hangs off a part left
        out, or is hidden while a member is not, the first member that is seen, hangs off no
        part left out and off parts drawn before the group leads it instead (the copy of a part
        left out is then the one placed by eye); failing that, a hidden first part is drawn on
        its own before the others (it anchors them)."""
        order = self.guided_order(keep)
        boxes = {p: self.chosen[p].box for p in order}
        parents = {p: self.parents_of(p) & keep for p in order}
        out: list[list[str]] = []
        before: set[str] = set()
        for group in self.repeat_groups(order, boxes, parents):
            head = group[0]
            seen = [q for q in group if q in visible]
            if not self.parents_of(head) <= keep or (head not in visible and seen):
                lead = next((q for q in group[1:] if q in visible
                             and self.parents_of(q) <= before), None)
                if lead is not None:
                    group = [lead] + [q for q in group if q != lead]
                elif head not in visible and seen:
                    out.append([head])
                    before.add(head)
                    group = group[1:]
            out.append(group)
            before.update(group)
        return out

    def say(self, part: str) -> str:
        """What the texts call ``part`` (:func:`h2s_print.names.display_names`)."""
        return self.names[part].label

    def part_labels(self, part: str, box: Box, numbered: bool = False,
                    others: Sequence[Box] = ()) -> tuple[tuple[str, Vec3], ...]:
        """The short name drawn next to a part whose own name is not readable, or (with
        ``numbered``) whose step draws another part named alike but for its number: the
        train's "wheel 1, wheel 3, wheel 5 and wheel 7" left a reader asking which was which
        (else none)."""
        if self.names[part].readable and not numbered:
            return ()
        return ((self.names[part].label, self.label_point(part, box, others)),)

    def label_point(self, part: str, box: Box, others: Sequence[Box] = ()) -> Vec3:
        """Where a part's short name goes: the middle of its box, unless the picture of
        another box (``others``) covers that point on the sheet; then the first point of the
        faces the view shows (their middles, then at a quarter and three quarters across
        them) that no other box covers (the IVAR box's two panels, one behind the other:
        "part 3" stood inside the front panel, "part 2" below it, a read-through read them
        swapped); where every one is covered, the middle."""
        b = np.asarray(box, dtype=float)
        centre = b.mean(axis=0)
        if not others:
            return _vec(centre)
        pts = [centre]
        shown = [f for f in (Face(box, n, e) for n in range(3) for e in ("lo", "hi"))
                 if _front_facing(f, self.camera)]
        shown.sort(key=lambda f: -_polygon_area_mm2(self.camera, f.corners))
        for f in shown:
            u, v = f.in_axes
            for su, sv in ((0.5, 0.5), (0.25, 0.5), (0.75, 0.5), (0.5, 0.25), (0.5, 0.75)):
                p = np.array(centre)
                p[f.normal] = f.coord
                p[u] = b[0][u] + su * (b[1][u] - b[0][u])
                p[v] = b[0][v] + sv * (b[1][v] - b[0][v])
                pts.append(p)
        covered = _covers(np.stack([self.box_picture(other) for other in others]),
                          self.camera.project(np.asarray(pts, dtype=float)))
        free = np.flatnonzero(~covered)
        return _vec(pts[int(free[0])] if len(free) else centre)

    def box_picture(self, box: Box) -> np.ndarray:
        """A box's eight corners projected on the sheet (:func:`_box_corners`' order), mm;
        remembered per box (the part labels of every step ask again for the boxes drawn
        before: gen80's sequence stage spent 0.66 of 3.4 s projecting them)."""
        key = tuple(map(tuple, box))
        got = self._box_pictures.get(key)
        if got is None:
            got = self._box_pictures[key] = np.asarray(
                self.camera.project(_box_corners(box)), dtype=float)
        return got

    def lettered(self, specs: Sequence[Spec]) -> tuple[Spec, ...]:
        """A step's sub-steps, each said once, twins together
        (:func:`h2s_print.instructions.unique_specs`), lines from earlier steps first (so no
        point is used before a sub-step names it); lettered later (:meth:`letter`)."""
        ordered = sorted(specs, key=lambda x: x.key not in ("reuse", "box_reuse"))
        return tuple(_paired(x) for x in self.uncited(unique_specs(ordered, _plural)))

    def uncited(self, specs: Sequence[Spec]) -> list[Spec]:
        """``specs`` without citing a line that a later sub-step of the step names: "Use KL
        from step 2" or "Use the edge KL" before "Carry KL vertically" only repeated KL,
        which the picture shows as used again (issue 11: one sub-step per construction).  A
        citation keeps the lines no later sub-step names."""
        specs = self.centred_cited(specs)
        out: list[Spec] = []
        for i, s in enumerate(specs):
            if s.key in _CITES:
                later = [run.points for x in specs[i + 1:] if x.key not in _CITES
                         for _, v in x.fields if isinstance(v, (Pts, Many))
                         for run in line_runs(v) if len(run.points) == 2]
                f = dict(s.fields)
                runs = line_runs(f["line"])
                left = tuple(r for r in runs if not any(
                    _same_segment(r.points[0], r.points[1], p, q, self.tol) for p, q in later))
                if not left:
                    continue
                if len(left) < len(runs):
                    f["line"] = left[0] if len(left) == 1 else Many(left)
                    key = "edge" if s.key == "edge_two" and len(left) == 1 else s.key
                    if key == "reuse_for":  # the sides were said of all its lines together
                        key = "reuse"
                        f.pop("sides")
                    elif key == "edge_for_two":  # each line's side: said of the lines left
                        each = tuple(e for r, e in zip(runs, f["each"]) if r in left)
                        key = "edge_for" if len(left) == 1 else key
                        f["sides"], f["each"] = _join(each), each
                    s = spec(key, s.same, s.pair, **f)
            out.append(s)
        return out

    def centred_cited(self, specs: Sequence[Spec]) -> list[Spec]:
        """``specs`` with "Centre the part on KL" saying what KL is when an earlier sub-step
        only cites it (:meth:`uncited` then drops that citation): "on the edge KL", "on KL
        from step 3", or "on KL, carried in step 3" for a line only cited among "the lines
        carried in step 3" (a read-through: "Centre part 2 on AB" with AB the base's front
        edge, said nowhere, read as a line to construct)."""
        out = list(specs)
        drop: dict[int, int] = {}  # step -> centring sentences now citing its carried lines
        for j, s in enumerate(out):
            if s.key != "centred":
                continue
            f = dict(s.fields)
            if not isinstance(f["line"], Pts) or len(f["line"].points) != 2:
                continue  # twins said together ("on AB and CD"): left as they are
            a, b = f["line"].points
            for c in out[:j]:
                if c.key not in _CITES:
                    continue
                cf = dict(c.fields)
                if any(_same_segment(a, b, r.points[0], r.points[1], self.tol)
                       for r in line_runs(cf["line"]) if len(r.points) == 2):
                    out[j] = (spec("centred_edge", s.same, s.pair, **f)
                              if c.key in _EDGE_CITES
                              else spec("centred_reuse", s.same, s.pair, step=cf["step"], **f))
                    break
            else:
                # a line carried in one earlier step, which the step cites only among "the
                # lines carried in step 9" (the roller's frame shaft: "Centre the frame shaft
                # on EN"), or "for its middle (front to back)" (the desk's foot: "Centre part
                # 6 on HJ", J lettered nowhere before): said with its step, and the middle
                # it places left to this sentence
                named = any(_same_segment(a, b, r.points[0], r.points[1], self.tol)
                            for x in out[:j] for _, v in x.fields if isinstance(v, (Pts, Many))
                            for r in line_runs(v) if len(r.points) == 2)
                cites = [(x.key.startswith("reuse_carried"), xf["step"], xf.get("mids", ()))
                         for x in specs[:j] if x.key in _MOVED_CITES for xf in (dict(x.fields),)]
                moved = {(c, n) for c, n, _ in cites}
                if len(moved) > 1:
                    # lines carried in several steps: the step whose lines place this middle
                    # (the roller's handle, centred both ways on lines of steps 3 and 4)
                    mid = self.words.side(_raw("directions").index(f["directions"]), "mid")
                    moved = {(c, n) for c, n, mids in cites if mid in mids}
                if not named and len(moved) == 1:  # (its far end is lettered only now)
                    carried, n = next(iter(moved))
                    out[j] = spec("centred_carried" if carried else "centred_extended",
                                  s.same, s.pair, step=n, **f)
                    drop[n] = drop.get(n, 0) + 1
        # a second centring on a line the first said carried: carried too, and said with it
        # (centred_together)
        for j, s in enumerate(out):
            if s.key != "centred" or not isinstance(dict(s.fields)["line"], Pts):
                continue
            f = dict(s.fields)
            first = next((x for x in out[:j] if x.key in ("centred_carried", "centred_extended")
                          and isinstance(dict(x.fields)["line"], Pts)
                          and _same_segment(*dict(x.fields)["line"].points,
                                            *f["line"].points, self.tol)), None)
            if first is not None and len(f["line"].points) == 2:
                n = dict(first.fields)["step"]
                out[j] = spec(first.key, s.same, s.pair, step=n, **f)
                drop[n] = drop.get(n, 0) + 1
        # "Use the lines carried in step 9." says no more than "Centre it on EN, carried in
        # step 9."; "... for its middle (front to back) and bottom." keeps its bottom
        kept: list[Spec] = []
        for x in out:
            if x.key in _MOVED_CITES and dict(x.fields)["step"] in drop:
                if not x.key.endswith("_for"):
                    continue
                xf = dict(x.fields)
                if len(xf["mids"]) > drop[xf["step"]]:  # a middle no sentence centres on
                    kept.append(x)
                    continue
                each = tuple(e for e in xf["each"] if e not in xf["mids"])
                if not each:
                    continue
                x = spec(x.key, x.same, x.pair, **{**xf, "sides": _join(each), "each": each,
                                                   "mids": ()})
            kept.append(x)
        return self.centred_together(kept)

    def centred_together(self, specs: Sequence[Spec]) -> list[Spec]:
        """Two centrings on one line, one sentence: "Centre the handle left to right and
        front to back on QR, carried in step 4." (a read-through: the same line in two
        sentences read as two lines).  Two centrings said alike, in two directions, on two
        lines that cross: where they cross ("Centre the neck where GN and MN cross, both
        carried in step 3." for two sentences of 11 words each: the box's middle in both
        directions is the crossing; issue 11, and a dowel's step 79 words long)."""
        out: list[Spec] = []
        for x in specs:
            prev = out[-1] if out else None
            if (prev is not None and x.key.startswith("centred") and prev.key == x.key):
                pf, xf = dict(prev.fields), dict(x.fields)
                if (isinstance(pf["line"], Pts) and isinstance(xf["line"], Pts)
                        and len(pf["line"].points) == len(xf["line"].points) == 2
                        and pf.get("step") == xf.get("step")
                        and pf["directions"] != xf["directions"]):
                    if _same_segment(*pf["line"].points, *xf["line"].points, self.tol):
                        out[-1] = spec(x.key, prev.same, prev.pair, **{
                            **pf, "directions": _join([pf["directions"], xf["directions"]])})
                        continue
                    if (x.key in _CROSS_CENTRED and pf["part"] == xf["part"]
                            and _segments_cross(*pf["line"].points, *xf["line"].points,
                                                self.tol)):
                        out[-1] = spec(_CROSS_CENTRED[x.key], prev.same + x.same, prev.pair,
                                       **{k: v for k, v in pf.items() if k != "directions"},
                                       other=xf["line"])
                        continue
            out.append(x)
        return out

    def letter(self, drafts: Sequence[_Draft], roles: frozenset[str] = LEVEL_ROLES["novice"]
               ) -> list[_Draft]:
        """The drafts with their sub-steps formatted and their points lettered, the whole
        tutorial at once (:func:`h2s_print.instructions.letter_steps`), for a level that
        shows lines of ``roles``."""
        # a line is drawn from the first step that uses it to the last (the guides' lifetime):
        # its ends stay on the paper that long
        last: dict[tuple, tuple[int, Vec3, Vec3]] = {}  # by line: its last step, its ends
        for k, d in enumerate(drafts):
            for ln in d.lines:
                if ln.role not in roles:
                    continue
                last[points_key((ln.start, ln.end), self.tol)] = (k, ln.start, ln.end)
        drawn = [(a, b, k) for k, a, b in last.values()]  # every point on them, ends too
        # the sheet's floor line's ends, kept while a step stands a part on the floor
        on_paper: list[tuple[Vec3, int]] = []
        start, until = _floor_span(drafts)
        if start is not None and until > start:
            lines = _first_lines(drafts[start].strokes, self.camera, self.floor_z(False))
            if lines is not None and lines.floor is not None:
                on_paper += [(p, until) for p in lines.floor]
        drafts = self.cite_earlier(drafts, roles)
        done = letter_steps([d.specs for d in drafts], self.tol, _substep, _join, on_paper,
                            drawn)
        return [replace(d, substeps=tuple(subs), labels=tuple(labels))
                for d, (subs, labels) in zip(drafts, done)]

    def cite_earlier(self, drafts: Sequence[_Draft], roles: frozenset[str]) -> list[_Draft]:
        """The drafts with each line a sub-step names but neither draws nor cites, drawn by
        an earlier step, marked with that step where the step has room (:attr:`Pts.step`:
        "Carry MP and XY (step 7) toward ..."; the primer says so; a read-through met lines
        of earlier steps named with no step, where the primer promised one).

        The step is the first that drew the line (of ``roles``, the same two ends: an edge of
        a box drawn on a guide of step 2 is that box's, not step 2's, whose picture shows no
        such points).  Left alone: a sub-step that cites a step itself ("Use KL from step
        2."), one that cites a box's edge ("Put its bottom on the edge AB.": the box is on
        the sheet, not a step's line), the lines a sentence draws (:func:`drawn_fields`),
        and a line the step names again (:meth:`said_lines`: "Draw DV; it crosses CB at K."
        after "Use diagonals CB and DA from step 3.").

        Room: the steps were packed and sized to :data:`MAX_STEP_WORDS` before they had
        numbers; a step the citations would take over it leaves out those of the nearest
        steps, one at a time, until it fits (the page the reader has just turned is the one
        they least need sending back to; the letters are on this step's picture either way).
        Counting the citations while packing instead gave up constructions for them (the
        roller's frame shaft walked to its line in 70 words; with "(step 2)" its turn went
        by eye)."""
        drawn: list[tuple[int, Vec3, Vec3]] = []  # (first step, start, end), steps in order
        seen: set[frozenset] = set()
        for k, d in enumerate(drafts):
            for ln in d.lines:
                key = points_key((ln.start, ln.end), self.tol)
                if ln.role in roles and key not in seen:
                    seen.add(key)
                    drawn.append((k, ln.start, ln.end))

        def first_drawn(run: Pts, k: int) -> int:
            for j, p, q in drawn:
                if j >= k:
                    break
                if _same_segment(*run.points, p, q, self.tol):
                    return j + 1
            return 0

        out: list[_Draft] = []
        for k, d in enumerate(drafts):
            said = self.said_lines(d.specs)
            cites: list[tuple[int, int, str, int]] = []  # (step, spec, field, item)
            for i, x in enumerate(d.specs):
                f = dict(x.fields)
                if "step" in f or _edge_cite(x.key):
                    continue
                skip = drawn_fields(x.key) | {"edge"}  # (an edge extended: a box's)
                for name, v in f.items():
                    if name in skip or not isinstance(v, (Pts, Many)):
                        continue
                    for m, run in enumerate(line_runs(v)):
                        key = points_key(run.points, self.tol)
                        if len(run.points) != 2 or run.step or key in said:
                            continue
                        said.add(key)  # cited once a step
                        n = first_drawn(run, k)
                        if n:
                            cites.append((n, i, name, m))

            def with_cites(kept: list[tuple[int, int, str, int]]) -> tuple[Spec, ...]:
                at = {(i, name, m): n for n, i, name, m in kept}
                specs = list(d.specs)
                for i in sorted({c[1] for c in kept}):
                    x = specs[i]
                    f = dict(x.fields)
                    for name in sorted({c[2] for c in kept if c[1] == i}):
                        v = f[name]
                        runs = tuple(replace(r, step=at.get((i, name, m), 0))
                                     for m, r in enumerate(line_runs(v)))
                        f[name] = runs[0] if isinstance(v, Pts) else Many(runs)
                    specs[i] = spec(x.key, x.same, x.pair, **f)
                return tuple(specs)

            # farthest back first: the ones kept longest where the step has no room for all
            cites.sort(key=lambda c: (c[0], c[1], c[3]))
            while cites and self.step_words(with_cites(cites), d.headline) > max(
                    MAX_STEP_WORDS, self.step_words(d.specs, d.headline)):
                cites.pop()
            out.append(replace(d, specs=with_cites(cites)) if cites else d)
        return out

    def primitive_drafts(self, part: str, first: bool, step: int = 0,
                         described: list[tuple[Vec3, Vec3, int]] | None = None,
                         drawn: Sequence[str] = (), repeat: Sequence[Spec] = (),
                         copies_of: Sequence[str] = ()) -> list[_Draft]:
        """:meth:`drafts_of` the part, with carries that would turn by eye walked
        (:meth:`walk_carries`) unless that makes a step too long for :data:`MAX_STEP_WORDS`
        (a walk says more, and a guides step is not cut: the mixer's head, high-right, 73
        words): then as before, the turns by eye."""
        mark, boxes = len(described or ()), dict(self._box_steps)
        self._walked = False
        made = self.drafts_of(part, first, step, described, drawn, repeat, copies_of)
        if self._walked and any(self.step_words(list(d.specs), d.headline) > MAX_STEP_WORDS
                                for d in made if d.kind in ("guides", "primitive")):
            if described is not None:
                del described[mark:]
            self._box_steps.clear()
            self._box_steps.update(boxes)
            made = self.drafts_of(part, first, step, described, drawn, repeat, copies_of,
                                  walk=False)
        return made

    def drafts_of(self, part: str, first: bool, step: int = 0,
                  described: list[tuple[Vec3, Vec3, int]] | None = None,
                  drawn: Sequence[str] = (), repeat: Sequence[Spec] = (),
                  copies_of: Sequence[str] = (), walk: bool = True) -> list[_Draft]:
        """The primitive step of ``part`` (step number ``step``), preceded by guides steps when
        its sub-steps would not fit :data:`MAX_STEP_WORDS` (module docstring, *Text*);
        ``repeat`` are the sub-steps drawing its copies ``copies_of`` (identical parts), said
        last."""
        cand = self.chosen[part]
        prim = self.plan.primitive(part)
        words = self.words
        strokes = self.scaffold(part)
        shape = words.shape(prim.type)
        taper = self.taper_specs(part)  # the box's taper: before it is drawn on its lines
        copies = list(repeat)
        repeat = [*taper, *copies]  # by eye: after its position and sizes, before any copies
        name = self.say(part)
        # said of the first round part only: once read, a round part drawn as a box needs no
        # note (a read-through: "Ellipses come later" in every such headline said nothing)
        note = (_raw("headline.cylinder_note") if _round(prim)
                and not any(_round(self.plan.primitive(q)) for q in drawn) else "")
        if first:
            subs = self.lettered([*_first_specs(_first_lines(strokes, self.camera,
                                                             self.floor_z(False))),
                                  *repeat])
            return [_Draft(part, "primitive", False, (), strokes,
                           _t("headline.first", Part=_cap(name), shape=shape) + note, subs)]
        if not cand.anchors:  # free: say what it touches among the parts drawn so far
            near = [q for q in _touching(part, self.chosen, 100.0 * self.tol) if q in drawn]
            near.sort(key=lambda q: -part_size(self.chosen[q].box))
            positions = self.free_positions(part, drawn)
            where = self.free_specs(positions)
            # a side standing on a line from the floor line's foot: the line places it, and
            # says so instead of lining it up in words (the train's wheels' backs)
            floor = self.floor_size(part, drawn)
            side = self.floor_side(part, drawn, copies_of)
            if side is not None and floor and floor[0][0].key in ("floor_side",
                                                                  "floor_side_through"):
                said_by_line = [(q, a) for q, a in positions
                                if (a.axis, a.end) != side[2] or a.axis == 2]
                where = self.free_specs(said_by_line) + [side[0]]
                floor = []
                # copies placed by the picture whose side is on the line too: said so (the
                # line runs under them all: the train's wheels)
                if (side[3] and len(copies) == 1
                        and copies[0].key in ("repeat_free", "repeat_free_one")):
                    f = dict(copies[0].fields)
                    copies = [spec(copies[0].key.replace("free", "floor"), parts=f["parts"],
                                   shape=f["shape"], line=dict(side[0].fields)["line"])]
                    repeat = [*taper, *copies]
            # a master reads where it lines up too (a read-through: by eye, and nothing said)
            lined_up = _join(self.lined_up(positions))
            refs = near + sorted((q for q in drawn if q not in near),
                                 key=lambda q: (-part_size(self.chosen[q].box), q))
            head = _t("headline.free", Part=_cap(name), shape=shape) + note

            def free(sizes: list[tuple[Spec, list[int]]]) -> list[Spec]:
                # with sizes said, "compare their sizes" is said by them
                placing = (spec("free_near_sized" if sizes else "free_near",
                                other=self.say(near[0])) if near else spec("free"))
                return [placing, *where, *(x for x, _ in sizes), *repeat]

            loose = self.loose_axes(cand)
            subs = self.lettered(self.copies_pictured(self.sized(
                head, free, floor + self.size_specs(part, loose, refs), part, loose), head))
            return [_Draft(part, "primitive", False, tuple(self.floor_side_lines(subs)), strokes,
                           head, subs, _cap(lined_up) + "." if lined_up else "")]
        built: list[tuple[Any, str, Face, Any, list[_Line], list[_Line]]] = []
        # a part on the floor whose top no anchor places: a carry down to it turns on the
        # floor, found from the floor line's foot (geometry._turn_plane)
        foot = (None if any(a.axis == 2 and a.end == "hi" for a in cand.anchors)
                else self.floor_foot(part, drawn))
        floor_z = None if foot is None else float(cand.box[0][2])
        flat: list[Spec] = []
        # parent -> (side, face name, axis, flush, anchor)
        on_faces: dict[str, list[tuple[str, str, int, bool, Any]]] = {}
        reused_for: dict[tuple[Vec3, Vec3], str] = {}  # a line reused: the side it places
        contact_of: dict[Spec, list[Any]] = {}  # a sentence placing sides on faces: anchors
        faces: dict[tuple[str, int, str], tuple[Face, list[_Line]]] = {}
        for ai, anchor in enumerate(cand.anchors):
            parent = self.by_id[anchor.parent]
            if anchor.face_normal == anchor.axis:
                flat.append(spec("flat", side=words.side(anchor.axis, anchor.end),
                                 parent=self.say(parent.part)))
                continue
            if _on_face(anchor, parent.box, cand.box, self.tol):  # the face itself is the guide
                pend = "lo" if anchor.ratio < 0.5 else "hi"
                on_faces.setdefault(parent.part, []).append(
                    (words.side(anchor.axis, anchor.end), words.face(anchor.axis, pend),
                     anchor.axis, anchor.end == pend, anchor))
                continue
            face, con, own, carry = self.anchor_lines(cand, ai, floor_z, foot)
            if floor_z is not None and self.floor_leg(carry, floor_z, foot) is None:
                # turning on the floor only where a line from its foot reaches the turn
                face, con, own, carry = self.anchor_lines(cand, ai)
            if carry and sum(_sheet_length(self.camera, ln) for ln in carry) < TINY_CARRY_MM:
                carry = []  # (the chair's seat: "Extend QR as pictured" by nothing visible)
            if entry_for(anchor.ratio).needs_room:  # an edge extended needs no room on the face
                faces.setdefault((anchor.parent, face.normal, face.end), (face, []))[1].extend(own)
            built.append((anchor, parent.part, face, con, own, carry))
        # two centring lines off one parent that would not meet where they turn (one turned
        # by eye where the part's face will be: the roller's handle, high-right), made to
        # cross on the parent's face toward the part (geometry._meeting_carries)
        meeting: tuple[int, int, _Meeting] | None = None
        mids = [k for k, (an, _, _, _, _, c) in enumerate(built) if an.end == "mid" and c]
        if len(mids) == 2 and built[mids[0]][0].parent == built[mids[1]][0].parent:
            i, j = mids
            got = _meeting_carries((built[i][3], built[j][3]), (built[i][2], built[j][2]),
                                   _drawn_box(self.plan.primitive(part), cand.box),
                                   self.camera, 10.0 * self.tol)
            if got is not None:
                meeting = (i, j, got)
                for k, c in zip((i, j), got.carries):
                    built[k] = built[k][:5] + (list(c),)
        for ppart, pairs in on_faces.items():  # said once per parent
            # a flat rectangle's "face" across its plane is an edge (a read-through: "lie on
            # part 1's right, left and bottom faces" of the IVAR box's flat base), and its
            # face along its plane is the rectangle itself ("Its bottom lies on part 1.", not
            # "on part 1's bottom face": a rectangle has no bottom face to find)
            # A box's face on the parent's face of the same side (flush: the oven's door's
            # sides with the body's) is in line with it, not on it (a read-through: "lie on
            # the base body's right face", a face hidden behind the body)
            pprim = self.plan.primitive(ppart)
            edge_axis = pprim.axis if pprim.type == "plane" else None
            for kind in ("on_edge", "on_plane", "in_line_face", "on_face"):
                some = [(sd, nm, an, flush) for sd, nm, ax, flush, an in pairs
                        if kind == ("on_plane" if ax == edge_axis
                                    else "on_edge" if edge_axis is not None
                                    else "in_line_face" if flush else "on_face")]
                if not some:
                    continue
                sides, names, anchors, flushes = zip(*some)
                key = kind + ("" if len(some) == 1 else "s")
                if key == "on_edges" and all(flushes):  # each side at its namesake edge: "Line
                    key = "in_line_faces"  # up its right side and left side with part 1's."
                flat.append(spec(key, sides=_join(sides), parent=self.say(ppart),
                                 faces=_join(names)))
                contact_of[flat[-1]] = list(anchors)
        # the one face of a drawn part it lies on, said in the headline ("Lens: a box in front
        # of the body's front face.", not "from the body" and "Its back lies on the body's front
        # face.": the sentence's words went to the sizes it had no room for, the lens's
        # "Make its height the same as its width", a read-through); a master's ratio words
        # then leave it out too ("its back in line with the body's front")
        lies_on = [x for x in flat if x.key == "on_face"]
        lies = dict(lies_on[0].fields) if len(lies_on) == 1 else None
        contact = contact_of[lies_on[0]] if lies is not None else []
        if lies is not None:
            flat.remove(lies_on[0])
        eyeball = False
        for face, own in faces.values():
            k = len(_distinct(own, self.tol))
            if k and _too_small(self.camera, face.corners, k, self.settings.eyeball_mm2):
                eyeball = True
        loose = self.loose_axes(cand)
        # its bottom on the floor, found from the floor line's foot (its height is then
        # constructed, not judged)
        floor = None if eyeball else self.floor_unit(part, drawn)
        if floor is None and not eyeball:  # ... or the middle of its bottom, under the point
            # where its centring lines meet on the first box's bottom face (the roller's handle)
            meets = [c[0].end for anchor, _, _, _, _, c in built
                     if anchor.end == "mid" and anchor.axis in (0, 1) and len(c) >= 2]
            if len(meets) == 2 and _same_point(meets[0], meets[1], 10.0 * self.tol):
                floor = self.floor_middle_unit(part, drawn, meets[0], [
                    (ln.start, ln.end) for *_, c in built for ln in c])
        if floor is not None:
            loose = [a for a in loose if a != 2]
        # sizes judged by eye: compared with the parts it hangs off, then those it touches
        refs = _unique([self.by_id[a.parent].part for a in cand.anchors]
                       + [q for q in _touching(part, self.chosen, 100.0 * self.tol)
                          if q in drawn])
        # a centring line carried down to the floor under it (geometry._turn_plane): its
        # bottom stands there, not "judge where by eye" (the desk's feet)
        on_line = next((Pts((c[-1].start, c[-1].end)) for *_, c in built
                        if floor_z is not None and len(c) >= 2
                        and all(abs(q[2] - floor_z) <= 10.0 * self.tol
                                for q in (c[-1].start, c[-1].end))), None)
        standing = self.floor_size(part, drawn)
        if on_line is not None and standing:
            standing = [(spec("on_floor_line", line=on_line), standing[0][1])]
        sizes = ([] if floor is not None else standing) \
            + self.size_specs(part, loose, refs)

        def by_eye(chosen: list[tuple[Spec, list[int]]]) -> tuple[list[Spec], str]:
            """The size sentences chosen, and the sizes left to the eye."""
            done = {a for _, group in chosen for a in group}
            return [x for x, _ in chosen], _join([words.dim(a) for a in loose if a not in done])
        parents = _join([_the(x) for x in _unique(self.parent_name(a) for a in cand.anchors)])
        # what the anchors place, then what the part lines up with on an axis none places
        # (a master read nothing of the shutter button's "Centre it front to back")
        unguided = self.free_positions(part, drawn, cand.unguided_axes)
        # (a part placed by eye has a headline that names no face: all its anchors said)
        phrases = (_ratio_phrases(words, [a for a in cand.anchors if eyeball or a not in contact],
                                  self.parent_name)
                   + self.lined_up(unguided))

        def summed(head: str) -> str:
            # a master's ratio words after ``head``; where the step would pass the limit, the
            # longest said as pictured ("..., and the rest as pictured.": generated
            # assemblies' parts placed off three parts, 72-73 words)
            def text(kept: list[str]) -> str:
                said = _join(kept + ([_t("ratio_words.rest")] if len(kept) < len(phrases)
                                     else []))
                return _cap(said) + "." if said else ""  # (a master read "front face. .")

            return text(_fewest_longest(
                phrases, lambda kept: len(f"{head} {text(kept)}".split()) <= MAX_STEP_WORDS, 1))
        if eyeball:
            positions = _positions(words, cand.anchors, self.parent_name, True)
            head = _t("headline.eyeball", Part=_cap(name), shape=shape) + note

            def placed(kept: list[str]) -> Callable[[list[tuple[Spec, list[int]]]], list[Spec]]:
                specs = [spec("position", position=x) for x in kept] + (
                    [spec("position_rest")] if len(kept) < len(positions) else [])

                def eyeballed(chosen: list[tuple[Spec, list[int]]]) -> list[Spec]:
                    said, dims = by_eye(chosen)
                    return (specs + said + ([spec("by_eye", dims=dims)] if dims else [])
                            + list(repeat))
                return eyeballed

            # a part placed by eye with more positions than a step has words for (the mixer's
            # bowl from the side, six in 93 words; generated assemblies): the longest said as
            # pictured until the step fits (issue 11: no step over 70 words)
            def made(kept: list[str]) -> list[Spec]:
                return self.copies_pictured(self.sized(head, placed(kept), sizes, part, loose),
                                            head)

            subs = self.lettered(made(_fewest_longest(
                positions, lambda kept: self.fits_levels(made(kept), head), 0)))
            return [_Draft(part, "primitive", True, tuple(self.floor_side_lines(subs)), strokes,
                           head, subs, summed(head))]
        # Units of construction, one per parent face (lines shared on a face stay together).
        units: dict[tuple[str, int, str], _Unit] = {}
        earlier = [] if described is None else described
        boxed: set[str] = set()
        known: list[tuple[Vec3, Vec3]] = []  # lines reused from earlier steps
        carried: dict[tuple[int, int | None], list[Pts]] = {}  # by (first axis, turn)
        ends: dict[tuple[int, int | None], list[Pts | None]] = {}  # each run's end, if one
        corners: dict[tuple[int, int | None], list[Pts]] = {}  # where those turn, in order
        # which way each carry moves (first leg, turning leg: 3D start and end), for "toward"
        # or "away from" its vanishing point (_Words.vp)
        legs: dict[tuple[int, int | None], tuple[tuple[Vec3, Vec3], ...]] = {}
        # carries that turn where the part's own face will be, a face no anchor places: the
        # turn is judged by eye (both read-throughs: "to Q" where nothing defined Q)
        by_eye_turns: set[tuple[int, int | None]] = set()
        # carries that turn on the floor: the lines along it from the floor line's foot
        floor_legs: dict[tuple[int, int | None], list[tuple[Vec3, Vec3]]] = {}
        turns: list[tuple[tuple[int, int | None], Vec3, tuple[_Line, ...]]] = []
        # per carry (axis, turn): its lines and the anchors they place
        by_group: dict[tuple[int, int | None], tuple[list[_Line], list[Any]]] = {}
        carry_lines: list[_Line] = []
        carried_anchors: list[Any] = []  # the anchors whose lines are carried to the part
        run_for: list[tuple[Vec3, Vec3, Any]] = []  # each carried line and an anchor it places
        # a line that would turn by eye, crossed in its face's plane by a centring line of the
        # part: carried from that crossing to the centre line's carried leg instead (the
        # roller's handle's top: "Extend GF to NP, meeting it at U; from U, draw US toward the
        # left vanishing point, meeting QS at S", where "to R (by eye)" was)
        crossings: dict[int, _Crossing] = {}
        for k, (anchor, _, face, con, _, carry) in enumerate(built):
            if anchor.end == "mid" or len(carry) != 2:
                continue
            for m_anchor, _, m_face, m_con, _, m_carry in built:
                if m_anchor.end != "mid" or m_anchor.parent != anchor.parent:
                    continue
                got = _crossing_carry(con, face, carry, m_con, m_face, m_carry, 10.0 * self.tol)
                if got is not None:
                    crossings[k] = got
                    break
        # carries that would turn by eye, walked along lines drawn before instead
        # (geometry._walk_carry: the camera's flash)
        self._merged, self._far = {}, set()
        walked = (self.walk_carries(part, cand, built, {*crossings, *(meeting or ())[:2]},
                                    drawn, floor_z, foot, earlier) if walk else {})
        self._walked = bool(walked or self._merged)
        seconds: dict[tuple[int, int | None], list[Pts]] = {}  # a walk's second turns
        lasts: dict[tuple[int, int | None], tuple[Vec3, Vec3]] = {}  # and its last leg
        walked_keys: set[tuple[int, int | None]] = set()
        starts: dict[tuple[int, int | None], list[Pts]] = {}  # walks from the farther end
        walk_boxes: dict[tuple[int, int | None], list[str]] = {}  # boxes they turn on
        walk_lines: dict[tuple[int, int | None], list[tuple[Vec3, Vec3, int]]] = {}  # lines
        crossed: list[tuple[Spec, list[_Line], Any]] = []  # (sentence, its lines, anchor)
        for k, (anchor, ppart, face, con, own, carry) in enumerate(built):
            unit = units.setdefault((anchor.parent, face.normal, face.end,
                                     points_key((con.result.start, con.result.end), self.tol)),
                                    _Unit(ppart))
            unit.anchors.append(anchor)
            around = self.box_around(ppart)
            # constructions on a tapered parent start from its box, where they use it: a
            # point of theirs on an edge of the box that the scaffold does not draw
            if around and ppart not in boxed and self.uses_box(ppart, around, con):
                boxed.add(ppart)
                unit.lines += around
                seen = self._box_steps.get(ppart)
                unit.specs.append(spec("box_around", parent=self.say(ppart)) if seen is None
                                  else spec("box_reuse", parent=self.say(ppart), step=seen))
            a, b = con.result.start, con.result.end
            # drawn before, as a result or as any construction line (the train's boiler sits
            # on FG, the cab's half line: its guides step only said "Use diagonals AC and DB
            # from step 3 ... Use FG from step 3", drawing nothing)
            old = [n for p, q, n in earlier if _same_segment(a, b, p, q, self.tol)] or sorted(
                n for _, _, n in self.drawn_like(a, b) if n < step)
            twice = any(_same_segment(a, b, p, q, self.tol)
                        for u in units.values() for p, q in u.results)
            if twice:  # the same line from another face of the parent: said once
                pass
            elif old and old[0] < step and not entry_for(anchor.ratio).in_line:
                # (an edge of the parent is cited as its edge, not "from step 2" where step 2
                # only extended it: the train's cab read "Use AB and CD from step 2", the
                # engine's edges, which step 2 offered to erase, a read-through)
                unit.specs.append(spec("reuse", ("reuse", old[0], a, b), ("reuse", old[0]),
                                       line=Pts((a, b)), step=old[0]))
                reused_for[a, b] = self.anchor_side(anchor)
                known.append((a, b))
                unit.results.append((a, b))
                unit.origin[len(unit.results) - 1] = old[0]
            else:
                made = construction_specs(con, self.say(ppart), words.face(face.normal, face.end),
                                          words.vp, self.tol, words.dim(con.axis),
                                          (words.side(con.axis, "lo"), words.side(con.axis, "hi")))
                if around and self.uses_box(ppart, around, con):
                    # the face is the box's around the tapered part, larger than the part's
                    # own end (a read-through: "the prism's top face" is the smaller one)
                    made = [replace(x, key="diagonals_box") if x.key == "diagonals"
                            else spec(x.key, x.same, x.pair, box=True, **dict(x.fields))
                            if any(k == "brief" for k, _ in x.fields) else x
                            for x in made]
                unit.specs += made
                unit.room = unit.room or entry_for(anchor.ratio).needs_room
                unit.results.append((a, b))
            unit.lines += own
            if meeting is not None and k in meeting[:2]:
                carried_anchors.append(anchor)  # said once both are built, below
            elif carry and k in crossings:
                x = crossings[k]
                carried_anchors.append(anchor)
                carry_lines += x.lines
                crossed.append((spec(
                    "cross_carry_for" if x.extended else "cross_on_for", part=name,
                    line=Pts(x.centring), other=Pts((con.result.start, con.result.end)),
                    point=Pts((x.at,)), line2=Pts((x.at, x.end)),
                    vp=words.vp(face.normal, x.at, x.end), other2=Pts(x.leg),
                    point2=Pts((x.end,)), sides=self.anchor_side(anchor)),
                    list(x.lines), anchor))
            elif carry and k in self._merged:  # said with another carry's line (walk_carries)
                carried_anchors.append(anchor)
                other = built[self._merged[k]][3].result
                run_for.append((other.start, other.end, anchor))
            elif carry:
                carried_anchors.append(anchor)
                run_for.append((a, b, anchor))
                # (a walk's first leg along the line itself, to a turn on it, draws nothing)
                new_legs = [c for c in carry if k not in walked or not (
                    _on_segment(c.start, a, b, self.tol) and _on_segment(c.end, a, b, self.tol))]
                carry_lines += new_legs
                axes = [_moving_axis(c) for c in carry]
                first = axes[0]
                turn = next((x for x in axes[1:] if x != first), None)  # around a corner
                by_group.setdefault((first, turn), ([], []))[0].extend(new_legs)
                by_group[first, turn][1].append(anchor)
                runs = carried.setdefault((first, turn), [])
                # the first leg, and the first line along the turn
                legs.setdefault((first, turn), ((carry[0].start, carry[0].end),) + tuple(
                    (c.start, c.end) for c, x in zip(carry[1:], axes[1:]) if x == turn)[:1])
                if not any(_same_segment(a, b, r.points[0], r.points[1], self.tol) for r in runs):
                    runs.append(Pts((a, b)))
                    # where a centring line's carry ends (a straight one when it runs one
                    # way): lettered and said, since the part's step names the line by it
                    # ("Centre part 3 on FJ, carried in step 2" after "Carry FG ..., as
                    # pictured", a read-through); the other carried lines it calls "the
                    # lines carried in step 2", and their ends cost no words
                    ends.setdefault((first, turn), []).append(
                        Pts((carry[-1].end,)) if anchor.end == "mid"
                        and (turn is not None or len(carry) == 1) else None)
                    if turn is not None:  # where it turns, lettered on the picture
                        corners.setdefault((first, turn), []).append(Pts((carry[0].end,)))
                    if turn is not None and k in walked:  # it turns where drawn lines cross
                        walked_keys.add((first, turn))
                        if k in self._far:
                            starts.setdefault((first, turn), []).append(Pts((carry[0].start,)))
                        for other in walked[k][0]:
                            if other not in walk_boxes.setdefault((first, turn), []):
                                walk_boxes[first, turn].append(other)
                        for old_line in walked[k][1]:
                            if old_line not in walk_lines.setdefault((first, turn), []):
                                walk_lines[first, turn].append(old_line)
                        if len(carry) > 2:
                            seconds.setdefault((first, turn), []).append(Pts((carry[1].end,)))
                            lasts[first, turn] = (carry[2].start, carry[2].end)
                    elif turn is not None:
                        n = face.normal  # the turn lies on a plane of the part across n
                        placed = _placed_planes(cand.box, cand.anchors, n)
                        leg = (None if floor_z is None or n != 2
                               else self.floor_leg(carry, floor_z, foot))
                        if leg is not None:  # on the floor, where a line from its foot goes
                            placed.append(floor_z)
                            floor_legs.setdefault((first, turn), []).append(leg)
                        if not any(abs(carry[0].end[n] - v) <= 10.0 * self.tol for v in placed):
                            by_eye_turns.add((first, turn))
                        else:
                            turns.append(((first, turn), carry[0].end, tuple(carry)))
        # a turn where an anchor places the part's face, but on no line on the paper, is
        # judged by eye too: nothing drawn shows where to stop (a read-through of stop 27:
        # "Carry VW toward the left vanishing point to B", B on no line); one on a drawn
        # part's edge, a guide of this part's constructions or another carry's leg is where
        # that line is crossed
        if turns:  # (lines every level with guides shows: not construction lines)
            on_paper = ([(ln.start, ln.end) for u in units.values() for ln in u.lines
                         if ln.role != "construction"]
                        + [(s0, s1) for other in drawn for s0, s1 in self.scaffold_ends(other)]
                        + [leg for legs3 in floor_legs.values() for leg in legs3])
            for key, point, _ in turns:
                if key in by_eye_turns:
                    continue
                legs_elsewhere = [(c.start, c.end) for k2, _, legs2 in turns if k2 != key
                                  for c in legs2]
                if not any(_near_segment(point, s0, s1, 20.0 * self.tol)
                           and _on_segment(point, s0, s1, 10.0 * self.tol)
                           for s0, s1 in on_paper + legs_elsewhere):
                    by_eye_turns.add(key)
        for unit in units.values():  # a line reused from an earlier step is not drawn again
            unit.specs = [self.along_edge(self.drawn_before(x, step), drawn)
                          for x in unit.specs if not _draws_known(x, known, self.tol)]
        # A carry that turns a corner (toward a vanishing point to the part's plane, then
        # across to its face) says both directions: the read-through missed the turn when
        # only the first was said.
        # a line that already runs along its carry direction is extended, not carried
        # ("Carry AB to part 4, vertically" where AB is vertical read as nonsense)
        extended = [r for (axis, turn), runs in sorted(carried.items(), key=_carry_key)
                    for r in runs if turn is None and _runs_along(r, axis)]
        carries = [(axis, turn, kept) for (axis, turn), runs in carried.items()
                   if (kept := [r for r in runs if turn is not None
                                or not _runs_along(r, axis)])]

        def moving(key: str, runs: Sequence[Pts], placing: Sequence[Pts] = (),
                   **f: Any) -> Spec:
            """A carry or extension sentence of ``runs``, saying what they (and the lines
            ``placing`` it also moves) place ("Extend VX for its back, as pictured": a
            read-through of the mixer's head could not tell which of three lines was its
            back)."""
            each = [_unique(self.anchor_side(an) for p, q, an in run_for
                            if _same_segment(p, q, r.points[0], r.points[1], self.tol))
                    for r in [*runs, *placing]]
            if len(each) == 1 and each[0] or (all(len(e) == 1 for e in each)
                                              and len({e[0] for e in each}) == len(each)):
                # one line, or one side a line: the sides in the lines' order ("Extend AB
                # and CD for its left side and back")
                return spec(key + "_for", lines=Many(tuple(runs)), part=name,
                            sides=_join([e[0] for e in each]), **f)
            if any(each):  # else each line with its own (the train's roof: "Extend QR, FD,
                # SR and TB for its right side, left side, back, front and bottom" paired
                # four lines with five sides, a read-through)
                said = [Pts(r.points, _join(e)) for r, e in zip([*runs, *placing], each)]
                f = {k: Many(tuple(said[len(runs):])) if k == "lines2" else v
                     for k, v in f.items()}
                return spec(key, lines=Many(tuple(said[:len(runs)])), part=name, **f)
            return spec(key, lines=Many(tuple(runs)), part=name, **f)

        if len(carries) == 2 and carries[0][1] is None and carries[1][1] is None:
            (a0, _, r0), (a1, _, r1) = carries  # two directions: one sentence
            e0, e1 = legs[a0, None][0][1], legs[a1, None][0][1]
            if len(r0) == len(r1) == 1 and _same_point(e0, e1, 10.0 * self.tol):
                # both end where they cross (a part centred both ways on the face it stands
                # on: the bottle's neck), a point, not "as pictured"
                carrying = [moving("carry_two_meet", r0, r1, vp=words.vp(a0, *legs[a0, None][0]),
                                   lines2=Many(tuple(r1)),
                                   vp2=words.vp(a1, *legs[a1, None][0]),
                                   turns=Many((Pts((e0,)),)))]
            else:
                carrying = [moving("carry_two", r0, r1, vp=words.vp(a0, *legs[a0, None][0]),
                                   lines2=Many(tuple(r1)),
                                   vp2=words.vp(a1, *legs[a1, None][0]))]
            pieces = [[(a0, None), (a1, None)]]
        else:
            # two lines carried from two sides to one turn, where they cross (the roller's
            # handle: its two centring lines meet on the roller's common bisector planes):
            # one sentence, the crossing said once ("Carry FG ... to Q" then "LM ... to Q" had
            # the reader look for Q before the second line made it)
            meet: dict[tuple[int, int | None], tuple[int, int | None]] = {}
            for i, (ax0, t0, r0) in enumerate(carries):
                for ax1, t1, r1 in carries[i + 1:]:
                    if (t0 is not None and t0 == t1 and ax0 != ax1 and len(r0) == len(r1) == 1
                            and (ax0, t0) not in meet and (ax1, t1) not in meet
                            and (ax0, t0) not in by_eye_turns and (ax1, t1) not in by_eye_turns
                            and _same_point(corners[ax0, t0][0].points[0],
                                            corners[ax1, t1][0].points[0], 10.0 * self.tol)):
                        meet[ax0, t0], meet[ax1, t1] = (ax1, t1), (ax0, t0)
            carrying = []
            pieces = []  # per sentence, the carries (first axis, turn) it says
            for axis, turn, runs in carries:
                if turn is None:
                    at = [e for r, e in zip(carried[axis, turn], ends[axis, turn]) if r in runs]
                    vp = words.vp(axis, *legs[axis, turn][0])
                    carrying.append(moving("carry_to", runs, vp=vp, points=Many(tuple(at)))
                                    if all(at) else moving("carry", runs, vp=vp))
                    pieces.append([(axis, turn)])
                elif (axis, turn) in meet:
                    other = meet[axis, turn]
                    if other < (axis, turn):
                        continue  # said with the other
                    pieces.append([(axis, turn), other])
                    r1 = carried[other]
                    # which face of the parent they cross on (from both ends of a line on
                    # its faces they would cross on two: a read-through took the top one),
                    # and the line on from the crossing, named ("then vertically" stopped at
                    # a point said only later)
                    q = corners[axis, turn][0].points[0]
                    k = 3 - axis - other[0]  # both first legs run on a face across k
                    parent = self.by_id[by_group[axis, turn][1][0].parent]
                    lo, hi = parent.box
                    end = ("lo" if abs(q[k] - lo[k]) <= 10.0 * self.tol
                           else "hi" if abs(q[k] - hi[k]) <= 10.0 * self.tol else None)
                    inside = all(lo[b] - 10.0 * self.tol <= q[b] <= hi[b] + 10.0 * self.tol
                                 for b in (axis, other[0]))
                    on = ({"the_parent": _the(self.say(parent.part)),
                           "face": words.face(k, end)} if end is not None and inside else {})
                    # (what they place, the part's middles, its centring sentences say)
                    carrying.append(_unsaid(moving(
                        "carry_meet_on" if on else "carry_meet", runs, r1,
                        vp=words.vp(axis, *legs[axis, turn][0]),
                        lines2=Many(tuple(r1)), vp2=words.vp(other[0], *legs[other][0]),
                        vp3=words.vp(turn, *legs[axis, turn][-1]),
                        turns=Many(tuple(corners[axis, turn])),
                        line=Pts(legs[axis, turn][-1]), **on)))
                else:
                    pieces.append([(axis, turn)])
                    at = [e for r, e in zip(carried[axis, turn], ends[axis, turn]) if r in runs]
                    key = "carry_turn_eye" if (axis, turn) in by_eye_turns else "carry_turn"
                    to = {"points": Many(tuple(at))} if all(at) else {}
                    if (axis, turn) in seconds:  # a walk that turns twice
                        last = lasts[axis, turn]
                        to = dict(to, turns2=Many(tuple(seconds[axis, turn])),
                                  vp3=words.vp(_moving_axis(_Line("", *last)), *last))
                        key = "carry_walk"
                    if (axis, turn) in walked_keys and all(_runs_along(r, axis) for r in runs):
                        # its first leg along the line: extended to the turn, or carried from
                        # it where the turn is on the line drawn (where a drawn line crosses)
                        on = [_on_segment(c.points[0], *r.points, 10.0 * self.tol)
                              for r, c in zip(runs, corners[axis, turn])]
                        key = (("carry_from_walk" if key == "carry_walk" else "carry_from")
                               if all(on) else "extend" + key[len("carry"):])
                        # ... and the line drawn that crosses it there, said (a read-through:
                        # "Carry XY from V' ..." where nothing said V' is where G'K' crosses)
                        crossing = self.crossing_lines(
                            runs, corners[axis, turn], units, drawn,
                            walk_lines.get((axis, turn), []), walk_boxes.get((axis, turn), []))
                        if all(on) and crossing is not None:
                            key = key.replace("carry_from", "carry_on")
                            to = dict(to, others=crossing)
                    elif (axis, turn) in starts and key == "carry_turn":  # said where it starts
                        to = dict(to, turns2=Many(tuple(corners[axis, turn])),
                                  vp3=words.vp(turn, *legs[axis, turn][-1]))
                        carrying.append(moving(
                            "carry_from_walk_to" if "points" in to else "carry_from_walk", runs,
                            vp2=words.vp(axis, *legs[axis, turn][0]),
                            turns=Many(tuple(starts[axis, turn])), **to))
                        continue
                    carrying.append(moving(
                        key + "_to" if "points" in to else key, runs,
                        vp=words.vp(axis, *legs[axis, turn][0]),
                        vp2=words.vp(turn, *legs[axis, turn][-1]),
                        turns=Many(tuple(corners[axis, turn])), **to))
        if extended:
            carrying.append(moving("extend_to", extended))
        # each sentence's lines and the anchors they place (a line extended along itself is
        # the extension sentence's, after the carries': "Extend K''A'' for its right side")
        def along_extended(ln: _Line) -> bool:
            return any(_on_line(ln.start, *r.points, self.tol)
                       and _on_line(ln.end, *r.points, self.tol) for r in extended)

        said_by = [([ln for g in keys for ln in by_group[g][0]
                     if g[1] is not None or not along_extended(ln)],
                    [a for g in keys for a in by_group[g][1]]) for keys in pieces]
        if extended:
            said_by.append((
                [ln for g in by_group if g[1] is None for ln in by_group[g][0]
                 if along_extended(ln)],
                [anc for a, b, anc in run_for if any(
                    _same_segment(a, b, *r.points, self.tol) for r in extended)]))
        if meeting is not None:  # the carry without a stop first: "Carry FG ... and LM ...
            i, j, got = meeting  # to S on the roller's bottom edge, then ..."
            plain, stopped = ((j, i) if got.stopped == 0 else (i, j))
            go, gs = got.carries[plain == j], got.carries[stopped == j]
            ppart = built[i][1]
            res = [(built[k][3].result.start, built[k][3].result.end) for k in (plain, stopped)]
            slide = _moving_axis(gs[1])
            x = spec("carry_meet_edge", lines=Many((Pts(res[0]),)),
                     vp=words.vp(_moving_axis(go[0]), go[0].start, go[0].end),
                     lines2=Many((Pts(res[1]),)),
                     vp2=words.vp(_moving_axis(gs[0]), gs[0].start, gs[0].end),
                     point=Pts((got.stop,)), vp4=words.vp(slide, gs[1].start, gs[1].end),
                     turns=Many((Pts((got.at,)),)), line=Pts((got.at, got.end)),
                     vp3=words.vp(got.plane[0], got.at, got.end),
                     the_parent=_the(self.say(ppart)), face=words.face(*got.plane))
            lines = _distinct(list(go) + list(gs), self.tol)
            carry_lines += lines
            carrying.append(x)
            said_by.append((lines, [built[i][0], built[j][0]]))
        carrying += [x for x, _, _ in crossed]  # after the carries: the line they meet first
        said_by += [(lines, [anchor]) for _, lines, anchor in crossed]
        # per sentence, its specs: a carry that turns on the floor after the line along the
        # floor from the floor line's foot to where it turns (one line each way it runs)
        sentences = [[x] for x in carrying]
        for i, keys in enumerate(pieces):  # a walk turning on a box drawn before: drawn again
            for other in [o for key in keys for o in walk_boxes.get(key, ())]:
                around = self.box_around(other)
                sentences[i].insert(0, spec("box_reuse", parent=self.say(other),
                                            step=self._box_steps[other]))
                said_by[i][0].extend(around)
                carry_lines += around
            for a, b, n in [x for key in keys for x in walk_lines.get(key, ())]:
                sentences[i].insert(0, spec("reuse", line=Pts((a, b)), step=n))
                said_by[i][0].append(_Line("guide", a, b))
                carry_lines.append(_Line("guide", a, b))
        for i, keys in enumerate(pieces):
            for key in keys:
                if key not in floor_legs or key in by_eye_turns:
                    continue
                longest: dict[int, tuple[Vec3, Vec3]] = {}
                for a, b in floor_legs[key]:
                    ax = 0 if abs(b[0] - a[0]) > abs(b[1] - a[1]) else 1
                    if ax not in longest or math.dist(a, b) > math.dist(*longest[ax]):
                        longest[ax] = (a, b)
                for ax in sorted(longest):
                    a, b = longest[ax]
                    sentences[i].insert(-1, spec("floor_line", line=Pts((a, b)),
                                                 point=Pts((a,)), vp=words.vp(ax, a, b)))
                    said_by[i][0].append(_Line("vanishing", a, b))
                    carry_lines.append(_Line("vanishing", a, b))
        carrying = [x for group in sentences for x in group]
        carry_units: list[_Unit] = []
        if carrying:  # carrying lines needs no room: it stays with the part unless too long
            owner = self.by_id[cand.anchors[0].parent].part
            carry_units = [_Unit(owner, carrying, carry_lines, carried_for=carried_anchors)]
            # a carry sentence each, each a unit, when all of them are too long for one
            # step (a guides step over the word limit cannot be cut: the train's chimney
            # carried three lines around corners in 71 words; a generated assembly's part
            # four lines and an extension in 79)
            if (len(sentences) > 1
                    and self.step_words(carrying, _guides_of(9, 9, part=name,
                                                             the_parents=_the(self.say(owner))))
                    > MAX_STEP_WORDS):
                carry_units = [_Unit(owner, group, lines, carried_for=anchors)
                               for group, (lines, anchors) in zip(sentences, said_by)]
            for k, u in enumerate(carry_units):
                units[("carry", k)] = u
        if floor is not None:
            units[("floor", 0)] = floor
        placing: list[Spec] = list(flat)
        for anchor, ppart, face, con, _, carry in built:  # a mid-plane anchor: the part
            if anchor.end == "mid":                       # straddles a line
                line = (con.result.start, con.result.end)
                # carried off its own line: the line the carry ends on, lettered, is the one
                # at the part (the plate's dowel read "Centre dowel 4 on AB" with AB the
                # plate's front edge, far from the dowel)
                if carry and not all(_on_line(p, *line, self.tol)
                                     for p in (carry[-1].start, carry[-1].end)):
                    line = (carry[-1].start, carry[-1].end)
                # which way it is centred (a read-through: "Centre the head on GY", a box
                # on a vertical line, did not say across which of its sizes)
                placing.append(spec("centred", (), ("centred", anchor.axis), part=name,
                                    line=Pts(line),
                                    directions=_raw("directions")[anchor.axis]))
        # an axis with no anchor at all: say what it lines up with, as for a part by eye
        placing += self.free_specs(unguided)
        # no line constructed (faces and planes of drawn parts only): no "these lines" to name
        there = "" if built else "_there"
        # an axis no anchor places and nothing drawn lines it up on: where along it, by the
        # picture, "as pictured" (a read-through of stop 27: the roller's ferrule, "its height
        # by eye", said nowhere how high it sits)
        lined = {a.axis for _, a in unguided}
        unplaced = "_where" if any(ax not in lined for ax in cand.unguided_axes) else ""

        # a tapered part whose smaller end is an easy ratio of its larger: the lines place
        # the box around it, drawn first, then its smaller end shrunk within it ("Draw the
        # tapered box on these lines" left the mixer's bowl's top corners on no line; said
        # before the box, the taper was read before the box it shrinks, a read-through)
        placed = words.shape("frustum_around") if taper else shape

        def closing_with(chosen: list[tuple[Spec, list[int]]]) -> list[Spec]:
            said, dims = by_eye(chosen)
            return (placing + said
                    + [spec("place_by_eye" + there, shape=placed, dims=dims) if dims
                       else spec("place" + there, shape=placed)] + taper + copies)

        closing = closing_with([])
        if lies is None:
            head = _t("headline.anchored", Part=_cap(name), shape=shape,
                      the_parents=parents) + note
        else:
            others = [n for n in _unique(self.parent_name(a) for a in cand.anchors)
                      if n != lies["parent"]]
            # on a top face, under a bottom face, beside a side face (a read-through took the
            # mixer's bowl "on the column's front face" for standing on it)
            a = contact[0]
            pend = "lo" if a.ratio < 0.5 else "hi"  # the parent's face it lies on
            where = "against" if a.axis != 2 else "on" if pend == "hi" else "under"
            head = _t(f"headline.{where}_face" + ("_from" if others else ""),
                      Part=_cap(name), shape=shape, parent=lies["parent"], face=lies["faces"],
                      the_others=_join([_the(x) for x in others]),
                      beyond=words.beyond(a.axis, pend)) + note
        def guides_head(group: list[_Unit], n: int = 0, total: int = 1) -> str:
            gparents = _join([_the(x) for x in _unique(self.say(u.parent) for u in group)])
            if total > 1:  # several guides steps for one part: numbered (a read-through took
                # three pages headed alike for one page repeated)
                return _guides_of(n, total, part=name, the_parents=gparents)
            return _t("headline.guides", part=name, the_parents=gparents)

        def packed() -> list[list[_Unit]]:
            groups = self.pack(list(units.values()), closing, head, step, guides_head, cand.box)
            if len(groups) > 2:  # numbered guides steps: their longer headlines counted too
                groups = self.pack(list(units.values()), closing, head, step,
                                   lambda g: guides_head(g, 9, 9), cand.box)
            return groups

        groups = packed()
        # carries saying what they place ("for its back") only where that costs no step
        # (the roller's went over the issue's steps per shape)
        saying = [list(u.specs) for u in carry_units]
        if len(groups) > 1 and any(_unsaid(x) != x for specs in saying for x in specs):
            for u in carry_units:
                u.specs = [_unsaid(x) for x in u.specs]
            plain = packed()
            if len(plain) < len(groups):
                groups = plain
            else:
                for u, specs in zip(carry_units, saying):
                    u.specs = specs
        drafts: list[_Draft] = []
        said: set = set()  # lines an earlier guides step of this part drew: not drawn again
        for k, group in enumerate(groups[:-1]):
            here = step + k
            # an edge of a drawn part is cited where it is used (the placing step), never in
            # a guides step, which would have nothing to do with it ("Use the edge HJ."); a
            # guides step draws it only where another of its sentences names it ("Extend NQ
            # as pictured"): else neither its line nor its part is on the guides step (the
            # mixer's column edge was drawn orange in "Guides for the head (1/2), on the
            # bowl and the column", which never said it: a read-through of stop 27)
            shown = [u for u in group if not (all(x.key in _EDGE_CITES for x in u.specs)
                                              and not _names_lines_of(u, group, self.tol))]
            subs = self.lettered([x for u in shown for x in u.specs
                                  if not (x.same and x.same in said) and x.key != "edge"])
            said.update(x.same for x in subs if x.same)
            self.record(group, here, described)
            gsummary = _t("substep.guides_for", words=_join(_unique(
                _ratio_phrases(words, [a for u in shown for a in u.anchors],
                               self.parent_name))))
            drafts.append(_Draft(part, "guides", False, tuple(ln for u in shown for ln in u.lines),
                                 (), guides_head(shown, k + 1, len(groups) - 1), subs,
                                 gsummary))
        last = groups[-1]
        here = step + len(groups) - 1
        before = [u for g in groups[:-1] for u in g]
        moved = _carried(groups[:-1])
        owned = [(u, x) for u in last for x in u.specs if not (x.same and x.same in said)
                 and not (x.key == "reuse" and tuple(dict(x.fields)["line"].points) in moved)]
        own = [x for _, x in owned]
        # an edge the placing step cites says what it places too ("Use the edge DC for its
        # back."), as a line from a guides step does
        # a line an earlier step drew, reused, says what it places too ("Use LM from step 3
        # for its right side."; the train's boiler read "Use LM from step 3.", a
        # read-through), each its own (not said with a twin: their sides differ)
        def reuse_for(x: Spec) -> Spec:
            if x.key != "reuse":
                return x
            points = tuple(dict(x.fields)["line"].points)
            if points not in reused_for:
                return x
            return spec("reuse_for", x.same, (), **dict(x.fields), sides=reused_for[points])

        own_for = _edges_together([_edge_for(x, u.anchors, self.anchor_side, cand.box)
                                   if x.key == "edge" else reuse_for(x) for u, x in owned])
        saying = _citations(groups[:-1], step, self.anchor_side, cand.box)
        mine = saying + own_for
        if self.step_words(mine + closing_with([]), head) > MAX_STEP_WORDS:
            # what they place only if it fits: citation by citation, in order, where the
            # step keeps within its words (the mixer's bowl read "Use ST from step 3. Use UV
            # from step 4." for sides all said would have taken it four words over)
            mine = _citations(groups[:-1], step) + own
            if len(saying) + len(own) == len(mine):
                for i, x in enumerate(saying + [reuse_for(y) for y in own]):
                    trial = mine[:i] + [x] + mine[i + 1:]
                    if x != mine[i] and self.step_words(trial + closing_with([]),
                                                        head) <= MAX_STEP_WORDS:
                        mine = trial
        specs = self.sized(head, lambda chosen: mine + closing_with(chosen), sizes, part, loose)
        if unplaced:  # "as pictured" where the step has room left for it: it never splits a
            # step (packing counts the closing without it) nor displaces a size sentence
            pictured = [spec(x.key + unplaced, x.same, x.pair, **dict(x.fields))
                        if x.key in ("place" + there, "place_by_eye" + there) else x
                        for x in specs]
            if self.fits_levels(pictured, head):
                specs = pictured
        subs = self.lettered(self.copies_pictured(specs, head))
        self.record(last, here, described)
        # the box is drawn on the carried lines: carried in a guides step, they stay (the
        # read-through found them erased before the step that uses them)
        lines = ([_Line("guide", a, b) for u in before for a, b in u.results]
                 + [ln for u in before if any(u is c for c in carry_units) for ln in u.lines]
                 + [ln for u in last for ln in u.lines])
        lines += self.floor_side_lines(subs)
        if taper:  # "Draw the box around it": its edges are on the picture, and a later
            # construction on it uses it from here ("Use the box around the prism from step 7")
            lines += self.box_around(part)
            self._box_steps.setdefault(part, here)
        drafts.append(_Draft(part, "primitive", False, tuple(lines), strokes, head, subs,
                             summed(head)))
        return drafts

    def record(self, units: Sequence["_Unit"], step: int,
               described: list[tuple[Vec3, Vec3, int]] | None) -> None:
        """Note that step ``step`` drew these units: their result lines (for later steps to
        cite) and the box around a tapered parent (for later steps to reuse)."""
        for u in units:
            if described is not None:
                described.extend((a, b, step) for a, b in u.results)
            for x in u.specs:
                if x.key == "box_around":
                    self._box_steps.setdefault(u.parent, step)

    def along_edge(self, s: Spec, drawn: Sequence[str]) -> Spec:
        """``s``, said "along the base's edge" when most of the line it draws lies on a
        visible scaffold edge of a part drawn before, on the sheet (:data:`ALONG_MM`; the
        read-through saw nothing new where an orange line lay on a grey edge).  Not a hidden
        edge: the line then only crosses behind it on the paper, and a read-through of stop
        32 looked for the roller's handle's edge along a centre line."""
        if s.key not in ("from", "through", "cross"):
            return s
        f = dict(s.fields)
        line = f.get("line")
        if not isinstance(line, Pts) or len(line.points) != 2:
            return s
        # on the sheet: an edge behind the line in space still lies under it on the paper
        a, b = np.asarray(self.camera.project(np.asarray(line.points, dtype=float)), dtype=float)
        # a line mostly on an edge has a stretch within ALONG_MM of the edge itself, so the
        # line's box on the sheet meets the edge's grown by that much: edges whose boxes are
        # further (grown by twice as much, well beyond rounding) cannot hold it
        reach = 2.0 * ALONG_MM
        lx, ly = min(a[0], b[0]) - reach, min(a[1], b[1]) - reach
        hx, hy = max(a[0], b[0]) + reach, max(a[1], b[1]) + reach
        for part in drawn:
            if part not in self._edges:
                ends = [(np.asarray(st.points_mm[0], dtype=float),
                         np.asarray(st.points_mm[-1], dtype=float))
                        for st in self.scaffold(part) if st.kind == "scaffold"]
                self._edges[part] = [(p, q, (min(float(p[0]), float(q[0])),
                                             min(float(p[1]), float(q[1])),
                                             max(float(p[0]), float(q[0])),
                                             max(float(p[1]), float(q[1]))))
                                     for p, q in ends]
            if any(x0 <= hx and lx <= x1 and y0 <= hy and ly <= y1
                   and _mostly_on(a, b, p, q, ALONG_MM)
                   for p, q, (x0, y0, x1, y1) in self._edges[part]):
                return spec(f"{s.key}_along", s.same, s.pair, part=self.say(part), **f)
        return s

    def drawn_like(self, a: Vec3, b: Vec3) -> list[tuple[Vec3, Vec3, int]]:
        """The lines drawn so far (``_drawn``, in order) that are ``a-b`` within the tolerance
        (:func:`_same_segment`), found by one array comparison (:class:`_Segments`, kept in
        step with ``_drawn``, which only grows)."""
        if self._drawn_segs is None:
            self._drawn_segs = _Segments(self.tol)
        segs = self._drawn_segs
        for p, q, _ in self._drawn[segs.n:]:
            segs.add(p, q)
        return [self._drawn[i] for i in np.flatnonzero(segs.matches(a, b))]

    def drawn_before(self, s: Spec, step: int) -> Spec:
        """``s``, or "Use ... from step N" when an earlier step drew all its lines (the
        diagonals of a face another part's step already divided, say); either way, each
        two-point field naming a line an earlier step drew (an edge extended aside) has its
        points in the order of that line as drawn, which is the order the sub-steps that drew
        it named it in (constructions and ellipses build both alike)."""
        if not self._drawn:
            return s
        # a line an earlier step drew is named as that step named it: "Use diagonals SH and
        # TJ from step 7 ... it crosses TJ", not "JT" (a read-through)
        f = dict(s.fields)
        drawn_in: dict[str, int] = {}
        for k, v in f.items():
            if not (isinstance(v, Pts) and len(v.points) == 2) or k == "edge":
                continue  # (an edge extended is named toward the end it is extended beyond)
            a, b = v.points
            at = [(n, p) for p, _, n in self.drawn_like(a, b) if n < step]
            if at:
                drawn_in[k], p = at[0]
                if not _same_point(a, p, self.tol):
                    f[k] = Pts((b, a))
        if s.key not in _DRAWS:
            return spec(s.key, s.same, s.pair, **f) if drawn_in else s
        keys = [k for k in _DRAWS[s.key] if isinstance(f.get(k), Pts)]
        if not all(k in drawn_in for k in keys):
            return spec(s.key, s.same, s.pair, **f) if drawn_in else s
        return spec(f"{s.key}_reuse", s.same, s.pair, step=max(drawn_in[k] for k in keys), **f)

    def parent_name(self, anchor: Any) -> str:
        """The name of the part an anchor hangs off, as said ("the base")."""
        return self.say(self.by_id[anchor.parent].part)

    def anchor_side(self, anchor: Any) -> str:
        """The side of the part an anchor places ("back", "middle (front to back)")."""
        return self.words.side(anchor.axis, anchor.end)

    def pack(self, units: list["_Unit"], closing: list[Spec], head: str, step: int,
             guides_head: Callable[[list["_Unit"]], str], box: Any = None
             ) -> list[list["_Unit"]]:
        """Units of construction grouped into steps of at most :data:`MAX_STEP_WORDS` words:
        the last group goes with ``closing`` (the placing sub-steps) under ``head``, the
        others are guides steps under ``guides_head(group)``; a unit too long for a step of
        its own is cut in two where it can be (:meth:`split_unit`), else it exceeds the
        limit.  Lines an earlier group drew are not counted again (they are
        not said again).  An edge the placing step cites is counted with what it places, as
        that step says it ("Use the edge QR for its front.")."""
        def fits(group: list[_Unit], extra: list[Spec], said: set) -> bool:
            specs = [_edge_for(x, u.anchors, self.anchor_side, box)
                     if extra and x.key == "edge" else x
                     for u in group for x in u.specs if not (x.same and x.same in said)]
            specs = _edges_together(specs) if extra else specs
            return self.step_words(specs + extra, head if extra else guides_head(group)
                                   ) <= MAX_STEP_WORDS

        if not units or fits(units, closing, set()):
            return [units]
        # as the placing step will cite them (worst case)
        reuse = _citations([units], step, self.anchor_side, box)
        # Edges extended and guides reused need no room: they stay with the placing step.
        tail = [u for u in units if not u.room]
        rest = [v for u in units if u.room
                for v in (self.split_unit(u, guides_head) if not fits([u], [], set()) else [u])]

        def said_by(groups: list[list[_Unit]]) -> set:
            return {x.same for g in groups for u in g for x in u.specs if x.same}

        while rest and fits([rest[-1]] + tail, reuse + closing, said_by([rest[:-1]])):
            tail.insert(0, rest.pop())
        movable = [u for u in tail if any(x.key != "reuse" for x in u.specs)]
        while movable and not fits(tail, reuse + closing, said_by([rest])):  # edges: move too
            u = movable.pop(0)  # (a line only reused stays: moving it would cite it twice)
            tail.remove(u)
            rest.append(u)
        def grouped(rest: list[_Unit]) -> list[list[_Unit]]:
            groups: list[list[_Unit]] = []
            for u in rest:
                if groups and fits(groups[-1] + [u], [], said_by(groups[:-1])):
                    groups[-1].append(u)
                else:
                    groups.append([u])
            # a group may also join a later one when both fit one step and no group between
            # them shares a point with it (none uses what it draws): the mixer's head had
            # guides on the base, on the bowl, then carried from the base, now two steps
            merged = True
            while merged:
                merged = False
                for i, j in ((i, j) for i in range(len(groups) - 1)
                             for j in range(len(groups) - 1, i + 1, -1)):
                    trial = groups[:i] + groups[i + 1:j] + [groups[i] + groups[j]]
                    if fits(trial[-1], [], said_by(trial[:-1])) and not any(
                            _touch(u, v, self.tol) for k in range(i + 1, j)
                            for u in groups[i] for v in groups[k]):
                        groups = trial + groups[j + 1:]
                        merged = True
                        break
            return groups

        groups = grouped(rest)
        # the estimate above cites every line as one step's; the guides steps now known, the
        # placing step cites each with its own step ("Use UV from step 5. Use HJ from step 6.")
        while movable and not fits(tail, _citations(groups, step, self.anchor_side, box)
                                   + closing, said_by(groups)):
            u = movable.pop(0)
            tail.remove(u)
            rest.append(u)
            groups = grouped(rest)
        # a group that only cites lines (edges of drawn parts, lines of earlier steps) draws
        # nothing: it is never a guides step of its own (a read-through: "Guides for the grip
        # (2/2), on the body. 1. Use the edge AD.", then "Use AD from step 7"); it stays
        # with the placing step
        idle = [g for g in groups if all(x.key in _CITES for u in g for x in u.specs)]
        if idle:
            groups = [g for g in groups if g not in idle]
            tail = [u for g in idle for u in g] + tail
        return groups + [tail]

    def crossing_lines(self, runs: Sequence[Pts], turns: Sequence[Pts],
                       units: Mapping[Any, "_Unit"], drawn: Sequence[str],
                       lines: Sequence[tuple[Vec3, Vec3, int]], boxes: Sequence[str]
                       ) -> Many | None:
        """The lines on the paper that cross each of ``runs`` at its turn (a walked carry's
        first turn on its own line), one per turn, or None where one has none: this step's
        lines first (lettered already), then the earlier lines and boxes the walk turns on,
        then the edges of the parts drawn before."""
        paper = ([(ln.start, ln.end) for u in units.values() for ln in u.lines
                  if ln.role != "construction"]
                 + [(a, b) for a, b, _ in lines]
                 + [(ln.start, ln.end) for other in boxes for ln in self.box_around(other)]
                 + [(p, q) for other in drawn for p, q in self.scaffold_ends(other)])
        tol = 10.0 * self.tol
        found: list[Pts] = []
        for run, at in zip(runs, turns):
            c = at.points[0]
            got = next((Pts((_vec(p), _vec(q))) for p, q in paper if _on_segment(c, p, q, tol)
                        and not (_on_line(p, *run.points, tol) and _on_line(q, *run.points, tol))),
                       None)
            if got is None:
                return None
            if not any(_same_segment(*got.points, *f.points, self.tol) for f in found):
                found.append(got)
        return Many(tuple(found))

    def split_unit(self, u: "_Unit", guides_head: Callable[[list["_Unit"]], str]
                   ) -> list["_Unit"]:
        """``u``, a unit too long for a guides step of its own, as two units of consecutive
        sub-steps that each fit one, or ``[u]`` where no cut does.  The first takes the lines
        whose ends its sub-steps name (every line it draws is one it says), the second the
        others with the anchors and results; the cut is where the two come closest in
        words.  From views nobody tuned, the train's chimney found its middle lines on the
        boiler and extended half the face in one step of six sub-steps, 73-74 words: now
        "Draw diagonals ..., through M draw FU ... and VE' ..." and then "Extend LQ ... from
        U through E' ... from X' draw X'Y'" (issue 11: no step over 70 words)."""
        best: tuple[int, "_Unit", "_Unit"] | None = None
        for k in range(1, len(u.specs)):
            named = [p for x in u.specs[:k] for _, v in x.fields for p in points_of(v)]

            def said(q: Vec3) -> bool:
                return any(_same_point(q, r, self.tol) for r in named)

            mine = [ln for ln in u.lines if said(ln.start) and said(ln.end)]
            if not mine:
                continue
            first = _Unit(u.parent, list(u.specs[:k]), mine, room=True)
            # the first's lines the second's sentences start from stay on its picture too
            # (a read-through: "Through M, draw VN" after the step before offered to erase
            # the diagonals crossing at M)
            later = [p for x in u.specs[k:] for _, v in x.fields for p in points_of(v)]
            kept = [ln for ln in mine if any(_on_segment(q, ln.start, ln.end, self.tol)
                                             for q in later)]
            second = replace(u, specs=list(u.specs[k:]),
                             lines=kept + [ln for ln in u.lines if ln not in mine])
            words = [self.step_words(v.specs, guides_head([v])) for v in (first, second)]
            if max(words) > MAX_STEP_WORDS:
                continue
            if best is None or abs(words[0] - words[1]) < best[0]:
                best = (abs(words[0] - words[1]), first, second)
        return [u] if best is None else [best[1], best[2]]

    def uses_box(self, part: str, around: Sequence[_Line], con: Any) -> bool:
        """Does construction ``con`` on tapered ``part`` use its box: does an end of one of its
        lines lie on a box edge of ``around`` (those the scaffold leaves out) and on no edge
        the scaffold draws?  Not when it lies on the face the scaffold draws whole (the
        camera's prism's top, the bowl's rim face)."""
        drawn = self.scaffold_ends(part)
        missing = [(np.asarray(ln.start, dtype=float), np.asarray(ln.end, dtype=float))
                   for ln in around]

        def on(p: np.ndarray, segs: list[tuple[np.ndarray, np.ndarray]]) -> bool:
            for a, b in segs:
                d = b - a
                t = float(np.clip(np.dot(p - a, d) / max(float(np.dot(d, d)), 1e-300), 0, 1))
                if float(np.abs(a + t * d - p).max()) <= self.tol:
                    return True
            return False

        ends = [np.asarray(q, dtype=float) for ln in con.lines for q in (ln.start, ln.end)]
        return any(on(p, missing) and not on(p, drawn) for p in ends)

    def anchor_lines(self, cand: Any, k: int, floor: float | None = None, foot: Any = None
                     ) -> tuple[Face, Any, list[_Line], list[_Line]]:
        """:func:`_anchor_lines` of ``cand``'s anchor ``k`` in this view; not turning on a
        floor, those the camera fit worked out already with this camera (``_anchor_memo``,
        :func:`_fit_camera`), when it kept them (lists copied: the caller's own)."""
        if floor is None and foot is None:
            hit = self._anchor_memo.get((cand.id, k))
            if hit is not None:
                face, con, own, carry = hit
                return face, con, list(own), list(carry)
        anchor = cand.anchors[k]
        return _anchor_lines(anchor, self.by_id[anchor.parent], cand, self.plan, self.camera,
                             self.tol, floor, foot)

    def scaffold(self, part: str) -> tuple[Stroke, ...]:
        """``part``'s scaffold in its selected box (:func:`_scaffold`), made once: its step,
        the steps after it (edges along, ends) and the floor line all ask for it."""
        if part not in self._scaffolds:
            self._scaffolds[part] = _scaffold(part, self.plan.primitive(part),
                                              self.chosen[part].box, self.camera, self.tol)
        return self._scaffolds[part]

    def walk_carries(self, part: str, cand: Any, built: list[Any], skip: set[int],
                     drawn: Sequence[str], floor_z: float | None, foot: Vec3 | None,
                     earlier: Sequence[tuple[Vec3, Vec3, int]] = ()
                     ) -> dict[int, tuple[tuple[str, ...], tuple[tuple[Vec3, Vec3, int], ...]]]:
        """The carries of ``part``'s anchors (``built``, replaced in place) that would turn
        by eye, walked along lines drawn before instead (geometry._walk_carry).

        A carry turns by eye where it turns on a plane of the part no anchor places (nor the
        floor it stands on): said "(by eye)", as the primitive step's loop finds it.  Carries
        that one sentence says together (the same directions) are walked together, all of
        them or none, and only where the walks share their directions and no other sentence
        already uses them.  The lines a walk may turn on: the edges of the parts drawn
        before and this step's own constructions; else also the boxes drawn around tapered
        parts in earlier steps; else also the lines earlier steps placed parts with
        (``earlier``: ends and step), each said again where a walk turns on it ("Use NP
        from step 3.": the roller's frame shaft, centred on the line that placed the
        handle's top).  Not ``skip``: carries made another way (a crossing, two carries
        meeting).  Returned: each walked carry's index, the tapered parts whose boxes it
        turns on and the earlier lines it turns on (its step draws them again)."""
        tol = 10.0 * self.tol

        def grouped() -> dict[tuple[int, int | None], list[int]]:
            """The carries by the sentence they are said in (their directions)."""
            out: dict[tuple[int, int | None], list[int]] = {}
            for k, (_, _, _, _, _, carry) in enumerate(built):
                if carry and k not in skip:
                    out.setdefault(_carry_ways(carry), []).append(k)
            return out

        groups = grouped()
        self._merged = {}
        self._far = set()
        # the lines on the paper: edges of the parts drawn before, this step's lines every
        # level with guides shows (not construction lines)
        segments = [(p, q) for other in drawn for p, q in self.scaffold_ends(other)]
        segments += [(ln.start, ln.end) for entry in built for ln in entry[4]
                     if ln.role != "construction"]
        eyed = []
        for key, ks in groups.items():
            if key[1] is None:
                continue
            # (what the loop finds a turn on: also the floor's line, the other carries' legs)
            paper = segments + [(ln.start, ln.end) for k2, entry in enumerate(built)
                                if k2 not in ks for ln in entry[5]]
            for k in ks:
                carry, n = built[k][5], built[k][2].normal
                placed = _placed_planes(cand.box, cand.anchors, n)
                leg = (None if floor_z is None or n != 2
                       else self.floor_leg(carry, floor_z, foot))
                if leg is not None:
                    placed.append(floor_z)
                turn = carry[0].end
                if (not any(abs(turn[n] - v) <= tol for v in placed)
                        or not any(_near_segment(turn, p, q, 2.0 * tol)
                                   and _on_segment(turn, p, q, tol)
                                   for p, q in paper + ([leg] if leg else []))):
                    eyed.append(key)
                    break
        if not eyed:
            return {}
        # and the boxes drawn around tapered parts before: a walk may turn on them, and its
        # step then draws them again ("Use the box around the prism from step 6")
        boxes = {other: [(ln.start, ln.end) for ln in self.box_around(other)]
                 for other in drawn if other in self._box_steps}
        boxed = segments + [seg for lines in boxes.values() for seg in lines]
        tiers = (segments, boxed, boxed + [(a, b) for a, b, _ in earlier])
        child = _drawn_box(self.plan.primitive(part), cand.box)
        mids = sorted({a.axis for a in cand.anchors if a.end == "mid"})
        used = set(groups)
        out: dict[int, tuple[tuple[str, ...], tuple[tuple[Vec3, Vec3, int], ...]]] = {}
        for key in eyed:
            for tier in tiers:  # the fewest lines said again
                walks = [_walk_carry(built[k][3], built[k][2], child, tier, tol, mids)
                         for k in groups[key]]
                if all(w is not None for w in walks):
                    break
            if any(w is None for w in walks):
                continue
            # one sentence says them: the same directions, each extended along its own line
            # first or each carried off it
            # ... and each from the end of its line a carry starts from (the primer: the end
            # nearer the part) or each said to start from the other ("Carry B'C' from B'
            # ...": a read-through of the mixer's head began at C'), once it turns only once
            far = [self.far_start(built[k][3].result, w, child)
                   for k, w in zip(groups[key], walks) if w is not None]
            ways = {(tuple(_moving_axis(ln) for ln in w),
                     _moving_axis(_Line("", built[k][3].result.start, built[k][3].result.end))
                     == _moving_axis(w[0]))
                    for k, w in zip(groups[key], walks) if w is not None}
            if len(ways) != 1 or len(set(far)) != 1 or (far[0] and len(walks[0] or ()) > 2):
                continue
            new = _carry_ways([ln for ln in walks[0] or ()])
            if new != key and new in used:
                continue
            used.add(new)
            for k, w in zip(groups[key], walks):
                built[k] = built[k][:5] + (list(w or ()),)
                if far[0]:
                    self._far.add(k)
                turns = [ln.end for ln in (w or ())[:-1]
                         if not any(_on_segment(ln.end, p, q, tol) for p, q in segments)]
                parts = tuple(other for other, lines in boxes.items()
                              if any(_on_segment(t, p, q, tol) for p, q in lines for t in turns))
                rest = [t for t in turns if not any(_on_segment(t, p, q, tol) for p, q in boxed)]
                lines_ = tuple(next((a, b, n) for a, b, n in earlier
                                    if _on_segment(t, a, b, tol)) for t in rest)
                out[k] = (parts, tuple(dict.fromkeys(lines_)))
        # a walk that draws, besides its own line, only what another carry draws (the
        # chair's seat: its bottom carried "from F", along the line carrying its middle; the
        # train's chimney: its front and its right side up from one corner) is said with
        # that carry ("..., for its middle (left to right) and bottom"): the larger
        # sentences' lines into the smaller ones
        size = {k: len(ks) for ks in grouped().values() for k in ks}  # (walks regrouped)
        merged: dict[int, int] = {}
        for k in sorted(out, key=lambda k: (-size[k], k)):
            res = built[k][3].result
            extra = [ln for ln in built[k][5] if not (_on_line(ln.start, res.start, res.end, tol)
                                                      and _on_line(ln.end, res.start, res.end, tol))]
            if not extra:
                continue
            into = [j for j in sorted(size, key=lambda j: (size[j], j))
                    if j != k and j not in merged and merged.get(j) != k
                    and _carry_ways(built[j][5]) != _carry_ways(built[k][5])
                    and all(any(_on_segment(ln.start, q.start, q.end, tol)
                                and _on_segment(ln.end, q.start, q.end, tol)
                                for q in built[j][5]) for ln in extra)]
            if into:
                merged[k] = into[0]
        self._merged = merged
        return {k: v for k, v in out.items() if k not in merged}

    @staticmethod
    def far_start(result: Any, walk: Sequence[_Line], child: Box) -> bool:
        """Does ``walk`` leave its line (``result``) from the end farther from the ``child``
        box, the first leg running across the line (a reader starts a carry at the end nearer
        the part, as the primer says, unless told)?"""
        if _moving_axis(walk[0]) == _moving_axis(_Line("", result.start, result.end)):
            return False  # extended along the line, or carried from a point on it: said
        lo, hi = (np.asarray(v, dtype=float) for v in child)

        def gap(p: Any) -> float:
            q = np.asarray(p, dtype=float)
            return float(np.linalg.norm(np.maximum(lo - q, 0.0) + np.maximum(q - hi, 0.0)))

        near = min((result.start, result.end), key=gap)
        return gap(walk[0].start) > gap(near) and not _same_point(walk[0].start, near, 0.0)

    def scaffold_ends(self, part: str) -> list[tuple[np.ndarray, np.ndarray]]:
        """The 3D ends of ``part``'s scaffold strokes in its selected box (computed once)."""
        if part not in self._scaffold_ends:
            self._scaffold_ends[part] = [
                (np.asarray(st.points3d[0], dtype=float), np.asarray(st.points3d[-1], dtype=float))
                for st in self.scaffold(part)]
        return self._scaffold_ends[part]

    def box_around(self, part: str) -> list[_Line]:
        """For a part whose scaffold does not draw its selected box's faces (a frustum), the
        box edges the scaffold leaves out (role ``vanishing``); else nothing."""
        if self.plan.primitive(part).type != "frustum":
            return []
        drawn = self.scaffold_ends(part)
        pts = _box_corners(self.chosen[part].box)
        out = []
        for i in range(8):
            for j in range(i + 1, 8):
                if bin(i ^ j).count("1") != 1:  # corners i*4 + j*2 + k differ in one axis
                    continue
                a, b = pts[i], pts[j]
                if float(np.abs(b - a).max()) <= self.tol:
                    continue
                if not any(_same_segment(a, b, p, q, self.tol) for p, q in drawn):
                    out.append(_Line("vanishing", _vec(a), _vec(b)))
        return out

    def loose_axes(self, cand: Any) -> list[int]:
        """Axes of ``cand`` with fewer than two anchored ends (judged by eye), not flat: a
        plane is drawn as a rectangle in its mid-plane (:func:`_solid`), so its normal has no
        size to judge even when its box keeps the panel's thickness."""
        biggest = max(_extent(cand.box, a) for a in range(3))
        prim = self.plan.primitive(cand.part)
        normal = prim.axis if prim.type == "plane" else None
        return [a for a in range(3)
                if sum(1 for an in cand.anchors if an.axis == a) < 2
                and _extent(cand.box, a) > 1e-9 * biggest and a != normal]

    def guided(self) -> tuple[_Draft, ...]:
        if self._guided is None:
            groups, keep = self.guided_parts()
            boxes = {p: self.chosen[p].box for g in groups for p in g}
            described: list[tuple[Vec3, Vec3, int]] = []
            drafts: list[_Draft] = []
            drawn: list[str] = []
            for gi, group in enumerate(groups):
                p = group[0]
                shape = self.words.shape(self.plan.primitive(p).type)
                rows = self.spaced_rows(group, boxes)
                spaced = {q for row, _, _ in rows for q in row[2:]}
                rest = [q for q in group[1:] if q not in spaced]
                repeat = self.same_sentence(rest, shape, keep, p)
                made = self.primitive_drafts(p, gi == 0, len(drafts) + 1, described, drawn=drawn,
                                             repeat=repeat, copies_of=rest)
                if rest:
                    others = [_Draft(q, "primitive", False, (), self.scaffold(q), "")
                              for q in rest]
                    made[-1] = self.merge_group(made[-1], [p, *rest], others, repeat)
                made += [self.spacing_draft(row, axis, face, boxes, shape)
                         for row, axis, face in rows]
                # the boxes' edges behind the parts drawn before them, dotted
                made = [replace(d, strokes=self.behind(d.strokes, drawn))
                        if d.kind == "primitive" else d for d in made]
                for k, d in enumerate(made):  # lines a later step may say "use" of
                    self._drawn.extend((ln.start, ln.end, len(drafts) + 1 + k) for ln in d.lines)
                drafts += made
                drawn += group
            order = [q for g in groups for q in g]
            lead = {q: g[0] for g in groups for q in g}
            ellipses: list[_Draft] = []
            small: dict[str, _Draft] = {}  # ellipses sketched by eye: with the outlines
            for group in groups:
                p = group[0]
                prim = self.plan.primitive(p)
                if not _round(prim):
                    continue
                made = [replace(d, group=tuple(group)) for d in self.ellipse_drafts(
                    p, boxes[p], False, [(q, boxes[q]) for q in group[1:]])]
                if made[0].eyeball:
                    small[p] = made[0]
                else:
                    ellipses += made
            drawn_ellipses: dict[tuple, tuple[str, int]] = {}  # ellipse -> (part, step)
            for d in ellipses:  # diagonals a primitive step drew already: used, not redrawn
                here = len(drafts) + 1
                key = self.ellipse_key(d)
                if key in drawn_ellipses and drawn_ellipses[key][0] != d.part:
                    # the same ellipse another part's step drew (a lid on a neck: the lid's
                    # bottom is the neck's top): said, not drawn again (a read-through redrew
                    # it, carrying four points onto themselves)
                    other, n = drawn_ellipses[key]
                    if drafts and drafts[-1].part == d.part and drafts[-1].kind == "ellipse":
                        drafts[-1] = replace(drafts[-1], specs=drafts[-1].specs + (
                            spec("ellipse_shared", face=self.ellipse_face(d), other=self.say(other),
                                 step=n),))
                        continue
                drawn_ellipses.setdefault(key, (d.part, here))
                drafts.append(replace(d, specs=tuple(self.drawn_before(x, here) for x in d.specs)))
            traced = self.traced_only()
            contours = self.contour_drafts(order + traced, self.adjusted)
            merged: list[_Draft] = []
            at: dict[str, int] = {}
            unnamed: list[Stroke] = []  # lines of parts only traced, not yet in a step
            for d in contours:  # a group's outlines together, where its first one comes
                if d.part in traced:  # its few lines go with the outlines traced around them,
                    # unnamed (a read-through: "wheel 4" named where nothing of it showed)
                    if merged:
                        merged[-1] = replace(merged[-1], strokes=merged[-1].strokes + d.strokes)
                    else:
                        unnamed += d.strokes
                    continue
                if unnamed:
                    d = replace(d, strokes=tuple(unnamed) + d.strokes)
                    unnamed = []
                head = lead.get(d.part, d.part)
                if head in at:  # named after all its parts (a read-through: the desk's
                    k = at[head]  # "Part 2: its outlines" traced part 3 too, unnamed)
                    group = merged[k].group + (d.part,)
                    merged[k] = replace(merged[k], strokes=merged[k].strokes + d.strokes,
                                        group=group, headline=_t(
                                            "headline.contour_many",
                                            Parts=_cap(_join([self.say(q) for q in group]))))
                else:  # the step is named after the group's first part, as its other steps
                    at[head] = len(merged)
                    merged.append(replace(d, part=head, group=(d.part,)))
            for head, e in small.items():  # a small ellipse joins its part's outlines
                if head in at:
                    k = at[head]
                    # a part and its copies: all their ellipses (a read-through of the
                    # pins plate: "Sketch dowel 1's ellipses" drew six dowels' ellipses)
                    key = "ellipse_by_eye_copies" if len(e.group) > 1 else "ellipse_by_eye_part"
                    merged[k] = replace(merged[k], strokes=e.strokes + merged[k].strokes,
                                        specs=(spec(key, part=self.say(head)),)
                                        + merged[k].specs)
                else:
                    drafts.append(e)
            drafts += self.pack_outlines(merged, lead, self.hidden_drawn(order, self.adjusted))
            self._unlettered = tuple(self.promoted(drafts))
            self._guided = tuple(self.letter(self._unlettered))
        return self._guided

    @staticmethod
    def brief_where(kind: str, parent: str, face: str) -> str:
        """The face an apprentice's construction sentence names (``brief_where``)."""
        return _t(f"brief_where.{kind}", parent=parent, face=face)

    def promoted(self, drafts: Sequence[_Draft]) -> list[_Draft]:
        """``drafts`` with a construction line that a later step uses as a guide of its own
        made a guide where a sub-step that can say how draws it (field ``brief``): the
        train's boiler is centred on FG, the half line step 3 drew on the way to the cab's
        third.  An apprentice, who sees guides only, then sees FG drawn in step 3 and reads
        "Halve the engine's top face: draw FG ..." there, where step 5 cites it; plan.json
        calls it a guide."""
        used = [(ln.start, ln.end, k) for k, d in enumerate(drafts) for ln in d.lines
                if ln.role != "construction"]
        out = []
        for k, d in enumerate(drafts):
            def later(a: Vec3, b: Vec3) -> bool:
                return any(j > k and _same_segment(a, b, p, q, self.tol) for p, q, j in used)

            up: list[Pts] = []
            specs = []
            for s in d.specs:
                f = dict(s.fields)
                line = f.get("line")
                if (f.get("role") == "construction" and "brief" in f and isinstance(line, Pts)
                        and len(line.points) == 2 and later(*line.points)):
                    up.append(line)
                    s = spec(s.key, s.same, s.pair, **{**f, "role": "guide"})
                specs.append(s)
            if up:
                d = replace(d, specs=tuple(specs), lines=tuple(
                    _Line("guide", ln.start, ln.end) if ln.role == "construction" and any(
                        _same_segment(ln.start, ln.end, *u.points, self.tol) for u in up)
                    else ln for ln in d.lines))
            out.append(d)
        return out

    def apprentice(self) -> tuple[_Draft, ...]:
        """The guided drafts as an apprentice reads them: the same steps, each sub-step that
        draws only construction lines (which the apprentice's picture leaves out) left out,
        a construction's result said as the construction (:func:`brief_specs`), lettered
        anew over the apprentice's steps."""
        if self._apprentice is None:
            self.guided()
            drafts = self._unlettered
            roles = LEVEL_ROLES["apprentice"]

            def shown(line: Pts, step: int) -> bool:  # on step ``step``'s picture
                a, b = line.points
                return any(ln.role in roles and _same_segment(a, b, ln.start, ln.end, self.tol)
                           for ln in drafts[step - 1].lines)

            self._apprentice = tuple(self.letter(
                [replace(d, specs=tuple(brief_specs(d.specs, self.brief_where, shown)))
                 for d in drafts], roles))
        return self._apprentice

    def basic(self) -> tuple[_Draft, ...]:
        if self._basic is None:
            keep = self.visible(self.originals)
            left_out = sorted({p.name for p in self.plan.model.parts} - keep)
            if left_out:
                log.info("left out (hidden): %s", ", ".join(left_out))

            order = self.basic_order(keep)
            drafts: list[_Draft] = []
            for i, p in enumerate(order):
                prim = self.plan.primitive(p)
                shape = self.words.shape(prim.type)
                head = _t("headline.first" if i == 0 else "headline.basic",
                          Part=_cap(self.say(p)), shape=shape)
                lines = _scaffold(p, prim, prim.box, self.camera, self.tol)
                subs = (tuple(_first_specs(_first_lines(lines, self.camera, self.floor_z(True))))
                        if i == 0
                        else (spec("basic_part"),))
                # its edges behind the boxes drawn before it dotted, as in the guided tutorial
                drafts.append(_Draft(p, "basic", True, (), self.behind(lines, order[:i], True),
                                     head, subs))
            drafts += [d for p in order if _round(self.plan.primitive(p))
                       for d in self.ellipse_drafts(p, self.plan.primitive(p).box, True)]
            outlines = self.contour_drafts(order, self.originals)
            unseen = self.hidden_drawn(order, self.originals)
            drafts += outlines[:-1] + [self.finish(d, basic=True, unseen=unseen)
                                       for d in outlines[-1:]]
            self._basic = tuple(self.letter(drafts))
        return self._basic

    def guide_ids(self) -> tuple[tuple[tuple[str, str], ...], ...]:
        """Per guided draft, its lines as ``(guide id, role)``, merged within the step."""
        if self._ids is None:
            reg = _Segments(self.tol)  # the first guide each line is, as a scan in order
            out = []
            for d in self.guided():
                step: dict[str, str] = {}
                for ln in d.lines:
                    i = reg.first(ln.start, ln.end)
                    if i is None:
                        i = reg.add(ln.start, ln.end)
                        self._canon[f"g{i + 1}"] = (ln.start, ln.end)
                    gid = f"g{i + 1}"
                    if gid not in step or _ROLE_RANK[ln.role] > _ROLE_RANK[step[gid]]:
                        step[gid] = ln.role
                out.append(tuple(step.items()))
            self._ids = tuple(out)
        return self._ids

    def face_labels(self, part: str) -> tuple[Label, ...]:
        """The faces of the first box ``part`` that the view shows, each named on the
        picture in the steps' words ("front", "left", "top"; kind ``face``, at the face's
        centre), where the face is at least :data:`FACE_LABEL_MM` wide on the sheet: the
        steps name sides and sizes by these words ("its front", "the base's width"), and a
        read-through could not tell which of the train's faces was its front, nor which edge
        of the mixer's base was its width (the primer ties width, depth and height to them).
        None for a tapered first part, whose faces are not its box's."""
        prim = self.plan.primitive(part)
        if prim.type == "frustum":
            return ()
        box = _drawn_box(prim, self.chosen[part].box)
        lo, hi = (np.asarray(b, dtype=float) for b in box)
        eye = np.asarray(self.camera.position, dtype=float)
        out = []
        for axis in range(3):
            u, v = (a for a in range(3) if a != axis)
            if hi[u] - lo[u] <= self.tol or hi[v] - lo[v] <= self.tol:
                continue
            for end, at, sign in (("lo", lo[axis], -1.0), ("hi", hi[axis], 1.0)):
                if sign * (eye[axis] - at) <= 0.0:
                    continue  # seen from behind
                corners = []
                for a, b in ((0, 0), (1, 0), (1, 1), (0, 1)):
                    c = [0.0, 0.0, 0.0]
                    c[axis], c[u], c[v] = at, (lo[u], hi[u])[a], (lo[v], hi[v])[b]
                    corners.append(tuple(c))
                area, longest = _sheet_polygon(self.camera, corners)
                centre = _vec(np.mean(np.array(corners, dtype=float), axis=0))
                if area < FACE_LABEL_MM * longest:
                    # too thin to hold its name: named at the middle of its outer edge, the
                    # one furthest on the sheet from the box's middle (the mixer's base named
                    # its top only, and the steps spoke of its front, a read-through)
                    mids = [_vec(0.5 * (np.asarray(corners[i]) + np.asarray(corners[i - 1])))
                            for i in range(4)]
                    ends = self.camera.project(np.array(corners, dtype=float))
                    long = sorted(range(4), key=lambda i: -float(np.hypot(
                        *(ends[i] - ends[i - 1]))))[:2]  # its two long edges
                    middle = self.camera.project(np.array([(lo + hi) / 2.0]))[0]
                    at = self.camera.project(np.array(mids, dtype=float))
                    centre = mids[max(long, key=lambda i: float(np.hypot(*(at[i] - middle))))]
                out.append(self.label(self.words.face_label(axis, end), centre, "face"))
        return tuple(out)

    def label(self, name: str, point: Vec3, kind: str = "point") -> Label:
        mm = self.camera.project(np.array([point], dtype=float))[0]
        return Label(name, point, (float(mm[0]), float(mm[1])), kind)

    def view_plan(self, name: str, level: str, paper: PaperSpec) -> ViewPlan:
        if level not in LEVEL_ROLES:
            raise ValueError(f"level must be one of {', '.join(LEVEL_ROLES)}, got {level!r}")
        if level == "basic":
            drafts = self.basic()
            shown: list[list[tuple[str, str]]] = [[] for _ in drafts]
        else:
            drafts = self.apprentice() if level == "apprentice" else self.guided()
            roles = LEVEL_ROLES[level]
            shown = [[(g, r) for g, r in ids if r in roles] for ids in self.guide_ids()]
            if level == "master":  # a master sees no guides: no guides steps, the ratio words
                keep = [i for i, d in enumerate(drafts) if d.kind != "guides"]
                drafts = tuple(drafts[i] for i in keep)
                shown = [shown[i] for i in keep]
        first: dict[str, int] = {}
        last: dict[str, int] = {}
        for i, gs in enumerate(shown):
            for gid, _ in gs:
                first.setdefault(gid, i)
                last[gid] = i
        ordered = sorted(first, key=lambda g: (first[g], int(g[1:])))
        mm: dict[str, tuple[tuple[float, float], tuple[float, float]]] = {}
        for gid in ordered:
            a, b = self._canon[gid]
            p = self.camera.project(np.array([a, b], dtype=float))
            mm[gid] = ((float(p[0, 0]), float(p[0, 1])), (float(p[1, 0]), float(p[1, 1])))
        # the sheet prints the first box's footprint and height: the first scaffold step's
        # guides where the level shows guides (DESIGN.md §2.6: a master sees none, and the
        # control tutorial has none)
        start, floor_until = _floor_span(drafts)
        printed = (() if start is None or not LEVEL_ROLES[level]
                   else _sheet_guides(_first_lines(drafts[start].strokes, self.camera,
                                                   self.floor_z(level == "basic")),
                                      self.camera))
        floor = [g for g in printed if g.id == SHEET_FLOOR]
        steps = []
        for i, (d, gs) in enumerate(zip(drafts, shown)):
            guides = tuple(
                Guide(gid, "new" if first[gid] == i else "reused", self._canon[gid][0],
                      self._canon[gid][1], mm[gid][0], mm[gid][1], role)
                for gid, role in gs)
            alive = tuple(g for g in ordered if first[g] <= i <= last[g])
            if i == start and printed:
                guides = printed + guides
                alive = tuple(g.id for g in printed) + alive
            elif floor and start is not None and start < i <= floor_until:
                # the floor line stays on the paper while a later step stands a part on it,
                # and is shown where one does
                if _stands_on_floor(d):
                    guides = (replace(floor[0], status="reused"),) + guides
                alive = (floor[0].id,) + alive
            box = None
            if d.part is not None and d.kind in ("primitive", "basic", "contour", "ellipse"):
                box = (self.plan.primitive(d.part).box if level == "basic"
                       else self.chosen[d.part].box)
            members = list(dict.fromkeys([d.part] + [st.part for st in d.strokes])) \
                if box is not None else []
            stems = [stem(self.say(q)) for q in members]
            def box_of(q: str) -> Box:
                return box if q == d.part and box is not None else (
                    self.plan.primitive(q).box if level == "basic" else self.chosen[q].box)

            # (the boxes on the picture: the parts drawn so far)
            on_picture = list(dict.fromkeys(q for st in steps for q in
                                            [st.part, *(s.part for s in st.strokes)]
                                            if q is not None)) + members
            named = tuple(self.label(n, p, "part") for q, base in zip(members, stems)
                          for n, p in self.part_labels(
                              q, box_of(q), base is not None and stems.count(base) > 1,
                              [box_of(o) for o in dict.fromkeys(on_picture) if o != q]))
            if level == "master":
                subs: tuple[str, ...] = ()
                labels: tuple[Label, ...] = named
                summary = d.summary or _by_eye_ellipses(d)
                text = " ".join(x for x in (d.headline, summary) if x)
            else:
                subs, summary = d.substeps, ""
                labels = tuple(self.label(n, p) for n, p in d.labels) + named
                text = " ".join([d.headline] + [_t("step_text.number", n=k + 1, text=x)
                                                 for k, x in enumerate(subs)])
            if i == start and level != "basic" and d.part is not None:
                labels += self.face_labels(d.part)
            steps.append(Step(i + 1, d.part, d.kind, text, d.eyeball, guides, d.strokes, alive,
                              d.headline, subs, summary, labels))
        shown = {st.part for st in steps if st.part is not None} | {
            s.part for st in steps for s in st.strokes}
        renamed = tuple(sorted(((self.names[p].label, p) for p in shown
                                if not self.names[p].readable),
                               key=lambda lp: (natural_key(lp[0]), lp[1])))
        return ViewPlan(name, level, (float(paper.width_mm), float(paper.height_mm)), self.camera,
                        self.vps, tuple(steps), renamed, self.floor_z(level == "basic"))


def _distinct(lines: Sequence[_Line], tol: float) -> list[_Line]:
    out: list[_Line] = []
    for ln in lines:
        if not any(_same_segment(ln.start, ln.end, o.start, o.end, tol) for o in out):
            out.append(ln)
    return out


#: A part whose lines in the finished drawing total less than this on the sheet (mm) is not
#: constructed: a teacher does not block in what barely shows (:meth:`_Context.guided_parts`).
BARELY_MM = 10.0


def _ink_mm(strokes: Sequence[Stroke]) -> float:
    """Total length of ``strokes`` on the sheet, mm."""
    return float(sum(np.linalg.norm(np.diff(np.asarray(st.points_mm, dtype=float), axis=0),
                                    axis=1).sum() for st in strokes))


def _numbering(plan: Any, chosen: dict[str, Any]) -> list[str]:
    """The order parts called by a number are numbered in, the same in every view: the start
    part first (drawn first in every view), then larger before smaller (the selected boxes'
    largest faces), then by name."""
    first = start_part(plan.primitives)
    rest = sorted((p for p in chosen if p != first),
                  key=lambda p: (-part_size(chosen[p].box), natural_key(p)))
    return [first, *rest] if first in chosen else rest


def _context(plan: Any, view: ViewSpec, paper: PaperSpec, settings: SequenceSettings) -> _Context:
    adjusted = _adjusted_parts(plan)
    tol = _tolerance(plan)
    lines: dict[tuple[str, int], tuple] = {}
    camera = _fit_camera(plan, view, paper, adjusted, tol, lines)
    vps = vanishing_points(camera)
    chosen = plan.chosen()
    corners = np.vstack([_box_corners(c.box) for c in chosen.values()])
    bounds = (_vec(corners.min(axis=0)), _vec(corners.max(axis=0)))
    ctx = _Context(plan=plan, camera=camera, settings=settings, vps=vps,
                   words=_Words(camera, vps, bounds), tol=tol,
                   by_id={c.id: c for c in plan.candidates}, chosen=chosen, adjusted=adjusted,
                   _anchor_memo=lines,
                   originals={p.name: p for p in plan.model.parts},
                   names=display_names([p.name for p in plan.model.parts],
                                       label_format=templates.lookup("pages", "parts.label"),
                                       order=_numbering(plan, chosen)))
    return ctx
