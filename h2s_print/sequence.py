"""Stage 6, *sequence*: a solved :class:`~h2s_print.plan.Plan` -> the steps of one view and level.

DESIGN.md §2.6 and paper §5.  Public verbs:

* :func:`view_camera` -- the one camera of a view, shared by all its levels;
* :func:`sequence_view` (and :func:`sequence_views` for several levels at once) -- the
  :class:`~h2s_print.types.ViewPlan` of a view and level;
* :func:`final_strokes` -- the finished drawing (every part's contours hidden by all parts);
* :func:`steps_text` -- a readable dump, one line per step.

What a tutorial contains, in order
----------------------------------
1. **Primitive steps** (kind ``primitive``), one per part, in *drawing order*, coarse to fine
   (paper §3 (ii); decisions below): the start part first, then a topological order of the
   anchoring graph of the selected candidates (parents first), bigger before smaller wherever
   the anchoring allows, nearest first among parts of similar size.  Each
   step's guides are built in 3D from its anchors: the ratio's construction
   (:func:`h2s_print.constructions.construct`) on the
   parent's *selected* box face named by the anchor; when the anchor leaves the side open
   (``face_side is None``) the view picks, among the parent's faces parallel to the anchored
   axis, the front-facing one with the largest projected area.  Alignment lines (role
   ``vanishing``, :func:`h2s_print.constructions.align`) then carry the resulting line across,
   in the plane of the anchored end, to the child's end face: along the line itself when the
   child touches the face's plane, otherwise along the face normal from the result line's end
   nearest the child (and, if needed, across to the child).  An anchor on a parent that is
   flat along the anchored axis (``face_normal == axis``) needs no construction: the text says
   "in the plane of ..." and no guide is drawn.  A frustum parent's box faces are not drawn
   (its scaffold is the tapered solid), so a construction on it first draws the box around it
   (the box edges its scaffold leaves out, role ``vanishing``, "Draw the box around ...").
   Each distinct result line gets one sentence; one an earlier step described is referred to
   ("Use the quarter lines of the body's front face from step 4").
2. **Ellipse steps** (kind ``ellipse``) for cylinders, in drawing order: both end faces of the
   selected box (front-facing first), each with its diagonals (role ``construction``), the two
   lines through the centre toward the vanishing points (role ``guide``) and the exact
   projection of the inscribed circle (:func:`h2s_print.constructions.ellipse_on_face`).
   Frusta here are rectangular: no ellipse.
3. **Contour steps** (kind ``contour``), one per part, *front to back*: a part that hides some
   of another part's lines (rays from the camera position to samples of that part's own
   visible contours) comes before it; among the parts nothing left hides, the nearest box
   centre first (ties: name); parts that hide each other (interpenetrating) start with the one
   the rest hide least.  Each step draws the part's lines of the finished drawing
   (:func:`final_strokes`: the *adjusted* mesh, :func:`h2s_print.contours.adjust_part`, hidden
   by all parts), which in that order are the lines hidden by the parts drawn so far plus
   itself; so the steps add up to exactly the finished drawing.  A part with nothing visible
   gets no contour step.  Closed loops under ``TINY_LOOP_MM`` on the sheet are dropped.

Decisions where the brief is open (kept here, in one place)
-----------------------------------------------------------
* **Scaffold strokes.**  Cuboids, cylinders and custom parts: the 12 box edges; planes: the
  rectangle at the box's mid-plane along the plane normal; frusta: both end rectangles and the
  4 side edges.  An edge none of whose faces is front-facing (seen from the camera position;
  occlusion by other parts is ignored: scaffolds are drawn "through") is kind
  ``scaffold_hidden`` -- the layout may dash it -- the others kind ``scaffold``.
* **Drawing order** (issue 10 point 3, :func:`h2s_print.order.drawing_order`; sizes are
  :func:`h2s_print.order.part_size`, the largest face, of the *selected* boxes; distances from
  the camera position to the selected box centres).  Only the parts kept (see "Left out") are
  ordered.

  - *First*: the start part (:func:`h2s_print.order.start_part` of the fitted primitives: the
    largest part, or a grounded one at least half as large), so the calibrated sheet's ground
    plane is the object's ground.  If it is left out, the start part of the kept parts.  If the
    selection hung it off other parts (it should make it a root), its ancestors come first, by
    the rules below, then it; a log line says so.
  - *Then*, among the *ready* parts (parents all drawn): a part's *reach* is the largest size
    over itself and the undrawn parts that wait for it (descendants, and free parts still
    waiting to rest on it); keep the ready parts whose reach is within a factor
    :data:`~h2s_print.order.SIMILAR_FACTOR` (2) of the largest reach, of those the ones whose
    own size is within 2 of the largest own size, and draw the nearest of those (the paper's
    tie rule, §5 (i); then the name).  So a small parent of a big part comes early (the way to
    the big part), an unrelated small part comes after bigger ones, and tiny details come
    last.  Nearness only decides between parts within 2x of each other, a margin below the 4x
    of a coarse-to-fine inversion.
  - *Free parts* (no anchor) are placed by eye.  After the first step a free part waits until
    one of the parts its box touches or overlaps (it rests on or sits in them) is drawn, as a
    teacher puts the chimney on a drawn boiler; but it waits only on parts at most
    :data:`~h2s_print.order.COARSER_FACTOR` (4) times smaller than itself and not anchored
    off it (a big roller is not held back for its small axle: that would draw the small part
    first), and free parts that only wait on each other are all ready.
* **Eyeball rule** (paper §5 (ii), issue 10 point 1c).  For each parent face a primitive step
  constructs on, ``A_p / k`` is the face's projected area on the sheet (mm²) over the number
  ``k`` of distinct lines drawn on it *that need room on the face*: an alignment (ratio 0 or
  1, :attr:`h2s_print.ratios.RatioEntry.needs_room` False) is an existing edge extended toward
  its vanishing point and counts for nothing, so a face carrying only alignments is never
  tested and a step whose anchors only align is never eyeballed.  The part is "eyeballed" when
  any tested face falls below ``settings.eyeball_mm2``, or when a tested face is seen almost
  edge-on: its projected width (its projected area over its longest projected side) is under
  ``MIN_FACE_WIDTH_MM`` (3 mm), whatever the threshold.  An eyeballed part gets no guides at
  any level, and the text says where to put it by eye ("about a third of the way ...").
  Ellipse steps use the same rule with ``k = 4`` per end face.
  Parts without anchors are never eyeballed (there is nothing to construct).
* **Left out** (paper §5 (iii)).  A part is *hidden* when :func:`~h2s_print.contours.final_contours`
  (all parts hide all parts) leaves it no polyline; a hidden part is left out unless it is an
  ancestor (in the anchoring graph) of a part that is not hidden.
* **Levels.**  ``novice`` sees every line (roles ``construction``, ``guide``, ``vanishing``),
  ``apprentice`` the resulting lines and the alignment lines that carry them (``guide``,
  ``vanishing``), ``master`` none.  All three have the same steps, in the same order, with the
  same texts (the text always says what to construct).  ``basic`` is the paper's control
  tutorial: the fitted (original) primitives, the start part first (as the guided order; the
  paper's control also starts on the ground plane), then from largest to smallest
  :func:`h2s_print.order.part_size` of the fitted box (ties: name), kind ``basic``, eyeball
  True, no guides at all, no adjustment; then ellipses (no guides) and contours of the
  unadjusted meshes in that order; hidden parts are left out.
* **Guide identity and lifetime** (paper §5).  Two lines are the same guide when they are the
  same 3D segment up to endpoint order, within ``MERGE_TOL`` × the model's bounding-box
  diagonal (collinear but different segments stay different guides: they are different pencil
  strokes).  Ids ``g1``, ``g2`` ... are numbered over the novice tutorial of the view in order
  of first appearance, so a guide keeps its id at every level; a merged guide keeps the 3D
  end points of its first appearance.  Within one step a line used with several roles takes
  the strongest (``guide`` > ``vanishing`` > ``construction``).  Per level, a guide is
  ``new`` in the first step that shows it, ``reused`` in later steps that show it, and
  ``Step.alive`` lists (in id order of first appearance) every guide whose first use is at or
  before the step and whose last use is at or after it.
* **Camera.**  :func:`view_camera` frames the selected boxes' corners, the adjusted meshes'
  vertices, *and* the fitted (original) boxes and meshes, so that the ``basic`` tutorial fits
  the margins with the same camera.  Guides of extrusions can reach beyond those points: then
  the picture is scaled down about the sheet centre (same camera pose) until every guide any
  level could show lies inside the margins too.
* **Text.**  Every sentence comes from ``templates/steps.yaml``.  Vanishing points are named by
  :func:`h2s_print.project.vp_side` seen from the *sheet's* centre (left/right when the
  horizontal offset dominates, above/below otherwise), "parallel to the ... edges" at infinity:
  the same rule and centre as the calibrated sheet's labels (:func:`h2s_print.layout.vp_names`).
  Front/back and top/bottom faces follow the model (the front is the object's front, ``y_lo``);
  the x faces and sides follow the *picture*: of ``x_lo`` / ``x_hi``, the one whose face centre
  (on the selected boxes' bounding box) projects further left on the sheet is "left", so a view
  from behind (azimuth 180) calls ``x_hi`` "left".

Every ``*_mm`` coordinate is ``camera.project`` of its 3D point.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Any, Iterable, Sequence

import numpy as np

from . import templates
from .config import PaperSpec, SequenceSettings, ViewSpec
from .constructions import Face, align, construct, ellipse_on_face
from .contours import adjust_part, final_contours, trace_contours, visible_points
from .errors import SelectionError
from .order import drawing_order, part_size, start_part
from .project import make_camera, vanishing_points, vp_side
from .ratios import entry_for
from .types import Box, Camera, Guide, Part, Step, Stroke, VanishingPoint, Vec3, ViewPlan

log = logging.getLogger(__name__)

#: Lines whose end points agree within this fraction of the model's diagonal are one guide.
MERGE_TOL = 1e-6
#: Closed contour loops smaller than this on the sheet (largest side of their extent, mm) are
#: dropped from the contour steps and the final drawing: a merged screw head draws a dot.
TINY_LOOP_MM = 1.0
#: Roles shown at each level.
LEVEL_ROLES: dict[str, frozenset[str]] = {
    "novice": frozenset({"construction", "guide", "vanishing"}),
    "apprentice": frozenset({"guide", "vanishing"}),
    "master": frozenset(),
    "basic": frozenset(),
}
#: A face whose projected width on the sheet (its projected area over its longest projected
#: side, mm) is under this is too thin for guide lines (seen almost edge-on): its
#: constructions are eyeballed whatever ``settings.eyeball_mm2`` says.
MIN_FACE_WIDTH_MM = 3.0
_ROLE_RANK = {"construction": 0, "vanishing": 1, "guide": 2}
_XYZ = "xyz"


def _t(key: str, **fields: Any) -> str:
    for k in ("part", "parent"):  # part names are identifiers: "shutter_button" -> "shutter button"
        if isinstance(fields.get(k), str):
            fields[k] = fields[k].replace("_", " ")
    return templates.text("steps", key, **fields)


def _raw(key: str) -> Any:
    return templates.lookup("steps", key)


# ----------------------------------------------------------------------------- geometry helpers


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


def _same_segment(a: Any, b: Any, p: Any, q: Any, tol: float) -> bool:
    """True when segment ``a-b`` is segment ``p-q`` up to endpoint order, within ``tol``."""
    a, b, p, q = (np.asarray(x, dtype=float) for x in (a, b, p, q))
    return bool((np.abs(a - p).max() <= tol and np.abs(b - q).max() <= tol)
                or (np.abs(a - q).max() <= tol and np.abs(b - p).max() <= tol))


def _tiny_loop(mm: np.ndarray) -> bool:
    """True for a closed polyline whose extent on the sheet is under ``TINY_LOOP_MM``."""
    if len(mm) < 3 or float(np.abs(mm[0] - mm[-1]).max()) > 1e-6 * max(1.0, float(np.abs(mm).max())):
        return False
    ext = mm.max(axis=0) - mm.min(axis=0)
    return float(max(ext[0], ext[1])) < TINY_LOOP_MM


def _polygon_area_mm2(camera: Camera, corners: Sequence[Vec3]) -> float:
    """Area on the sheet (mm²) of a planar polygon's projection (shoelace)."""
    p = camera.project(np.asarray(corners, dtype=float))
    x, y = p[:, 0], p[:, 1]
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def _too_small(camera: Camera, corners: Sequence[Vec3], k: int, eyeball_mm2: float) -> bool:
    """The eyeball rule for one face with ``k`` lines on it (module docstring): projected area
    over ``k`` under ``eyeball_mm2`` mm², or projected width (area over the longest projected
    side) under ``MIN_FACE_WIDTH_MM``."""
    p = camera.project(np.asarray(corners, dtype=float))
    x, y = p[:, 0], p[:, 1]
    area = 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))
    longest = float(np.linalg.norm(p - np.roll(p, -1, axis=0), axis=1).max())
    return area / k < eyeball_mm2 or not area >= MIN_FACE_WIDTH_MM * longest


