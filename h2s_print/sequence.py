"""Stage 6, *sequence*: a solved :class:`~h2s_print.plan.Plan` -> the steps of one view and level.

DESIGN.md §2.6 and paper §5.  Public verbs:

* :func:`view_camera` -- the one camera of a view, shared by all its levels;
* :func:`sequence_view` (and :func:`sequence_views` for several levels at once) -- the
  :class:`~h2s_print.types.ViewPlan` of a view and level;
* :func:`final_strokes` -- the finished drawing (every part's contours hidden by all parts);
* :func:`sequence_workbooks` -- :func:`sequence_views` with each level's finished drawing, from
  the contours the steps were made of (what the pipeline calls);
* :func:`steps_text` -- a readable dump, one line per step.

What a tutorial contains, in order
----------------------------------
1. **Primitive steps** (kind ``primitive``), one per part, in *drawing order*, coarse to fine
   (paper §3 (ii); decisions below): the start part first, then a topological order of the
   anchoring graph of the selected candidates (parents first), bigger before smaller wherever
   the anchoring allows, nearest first among parts of similar size.  Each
   step's guides are built in 3D from its anchors: the ratio's construction
   (:func:`h2s_print.constructions.construct`) on the
   parent's *selected* box face named by the anchor, or its twin across the box when the view
   shows the named face from behind (issue 12: guides only where they can be drawn); when the
   anchor leaves the side open (``face_side is None``), or both are seen from behind, the view
   picks, among the parent's faces parallel to the anchored axis, the front-facing one with
   the largest projected area.  Alignment lines (role
   ``vanishing``, :func:`h2s_print.constructions.align`) then carry the resulting line across,
   in the plane of the anchored end, to the child's end face: along the line itself when the
   child touches the face's plane, otherwise along the face normal from the result line's end
   nearest the child (and, if needed, across to the child).  An anchor on a parent that is
   flat along the anchored axis (``face_normal == axis``) needs no construction: the text says
   "in the plane of ..." and no guide is drawn.  A frustum parent's box faces are not drawn
   (its scaffold is the tapered solid), so a construction on it first draws the box around it
   (the box edges its scaffold leaves out, role ``vanishing``, "Draw the box around ...").
   The text is a headline and one sub-step per ruler operation
   (:func:`h2s_print.instructions.construction_specs`), naming lettered points; a result line
   an earlier step drew is cited with that step ("Use KL and MN from step 2.").  A step over
   :data:`MAX_STEP_WORDS` words moves its constructions into steps of kind ``guides`` before
   it (:meth:`_Context.pack`).  Identical parts (:meth:`_Context.congruent`) are one step: the
   first constructed, the copies "the same box" in its last sub-step.
2. **Ellipse steps** (kind ``ellipse``) for cylinders, in drawing order: both end faces of the
   selected box (front-facing first), each with its diagonals (role ``construction``), the two
   lines through the centre toward the vanishing points (role ``guide``) and the exact
   projection of the inscribed circle (:func:`h2s_print.constructions.ellipse_on_face`).
   A round frustum (a bowl, ``detail["round"]``) gets them on its two end rectangles, each
   constructed in its own rectangle (:meth:`_Context.ellipse_drafts`); a rectangular one none.
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
* **Sizes to compare** (read-through of 2026-11-24).  A size left to the eye is compared with
  a drawn part where the two make an easy ratio (:data:`SIZE_RATIOS`, within
  :data:`SIZE_TOLERANCE`): "Make its width about three quarters of the base's."
  (:meth:`_Context.size_ratios`).  The reference is a part the part hangs off, then one it
  touches; for a part placed by eye, one it touches, then the biggest drawn.  At most
  :data:`SIZE_SENTENCES` a step, and only while the step stays within
  :data:`MAX_STEP_WORDS`: they never split a step (:meth:`_Context.sized`).
* **Left out** (paper §5 (iii)).  A part is *hidden* when :func:`~h2s_print.contours.final_contours`
  (all parts hide all parts) leaves it no polyline; a hidden part is left out unless a kept
  part's construction is drawn from it (:meth:`_Context.guided_parts`): the first part of a
  group of identical parts is constructed from its parents, a copy only when its sentence
  places it by them, so the train's far wheels, hidden, are no longer drawn to place a near
  wheel that is drawn as a copy anyway.  Each hidden part kept is logged with the parts it
  anchors ("kept though hidden: ..."); the control tutorial keeps the visible parts only.
* **Levels.**  ``novice`` sees every line (roles ``construction``, ``guide``, ``vanishing``),
  ``apprentice`` the resulting lines and the alignment lines that carry them (``guide``,
  ``vanishing``), ``master`` none.  Novice and apprentice have the same steps and texts (the
  lettered sub-steps say what to construct); a master has the same steps but the guides
  steps (kind ``guides``), and reads each step's headline and its ratio words.  ``basic`` is the paper's control
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
* **Text.**  Every sentence comes from ``templates/steps.yaml``: a headline, numbered
  sub-steps (novice, apprentice), or the headline and the ratio words (master); points are
  lettered over the whole tutorial at once (:func:`h2s_print.instructions.letter_steps`), a
  point keeping its letter while later steps name it; parts are called by
  :func:`h2s_print.names.display_names`.  Outlines come two parts a step; an ellipse too small
  to construct is sketched in its part's outlines step.  Vanishing points are named by
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
from dataclasses import dataclass, field, replace
from typing import Any, Callable, Iterable, Mapping, Sequence

import numpy as np

from . import templates
from .config import PaperSpec, SequenceSettings, ViewSpec
from .candidates import Anchor, relation_holds
from .constructions import Face, align, construct, ellipse_on_face, equal_spacing
from .contours import adjust_part, final_contours, own_contours
from .errors import SelectionError
from .names import PartName, display_names, natural_key, stem
from .occlude import (Solid, box_solid, cylinder_solid, hidden, outward_normals, polyhedron,
                      runs)
from .instructions import (Many, Pts, Spec, construction_specs, letter_steps, line_runs,
                           points_key, spec, unique_specs)
from .order import drawing_order, part_size, start_part
from .project import FirstBoxLines, first_box_lines, make_camera, vanishing_points, vp_side
from .ratios import entry_for
from .types import Box, Camera, Guide, Label, Part, Step, Stroke, VanishingPoint, Vec3, ViewPlan

log = logging.getLogger(__name__)

#: A step's text (headline and numbered sub-steps) longer than this many words is split: its
#: constructions go to steps of their own (kind ``guides``) before the part's step.
MAX_STEP_WORDS = 70
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


def _easy_ratio(ratio: float) -> str | None:
    """The name of the :data:`SIZE_RATIOS` entry ``ratio`` lies within
    :data:`SIZE_TOLERANCE` of (the nearest), or None."""
    value, name = min(SIZE_RATIOS, key=lambda vn: abs(ratio / vn[0] - 1.0))
    return name if abs(ratio / value - 1.0) <= SIZE_TOLERANCE else None
#: Sub-steps that only point at lines already drawn (:meth:`_Context.uncited`).
_CITES = ("reuse", "reuse_for", "edge", "edge_two")
#: Two parts are the same shape when their boxes' extents and mesh areas agree within this
#: fraction (and their primitive types and triangle counts are equal): drawn as one step.
REPEAT_TOL = 0.02
#: A copy's position is said in ratio words up to this many words; longer, it is placed as the
#: picture shows it (the words would outweigh the drawing).
REPEAT_WHERE_WORDS = 16
#: Identical parts form an equally spaced row (:meth:`_Context.spaced_rows`) when their steps
#: along the row agree within this fraction of the step, and their other intervals within this
#: fraction of a part's largest extent.
SPACING_TOL = 0.005
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
    for k in ("part", "parent", "other"):  # names are identifiers: "shutter_button" -> "shutter button"
        if isinstance(fields.get(k), str):
            fields[k] = fields[k].replace("_", " ")
            fields.setdefault(f"the_{k}", _the(fields[k]))
    return templates.text("steps", key, **fields)


_the = templates.the


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
    """True when segment ``a-b`` is segment ``p-q`` up to endpoint order, within ``tol``
    (per coordinate; plain floats: called some 10 000 times a view)."""
    def near(x: Any, y: Any) -> bool:
        return (abs(float(x[0]) - float(y[0])) <= tol and abs(float(x[1]) - float(y[1])) <= tol
                and abs(float(x[2]) - float(y[2])) <= tol)

    return (near(a, p) and near(b, q)) or (near(a, q) and near(b, p))


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
                self.vps[vp.axis] = (_t("vp.vertical") if vp.axis == 2
                                     else _t("vp.infinite", edges=edges[vp.axis]))
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
    eyeball: bool
    lines: tuple[_Line, ...]
    strokes: tuple[Stroke, ...]
    headline: str
    specs: tuple[Spec, ...] = ()  # sub-steps before letters (:mod:`h2s_print.instructions`)
    summary: str = ""
    substeps: tuple[str, ...] = ()  # the sub-steps with letters (:meth:`_Context.letter`)
    labels: tuple[tuple[str, Vec3], ...] = ()
    group: tuple[str, ...] = ()  # identical parts drawn in this step (their first is ``part``)


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


def _first_lines(strokes: Sequence[Stroke], camera: Camera) -> FirstBoxLines | None:
    """What the sheet prints of the box of the first step's ``strokes``
    (:func:`h2s_print.project.first_box_lines`; the sheet reads the same)."""
    return first_box_lines(camera, [p for s in strokes for p in s.points3d])


def _first_specs(lines: FirstBoxLines | None) -> list[Spec]:
    """The first box's sub-steps: its footprint on the sheet, and its nearest upright edge
    (printed on the sheet too) when it has a height, then its edges and the paper corners."""
    tall = lines is not None and lines.height is not None
    return [spec("first_footprint"), *([spec("first_height")] if tall else []),
            spec("first_edges"), spec("first_corners")]


#: Guide ids of the sheet's printed lines on the first step (:func:`_sheet_guides`).
SHEET_GUIDE = "sheet"


def _sheet_guides(lines: FirstBoxLines | None, camera: Camera) -> tuple[Guide, ...]:
    """The first step's guides that the calibrated sheet prints (role ``sheet``): the first
    box's footprint, edge by edge, and its nearest upright edge.  The first box is drawn on
    them, not by eye; they are new in that step (status ``new``) and shown only there (the
    box's own edges cover them after).  Novice and apprentice only: a master sees no guides
    (DESIGN.md §2.6)."""
    if lines is None:
        return ()
    foot = lines.footprint
    segs = [(foot[k], foot[(k + 1) % 4]) for k in range(4)]
    if lines.height is not None:
        segs.append(lines.height)
    out = []
    for k, (a, b) in enumerate(segs, start=1):
        mm = camera.project(np.array([a, b], dtype=float))
        out.append(Guide(f"{SHEET_GUIDE}{k}", "new", a, b, (float(mm[0, 0]), float(mm[0, 1])),
                         (float(mm[1, 0]), float(mm[1, 1])), "sheet"))
    return tuple(out)


def _citations(groups: Sequence[Sequence[_Unit]], step: int,
               side_of: Callable[[Any], str] | None = None) -> list[Spec]:
    """"Use KL from step 2 for its back.": every line the units of ``groups`` (the guides
    steps numbered from ``step``) draw, cited with the step that drew it (an earlier one for a
    line reused) and, with ``side_of`` (an anchor's side of the part, "back", "middle (front
    to back)"), what the lines place (a read-through: "Use MP from step 8" did not say MP is
    the flash's back, and a reader who had just centred the lens on PQ centred the flash)."""
    cited: dict[int, list[Pts]] = {}
    sides: dict[int, list[str]] = {}
    carried: list[int] = []
    moved = _carried(groups)
    for k, g in enumerate(groups):
        for u in g:
            for i, r in enumerate(u.results):
                if tuple(r) not in moved:
                    n = u.origin.get(i, step + k)
                    cited.setdefault(n, []).append(Pts(r))
                    if side_of is not None:
                        sides.setdefault(n, []).extend(side_of(a) for a in u.anchors)
            if any(x.key in _CARRIES for x in u.specs):
                carried.append(step + k)
    out = []
    for n, lines in sorted(cited.items()):
        said = list(dict.fromkeys(sides.get(n, ())))
        out.append(spec("reuse_for", line=Many(tuple(lines)), step=n, sides=_join(said))
                   if said else spec("reuse", line=Many(tuple(lines)), step=n))
    return out + [spec("reuse_carried", step=n) for n in carried]


def _carried(groups: Sequence[Sequence[_Unit]]) -> set[tuple]:
    """The lines (end points, both ways round) that the units of ``groups`` carry to the
    part.  Such a line is cited as carried ("Use the lines carried in step 9"), not also as
    itself ("Use FG from step 2"): the part sits on the carried copy, which the step names
    (:func:`_citations`, and the placing step's own citations)."""
    out: set[tuple] = set()
    for g in groups:
        for u in g:
            for x in u.specs:
                if x.key in _CARRIES:
                    for name, v in x.fields:
                        if name in ("lines", "lines2"):
                            for run in line_runs(v):
                                out.update((tuple(run.points), tuple(run.points)[::-1]))
    return out


#: Sub-steps that carry lines to the part (the carry unit's).
_CARRIES = ("carry", "carry_two", "carry_turn", "extend_to")


def _touch(a: "_Unit", b: "_Unit", tol: float) -> bool:
    """Do two units of construction share a point (a line's end, a result's end)?  Then one
    may use what the other draws, and their order stays."""
    def points(u: _Unit) -> np.ndarray:
        pts = [p for ln in u.lines for p in (ln.start, ln.end)] + [p for r in u.results for p in r]
        return np.asarray(pts, dtype=float).reshape(-1, 3)

    pa, pb = points(a), points(b)
    return bool(len(pa) and len(pb)
                and (np.abs(pa[:, None, :] - pb[None, :, :]).max(axis=2) <= tol).any())


@dataclass
class _Unit:
    """The constructions of one primitive step on one parent face: sub-steps, lines, results."""

    parent: str
    specs: list[Spec] = field(default_factory=list)
    lines: list[_Line] = field(default_factory=list)
    results: list[tuple[Vec3, Vec3]] = field(default_factory=list)
    room: bool = False  # a construction that needs room on the face (not only edges)
    anchors: list[Any] = field(default_factory=list)
    origin: dict[int, int] = field(default_factory=dict)  # result index -> step that drew it


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


def _on_face(anchor: Any, pbox: Box, cbox: Box, tol: float) -> bool:
    """An end aligned with a parent's face (ratio 0 or 1) whose face overlaps that face's
    rectangle (an area, not an edge): the face already drawn is the guide ("Its back lies on
    the body's front face"), no line needs carrying."""
    if anchor.end == "mid" or entry_for(anchor.ratio).name not in ("start", "end"):
        return False
    return all(cbox[0][b] < pbox[1][b] - tol and pbox[0][b] < cbox[1][b] - tol
               for b in range(3) if b != anchor.axis)


def _ratio_words(words: _Words, anchor: Any, parent: str) -> str:
    """Where one anchor puts the part, in ratio words (a master's text): "its left side at a
    quarter of the body's width"."""
    axis, r = anchor.axis, anchor.ratio
    side = words.side(axis, anchor.end)
    if anchor.face_normal == axis:
        return _t("ratio_words.flat", side=side, parent=parent)
    entry = entry_for(r)
    if entry.name in ("start", "end"):
        return _t("ratio_words.align", side=side, parent=parent,
                  pside=words.side(axis, "lo" if r < 0.5 else "hi"))
    if not entry.extrusion:
        return _t("ratio_words.inside", side=side, parent=parent, dim=words.dim(axis),
                  fraction=_raw("primitive.fractions")[entry.name])
    amount = _raw("primitive.amounts")["one" if entry.name.startswith("extend-1") else "half"]
    return _t("ratio_words.extend", side=side, amount=amount, parent=parent,
              dim=words.dim(axis), pside=words.side(axis, "lo" if r < 0 else "hi"))


def _merged_outlines(prev: _Draft, d: _Draft, say: Any) -> _Draft:
    """Two outline drafts as one step: small ellipses first (one sentence for all the parts'
    ellipses sketched by eye), then one tracing sub-step; named after all its parts."""
    members = prev.group + d.group
    both = list(prev.specs) + list(d.specs)
    small = [x for x in both if x.key in ("ellipse_by_eye_part", "ellipse_by_eye_parts")]
    if len(small) > 1:
        names = [n for x in small for n in (
            [dict(x.fields)["part"]] if x.key == "ellipse_by_eye_part"
            else list(dict(x.fields)["parts"]))]
        one = spec("ellipse_by_eye_parts", parts=tuple(names),
                   the_parents=_join([_the(n) for n in names]))
        both = [one] + [x for x in both if x not in small]
    both = ([x for x in both if not x.key.startswith("contour")]
            + [x for x in both if x.key.startswith("contour")][:1])
    return replace(prev, strokes=prev.strokes + d.strokes, lines=prev.lines + d.lines,
                   specs=tuple(unique_specs(both)), eyeball=prev.eyeball or d.eyeball,
                   group=members,
                   headline=_t("headline.contour_many", Parts=_cap(_join([say(q)
                                                                        for q in members]))))


#: The lines a sub-step draws, by template key (fields holding two points each).
_DRAWS: dict[str, tuple[str, ...]] = {
    "diagonals": ("first", "second"), "half_diagonals": ("first", "second"),
    "through": ("line",), "cross": ("line",), "from": ("line",),
    "ellipse_diagonals": ("first", "second"), "ellipse_diagonals_plate": ("first", "second"),
}


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


def _draws_known(s: Spec, known: Sequence[tuple[Vec3, Vec3]], tol: float) -> bool:
    """Does sub-step ``s`` only draw a line already on the sheet (one of ``known``)?"""
    if s.key not in ("cross", "through", "from", "edge"):
        return False
    line = dict(s.fields).get("line")
    if not isinstance(line, Pts) or len(line.points) != 2:
        return False
    return any(_same_segment(line.points[0], line.points[1], p, q, tol) for p, q in known)


def _substep(key: str, fields: dict[str, Any]) -> str:
    """A sub-step's sentence from ``templates/steps.yaml`` (section ``substep``)."""
    return _t(f"substep.{key}", **fields)


def _substep_of(s: Spec) -> str:
    """A sub-step that names no point, formatted (a master's summary reuses it)."""
    return _substep(s.key, dict(s.fields))


def _plural(key: str) -> str:
    """The template key of a sub-step said for two twins at once (``edge`` -> ``edge_two``)."""
    return f"{key}_two" if isinstance(_raw("substep").get(f"{key}_two"), str) else key


def _mesh_area(part: Part) -> float:
    v = np.asarray(part.vertices, dtype=float)
    f = np.asarray(part.faces, dtype=np.int64)
    if not len(f):
        return 0.0
    return float(0.5 * np.linalg.norm(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]),
                                      axis=1).sum())


