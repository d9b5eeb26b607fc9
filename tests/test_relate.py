"""Stage 3, relate: coplanar, coaxial and bisector relations within a size-relative tolerance."""

from __future__ import annotations

import random

import pytest

from h2s_print.errors import ModelError
from h2s_print.relate import PLANE_GAP, detect_relations
from h2s_print.types import RELATION_PREFERENCE, Primitive, as_box


def _cuboid(name, lo, hi) -> Primitive:
    return Primitive(name, "cuboid", None, as_box(lo, hi), 0.0, {})


def _round(name, kind, axis, centre, radius, lo, hi) -> Primitive:
    """A cylinder (or square-ended frustum) along ``axis``: centre (u, v), extent [lo, hi]."""
    others = [k for k in range(3) if k != axis]
    blo, bhi = [0.0] * 3, [0.0] * 3
    blo[axis], bhi[axis] = lo, hi
    for k, c in zip(others, centre):
        blo[k], bhi[k] = c - radius, c + radius
    detail = ({"radius": radius, "centre": list(centre)} if kind == "cylinder" else
              {"lo_half": [radius, radius], "hi_half": [radius / 2, radius / 2],
               "centre": list(centre)})
    return Primitive(name, kind, axis, as_box(blo, bhi), 0.0, detail)


def _of(rels, a, b, kind=None):
    return [r for r in rels if (r.a, r.b) == (a, b) and (kind is None or r.type == kind)]


# Two 1 x 1 x 1 cubes: box diagonal sqrt(3) = 1.732, so tol = 0.02 * 1.732 = 0.03464.
TOL = 0.02 * 3 ** 0.5


def test_tolerance_is_relative_to_the_smaller_part():
    big = _cuboid("big", (0, 0, 0), (10, 10, 10))  # diagonal 17.32
    small = _cuboid("small", (10, 0, 0), (11, 1, 1))  # diagonal 1.732: the smaller one counts
    rels = detect_relations([big, small])
    assert rels and all(r.tolerance == pytest.approx(TOL) for r in rels)


def test_coplanar_faces_found_with_ends_and_coord():
    a = _cuboid("a", (0, 0, 0), (1, 1, 1))
    b = _cuboid("b", (1, 0, 0.01), (2, 1, 1.5))  # beside a, floor 0.01 up (< tol 0.0346)
    rels = detect_relations([b, a])
    floor = [r for r in _of(rels, "a", "b", "coplanar") if r.axis == 2]
    assert [(r.detail["a_end"], r.detail["b_end"]) for r in floor] == [("lo", "lo")]
    assert floor[0].detail["coord"] == pytest.approx(0.005)  # mean of 0 and 0.01
    # a's x-hi face touches b's x-lo face: one plane x = 1
    touch = [r for r in _of(rels, "a", "b", "coplanar") if r.axis == 0]
    assert [(r.detail["a_end"], r.detail["b_end"], r.detail["coord"]) for r in touch] == [
        ("hi", "lo", 1.0)]


@pytest.mark.parametrize("factor, found", [(0.99, True), (1.01, False)])
def test_coplanar_near_miss(factor, found):
    a = _cuboid("a", (0, 0, 0), (1, 1, 1))
    dz = factor * TOL
    b = _cuboid("b", (1.0, 0, dz), (2.0, 1, 2))  # beside a, its floor dz up
    floor = [r for r in _of(detect_relations([a, b]), "a", "b", "coplanar")
             if r.axis == 2 and r.detail["a_end"] == "lo"]
    assert bool(floor) is found