def _front_facing(face: Face, camera: Camera) -> bool:
    """True when the face's outer side looks toward the camera position."""
    sign = 1.0 if face.end == "hi" else -1.0
    return sign * (camera.position[face.normal] - face.coord) > 0.0


# ----------------------------------------------------------------------------- camera


def _adjusted_parts(plan: Any) -> dict[str, Part]:
    chosen = plan.chosen()
    return {p.name: adjust_part(p, plan.primitive(p.name).box, chosen[p.name].box)
            for p in plan.model.parts}


def _frame_points(plan: Any, adjusted: dict[str, Part]) -> np.ndarray:
    chosen = plan.chosen()
    pts = [_box_corners(chosen[p.name].box) for p in plan.model.parts]
    pts += [_box_corners(plan.primitive(p.name).box) for p in plan.model.parts]
    pts += [np.asarray(adjusted[p.name].vertices, dtype=float) for p in plan.model.parts]
    pts += [np.asarray(p.vertices, dtype=float) for p in plan.model.parts]
    return np.vstack([p for p in pts if len(p)])


def _guide_points(plan: Any, camera: Camera, tol: float) -> np.ndarray:
    """End points of every guide any level of this view could show (eyeball rule ignored)."""
    by_id = {c.id: c for c in plan.candidates}
    pts: list[Vec3] = []
    for cand in plan.chosen().values():
        for anchor in cand.anchors:
            if anchor.face_normal == anchor.axis:
                continue
            _, _, own, carry = _anchor_lines(anchor, by_id[anchor.parent].box, cand.box, camera,
                                             tol)
            pts += [p for ln in own + carry for p in (ln.start, ln.end)]
    return np.array(pts, dtype=float).reshape(-1, 3)


