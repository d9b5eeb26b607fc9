"""Stage 3, *relate*: relations between pairs of primitives (paper §4.1, DESIGN.md §2.3).

Every pair of fitted primitives (``custom`` ones excluded: they are unguided) is tested for

* **coplanar** along an axis: a face of a's box and a face of b's box lie in one plane normal to
  that axis within the tolerance (every lo/hi pairing is tested, so a leg whose top touches a
  table top's underside is coplanar with it), **and** the two face rectangles are near each
  other in that plane: their gap (the Euclidean distance between the two rectangles, 0 when
  they overlap) is at most :data:`PLANE_GAP` (½) times the larger of the two box diagonals.  So
  two boxes standing on one floor side by side are coplanar, and two parts that merely happen
  to sit at one height at opposite ends of a long object are not: a guide transfers by eye
  within a shared plane only over a short distance.  (Measured with this rule instead of
  requiring the rectangles to touch: objectives train 59.2 -> 54.9, chair 25.4 -> 21.0,
  roller 35.5 -> 33.6.)
* **coaxial** along an axis: one is rotational (cylinder or frustum) about that axis and the
  other is rotational about it too or a cuboid (whose axis line is its box's centre line: the
  mixer's flat beater turns about the bowl's axis), and their axis lines (each box's centre
  line along the axis) are within the tolerance of each other (Euclidean distance across the
  axis: ``hypot(du, dv) <= tolerance``, the same rule ``candidates.relation_holds`` applies).
  ``detail = {"line": [u, v]}``, the mean of the two lines.
* **bisector** along an axis: the mid-planes of the two boxes normal to that axis coincide.
  ``detail = {"coord": mean mid-plane coordinate}``.

* **embedded** (a coplanar relation marked ``detail["embedded"]``): a pair nothing above
  relates, where one box's end is sunk into the other (its cross-section within the other's,
  its other end outside): that end is coplanar with the face it passes through, within a
  tolerance of the depth sunk (:func:`_embedded`).  The desk's legs reach into the middle of
  the desk top's thickness and were related to nothing, so each was drawn by eye; a drawing
  teacher starts a leg at the top's underside, and the hidden length may go.  Measured
  (2026-11-25): the desk's anchored ends 31.0 -> 38.1 %, its legs standing on the rails and
  touching the top; no other benchmark model has such a pair.

Boxes are the primitives' axis-aligned boxes (a plane's box is its slab, a cylinder's the box
around it), so the test is the same for every type.

Tolerance: ``rel_tol × min(diagonal of a's box, diagonal of b's box)``, model units, kept in
:attr:`Relation.tolerance`: relative to the *smaller* part so that a small part near a large
one is not related by the large one's slack (an embedded relation's: its depth).

Preservation: every relation is returned, and one per related pair carries
``detail["preserved"] = True``: the first in preference order bisector > coaxial > coplanar
(:data:`types.RELATION_PREFERENCE`), then lowest axis, then ends (lo before hi, a's end first).
Besides it, every coplanar relation of parts that *touch* is preserved too, marked
``detail["contact"]`` (faces facing each other, overlapping: a part standing on another) or
``detail["flush"]`` (faces on the same side, boxes touching: flush fronts): touching parts stay
touching in every selection.

Output order (deterministic): sorted by ``(a, b, RELATION_PREFERENCE[type], axis, a_end,
b_end)`` with ``lo`` < ``hi``; so the preserved relation is the first of its pair.

Implied relations: two coaxial primitives along axis k also have their box mid-planes across
k within the tolerance; those two bisectors are *implied* by the coaxial relation (its axis line
is exactly those two mid-planes), so they are not reported separately.  Otherwise the
preference rule would always keep a bisector, a weaker relation, for a coaxial pair (the
mixer's bowl and beater would only keep one mid-plane).  A bisector along k itself (the two
parts' mid-heights coincide) is a different fact and is still reported.
"""

from __future__ import annotations

import logging
import math
from typing import Any, Sequence

from .errors import ModelError
from .types import RELATION_PREFERENCE, Primitive, Relation, box_diagonal

log = logging.getLogger(__name__)

#: Default relative tolerance (of the smaller part's box diagonal).
REL_TOL = 0.02
#: Largest in-plane gap between coplanar faces, as a fraction of the larger box diagonal.
PLANE_GAP = 0.5

_ROTATIONAL = ("cylinder", "frustum")
_ENDS = ("lo", "hi")


