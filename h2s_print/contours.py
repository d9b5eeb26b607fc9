"""Stage 8, contours: visible contour polylines of the adjusted part meshes (DESIGN.md §2.8, paper §5).

For one view (a :class:`~h2s_print.types.Camera`) every part mesh gives

* **silhouettes**: edges between a front-facing and a back-facing face, seen from the camera
  *position* (a perspective test, not a fixed direction);
* **creases**: edges whose dihedral angle exceeds ``crease_deg`` and where at least one of the
  two faces is front-facing;
* **boundaries**: open edges with one face;
* **suggestive contours** (optional, for smooth parts): zeros of the radial curvature where its
  derivative along the projected view direction is positive (DeCarlo et al. 2003).

Segments are sampled every ``spacing_mm`` on the sheet, cut where visibility changes (the cut
point refined by bisection to ``tolerance_mm``) and chained into polylines per kind.  Three
interchangeable occlusion engines answer "is this sample seen from the camera?":

* ``grid`` (default, ``auto``): occluder triangles binned by their projected box on a coarse sheet
  grid (cell about two median edge lengths); each sample is tested exactly (barycentric
  coordinates and ``1/depth``, affine on the sheet) against the triangles of its cell;
* ``zbuffer``: the triangles' depth rasterised into a 0.1 mm grid with an item buffer; a sample
  is tested exactly against the nearest triangles of its cell and the 8 around it (misses
  occluders that are nearest at none of those cell centres, e.g. behind grazing silhouettes);
* ``ray``: a ray from each sample toward the camera through trimesh (Embree when the optional
  ``embreex`` package is installed, else trimesh's very slow pure-python intersector).

Measured on the 111k-triangle benchmark (``benchmarks/bench_contours.py``, 2 cores): grid 0.8 s,
Embree rays 0.8 s, z-buffer 3.8 s for one view; grid and ray give identical lines.  The grid is
the default: as exact as rays, no optional dependency, so output does not depend on what is
installed.  Every engine applies a relative depth bias toward the camera (``depth_bias``), so a
line lying on its own faces is never hidden by them.

Progressive occlusion (paper §5, "Contour ordering"): while part *k* is drawn, the occluders are
the parts drawn so far plus part *k*; the final drawing uses all parts.  :func:`contour_steps`
and :func:`final_contours` implement exactly that on top of :func:`trace_contours`.

Known limits: triangles crossing the camera plane are ignored as occluders and segments behind
the camera are dropped; the grid covers the sheet and one sheet around it (outside it nothing
hides); occlusion changes between two samples (0.5 mm apart by default) are not seen, nor are
visible pieces shorter than ``min_length_mm``; non-manifold edges keep their first two faces;
polyhedral silhouettes of coarse smooth meshes zig-zag and may break into short pieces;
suggestive contours use a per-vertex curvature tensor averaged from per-face estimates (Rusinkiewicz 2004, without the
frame rotation) and a per-face gradient of ``k_r`` for its derivative, so on coarse meshes they
are noisy: they are filtered by strength and length, and skipped within two face rings of sharp
edges (where vertex normals are smeared).
"""

from __future__ import annotations

import logging
import math
from collections import OrderedDict
from dataclasses import dataclass, replace
from typing import Any, Callable, Sequence

import numpy as np

from .types import Box, Camera, Part, Vec3, readonly

log = logging.getLogger(__name__)

#: Contour kinds, in the order a polyline's kind is decided when an edge is several at once.
KINDS = ("silhouette", "boundary", "crease", "suggestive")
_SIL, _BND, _CRS, _SUG = 0, 1, 2, 3
ENGINES = ("auto", "grid", "zbuffer", "ray")


@dataclass(frozen=True, slots=True)
class ContourSet:
    """The visible contour lines of one part in one view.

    Attributes:
        part: the part's name.
        polylines3d: polylines of model points, model units; a closed loop repeats its first point.
        polylines_mm: the same polylines projected on the sheet, mm (``camera.project``).
        kinds: one of ``KINDS`` per polyline (extra to plan.json's ``polylines3d``/``polylines_mm``).
    """

    part: str
    polylines3d: tuple[tuple[Vec3, ...], ...]
    polylines_mm: tuple[tuple[tuple[float, float], ...], ...]
    kinds: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True)
class ContourSettings:
    """How contours are found and cut.

    Attributes:
        crease_deg: dihedral angle above which an edge is a crease, degrees.
        suggestive: also trace suggestive contours.
        engine: ``auto`` (= ``grid``), ``grid``, ``zbuffer`` or ``ray`` (see the module docstring).
        spacing_mm: distance between visibility samples along a segment, sheet mm.
        tolerance_mm: bisection stops when a visibility change is located this well, sheet mm.
        pixel_mm: cell size of the ``zbuffer`` engine, sheet mm.
        min_length_mm: visible pieces shorter than this on the sheet are dropped, mm.
        depth_bias: relative depth offset toward the camera applied to samples (unit-free).
        suggestive_strength: suggestive zero-crossings whose normalised derivative
            ``D_w k_r * L^2`` (``L`` the part's box diagonal) is below this are dropped (unit-free).
        suggestive_min_mm: suggestive polylines shorter than this on the sheet are dropped, mm.
    """

    crease_deg: float = 35.0
    suggestive: bool = False
    engine: str = "auto"
    spacing_mm: float = 0.5
    tolerance_mm: float = 0.01
    pixel_mm: float = 0.1
    min_length_mm: float = 0.05
    depth_bias: float = 5e-4
    suggestive_strength: float = 2.0
    suggestive_min_mm: float = 2.0


# ----------------------------------------------------------------------------- public API


def adjust_part(part: Part, from_box: Box, to_box: Box) -> Part:
    """Map a part's mesh by the per-axis affine change taking ``from_box`` to ``to_box``.

    Along each axis ``x -> to_lo + t (to_hi - to_lo)`` with ``t = (x - from_lo) / (from_hi - from_lo)``,
    written as ``(1 - t) to_lo + t to_hi`` so that ``from_lo`` lands exactly on ``to_lo`` and
    ``from_hi`` exactly on ``to_hi``.  An axis along which ``from_box`` has zero extent is only
    translated (``from_lo -> to_lo``).

    Args:
        part: the part to map.
        from_box: the box the part was fitted in (its primitive's box), model units.
        to_box: the selected (adjusted) box, model units.

    Returns:
        A new ``Part`` with the same name, faces and sources.

    Raises:
        ValueError: when a box has ``lo > hi`` or non-finite coordinates.
    """
    flo, fhi = (np.asarray(v, dtype=float) for v in from_box)
    tlo, thi = (np.asarray(v, dtype=float) for v in to_box)
    for name, lo, hi in (("from_box", flo, fhi), ("to_box", tlo, thi)):
        if lo.shape != (3,) or hi.shape != (3,) or not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))):
            raise ValueError(f"{name} must be two finite 3-vectors, got {(lo, hi)!r}")
        if np.any(lo > hi):
            raise ValueError(f"{name} has lo > hi: {(lo.tolist(), hi.tolist())!r}")
    v = np.asarray(part.vertices, dtype=float)
    out = np.empty_like(v)
    for ax in range(3):
        ext = fhi[ax] - flo[ax]
        if ext > 0.0:
            t = (v[:, ax] - flo[ax]) / ext
            out[:, ax] = (1.0 - t) * tlo[ax] + t * thi[ax]
        else:
            out[:, ax] = v[:, ax] - flo[ax] + tlo[ax]
    return Part(part.name, readonly(out, np.float64), part.faces, part.sources)


