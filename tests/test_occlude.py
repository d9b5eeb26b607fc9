"""Scaffold occlusion by the drawn primitives (h2s_print.occlude), checked by brute force."""

from __future__ import annotations

import numpy as np
import pytest

from h2s_print.occlude import box_solid, cylinder_solid, hidden, outward_normals, polyhedron, runs


def _inside_box(x, lo, hi):
    return np.all((x > lo) & (x < hi), axis=-1)


def _inside_cylinder(x, lo, hi, axis):
    u, v = (a for a in range(3) if a != axis)
    c = (np.asarray(lo) + hi) / 2
    r = (np.asarray(hi) - lo) / 2
    q = ((x[..., u] - c[u]) / r[u]) ** 2 + ((x[..., v] - c[v]) / r[v]) ** 2
    return (q < 1) & (x[..., axis] > lo[axis]) & (x[..., axis] < hi[axis])


def _brute(points, eye, inside, steps=4000):
    """Hidden when some sample strictly between the eye and the point (not within 0.1 % of the
    point) lies strictly inside the solid."""
    t = np.linspace(0.0, 0.999, steps)[None, :, None]
    seg = eye + t * (points[:, None, :] - eye)
    return inside(seg).any(axis=1)


@pytest.mark.parametrize("seed", range(3))
def test_box_and_cylinder_hide_what_brute_force_says(seed):
    rng = np.random.default_rng(seed)
    lo, hi = np.array([-1.0, -2.0, 0.0]), np.array([1.0, 2.0, 3.0])
    eye = np.array([6.0, -5.0, 8.0]) * rng.uniform(0.8, 1.2, 3)
    pts = rng.uniform(-3, 4, (400, 3))
    for solid, inside in ((box_solid((lo, hi)), lambda x: _inside_box(x, lo, hi)),
                          (cylinder_solid((lo, hi), 2),
                           lambda x: _inside_cylinder(x, lo, hi, 2))):
        got = hidden(pts, eye, [solid])
        want = _brute(pts, eye, inside)
        # brute force samples the segment: it can miss a graze shorter than its step
        assert np.mean(got == want) > 0.99
        assert not (want & ~got).any()  # whatever sampling finds inside, the exact test does


def test_points_on_surfaces_facing_the_eye_are_seen_and_the_far_side_is_not():
    box = box_solid(((0, 0, 0), (1, 1, 1)))
    eye = (0.5, 0.5, 5.0)
    pts = np.array([(0.5, 0.5, 1.0), (0.2, 0.9, 1.0), (0.5, 0.5, 0.0), (0.5, 0.5, 0.5),
                    (2.0, 0.5, 0.5)])
    assert hidden(pts, eye, [box]).tolist() == [False, False, True, True, False]
    # a cylinder's far rim from above and aside: the near half seen, the far half hidden
    cyl = cylinder_solid(((-1, -1, 0), (1, 1, 2)), 2)
    theta = np.linspace(0, 2 * np.pi, 72, endpoint=False)
    rim = np.stack([np.cos(theta), np.sin(theta), np.zeros_like(theta)], axis=1)
    h = hidden(rim, (6.0, 0.0, 10.0), [cyl])
    assert not h[np.cos(theta) > 0.2].any() and h[np.cos(theta) < -0.2].all()
    assert not hidden(rim + (0, 0, 2), (6.0, 0.0, 10.0), [cyl]).any()  # the near (top) rim