@pytest.mark.parametrize("factor, found", [(0.99, True), (1.01, False)])
def test_faces_in_one_plane_are_coplanar_only_when_near(factor, found):
    # both stand on z = 0; b's diagonal sqrt(1 + 1 + 4) = 2.449 is the larger, so the faces may
    # be up to PLANE_GAP * 2.449 = 1.2247 apart in the plane (a gap of 0.5 is fine: two boxes
    # standing side by side on one floor)
    limit = PLANE_GAP * 6 ** 0.5
    assert PLANE_GAP == 0.5
    a = _cuboid("a", (0, 0, 0), (1, 1, 1))
    g = factor * limit
    b = _cuboid("b", (1 + g, 0, 0), (2 + g, 1, 2))
    floor = [r for r in _of(detect_relations([a, b]), "a", "b", "coplanar") if r.axis == 2]
    assert bool(floor) is found
    assert [r for r in _of(detect_relations([a, _cuboid("c", (1.5, 0, 0), (2.5, 1, 2))]), "a", "c",
                                            "coplanar") if r.axis == 2]


def test_the_gap_in_the_plane_is_euclidean():
    # 0.9 apart in x and in y: each alone is within 1.2247, together sqrt(0.81 + 0.81) = 1.273
    a = _cuboid("a", (0, 0, 0), (1, 1, 1))
    b = _cuboid("b", (1.9, 1.9, 0), (2.9, 2.9, 2))
    assert not [r for r in _of(detect_relations([a, b]), "a", "b", "coplanar") if r.axis == 2]
    c = _cuboid("c", (1.8, 1.8, 0), (2.8, 2.8, 2))  # sqrt(0.64 + 0.64) = 1.131: near enough
    assert [r for r in _of(detect_relations([a, c]), "a", "c", "coplanar") if r.axis == 2]


@pytest.mark.parametrize("offset, found", [(0.99, True), (1.01, False)])
def test_coaxial_cylinders_and_near_miss(offset, found):
    # radius 0.5, length 2 along y: box 1 x 2 x 1, diagonal sqrt(6) = 2.449, tol = 0.04899
    tol = 0.02 * 6 ** 0.5
    a = _round("a", "cylinder", 1, (0.0, 0.0), 0.5, 0.0, 2.0)
    # b's axis line is offset * tol away, diagonally (3-4-5 split over x and z)
    d = offset * tol
    b = _round("b", "frustum", 1, (0.6 * d, 0.8 * d), 0.5, 2.0, 4.0)
    rels = detect_relations([a, b])
    coax = _of(rels, "a", "b", "coaxial")
    assert bool(coax) is found
    if found:
        assert coax[0].axis == 1
        assert coax[0].detail["line"] == pytest.approx([0.3 * d, 0.4 * d])


def test_coaxial_needs_a_rotational_primitive_on_the_axis():
    cyl = _round("a", "cylinder", 2, (0.0, 0.0), 0.5, 0.0, 1.0)
    # a box centred on the cylinder's axis shares its axis line (its box centre line)
    box = _cuboid("b", (-0.5, -0.5, 1), (0.5, 0.5, 2))
    other_axis = _round("c", "cylinder", 0, (0.5, 0.5), 0.5, -0.5, 0.5)
    off_box = _cuboid("d", (0.3, -0.5, 1), (1.3, 0.5, 2))  # centre line 0.8 off the axis
    plain = _cuboid("e", (-0.5, -0.5, 2), (0.5, 0.5, 3))  # two cuboids: never coaxial
    rels = detect_relations([cyl, box, other_axis, off_box, plain])
    coax = {(r.a, r.b, r.axis) for r in rels if r.type == "coaxial"}
    assert coax == {("a", "b", 2), ("a", "e", 2)}


@pytest.mark.parametrize("factor, found", [(0.99, True), (1.01, False)])
def test_bisector_and_near_miss(factor, found):
    a = _cuboid("a", (0, 0, 0), (1, 1, 1))  # mid-plane x = 0.5
    # b is 2 wide in x, 3 up, so no face meets a's; its x mid-plane is 0.5 + factor * tol
    s = factor * TOL
    b = _cuboid("b", (-0.5 + s, 0.2, 3), (1.5 + s, 0.6, 4))
    rels = detect_relations([a, b])
    bis = [r for r in _of(rels, "a", "b", "bisector") if r.axis == 0]
    assert bool(bis) is found
    if found:
        assert bis[0].detail["coord"] == pytest.approx(0.5 + s / 2)