def trace_contours(
    parts: Sequence[Part],
    camera: Camera,
    *,
    crease_deg: float = 35.0,
    suggestive: bool = False,
    occluders: Sequence[Part] | None = None,
    settings: ContourSettings | None = None,
) -> tuple[ContourSet, ...]:
    """Visible contour polylines of each part, hidden by ``occluders``.

    Args:
        parts: the (adjusted) parts whose lines are traced.
        camera: the view.
        crease_deg: dihedral angle above which an edge is a crease, degrees (overrides ``settings``).
        suggestive: also trace suggestive contours (overrides ``settings``).
        occluders: the parts that hide lines; ``None`` means ``parts`` themselves.  Pass a part in
            both lists to let it hide its own far side (the usual case).
        settings: sampling, engine and filter settings; defaults when ``None``.

    Returns:
        One ``ContourSet`` per part, in the order of ``parts``.
    """
    cs = _settings(settings, crease_deg, suggestive)
    occ = tuple(parts) if occluders is None else tuple(occluders)
    meshes = [_Mesh.of(p) for p in occ]
    engine = _make_engine(cs, camera, meshes)
    out = []
    for p in parts:
        m = _Mesh.of(p)
        out.append(_trace_one(m, camera, cs, engine, holds=any(m is o for o in meshes),
                              alone=len(meshes) == 1 and meshes[0] is m))
    return tuple(out)


def contour_steps(
    parts_in_order: Sequence[Part],
    camera: Camera,
    *,
    crease_deg: float = 35.0,
    suggestive: bool = False,
    settings: ContourSettings | None = None,
) -> tuple[ContourSet, ...]:
    """Contours for progressive drawing: part ``k``'s lines are hidden by ``parts[0..k]`` only.

    Args:
        parts_in_order: parts in drawing order.
        camera, crease_deg, suggestive, settings: as for :func:`trace_contours`.

    Returns:
        One ``ContourSet`` per part, in drawing order.
    """
    cs = _settings(settings, crease_deg, suggestive)
    meshes = [_Mesh.of(p) for p in parts_in_order]
    out = []
    if _engine_name(cs) in ("grid", "zbuffer"):
        zb = (_GridEngine if _engine_name(cs) == "grid" else _ZBuffer)(camera, cs, meshes)
        for m in meshes:
            zb.add(m)  # the engine after part k holds parts 0..k
            out.append(_trace_one(m, camera, cs, zb, holds=True))
        return tuple(out)
    for k, m in enumerate(meshes):
        out.append(_trace_one(m, camera, cs, _make_engine(cs, camera, meshes[: k + 1])))
    return tuple(out)


def final_contours(
    parts: Sequence[Part],
    camera: Camera,
    *,
    crease_deg: float = 35.0,
    suggestive: bool = False,
    settings: ContourSettings | None = None,
) -> tuple[ContourSet, ...]:
    """Contours of the final drawing: every part's lines hidden by all parts."""
    return trace_contours(parts, camera, crease_deg=crease_deg, suggestive=suggestive,
                          occluders=parts, settings=settings)


# ----------------------------------------------------------------------------- meshes


def _settings(settings: ContourSettings | None, crease_deg: float, suggestive: bool) -> ContourSettings:
    base = settings or ContourSettings()
    if base.engine not in ENGINES:
        raise ValueError(f"engine must be one of {ENGINES}, got {base.engine!r}")
    return replace(base, crease_deg=float(crease_deg), suggestive=bool(suggestive))


def _engine_name(cs: ContourSettings) -> str:
    return "grid" if cs.engine == "auto" else cs.engine


#: Welded meshes kept (:meth:`_Mesh.of`), the most recently used, with the parts they are of.
_MESH_CACHE = 64
_MESHES: "OrderedDict[int, tuple[Part, _Mesh]]" = OrderedDict()


#: Views a welded mesh remembers its lines' visibility for (:meth:`_Mesh.remember`).
_SEEN_VIEWS = 4


