"""Stage 7 (project): the camera, its fit to the sheet, vanishing points and the horizon.

Projective facts are checked against their definitions with arithmetic written here, not
with the module's helpers: ``_apply`` is an independent matrix product.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from h2s_print.config import PaperSpec, ViewSpec
from h2s_print.errors import ConfigError, H2SError
from h2s_print.project import (VP_FAR_SHEETS, edge_exit, horizon_mm, make_camera, vp_side,
                               vanishing_point, vanishing_points)

A4 = PaperSpec()  # A4 landscape, 12 mm margins: 297 x 210 mm sheet


def _apply(matrix, xyzw):
    """Independent homogeneous product with explicit sums: 3x4 matrix times a 4-vector."""
    return [sum(float(matrix[r][k]) * float(xyzw[k]) for k in range(4)) for r in range(3)]


def _dehom(h):
    return (h[0] / h[2], h[1] / h[2])


def _box_corners(lo, hi):
    return np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                     for z in (lo[2], hi[2])], dtype=float)


def _random_views(seed: int, count: int):
    """Seeded random (view, points) pairs over both perspectives."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(count):
        lo = rng.uniform(-50, 50, 3)
        hi = lo + rng.uniform(5, 80, 3)
        pts = np.vstack([_box_corners(lo, hi), rng.uniform(lo, hi, (20, 3))])
        persp = "two-point" if i % 2 == 0 else "three-point"
        # two-point keeps the axis level: stay where every point is in front of the camera
        el = rng.uniform(-35, 35) if persp == "two-point" else rng.uniform(-80, 80)
        view = ViewSpec(name=f"v{i}", azimuth_deg=float(rng.uniform(-180, 180)),
                        elevation_deg=float(el), distance=float(rng.uniform(2.5, 8)),
                        lens_mm=float(rng.uniform(20, 120)), perspective=persp)
        out.append((view, pts))
    return out


VIEWS = _random_views(7, 40)


def _line(p, q):
    return np.cross([p[0], p[1], 1.0], [q[0], q[1], 1.0])


# ----------------------------------------------------------------------------- camera


def test_position_follows_the_contract_formula():
    # box (0,0,0)-(2,2,1): diagonal sqrt(4+4+1) = 3, radius 1.5; distance 3 -> d = 4.5
    pts = _box_corners((0, 0, 0), (2, 2, 1))
    cam = make_camera(ViewSpec("front", azimuth_deg=0, elevation_deg=0, distance=3.0), pts, A4)
    # az 0, el 0: target (1, 1, 0.5) + 4.5 * (0, -1, 0)
    assert cam.position == pytest.approx((1.0, -3.5, 0.5), abs=1e-12)
    # depth of the target is d along the (level) optical axis
    assert cam.depth([(1, 1, 0.5)])[0] == pytest.approx(4.5, abs=1e-12)


@pytest.mark.parametrize("view,pts", VIEWS[:12])
def test_position_formula_random(view, pts):
    cam = make_camera(view, pts, A4)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    target, radius = (lo + hi) / 2, np.linalg.norm(hi - lo) / 2
    az, el = math.radians(view.azimuth_deg), math.radians(view.elevation_deg)
    expect = target + view.distance * radius * np.array(
        [math.sin(az) * math.cos(el), -math.cos(az) * math.cos(el), math.sin(el)])
    assert np.allclose(cam.position, expect, atol=1e-9)
    # the third row is depth in model units: 0 at the camera centre, and for three-point the
    # target sits at depth d = distance * radius
    assert abs(cam.depth([cam.position])[0]) < 1e-9
    d = view.distance * radius
    want = d if view.perspective == "three-point" else d * math.cos(el)
    assert cam.depth([target])[0] == pytest.approx(want, rel=1e-12)


@pytest.mark.parametrize("view,pts", VIEWS)
def test_projection_is_the_matrix_product(view, pts):
    cam = make_camera(view, pts, A4)
    got = cam.project(pts)
    for p, g in zip(pts, got):
        x, y = _dehom(_apply(cam.projection_mm, [p[0], p[1], p[2], 1.0]))
        assert abs(g[0] - x) < 1e-9 and abs(g[1] - y) < 1e-9
    assert cam.projection_mm.shape == (3, 4) and not cam.projection_mm.flags.writeable
    assert cam.paper_mm == (297.0, 210.0)  # A4 landscape


