"""Stage 4: candidate primitives, anchored off each other at easy ratios (paper §4.2, §4.4).

``generate_candidates(primitives, relations, settings)`` returns every way of drawing each part
that the selection stage (``h2s_print.select``) chooses from.  A :class:`Candidate` is an
adjusted axis-aligned box of one part plus the candidates it hangs off (its parents) and the
anchors that tie its interval ends to ratios of the parents' intervals.

What "anchored" means (the plan.json contract, DESIGN.md §3)
------------------------------------------------------------
Every axis of a child is treated independently; each *end* (``lo``/``hi``) of the child's
interval along an axis is either *anchored* or *free*.  An anchored end lies exactly at a ratio
of a parent candidate's interval along the **same** axis::

    child.box[e][axis] == parent.box[0][axis] + ratio * (parent.box[1][axis] - parent.box[0][axis])

(computed with exactly this expression, so the equality holds in floating point), ``ratio`` one
of the catalogue ratios of ``h2s_print.ratios`` (0, ¼, ⅓, ½, ⅔, ¾, 1 and the extrusions −1, −½,
3/2, 2).  Per axis a candidate is one of:

* **both ends anchored** (to the same parent or to two different parents, e.g. a shelf between
  two side panels): the axis is fully guided;
* **one end anchored, length kept**: the free end lies at the anchored end ± the input length
  (a cylinder's: ± the length its round cross-section needs, below); the position is guided,
  the length is estimated by eye;
* **unguided**: no end anchored (listed in ``unguided_axes``): the input interval, or the input
  interval moved toward a related parent's centre line (re-centred, below).

An axis of zero length (a plane's normal) stays of zero length: both ends are anchored at the
same value (two anchors with the same ratio), which guides it fully.

Cylinders stay round: a cylinder candidate's two extents across its axis keep the input's
proportion (square from the fit: equal) within :data:`ROUND` (1 %).  When the combined axes do
not, the axis with more anchored ends decides and the other takes the matching length, kept at
its anchored end or about its centre when unguided; two fully anchored axes that disagree make
no candidate.  (Before this rule the train's boiler came out 43.7 by 47.6 mm: an oval.)

Where anchors come from
-----------------------
Anchoring needs a *relation* between the child's part and the parent's part: a plane the two
share, on which a guide constructed on the parent reaches the child (guides transfer within a
plane).  Every relation offers one:

* **coplanar** normal to ``n`` (a shared face plane): the child's in-plane axes are anchored at
  ratios of the parent's extents, constructed on the parent's face in the shared plane
  (``face_normal = n``, ``face_side`` that face's end); the normal axis ``n`` is anchored at
  ratios of the parent's extent along ``n`` (flush with the shared plane at 0 or 1, or
  extruded/divided: "grip extended by ½ the depth of the body"), constructed on the larger
  parent face that contains ``n`` (``face_side`` left to the view);
* **bisector** normal to ``n`` (a *common bisector plane*, the paper's "the handle anchors the
  roller using the common bisector plane"): the same anchors, constructed on the parent's
  faces normal to ``n`` (``face_side`` left to the view) and carried to the shared mid-plane;
* **coaxial** (a shared axis, whose two cross mid-planes are common bisector planes): the same
  anchors, constructed on the parent's largest face that contains the anchored axis.

Besides the ends, an anchor may place the child's **mid-plane** (``end == "mid"``): the child
is centred on the parent's line at that ratio, typically on the parent's own mid-plane at ½
(found with the face's diagonals), and keeps its input length (estimated by eye).  With
``box`` the candidate's box and ``p`` the parent's: ``(box[0][axis] + box[1][axis]) / 2 ==
p[0][axis] + ratio * (p[1][axis] - p[0][axis])`` up to one rounding of the halving.

Bisector and coaxial relations also shape candidates in two more ways:

* **re-centring** (stage i): a child hanging off an *adjusted* parent candidate would break a
  preserved bisector or coaxial relation with it on an axis left at its input interval; so on
  those axes the child may also take its input interval moved toward the parent's mid-plane
  (onto it, or as far as ``settings.max_change`` allows: the relation's tolerance may cover
  the rest), still unguided, and only together with anchors off that same parent;
* **restoring** (paper stage ii): when a candidate ``C`` of part ``i`` breaks a preserved
  relation with part ``j``, candidates of ``j`` are made from ``j``'s input box, re-aligned to
  ``C`` (parent ``C``): for coplanar, its face is anchored to ``C``'s face (ratio 0 or 1) and
  the opposite face either moves with it (length kept) or stays; for bisector/coaxial, the
  relation's axes are anchored symmetrically at ``(r, 1 - r)`` of ``C`` (so the mid-planes
  coincide) or, failing that, re-centred on ``C`` as above.  Each other axis keeps its input
  interval or, when ``j`` is coplanar with ``i``, takes one of the best anchors off ``C`` (the
  camera's shutter button, re-centred on a moved grip, still sits flush on the grip's top).
  The ``RESTORED_PER_RELATION`` cheapest are kept.

The *start part* (``order.start_part``: the part a drawing teacher blocks in first, the
largest one or a large part standing on the ground) gets only its original: it is the root the
tutorial starts from, and the calibrated sheet's ground plane is its bottom.

Levels (paper stage iii): level 1 anchors off the input primitives ("originals"); level ``k``
anchors off the candidates of level ``k - 1`` and keeps only candidates that use at least one of
them.  ``settings.depth`` levels are made.  ``Candidate.depth`` is 0 for originals and
``1 + max(parent depths)`` otherwise.

Pruning keeps *diverse* candidates, not only the cheapest: per part and level the
``CANDIDATES_PER_PART`` kept, the ``RESTORE_PER_PART`` restored and the order in which the next
level's parents are offered are taken round-robin over the candidates' sets of ancestor parts
(the best of each set first).  A child hangs off the first ``PARENTS_PER_PART`` candidates of
a parent part that do not descend from the child itself.  Measured on the camera: the 16
cheapest prisms all hung off the flash, so the flash could hang off none of them.

Of a part's combinations of axis options, only those pruning could keep are built: cheapest
lower bound first, stopping once none left can be kept (``_Generator.build_cheapest``; the
same candidates as building all of them).

A candidate that could never be selected is dropped: one whose ancestors include two candidates
of one part or a candidate of its own part, or whose box breaks a preserved relation with an
ancestor (ancestors are always selected with it).

Off a selection (:func:`extend_candidates`, used by ``plan.choose``): the same levels are made
again with the selected candidates as the only first parents (the *seeds*), so pruning no
longer spends a part's few options on candidates that were not chosen (the IKEA table's leg
could reach the top's underside only in pairs with other legs' originals).  A candidate made
again is handed back as a parent of the next level; the next level hangs only off candidates
that cost less than their part's seed; one made again is not restored again.

Costs (unit-free, raw; weights apply in the selection objective)
----------------------------------------------------------------
``L`` is the input length of an axis (for a zero-length axis: ``THIN_FRACTION`` of the part's
largest extent).  Per axis: fully guided ``|Δlength|/L + |Δmidpoint|/L``; one end anchored
``|Δlength|/L + |Δmidpoint|/L + 1`` (a free end costs half an unguided axis); unguided ``2``.
``cost_adjust`` (E_d) is their sum; the original costs 6.  Candidates whose ``|Δlength|`` or
``|Δmidpoint|`` exceeds ``settings.max_change × L`` on any axis are discarded.

``cost_difficulty`` (E_e) = ``settings.guide_cost × Σ_faces lines × A_ref / A_face``: anchors
on the same parent candidate and construction face (``face_normal``, ``face_side``), along
either of the face's two axes, share construction lines, counted once
(``ratios.distinct_face_lines``: an anchor at ½ along x and one at ½ along y on the same face
draw the face's two diagonals once, 4 lines, not 6); ``A_ref`` is the largest face area of any
input primitive box and ``A_face`` the parent's construction face area (floored at 1e-6
``A_ref``).  An end aligned with a flat parent's plane (``face_normal == axis``) is a line of
its own.

Ids
---
The original's id is its part name (``"body"``).  Others are
``"<part><<parent parts joined by '+'>#<k>"``, e.g. ``"grip<body#3"`` or ``"lens<body+grip#1"``,
``k`` counting from 1 per prefix in generation order, which is deterministic (parts sorted, each
batch sorted by box and anchors).  The returned tuple is sorted by part, then original first,
then generation order.  An id that clashes with an existing one (a part named like a candidate,
``"lens<body#1"``) is a :class:`SelectionError`, never a silent replacement.
"""

from __future__ import annotations

import bisect
import functools
import heapq
import itertools
import logging
import math
from dataclasses import dataclass, field
from typing import Any, Iterable, Mapping, Sequence

import numpy as np

from .config import SolverSettings
from .errors import SelectionError
from .order import part_size, start_part
from .ratios import ALIGN_ONLY, CATALOGUE, distinct_face_lines, distinct_lines, entry_for
from .types import Box, Primitive, Relation

log = logging.getLogger(__name__)

ENDS = ("lo", "hi")
#: Interval points an anchor may place: an end, or the mid-plane (a common bisector plane).
POINTS = ("lo", "hi", "mid")
#: Fraction of a part's largest extent used as ``L`` for its zero-length axes.
THIN_FRACTION = 0.05
#: An extent below this fraction of the box's largest extent counts as zero.
DEGENERATE = 1e-9
#: Anchored options kept per axis and parent part set before combining axes ...
OPTIONS_PER_AXIS = 3
#: ... and per axis in all (so at most (1 + AXIS_OPTIONS)^3 combinations per part and level).
AXIS_OPTIONS = 6
#: Candidates kept per part and level (best weighted cost first).
CANDIDATES_PER_PART = 16
#: Candidates per part (of the previous level) that may act as parents of the next level.
PARENTS_PER_PART = 3
#: Candidates per part whose broken relations are restored (stage ii), best first.
RESTORE_PER_PART = 6
#: A cylinder candidate's two cross extents keep the input's proportion within this fraction.
ROUND = 0.01
#: Restored candidates kept per broken relation (the cheapest).
RESTORED_PER_RELATION = 4
#: Symmetric ratio pairs used to restore bisector and coaxial relations.
SYMMETRIC = ((-1.0, 2.0), (-0.5, 1.5), (0.0, 1.0), (0.25, 0.75), (1 / 3, 2 / 3))
_EPS = 1e-9
#: Pools of at most this many ends are ranked one row at a time (``_Generator.ranked_few``):
#: the array path's fixed cost (~0.2 ms) is most of a small pool's time.
SMALL_POOL = 24


# --------------------------------------------------------------------------- values


@dataclass(frozen=True, slots=True)
class Anchor:
    """One anchored interval end (DESIGN.md §3 ``anchors``).

    Attributes:
        axis: 0, 1 or 2.
        end: ``lo`` or ``hi``: which end of the child's interval.
        parent: the parent candidate's id.
        ratio: catalogue ratio of the parent's interval along ``axis`` (< 0 or > 1: extrusion).
        guide_lines: lines of the ratio's construction (``ratios.entry_for(ratio)``).
        face_normal: normal axis of the parent face the construction is drawn on (the face is
            spanned by ``axis`` and the remaining axis).  ``face_normal == axis`` means the
            parent is flat along ``axis`` and the end is aligned with its plane.
        face_side: ``lo``/``hi``: which of the two parent faces normal to ``face_normal`` (the
            shared coplanar plane), or ``None`` when either will do (the view decides).
    """

    axis: int
    end: str
    parent: str
    ratio: float
    guide_lines: int
    face_normal: int
    face_side: str | None = None

    def to_json(self) -> dict[str, Any]:
        """The plan.json ``anchors`` entry (plus ``face_normal`` and ``face_side``)."""
        return {"axis": self.axis, "end": self.end, "parent": self.parent,
                "ratio": self.ratio, "guide_lines": self.guide_lines,
                "face_normal": self.face_normal, "face_side": self.face_side}


