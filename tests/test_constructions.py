"""Guide constructions on box faces: exact in 3D, and repeatable with a ruler on the sheet.

The 2D checks redo each construction on the *projected* face with homogeneous line
arithmetic written here (lines through two points, intersections, lines toward a vanishing
point found by intersecting two projected edges), independent of ``h2s_print.constructions``.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from h2s_print.config import PaperSpec, ViewSpec
from h2s_print.constructions import (GUIDE_LINES, RATIOS, Face, align, box_faces, construct,
                                     ellipse_on_face, equal_spacing, guide_lines, ratio_key)
from h2s_print.errors import RenderError
from h2s_print.project import make_camera

A4 = PaperSpec()
TOL_MM = 0.05
BOX = ((1.0, 2.0, 3.0), (5.0, 5.0, 4.0))  # extents 4, 3, 1


# ----------------------------------------------------------------------------- helpers


def _meet3(p1, q1, p2, q2):
    """Closest points of two 3D lines; returns (point on line 1, gap between the lines)."""
    p1, q1, p2, q2 = (np.asarray(v, dtype=float) for v in (p1, q1, p2, q2))
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a, b, c, d, e = d1 @ d1, d1 @ d2, d2 @ d2, d1 @ r, d2 @ r
    den = a * c - b * b
    s = (b * e - c * d) / den
    t = (a * e - b * d) / den
    x1, x2 = p1 + s * d1, p2 + t * d2
    return x1, float(np.linalg.norm(x1 - x2))


def _on_segment_line(x, line, tol=1e-9):
    """Distance of point x from the infinite line through a ConstructionLine."""
    a, b = np.asarray(line.start), np.asarray(line.end)
    d = (b - a) / np.linalg.norm(b - a)
    v = np.asarray(x) - a
    return float(np.linalg.norm(v - (v @ d) * d)) <= tol


def _lines(con, key):
    return [ln for ln in con.lines if ln.key == key]


def _h(p):
    return np.array([p[0], p[1], 1.0])


def _join(p, q):
    return np.cross(p, q)


def _cross2(p, q):
    return float(p[0] * q[1] - p[1] * q[0])


def _pt(h):
    return h[:2] / h[2]


# ----------------------------------------------------------------------------- faces


def test_face_corners_in_documented_order():
    top = Face(BOX, 2, "hi")
    assert top.in_axes == (0, 1) and top.coord == 4.0
    # A (u_lo, v_lo), B (u_hi, v_lo), C (u_hi, v_hi), D (u_lo, v_hi) at z = 4
    assert top.corners == ((1, 2, 4), (5, 2, 4), (5, 5, 4), (1, 5, 4))
    side = Face(BOX, 1, "lo")
    assert side.in_axes == (0, 2)
    assert side.corners == ((1, 2, 3), (5, 2, 3), (5, 2, 4), (1, 2, 4))
    assert len(box_faces(BOX)) == 6
    with pytest.raises(ValueError):
        Face(BOX, 3, "hi")
    with pytest.raises(ValueError):
        Face(BOX, 0, "top")


# ----------------------------------------------------------------------------- 3D facts


def test_guide_line_counts_match_the_constructions():
    face = Face(BOX, 2, "hi")
    assert set(GUIDE_LINES) == {float(r) for r in RATIOS}
    for r in RATIOS:
        for axis in face.in_axes:
            con = construct(face, axis, float(r))
            assert con.guide_lines == len(con.lines) == GUIDE_LINES[float(r)] == guide_lines(r)
    # paper §5: "dividing a face ... into halves requires three guidelines"
    assert GUIDE_LINES[0.5] == 3
    # 0 and 1: no construction, the existing edge (extended) is the one guide
    assert GUIDE_LINES[0.0] == GUIDE_LINES[1.0] == 1


@pytest.mark.parametrize("ratio", RATIOS)
@pytest.mark.parametrize("normal,end,axis", [(2, "hi", 0), (2, "hi", 1), (0, "lo", 2),
                                             (1, "hi", 0)])
def test_result_line_sits_exactly_at_the_ratio(ratio, normal, end, axis):
    face = Face(BOX, normal, end)
    con = construct(face, axis, float(ratio))
    lo, hi = BOX[0][axis], BOX[1][axis]
    want = lo + float(ratio) * (hi - lo)  # e.g. x: 1 + (1/3) * 4 = 2.333...
    assert con.coord == pytest.approx(want, abs=1e-12)
    other = face.in_axes[1] if axis == face.in_axes[0] else face.in_axes[0]
    res = con.result
    assert res.start[axis] == pytest.approx(want, abs=1e-12)
    assert res.end[axis] == pytest.approx(want, abs=1e-12)
    assert {res.start[other], res.end[other]} == {BOX[0][other], BOX[1][other]}
    assert res.axis == other and res.role == "guide"
    for ln in con.lines:  # every line lies in the face plane (extended)
        assert ln.start[normal] == face.coord and ln.end[normal] == face.coord
        assert ln.role in ("construction", "guide")
    if con.lines:
        assert con.lines[-1] == res
        assert [ln.role for ln in con.lines[:-1]] == ["construction"] * (len(con.lines) - 1)


def test_one_third_is_diagonal_bd_meets_line_ce():
    """Paper Fig. 3c: line C-E (E the midpoint of AD, made by the cross line through the
    centre) meets diagonal B-D at exactly 1/3; D-F meets A-C at 2/3."""
    face = Face(BOX, 2, "hi")  # A (1,2), B (5,2), C (5,5), D (1,5) at z = 4 for axis x
    for r, line, diag, want in ((Fraction(1, 3), ("C", "E"), ("B", "D"), 1 + 4 / 3),
                                (Fraction(2, 3), ("D", "F"), ("A", "C"), 1 + 8 / 3)):
        con = construct(face, 0, r)
        (cross,) = _lines(con, "cross")
        (conn,) = _lines(con, "connect")
        assert conn.names == line
        (dg,) = [ln for ln in _lines(con, "diagonal") if ln.names == diag]
        # E and F: where the cross line (through the diagonals' meeting point, along x)
        # meets the edges AD (x = 1) and BC (x = 5): midpoints, y = 3.5
        o, gap = _meet3(*[(ln.start, ln.end) for ln in _lines(con, "diagonal")][0],
                        *[(ln.start, ln.end) for ln in _lines(con, "diagonal")][1])
        assert gap < 1e-12 and _on_segment_line(o, cross)
        assert con.point("E") == (1.0, 3.5, 4.0) and con.point("F") == (5.0, 3.5, 4.0)
        x, gap = _meet3(conn.start, conn.end, dg.start, dg.end)
        assert gap < 1e-12
        # x = 1 + 4/3 (or 8/3); y = 2 + 3 * 2/3 = 4
        assert x[0] == pytest.approx(want, abs=1e-12) and x[1] == pytest.approx(4.0, abs=1e-12)
        assert _on_segment_line(x, con.result)
        assert np.allclose(x, con.point("I1" if r < 0.5 else "I2"), atol=1e-12)


def test_half_is_where_the_diagonals_meet():
    face = Face(BOX, 0, "hi")  # in-face axes y, z
    con = construct(face, 2, 0.5)
    d1, d2 = _lines(con, "diagonal")
    x, gap = _meet3(d1.start, d1.end, d2.start, d2.end)
    assert gap < 1e-12
    assert np.allclose(x, (5.0, 3.5, 3.5), atol=1e-12)  # centre of y 2..5, z 3..4 at x = 5
    assert _on_segment_line(x, con.result)


def test_quarter_is_halving_twice():
    face = Face(BOX, 2, "lo")
    for r, want in ((0.25, 2.0), (0.75, 4.0)):  # x = 1 + 4 * r
        con = construct(face, 0, r)
        diags = _lines(con, "diagonal")
        assert len(diags) == 4
        x, gap = _meet3(diags[2].start, diags[2].end, diags[3].start, diags[3].end)
        assert gap < 1e-12 and x[0] == pytest.approx(want, abs=1e-12)
        assert _on_segment_line(x, con.result)
        half = _lines(con, "division")[0]
        assert half.role == "construction" and half.start[0] == pytest.approx(3.0)


@pytest.mark.parametrize("ratio,want", [(2, 9.0), (-1, -3.0), (1.5, 7.0), (-0.5, -1.0)])
def test_extension_by_reflection(ratio, want):
    """Extend by 1 (or 1/2): the line through the shared edge's midpoint meets the extended
    edge AB where the new end goes: x = 1 + ratio * 4."""
    face = Face(BOX, 2, "hi")
    con = construct(face, 0, ratio)
    (cross,) = _lines(con, "cross")
    (conn,) = _lines(con, "connect")
    (ext,) = _lines(con, "extend")
    shared_x = 5.0 if ratio > 1 else 1.0
    mid = con.point("F" if ratio > 1 else "E")
    assert mid == pytest.approx((shared_x, 3.5, 4.0))  # midpoint of the shared edge (y 2..5)
    assert _on_segment_line(mid, cross) and _on_segment_line(mid, conn)
    # the connecting line starts at a far corner (extend by 1) or at T1/2 (by 1/2)
    start = {2: (1.0, 5.0), -1: (5.0, 5.0), 1.5: (3.0, 5.0), -0.5: (3.0, 5.0)}[ratio]
    assert conn.start == (*start, 4.0)
    # reflection: the copied distance equals the original along x, |start - mid| = |mid - S|
    x, gap = _meet3(conn.start, conn.end, ext.start, ext.end)
    assert gap < 1e-12 and x[0] == pytest.approx(want, abs=1e-12) and x[1] == 2.0
    assert x[0] - shared_x == pytest.approx(shared_x - start[0], abs=1e-12)
    assert _on_segment_line(x, con.result)
    assert ext.axis == 0 and ext.names[0] == ("B" if ratio < 0 else "A")  # toward the x VP


def test_zero_and_one_are_existing_edges():
    face = Face(BOX, 2, "hi")
    for r, x in ((0, 1.0), (1, 5.0)):
        con = construct(face, 0, r)
        assert len(con.lines) == 1 and con.result.key == "align"
        assert con.result.start == (x, 2.0, 4.0) and con.result.end == (x, 5.0, 4.0)


def test_matches_the_ratio_catalogue():
    """Same lines, in the same order, through the same named points as h2s_print.ratios."""
    ratios = pytest.importorskip("h2s_print.ratios")
    face = Face(BOX, 1, "lo")
    for axis in face.in_axes:
        for entry in ratios.CATALOGUE:
            con = construct(face, axis, entry.ratio)
            assert con.guide_lines == entry.guide_lines == guide_lines(entry.ratio)
            # the catalogue's face: A, B = A + axis extent, D = A + other extent
            a, b, _, d = (dict(con.points)[n] for n in "ABCD")
            for step, line in zip(entry.construction, con.lines):
                assert line.key == step.kind and line.names == (step.start, step.end)
                assert np.allclose(line.start, ratios.face_point(step.start, a, b, d))
                assert np.allclose(line.end, ratios.face_point(step.end, a, b, d))
            assert set(GUIDE_LINES) == {e.ratio for e in ratios.CATALOGUE}


def test_unsupported_input_is_a_bug():
    face = Face(BOX, 2, "hi")
    with pytest.raises(ValueError, match="ratio 0.2"):
        construct(face, 0, 0.2)
    with pytest.raises(ValueError, match="not in the face"):
        construct(face, 2, 0.5)
    assert ratio_key(1 / 3) == Fraction(1, 3) and ratio_key(0.3333333333333) == Fraction(1, 3)


def test_sketch_made_once_per_ratio_is_the_construction_made_afresh():
    """construct() maps a sketch made once per ratio (``_sketch``, its points as floats); on
    seeded boxes (a -0.0 among their coordinates) it is the construction of a fresh
    ``_Sketch`` in exact fractions mapped point by point, to the bit."""
    from h2s_print.constructions import _BUILDERS, _Sketch

    rng = np.random.default_rng(7)
    boxes = [BOX, ((-0.0, -1.5, 0.0), (2.0, 0.0, 3.25))]
    boxes += [tuple(map(tuple, np.sort(rng.normal(size=(2, 3)) * 40.0, axis=0)))
              for _ in range(4)]
    for box in boxes:
        for face in box_faces(box):
            for axis in face.in_axes:
                for r in RATIOS:
                    sk = _Sketch()
                    _BUILDERS[r](sk)

                    def to3d(name, face=face, axis=axis, sk=sk):
                        s, t = sk.at[name]
                        return face.point(s, t) if axis == face.in_axes[0] else face.point(t, s)

                    got = construct(face, axis, float(r))
                    want = [to3d(n) for n in ("A", "B", "C", "D", *sk.made)]
                    assert [p for _, p in got.points] == want
                    assert [str(p) for _, p in got.points] == [str(p) for p in want]  # -0.0
                    assert [(ln.start, ln.end, ln.names) for ln in got.lines] == [
                        (to3d(a), to3d(b), (a, b)) for _, _, a, b, _ in sk.lines]


def test_align():
    ln = align((1, 2, 3), (1, 9, 3))
    assert ln.axis == 1 and ln.key == "align" and ln.role == "guide"
    with pytest.raises(ValueError):
        align((1, 2, 3), (2, 9, 3))


# ----------------------------------------------------------------------------- 2D redo


def _random_setups(seed, count):
    rng = np.random.default_rng(seed)
    out = []
    for i in range(count):
        lo = rng.uniform(-20, 20, 3)
        hi = lo + rng.uniform(2, 30, 3)
        box = (tuple(lo), tuple(hi))
        persp = "two-point" if i % 2 == 0 else "three-point"
        el = rng.uniform(-30, 30) if persp == "two-point" else rng.uniform(-70, 70)
        view = ViewSpec(f"v{i}", float(rng.uniform(-180, 180)), float(el),
                        float(rng.uniform(3, 8)), 50.0, persp)
        normal = int(rng.integers(3))
        face = Face(box, normal, ("lo", "hi")[int(rng.integers(2))])
        axis = face.in_axes[int(rng.integers(2))]
        out.append((view, face, axis))
    return out


SETUPS = _random_setups(2024, 24)


def _camera_for(view, face):
    # frame the box grown 2x each way so the extensions are in front of the camera too
    lo, hi = np.array(face.box[0]), np.array(face.box[1])
    size = hi - lo
    pts = [lo - 2 * size, hi + 2 * size]
    corners = np.array([[a[0], b[1], c[2]] for a in pts for b in pts for c in pts])
    return make_camera(view, corners, A4)


def _projected_frame(cam, face, axis):
    """Projected local corners a=(0,0), b=(1,0), c=(1,1), d=(0,1) (s along axis)."""
    def at(s, t):
        fu, fv = (s, t) if axis == face.in_axes[0] else (t, s)
        return _h(cam.project([face.point(fu, fv)])[0])
    return at(0, 0), at(1, 0), at(1, 1), at(0, 1)


def _redo_2d(a, b, c, d, ratio):
    """The construction on paper, with a ruler: returns the homogeneous point where the
    result line meets the (extended) projected edge A-B (S<ratio>)."""
    ab, dc = _join(a, b), _join(d, c)
    vp_t = np.cross(_join(a, d), _join(b, c))  # where the AD-direction edges meet (maybe at inf)
    vp_s = np.cross(ab, dc)
    centre = np.cross(_join(a, c), _join(b, d))
    half = _join(centre, vp_t)
    s_half, t_half = np.cross(half, ab), np.cross(half, dc)
    cross = _join(centre, vp_s)
    e, f = np.cross(cross, _join(a, d)), np.cross(cross, _join(b, c))  # midpoints of AD, BC
    if ratio == Fraction(1, 2):
        return s_half
    if ratio == Fraction(1, 4):
        q1 = np.cross(_join(a, t_half), _join(s_half, d))
        return np.cross(_join(q1, vp_t), ab)
    if ratio == Fraction(1, 3):
        i1 = np.cross(_join(c, e), _join(b, d))  # paper Fig. 3c
        return np.cross(_join(i1, vp_t), ab)
    if ratio == Fraction(2):
        return np.cross(_join(d, f), ab)
    if ratio == Fraction(3, 2):
        return np.cross(_join(t_half, f), ab)
    raise AssertionError(ratio)


@pytest.mark.parametrize("view,face,axis", SETUPS)
@pytest.mark.parametrize("ratio", [Fraction(1, 2), Fraction(1, 3), Fraction(1, 4),
                                   Fraction(2), Fraction(3, 2)])
def test_construction_redone_on_paper_lands_on_the_projected_ratio(view, face, axis, ratio):
    cam = _camera_for(view, face)
    con = construct(face, axis, ratio)
    a, b, c, d = _projected_frame(cam, face, axis)
    got = _pt(_redo_2d(a, b, c, d, ratio))
    want = cam.project([con.result.start])[0]  # S<ratio>, on edge AB (extended)
    assert math.dist(got, want) < TOL_MM
    # the mirrored ratio (2/3, 3/4, -1, -1/2) done on the mirrored frame lands on its own too
    mirrored = construct(face, axis, 1 - ratio)
    got_m = _pt(_redo_2d(b, a, d, c, ratio))
    assert math.dist(got_m, cam.project([mirrored.result.start])[0]) < TOL_MM


@pytest.mark.parametrize("view,face,axis", SETUPS[:8])
def test_every_construction_point_projects_onto_its_lines(view, face, axis):
    """Incidence survives projection: each named point lies on the projected lines through
    it (within 0.05 mm), e.g. I1 on the line C-E, the diagonal B-D and the 1/3 line."""
    cam = _camera_for(view, face)
    for r in RATIOS:
        con = construct(face, axis, r)
        for name, p in con.points:
            through = [ln for ln in con.lines if _on_segment_line(p, ln, tol=1e-9)]
            if name not in "ABCD":  # every made point is on at least one line drawn
                assert through, (r, name)
            if name in ("O", "Q1", "Q3", "I1", "I2"):  # made by two lines, used by a third
                assert len(through) >= 3, (r, name)
            pm = cam.project([p])[0]
            for ln in through:
                s, e = cam.project([ln.start, ln.end])
                dist = abs(_cross2(e - s, pm - s)) / np.linalg.norm(e - s)
                assert dist < TOL_MM


# ----------------------------------------------------------------------------- ellipses


def _inside_convex(poly, p, tol):
    """Signed distances of p from each edge of a convex polygon (positive inside)."""
    out = []
    n = len(poly)
    orient = np.sign(sum(_cross2(poly[i], poly[(i + 1) % n]) for i in range(n)))
    for i in range(n):
        s, e = poly[i], poly[(i + 1) % n]
        out.append(orient * _cross2(e - s, p - s) / np.linalg.norm(e - s))
    return min(out) >= -tol, out


@pytest.mark.parametrize("view,face,axis", SETUPS)
def test_ellipse_touches_its_face_at_the_perspective_midpoints(view, face, axis):
    cam = _camera_for(view, face)
    ell = ellipse_on_face(face, cam)
    assert ell.points_mm.shape == (96, 2) and ell.points3d.shape == (96, 3)
    quad = cam.project(face.corners)
    # projected 3D edge midpoints (not the 2D midpoints of the projected edges)
    a, b, c, dd = face.corners
    mids = cam.project([(np.add(b, c)) / 2, np.add(c, dd) / 2, np.add(dd, a) / 2,
                        np.add(a, b) / 2])
    assert np.allclose(ell.touch_mm, mids, atol=1e-9)
    poly = np.asarray(ell.points_mm)
    for m in mids:  # on the polyline
        seg = [_dist_to_segment(m, poly[i], poly[(i + 1) % len(poly)]) for i in range(len(poly))]
        assert min(seg) < TOL_MM
    # the same points by ruler: lines from the projected centre toward the VPs of the face
    # edges meet the projected edges there
    ha, hb, hc, hd = (_h(p) for p in quad)
    centre = np.cross(_join(ha, hc), _join(hb, hd))
    assert math.dist(_pt(centre), ell.centre_mm) < TOL_MM
    vp_u = np.cross(_join(ha, hb), _join(hd, hc))
    vp_v = np.cross(_join(ha, hd), _join(hb, hc))
    ruler = [np.cross(_join(centre, vp_u), _join(hb, hc)),  # line along u meets edge BC
             np.cross(_join(centre, vp_v), _join(hc, hd)),
             np.cross(_join(centre, vp_u), _join(hd, ha)),
             np.cross(_join(centre, vp_v), _join(ha, hb))]
    for r, m in zip(ruler, mids):
        assert math.dist(_pt(r), m) < TOL_MM
    # inside the projected face (tangent to its edges, never crossing them)
    size = np.ptp(quad, axis=0).max()
    for p in poly:
        ok, _ = _inside_convex(quad, p, tol=1e-9 * size)
        assert ok
    # an exact conic: all 96 points satisfy one quadratic equation (smallest singular value
    # of the design matrix [x^2, xy, y^2, x, y, 1] vanishes, points normalised to O(1))
    q = (poly - poly.mean(axis=0)) / size
    design = np.column_stack([q[:, 0] ** 2, q[:, 0] * q[:, 1], q[:, 1] ** 2, q[:, 0], q[:, 1],
                              np.ones(len(q))])
    sv = np.linalg.svd(design, compute_uv=False)
    assert sv[-1] < 1e-9 * sv[0]


def _dist_to_segment(p, s, e):
    d = e - s
    t = np.clip(np.dot(p - s, d) / np.dot(d, d), 0.0, 1.0)
    return float(np.linalg.norm(p - (s + t * d)))


def test_ellipse_3d_is_the_inscribed_ellipse():
    face = Face(BOX, 2, "hi")  # x 1..5, y 2..5: semi-axes 2 and 1.5 about (3, 3.5) at z = 4
    cam = make_camera(ViewSpec("v"), np.array(box_faces(BOX)[0].corners + face.corners), A4)
    ell = ellipse_on_face(face, cam, n=8)
    p = ell.points3d
    assert np.allclose(((p[:, 0] - 3) / 2) ** 2 + ((p[:, 1] - 3.5) / 1.5) ** 2, 1.0)
    assert np.all(p[:, 2] == 4.0)
    assert tuple(p[0]) == (5.0, 3.5, 4.0) and tuple(p[2]) == (3.0, 5.0, 4.0)  # θ = 0, 90 deg
    assert [ln.role for ln in ell.lines] == ["construction", "construction", "guide", "guide"]
    with pytest.raises(ValueError):
        ellipse_on_face(face, cam, n=30)


def test_ellipse_behind_the_camera_is_an_error():
    cam = make_camera(ViewSpec("v", azimuth_deg=0, elevation_deg=0),
                      np.array(Face(BOX, 2, "hi").corners), A4)
    behind = Face(((0.0, -100.0, 0.0), (1.0, -99.0, 1.0)), 2, "hi")  # far behind, at y = -100
    with pytest.raises(RenderError, match="behind"):
        ellipse_on_face(behind, cam)


# ----------------------------------------------------------------------------- equal spacing


@pytest.mark.parametrize("view,face,axis", SETUPS[:12])
@pytest.mark.parametrize("gap", [0.0, 0.35, 1.5])
def test_equal_spacing_redone_on_paper_lands_on_each_next_box(view, face, axis, gap):
    """Boxes 2, 3 ... of a row at equal spacing, placed with a ruler from the two before: on
    paper, the line from the end of box k-2 on the top line through the end of box k-1 on the
    middle line (the line through the first face's diagonal crossing toward the row's
    vanishing point) meets the bottom line at the projected end of box k (0.05 mm)."""
    lo, hi = face.box
    length = hi[axis] - lo[axis]
    step = length * (1 + gap)
    row = [(lo[axis] + k * step, hi[axis] + k * step) for k in range(4)]
    sp = equal_spacing(face, axis, row)
    across = sp.across
    span = list(map(list, face.box))
    span[1][axis] = row[-1][1]
    cam = _camera_for(view, Face((tuple(span[0]), tuple(span[1])), face.normal, face.end))

    def at(x, y):  # a point of the face plane, projected, homogeneous
        p = [0.0, 0.0, 0.0]
        p[face.normal], p[axis], p[across] = face.coord, x, y
        return _h(cam.project([p])[0])

    b_lo, b_hi = lo[across], hi[across]
    # the middle line, redone: diagonals of the first face, then toward the row's vanishing point
    a2, b2, c2, d2 = (at(row[0][0], b_lo), at(row[0][1], b_lo), at(row[0][1], b_hi),
                      at(row[0][0], b_hi))
    centre = np.cross(_join(a2, c2), _join(b2, d2))
    bottom, top = _join(a2, b2), _join(d2, c2)
    middle = _join(centre, np.cross(bottom, top))
    for k in range(2, 4):
        for e in (0, 1):
            start = at(row[k - 2][e], b_hi)
            edge = _join(at(row[k - 1][e], b_lo), at(row[k - 1][e], b_hi))
            through = np.cross(middle, edge)
            got = _pt(np.cross(_join(start, through), bottom))
            want = _pt(at(row[k][e], b_lo))
            assert math.dist(got, want) < TOL_MM, (k, e)
            # and the construction's own 3D points are those
            end = sp.ends[k - 2][e]
            assert np.allclose(end.end, [face.coord if i == face.normal else
                                         row[k][e] if i == axis else b_lo for i in range(3)])
            assert math.dist(_pt(_h(cam.project([end.through])[0])), _pt(through)) < TOL_MM
    assert len(sp.lines) == 5 + 4 * 2


def test_equal_spacing_lands_where_the_spacing_says_even_when_it_is_uneven():
    """The construction is exact geometry, not a fit: with uneven boxes its end is
    2 e(k-1) - e(k-2), which is why the sequence stage only uses it on even rows."""
    face = Face(BOX, 1, "lo")
    sp = equal_spacing(face, 0, [(1.0, 5.0), (7.0, 11.0), (100.0, 104.0)])
    assert sp.ends[0][0].end[0] == 13.0 and sp.ends[0][1].end[0] == 17.0
    with pytest.raises(ValueError):
        equal_spacing(face, 1, [(1.0, 5.0)] * 3)  # axis 1 is the face's normal
    with pytest.raises(ValueError):
        equal_spacing(face, 0, [(1.0, 5.0), (7.0, 11.0)])