@pytest.mark.parametrize("view,pts", VIEWS)
def test_fit_inside_area_centred_and_tight(view, pts):
    area = (20.0, 30.0, 200.0, 150.0)
    cam = make_camera(view, pts, A4, area_mm=area)
    xy = cam.project(pts)
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    assert lo[0] >= area[0] - 1e-9 and lo[1] >= area[1] - 1e-9
    assert hi[0] <= area[2] + 1e-9 and hi[1] <= area[3] + 1e-9
    # centred: bbox centre = area centre (110, 90)
    assert np.allclose((lo + hi) / 2, (110.0, 90.0), atol=1e-9)
    # uniform scale fills one dimension: width 180 mm or height 120 mm is used fully
    assert math.isclose(hi[0] - lo[0], 180.0, abs_tol=1e-9) or \
        math.isclose(hi[1] - lo[1], 120.0, abs_tol=1e-9)


def test_default_area_is_inside_the_margins():
    view, pts = VIEWS[3]
    xy = make_camera(view, pts, PaperSpec(margin_mm=20)).project(pts)
    assert xy.min() >= 20 - 1e-9
    assert xy[:, 0].max() <= 297 - 20 + 1e-9 and xy[:, 1].max() <= 210 - 20 + 1e-9


@pytest.mark.parametrize("view,pts", VIEWS[:10])
def test_fit_is_a_similarity_of_the_image(view, pts):
    """Two areas give images related by one scale and a translation (perspective kept)."""
    a = make_camera(view, pts, A4, area_mm=(10, 10, 100, 100)).project(pts)
    b = make_camera(view, pts, A4, area_mm=(50, 20, 290, 200)).project(pts)
    # solve b = s * a + t by least squares on (s, tx, ty)
    rows = np.vstack([np.column_stack([a[:, 0], np.ones(len(a)), np.zeros(len(a))]),
                      np.column_stack([a[:, 1], np.zeros(len(a)), np.ones(len(a))])])
    sol, *_ = np.linalg.lstsq(rows, np.concatenate([b[:, 0], b[:, 1]]), rcond=None)
    assert np.abs(rows @ sol - np.concatenate([b[:, 0], b[:, 1]])).max() < 1e-8


def test_lens_does_not_change_the_fitted_drawing():
    view, pts = VIEWS[4]
    a = make_camera(view, pts, A4).project(pts)
    other = ViewSpec(view.name, view.azimuth_deg, view.elevation_deg, view.distance, 200.0,
                     view.perspective)
    assert np.allclose(make_camera(other, pts, A4).project(pts), a, atol=1e-9)


# ----------------------------------------------------------------------------- vanishing points


@pytest.mark.parametrize("view,pts", VIEWS)
def test_vanishing_points_are_projected_axis_directions(view, pts):
    cam = make_camera(view, pts, A4)
    vps = vanishing_points(cam)
    assert [vp.axis for vp in vps] == [0, 1, 2]
    for axis, vp in enumerate(vps):
        e = [0.0, 0.0, 0.0, 0.0]
        e[axis] = 1.0
        h = _apply(cam.projection_mm, e)
        assert math.isclose(math.hypot(*vp.direction_mm), 1.0, abs_tol=1e-12)
        if vp.at_infinity:
            assert vp.xy_mm is None
            continue
        x, y = _dehom(h)
        scale = max(1.0, math.hypot(x, y))
        assert abs(vp.xy_mm[0] - x) <= 1e-9 * scale and abs(vp.xy_mm[1] - y) <= 1e-9 * scale
        # direction_mm points from the sheet centre (148.5, 105) toward it
        dx, dy = x - 148.5, y - 105.0
        n = math.hypot(dx, dy)
        assert vp.direction_mm == pytest.approx((dx / n, dy / n), abs=1e-9)