@dataclass(frozen=True, slots=True)
class Candidate:
    """One way to draw a part: its adjusted box and what it hangs off.

    Attributes:
        id: stable, readable id (module docstring), e.g. ``"grip<body#3"``.
        part: the part's name.
        box: adjusted axis-aligned box, model units.
        original: True for the input primitive itself (all axes unguided).
        parents: candidate ids that must be drawn (and selected) first, sorted.
        depth: 0 for originals, else 1 + the largest parent depth.
        anchors: one per anchored interval end, sorted by (axis, end).
        unguided_axes: axes with no anchored end, sorted.
        cost_adjust: E_d, unit-free (module docstring).
        cost_difficulty: E_e, unit-free.
        primitive_type: the part's primitive type (``cuboid`` ...).
        axis: the primitive's axis (``None`` for cuboids and custom).
    """

    id: str
    part: str
    box: Box
    original: bool
    parents: tuple[str, ...]
    depth: int
    anchors: tuple[Anchor, ...]
    unguided_axes: tuple[int, ...]
    cost_adjust: float
    cost_difficulty: float
    primitive_type: str = "cuboid"
    axis: int | None = None

    def cost(self, weight_adjust: float = 1.0, weight_difficulty: float = 1.0) -> float:
        """Weighted cost ``w_a E_d + w_d E_e`` (the selection objective's term)."""
        return weight_adjust * self.cost_adjust + weight_difficulty * self.cost_difficulty

    def to_json(self) -> dict[str, Any]:
        """The plan.json ``candidates`` entry (plus ``primitive_type`` and ``axis``)."""
        return {
            "id": self.id,
            "part": self.part,
            "box": [list(self.box[0]), list(self.box[1])],
            "original": self.original,
            "parents": list(self.parents),
            "depth": self.depth,
            "anchors": [a.to_json() for a in self.anchors],
            "unguided_axes": list(self.unguided_axes),
            "cost_adjust": self.cost_adjust,
            "cost_difficulty": self.cost_difficulty,
            "primitive_type": self.primitive_type,
            "axis": self.axis,
        }


# --------------------------------------------------------------------------- relations


def _mid(box: Box, axis: int) -> float:
    return 0.5 * (box[0][axis] + box[1][axis])


def _close(x: float, y: float, tol: float) -> bool:
    return abs(x - y) <= tol + _EPS * max(1.0, abs(x), abs(y))


def relation_axes(relation: Relation) -> tuple[int, ...]:
    """Axes whose intervals decide whether ``relation`` holds."""
    if relation.type == "coaxial":
        return tuple(a for a in range(3) if a != relation.axis)
    return (relation.axis,)


def _relation_axis_holds(relation: Relation, axis: int, a_lo: float, a_hi: float,
                         b_lo: float, b_hi: float) -> bool:
    """Does ``relation`` hold along ``axis`` between intervals of part a and part b?

    Exact for coplanar and bisector.  For coaxial it is only *necessary* (one cross axis of the
    two; :func:`relation_holds` measures both together): per-axis pruning may use it.
    """
    if relation.type == "coplanar":
        if axis != relation.axis:
            return True
        fa = a_lo if relation.detail.get("a_end", "lo") == "lo" else a_hi
        fb = b_lo if relation.detail.get("b_end", "lo") == "lo" else b_hi
        return _close(fa, fb, relation.tolerance)
    if axis not in relation_axes(relation):
        return True
    return _close(0.5 * (a_lo + a_hi), 0.5 * (b_lo + b_hi), relation.tolerance)


def _relation_axis_holds_on(relation: Relation, axis: int, a_lo: Any, a_hi: Any, b_lo: Any,
                            b_hi: Any) -> Any:
    """:func:`_relation_axis_holds` on arrays of intervals (either side may be an array):
    the same arithmetic, element by element."""
    if relation.type == "coplanar":
        if axis != relation.axis:
            return True
        fa = a_lo if relation.detail.get("a_end", "lo") == "lo" else a_hi
        fb = b_lo if relation.detail.get("b_end", "lo") == "lo" else b_hi
    elif axis not in relation_axes(relation):
        return True
    else:
        fa, fb = 0.5 * (a_lo + a_hi), 0.5 * (b_lo + b_hi)
    return np.abs(fa - fb) <= relation.tolerance + _EPS * np.maximum(
        1.0, np.maximum(np.abs(fa), np.abs(fb)))


def _relation_decides(relation: Relation, axis: int) -> bool:
    """Whether :func:`_relation_axis_holds` along ``axis`` can be False for ``relation``."""
    if relation.type == "coplanar":
        return axis == relation.axis
    return axis in relation_axes(relation)


def relation_holds(relation: Relation, box_a: Box, box_b: Box) -> bool:
    """True when ``relation`` holds between boxes of its parts ``a`` and ``b``.

    coplanar: the two named faces' coordinates agree within ``relation.tolerance``; coaxial:
    the box centre lines along the axis are within the tolerance, Euclidean across the axis
    (``hypot(du, dv) <= tolerance``, as ``relate`` found it); bisector: the mid-planes along
    the axis agree.
    """
    if relation.type == "coaxial":
        u, v = relation_axes(relation)
        du = _mid(box_a, u) - _mid(box_b, u)
        dv = _mid(box_a, v) - _mid(box_b, v)
        scale = max(1.0, *(abs(x) for box in (box_a, box_b) for x in (*box[0], *box[1])))
        return math.hypot(du, dv) <= relation.tolerance + _EPS * scale
    return all(_relation_axis_holds(relation, ax, box_a[0][ax], box_a[1][ax],
                                    box_b[0][ax], box_b[1][ax]) for ax in relation_axes(relation))


def relation_holds_table(relation: Relation, boxes_a: Sequence[Box], boxes_b: Sequence[Box]
                         ) -> np.ndarray:
    """:func:`relation_holds` for every pair of ``boxes_a`` (rows) and ``boxes_b`` (columns),
    as a boolean array, with the same arithmetic (a coaxial pair near its tolerance is
    measured again with ``math.hypot``, so the answer is the same to the last bit)."""
    a = np.asarray(boxes_a, dtype=float).reshape(-1, 2, 3)
    b = np.asarray(boxes_b, dtype=float).reshape(-1, 2, 3)
    if relation.type != "coaxial":
        out = np.ones((len(a), len(b)), dtype=bool)
        for ax in relation_axes(relation):
            out &= _relation_axis_holds_on(relation, ax, a[:, 0, ax][:, None], a[:, 1, ax][:, None],
                                           b[:, 0, ax][None, :], b[:, 1, ax][None, :])
        return out
    u, v = relation_axes(relation)
    mid_a, mid_b = 0.5 * (a[:, 0] + a[:, 1]), 0.5 * (b[:, 0] + b[:, 1])
    du = mid_a[:, u][:, None] - mid_b[:, u][None, :]
    dv = mid_a[:, v][:, None] - mid_b[:, v][None, :]
    big_a = np.abs(a.reshape(len(a), 6)).max(axis=1, initial=0.0)
    big_b = np.abs(b.reshape(len(b), 6)).max(axis=1, initial=0.0)
    scale = np.maximum(1.0, np.maximum(big_a[:, None], big_b[None, :]))
    limit = relation.tolerance + _EPS * scale
    dist = np.hypot(du, dv)
    out = dist <= limit
    for i, j in zip(*np.nonzero(np.abs(dist - limit) <= 1e-12 * np.maximum(limit, 1e-300))):
        out[i, j] = math.hypot(float(du[i, j]), float(dv[i, j])) <= float(limit[i, j])
    return out


def _holds(relation: Relation, box_a: Box, box_b: Box) -> bool:
    """:func:`relation_holds` with its one-axis cases written out (the generator asks it
    hundreds of thousands of times): the same arithmetic, so the same answers."""
    if relation.type == "coaxial":
        return relation_holds(relation, box_a, box_b)
    axis = relation.axis
    if relation.type == "coplanar":
        fa = box_a[0 if relation.detail.get("a_end", "lo") == "lo" else 1][axis]
        fb = box_b[0 if relation.detail.get("b_end", "lo") == "lo" else 1][axis]
    else:
        fa = 0.5 * (box_a[0][axis] + box_a[1][axis])
        fb = 0.5 * (box_b[0][axis] + box_b[1][axis])
    return abs(fa - fb) <= relation.tolerance + _EPS * max(1.0, abs(fa), abs(fb))


def preserved_relations(relations: Iterable[Relation]) -> tuple[Relation, ...]:
    """The relations selection must keep (``detail["preserved"]`` true), sorted."""
    return tuple(sorted((r for r in relations if r.detail.get("preserved")),
                        key=lambda r: (r.a, r.b, r.type, r.axis)))


# --------------------------------------------------------------------------- generation


@dataclass(frozen=True, slots=True)
class _End:
    """A possible position of one interval end, anchored at a parent's ratio."""

    value: float
    anchor: Anchor
    parent_part: str
    face_area: float


@dataclass(frozen=True, slots=True)
class _AxisOption:
    """One way to place one axis interval of a child."""

    lo: float
    hi: float
    anchors: tuple[Anchor, ...]
    cost_adjust: float
    parents: tuple[tuple[str, str], ...]  # (part, candidate id), sorted
    areas: tuple[tuple[tuple[str, int, int, str | None], float], ...] = ()

    @property
    def unguided(self) -> bool:
        return not self.anchors


@dataclass(frozen=True, slots=True)
class _Lineage:
    """What a new candidate of a part learns from its parents alone (``_Generator.lineage``).

    Attributes:
        ancestry: part -> candidate id over all ancestors (shared: never to be changed).
        checks: the preserved relations with those ancestors, in ``_Context.preserved``
            order, each ``(relation, ancestor box, part is the relation's a, axis, point,
            ancestor's coordinate)``; ``point`` 0/1/2 reads the candidate's lo/hi/mid along
            ``axis`` (the one-axis relations, :func:`_holds`), -1 a coaxial one
            (:func:`relation_holds` on both boxes).
        depth: the candidate's depth, 1 + the parents' largest.
    """

    ancestry: dict[str, str]
    checks: tuple[tuple[Relation, Box, bool, int, int, float], ...]
    depth: int


@dataclass
class _Context:
    """Mutable bookkeeping while generating (never escapes this module)."""

    settings: SolverSettings
    prims: dict[str, Primitive]
    a_ref: float
    coplanar: dict[str, list[tuple[str, Relation]]]
    preserved: dict[str, list[tuple[str, Relation]]]
    preserved_pairs: dict[tuple[str, str], list[Relation]] = field(default_factory=dict)
    start: str | None = None
    cands: dict[str, Candidate] = field(default_factory=dict)
    order: list[str] = field(default_factory=list)
    ancestry: dict[str, dict[str, str]] = field(default_factory=dict)
    counters: dict[str, int] = field(default_factory=dict)
    seen: dict[tuple, str] = field(default_factory=dict)  # (part, box, parents) -> id
    # (part, parent ids) -> their lineage or None (_Generator.lineage): a stored
    # candidate's ancestry never changes, and a part's combinations share few parent sets
    # (a generated 40-part model: 122 268 asks, 19 147 distinct)
    merged: dict[tuple[str, tuple[str, ...]], _Lineage | None] = field(default_factory=dict)
    # anchor -> its code (_Generator.codes), and per code the anchor's face and its entry
    # on it, ``(face key, (ratio, across))`` (_anchor_face): equal anchors, one code
    anchor_codes: dict[Anchor, int] = field(default_factory=dict)
    anchor_faces: list[tuple[tuple[str, int, str, int], tuple[float, bool]]] = field(
        default_factory=list)
    # anchors' codes -> their E_e (_Generator.difficulty): combinations of one part's
    # per-axis options repeat anchor sets (a generated 40-part model: 69 119 asks, 45 037
    # distinct); keyed by codes, whose hash is a tuple of ints', not seven fields' an anchor
    difficulty: dict[tuple[int, ...], float] = field(default_factory=dict)
    # (face key, its anchors' (ratio, across)) -> the face's term of E_e (a stored
    # candidate's face never changes; the anchor sets above share their faces)
    face_terms: dict[tuple, float] = field(default_factory=dict)
    # (parent id, axis, shared plane, side) -> _Generator.parent_axis
    parent_axes: dict[tuple, tuple] = field(default_factory=dict)
    # part -> per axis (L, input length, input midpoint): the terms of _axis_cost
    axis_terms: dict[str, tuple[tuple[float, float, float], ...]] = field(default_factory=dict)
    # part -> its bit in sets of parts (_Generator.part_bits); candidate id -> its
    # ancestry's parts as bits (_Generator.ancestor_bits)
    part_bit: dict[str, int] = field(default_factory=dict)
    ancestor_bits: dict[str, int] = field(default_factory=dict)


