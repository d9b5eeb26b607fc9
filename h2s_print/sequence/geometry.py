"""Geometry of the steps: boxes, faces seen from the camera, scaffolds, anchor constructions."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from ..constructions import Face, align, construct
from ..instructions import Pts
from ..occlude import outward_normals
from ..ratios import entry_for
from ..types import Box, Camera, Part, Stroke, Vec3

#: Closed contour loops smaller than this on the sheet (largest side of their extent, mm) are
#: dropped from the contour steps and the final drawing: a merged screw head draws a dot.
TINY_LOOP_MM = 1.0


#: A face whose projected width on the sheet (its projected area over its longest projected
#: side, mm) is under this is too thin for guide lines (seen almost edge-on): its
#: constructions are eyeballed whatever ``settings.eyeball_mm2`` says.
MIN_FACE_WIDTH_MM = 3.0


#: A carry whose lines are shorter than this on the sheet, together (mm), moves a line by
#: about three pencil widths or less, nothing one draws on purpose: the line is used where
#: it is ("Extend QR as pictured" by a millimetre, the chair's seat, a read-through).
TINY_CARRY_MM = 1.5


def _sheet_length(camera: Camera, line: Any) -> float:
    """The length of a 3D line on the sheet, mm."""
    a, b = camera.project(np.array([line.start, line.end], dtype=float))
    return float(np.linalg.norm(b - a))


def _vec(p: Any) -> Vec3:
    return (float(p[0]), float(p[1]), float(p[2]))


def _box_corners(box: Box) -> np.ndarray:
    lo, hi = box
    return np.array([[(lo, hi)[i][0], (lo, hi)[j][1], (lo, hi)[k][2]]
                     for i in (0, 1) for j in (0, 1) for k in (0, 1)], dtype=float)


def _extent(box: Box, axis: int) -> float:
    return box[1][axis] - box[0][axis]


def _map_points(points: np.ndarray, from_box: Box, to_box: Box) -> np.ndarray:
    """The per-axis affine change of :func:`h2s_print.contours.adjust_part`, on points."""
    out = np.empty_like(points)
    for ax in range(3):
        flo, fhi, tlo, thi = from_box[0][ax], from_box[1][ax], to_box[0][ax], to_box[1][ax]
        if fhi - flo > 0.0:
            t = (points[:, ax] - flo) / (fhi - flo)
            out[:, ax] = (1.0 - t) * tlo + t * thi
        else:
            out[:, ax] = points[:, ax] - flo + tlo
    return out


def _same_point(x: Any, y: Any, tol: float) -> bool:
    """True when 3D points ``x`` and ``y`` agree within ``tol`` per coordinate."""
    return (abs(float(x[0]) - float(y[0])) <= tol and abs(float(x[1]) - float(y[1])) <= tol
            and abs(float(x[2]) - float(y[2])) <= tol)


def _same_segment(a: Any, b: Any, p: Any, q: Any, tol: float) -> bool:
    """True when segment ``a-b`` is segment ``p-q`` up to endpoint order, within ``tol``
    (per coordinate; plain floats: called some 10 000 times a view)."""
    return ((_same_point(a, p, tol) and _same_point(b, q, tol))
            or (_same_point(a, q, tol) and _same_point(b, p, tol)))


def _same_segments(a: Any, b: Any, starts: np.ndarray, ends: np.ndarray,
                   tol: float) -> np.ndarray:
    """:func:`_same_segment` of ``a-b`` with each row's segment ``starts[i]-ends[i]`` ((n, 3)
    arrays), at once: (n,) bool.  The same differences, the same ``abs`` and the same
    comparisons, element by element, so the same answers."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return (((np.abs(starts - a) <= tol).all(axis=1) & (np.abs(ends - b) <= tol).all(axis=1))
            | ((np.abs(starts - b) <= tol).all(axis=1) & (np.abs(ends - a) <= tol).all(axis=1)))


class _Segments:
    """Segments kept in order, looked up within ``tol`` (:func:`_same_segment`, either end
    first): :meth:`matches` says which, as a scan in order would, by one array comparison
    (a view's guides and drawn lines are looked up some 100 000 times on the generated
    assemblies)."""

    def __init__(self, tol: float) -> None:
        self.tol = tol
        self.n = 0
        self._ends = np.empty((16, 2, 3))

    def add(self, a: Any, b: Any) -> int:
        """Keep ``a-b`` (its index returned)."""
        if self.n == len(self._ends):
            self._ends = np.concatenate([self._ends, np.empty_like(self._ends)])
        self._ends[self.n, 0], self._ends[self.n, 1] = a, b
        self.n += 1
        return self.n - 1

    def matches(self, a: Any, b: Any) -> np.ndarray:
        """(n,) bool: the kept segments that are ``a-b`` within ``tol``."""
        ends = self._ends[:self.n]
        return _same_segments(a, b, ends[:, 0], ends[:, 1], self.tol)

    def first(self, a: Any, b: Any) -> int | None:
        """The index of the first kept segment that is ``a-b`` within ``tol``, if any."""
        if not self.n:
            return None
        hit = self.matches(a, b)
        i = int(hit.argmax())
        return i if hit[i] else None


def _tiny_loop(mm: np.ndarray) -> bool:
    """True for a closed polyline whose extent on the sheet is under ``TINY_LOOP_MM``."""
    if len(mm) < 3 or float(np.abs(mm[0] - mm[-1]).max()) > 1e-6 * max(1.0, float(np.abs(mm).max())):
        return False
    ext = mm.max(axis=0) - mm.min(axis=0)
    return float(max(ext[0], ext[1])) < TINY_LOOP_MM