def _cap(text: str) -> str:
    """``text`` with its first letter a capital (a headline starts with the part's name)."""
    return text[:1].upper() + text[1:]


def _carry_key(item: tuple[tuple[int, int | None], Any]) -> tuple[int, int]:
    """Sort key of a carry group ``((axis, turn or None), runs)``."""
    (axis, turn), _ = item
    return (axis, -1 if turn is None else turn)


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


#: Samples per part's own visible contours for the occlusion test of the contour order.
_OCCLUSION_SAMPLES = 160


def _hidden_counts(parts: Sequence[Part], camera: Camera, settings: SequenceSettings) -> np.ndarray:
    """``h[i, j]``: how many samples of part ``j``'s own visible contours (hidden by itself only)
    part ``i`` hides (the contours' exact occlusion test against ``i``'s triangles)."""
    n = len(parts)
    own, tests = own_contours(parts, camera, crease_deg=settings.crease_deg,
                              suggestive=settings.suggestive)
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
            # the contours' own exact occlusion test, on the engine that traced part i
            seen = tests[i](samples[j][inside])
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
    _solids: dict[str, list[tuple[str, Solid]]] = field(default_factory=dict)
    _edges: dict[str, list[tuple[np.ndarray, np.ndarray]]] = field(default_factory=dict)
    _scaffold_ends: dict[str, list[tuple[np.ndarray, np.ndarray]]] = field(default_factory=dict)
    _parts: tuple[list[list[str]], set[str]] | None = None
    _drawn: list[tuple[Vec3, Vec3, int]] = field(default_factory=list)  # guide lines, by step
    names: dict[str, PartName] = field(default_factory=dict)

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

    def step_words(self, specs: Sequence[Spec], headline: str) -> int:
        """Words of a step's text with ``headline`` and these sub-steps, lettered and
        numbered as the page says them."""
        (subs, _), = letter_steps([self.lettered(specs)], self.tol, _substep, _join)
        text = " ".join([headline] + [_t("step_text.number", n=k + 1, text=x)
                                      for k, x in enumerate(subs)])
        return len(text.split())

    def sized(self, headline: str, build: Callable[[list[tuple[Spec, list[int]]]], list[Spec]],
              sizes: list[tuple[Spec, list[int]]]) -> list[Spec]:
        """``build(sizes[:n])``, the sub-steps with the most size sentences (biggest axes
        first) that keep the step within :data:`MAX_STEP_WORDS`: sizes help the eye, but
        never make a step longer than the limit or split it (they are not counted when
        constructions are packed into steps)."""
        for n in range(len(sizes), 0, -1):
            specs = build(sizes[:n])
            if self.step_words(specs, headline) <= MAX_STEP_WORDS:
                return specs
        return build([])

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
        visible = self.visible(self.adjusted)
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
            log.info("left out (hidden, anchoring nothing visible): %s", ", ".join(left_out))
        for part in sorted(keep - visible):
            users = sorted(q for q in keep if part in uses.get(q, ()))
            log.info("kept though hidden: %s (anchors %s)", part, ", ".join(users) or "nothing")
        self._parts = (groups, keep)
        return self._parts

    def uses(self, groups: Sequence[Sequence[str]], keep: set[str]) -> dict[str, set[str]]:
        """Per part, the parts its construction is drawn from (:meth:`guided_parts`)."""
        uses: dict[str, set[str]] = {}
        for group in groups:
            uses[group[0]] = self.parents_of(group[0])
            placed = self.copy_places(group[1:], keep)
            for q in group[1:]:
                uses[q] = self.parents_of(q) if placed.get(q) else set()
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

    # -------------------------------------------------------------- drafts
    def say(self, part: str) -> str:
        """What the texts call ``part`` (:func:`h2s_print.names.display_names`)."""
        return self.names[part].label

    def part_labels(self, part: str, box: Box, numbered: bool = False
                    ) -> tuple[tuple[str, Vec3], ...]:
        """The short name drawn next to a part whose own name is not readable, or (with
        ``numbered``) whose step draws another part named alike but for its number: the
        train's "wheel 1, wheel 3, wheel 5 and wheel 7" left a reader asking which was which
        (else none)."""
        if self.names[part].readable and not numbered:
            return ()
        return ((self.names[part].label, _vec(np.mean(np.asarray(box, dtype=float), axis=0))),)

    def lettered(self, specs: Sequence[Spec]) -> tuple[Spec, ...]:
        """A step's sub-steps, each said once, twins together
        (:func:`h2s_print.instructions.unique_specs`), lines from earlier steps first (so no
        point is used before a sub-step names it); lettered later (:meth:`letter`)."""
        ordered = sorted(specs, key=lambda x: x.key not in ("reuse", "box_reuse"))
        return tuple(self.uncited(unique_specs(ordered, _plural)))

    def uncited(self, specs: Sequence[Spec]) -> list[Spec]:
        """``specs`` without citing a line that a later sub-step of the step names: "Use KL
        from step 2" or "Use the edge KL" before "Carry KL to the grip" only repeated KL,
        which the picture shows as used again (issue 11: one sub-step per construction).  A
        citation keeps the lines no later sub-step names."""
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
                    s = spec(key, s.same, s.pair, **f)
            out.append(s)
        return out

    def letter(self, drafts: Sequence[_Draft]) -> list[_Draft]:
        """The drafts with their sub-steps formatted and their points lettered, the whole
        tutorial at once (:func:`h2s_print.instructions.letter_steps`)."""
        # a line is drawn from the first step that uses it to the last (the guides' lifetime):
        # its ends stay on the paper that long
        last: dict[tuple, tuple[int, Vec3, Vec3]] = {}  # by line: its last step, its ends
        for k, d in enumerate(drafts):
            for ln in d.lines:
                last[points_key((ln.start, ln.end), self.tol)] = (k, ln.start, ln.end)
        on_paper = [(p, k) for k, a, b in last.values() for p in (a, b)]
        done = letter_steps([d.specs for d in drafts], self.tol, _substep, _join, on_paper)
        return [replace(d, substeps=tuple(subs), labels=tuple(labels))
                for d, (subs, labels) in zip(drafts, done)]

    def primitive_drafts(self, part: str, first: bool, step: int = 0,
                         described: list[tuple[Vec3, Vec3, int]] | None = None,
                         drawn: Sequence[str] = (), repeat: Sequence[Spec] = ()
                         ) -> list[_Draft]:
        """The primitive step of ``part`` (step number ``step``), preceded by guides steps when
        its sub-steps would not fit :data:`MAX_STEP_WORDS` (module docstring, *Text*);
        ``repeat`` are the sub-steps drawing its copies (identical parts), said last."""
        cand = self.chosen[part]
        prim = self.plan.primitive(part)
        words = self.words
        strokes = _scaffold(part, prim, cand.box, self.camera, self.tol)
        shape = words.shape(prim.type)
        repeat = [*self.taper_specs(part), *repeat]  # said after the box, before any copies
        name = self.say(part)
        note = _raw("headline.cylinder_note") if _round(prim) else ""
        if first:
            subs = self.lettered([*_first_specs(_first_lines(strokes, self.camera)), *repeat])
            return [_Draft(part, "primitive", False, (), strokes,
                           _t("headline.first", Part=_cap(name), shape=shape) + note, subs)]
        if not cand.anchors:  # free: say what it touches among the parts drawn so far
            near = [q for q in _touching(part, self.chosen, 100.0 * self.tol) if q in drawn]
            near.sort(key=lambda q: -part_size(self.chosen[q].box))
            where = self.free_specs(self.free_positions(part, drawn))
            refs = near + sorted((q for q in drawn if q not in near),
                                 key=lambda q: (-part_size(self.chosen[q].box), q))
            head = _t("headline.free", Part=_cap(name), shape=shape) + note

            def free(sizes: list[tuple[Spec, list[int]]]) -> list[Spec]:
                # with sizes said, "compare their sizes" is said by them
                placing = (spec("free_near_sized" if sizes else "free_near",
                                other=self.say(near[0])) if near else spec("free"))
                return [placing, *where, *(x for x, _ in sizes), *repeat]

            subs = self.lettered(self.sized(head, free, self.size_specs(
                part, self.loose_axes(cand), refs)))
            return [_Draft(part, "primitive", False, (), strokes, head, subs)]
        built: list[tuple[Any, str, Face, Any, list[_Line], list[_Line]]] = []
        flat: list[Spec] = []
        on_faces: dict[str, list[tuple[str, str]]] = {}  # parent -> (side, face name)
        faces: dict[tuple[str, int, str], tuple[Face, list[_Line]]] = {}
        for anchor in cand.anchors:
            parent = self.by_id[anchor.parent]
            if anchor.face_normal == anchor.axis:
                flat.append(spec("flat", side=words.side(anchor.axis, anchor.end),
                                 parent=self.say(parent.part)))
                continue
            if _on_face(anchor, parent.box, cand.box, self.tol):  # the face itself is the guide
                on_faces.setdefault(parent.part, []).append(
                    (words.side(anchor.axis, anchor.end),
                     words.face(anchor.axis, "lo" if anchor.ratio < 0.5 else "hi")))
                continue
            face, con, own, carry = _anchor_lines(anchor, parent.box, cand.box, self.camera,
                                                  self.tol)
            if entry_for(anchor.ratio).needs_room:  # an edge extended needs no room on the face
                faces.setdefault((anchor.parent, face.normal, face.end), (face, []))[1].extend(own)
            built.append((anchor, parent.part, face, con, own, carry))
        for ppart, pairs in on_faces.items():  # said once per parent
            sides, names = zip(*pairs)
            flat.append(spec("on_face" if len(pairs) == 1 else "on_faces", sides=_join(sides),
                             parent=self.say(ppart), faces=_join(names)))
        eyeball = False
        for face, own in faces.values():
            k = len(_distinct(own, self.tol))
            if k and _too_small(self.camera, face.corners, k, self.settings.eyeball_mm2):
                eyeball = True
        loose = self.loose_axes(cand)
        # sizes judged by eye: compared with the parts it hangs off, then those it touches
        refs = _unique([self.by_id[a.parent].part for a in cand.anchors]
                       + [q for q in _touching(part, self.chosen, 100.0 * self.tol)
                          if q in drawn])
        sizes = self.size_specs(part, loose, refs)

        def by_eye(chosen: list[tuple[Spec, list[int]]]) -> tuple[list[Spec], str]:
            """The size sentences chosen, and the sizes left to the eye."""
            done = {a for _, group in chosen for a in group}
            return [x for x, _ in chosen], _join([words.dim(a) for a in loose if a not in done])
        parents = _join([_the(x) for x in _unique(self.say(self.by_id[a.parent].part)
                                                  for a in cand.anchors)])
        summary = _cap(_join([_ratio_words(words, a, self.say(self.by_id[a.parent].part))
                              for a in cand.anchors])) + "."
        if eyeball:
            specs = [spec("position", position=_position(words, a, self.say(self.by_id[a.parent].part),
                                                         True)) for a in cand.anchors]
            head = _t("headline.eyeball", Part=_cap(name), shape=shape) + note

            def eyeballed(chosen: list[tuple[Spec, list[int]]]) -> list[Spec]:
                said, dims = by_eye(chosen)
                return specs + said + ([spec("by_eye", dims=dims)] if dims else []) + list(repeat)

            subs = self.lettered(self.sized(head, eyeballed, sizes))
            return [_Draft(part, "primitive", True, (), strokes, head, subs, summary)]
        # Units of construction, one per parent face (lines shared on a face stay together).
        units: dict[tuple[str, int, str], _Unit] = {}
        earlier = [] if described is None else described
        boxed: set[str] = set()
        known: list[tuple[Vec3, Vec3]] = []  # lines reused from earlier steps
        carried: dict[tuple[int, int | None], list[Pts]] = {}  # by (first axis, turn)
        corners: dict[tuple[int, int | None], list[Pts]] = {}  # where those turn, in order
        carry_lines: list[_Line] = []
        for anchor, ppart, face, con, own, carry in built:
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
                n for p, q, n in self._drawn if n < step and _same_segment(a, b, p, q, self.tol))
            twice = any(_same_segment(a, b, p, q, self.tol)
                        for u in units.values() for p, q in u.results)
            if twice:  # the same line from another face of the parent: said once
                pass
            elif old and old[0] < step:
                unit.specs.append(spec("reuse", ("reuse", old[0], a, b), ("reuse", old[0]),
                                       line=Pts((a, b)), step=old[0]))
                known.append((a, b))
                unit.results.append((a, b))
                unit.origin[len(unit.results) - 1] = old[0]
            else:
                unit.specs += construction_specs(con, self.say(ppart),
                                                 words.face(face.normal, face.end), words.vp,
                                                 self.tol)
                unit.room = unit.room or entry_for(anchor.ratio).needs_room
                unit.results.append((a, b))
            unit.lines += own
            if carry:
                carry_lines += carry
                first, *rest = [_moving_axis(c) for c in carry]
                turn = next((x for x in rest if x != first), None)  # around a corner: then this
                runs = carried.setdefault((first, turn), [])
                if not any(_same_segment(a, b, r.points[0], r.points[1], self.tol) for r in runs):
                    runs.append(Pts((a, b)))
                    if turn is not None:  # where it turns, lettered on the picture
                        corners.setdefault((first, turn), []).append(Pts((carry[0].end,)))
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
        if len(carries) == 2 and carries[0][1] is None and carries[1][1] is None:
            (a0, _, r0), (a1, _, r1) = carries  # two directions: one sentence
            carrying = [spec("carry_two", lines=Many(tuple(r0)), part=name, vp=words.vp(a0),
                             lines2=Many(tuple(r1)), vp2=words.vp(a1))]
        else:
            carrying = [spec("carry", lines=Many(tuple(runs)), part=name, vp=words.vp(axis))
                        if turn is None else
                        spec("carry_turn", lines=Many(tuple(runs)), part=name,
                             vp=words.vp(axis), vp2=words.vp(turn),
                             turns=Many(tuple(corners[axis, turn])))
                        for axis, turn, runs in carries]
        if extended:
            carrying.append(spec("extend_to", lines=Many(tuple(extended)), part=name))
        carry_unit: _Unit | None = None
        if carrying:  # carrying lines needs no room: it stays with the part unless too long
            carry_unit = units[("carry",)] = _Unit(self.by_id[cand.anchors[0].parent].part,
                                                   carrying, carry_lines)
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
                placing.append(spec("centred", (), ("centred",), part=name, line=Pts(line)))
        # an axis with no anchor at all: say what it lines up with, as for a part by eye
        placing += self.free_specs(self.free_positions(part, drawn, cand.unguided_axes))
        # no line constructed (faces and planes of drawn parts only): no "these lines" to name
        there = "" if built else "_there"

        def closing_with(chosen: list[tuple[Spec, list[int]]]) -> list[Spec]:
            said, dims = by_eye(chosen)
            return (placing + said + [spec("place_by_eye" + there, shape=shape, dims=dims) if dims
                                      else spec("place" + there, shape=shape)] + list(repeat))

        closing = closing_with([])
        head = _t("headline.anchored", Part=_cap(name), shape=shape, the_parents=parents) + note
        def guides_head(group: list[_Unit]) -> str:
            gparents = _join([_the(x) for x in _unique(self.say(u.parent) for u in group)])
            return _t("headline.guides", part=name, the_parents=gparents)

        groups = self.pack(list(units.values()), closing, head, step, guides_head)
        drafts: list[_Draft] = []
        said: set = set()  # lines an earlier guides step of this part drew: not drawn again
        for k, group in enumerate(groups[:-1]):
            here = step + k
            subs = self.lettered([x for u in group for x in u.specs
                                  if not (x.same and x.same in said)])
            said.update(x.same for x in subs if x.same)
            self.record(group, here, described)
            gsummary = _t("substep.guides_for", words=_join(_unique(
                _ratio_words(words, a, self.say(self.by_id[a.parent].part))
                for u in group for a in u.anchors)))
            drafts.append(_Draft(part, "guides", False, tuple(ln for u in group for ln in u.lines),
                                 (), guides_head(group), subs,
                                 gsummary))
        last = groups[-1]
        here = step + len(groups) - 1
        before = [u for g in groups[:-1] for u in g]
        moved = _carried(groups[:-1])
        own = [x for u in last for x in u.specs if not (x.same and x.same in said)
               and not (x.key == "reuse" and tuple(dict(x.fields)["line"].points) in moved)]
        mine = _citations(groups[:-1], step, self.anchor_side) + own
        if self.step_words(mine + closing_with([]), head) > MAX_STEP_WORDS:
            mine = _citations(groups[:-1], step) + own  # what they place: only if it fits
        subs = self.lettered(self.sized(head, lambda chosen: mine + closing_with(chosen), sizes))
        self.record(last, here, described)
        # the box is drawn on the carried lines: carried in a guides step, they stay (the
        # read-through found them erased before the step that uses them)
        lines = ([_Line("guide", a, b) for u in before for a, b in u.results]
                 + [ln for u in before if u is carry_unit for ln in u.lines]
                 + [ln for u in last for ln in u.lines])
        drafts.append(_Draft(part, "primitive", False, tuple(lines), strokes, head, subs,
                             summary))
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
        scaffold edge of a part drawn before, on the sheet (:data:`ALONG_MM`; the
        read-through saw nothing new where an orange line lay on a grey edge)."""
        if s.key not in ("from", "through", "cross"):
            return s
        f = dict(s.fields)
        line = f.get("line")
        if not isinstance(line, Pts) or len(line.points) != 2:
            return s
        # on the sheet: an edge behind the line in space still lies under it on the paper
        a, b = np.asarray(self.camera.project(np.asarray(line.points, dtype=float)), dtype=float)
        for part in drawn:
            if part not in self._edges:
                prim = self.plan.primitive(part)
                self._edges[part] = [
                    (np.asarray(st.points_mm[0], dtype=float), np.asarray(st.points_mm[-1], dtype=float))
                    for st in _scaffold(part, prim, self.chosen[part].box, self.camera, self.tol)]
            if any(_mostly_on(a, b, p, q, ALONG_MM) for p, q in self._edges[part]):
                return spec(f"{s.key}_along", s.same, s.pair, part=self.say(part), **f)
        return s

    def drawn_before(self, s: Spec, step: int) -> Spec:
        """``s``, or "Use ... from step N" when an earlier step drew all its lines (the
        diagonals of a face another part's step already divided, say)."""
        if s.key not in _DRAWS or not self._drawn:
            return s
        f = dict(s.fields)
        lines = [f[k].points for k in _DRAWS[s.key] if isinstance(f.get(k), Pts)]
        steps = []
        for a, b in lines:
            at = [n for p, q, n in self._drawn if n < step and _same_segment(a, b, p, q, self.tol)]
            if not at:
                return s
            steps.append(at[0])
        return spec(f"{s.key}_reuse", s.same, s.pair, step=max(steps), **f)

    def anchor_side(self, anchor: Any) -> str:
        """The side of the part an anchor places ("back", "middle (front to back)")."""
        return self.words.side(anchor.axis, anchor.end)

    def pack(self, units: list["_Unit"], closing: list[Spec], head: str, step: int,
             guides_head: Callable[[list["_Unit"]], str]) -> list[list["_Unit"]]:
        """Units of construction grouped into steps of at most :data:`MAX_STEP_WORDS` words:
        the last group goes with ``closing`` (the placing sub-steps) under ``head``, the
        others are guides steps under ``guides_head(group)``; one unit alone may exceed the
        limit (it is not cut).  Lines an earlier group drew are not counted again (they are
        not said again)."""
        def fits(group: list[_Unit], extra: list[Spec], said: set) -> bool:
            specs = [x for u in group for x in u.specs if not (x.same and x.same in said)]
            return self.step_words(specs + extra, head if extra else guides_head(group)
                                   ) <= MAX_STEP_WORDS

        if not units or fits(units, closing, set()):
            return [units]
        reuse = _citations([units], step, self.anchor_side)  # as the placing step will cite
        # them (worst case)
        # Edges extended and guides reused need no room: they stay with the placing step.
        tail = [u for u in units if not u.room]
        rest = [u for u in units if u.room]

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
        while movable and not fits(tail, _citations(groups, step, self.anchor_side) + closing,
                                   said_by(groups)):
            u = movable.pop(0)
            tail.remove(u)
            rest.append(u)
            groups = grouped(rest)
        return groups + [tail]

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

    def scaffold_ends(self, part: str) -> list[tuple[np.ndarray, np.ndarray]]:
        """The 3D ends of ``part``'s scaffold strokes in its selected box (computed once)."""
        if part not in self._scaffold_ends:
            prim = self.plan.primitive(part)
            self._scaffold_ends[part] = [
                (np.asarray(st.points3d[0], dtype=float), np.asarray(st.points3d[-1], dtype=float))
                for st in _scaffold(part, prim, self.chosen[part].box, self.camera, self.tol)]
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

    def solids(self, basic: bool) -> list[tuple[str, Solid]]:
        """The drawn primitives as solids (:mod:`h2s_print.occlude`), by part: the guided
        tutorial's kept parts in their selected boxes, or (``basic``) the visible parts in
        their fitted ones."""
        key = "basic" if basic else "guided"
        if key not in self._solids:
            if basic:
                names = sorted(self.visible(self.originals))
            else:
                names = sorted(self.guided_parts()[1])
            out = []
            for name in names:
                prim = self.plan.primitive(name)
                box = prim.box if basic else self.chosen[name].box
                if prim.type == "cylinder" and prim.axis is not None:
                    out.append((name, cylinder_solid(box, prim.axis)))
                elif prim.type == "frustum":
                    pts, faces, _ = _solid(prim, box)
                    out.append((name, polyhedron(pts, faces)))
                else:  # a cuboid, a plane (its slab), a custom part: its box
                    out.append((name, box_solid(box)))
            self._solids[key] = out
        return self._solids[key]

    def ellipse_strokes(self, part: str, fe: Any, basic: bool) -> list[Stroke]:
        """The ellipse ``fe`` of ``part`` as strokes, ``ellipse`` where the drawn primitives
        leave it seen and ``ellipse_hidden`` where they hide it (:func:`occlude.hidden`; a
        round plate's ellipse lies inside its own slab, which does not count)."""
        flat = self.plan.primitive(part).type == "plane"
        solids = [sd for name, sd in self.solids(basic) if not (flat and name == part)]
        pts = np.vstack([fe.points3d, fe.points3d[:1]])
        mask = hidden(pts, self.camera.position, solids)
        return [_stroke("ellipse_hidden" if off else "ellipse", part, run, self.camera)
                for off, run in runs(pts, mask)]

    def ellipse_drafts(self, part: str, box: Box, basic: bool,
                       copies: Sequence[tuple[str, Box]] = ()) -> list[_Draft]:
        """The ellipse steps of a round part (and of its identical ``copies``).

        A round plate has one ellipse, a cylinder and a round frustum two, each its own step
        (one ellipse a page): the ellipse of the end face turned toward the camera (the *near*
        one) is constructed in that face (diagonals for its centre, lines through the centre
        toward the vanishing points, the ellipse through the four points where they meet the
        edges), its points lettered.  A cylinder's far end face, which the view shows from
        behind, is never constructed on: lines carried from the four points toward the axis'
        vanishing point meet its edges where its ellipse touches them.  A round frustum's
        (a bowl's) ends differ in size, so nothing carries: its far end rectangle, which its
        scaffold draws, gets the same construction as the near one (or, under the eyeball
        rule, its ellipse by eye).  Copies get the same lines and ellipses, said once.
        The construction is shown on the copy whose near face the picture shows largest; that
        face under the eyeball rule (``k = 4``), or ``basic``, makes one step "by eye" for both
        ellipses (it joins the part's outline step in a guided tutorial).
        """
        prim = self.plan.primitive(part)
        axis = prim.axis
        members = [(part, box), *copies]
        names = sorted((self.say(q) for q, _ in members), key=natural_key)
        who = _cap(_join(names))
        # per copy: its near ellipse and (a cylinder, a round frustum) its far one
        ends: list[tuple[str, Any, Any]] = []
        for q, b in members:
            if prim.type == "plane":  # a round plate: its ellipse in the rectangle drawn
                mid = 0.5 * (b[0][axis] + b[1][axis])
                lo, hi = list(b[0]), list(b[1])
                lo[axis] = hi[axis] = mid
                ends.append((q, ellipse_on_face(Face((tuple(lo), tuple(hi)), axis, "lo"),
                                                self.camera), None))
                continue
            faces = sorted(_end_faces(prim, b),
                           key=lambda f: (not _front_facing(f, self.camera), f.end))
            ends.append((q, ellipse_on_face(faces[0], self.camera),
                         ellipse_on_face(faces[1], self.camera)))
        one = not copies
        # the construction is shown on the copy whose near face the picture shows largest
        show = max(range(len(ends)), key=lambda k: (
            _polygon_area_mm2(self.camera, ends[k][1].face.corners), -k))
        ends.insert(0, ends.pop(show))
        near = [(q, fe) for q, fe, _ in ends]
        far = [(q, fe, be) for q, fe, be in ends if be is not None]
        if basic or _too_small(self.camera, near[0][1].face.corners, 4,
                               self.settings.eyeball_mm2):
            head = _t("headline.ellipse_eyeball" if one else "headline.ellipse_many_eyeball",
                      Part=_cap(self.say(part)), Parts=who)
            strokes = [st for q, fe in near for st in self.ellipse_strokes(q, fe, basic)]
            strokes += [st for q, _, be in far for st in self.ellipse_strokes(q, be, basic)]
            return [_Draft(part, "ellipse", True, (), tuple(strokes), head,
                           self.lettered([spec("ellipse_by_eye")]))]
        same = [spec("ellipse_copies")] if copies else []
        key = "ellipse_plate" if not far else "ellipse_end"
        strokes = tuple(st for q, e in near for st in self.ellipse_strokes(q, e, basic))
        out = [_Draft(part, "ellipse", False,
                      tuple(_Line(ln.role, ln.start, ln.end) for _, e in near for ln in e.lines),
                      strokes,
                      _t(f"headline.{key}" + ("" if one else "_many"),
                         Part=_cap(self.say(part)), Parts=who,
                         face=self.words.face(axis, near[0][1].face.end)),
                      self.lettered(self.ellipse_specs(near[0][0], near[0][1], bool(far),
                                                       strokes) + same))]
        if not far:
            return out
        head = _t("headline.ellipse_end" + ("" if one else "_many"), Part=_cap(self.say(part)),
                  Parts=who, face=self.words.face(axis, far[0][2].face.end))
        strokes = tuple(st for q, _, be in far for st in self.ellipse_strokes(q, be, basic))
        if prim.type == "frustum":  # its own construction on the far end rectangle
            be = far[0][2]
            if _too_small(self.camera, be.face.corners, 4, self.settings.eyeball_mm2):
                out.append(_Draft(part, "ellipse", True, (), strokes, head,
                                  self.lettered([spec("ellipse_by_eye_end")])))
            else:
                out.append(_Draft(
                    part, "ellipse", False,
                    tuple(_Line(ln.role, ln.start, ln.end) for _, _, e in far for ln in e.lines),
                    strokes, head,
                    self.lettered(self.ellipse_specs(far[0][0], be, True, strokes) + same)))
            return out
        fe, be = near[0][1], far[0][2]
        around = Many(tuple(Pts((x,)) for x in fe.touch))
        # the carried points where they meet the far face's edges, lettered
        reached = Many(tuple(Pts((x,)) for x in be.touch))
        out.append(_Draft(
            part, "ellipse", False,
            tuple(_Line("vanishing", x, y) for _, e, be in far for x, y in zip(e.touch, be.touch)),
            strokes, head,
            self.lettered([spec("ellipse_carry", points=around, new=reached,
                                vp=self.words.vp(axis)), *same])))
        return out

    def ellipse_specs(self, part: str, fe: Any, solid: bool,
                      strokes: Sequence[Stroke]) -> list[Spec]:
        """The sub-steps constructing ellipse ``fe`` of ``part`` in its face: diagonals for the
        centre, the lines through it toward the vanishing points, the ellipse through the four
        points (``dotted where hidden`` when ``strokes`` has hidden runs)."""
        u, v = fe.face.in_axes
        a, b, c, d = fe.face.corners
        t = fe.touch  # the middles of the edges: (u hi, v hi, u lo, v lo), round the face
        around = Many(tuple(Pts((x,)) for x in t))
        hidden_runs = any(st.kind == "ellipse_hidden" for st in strokes)
        return [spec("ellipse_diagonals", first=Pts((a, c)), second=Pts((b, d)),
                     point=Pts((fe.centre,)), part=self.say(part),
                     face=self.words.face(fe.face.normal, fe.face.end))
                if solid else  # a plate is drawn as one rectangle
                spec("ellipse_diagonals_plate", first=Pts((a, c)), second=Pts((b, d)),
                     point=Pts((fe.centre,)), part=self.say(part)),
                spec("through", point=Pts((fe.centre,)), line=Pts((t[2], t[0])),
                     vp=self.words.vp(u)),
                spec("through", point=Pts((fe.centre,)), line=Pts((t[3], t[1])),
                     vp=self.words.vp(v)),
                spec("ellipse_draw_hidden" if hidden_runs else "ellipse_draw", points=around)]

    def contour_drafts(self, order: Sequence[str], parts: dict[str, Part]) -> list[_Draft]:
        """Contour steps, front to back (:func:`_front_to_back`); each part's lines are its
        lines in the finished drawing, so the steps add up to exactly the finished drawing."""
        finals = self.finals(parts)
        order = _front_to_back([parts[p] for p in order], self.camera, self.settings)
        out: list[_Draft] = []
        for part in order:
            if not finals[part]:
                continue
            key = "contour_first" if not out else "contour_next"
            out.append(_Draft(part, "contour", False, (), finals[part],
                              _t("headline.contour", Part=_cap(self.say(part))),
                              (spec(key),)))
        return out

    # -------------------------------------------------------------- repeated parts
    def congruent(self, a: str, b: str, boxes: dict[str, Box]) -> bool:
        """Two parts are the same shape: same primitive type and axis, box extents within
        :data:`REPEAT_TOL` of the larger box's largest extent, and meshes with the same number
        of triangles and surface areas within ``REPEAT_TOL`` (instances of one mesh)."""
        pa, pb = self.plan.primitive(a), self.plan.primitive(b)
        if (pa.type, pa.axis) != (pb.type, pb.axis) or pa.type == "custom":
            return False
        ea = np.subtract(boxes[a][1], boxes[a][0])
        eb = np.subtract(boxes[b][1], boxes[b][0])
        scale = max(float(ea.max()), float(eb.max()), 1e-300)
        if float(np.abs(ea - eb).max()) > REPEAT_TOL * scale:
            return False
        ma, mb = self.originals[a], self.originals[b]
        if len(ma.faces) != len(mb.faces):
            return False
        area_a, area_b = _mesh_area(ma), _mesh_area(mb)
        return abs(area_a - area_b) <= REPEAT_TOL * max(area_a, area_b)

    def repeat_groups(self, order: Sequence[str], boxes: dict[str, Box],
                      parents: dict[str, set[str]]) -> list[list[str]]:
        """Parts in drawing order, identical ones (:meth:`congruent`) drawn as one group at the
        first one's place: a later part joins when every part it hangs off is drawn by then
        (before the group, or in it)."""
        groups: list[list[str]] = []
        placed: set[str] = set()
        for i, p in enumerate(order):
            if p in placed:
                continue
            group = [p]
            before = set(order[:i]) - placed | placed
            for q in order[i + 1:]:
                if q in placed or not self.congruent(p, q, boxes):
                    continue
                if parents.get(q, set()) <= before | set(group):
                    group.append(q)
            placed.update(group)
            groups.append(group)
        return groups

    def copy_places(self, members: Sequence[str], keep: set[str]) -> dict[str, str]:
        """Per copy of a group, the words placing it by its parents ("its back in line with the
        body's front"), or "" when it is placed where the picture shows it: when the words are
        too long to read (:data:`REPEAT_WHERE_WORDS`), name a part not in ``keep`` (left out),
        or the copies are placed differently."""
        where = {}
        for q in members:
            cand = self.chosen[q]
            w = _join([_ratio_words(self.words, a, self.say(self.by_id[a.parent].part))
                       for a in cand.anchors])
            short = len(w.split()) <= REPEAT_WHERE_WORDS
            where[q] = w if short and self.parents_of(q) <= keep else ""
        if len(set(where.values())) > 1:
            return {q: "" for q in members}
        return where

    def same_sentence(self, members: Sequence[str], shape: str, keep: set[str]) -> list[Spec]:
        """"Knob 2 and knob 3: the same box, its back in line with the body's front." for the
        group's other members, those placed alike said together (:meth:`copy_places`)."""
        if not members:
            return []
        places = self.copy_places(members, keep)
        by_where: dict[str, list[str]] = {}
        for q in sorted(members, key=lambda q: natural_key(self.say(q))):
            by_where.setdefault(places[q], []).append(q)
        out = []
        for where, qs in by_where.items():
            who = _cap(_join([self.say(q) for q in qs]))
            out.append(spec("repeat", parts=who, shape=shape, where=where) if where
                       else spec("repeat_free" if len(qs) > 1 else "repeat_free_one", parts=who,
                                 shape=shape))
        return out

    def spaced_rows(self, group: Sequence[str], boxes: dict[str, Box]
                    ) -> list[tuple[list[str], int, Face]]:
        """Rows of identical parts at equal spacing, each to be placed by the equal-spacing
        construction (:func:`h2s_print.constructions.equal_spacing`) from its first two: (the
        row's parts in order, its axis, the face the construction is drawn on).

        A row is 3 or more of the group's parts with the same intervals on two axes and, along
        the third, the same step from one to the next (within :data:`SPACING_TOL`), no two
        overlapping.  The group's first part (constructed from its parents) starts its row:
        when it lies inside one, the row is split there and each side runs away from it.
        Rows are taken longest first, a part in one row only.  A row whose faces the view
        shows edge-on or too small for its lines (the eyeball rule) is left to the copies'
        sentences ("the same box, where the picture shows it")."""
        if len(group) < 3:
            return []
        free = list(group)
        rows: list[tuple[list[str], int, Face]] = []
        while True:
            found = [(r, axis, face) for axis in range(3) for r in self._runs(free, boxes, axis)
                     for face in [self._spacing_face(r, boxes, axis)] if face is not None]
            if not found:
                return rows
            best = max(found, key=lambda f: (len(f[0]), [-group.index(q) for q in f[0]]))
            rows.append(best)
            free = [q for q in free if q not in best[0][2:]]

    def _runs(self, members: Sequence[str], boxes: dict[str, Box], axis: int
              ) -> list[list[str]]:
        """Equally spaced runs of ``members`` along ``axis`` (:meth:`spaced_rows`), each
        starting from the group's first part when it holds it."""
        others = [a for a in range(3) if a != axis]
        lines: list[list[str]] = []
        for q in members:  # parts on one line along ``axis``
            box = boxes[q]
            tol = SPACING_TOL * max(_extent(box, a) for a in range(3))
            for line in lines:
                ref = boxes[line[0]]
                if all(abs(box[e][a] - ref[e][a]) <= tol for a in others for e in (0, 1)):
                    line.append(q)
                    break
            else:
                lines.append([q])
        lead = members[0] if members else None
        out: list[list[str]] = []
        for line in lines:
            line.sort(key=lambda q: boxes[q][0][axis])
            lo = [boxes[q][0][axis] for q in line]
            length = _extent(boxes[line[0]], axis)
            i = 0
            while i + 2 < len(line):
                step = lo[i + 1] - lo[i]
                j = i + 1
                if step > 0 and step >= length * (1 - SPACING_TOL):  # apart, not overlapping
                    while j + 1 < len(line) and abs(lo[j + 1] - lo[j] - step) <= SPACING_TOL * step:
                        j += 1
                run = line[i:j + 1]
                if len(run) >= 3:
                    k = run.index(lead) if lead in run else 0
                    if k >= 2:  # the group's first part inside: each side runs away from it
                        out += [r for r in (run[:k + 1][::-1], run[k:]) if len(r) >= 3]
                    else:
                        out.append(run)
                i = j
        return out

    def _spacing_face(self, row: Sequence[str], boxes: dict[str, Box], axis: int
                      ) -> Face | None:
        """The face of the row's first part the construction is drawn on: turned toward the
        camera, containing the row's ``axis``, the largest on the sheet; None when every such
        face (or the row's whole band) is too small for its lines under the eyeball rule."""
        first = boxes[row[0]]
        lo = [min(boxes[q][0][a] for q in row) for a in range(3)]
        hi = [max(boxes[q][1][a] for q in row) for a in range(3)]
        n_lines = 3 + 2 * (len(row) - 2)
        best: tuple[float, Face] | None = None
        for normal in (a for a in range(3) if a != axis):
            for end in ("lo", "hi"):
                face = Face(first, normal, end)
                if not _front_facing(face, self.camera):
                    continue
                band = Face((tuple(lo), tuple(hi)), normal, end)
                if (_too_small(self.camera, face.corners, 3, self.settings.eyeball_mm2)
                        or _too_small(self.camera, band.corners, n_lines,
                                      self.settings.eyeball_mm2)):
                    continue
                area = _polygon_area_mm2(self.camera, face.corners)
                if best is None or area > best[0]:
                    best = (area, face)
        return None if best is None else best[1]

    def spacing_draft(self, row: Sequence[str], axis: int, face: Face, boxes: dict[str, Box],
                      shape: str) -> _Draft:
        """The step placing a row's parts after its first two by equal spacing
        (:class:`h2s_print.constructions.Spacing`, along ``axis`` on ``face``:
        :meth:`spaced_rows`): its sub-steps, lines and the parts' boxes."""
        sp = equal_spacing(face, axis, [(boxes[q][0][axis], boxes[q][1][axis]) for q in row])
        (a, c), (b, d) = sp.diagonals
        placed = [self.say(q) for q in row[2:]]
        specs = [spec("diagonals", first=Pts((a, c)), second=Pts((b, d)),
                      point=Pts((sp.centre,)), parent=self.say(row[0]),
                      face=self.words.face(face.normal, face.end)),
                 spec("through", point=Pts((sp.centre,)),
                      line=Pts((sp.middle.start, sp.middle.end)), vp=self.words.vp(axis)),
                 spec("row_edges", lines=Many((Pts((sp.top.start, sp.top.end)),
                                               Pts((sp.bottom.start, sp.bottom.end)))),
                      vp=self.words.vp(axis))]
        for q, (lo_end, hi_end) in zip(row[2:], sp.ends):
            specs.append(spec("space", lines=Many((Pts((lo_end.start, lo_end.end)),
                                                   Pts((hi_end.start, hi_end.end)))),
                              points=Many((Pts((lo_end.through,)), Pts((hi_end.through,)))),
                              part=self.say(q)))
        specs.append(spec("space_place", parts=_join(placed), shape=shape))
        pair = _join([self.say(q) for q in row[:2]])
        strokes = tuple(st for q in row[2:] for st in _scaffold(
            q, self.plan.primitive(q), boxes[q], self.camera, self.tol))
        return _Draft(row[2], "primitive", False,
                      tuple(_Line(ln.role, ln.start, ln.end) for ln in sp.lines), strokes,
                      _t("headline.spaced", Parts=_cap(_join(placed)), shape=shape, first=pair),
                      self.lettered(specs), _t("substep.space_summary", first=pair),
                      group=tuple(row[2:]))

    def merge_group(self, first: _Draft, members: Sequence[str], extra: Sequence[_Draft],
                    sentences: Sequence[Spec]) -> _Draft:
        """``first`` (whose sub-steps end with ``sentences``) with the other members' strokes
        (and guides), and ``sentences`` in a master's summary too."""
        return replace(first, strokes=first.strokes + tuple(s for d in extra for s in d.strokes),
                       lines=first.lines + tuple(ln for d in extra for ln in d.lines),
                       summary=" ".join(x for x in (first.summary, *map(_substep_of, sentences))
                                        if x),
                       group=tuple(members))

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
                repeat = self.same_sentence(rest, shape, keep)
                made = self.primitive_drafts(p, gi == 0, len(drafts) + 1, described, drawn=drawn,
                                             repeat=repeat)
                if rest:
                    others = [_Draft(q, "primitive", False, (),
                                     _scaffold(q, self.plan.primitive(q), boxes[q], self.camera,
                                               self.tol), "") for q in rest]
                    made[-1] = self.merge_group(made[-1], [p, *rest], others, repeat)
                made += [self.spacing_draft(row, axis, face, boxes, shape)
                         for row, axis, face in rows]
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
            for d in ellipses:  # diagonals a primitive step drew already: used, not redrawn
                here = len(drafts) + 1
                drafts.append(replace(d, specs=tuple(self.drawn_before(x, here) for x in d.specs)))
            contours = self.contour_drafts(order, self.adjusted)
            merged: list[_Draft] = []
            at: dict[str, int] = {}
            for d in contours:  # a group's outlines together, where its first one comes
                head = lead.get(d.part, d.part)
                if head in at:
                    k = at[head]
                    merged[k] = replace(merged[k], strokes=merged[k].strokes + d.strokes,
                                        group=merged[k].group + (d.part,))
                else:  # the step is named after the group's first part, as its other steps
                    at[head] = len(merged)
                    merged.append(replace(d, part=head, group=(d.part,)))
            for head, e in small.items():  # a small ellipse joins its part's outlines
                if head in at:
                    k = at[head]
                    merged[k] = replace(merged[k], strokes=e.strokes + merged[k].strokes,
                                        specs=(spec("ellipse_by_eye_part",
                                                    part=self.say(head)),) + merged[k].specs)
                else:
                    drafts.append(e)
            drafts += self.pack_outlines(merged, lead)
            self._guided = tuple(self.letter(drafts))
        return self._guided

    def pack_outlines(self, drafts: Sequence[_Draft], lead: Mapping[str, str]) -> list[_Draft]:
        """Consecutive outline drafts packed into steps while the text stays within
        :data:`MAX_STEP_WORDS`: a drawing teacher does not give each small part a page of its
        own (before stop 24: two to a step, whatever their length; the roller's high-right
        view took four outline steps for seven parts)."""
        out: list[_Draft] = []
        for d in drafts:
            if out and out[-1].kind == d.kind:
                both = _merged_outlines(out[-1], d, self.say)
                if self.step_words(self.round_sides(both, lead).specs,
                                   both.headline) <= MAX_STEP_WORDS:
                    out[-1] = both
                    continue
            out.append(d)
        return [self.round_sides(d, lead) for d in out]

    def round_sides(self, d: _Draft, lead: Mapping[str, str]) -> _Draft:
        """An outline draft with the sentence joining its round parts' ellipses: the two
        lines touching both, which no scaffold line gives (the read-through: "trace" did not
        say to draw them); one sentence for the step's cylinders, after their ellipses,
        before the tracing, and one for its tapered round parts, whose sides follow the
        picture (a read-through: the mixer's bowl curves, "two straight lines" did not)."""
        rounds = [q for q in d.group if _round(self.plan.primitive(q))
                  and self.plan.primitive(q).type == "cylinder"]
        tapers = [q for q in d.group if _round(self.plan.primitive(q))
                  and self.plan.primitive(q).type == "frustum"]
        joins: list[Spec] = []
        if rounds:
            leads = list(dict.fromkeys(lead.get(q, q) for q in rounds))
            if len(leads) == 1 and len(rounds) > 1:  # one part and its copies
                joins.append(spec("round_sides_copies", the_parents=_the(self.say(leads[0]))))
            else:
                joins.append(spec("round_sides_many" if len(rounds) > 1 else "round_sides",
                                  the_parents=_join([_the(self.say(q)) for q in rounds])))
        if tapers:  # a bowl's sides curve: "two straight lines" contradicted its picture
            joins.append(spec("round_sides_taper",
                              the_parents=_join([_the(self.say(q)) for q in tapers])))
        if not joins:
            return d
        at = next(i for i, x in enumerate(d.specs) if x.key.startswith("contour"))
        return replace(d, specs=d.specs[:at] + tuple(joins) + d.specs[at:])

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
                subs = (tuple(_first_specs(_first_lines(lines, self.camera))) if i == 0
                        else (spec("basic_part"),))
                drafts.append(_Draft(p, "basic", True, (), lines, head, subs))
            drafts += [d for p in order if _round(self.plan.primitive(p))
                       for d in self.ellipse_drafts(p, self.plan.primitive(p).box, True)]
            drafts += self.contour_drafts(order, self.originals)
            self._basic = tuple(self.letter(drafts))
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
            drafts = self.guided()
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
        start = next((i for i, d in enumerate(drafts) if d.kind == "primitive" and d.strokes),
                     None)
        printed = (() if start is None or not LEVEL_ROLES[level]
                   else _sheet_guides(_first_lines(drafts[start].strokes, self.camera),
                                      self.camera))
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
            box = None
            if d.part is not None and d.kind in ("primitive", "basic", "contour", "ellipse"):
                box = (self.plan.primitive(d.part).box if level == "basic"
                       else self.chosen[d.part].box)
            members = list(dict.fromkeys([d.part] + [st.part for st in d.strokes])) \
                if box is not None else []
            stems = [stem(self.say(q)) for q in members]
            named = tuple(self.label(n, p, "part") for q, base in zip(members, stems)
                          for n, p in self.part_labels(q, box if q == d.part else (
                              self.plan.primitive(q).box if level == "basic"
                              else self.chosen[q].box), base is not None
                              and stems.count(base) > 1))
            if level == "master":
                subs: tuple[str, ...] = ()
                labels: tuple[Label, ...] = named
                summary = d.summary
                text = " ".join(x for x in (d.headline, summary) if x)
            else:
                subs, summary = d.substeps, ""
                labels = tuple(self.label(n, p) for n, p in d.labels) + named
                text = " ".join([d.headline] + [_t("step_text.number", n=k + 1, text=x)
                                                 for k, x in enumerate(subs)])
            steps.append(Step(i + 1, d.part, d.kind, text, d.eyeball, guides, d.strokes, alive,
                              d.headline, subs, summary, labels))
        shown = {st.part for st in steps if st.part is not None} | {
            s.part for st in steps for s in st.strokes}
        renamed = tuple((self.names[p].label, p) for p in sorted(shown)
                        if not self.names[p].readable)
        return ViewPlan(name, level, (float(paper.width_mm), float(paper.height_mm)), self.camera,
                        self.vps, tuple(steps), renamed)


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
                   originals={p.name: p for p in plan.model.parts},
                   names=display_names([p.name for p in plan.model.parts],
                                       label_format=templates.lookup("pages", "parts.label")))
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
    return tuple(vp for vp, _ in sequence_workbooks(plan, view, levels, paper, settings))


def sequence_workbooks(plan: Any, view: ViewSpec, levels: Sequence[str], paper: PaperSpec,
                       settings: SequenceSettings
                       ) -> tuple[tuple[ViewPlan, tuple[Stroke, ...]], ...]:
    """:func:`sequence_views` with each level's finished drawing (:func:`final_strokes`),
    from the contours the view's steps were made of (traced once a view, not again per
    level)."""
    ctx = _context(plan, view, paper, settings)
    out = []
    for level in levels:
        vp = ctx.view_plan(view.name, level, paper)  # (an unknown level fails here, first)
        finals = ctx.finals(ctx.originals if level == "basic" else ctx.adjusted)
        out.append((vp, tuple(st for p in plan.model.parts for st in finals[p.name])))
    return tuple(out)


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