def _extent(box: Box, axis: int) -> float:
    return box[1][axis] - box[0][axis]


def _largest_extent(box: Box) -> float:
    lo, hi = box
    return max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2])


def _norm_length(box: Box, axis: int) -> float:
    """``L`` of the cost and change limits (module docstring)."""
    big = _largest_extent(box)
    length = _extent(box, axis)
    if length <= DEGENERATE * big:
        return THIN_FRACTION * big
    return length


def _is_flat(box: Box, axis: int) -> bool:
    return _extent(box, axis) <= DEGENERATE * _largest_extent(box)


def _face_for(pbox: Box, axis: int, normal: int | None,
              side: str | None) -> tuple[int, str | None, float]:
    """Construction face on a parent box for anchoring ``axis``: (face_normal, side, area).

    ``normal`` is the shared coplanar plane's normal (``None``: no shared plane).
    """
    if _is_flat(pbox, axis):
        return axis, None, part_size(pbox)
    if normal is not None and normal != axis:
        u, v = (a for a in range(3) if a != normal)
        area = _extent(pbox, u) * _extent(pbox, v)
        if area > DEGENERATE * part_size(pbox):
            return normal, side, area
    others = [a for a in range(3) if a != axis]
    b = max(others, key=lambda a: (_extent(pbox, a), -a))
    face_normal = next(a for a in others if a != b)
    return face_normal, None, _extent(pbox, axis) * _extent(pbox, b)


def _point(box: Box, axis: int, end: str) -> float:
    """An interval's ``lo``, ``hi`` or ``mid`` coordinate along ``axis``."""
    if end == "mid":
        return _mid(box, axis)
    return box[0][axis] if end == "lo" else box[1][axis]


def _ratio_value(pbox: Box, axis: int, ratio: float) -> float:
    # Exactly the contract's expression, so plan.json readers can check it with ==.
    return pbox[0][axis] + ratio * (pbox[1][axis] - pbox[0][axis])


def _axis_cost(orig: Box, axis: int, lo: float, hi: float, n_free_ends: int) -> float:
    if n_free_ends >= 2:
        return 2.0
    length = _norm_length(orig, axis)
    d_len = abs((hi - lo) - _extent(orig, axis)) / length
    d_mid = abs(0.5 * (lo + hi) - _mid(orig, axis)) / length
    return d_len + d_mid + float(n_free_ends)


def _cost_of_axis(terms: tuple[float, float, float], lo: float, hi: float,
                  n_free_ends: int) -> float:
    """:func:`_axis_cost` from the input box's terms of the axis (``_Generator.axis_terms``):
    the same expressions in the same order, so the same cost to the last bit."""
    if n_free_ends >= 2:
        return 2.0
    length, extent, mid = terms
    return abs((hi - lo) - extent) / length + abs(0.5 * (lo + hi) - mid) / length + float(n_free_ends)


def _change_terms(orig: Box, axis: int, max_change: float) -> tuple[float, float, float]:
    """The per-part terms of :func:`_within_change`: the limit before rounding slack, the
    input interval's length and midpoint."""
    return max_change * _norm_length(orig, axis) * (1 + 1e-9), _extent(orig, axis), _mid(orig, axis)


def _within(terms: tuple[float, float, float], lo: float, hi: float) -> bool:
    """:func:`_within_change` from its per-part ``terms`` (:func:`_change_terms`)."""
    base, length, mid = terms
    limit = base + _EPS * max(1.0, abs(lo), abs(hi))
    return abs((hi - lo) - length) <= limit and abs(0.5 * (lo + hi) - mid) <= limit


def _within_change(orig: Box, axis: int, lo: float, hi: float, max_change: float) -> bool:
    return _within(_change_terms(orig, axis, max_change), lo, hi)


def _centred_on(orig: Box, axis: int, centre: float, max_change: float) -> tuple[float, float]:
    """The input interval moved toward ``centre``: onto it, or as far as ``max_change`` allows.

    Moving only part of the way still keeps a bisector or coaxial relation when the rest is
    within its tolerance (``build`` checks), and a small part can follow a larger one that moved
    by more than the small part's own change limit.
    """
    lo0, hi0 = orig[0][axis], orig[1][axis]
    limit = max_change * _norm_length(orig, axis)
    shift = min(max(centre - _mid(orig, axis), -limit), limit)
    return lo0 + shift, hi0 + shift


def _round_cross(prim: Primitive, box: Box, anchors: Sequence[Anchor],
                 max_change: float) -> Box | None:
    """``box`` with a cylinder's cross-section kept round, or None when it cannot be.

    The two extents across the axis must keep the input's proportion (square from the fit:
    equal) within :data:`ROUND`.  When they do not, the axis with more anchored ends decides and
    the other takes the matching length: kept at its anchored end, or about its centre when
    unguided.  Equally anchored axes that disagree (both fully anchored) cannot be rounded.
    """
    orig = prim.box
    u, v = (a for a in range(3) if a != prim.axis)
    ou, ov = _extent(orig, u), _extent(orig, v)
    lu, lv = _extent(box, u), _extent(box, v)
    if ou <= 0 or ov <= 0 or abs(lu * ov - lv * ou) <= ROUND * max(lu * ov, lv * ou):
        return box
    ends = {ax: {a.end for a in anchors if a.axis == ax} for ax in (u, v)}
    if len(ends[u]) == len(ends[v]):
        return None
    lead, follow = (u, v) if len(ends[u]) > len(ends[v]) else (v, u)
    length = _extent(box, lead) * _extent(orig, follow) / _extent(orig, lead)
    lo, hi = box[0][follow], box[1][follow]
    if ends[follow] == {"lo"}:
        hi = lo + length
    elif ends[follow] == {"hi"}:
        lo = hi - length
    else:
        mid = 0.5 * (lo + hi)
        lo, hi = mid - 0.5 * length, mid + 0.5 * length
    if not _within_change(orig, follow, lo, hi, max_change):
        return None
    new_lo, new_hi = list(box[0]), list(box[1])
    new_lo[follow], new_hi[follow] = lo, hi
    return (tuple(new_lo), tuple(new_hi))  # type: ignore[return-value]


class _Settling:
    """What :meth:`_Generator.build_cheapest` knows of the candidates it built, kept up as the
    bound grows: those cheaper than every bound left are *settled*, counted per ancestor-part
    set; the others wait in a heap by cost."""

    def __init__(self, left: dict[int, int]):
        self.left = left  # combinations not built yet, per set (updated by the caller)
        self.waiting: list[tuple[float, int, int]] = []  # (cost, seq, set), a heap
        self.waits: dict[int, int] = {}
        self.settled: dict[int, int] = {}
        self.total = 0
        self.added = 0

    def add(self, cost: float, group: int) -> None:
        self.added += 1
        heapq.heappush(self.waiting, (cost, self.added, group))
        self.waits[group] = self.waits.get(group, 0) + 1

    def decided(self, low: float, k: int, diverse: bool) -> bool:
        """True when no combination of bound ``low`` or more can be kept (the rule in
        :meth:`_Generator.build_cheapest`)."""
        while self.waiting and self.waiting[0][0] < low:
            _, _, g = heapq.heappop(self.waiting)
            self.waits[g] -= 1
            self.settled[g] = self.settled.get(g, 0) + 1
            self.total += 1
        if not diverse:
            return self.total >= k
        # m: the least settled count over the sets that still have others (combinations
        # not built, or built and waiting); a set of none settled makes it 0, the least
        # there is, so the search stops there (most sets have none settled)
        settled, m = self.settled, None
        for counts in (self.left, self.waits):
            for g, n in counts.items():
                if n:
                    got = settled.get(g, 0)
                    m = got if m is None else min(m, got)
                    if m == 0:
                        break
            if m == 0:
                break
        if m is None:
            return True
        # the sum never exceeds the settled ones in all (self.total)
        return self.total >= k and sum(min(n, m + 1) for n in settled.values()) >= k


@dataclass(frozen=True, slots=True)
class _Facts:
    """What :meth:`_Generator.build_cheapest` reads off one axis option, once per option (a
    part's hundreds of combinations share a few options per axis).

    Attributes:
        codes: its anchors' codes (``_Generator.codes``).
        ordered: its anchors sorted by :func:`_anchor_key`.
        parents: its anchors' parent ids.
        reach: the ancestor parts its anchors bring, as bits (``_Generator.part_bits``).
        difficulty: its own E_e (0 unanchored).
        cost_adjust: its axis cost (``_AxisOption.cost_adjust``).
        anchored: whether it has anchors (its axis is not unguided).
    """

    codes: tuple[int, ...]
    ordered: tuple[Anchor, ...]
    parents: frozenset[str]
    reach: int
    difficulty: float
    cost_adjust: float
    anchored: bool


#: The unguided axes of a combination by whether each axis's option is anchored.
_UNGUIDED = {flags: tuple(ax for ax in range(3) if not flags[ax])
             for flags in itertools.product((False, True), repeat=3)}


class _TooMany(SelectionError):
    """More candidates than ``settings.max_candidates`` (internal: :func:`extend_candidates`
    gives up quietly, :func:`generate_candidates` lets it through as the user's error)."""


