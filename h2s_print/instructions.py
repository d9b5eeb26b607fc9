"""Instructions a person can follow while drawing: lettered points and short sub-steps (issue 11).

A drawing book does not describe every line in a paragraph: its picture carries letters at the
points that matter (A, B, C ...), and its text is a short headline plus numbered sub-steps,
one construction each ("1. Draw the diagonals AC and BD of the body's front face. 2. Through
their crossing E draw FG toward the right vanishing point.").  This module turns the sequence
stage's constructions into such sub-steps.

Two passes, so that letters are chosen knowing every point a step names:

1. :func:`construction_specs` (and the sequence stage's own specs) describe each sub-step as a
   :class:`Spec`: a template key and its fields, where a field may be a tuple of 3D points
   (:class:`Pts`, printed as their letters run together: ``AC``).  Specs that draw the same
   lines (the diagonals of one face serve its ½ line along both axes and every ¼ line) are
   said once (:func:`unique_specs`).
2. :func:`letter_steps` gives the points of the whole tutorial their letters and formats the
   sentences.

Letters (decisions where the issue is silent)
---------------------------------------------
* Letters are the capitals without ``I`` and ``O`` (they read as 1 and 0 next to a ruler);
  after ``Z`` come ``A'``, ``B'`` ...
* **A point keeps its letter** from the first step that names it to the last (a guide reused
  later keeps its letters, and so does a face used again): :func:`letter_steps` letters the
  whole tutorial at once, so that two points named in overlapping stretches of steps never
  share a letter, and each new point takes the letter free longest: one never used first, in
  alphabetical order, so a letter names a second point only after the whole alphabet has
  been used (a beginner's read-through of the bottle met B, C and E as the body's corners on
  one page and the neck's two pages later; before stop 24 pages started again near ``A``).
* **A letter rests one step** (:data:`REST`) after its point's last step before it names
  another point: the page just turned never used a letter of this page for something else.
  A reader who found the mixer's column corners H and J on one page read H and J as its
  other corners on the next, and the old centre M stayed on the picture while a new M was
  named (read-through of 2026-11-24).  When every plain letter is living or resting, a
  primed one (``A'``) is used rather than a resting one (since stop 24: the train's chimney
  guides named E and H as other points on consecutive pages).
* Two 3D points within ``tol`` are one point.
* Sub-steps that do the same thing twice on one face (the diagonals of both half faces for
  the ¼ and ¾ lines, the two connecting lines of ⅓ and ⅔, both edges of a face) are said
  once, in the plural (:func:`unique_specs`; template key ``<key>_two`` where the plural
  needs other words).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Callable, Sequence

import numpy as np

from .constructions import Construction
from .types import Vec3

#: Letters for points, in order (no I and O).
ALPHABET = tuple("ABCDEFGHJKLMNPQRSTUVWXYZ")
#: Steps a letter rests after its point's last step before it names another point.  Two
#: (no letter meaning two points within two steps) doubled the primed letters (32 -> 68 on
#: the teaching benchmark's novice steps, 2026-11-24) for pages the reader does not turn
#: back to; the pages a step cites are kept clear instead (:func:`letter_steps`).
REST = 1


@dataclass(frozen=True, slots=True)
class Pts:
    """Points named by their letters run together in a sentence (``AC`` for a line).

    ``places``: what the line places, said after its letters with the template
    ``substep.line_for`` ("QR for its bottom"; empty: the letters alone).
    ``step``: the earlier step that drew the line, said after its letters with the template
    ``substep.line_step`` ("MP (step 7)"; 0: not said): set by the sequence stage where a
    sub-step names a line it does not draw (``_Context.cite_earlier``); the line's letters
    are then on that step's picture too."""

    points: tuple[Vec3, ...]
    places: str = ""
    step: int = 0


@dataclass(frozen=True, slots=True)
class Many:
    """Several runs of points, joined as a list in a sentence (``AB, CD and EF``)."""

    items: tuple[Pts, ...]