def _faces_near(a: Primitive, b: Primitive, axis: int) -> bool:
    """True when a's and b's box faces normal to ``axis`` are near in the plane (docstring)."""
    gaps = [max(a.box[0][k] - b.box[1][k], b.box[0][k] - a.box[1][k], 0.0)
            for k in range(3) if k != axis]
    limit = PLANE_GAP * max(box_diagonal(a.box), box_diagonal(b.box))
    return math.hypot(*gaps) <= limit


def _shared_axis(a: Primitive, b: Primitive) -> int | None:
    """The axis along which a and b could be coaxial, or None.

    At least one must be rotational (cylinder, frustum) about that axis; the other is rotational
    about the same axis or a cuboid, whose axis line is its box's centre line (a beater shaft in
    a bowl, a lens barrel on a square mount).
    """
    for p, q in ((a, b), (b, a)):
        if p.type in _ROTATIONAL and p.axis is not None:
            if (q.type in _ROTATIONAL and q.axis == p.axis) or q.type == "cuboid":
                return p.axis
    return None


def _axis_line(p: Primitive, axis: int) -> tuple[float, float]:
    """The (u, v) coordinates of p's axis line along ``axis`` (u, v the other axes, in order).

    The centre line of p's box, for every type: a cylinder's or frustum's box is centred on its
    axis, and a cuboid's centre line is its axis.  ``candidates.relation_holds`` and the plan
    checker use the same line, so a relation found here holds there.
    """
    others = [k for k in range(3) if k != axis]
    u, v = (float((p.box[0][k] + p.box[1][k]) / 2) for k in others)
    return u, v


def _pair_relations(a: Primitive, b: Primitive, rel_tol: float) -> list[tuple[tuple, Relation]]:
    """All relations of one pair (a.part < b.part), each with its sort key."""
    tol = rel_tol * min(box_diagonal(a.box), box_diagonal(b.box))
    out: list[tuple[tuple, Relation]] = []

    def add(kind: str, axis: int, detail: dict[str, Any], ends: tuple[int, int] = (0, 0)) -> None:
        key = (a.part, b.part, RELATION_PREFERENCE[kind], axis, ends[0], ends[1])
        out.append((key, Relation(a.part, b.part, kind, axis, tol, detail)))

    coaxial_axis = _shared_axis(a, b)
    if coaxial_axis is not None:
        (ua, va), (ub, vb) = _axis_line(a, coaxial_axis), _axis_line(b, coaxial_axis)
        if math.hypot(ua - ub, va - vb) <= tol:
            add("coaxial", coaxial_axis,
                {"line": [float((ua + ub) / 2), float((va + vb) / 2)]})
        else:
            coaxial_axis = None
    for axis in range(3):
        # bisector (those across a coaxial pair's axis are implied by the coaxial relation)
        mid_a = (a.box[0][axis] + a.box[1][axis]) / 2
        mid_b = (b.box[0][axis] + b.box[1][axis]) / 2
        if abs(mid_a - mid_b) <= tol and coaxial_axis in (None, axis):
            add("bisector", axis, {"coord": float((mid_a + mid_b) / 2)})
        # coplanar (every lo/hi pairing of the two boxes' faces normal to this axis)
        if _faces_near(a, b, axis):
            for ea in range(2):
                for eb in range(2):
                    ca, cb = a.box[ea][axis], b.box[eb][axis]
                    if abs(ca - cb) <= tol:
                        add("coplanar", axis, {"a_end": _ENDS[ea], "b_end": _ENDS[eb],
                                               "coord": float((ca + cb) / 2)}, (ea, eb))
    return out