class _Generator:
    def __init__(self, ctx: _Context):
        self.ctx = ctx
        s = ctx.settings
        self.w_a, self.w_d = s.weight_adjust, s.weight_difficulty

    # ------------------------------------------------------------------ bookkeeping
    def lineage(self, part: str, parent_ids: Sequence[str]) -> _Lineage | None:
        """The merged ancestry of ``part``'s candidate off ``parent_ids`` with what follows
        from it, or None when inconsistent (two candidates of one part, or one of ``part``
        itself); remembered per (part, parent ids)."""
        key = (part, tuple(parent_ids))
        known = self.ctx.merged.get(key, self)  # a lineage, None, or self: not asked yet
        if known is not self:
            return known  # type: ignore[return-value]
        merged: dict[str, str] | None = {}
        for pid in parent_ids:
            for p, c in self.ctx.ancestry[pid].items():
                if p == part or merged.setdefault(p, c) != c:
                    merged = None
                    break
            if merged is None:
                break
        found = None
        if merged is not None:
            checks = []
            for other, rel in self.ctx.preserved.get(part, ()):
                cid = merged.get(other)
                if cid is None:
                    continue
                obox, here_is_a = self.ctx.cands[cid].box, rel.a == part
                if rel.type == "coaxial":
                    checks.append((rel, obox, here_is_a, 0, -1, 0.0))
                    continue
                if rel.type == "coplanar":
                    mine = rel.detail.get("a_end" if here_is_a else "b_end", "lo")
                    theirs = rel.detail.get("b_end" if here_is_a else "a_end", "lo")
                    point = 0 if mine == "lo" else 1
                    value = obox[0 if theirs == "lo" else 1][rel.axis]
                else:
                    point, value = 2, 0.5 * (obox[0][rel.axis] + obox[1][rel.axis])
                checks.append((rel, obox, here_is_a, rel.axis, point, value))
            found = _Lineage(merged, tuple(checks),
                             1 + max(self.ctx.cands[p].depth for p in parent_ids))
        self.ctx.merged[key] = found
        return found

    @staticmethod
    def keeps_relations(box: Box, lineage: _Lineage) -> bool:
        """Does ``box`` keep every preserved relation with the ancestors of ``lineage``?

        :func:`_holds` with the ancestor's side read once per lineage: the same arithmetic
        (``|x - y|`` is ``|y - x|`` and ``max`` does not depend on its arguments' order),
        so the same answers."""
        for rel, obox, here_is_a, axis, point, theirs in lineage.checks:
            if point < 0:
                if not (relation_holds(rel, box, obox) if here_is_a
                        else relation_holds(rel, obox, box)):
                    return False
                continue
            mine = box[point][axis] if point < 2 else 0.5 * (box[0][axis] + box[1][axis])
            if not abs(mine - theirs) <= rel.tolerance + _EPS * max(1.0, abs(mine), abs(theirs)):
                return False
        return True

    def add_original(self, prim: Primitive) -> None:
        cand = Candidate(id=prim.part, part=prim.part, box=prim.box, original=True, parents=(),
                         depth=0, anchors=(), unguided_axes=(0, 1, 2), cost_adjust=6.0,
                         cost_difficulty=0.0, primitive_type=prim.type, axis=prim.axis)
        self.ctx.cands[cand.id] = cand
        self.ctx.order.append(cand.id)
        self.ctx.ancestry[cand.id] = {prim.part: cand.id}

    def codes(self, anchors: Iterable[Anchor]) -> tuple[int, ...]:
        """Each anchor's code, in order: equal anchors have equal codes (numbered as first
        met, per generator), so equal code tuples are equal anchor tuples."""
        table, faces = self.ctx.anchor_codes, self.ctx.anchor_faces
        out = []
        for a in anchors:
            code = table.get(a)
            if code is None:
                code = table[a] = len(faces)
                faces.append(_anchor_face(a))
            out.append(code)
        return tuple(out)

    def difficulty(self, anchors: Sequence[Anchor]) -> float:
        """E_e of a set of anchors (module docstring, *Costs*): :meth:`coded_difficulty` of
        their codes."""
        return self.coded_difficulty(self.codes(anchors))

    def coded_difficulty(self, codes: tuple[int, ...]) -> float:
        """E_e of the anchors of ``codes`` (:meth:`codes`).

        Anchors on one parent face share construction lines, across both of the face's axes
        (its diagonals serve both): counted once with ``ratios.distinct_face_lines``.
        Remembered per anchors (in their order, which the sum follows).
        """
        memo = self.ctx.difficulty
        cost = memo.get(codes)
        if cost is not None:
            return cost
        groups: dict[tuple[str, int, str, int], list[tuple[float, bool]]] = {}
        faces = self.ctx.anchor_faces
        for code in codes:
            key, entry = faces[code]
            groups.setdefault(key, []).append(entry)
        total = 0.0
        terms = self.ctx.face_terms
        for key in sorted(groups):
            face = (key, tuple(groups[key]))
            term = terms.get(face)
            if term is None:
                pid, normal, _, axis = key
                area = _face_area_of(self.ctx.cands[pid].box, axis, normal)
                term = terms[face] = (_face_lines_of(face[1]) * self.ctx.a_ref
                                      / max(area, 1e-6 * self.ctx.a_ref))
            total += term
        cost = memo[codes] = self.ctx.settings.guide_cost * total
        return cost

    def adjust_cost(self, part: str, box: Box, anchors: Sequence[Anchor]) -> float:
        """E_d of a box of ``part`` against its input box, given which ends are anchored:
        :func:`_axis_cost` summed over the axes, its input box's terms found once per part
        (the same expressions in the same order, so the same E_d: the test's reference sums
        ``_axis_cost`` itself)."""
        terms = self.axis_terms(part)
        ends: tuple[set[str], set[str], set[str]] = (set(), set(), set())
        for a in anchors:
            ends[a.axis].add(a.end)
        total = 0.0
        for axis in range(3):
            total += _cost_of_axis(terms[axis], box[0][axis], box[1][axis], 2 - len(ends[axis]))
        return total

    def axis_terms(self, part: str) -> tuple[tuple[float, float, float], ...]:
        """Per axis of ``part``'s input box, the terms of :func:`_axis_cost` (L, length,
        midpoint), found once per part."""
        terms = self.ctx.axis_terms.get(part)
        if terms is None:
            orig = self.ctx.prims[part].box
            terms = self.ctx.axis_terms[part] = tuple(
                (_norm_length(orig, ax), _extent(orig, ax), _mid(orig, ax)) for ax in range(3))
        return terms

    def build(self, part: str, box: Box, anchors: Sequence[Anchor],
              extra_parents: Sequence[str] = (),
              axis_costs: tuple[float, float, float] | None = None
              ) -> tuple[Candidate, dict] | None:
        """A new (unnamed) candidate, or None when it can never be selected.

        A cylinder's cross-section is made round first (:func:`_round_cross`).  ``E_d`` and the
        unguided axes follow from the box and the anchors (module docstring, *Costs*).
        ``axis_costs``: the axes' costs when ``box`` is made of axis options (their
        ``cost_adjust``: :func:`_axis_cost` of the interval with as many free ends as the
        option's anchors leave), so E_d is their sum in axis order, as
        :meth:`adjust_cost` sums it, unless rounding moved an axis.
        """
        axes = {a.axis for a in anchors}
        return self.make(part, box, anchors,
                         tuple(sorted({a.parent for a in anchors} | set(extra_parents))),
                         tuple(sorted(anchors, key=_anchor_key)),
                         tuple(ax for ax in range(3) if ax not in axes), self.codes(anchors),
                         axis_costs)

    def make(self, part: str, box: Box, anchors: Sequence[Anchor], parent_ids: tuple[str, ...],
             ordered: tuple[Anchor, ...], unguided: tuple[int, ...], codes: tuple[int, ...],
             axis_costs: tuple[float, float, float] | None) -> tuple[Candidate, dict] | None:
        """:meth:`build` given what it reads off the anchors: the parent ids (sorted, with
        the extra parents), the anchors sorted by :func:`_anchor_key`, the unguided axes and
        the anchors' codes (:meth:`build_cheapest` puts them together from its options')."""
        prim = self.ctx.prims[part]
        lineage = self.lineage(part, parent_ids)  # remembered: the cheapest test
        if lineage is None:
            return None
        given = box
        if prim.type == "cylinder" and prim.axis is not None:
            box = _round_cross(prim, box, anchors, self.ctx.settings.max_change)
            if box is None:
                return None
        if not self.keeps_relations(box, lineage):
            return None
        if axis_costs is not None and box is given:  # not rounded (_round_cross returns it)
            cost_adjust = 0.0 + axis_costs[0] + axis_costs[1] + axis_costs[2]
        else:
            cost_adjust = self.adjust_cost(part, box, anchors)
        cand = Candidate(id="", part=part, box=box, original=False, parents=parent_ids,
                         depth=lineage.depth, anchors=ordered, unguided_axes=unguided,
                         cost_adjust=cost_adjust, cost_difficulty=self.coded_difficulty(codes),
                         primitive_type=prim.type, axis=prim.axis)
        return cand, lineage.ancestry

    def commit(self, batch: list[tuple[Candidate, dict]], again: bool = False
               ) -> list[Candidate]:
        """Name, dedupe and store a batch of new candidates; returns the stored ones, and with
        ``again`` (off a selection) also those stored before that the batch made again."""
        # Same part, box and parents: keep the cheapest way of anchoring it.
        best: dict[tuple, tuple[Candidate, dict]] = {}
        stored: set[str] = set()
        for cand, ancestry in batch:
            key = (cand.part, cand.box, cand.parents)
            if key in self.ctx.seen:
                stored.add(self.ctx.seen[key])
                continue
            old = best.get(key)
            if old is None:
                best[key] = (cand, ancestry)
                continue
            # (cost, sort key) below the old one's, the keys made only on a tie of costs
            cost, old_cost = cand.cost(self.w_a, self.w_d), old[0].cost(self.w_a, self.w_d)
            if (cost < old_cost if cost != old_cost
                    else _cand_sort_key(cand) < _cand_sort_key(old[0])):
                best[key] = (cand, ancestry)
        out: list[Candidate] = []
        for key in sorted(best, key=lambda k: _cand_sort_key(best[k][0])):
            cand, ancestry = best[key]
            parts = sorted({self.ctx.cands[p].part for p in cand.parents})
            prefix = f"{cand.part}<{'+'.join(parts)}"
            k = self.ctx.counters.get(prefix, 0) + 1
            self.ctx.counters[prefix] = k
            named = _replace_id(cand, f"{prefix}#{k}")
            self.ctx.seen[key] = named.id
            if named.id in self.ctx.cands:
                raise SelectionError(
                    f"candidate id {named.id!r} (a candidate of part {cand.part!r}) clashes with "
                    f"an existing candidate or part name; part names must not look like "
                    f"candidate ids (no '<' or '#')")
            self.ctx.cands[named.id] = named
            self.ctx.order.append(named.id)
            self.ctx.ancestry[named.id] = {**ancestry, cand.part: named.id}
            out.append(named)
        if again:  # made again off this round's parents: they parent the next level
            out += sorted((self.ctx.cands[i] for i in stored), key=_cand_sort_key)
        limit = self.ctx.settings.max_candidates
        if len(self.ctx.cands) > limit:
            raise _TooMany(
                f"candidate generation made more than solver.max_candidates = {limit} "
                f"candidates ({len(self.ctx.cands)} so far, {len(self.ctx.prims)} parts); "
                "raise solver.max_candidates or lower solver.depth")
        return out

    # ------------------------------------------------------------------ stage (i)
    def usable(self, part: str, pool: Sequence[str]) -> list[str]:
        """The pool candidates ``part`` may hang off: originals and the first
        ``PARENTS_PER_PART`` others (in pool order, cheapest first) that do not descend from
        a candidate of ``part`` (which would be a cycle)."""
        out: list[str] = []
        n = 0
        for pid in pool:
            cand = self.ctx.cands[pid]
            if cand.original:
                out.append(pid)
            elif n < PARENTS_PER_PART and part not in self.ctx.ancestry[pid]:
                out.append(pid)
                n += 1
        return out

    def end_options(self, part: str, parent_pool: Mapping[str, Sequence[str]],
                    axes: Sequence[int] = (0, 1, 2)) -> list[dict[str, list[_End]]]:
        """Per axis, per end: every anchored position within reach of the change limit
        (only along ``axes``: the others' are left empty)."""
        orig = self.ctx.prims[part].box
        mc = self.ctx.settings.max_change
        # per axis: (end, parent id, ratio) -> (rank of its face, value, parent part, face
        # area, face normal, face side, guide lines); the anchors are made once, at the end
        found: list[dict[tuple, tuple]] = [{} for _ in range(3)]
        # per axis: each interval point's input coordinate, how far an anchor may move it,
        # and the window of values tested (a little wider than the reach: the catalogue's
        # ratios ascend, so the values do; those in it are tested exactly, below)
        targets: list[list[tuple[str, float, float, float, float]]] = [[], [], []]
        for axis in axes:
            reach = 1.5 * mc * _norm_length(orig, axis) * (1 + 1e-9)
            reach_mid = mc * _norm_length(orig, axis) * (1 + 1e-9)
            for end in POINTS:
                target, r = _point(orig, axis, end), reach_mid if end == "mid" else reach
                slack = 1e-9 * (abs(target) + r)
                targets[axis].append((end, target, r, target - r - slack, target + r + slack))
        for parent_part, rel in self.ctx.coplanar.get(part, ()):
            if not parent_pool.get(parent_part):
                continue
            side = (rel.detail.get("b_end" if rel.a == part else "a_end")
                    if rel.type == "coplanar" else None)
            plane = None if rel.type == "coaxial" else rel.axis
            for pid in self.usable(part, parent_pool[parent_part]):
                for axis in axes:
                    normal, fside, area, entries, values = self.parent_axis(pid, axis, plane,
                                                                            side)
                    better = (area, fside is not None)
                    at = found[axis]
                    for end, target, reach, low, high in targets[axis]:
                        # each key is met once here, so the order they are met in is the same
                        for k in range(bisect.bisect_left(values, low),
                                       bisect.bisect_right(values, high)):
                            value, entry = values[k], entries[k]
                            if abs(value - target) > reach:
                                continue
                            key = (end, pid, entry.ratio)
                            old = at.get(key)
                            # prefer the larger face; on a tie, the shared plane itself
                            if old is None or better > old[0]:
                                at[key] = (better, value, parent_part, area, normal, fside,
                                           entry.guide_lines)
        out: list[dict[str, list[_End]]] = []
        for axis in range(3):
            per_end: dict[str, list[_End]] = {"lo": [], "hi": [], "mid": []}
            for key in sorted(found[axis]):  # (end, parent id, ratio)
                end, pid, ratio = key
                _, value, parent_part, area, normal, fside, lines = found[axis][key]
                per_end[end].append(_End(value, Anchor(axis, end, pid, ratio, lines, normal,
                                                       fside), parent_part, area))
            out.append(per_end)
        return out

    def parent_axis(self, pid: str, axis: int, plane: int | None, side: str | None
                    ) -> tuple[int, str | None, float, Sequence[Any], list[float]]:
        """What :meth:`end_options` reads off a parent candidate's axis: its construction face
        (:func:`_face_for`: normal, side, area), the catalogue entries that apply and their
        values.  Remembered: a stored candidate's box never changes, and it is offered as
        a parent to many parts at every level."""
        key = (pid, axis, plane, side)
        found = self.ctx.parent_axes.get(key)
        if found is None:
            pbox = self.ctx.cands[pid].box
            entries = ALIGN_ONLY if _is_flat(pbox, axis) else CATALOGUE
            found = self.ctx.parent_axes[key] = (
                *_face_for(pbox, axis, plane, side), entries,
                [_ratio_value(pbox, axis, entry.ratio) for entry in entries])
        return found

    def ranked_axis_options(self, part: str, axis: int, ends: Mapping[str, list[_End]],
                            fresh: frozenset[str], per_group: int, total: int | None
                            ) -> list[_AxisOption]:
        """The anchored options of one axis that pruning keeps, cheapest first.

        Every option is an interval of the axis with one or two anchored ends (a pair of
        ``lo``/``hi`` ends, or one end and the input length); it is valid when it stays within
        the change limit and keeps, along the axis, the preserved relations with its parents'
        candidates.  Its rank is ``(w_a E_d + w_d E_e, lo, hi, anchor keys)``: E_d the axis
        cost (:func:`_axis_cost`), E_e ``guide_cost`` times the sum over its parent faces of
        ``distinct_lines(ratios on the face) * A_ref / A_face``.  Options are grouped by the
        set of parent parts they hang off (with ``fresh`` set, options using a fresh parent
        form groups of their own).  Returned: the first ``per_group`` valid options of each
        group, then of those the first ``total`` by (place in group, rank), in rank order (the
        round-robin keeps alternatives off different parts, which relation preservation and
        later levels need); with ``total`` None simply the first ``per_group`` valid options.

        Validity, costs and ranks are computed on arrays, and only the options kept are built:
        a big part has up to a million pairs of anchored ends, of which a few are kept (the
        80-part generated model's candidates 11.3 -> 5.3 s, identical).  The straightforward
        version, one option at a time, is the test's reference
        (``test_candidates.test_ranked_axis_options_equal_the_definition``).
        """
        orig = self.ctx.prims[part].box
        mc = self.ctx.settings.max_change
        lo0, hi0 = orig[0][axis], orig[1][axis]
        length = hi0 - lo0
        pool: list[_End] = []  # every end, indexed
        for key in ("lo", "hi", "mid"):
            pool += ends[key]
        if not pool:
            return []
        n_lo, n_hi = len(ends["lo"]), len(ends["hi"])
        if len(pool) <= SMALL_POOL:
            return self.ranked_few(part, axis, pool, n_lo, n_hi, fresh, per_group, total)
        value = np.array([e.value for e in pool])
        pp = self._codes([e.parent_part for e in pool])  # parent part, by code
        parent = self._codes([e.anchor.parent for e in pool])  # parent candidate, by code
        # rows: (first end, second end or -1, lo, hi, free ends); the flat case pairs an end
        # with its own twin (second end == first end, said as lo and hi)
        if _is_flat(orig, axis):
            first = np.arange(n_lo)
            second = first.copy()
            los, his, free = value[:n_lo], value[:n_lo], np.zeros(n_lo)
        else:
            li, hj = np.arange(n_lo), np.arange(n_lo, n_lo + n_hi)
            lv, hv = value[li][:, None], value[hj][None, :]
            base, ext, mid = _change_terms(orig, axis, mc)
            limit = base + _EPS * np.maximum(1.0, np.maximum(np.abs(lv), np.abs(hv)))
            near = ((np.abs((hv - lv) - ext) <= limit) & (np.abs(0.5 * (lv + hv) - mid) <= limit))
            a, b = np.nonzero(near)
            pi, pj = li[a], hj[b]
            ok = ~((pp[pi] == pp[pj]) & (parent[pi] != parent[pj]))
            ok &= ~(value[pj] - value[pi] <= DEGENERATE * max(length, 1e-300))
            pi, pj = pi[ok], pj[ok]
            singles = np.arange(len(pool))
            kind = np.array([0] * n_lo + [1] * n_hi + [2] * (len(pool) - n_lo - n_hi))
            s_lo = np.where(kind == 0, value, np.where(kind == 1, value - length,
                                                       value - 0.5 * length))
            s_hi = np.where(kind == 0, value + length, np.where(kind == 1, value,
                                                                value + 0.5 * length))
            first = np.concatenate([pi, singles])
            second = np.concatenate([pj, np.full(len(pool), -1)])
            los = np.concatenate([value[pi], s_lo])
            his = np.concatenate([value[pj], s_hi])
            free = np.concatenate([np.zeros(len(pi)), np.ones(len(pool))])
        if not len(first):
            return []
        # validity within the change limit (_within, on arrays); every later test, cost and
        # rank only on the rows that pass it (the ranks' ties go by row order either way)
        base, ext, mid = _change_terms(orig, axis, mc)
        limit = base + _EPS * np.maximum(1.0, np.maximum(np.abs(los), np.abs(his)))
        keep = np.nonzero((np.abs((his - los) - ext) <= limit)
                          & (np.abs(0.5 * (los + his) - mid) <= limit))[0]
        if not len(keep):
            return []
        first, second, los, his, free = (first[keep], second[keep], los[keep], his[keep],
                                         free[keep])
        two = second >= 0
        sec = np.where(two, second, first)
        # along this axis, the preserved relations with the parents (per parent candidate):
        # each parent candidate's rows found once from rows sorted by it, not by a mask over
        # every row per parent (a big part has hundreds of parents and 10^4-10^5 rows)
        valid = np.ones(len(first), dtype=bool)
        pairs = self.preserved_pairs()
        codes, at_first = np.unique(parent, return_index=True)
        checks = []
        for c, e in zip(codes.tolist(), at_first.tolist()):
            rels = [rel for rel in pairs.get((part, pool[e].parent_part), ())
                    if _relation_decides(rel, axis)]
            if rels:
                checks.append((c, e, rels))
        if checks:
            p_first = parent[first]
            p_sec = np.where(two & (parent[sec] != p_first), parent[sec], -1)
            by_first, by_sec = np.argsort(p_first, kind="stable"), np.argsort(p_sec, kind="stable")
            sorted_first, sorted_sec = p_first[by_first], p_sec[by_sec]
            for c, e, rels in checks:
                i0, i1 = np.searchsorted(sorted_first, [c, c + 1])
                j0, j1 = np.searchsorted(sorted_sec, [c, c + 1])
                if i0 == i1 and j0 == j1:
                    continue
                uses = np.concatenate([by_first[i0:i1], by_sec[j0:j1]])  # disjoint rows
                pbox = self.ctx.cands[pool[e].anchor.parent].box
                p_lo, p_hi = pbox[0][axis], pbox[1][axis]
                o_lo, o_hi = los[uses], his[uses]
                ok = np.ones(len(uses), dtype=bool)
                for rel in rels:
                    ok &= (_relation_axis_holds_on(rel, axis, o_lo, o_hi, p_lo, p_hi)
                           if rel.a == part
                           else _relation_axis_holds_on(rel, axis, p_lo, p_hi, o_lo, o_hi))
                valid[uses] &= ok
        # costs and ranks only of the valid rows (kept in row order: ties go by it)
        rows_ok = np.flatnonzero(valid)
        if not len(rows_ok):
            return []
        first, second, sec, two, los, his, free = (
            first[rows_ok], second[rows_ok], sec[rows_ok], two[rows_ok], los[rows_ok],
            his[rows_ok], free[rows_ok])
        # E_d of the axis (_axis_cost) and E_e (the construction lines)
        norm = _norm_length(orig, axis)
        cost = (np.abs((his - los) - _extent(orig, axis)) / norm
                + np.abs(0.5 * (los + his) - _mid(orig, axis)) / norm + free)
        a_ref, floor = self.ctx.a_ref, 1e-6 * self.ctx.a_ref
        face = self._codes([(e.anchor.parent, e.anchor.face_normal, e.anchor.face_side)
                            for e in pool])
        # lines per ratio and per pair of ratios, looked up by the ratios' codes (a few
        # catalogue ratios recur in every pool)
        ratios: dict[float, int] = {}
        r_code = np.array([ratios.setdefault(e.anchor.ratio, len(ratios)) for e in pool],
                          dtype=np.int64)
        distinct = list(ratios)
        area = np.array([max(e.face_area, floor) for e in pool])
        one = _pair_lines(tuple(distinct)).diagonal()[r_code] * a_ref / area
        shared = two & (face[first] == face[sec])
        both = np.where(shared, _pair_lines(tuple(distinct))[r_code[first], r_code[sec]], 0.0)
        diff = np.where(shared, both * a_ref / area[sec],
                        one[first] + np.where(two & ~shared, one[sec], 0.0))
        diff = diff * self.ctx.settings.guide_cost
        score = self.w_a * cost + self.w_d * diff
        # ties on (score, lo, hi) go by the anchors' keys: each end's key ranked
        # once, a single end before any pair it starts
        keys = [_anchor_key(e.anchor) for e in pool]
        key_rank = np.empty(len(pool), dtype=np.int64)
        key_rank[sorted(range(len(pool)), key=keys.__getitem__)] = np.arange(len(pool))
        r_first = key_rank[first]
        r_second = np.where(two & (second != first), key_rank[sec], -1)
        order = np.lexsort((r_second, r_first, his, los, score))
        if not len(order):
            return []
        # groups: the parent parts used, and whether a fresh parent is among them
        if total is None:
            group = np.zeros(len(order), dtype=np.int64)
        else:
            g_first, g_second = pp[first], np.where(two, pp[sec], -1)
            g_lo = np.minimum(g_first, np.where(two, g_second, g_first))
            g_hi = np.maximum(g_first, g_second)
            is_fresh = np.array([bool(fresh) and e.anchor.parent in fresh for e in pool])
            g_fresh = is_fresh[first] | (two & is_fresh[sec])
            n_codes = int(pp.max()) + 2  # codes and the -1 of a single end
            group = (((g_lo + 1) * n_codes + (g_hi + 1)) * 2 + g_fresh)[order]
        # each option's place in its group (0 for its group's cheapest); the first
        # ``per_group`` of each group are kept, then of those the first ``total`` by
        # (place, rank), returned in rank order
        by_group = np.argsort(group, kind="stable")
        sorted_groups = group[by_group]
        starts = np.flatnonzero(np.concatenate(([True], sorted_groups[1:] != sorted_groups[:-1])))
        sizes = np.diff(np.append(starts, len(order)))
        place = np.empty(len(order), dtype=np.int64)
        place[by_group] = np.arange(len(order)) - np.repeat(starts, sizes)
        kept_at = np.flatnonzero(place < per_group)
        if total is not None:
            kept_at = np.sort(kept_at[np.lexsort((kept_at, place[kept_at]))][:total])
        rows = order[kept_at].tolist()
        terms = self.axis_terms(part)[axis]
        return [self._option(pool, int(first[x]), int(second[x]), float(los[x]),
                             float(his[x]), int(free[x]), axis, terms) for x in rows]

    def ranked_few(self, part: str, axis: int, pool: Sequence[_End], n_lo: int, n_hi: int,
                   fresh: frozenset[str], per_group: int, total: int | None
                   ) -> list[_AxisOption]:
        """:meth:`ranked_axis_options` of a small ``pool`` (its ``lo``, ``hi`` then ``mid``
        ends), one row at a time: the same rows in the same order, the same float
        expressions (numpy's elementwise ``+ - * /``, ``abs`` and ``maximum`` round as
        Python's do) and the same total order of ranks, so the same options.  Restoring asks
        thousands of times with a handful of ends, where the arrays' fixed cost is most of
        the time (the test compares this path with the definition too)."""
        orig = self.ctx.prims[part].box
        terms = _change_terms(orig, axis, self.ctx.settings.max_change)
        length = orig[1][axis] - orig[0][axis]
        rows: list[tuple[int, int, float, float, float]] = []  # (first, second, lo, hi, free)
        if _is_flat(orig, axis):  # an end paired with its own twin
            rows = [(i, i, pool[i].value, pool[i].value, 0.0) for i in range(n_lo)]
        else:
            degenerate = DEGENERATE * max(length, 1e-300)
            for i in range(n_lo):
                e = pool[i]
                for j in range(n_lo, n_lo + n_hi):
                    f = pool[j]
                    if (_within(terms, e.value, f.value)
                            and not (e.parent_part == f.parent_part
                                     and e.anchor.parent != f.anchor.parent)
                            and not f.value - e.value <= degenerate):
                        rows.append((i, j, e.value, f.value, 0.0))
            for i, e in enumerate(pool):
                v = e.value
                if i < n_lo:
                    rows.append((i, -1, v, v + length, 1.0))
                elif i < n_lo + n_hi:
                    rows.append((i, -1, v - length, v, 1.0))
                else:
                    rows.append((i, -1, v - 0.5 * length, v + 0.5 * length, 1.0))
        pairs = self.preserved_pairs()
        checks: dict[str, tuple[list[Relation], float, float]] = {}  # parent id -> relations
        for e in pool:
            pid = e.anchor.parent
            if pid not in checks:
                pbox = self.ctx.cands[pid].box
                checks[pid] = ([rel for rel in pairs.get((part, e.parent_part), ())
                                if _relation_decides(rel, axis)], pbox[0][axis], pbox[1][axis])

        def keeps(pid: str, lo: float, hi: float) -> bool:
            rels, p_lo, p_hi = checks[pid]
            return not rels or all(_relation_axis_holds(rel, axis, lo, hi, p_lo, p_hi) if rel.a == part
                       else _relation_axis_holds(rel, axis, p_lo, p_hi, lo, hi) for rel in rels)

        keys = [_anchor_key(e.anchor) for e in pool]
        key_rank = [0] * len(pool)
        for r, i in enumerate(sorted(range(len(pool)), key=keys.__getitem__)):
            key_rank[i] = r
        a_ref, floor = self.ctx.a_ref, 1e-6 * self.ctx.a_ref
        norm, ext, mid = _norm_length(orig, axis), _extent(orig, axis), _mid(orig, axis)
        ranked = []  # (rank, row)
        for row in rows:
            i, j, lo, hi, free = row
            if not _within(terms, lo, hi):
                continue
            a = pool[i].anchor
            b = pool[j].anchor if j >= 0 else a
            if not keeps(a.parent, lo, hi) or (b.parent != a.parent and not keeps(b.parent, lo, hi)):
                continue
            cost = abs((hi - lo) - ext) / norm + abs(0.5 * (lo + hi) - mid) / norm + free
            area_i = max(pool[i].face_area, floor)
            if j < 0:
                diff = _lines_of((a.ratio, a.ratio)) * a_ref / area_i + 0.0
            elif (a.parent, a.face_normal, a.face_side) == (b.parent, b.face_normal, b.face_side):
                diff = _lines_of((a.ratio, b.ratio)) * a_ref / max(pool[j].face_area, floor)
            else:
                diff = (_lines_of((a.ratio, a.ratio)) * a_ref / area_i
                        + _lines_of((b.ratio, b.ratio)) * a_ref / max(pool[j].face_area, floor))
            diff = diff * self.ctx.settings.guide_cost
            score = self.w_a * cost + self.w_d * diff
            r_second = key_rank[j] if j >= 0 and j != i else -1
            ranked.append(((score, lo, hi, key_rank[i], r_second), row))
        ranked.sort(key=lambda x: x[0])
        # each option's place in its group of parent parts (and freshness), as the arrays do
        places: dict[tuple, int] = {}
        kept: list[tuple[int, int]] = []  # (place, position in rank order)
        for at, (_, (i, j, _, _, _)) in enumerate(ranked):
            group: tuple = ()
            if total is not None:
                used = (pool[i],) if j < 0 else (pool[i], pool[j])
                group = (frozenset(u.parent_part for u in used),
                         any(bool(fresh) and u.anchor.parent in fresh for u in used))
            place = places[group] = places.get(group, -1) + 1
            if place < per_group:
                kept.append((place, at))
        chosen = sorted(at for _, at in (sorted(kept)[:total] if total is not None else kept))
        terms = self.axis_terms(part)[axis]
        return [self._option(pool, i, j, lo, hi, int(free), axis, terms)
                for i, j, lo, hi, free in (ranked[at][1] for at in chosen)]

    def _option(self, pool: Sequence[_End], i: int, j: int, lo: float, hi: float, free: int,
                axis: int, terms: tuple[float, float, float]) -> _AxisOption:
        """The :class:`_AxisOption` of ends ``i`` (and ``j``, or -1) of ``pool``; ``terms``
        the axis's terms of its cost (``axis_terms``)."""
        if j < 0:
            used: tuple[_End, ...] = (pool[i],)
        elif j == i:  # a flat axis: the end and its twin
            e = pool[i]
            used = (e, _End(e.value, _with_end(e.anchor, "hi"), e.parent_part, e.face_area))
        else:
            used = (pool[i], pool[j])
        parents = tuple(sorted({(u.parent_part, u.anchor.parent) for u in used}))
        return _AxisOption(
            lo=lo, hi=hi, anchors=tuple(u.anchor for u in used),
            cost_adjust=_cost_of_axis(terms, lo, hi, free), parents=parents,
            areas=tuple(((u.anchor.parent, axis, u.anchor.face_normal, u.anchor.face_side),
                         u.face_area) for u in used))

    @staticmethod
    def _codes(keys: Sequence[Any]) -> np.ndarray:
        """Integer codes of hashable ``keys`` (equal keys, equal codes)."""
        index: dict[Any, int] = {}
        return np.array([index.setdefault(k, len(index)) for k in keys], dtype=np.int64)

    def preserved_pairs(self) -> dict[tuple[str, str], list[Relation]]:
        """Preserved relations by (part, other part), in the order of ``ctx.preserved``."""
        pairs = self.ctx.preserved_pairs
        if not pairs:
            for me, rels in self.ctx.preserved.items():
                for other, rel in rels:
                    pairs.setdefault((me, other), []).append(rel)
        return pairs

    def anchor_part(self, part: str, parent_pool: Mapping[str, Sequence[str]],
                    fresh: frozenset[str]) -> list[tuple[Candidate, dict]]:
        """Stage (i) for one part: combine per-axis options into whole candidates.

        Per axis the options are: unguided (the input interval), the best anchored ones, and
        for the axes of a preserved bisector or coaxial relation with a parent part, the input
        interval re-centred on each of that part's pool candidates (still unguided).  Without
        the last, hanging off an *adjusted* parent on another axis would break the relation on
        this one, and every such combination would be rejected.  A re-centred option is only
        combined with anchors off the same parent candidate.

        Args:
            fresh: candidate ids new at the previous level; when non-empty, only candidates
                hanging off at least one of them are made.
        """
        prim = self.ctx.prims[part]
        orig = prim.box
        ends = self.end_options(part, parent_pool)
        per_axis: list[list[_AxisOption]] = []
        for axis in range(3):
            kept = self.ranked_axis_options(part, axis, ends[axis], fresh, OPTIONS_PER_AXIS,
                                            AXIS_OPTIONS)
            unguided = _AxisOption(orig[0][axis], orig[1][axis], (), 2.0, ())
            per_axis.append([unguided] + kept + self.recentred(part, axis, parent_pool))
        # per option: (unguided, parent ids if anchored, parent ids if unguided)
        tagged = [[(o, o.unguided, frozenset(pid for _, pid in o.parents if o.anchors),
                    frozenset(pid for _, pid in o.parents if o.unguided)) for o in options]
                  for options in per_axis]
        combos: list[tuple[_AxisOption, ...]] = []
        for (o0, u0, a0, r0), (o1, u1, a1, r1), (o2, u2, a2, r2) in itertools.product(*tagged):
            if u0 and u1 and u2:
                continue
            anchored_ids = a0 | a1 | a2
            if not (r0 | r1 | r2) <= anchored_ids:  # re-centred only with that parent's anchors
                continue
            if fresh and fresh.isdisjoint(anchored_ids):
                continue
            combos.append((o0, o1, o2))
        return _diverse(self.build_cheapest(part, combos, CANDIDATES_PER_PART, True),
                        CANDIDATES_PER_PART, self.w_a, self.w_d)

    def build_cheapest(self, part: str, combos: Sequence[tuple[_AxisOption, ...]], k: int,
                       diverse: bool, extra_parents: Sequence[str] = ()
                       ) -> list[tuple[Candidate, dict]]:
        """The candidates of ``combos`` (one option per axis) that :func:`_diverse` (``diverse``)
        or the plain ``k`` cheapest would keep, and possibly some more; never fewer.

        A part may have hundreds of combinations of which a few are kept.  They are built
        cheapest *bound* first and building stops once no combination left can be kept.  The
        bound is exact arithmetic on what the options know: E_d is the sum of the axes'
        costs (a cylinder's rounding may change one cross axis: then only the cheaper of the
        two counts), and E_e is at least the largest of the options' own, since construction
        lines are only ever shared, never removed (``difficulty`` grows with the anchors).
        A combination costs at least its bound, so

        * plain: once ``k`` built cost less than every bound left, the rest cannot enter;
        * diverse (round-robin over ancestor-part sets, :func:`_diverse`): a candidate built
          and cheaper than every bound left (*settled*) keeps its place in its set.  Any other
          one ranks at least ``n`` in its set, ``n`` the settled ones of that set; with ``m``
          the least such ``n`` over the sets that still have others, a settled candidate of
          place ``<= m`` comes before every other.  Once ``k`` do, the rest cannot enter.

        The test ``test_candidates.test_build_cheapest_equals_building_all`` checks that the
        result keeps what building every combination keeps.

        What a combination's candidate reads off its anchors (parent ids, sorted anchors,
        unguided axes, the anchors' codes for E_e) and its ancestor parts are put together
        from its options' :class:`_Facts`, each found once (a part's hundreds of
        combinations share a few options per axis); the ancestor-part sets are bits, not
        frozensets (``test_make_reads_the_anchors_as_build_does``; the generated 40-part
        model's candidates and refine rounds 3.34 -> 3.03 s, plan.json identical).
        """
        facts: dict[int, _Facts] = {}  # id(option) -> its facts (every option outlives this)
        get, find = facts.get, self.facts
        rows = [(get(id(o0)) or find(o0, facts), get(id(o1)) or find(o1, facts),
                 get(id(o2)) or find(o2, facts)) for o0, o1, o2 in combos]
        extra_ids = frozenset(extra_parents)
        extra = 0  # the ancestor parts of the extra parents, as bits (_Generator.part_bits)
        for pid in extra_parents:
            extra |= self.ancestor_bits(pid)
        mine = ~self.part_bits((part,))
        ranked = sorted(zip(self.bounds(part, rows), itertools.count()))
        left: dict[int, int] = {}
        groups = [(f0.reach | f1.reach | f2.reach | extra) & mine
                  for f0, f1, f2 in rows] if diverse else []
        for g in groups:
            left[g] = left.get(g, 0) + 1
        made: list[tuple[Candidate, dict]] = []
        state = _Settling(left)
        decided_at = -1.0  # the bound last checked: a check is made only when the bound grows
        for low, i in ranked:
            if len(made) >= k and low > decided_at:
                if state.decided(low, k, diverse):
                    break
                decided_at = low
            o = combos[i]
            f0, f1, f2 = rows[i]
            box = ((o[0].lo, o[1].lo, o[2].lo), (o[0].hi, o[1].hi, o[2].hi))
            # one option per axis, each along its own: sorted by axis first, the anchors
            # are the options' sorted anchors in axis order
            built = self.make(part, box, [*o[0].anchors, *o[1].anchors, *o[2].anchors],
                              tuple(sorted(f0.parents | f1.parents | f2.parents | extra_ids)),
                              f0.ordered + f1.ordered + f2.ordered,
                              _UNGUIDED[f0.anchored, f1.anchored, f2.anchored],
                              f0.codes + f1.codes + f2.codes,
                              (o[0].cost_adjust, o[1].cost_adjust, o[2].cost_adjust))
            if diverse:
                left[groups[i]] -= 1
            if built is not None:
                made.append(built)
                state.add(built[0].cost(self.w_a, self.w_d), groups[i] if diverse else 0)
        return made

    def facts(self, option: _AxisOption, facts: dict[int, _Facts]) -> _Facts:
        """``option``'s :class:`_Facts`, stored in ``facts`` by its id."""
        anchors = option.anchors
        codes = self.codes(anchors)
        bits = 0
        for a in anchors:
            bits |= self.ancestor_bits(a.parent)
        found = facts[id(option)] = _Facts(
            codes, tuple(sorted(anchors, key=_anchor_key)), frozenset(a.parent for a in anchors),
            bits, self.coded_difficulty(codes) if anchors else 0.0, option.cost_adjust,
            bool(anchors))
        return found

    def part_bits(self, parts: Iterable[str]) -> int:
        """``parts`` as a set of bits, one per part of the model (in sorted order): their
        union is the union of sets, and equal sets have equal bits."""
        bit = self.ctx.part_bit
        if not bit:
            bit.update((p, 1 << i) for i, p in enumerate(sorted(self.ctx.prims)))
        out = 0
        for p in parts:
            out |= bit[p]
        return out

    def ancestor_bits(self, cid: str) -> int:
        """:meth:`part_bits` of the parts of stored candidate ``cid``'s ancestry (itself
        included), remembered: an ancestry never changes."""
        bits = self.ctx.ancestor_bits.get(cid)
        if bits is None:
            bits = self.ctx.ancestor_bits[cid] = self.part_bits(self.ctx.ancestry[cid])
        return bits

    def bounds(self, part: str, rows: Sequence[tuple[_Facts, ...]]) -> list[float]:
        """A lower bound of the weighted cost of the candidate each combination builds
        (:meth:`build_cheapest`), from its options' :class:`_Facts`: their axis costs summed
        (a cylinder's rounding may move one cross axis: then only the cheaper of the two
        counts) and the largest of their own E_e (the test compares them with the
        definition, combination by combination)."""
        prim = self.ctx.prims[part]
        cyl = prim.axis if prim.type == "cylinder" and prim.axis is not None else None
        w_a, w_d, shrink = self.w_a, self.w_d, 1 - 1e-9
        if cyl is None:
            return [(w_a * (f0.cost_adjust + f1.cost_adjust + f2.cost_adjust)
                     + w_d * max(0.0, f0.difficulty, f1.difficulty, f2.difficulty)) * shrink
                    for f0, f1, f2 in rows]
        u, v = (a for a in range(3) if a != cyl)
        return [(w_a * (r[cyl].cost_adjust + min(r[u].cost_adjust, r[v].cost_adjust))
                 + w_d * max(0.0, r[0].difficulty, r[1].difficulty, r[2].difficulty)) * shrink
                for r in rows]

    def recentred(self, part: str, axis: int, parent_pool: Mapping[str, Sequence[str]]
                  ) -> list[_AxisOption]:
        """Unguided options: the input interval centred on a related pool candidate."""
        orig = self.ctx.prims[part].box
        lo0, hi0 = orig[0][axis], orig[1][axis]
        out: list[_AxisOption] = []
        for other, rel in self.ctx.preserved.get(part, ()):
            if rel.type == "coplanar" or axis not in relation_axes(rel):
                continue
            for pid in self.usable(part, parent_pool.get(other, ())):
                lo, hi = _centred_on(orig, axis, _mid(self.ctx.cands[pid].box, axis),
                                     self.ctx.settings.max_change)
                if (lo, hi) != (lo0, hi0):
                    out.append(_AxisOption(lo, hi, (), 2.0, ((other, pid),)))
        return out

    # ------------------------------------------------------------------ stage (ii)
    def restore(self, cand: Candidate) -> list[tuple[Candidate, dict]]:
        """Candidates of related parts re-aligned to ``cand`` where it breaks a relation.

        The relation's axes are re-aligned (:meth:`restore_axis`); each other axis keeps its
        input interval or, when the part is coplanar with ``cand``'s part, takes one of the best
        anchors off ``cand`` (a button re-centred on a moved grip still sits flush on its top).
        """
        made: list[tuple[Candidate, dict]] = []
        anc = self.ctx.ancestry[cand.id]
        for other, rel in self.ctx.preserved.get(cand.part, ()):
            prim = self.ctx.prims[other]
            if prim.type == "custom" or other in anc or other == self.ctx.start:
                continue
            obox = prim.box
            here_is_a = rel.a == cand.part
            holds = (relation_holds(rel, cand.box, obox) if here_is_a
                     else relation_holds(rel, obox, cand.box))
            if holds:
                continue
            # the relation's own axes are re-aligned (restore_axis), never anchored freely
            ends = self.end_options(other, {cand.part: [cand.id]},
                                    [ax for ax in range(3) if ax not in relation_axes(rel)])
            per_axis: list[list[_AxisOption]] = []
            for axis in range(3):
                if axis in relation_axes(rel):
                    per_axis.append(self.restore_axis(other, axis, rel, cand, here_is_a))
                else:
                    anchored = self.ranked_axis_options(other, axis, ends[axis], frozenset(),
                                                        OPTIONS_PER_AXIS, None)
                    per_axis.append([_AxisOption(obox[0][axis], obox[1][axis], (), 2.0, ())]
                                    + anchored)
            options = self.build_cheapest(other, list(itertools.product(*per_axis)),
                                          RESTORED_PER_RELATION, False, (cand.id,))
            options = [options[i] for i in _cheapest_first([c for c, _ in options],
                                                           self.w_a, self.w_d)]
            made.extend(options[:RESTORED_PER_RELATION])
        return made

    def restore_axis(self, part: str, axis: int, rel: Relation, cand: Candidate,
                     cand_is_a: bool) -> list[_AxisOption]:
        orig = self.ctx.prims[part].box
        mc = self.ctx.settings.max_change
        cbox = cand.box
        lo0, hi0 = orig[0][axis], orig[1][axis]
        length = hi0 - lo0
        flat = _is_flat(orig, axis)
        out: list[_AxisOption] = []
        if rel.type == "coplanar":
            cand_end = rel.detail.get("a_end" if cand_is_a else "b_end", "lo")
            my_end = rel.detail.get("b_end" if cand_is_a else "a_end", "lo")
            ratio = 0.0 if cand_end == "lo" else 1.0
            if _is_flat(cbox, axis):
                ratio = 0.0
            value = _ratio_value(cbox, axis, ratio)
            normal, side, _ = _face_for(cbox, axis, None, None)
            lines = 1
            anchor = Anchor(axis, my_end, cand.id, ratio, lines, normal, side)
            if flat:
                both = (_with_end(anchor, "lo"), _with_end(anchor, "hi"))
                out.append(_AxisOption(value, value, both, _axis_cost(orig, axis, value, value, 0),
                                       ()))
            else:
                shapes = [(value, value + length) if my_end == "lo" else (value - length, value),
                          (value, hi0) if my_end == "lo" else (lo0, value)]
                for lo, hi in shapes:
                    if hi - lo > 0:
                        out.append(_AxisOption(lo, hi, (anchor,),
                                               _axis_cost(orig, axis, lo, hi, 1), ()))
        else:
            normal, side, _ = _face_for(cbox, axis, None, None)
            if not flat and not _is_flat(cbox, axis):
                for r_lo, r_hi in SYMMETRIC:
                    lo = _ratio_value(cbox, axis, r_lo)
                    hi = _ratio_value(cbox, axis, r_hi)
                    anchors = (Anchor(axis, "lo", cand.id, r_lo, _lines(r_lo), normal, side),
                               Anchor(axis, "hi", cand.id, r_hi, _lines(r_hi), normal, side))
                    out.append(_AxisOption(lo, hi, anchors, _axis_cost(orig, axis, lo, hi, 0),
                                           ()))
            lo, hi = _centred_on(orig, axis, _mid(cbox, axis), mc)
            out.append(_AxisOption(lo, hi, (), 2.0, ()))
        kept = [o for o in out if _within_change(orig, axis, o.lo, o.hi, mc)]
        kept.sort(key=lambda o: (o.cost_adjust, o.lo, o.hi))
        return kept[:OPTIONS_PER_AXIS]

    # ------------------------------------------------------------------ driver
    def best_diverse(self, cands: Sequence[Candidate], k: int,
                     ordered: bool = True) -> list[Candidate]:
        """Up to ``k`` stored candidates of one part: :func:`_diverse` over ancestor parts."""
        return [c for c, _ in _diverse([(c, self.ctx.ancestry[c.id]) for c in cands], k,
                                       self.w_a, self.w_d, ordered)]

    def run(self, seeds: Mapping[str, str] | None = None) -> None:
        """Every level of candidates: off the originals, or with ``seeds`` (part -> a stored
        candidate, :func:`extend_candidates`) off those alone, each new level off the seeds
        and the level before."""
        ctx = self.ctx
        if seeds is None:
            for part in sorted(ctx.prims):
                self.add_original(ctx.prims[part])
            base = {p: [p] for p in ctx.prims if ctx.prims[p].type != "custom"}
            fresh: frozenset[str] = frozenset()
        else:
            base = {p: [seeds[p]] for p in sorted(seeds) if ctx.prims[p].type != "custom"}
            fresh = frozenset(base[p][0] for p in base)
        pool: dict[str, list[str]] = {p: list(ids) for p, ids in base.items()}
        made_before = set(ctx.cands)
        for level in range(1, ctx.settings.depth + 1):
            batch: list[tuple[Candidate, dict]] = []
            for part in sorted(ctx.prims):
                if (ctx.prims[part].type == "custom" or part == ctx.start
                        or _largest_extent(ctx.prims[part].box) <= 0):
                    continue
                batch.extend(self.anchor_part(part, pool, fresh))
            anchored = self.commit(batch, seeds is not None)
            restored_batch: list[tuple[Candidate, dict]] = []
            by_part: dict[str, list[Candidate]] = {}
            for c in anchored:
                if c.id not in made_before:  # one made again was restored when first made
                    by_part.setdefault(c.part, []).append(c)
            for part in sorted(by_part):
                for c in self.best_diverse(by_part[part], RESTORE_PER_PART):
                    restored_batch.extend(self.restore(c))
            restored = self.commit(restored_batch, seeds is not None)
            new = anchored + restored
            log.debug("level %d: %d anchored, %d restored candidates", level, len(anchored),
                      len(restored))
            if not new:
                break
            # Prune before the next level: the best few new candidates per part act as parents.
            grouped: dict[str, list[Candidate]] = {}
            for c in new:
                grouped.setdefault(c.part, []).append(c)
            pool = {p: list(ids) for p, ids in base.items()}
            fresh_ids: set[str] = set()
            for part, cs in grouped.items():
                # every new candidate, best of each ancestor set first: each child takes the
                # first few it may use (``usable``)
                if seeds is not None:  # off a selection: only what beats the part's seed
                    bar = ctx.cands[seeds[part]].cost(self.w_a, self.w_d)
                    cs = [c for c in cs if c.cost(self.w_a, self.w_d) < bar]
                chosen = [c.id for c in self.best_diverse(cs, len(cs), ordered=False)]
                pool[part] = pool.get(part, []) + chosen
                fresh_ids.update(chosen)
            fresh = frozenset(fresh_ids)