@dataclass(frozen=True, slots=True)
class Spec:
    """One sub-step before letters: a template key under ``substep`` and its fields.

    Attributes:
        key: template key (``templates/steps.yaml``, section ``substep``).
        fields: template fields; :class:`Pts` values become letters.
        same: identity for :func:`unique_specs` (two specs with equal ``same`` draw the same
            lines: said once).  Empty: never merged.
    """

    key: str
    fields: tuple[tuple[str, Any], ...]
    same: tuple = ()
    pair: tuple = ()


def spec(key: str, same: tuple = (), pair: tuple = (), **fields: Any) -> Spec:
    """A :class:`Spec` (fields sorted by name, so equal specs compare equal)."""
    return Spec(key, tuple(sorted(fields.items())), same, pair)


def unique_specs(specs: Sequence[Spec], plural: Callable[[str], str] = lambda k: k
                 ) -> list[Spec]:
    """``specs`` without repeats, twins said together.

    A spec equal to an earlier one (same ``same``, or the same key and fields) is dropped (but
    a result line's fields, ``role`` ``guide``, replace a construction line's).  A spec with
    the same ``pair`` (and key) as an earlier one is merged into it: fields that differ
    become a :class:`Many` of both, and the key becomes ``plural(key)``.
    """
    out: list[Spec] = []
    seen: dict[tuple, int] = {}  # key -> its index in ``out``
    paired: dict[tuple, int] = {}
    merged: set[int] = set()  # indices of twins said together
    for s in specs:
        key = ("same",) + s.same if s.same else ("spec", s.key, s.fields)
        if key in seen:
            # the same line drawn as a construction's intermediate and as another's result:
            # said as the result (an apprentice, who sees results only, reads it)
            k = seen[key]
            if (dict(s.fields).get("role") == "guide" and out[k].key == s.key and k not in merged
                    and dict(out[k].fields).get("role") == "construction"):
                out[k] = Spec(s.key, s.fields, out[k].same, out[k].pair)
            continue
        twin = paired.get((s.key,) + s.pair) if s.pair else None
        seen[key] = len(out) if twin is None else twin
        if twin is None:
            if s.pair:
                paired[(s.key,) + s.pair] = len(out)
            out.append(s)
            continue
        first = out[twin]
        mine = dict(s.fields)
        fields = []
        for name, value in first.fields:
            other = mine.get(name, value)
            if other != value and isinstance(value, (Pts, Many)) and isinstance(other, (Pts, Many)):
                value = Many(line_runs(value) + line_runs(other))
            fields.append((name, value))
        out[twin] = Spec(plural(first.key), tuple(fields), first.same, ())
        merged.add(twin)
    return out