def test_exactly_one_preserved_per_pair_by_preference():
    # a, b: side by side on one floor with centred y (coplanar z, coplanar x, bisector y)
    a = _cuboid("a", (0, 0, 0), (1, 1, 1))
    b = _cuboid("b", (1, 0.2, 0), (2, 0.8, 0.5))
    # c, d: coaxial cylinders along z: the x and y bisectors are implied by (folded into) the
    # coaxial relation, so coaxial is what is preserved
    c = _round("c", "cylinder", 2, (5.0, 5.0), 0.5, 0.0, 1.0)
    d = _round("d", "cylinder", 2, (5.0, 5.0), 0.3, 1.0, 3.0)
    # e, f: only coplanar faces (a floor and a touching wall), different mid-planes everywhere
    e = _cuboid("e", (10, 10, 0), (11, 11, 1))
    f = _cuboid("f", (11, 10.5, 0), (13, 12, 3))
    rels = detect_relations([f, e, d, c, b, a])
    pairs = {(r.a, r.b) for r in rels}
    for pair in pairs:
        mine = [r for r in rels if (r.a, r.b) == pair]
        first = mine[0]  # the preferred relation of the pair comes first
        assert first.detail["preserved"]
        best = min(RELATION_PREFERENCE[r.type] for r in mine)
        assert RELATION_PREFERENCE[first.type] == best
        # besides it, exactly the coplanar relations of touching faces are preserved
        for r in mine[1:]:
            touching = r.detail.get("contact", False) or r.detail.get("flush", False)
            assert r.detail["preserved"] == touching
    kept = {(r.a, r.b): r for r in reversed(rels) if r.detail["preserved"]}
    assert (kept["a", "b"].type, kept["a", "b"].axis) == ("bisector", 1)
    assert (kept["c", "d"].type, kept["c", "d"].axis) == ("coaxial", 2)
    assert not [r for r in _of(rels, "c", "d", "bisector") if r.axis != 2]  # implied, not listed
    # e, f: coplanar on x (e.hi meets f.lo at x = 11) before z (floor), lowest axis first
    ef = kept["e", "f"]
    assert (ef.type, ef.axis, ef.detail["a_end"], ef.detail["b_end"]) == ("coplanar", 0, "hi", "lo")
    assert len(_of(rels, "e", "f")) == 2  # all coplanar face pairs are kept


def test_touching_faces_are_preserved_as_contact_or_flush():
    floor = _cuboid("floor", (0, 0, 0), (4, 4, 1))
    box = _cuboid("box", (1, 1, 1), (2, 2, 2))          # stands on the floor: contact on z
    side = _cuboid("side", (4, 0, 0), (5, 4, 1))         # beside the floor, same top: flush on z
    away = _cuboid("away", (9, 0, 0), (10, 4, 1))        # same top, 4 away: coplanar, not touching
    rels = detect_relations([floor, box, side, away])
    contact = [r for r in _of(rels, "box", "floor") if r.detail.get("contact")]
    assert [(r.axis, r.detail["a_end"], r.detail["b_end"]) for r in contact] == [(2, "lo", "hi")]
    assert all(r.detail["preserved"] for r in contact)
    flush = [r for r in _of(rels, "floor", "side") if r.detail.get("flush")]
    # top and bottom, front and back faces flush
    assert {(r.axis, r.detail["a_end"]) for r in flush} == {(1, "lo"), (1, "hi"), (2, "lo"),
                                                             (2, "hi")}
    assert all(r.detail["preserved"] for r in flush)
    far = _of(rels, "away", "floor")
    assert not any(r.detail.get("flush") or r.detail.get("contact") for r in far)
    assert sum(r.detail["preserved"] for r in far) <= 1  # only the pair's preferred relation