#: A box's faces as corner indices of :func:`_box_corners` (each a loop).
_BOX_FACES = ((0, 1, 3, 2), (4, 5, 7, 6), (0, 1, 5, 4), (2, 3, 7, 6), (0, 2, 6, 4), (1, 3, 7, 5))
_FACE_INDEX = np.array(_BOX_FACES)


def _covers(corners_mm: np.ndarray, points_mm: np.ndarray) -> np.ndarray:
    """Which of ``points_mm`` (n, 2) lie inside the sheet picture of a box, given its eight
    corners' projections (8, 2) in :func:`_box_corners`' order, or of any of several boxes
    (k, 8, 2): a box's picture is the union of its faces' pictures, each a convex
    quadrilateral (strictly inside, so a flat box covers nothing)."""
    pts = np.asarray(points_mm, dtype=float).reshape(-1, 2)
    boxes = np.asarray(corners_mm, dtype=float).reshape(-1, 8, 2)
    quads = boxes[:, _FACE_INDEX]  # (k, 6, 4, 2)
    edge = np.roll(quads, -1, axis=2) - quads
    rel = pts[None, None, None, :, :] - quads[:, :, :, None, :]  # (k, 6, 4, n, 2)
    cross = edge[..., None, 0] * rel[..., 1] - edge[..., None, 1] * rel[..., 0]  # (k, 6, 4, n)
    inside = (cross > 1e-9).all(axis=2) | (cross < -1e-9).all(axis=2)  # (k, 6, n)
    return inside.any(axis=(0, 1))


def _sheet_polygon(camera: Camera, corners: Sequence[Vec3]) -> tuple[float, float]:
    """A planar polygon's projection on the sheet: its area (mm², shoelace) and its longest
    side (mm); the area over the longest side is how wide it is."""
    p = camera.project(np.asarray(corners, dtype=float))
    x, y = p[:, 0], p[:, 1]

    def roll(a: np.ndarray) -> np.ndarray:  # np.roll(a, -1, axis=0), a copy as it is, faster
        return np.concatenate([a[1:], a[:1]])

    area = 0.5 * abs(float(np.dot(x, roll(y)) - np.dot(y, roll(x))))
    return area, float(np.linalg.norm(p - roll(p), axis=1).max())


def _polygon_area_mm2(camera: Camera, corners: Sequence[Vec3]) -> float:
    """Area on the sheet (mm²) of a planar polygon's projection (shoelace)."""
    return _sheet_polygon(camera, corners)[0]


def _too_small(camera: Camera, corners: Sequence[Vec3], k: int, eyeball_mm2: float) -> bool:
    """The eyeball rule for one face with ``k`` lines on it (module docstring): projected area
    over ``k`` under ``eyeball_mm2`` mm², or projected width (area over the longest projected
    side) under ``MIN_FACE_WIDTH_MM``."""
    area, longest = _sheet_polygon(camera, corners)
    return area / k < eyeball_mm2 or not area >= MIN_FACE_WIDTH_MM * longest


def _front_facing(face: Face, camera: Camera) -> bool:
    """True when the face's outer side looks toward the camera position."""
    sign = 1.0 if face.end == "hi" else -1.0
    return sign * (camera.position[face.normal] - face.coord) > 0.0


@dataclass(frozen=True, slots=True)
class _Line:
    """A guide line before ids: role and 3D end points."""

    role: str
    start: Vec3
    end: Vec3


#: A line drawn "along" an edge on the sheet: both its ends within this of the edge's line, mm
#: (about a pencil line's width: the mixer's HJ lies 0.37 mm beside the column's edge).
ALONG_MM = 0.5


def _mostly_on(a: np.ndarray, b: np.ndarray, p: np.ndarray, q: np.ndarray, tol: float) -> bool:
    """Does segment ``a-b`` lie on the line of segment ``p-q`` (both ends within ``tol``) and
    overlap ``p-q`` over more than half its own length?"""
    d = q - p
    n = float(np.linalg.norm(d))
    length = float(np.linalg.norm(b - a))
    if n <= tol or length <= tol:
        return False
    u = d / n
    for x in (a, b):
        off = x - p
        if float(np.linalg.norm(off - (off @ u) * u)) > tol:
            return False
    ta, tb = sorted((float((a - p) @ u), float((b - p) @ u)))
    return min(tb, n) - max(ta, 0.0) > 0.5 * length


def _stroke(kind: str, part: str, points: np.ndarray, camera: Camera) -> Stroke:
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    mm = camera.project(pts)
    return Stroke(kind, part, tuple(_vec(p) for p in pts),
                  tuple((float(q[0]), float(q[1])) for q in mm))


def _contour_strokes(cs: Any, camera: Camera) -> tuple[Stroke, ...]:
    """A contour set's polylines as strokes, without tiny closed loops (``TINY_LOOP_MM``)."""
    out = []
    for pl in cs.polylines3d:
        if len(pl) < 2:
            continue
        st = _stroke("contour", cs.part, np.asarray(pl, dtype=float), camera)
        if not _tiny_loop(np.asarray(st.points_mm, dtype=float)):
            out.append(st)
    return tuple(out)


def _drawn_box(primitive: Any, box: Box) -> Box:
    """``box`` as the scaffold draws it: a flat rectangle (a plane fitted with some
    thickness, the IVAR box's base board) in its mid-plane (:func:`_solid`), where the
    constructions on it must lie too (they lay on the board's top face, 2-4 mm off the drawn
    corners on the page: "Centre part 2 on the edge AB" with AB off the edge)."""
    if primitive.type != "plane" or primitive.axis is None:
        return box
    axis = primitive.axis
    mid = 0.5 * (box[0][axis] + box[1][axis])
    lo, hi = list(box[0]), list(box[1])
    lo[axis] = hi[axis] = mid
    return (tuple(lo), tuple(hi))


