"""Stage 7, *project*: a pinhole camera fitted to a sheet, vanishing points and the horizon.

The camera (DESIGN.md §2.7, §3b):

* Z-up world; the camera is aimed at the centre ``T`` of the points' bounding box and sits at
  ``C = T + d·(sin az·cos el, −cos az·cos el, sin el)`` with ``d = distance × r``, ``r`` the
  bounding-sphere radius (half the box diagonal).
* ``three-point``: the optical axis points from ``C`` at ``T`` (tilted when ``el != 0``: vertical
  edges converge to a finite z vanishing point).
* ``two-point``: the optical axis is kept horizontal, pointing in the azimuth direction
  ``(−sin az, cos az, 0)``, and the image window is shifted (a shift lens) so that ``T`` is on the
  window's centre: vertical edges stay exactly vertical, the z vanishing point is at infinity.
* The film image uses the 35 mm-equivalent focal length ``lens_mm`` (a 36 × 24 mm frame).  It is
  then fitted into ``area_mm`` (default: the sheet inside its margins) with one uniform scale
  and a translation, centring the points' projected bounding box.  That 2D similarity is
  folded into ``Camera.projection_mm``.  Because the fit rescales uniformly, the drawing on
  the sheet does not depend on ``lens_mm`` (the perspective strength comes from ``distance``
  alone); ``lens_mm`` fixes the nominal film scale and is logged with the fitted scale.

``projection_mm`` rows 1-2 give sheet mm times depth, row 3 gives the depth ``w`` along the
optical axis in model units (positive in front), so ``Camera.depth`` is a real distance.

Sheet coordinates are millimetres, origin at the sheet's bottom-left corner, x right, y up.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from .config import PERSPECTIVES, PaperSpec, ViewSpec
from .errors import ConfigError
from .types import Camera, VanishingPoint, ViewPlan, readonly

log = logging.getLogger(__name__)

#: A vanishing point farther than this many sheet diagonals from the sheet centre is treated
#: as at infinity (its lines converge by less than a microradian across the sheet):
#: ``|w| · VP_FAR_SHEETS · diagonal <= |(h_x, h_y) − w·centre|`` for the column ``h`` of the axis.
VP_FAR_SHEETS = 1e6
#: Points whose depth is at most this fraction of the bounding-sphere radius count as "at the
#: camera plane" (their projection would be unbounded).
DEPTH_EPS = 1e-6
#: Below this ``|forward × z|`` a three-point camera's up vector is undefined (looking straight
#: up or down).
UP_EPS = 1e-6
#: Film frame of the 35 mm-equivalent lens, mm (width, height).
FRAME_MM = (36.0, 24.0)


@dataclass(frozen=True, slots=True)
class EdgeExit:
    """Where the line from the sheet centre (or another origin) toward a vanishing point leaves
    the sheet.

    Attributes:
        point_mm: the exit point on the sheet border (or the inset border), mm.
        direction_mm: unit direction from the origin (default the sheet centre) toward the
            vanishing point.
        distance_mm: distance from ``point_mm`` to the vanishing point, mm (``inf`` at infinity).
        side: ``left``, ``right``, ``bottom`` or ``top``: the border crossed.
    """

    point_mm: tuple[float, float]
    direction_mm: tuple[float, float]
    distance_mm: float
    side: str


def _fail(view: ViewSpec, message: str) -> ConfigError:
    return ConfigError(f"view {view.name!r}: {message}")


def _area(view: ViewSpec, paper: PaperSpec, area_mm: Any) -> tuple[float, float, float, float]:
    if area_mm is None:
        m = paper.margin_mm
        area = (m, m, paper.width_mm - m, paper.height_mm - m)
    else:
        try:
            area = tuple(float(v) for v in area_mm)
        except (TypeError, ValueError):
            raise _fail(view, f"area_mm must be four numbers (x0, y0, x1, y1), got {area_mm!r}") \
                from None
        if len(area) != 4:
            raise _fail(view, f"area_mm must be four numbers (x0, y0, x1, y1), got {area_mm!r}")
    x0, y0, x1, y1 = area
    if not all(math.isfinite(v) for v in area) or not (x0 < x1 and y0 < y1):
        raise _fail(view, f"drawing area {area} mm is empty (paper {paper.width_mm:g} x "
                          f"{paper.height_mm:g} mm, margin {paper.margin_mm:g} mm)")
    return x0, y0, x1, y1


def view_direction(view: ViewSpec) -> np.ndarray:
    """The unit vector from the object's centre toward ``view``'s eye (model axes)."""
    az, el = math.radians(view.azimuth_deg), math.radians(view.elevation_deg)
    return np.array([math.sin(az) * math.cos(el), -math.cos(az) * math.cos(el), math.sin(el)])


def make_camera(view: ViewSpec, points: Any, paper: PaperSpec, *,
                area_mm: Any = None) -> Camera:
    """Build the pinhole camera of ``view`` framing ``points`` on ``paper``.

    Args:
        view: azimuth, elevation, distance (bounding-sphere radii), lens and perspective.
        points: (n, 3) float, model units: what must be in the picture (e.g. the model's
            vertices or the corners of every box).  Their bounding box sets target and radius.
        paper: the sheet; its margins give the default drawing area.
        area_mm: ``(x0, y0, x1, y1)`` sheet mm into which the projected points are fitted
            (uniform scale, centred); default the sheet inside its margins.

    Returns:
        A :class:`Camera` whose ``projection_mm`` maps model points to sheet mm.

    Raises:
        ConfigError: naming the view, when the points are empty or degenerate, the camera is
            inside the bounding sphere, a three-point camera looks straight up or down, or a
            point is behind or at the camera plane.
    """
    if view.perspective not in PERSPECTIVES:
        raise _fail(view, f"perspective must be one of {', '.join(PERSPECTIVES)}, "
                          f"got {view.perspective!r}")
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 3 or len(pts) == 0:
        raise _fail(view, f"expected (n, 3) points to frame, got shape {pts.shape}")
    if not np.isfinite(pts).all():
        raise _fail(view, "points to frame contain NaN or infinity")
    area = _area(view, paper, area_mm)

    lo, hi = pts.min(axis=0), pts.max(axis=0)
    target = (lo + hi) / 2
    radius = 0.5 * float(np.linalg.norm(hi - lo))
    if radius <= 0:
        raise _fail(view, "the points to frame have no extent (all equal)")
    if not view.distance > 1.0:
        raise _fail(view, f"distance {view.distance:g} bounding-sphere radii puts the camera "
                          "inside the object's bounding sphere (need > 1)")
    az = math.radians(view.azimuth_deg)
    out = view_direction(view)
    d = view.distance * radius
    position = target + d * out

    if view.perspective == "three-point":
        forward = -out / float(np.linalg.norm(out))
        right = np.cross(forward, (0.0, 0.0, 1.0))
        n = float(np.linalg.norm(right))
        if n < UP_EPS:
            raise _fail(view, f"a three-point camera at elevation {view.elevation_deg:g} deg "
                              "looks straight up or down: its up direction is undefined")
        right = right / n
        up = np.cross(right, forward)
    else:
        # Level optical axis; exact zeros keep verticals exactly vertical on the sheet.
        forward = np.array([-math.sin(az), math.cos(az), 0.0])
        right = np.array([math.cos(az), math.sin(az), 0.0])
        up = np.array([0.0, 0.0, 1.0])
    rot = np.vstack([right, up, forward])
    extrinsic = np.hstack([rot, (-rot @ position)[:, None]])  # (3, 4): camera coordinates

    cam = pts @ extrinsic[:, :3].T + extrinsic[:, 3]
    depth = cam[:, 2]
    bad = int(np.count_nonzero(depth <= DEPTH_EPS * radius))
    if bad:
        hint = (" (a two-point camera keeps its axis level: lower the elevation, raise the "
                "distance, or use three-point)" if view.perspective == "two-point" else "")
        raise _fail(view, f"{bad} of {len(pts)} points lie behind or at the camera plane{hint}")

    focal = float(view.lens_mm)
    shift = np.zeros(2)
    if view.perspective == "two-point":
        t_cam = extrinsic[:, :3] @ target + extrinsic[:, 3]
        shift = -focal * t_cam[:2] / t_cam[2]  # shift lens: target on the window's centre
    film = focal * cam[:, :2] / depth[:, None] + shift
    fmin, fmax = film.min(axis=0), film.max(axis=0)
    span = fmax - fmin
    x0, y0, x1, y1 = area
    scales = [size / s for size, s in ((x1 - x0, span[0]), (y1 - y0, span[1]))
              if s > 1e-12 * focal]
    if not scales:
        raise _fail(view, "all points project to a single point")
    scale = min(scales)
    tx = (x0 + x1) / 2 - scale * (fmin[0] + fmax[0]) / 2
    ty = (y0 + y1) / 2 - scale * (fmin[1] + fmax[1]) / 2
    intrinsic = np.array([[focal, 0.0, shift[0]], [0.0, focal, shift[1]], [0.0, 0.0, 1.0]])
    fit = np.array([[scale, 0.0, tx], [0.0, scale, ty], [0.0, 0.0, 1.0]])
    projection = fit @ intrinsic @ extrinsic
    frame_used = float(max(span[0] / FRAME_MM[0], span[1] / FRAME_MM[1]))
    log.debug("view %r: %s camera at %s, %.3f mm per film mm; the object spans %.0f%% of a "
              "%g mm lens's frame", view.name, view.perspective, position.round(6).tolist(),
              scale, 100 * frame_used, focal)
    return Camera(
        position=(float(position[0]), float(position[1]), float(position[2])),
        projection_mm=readonly(projection, np.float64),
        paper_mm=(float(paper.width_mm), float(paper.height_mm)),
        perspective=view.perspective,
    )


def _unit(v: np.ndarray) -> tuple[float, float]:
    n = float(np.hypot(v[0], v[1]))
    if n == 0.0:
        return (1.0, 0.0)
    return (float(v[0] / n), float(v[1] / n))


def _sheet(camera: Camera) -> tuple[np.ndarray, float]:
    w, h = camera.paper_mm
    return np.array([w / 2, h / 2]), float(math.hypot(w, h))


def vanishing_point(camera: Camera, axis: int) -> VanishingPoint:
    """The vanishing point of model axis ``axis`` (0, 1, 2): the projection of ``(e_axis, 0)``.

    A point farther than ``VP_FAR_SHEETS`` sheet diagonals from the sheet centre is at
    infinity; its ``direction_mm`` is then the sheet direction of the axis's (parallel) lines,
    pointing the way ``+axis`` runs.  A finite point's ``direction_mm`` points from the sheet
    centre toward it (``(1, 0)`` in the degenerate case of a VP exactly at the centre).
    """
    if axis not in (0, 1, 2):
        raise ValueError(f"axis must be 0, 1 or 2, got {axis!r}")
    h = np.asarray(camera.projection_mm[:, axis], dtype=float)
    centre, diag = _sheet(camera)
    w = float(h[2])
    toward = h[:2] - w * centre  # w × (VP − centre)
    if abs(w) * VP_FAR_SHEETS * diag <= float(np.hypot(*toward)):
        return VanishingPoint(axis, True, None, _unit(toward if w >= 0 else -toward))
    xy = h[:2] / w
    return VanishingPoint(axis, False, (float(xy[0]), float(xy[1])), _unit(xy - centre))


def vanishing_points(camera: Camera) -> tuple[VanishingPoint, ...]:
    """Vanishing points of the x, y and z axes, in that order (see :func:`vanishing_point`)."""
    return tuple(vanishing_point(camera, axis) for axis in (0, 1, 2))


def horizon_mm(camera: Camera) -> tuple[tuple[float, float], tuple[float, float]] | None:
    """The horizon: the line through the vanishing points of all horizontal directions.

    It is also the image of the horizontal plane at the camera's eye height.  Returned as two
    points of the (infinite) line: where it crosses ``x = 0`` and ``x = width`` of the sheet
    (``y = 0`` and ``y = height`` for a steep line), which may lie off the sheet.  ``None`` when
    the horizon is at infinity (a camera looking straight down or up).
    """
    p = np.asarray(camera.projection_mm, dtype=float)
    line = np.cross(p[:, 0], p[:, 1])  # homogeneous line through both horizontal VPs
    centre, diag = _sheet(camera)
    normal = float(np.hypot(line[0], line[1]))
    offset = abs(float(line[0] * centre[0] + line[1] * centre[1] + line[2]))
    if normal * VP_FAR_SHEETS * diag <= offset:
        return None
    w, h = camera.paper_mm
    if abs(line[1]) >= abs(line[0]):
        ys = [-(line[0] * x + line[2]) / line[1] for x in (0.0, w)]
        return ((0.0, float(ys[0])), (float(w), float(ys[1])))
    xs = [-(line[1] * y + line[2]) / line[0] for y in (0.0, h)]
    return ((float(xs[0]), 0.0), (float(xs[1]), float(h)))


def vp_side(vp: VanishingPoint, centre_mm: Any) -> str | None:
    """Where ``vp`` lies seen from ``centre_mm``, the word the texts name it by.

    ``right`` or ``left`` when it is at least as far sideways as up or down
    (``|dx| >= |dy|``, ``dx > 0`` is right), else ``above`` or ``below`` (``dy > 0`` is
    above); ``dx``, ``dy`` are sheet mm from ``centre_mm`` to the point.  One rule for every
    text that names a vanishing point (drawing sheet labels, step instructions).

    Args:
        vp: the vanishing point.
        centre_mm: ``(x, y)`` sheet mm it is seen from (e.g. the sheet's centre).

    Returns:
        ``"left"``, ``"right"``, ``"above"`` or ``"below"``; ``None`` at infinity.
    """
    if vp.at_infinity or vp.xy_mm is None:
        return None
    dx = float(vp.xy_mm[0]) - float(centre_mm[0])
    dy = float(vp.xy_mm[1]) - float(centre_mm[1])
    if abs(dx) >= abs(dy):
        return "right" if dx > 0 else "left"
    return "above" if dy > 0 else "below"


def edge_exit(camera: Camera, vp: VanishingPoint, *, inset_mm: float = 0.0,
              origin_mm: Any = None) -> EdgeExit | None:
    """Where the line from the sheet centre (or ``origin_mm``) toward ``vp`` leaves the sheet.

    For an off-sheet vanishing point the layout draws a mark there with "VP is ``distance_mm``
    this way".  ``inset_mm`` shrinks the sheet rectangle on every side (e.g. to the margins).

    Args:
        camera: gives the sheet size ``paper_mm``.
        vp: the vanishing point.
        inset_mm: the rectangle is the sheet shrunk by this much on every side, mm.
        origin_mm: ``(x, y)`` sheet mm the ray starts from (it should lie inside the
            rectangle); default the sheet's centre.  Toward a finite VP the ray runs from
            the origin to the VP; at infinity along ``vp.direction_mm``.

    Returns:
        The exit, or ``None`` when ``vp`` is finite and lies inside the (inset) rectangle, or
        when a finite ``vp`` coincides with ``origin_mm`` (no direction).
    """
    w, h = camera.paper_mm
    x0, y0, x1, y1 = inset_mm, inset_mm, w - inset_mm, h - inset_mm
    if not (x0 < x1 and y0 < y1):
        raise ValueError(f"inset {inset_mm} mm leaves no sheet")
    centre = np.array([w / 2, h / 2])
    if vp.xy_mm is not None and x0 <= vp.xy_mm[0] <= x1 and y0 <= vp.xy_mm[1] <= y1:
        return None
    if origin_mm is None:
        dx, dy = vp.direction_mm
    else:
        centre = np.array([float(origin_mm[0]), float(origin_mm[1])])
        if vp.xy_mm is None:
            dx, dy = vp.direction_mm
        else:
            toward = np.array(vp.xy_mm, dtype=float) - centre
            if not float(np.hypot(*toward)) > 0.0:
                return None
            dx, dy = _unit(toward)
    hits = []
    if dx > 0:
        hits.append(((x1 - centre[0]) / dx, "right"))
    elif dx < 0:
        hits.append(((x0 - centre[0]) / dx, "left"))
    if dy > 0:
        hits.append(((y1 - centre[1]) / dy, "top"))
    elif dy < 0:
        hits.append(((y0 - centre[1]) / dy, "bottom"))
    t, side = min(hits)
    point = centre + t * np.array([dx, dy])
    distance = math.inf if vp.xy_mm is None else float(np.hypot(*(np.array(vp.xy_mm) - point)))
    return EdgeExit((float(point[0]), float(point[1])), (float(dx), float(dy)), distance, side)


Point3 = tuple[float, float, float]


@dataclass(frozen=True, slots=True)
class FirstBoxLines:
    """What the calibrated sheet prints of the first box (the tutorial's first scaffold step):
    its bottom face, the ground the drawing stands on, and its upright edge nearest the eye,
    which gives its height (every later size is measured against this box).

    When the first box stands above the floor (a table's top, a train's engine on its
    wheels), the sheet also prints the floor under that nearest corner (``floor``): the
    object's whole height, which nothing else on the sheet gives (a read-through: the table's
    legs and the desk's uprights were all "height by eye").

    Attributes:
        footprint: the bottom face's corners in order around it (3D, model units).
        height: ``(bottom, top)`` of the nearest upright edge, or ``None`` for a flat box.
        floor: ``(corner, its foot on the floor)``: the nearest bottom corner and the point
            straight below it at the floor, or ``None`` when the box stands on the floor.
        flat: the box has no height (a flat part drawn as its rectangle): its footprint is
            the part itself.  (``height`` is ``None`` then, but also for a box whose upright
            edge reaches behind the eye.)
    """

    footprint: tuple[Point3, Point3, Point3, Point3]
    height: tuple[Point3, Point3] | None
    floor: tuple[Point3, Point3] | None = None
    flat: bool = False


#: The first box "stands above the floor" (:class:`FirstBoxLines`) when its bottom is more
#: than this share of its own largest extent above the floor.
FLOOR_DROP = 0.05


def raised(lo: Sequence[float], hi: Sequence[float], floor_z: float) -> bool:
    """Does the box ``lo``-``hi`` stand above the floor ``floor_z`` (:data:`FLOOR_DROP`)?"""
    return lo[2] - floor_z > FLOOR_DROP * max(hi[a] - lo[a] for a in range(3))


def first_box_lines(camera: Camera, points3d: Any,
                    floor_z: float | None = None) -> FirstBoxLines | None:
    """The sheet's lines of the box around ``points3d`` (the first scaffold step's stroke
    points; :class:`FirstBoxLines`), or ``None`` when there are none or the footprint is not
    wholly in front of the camera.  The nearest edge is the corner column closest to the
    eye in plan (ties: the smaller corner); the floor line drops from its bottom to
    ``floor_z`` when that is more than :data:`FLOOR_DROP` of the box's largest extent
    below."""
    pts = np.asarray(points3d, dtype=float).reshape(-1, 3)
    if len(pts) == 0:
        return None
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    z = float(lo[2])
    xs, ys = (float(lo[0]), float(hi[0])), (float(lo[1]), float(hi[1]))
    foot = ((xs[0], ys[0], z), (xs[1], ys[0], z), (xs[1], ys[1], z), (xs[0], ys[1], z))
    if np.any(camera.depth(foot) <= 0):
        return None
    eye = np.asarray(camera.position, dtype=float)
    x, y = min(((x, y) for x in xs for y in ys),
               key=lambda c: (math.hypot(c[0] - eye[0], c[1] - eye[1]), c))
    height = None
    if hi[2] > lo[2]:
        ends = ((x, y, z), (x, y, float(hi[2])))
        if not np.any(camera.depth(ends) <= 0):
            height = ends
    floor = None
    if floor_z is not None and raised(lo, hi, floor_z):
        drop = ((x, y, z), (x, y, float(floor_z)))
        if not np.any(camera.depth(drop) <= 0):
            floor = drop
    return FirstBoxLines(foot, height, floor, flat=not hi[2] > lo[2])


def first_scaffold_lines(plan: ViewPlan) -> tuple[int, FirstBoxLines] | None:
    """The index of ``plan``'s first scaffold step (kind ``primitive`` or ``basic``, with
    strokes) and what the calibrated sheet prints of its box (:func:`first_box_lines`, above
    ``plan.floor_z``); None without such a step or lines.  The sheet prints these lines and
    the control tutorial's step 1 shows them."""
    for k, step in enumerate(plan.steps):
        if step.kind not in ("primitive", "basic") or not step.strokes:
            continue
        pts = [p for s in step.strokes for p in s.points3d]
        if not pts:
            continue
        lines = first_box_lines(plan.camera, pts, plan.floor_z)
        return None if lines is None else (k, lines)
    return None