def test_ends_follow_name_order_and_output_is_deterministic():
    lower = _cuboid("zeta", (0, 0, 1), (1, 1, 2))  # its lo face meets alpha's hi face at z = 1
    upper = _cuboid("alpha", (0, 0, 0), (1, 1, 1))
    rels = detect_relations([lower, upper])
    top = [r for r in rels if r.type == "coplanar" and r.axis == 2]
    assert [(r.a, r.b, r.detail["a_end"], r.detail["b_end"]) for r in top] == [
        ("alpha", "zeta", "hi", "lo")]
    prims = [_cuboid(f"p{i}", (i * 0.9, 0, 0), (i * 0.9 + 1, 1, 1 + i % 2)) for i in range(6)]
    expect = detect_relations(prims)
    shuffled = prims[:]
    random.Random(7).shuffle(shuffled)
    assert detect_relations(shuffled) == expect
    keys = [(r.a, r.b, RELATION_PREFERENCE[r.type], r.axis,
             ("lo", "hi").index(r.detail.get("a_end", "lo")),
             ("lo", "hi").index(r.detail.get("b_end", "lo"))) for r in expect]
    assert keys == sorted(keys)


def test_custom_parts_are_not_related():
    a = _cuboid("a", (0, 0, 0), (1, 1, 1))
    blob = Primitive("blob", "custom", None, as_box((0, 0, 0), (1, 1, 1)), 0.2, {})
    assert detect_relations([a, blob]) == ()


def test_duplicate_names_are_a_model_error():
    a = _cuboid("a", (0, 0, 0), (1, 1, 1))
    with pytest.raises(ModelError, match="repeated: a"):
        detect_relations([a, a])


def test_an_end_sunk_into_an_unrelated_part_is_a_contact_at_its_face():
    # The desk's legs reach into the middle of the desk top's thickness, related to nothing:
    # the leg's top gets a coplanar relation with the top's underside, its tolerance the depth
    # sunk (the hidden length may go), marked "embedded" and kept (preserved).  The relation
    # holds on the inputs, as the selection requires.
    from h2s_print.candidates import relation_holds

    top = _cuboid("top", (-5, -3, 10), (5, 3, 11))
    leg = _cuboid("leg", (-4.2, 0.8, 0), (-3.8, 1.2, 10.5))  # 0.5 into a 1-thick top
    rels = detect_relations([top, leg])
    sunk = [r for r in rels if r.detail.get("embedded")]
    assert len(sunk) == 1
    (r,) = sunk
    assert (r.a, r.b, r.type, r.axis) == ("leg", "top", "coplanar", 2)
    assert (r.detail["a_end"], r.detail["b_end"]) == ("hi", "lo")
    assert r.tolerance == pytest.approx(0.5) and r.detail["coord"] == pytest.approx(10.0)
    assert r.detail["preserved"] and relation_holds(r, leg.box, top.box)
    # ... but only where nothing else relates them (a pair related otherwise is anchored
    # through that relation), so not a centred leg; a leg whose top is on the underside
    # within the tolerance is coplanar already, and one that passes right through, or sticks
    # out across the top, is not sunk into it
    flush = _cuboid("leg", (-4.2, 0.8, 0), (-3.8, 1.2, 10.01))
    assert not any(r.detail.get("embedded") for r in detect_relations([top, flush]))
    through = _cuboid("leg", (-4.2, 0.8, 0), (-3.8, 1.2, 12))
    wide = _cuboid("leg", (-6, 0.8, 0), (-3.8, 1.2, 10.5))
    centred = _cuboid("leg", (-4.2, -0.2, 0), (-3.8, 0.2, 10.5))  # a bisector relates them
    for other in (through, wide, centred):
        assert not any(r.detail.get("embedded") for r in detect_relations([top, other]))