def _solid(primitive: Any, box: Box) -> tuple[np.ndarray, list[tuple[int, ...]], bool]:
    """Vertices, faces (index tuples) and "flat" flag of the scaffold of ``primitive`` drawn in
    ``box`` (the fitted box mapped to ``box`` per axis for frusta)."""
    kind, axis = primitive.type, primitive.axis
    if kind == "plane" and axis is not None:
        u, v = (a for a in range(3) if a != axis)
        mid = _drawn_box(primitive, box)[0][axis]
        quad = []
        for cu, cv in ((0, 0), (1, 0), (1, 1), (0, 1)):
            p = [0.0, 0.0, 0.0]
            p[axis] = mid
            p[u] = box[cu][u]
            p[v] = box[cv][v]
            quad.append(p)
        return np.array(quad, dtype=float), [(0, 1, 2, 3)], True
    detail = primitive.detail or {}
    if kind == "frustum" and axis is not None and {"lo_half", "hi_half", "centre"} <= set(detail):
        u, v = (a for a in range(3) if a != axis)
        fb = primitive.box
        verts = []
        for end, half in ((0, detail["lo_half"]), (1, detail["hi_half"])):
            for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis] = fb[end][axis]
                p[u] = float(detail["centre"][0]) + su * float(half[0])
                p[v] = float(detail["centre"][1]) + sv * float(half[1])
                verts.append(p)
        pts = _map_points(np.array(verts, dtype=float), fb, box)
        faces = [(0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
        return pts, faces, False
    # box: corner index i*4 + j*2 + k for (x, y, z) ends (i, j, k)
    pts = _box_corners(box)
    return pts, [tuple(f) for f in _BOX_FACES], False


def _scaffold(part: str, primitive: Any, box: Box, camera: Camera, tol: float) -> tuple[Stroke, ...]:
    """The primitive's edges as strokes: ``scaffold`` when an adjacent face is front-facing,
    else ``scaffold_hidden`` (see the module docstring)."""
    pts, faces, flat = _solid(primitive, box)
    cam = np.asarray(camera.position, dtype=float)
    front = [bool(np.dot(n, cam - fc) > 0) and float(np.linalg.norm(n)) > 0
             for n, fc in outward_normals(pts, faces)]
    edges: dict[tuple[int, int], bool] = {}
    for f, fr in zip(faces, front):
        for i in range(len(f)):
            e = tuple(sorted((f[i], f[(i + 1) % len(f)])))
            edges[e] = edges.get(e, False) or fr or flat
    strokes: list[Stroke] = []
    seen: list[tuple[np.ndarray, np.ndarray]] = []
    for (i, j), visible in sorted(edges.items()):
        a, b = pts[i], pts[j]
        if float(np.linalg.norm(b - a)) <= tol:
            continue
        if any(_same_segment(a, b, p, q, tol) for p, q in seen):
            continue
        seen.append((a, b))
        strokes.append(_stroke("scaffold" if visible else "scaffold_hidden", part,
                               np.array([a, b]), camera))
    # visible edges first, each group in a stable order
    return tuple(sorted(strokes, key=lambda s: s.kind != "scaffold"))


def _anchor_face(anchor: Any, pbox: Box, camera: Camera) -> Face:
    """The parent face an anchor's construction is drawn on (module docstring).

    A face the view shows from behind is never used: the anchor's named face, else its twin
    across the box (the same ratio line lies on both), else the view's choice below.
    """
    if anchor.face_side is not None:
        named = Face(pbox, anchor.face_normal, anchor.face_side)
        if _front_facing(named, camera):
            return named
        twin = Face(pbox, anchor.face_normal, "hi" if anchor.face_side == "lo" else "lo")
        if _front_facing(twin, camera):
            return twin
    best: tuple[tuple[bool, float], Face] | None = None
    biggest = max(_extent(pbox, a) for a in range(3))
    for n in range(3):
        if n == anchor.axis:
            continue
        other = 3 - n - anchor.axis
        if _extent(pbox, other) <= 1e-12 * biggest or _extent(pbox, anchor.axis) <= 0.0:
            continue
        for end in ("lo", "hi"):
            f = Face(pbox, n, end)
            key = (_front_facing(f, camera), _polygon_area_mm2(camera, f.corners))
            if best is None or key > best[0]:
                best = (key, f)
    if best is None:  # degenerate parent: fall back to the candidate's own choice
        return Face(pbox, anchor.face_normal, "lo")
    return best[1]


def _turn_plane(anchors: Sequence[Any], child: Box, n: int, near: str,
                floor: float | None = None) -> float:
    """Where along axis ``n`` a carry toward the child turns: on a plane of the child one of
    its ``anchors`` places, so that the turn lies where a construction crosses (read-throughs
    found "Carry FG ... to Q (by eye)" where Q was on no line).  The near face (``near``:
    ``lo`` or ``hi``), else the anchored middle, where the part's centring lines meet on
    their common bisector planes (the paper's roller).  Not the anchored far face: its
    line is often carried a step later, and a corner judged there first then had to meet
    it exactly (a read-through of the train's chimney, stop 32).  A carry down to a part
    standing on the floor (``floor``: its bottom's height) whose top no anchor places turns
    on the floor, where a line from the sheet's floor line can meet it (a read-through of
    the desk: "Carry FG vertically to H (by eye)", H on the floor, exactly found from the
    floor line's foot)."""
    ends = {a.end for a in anchors if a.axis == n}
    side = 0 if near == "lo" else 1
    if near not in ends and "mid" in ends:
        return 0.5 * (child[0][n] + child[1][n])
    if near not in ends and n == 2 and near == "hi" and floor is not None:
        return floor
    return child[side][n]


def _carry_lines(con: Any, face: Face, child: Box, tol: float,
                 anchors: Sequence[Any] = (), floor: float | None = None,
                 foot: Any = None) -> list[_Line]:
    """Alignment lines, in the plane of the anchored end, from the construction's result line
    to the child's end face (module docstring); with the child's ``anchors``, a carry across
    the face's normal turns on a plane they place, or on the ``floor`` the child stands on
    (:func:`_turn_plane`); it leaves the parent's face along the face's edge nearest the
    child, or, turning on the floor, the edge in line with the floor line's ``foot`` (a line
    from the foot along the floor then meets the turn)."""
    a, n = con.axis, face.normal
    o = 3 - a - n
    c = face.coord
    plo, phi = face.box[0][o], face.box[1][o]
    clo, chi = child[0][o], child[1][o]

    def pt(nv: float, ov: float) -> Vec3:
        p = [0.0, 0.0, 0.0]
        p[a], p[n], p[o] = con.coord, nv, ov
        return (p[0], p[1], p[2])

    segs: list[tuple[Vec3, Vec3]] = []
    if child[0][n] - tol <= c <= child[1][n] + tol:
        if chi > phi + tol:
            segs.append((pt(c, phi), pt(c, chi)))
        if clo < plo - tol:
            segs.append((pt(c, plo), pt(c, clo)))
    else:
        m = _turn_plane(anchors, child, n, "lo" if c < child[0][n] else "hi", floor)
        centre = 0.5 * (clo + chi)
        ostar = plo if abs(plo - centre) < abs(phi - centre) else phi
        if foot is not None and floor is not None and m == floor:
            ostar = next((e for e in (ostar, plo, phi) if abs(foot[o] - e) <= tol), ostar)
        segs.append((pt(c, ostar), pt(m, ostar)))
        if ostar > chi + tol:
            segs.append((pt(m, ostar), pt(m, chi)))
        elif ostar < clo - tol:
            segs.append((pt(m, ostar), pt(m, clo)))
    out = []
    for s, e in segs:
        if max(abs(s[i] - e[i]) for i in range(3)) <= tol:
            continue
        ln = align(s, e)
        out.append(_Line("vanishing", ln.start, ln.end))
    return out


@dataclass(frozen=True, slots=True)
class _Crossing:
    """A line carried from where a centring line crosses it (:func:`_crossing_carry`)."""

    lines: tuple[_Line, ...]  # the centring line's extension (when it falls short), U-V
    extended: bool  # the centring line is extended to the crossing
    centring: tuple[Vec3, Vec3]  # the centring line's ends, the one toward U last
    at: Vec3  # U, the crossing
    end: Vec3  # V, on the centring line's carried leg
    leg: tuple[Vec3, Vec3]  # that leg


def _crossing_carry(con: Any, face: Face, carry: Sequence[_Line], mid_con: Any,
                    mid_face: Face, mid_carry: Sequence[_Line], tol: float) -> _Crossing | None:
    """A constructed carry for a line that would turn by eye (the roller's handle's top,
    read-throughs of stop 32): where the part is also centred across the face's other axis by
    a line in the same face plane (``mid_con``, carried off the face and then along the first
    line's axis: the handle's vertical centre line QS), the first line's result (NP) is
    crossed by that centring line (FG, extended to it when short) at ``U``; from ``U`` a
    line along the face's normal meets the centre line's carried leg at ``V`` (S), a point
    of the part's plane the first line places.  None where the geometry is not that."""
    if len(carry) != 2 or len(mid_carry) != 2:
        return None
    a, n = con.axis, face.normal
    o = 3 - a - n
    if (mid_con.axis != o or mid_face.normal != n or abs(mid_face.coord - face.coord) > tol
            or _moving_axis(carry[0]) != n or _moving_axis(carry[1]) != o
            or _moving_axis(mid_carry[0]) != n or _moving_axis(mid_carry[1]) != a):
        return None
    u = [0.0, 0.0, 0.0]
    u[a], u[n], u[o] = con.coord, face.coord, mid_con.coord
    v = list(u)
    v[n] = carry[0].end[n]  # the plane the first line's carry turned on
    U, V = (u[0], u[1], u[2]), (v[0], v[1], v[2])
    res, mres = con.result, mid_con.result
    leg = mid_carry[1]  # the centre line's leg along a: V lies on it (or at its end)
    if not (_on_segment(U, res.start, res.end, tol) and _on_segment(V, leg.start, leg.end, tol)
            and max(abs(U[k] - V[k]) for k in range(3)) > tol):
        return None
    run = _Line("vanishing", U, V)
    if _on_segment(U, mres.start, mres.end, tol):
        return _Crossing((run,), False, (mres.end, mres.start), U, V, (leg.start, leg.end))
    near = min((mres.start, mres.end), key=lambda p: math.dist(p, U))
    far = mres.end if near is mres.start else mres.start
    return _Crossing((_Line("vanishing", near, U), run), True, (far, near), U, V,
                     (leg.start, leg.end))


@dataclass(frozen=True, slots=True)
class _Meeting:
    """Two centring carries made to cross on the parent's face toward the part
    (:func:`_meeting_carries`)."""

    carries: tuple[tuple[_Line, ...], tuple[_Line, ...]]  # each, in the order given, to R
    stop: Vec3  # T: where the carry down a side face meets the parent's edge
    stopped: int  # which of the two carries stops there (0 or 1)
    at: Vec3  # R, the crossing, on the parent's face toward the part
    end: Vec3  # Q, on the part's face toward the parent: R-Q is both carries' last leg
    plane: tuple[int, str]  # that parent face: (axis, "lo" or "hi")


def _meeting_carries(cons: Sequence[Any], faces: Sequence[Face], child: Box, camera: Camera,
                     tol: float) -> _Meeting | None:
    """Two centring lines of one part on one parent (``cons``, on ``faces``), across the two
    axes other than the one along which the part lies beyond the parent (the roller's handle,
    below the roller, seen from above): both carried along the parent's own faces to its face
    toward the part, where they cross at ``R`` (the crossing of two drawn lines), then on
    together to the part's face at ``Q``.  A line on a face across that axis (the roller's
    top) goes down a side face the view shows to the parent's edge at ``T``, a drawn edge,
    then along the face toward the part; a line on a side face leaves it along that face.
    :func:`_carry_lines` turned the first at the part's face, where no line shows (a
    read-through: "to R (by eye)", R fixing how far back the handle's top sits).  None where
    the geometry is not that, or where both lines reach the crossing without a stop (they
    meet on that face already: the front-left view)."""
    c0, c1 = cons
    if c0.axis == c1.axis:
        return None
    d = 3 - c0.axis - c1.axis
    pbox = faces[0].box
    if child[1][d] <= pbox[0][d] + tol:
        side, plane, near = "lo", pbox[0][d], child[1][d]
    elif child[0][d] >= pbox[1][d] - tol:
        side, plane, near = "hi", pbox[1][d], child[0][d]
    else:
        return None
    r = [0.0, 0.0, 0.0]
    r[c0.axis], r[c1.axis], r[d] = c0.coord, c1.coord, plane
    R = (r[0], r[1], r[2])
    q = list(r)
    q[d] = near
    Q = (q[0], q[1], q[2])
    if (abs(plane - near) <= tol or not all(pbox[0][b] - tol <= R[b] <= pbox[1][b] + tol
                                            for b in (c0.axis, c1.axis))):
        return None
    if sum(f.normal == d for f in faces) != 1:
        return None
    out: list[tuple[_Line, ...]] = []
    stop: Vec3 | None = None
    stopped = 0
    for i, (con, face) in enumerate(zip(cons, faces)):
        a, n = con.axis, face.normal
        if n != d:  # the line runs along d on a side face: leave it along the face plane
            if _moving_axis(_Line("", con.result.start, con.result.end)) != d:
                return None
            e = [0.0, 0.0, 0.0]
            e[a], e[n], e[d] = con.coord, face.coord, plane
            pts = [(e[0], e[1], e[2]), R]
        else:  # on the face across d, away from the part: down a side face the view shows
            if abs(face.coord - plane) <= tol:
                return None
            o = 3 - a - d
            centre = 0.5 * (child[0][o] + child[1][o])
            ends = sorted(("lo", "hi"), key=lambda s: (
                not _front_facing(Face(pbox, o, s), camera),
                abs(pbox[0 if s == "lo" else 1][o] - centre)))
            ov = pbox[0 if ends[0] == "lo" else 1][o]
            e = [0.0, 0.0, 0.0]
            e[a], e[o], e[d] = con.coord, ov, face.coord
            t = list(e)
            t[d] = plane
            stop, stopped = (t[0], t[1], t[2]), i
            if not _on_segment(e, con.result.start, con.result.end, tol):
                return None
            pts = [(e[0], e[1], e[2]), stop, R]
        legs = []
        for s, t_ in zip(pts, pts[1:]):
            if max(abs(s[k] - t_[k]) for k in range(3)) <= tol:
                continue
            ln = align(s, t_)
            legs.append(_Line("vanishing", ln.start, ln.end))
        if not legs:
            return None
        out.append(tuple(legs))
    if stop is None:
        return None
    ln = align(R, Q)
    last = _Line("vanishing", ln.start, ln.end)
    return _Meeting((out[0] + (last,), out[1] + (last,)), stop, stopped, R, Q, (d, side))


#: Legs a walked carry (:func:`_walk_carry`) takes before its last one, at most.
WALK_LEGS = 2


def _walk_carry(con: Any, face: Face, child: Box, segments: Sequence[tuple[Any, Any]],
                tol: float, mids: Sequence[int] = ()) -> tuple[_Line, ...] | None:
    """A carry that turns only where a drawn line crosses its plane, for one that
    :func:`_carry_lines` would turn by eye (the camera's flash: "Carry MP and XY toward the
    left vanishing point to C and D (by eye), then vertically", C and D inside the body,
    where the flash's front will be, which no anchor places).

    The carry stays in the plane of the construction's result line (``con.axis`` at
    ``con.coord``), as any carry does.  In that plane, a drawn line running along
    ``con.axis`` (an edge of a box drawn before, a guide of the step: ``segments``, 3D end
    pairs) shows as a point the reader can find: where the carry meets that line.  From an
    end of the result line, legs along the plane's two other axes join such points, at most
    :data:`WALK_LEGS` of them (the flash: along the lens's top face to its back edge, then
    up the body's and the prism box's fronts to the box's top edge), until one lies on the
    line of a side of the ``child``'s box in the plane; a last leg along that line reaches
    the child's box (its edge on that face) at its near side, as :func:`_carry_lines` ends
    (from a point already beside the box, across it to its far side).  A middle of the child that an
    anchor places (``mids``: the axes) counts as a side: a line across the child there (the
    mixer's head, centred left to right: its front carried up its middle from the base's
    centre line, nothing being drawn at the head's height).  The fewest legs, then the
    shortest, then the lowest coordinates.  None where no such walk exists (a part that
    floats: nothing drawn reaches its planes)."""
    a, n = con.axis, face.normal
    o = 3 - a - n
    x = con.coord
    points: list[tuple[float, float]] = []
    for p, q in segments:
        if (abs(q[n] - p[n]) > tol or abs(q[o] - p[o]) > tol or abs(q[a] - p[a]) <= tol
                or not min(p[a], q[a]) - tol <= x <= max(p[a], q[a]) + tol):
            continue
        v = (0.5 * float(p[n] + q[n]), 0.5 * float(p[o] + q[o]))
        if not any(abs(v[0] - w[0]) <= tol and abs(v[1] - w[1]) <= tol for w in points):
            points.append(v)
    points.sort()
    res = con.result
    starts = sorted({(float(e[n]), float(e[o])) for e in (res.start, res.end)})
    sides = ((0, float(child[0][n]), float(child[1][n])), (1, float(child[0][o]), float(child[1][o])))
    lines = [(k, (lo, hi) + ((0.5 * (lo + hi),) if (n, o)[k] in mids else ()))
             for k, lo, hi in sides]

    def last_leg(v: tuple[float, float]) -> tuple[float, float] | None:
        """The last leg from ``v`` along a side line of the child through ``v``, else None."""
        for k, at in lines:  # k: which coordinate the line fixes (0: n, 1: o)
            if any(abs(v[k] - c) <= tol for c in at):
                j = 1 - k  # the leg runs along the other to the child's near side, as any
                lo2, hi2 = sides[j][1], sides[j][2]  # carry does (its far one from inside)
                to = (lo2 if v[j] < lo2 - tol else hi2 if v[j] > hi2 + tol
                      else hi2 if abs(hi2 - v[j]) >= abs(lo2 - v[j]) else lo2)
                w = list(v)
                w[j] = to
                if abs(to - v[j]) > tol:
                    return (w[0], w[1])
        return None

    best: tuple[tuple[float, ...], list[tuple[float, float]]] | None = None
    paths = [[s] for s in starts]
    for _ in range(WALK_LEGS + 1):
        for path in paths:
            end = last_leg(path[-1])
            if end is None:
                continue
            full = path + [end]
            length = sum(abs(p[0] - q[0]) + abs(p[1] - q[1]) for p, q in zip(full, full[1:]))
            key = (length, *[c for p in full for c in p])
            if best is None or key < best[0]:
                best = (key, full)
        if best is not None:
            break
        grown = []
        for path in paths:
            v = path[-1]
            along = (None if len(path) < 2
                     else 0 if abs(path[-2][1] - v[1]) <= tol else 1)  # the last leg's way
            for w in points:
                if any(max(abs(w[0] - u[0]), abs(w[1] - u[1])) <= tol for u in path):
                    continue
                way = 0 if abs(w[1] - v[1]) <= tol else 1 if abs(w[0] - v[0]) <= tol else None
                if way is not None and way != along:  # legs alternate: one line each
                    # (on the line it runs along exactly: the point differs by rounding)
                    grown.append(path + [(w[0], v[1]) if way == 0 else (v[0], w[1])])
        paths = grown
    if best is None:
        return None
    out = []
    for p, q in zip(best[1], best[1][1:]):
        s_, e_ = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
        s_[a] = e_[a] = x
        s_[n], s_[o], e_[n], e_[o] = p[0], p[1], q[0], q[1]
        ln = align((s_[0], s_[1], s_[2]), (e_[0], e_[1], e_[2]))
        out.append(_Line("vanishing", ln.start, ln.end))
    return tuple(out)


def _carry_cost(con: Any, carry: list[_Line], pbox: Box, tol: float) -> tuple[int, float]:
    """What ``carry`` costs the reader: its legs along an edge of the parent's box first
    (they draw nothing new: "Carry ST toward the left vanishing point" along the seat's own
    edge), then how far it moves the result line across (a leg along the line itself only
    extends it: one stroke along the edge)."""
    along = _moving_axis(_Line("", con.result.start, con.result.end))
    lo, hi = pbox
    on_edges = moved = 0
    for ln in carry:
        if _moving_axis(ln) == along:
            continue
        moved += float(np.linalg.norm(np.subtract(ln.end, ln.start)))
        k = _moving_axis(ln)
        across = [b for b in range(3) if b != k]  # on two of the box's planes, inside along k
        if (all(abs(ln.start[b] - ln.end[b]) <= tol
                and min(abs(ln.start[b] - lo[b]), abs(ln.start[b] - hi[b])) <= tol
                for b in across)
                and all(lo[k] - tol <= p[k] <= hi[k] + tol for p in (ln.start, ln.end))):
            on_edges += 1
    return on_edges, moved


def _anchor_lines(anchor: Any, parent: Any, cand: Any, plan: Any, camera: Camera,
                  tol: float, floor: float | None = None, foot: Any = None
                  ) -> tuple[Face, Any, list[_Line], list[_Line]]:
    """An anchor of candidate ``cand`` on candidate ``parent``: its construction face, its
    construction, its lines and the carrying lines, on both boxes as drawn
    (:func:`_drawn_box`).

    An end in line with a parent's edge (ratio 0 or 1) draws nothing on the face: its line is
    an edge of the parent's box, drawn with it (dashed where hidden).  It is taken from the
    face whose carry to the part runs least along the parent's own edges, then moves the
    line least (:func:`_carry_cost`), the view's face first on a tie (the
    chair's back rail: its top was carried from the seat's front top edge along the seat's
    own side edges to its back top edge, which the picture already showed; a read-through
    found nothing new drawn).  Other ratios construct on a face the view shows
    (:func:`_anchor_face`).  ``floor``: the height of the floor ``cand`` stands on, if it
    does, and ``foot`` the floor line's foot (:func:`_carry_lines`)."""
    pbox = _drawn_box(plan.primitive(parent.part), parent.box)
    cbox = _drawn_box(plan.primitive(cand.part), cand.box)
    face = _anchor_face(anchor, pbox, camera)
    con = construct(face, anchor.axis, anchor.ratio)
    carry = _carry_lines(con, face, cbox, tol, cand.anchors, floor, foot)
    if carry and anchor.end != "mid" and entry_for(anchor.ratio).in_line:
        best = _carry_cost(con, carry, pbox, tol)
        biggest = max(_extent(pbox, a) for a in range(3))
        for n in range(3):
            if n == anchor.axis or _extent(pbox, 3 - n - anchor.axis) <= 1e-12 * biggest:
                continue
            for end in ("lo", "hi"):
                other = Face(pbox, n, end)
                c2 = construct(other, anchor.axis, anchor.ratio)
                k2 = _carry_lines(c2, other, cbox, tol, cand.anchors, floor, foot)
                cost = _carry_cost(c2, k2, pbox, tol)
                if cost[0] < best[0] or (cost[0] == best[0] and cost[1] < best[1] - tol):
                    face, con, carry, best = other, c2, k2, cost
    own = [_Line(ln.role, ln.start, ln.end) for ln in con.lines]
    return face, con, own, carry


def _on_face(anchor: Any, pbox: Box, cbox: Box, tol: float) -> bool:
    """An end aligned with a parent's face (ratio 0 or 1) whose face overlaps that face's
    rectangle (an area, not an edge): the face already drawn is the guide ("Its back lies on
    the body's front face"), no line needs carrying."""
    if anchor.end == "mid" or not entry_for(anchor.ratio).in_line:
        return False
    return all(cbox[0][b] < pbox[1][b] - tol and pbox[0][b] < cbox[1][b] - tol
               for b in range(3) if b != anchor.axis)


def _round(prim: Any) -> bool:
    """Does the part get ellipses: a cylinder, or a plane or frustum that is round (a disc, a
    bowl: ``detail["round"]``, :mod:`h2s_print.fit`)?"""
    if prim.axis is None:
        return False
    return prim.type == "cylinder" or (prim.type in ("plane", "frustum")
                                       and bool(prim.detail.get("round")))


def _end_faces(prim: Any, box: Box) -> tuple[Face, Face]:
    """The two end faces normal to the axis of a cylinder or frustum drawn in ``box``: the
    box's faces, or a frustum's end rectangles (its scaffold's caps, :func:`_solid`) as flat
    faces, ``lo`` then ``hi``."""
    axis = prim.axis
    if prim.type != "frustum":
        return Face(box, axis, "lo"), Face(box, axis, "hi")
    pts, _, _ = _solid(prim, box)
    out = []
    for end, quad in (("lo", pts[:4]), ("hi", pts[4:])):
        out.append(Face((tuple(map(float, quad.min(axis=0))), tuple(map(float, quad.max(axis=0)))),
                        axis, end))
    return out[0], out[1]


def _mesh_area(part: Part) -> float:
    v = np.asarray(part.vertices, dtype=float)
    f = np.asarray(part.faces, dtype=np.int64)
    if not len(f):
        return 0.0
    return float(0.5 * np.linalg.norm(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]),
                                      axis=1).sum())


