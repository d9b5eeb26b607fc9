"""Which points of the scaffold the drawn primitives hide (exact, for convex solids).

The finished drawing's lines are hidden by the parts' meshes (:mod:`h2s_print.contours`); the
*scaffold* is drawn over the primitives the reader has drawn, so what hides a scaffold line is
those primitives: boxes, frusta (convex polyhedra) and cylinders.  A point ``P`` is hidden when
the segment from the eye to ``P`` runs through the inside of a solid for a stretch longer than
:data:`EPS` of its length before reaching ``P``: a point on a solid's surface facing the eye is
seen, one on its far side or inside it is not.  Used for the ellipses of the ellipse steps (the
far end of a cylinder is half hidden by the cylinder itself; a column's top ellipse lies
inside the table top drawn before it), which the pages then draw dotted, and for the edges of
a box drawn behind or inside a part drawn before it (:func:`hidden_spans`: a desk's leg under
its top, a plate's dowels sunk in it).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

#: Share of the eye-point segment inside a solid below which the point counts as seen
#: (points on a surface facing the eye, up to rounding and tessellation).
EPS = 1e-6


@dataclass(frozen=True, slots=True, eq=False)
class Solid:
    """A convex solid: the half-spaces ``normals @ x <= offsets`` and, for a cylinder, the
    elliptic cross-section ``((x_u - cu) / ru)**2 + ((x_v - cv) / rv)**2 <= 1`` (``round``:
    ``(axis, (cu, cv), (ru, rv))``) as well."""

    normals: np.ndarray
    offsets: np.ndarray
    round: tuple[int, tuple[float, float], tuple[float, float]] | None = None


def outward_normals(points: np.ndarray, faces: Sequence[Sequence[int]]
                    ) -> list[tuple[np.ndarray, np.ndarray]]:
    """Per face of a convex solid: its normal by Newell's method (not normalised; zero for a
    degenerate face), turned away from the vertices' centroid, and the face's centroid."""
    pts = np.asarray(points, dtype=float)
    centre = pts.mean(axis=0)
    out = []
    for f in faces:
        poly = pts[list(f)]
        # each edge's cross product at once, summed in edge order from zero (accumulate
        # adds one after the other: the same sum as adding them one by one)
        crosses = np.cross(poly, np.concatenate([poly[1:], poly[:1]]))  # edge by edge
        n = np.add.accumulate(np.vstack([np.zeros((1, 3)), crosses]), axis=0)[-1]
        fc = poly.mean(axis=0)
        out.append((-n if np.dot(n, fc - centre) < 0 else n, fc))
    return out


def polyhedron(points: np.ndarray, faces: Sequence[Sequence[int]]) -> Solid:
    """The convex polyhedron with these vertices and (planar) faces, normals pointing out."""
    normals, offsets = [], []
    for n, fc in outward_normals(points, faces):
        length = float(np.linalg.norm(n))
        if length == 0.0:
            continue
        n = n / length
        normals.append(n)
        offsets.append(float(n @ fc))
    return Solid(np.array(normals).reshape(-1, 3), np.array(offsets))


def box_solid(box: Sequence[Sequence[float]]) -> Solid:
    """The axis-aligned box ``box``."""
    lo, hi = (np.asarray(x, dtype=float) for x in box)
    eye = np.eye(3)
    return Solid(np.vstack([eye, -eye]), np.concatenate([hi, -lo]))


def cylinder_solid(box: Sequence[Sequence[float]], axis: int) -> Solid:
    """The cylinder inscribed in ``box`` along ``axis`` (an elliptic one if the box is not
    square across)."""
    lo, hi = (np.asarray(x, dtype=float) for x in box)
    u, v = (a for a in range(3) if a != axis)
    eye = np.eye(3)
    caps = Solid(np.vstack([eye[axis], -eye[axis]]), np.array([hi[axis], -lo[axis]]))
    return Solid(caps.normals, caps.offsets,
                 (axis, ((lo[u] + hi[u]) / 2, (lo[v] + hi[v]) / 2),
                  ((hi[u] - lo[u]) / 2, (hi[v] - lo[v]) / 2)))


def _inside(solid: Solid, eye: np.ndarray, d: np.ndarray,
            planes: _Planes | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Per segment ``eye + t d`` (``t`` in [0, 1]), the interval ``[t0, t1]`` inside ``solid``
    (empty when ``t0 >= t1``); ``planes``: its planes as :func:`_planes` of ``[solid]`` gives
    them, when already at hand."""
    planes = _planes([solid], eye) if planes is None else planes
    t0, t1 = (t[:, 0] for t in _inside_planes(planes, d))  # its planes
    if solid.round is not None:
        axis, (cu, cv), (ru, rv) = solid.round
        u, v = (a for a in range(3) if a != axis)
        au, av = (eye[u] - cu) / ru, (eye[v] - cv) / rv
        bu, bv = d[:, u] / ru, d[:, v] / rv
        a = bu * bu + bv * bv
        b = 2.0 * (au * bu + av * bv)
        c = au * au + av * av - 1.0
        disc = b * b - 4.0 * a * c
        ok = (a > 0) & (disc >= 0)
        root = np.sqrt(np.where(ok, disc, 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            r0 = np.where(ok, (-b - root) / (2.0 * a), np.inf)
            r1 = np.where(ok, (-b + root) / (2.0 * a), -np.inf)
        parallel = a <= 0  # along the axis: inside the cross-section throughout, or never
        r0 = np.where(parallel, np.where(c <= 0, -np.inf, np.inf), r0)
        r1 = np.where(parallel, np.where(c <= 0, np.inf, -np.inf), r1)
        t0, t1 = np.maximum(t0, r0), np.minimum(t1, r1)
    return t0, t1


def hidden(points: np.ndarray, eye: Sequence[float], solids: Sequence[Solid]) -> np.ndarray:
    """Per point, whether a solid hides it from ``eye`` (module docstring)."""
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    e = np.asarray(eye, dtype=float)
    d = p - e
    out = np.zeros(len(p), dtype=bool)
    for solid in solids:
        t0, t1 = _inside(solid, e, d)
        out |= (t1 - t0 > EPS) & (t0 < 1.0 - EPS)
    return out


def runs(points: np.ndarray, mask: np.ndarray) -> list[tuple[bool, np.ndarray]]:
    """A closed polyline (last point = first) cut where ``mask`` changes: ``(masked, run)``
    pairs, consecutive runs sharing their end points, together the whole polyline."""
    pts = np.asarray(points, dtype=float)
    flags = np.asarray(mask, dtype=bool)
    n = len(pts) - 1  # distinct points of the closed loop
    if n < 1 or flags[:n].all() or not flags[:n].any():
        return [(bool(flags[0]) if len(flags) else False, pts)]
    start = int(np.flatnonzero(flags[:n] != np.roll(flags[:n], 1))[0])  # a change at start
    order = [(start + k) % n for k in range(n + 1)]
    out: list[tuple[bool, np.ndarray]] = []
    run = [order[0]]
    for i in order[1:]:
        run.append(i)
        if flags[i] != flags[run[0]] or i == order[-1]:
            out.append((bool(flags[run[0]]), pts[run]))
            run = [i]
    return out


@dataclass(frozen=True, slots=True, eq=False)
class _Planes:
    """Solids with as many planes each, stacked, and seen from one eye (:func:`_planes`)."""

    normals: np.ndarray  # (S, k, 3)
    offsets: np.ndarray  # (S, k)
    room: np.ndarray  # (S, k): offsets - normals @ eye


def _planes(solids: Sequence[Solid], eye: np.ndarray) -> _Planes:
    """The half-spaces of ``solids`` (as many planes each) stacked for :func:`_inside_planes`."""
    normals = np.stack([sd.normals for sd in solids])  # (S, k, 3)
    offsets = np.stack([sd.offsets for sd in solids])  # (S, k)
    return _Planes(normals, offsets, offsets - normals @ eye)


@dataclass(frozen=True, slots=True, eq=False)
class _Occluders:
    """Solids seen from ``eye``, prepared for :func:`_hidden_deep` (:func:`_occluders`): the
    round ones one by one with their planes, the others stacked by their number of planes."""

    eye: np.ndarray
    round: tuple[tuple[Solid, _Planes], ...]
    flat: tuple[_Planes, ...]


def _occluders(solids: Sequence[Solid], eye: np.ndarray) -> _Occluders:
    flat: dict[int, list[Solid]] = {}
    rnd = []
    for solid in solids:
        if solid.round is None:
            flat.setdefault(len(solid.offsets), []).append(solid)
        else:
            rnd.append((solid, _planes([solid], eye)))
    return _Occluders(eye, tuple(rnd), tuple(_planes(g, eye) for g in flat.values()))


def _hidden_deep(points: np.ndarray, eye: np.ndarray, solids: Sequence[Solid] | _Occluders,
                 depth: float) -> np.ndarray:
    """Per point, whether the segment from ``eye`` to it runs inside a solid for longer than
    ``depth`` (model units) before reaching it.  Solids bounded by planes only, with as many
    planes each (boxes), are taken together (:func:`_inside_planes`); the others one by one.
    ``solids`` may come prepared (:func:`_occluders`, for ``eye``): :func:`hidden_spans` asks
    of the same solids some twenty times, and stacking them is most of a small call."""
    occ = solids if isinstance(solids, _Occluders) else _occluders(solids, eye)
    d = points - eye
    length = np.linalg.norm(d, axis=1)
    out = np.zeros(len(points), dtype=bool)
    for solid, planes in occ.round:
        t0, t1 = _inside(solid, eye, d, planes)
        out |= (t1 - t0) * length > depth
    for planes in occ.flat:
        t0, t1 = _inside_planes(planes, d)  # (m, S)
        out |= (((t1 - t0) * length[:, None]) > depth).any(axis=1)
    return out


def _inside_flat(solids: Sequence[Solid], eye: np.ndarray, d: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Per segment ``eye + t d`` and solid, the interval ``[t0, t1]`` inside the solid's
    half-spaces (its round cross-section, if any, left to :func:`_inside`), for solids with
    the same number of planes, at once: ``(t0, t1)`` of shape (segments, solids)."""
    return _inside_planes(_planes(solids, eye), d)


def _inside_planes(planes: _Planes, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`_inside_flat` of solids already stacked (:func:`_planes`)."""
    normals, offsets, room = planes.normals, planes.offsets, planes.room
    nd = (d @ normals.reshape(-1, 3).T).reshape(len(d), *offsets.shape)  # (m, S, k)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = room[None, :, :] / nd
    entering = nd < 0
    leaving = nd > 0
    never = (nd == 0) & (room[None, :, :] < 0)
    t0 = np.maximum(0.0, np.where(entering, t, -np.inf).max(axis=2, initial=-np.inf))
    t1 = np.minimum(1.0, np.where(leaving, t, np.inf).min(axis=2, initial=np.inf))
    t1 = np.where(never.any(axis=2), -np.inf, t1)
    return t0, t1


#: Points sampled along a segment by :func:`hidden_spans` before its changes are refined.
SPAN_SAMPLES = 129
#: Bisection rounds refining each change (the change is then known to 2**-18 of the segment:
#: under a thousandth of a millimetre for an edge up to 260 mm long on the sheet).
SPAN_ROUNDS = 18


def hidden_spans(a: Sequence[float], b: Sequence[float], eye: Sequence[float],
                 solids: Sequence[Solid], depth: float) -> list[tuple[float, float]]:
    """The stretches ``(s0, s1)`` (``0 <= s0 < s1 <= 1``, along ``a + s (b - a)``) of the
    segment that ``solids`` hide from ``eye``: the eye's line of sight to the point runs inside
    one of them for longer than ``depth`` (a point on a surface, or inside by less than
    ``depth``, counts as seen: parts touching within the model's tolerances hide nothing of
    each other).  Found on :data:`SPAN_SAMPLES` points, each change refined by bisection; a
    hidden stretch shorter than the samples' spacing may be missed."""
    pa, pb, e = (np.asarray(x, dtype=float) for x in (a, b, eye))
    if not solids:
        return []
    occ = _occluders(solids, e)  # stacked once for the samples and every bisection round
    s = np.linspace(0.0, 1.0, SPAN_SAMPLES)
    mask = _hidden_deep(pa + s[:, None] * (pb - pa), e, occ, depth)
    if not mask.any():
        return []
    change = np.flatnonzero(mask[1:] != mask[:-1])
    lo, hi = s[change], s[change + 1]
    start_hidden = mask[change]  # hidden at lo: the change ends a hidden stretch
    for _ in range(SPAN_ROUNDS):
        mid = 0.5 * (lo + hi)
        m = _hidden_deep(pa + mid[:, None] * (pb - pa), e, occ, depth)
        same = m == start_hidden
        lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
    cuts = 0.5 * (lo + hi)
    bounds = [0.0, *cuts.tolist(), 1.0]
    flags = [bool(mask[0]), *[not bool(f) for f in start_hidden]]
    return [(bounds[k], bounds[k + 1]) for k, f in enumerate(flags) if f]