def _fit_camera(plan: Any, view: ViewSpec, paper: PaperSpec, adjusted: dict[str, Part],
                tol: float) -> Camera:
    framed = _frame_points(plan, adjusted)
    camera = make_camera(view, framed, paper)
    guides = _guide_points(plan, camera, tol)
    if not len(guides):
        return camera
    m = paper.margin_mm
    x0, y0, x1, y1 = m, m, paper.width_mm - m, paper.height_mm - m
    f = camera.project(framed)
    flo, fhi = f.min(axis=0), f.max(axis=0)
    a = np.vstack([f, camera.project(guides)])
    alo, ahi = a.min(axis=0), a.max(axis=0)
    if alo[0] >= x0 - 1e-9 and alo[1] >= y0 - 1e-9 and ahi[0] <= x1 + 1e-9 and ahi[1] <= y1 + 1e-9:
        return camera
    # Shrink and centre everything (points and guides) into the margins.  The camera's pose
    # does not change, only the 2D similarity on the sheet: passing make_camera the area where
    # the framed points must land reproduces exactly that similarity.
    k = min((x1 - x0) / (ahi[0] - alo[0]), (y1 - y0) / (ahi[1] - alo[1]))
    centre = np.array([(x0 + x1) / 2, (y0 + y1) / 2])
    mid = (alo + ahi) / 2
    lo = centre + k * (flo - mid)
    hi = centre + k * (fhi - mid)
    log.debug("view %r: guides reach beyond the margins; drawing scaled by %.4f", view.name, k)
    return make_camera(view, framed, paper, area_mm=(lo[0], lo[1], hi[0], hi[1]))


def _tolerance(plan: Any) -> float:
    lo, hi = plan.model.bounds
    return MERGE_TOL * (float(np.linalg.norm(np.subtract(hi, lo))) or 1.0)


def view_camera(plan: Any, view: ViewSpec, paper: PaperSpec) -> Camera:
    """The camera of ``view``, shared by all its levels and its calibrated sheet.

    It frames (inside the paper margins) the selected boxes' corners, the adjusted part meshes'
    vertices, and the fitted primitives' boxes and unadjusted meshes (used by ``basic``); when
    a guide (of any level) would reach beyond the margins, the drawing is scaled down about
    the sheet's centre until every guide fits too (same camera pose, smaller picture).

    Raises:
        ConfigError: the view cannot see the model (see :func:`h2s_print.project.make_camera`).
    """
    return _fit_camera(plan, view, paper, _adjusted_parts(plan), _tolerance(plan))


# ----------------------------------------------------------------------------- words