def _carry_ways(carry: Sequence[_Line]) -> tuple[int, int | None]:
    """A carry's first direction and the one it turns to (None: it does not turn): the
    sentence it is said in (carries going the same ways are said together)."""
    axes = [_moving_axis(c) for c in carry]
    return axes[0], next((x for x in axes[1:] if x != axes[0]), None)


def _placed_planes(box: Box, anchors: Sequence[Any], n: int) -> list[float]:
    """The planes across axis ``n`` of a part's ``box`` that its ``anchors`` place (its
    faces, or its middle)."""
    return [box[0][n] if a.end == "lo" else box[1][n] if a.end == "hi"
            else 0.5 * (box[0][n] + box[1][n]) for a in anchors if a.axis == n]


def _moving_axis(line: _Line) -> int:
    """The model axis a carrying line runs along."""
    d = np.abs(np.asarray(line.end, dtype=float) - np.asarray(line.start, dtype=float))
    return int(np.argmax(d))


def _on_line(p: Any, a: Any, b: Any, tol: float) -> bool:
    """Is the point ``p`` on the infinite line through ``a`` and ``b`` (within ``tol``)?"""
    a_, d = np.asarray(a, dtype=float), np.asarray(b, dtype=float) - np.asarray(a, dtype=float)
    w = np.asarray(p, dtype=float) - a_
    n = float(np.linalg.norm(d))
    return n > 0.0 and float(np.linalg.norm(np.cross(d, w))) <= tol * n


