"""Perspective guide constructions, defined in 3D on a box face (paper §3(c), Fig. 3; §5).

Every construction is built on one face of an axis-aligned box, in 3D, and only then
projected: a person who repeats it with a ruler on the printed sheet (diagonals, lines toward
a vanishing point, intersections) lands exactly on the projection of the 3D ratio point,
because projection preserves lines and their incidences.

Local frame of a construction (the same as ``h2s_print.ratios``).  A construction along
in-face axis ``axis`` works in unit coordinates ``(s, t)`` of the face: ``s`` runs along ``axis``
(0 at the box's ``lo``, 1 at its ``hi``), ``t`` along the face's other in-face axis (0 at its
``lo``).  Corners ``A = (0, 0)``, ``B = (1, 0)``, ``C = (1, 1)``, ``D = (0, 1)``; ``S<r>`` and
``T<r>`` are the ends ``(r, 0)`` and ``(r, 1)`` of the line ``s = r``.  Every point is computed
exactly (``fractions.Fraction``) as the intersection of lines drawn before it, then mapped to
model units; so each construction is genuine, and its result lies at exactly the ratio.

Constructions (lines in drawing order, ``key`` in brackets; ``GUIDE_LINES`` counts them; they
follow ``h2s_print.ratios.CATALOGUE`` step by step):

* ``0``, ``1``: no construction: the existing edge ``A–D`` (``B–C``) is the guide [align].  1.
* ``1/2``: diagonals ``A–C``, ``B–D`` [diagonal] meet at the centre ``O``; the line through
  ``O`` parallel to ``AD`` (toward that axis's VP on paper) [division].  3.
* ``1/4`` (``3/4``): the ``1/2`` construction, then diagonals of the left (right) half face
  meet at ``Q1`` (``Q3``); the line through it parallel to ``AD``.  6.
* ``1/3`` (``2/3``), paper Fig. 3c: diagonals give ``O``; the line through ``O`` parallel to
  ``AB`` [cross] gives the midpoints ``E`` of ``AD`` and ``F`` of ``BC``; line ``C–E``
  [connect] meets diagonal ``B–D`` at ``I1 = (1/3, 2/3)`` (``D–F`` meets ``A–C`` at
  ``I2 = (2/3, 2/3)``); the line through it parallel to ``AD``.  5.
* ``2`` (``−1``), extend by 1 by reflection through the midpoint of the shared edge, paper
  Fig. 3d: diagonals, cross (``F`` = midpoint of ``BC``); edge ``AB`` extended beyond ``B``
  [extend]; line ``D–F`` extended [connect] meets it at ``S2 = (2, 0)``; the new end through
  ``S2`` parallel to ``AD``.  (Before ``A``: ``C–E`` meets ``BA`` extended at ``S-1``.)  6.
* ``3/2`` (``−1/2``), extend by a half: the ``1/2`` construction (its line becomes a
  construction line), cross, ``AB`` extended, line ``T1/2–F`` extended meets it at
  ``S3/2``; the new end through it.  (Before ``A``: ``T1/2–E`` meets at ``S-1/2``.)  7.

Each line has a ``role``: ``construction`` (intermediate, shown to novices) or ``guide`` (the
resulting line, shown to novices and apprentices).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from fractions import Fraction
from typing import Any, Callable

import numpy as np

from .errors import RenderError
from .types import Box, Camera, Vec3, as_box, readonly

#: Ratios ``construct`` supports (exact values).
RATIOS: tuple[Fraction, ...] = tuple(
    Fraction(r) for r in ("-1", "-1/2", "0", "1/4", "1/3", "1/2", "2/3", "3/4", "1", "3/2", "2"))
#: Number of lines (construction + guide) each ratio's construction draws, keyed by the ratio
#: as a Python float (``1/3`` is the float ``1/3``).  ``guide_lines`` snaps nearby floats.
GUIDE_LINES: dict[float, int] = {
    -1.0: 6, -0.5: 7, 0.0: 1, 0.25: 6, 1 / 3: 5, 0.5: 3, 2 / 3: 5, 0.75: 6, 1.0: 1, 1.5: 7,
    2.0: 6,
}
#: Two ratios closer than this are the same ratio.
RATIO_TOL = 1e-9

Local = tuple[Fraction, Fraction]


def ratio_key(ratio: float) -> Fraction:
    """The supported exact ratio within ``RATIO_TOL`` of ``ratio`` (``ValueError`` if none)."""
    for r in RATIOS:
        if abs(float(ratio) - float(r)) <= RATIO_TOL:
            return r
    raise ValueError(f"no perspective construction for ratio {ratio!r} "
                     f"(supported: {', '.join(str(r) for r in RATIOS)})")


def guide_lines(ratio: float) -> int:
    """Number of lines the construction for ``ratio`` draws (see ``GUIDE_LINES``)."""
    return GUIDE_LINES[float(ratio_key(ratio))]


def _label(r: Fraction) -> str:
    return str(r)


# ----------------------------------------------------------------------------- values


@dataclass(frozen=True, slots=True)
class Face:
    """One face of an axis-aligned box.

    Attributes:
        box: ``(lo, hi)``, model units.
        normal: the axis (0, 1, 2) the face is normal to.
        end: ``lo`` or ``hi``: which of the box's two faces normal to ``normal``.

    The in-face axes ``u < v`` are the other two axes.  ``corners`` are ``A = (u_lo, v_lo)``,
    ``B = (u_hi, v_lo)``, ``C = (u_hi, v_hi)``, ``D = (u_lo, v_hi)`` (counter-clockwise seen
    from the side ``+normal``), at the face's plane coordinate.
    """

    box: Box
    normal: int
    end: str

    def __post_init__(self) -> None:
        if self.normal not in (0, 1, 2):
            raise ValueError(f"normal must be 0, 1 or 2, got {self.normal!r}")
        if self.end not in ("lo", "hi"):
            raise ValueError(f"end must be 'lo' or 'hi', got {self.end!r}")
        box = as_box(*self.box)
        lo, hi = box
        if any(not (lo[i] <= hi[i]) for i in range(3)):
            raise ValueError(f"box lo must be <= hi, got {self.box!r}")
        object.__setattr__(self, "box", box)  # plain floats, whatever was passed

    @property
    def in_axes(self) -> tuple[int, int]:
        """The two in-face axes ``(u, v)``, increasing."""
        u, v = (a for a in (0, 1, 2) if a != self.normal)
        return (u, v)

    @property
    def coord(self) -> float:
        """The face plane's coordinate along ``normal``, model units."""
        return self.box[0 if self.end == "lo" else 1][self.normal]

    def point(self, fu: float, fv: float) -> Vec3:
        """The face point at fractions ``fu``, ``fv`` of its ``u`` and ``v`` extents (may lie
        outside ``[0, 1]``: the face plane extended), model units."""
        u, v = self.in_axes
        lo, hi = self.box
        p = [0.0, 0.0, 0.0]
        p[self.normal] = self.coord
        p[u] = lo[u] + float(fu) * (hi[u] - lo[u])
        p[v] = lo[v] + float(fv) * (hi[v] - lo[v])
        return (p[0], p[1], p[2])

    @property
    def corners(self) -> tuple[Vec3, Vec3, Vec3, Vec3]:
        """``A, B, C, D`` (see the class doc), model units."""
        return (self.point(0, 0), self.point(1, 0), self.point(1, 1), self.point(0, 1))

    @property
    def centre(self) -> Vec3:
        """The face's centre, model units."""
        return self.point(0.5, 0.5)