class _Mesh:
    """A part's mesh welded by position, with its edge table (view independent; never
    changed after it is built, so one may serve every trace of its part), and the samples of
    its lines that a trace found visible (:meth:`remember`, :meth:`known_visible`)."""

    __slots__ = ("name", "v", "f", "n", "diag", "edges", "ef", "consistent", "boundary", "closed",
                 "seen")

    @staticmethod
    def of(part: Part) -> "_Mesh":
        """``part``'s welded mesh, built once while the part is among the last
        :data:`_MESH_CACHE` asked for (a sequence stage traces a part several times: its own
        lines, the finished drawing, the occlusion counts; welding is the costly step)."""
        hit = _MESHES.get(id(part))
        if hit is not None and hit[0] is part:  # the part is held, so its id is its own
            _MESHES.move_to_end(id(part))
            return hit[1]
        mesh = _Mesh(part)
        _MESHES[id(part)] = (part, mesh)
        while len(_MESHES) > _MESH_CACHE:
            _MESHES.popitem(last=False)
        return mesh

    def remember(self, camera: Camera, cs: ContourSettings, points: np.ndarray,
                 clear: np.ndarray) -> None:
        """Keep, for this view and these settings, the samples of this mesh's lines
        (``points``) and which of them ``clear`` marks as not hidden by the mesh itself (see
        :meth:`_GridEngine.certain`); the last :data:`_SEEN_VIEWS` views are kept."""
        self.seen = [r for r in self.seen if not (r[0] is camera and r[1] == cs)]
        self.seen.append((camera, cs, points, clear))
        del self.seen[:-_SEEN_VIEWS]

    def known_visible(self, camera: Camera, cs: ContourSettings,
                      points: np.ndarray) -> np.ndarray | None:
        """The ``clear`` mask :meth:`remember` kept for exactly these samples in this view,
        or ``None``."""
        for cam, s, pts, clear in self.seen:
            if cam is camera and s == cs and pts.shape == points.shape and np.array_equal(pts, points):
                return clear
        return None

    def __init__(self, part: Part):
        self.name = part.name
        self.seen: list[tuple[Camera, ContourSettings, np.ndarray, np.ndarray]] = []
        v, f = _weld(np.asarray(part.vertices, dtype=float), np.asarray(part.faces, dtype=np.int64))
        # A double-sided mesh lists each triangle twice, once per side: one is kept.  Else
        # every edge has four faces, the first two a triangle and its own back, and all its
        # edges became silhouettes (PartNet's bottle: its outline steps traced every facet).
        if len(f):
            _, once = np.unique(np.sort(f, axis=1), axis=0, return_index=True)
            if len(once) < len(f):
                f = f[np.sort(once)]
        cross = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
        area2 = np.linalg.norm(cross, axis=1)
        self.diag = float(np.linalg.norm(v.max(axis=0) - v.min(axis=0))) if len(v) else 0.0
        keep = area2 > (1e-12 * max(self.diag, 1e-300)) ** 2
        f, cross, area2 = f[keep], cross[keep], area2[keep]
        self.v, self.f = v, f
        self.n = cross / area2[:, None] if len(f) else np.zeros((0, 3))
        # Edge table: one row per undirected edge (a < b) with up to two faces.
        he = np.stack([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]], axis=1).reshape(-1, 2)
        hf = np.repeat(np.arange(len(f)), 3)
        key = np.sort(he, axis=1)
        # the rows of ``key`` in lexicographic order, as np.unique(key, axis=0) gives them, from
        # one integer per row (a * nv + b orders rows as (a, b) does: 0 <= a, b < nv); 10x faster
        nv = max(len(v), 1)
        code, inv, counts = np.unique(key[:, 0] * nv + key[:, 1], return_inverse=True,
                                      return_counts=True)
        uniq = np.stack([code // nv, code % nv], axis=1)
        inv = inv.reshape(-1)
        order = np.argsort(inv, kind="stable")
        start = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
        first = order[start]
        second = order[np.minimum(start + 1, len(order) - 1)] if len(order) else first
        self.edges = uniq.astype(np.int64)
        ef = np.full((len(uniq), 2), -1, dtype=np.int64)
        ef[:, 0] = hf[first]
        two = counts >= 2
        ef[two, 1] = hf[second[two]]
        self.ef = ef
        # Two faces are consistently oriented when they run through the edge in opposite directions.
        cons = np.ones(len(uniq), dtype=bool)
        cons[two] = he[first[two], 0] != he[second[two], 0]
        self.consistent = cons
        self.boundary = counts == 1
        self.closed = bool(len(uniq)) and bool(np.all(counts == 2)) and bool(np.all(cons))
        if self.closed:
            vol = float(np.einsum("ij,ij->i", v[f[:, 0]], cross).sum())
            if vol < 0:  # inward winding: flip so "front-facing" means facing the camera
                self.n = -self.n
        # Non-manifold edges (3+ faces) keep only their first two faces: an approximation.


def _weld(v: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Merge vertices closer than 1e-7 of the box diagonal; keep the lowest index's coordinates."""
    if len(v) == 0 or len(f) == 0:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    diag = float(np.linalg.norm(v.max(axis=0) - v.min(axis=0)))
    tol = 1e-7 * diag if diag > 0 else 0.0
    pairs = cKDTree(v).query_pairs(tol, output_type="ndarray") if tol > 0 else np.zeros((0, 2), int)
    n = len(v)
    g = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, label = connected_components(g, directed=False)
    rep = np.full(label.max() + 1, n, dtype=np.int64)
    np.minimum.at(rep, label, np.arange(n))
    f = rep[label[f]]
    f = f[(f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 2] != f[:, 0])]
    used, f = np.unique(f, return_inverse=True)
    return v[used], f.reshape(-1, 3).astype(np.int64)


# ----------------------------------------------------------------------------- contour edges


def _classify(m: _Mesh, camera: Camera, crease_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """Edge ids and kinds of the view's silhouette, boundary and crease edges."""
    if len(m.f) == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    eye = np.asarray(camera.position, dtype=float)
    centroid = m.v[m.f].mean(axis=1)
    facing = np.einsum("ij,ij->i", m.n, eye - centroid)
    front = facing > 0
    f0, f1 = m.ef[:, 0], m.ef[:, 1]
    two = f1 >= 0
    sign = np.where(m.consistent, 1.0, -1.0)  # an inconsistent neighbour's normal is flipped
    front1 = np.where(two, np.where(m.consistent, front[np.maximum(f1, 0)], ~front[np.maximum(f1, 0)]), False)
    sil = two & (front[f0] != front1)
    cosang = np.einsum("ij,ij->i", m.n[f0], m.n[np.maximum(f1, 0)]) * sign
    crease = two & ~sil & (front[f0] | front1) & (cosang < math.cos(math.radians(crease_deg)))
    kind = np.full(len(m.edges), -1, dtype=np.int64)
    kind[crease] = _CRS
    kind[m.boundary] = _BND
    kind[sil] = _SIL
    ids = np.flatnonzero(kind >= 0)
    return ids, kind[ids]


# ----------------------------------------------------------------------------- tracing


def _trace_one(m: _Mesh, camera: Camera, cs: ContourSettings, engine, *,
               holds: bool = False, alone: bool = False) -> ContourSet:
    """``m``'s visible lines against ``engine``'s occluders.

    ``holds``: the occluders include ``m`` itself, then a grid engine's verdicts are remembered
    on ``m``; ``alone``: they are ``m`` only, then the verdicts remembered are reused (see
    :func:`_visible_pieces`).
    """
    ids, kinds = _classify(m, camera, cs.crease_deg)
    p0 = m.v[m.edges[ids, 0]]
    p1 = m.v[m.edges[ids, 1]]
    nodes = m.edges[ids].copy()
    if cs.suggestive:
        s0, s1, snodes = _suggestive(m, camera, cs)
        p0 = np.concatenate([p0, s0])
        p1 = np.concatenate([p1, s1])
        nodes = np.concatenate([nodes, snodes + len(m.v)])
        kinds = np.concatenate([kinds, np.full(len(s0), _SUG, dtype=np.int64)])
    grid = isinstance(engine, _GridEngine)
    pieces = _visible_pieces(p0, p1, nodes, kinds, camera, cs, engine,
                             memo=m if grid and (holds or alone) else None, reuse=grid and alone)
    lines3d, lines_mm, lkinds = [], [], []
    for kind, chain in _chain(pieces):
        pts = np.asarray(chain, dtype=float)
        mm = camera.project(pts)
        if kind == _SUG and np.linalg.norm(np.diff(mm, axis=0), axis=1).sum() < cs.suggestive_min_mm:
            continue  # short suggestive fragments are mostly curvature noise
        lines3d.append(tuple(map(tuple, pts.tolist())))  # Python floats, as float(x) gives
        lines_mm.append(tuple(map(tuple, mm.tolist())))
        lkinds.append(KINDS[kind])
    log.debug("part %s: %d contour edges -> %d polylines", m.name, len(ids), len(lines3d))
    return ContourSet(m.name, tuple(lines3d), tuple(lines_mm), tuple(lkinds))


def _visible_pieces(p0, p1, nodes, kinds, camera: Camera, cs: ContourSettings, engine,
                    memo: _Mesh | None = None, reuse: bool = False):
    """Cut segments ``p0 -> p1`` at visibility changes.

    ``memo``: the mesh the segments are of, when ``engine`` is a grid engine holding it among
    its occluders: the samples found visible for certain (:meth:`_GridEngine.certain`) are
    remembered on it.  ``reuse``: the engine holds that mesh alone; then the samples an earlier
    trace in this view remembered (against occluders that held the mesh, e.g. the finished
    drawing's) are not tested again: with fewer occluders they stay visible (see
    :meth:`_GridEngine.certain`), so the answers, and the lines, are those of testing every sample.

    Returns:
        list of ``(kind, node_a, node_b, point_a, point_b)``; cut points get fresh negative node ids.
    """
    if len(p0) == 0:
        return []
    d0, d1 = camera.depth(p0), camera.depth(p1)
    front = (d0 > 0) & (d1 > 0)
    p0, p1, nodes, kinds = p0[front], p1[front], nodes[front], kinds[front]
    if len(p0) == 0:
        return []
    len_mm = np.linalg.norm(camera.project(p1) - camera.project(p0), axis=1)
    nseg = np.maximum(1, np.ceil(len_mm / cs.spacing_mm)).astype(np.int64)
    counts = nseg + 1
    seg = np.repeat(np.arange(len(p0)), counts)
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    j = np.arange(counts.sum()) - np.repeat(starts, counts)
    t = j / np.repeat(nseg, counts)
    pts = p0[seg] + t[:, None] * (p1 - p0)[seg]
    known = memo.known_visible(camera, cs, pts) if memo is not None and reuse else None
    vis = engine.visible(pts) if known is None else engine.visible(pts, known)
    if memo is not None:
        memo.remember(camera, cs, pts, vis & engine.certain(pts))
    # visibility changes between consecutive samples of one segment: bisect each
    change = np.flatnonzero((vis[:-1] != vis[1:]) & (seg[:-1] == seg[1:]))
    cut_t = np.zeros(0)
    if len(change):
        lo, hi = t[change].copy(), t[change + 1].copy()
        vlo = vis[change]
        cs_seg = seg[change]
        step_mm = len_mm[cs_seg] / nseg[cs_seg]
        iters = int(max(1, math.ceil(math.log2(max(float(step_mm.max()), 1e-12) / cs.tolerance_mm))))
        for _ in range(iters):
            mid = 0.5 * (lo + hi)
            vm = engine.visible(p0[cs_seg] + mid[:, None] * (p1 - p0)[cs_seg])
            same = vm == vlo
            lo = np.where(same, mid, lo)
            hi = np.where(same, hi, mid)
        cut_t = 0.5 * (lo + hi)
    pieces = []
    full = np.ones(len(p0), dtype=bool)
    anyvis = np.zeros(len(p0), dtype=bool)
    np.logical_and.at(full, seg, vis)
    np.logical_or.at(anyvis, seg, vis)
    mixed = anyvis & ~full
    for s in np.flatnonzero(full):
        pieces.append((int(kinds[s]), int(nodes[s, 0]), int(nodes[s, 1]), p0[s], p1[s]))
    if not np.any(mixed):
        return pieces
    fresh = -1
    change_of_seg: dict[int, list[int]] = {}
    for ci, c in enumerate(change):
        change_of_seg.setdefault(int(seg[c]), []).append(ci)
    for s in np.flatnonzero(mixed):
        s = int(s)
        first_vis = bool(vis[starts[s]])
        bounds = [0.0] + [float(cut_t[ci]) for ci in change_of_seg.get(s, [])] + [1.0]
        state = first_vis
        for a, b in zip(bounds[:-1], bounds[1:]):
            if state and b > a:
                pa = p0[s] + a * (p1[s] - p0[s])
                pb = p0[s] + b * (p1[s] - p0[s])
                if a == 0.0:
                    na = int(nodes[s, 0])
                else:
                    na, fresh = fresh, fresh - 1
                if b == 1.0:
                    nb = int(nodes[s, 1])
                else:
                    nb, fresh = fresh, fresh - 1
                lmm = float(np.linalg.norm(np.diff(camera.project(np.stack([pa, pb])), axis=0)))
                if lmm >= cs.min_length_mm:
                    pieces.append((int(kinds[s]), na, nb, pa, pb))
            state = not state
    return pieces


def _chain(pieces) -> list[tuple[int, list[np.ndarray]]]:
    """Join pieces of one kind that share nodes into polylines, deterministically.

    Chains start at nodes whose degree is not 2 (ends and junctions), in increasing node order;
    the remaining pieces form closed loops, started at their smallest piece.
    """
    out = []
    for kind in range(len(KINDS)):
        mine = [p for p in pieces if p[0] == kind]
        if not mine:
            continue
        adj: dict[int, list[int]] = {}
        pos: dict[int, np.ndarray] = {}
        for i, (_, a, b, pa, pb) in enumerate(mine):
            adj.setdefault(a, []).append(i)
            adj.setdefault(b, []).append(i)
            pos[a], pos[b] = pa, pb
        used = [False] * len(mine)

        def walk(node: int, i: int) -> list[np.ndarray]:
            pts = [pos[node]]
            while True:
                used[i] = True
                _, a, b, _, _ = mine[i]
                node = b if a == node else a
                pts.append(pos[node])
                nxt = [k for k in adj[node] if not used[k]]
                if len(adj[node]) != 2 or not nxt:
                    return pts
                i = nxt[0]

        for node in sorted(adj):
            if len(adj[node]) == 2:
                continue
            for i in adj[node]:
                if not used[i]:
                    out.append((kind, walk(node, i)))
        for i in range(len(mine)):
            if not used[i]:
                out.append((kind, walk(mine[i][1], i)))
    return out


# ----------------------------------------------------------------------------- occlusion engines


def visible_points(points: Any, occluders: Sequence[Part], camera: Camera,
                   settings: ContourSettings | None = None) -> np.ndarray:
    """(n,) bool: True where no triangle of ``occluders`` hides the model point from ``camera``.

    The same exact test the contours use (the configured engine, default ``grid``), with its
    depth bias, so a point lying on an occluder's own surface counts as visible.

    Args:
        points: (n, 3) model points.
        occluders: the parts whose triangles may hide them.
        camera: the view.
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    if not len(pts) or not occluders:
        return np.ones(len(pts), dtype=bool)
    return occlusion_test(occluders, camera, settings)(pts)


def occlusion_test(occluders: Sequence[Part], camera: Camera,
                   settings: ContourSettings | None = None) -> Callable[[Any], np.ndarray]:
    """:func:`visible_points` against ``occluders`` as a function of the points, the engine
    built once (to test many point sets against the same parts)."""
    meshes = [_Mesh.of(p) for p in occluders]
    if not meshes:
        return lambda points: np.ones(len(np.asarray(points).reshape(-1, 3)), dtype=bool)
    return _points_test(_make_engine(settings or ContourSettings(), camera, meshes))


def _points_test(engine: Any) -> Callable[[Any], np.ndarray]:
    """``engine``'s visibility as a function of any array of points: (n,) bool."""
    return lambda points: np.asarray(
        engine.visible(np.asarray(points, dtype=float).reshape(-1, 3)), dtype=bool)



def own_contours(parts: Sequence[Part], camera: Camera, *, crease_deg: float = 35.0,
                 suggestive: bool = False, settings: ContourSettings | None = None
                 ) -> tuple[tuple[ContourSet, ...], tuple[Callable[[Any], np.ndarray], ...]]:
    """Each part's visible lines hidden by itself only (``trace_contours([part])``), and for
    each part :func:`occlusion_test` against it: one hidden-line engine per part serves both
    (the contour order's occlusion counts need the two).

    A sample of a part's lines found visible for certain by an earlier trace in this view whose
    occluders held the part (the finished drawing, :func:`final_contours`) is not tested again
    (:func:`_visible_pieces`): the same lines, without testing again every line the finished
    drawing shows (``dense``: about half of its samples)."""
    cs = _settings(settings, crease_deg, suggestive)
    sets, tests = [], []
    for p in parts:
        m = _Mesh.of(p)
        engine = _make_engine(cs, camera, [m])
        sets.append(_trace_one(m, camera, cs, engine, holds=True, alone=True))
        tests.append(_points_test(engine))
    return tuple(sets), tuple(tests)


def _make_engine(cs: ContourSettings, camera: Camera, meshes: Sequence[_Mesh]):
    if _engine_name(cs) == "ray":
        return _RayEngine(camera, cs, meshes)
    zb = (_GridEngine if _engine_name(cs) == "grid" else _ZBuffer)(camera, cs, meshes)
    for m in meshes:
        zb.add(m)
    return zb


def _sheet_window(camera: Camera, meshes: Sequence[_Mesh], cell: float) -> tuple[np.ndarray, np.ndarray]:
    """Where the meshes project (plus two cells), clipped to the sheet and one sheet around it, mm."""
    w, hgt = (float(x) for x in camera.paper_mm)
    lo, hi = np.array([-w, -hgt]), np.array([2 * w, 2 * hgt])
    qs = []
    for m in meshes:
        if len(m.v):
            d = camera.depth(m.v)
            if np.any(d > 0):
                qs.append(camera.project(m.v[d > 0]))
    if qs:
        q = np.concatenate(qs)
        lo = np.maximum(lo, q.min(axis=0) - 2 * cell)
        hi = np.maximum(np.minimum(hi, q.max(axis=0) + 2 * cell), lo)
    return lo, hi


def _screen_triangles(m: _Mesh, camera: Camera) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A mesh's occluder triangles on the sheet.

    Back faces are culled when the mesh is closed; triangles reaching behind the camera and
    triangles seen edge-on are skipped.

    Returns:
        ``(coef, xs, ys)``: (k, 12) barycentric edge functions ``l_i = A_i x + B_i y + C_i`` (columns
        ``3i .. 3i+2``) and the plane of ``1/depth`` (columns 9..11) on the sheet (mm); (k, 3) corner
        x and y, mm.
    """
    empty = (np.zeros((0, 12)), np.zeros((0, 3)), np.zeros((0, 3)))
    if len(m.f) == 0:
        return empty
    f = m.f
    if m.closed:
        eye = np.asarray(camera.position, dtype=float)
        f = f[np.einsum("ij,ij->i", m.n, eye - m.v[f[:, 0]]) > 0]
    w = camera.depth(m.v)
    f = f[np.all(w[f] > 1e-9 * max(m.diag, 1e-300), axis=1)]
    if len(f) == 0:
        return empty
    q = camera.project(m.v)
    u = 1.0 / w  # 1/depth is affine on the sheet
    a, b, c = q[f[:, 0]], q[f[:, 1]], q[f[:, 2]]
    area2 = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    ok = np.abs(area2) > 1e-12
    f, a, b, c, area2 = f[ok], a[ok], b[ok], c[ok], area2[ok]
    cols = []
    for p, r in ((b, c), (c, a), (a, b)):
        cols += [(p[:, 1] - r[:, 1]) / area2, (r[:, 0] - p[:, 0]) / area2,
                 (p[:, 0] * r[:, 1] - r[:, 0] * p[:, 1]) / area2]
    uu = u[f]
    for j in range(3):
        cols.append(sum(cols[3 * i + j] * uu[:, i] for i in range(3)))
    xs = np.stack([a[:, 0], b[:, 0], c[:, 0]], axis=1)
    ys = np.stack([a[:, 1], b[:, 1], c[:, 1]], axis=1)
    return np.stack(cols, axis=1), xs, ys


def _covers_in_front(coef: np.ndarray, x: np.ndarray, y: np.ndarray, w: np.ndarray) -> np.ndarray:
    """True where triangle ``coef[i]`` covers sheet point ``(x[i], y[i])`` nearer than depth ``w[i]``."""
    inside = np.ones(len(x), dtype=bool)
    for i in range(3):
        inside &= coef[:, 3 * i] * x + coef[:, 3 * i + 1] * y + coef[:, 3 * i + 2] >= -1e-9
    uv = coef[:, 9] * x + coef[:, 10] * y + coef[:, 11]
    return inside & (uv > 0) & (uv * w > 1.0)  # 1/depth larger: nearer


def _hits_in_front(coef_t: np.ndarray, tri: np.ndarray, x: np.ndarray, y: np.ndarray,
                   w: np.ndarray) -> np.ndarray:
    """Indices ``i`` where triangle ``tri[i]`` covers ``(x[i], y[i])`` nearer than ``w[i]``:
    :func:`_covers_in_front` on ``coef_t.T[tri]``, each of its tests computed only for the pairs
    that passed the ones before (the same arithmetic on the same numbers per pair, so the same
    answers), reading the columns of ``coef_t`` (12, k) one at a time."""
    at = np.arange(len(tri))
    for i in range(3):
        a, b, c = (coef_t[3 * i + k].take(tri) for k in range(3))
        keep = np.flatnonzero(a * x + b * y + c >= -1e-9)
        at, tri, x, y, w = at[keep], tri[keep], x[keep], y[keep], w[keep]
    uv = coef_t[9].take(tri) * x + coef_t[10].take(tri) * y + coef_t[11].take(tri)
    return at[(uv > 0) & (uv * w > 1.0)]  # 1/depth larger: nearer


class _GridEngine:
    """Exact occlusion tests against the triangles binned by their box on a coarse sheet grid.

    A sample is tested only against the triangles of its cell whose nearest corner is nearer
    than it, nearest first, in rounds that stop at its first hit, and only where it lies in the
    triangle's projected box (conservative: no pair the exact test would call hidden is
    dropped); at most :attr:`PAIRS` pairs at once.  A triangle is binned only in the cells it
    may reach.

    Each sample is tested (barycentric coordinates and ``1/depth`` on the sheet) against every
    occluder triangle whose projected box touches the sample's cell: no resolution limit, and a
    sample lying on its own faces is not hidden by them (they are at its depth, less the bias).

    The per-pair numbers are read column by column (the boxes in the order of the cells'
    entries, the 12 coefficients as rows of :attr:`coef_t`) and each test of the exact one is
    computed only for the pairs that passed the tests before it (:func:`_hits_in_front`): the
    same pairs tested with the same arithmetic as one (k, 12) gather per pair, about 3x faster
    (``dense``: 5.3 s -> 1.7 s of tests, the same answers for every sample).
    """

    #: Most (sample, triangle) pairs handled at once: small chunks stay in the CPU's cache
    #: (measured on the 146k-triangle model: 2M pairs 12.8 s, 1M 11.7 s, 250k 9.8 s, 100k
    #: 9.0 s, 50k 8.7 s; peak memory 604 -> 552 MB; the same lines).
    PAIRS = 100_000

    def __init__(self, camera: Camera, cs: ContourSettings, meshes: Sequence[_Mesh]):
        """An empty engine whose cell size suits ``meshes`` (all occluders to come)."""
        self.camera = camera
        self.bias = float(cs.depth_bias)
        lengths = []
        for m in meshes:
            if len(m.edges):
                d = camera.depth(m.v)
                e = m.edges[(d[m.edges] > 0).all(axis=1)]
                if len(e):
                    q = camera.project(m.v)
                    lengths.append(np.linalg.norm(q[e[:, 0]] - q[e[:, 1]], axis=1))
        med = float(np.median(np.concatenate(lengths))) if lengths else 1.0
        self.s = float(np.clip(2.0 * med, 0.25, 25.0))  # cell size, mm
        lo, hi = _sheet_window(camera, meshes, self.s)
        self.x0, self.y0 = float(lo[0]), float(lo[1])
        self.nx = max(1, int(math.ceil((hi[0] - lo[0]) / self.s)))
        self.ny = max(1, int(math.ceil((hi[1] - lo[1]) / self.s)))
        self._parts: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
        self._built = -1

    def add(self, m: _Mesh) -> None:
        """Add a mesh's triangles as occluders."""
        coef, xs, ys = _screen_triangles(m, self.camera)
        if len(coef):
            self._parts.append((coef, xs, ys))

    def _build(self) -> None:
        """The cells' entries: ``order`` (triangle per entry), sorted by ``key`` (cell, then
        nearness rank), ``start`` (first entry per cell), ``box`` (the entries' triangles'
        padded boxes: xmin, xmax, ymin, ymax), ``coef_t`` (12, triangles), ``near``/``near_up``."""
        self._built = len(self._parts)
        if not self._parts:
            self.coef_t = np.zeros((12, 0))
            self.start = np.zeros(self.nx * self.ny + 1, dtype=np.int64)
            self.order = self.key = np.zeros(0, dtype=np.int64)
            self.near = self.near_up = np.zeros(0)
            self.box = tuple(np.zeros(0) for _ in range(4))
            self.pad_max = 0.0
            return
        ct = self.coef_t = np.ascontiguousarray(np.concatenate([p[0] for p in self._parts]).T)
        xs = np.concatenate([p[1] for p in self._parts])
        ys = np.concatenate([p[2] for p in self._parts])
        xmin, xmax, ymin, ymax = xs.min(axis=1), xs.max(axis=1), ys.min(axis=1), ys.max(axis=1)
        # cheap, conservative pre-tests of a pair (see visible): the triangle's projected box,
        # grown a hair beyond the edge tolerance, and its nearest corner's 1/depth
        pad = 1e-6 * (1.0 + np.maximum(xmax - xmin, ymax - ymin))
        bounds = (xmin - pad, xmax + pad, ymin - pad, ymax + pad)
        self.pad_max = float(pad.max())
        self.near = np.stack([ct[9] * xs[:, k] + ct[10] * ys[:, k] + ct[11] for k in range(3)],
                             axis=1).max(axis=1)
        i0 = np.clip(np.floor((xmin - self.x0) / self.s), 0, self.nx).astype(np.int64)
        i1 = np.clip(np.floor((xmax - self.x0) / self.s), -1, self.nx - 1).astype(np.int64)
        j0 = np.clip(np.floor((ymin - self.y0) / self.s), 0, self.ny).astype(np.int64)
        j1 = np.clip(np.floor((ymax - self.y0) / self.s), -1, self.ny - 1).astype(np.int64)
        cw = np.maximum(i1 - i0 + 1, 0)
        cnt = cw * np.maximum(j1 - j0 + 1, 0)
        ti = np.repeat(np.arange(len(cnt)), cnt)
        dy, dx = np.divmod(np.arange(len(ti)) - np.repeat(np.cumsum(cnt) - cnt, cnt), cw[ti])
        cx = i0[ti] + dx
        cy = j0[ti] + dy
        # a triangle is binned only in the cells it may reach, not every cell of its box (a
        # thin diagonal triangle's box holds many cells it misses): a cell is dropped when it
        # lies wholly outside one of the triangle's edges, i.e. that edge function is below the
        # inside test's tolerance at the cell's best corner (cell grown by 1e-6 mm: rounding);
        # the cells' sides from tables (low sides, then high sides), each edge tested only on
        # the cells the edges before it kept
        pad = 1e-6
        col, row = np.arange(self.nx), np.arange(self.ny)
        xside = np.concatenate([self.x0 + col * self.s - pad, self.x0 + (col + 1) * self.s + pad])
        yside = np.concatenate([self.y0 + row * self.s - pad, self.y0 + (row + 1) * self.s + pad])
        for i in range(3):
            a_, b_, c_ = (ct[3 * i + k].take(ti) for k in range(3))
            keep = np.flatnonzero(a_ * xside.take(cx + self.nx * (a_ > 0))
                                  + b_ * yside.take(cy + self.ny * (b_ > 0)) + c_ >= -1e-9)
            ti, cx, cy = ti[keep], cx[keep], cy[keep]
        cell = cy * self.nx + cx
        # within a cell, nearest triangles first: entry key = cell * T + rank of the triangle
        # by its nearest corner (0 = nearest of all), so the triangles of a cell nearer than
        # a sample are a prefix of its run, found by one binary search
        t = len(self.near)
        by_near = np.argsort(-self.near, kind="stable")
        rank = np.empty(t, dtype=np.int64)
        rank[by_near] = np.arange(t)
        self.near_up = self.near[by_near][::-1].copy()  # ascending
        key = cell * t + rank[ti]
        order = np.argsort(key, kind="stable")
        self.order = ti[order]
        self.key = key[order]
        self.start = np.searchsorted(self.key, np.arange(self.nx * self.ny + 1) * t)
        self.box = tuple(b.take(self.order) for b in bounds)

    def _cells(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The points on the sheet, their biased depth, cell column and row (of the whole array
        of samples, as every engine asked about the same samples computes them)."""
        if self._built != len(self._parts):
            self._build()
        q = self.camera.project(points)
        w = self.camera.depth(points) * (1.0 - self.bias)
        ix = np.floor((q[:, 0] - self.x0) / self.s).astype(np.int64)
        iy = np.floor((q[:, 1] - self.y0) / self.s).astype(np.int64)
        return q, w, ix, iy

    def certain(self, points: np.ndarray) -> np.ndarray:
        """(n,) bool: True where the point lies in the grid, farther than twice the largest box
        padding from its cell's sides.

        Where this engine finds such a point visible, so does a grid engine holding only some
        of this engine's meshes (any cell size; the same camera and depth bias, asked about the
        same array of samples, :meth:`_cells`): were a triangle ``T`` of those meshes to hide
        it there, the point lies in ``T``'s padded box (that engine's own pre-test), so ``T``'s
        unpadded box reaches the point's cell here and ``T`` is binned in it (a cell is dropped
        only when it lies wholly outside an edge, 1e-6 mm to spare); ``T``'s nearest corner and
        box are the same numbers here, so this engine tests the same pair, with the same
        arithmetic, and would have found it hidden.
        """
        q, _, ix, iy = self._cells(points)
        d = 2.0 * self.pad_max
        x, y = self.x0 + ix * self.s, self.y0 + iy * self.s
        return ((ix >= 0) & (ix < self.nx) & (iy >= 0) & (iy < self.ny)
                & (q[:, 0] - x > d) & (x + self.s - q[:, 0] > d)
                & (q[:, 1] - y > d) & (y + self.s - q[:, 1] > d))

    def visible(self, points: np.ndarray, known: np.ndarray | None = None) -> np.ndarray:
        """(n,) bool: True where no occluder triangle covers the point from the front.

        ``known``: (n,) bool, points already known to be visible (not tested).
        """
        q, w, ix, iy = self._cells(points)
        ok = (ix >= 0) & (ix < self.nx) & (iy >= 0) & (iy < self.ny)
        if known is not None:
            ok &= ~known
        idx = np.flatnonzero(ok)
        cell = iy[idx] * self.nx + ix[idx]
        # the cell's triangles whose nearest corner is nearer than the sample (1/depth inside
        # a triangle is at most its corners' largest; 1e-9 to spare): entries pos .. end - 1
        t = len(self.near)
        qx, qy, wi = q[idx, 0], q[idx, 1], w[idx]
        with np.errstate(divide="ignore"):
            th = np.where(wi > 0, (1.0 - 1e-9) / np.where(wi > 0, wi, 1.0), np.inf)
        nearer = t - np.searchsorted(self.near_up, th, side="right")
        end = np.searchsorted(self.key, cell * t + nearer)
        pos = self.start[cell]  # (a copy: advanced by the rounds)
        hid = np.zeros(len(idx), dtype=bool)
        bx0, bx1, by0, by1 = self.box
        # In rounds, nearest triangles first: each round tests the next ``k`` candidates of
        # every sample not yet hidden (``k`` doubling), so a sample stops at the first round
        # with a hit; at most PAIRS pairs at once (memory).
        live = np.flatnonzero(end > pos)
        k = 16
        while len(live):
            for part in np.array_split(live, max(1, -(-len(live) * k // self.PAIRS))):
                if not len(part):
                    continue
                n = np.minimum(end[part] - pos[part], k)
                last = np.cumsum(n)
                rep = np.repeat(np.arange(len(part)), n)
                at = np.arange(int(last[-1])) + np.repeat(pos[part] - (last - n), n)
                x, y = np.repeat(qx[part], n), np.repeat(qy[part], n)
                # the exact test only where the sample lies in the triangle's box
                inbox = np.flatnonzero((x >= bx0.take(at)) & (x <= bx1.take(at))
                                       & (y >= by0.take(at)) & (y <= by1.take(at)))
                sample = part.take(rep.take(inbox))
                hit = _hits_in_front(self.coef_t, self.order.take(at.take(inbox)),
                                     x.take(inbox), y.take(inbox), wi.take(sample))
                hid[sample.take(hit)] = True
            pos[live] += k
            live = live[(pos[live] < end[live]) & ~hid[live]]
            k *= 2
        hidden = np.zeros(len(q), dtype=bool)
        hidden[idx[hid]] = True
        return ~hidden


class _ZBuffer:
    """A depth buffer with an item buffer: per cell, the nearest occluder triangle at its centre.

    A sample is hidden when one of the triangles recorded in its cell or the 8 cells around it
    covers the sample's exact projection and is nearer there than the sample (less the relative
    bias).  The final test is exact (barycentric coordinates and ``1/depth``, which is affine on
    the sheet), so a sample lying on its own faces is never hidden by them; the grid only chooses
    which triangles to test.
    """

    def __init__(self, camera: Camera, cs: ContourSettings, meshes: Sequence[_Mesh]):
        """An empty buffer covering where ``meshes`` (all occluders to come) project.

        The grid spans their projected box, clipped to the sheet and one sheet around it.
        """
        self.camera = camera
        self.h = float(cs.pixel_mm)
        self.bias = float(cs.depth_bias)
        lo, hi = _sheet_window(camera, meshes, self.h)
        self.x0, self.y0 = float(lo[0]), float(lo[1])
        self.nx = max(1, int(math.ceil((hi[0] - lo[0]) / self.h)))
        self.ny = max(1, int(math.ceil((hi[1] - lo[1]) / self.h)))
        self.z = np.full(self.nx * self.ny, np.inf)
        self.item = np.full(self.nx * self.ny, -1, dtype=np.int64)
        self._coef: list[np.ndarray] = []  # per add(): (k, 12) edge functions and 1/depth plane
        self._all = np.zeros((0, 12))
        self.ntri = 0

    def add(self, m: _Mesh) -> None:
        """Rasterise a mesh's triangles (back faces culled when the mesh is closed)."""
        coef, xs, ys = _screen_triangles(m, self.camera)
        if len(coef) == 0:
            return
        base = self.ntri
        self._coef.append(coef)
        self.ntri += len(coef)
        i0 = np.clip(np.ceil((xs.min(axis=1) - self.x0) / self.h - 0.5), 0, self.nx).astype(np.int64)
        i1 = np.clip(np.floor((xs.max(axis=1) - self.x0) / self.h - 0.5), -1, self.nx - 1).astype(np.int64)
        j0 = np.clip(np.ceil((ys.min(axis=1) - self.y0) / self.h - 0.5), 0, self.ny).astype(np.int64)
        j1 = np.clip(np.floor((ys.max(axis=1) - self.y0) / self.h - 0.5), -1, self.ny - 1).astype(np.int64)
        cw = np.maximum(i1 - i0 + 1, 0)
        cnt = cw * np.maximum(j1 - j0 + 1, 0)
        tri = np.flatnonzero(cnt > 0)
        budget = 1_000_000
        csum = np.cumsum(cnt[tri])
        lo = 0
        while lo < len(tri):
            hi = int(np.searchsorted(csum, (csum[lo - 1] if lo else 0) + budget, side="right"))
            hi = max(hi, lo + 1)
            tt = tri[lo:hi]
            lo = hi
            k = np.repeat(np.arange(len(tt)), cnt[tt])
            off = np.arange(len(k)) - np.repeat(np.concatenate([[0], np.cumsum(cnt[tt])[:-1]]), cnt[tt])
            ti = tt[k]
            ix = i0[ti] + off % cw[ti]
            iy = j0[ti] + off // cw[ti]
            px = self.x0 + (ix + 0.5) * self.h
            py = self.y0 + (iy + 0.5) * self.h
            cf = coef[ti]
            inside = np.ones(len(k), dtype=bool)
            for i in range(3):
                inside &= cf[:, 3 * i] * px + cf[:, 3 * i + 1] * py + cf[:, 3 * i + 2] >= -1e-9
            uv = cf[:, 9] * px + cf[:, 10] * py + cf[:, 11]
            keep = inside & (uv > 0)
            ti, cell, depth = ti[keep], (iy * self.nx + ix)[keep], 1.0 / uv[keep]
            np.minimum.at(self.z, cell, depth)
            won = depth == self.z[cell]  # ties: the later triangle, deterministically
            self.item[cell[won]] = ti[won] + base

    def visible(self, points: np.ndarray) -> np.ndarray:
        """(n,) bool: True where no triangle recorded around the point covers it from the front."""
        if len(self._coef) > 1 or (self._coef and len(self._all) != self.ntri):
            self._all = np.concatenate(self._coef)
            self._coef = [self._all]
        q = self.camera.project(points)
        w = self.camera.depth(points) * (1.0 - self.bias)
        ix = np.floor((q[:, 0] - self.x0) / self.h).astype(np.int64)
        iy = np.floor((q[:, 1] - self.y0) / self.h).astype(np.int64)
        hidden = np.zeros(len(q), dtype=bool)
        if self.ntri == 0:
            return ~hidden
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                cx, cy = ix + dx, iy + dy
                ok = (cx >= 0) & (cx < self.nx) & (cy >= 0) & (cy < self.ny)
                tid = np.full(len(q), -1, dtype=np.int64)
                tid[ok] = self.item[cy[ok] * self.nx + cx[ok]]
                sel = np.flatnonzero((tid >= 0) & ~hidden)
                if len(sel) == 0:
                    continue
                hidden[sel] = _covers_in_front(self._all[tid[sel]], q[sel, 0], q[sel, 1], w[sel])
        return ~hidden