def _segments_cross(a: Any, b: Any, p: Any, q: Any, tol: float) -> bool:
    """Do the segments ``a``-``b`` and ``p``-``q`` meet (their nearest points within ``tol``
    of each other), not running along one line?"""
    a_, p_ = np.asarray(a, dtype=float), np.asarray(p, dtype=float)
    d, e = np.asarray(b, dtype=float) - a_, np.asarray(q, dtype=float) - p_
    n = np.cross(d, e)
    nn = float(np.dot(n, n))
    if nn <= (1e-9 * float(np.linalg.norm(d)) * float(np.linalg.norm(e))) ** 2:
        return False  # parallel
    w = p_ - a_
    s = float(np.dot(np.cross(w, e), n)) / nn  # the nearest points: a + s d, p + t e
    t = float(np.dot(np.cross(w, d), n)) / nn
    ld, le = float(np.linalg.norm(d)), float(np.linalg.norm(e))
    if not (-tol <= s * ld <= ld + tol and -tol <= t * le <= le + tol):
        return False
    return float(np.linalg.norm((a_ + s * d) - (p_ + t * e))) <= tol


def _near_segment(p: Any, a: Any, b: Any, reach: float) -> bool:
    """Is ``p`` inside the box of segment ``a``-``b`` grown by ``reach``?  A point within
    ``tol`` of the segment is (:func:`_on_segment`, for any ``reach`` of ``2 tol``, well beyond
    rounding): a test that far cheaper can skip the point-to-segment distance."""
    return all(min(a[k], b[k]) - reach <= p[k] <= max(a[k], b[k]) + reach for k in range(3))