def _diverse(made: Sequence[tuple[Candidate, Mapping[str, str]]], k: int, w_a: float,
             w_d: float, ordered: bool = True) -> list[tuple[Candidate, Mapping[str, str]]]:
    """Up to ``k`` of one part's candidates (with their ancestries), cheapest first, taken
    round-robin over their sets of ancestor parts.

    The cheapest candidates often all hang off the same parts (measured on the camera: all
    16 cheapest prisms hung off the flash, whose top is 3 µm from the prism's); a part among
    those ancestors can then hang off none of them (no cycles), and all of them break a
    relation the same way.  Taking the best of each ancestor set first keeps the alternatives
    that relation restoring and the next level need.

    Returned cheapest first, or with ``ordered`` False in round-robin order (the best of every
    ancestor set, then the second best of every set ...).
    """
    ranked = [made[i] for i in _cheapest_first([c for c, _ in made], w_a, w_d)]
    seen: dict[tuple[str, ...], int] = {}
    order: list[tuple[int, int]] = []
    for i, (c, ancestry) in enumerate(ranked):
        group = tuple(sorted(p for p in ancestry if p != c.part))
        seen[group] = seen.get(group, 0) + 1
        order.append((seen[group] - 1, i))
    picked = [i for _, i in sorted(order)[:k]]
    return [ranked[i] for i in (sorted(picked) if ordered else picked)]