class _RayEngine:
    """Rays from each sample toward the camera position through trimesh's ray interface."""

    def __init__(self, camera: Camera, cs: ContourSettings, meshes: Sequence[_Mesh]):
        import trimesh

        self.eye = np.asarray(camera.position, dtype=float)
        vs, fs, off = [], [], 0
        for m in meshes:
            vs.append(m.v)
            fs.append(m.f + off)
            off += len(m.v)
        v = np.concatenate(vs) if vs else np.zeros((0, 3))
        f = np.concatenate(fs) if fs else np.zeros((0, 3), dtype=np.int64)
        self.empty = len(f) == 0
        if self.empty:
            return
        scale = float(np.linalg.norm(v.max(axis=0) - v.min(axis=0))) + float(np.abs(self.eye).max())
        self.eps = 1e-6 * scale
        self.bias = float(cs.depth_bias)
        mesh = trimesh.Trimesh(vertices=v, faces=f, process=False)
        try:
            from trimesh.ray.ray_pyembree import RayMeshIntersector

            self.intersector = RayMeshIntersector(mesh)
            self.kind = "embree"
        except Exception:  # embreex is optional
            from trimesh.ray.ray_triangle import RayMeshIntersector

            self.intersector = RayMeshIntersector(mesh)
            self.kind = "triangle"

    def visible(self, points: np.ndarray) -> np.ndarray:
        """(n,) bool: True where the segment from the point to the camera meets no triangle."""
        points = np.asarray(points, dtype=float)
        vis = np.ones(len(points), dtype=bool)
        if self.empty or len(points) == 0:
            return vis
        d = self.eye - points
        dist = np.linalg.norm(d, axis=1)
        d = d / dist[:, None]
        # start slightly toward the camera (the relative bias): a sample on a face is not hidden by it
        start = np.maximum(self.bias * dist, 4 * self.eps)
        origin = points + d * start[:, None]
        pending = np.arange(len(points))
        for _ in range(4):  # re-cast past spurious grazing hits at (almost) the origin
            if len(pending) == 0:
                break
            _, ri, loc = self.intersector.intersects_id(
                origin[pending], d[pending], multiple_hits=False, return_locations=True)
            if len(ri) == 0:
                break
            rays = pending[ri]
            t = np.einsum("ij,ij->i", loc - origin[rays], d[rays])
            real = (t > self.eps) & (t < dist[rays] - start[rays] - self.eps)
            vis[rays[real]] = False
            again = rays[(t <= self.eps)]
            origin[again] = origin[again] + d[again] * (4 * self.eps)
            pending = np.sort(again)
        return vis


