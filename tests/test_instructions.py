"""Instructions a person can follow (issue 11): lettered points, headline plus sub-steps,
readable part names, repeated parts as one step.

Facts are checked against their definitions: a point a sub-step names lies where the
construction put it (a crossing lies on both lines that make it, a line drawn through a point
passes through it), every letter a sub-step names is drawn on that step's picture at the
projection of its 3D point, labels never overlap or leave the picture, and a group step draws
every member's own box.
"""

from __future__ import annotations

import itertools
import re

import numpy as np
import pytest

from h2s_print import layout as L
from h2s_print import sequence as seq
from h2s_print import sheet as S
from h2s_print.constructions import RATIOS, Face, construct
from h2s_print.instructions import (
    ALPHABET,
    Many,
    Pts,
    brief_specs,
    construction_specs,
    letter_steps,
    spec,
    unique_specs,
)
from h2s_print.plan import build_plan
from h2s_print.sequence import drafts as seq_drafts
from h2s_print.sequence import geometry as seq_geometry
from h2s_print.sequence import words as seq_words

BOX = ((0.0, 0.0, 0.0), (40.0, 30.0, 20.0))


def _vp(axis: int, start=None, end=None) -> str:
    """The phrase for lines along ``axis`` (and, for a line drawn from ``start`` to ``end``,
    the same: these tests read which lines are named, not which way)."""
    return f"toward VP{axis}"


def _render(key, fields):
    return key + ":" + ",".join(f"{k}={v}" for k, v in sorted(fields.items()))


def _on_line(p, a, b, tol=1e-9) -> bool:
    p, a, b = (np.asarray(x, dtype=float) for x in (p, a, b))
    d = b - a
    return float(np.linalg.norm(np.cross(d, p - a))) <= tol * max(1.0, float(np.dot(d, d)))


# ----------------------------------------------------------------------------- sub-steps


@pytest.mark.parametrize("ratio", [float(r) for r in RATIOS])
@pytest.mark.parametrize("normal,axis", [(1, 0), (1, 2), (2, 0), (0, 1)])
def test_substeps_name_every_line_and_their_points_lie_where_the_construction_put_them(
        ratio, normal, axis):
    face = Face(BOX, normal, "lo")
    con = construct(face, axis, ratio)
    specs = construction_specs(con, "body", "front", _vp, 1e-9)
    named = [p for s in specs for _, v in s.fields if isinstance(v, Pts) for p in v.points]

    def is_named(p):
        return any(np.allclose(p, q, atol=1e-9) for q in named)

    # every line the construction draws runs between points the sub-steps name
    for ln in con.lines:
        if ln.key == "extend":  # an edge extended beyond its end: its far end is named later
            assert is_named(ln.start) and is_named(ln.end), (ratio, ln.names)
        else:
            assert is_named(ln.start) and is_named(ln.end), (ratio, ln.key, ln.names)
    for s in specs:
        f = dict(s.fields)
        if s.key in ("through", "from", "cross"):  # the line drawn passes through the point
            (p,), (a, b) = f["point"].points, f["line"].points
            assert _on_line(p, a, b), (ratio, s)
        if s.key in ("diagonals", "half_diagonals"):  # the crossing lies on both diagonals
            (p,) = f["point"].points
            assert _on_line(p, *f["first"].points) and _on_line(p, *f["second"].points), s
        if s.key == "connect":
            (p,) = f["point"].points
            assert _on_line(p, *f["line"].points) and _on_line(p, *f["other"].points), s
        if s.key == "connect_through":  # start, through and the new point are collinear,
            # and the new point lies on the extension of the edge it names
            (a,), (m,), (p,) = f["start"].points, f["through"].points, f["point"].points
            assert _on_line(m, a, p), s
            assert _on_line(p, *f["edge"].points), s
    # the last sub-step draws the resulting guide
    last = dict(specs[-1].fields)["line"].points
    res = (con.result.start, con.result.end)
    assert {tuple(np.round(p, 9)) for p in last} == {tuple(np.round(p, 9)) for p in res}


def test_twins_are_said_once_in_the_plural():
    face = Face(BOX, 1, "lo")
    quarter, three = (construct(face, 0, r) for r in (0.25, 0.75))
    specs = unique_specs(construction_specs(quarter, "body", "front", _vp, 1e-9)
                         + construction_specs(three, "body", "front", _vp, 1e-9),
                         lambda k: k + "_two" if k == "half_diagonals" else k)
    keys = [s.key for s in specs]
    # the diagonals and the half line once, then both halves' diagonals, then both quarter lines
    assert keys == ["diagonals", "through", "half_diagonals_two", "through"]
    last = dict(specs[-1].fields)
    assert isinstance(last["line"], Many) and len(last["line"].items) == 2
    assert isinstance(last["point"], Many) and len(last["point"].items) == 2


@pytest.mark.parametrize("ratio, brief", [(0.5, "half"), (0.25, "quarter"), (2 / 3, "third"),
                                          (2.0, "extend"), (-0.5, "extend_half")])
def test_an_apprentice_reads_the_construction_by_name_and_the_result_line(ratio, brief):
    """An apprentice's picture shows the result line only: the construction's sub-steps
    become one, naming the construction and the line, and no other point is named."""
    face = Face(BOX, 1, "lo")
    con = construct(face, 0, ratio)
    full = construction_specs(con, "body", "front", _vp, 1e-9, "width", ("left side", "right side"))
    short = brief_specs(full, lambda kind, parent, face: f"{parent}'s {face} face")
    assert len(short) == 1 and short[0].key == f"brief_{brief}" and len(full) > 1
    if brief in ("quarter", "third"):  # which of the lines: the end it is nearer
        assert dict(short[0].fields)["near"] == ("left side" if ratio < 0.5 else "right side")
    f = dict(short[0].fields)
    named = [v for _, v in short[0].fields if isinstance(v, (Pts, Many))]
    assert named == [f["line"]]
    # the line is the construction's result
    a, b = f["line"].points
    assert {tuple(np.round(a, 9)), tuple(np.round(b, 9))} == {
        tuple(np.round(con.result.start, 9)), tuple(np.round(con.result.end, 9))}
    if brief.startswith("extend"):
        assert f["beyond"] == ("right side" if ratio > 1 else "left side") and f["dim"] == "width"
    text = seq_words._substep(short[0].key, {**f, "line": "XY"})
    assert "XY" in text and "body's front face" in text


# ----------------------------------------------------------------------------- letters


def test_a_point_keeps_its_letter_while_it_lives_letters_rest_and_skip_i_and_o():
    p = [(float(i), 0.0, 0.0) for i in range(30)]
    steps = [
        [spec("a", line=Pts((p[0], p[1])))],                         # A B
        [spec("b", line=Pts((p[2], p[3])))],                         # C D: A, B still live
        [spec("c", line=Pts((p[0], p[1]))), spec("d", x=Pts((p[4],)))],  # A B again, E new
        [spec("e", line=Pts((p[5], p[6])))],                         # all earlier points done
    ]
    out = letter_steps(steps, 1e-9, _render)
    assert out[0][0] == ["a:line=AB"]
    assert out[1][0] == ["b:line=CD"]
    # C and D are done with, but they named other points on the page just turned: they rest
    assert out[2][0] == ["c:line=AB", "d:x=E"]
    # A, B and E rest now, C and D are free again, but letters never used come first: a
    # letter names a second point only once the alphabet is used up
    assert out[3][0] == ["e:line=FG"]
    assert [n for n, _ in out[2][1]] == ["A", "B", "E"]
    assert "I" not in ALPHABET and "O" not in ALPHABET
    many = letter_steps([[spec("f", lines=Many(tuple(Pts((p[i],)) for i in range(26))))]],
                        1e-9, _render, " ".join)
    letters = many[0][0][0].split("=")[1].split()
    assert letters[:3] == ["A", "B", "C"] and letters[24:] == ["A'", "B'"]
    assert len(set(letters)) == 26


def test_a_letter_names_a_second_point_only_after_the_alphabet_is_used():
    """One new point a step: the first 24 get the 24 letters, then the letter free longest
    comes back (A, whose point ended first), never the one the page before used."""
    p = [(float(i), 0.0, 0.0) for i in range(30)]
    out = letter_steps([[spec("a", x=Pts((p[i],)))] for i in range(30)], 1e-9, _render)
    names = [n for _, labels in out for n, _ in labels]
    assert names[:24] == list(ALPHABET)
    assert names[24:27] == ["A", "B", "C"]


def test_a_primed_letter_comes_before_one_the_page_just_turned_used():
    """The train's chimney guides named E and H as other points on consecutive pages; a
    primed letter is used instead of a resting one."""
    p = [(float(i), 0.0, 0.0) for i in range(60)]
    first = [spec("f", lines=Many(tuple(Pts((p[i],)) for i in range(20))))]   # A .. V
    second = [spec("g", lines=Many(tuple(Pts((p[i],)) for i in range(20, 30))))]
    out = letter_steps([first, second], 1e-9, _render, " ".join)
    letters = out[1][0][0].split("=")[1].split()
    # W X Y Z are neither living nor resting; then primed ones, never a letter of page one
    assert letters[:4] == ["W", "X", "Y", "Z"] and letters[4:] == ["A'", "B'", "C'", "D'",
                                                                    "E'", "F'"]


def test_a_primed_letter_is_not_the_twin_of_a_letter_on_its_page():
    """A read-through took Q' beside Q, in one picture, for an image of Q: where every plain
    letter is taken, the primed letter given is one whose plain letter the page does not
    show (the page before neither), where there is one; and a plain letter given is not the
    twin of a primed one the page shows."""
    p = [(float(i), 0.0, 0.0) for i in range(60)]
    first = [spec("f", lines=Many(tuple(Pts((p[i],)) for i in range(24))))]  # A .. Z
    alive = [(p[i], 2) for i in range(24)]  # their lines stay on the paper to page three
    third = [spec("g", lines=Many((Pts((p[0],)), Pts((p[30],)))))]  # A again, a new point
    out = letter_steps([first, [], third], 1e-9, _render, " ".join, on_paper=alive)
    old, new = out[2][0][0].split("=")[1].split()
    assert old == "A" and new.endswith("'") and new[0] != "A"
    # a point primed on page two, named again on page three beside a new one: plain, not
    # its twin (page one's letters have rested by then)
    second = [spec("g", lines=Many((Pts((p[30],)),)))]
    fourth = [spec("h", lines=Many((Pts((p[30],)), Pts((p[31],)))))]
    out = letter_steps([first, second, [], fourth], 1e-9, _render, " ".join,
                       on_paper=[(p[i], 1) for i in range(24)])
    primed, plain = out[3][0][0].split("=")[1].split()
    assert primed.endswith("'") and not plain.endswith("'") and plain != primed[0]


def test_points_within_tolerance_share_a_letter():
    out = letter_steps([[spec("a", line=Pts(((0, 0, 0), (1e-12, 0, 0))))]], 1e-9, _render)
    assert out[0][0] == ["a:line=AA"]


# ----------------------------------------------------------------------------- on the pages


# ``examples`` (every view and level of the four examples) is conftest's shared fixture.


def _letters_in(substeps) -> set[str]:
    out = set()
    for x in substeps:
        for token in re.findall(r"(?<![A-Za-z'])(?:[A-Z]'*)+(?![a-z])", x):
            out.update(re.findall(r"[A-Z]'*", token))
    return out


def _novice_step_pages(examples):
    """(model, view, view plan, step, its page) over the examples' novice workbooks."""
    for name, (t, plan, views) in examples.items():
        for (view, lv), vp in views.items():
            if lv != "novice":
                continue
            pages = [p for p in L.lay_out_workbook(t.title, vp, t.paper, view_label=view)
                     if p.kind == "steps"]
            for step, page in zip(vp.steps, pages):
                yield name, view, vp, step, page