@pytest.mark.parametrize("view,pts", VIEWS)
def test_parallel_lines_meet_at_the_vanishing_point(view, pts):
    """Two parallel 3D lines along each axis project to 2D lines crossing at its VP."""
    cam = make_camera(view, pts, A4)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    for vp in vanishing_points(cam):
        step = np.zeros(3)
        step[vp.axis] = (hi - lo)[vp.axis] / 4
        p1, p2 = lo + (hi - lo) * 0.25, lo + (hi - lo) * [0.7, 0.6, 0.8]
        p2[vp.axis] = p1[vp.axis]
        lines = []
        for p in (p1, p2):
            a, b = cam.project([p - step, p + step])
            lines.append(_line(a, b))
        meet = np.cross(lines[0], lines[1])  # homogeneous intersection
        if vp.at_infinity:
            # parallel on the sheet: meet at infinity, along direction_mm
            d = meet[:2] / np.linalg.norm(meet[:2])
            assert abs(meet[2]) / np.linalg.norm(meet[:2]) < 1e-6
            assert abs(d[0] * vp.direction_mm[1] - d[1] * vp.direction_mm[0]) < 1e-6
            # +axis runs along direction_mm: the projected segment points the same way
            a, b = cam.project([p1 - step, p1 + step])
            assert np.dot(b - a, vp.direction_mm) > 0
        else:
            xy = meet[:2] / meet[2]
            far = math.hypot(*vp.xy_mm)
            # 0.05 mm on the sheet; far VPs (beyond 2 m) only to 2.5e-5 relative
            tol = max(0.05, 2.5e-5 * far)
            assert math.hypot(xy[0] - vp.xy_mm[0], xy[1] - vp.xy_mm[1]) < tol


@pytest.mark.parametrize("view,pts", VIEWS[:10])
def test_long_lines_converge_toward_their_vanishing_point(view, pts):
    cam = make_camera(view, pts, A4)
    start = pts.mean(axis=0)
    radius = np.linalg.norm(pts.max(axis=0) - pts.min(axis=0)) / 2
    for vp in vanishing_points(cam):
        if vp.at_infinity:
            continue
        e = np.zeros(3)
        e[vp.axis] = 1.0
        sign = 1.0 if cam.projection_mm[2, vp.axis] > 0 else -1.0  # walk away from the camera
        ts = (0.0, 10.0, 1e3, 1e6)
        walk = [start + sign * t * radius * e for t in ts]
        dist = [math.dist(cam.project([p])[0], vp.xy_mm) for p in walk]
        assert dist[0] > dist[1] > dist[2] > dist[3]
        # on the sheet, x(t) - VP = (x(0) - VP) * w(0) / w(t): the gap shrinks with 1/depth
        w = cam.depth(walk)
        for i in (1, 2, 3):
            assert dist[i] == pytest.approx(dist[0] * w[0] / w[i], rel=1e-6, abs=1e-9)


@pytest.mark.parametrize("view,pts", [v for v in VIEWS if v[0].perspective == "two-point"])
def test_two_point_verticals_stay_vertical(view, pts):
    cam = make_camera(view, pts, A4)
    rng = np.random.default_rng(11)
    for x, y in rng.uniform(pts.min(axis=0)[:2], pts.max(axis=0)[:2], (10, 2)):
        h = pts[:, 2].max() - pts[:, 2].min()
        a, b = cam.project([(x, y, 0.0), (x, y, h)])
        assert abs(a[0] - b[0]) < 1e-9
    z = vanishing_point(cam, 2)
    assert z.at_infinity and z.xy_mm is None
    assert z.direction_mm == pytest.approx((0.0, 1.0), abs=1e-12)  # +z is up on the sheet