# ----------------------------------------------------------------------------- suggestive contours


def _suggestive(m: _Mesh, camera: Camera, cs: ContourSettings):
    """Zero crossings of the radial curvature with ``D_w k_r > 0`` on front faces (DeCarlo 2003).

    Returns:
        ``(p0, p1, nodes)``: segment end points (k, 3), model units, and (k, 2) node ids (mesh edge
        ids, so that segments of neighbouring faces share end points).
    """
    empty = (np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 2), dtype=np.int64))
    if len(m.f) == 0 or m.diag <= 0:
        return empty
    v, f, fn = m.v, m.f, m.n
    # vertex normals: area-weighted face normals
    cross = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    vn = np.zeros_like(v)
    for i in range(3):
        np.add.at(vn, f[:, i], cross)
    if m.closed and np.dot(cross[0], fn[0]) < 0:
        vn = -vn
    vn /= np.maximum(np.linalg.norm(vn, axis=1), 1e-300)[:, None]
    # per-face second fundamental form from normal differences (Rusinkiewicz 2004), as a 3x3 tensor
    e1 = v[f[:, 1]] - v[f[:, 0]]
    e1 /= np.linalg.norm(e1, axis=1)[:, None]
    e2 = np.cross(fn, e1)
    rows, rhs = [], []
    for i, j in ((0, 1), (1, 2), (2, 0)):
        e = v[f[:, j]] - v[f[:, i]]
        dn = vn[f[:, j]] - vn[f[:, i]]
        u, w = np.einsum("ij,ij->i", e, e1), np.einsum("ij,ij->i", e, e2)
        du, dw = np.einsum("ij,ij->i", dn, e1), np.einsum("ij,ij->i", dn, e2)
        z = np.zeros_like(u)
        rows += [np.stack([u, w, z], axis=1), np.stack([z, u, w], axis=1)]
        rhs += [du, dw]
    A = np.stack(rows, axis=1)  # (m, 6, 3): unknowns (L, M, N)
    bvec = np.stack(rhs, axis=1)
    ata = np.einsum("kij,kil->kjl", A, A) + 1e-12 * np.eye(3)
    atb = np.einsum("kij,ki->kj", A, bvec)
    L, M, N = np.linalg.solve(ata, atb[..., None])[..., 0].T
    T = (L[:, None, None] * np.einsum("ki,kj->kij", e1, e1)
         + M[:, None, None] * (np.einsum("ki,kj->kij", e1, e2) + np.einsum("ki,kj->kij", e2, e1))
         + N[:, None, None] * np.einsum("ki,kj->kij", e2, e2))
    area = np.linalg.norm(cross, axis=1)
    VT = np.zeros((len(v), 3, 3))
    wsum = np.zeros(len(v))
    for i in range(3):
        np.add.at(VT, f[:, i], T * area[:, None, None])
        np.add.at(wsum, f[:, i], area)
    VT /= np.maximum(wsum, 1e-300)[:, None, None]
    # radial curvature k_r = II(w, w) / |w|^2, w the view vector projected on the tangent plane
    eye = np.asarray(camera.position, dtype=float)
    view = eye - v
    view /= np.linalg.norm(view, axis=1)[:, None]
    wv = view - np.einsum("ij,ij->i", view, vn)[:, None] * vn
    wn = np.linalg.norm(wv, axis=1)
    wv = wv / np.maximum(wn, 1e-300)[:, None]
    kr = np.einsum("ki,kij,kj->k", wv, VT, wv)
    # per-face: sign change, front-facing, derivative of k_r along w (face gradient of k_r)
    kf = kr[f]
    pos = kf > 0
    crossing = pos.any(axis=1) & ~pos.all(axis=1)
    fc = v[f].mean(axis=1)
    fview = eye - fc
    fview /= np.linalg.norm(fview, axis=1)[:, None]
    ndotv = np.einsum("ij,ij->i", fn, fview)
    # faces near a sharp edge (crease or boundary) have smeared normals: no suggestive lines there
    two = m.ef[:, 1] >= 0
    sgn = np.where(m.consistent, 1.0, -1.0)
    cosang = np.einsum("ij,ij->i", fn[m.ef[:, 0]], fn[np.maximum(m.ef[:, 1], 0)]) * sgn
    sharp = ~two | (cosang < math.cos(math.radians(cs.crease_deg)))
    sharp_v = np.zeros(len(v), dtype=bool)
    sharp_v[m.edges[sharp].reshape(-1)] = True
    near = sharp_v[f].any(axis=1)  # the ring of faces around sharp vertices has bent vertex normals,
    sharp_v[f[near].reshape(-1)] = True  # and the next ring averages their tensors: skip both
    smooth = ~sharp_v[f].any(axis=1)
    cand = np.flatnonzero(crossing & smooth & (ndotv > 0.05))
    if len(cand) == 0:
        return empty
    fa = f[cand]
    pa, pb, pc = v[fa[:, 0]], v[fa[:, 1]], v[fa[:, 2]]
    nrm = fn[cand]
    ar2 = np.einsum("ij,ij->i", np.cross(pb - pa, pc - pa), nrm)
    grad = (kf[cand, 0, None] * np.cross(nrm, pc - pb) + kf[cand, 1, None] * np.cross(nrm, pa - pc)
            + kf[cand, 2, None] * np.cross(nrm, pb - pa)) / ar2[:, None]
    wf = fview[cand] - ndotv[cand, None] * nrm
    wf /= np.maximum(np.linalg.norm(wf, axis=1), 1e-300)[:, None]
    dwkr = np.einsum("ij,ij->i", grad, wf)
    strong = dwkr * m.diag ** 2 > cs.suggestive_strength
    cand = cand[strong]
    if len(cand) == 0:
        return empty
    # the zero crossing on each face: the two edges whose end values differ in sign
    edge_index = {}
    for idx, (a, b) in enumerate(m.edges.tolist()):
        edge_index[(a, b)] = idx
    p0s, p1s, nodes = [], [], []
    for fi in cand.tolist():
        tri = f[fi]
        pts, ids = [], []
        for i, j in ((0, 1), (1, 2), (2, 0)):
            a, b = int(tri[i]), int(tri[j])
            ka, kb = kr[a], kr[b]
            if (ka > 0) != (kb > 0):
                if a > b:
                    a, b, ka, kb = b, a, kb, ka
                s = ka / (ka - kb)
                pts.append(v[a] + s * (v[b] - v[a]))
                ids.append(edge_index[(a, b)])
        if len(pts) == 2:
            p0s.append(pts[0])
            p1s.append(pts[1])
            nodes.append(ids)
    if not p0s:
        return empty
    return np.asarray(p0s), np.asarray(p1s), np.asarray(nodes, dtype=np.int64)