def _on_segment(p: Any, a: Any, b: Any, tol: float) -> bool:
    """Is the point ``p`` within ``tol`` of the segment ``a``-``b``?"""
    a_, d = np.asarray(a, dtype=float), np.asarray(b, dtype=float) - np.asarray(a, dtype=float)
    w = np.asarray(p, dtype=float) - a_
    t = float(np.clip(np.dot(w, d) / max(float(np.dot(d, d)), 1e-300), 0.0, 1.0))
    return float(np.linalg.norm(w - t * d)) <= tol


def _runs_along(run: Pts, axis: int) -> bool:
    """Does the line ``run`` (two points) run along model axis ``axis``?"""
    d = np.asarray(run.points[1], dtype=float) - np.asarray(run.points[0], dtype=float)
    return bool(abs(d[axis]) >= (1.0 - 1e-9) * float(np.linalg.norm(d)) > 0.0)


def _touching(part: str, chosen: dict[str, Any], tol: float) -> list[str]:
    """Other parts whose selected box touches or overlaps ``part``'s (closed boxes, within
    ``tol``): the parts a free part rests on or sits in."""
    lo, hi = (np.asarray(x, dtype=float) for x in chosen[part].box)
    out = []
    for other, c in sorted(chosen.items()):
        if other == part:
            continue
        olo, ohi = (np.asarray(x, dtype=float) for x in c.box)
        if all(lo[a] <= ohi[a] + tol and olo[a] <= hi[a] + tol for a in range(3)):
            out.append(other)
    return out