def _letter(k: int) -> str:
    n = len(ALPHABET)
    return ALPHABET[k % n] + "'" * (k // n)


def letter_steps(steps: Sequence[Sequence[Spec]], tol: float,
                 render: Callable[[str, dict[str, Any]], str],
                 join: Callable[[list[str]], str] = ", ".join,
                 on_paper: Sequence[tuple[Vec3, int]] = (),
                 lines_on_paper: Sequence[tuple[Vec3, Vec3, int]] = ()
                 ) -> list[tuple[list[str], list[tuple[str, Vec3]]]]:
    """Letters for every point the steps' sub-steps name, and the formatted sub-steps.

    A point *lives* from the first step that names it to the last; two points whose lives
    overlap get different letters, and a point keeps its letter all its life (module docstring,
    *Letters*).  Letters are given greedily in order of first mention, each point the letter
    free longest (never used first, then the one whose last point ended earliest) among those
    that no living point holds, that named no other point in the :data:`REST` steps
    before, and that name no other point on a page the step cites ("Use KL from step 8":
    the reader turns back to step 8, where E and H must not name other points than on
    this page); when every plain letter is living or resting, the first primed letter free
    (``A'``) whose plain letter neither this page nor the one before shows, where there is
    one (a read-through took Q' beside Q for an image of Q): a letter the page just turned
    used for another point misleads more than a prime (the train's chimney guides: E and H
    named other points on consecutive pages).

    Args:
        steps: each step's sub-steps, in order.
        tol: two points within this distance (model units, max norm) are one point.
        render: formats a template key with fields (letters already substituted).
        join: joins the runs of a :class:`Many` field.
        on_paper: ``(point, step)``: the point is still on the paper at that step (an end of
            a guide shown there); a named point lives at least that long, so its letter is
            not given to another point while its line is still drawn.
        lines_on_paper: ``(start, end, step)``: a line still on the paper at that step; a
            named point on it (a crossing of two diagonals, say) lives at least that long:
            the train's "E" named the crossing of AC and BD, then, with both still drawn,
            another point (a read-through).

    Returns:
        per step, ``(sentences, labels)``: one sentence per spec, and ``(letter, point)`` for
        each point it names, in order of first mention.
    """
    points: list[tuple[float, float, float]] = []
    # a point found again exactly (most are: the same Vec3 named in several sub-steps) is
    # the point it was stored as: none before it lay within tol when it was stored, so the
    # first point within tol of it is itself
    exact: dict[tuple[float, float, float], int] = {}

    def find(p: Vec3) -> int:
        x, y, z = key = (float(p[0]), float(p[1]), float(p[2]))
        i = exact.get(key)
        if i is not None:
            return i
        for i, (rx, ry, rz) in enumerate(points):
            if abs(rx - x) <= tol and abs(ry - y) <= tol and abs(rz - z) <= tol:
                return i
        points.append(key)
        exact[key] = len(points) - 1
        return len(points) - 1

    named: list[list[int]] = []
    for specs in steps:
        order: list[int] = []
        for s in specs:
            for _, value in s.fields:
                for p in points_of(value):
                    i = find(p)
                    if i not in order:
                        order.append(i)
        named.append(order)
    # a line a step takes "from step N" is lettered on step N's picture too, where it was
    # drawn (the desk's "Centre part 2 on HM from step 3": step 3 carried the line to M
    # without naming M)
    for k, specs in enumerate(steps):
        for s in specs:
            fields = dict(s.fields)
            n = fields.get("step")
            cited = ([(n, points_of(v)) for v in fields.values()]
                     if isinstance(n, int) and 0 < n <= k else [])
            cited += [(run.step, run.points) for v in fields.values()
                      if isinstance(v, (Pts, Many)) for run in line_runs(v)
                      if 0 < run.step <= k]
            for m, pts in cited:
                for p in pts:
                    i = find(p)
                    if i not in named[m - 1]:
                        named[m - 1].append(i)
    last: dict[int, int] = {}
    for k, order in enumerate(named):
        for i in order:
            last[i] = k
    for p, k in on_paper:  # a named point whose line is still drawn lives on
        x, y, z = (float(c) for c in p)
        for i in last:
            rx, ry, rz = points[i]
            if abs(rx - x) <= tol and abs(ry - y) <= tol and abs(rz - z) <= tol:
                last[i] = max(last[i], k)
    if lines_on_paper and last:  # a named point on a line still drawn lives on too
        ids = list(last)
        pts = np.array([points[i] for i in ids], dtype=float)  # (n, 3)
        a = np.array([ln[0] for ln in lines_on_paper], dtype=float)  # (m, 3)
        d = np.array([ln[1] for ln in lines_on_paper], dtype=float) - a
        until = np.array([ln[2] for ln in lines_on_paper])
        w = pts[:, None, :] - a[None, :, :]  # (n, m, 3)
        t = np.clip((w * d[None]).sum(axis=2) / np.maximum((d * d).sum(axis=1), 1e-300),
                    0.0, 1.0)
        off = np.abs(w - t[:, :, None] * d[None]).max(axis=2)  # (n, m), max norm as find()
        for row, i in enumerate(ids):
            on = off[row] <= tol
            if on.any():
                last[i] = max(last[i], int(until[on].max()))
    # the earlier steps each step sends the reader back to ("Use KL from step 2", "Carry
    # MP (step 7) ...")
    cites = [{v - 1 for s in specs for name, v in s.fields
              if name == "step" and isinstance(v, int) and 0 < v <= k}
             | {run.step - 1 for s in specs for _, v in s.fields if isinstance(v, (Pts, Many))
                for run in line_runs(v) if 0 < run.step <= k}
             for k, specs in enumerate(steps)]
    letter: dict[int, str] = {}
    held: list[tuple[int, str]] = []  # (last step, letter) of points lettered so far
    ended: dict[str, int] = {}  # each letter's latest point's last step
    for k, order in enumerate(named):
        # letters on the pages this step cites name those points only (a read-through
        # turned back to step 8 from step 10 and met E, H, S and W naming other points)
        cited = {letter[j] for c in cites[k] for j in named[c] if j in letter}
        for i in order:
            if i in letter:
                continue
            # busy: held by a living point, or resting (it named another point in the
            # previous REST steps, whose page the reader has just turned), or on a page
            # this step cites
            busy = {x for end, x in held if end >= k - REST} | cited
            free = [x for x in ALPHABET if x not in busy]
            # not the plain twin of a primed letter this page shows (Q beside Q')
            twins = {letter[j][0] for j in named[k] if j in letter and len(letter[j]) > 1}
            free = [x for x in free if x not in twins] or free
            if free:  # the letter free longest: one never used first, in alphabetical order
                # (free is in alphabetical order, min keeps the first of equals, and a used
                # letter ended at a step >= 0)
                letter[i] = next((x for x in free if x not in ended), None) or min(
                    free, key=ended.__getitem__)
            else:  # primed: one whose plain letter this page and the one before do not
                # show, where one is free (read-throughs took Q' beside Q for an image of Q)
                shown = {letter[j][0] for c in (k - 1, k) if c >= 0 for j in named[c]
                         if j in letter}
                n = len(ALPHABET)
                primed = [x for x in map(_letter, range(n, 4 * n)) if x not in busy]
                pick = next((x for x in primed if x[0] not in shown), None)
                if pick is None:
                    while _letter(n) in busy:
                        n += 1
                    pick = _letter(n)
                letter[i] = pick
            held.append((last[i], letter[i]))
            ended[letter[i]] = last[i]

    def said(run: Pts, step: bool = True) -> str:
        letters = "".join(letter[find(p)] for p in run.points)
        if run.step and step:
            letters = render("line_step", {"line": letters, "step": run.step})
        return render("line_for", {"line": letters, "sides": run.places}) if run.places \
            else letters

    def said_many(runs: tuple[Pts, ...]) -> str:
        """Runs joined; one step said after them all when all come from it and none says
        what it places ("MP and XY (step 7)")."""
        steps = {run.step for run in runs}
        if len(runs) > 1 and len(steps) == 1 and 0 not in steps and not any(
                run.places for run in runs):
            return render("line_step", {"line": join([said(run, False) for run in runs]),
                                        "step": runs[0].step})
        return join([said(run) for run in runs])

    out = []
    for specs, order in zip(steps, named):
        sentences = []
        for s in specs:
            fields = {}
            for name, value in s.fields:
                if isinstance(value, Pts):
                    value = said(value)
                elif isinstance(value, Many):
                    value = said_many(value.items)
                fields[name] = value
            sentences.append(render(s.key, fields))
        out.append((sentences, [(letter[i], _vec(points[i])) for i in order]))
    return out


def line_runs(value: Pts | Many) -> tuple[Pts, ...]:
    """The runs of points a field names: one for :class:`Pts`, each item of :class:`Many`."""
    return value.items if isinstance(value, Many) else (value,)


def points_of(value: Any) -> tuple[Vec3, ...]:
    """The points a field's value names (a :class:`Pts` or :class:`Many`; none else)."""
    if isinstance(value, Pts):
        return value.points
    if isinstance(value, Many):
        return tuple(p for run in value.items for p in run.points)
    return ()


def _vec(p: np.ndarray) -> Vec3:
    return (float(p[0]), float(p[1]), float(p[2]))


def points_key(points: Sequence[Vec3], tol: float) -> frozenset:
    """The same points, in any order, within ``tol`` (a dictionary key)."""
    return frozenset(tuple(int(round(c / tol)) for c in p) for p in points)


#: What an apprentice reads for a construction's result line (:func:`brief_specs`), by
#: its ratio: the construction named as in the primer, the line shown.
BRIEFS: dict[Fraction, str] = {
    Fraction(1, 2): "half", Fraction(1, 4): "quarter", Fraction(3, 4): "quarter",
    Fraction(1, 3): "third", Fraction(2, 3): "third", Fraction(2): "extend",
    Fraction(-1): "extend", Fraction(3, 2): "extend_half", Fraction(-1, 2): "extend_half",
}
#: Sub-step keys that draw a construction's result line themselves (not "from step N").
DRAWING_KEYS = frozenset({"through", "from", "cross", "through_along", "from_along",
                          "cross_along"})


def brief_fields(kind: str, parent: str, face: str, dim: str = "", beyond: str = "",
                 near: str = "") -> dict[str, str]:
    """The fields a sub-step carries for :func:`brief_specs` (``role`` aside): ``kind`` a
    key of :data:`BRIEFS`'s values, ``centre`` or ``centre_plate``; the rest as
    :func:`construction_specs` says."""
    return dict(brief=kind, parent=parent, face=face, dim=dim, beyond=beyond, near=near)


def construction_specs(con: Construction, parent: str, face: str,
                       vp: Callable[..., str], tol: float, dim: str = "",
                       ends: tuple[str, str] = ("", "")) -> list[Spec]:
    """The sub-steps of one construction (``h2s_print.constructions.construct``), one per
    ruler operation: the diagonals of a (half) face, a line through their crossing, a line
    through two points and where it crosses another, an edge extended.

    Each spec's field ``role`` is the role of the lines it draws (``construction``: shown
    to novices only; ``guide``).  The result line's spec also carries what an apprentice
    reads instead (:func:`brief_specs`): ``brief`` (a key of :data:`BRIEFS`), ``parent``,
    ``face``, ``near`` (the face's end the line is nearer, for a quarter or a third), and
    for an extension ``dim`` (the face's extent the ratio measures) and ``beyond`` (the
    face's end it extends beyond); the sequence stage adds ``box`` where the face is the box
    around a tapered part's.  So does a construction line through the
    face's centre (``brief`` ``half``), said to an apprentice where a later step uses it.

    Args:
        con: the construction.
        parent: the parent's name as the text calls it.
        face: the construction face's name (``front`` ...).
        vp: the phrase for lines along a model axis (``toward the left vanishing point``),
            called ``vp(axis)``, or ``vp(axis, start, end)`` for a line drawn from ``start``
            (``away from ...`` when it moves away from the vanishing point).
        tol: two points within this distance are one (for merging equal sub-steps).
        dim: the name of the face's extent along the construction's axis (``depth`` ...).
        ends: the names of the face's ends along that axis, ``lo`` then ``hi`` (``front``,
            ``back``).
    """
    at = dict(con.points)
    # a construction line through the face's centre halves it: said so to an apprentice
    # where a later step uses the line as a guide of its own (_Context.promoted)
    halves = brief_fields("half", parent, face, dim)
    face_id = (points_key(con.face.corners, tol), con.axis)
    s_axis = con.axis
    t_axis = con.result.axis if con.result.axis is not None else s_axis
    out: list[Spec] = []
    last: str | None = None
    extended: dict[str, Pts] = {}  # a new point -> the edge whose extension it lies on
    lines = list(con.lines)
    i = 0
    while i < len(lines):
        ln = lines[i]
        a, b = ln.names
        if ln.key == "align":
            out.append(spec("edge", ("edge", points_key((at[a], at[b]), tol)), ("edge",),
                            line=Pts((at[a], at[b])), parent=parent, face=face, vp=vp(t_axis),
                            role=ln.role))
        elif ln.key == "diagonal":
            a2, b2 = lines[i + 1].names
            i += 1
            if {a, b} == {"A", "C"}:
                corners = Pts(tuple(at[n] for n in "ABCD"))
                out.append(spec("diagonals", ("diagonals", points_key(corners.points, tol)),
                                corners=corners, first=Pts((at["A"], at["C"])),
                                second=Pts((at["B"], at["D"])), point=Pts((at["O"],)),
                                parent=parent, face=face, role=ln.role))
                last = "O"
            else:
                left = "A" in (a, b)
                half = _half_corners(a, b, a2, b2, left)
                last = "Q1" if left else "Q3"
                out.append(spec("half_diagonals", ("diagonals", points_key([at[n] for n in half], tol)),
                                ("half", face_id), half=Pts(tuple(at[n] for n in half)),
                                first=Pts((at[a], at[b])), second=Pts((at[a2], at[b2])),
                                point=Pts((at[last],)), role=ln.role))
        elif ln.key == "cross":  # (through the centre: it halves the face)
            out.append(spec("cross", ("line", points_key((at[a], at[b]), tol)), point=Pts((at["O"],)),
                            line=Pts((at[a], at[b])), vp=vp(s_axis), role=ln.role,
                            **halves))
        elif ln.key == "connect":
            if not b.startswith("S"):  # thirds: C-E meets B-D at I1 (D-F meets A-C at I2)
                crossing = "I1" if "C" in (a, b) else "I2"
                diagonal = ("B", "D") if crossing == "I1" else ("A", "C")
                out.append(spec("connect", ("line", points_key((at[a], at[b]), tol)), ("third", face_id),
                                line=Pts((at[a], at[b])), other=Pts(tuple(at[n] for n in diagonal)),
                                point=Pts((at[crossing],)), role=ln.role))
                last = crossing
            else:  # extension: origin -> midpoint of the shared edge -> the new point
                mid = "F" if _s(at, con, b) > 1 else "E"
                # the line it meets is named (the edge's extension, drawn just before): "it"
                # read as the line being drawn (a read-through)
                out.append(spec("connect_through", ("line", points_key((at[a], at[b]), tol)),
                                start=Pts((at[a],)), through=Pts((at[mid],)),
                                point=Pts((at[b],)), edge=extended[b], role=ln.role))
                last = b
        elif ln.key == "extend":
            beyond = "B" if a == "A" else "A"
            extended[b] = Pts((at[a], at[beyond]))
            out.append(spec("extend", ("line", points_key((at[a], at[b]), tol)),
                            edge=Pts((at[a], at[beyond])), end=Pts((at[beyond],)),
                            vp=vp(s_axis), role=ln.role))
        elif ln.key == "division":
            through = last if last is not None else a
            key = "from" if through in (a, b) else "through"
            # twins: both quarter lines, or both third lines, of one face (never a quarter
            # with a third: an apprentice reads them by the construction's name)
            twin = (("result", face_id, BRIEFS[con.ratio])
                    if ln.role == "guide" and through in ("Q1", "Q3", "I1", "I2") else ())
            # a line drawn from a point runs one way: toward its vanishing point or away
            way = (at[through], at[b if through == a else a]) if key == "from" else ()
            brief = (brief_fields(BRIEFS[con.ratio], parent, face, dim,
                                  beyond=ends[1] if con.ratio > 1 else ends[0],
                                  near=ends[0] if con.ratio < Fraction(1, 2) else ends[1])
                     if ln.role == "guide" and con.ratio in BRIEFS
                     else halves if through == "O" else {})
            out.append(spec(key, ("line", points_key((at[a], at[b]), tol)), twin,
                            point=Pts((at[through],)), line=Pts((at[a], at[b])),
                            vp=vp(t_axis, *way), role=ln.role, **brief))
        i += 1
    return out


#: Constructions that give several lines: said in the plural when the step draws two
#: (``brief_quarters``), else with the end the line is nearer.
_SEVERAL = ("quarter", "third")


def brief_specs(specs: Sequence[Spec], where: Callable[[str, str, str], str],
                shown: Callable[[Pts, int], bool] = lambda line, step: True) -> list[Spec]:
    """What an apprentice reads for ``specs``: the picture shows the resulting guides only
    (DESIGN.md §2.6), so a sub-step that draws only construction lines (field ``role``) is
    left out, and one that draws a construction's result line names the construction as
    the primer does, with the line: "Halve the body's top face: draw XY toward the right
    vanishing point."  A result taken from an earlier step ("Use XY from step 4"), and
    every sub-step that is not a construction's, stays as it is, except that a line reused
    "through E" is only reused (the crossing E is of construction lines not drawn).  A line
    an earlier step drew as a construction line (``shown(line, step)`` false: the
    apprentice's picture of that step left it out) is said as constructed here when the
    sub-step can say so (the mixer's "Use NP from step 6" for a bowl ellipse's middle line,
    where step 6 drew NP only to quarter the face).

    The face is said by ``where(kind, parent, face)``, ``kind`` ``face``, ``box`` (the
    box around a tapered part, field ``box``) or ``plate`` (a round plate's rectangle):
    field ``where``.  The two lines through an ellipse's centre are one sub-step.

    A read-through of stop 26: the apprentice's text asked for the diagonals DS and RC, the
    lines UV and GW and their crossing T, none of which its picture drew (only T's letter).
    A read-through of stop 27: "Quarter the base body's front face: draw AB" left the
    reader to guess which of three quarter lines AB is ("..., a quarter in from its top"),
    and "the prism's top face" was the top of the box around it.
    """
    out: list[Spec] = []
    for s in specs:
        f = dict(s.fields)
        if f.get("role") == "construction":
            continue
        cited = s.key in ("through_reuse", "cross_reuse", "from_reuse")
        line = f.get("line")
        if cited and (not isinstance(line, Pts) or len(line.points) != 2
                      or shown(line, f["step"])):  # (through a crossing not drawn)
            s = spec("from_reuse", s.same, s.pair, line=f["line"], step=f["step"])
        elif "brief" in f and (s.key in DRAWING_KEYS or cited):
            kind, place = f["brief"], "box" if f.get("box") else "face"
            if kind in _SEVERAL and isinstance(f["line"], Many):
                kind += "s"
            elif kind == "centre_plate":
                kind, place = "centre", "plate"
            s = spec(f"brief_{kind}", s.same, s.pair, line=f["line"], vp=f["vp"],
                     where=where(place, f["parent"], f["face"]), dim=f["dim"],
                     beyond=f["beyond"], near=f["near"])
            if out and out[-1].key == s.key == "brief_centre":
                first = dict(out[-1].fields)  # both lines through one centre: one sub-step
                if first["where"] == dict(s.fields)["where"]:
                    out[-1] = spec("brief_centre_two", out[-1].same, (), line=first["line"],
                                   vp=first["vp"], where=first["where"], lines2=f["line"],
                                   vp2=f["vp"])
                    continue
        out.append(s)
    return out


def _half_corners(a: str, b: str, a2: str, b2: str, left: bool) -> tuple[str, str, str, str]:
    """Corners of the half face whose diagonals are ``a-b`` and ``a2-b2``, in order round it."""
    names = {a, b, a2, b2}
    s_half = next(n for n in names if n.startswith("S"))
    t_half = next(n for n in names if n.startswith("T"))
    return ("A", s_half, t_half, "D") if left else (s_half, "B", "C", t_half)


def _s(at: dict[str, Vec3], con: Construction, name: str) -> float:
    """The ``s`` coordinate (along the anchored axis, 0 at A, 1 at B) of a named point."""
    lo, hi = con.face.box[0][con.axis], con.face.box[1][con.axis]
    return (at[name][con.axis] - lo) / (hi - lo) if hi != lo else 0.0