def _lines(ratio: float) -> int:
    return entry_for(ratio).guide_lines


@functools.lru_cache(maxsize=4096)
def _face_lines_of(anchors: tuple[tuple[float, bool], ...]) -> int:
    """``distinct_face_lines(anchors)``, remembered (as :func:`_lines_of`)."""
    return distinct_face_lines(anchors)


@functools.lru_cache(maxsize=1024)
def _lines_of(ratios: tuple[float, ...]) -> int:
    """``distinct_lines(ratios)``, remembered: a few catalogue ratios recur millions of times."""
    return distinct_lines(ratios)


@functools.lru_cache(maxsize=256)
def _pair_lines(ratios: tuple[float, ...]) -> np.ndarray:
    """``distinct_lines((x, y))`` for every pair of ``ratios``, as a read-only table; its
    diagonal is each ratio's own count (the lines are a set: ``(x, x)`` counts as ``(x,)``)."""
    table = np.array([[_lines_of((x, y)) for y in ratios] for x in ratios], dtype=float)
    table.flags.writeable = False
    return table


def _face_area_of(pbox: Box, axis: int, normal: int) -> float:
    if normal == axis:  # aligned with a flat parent's plane
        return part_size(pbox)
    u, v = (a for a in range(3) if a != normal)
    return _extent(pbox, u) * _extent(pbox, v)


