"""The catalogue of easy ratios and their perspective constructions (paper §3(c), Fig. 3).

Every anchor of a candidate (``h2s_print.candidates``) places one end of one axis interval of a
child at a ratio ``r`` of a parent's interval along the same axis::

    value = parent_lo + r * (parent_hi - parent_lo)

``r`` in ``[0, 1]`` divides the parent (¼, ⅓, ½ ...); ``r < 0`` or ``r > 1`` extends it beyond
its ``lo`` or ``hi`` end (an *extrusion*: extend by ½× or 1×).

Each ratio is drawn by a fixed ruler construction on one rectangular face ``ABCD`` of the parent
(the *construction face*).  Face coordinates ``(s, t)`` name every point of a construction:

* ``s`` runs along the anchored axis: ``A = (0, 0)`` and ``D = (0, 1)`` lie on the parent's
  ``lo`` end, ``B = (1, 0)`` and ``C = (1, 1)`` on its ``hi`` end;
* ``t`` runs along the face's other axis: edge ``AB`` at ``t = 0``, edge ``DC`` at ``t = 1``.

So ``A -> B`` is the anchored axis, ``A -> D`` the face's other axis, and the resulting guide of
ratio ``r`` is the *division line* ``s = r`` (from ``(r, 0)`` to ``(r, 1)``), parallel to
``AD`` (in perspective: toward the vanishing point of ``AD``'s direction).  The point of a
name in 3D is ``A + s (B - A) + t (D - A)``: use :func:`face_point` or
:func:`construction_segments`.  Because the constructions are incidence constructions (lines
through points, intersections), building them on the 3D rectangle and projecting is exactly the
construction a person repeats with a ruler on the page.

A construction is an ordered tuple of :class:`ConstructionStep`; the number of steps is the
entry's ``guide_lines``.  Steps are shared between entries with the same ``key`` (the ½ lines
inside the ¼ construction are the ½ construction's), so several anchors on one face can count
their common lines once (:func:`distinct_lines` along one axis, :func:`distinct_face_lines`
along both axes of the face: the diagonals are common to both).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache
from typing import Iterable, Mapping

#: Face coordinates ``(s, t)`` of every named point used by the catalogue.
#: Corners ``A B C D``; ``O`` the face centre; ``E``/``F`` the midpoints of ``AD``/``BC``;
#: ``Q1``/``Q3`` the centres of the left/right half faces; ``I1``/``I2`` the intersections that
#: give ⅓ and ⅔; ``S<r>``/``T<r>`` the ends of the division line ``s = r`` on ``AB``/``DC``.
POINTS: Mapping[str, tuple[float, float]] = {
    "A": (0.0, 0.0),
    "B": (1.0, 0.0),
    "C": (1.0, 1.0),
    "D": (0.0, 1.0),
    "O": (0.5, 0.5),
    "E": (0.0, 0.5),
    "F": (1.0, 0.5),
    "Q1": (0.25, 0.5),
    "Q3": (0.75, 0.5),
    "I1": (1 / 3, 2 / 3),
    "I2": (2 / 3, 2 / 3),
}

#: Step kinds, in words (the views stage prints these; the sequence stage may style by kind).
STEP_KINDS: Mapping[str, str] = {
    "diagonal": "a diagonal of a (half) face, corner to corner",
    "cross": "the line through the centre parallel to the anchored axis (halves the other axis)",
    "connect": "a line through two known points, extended until it meets the named line",
    "extend": "an existing edge extended beyond the face toward its vanishing point",
    "division": "the resulting guide: the line s = r across the face, parallel to AD",
    "align": "the resulting guide is an existing edge of the face (s = 0 or s = 1), extended",
}


def _division_points(r: float) -> tuple[str, str]:
    name = _ratio_label(r)
    return f"S{name}", f"T{name}"


def _ratio_label(r: float) -> str:
    frac = Fraction(r).limit_denominator(12)
    return str(frac.numerator) if frac.denominator == 1 else f"{frac.numerator}/{frac.denominator}"


def point_st(name: str) -> tuple[float, float]:
    """Face coordinates ``(s, t)`` of a named point (``S<r>``/``T<r>`` included).

    Raises:
        KeyError: an unknown name.
    """
    if name in POINTS:
        return POINTS[name]
    if name[:1] in ("S", "T") and len(name) > 1:
        frac = Fraction(name[1:])
        return (float(frac), 0.0 if name[0] == "S" else 1.0)
    raise KeyError(name)


@dataclass(frozen=True, slots=True)
class ConstructionStep:
    """One straight line a person draws with a ruler on the construction face.

    Attributes:
        kind: one of ``STEP_KINDS`` (``diagonal``, ``cross``, ``connect``, ``extend``,
            ``division``, ``align``).
        start, end: names of the points the line runs through (see ``POINTS``; ``S<r>`` and
            ``T<r>`` are the ends of the division line ``s = r`` on edges ``AB`` and ``DC``).
            The drawn segment runs from ``start`` to ``end``; for ``connect`` and ``extend``
            ``end`` is the point the extended line reaches.
        through: the already known points that define the line: two points, or one point
            when ``parallel`` is set.
        parallel: ``"AD"`` or ``"AB"`` when the line is drawn through one point parallel to
            that edge (in perspective: toward the vanishing point of that edge's direction).
        makes: points this line newly defines (by meeting earlier lines or edges), in order.
        text: a short plain-language description, e.g. ``"diagonal A-C"``.
    """

    kind: str
    start: str
    end: str
    through: tuple[str, ...]
    parallel: str | None = None
    makes: tuple[str, ...] = ()
    text: str = ""

    @property
    def key(self) -> tuple[str, str, str]:
        """Identity of the line (two entries sharing a line share its key)."""
        a, b = sorted((self.start, self.end))
        return (self.kind, a, b)


@dataclass(frozen=True, slots=True)
class RatioEntry:
    """One easy ratio: where it puts an interval end, and how to construct it.

    Attributes:
        ratio: the ratio of the parent's interval (``< 0`` or ``> 1``: an extrusion).
        name: short English name: ``start``, ``quarter``, ``third``, ``half``, ``two-thirds``,
            ``three-quarters``, ``end``, ``extend-1-before``, ``extend-half-before``,
            ``extend-half-after``, ``extend-1-after``.
        label: the ratio as a fraction, e.g. ``"1/3"``, ``"-1/2"`` (used in candidate ids).
        guide_lines: number of lines of the construction (``len(construction)``).
        construction: the ordered ruler steps on face ``ABCD`` (module docstring); the last
            step is always the resulting guide (``division`` or ``align``).
        phrase: words for instructions: ``"half"``, ``"a third"``, ``"extend by one"`` ...
    """

    ratio: float
    name: str
    label: str
    guide_lines: int
    construction: tuple[ConstructionStep, ...]
    phrase: str

    @property
    def extrusion(self) -> bool:
        """True for ratios outside ``[0, 1]`` (the face is extended)."""
        return self.ratio < 0.0 or self.ratio > 1.0

    @property
    def in_line(self) -> bool:
        """True for an end in line with one of the parent's edges (``start`` or ``end``:
        ratio 0 or 1), the edge extended rather than a division or an extrusion."""
        return self.name in ("start", "end")

    @property
    def needs_room(self) -> bool:
        """False when the construction is only an existing edge extended (``align``: ratio 0
        or 1), which needs no room on the face; True for every division or extrusion."""
        return any(step.kind != "align" for step in self.construction)


# --------------------------------------------------------------------------- constructions

def _step(kind: str, start: str, end: str, through: tuple[str, ...], parallel: str | None,
          makes: tuple[str, ...], text: str) -> ConstructionStep:
    return ConstructionStep(kind, start, end, through, parallel, makes, text)


_DIAG_AC = _step("diagonal", "A", "C", ("A", "C"), None, (), "diagonal A-C")
_DIAG_BD = _step("diagonal", "B", "D", ("B", "D"), None, ("O",),
                 "diagonal B-D, meets A-C at the centre O")
_HALF = _step("division", "S1/2", "T1/2", ("O",), "AD", ("S1/2", "T1/2"),
              "line through O parallel to A-D: the 1/2 line")
_CROSS = _step("cross", "E", "F", ("O",), "AB", ("E", "F"),
               "line through O parallel to A-B: midpoints E of A-D and F of B-C")


def _steps_half() -> tuple[ConstructionStep, ...]:
    return (_DIAG_AC, _DIAG_BD, _HALF)


def _steps_quarter(left: bool) -> tuple[ConstructionStep, ...]:
    if left:  # half face A, S1/2, T1/2, D
        q = (_step("diagonal", "A", "T1/2", ("A", "T1/2"), None, (),
                   "diagonal A-T1/2 of the left half"),
             _step("diagonal", "S1/2", "D", ("S1/2", "D"), None, ("Q1",),
                   "diagonal S1/2-D of the left half, meets at its centre Q1"),
             _step("division", "S1/4", "T1/4", ("Q1",), "AD", ("S1/4", "T1/4"),
                   "line through Q1 parallel to A-D: the 1/4 line"))
    else:  # half face S1/2, B, C, T1/2
        q = (_step("diagonal", "S1/2", "C", ("S1/2", "C"), None, (),
                   "diagonal S1/2-C of the right half"),
             _step("diagonal", "B", "T1/2", ("B", "T1/2"), None, ("Q3",),
                   "diagonal B-T1/2 of the right half, meets at its centre Q3"),
             _step("division", "S3/4", "T3/4", ("Q3",), "AD", ("S3/4", "T3/4"),
                   "line through Q3 parallel to A-D: the 3/4 line"))
    return _steps_half() + q


def _steps_third(first: bool) -> tuple[ConstructionStep, ...]:
    # Paper Fig. 3c: the diagonal B-D meets the line C-E at I1 = (1/3, 2/3); symmetrically the
    # diagonal A-C meets D-F at I2 = (2/3, 2/3).  Check I1: C + u (E - C) = (1 - u, 1 - u/2) lies
    # on B-D (s + t = 1) for u = 2/3, i.e. at (1/3, 2/3).
    if first:
        tail = (_step("connect", "C", "E", ("C", "E"), None, ("I1",),
                      "line C-E, meets B-D at I1"),
                _step("division", "S1/3", "T1/3", ("I1",), "AD", ("S1/3", "T1/3"),
                      "line through I1 parallel to A-D: the 1/3 line"))
    else:
        tail = (_step("connect", "D", "F", ("D", "F"), None, ("I2",),
                      "line D-F, meets A-C at I2"),
                _step("division", "S2/3", "T2/3", ("I2",), "AD", ("S2/3", "T2/3"),
                      "line through I2 parallel to A-D: the 2/3 line"))
    return (_DIAG_AC, _DIAG_BD, _CROSS) + tail


def _steps_extend_one(after: bool) -> tuple[ConstructionStep, ...]:
    # Reflection through the midpoint of the shared edge (paper Fig. 3d).  After B: the line
    # D-F (F the midpoint of B-C) meets the extended edge A-B at S2 = (2, 0), since the
    # triangles D-C-F and S2-B-F are congruent, so B-S2 = D-C = A-B.
    if after:
        return (_DIAG_AC, _DIAG_BD, _CROSS,
                _step("extend", "A", "S2", ("A", "B"), None, (), "extend edge A-B beyond B"),
                _step("connect", "D", "S2", ("D", "F"), None, ("S2",),
                      "line D-F extended, meets the extended A-B at S2"),
                _step("division", "S2", "T2", ("S2",), "AD", ("T2",),
                      "line through S2 parallel to A-D: the new end, 1x beyond B"))
    return (_DIAG_AC, _DIAG_BD, _CROSS,
            _step("extend", "B", "S-1", ("B", "A"), None, (), "extend edge B-A beyond A"),
            _step("connect", "C", "S-1", ("C", "E"), None, ("S-1",),
                  "line C-E extended, meets the extended B-A at S-1"),
            _step("division", "S-1", "T-1", ("S-1",), "AD", ("T-1",),
                  "line through S-1 parallel to A-D: the new end, 1x before A"))


def _steps_extend_half(after: bool) -> tuple[ConstructionStep, ...]:
    # Halve the face, then reflect the half next to the shared edge through that edge's
    # midpoint: T1/2 + u (F - T1/2) = (1/2 + u/2, 1 - u/2) meets t = 0 at u = 2, s = 3/2.
    if after:
        return _steps_half() + (
            _CROSS,
            _step("extend", "A", "S3/2", ("A", "B"), None, (), "extend edge A-B beyond B"),
            _step("connect", "T1/2", "S3/2", ("T1/2", "F"), None, ("S3/2",),
                  "line T1/2-F extended, meets the extended A-B at S3/2"),
            _step("division", "S3/2", "T3/2", ("S3/2",), "AD", ("T3/2",),
                  "line through S3/2 parallel to A-D: the new end, 1/2 beyond B"))
    return _steps_half() + (
        _CROSS,
        _step("extend", "B", "S-1/2", ("B", "A"), None, (), "extend edge B-A beyond A"),
        _step("connect", "T1/2", "S-1/2", ("T1/2", "E"), None, ("S-1/2",),
              "line T1/2-E extended, meets the extended B-A at S-1/2"),
        _step("division", "S-1/2", "T-1/2", ("S-1/2",), "AD", ("T-1/2",),
              "line through S-1/2 parallel to A-D: the new end, 1/2 before A"))


def _entry(ratio: float, name: str, phrase: str,
           steps: tuple[ConstructionStep, ...]) -> RatioEntry:
    return RatioEntry(ratio=ratio, name=name, label=_ratio_label(ratio),
                      guide_lines=len(steps), construction=steps, phrase=phrase)


#: The catalogue, sorted by ratio.  Alignment with an existing edge (0 or 1) is one line: the
#: edge extended (paper Fig. 3e); ½ is 3 lines; ¼ and ¾ are 6; ⅓ and ⅔ are 5; extend by 1× is
#: 6; extend by ½× is 7.
CATALOGUE: tuple[RatioEntry, ...] = (
    _entry(-1.0, "extend-1-before", "extend by one", _steps_extend_one(after=False)),
    _entry(-0.5, "extend-half-before", "extend by a half", _steps_extend_half(after=False)),
    _entry(0.0, "start", "align with the edge",
           (_step("align", "A", "D", ("A", "D"), None, ("S0", "T0"), "edge A-D, extended"),)),
    _entry(0.25, "quarter", "a quarter", _steps_quarter(left=True)),
    _entry(1 / 3, "third", "a third", _steps_third(first=True)),
    _entry(0.5, "half", "half", _steps_half()),
    _entry(2 / 3, "two-thirds", "two thirds", _steps_third(first=False)),
    _entry(0.75, "three-quarters", "three quarters", _steps_quarter(left=False)),
    _entry(1.0, "end", "align with the edge",
           (_step("align", "B", "C", ("B", "C"), None, ("S1", "T1"), "edge B-C, extended"),)),
    _entry(1.5, "extend-half-after", "extend by a half", _steps_extend_half(after=True)),
    _entry(2.0, "extend-1-after", "extend by one", _steps_extend_one(after=True)),
)

#: Catalogue entries by their exact ratio (:func:`entry_for`'s fast path).
_ENTRIES: dict[float, RatioEntry] = {e.ratio: e for e in CATALOGUE}
#: The only entry usable when the parent's interval has no length (a plane's thickness).
ALIGN_ONLY: tuple[RatioEntry, ...] = tuple(e for e in CATALOGUE if e.ratio == 0.0)


def entry_for(ratio: float) -> RatioEntry:
    """The catalogue entry of ``ratio`` (matched within 1e-9).

    Raises:
        KeyError: ``ratio`` is not in the catalogue.
    """
    found = _ENTRIES.get(ratio)  # the catalogue's own floats, as candidates carry them
    if found is not None:
        return found
    for e in CATALOGUE:
        if abs(e.ratio - ratio) <= 1e-9:
            return e
    raise KeyError(ratio)


def distinct_lines(ratios: Iterable[float]) -> int:
    """Number of distinct lines needed to construct all ``ratios`` along one axis of one face.

    Shared steps count once: ``distinct_lines([0.25, 0.75]) == 9`` (the three ½ lines plus three
    for each quarter), while each alone needs 6.
    """
    return distinct_face_lines((r, False) for r in ratios)


def distinct_face_lines(anchors: Iterable[tuple[float, bool]]) -> int:
    """Number of distinct lines needed to construct ratios along *both* axes of one face.

    Args:
        anchors: ``(ratio, across)`` pairs; ``across`` False constructs the ratio along the
            face's first axis (``s`` of the module docstring), True along its second axis: the
            same construction with ``s`` and ``t`` swapped (``A`` stays, ``B`` and ``D`` swap).

    A line is identified by its two end points in the face's own coordinates (the first axis's
    ``(s, t)``), so lines common to both axes count once: the two diagonals of the face, and the
    ½ line of one axis, which is the other's ``cross`` line.  ``distinct_face_lines([(0.5,
    False), (0.5, True)]) == 4`` (diagonals A-C and B-D, the two ½ lines), not 3 + 3.  Along
    one axis this counts exactly as the steps' ``key`` does.
    """
    return _count_face_lines(frozenset((entry_for(r).ratio, bool(a)) for r, a in anchors))


@lru_cache(maxsize=4096)
def _count_face_lines(anchors: frozenset[tuple[float, bool]]) -> int:
    """:func:`distinct_face_lines` of a set of (catalogue ratio, across) pairs."""
    lines: set[tuple[tuple[float, float], ...]] = set()
    for ratio, across in anchors:
        lines.update(_face_lines(ratio, across))
    return len(lines)


@lru_cache(maxsize=None)
def _face_lines(ratio: float, across: bool) -> frozenset[tuple[tuple[float, float], ...]]:
    """The lines of one entry's construction as end-point pairs in the face's coordinates."""
    out = set()
    for step in entry_for(ratio).construction:
        ends = []
        for name in (step.start, step.end):
            s, t = point_st(name)
            if across:
                s, t = t, s
            ends.append((round(s, 9), round(t, 9)))
        out.add(tuple(sorted(ends)))
    return frozenset(out)


def face_point(name: str, a, b, d) -> tuple[float, ...]:
    """The point called ``name`` on the face with corners ``A = a``, ``B = b``, ``D = d``.

    Args:
        name: a point name (``POINTS`` or ``S<r>``/``T<r>``).
        a, b, d: corners as sequences of equal length (3D model units, or 2D).

    Returns:
        ``A + s (B - A) + t (D - A)`` as a tuple of floats.
    """
    s, t = point_st(name)
    return tuple(float(ai + s * (bi - ai) + t * (di - ai)) for ai, bi, di in zip(a, b, d))


def construction_segments(entry: RatioEntry, a, b, d):
    """The construction of ``entry`` on face ``A = a``, ``B = b``, ``D = d`` as segments.

    Returns:
        tuple of ``(step, start_point, end_point)`` in construction order, points as tuples.
    """
    return tuple((step, face_point(step.start, a, b, d), face_point(step.end, a, b, d))
                 for step in entry.construction)