def box_faces(box: Box) -> tuple[Face, ...]:
    """The six faces of ``box``: normal 0 lo, 0 hi, 1 lo, 1 hi, 2 lo, 2 hi."""
    b = as_box(*box)
    return tuple(Face(b, n, e) for n in (0, 1, 2) for e in ("lo", "hi"))


@dataclass(frozen=True, slots=True)
class ConstructionLine:
    """A straight line segment of a construction, model units.

    Attributes:
        key: what it is, the step kinds of ``h2s_print.ratios``: ``diagonal``, ``cross``,
            ``connect``, ``extend``, ``division``, ``align`` (see the module doc); ellipse
            guides through the centre are ``mid``.
        role: ``construction`` (intermediate) or ``guide`` (the resulting line).
        start, end: end points, model units.
        axis: the model axis the line runs along (on paper: toward that axis's vanishing
            point), or ``None`` for oblique lines (diagonals, connecting lines).
        names: names of its end points in the construction's local frame (``("A", "C")``,
            ``("S1/2", "T1/2")`` ...), as in ``h2s_print.ratios``; empty when not from one.
    """

    key: str
    role: str
    start: Vec3
    end: Vec3
    axis: int | None = None
    names: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True)
class Construction:
    """How to place a line at ``ratio`` along ``axis`` of ``face`` with a ruler.

    Attributes:
        face: the face it is drawn on.
        axis: the in-face axis the ratio is measured along (from the box's ``lo``).
        ratio: the exact ratio (``Fraction``); below 0 or above 1 it is an extension.
        lines: every line to draw, in drawing order; the last is the resulting guide (for
            ratios 0 and 1 the only line: the existing edge, key ``align``).
        result: the resulting line: the face's (extended) cross-section at ``coord``, running
            along the other in-face axis.
        coord: ``lo + ratio · (hi − lo)`` along ``axis``, model units.
        points: named points ``(name, xyz)`` of the construction's local frame (module doc;
            its ``A B C D`` are ``face.corners`` only when ``axis`` is the face's ``u`` axis):
            the corners and every point the lines make, in order (``O``, ``E``, ``F``,
            ``Q1``, ``I1``, ``S1/3``, ``T1/3`` ...).
    """

    face: Face
    axis: int
    ratio: Fraction
    lines: tuple[ConstructionLine, ...]
    result: ConstructionLine
    coord: float
    points: tuple[tuple[str, Vec3], ...]

    @property
    def label(self) -> str:
        """The ratio as text, e.g. ``1/3``, ``-1/2``."""
        return _label(self.ratio)

    @property
    def guide_lines(self) -> int:
        """Number of lines drawn (``len(lines)``)."""
        return len(self.lines)

    def point(self, name: str) -> Vec3:
        """The named construction point ``name`` (``KeyError`` if absent)."""
        for n, p in self.points:
            if n == name:
                return p
        raise KeyError(name)