class _Words:
    """Names of faces, sides, dimensions and vanishing points for this view's texts.

    Vanishing points: :func:`h2s_print.project.vp_side` seen from the sheet's centre (the rule
    the calibrated sheet's labels use, :func:`h2s_print.layout.vp_names`).  The x faces and
    sides are named by the picture: the one of ``x_lo`` / ``x_hi`` whose face centre (of the
    model's bounding box) projects further left is "left" (``swap_x`` when that is ``x_hi``).
    """

    def __init__(self, camera: Camera, vps: Sequence[VanishingPoint], bounds: Box):
        edges = _raw("edges")
        centre_mm = (camera.paper_mm[0] / 2.0, camera.paper_mm[1] / 2.0)
        keys: dict[int, str] = {}
        for vp in vps:
            side = vp_side(vp, centre_mm)
            if side is not None:
                keys[vp.axis] = side
        self.vps: dict[int, str] = {}
        for vp in vps:
            if vp.axis not in keys:
                self.vps[vp.axis] = _t("vp.infinite", edges=edges[vp.axis])
                continue
            key = keys[vp.axis]
            clash = sum(1 for k in keys.values() if k == key) > 1
            self.vps[vp.axis] = (_t(f"vp.{key}_of", edges=edges[vp.axis]) if clash
                                 else _t(f"vp.{key}"))
        xs = [Face(bounds, 0, end) for end in ("lo", "hi")]
        cx = camera.project(np.array([np.mean(np.asarray(f.corners, dtype=float), axis=0)
                                      for f in xs]))[:, 0]
        self.swap_x = bool(cx[1] < cx[0])

    def vp(self, axis: int) -> str:
        return self.vps[axis]

    def _key(self, axis: int, end: str) -> str:
        if axis == 0 and self.swap_x and end != "mid":
            end = "hi" if end == "lo" else "lo"
        return f"{_XYZ[axis]}_{end}"

    def face(self, axis: int, end: str) -> str:
        return _raw("faces")[self._key(axis, end)]

    def side(self, axis: int, end: str) -> str:
        return _raw("sides")[self._key(axis, end)]

    @staticmethod
    def dim(axis: int) -> str:
        return _raw("dims")[axis]

    @staticmethod
    def shape(kind: str) -> str:
        shapes = _raw("shapes")
        return shapes.get(kind, shapes["cuboid"])


def _join(items: Sequence[str]) -> str:
    items = list(items)
    if len(items) <= 1:
        return "".join(items)
    return _raw("join").join(items[:-1]) + _raw("join_last") + items[-1]


def _unique(items: Iterable[str]) -> list[str]:
    out: list[str] = []
    for s in items:
        if s not in out:
            out.append(s)
    return out


# ----------------------------------------------------------------------------- drafts


@dataclass(frozen=True, slots=True)
class _Line:
    """A guide line before ids: role and 3D end points."""

    role: str
    start: Vec3
    end: Vec3


@dataclass(frozen=True, slots=True)
class _Draft:
    """A step before guide ids, statuses and level filtering."""

    part: str | None
    kind: str
    text: str
    eyeball: bool
    lines: tuple[_Line, ...]
    strokes: tuple[Stroke, ...]


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


def _solid(primitive: Any, box: Box) -> tuple[np.ndarray, list[tuple[int, ...]], bool]:
    """Vertices, faces (index tuples) and "flat" flag of the scaffold of ``primitive`` drawn in
    ``box`` (the fitted box mapped to ``box`` per axis for frusta)."""
    kind, axis = primitive.type, primitive.axis
    if kind == "plane" and axis is not None:
        u, v = (a for a in range(3) if a != axis)
        mid = 0.5 * (box[0][axis] + box[1][axis])
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
    faces = [(0, 1, 3, 2), (4, 5, 7, 6), (0, 1, 5, 4), (2, 3, 7, 6), (0, 2, 6, 4), (1, 3, 7, 5)]
    return pts, faces, False


def _scaffold(part: str, primitive: Any, box: Box, camera: Camera, tol: float) -> tuple[Stroke, ...]:
    """The primitive's edges as strokes: ``scaffold`` when an adjacent face is front-facing,
    else ``scaffold_hidden`` (see the module docstring)."""
    pts, faces, flat = _solid(primitive, box)
    centre = pts.mean(axis=0)
    cam = np.asarray(camera.position, dtype=float)
    front: list[bool] = []
    for f in faces:
        poly = pts[list(f)]
        normal = np.zeros(3)
        for i in range(len(poly)):  # Newell's method
            a, b = poly[i], poly[(i + 1) % len(poly)]
            normal += np.cross(a, b)
        fc = poly.mean(axis=0)
        if np.dot(normal, fc - centre) < 0:
            normal = -normal
        front.append(bool(np.dot(normal, cam - fc) > 0) and float(np.linalg.norm(normal)) > 0)
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
    """The parent face an anchor's construction is drawn on (module docstring)."""
    if anchor.face_side is not None:
        return Face(pbox, anchor.face_normal, anchor.face_side)
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


def _carry_lines(con: Any, face: Face, child: Box, tol: float) -> list[_Line]:
    """Alignment lines, in the plane of the anchored end, from the construction's result line
    to the child's end face (module docstring)."""
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
        m = child[0][n] if c < child[0][n] else child[1][n]
        centre = 0.5 * (clo + chi)
        ostar = plo if abs(plo - centre) < abs(phi - centre) else phi
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


def _anchor_lines(anchor: Any, pbox: Box, cbox: Box, camera: Camera,
                  tol: float) -> tuple[Face, Any, list[_Line], list[_Line]]:
    """An anchor's construction face, its construction, its lines and the carrying lines."""
    face = _anchor_face(anchor, pbox, camera)
    con = construct(face, anchor.axis, anchor.ratio)
    own = [_Line(ln.role, ln.start, ln.end) for ln in con.lines]
    return face, con, own, _carry_lines(con, face, cbox, tol)