def test_a_frustum_polyhedron_matches_its_half_spaces():
    # a truncated pyramid: base 2 x 2 at z = 0, top 1 x 1 at z = 1
    pts = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0],
                    [-.5, -.5, 1], [.5, -.5, 1], [.5, .5, 1], [-.5, .5, 1]], float)
    faces = [(0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    solid = polyhedron(pts, faces)
    assert np.all(solid.normals @ np.array([0, 0, 0.5]) < solid.offsets)  # a middle point is inside
    assert np.allclose(np.max(pts @ solid.normals.T - solid.offsets, axis=1), 0.0)
    eye = np.array([0.0, 0.0, 5.0])
    # seen from above: the top face is seen, a point of the base under it is hidden, a point
    # on the base outside the top's shadow but under a slanted side is hidden too
    got = hidden(np.array([(0, 0, 1), (0, 0, 0), (0.9, 0, 0), (1.5, 0, 0)], float), eye, [solid])
    assert got.tolist() == [False, True, True, False]


def test_runs_cut_a_closed_loop_where_the_mask_changes_and_join_up():
    theta = np.linspace(0, 2 * np.pi, 13)
    loop = np.stack([np.cos(theta), np.sin(theta), 0 * theta], axis=1)
    loop[-1] = loop[0]
    mask = np.array([0, 0, 1, 1, 1, 0, 0, 0, 1, 0, 0, 0, 0], bool)
    out = runs(loop, mask)
    assert [m for m, _ in out].count(True) == 2 and [m for m, _ in out].count(False) == 2
    for (_, a), (_, b) in zip(out, out[1:] + out[:1]):
        assert np.allclose(a[-1], b[0])  # each run ends where the next starts
    assert sum(len(r) - 1 for _, r in out) == 12  # every segment of the loop, once
    whole = runs(loop, np.zeros(13, bool))
    assert len(whole) == 1 and whole[0][0] is False and len(whole[0][1]) == 13


def test_hidden_spans_is_the_shadow_of_a_box_worked_out_by_hand():
    """A segment under a box, seen from above: the eye at (0, 0, 10), the box
    [-1, 1] x [-1, 1] x [0, 1], the segment from (-3, 0, -1) to (3, 0, -1).  The sight line
    to (x, 0, -1) meets the box's top (z = 1) at x * 9 / 11, so the box hides |x| < 11 / 9:
    s in ((3 - 11/9) / 6, (3 + 11/9) / 6).  A segment beside the box is hidden nowhere; one
    in the box's top face is seen (on a surface facing the eye), and one sunk into the box
    by less than ``depth`` counts as seen, deeper as hidden."""
    from h2s_print.occlude import box_solid, hidden_spans

    eye = (0.0, 0.0, 10.0)
    box = box_solid(((-1.0, -1.0, 0.0), (1.0, 1.0, 1.0)))
    (s0, s1), = hidden_spans((-3.0, 0.0, -1.0), (3.0, 0.0, -1.0), eye, [box], 1e-9)
    want = ((3 - 11 / 9) / 6, (3 + 11 / 9) / 6)
    assert abs(s0 - want[0]) < 1e-6 and abs(s1 - want[1]) < 1e-6
    assert hidden_spans((-3.0, 5.0, -1.0), (3.0, 5.0, -1.0), eye, [box], 1e-9) == []
    assert hidden_spans((-0.5, 0.0, 1.0), (0.5, 0.0, 1.0), eye, [box], 1e-9) == []
    assert hidden_spans((-0.5, 0.0, 0.99), (0.5, 0.0, 0.99), eye, [box], 0.02) == []
    (s0, s1), = hidden_spans((-0.5, 0.0, 0.9), (0.5, 0.0, 0.9), eye, [box], 0.02)
    assert (s0, s1) == (0.0, 1.0)
    assert hidden_spans((-3.0, 0.0, -1.0), (3.0, 0.0, -1.0), eye, [], 1e-9) == []


def test_boxes_taken_together_hide_what_each_hides():
    """_hidden_deep takes the boxes together (one array operation); the points it finds
    hidden are those some box hides by itself, per :func:`_inside`, on seeded boxes, eyes
    and points (touching and degenerate cases on a coarse grid)."""
    from h2s_print.occlude import _hidden_deep, _inside

    rng = np.random.default_rng(7)
    for trial in range(40):
        boxes = []
        for _ in range(rng.integers(1, 6)):
            lo = rng.integers(-4, 4, 3).astype(float)
            boxes.append(box_solid((lo, lo + rng.integers(0, 4, 3))))
        eye = rng.integers(-9, 10, 3).astype(float) * 2.0
        pts = rng.integers(-6, 7, (60, 3)).astype(float) / 2.0
        depth = float(rng.choice([0.0, 0.1, 1.0]))
        d = pts - eye
        want = np.zeros(len(pts), dtype=bool)
        for b in boxes:
            t0, t1 = _inside(b, eye, d)
            want |= (t1 - t0) * np.linalg.norm(d, axis=1) > depth
        assert (_hidden_deep(pts, eye, boxes, depth) == want).all(), trial


def test_outward_normals_sum_each_edge_in_order():
    """Newell's normal summed over a face's edges at once equals, bit for bit, the sum made
    one edge at a time from zero (the definition), for random faces of any size and scale;
    and it points away from the vertices' centroid."""
    rng = np.random.default_rng(7)
    for _ in range(300):
        k = int(rng.integers(4, 30))
        pts = rng.normal(size=(k, 3)) * 10 ** rng.uniform(-3, 3)
        faces = [tuple(int(i) for i in rng.choice(k, size=int(rng.integers(3, min(k, 10) + 1)),
                                                   replace=False)) for _ in range(4)]
        centre = pts.mean(axis=0)
        for f, (n, fc) in zip(faces, outward_normals(pts, faces)):
            poly = pts[list(f)]
            want = np.zeros(3)
            for i in range(len(poly)):
                want += np.cross(poly[i], poly[(i + 1) % len(poly)])
            if np.dot(want, fc - centre) < 0:
                want = -want
            assert n.tobytes() == want.tobytes()
            assert fc.tobytes() == poly.mean(axis=0).tobytes()