# ----------------------------------------------------------------------------- exact sketching


def _meet(p1: Local, q1: Local, p2: Local, q2: Local) -> Local:
    """Exact intersection of the lines ``p1 q1`` and ``p2 q2`` in local coordinates."""
    d1 = (q1[0] - p1[0], q1[1] - p1[1])
    d2 = (q2[0] - p2[0], q2[1] - p2[1])
    den = d1[0] * d2[1] - d1[1] * d2[0]
    if den == 0:
        raise ValueError("parallel construction lines")  # a bug in a construction below
    r = (p2[0] - p1[0], p2[1] - p1[1])
    lam = (r[0] * d2[1] - r[1] * d2[0]) / den
    return (p1[0] + lam * d1[0], p1[1] + lam * d1[1])


_ZERO, _ONE = Fraction(0), Fraction(1)


class _Sketch:
    """Named points and lines in local ``(s, t)``, each point made by earlier lines."""

    def __init__(self) -> None:
        self.at: dict[str, Local] = {"A": (_ZERO, _ZERO), "B": (_ONE, _ZERO),
                                     "C": (_ONE, _ONE), "D": (_ZERO, _ONE)}
        self.made: list[str] = []
        self.lines: list[tuple[str, str, str, str, str | None]] = []

    def put(self, name: str, p: Local) -> str:
        if name in self.at:
            if self.at[name] != p:
                raise ArithmeticError(f"point {name} made twice at different places")  # a bug
            return name
        self.at[name] = p
        self.made.append(name)
        return name

    def line(self, key: str, start: str, end: str, along: str | None = None,
             role: str = "construction") -> None:
        self.lines.append((key, role, start, end, along))

    def meet(self, name: str, l1: tuple[str, str], l2: tuple[str, str]) -> str:
        at = self.at
        return self.put(name, _meet(at[l1[0]], at[l1[1]], at[l2[0]], at[l2[1]]))

    def division(self, through: str, role: str = "guide") -> Fraction:
        """The line through point ``through`` parallel to ``AD``, from edge AB to edge DC."""
        s = self.at[through][0]
        lo, hi = self.put(f"S{s}", (s, _ZERO)), self.put(f"T{s}", (s, _ONE))
        self.line("division", lo, hi, "t", role)
        return s

    def centre(self) -> None:
        self.line("diagonal", "A", "C")
        self.line("diagonal", "B", "D")
        self.meet("O", ("A", "C"), ("B", "D"))

    def cross(self) -> None:
        """The line through ``O`` parallel to ``AB``: midpoints ``E`` of AD, ``F`` of BC."""
        t = self.at["O"][1]
        self.put("E", (_ZERO, t))
        self.put("F", (_ONE, t))
        self.line("cross", "E", "F", "s")