def _construct_sentence(words: _Words, anchor: Any, parent: str, face: Face, con: Any) -> str:
    entry = entry_for(anchor.ratio)
    axis, r = anchor.axis, anchor.ratio
    fname = words.face(face.normal, face.end)
    vp = words.vp(con.result.axis if con.result.axis is not None else 3 - axis - face.normal)
    name = entry.name
    if name in ("start", "end"):
        return _t("primitive.construct.align", edge=words.face(axis, "lo" if r < 0.5 else "hi"),
                  parent=parent, face=fname, vp=vp)
    near = words.face(axis, "lo" if r < 0.5 else "hi")
    if name == "half":
        return _t("primitive.construct.half", parent=parent, face=fname, vp=vp)
    if name in ("quarter", "three-quarters"):
        return _t("primitive.construct.quarter", parent=parent, face=fname, near=near, vp=vp)
    if name in ("third", "two-thirds"):
        return _t("primitive.construct.third", parent=parent, face=fname, near=near, vp=vp)
    key = "extend_one" if name.startswith("extend-1") else "extend_half"
    return _t(f"primitive.construct.{key}", parent=parent, face=fname, near=near,
              dim=words.dim(axis), vp=vp)


def _reuse_sentence(words: _Words, anchor: Any, parent: str, face: Face, step: int) -> str:
    entry = entry_for(anchor.ratio)
    what = _raw("primitive.reuse_what")
    key = entry.name if entry.name in what else "extend"
    return _t("primitive.construct.reuse", parent=parent, face=words.face(face.normal, face.end),
              step=step, what=what[key].format(
                  edge=words.face(anchor.axis, "lo" if anchor.ratio < 0.5 else "hi")))


def _construct_sentences(words: _Words, built: Sequence[tuple[Any, str, Face, Any]],
                         described: list[tuple[Vec3, Vec3, int, Any]], step: int,
                         tol: float) -> list[str]:
    """One sentence per distinct result line, pairs on one face said together: the two edges
    of an alignment, quarters (1/4 and 3/4), thirds (1/3 and 2/3).  A result line an earlier
    step described (``described``: its end points and step number, appended to here) is
    referred to ("Use the ... from step 4"); a result line already said in this step is not
    said again."""
    out: list[str] = []
    fresh: list[tuple[Any, str, Face, Any]] = []
    mine: list[tuple[Vec3, Vec3, Any]] = []
    for item in built:
        anchor, parent, face, con = item
        a, b = con.result.start, con.result.end
        old = [(n, it) for p, q, n, it in described if _same_segment(a, b, p, q, tol)]
        if old and old[0][0] < step:  # named as the step that said it
            n, (oa, op, of, _) = old[0]
            out.append(_reuse_sentence(words, oa, op, of, n))
        elif not any(_same_segment(a, b, p, q, tol) for p, q, _ in mine):
            mine.append((a, b, item))
            fresh.append(item)
    described.extend((p, q, step, it) for p, q, it in mine)
    reuse, out = out, []
    groups: dict[tuple, list[tuple[Any, str, Face, Any]]] = {}
    for item in fresh:
        anchor, parent, face, _ = item
        groups.setdefault((anchor.parent, face.normal, face.end, anchor.axis), []).append(item)
    out: list[str] = []
    for items in groups.values():
        names = {entry_for(a.ratio).name: (a, p, f, c) for a, p, f, c in items}
        pair = None
        for key, (x, y) in (("align_both", ("start", "end")), ("quarters", ("quarter", "three-quarters")),
                            ("thirds", ("third", "two-thirds"))):
            if x in names and y in names:
                pair = key, x, y
                break
        done: set[str] = set()
        if pair is not None:
            key, x, y = pair
            anchor, parent, face, con = names[x]
            out.append(_t(f"primitive.construct.{key}", parent=parent,
                          face=words.face(face.normal, face.end),
                          edge=words.face(anchor.axis, "lo"), edge2=words.face(anchor.axis, "hi"),
                          vp=words.vp(con.result.axis)))
            done = {x, y}
        for a, p, f, c in items:
            if entry_for(a.ratio).name not in done:
                out.append(_construct_sentence(words, a, p, f, c))
    return _unique(reuse) + out


def _position(words: _Words, anchor: Any, parent: str, about: bool) -> str:
    axis, r = anchor.axis, anchor.ratio
    side = words.side(axis, anchor.end)
    if anchor.face_normal == axis:
        return _t("primitive.position.flat", side=side, parent=parent)
    entry = entry_for(r)
    ab = _raw("about") if about else ""
    if entry.name in ("start", "end"):
        return _t("primitive.position.align", side=side, parent=parent,
                  pside=words.side(axis, "lo" if r < 0.5 else "hi"))
    if not entry.extrusion:
        return _t("primitive.position.inside", side=side, about=ab,
                  fraction=_raw("primitive.fractions")[entry.name], parent=parent,
                  lo=words.side(axis, "lo"), hi=words.side(axis, "hi"))
    amount = _raw("primitive.amounts")["one" if entry.name.startswith("extend-1") else "half"]
    return _t("primitive.position.extend", side=side, about=ab, amount=amount, parent=parent,
              dim=words.dim(axis), pside=words.side(axis, "lo" if r < 0 else "hi"))


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


#: Samples per part's own visible contours for the occlusion test of the contour order.
_OCCLUSION_SAMPLES = 160