def _close_up_of(page):
    """(region, close-up) rectangles of a step page's close-up, or None."""
    regions = [it for it in page.items if isinstance(it, L.Rect) and it.role == "close_up_region"]
    closes = [it for it in page.items if isinstance(it, L.Rect) and it.role == "close_up"]
    return (regions[0], closes[0]) if regions and closes else None


def _within(pts, r):
    return bool(np.all(pts >= (r.x_mm - 1e-6, r.y_mm - 1e-6))
                and np.all(pts <= (r.x_mm + r.w_mm + 1e-6, r.y_mm + r.h_mm + 1e-6)))


def _pictures(page, plan):
    """(paper rect on the page, mm per sheet mm) for each step picture of a page."""
    rects = [it for it in page.items if isinstance(it, L.Rect) and it.role == "paper"]
    return [(r, r.w_mm / plan.paper_mm[0]) for r in rects]


def test_a_small_new_part_is_shown_enlarged(examples):
    """A step whose new lines all fit within ``CLOSE_UP_SMALL_MM`` on its picture (a
    read-through: the oven's five buttons were one orange blob 8 mm wide) has a close-up;
    where its letters did not ask for one, the close-up's region holds all those lines and
    magnifies them at least ``CLOSE_UP_MIN_ZOOM`` times."""
    small = held = 0
    for name, view, vp, step, page in _novice_step_pages(examples):
        rect, scale = _pictures(page, vp)[0]
        pts = np.array([p for st in step.strokes for p in st.points_mm], dtype=float)
        if not len(pts):
            continue
        pts = pts * scale + (rect.x_mm, rect.y_mm)  # on the page
        if max(np.ptp(pts[:, 0]), np.ptp(pts[:, 1])) >= L.CLOSE_UP_SMALL_MM:
            continue
        small += 1
        zoom = _close_up_of(page)
        assert zoom is not None, (name, view, step.index)
        r, c = zoom
        if _within(pts, r):
            assert c.w_mm / r.w_mm >= L.CLOSE_UP_MIN_ZOOM - 1e-9
            held += 1
    assert small and held