def _half(sk: _Sketch, role: str = "guide") -> Fraction:
    sk.centre()
    return sk.division("O", role)


def _quarter(sk: _Sketch, left: bool) -> Fraction:
    half = f"{_half(sk, 'construction')}"
    s_half, t_half = f"S{half}", f"T{half}"
    if left:  # half face A, S1/2, T1/2, D
        sk.line("diagonal", "A", t_half)
        sk.line("diagonal", s_half, "D")
        sk.meet("Q1", ("A", t_half), (s_half, "D"))
        return sk.division("Q1")
    sk.line("diagonal", s_half, "C")  # half face S1/2, B, C, T1/2
    sk.line("diagonal", "B", t_half)
    sk.meet("Q3", (s_half, "C"), ("B", t_half))
    return sk.division("Q3")


def _third(sk: _Sketch, first: bool) -> Fraction:
    sk.centre()
    sk.cross()
    if first:  # paper Fig. 3c: C-E meets the diagonal B-D at I1 = (1/3, 2/3)
        sk.line("connect", "C", "E")
        sk.meet("I1", ("C", "E"), ("B", "D"))
        return sk.division("I1")
    sk.line("connect", "D", "F")
    sk.meet("I2", ("D", "F"), ("A", "C"))
    return sk.division("I2")


def _extend(sk: _Sketch, after: bool, by_half: bool) -> Fraction:
    """Reflection through the midpoint of the shared edge (paper Fig. 3d), of the whole face
    or (``by_half``) of the half face next to the shared edge."""
    if by_half:
        half = _half(sk, "construction")
        origin = f"T{half}"
    else:
        sk.centre()
        origin = "D" if after else "C"
    sk.cross()
    mid = "F" if after else "E"  # midpoint of the shared edge BC (AD)
    edge = ("A", "B") if after else ("B", "A")
    at = sk.at
    s_new = _meet(at[origin], at[mid], at[edge[0]], at[edge[1]])[0]
    sk.line("extend", edge[0], f"S{s_new}", "s")   # edge AB extended toward its VP
    sk.line("connect", origin, f"S{s_new}")         # ... through the midpoint, to the extension
    return sk.division(sk.meet(f"S{s_new}", (origin, mid), edge))


def _edge(sk: _Sketch, end: bool) -> Fraction:
    lo, hi = ("B", "C") if end else ("A", "D")
    r = _ONE if end else _ZERO
    sk.put(f"S{r}", sk.at[lo])
    sk.put(f"T{r}", sk.at[hi])
    sk.line("align", lo, hi, "t", "guide")
    return r


_BUILDERS: dict[Fraction, Callable[[_Sketch], Fraction]] = {
    Fraction(-1): lambda sk: _extend(sk, after=False, by_half=False),
    Fraction(-1, 2): lambda sk: _extend(sk, after=False, by_half=True),
    Fraction(0): lambda sk: _edge(sk, end=False),
    Fraction(1, 4): lambda sk: _quarter(sk, left=True),
    Fraction(1, 3): lambda sk: _third(sk, first=True),
    Fraction(1, 2): _half,
    Fraction(2, 3): lambda sk: _third(sk, first=False),
    Fraction(3, 4): lambda sk: _quarter(sk, left=False),
    Fraction(1): lambda sk: _edge(sk, end=True),
    Fraction(3, 2): lambda sk: _extend(sk, after=True, by_half=True),
    Fraction(2): lambda sk: _extend(sk, after=True, by_half=False),
}