def _hidden_counts(parts: Sequence[Part], camera: Camera, settings: SequenceSettings) -> np.ndarray:
    """``h[i, j]``: how many samples of part ``j``'s own visible contours (hidden by itself only)
    part ``i`` hides (the contours' exact occlusion test against ``i``'s triangles)."""
    n = len(parts)
    own = [trace_contours([p], camera, crease_deg=settings.crease_deg,
                          suggestive=settings.suggestive)[0] for p in parts]
    samples: list[np.ndarray] = []
    for cs in own:
        pts = [np.asarray(pl, dtype=float) for pl in cs.polylines3d if len(pl) >= 2]
        allp = np.vstack(pts) if pts else np.zeros((0, 3))
        if len(allp) > _OCCLUSION_SAMPLES:
            allp = allp[np.linspace(0, len(allp) - 1, _OCCLUSION_SAMPLES).round().astype(int)]
        samples.append(allp)
    proj = [camera.project(np.asarray(p.vertices, dtype=float)) for p in parts]
    h = np.zeros((n, n), dtype=int)
    for j in range(n):
        if not len(samples[j]):
            continue
        sj = camera.project(samples[j])
        for i in range(n):
            if i == j or not len(proj[i]):
                continue
            lo, hi = proj[i].min(axis=0), proj[i].max(axis=0)
            inside = np.all((sj >= lo) & (sj <= hi), axis=1)
            if not inside.any():
                continue
            # the contours' own exact occlusion test (no optional ray package needed)
            seen = visible_points(samples[j][inside], [parts[i]], camera)
            h[i, j] = int(np.count_nonzero(~seen))
    return h


def _front_to_back(parts: Sequence[Part], camera: Camera, settings: SequenceSettings) -> list[str]:
    """Contour order: a part that hides some of another's lines comes before it; among the
    parts nothing left hides, the nearest (box centre to the camera position), then the name;
    mutual hiding (a cycle) starts with the part the remaining ones hide least."""
    names = [p.name for p in parts]
    h = _hidden_counts(parts, camera, settings)
    cam = np.asarray(camera.position, dtype=float)
    dist = {}
    for p in parts:
        lo, hi = p.box
        dist[p.name] = float(np.linalg.norm((np.asarray(lo) + np.asarray(hi)) / 2 - cam))
    left = list(range(len(parts)))
    out: list[str] = []
    while left:
        blocked = {j: int(sum(h[i, j] for i in left if i != j)) for j in left}
        nxt = min(left, key=lambda j: (blocked[j], dist[names[j]], names[j]))
        out.append(names[nxt])
        left.remove(nxt)
    return out


# ----------------------------------------------------------------------------- the view context