@pytest.mark.parametrize("view,pts", [v for v in VIEWS if v[0].perspective == "three-point"])
def test_three_point_verticals_converge(view, pts):
    cam = make_camera(view, pts, A4)
    z = vanishing_point(cam, 2)
    assert abs(view.elevation_deg) > 0.5  # the seeded views are tilted
    assert not z.at_infinity
    # looking down (elevation > 0) puts the z VP below the sheet centre, looking up above it
    assert (z.xy_mm[1] < 105.0) == (view.elevation_deg > 0)
    # two verticals, projected, cross at the z VP
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    l1 = _line(*cam.project([lo, (lo[0], lo[1], hi[2])]))
    l2 = _line(*cam.project([(hi[0], lo[1], lo[2]), (hi[0], lo[1], hi[2])]))
    m = np.cross(l1, l2)
    xy = m[:2] / m[2]
    assert math.dist(xy, z.xy_mm) < max(0.05, 2.5e-5 * math.hypot(*z.xy_mm))


def test_level_three_point_view_has_parallel_verticals():
    pts = _box_corners((0, 0, 0), (3, 2, 1))
    cam = make_camera(ViewSpec("level", elevation_deg=0.0, perspective="three-point"), pts, A4)
    assert vanishing_point(cam, 2).at_infinity


@pytest.mark.parametrize("perspective", ["two-point", "three-point"])
def test_frontal_view_has_x_at_infinity(perspective):
    # azimuth 0: the camera looks along +y, so x is parallel to the sheet, running right
    pts = _box_corners((0, 0, 0), (3, 2, 1))
    cam = make_camera(ViewSpec("front", azimuth_deg=0.0, perspective=perspective), pts, A4)
    x = vanishing_point(cam, 0)
    assert x.at_infinity and x.direction_mm == pytest.approx((1.0, 0.0), abs=1e-12)
    # one degree off: the x VP is finite, far but well within VP_FAR_SHEETS diagonals
    cam = make_camera(ViewSpec("front", azimuth_deg=1.0, perspective=perspective), pts, A4)
    x = vanishing_point(cam, 0)
    assert not x.at_infinity
    assert 1000 < math.hypot(*x.xy_mm) < VP_FAR_SHEETS * 364  # A4 diagonal ~ 363.6 mm


# ----------------------------------------------------------------------------- horizon, exits


@pytest.mark.parametrize("view,pts", VIEWS[:16])
def test_horizon_is_the_image_of_eye_height(view, pts):
    cam = make_camera(view, pts, A4)
    (x0, y0), (x1, y1) = horizon_mm(cam)
    assert (x0, x1) == (0.0, 297.0)  # camera never rolls: the horizon crosses both sides
    assert abs(y0 - y1) < 1e-9  # ... and is level
    # points at eye height (z = camera z) in front of the camera project onto it
    rng = np.random.default_rng(3)
    cx, cy, cz = cam.position
    for x, y in rng.uniform(-200, 200, (20, 2)):
        p = (cx + x, cy + y, cz)
        if cam.depth([p])[0] < 1.0:
            continue
        assert abs(cam.project([p])[0][1] - y0) < 1e-6
    for vp in vanishing_points(cam)[:2]:
        if not vp.at_infinity:
            assert abs(vp.xy_mm[1] - y0) < 1e-6 * max(1.0, abs(vp.xy_mm[1]))


def test_edge_exit_points_at_the_vanishing_point():
    view, pts = VIEWS[1]
    cam = make_camera(view, pts, A4)
    checked = 0
    for vp in vanishing_points(cam):
        ex = edge_exit(cam, vp)
        if ex is None:
            assert 0 <= vp.xy_mm[0] <= 297 and 0 <= vp.xy_mm[1] <= 210
            continue
        x, y = ex.point_mm
        on = {"left": abs(x) < 1e-9, "right": abs(x - 297) < 1e-9,
              "bottom": abs(y) < 1e-9, "top": abs(y - 210) < 1e-9}
        assert on[ex.side]
        assert -1e-9 <= x <= 297 + 1e-9 and -1e-9 <= y <= 210 + 1e-9
        if vp.xy_mm is not None:
            # centre (148.5, 105), exit and VP are collinear, exit between them
            c = np.array([148.5, 105.0])
            whole = math.dist(c, vp.xy_mm)
            assert math.dist(c, ex.point_mm) + ex.distance_mm == pytest.approx(whole, rel=1e-9)
        checked += 1
    assert checked >= 1