def construct(face: Face, axis: int, ratio: float) -> Construction:
    """The construction of the line at ``ratio`` along in-face ``axis`` of ``face``.

    Args:
        face: the face to draw on.
        axis: one of ``face.in_axes``; the ratio is measured from the box's ``lo`` along it.
        ratio: one of ``RATIOS`` (a float within ``RATIO_TOL`` is accepted).

    Returns:
        The construction, with exact 3D points (see the module doc for each ratio's lines).

    Raises:
        ValueError: ``axis`` is not in the face or ``ratio`` has no construction (a bug: the
            ratio catalogue lists only supported ratios).
    """
    if axis not in face.in_axes:
        raise ValueError(f"axis {axis!r} is not in the face normal to {face.normal}")
    r = ratio_key(ratio)
    other = face.in_axes[1] if axis == face.in_axes[0] else face.in_axes[0]
    sketch = _sketch(r)
    u_first = axis == face.in_axes[0]
    # each named point once (face.point is pure: the same point wherever it is used)
    at = {name: face.point(s, t) if u_first else face.point(t, s)
          for name, (s, t) in sketch.at.items()}
    along = {"s": axis, "t": other, None: None}
    lines = tuple(ConstructionLine(k, role, at[a], at[b], along[al], (a, b))
                  for k, role, a, b, al in sketch.lines)
    lo, hi = face.box[0][axis], face.box[1][axis]
    return Construction(
        face=face, axis=axis, ratio=r, lines=lines, result=lines[-1],
        coord=lo + float(r) * (hi - lo),
        points=tuple((name, at[name]) for name in sketch.names),
    )


@dataclass(frozen=True, slots=True)
class _Sketched:
    """A ratio's construction in local ``(s, t)`` (:class:`_Sketch`), as :func:`construct`
    maps it onto a face."""

    at: dict[str, tuple[float, float]]  #: every named point, as floats (``float`` of exact)
    names: tuple[str, ...]  #: ``A B C D`` and the points made, in order
    lines: tuple[tuple[str, str, str, str, str | None], ...]  #: key, role, start, end, along


@lru_cache(maxsize=None)
def _sketch(r: Fraction) -> _Sketched:
    """The construction of ratio ``r`` (one of ``RATIOS``) in local coordinates, made once:
    it depends on the ratio alone, and its exact arithmetic (``Fraction``) was most of a
    :func:`construct` (a view's sequence constructs some hundred lines).  The points are kept
    as floats: ``Face.point`` takes ``float`` of its fractions, the same number either way."""
    sk = _Sketch()
    got = _BUILDERS[r](sk)
    if got != r:  # the constructions are exact: this is a bug, not a tolerance question
        raise ArithmeticError(f"construction for {r} landed at {got}")
    at = {name: (float(s), float(t)) for name, (s, t) in sk.at.items()}
    return _Sketched(at, ("A", "B", "C", "D", *sk.made), tuple(sk.lines))


def align(start: Any, end: Any, *, tol: float = 1e-9) -> ConstructionLine:
    """An alignment guide (paper Fig. 3e): the segment ``start``–``end`` along one model axis.

    On paper it runs toward that axis's vanishing point, carrying a position from one face to
    another (``M'N'`` aligned with ``MN``).

    Raises:
        ValueError: the points differ along more or fewer than one axis (beyond ``tol`` times
            their distance).
    """
    a = np.asarray(start, dtype=float).reshape(3)
    b = np.asarray(end, dtype=float).reshape(3)
    diff = np.abs(b - a)
    length = float(diff.max())
    moving = [i for i in range(3) if diff[i] > tol * max(length, 1e-300)]
    if len(moving) != 1:
        raise ValueError(f"alignment needs two points apart along exactly one axis, got "
                         f"{a.tolist()} and {b.tolist()}")
    return ConstructionLine("align", "guide", (float(a[0]), float(a[1]), float(a[2])),
                            (float(b[0]), float(b[1]), float(b[2])), moving[0])


# ----------------------------------------------------------------------------- equal spacing


@dataclass(frozen=True, slots=True)
class SpacedEnd:
    """One end of a box placed by equal spacing: the line from the end two boxes back (at the
    face's ``across`` top), through the end one box back (on the middle line), meets the
    row's bottom line where this end lies.

    Attributes:
        start, through, end: the line's end points and the point it passes through, model
            units; ``end`` is the constructed end (exactly ``2 e(k-1) - e(k-2)`` along the row).
        edge: the resulting line, the box's edge through ``end`` across the row (role guide).
    """

    start: Vec3
    through: Vec3
    end: Vec3
    edge: ConstructionLine