def _embedded(a: Primitive, b: Primitive, rel_tol: float) -> list[tuple[tuple, Relation]]:
    """A contact where one box's end is sunk into the other (the desk's legs reach into the
    middle of the desk top's thickness; nothing else relates them): for each axis where one
    end of ``p`` lies strictly inside ``q``'s interval while its other end is outside, and
    ``p``'s cross-section lies within ``q``'s, a coplanar relation of that end with ``q``'s
    face it passes through, ``detail["embedded"]`` the depth, its tolerance that depth (the
    hidden length may go; a drawing teacher starts the leg at the top's underside).  At most
    one, the shallowest."""
    best: tuple[float, tuple, Relation] | None = None
    for p, q, flip in ((a, b, False), (b, a, True)):
        for axis in range(3):
            across = [k for k in range(3) if k != axis]
            if not all(q.box[0][k] <= p.box[0][k] and p.box[1][k] <= q.box[1][k]
                       for k in across):
                continue
            lo, hi = q.box[0][axis], q.box[1][axis]
            for ep, eq, inside, outside in ((1, 0, p.box[1][axis], p.box[0][axis] < lo),
                                            (0, 1, p.box[0][axis], p.box[1][axis] > hi)):
                if not (outside and lo < inside < hi):
                    continue
                depth = float(abs(inside - q.box[eq][axis]))
                if depth <= rel_tol * min(box_diagonal(a.box), box_diagonal(b.box)):
                    continue  # within the tolerance: the coplanar test found it
                ea, eb = (eq, ep) if flip else (ep, eq)
                key = (a.part, b.part, RELATION_PREFERENCE["coplanar"], axis, ea, eb)
                rel = Relation(a.part, b.part, "coplanar", axis, depth,
                               {"a_end": _ENDS[ea], "b_end": _ENDS[eb],
                                "coord": float(q.box[eq][axis]), "embedded": depth})
                if best is None or depth < best[0]:
                    best = (depth, key, rel)
    return [] if best is None else [(best[1], best[2])]


def _touching(a: Primitive, b: Primitive, rel: Relation) -> dict[str, bool]:
    """``{"contact": True}`` or ``{"flush": True}`` for a coplanar pair that touches, else {}.

    contact: the two faces face each other (one box's ``hi`` face on the other's ``lo`` face)
    and their rectangles overlap with positive area (a part standing on another);
    flush: the faces are on the same side and the two boxes touch or overlap (a panel's front
    flush with its neighbour's).  Both are kept by every selection (issue: touching parts must
    stay touching), besides the one preferred relation per pair.
    """
    n = rel.axis
    tol = rel.tolerance
    inplane = [k for k in range(3) if k != n]
    overlap = [min(a.box[1][k], b.box[1][k]) - max(a.box[0][k], b.box[0][k]) for k in inplane]
    if rel.detail.get("a_end") != rel.detail.get("b_end"):
        return {"contact": True} if all(o > tol for o in overlap) else {}
    gaps = [max(a.box[0][k] - b.box[1][k], b.box[0][k] - a.box[1][k], 0.0) for k in inplane]
    return {"flush": True} if math.hypot(*gaps) <= tol else {}


def detect_relations(
    primitives: Sequence[Primitive], *, rel_tol: float = REL_TOL
) -> tuple[Relation, ...]:
    """Stage verb: every coplanar, coaxial and bisector relation between pairs of primitives.

    Args:
        primitives: fitted primitives, one per part (any order); ``custom`` ones are skipped.
        rel_tol: unit-free; a pair's tolerance is ``rel_tol`` times the smaller of the two box
            diagonals (model units).

    Returns:
        Relations with ``a < b``, sorted as the module docstring says; the first of each related
        pair has ``detail["preserved"] = True``, the others ``False``.

    Raises:
        ModelError: two primitives carry the same part name.
    """
    if rel_tol < 0 or not math.isfinite(rel_tol):
        raise ValueError(f"rel_tol must be a finite non-negative number, got {rel_tol}")
    names = [p.part for p in primitives]
    if len(set(names)) != len(names):
        dup = sorted({n for n in names if names.count(n) > 1})
        raise ModelError(f"primitives: part names must be unique, repeated: {', '.join(dup)}")
    usable = sorted((p for p in primitives if p.type != "custom"), key=lambda p: p.part)
    keyed: list[tuple[tuple, Relation]] = []
    for i, a in enumerate(usable):
        for b in usable[i + 1:]:
            keyed.extend(_pair_relations(a, b, rel_tol))
    related = {(r.a, r.b) for _, r in keyed}
    for i, a in enumerate(usable):  # an end sunk into a part it is otherwise unrelated to
        for b in usable[i + 1:]:
            if (a.part, b.part) not in related:
                keyed.extend(_embedded(a, b, rel_tol))
    keyed.sort(key=lambda kr: kr[0])
    out: list[Relation] = []
    previous: tuple[str, str] | None = None
    prims = {p.part: p for p in usable}
    for _, rel in keyed:
        first = (rel.a, rel.b) != previous
        previous = (rel.a, rel.b)
        touch = _touching(prims[rel.a], prims[rel.b], rel) if rel.type == "coplanar" else {}
        out.append(Relation(rel.a, rel.b, rel.type, rel.axis, rel.tolerance,
                            {**rel.detail, **touch, "preserved": first or bool(touch)}))
    log.debug("%d relations between %d primitives", len(out), len(usable))
    return tuple(out)