@dataclass(frozen=True, slots=True)
class _FloorCorner:
    """The floor under a part's nearest bottom corner, constructed from the floor line's foot
    (:func:`_floor_corner`).  Points: Q the part's top corner, R on the first box's bottom
    edge through the floor line's corner C (from Q along axis ``a``), F the floor line's foot,
    S under R (from F along the other floor axis), T under Q (the bottom corner).
    ``moved_a``/``moved_b``: Q and C differ along ``a``/the other axis (a line is drawn)."""

    a: int
    Q: Vec3
    R: Vec3
    F: Vec3
    S: Vec3
    T: Vec3
    moved_a: bool
    moved_b: bool


def _floor_corner(first: Box, part: Box, corner: Any, foot: Any, eye: np.ndarray,
                  tol: float, placed: Sequence[tuple[int, float]] = ()) -> _FloorCorner | None:
    """The construction of :class:`_FloorCorner` for a part whose top lies in the bottom face
    of the ``first`` box (raised above the floor), under which the sheet prints the floor line
    from ``corner`` (C) down to ``foot`` (F): the part's top corner (Q) on the most of the
    ``placed`` planes ((axis, coordinate): its sides that anchors place, so that Q is where
    drawn lines cross, not a point judged by eye: a read-through of the table's leg, whose
    "top corner C" was said nowhere), then nearest the ``eye``,
    carried along one floor axis to the first box's bottom edge through C (R), dropped to the
    floor (S, on the floor line from F along the other axis), and back under Q (T).  ``a`` is
    an axis along which Q and C agree where there is one (then one line: Q's own edge meets
    F's).  None where the part's top is not in that face, its corner not over it, or the
    corner is C itself (the floor line is the guide)."""
    if abs(float(part[1][2]) - float(corner[2])) > tol:
        return None  # its top is not in the first box's bottom face
    def on_placed(c: tuple[float, float]) -> int:
        return sum(any(ax == k and abs(c[k] - v) <= tol for ax, v in placed) for k in (0, 1))

    q = min(((float(x), float(y)) for x in (part[0][0], part[1][0])
             for y in (part[0][1], part[1][1])),
            key=lambda c: (-on_placed(c), math.hypot(c[0] - eye[0], c[1] - eye[1]), c))
    return _floor_under(first, q, corner, foot, tol)