@dataclass(frozen=True, slots=True)
class Spacing:
    """Boxes repeated at equal spacing along a row, in one face plane (paper Fig. 3d's
    "extend by 1x", repeated: the spacing of two boxes carried to the next).

    The first box's face gets its diagonals, crossing at ``centre``; the line through the
    centre along the row is the row's *middle line*, and the row's top and bottom edge lines
    run along it.  A box ``k >= 2`` is placed from boxes ``k - 2`` and ``k - 1``: for each of
    its two ends, a line from the end of box ``k - 2`` on the top line, through the same end of
    box ``k - 1`` on the middle line, meets the bottom line at the end of box ``k``.  It is
    exact because those three points are collinear in 3D exactly when the spacing is equal
    (the middle line is halfway between top and bottom), and projection keeps lines straight.

    Attributes:
        face: the first box's face (plane and across extent shared by the row).
        axis: the row's axis (an in-face axis of ``face``); ``across`` the other in-face axis.
        diagonals: ``((A, C), (B, D))``: the first face's diagonals (role construction).
        centre: where they cross.
        middle, top, bottom: the row's middle line (construction) and its top and bottom edge
            lines (guide), from the first box's ``lo`` to the last box's ``hi`` along ``axis``.
        ends: per placed box (``k = 2, 3 ...``), its ``(lo, hi)`` :class:`SpacedEnd`.
    """

    face: Face
    axis: int
    across: int
    diagonals: tuple[tuple[Vec3, Vec3], tuple[Vec3, Vec3]]
    centre: Vec3
    middle: ConstructionLine
    top: ConstructionLine
    bottom: ConstructionLine
    ends: tuple[tuple[SpacedEnd, SpacedEnd], ...]

    @property
    def lines(self) -> tuple[ConstructionLine, ...]:
        """Every line drawn, in order: diagonals, middle, top, bottom, then per placed box its
        two spacing lines (construction) and two edges (guide)."""
        (a, c), (b, d) = self.diagonals
        out = [ConstructionLine("diagonal", "construction", a, c),
               ConstructionLine("diagonal", "construction", b, d),
               self.middle, self.top, self.bottom]
        for pair in self.ends:
            out += [ConstructionLine("connect", "construction", e.start, e.end) for e in pair]
            out += [e.edge for e in pair]
        return tuple(out)


def equal_spacing(face: Face, axis: int, intervals: Any) -> Spacing:
    """The equal-spacing construction (:class:`Spacing`) of a row of boxes.

    Args:
        face: a face of the row's first box whose in-face axes include ``axis``.
        axis: the row's axis.
        intervals: ``(lo, hi)`` of each box along ``axis``, in row order (at least 3); the
            spacing from one box to the next must be the same for the construction to land
            on the boxes (it lands at ``2 e(k-1) - e(k-2)`` whatever they are).

    Raises:
        ValueError: ``axis`` is not in the face, or fewer than 3 intervals.
    """
    if axis not in face.in_axes:
        raise ValueError(f"axis {axis} does not lie in a face normal to {face.normal}")
    iv = [(float(lo), float(hi)) for lo, hi in intervals]
    if len(iv) < 3:
        raise ValueError(f"equal spacing needs at least 3 boxes, got {len(iv)}")
    across = next(a for a in face.in_axes if a != axis)
    b_lo, b_hi = face.box[0][across], face.box[1][across]
    b_mid = 0.5 * (b_lo + b_hi)

    def at(x: float, y: float) -> Vec3:
        p = [0.0, 0.0, 0.0]
        p[face.normal], p[axis], p[across] = face.coord, x, y
        return (p[0], p[1], p[2])

    first, last = iv[0][0], iv[-1][1]
    a, b, c, d = face.corners
    ends = []
    for k in range(2, len(iv)):
        pair = []
        for e in (0, 1):
            x2, x1 = iv[k - 2][e], iv[k - 1][e]
            x = 2.0 * x1 - x2
            pair.append(SpacedEnd(at(x2, b_hi), at(x1, b_mid), at(x, b_lo),
                                  ConstructionLine("division", "guide", at(x, b_lo),
                                                   at(x, b_hi), across)))
        ends.append((pair[0], pair[1]))
    return Spacing(face=face, axis=axis, across=across, diagonals=((a, c), (b, d)),
                   centre=face.centre,
                   middle=ConstructionLine("cross", "construction", at(first, b_mid),
                                           at(last, b_mid), axis),
                   top=ConstructionLine("align", "guide", at(first, b_hi), at(last, b_hi), axis),
                   bottom=ConstructionLine("align", "guide", at(first, b_lo), at(last, b_lo),
                                           axis),
                   ends=tuple(ends))