def test_edge_exit_with_inset_and_inside():
    from h2s_print.types import VanishingPoint

    cam = make_camera(ViewSpec("v"), _box_corners((0, 0, 0), (1, 1, 1)), A4)
    inside = VanishingPoint(0, False, (100.0, 100.0), (1.0, 0.0))
    assert edge_exit(cam, inside) is None
    # (100, 100) is within the sheet but left of a 60 mm inset? no: 60 <= 100 <= 237: inside
    assert edge_exit(cam, inside, inset_mm=60) is None
    far = VanishingPoint(0, False, (1148.5, 105.0), (1.0, 0.0))
    ex = edge_exit(cam, far, inset_mm=12)
    # exits the right margin line at x = 297 - 12 = 285; 1148.5 - 285 = 863.5 mm to go
    assert ex.point_mm == (285.0, 105.0) and ex.side == "right"
    assert ex.distance_mm == pytest.approx(863.5)


# ----------------------------------------------------------------------------- errors


def test_camera_inside_bounding_sphere_is_an_error():
    pts = _box_corners((0, 0, 0), (1, 1, 1))
    with pytest.raises(ConfigError, match="view 'close'.*inside"):
        make_camera(ViewSpec("close", distance=0.8), pts, A4)


def test_three_point_straight_down_is_an_error():
    pts = _box_corners((0, 0, 0), (1, 1, 1))
    with pytest.raises(ConfigError, match="view 'top'.*straight up or down"):
        make_camera(ViewSpec("top", elevation_deg=90.0, perspective="three-point"), pts, A4)


def test_points_behind_a_level_camera_are_an_error():
    # two-point at 80 deg, distance 1.5 r: the level camera plane sits 1.5 r cos 80 = 0.26 r
    # in front of the target, so points up to r beyond it lie behind the camera
    pts = _box_corners((0, 0, 0), (1, 1, 1))
    with pytest.raises(ConfigError, match="view 'steep'.*behind or at the camera plane"):
        make_camera(ViewSpec("steep", elevation_deg=80.0, distance=1.5), pts, A4)
    # the same view tilted (three-point) is fine: everything is at depth >= 0.5 r
    make_camera(ViewSpec("steep", elevation_deg=80.0, distance=1.5,
                         perspective="three-point"), pts, A4)


@pytest.mark.parametrize("points,area,match", [
    (np.zeros((0, 3)), None, "points"),
    (np.ones((4, 3)), None, "no extent"),
    ([[0, 0, np.nan], [1, 1, 1]], None, "NaN"),
    (_box_corners((0, 0, 0), (1, 1, 1)), (10, 10, 5, 50), "empty"),
])
def test_bad_input_is_a_user_error(points, area, match):
    with pytest.raises(H2SError, match=match):
        make_camera(ViewSpec("v"), points, A4, area_mm=area)


def test_deterministic():
    view, pts = VIEWS[5]
    a = make_camera(view, pts, A4).projection_mm.tobytes()
    assert make_camera(view, pts, A4).projection_mm.tobytes() == a


@pytest.mark.parametrize("name", ["ikea_chair_ingolf/chair_ingolf_0650.glb",
                                  "ikea_table_lack/table_lack_0825.glb",
                                  "trimesh_pins_plate/pins.glb"])
def test_real_models_frame_inside_the_margins(shared_models, name):
    trimesh = pytest.importorskip("trimesh")
    scene = trimesh.load(shared_models / name, force="scene")
    pts = np.asarray(scene.to_geometry().vertices if hasattr(scene, "to_geometry")
                     else scene.dump(concatenate=True).vertices, dtype=float)  # z-up (README)
    for persp in ("two-point", "three-point"):
        cam = make_camera(ViewSpec("real", perspective=persp), pts, A4)
        xy = cam.project(pts)
        # A4 landscape inside 12 mm margins: x in [12, 285], y in [12, 198]
        assert xy.min() >= 12 - 1e-9
        assert xy[:, 0].max() <= 285 + 1e-9 and xy[:, 1].max() <= 198 + 1e-9
        span = np.ptp(xy, axis=0)  # tight: 285 - 12 = 273 mm wide or 198 - 12 = 186 mm high
        assert math.isclose(span[0], 273, abs_tol=1e-9) or math.isclose(span[1], 186,
                                                                        abs_tol=1e-9)
        assert (cam.depth(pts) > 0).all()
        assert vanishing_point(cam, 2).at_infinity == (persp == "two-point")