@dataclass(eq=False)
class _Context:
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
    _basic: tuple[_Draft, ...] | None = None
    _ids: tuple[tuple[tuple[str, str], ...], ...] | None = None
    _canon: dict[str, tuple[Vec3, Vec3]] = field(default_factory=dict)
    _finals: dict[str, dict[str, tuple[Stroke, ...]]] = field(default_factory=dict)
    _box_steps: dict[str, int] = field(default_factory=dict)

    # -------------------------------------------------------------- order and visibility
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

    def kept(self, parts: dict[str, Part], anchoring: bool) -> set[str]:
        """Parts not left out: visible ones and (``anchoring``) their ancestors."""
        names = [p.name for p in self.plan.model.parts]
        finals = self.finals(parts)
        visible = {n for n in names if finals[n]}
        keep = set(visible)
        if anchoring:
            stack = list(visible)
            while stack:
                part = stack.pop()
                for pid in self.chosen[part].parents:
                    pp = self.by_id[pid].part
                    if pp not in keep:
                        keep.add(pp)
                        stack.append(pp)
        left_out = sorted(set(names) - keep)
        if left_out:
            log.info("left out (hidden, anchoring nothing visible): %s", ", ".join(left_out))
        return keep

    # -------------------------------------------------------------- drafts
    def primitive_draft(self, part: str, first: bool, step: int = 0,
                        described: list[tuple[Vec3, Vec3, int, Any]] | None = None,
                        drawn: Sequence[str] = ()) -> _Draft:
        cand = self.chosen[part]
        prim = self.plan.primitive(part)
        words = self.words
        strokes = _scaffold(part, prim, cand.box, self.camera, self.tol)
        shape = words.shape(prim.type)
        if first:
            return _Draft(part, "primitive", _t("primitive.first", part=part, shape=shape), False,
                          (), strokes)
        if not cand.anchors:  # free: say what it touches among the parts drawn so far
            near = [q for q in _touching(part, self.chosen, 100.0 * self.tol) if q in drawn]
            near.sort(key=lambda q: -part_size(self.chosen[q].box))
            text = (_t("primitive.root_near", part=part, shape=shape, other=near[0]) if near
                    else _t("primitive.root", part=part, shape=shape))
            return _Draft(part, "primitive", text, False, (), strokes)
        lines: list[_Line] = []
        built: list[tuple[Any, str, Face, Any]] = []
        flat_sentences: list[str] = []
        faces: dict[tuple[str, int, str], tuple[Face, list[_Line]]] = {}
        carried = False
        box_sentences: list[str] = []
        for anchor in cand.anchors:
            parent = self.by_id[anchor.parent]
            if anchor.face_normal == anchor.axis:
                flat_sentences.append(_t("primitive.flat", part=part, parent=parent.part,
                                         side=words.side(anchor.axis, anchor.end)))
                continue
            around = self.box_around(parent.part)
            if around:  # constructions on a tapered parent start from its (undrawn) box
                lines += around
                seen = (self._box_steps if described is not None else {}).setdefault(
                    parent.part, step)
                box_sentences.append(
                    _t("primitive.box_around", parent=parent.part) if seen == step
                    else _t("primitive.box_reuse", parent=parent.part, step=seen))
            face, con, own, carry = _anchor_lines(anchor, parent.box, cand.box, self.camera,
                                                  self.tol)
            lines += own
            if entry_for(anchor.ratio).needs_room:  # an edge extended needs no room on the face
                faces.setdefault((anchor.parent, face.normal, face.end), (face, []))[1].extend(own)
            built.append((anchor, parent.part, face, con))
            if carry:
                carried = True
                lines += carry
        eyeball = False
        for face, own in faces.values():
            k = len(_distinct(own, self.tol))
            if k and _too_small(self.camera, face.corners, k, self.settings.eyeball_mm2):
                eyeball = True
        by_eye = self.by_eye_sentence(cand)
        if eyeball:
            where = _join([_position(words, a, self.by_id[a.parent].part, True)
                           for a in cand.anchors])
            text = " ".join([_t("primitive.eyeball", part=part, where=where, shape=shape)]
                            + ([by_eye] if by_eye else []))
            return _Draft(part, "primitive", text, True, (), strokes)
        parts = _unique(box_sentences) + _unique(_construct_sentences(words, built, [] if described is None else described,
                                             step, self.tol)) + _unique(flat_sentences)
        if carried:
            parts.append(_t("primitive.carry", part=part))
        for anchor, ppart, face, _ in built:  # a mid-plane anchor: the part straddles a line
            if anchor.end == "mid":
                entry = entry_for(anchor.ratio)
                names = _raw("primitive.centred_on")
                line = names.get(entry.name, names["extend"]).format(
                    edge=words.face(anchor.axis, "lo" if anchor.ratio < 0.5 else "hi"))
                parts.append(_t("primitive.centred", part=part, line=line, parent=ppart,
                                face=words.face(face.normal, face.end),
                                lo=words.side(anchor.axis, "lo"),
                                hi=words.side(anchor.axis, "hi")))
        parts.append(_t("primitive.place", part=part, shape=shape))
        if by_eye:
            parts.append(by_eye)
        return _Draft(part, "primitive", " ".join(parts), False, tuple(lines), strokes)

    def box_around(self, part: str) -> list[_Line]:
        """For a part whose scaffold does not draw its selected box's faces (a frustum), the
        box edges the scaffold leaves out (role ``vanishing``); else nothing."""
        prim = self.plan.primitive(part)
        if prim.type != "frustum":
            return []
        box = self.chosen[part].box
        drawn = [(np.asarray(st.points3d[0]), np.asarray(st.points3d[-1]))
                 for st in _scaffold(part, prim, box, self.camera, self.tol)]
        pts = _box_corners(box)
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

    def by_eye_sentence(self, cand: Any) -> str:
        biggest = max(_extent(cand.box, a) for a in range(3))
        loose = [a for a in range(3)
                 if sum(1 for an in cand.anchors if an.axis == a) < 2
                 and _extent(cand.box, a) > 1e-9 * biggest]
        if not loose:
            return ""
        return _t("primitive.by_eye", dims=_join([self.words.dim(a) for a in loose]))

    def ellipse_draft(self, part: str, box: Box, basic: bool) -> _Draft:
        prim = self.plan.primitive(part)
        axis = prim.axis
        ends = [Face(box, axis, "lo"), Face(box, axis, "hi")]
        ends.sort(key=lambda f: (not _front_facing(f, self.camera), f.end))
        lines: list[_Line] = []
        strokes: list[Stroke] = []
        eyeball = basic
        for face in ends:
            fe = ellipse_on_face(face, self.camera)
            lines += [_Line(ln.role, ln.start, ln.end) for ln in fe.lines]
            pts = np.vstack([fe.points3d, fe.points3d[:1]])
            strokes.append(_stroke("ellipse", part, pts, self.camera))
            if _too_small(self.camera, face.corners, 4, self.settings.eyeball_mm2):
                eyeball = True
        u, v = ends[0].in_axes
        if basic:
            text = _t("basic.ellipse", part=part)
        elif eyeball:
            text = _t("ellipse.eyeball", part=part)
        else:
            text = _t("ellipse.guided", part=part, vp_u=self.words.vp(u), vp_v=self.words.vp(v))
        return _Draft(part, "ellipse", text, eyeball, () if eyeball else tuple(lines),
                      tuple(strokes))

    def contour_drafts(self, order: Sequence[str], parts: dict[str, Part]) -> list[_Draft]:
        """Contour steps, front to back (:func:`_front_to_back`); each part's lines are its
        lines in the finished drawing, so the steps add up to exactly the finished drawing."""
        finals = self.finals(parts)
        order = _front_to_back([parts[p] for p in order], self.camera, self.settings)
        out: list[_Draft] = []
        for part in order:
            if not finals[part]:
                continue
            key = "contour.first" if not out else "contour.next"
            out.append(_Draft(part, "contour", _t(key, part=part), False, (), finals[part]))
        return out

    def guided(self) -> tuple[_Draft, ...]:
        if self._guided is None:
            keep = self.kept(self.adjusted, anchoring=True)
            order = self.guided_order(keep)
            described: list[tuple[Vec3, Vec3, int, Any]] = []
            drafts = [self.primitive_draft(p, i == 0, i + 1, described, drawn=order[:i])
                      for i, p in enumerate(order)]
            drafts += [self.ellipse_draft(p, self.chosen[p].box, False) for p in order
                       if self.plan.primitive(p).type == "cylinder"
                       and self.plan.primitive(p).axis is not None]
            drafts += self.contour_drafts(order, self.adjusted)
            self._guided = tuple(drafts)
        return self._guided

    def basic(self) -> tuple[_Draft, ...]:
        if self._basic is None:
            keep = self.kept(self.originals, anchoring=False)

            order = self.basic_order(keep)
            drafts: list[_Draft] = []
            for i, p in enumerate(order):
                prim = self.plan.primitive(p)
                shape = self.words.shape(prim.type)
                text = _t("basic.first" if i == 0 else "basic.part", part=p, shape=shape)
                drafts.append(_Draft(p, "basic", text, True, (),
                                     _scaffold(p, prim, prim.box, self.camera, self.tol)))
            drafts += [self.ellipse_draft(p, self.plan.primitive(p).box, True) for p in order
                       if self.plan.primitive(p).type == "cylinder"
                       and self.plan.primitive(p).axis is not None]
            drafts += self.contour_drafts(order, self.originals)
            self._basic = tuple(drafts)
        return self._basic

    # -------------------------------------------------------------- guides
    def guide_ids(self) -> tuple[tuple[tuple[str, str], ...], ...]:
        """Per guided draft, its lines as ``(guide id, role)``, merged within the step."""
        if self._ids is None:
            reg: list[tuple[np.ndarray, np.ndarray]] = []
            out = []
            for d in self.guided():
                step: dict[str, str] = {}
                for ln in d.lines:
                    a, b = np.asarray(ln.start), np.asarray(ln.end)
                    gid = None
                    for i, (p, q) in enumerate(reg):
                        if _same_segment(a, b, p, q, self.tol):
                            gid = f"g{i + 1}"
                            break
                    if gid is None:
                        reg.append((a, b))
                        gid = f"g{len(reg)}"
                        self._canon[gid] = (ln.start, ln.end)
                    if gid not in step or _ROLE_RANK[ln.role] > _ROLE_RANK[step[gid]]:
                        step[gid] = ln.role
                out.append(tuple(step.items()))
            self._ids = tuple(out)
        return self._ids

    def view_plan(self, name: str, level: str, paper: PaperSpec) -> ViewPlan:
        if level not in LEVEL_ROLES:
            raise ValueError(f"level must be one of {', '.join(LEVEL_ROLES)}, got {level!r}")
        if level == "basic":
            drafts = self.basic()
            shown: list[list[tuple[str, str]]] = [[] for _ in drafts]
        else:
            drafts = self.guided()
            roles = LEVEL_ROLES[level]
            shown = [[(g, r) for g, r in ids if r in roles] for ids in self.guide_ids()]
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
        steps = []
        for i, (d, gs) in enumerate(zip(drafts, shown)):
            guides = tuple(
                Guide(gid, "new" if first[gid] == i else "reused", self._canon[gid][0],
                      self._canon[gid][1], mm[gid][0], mm[gid][1], role)
                for gid, role in gs)
            alive = tuple(g for g in ordered if first[g] <= i <= last[g])
            steps.append(Step(i + 1, d.part, d.kind, d.text, d.eyeball, guides, d.strokes, alive))
        return ViewPlan(name, level, (float(paper.width_mm), float(paper.height_mm)), self.camera,
                        self.vps, tuple(steps))