def _anchor_face(a: Anchor) -> tuple[tuple[str, int, str, int], tuple[float, bool]]:
    """The parent face an anchor's construction is drawn on and its entry there, as E_e
    groups them (``_Generator.coded_difficulty``): ``((parent, face normal, side, axis or -1),
    (ratio, across))``; an end aligned with a flat parent's plane is a line of its own (its
    axis in the key), any other shares its face's lines with the face's other axis
    (``across``: not the face's first axis, the lowest one besides its normal)."""
    if a.face_normal == a.axis:
        return (a.parent, a.face_normal, a.face_side or "", a.axis), (a.ratio, False)
    return ((a.parent, a.face_normal, a.face_side or "", -1),
            (a.ratio, a.axis != (1 if a.face_normal == 0 else 0)))


def _anchor_key(a: Anchor) -> tuple:
    return (a.axis, a.end, a.parent, a.ratio, a.face_normal, a.face_side or "")


def _cand_sort_key(c: Candidate) -> tuple:
    return (c.part, c.parents, c.box, tuple(_anchor_key(a) for a in c.anchors))


def _cheapest_first(cands: Sequence[Candidate], w_a: float, w_d: float) -> list[int]:
    """Indices of ``cands`` in the order of ``sorted(cands, key=lambda c: (c.cost(w_a, w_d),
    _cand_sort_key(c)))``, the sort key made only for candidates whose cost ties another's
    (the only ones it orders): stable by cost, then each run of equal costs stable by the
    key.  Pruning ranks every part's candidates at every level, and a key is a tuple per
    anchor: the generated 40-part model made 67 606 keys, now 19 852
    (``test_cheapest_first_is_sorted_by_cost_and_key``)."""
    costs = [c.cost(w_a, w_d) for c in cands]
    order = sorted(range(len(cands)), key=costs.__getitem__)
    out: list[int] = []
    start = 0
    while start < len(order):
        stop = start + 1
        while stop < len(order) and costs[order[stop]] == costs[order[start]]:
            stop += 1
        if stop - start > 1:
            out += sorted(order[start:stop], key=lambda i: _cand_sort_key(cands[i]))
        else:
            out.append(order[start])
        start = stop
    return out


