"""The one camera of a view (:func:`view_camera`), shared by all its levels and its sheet."""

from __future__ import annotations

import logging
from collections import OrderedDict
from typing import Any

import numpy as np

from ..config import PaperSpec, ViewSpec
from ..contours import adjust_part
from ..order import start_part
from ..project import make_camera, raised
from ..types import Camera, Part, Vec3
from .geometry import _anchor_lines, _box_corners

log = logging.getLogger(__name__)


#: Lines whose end points agree within this fraction of the model's diagonal are one guide.
MERGE_TOL = 1e-6


#: Plans whose adjusted parts are kept (:func:`_adjusted_parts`), the most recently used.
_ADJUSTED_CACHE = 4
_ADJUSTED: "OrderedDict[int, tuple[Any, dict[str, Part]]]" = OrderedDict()


def _adjusted_parts(plan: Any) -> dict[str, Part]:
    """Each part's mesh mapped into its selected box (:func:`~h2s_print.contours.adjust_part`).

    The same :class:`Part` objects for every view of a plan while it is among the last
    :data:`_ADJUSTED_CACHE` asked for: a part's welded mesh is remembered per part object
    (``contours._Mesh.of``), so the second view of a tutorial no longer welds its adjusted
    meshes again; the mapping is a pure function of the plan, so the parts are the same."""
    hit = _ADJUSTED.get(id(plan))
    if hit is not None and hit[0] is plan:  # the plan is held, so its id is its own
        _ADJUSTED.move_to_end(id(plan))
        return dict(hit[1])
    chosen = plan.chosen()
    parts = {p.name: adjust_part(p, plan.primitive(p.name).box, chosen[p.name].box)
             for p in plan.model.parts}
    _ADJUSTED[id(plan)] = (plan, parts)
    while len(_ADJUSTED) > _ADJUSTED_CACHE:
        _ADJUSTED.popitem(last=False)
    return dict(parts)


def _frame_points(plan: Any, adjusted: dict[str, Part]) -> np.ndarray:
    chosen = plan.chosen()
    pts = [_box_corners(chosen[p.name].box) for p in plan.model.parts]
    pts += [_box_corners(plan.primitive(p.name).box) for p in plan.model.parts]
    pts += [np.asarray(adjusted[p.name].vertices, dtype=float) for p in plan.model.parts]
    pts += [np.asarray(p.vertices, dtype=float) for p in plan.model.parts]
    return np.vstack([p for p in pts if len(p)])


def _guide_points(plan: Any, camera: Camera, tol: float,
                  lines: dict[tuple[str, int], tuple] | None = None) -> np.ndarray:
    """End points of every guide any level of this view could show (eyeball rule ignored);
    with ``lines``, each anchor's :func:`_anchor_lines` kept there by ``(candidate id, anchor
    index)``."""
    by_id = {c.id: c for c in plan.candidates}
    pts: list[Vec3] = []
    for cand in plan.chosen().values():
        for k, anchor in enumerate(cand.anchors):
            if anchor.face_normal == anchor.axis:
                continue
            made = _anchor_lines(anchor, by_id[anchor.parent], cand, plan, camera, tol)
            if lines is not None:
                lines[(cand.id, k)] = made
            _, _, own, carry = made
            pts += [p for ln in own + carry for p in (ln.start, ln.end)]
    pts += _floor_points(plan)
    return np.array(pts, dtype=float).reshape(-1, 3)


def _floor_points(plan: Any) -> list[Vec3]:
    """The floor under the first box's bottom corners, where it stands above the floor: the
    floor line the sheet prints drops from one of them (``project.FirstBoxLines``), for the
    selected boxes and for the fitted ones (the control tutorial's)."""
    start = start_part(plan.primitives)
    if start is None:
        return []
    chosen = plan.chosen()
    out: list[Vec3] = []
    for boxes, (lo, hi) in (([c.box for c in chosen.values()], chosen[start].box),
                            ([p.box for p in plan.primitives], plan.primitive(start).box)):
        floor = min(b[0][2] for b in boxes)
        if raised(lo, hi, floor):
            out += [(x, y, floor) for x in (lo[0], hi[0]) for y in (lo[1], hi[1])]
    return out


def _fit_camera(plan: Any, view: ViewSpec, paper: PaperSpec, adjusted: dict[str, Part],
                tol: float, lines: dict[tuple[str, int], tuple] | None = None) -> Camera:
    """The view's camera (:func:`view_camera`); with ``lines``, the anchors' lines the fit
    worked out (:func:`_guide_points`) are kept there when they are those of the camera
    returned (the first one, not scaled down), for the steps to use again."""
    framed = _frame_points(plan, adjusted)
    camera = make_camera(view, framed, paper)
    made: dict[tuple[str, int], tuple] = {}
    guides = _guide_points(plan, camera, tol, made)
    if lines is not None:
        lines.update(made)  # taken back below if the camera changes
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
    if lines is not None:
        lines.clear()  # (a face's area on the sheet, which chose it, changes with the scale)
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