def _floor_under(first: Box, q: tuple[float, float], corner: Any, foot: Any, tol: float
                 ) -> _FloorCorner | None:
    """The construction of :class:`_FloorCorner` under the point ``q`` (x, y) of the
    ``first`` box's bottom face (:func:`_floor_corner`'s, for a point given: the middle of a
    part centred both ways on the first box and hanging below it, where its centring lines
    meet on that face, the roller's handle); None where ``q`` is not over that face or is
    the floor line's own corner."""
    cx, cy, cz = (float(v) for v in corner)
    fz = float(foot[2])
    qx, qy = q
    if not (first[0][0] - tol <= qx <= first[1][0] + tol
            and first[0][1] - tol <= qy <= first[1][1] + tol):
        return None  # the point is not over the first box's bottom face
    c = (cx, cy)
    a = 1 if abs(q[0] - c[0]) > tol and abs(q[1] - c[1]) <= tol else 0
    b = 1 - a
    moved_a, moved_b = abs(q[a] - c[a]) > tol, abs(q[b] - c[b]) > tol
    if not moved_a and not moved_b:
        return None  # (its corner on the floor line itself: the line is the guide)

    def pt(u: float, v: float, z: float) -> Vec3:
        out = [0.0, 0.0, z]
        out[a], out[b] = u, v
        return (out[0], out[1], out[2])

    return _FloorCorner(a, Q=pt(q[a], q[b], cz), R=pt(c[a], q[b], cz), F=pt(c[a], c[b], fz),
                        S=pt(c[a], q[b], fz), T=pt(q[a], q[b], fz),
                        moved_a=moved_a, moved_b=moved_b)