def _with_end(anchor: Anchor, end: str) -> Anchor:
    return Anchor(anchor.axis, end, anchor.parent, anchor.ratio, anchor.guide_lines,
                  anchor.face_normal, anchor.face_side)


def _replace_id(c: Candidate, new_id: str) -> Candidate:
    return Candidate(id=new_id, part=c.part, box=c.box, original=c.original, parents=c.parents,
                     depth=c.depth, anchors=c.anchors, unguided_axes=c.unguided_axes,
                     cost_adjust=c.cost_adjust, cost_difficulty=c.cost_difficulty,
                     primitive_type=c.primitive_type, axis=c.axis)


def _check_inputs(primitives: Sequence[Primitive], relations: Sequence[Relation]) -> None:
    names = [p.part for p in primitives]
    if len(set(names)) != len(names):
        dup = sorted({n for n in names if names.count(n) > 1})
        raise SelectionError(f"primitives: part {dup[0]!r} appears more than once")
    for p in primitives:
        lo, hi = p.box
        if not all(math.isfinite(x) for x in (*lo, *hi)) or any(hi[a] < lo[a] for a in range(3)):
            raise SelectionError(f"primitives: part {p.part!r} has an invalid box {p.box}")
    known = set(names)
    for r in relations:
        if r.a not in known or r.b not in known:
            missing = r.a if r.a not in known else r.b
            raise SelectionError(f"relations: {r.type} {r.a}-{r.b} names unknown part {missing!r}")
        if r.axis not in (0, 1, 2):
            raise SelectionError(f"relations: {r.type} {r.a}-{r.b} has axis {r.axis!r}")


def generate_candidates(primitives: Sequence[Primitive], relations: Sequence[Relation],
                        settings: SolverSettings) -> tuple[Candidate, ...]:
    """Every candidate of every part (originals included), deterministic and sorted.

    Args:
        primitives: one per part (``fit`` stage); custom primitives only get their original.
        relations: all relations (``relate`` stage): coplanar ones drive anchoring, those with
            ``detail["preserved"]`` are restored and never broken between a candidate and its
            ancestors.
        settings: ``max_change``, ``depth``, ``guide_cost``, weights (for pruning only) and
            ``max_candidates``.

    Returns:
        candidates sorted by part, the original first, then in generation order.

    Raises:
        SelectionError: inconsistent input, or more than ``settings.max_candidates``.
    """
    ctx = _context(primitives, relations, settings)
    _Generator(ctx).run()
    ordered = _ordered(ctx, ctx.order)
    log.info("%d candidates for %d parts", len(ordered), len(ctx.prims))
    return ordered


def extend_candidates(primitives: Sequence[Primitive], relations: Sequence[Relation],
                      settings: SolverSettings, candidates: Sequence[Candidate],
                      seeds: Iterable[str]) -> tuple[Candidate, ...]:
    """New candidates hanging off ``seeds`` (one candidate id per part, from ``candidates``:
    a selection), ``settings.depth`` levels deep, made and pruned exactly as
    :func:`generate_candidates` makes its levels off the originals.

    Pruning keeps few options per axis, part and level (``AXIS_OPTIONS``,
    ``CANDIDATES_PER_PART``, ``PARENTS_PER_PART``), so a cheap way of anchoring a part off
    the parts it will really be drawn with can be cut for cheaper ways off candidates that
    are never selected (the IKEA table: a leg's top at the top's underside, off the top
    alone, lost to pairs of other legs' originals).  Offered only the selected candidates,
    the generator reaches them.  Every candidate given is kept (the new ones only add to
    them), so a selection over both costs at most what the seeds' selection cost.

    Returns:
        the new candidates only (ids continue each prefix's count), sorted as
        :func:`generate_candidates` sorts; empty when more would exceed
        ``settings.max_candidates`` (said in the log).
    """
    ctx = _context(primitives, relations, settings)
    by_id = {c.id: c for c in candidates}
    for c in sorted(candidates, key=lambda c: c.depth):  # parents are shallower
        ctx.cands[c.id] = c
        ctx.order.append(c.id)
        ancestry = {c.part: c.id}
        for pid in c.parents:
            ancestry.update(ctx.ancestry[pid])
        ctx.ancestry[c.id] = ancestry
        if not c.original:
            ctx.seen[(c.part, c.box, c.parents)] = c.id
            prefix, _, k = c.id.rstrip("*").rpartition("#")
            ctx.counters[prefix] = max(ctx.counters.get(prefix, 0), int(k))
    known = len(ctx.order)
    start = {by_id[cid].part: cid for cid in seeds}
    try:
        _Generator(ctx).run(start)
    except _TooMany as err:
        log.info("no candidates beyond the selection: %s", err)
        return ()
    return _ordered(ctx, ctx.order[known:])


def _ordered(ctx: _Context, ids: Sequence[str]) -> tuple[Candidate, ...]:
    """``ids``' candidates sorted by part, the original first, then in generation order."""
    index = {cid: i for i, cid in enumerate(ctx.order)}
    return tuple(sorted((ctx.cands[cid] for cid in ids),
                        key=lambda c: (c.part, not c.original, index[c.id])))


def _context(primitives: Sequence[Primitive], relations: Sequence[Relation],
             settings: SolverSettings) -> _Context:
    """The generator's bookkeeping for these primitives and relations, no candidate yet."""
    primitives = tuple(primitives)
    relations = tuple(relations)
    _check_inputs(primitives, relations)
    prims = {p.part: p for p in primitives}
    a_ref = max((part_size(p.box) for p in primitives), default=0.0)
    if a_ref <= 0:
        a_ref = 1.0
    coplanar: dict[str, list[tuple[str, Relation]]] = {}
    preserved: dict[str, list[tuple[str, Relation]]] = {}
    for r in sorted(relations, key=lambda r: (r.a, r.b, r.type, r.axis, sorted(
            (k, str(v)) for k, v in r.detail.items()))):
        # every relation offers construction planes: shared faces (coplanar), shared
        # mid-planes (bisector) and a shared axis (coaxial: both cross mid-planes)
        coplanar.setdefault(r.a, []).append((r.b, r))
        coplanar.setdefault(r.b, []).append((r.a, r))
        if r.detail.get("preserved"):
            preserved.setdefault(r.a, []).append((r.b, r))
            preserved.setdefault(r.b, []).append((r.a, r))
    return _Context(settings=settings, prims=prims, a_ref=a_ref, coplanar=coplanar,
                    preserved=preserved, start=start_part(primitives))