def _distinct(lines: Sequence[_Line], tol: float) -> list[_Line]:
    out: list[_Line] = []
    for ln in lines:
        if not any(_same_segment(ln.start, ln.end, o.start, o.end, tol) for o in out):
            out.append(ln)
    return out


def _context(plan: Any, view: ViewSpec, paper: PaperSpec, settings: SequenceSettings) -> _Context:
    adjusted = _adjusted_parts(plan)
    tol = _tolerance(plan)
    camera = _fit_camera(plan, view, paper, adjusted, tol)
    vps = vanishing_points(camera)
    chosen = plan.chosen()
    corners = np.vstack([_box_corners(c.box) for c in chosen.values()])
    bounds = (_vec(corners.min(axis=0)), _vec(corners.max(axis=0)))
    ctx = _Context(plan=plan, camera=camera, settings=settings, vps=vps,
                   words=_Words(camera, vps, bounds), tol=tol,
                   by_id={c.id: c for c in plan.candidates}, chosen=chosen, adjusted=adjusted,
                   originals={p.name: p for p in plan.model.parts})
    return ctx


# ----------------------------------------------------------------------------- public API


def sequence_views(plan: Any, view: ViewSpec, levels: Sequence[str], paper: PaperSpec,
                   settings: SequenceSettings) -> tuple[ViewPlan, ...]:
    """The :class:`ViewPlan` of ``view`` at each of ``levels`` (one camera, shared work).

    Raises:
        ValueError: an unknown level.
        SelectionError: the selected candidates' anchoring graph has a cycle.
        ConfigError: the view cannot see the model.
    """
    ctx = _context(plan, view, paper, settings)
    return tuple(ctx.view_plan(view.name, level, paper) for level in levels)


def sequence_view(plan: Any, view: ViewSpec, level: str, paper: PaperSpec,
                  settings: SequenceSettings) -> ViewPlan:
    """The steps a person follows for ``view`` at ``level`` (module docstring).

    Args:
        plan: the solved model-level plan (stages 1-5).
        view: the viewpoint.
        level: ``novice``, ``apprentice``, ``master`` or ``basic``.
        paper: the sheet (its margins frame the drawing).
        settings: eyeball threshold (mm²) and contour settings.

    Returns:
        The view plan: camera (:func:`view_camera`), vanishing points and ordered steps.
    """
    return sequence_views(plan, view, (level,), paper, settings)[0]


def final_strokes(plan: Any, camera: Camera, settings: SequenceSettings, *,
                  level: str | None = None) -> tuple[Stroke, ...]:
    """The finished drawing: every part's contours hidden by all parts (kind ``contour``).

    Args:
        plan: the solved plan.
        camera: the view's camera.
        settings: crease angle and suggestive contours.
        level: ``basic`` draws the unadjusted meshes (the control tutorial); any other value
            (or ``None``) the adjusted ones.
    """
    parts = (list(plan.model.parts) if level == "basic"
             else list(_adjusted_parts(plan).values()))
    sets = final_contours(parts, camera, crease_deg=settings.crease_deg,
                          suggestive=settings.suggestive)
    return tuple(s for cs in sets for s in _contour_strokes(cs, camera))


def steps_text(view_plan: ViewPlan) -> str:
    """One line per step: ``12. [primitive] lens: <sentence>  (3 new guides, 1 reused)``."""
    lines = []
    for step in view_plan.steps:
        new = sum(1 for g in step.guides if g.status == "new")
        counts = _t("text.counts", new=new, reused=len(step.guides) - new)
        kind = step.kind + (_raw("text.eyeball") if step.eyeball else "")
        lines.append(_t("text.line", index=step.index, kind=kind,
                        part=step.part if step.part is not None else _raw("text.no_part"),
                        text=step.text, counts=counts))
    return "\n".join(lines)