def test_edge_exit_from_another_origin():
    from h2s_print.types import VanishingPoint

    cam = make_camera(ViewSpec("v"), _box_corners((0, 0, 0), (1, 1, 1)), A4)
    # VP at (1000, 150) seen from (148.5, 150) on its horizontal: the ray runs along y = 150
    # and leaves the 12 mm inset at x = 285; 1000 - 285 = 715 mm to go
    vp = VanishingPoint(0, False, (1000.0, 150.0), (0.998, 0.05))
    ex = edge_exit(cam, vp, inset_mm=12, origin_mm=(148.5, 150.0))
    assert ex.point_mm == (285.0, 150.0) and ex.side == "right"
    assert ex.direction_mm == (1.0, 0.0) and ex.distance_mm == pytest.approx(715.0)
    # from the centre (148.5, 105) instead: toward (1000, 150), exit x = 285 at
    # y = 105 + 45 * (285 - 148.5) / (1000 - 148.5) = 112.214...
    ex = edge_exit(cam, vp, inset_mm=12, origin_mm=(148.5, 105.0))
    assert ex.point_mm[0] == pytest.approx(285.0)
    assert ex.point_mm[1] == pytest.approx(105 + 45 * 136.5 / 851.5)
    # at infinity the ray follows the VP's direction from the origin: (0, 1) -> the top
    inf = VanishingPoint(2, True, None, (0.0, 1.0))
    ex = edge_exit(cam, inf, inset_mm=12, origin_mm=(100.0, 50.0))
    assert ex.point_mm == (100.0, 198.0) and ex.side == "top" and ex.distance_mm == math.inf


def test_vp_side_names_where_the_point_lies():
    from h2s_print.types import VanishingPoint

    def vp(x, y):
        return VanishingPoint(0, False, (x, y), (1.0, 0.0))

    c = (148.5, 105.0)
    assert vp_side(vp(600.0, 300.0), c) == "right"  # dx 451.5 >= dy 195
    assert vp_side(vp(-300.0, 0.0), c) == "left"  # dx -448.5
    assert vp_side(vp(200.0, 900.0), c) == "above"  # dy 795 > dx 51.5
    assert vp_side(vp(100.0, -700.0), c) == "below"
    assert vp_side(vp(248.5, 5.0), c) == "right"  # |dx| = |dy| = 100: sideways wins
    assert vp_side(VanishingPoint(2, True, None, (0.0, 1.0)), c) is None


def test_the_floor_line_drops_from_the_nearest_bottom_corner_of_a_box_above_the_floor():
    # a table's top, 0.7 above the floor: the sheet prints the floor under the corner whose
    # upright it prints, so the object's whole height is given, not only the top's
    from h2s_print.project import FLOOR_DROP, first_box_lines

    top = np.array([[x, y, z] for x in (-0.6, 0.6) for y in (-0.3, 0.3) for z in (0.7, 0.75)])
    view = ViewSpec("v", azimuth_deg=-35.0, elevation_deg=20.0, distance=3.0)
    cam = make_camera(view, np.vstack([top, [[0.0, 0.0, 0.0]]]), A4)
    lines = first_box_lines(cam, top, 0.0)
    corner, foot = lines.floor
    assert corner == lines.height[0]  # the upright's bottom: the corner nearest the eye
    assert foot == (corner[0], corner[1], 0.0)
    assert first_box_lines(cam, top).floor is None  # no floor given
    # standing on the floor (within FLOOR_DROP of its size): no floor line
    assert first_box_lines(cam, top, 0.7 - 0.5 * FLOOR_DROP * 1.2).floor is None
    assert first_box_lines(cam, top, 0.7 - 2.0 * FLOOR_DROP * 1.2).floor is not None