# ----------------------------------------------------------------------------- ellipses


@dataclass(frozen=True, slots=True, eq=False)
class FaceEllipse:
    """The ellipse inscribed in a face, guided as in paper §5 ("Vanishing points and ellipses").

    Attributes:
        face: the enclosing face.
        centre: the face centre (where the diagonals meet), model units.
        touch: the four touching points, the midpoints of edges ``BC``, ``CD``, ``DA``, ``AB``
            (in the order of the parameter angle 0, 90, 180, 270 deg), model units.
        lines: the diagonals ``A–C``, ``B–D`` (construction) and the two lines through the
            centre parallel to the face edges (guide; toward the VPs on paper), which meet the
            edges at the touching points.
        points3d: (n, 3) float, read-only: the inscribed circle (ellipse for a non-square face)
            ``centre + (hu cos θ) e_u + (hv sin θ) e_v``, ``θ = 2πk/n``, model units; closed
            implicitly (the last point joins the first).
        points_mm: (n, 2) float, read-only: their exact projections on the sheet, mm.
        centre_mm: the centre's projection, mm.
        touch_mm: (4, 2) float, read-only: the touching points' projections, mm.
    """

    face: Face
    centre: Vec3
    touch: tuple[Vec3, Vec3, Vec3, Vec3]
    lines: tuple[ConstructionLine, ...]
    points3d: np.ndarray
    points_mm: np.ndarray
    centre_mm: tuple[float, float]
    touch_mm: np.ndarray


def ellipse_on_face(face: Face, camera: Camera, n: int = 96) -> FaceEllipse:
    """The ellipse inscribed in ``face`` and its projection by ``camera``.

    Args:
        face: the enclosing face (a cylinder's end face, say).
        camera: the view.
        n: number of polyline points, a positive multiple of 4 (so the touching points are
            vertices of the polyline).

    Raises:
        ValueError: ``n`` is not a positive multiple of 4.
        RenderError: part of the ellipse is behind or at the camera plane.
    """
    if not (isinstance(n, int) and n >= 4 and n % 4 == 0):
        raise ValueError(f"n must be a positive multiple of 4, got {n!r}")
    a, b, c, d = face.corners
    u, v = face.in_axes
    centre = face.centre
    touch = (face.point(1, 0.5), face.point(0.5, 1), face.point(0, 0.5), face.point(0.5, 0))
    lines = (
        ConstructionLine("diagonal", "construction", a, c),
        ConstructionLine("diagonal", "construction", b, d),
        ConstructionLine("mid", "guide", touch[2], touch[0], u),
        ConstructionLine("mid", "guide", touch[3], touch[1], v),
    )
    theta = 2 * np.pi * np.arange(n) / n
    cos, sin = np.cos(theta), np.sin(theta)
    # exact zeros at the quarter angles: the touching points are vertices
    q = np.arange(n) * 4 % n == 0
    cos[q], sin[q] = np.round(cos[q]), np.round(sin[q])
    pts = np.tile(np.asarray(centre, dtype=float), (n, 1))
    lo, hi = face.box
    pts[:, u] += (hi[u] - lo[u]) / 2 * cos
    pts[:, v] += (hi[v] - lo[v]) / 2 * sin
    if float(camera.depth(np.vstack([pts, [a, b, c, d]])).min()) <= 0:
        raise RenderError(f"the ellipse on face {face.normal}/{face.end} of box {face.box} is "
                          "behind or at the camera plane")
    cmm = camera.project([centre])[0]
    return FaceEllipse(
        face=face, centre=centre, touch=touch, lines=lines,
        points3d=readonly(pts, np.float64),
        points_mm=readonly(camera.project(pts), np.float64),
        centre_mm=(float(cmm[0]), float(cmm[1])),
        touch_mm=readonly(camera.project(np.array(touch)), np.float64),
    )
