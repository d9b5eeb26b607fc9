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
   nearest the child (and, if needed, across to the child).  Such a carry turns at the
   child's near face, or, where no anchor places that face but one centres the child, on
   its middle (two centring lines then meet on the parts' common bisector planes, the
   paper's roller); a turn on a plane no anchor places, or on no line of the paper, is
   said "(by eye)".  Two centring lines off one parent that would not meet so (one on the
   face away from the part: the roller's top, seen from above) are both carried along the
   parent's own faces to its face toward the part, the first down a side face to the
   parent's edge, and cross there (:func:`~.geometry._meeting_carries`: "... to S on the
   roller's bottom edge, then toward the left vanishing point, until they cross at Q").
   An anchor on a parent that is
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
  A part whose lines in the finished drawing total under :data:`~.context.BARELY_MM` (10 mm)
  on the sheet counts as hidden for this, unless it is a copy of a part that shows more (a
  copy costs one sentence): it gets no construction of its own, and its few lines are traced
  in the outline steps ("traced only", logged), so the steps still add up to the finished
  drawing (a read-through: the train's coupling, a 0.6 mm sliver behind the engine, had a
  step and a close-up of its own).
* **Levels.**  ``novice`` sees every line (roles ``construction``, ``guide``, ``vanishing``),
  ``apprentice`` the resulting lines and the alignment lines that carry them (``guide``,
  ``vanishing``), ``master`` none.  Novice and apprentice have the same steps; the
  apprentice's sub-steps leave out those that draw only construction lines, and say a
  construction's result by the construction's name ("Halve the body's front face: draw EF
  ..."; :func:`~h2s_print.instructions.brief_specs`), lettered anew; a construction line a
  later step uses as a guide is a guide where it is drawn (:meth:`_Context.promoted`).  A
  master has the same steps but the guides steps (kind ``guides``), and reads each step's
  headline and its ratio words.  ``basic`` is the paper's control
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
  :func:`h2s_print.names.display_names`.  Outline steps take consecutive parts up to three
  distinct shapes and :data:`MAX_STEP_WORDS` words (:meth:`_Ellipses.pack_outlines`), the last
  ending by erasing the scaffold; an ellipse too small to construct is sketched in its part's
  outlines step.  Vanishing points are named by
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
from typing import Any, Sequence

from ..config import PaperSpec, SequenceSettings, ViewSpec
from ..contours import final_contours
from ..types import Camera, Stroke, ViewPlan
from .camera import _adjusted_parts, view_camera
from .context import _context
from .geometry import _contour_strokes
from .words import _raw, _t

__all__ = ["final_strokes", "sequence_view", "sequence_views", "sequence_workbooks",
           "steps_text", "view_camera"]

log = logging.getLogger(__name__)


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