@pytest.mark.parametrize("level", ["novice", "apprentice"])
def test_every_letter_named_is_drawn_at_its_projection_without_overlap(examples, level):
    """Each letter at its point's projection (through the close-up's magnification when the
    step has one), inside the picture, no two overlapping."""
    checked = zoomed = 0
    for name, (t, plan, views) in examples.items():
        for (view, lv), vp in views.items():
            if lv != level:
                continue
            pages = [p for p in L.lay_out_workbook(t.title, vp, t.paper, view_label=view)
                     if p.kind == "steps"]
            per = 1 if level == "novice" else 2
            P = vp.camera.projection_mm
            for k, step in enumerate(vp.steps):
                page = pages[k // per]
                rect, scale = _pictures(page, vp)[k % per]
                box = (rect.x_mm, rect.y_mm, rect.x_mm + rect.w_mm, rect.y_mm + rect.h_mm)
                def inside(it, box=box):
                    return box[0] <= it.x_mm <= box[2] and box[1] <= it.y_mm <= box[3]
                # a close-up: its frame in the picture, the enlargement right after it in the
                # page's items (in the picture or beside it)
                regions = [it for it in page.items if isinstance(it, L.Rect)
                           and it.role == "close_up_region" and inside(it)]
                zoom = None
                if regions:
                    at = page.items.index(regions[0])
                    close = next(it for it in page.items[at:] if isinstance(it, L.Rect)
                                 and it.role == "close_up")
                    zoom = (regions[0], close)
                    region = regions[0]
                    assert not L._boxes_overlap(  # it shows the region it magnifies whole
                        (region.x_mm, region.y_mm, region.x_mm + region.w_mm,
                         region.y_mm + region.h_mm),
                        (close.x_mm, close.y_mm, close.x_mm + close.w_mm,
                         close.y_mm + close.h_mm))
                    zoomed += 1
                    box = (min(box[0], close.x_mm), min(box[1], close.y_mm),
                           max(box[2], close.x_mm + close.w_mm),
                           max(box[3], close.y_mm + close.h_mm))
                dots = [it for it in page.items if isinstance(it, L.Circle)
                        and it.role == "label_point"]
                texts = [it for it in page.items if isinstance(it, L.Text) and it.role == "label"]
                mine = [(d, tx) for d, tx in zip(dots, texts)
                        if box[0] <= d.cx_mm <= box[2] and box[1] <= d.cy_mm <= box[3]]
                drawn = {tx.string: d for d, tx in mine}
                named = _letters_in(step.substeps)
                assert named <= set(drawn), (name, view, step.index, named - set(drawn))
                parts = [it.string for it in page.items if isinstance(it, L.Text)
                         and it.role == "part_label" and box[0] <= it.x_mm <= box[2]
                         and box[1] <= it.y_mm <= box[3]]
                faces = [it.string for it in page.items if isinstance(it, L.Text)
                         and it.role == "face_label" and box[0] <= it.x_mm <= box[2]
                         and box[1] <= it.y_mm <= box[3]]
                for lb in step.labels:
                    if lb.kind == "part":  # a part's short name, on the picture, no dot
                        assert lb.name in parts, (name, step.index, lb.name)
                        continue
                    if lb.kind == "face":  # a face's name, on the picture, no dot
                        assert lb.name in faces, (name, step.index, lb.name)
                        continue
                    h = P @ np.array([*lb.at3d, 1.0])
                    want = h[:2] / h[2]  # the point's projection, sheet mm
                    d = drawn[lb.name]
                    x, y = d.cx_mm, d.cy_mm
                    in_close = zoom is not None and (
                        zoom[1].x_mm <= x <= zoom[1].x_mm + zoom[1].w_mm
                        and zoom[1].y_mm <= y <= zoom[1].y_mm + zoom[1].h_mm)
                    if in_close:  # letters in the close-up: back to the picture
                        region, close = zoom
                        z = close.w_mm / region.w_mm
                        assert close.h_mm / region.h_mm == pytest.approx(z)
                        assert z >= L.CLOSE_UP_MIN_ZOOM
                        x = region.x_mm + (x - close.x_mm) / z
                        y = region.y_mm + (y - close.y_mm) / z
                    got = ((x - rect.x_mm) / scale, (y - rect.y_mm) / scale)
                    assert np.allclose(got, want, atol=0.05), (name, step.index, lb.name)
                    checked += 1
                boxes = [tx.box_mm for _, tx in mine]
                for b in boxes:  # inside the picture
                    assert box[0] <= b[0] and b[2] <= box[2] and box[1] <= b[1] and b[3] <= box[3]
                for a, b in itertools.combinations(boxes, 2):  # no two labels overlap
                    assert not L._boxes_overlap(a, b), (name, step.index)
                for (d, _), b in itertools.product(mine, boxes):  # nor cover another's dot
                    inside = b[0] < d.cx_mm < b[2] and b[1] < d.cy_mm < b[3]
                    assert not inside or any(tx.box_mm == b and dd is d for dd, tx in mine)
    assert checked > 100 and zoomed > 0


def test_a_step_stays_short_and_a_master_reads_headline_and_ratio_words(examples):
    for name, (t, plan, views) in examples.items():
        for (view, level), vp in views.items():
            for s in vp.steps:
                if level == "master":
                    assert not s.substeps and s.text.startswith(s.headline)
                else:
                    assert s.text.split()[:len(s.headline.split())] == s.headline.split()
                    n = len(s.text.split())
                    if n <= seq_drafts.MAX_STEP_WORDS:
                        continue
                    # over the limit only what cannot be cut: one construction on its own, or a
                    # part's placing step with nothing left to move out (lines reused, carried,
                    # centred on, the box itself and its copies)
                    if s.kind == "guides":
                        assert not any(x.startswith("Use ") for x in s.substeps), s.substeps
                    else:
                        # (an apprentice's construction said as one sub-step: "Halve ...")
                        assert all(re.match(r"(Use [A-Z',]|Carry |Centre |Draw the |Keep its |Its |"
                                            r"[A-Z][a-z]+ \d+|[A-Z][a-z ]+: the same|"
                                            r"(Halve|Quarter|Divide|Extend) |Through the centre)", x)
                                   for x in s.substeps), (name, s.index, s.substeps)


def test_a_line_is_not_cited_when_a_later_sub_step_names_it(examples):
    """"Use KL from step 2" or "Use the edge KL" before "Carry KL vertically" only repeats
    KL (the picture shows it used again): such a citation is left out."""
    cited = 0
    for name, (t, plan, views) in examples.items():
        for (view, level), vp in views.items():
            if level != "novice":
                continue
            for s in vp.steps:
                for i, x in enumerate(s.substeps):
                    m = re.match(r"Use (?:the edges? )?([A-Z', and]+?)(?: from steps? [\d, and]+)?"
                                 r"(?: for its [a-z ,()]+)?\.$", x)
                    if not m:
                        continue
                    cited += 1
                    later = " ".join(s.substeps[i + 1:])
                    for line in re.split(r", | and ", m.group(1)):
                        a, b = re.findall(r"[A-Z]'*", line)
                        assert not re.search(rf"(?<![A-Z']){a}{b}(?!')|(?<![A-Z']){b}{a}(?!')",
                                             later), (name, view, s.index, x, later)
    assert cited > 10


def test_identical_parts_are_one_step_that_draws_every_instance_box(examples):
    t, plan, views = examples["train"]
    chosen = plan.chosen()
    vp = views[("front-left", "novice")]
    wheels = [s for s in vp.steps if s.kind == "primitive" and s.part.startswith("wheel")]
    assert len(wheels) == 1  # eight instances of one mesh, the hidden ones left out
    step = wheels[0]
    members = sorted({st.part for st in step.strokes})
    assert len(members) >= 4 and all(m.startswith("wheel") for m in members)
    for m in members:  # each instance's scaffold spans exactly its own selected box
        pts = np.array([p for st in step.strokes if st.part == m for p in st.points3d])
        box = np.asarray(chosen[m].box, dtype=float)
        assert np.allclose(pts.min(axis=0), box[0]) and np.allclose(pts.max(axis=0), box[1]), m
    others = [seq_words._cap(m.replace("_", " ")) for m in members if m != step.part]
    assert any(all(o.lower() in x.lower() for o in others) for x in step.substeps), step.substeps
    # their near ellipses, their far ellipses and their outlines are one step each too
    ell = [s for s in vp.steps if s.kind == "ellipse" and s.part == step.part]
    assert len(ell) == 2 and all({st.part for st in s.strokes} == set(members) for s in ell)
    assert len([s for s in vp.steps if s.kind == "contour" and s.part.startswith("wheel")]) == 1


# ----------------------------------------------------------------------------- part names


def test_id_named_parts_are_called_by_short_labels_drawn_on_the_picture_and_listed():
    from test_sequence import PAPER, _tiny_plan

    from h2s_print.candidates import Anchor
    from h2s_print.config import SequenceSettings, ViewSpec

    boxes = {"10_base_body": ((-100, 0, 0), (100, 100, 100)),
             "0_part0": ((-20, -10, 100), (20, 30, 140))}
    # the part's left side at the quarter line of the base's top face
    plan = _tiny_plan(boxes, {"0_part0": ("10_base_body", [Anchor(0, "lo", "10_base_body",
                                                                   0.25, 6, 2, "hi")])})
    view = ViewSpec("v", azimuth_deg=30.0, elevation_deg=25.0, distance=3.0, lens_mm=50.0,
                    perspective="two-point")
    for level in ("novice", "master"):
        vp = seq.sequence_view(plan, view, level, PAPER, SequenceSettings(eyeball_mm2=0.0))
        texts = " ".join(s.text for s in vp.steps)
        assert "0_part0" not in texts and "0 part0" not in texts and "10 base" not in texts
        assert "Part 1:" in texts and "base body" in texts
        assert "the part 1" not in texts  # a numbered label takes no article
        assert dict(vp.part_names) == {"part 1": "0_part0", "base body": "10_base_body"}
        step = next(s for s in vp.steps if s.kind == "primitive" and s.part == "0_part0")
        lb, = [lb for lb in step.labels if lb.kind == "part"]
        assert lb.name == "part 1"
        # on the part's box: its centre, seen from above inside the base's picture, moved to
        # the middle of its top face, which the base's picture does not cover
        # (test_sequence.test_parts_named_alike_but_for_a_number_are_labelled_on_their_step)
        assert np.allclose(lb.at3d, (0.0, 10.0, 140.0))
        pages = L.lay_out_workbook("Oven", vp, PAPER, view_label="v")
        cover = " ".join(t.string for t in pages[0].items if isinstance(t, L.Text))
        assert "part 1: 0_part0" in cover and "base body: 10_base_body" in cover
        page = [p for p in pages if p.kind == "steps"][(step.index - 1)
                                                      // (1 if level == "novice" else 2)]
        assert any(isinstance(t, L.Text) and t.role == "part_label" and t.string == "part 1"
                   for t in page.items)
        sheet = " ".join(t.string for t in pages[-1].items if isinstance(t, L.Text))
        assert "bottom face of the base body (step 1)" in sheet


def test_a_line_used_from_an_earlier_step_has_the_same_letters_there(examples):
    """"Use KL from step 2" (or "Centre it on EN, carried in step 9"): step 2's picture shows
    K and L at the same points (step 9 had carried EN without naming N)."""
    checked = 0
    for name, (t, plan, views) in examples.items():
        for (view, level), vp in views.items():
            if level != "novice":
                continue
            for s in vp.steps:
                here = {lb.name: lb.at3d for lb in s.labels if lb.kind == "point"}
                for x in s.substeps:
                    m = re.search(r"(?:from steps?|, carried in step|, extended in step) (\d+)",
                                  x)
                    if not m:
                        continue
                    n = int(m.group(1))
                    assert n < s.index
                    there = {lb.name: lb.at3d for lb in vp.steps[n - 1].labels
                             if lb.kind == "point"}
                    for letter in _letters_in([x[:m.start()]]):
                        assert letter in there, (name, s.index, x, sorted(there))
                        assert np.allclose(here[letter], there[letter]), (name, s.index, x)
                        checked += 1
    assert checked > 20


@pytest.mark.parametrize("level", ["novice", "apprentice", "master"])
def test_the_picture_keeps_one_scale_on_every_step_page(examples, level):
    """The scaffold must not grow and shrink from page to page while one copies it (issue 12):
    every step picture of a workbook is drawn at one scale."""
    for name, (t, plan, views) in examples.items():
        for (view, lv), vp in views.items():
            if lv != level:
                continue
            book = L.lay_out_workbook(t.title, vp, t.paper, view_label=view)
            pages = [p for p in book if p.kind == "steps"]
            widths = {round(r.w_mm, 9) for p in pages for r, _ in _pictures(p, vp)}
            assert len(widths) == 1, (name, view, sorted(widths))
            # and in the same place on every page; the finished drawing too
            places = {(round(r.x_mm, 9), round(r.y_mm, 9)) for p in pages
                      for r, _ in _pictures(p, vp)[:1]}
            assert len(places) == 1, (name, view, places)
            final, = [p for p in book if p.kind == "final"]
            (r, _), = _pictures(final, vp)
            assert {(round(r.x_mm, 9), round(r.y_mm, 9))} == places
            assert round(r.w_mm, 9) in widths


@pytest.mark.parametrize("grid", [False, True])
def test_drawing_sheet_labels_do_not_overlap(examples, grid):
    """The calibrated sheet's labels (vanishing points, horizon, footprint, title, scale) never
    overlap each other, and no drawn line crosses one: arrows, horizon, footprint, scale bar,
    registration marks, and the perspective grid, which stops short of them (issue 12)."""
    for name, (t, plan, views) in examples.items():
        for (view, level), vp in views.items():
            if level != "novice":
                continue
            page = S.lay_out_sheet(t.title, vp, margin_mm=t.paper.margin_mm, grid=grid)
            texts = [it for it in page.items if isinstance(it, L.Text) and it.string]
            for a, b in itertools.combinations(texts, 2):
                assert not L._boxes_overlap(a.box_mm, b.box_mm), (name, view, a.string, b.string)
            lines = [it for it in page.items if isinstance(it, L.Polyline)]
            assert {it.role for it in lines} >= {"vp_arrow", "ground", "scale_bar", "registration"}
            assert ("grid" in {it.role for it in lines}) is grid
            drawn = L._segments(lines)
            for tx in texts:
                assert not L._crossings(drawn, tx.box_mm), (name, view, tx.string)


def test_perspective_grid_lines_run_toward_their_vanishing_points(examples):
    for name, (t, plan, views) in examples.items():
        vp = views[(t.views[0].name, "novice")]
        plain = S.lay_out_sheet(t.title, vp, margin_mm=t.paper.margin_mm)
        assert not [it for it in plain.items if getattr(it, "role", "") == "grid"]
        page = S.lay_out_sheet(t.title, vp, margin_mm=t.paper.margin_mm, grid=True)
        lines = [it for it in page.items if isinstance(it, L.Polyline) and it.role == "grid"]
        frame = L._frame_box(vp.paper_mm, t.paper.margin_mm)
        for v in vp.vanishing_points:
            mine = []
            for ln in lines:
                (ax, ay), (bx, by) = ln.points_mm[0], ln.points_mm[-1]
                d = np.array([bx - ax, by - ay]) / np.hypot(bx - ax, by - ay)
                if v.at_infinity:
                    u = np.asarray(v.direction_mm, float) / np.linalg.norm(v.direction_mm)
                    hit = abs(d[0] * u[1] - d[1] * u[0]) < 1e-9
                else:  # the line, extended, passes through the VP (0.05 mm)
                    w = np.asarray(v.xy_mm, float) - (ax, ay)
                    hit = abs(d[0] * w[1] - d[1] * w[0]) < 0.05
                if hit:
                    mine.append(ln)
            assert len(mine) >= 8, (name, v.axis, len(mine))  # each VP has its fan
        for ln in lines:  # inside the frame
            for x, y in ln.points_mm:
                assert frame[0] - 1e-6 <= x <= frame[2] + 1e-6 and frame[1] - 1e-6 <= y <= frame[3] + 1e-6


def test_a_round_table_top_and_foot_get_their_ellipses(tmp_path):
    """A round plate (a plane whose outline is its box's inscribed ellipse) gets its ellipse,
    constructed in the rectangle its scaffold draws (issue 12 point 1)."""
    import trimesh
    from _meshfiles import write_glb

    from h2s_print.config import (
        ModelSpec,
        PaperSpec,
        SequenceSettings,
        SolverSettings,
        ViewSpec,
    )

    def mesh(m, dz):
        v = np.asarray(m.vertices, float) + (0.0, 0.0, dz)
        return v[:, [0, 2, 1]] * (1, 1, -1), np.asarray(m.faces)  # z-up -> glTF y-up

    top = mesh(trimesh.creation.cylinder(300.0, 12.0, sections=96), 706.0)
    column = mesh(trimesh.creation.cylinder(30.0, 700.0, sections=48), 350.0)
    foot = mesh(trimesh.creation.cylinder(150.0, 10.0, sections=96), 5.0)
    path = write_glb(tmp_path / "table.glb", [("top", *top), ("column", *column), ("foot", *foot)],
                     [{"name": "top", "mesh": 0}, {"name": "column", "mesh": 1},
                      {"name": "foot", "mesh": 2}], scene_extras={"units": "mm"})
    plan = build_plan(ModelSpec(path), SolverSettings())
    kinds = {p.part: (p.type, p.detail.get("round")) for p in plan.primitives}
    assert kinds["top"] == ("plane", True) and kinds["foot"] == ("plane", True)
    view = ViewSpec("v", azimuth_deg=30.0, elevation_deg=25.0, distance=3.0, lens_mm=50.0,
                    perspective="two-point")
    vp = seq.sequence_view(plan, view, "novice", PaperSpec("A4", "landscape", 12.0),
                           SequenceSettings())
    chosen = plan.chosen()
    for part in ("top", "foot"):
        ell = [st for s in vp.steps for st in s.strokes if st.kind == "ellipse" and st.part == part]
        assert len(ell) == 1, part  # one ellipse, in the plane drawn
        lo, hi = (np.asarray(x, float) for x in chosen[part].box)
        pts = np.asarray(ell[0].points3d)
        assert np.allclose(pts[:, 2], 0.5 * (lo[2] + hi[2]))  # in the mid-plane
        centre = 0.5 * (lo + hi)
        r = np.hypot((pts[:, 0] - centre[0]) / (0.5 * (hi[0] - lo[0])),
                     (pts[:, 1] - centre[1]) / (0.5 * (hi[1] - lo[1])))
        assert np.allclose(r, 1.0)  # inscribed in the rectangle: touching its edges


def _round_case(kind: str):
    """(meshes z-up as (name, vertices, faces), names of the round parts) on a 400 mm base."""
    import trimesh

    def at(m, off):
        return np.asarray(m.vertices, float) + off, np.asarray(m.faces)

    base = ("base", *at(trimesh.creation.box((400.0, 400.0, 40.0)), (0.0, 0.0, 20.0)))
    if kind == "disc":  # 8 mm thick: a plane that carries its ellipse
        return [base, ("disc", *at(trimesh.creation.cylinder(100.0, 8.0, sections=96),
                                   (0.0, 0.0, 44.0)))], ["disc"]
    if kind == "plate":  # a thick round plate: a flat cylinder
        return [base, ("plate", *at(trimesh.creation.cylinder(120.0, 30.0, sections=96),
                                    (0.0, 0.0, 55.0)))], ["plate"]
    if kind == "ring":  # a bearing ring: by score alone a cuboid
        return [base, ("ring", *at(trimesh.creation.annulus(90.0, 100.0, 10.0, sections=96),
                                   (0.0, 0.0, 45.0)))], ["ring"]
    if kind == "axle":  # one mesh holding the two wheels of an axle: split, then two cylinders
        wheel = trimesh.creation.cylinder(60.0, 30.0, sections=64)
        wheel.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
        pair = trimesh.util.concatenate([wheel.copy().apply_translation((0, -150, 100)),
                                         wheel.copy().apply_translation((0, 150, 100))])
        return [base, ("wheels", *at(pair, (0.0, 0.0, 0.0)))], ["wheels_1", "wheels_2"]
    raise ValueError(kind)


@pytest.mark.parametrize("kind", ["disc", "plate", "ring", "axle"])
def test_round_parts_get_round_primitives_and_constructed_ellipses(tmp_path, kind):
    """Issue 12 point 1: a disc, a round plate, a ring and a two-wheel axle mesh are round
    primitives, and each gets its ellipses constructed in an ellipse step (not by eye): every
    ellipse point lies on the ellipse inscribed in its box face."""
    from _meshfiles import write_glb

    from h2s_print.config import (
        ModelSpec,
        PaperSpec,
        SequenceSettings,
        SolverSettings,
        ViewSpec,
    )

    meshes, round_parts = _round_case(kind)
    zup = [(n, v[:, [0, 2, 1]] * (1, 1, -1), f) for n, v, f in meshes]  # z-up -> glTF y-up
    path = write_glb(tmp_path / f"{kind}.glb", zup,
                     [{"name": n, "mesh": i} for i, (n, _, _) in enumerate(zup)],
                     scene_extras={"units": "mm"})
    plan = build_plan(ModelSpec(path), SolverSettings())
    for part in round_parts:
        prim = plan.primitive(part)
        assert prim.type == "cylinder" or (prim.type == "plane" and prim.detail.get("round")), \
            (part, prim.type)
    view = ViewSpec("v", azimuth_deg=30.0, elevation_deg=25.0, distance=3.0, lens_mm=50.0,
                    perspective="two-point")
    vp = seq.sequence_view(plan, view, "novice", PaperSpec("A4", "landscape", 12.0),
                           SequenceSettings())
    chosen = plan.chosen()
    for part in round_parts:
        steps = [s for s in vp.steps if s.kind == "ellipse"
                 and any(st.part == part for st in s.strokes)]
        prim = plan.primitive(part)
        # a plate: one ellipse; a cylinder: its near and its far end, a step each
        assert len(steps) == (1 if prim.type == "plane" else 2), part
        assert not any(s.eyeball for s in steps), part
        lo, hi = (np.asarray(x, float) for x in chosen[part].box)
        u, v = [k for k in range(3) if k != prim.axis]
        centre = 0.5 * (lo + hi)
        for st in (st for s in steps for st in s.strokes):
            if st.part != part:
                continue
            assert st.kind in ("ellipse", "ellipse_hidden")
            pts = np.asarray(st.points3d)
            assert np.ptp(pts[:, prim.axis]) < 1e-9  # in one face (or the mid-plane)
            r = np.hypot((pts[:, u] - centre[u]) / (0.5 * (hi[u] - lo[u])),
                         (pts[:, v] - centre[v]) / (0.5 * (hi[v] - lo[v])))
            assert np.allclose(r, 1.0)  # inscribed: touching the face's four edges


# ----------------------------------------------------------------------------- equal spacing


def _knob_row(tmp_path, xs):
    """A 400 x 200 x 40 mm base with identical 40 x 30 x 60 knobs (instances of one mesh) on
    top, their left sides at ``xs``; planned and sequenced (novice, front-left)."""
    from _meshfiles import box, write_glb

    from h2s_print.config import (
        ModelSpec,
        PaperSpec,
        SequenceSettings,
        SolverSettings,
        ViewSpec,
    )

    def gl(v):
        return np.asarray(v, float)[:, [0, 2, 1]] * (1, 1, -1)  # z-up -> glTF y-up

    bv, bf = box((-200, -100, 0), (200, 100, 40))
    kv, kf = box((0, -15, 0), (40, 15, 60))
    nodes = [{"name": "base", "mesh": 0}] + [
        {"name": f"knob_{i + 1}", "mesh": 1, "translation": [float(x), 40.0, 0.0]}
        for i, x in enumerate(xs)]
    path = write_glb(tmp_path / "row.glb", [("base", gl(bv), bf), ("knob", gl(kv), kf)], nodes,
                     scene_extras={"units": "mm"})
    plan = build_plan(ModelSpec(path), SolverSettings())
    view = ViewSpec("front-left", azimuth_deg=-35.0, elevation_deg=25.0, distance=3.0,
                    lens_mm=50.0, perspective="two-point")
    return plan, seq.sequence_view(plan, view, "novice", PaperSpec("A4", "landscape", 12.0),
                                   SequenceSettings())


def test_a_row_of_evenly_spaced_copies_is_placed_by_equal_spacing(tmp_path):
    """Issue 11 point 4: identical parts in an even row are repeated by the equal-spacing
    construction (extend the spacing of the two before by 1x).  On the page, each lettered
    line of "Draw EK and BJ through L and M: knob 4's ends." runs from its first letter through
    the named point to the projected corner of that knob's box (0.05 mm)."""
    plan, vp = _knob_row(tmp_path, [-190.0, -110.0, -30.0, 50.0])
    chosen = plan.chosen()
    spaced = [s for s in vp.steps if "spaced like" in s.headline]
    assert spaced, [s.headline for s in vp.steps]
    P = vp.camera.projection_mm

    def mm(p):
        h = P @ np.array([*p, 1.0])
        return h[:2] / h[2]

    checked = 0
    for s in spaced:
        at = {lb.name: np.asarray(lb.at_mm) for lb in s.labels if lb.kind == "point"}
        for lb in s.labels:
            assert np.allclose(lb.at_mm, mm(lb.at3d), atol=0.05)
        for x in s.substeps:
            m = re.match(r"Draw (\w\w) and (\w\w) through (\w) and (\w): (.+)'s ends\.$", x)
            if not m:
                continue
            part = m.group(5).replace(" ", "_")
            lo, hi = (np.asarray(v, float) for v in chosen[part].box)
            corners = [mm((x0, lo[1], lo[2])) for x0 in (lo[0], hi[0])]  # front bottom corners
            for line, through in ((m.group(1), m.group(3)), (m.group(2), m.group(4))):
                a, b, c = at[line[0]], at[line[1]], at[through]
                d = b - a  # the named point lies on the line ...
                assert abs(d[0] * (c - a)[1] - d[1] * (c - a)[0]) / np.hypot(*d) < 0.05
                # ... and the line ends at a corner of the knob's box
                assert min(np.linalg.norm(b - k) for k in corners) < 0.05, (x, b, corners)
                checked += 1
        # the boxes drawn are the selected boxes, evenly spaced after the two before
        members = sorted({st.part for st in s.strokes}, key=lambda q: chosen[q].box[0][0])
        for q in members:
            pts = np.array([p for st in s.strokes if st.part == q for p in st.points3d])
            assert np.allclose(pts.min(axis=0), chosen[q].box[0])
    assert checked >= 2


def test_an_uneven_row_keeps_its_copies_where_the_picture_shows_them(tmp_path):
    plan, vp = _knob_row(tmp_path, [-190.0, -110.0, -10.0, 50.0])
    assert not [s for s in vp.steps if "spaced like" in s.headline]
    drawn = {st.part for s in vp.steps if s.kind == "primitive" for st in s.strokes}
    assert {"knob_1", "knob_2", "knob_3", "knob_4"} <= drawn


def _on_segment(p, a, b, tol=0.05):
    """Is sheet point ``p`` on segment ``a-b`` (within ``tol`` mm)?"""
    p, a, b = (np.asarray(x, dtype=float) for x in (p, a, b))
    d = b - a
    t = float(np.clip((p - a) @ d / max(float(d @ d), 1e-18), 0.0, 1.0))
    return float(np.linalg.norm(a + t * d - p)) <= tol


def test_erase_hint_names_the_lines_by_their_letters_when_it_can(examples):
    """"Afterwards you may erase AB and DE.": each name is two lettered points of the step's
    picture on a guide the step shows (its own, reused or kept) that the next step no longer
    shows, the piece between them on no edge of the scaffold (a guide extending an edge is
    erased beyond it only); each such guide is named once, and one lying on an edge whole
    not at all.  The others are counted ("... and 2 more guide lines: the next picture no
    longer shows them."), and where none is lettered the hint gives only that count."""
    named = counted = edged = partly = stepped = 0
    for name, (t, plan, views) in examples.items():
        for (view, level), vp in views.items():
            if level not in ("novice", "apprentice"):
                continue
            hints = L._erase_hints(vp)
            for i, step in enumerate(vp.steps[:-1]):
                shown = {g.id: g for g in step.guides}
                for gid in step.alive:  # kept from earlier steps: where they were drawn last
                    for earlier in reversed(vp.steps[:i]):
                        g = next((g for g in earlier.guides if g.id == gid), None)
                        if g is not None:
                            shown.setdefault(gid, g)
                            break
                nxt = vp.steps[i + 1]
                gone = [g for gid, g in shown.items()  # (print, on the sheet: not erased)
                        if gid not in {g.id for g in nxt.guides} | set(nxt.alive)
                        and g.role != "sheet"]
                # the scaffold edges drawn so far and by the next step (a guide the next
                # step's box is drawn on is not erased only to be drawn again)
                edges = [(s.points_mm[k], s.points_mm[k + 1]) for st in vp.steps[:i + 2]
                         for s in st.strokes if s.kind in ("scaffold", "scaffold_hidden")
                         for k in range(len(s.points_mm) - 1)]

                pen = seq_geometry.ALONG_MM  # a pencil's width on the sheet

                def along(g):  # the edges on the guide's line (both ends within a pencil)
                    a, b = np.asarray(g.from_mm), np.asarray(g.to_mm)
                    n = np.array([a[1] - b[1], b[0] - a[0]]) / np.linalg.norm(b - a)
                    return [(p, q) for p, q in edges
                            if abs((np.asarray(p) - a) @ n) <= pen
                            and abs((np.asarray(q) - a) @ n) <= pen]

                def covered(g):  # the share of 201 points of the guide on edges along it
                    mine = along(g)
                    return np.mean([any(_on_segment(np.add(g.from_mm, f * np.subtract(
                        g.to_mm, g.from_mm)), p, q, pen + 1e-9) for p, q in mine)
                        for f in np.linspace(0, 1, 201)])

                whole = [g for g in gone if covered(g) == 1.0]
                edged += len(whole)
                left = [g for g in gone if g not in whole]
                hint = hints[i]
                if not left:
                    assert hint == ""
                    continue
                m = (re.fullmatch(r"Afterwards you may erase ([A-Z',]+(?:, [A-Z']+)*"
                                  r"(?: and [A-Z']+)?)\.", hint)
                     or re.fullmatch(r"Afterwards you may erase ([A-Z',]+(?:, [A-Z']+)*) and "
                                     r"(\d+) more guide lines?: the next picture no longer "
                                     r"shows (?:it|them)\.", hint))
                if m is None and re.search(r"erase (?:this step's|the) guide lines", hint):
                    stepped += 1  # whole steps' lines (test_layout checks them)
                    continue
                if m is None:
                    assert f"erase {len(left)} guide line" in hint and "next picture" in hint
                    counted += 1
                    continue
                at = {lb.name: lb.at_mm for lb in step.labels if lb.kind == "point"}
                names = re.split(r", | and ", m.group(1))
                more = int(m.group(2)) if m.lastindex == 2 else 0  # the unlettered, counted
                partly += bool(more)
                assert len(names) + more == len(left), (name, view, step.index, hint)
                for n in names:
                    a, b = (at[x] for x in re.findall(r"[A-Z]'*", n))
                    owner = [g for g in left if _on_segment(a, g.from_mm, g.to_mm)
                             and _on_segment(b, g.from_mm, g.to_mm)]
                    assert owner, (name, view, step.index, n)
                    mid = np.add(a, b) / 2  # the piece named runs along no edge
                    assert not any(_on_segment(mid, p, q, pen) for p, q in along(owner[0])), \
                        (name, view, step.index, n)
                named += 1
    assert named > 10 and counted > 0 and edged > 0 and partly > 0 and stepped > 0


def test_a_carry_around_a_corner_says_both_directions(examples):
    """"Carry EF and GK toward the left vanishing point to M and P, then vertically.": said
    exactly when the step's carrying lines turn a corner (two of them meet
    end to end running along different model axes), the second direction being the turn's,
    and the corners lettered (the second read-through could not tell where to turn)."""
    from h2s_print.templates import lookup

    vp_words = lookup("steps", "vp")
    turns = plain = 0
    for name, (t, plan, views) in examples.items():
        for (view, level), vp in views.items():
            if level != "novice":
                continue
            for st in vp.steps:
                carry = [x for x in st.substeps if x.startswith("Carry ") and " to the far " not in x
                         and "floor line" not in x  # (the floor's foot carried to a part)
                         and " until they cross " not in x]  # (two carries meeting)
                # (in a placing step or a guides step of its own: since stop 36 the carries
                # that turned corners by eye in placing steps walk in guides steps)
                if st.kind not in ("primitive", "guides") or not carry or any(
                        "box around" in x for x in st.substeps):
                    continue
                lines = [g for g in st.guides if g.role == "vanishing"]

                def axis(g):
                    return int(np.argmax(np.abs(np.subtract(g.to3d, g.from3d))))

                turn = {axis(b) for a in lines for b in lines if a is not b
                        and np.allclose(a.to3d, b.from3d) and axis(a) != axis(b)}
                said = [x for x in carry if ", then " in x]
                assert bool(turn) == bool(said), (name, view, st.index, carry)
                if said:
                    turns += 1
                    then = said[0].split(", then ")[1].rstrip(".")
                    then = re.split(r" to [A-Z]|, for ", then)[0]  # (to the end, what for)
                    # the turns are lettered: "to M and P" names the corners, each the
                    # end of a carrying line where the next one starts
                    at = {lb.name: lb.at3d for lb in st.labels}
                    named = re.findall(r"[A-Z]'*", said[0].split(", then ")[0].rsplit(
                        " to ", 1)[1])
                    corners = [a.to3d for a in lines for b in lines
                               if a is not b and np.allclose(a.to3d, b.from3d)]
                    assert named and all(any(np.allclose(at[n], c) for c in corners)
                                         for n in named), (name, view, st.index, said)
                    # the turn's direction: upright edges' (vertically, or their vanishing
                    # point in a three-point view), else a vanishing point's
                    assert then == vp_words["vertical"] or "vanishing point" in then, then
                    assert (then == vp_words["vertical"]) <= (2 in turn), (then, turn)
                else:
                    plain += 1
    assert turns > 0 and plain > 0


def test_a_line_drawn_over_an_edge_says_so(examples):
    """"From H, draw HJ vertically, along the column's edge.": said exactly when, on the
    sheet, both ends of the line drawn lie within a pencil's width (seq_geometry.ALONG_MM) of a
    scaffold edge of a part drawn before, over more than half the line (an orange line on a
    grey edge looked like nothing new); a visible edge: a line over a hidden edge only crosses
    behind it (a read-through of stop 32 looked for the roller's handle's hidden edge)."""
    pat = re.compile(r"(?:From|Through) ([A-Z]'*), draw ([A-Z]'*)([A-Z]'*) .*?(, along (.+)'s edge)?\.")
    said = plain = 0
    for name, (t, plan, views) in examples.items():
        for (view, level), vp in views.items():
            if level != "novice":
                continue
            for k, st in enumerate(vp.steps):
                at = {lb.name: np.asarray(lb.at_mm) for lb in st.labels if lb.kind == "point"}
                edges = [(np.asarray(s.points_mm[0]), np.asarray(s.points_mm[-1]), s.part)
                         for e in vp.steps[:k] for s in e.strokes if s.kind == "scaffold"]
                for sub in st.substeps:
                    m = pat.fullmatch(sub)
                    if m is None:
                        continue
                    a, b = at[m.group(2)], at[m.group(3)]

                    def over(p, q):
                        d = q - p
                        n = np.linalg.norm(d)
                        u = d / n
                        off = [np.linalg.norm((x - p) - ((x - p) @ u) * u) for x in (a, b)]
                        lo, hi = sorted(((a - p) @ u, (b - p) @ u))
                        return max(off) <= seq_geometry.ALONG_MM and min(hi, n) - max(lo, 0) > 0.5 * np.linalg.norm(b - a)

                    hit = [part for p, q, part in edges if over(p, q)]
                    if m.group(4):
                        assert hit, (name, view, st.index, sub)
                        said += 1
                    else:
                        assert not hit, (name, view, st.index, sub, hit)
                        plain += 1
    assert said >= 3 and plain > 50



def test_a_close_up_of_crowded_letters_shows_the_part_drawn_with_them(examples):
    """Crowded letters get a close-up; where the part the step draws lies close by (adding at
    most half again to the letters' region each way), the close-up shows it whole too (a
    read-through: the camera's shutter button was cut off at the close-up's edge, high-right
    step 13)."""
    checked = 0
    for name, view, vp, step, page in _novice_step_pages(examples):
        zoom = _close_up_of(page)
        rect, scale = _pictures(page, vp)[0]
        letters = np.array([lb.at_mm for lb in step.labels if lb.kind == "point"],
                           dtype=float).reshape(-1, 2) * scale + (rect.x_mm, rect.y_mm)
        new = np.array([p for st in step.strokes for p in st.points_mm],
                       dtype=float).reshape(-1, 2) * scale + (rect.x_mm, rect.y_mm)
        if zoom is None or len(letters) < 2 or not len(new) or not _within(letters, zoom[0]):
            continue
        # the regions padded as the close-up pads them ("half again" of the letters' region)
        ext = lambda a: np.ptp(a, axis=0) + 2 * L.CLOSE_UP_PAD_MM  # noqa: E731
        both = np.vstack([letters, new])
        if np.all(ext(both) <= 1.5 * ext(letters) + 1e-6):
            assert _within(new, zoom[0]), (name, view, step.index)
            checked += 1
    assert checked
    # the read-through's page
    t, plan, views = examples["camera"]
    vp = views[("high-right", "novice")]
    pages = [p for p in L.lay_out_workbook(t.title, vp, t.paper, view_label="high-right")
             if p.kind == "steps"]
    step = next(s for s in vp.steps if s.part == "shutter_button" and s.kind == "primitive")
    rect, scale = _pictures(pages[step.index - 1], vp)[0]
    new = np.array([p for st in step.strokes for p in st.points_mm]) * scale + (rect.x_mm,
                                                                                 rect.y_mm)
    assert _within(new, _close_up_of(pages[step.index - 1])[0])


def test_letters_crowding_each_other_get_a_close_up_even_when_the_step_s_letters_span_the_picture(examples):
    """The roller's frame axle (front-left): V, X and Z lie within a few mm of each other at
    one end of the arm, W and Y at the other.  The crowded group gets the close-up, every
    letter of it magnified there (before, no close-up: all five letters spanned too much of
    the picture to magnify)."""
    t, plan, views = examples["roller"]
    vp = views[("front-left", "novice")]
    pages = [p for p in L.lay_out_workbook(t.title, vp, t.paper, view_label="front-left")
             if p.kind == "steps"]
    step = next(s for s in vp.steps if s.part == "frame_axle" and s.kind == "primitive")
    page = pages[step.index - 1]
    rect, scale = _pictures(page, vp)[0]
    pts = {lb.name: np.asarray(lb.at_mm) * scale + (rect.x_mm, rect.y_mm)
           for lb in step.labels if lb.kind == "point"}
    crowded = {a for a in pts for b in pts
               if a != b and np.linalg.norm(pts[a] - pts[b]) < L.CLOSE_UP_CROWDED_MM}
    assert len(crowded) >= 3
    zoom = _close_up_of(page)
    assert zoom is not None
    region, close = zoom
    held = [n for n in crowded if _within(pts[n][None, :], region)]
    assert len(held) >= 3
    assert close.w_mm / region.w_mm >= L.CLOSE_UP_MIN_ZOOM - 1e-9


def test_letters_sit_nearer_their_dot_than_a_corner_they_do_not_name(examples):
    """A letter nearer another corner of the drawing's straight lines (a box's corner, a
    guide's end) than its own dot reads as that corner's (a read-through put the roller's
    handle's top corner where its S, the top face's centre, was lettered).  Over the
    examples' novice pages at most 21 of about 850 letters are (41 before the placement
    counted such a corner as a line crossed), where every other place is nearer another
    dot or crosses more lines; checked here on the pages themselves (the lines' ends, the
    dots and the letters as drawn)."""
    cornered = total = 0
    for name, view, vp, step, page in _novice_step_pages(examples):
        ends = [p for it in page.items if isinstance(it, L.Polyline) and len(it.points_mm) == 2
                for p in it.points_mm]
        if not ends:
            continue
        corners = np.asarray(ends, dtype=float)
        dots = [(it.cx_mm, it.cy_mm) for it in page.items
                if isinstance(it, L.Circle) and it.role == "label_point"]
        texts = [it for it in page.items if isinstance(it, L.Text) and it.role == "label"]
        assert len(dots) == len(texts), (name, view, step.index)
        for (dx, dy), tx in zip(dots, texts):
            b = tx.box_mm
            mx, my = (b[0] + b[2]) / 2, (b[1] + b[3]) / 2
            own = np.hypot(mx - dx, my - dy)
            other = np.hypot(corners[:, 0] - dx, corners[:, 1] - dy) > L.CORNER_OWN_MM
            near = np.hypot(corners[:, 0] - mx, corners[:, 1] - my) < own
            cornered += bool((near & other).any())
            total += 1
    assert total > 500 and cornered <= 21, (cornered, total)


def test_letters_keep_off_the_step_s_new_lines(examples):
    """The step's new lines are thick and coloured: a letter across or touching one is lost
    in it (the train's J under the boiler's new edge).  Over the examples' novice pages at
    most two letters touch one (17 before the new lines counted more than other lines; since
    stop 32 sixteen directions round a dot, the roller's T and V, where every other place is
    nearer another dot), and never the train's J."""
    touching = total = 0
    g = L.STYLES["new"].width_mm / 2
    for name, view, vp, step, page in _novice_step_pages(examples):
        new = L._segments([it for it in page.items if isinstance(it, L.Polyline)
                           and it.role == "stroke_new"])
        for tx in (it for it in page.items if isinstance(it, L.Text) and it.role == "label"):
            b = tx.box_mm
            total += 1
            hit = bool(len(new)) and L._crossings(
                new, (b[0] - g, b[1] - g, b[2] + g, b[3] + g)) > 0
            touching += hit
            if (name, view, step.part, tx.string) == ("train", "front-left", "boiler", "J"):
                assert not hit
    assert total > 500 and touching <= 2, (touching, total)


def test_a_close_up_beside_the_picture_keeps_its_caption_out_of_the_picture(examples):
    """A close-up set beside the picture has its caption wrapped to its column: no caption
    line reaches into the picture (a read-through: the roller's and the desk's ran across
    its border)."""
    beside = 0
    for name, view, vp, step, page in _novice_step_pages(examples):
        zoom = _close_up_of(page)
        if zoom is None:
            continue
        rect, _ = _pictures(page, vp)[0]
        close = zoom[1]
        if rect.x_mm <= close.x_mm <= rect.x_mm + rect.w_mm:
            continue  # inside the picture
        beside += 1
        for tx in (it for it in page.items if isinstance(it, L.Text)
                   and it.role == "close_up_caption"):
            b = tx.box_mm
            assert b[2] <= rect.x_mm + 1e-6 or b[0] >= rect.x_mm + rect.w_mm - 1e-6, (
                name, view, step.index, tx.string)
    assert beside


_CENTRE = re.compile(r"^Centre .* on ([A-Z]'?)([A-Z]'?)"
                     r"( from step \d+|, (?:carried|extended) in step \d+| \(.*\))?\.$")


def _centred_lines_said(steps) -> list[str]:
    """Sub-steps "Centre X on KL." whose line KL the step neither draws nor says the origin
    of (an earlier sub-step naming K and L or carrying a line to K and on, "on the edge KL",
    "on KL from step 3", "on KL, carried in step 3"; "the lines carried in step 2 for its
    middle" did not say which line: the desk's foot, "Centre part 6 on HJ", J said nowhere)."""
    bad = []
    for s in steps:
        for i, sub in enumerate(s.substeps):
            m = _CENTRE.match(sub)
            if not m or m.group(3):
                continue
            k, l_ = m.group(1), m.group(2)

            def word(w: str) -> str:  # a letter, primed or not, as a whole word ("D'E'")
                return rf"(?<![A-Za-z']){w}(?![A-Za-z'])"

            # (the line's name said, both its letters, or a line carried in this step to
            # one of them and on: "Carry FG vertically to H, then toward ...")
            named = [x for x in s.substeps[:i]
                     if re.search(word(f"({k}{l_}|{l_}{k})"), x)
                     or (re.search(word(k), x) and re.search(word(l_), x))
                     or re.match(rf"Carry .* to (.*, )?({word(k)}|{word(l_)})\W.*, then ", x)]
            if not named:
                bad.append(f"step {s.index}: {sub}")
    return bad


def test_a_part_is_centred_on_a_line_the_step_says_the_origin_of(examples, shared_models):
    # a read-through: "Centre part 2 on AB" where AB was the base's front edge, said
    # nowhere, read as a line to construct; it now reads "on the edge AB"
    from h2s_print.config import load_tutorial

    for name, (t, _, views) in examples.items():
        for (view, level), vp in views.items():
            if level == "novice":
                assert not _centred_lines_said(vp.steps), (name, view)
    from conftest import CONFIGS

    for model in ("box_ivar", "desk_fredrik"):
        t = load_tutorial(CONFIGS.parent / "benchmarks" / "configs" / f"{model}.yaml")
        plan = build_plan(t.model, t.solver, t.views)
        for view in t.views:
            for level in ("novice", "apprentice"):
                vp = seq.sequence_view(plan, view, level, t.paper, t.sequence)
                assert not _centred_lines_said(vp.steps), (model, view.name, level)
                if model == "box_ivar" and level == "novice":
                    assert any(re.match(r"Centre part \d [a-z ]+ on the edge [A-Z]{2}\.$", sub)
                               for s in vp.steps for sub in s.substeps)


def test_a_guides_step_draws_something_and_cites_no_edge(examples):
    # a read-through: "Guides for the grip (2/2), on the body. 1. Use the edge AD." had
    # nothing to do, and the grip's step then said "Use AD from step 7"; an edge of a drawn
    # part is cited where the part is placed ("Use the edges AD and AB.")
    from h2s_print.templates import lookup

    edge = [lookup("steps", f"substep.{k}").split("{")[0] for k in ("edge", "edge_two")]
    drawing = 0
    for name, (t, _, views) in examples.items():
        for (view, level), vp in views.items():
            if level not in ("novice", "apprentice"):
                continue
            for s in vp.steps:
                if s.kind != "guides":
                    continue
                assert not any(x.startswith(tuple(edge)) for x in s.substeps), (
                    name, view, level, s.index, s.substeps)
                assert any(not x.startswith("Use ") for x in s.substeps), (
                    name, view, level, s.index, s.substeps)
                drawing += 1
    assert drawing > 20


@pytest.mark.parametrize("level", ["novice", "apprentice", "master"])
def test_ellipses_promised_to_come_later_come(examples, level):
    # a read-through of the master workbooks: the roller's parts were "Ellipses come later"
    # and no later step said a word of them ("Handle: its outlines.")
    from h2s_print.templates import lookup

    # The note is said of a tutorial's first round part only (a later read-through: in every
    # round part's headline it told nothing new); the promise holds for every round part
    # drawn as a box.
    note = lookup("steps", "headline.cylinder_note").strip()
    promised = kept = 0
    for name, (t, plan, views) in examples.items():
        for (view, lv), vp in views.items():
            if lv != level:
                continue
            for i, s in enumerate(vp.steps):
                prim = plan.primitive(s.part) if s.part is not None else None
                if s.kind != "primitive" or prim is None or prim.type != "cylinder":
                    continue
                part = s.headline.split(":")[0].lower()
                promised += note in s.headline
                kept += 1
                assert any("ellipse" in x.text and part in x.text.lower()
                           for x in vp.steps[i + 1:]), (name, view, s.headline)
    assert promised >= 6 and kept > 10


def _sheet_clashes_with_footprint(page) -> list[str]:
    """Texts whose middle lies inside the printed footprint, and vanishing-point arrows
    crossing the printed first box's lines (footprint, upright, floor line)."""
    ground = L._segments([it for it in page.items if isinstance(it, L.Polyline)
                          and it.role in ("ground", "ground_edge")])
    foot = L._segments([it for it in page.items if isinstance(it, L.Polyline)
                        and it.role == "ground"])
    hull = S._hull(foot.reshape(-1, 2).tolist())
    bad = [f"text {it.string!r}" for it in page.items
           if isinstance(it, L.Text) and it.string
           and it.role not in ("ground_label", "height_label")  # they name its lines
           and S._in_convex(hull, ((it.box_mm[0] + it.box_mm[2]) / 2,
                                   (it.box_mm[1] + it.box_mm[3]) / 2))]
    for it in page.items:
        if isinstance(it, L.Polyline) and it.role == "vp_arrow":
            for (ax, ay), (bx, by) in zip(it.points_mm, it.points_mm[1:]):
                box = (min(ax, bx) - 1e-9, min(ay, by) - 1e-9, max(ax, bx) + 1e-9,
                       max(ay, by) + 1e-9)
                if any(_segments_cross((ax, ay), (bx, by), g[:2], g[2:]) for g in ground
                       if min(g[0], g[2]) <= box[2] and max(g[0], g[2]) >= box[0]):
                    bad.append("arrow")
    return bad


def _segments_cross(p, q, r, s) -> bool:
    def side(a, b, c):
        return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    return (side(p, q, r) * side(p, q, s) < 0) and (side(r, s, p) * side(r, s, q) < 0)


def test_sheet_labels_and_arrows_keep_off_the_printed_first_box(examples, shared_models):
    # a read-through: the desk's "vertical edges: keep them parallel" was printed inside the
    # footprint the first box is drawn on, and the upward arrow crossed the footprint's edge
    from h2s_print.config import load_tutorial
    from conftest import CONFIGS

    def sheet(t, vp, view):  # as the workbook lays it out, off the finished drawing
        page, = [p for p in L.lay_out_workbook(t.title, vp, t.paper, view_label=view)
                 if p.kind == "sheet"]
        return page

    for name, (t, _, views) in examples.items():
        for (view, level), vp in views.items():
            if level == "novice":
                assert not _sheet_clashes_with_footprint(sheet(t, vp, view)), (name, view)
    t = load_tutorial(CONFIGS.parent / "benchmarks" / "configs" / "desk_fredrik.yaml")
    plan = build_plan(t.model, t.solver, t.views)
    for view in t.views:
        vp = seq.sequence_view(plan, view, "novice", t.paper, t.sequence)
        assert not _sheet_clashes_with_footprint(sheet(t, vp, view.name)), view.name


def test_the_first_boxs_height_sentence_matches_the_sheets_line(examples):
    # a read-through: in a three-point view (high-right) step 1 said "Its height is the blue
    # upright line on your sheet." where the sheet's height line leans toward the vanishing
    # point below.  The sentence names the footprint's corner the line rises from; that
    # corner is the footprint's nearest to the eye in plan (worked out here from the
    # camera), and no sentence calls a leaning line upright or vertical
    from h2s_print.templates import lookup

    plain = lookup("steps", "substep.first_height")
    assert "nearest corner" in plain
    leaning = 0
    for name, (t, plan, views) in examples.items():
        for (view, level), vp in views.items():
            if level != "novice":
                continue
            edge = S.first_near_edge(vp)
            first = vp.steps[0]
            if edge is None or plain not in first.substeps:
                continue
            pts = np.array([p for s in first.strokes for p in s.points3d], dtype=float)
            lo, hi = pts.min(axis=0), pts.max(axis=0)
            eye = np.asarray(vp.camera.position, dtype=float)
            corners = [(x, y) for x in (lo[0], hi[0]) for y in (lo[1], hi[1])]
            near = min(corners, key=lambda c: np.hypot(c[0] - eye[0], c[1] - eye[1]))
            bottom = vp.camera.project(np.array([[near[0], near[1], lo[2]]]))[0]
            assert np.allclose(edge[0], bottom, atol=1e-9), (name, view)
            (bx, by), (tx, ty) = edge
            lean = abs(np.degrees(np.arctan2(tx - bx, ty - by)))
            if lean > 0.5:
                leaning += 1
                said = " ".join(first.substeps).lower()
                assert "upright" not in said and "vertical" not in said, (name, view)
    assert leaning >= 2  # the camera's and the mixer's three-point views


def test_a_raised_first_boxs_height_is_told_apart_from_the_floor_line(examples, shared_models):
    # a read-through of the desk: its height and the floor line are one blue upright line
    # through the footprint's corner, and "Its height is the blue upright line" made the
    # desktop as tall as the whole desk.  The step says the part above the corner, and the
    # sheet names that part beside it; a first box on the floor is said as before
    from h2s_print.config import load_tutorial
    from h2s_print.templates import lookup
    from conftest import CONFIGS

    above = lookup("steps", "substep.first_height_floor")
    plain = lookup("steps", "substep.first_height")
    word = lookup("pages", "sheet.height")
    seen = labelled = 0
    for path in (CONFIGS.parent / "benchmarks" / "configs" / "desk_fredrik.yaml",
                 CONFIGS / "train.yaml", CONFIGS / "camera.yaml"):
        t = load_tutorial(path)
        plan = build_plan(t.model, t.solver, t.views)
        for view in t.views:
            vp = seq.sequence_view(plan, view, "novice", t.paper, t.sequence)
            edge, drop = S.first_near_edge(vp), S.first_floor_line(vp)
            page, = [p for p in L.lay_out_workbook(t.title, vp, t.paper, view_label=view.name)
                     if p.kind == "sheet"]
            named = [it for it in page.items if isinstance(it, L.Text) and it.string == word]
            first = vp.steps[0].substeps
            if drop is None:
                assert plain in first and above not in first and not named
                continue
            seen += 1
            assert above in first and plain not in first
            # one upright line: the height ends where the floor line starts
            assert np.allclose(edge[0], drop[0], atol=1e-9) and edge[1][1] > edge[0][1] > drop[1][1]
            # the height's name beside it or just above it, never beside the floor line
            # below (where there is no such room, the words alone say it)
            for label in named:
                x0, y0, x1, y1 = label.box_mm
                assert edge[0][1] - 1.0 <= 0.5 * (y0 + y1) <= edge[1][1] + 4.0
                assert x0 - 3.0 <= edge[1][0] <= x1 + 3.0 or min(
                    abs(x0 - edge[0][0]), abs(x1 - edge[0][0])) <= 3.0
            labelled += bool(named)
            # the height's top end marked across it, the floor line's foot by a dot (a
            # read-through: the train's height line runs on past the footprint's far edge,
            # and its short floor line ended in a gap of its dashes)
            tick, = [it for it in page.items if isinstance(it, L.Polyline)
                     and it.role == "height_tick"]
            (ax, ay), (bx, by) = tick.points_mm
            assert np.allclose(((ax + bx) / 2, (ay + by) / 2), edge[1], atol=1e-9)
            assert abs((bx - ax) * (edge[1][0] - edge[0][0])
                       + (by - ay) * (edge[1][1] - edge[0][1])) <= 1e-9  # across the line
            dot, = [it for it in page.items if isinstance(it, L.Circle)
                    and it.role == "floor_foot"]
            assert np.allclose((dot.cx_mm, dot.cy_mm), drop[1], atol=1e-9)
            # the footprint's name sits in the footprint or beside it, nearer it than the
            # floor line hanging from its corner (a read-through: "bottom face of part 1
            # (step 1)" below the corner read as naming the floor line)
            ground, = [it for it in page.items if isinstance(it, L.Text)
                       and it.role == "ground_label"]
            quad = [it for it in page.items if isinstance(it, L.Polyline) and it.role == "ground"]
            ring = np.array([q for it in quad for q in it.points_mm], float)
            x0, y0, x1, y1 = ground.box_mm
            gx, gy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
            rim = [(x, y) for x in (x0, gx, x1) for y in (y0, gy, y1)]  # the box's edge

            def near(a, b):
                return min(_point_segment(p, a, b) for p in rim)
            to_quad = min(near(ring[i], ring[(i + 1) % len(ring)]) for i in range(len(ring)))
            inside = S._in_convex(S._hull(ring.tolist()), (gx, gy))
            to_floor = near(np.array(drop[0]), np.array(drop[1]))
            assert inside or to_quad < to_floor, (path.stem, view.name, ground.string)


def _point_segment(p, a, b) -> float:
    """Distance from point ``p`` to the segment ``a``-``b`` (2D)."""
    p, a, b = (np.asarray(v, float) for v in (p, a, b))
    d = b - a
    t = float(np.clip(np.dot(p - a, d) / max(float(np.dot(d, d)), 1e-300), 0.0, 1.0))
    return float(np.linalg.norm(p - (a + t * d)))


def test_parts_on_the_floor_under_a_raised_first_box_are_stood_on_it(shared_models):
    # a read-through: the LACK table's top is drawn first, and its legs were "width, depth
    # and height by eye": nothing gave the table's height.  The sheet now prints the floor
    # under the top's nearest corner, and the legs stand on it: their height is given
    from h2s_print.config import load_tutorial
    from h2s_print.templates import lookup
    from conftest import CONFIGS

    t = load_tutorial(CONFIGS.parent / "benchmarks" / "configs" / "table_lack.yaml")
    plan = build_plan(t.model, t.solver, t.views)
    floor_z = min(c.box[0][2] for c in plan.chosen().values())
    on_floor = lookup("steps", "substep.on_floor")
    # (or, since stop 30, the floor under the leg constructed from the floor line's foot)
    foot = lookup("steps", "substep.floor_line").split("{")[1].split("}")[1].split(",")[1]
    for view in t.views:
        vp = seq.sequence_view(plan, view, "novice", t.paper, t.sequence)
        assert lookup("steps", "substep.first_floor") in vp.steps[0].substeps
        standing = [s for s in vp.steps if on_floor in s.substeps
                    or any(foot in x for x in s.substeps)]
        assert standing and all(s.kind in ("primitive", "guides") for s in standing)
        for s in standing:
            box = plan.chosen()[s.part].box
            assert box[0][2] == pytest.approx(floor_z)  # it does stand on the floor
            placing = next(p for p in vp.steps if p.part == s.part and p.kind == "primitive")
            assert not any("height" in x and "by eye" in x for x in placing.substeps)
            # the floor line is on the picture, ending on the floor
            line, = [g for g in s.guides if g.id == seq_drafts.SHEET_FLOOR]
            assert line.to3d[2] == floor_z
        # and stays on the paper until then (no erase hint retires it earlier)
        last = max(s.index for s in standing)
        assert all(seq_drafts.SHEET_FLOOR in s.alive for s in vp.steps[:last])


def test_a_part_stands_where_the_floor_line_ends_only_on_its_own_upright_edge(examples,
                                                                               shared_models):
    """"Its bottom stands on the floor, where the blue floor line ends." only for a part
    with an upright edge on the floor line (its box has a corner under the line's foot);
    another part on the floor is told to judge where by eye: in perspective the floor under
    it is not where the line ends (a read-through: the roller's handle, drawn down to the
    line's foot, came out far too long).  Both only for parts whose box stands on the floor."""
    from conftest import CONFIGS

    from h2s_print.config import load_tutorial
    from h2s_print.templates import lookup

    plans = [(t, plan, [(v, views[(v.name, "novice")]) for v in t.views])
             for t, plan, views in examples.values()]
    t = load_tutorial(CONFIGS.parent / "benchmarks" / "configs" / "desk_fredrik.yaml")
    plan = build_plan(t.model, t.solver, t.views)
    plans.append((t, plan, [(v, seq.sequence_view(plan, v, "novice", t.paper, t.sequence))
                            for v in t.views]))
    at_foot, by_eye = lookup("steps", "substep.on_floor"), lookup("steps", "substep.on_floor_eye")
    on_line = re.compile(re.escape(lookup("steps", "substep.on_floor_line")).replace(
        r"\{line\}", r"((?:[A-Z]'*){2})"))
    side_said = re.compile(re.escape(lookup("steps", "substep.floor_side")).replace(
        r"\{point\}", ".+").replace(r"\{line\}", ".+").replace(r"\{vp\}", ".+").replace(
        r"\{sides\}", ".+"))
    said = {at_foot: 0, by_eye: 0}
    for t, plan, views in plans:
        floor_z = min(c.box[0][2] for c in plan.chosen().values())
        for view, vp in views:
            for s in vp.steps:
                for key in (at_foot, by_eye):
                    if key not in s.substeps:
                        continue
                    box = np.asarray(plan.chosen()[s.part].box, float)
                    tol = 1e-9 * max(1.0, float(np.abs(box).max()))
                    assert box[0][2] == pytest.approx(floor_z, abs=tol)
                    line, = [g for g in s.guides if g.id == seq_drafts.SHEET_FLOOR]
                    foot = np.asarray(line.to3d, float)
                    on_edge = any(abs(box[i][0] - foot[0]) <= tol and abs(box[j][1] - foot[1])
                                  <= tol for i in (0, 1) for j in (0, 1))
                    assert on_edge == (key == at_foot), (t.title, view.name, s.index)
                    said[key] += 1
                # stop 33: a centring line carried down to the floor under the part says so
                # ("Its bottom stands on the floor, on JK.", the desk's feet): the line lies on
                # the floor and through the part's bottom face
                for x in s.substeps:
                    m = on_line.fullmatch(x)
                    if not m:
                        continue
                    box = np.asarray(plan.chosen()[s.part].box, float)
                    at = {lb.name: np.asarray(lb.at3d, float) for lb in s.labels}
                    p, q = (at[c] for c in re.findall(r"[A-Z]'*", m.group(1)))
                    assert p[2] == pytest.approx(floor_z) == q[2]
                    k = int(abs(q[1] - p[1]) <= abs(q[0] - p[0]) * 1e-9)  # constant axis
                    assert box[0][k] - 1e-9 <= p[k] <= box[1][k] + 1e-9
                    said["line"] = said.get("line", 0) + 1
                # and a side in line with the floor line's foot stands on a line from it
                # (test_sequence.test_a_side_in_line_with_the_floor_lines_foot_stands_...)
                for x in s.substeps:
                    if side_said.fullmatch(x) and s.part is not None:
                        box = np.asarray(plan.chosen()[s.part].box, float)
                        assert box[0][2] == pytest.approx(floor_z)
                        said["side"] = said.get("side", 0) + 1
    assert (said[by_eye] + said.get("line", 0) + said.get("side", 0) >= 4
            and said.get("line", 0) >= 2), said


def test_a_copy_right_over_its_original_says_which_way_it_lies(shared_models):
    # a read-through: the desk's two modesty panels, 12 mm apart in depth, read "Part 3: the
    # same flat rectangle, where the picture shows it" over what the picture drew as one
    # double line; a copy moved along one axis only, whose centre lies within NEAR_COPY_MM
    # of its original's on the sheet, now says "directly behind it" (in front, to its left..)
    from h2s_print.config import load_tutorial
    from h2s_print.sequence import repeats
    from h2s_print.templates import lookup
    from conftest import CONFIGS

    table = {k: lookup("steps", f"shifts.{k}") for k in
             ("x_lo", "x_hi", "y_lo", "y_hi", "z_lo", "z_hi")}
    said = 0
    for model in ("desk_fredrik", "oven_101773"):
        t = load_tutorial(CONFIGS.parent / "benchmarks" / "configs" / f"{model}.yaml")
        plan = build_plan(t.model, t.solver, t.views)
        for view in t.views:
            vp = seq.sequence_view(plan, view, "novice", t.paper, t.sequence)
            names = {lb.name: lb for s in vp.steps for lb in s.labels if lb.kind == "part"}
            for s in vp.steps:
                for x in s.substeps:
                    m = re.match(r"(.+): the same .+, directly (.+)\.$", x)
                    if not m:
                        continue
                    key = next(k for k, v in table.items() if v == m.group(2))
                    axis, end = "xyz".index(key[0]), key[2:]
                    first = plan.chosen()[s.part].box
                    copy_part = next(p for p in plan.chosen() if names.get(m.group(1).lower())
                                     and names[m.group(1).lower()].at3d is not None
                                     and _inside(names[m.group(1).lower()].at3d,
                                                 plan.chosen()[p].box))
                    copy = plan.chosen()[copy_part].box
                    a, b = np.asarray(first, float), np.asarray(copy, float)
                    moved = [k for k in range(3) if np.abs(a[:, k] - b[:, k]).max() > 1e-9]
                    assert moved == [axis], (model, x)
                    assert (b[:, axis].mean() > a[:, axis].mean()) == (end == "hi"), (model, x)
                    ca, cb = vp.camera.project(np.array([a.mean(axis=0), b.mean(axis=0)]))
                    assert np.hypot(*(cb - ca)) < repeats.NEAR_COPY_MM
                    said += 1
    assert said >= 2  # the desk's panels in both views


def _inside(p, box) -> bool:
    lo, hi = (np.asarray(x, float) for x in box)
    return bool(np.all(np.asarray(p) >= lo - 1e-9) and np.all(np.asarray(p) <= hi + 1e-9))


def test_both_ends_extended_alike_are_said_once(examples):
    # The mixer's master bowl said "its right side half a column width beyond the column's
    # right side, its left side half a column width beyond the column's left side": 75 words,
    # over the limit.  Both ends of an axis extended alike beyond one parent read as one
    # phrase, and every master step of the examples stays within the word limit.
    t, plan, views = examples["mixer"]
    bowl = plan.chosen()["bowl"]
    x = sorted((a.end, a.ratio, plan_part(plan, a.parent)) for a in bowl.anchors if a.axis == 0)
    assert x == [("hi", 1.5, "column"), ("lo", -0.5, "column")]
    step = next(s for s in views[("front-left", "master")].steps if s.part == "bowl")
    assert "Its width the column's, with half a column width more on each side" in step.text
    assert "right side half" not in step.text
    for name, (t, plan, views) in examples.items():
        for (view, level), vp in views.items():
            if level == "master":
                assert all(len(s.text.split()) <= seq_drafts.MAX_STEP_WORDS for s in vp.steps), (
                    name, view, [s.text for s in vp.steps
                                 if len(s.text.split()) > seq_drafts.MAX_STEP_WORDS])


def plan_part(plan, cid):
    return next(c.part for c in plan.candidates if c.id == cid)


def test_an_edge_cited_says_the_side_it_places(examples):
    # A read-through: "Use the edge DC." left the mixer's column's back to be guessed; each
    # edge cited for a side ("Put its left side and bottom on the edges AD and AB.";
    # "Use the edge QR for its front" read as an end of the part, a read-through of stop 33)
    # lies in the plane of that side of the part's box, in 3D, at its lettered ends.
    from conftest import side_names

    cite = re.compile(r"Put its (?P<sides>.+) on the edges? (?P<lines>.+)\.")
    letter = r"[A-Z]'?"
    checked = 0
    for name, (t, plan, views) in examples.items():
        chosen = plan.chosen()
        for view in t.views:
            where = side_names(t, plan, view)
            for level in ("novice", "apprentice"):
                for s in views[(view.name, level)].steps:
                    at = {lb.name: np.asarray(lb.at3d) for lb in s.labels if lb.kind == "point"}
                    box = np.asarray(chosen[s.part].box) if s.part else None
                    for sub in s.substeps:
                        m = cite.fullmatch(sub)
                        if m is None:
                            continue
                        lines = re.findall(rf"({letter})({letter})", m.group("lines"))
                        sides = re.split(r", | and ", m.group("sides"))
                        pairs = (zip(lines, sides) if len(lines) == len(sides)
                                 else [(ln, sd) for ln in lines for sd in sides])
                        for (p, q), side in pairs:
                            axis, end = where[side]
                            plane = (box[0, axis] if end == "lo" else box[1, axis] if end == "hi"
                                     else 0.5 * (box[0, axis] + box[1, axis]))
                            for point in (at[p], at[q]):
                                assert abs(point[axis] - plane) <= 1e-6 * max(
                                    1.0, float(np.abs(box).max())), (name, view.name, sub)
                            checked += 1
    assert checked >= 10
    t, plan, views = examples["mixer"]
    column = next(s for s in views[("front-left", "novice")].steps if s.part == "column")
    assert any(re.fullmatch(r"Put its back on the edge [A-Z]{2}\.", x)
               for x in column.substeps)


def test_a_round_parts_other_size_is_said_the_same(examples):
    # A read-through: the train's wheel read "Make its width about a quarter of the engine's"
    # and nothing of its height; "Make its width about a quarter of the engine's, and its
    # height the same" read as a quarter of the engine's height (a review): "Make its width
    # and height about a quarter of the engine's width."  A round part sized one way across its axis is said to be the
    # same the other way, and that holds on its box (both extents across its axis equal).
    from h2s_print.sequence import context as seq_context

    said = re.compile(r"Make its (\w+) and (\w+) about .+'s \1\.")
    same = re.compile(r"Make its (\w+) the same as its (\w+)\.")  # the other constructed
    checked = 0
    for name, (t, plan, views) in examples.items():
        words = seq_context._context(plan, t.views[0], t.paper, t.sequence).words
        axis_of = {words.dim(a): a for a in range(3)}
        for (view, level), vp in views.items():
            for s in vp.steps:
                for x in s.substeps:
                    m = said.fullmatch(x) or same.fullmatch(x)
                    if m is None:
                        continue
                    prim, box = plan.primitive(s.part), np.asarray(plan.chosen()[s.part].box)
                    if same.fullmatch(x):  # the size it copies is constructed: both ends
                        copied = axis_of[m.group(2)]
                        assert sum(a.axis == copied for a in plan.chosen()[s.part].anchors) == 2
                    a, b = axis_of[m.group(1)], axis_of[m.group(2)]
                    assert prim.type in ("cylinder", "frustum") and prim.axis not in (a, b)
                    ea, eb = box[1, a] - box[0, a], box[1, b] - box[0, b]
                    assert abs(ea - eb) <= 0.01 * max(ea, eb), (name, s.index, x)
                    checked += 1
    assert checked >= 4
    t, plan, views = examples["train"]
    wheel = next(s for s in views[("front-left", "novice")].steps if s.part == "wheel_1")
    assert any(said.fullmatch(x) for x in wheel.substeps), wheel.substeps
    chimney = next(s for s in views[("front-left", "novice")].steps if s.part == "chimney"
                   and s.kind == "primitive")
    assert any(same.fullmatch(x) for x in chimney.substeps), chimney.substeps


def test_sides_in_line_with_the_parents_same_sides_are_said_once(examples):
    # The train's master wagon read "Its back in line with the engine's back, its front in
    # line with the engine's front, its top ... and its bottom ...": 32 words naming the engine
    # four times.  Sides each in line with the parent's side of the same name read as one
    # phrase, and each holds on the boxes.
    from conftest import side_names

    said = re.compile(r"(?:^|, |and )[Ii]ts ((?:[a-z ]+, )*[a-z ]+ and [a-z ]+) in line with "
                      r"(?:the )?([a-z0-9 ]+)'s(?=,| and|\.)")
    checked = 0
    for name, (t, plan, views) in examples.items():
        chosen = plan.chosen()
        for view in t.views:
            sides = side_names(t, plan, view, ("lo", "hi"))
            for s in views[(view.name, "master")].steps:
                if s.kind != "primitive" or s.part is None:
                    continue
                for m in said.finditer(s.text):
                    parent = m.group(2).replace(" ", "_")
                    if parent not in chosen:
                        continue
                    box, pbox = np.asarray(chosen[s.part].box), np.asarray(chosen[parent].box)
                    for side in re.split(r", | and ", m.group(1)):
                        axis, end = sides[side]
                        k = int(end == "hi")
                        assert abs(box[k, axis] - pbox[k, axis]) <= 1e-6 * max(
                            1.0, float(np.abs(pbox).max())), (name, s.text)
                        checked += 1
    assert checked >= 6
    t, plan, views = examples["train"]
    wagon = next(s for s in views[("front-left", "master")].steps if s.part == "wagon")
    assert wagon.text.endswith("Its back, front, top and bottom in line with the engine's.")


def test_a_centring_says_which_way_and_its_line_lies_in_that_mid_plane(examples, shared_models):
    """"Centre the head left to right on GY": the direction said is the one across which
    the line halves the part: the line's lettered ends lie in the part's mid-plane normal to
    that direction (the box's middle along it), checked in 3D (a read-through could not see
    how to centre a box on a vertical line; two centrings are two sentences, each with its
    direction, but for two on one line, one sentence both ways: "Centre the handle left to
    right and front to back on QR", the line in both mid-planes)."""
    from h2s_print.templates import lookup

    words = lookup("steps", "directions")
    way = "|".join(map(re.escape, words))
    pat = re.compile(r"^Centre (?:the |part )?.*? (" + way + r")(?: and (" + way
                     + r"))? on (?:the edge )?([A-Z]'*)([A-Z]'*)")
    checked = both = 0
    for name, (t, plan, views) in examples.items():
        chosen = plan.chosen()
        for (view, level), vp in views.items():
            if level != "novice":
                continue
            for s in vp.steps:
                at = {lb.name: np.asarray(lb.at3d, float) for lb in s.labels
                      if lb.kind == "point"}
                for sub in s.substeps:
                    m = pat.match(sub)
                    if not m or s.part not in chosen:
                        continue
                    box = np.asarray(chosen[s.part].box, float)
                    tol = 1e-6 * float(np.linalg.norm(box[1] - box[0]))
                    for said in (m.group(1), m.group(2)):
                        if said is None:
                            continue
                        axis = words.index(said)
                        mid = box[:, axis].mean()
                        for p in (m.group(3), m.group(4)):
                            if p in at:  # (a line from an earlier step is lettered there)
                                assert abs(at[p][axis] - mid) <= tol, (name, view, s.index, sub)
                    both += m.group(2) is not None
                    checked += 1
    assert checked >= 10 and both >= 1


def test_a_line_named_as_carried_in_a_step_is_named_there(examples, shared_models):
    # a read-through of the chair: step 2 said "Carry FG away from the left vanishing
    # point ..., as pictured" and step 3 "Centre part 3 left to right on FJ, carried in
    # step 2": J was never said.  A straight carry that runs one way names where it ends
    from h2s_print.config import load_tutorial
    from conftest import CONFIGS

    letter = r"[A-Z]'*"
    said = re.compile(rf"on ({letter})({letter}), carried in step (\d+)")
    views = [vp for _, (_, _, vs) in sorted(examples.items()) for (v, lvl), vp in vs.items()
             if lvl in ("novice", "apprentice")]
    for stem in ("chair_ingolf", "desk_fredrik"):
        t = load_tutorial(CONFIGS.parent / "benchmarks" / "configs" / f"{stem}.yaml")
        plan = build_plan(t.model, t.solver, t.views)
        views += [seq.sequence_view(plan, view, "novice", t.paper, t.sequence)
                  for view in t.views]
    checked = 0
    for vp in views:
        for s in vp.steps:
            for a, b, k in said.findall(s.text):
                earlier = vp.steps[int(k) - 1].text
                tokens = set(re.findall(rf"(?<![A-Za-z']){letter}", earlier)) | {
                    x for pair in re.findall(rf"({letter})({letter})", earlier) for x in pair}
                assert {a, b} <= tokens, (s.text, earlier)
                checked += 1
    assert checked >= 4


def test_a_carry_from_a_point_on_its_line_says_the_line_crossing_there(examples):
    # a read-through of the train's chimney (high-right): "Carry XY from V' away from the
    # vanishing point below." where nothing said what V' was (where G'K' crosses XY).  Now
    # "Carry XY from A on LM ...": A lies on the carried line and on the line named, both
    # drawn, checked from the letters' 3D points
    from conftest import check_carries_from_on

    seen = sum(check_carries_from_on(vp.steps)
               for _, _, views in examples.values() for vp in views.values())
    assert seen >= 2  # the train's chimney, high-right, novice and apprentice


def test_a_line_of_an_earlier_step_says_which_step_where_the_step_has_room(examples):
    # the primer: "a step that uses it mostly says which step drew it, as in "MP (step 7)"";
    # a read-through found carries naming lines of earlier steps with no step ("Carry P'S'
    # and T'U' toward the left vanishing point ...", drawn in step 11).  Checked from the
    # plan alone: the guide whose ends are the letters' 3D points was first drawn in the
    # step cited, whose picture letters both ends alike; a line named without a step was
    # cited (or drawn) earlier in that step, or the step has no room for two more words; a
    # box's edge is not cited ("Put its bottom on the edge AB.", "Extend DA beyond A.")
    import numpy as np

    line = re.compile(r"(?<![A-Za-z'])([A-Z]'*)([A-Z]'*)(?![A-Za-z'])( \(step (\d+)\))?")
    cited = uncited = 0
    for name, (_, _, views) in examples.items():
        for (view, level), vp in views.items():
            if level not in ("novice", "apprentice"):
                continue
            first: dict[str, int] = {}
            guides = {}
            for s in vp.steps:
                for g in s.guides:
                    guides.setdefault(g.id, g)
                    if g.status == "new":
                        first.setdefault(g.id, s.index)
            for s in vp.steps:
                at = {lb.name: np.asarray(lb.at3d, dtype=float) for lb in s.labels}
                named: set[tuple[str, str]] = set()
                for sub in s.substeps:
                    says_step = re.search(r"(?:from|in) step \d+", sub)
                    for m in line.finditer(sub):
                        a, b = m.group(1), m.group(2)
                        if a not in at or b not in at:
                            continue
                        ends = [g for g in guides.values() if g.id in first and (
                            np.allclose(g.from3d, at[a]) and np.allclose(g.to3d, at[b])
                            or np.allclose(g.from3d, at[b]) and np.allclose(g.to3d, at[a]))]
                        # "MP (step 7)", or one of "MP and XY (step 7)"
                        later = re.match(r"(?:(?:, | and )[A-Z]'*[A-Z]'*)* \(step (\d+)\)",
                                         sub[m.end(2):])
                        if later:
                            n = int(later.group(1))
                            assert n < s.index and any(first[g.id] == n for g in ends), (
                                name, view, level, s.index, sub)
                            there = {lb.name: lb.at3d for lb in vp.steps[n - 1].labels}
                            assert all(k in there and np.allclose(there[k], at[k])
                                       for k in (a, b)), (name, view, level, s.index, sub)
                            cited += 1
                        elif (ends and all(first[g.id] < s.index for g in ends)
                              and not sub.startswith("Put its") and not says_step
                              and not re.match(r"Extend \S+ beyond", sub)  # a box's edge
                              and (a, b) not in named and (b, a) not in named):
                            assert len(s.text.split()) + 2 > seq_drafts.MAX_STEP_WORDS, (
                                name, view, level, s.index, sub)
                            uncited += 1
                        named.add((a, b))
    # 2026-11-29: 61 cited, 16 left out in 7 steps at 69-70 words (the roller's handle and
    # frame shaft, the train's chimney); before, none cited
    assert cited >= 50 and cited > 3 * uncited, (cited, uncited)
