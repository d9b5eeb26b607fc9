"""Layout stage: pages in mm, built from hand-made ViewPlans (no other stage involved)."""

from __future__ import annotations

import math
import re
from dataclasses import replace

import numpy as np
import pytest

from h2s_print import layout as L
from h2s_print import sheet as S
from h2s_print.config import PaperSpec
from h2s_print.errors import RenderError
from h2s_print.sequence import drafts as seq_drafts
from h2s_print.templates import lookup
from h2s_print.types import Camera, Guide, Step, Stroke, VanishingPoint, ViewPlan

# ----------------------------------------------------------------------------- factory


def make_camera(paper_mm=(297.0, 210.0), az_deg=35.0, el_deg=12.0, dist=700.0,
                target=(100.0, 60.0, 40.0), fill=0.5) -> tuple[Camera, dict]:
    """A two-point camera (optical axis horizontal, shifted window) fitted to the sheet.

    Image: x = cx + F (r.(X-C)) / depth, y = cy + F (z.(X-C)) / depth, depth = f.(X-C), with f
    the horizontal forward direction, r = f x z.  F is chosen so the 200 mm body spans about
    ``fill`` of the sheet width; (cx, cy) put the target at the sheet's centre.
    """
    az, el = math.radians(az_deg), math.radians(el_deg)
    t = np.array(target)
    c = t + dist * np.array([math.sin(az) * math.cos(el), -math.cos(az) * math.cos(el), math.sin(el)])
    fwd = np.array([-math.sin(az), math.cos(az), 0.0])
    right = np.cross(fwd, [0.0, 0.0, 1.0])
    up = np.array([0.0, 0.0, 1.0])
    depth_t = fwd @ (t - c)
    f_mm = fill * paper_mm[0] * depth_t / 200.0
    cx = paper_mm[0] / 2 - f_mm * (right @ (t - c)) / depth_t
    cy = paper_mm[1] / 2 - f_mm * (up @ (t - c)) / depth_t
    p = np.zeros((3, 4))
    p[0, :3] = f_mm * right + cx * fwd
    p[1, :3] = f_mm * up + cy * fwd
    p[2, :3] = fwd
    p[:, 3] = -p[:, :3] @ c
    p.setflags(write=False)
    cam = Camera(tuple(c), p, tuple(paper_mm), "two-point")
    return cam, {"f_mm": f_mm, "cx": cx, "cy": cy}


def vanishing_points(cam: Camera) -> tuple[VanishingPoint, ...]:
    out = []
    centre = np.array(cam.paper_mm) / 2
    for axis in range(3):
        col = cam.projection_mm[:, axis]
        if abs(col[2]) < 1e-12:
            d = col[:2] / np.linalg.norm(col[:2])
            out.append(VanishingPoint(axis, True, None, (float(d[0]), float(d[1]))))
        else:
            xy = col[:2] / col[2]
            d = (xy - centre) / np.linalg.norm(xy - centre)
            out.append(VanishingPoint(axis, False, (float(xy[0]), float(xy[1])),
                                      (float(d[0]), float(d[1]))))
    return tuple(out)


def box_strokes(cam: Camera, part: str, lo, hi) -> tuple[Stroke, ...]:
    corners = [(x, y, z) for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
    edges = []
    for i, a in enumerate(corners):
        for b in corners[i + 1:]:
            if sum(1 for k in range(3) if a[k] != b[k]) == 1:
                edges.append((a, b))
    return tuple(stroke(cam, "scaffold", part, [a, b]) for a, b in edges)


def stroke(cam: Camera, kind: str, part: str, pts3d) -> Stroke:
    pts3d = [tuple(float(v) for v in p) for p in pts3d]
    mm = [tuple(float(v) for v in q) for q in cam.project(pts3d)]
    return Stroke(kind, part, tuple(pts3d), tuple(mm))


def guide(cam: Camera, gid: str, status: str, a, b, role: str = "guide") -> Guide:
    pa, pb = cam.project([a, b])
    return Guide(gid, status, tuple(map(float, a)), tuple(map(float, b)),
                 (float(pa[0]), float(pa[1])), (float(pb[0]), float(pb[1])), role)


def make_plan(level: str = "apprentice", paper_mm=(297.0, 210.0), *, guides: bool = True,
              n_steps: int = 5, camera: Camera | None = None,
              vps: tuple[VanishingPoint, ...] | None = None, **camera_kw) -> ViewPlan:
    """A plausible 3-5 step camera-like tutorial: body, lens (on the front face's halves), an
    ellipse, a grip (half the top's depth), a contour.  Guide lifetimes: g_mid is new at step 2,
    idle at 3, reused at 4; g_half new at 2, reused at 3, retired after 3."""
    cam = camera if camera is not None else make_camera(paper_mm, **camera_kw)[0]
    g = (lambda *a, **k: guide(cam, *a, **k)) if guides else None
    steps = [
        Step(1, "body", "primitive", "Draw the body: a box whose bottom face sits on the ground plane.",
             False, (), box_strokes(cam, "body", (0, 0, 0), (200, 120, 80)), ()),
        Step(2, "lens", "primitive",
             "Divide the front face in half both ways, then draw the lens box centred on the "
             "crossing and extend it toward you by ⅓ of the body's depth.", False,
             (g("g_half", "new", (100, 0, 0), (100, 0, 80)),
              g("g_mid", "new", (0, 0, 40), (200, 0, 40))) if guides else (),
             box_strokes(cam, "lens", (70, -40, 20), (130, 0, 60)),
             ("g_half", "g_mid") if guides else ()),
        Step(3, "lens", "ellipse",
             "Draw the lens's round front: an ellipse touching the middle of each edge of the "
             "lens box's front face.", False,
             (g("g_half", "reused", (100, 0, 0), (100, 0, 80)),) if guides else (),
             (stroke(cam, "ellipse", "lens",
                     [(100 + 30 * math.cos(t), -40, 40 + 20 * math.sin(t))
                      for t in np.linspace(0, 2 * math.pi, 49)]),),
             ("g_half", "g_mid") if guides else ()),
        Step(4, "grip", "primitive",
             "Halve the top face's depth and draw the grip on its back half, as tall as half the "
             "lens.", True,
             (g("g_top", "new", (0, 60, 80), (200, 60, 80)),
              g("g_mid", "reused", (0, 0, 40), (200, 0, 40))) if guides else (),
             box_strokes(cam, "grip", (150, 60, 80), (200, 120, 100)),
             ("g_mid", "g_top") if guides else ()),
        Step(5, "body", "contour", "Trace the body's rounded outline over the box.", False, (),
             (stroke(cam, "contour", "body",
                     [(0, 0, 10), (0, 0, 70), (10, 0, 80), (190, 0, 80), (200, 0, 70),
                      (200, 0, 10), (190, 0, 0), (10, 0, 0), (0, 0, 10)]),), ()),
    ][:n_steps]
    vps = vanishing_points(cam) if vps is None else vps
    return ViewPlan("front-left", level, tuple(paper_mm), cam, vps, tuple(steps))


A4L = PaperSpec("A4", "landscape", 12.0)
A4P = PaperSpec("A4", "portrait", 12.0)


def workbook(level="apprentice", paper=A4L, **kw):
    plan = make_plan(level, (paper.width_mm, paper.height_mm), **kw)
    return plan, L.lay_out_workbook("Digital camera", plan, paper, view_label="front-left")


def polylines(page, role=None):
    return [it for it in page.items if isinstance(it, L.Polyline) and (role is None or it.role == role)]


def texts(page, role=None):
    return [it for it in page.items if isinstance(it, L.Text) and it.string
            and (role is None or it.role == role)]


# ----------------------------------------------------------------------------- page sizes


@pytest.mark.parametrize("paper, size", [
    (PaperSpec("A4", "landscape"), (297.0, 210.0)),   # ISO 216 A4 is 210 x 297; landscape swaps
    (PaperSpec("A4", "portrait"), (210.0, 297.0)),
    (PaperSpec("A3", "landscape"), (420.0, 297.0)),   # A3 = 297 x 420
    (PaperSpec("Letter", "portrait"), (215.9, 279.4)),  # 8.5 x 11 in = 215.9 x 279.4 mm
    (PaperSpec("Letter", "landscape"), (279.4, 215.9)),
])
def test_page_sizes_are_the_paper(paper, size):
    plan, pages = workbook(paper=paper)
    for page in pages[:-1]:
        assert (page.width_mm, page.height_mm) == size
    assert pages[-1].kind == "sheet"
    assert (pages[-1].width_mm, pages[-1].height_mm) == plan.paper_mm


def test_page_sequence_and_steps_per_page():
    _, pages = workbook("apprentice")
    # cover + primer + ceil(5 steps / 2 per page) = 3 + final + sheet = 7
    assert [p.kind for p in pages] == ["cover", "primer", "steps", "steps", "steps", "final", "sheet"]
    _, pages = workbook("novice")
    # novice: 1 step per page -> 2 + 5 + 2 = 9
    assert len(pages) == 9
    assert [b.title for p in pages for b in p.bookmarks][2:7] == [f"Step {i}" for i in range(1, 6)]


def test_margins_hold_on_every_workbook_page():
    for paper in (A4L, A4P, PaperSpec("Letter", "portrait", 6.0)):
        _, pages = workbook("apprentice", paper)
        for page in pages[:-1]:
            m = paper.margin_mm
            for it in page.items:
                if isinstance(it, L.Polyline):
                    for x, y in it.points_mm:
                        assert m - 1e-6 <= x <= page.width_mm - m + 1e-6, (page.kind, it.role)
                        assert m - 1e-6 <= y <= page.height_mm - m + 1e-6, (page.kind, it.role)
                elif isinstance(it, L.Text) and it.string:
                    x0, y0, x1, y1 = it.box_mm
                    assert x0 >= m - 1e-6 and x1 <= page.width_mm - m + 1e-6, (page.kind, it.string)
                    assert y0 >= m - 1e-6 and y1 <= page.height_mm - m + 1e-6, (page.kind, it.string)


def test_no_text_overlaps_text():
    for level, paper in (("novice", A4L), ("apprentice", A4L), ("master", A4P)):
        _, pages = workbook(level, paper)
        for page in pages:
            boxes = [(t, t.box_mm) for t in texts(page)]
            for i, (ta, a) in enumerate(boxes):
                for tb, b in boxes[i + 1:]:
                    overlap = min(a[2], b[2]) - max(a[0], b[0]) > 0.1 and \
                        min(a[3], b[3]) - max(a[1], b[1]) > 0.1
                    assert not overlap, (page.kind, ta.string, tb.string)


def test_margin_below_5mm_is_refused():
    plan = make_plan()
    with pytest.raises(RenderError, match="margin"):
        L.lay_out_workbook("t", plan, PaperSpec("A4", "landscape", 4.0), view_label="v")


# ----------------------------------------------------------------------------- step panels


def _panel_of(page, k=0):
    return [it for it in page.items if isinstance(it, L.Rect) and it.role == "paper"][k]


def test_step_panel_maps_the_sheet_uniformly_and_keeps_strokes_inside():
    plan, pages = workbook("novice")
    for i, page in enumerate(pages[2:7]):
        paper = _panel_of(page)
        s = paper.w_mm / plan.paper_mm[0]
        # uniform scale: the sheet's aspect 297/210 is kept
        assert paper.h_mm == pytest.approx(plan.paper_mm[1] * s, abs=1e-9)
        new = polylines(page, "stroke_new")
        assert len(new) == len(plan.steps[i].strokes)  # nothing clipped: strokes are on the sheet
        first = plan.steps[i].strokes[0].points_mm[0]
        assert new[0].points_mm[0] == pytest.approx((paper.x_mm + first[0] * s, paper.y_mm + first[1] * s))
        for it in polylines(page):
            if it.role.startswith(("stroke", "guide")):
                for x, y in it.points_mm:
                    assert paper.x_mm - 1e-6 <= x <= paper.x_mm + paper.w_mm + 1e-6
                    assert paper.y_mm - 1e-6 <= y <= paper.y_mm + paper.h_mm + 1e-6
        assert new[0].colour == "orange"
        if i:
            assert {it.colour for it in polylines(page, "stroke_earlier")} == {"grey"}
            # earlier strokes: every stroke of steps 1..i
            assert len(polylines(page, "stroke_earlier")) == sum(len(st.strokes) for st in plan.steps[:i])


def test_guide_lifetime_colours_and_greyscale_styles():
    plan, pages = workbook("novice")
    by_step = {i + 1: page for i, page in enumerate(pages[2:7])}
    def roles(p):
        return sorted(it.role for it in polylines(p) if it.role.startswith("guide"))
    assert roles(by_step[1]) == []
    assert roles(by_step[2]) == ["guide_new", "guide_new"]          # g_half, g_mid new
    assert roles(by_step[3]) == ["guide_idle", "guide_reused"]      # g_half reused, g_mid waits
    assert roles(by_step[4]) == ["guide_new", "guide_reused"]       # g_top new, g_mid reused
    assert roles(by_step[5]) == []                                   # all retired
    assert {it.colour for it in polylines(by_step[2], "guide_new")} == {"orange"}
    assert {it.colour for it in polylines(by_step[3])if it.role.startswith("guide")} == {"blue"}
    # greyscale: every line meaning differs by dash pattern or width
    keys = ["earlier", "earlier_hidden", "ink", "new", "new_hidden", "guide_new", "guide_reused",
            "guide_idle", "vanishing"]
    looks = {(L.STYLES[k].width_mm, L.STYLES[k].dash_mm) for k in keys}
    assert len(looks) == len(keys)
    # idle guide g_mid at step 3 is drawn where step 2 put it
    paper = _panel_of(by_step[3])
    s = paper.w_mm / plan.paper_mm[0]
    g_mid = plan.steps[1].guides[1]
    idle = polylines(by_step[3], "guide_idle")[0]
    assert idle.points_mm[0] == pytest.approx((paper.x_mm + g_mid.from_mm[0] * s,
                                               paper.y_mm + g_mid.from_mm[1] * s))


def test_erase_hint_counts_retired_guides():
    plan, pages = workbook("novice")
    hints = {i + 1: " ".join(t.string for t in texts(p, "erase_hint")) for i, p in enumerate(pages[2:7])}
    assert hints[1] == "" and hints[2] == ""
    assert "1 guide line" in hints[3]   # g_half shown at 3, gone at 4
    assert "2 guide lines" in hints[4]  # g_mid, g_top gone at 5


def test_instruction_text_is_wrapped_whole_and_spelled_for_the_font():
    plan, pages = workbook("apprentice")
    got = [" ".join(t.string for t in p.items if isinstance(t, L.Text)
                    and t.role in ("headline", "substep", "summary")) for p in pages[2:5]]
    joined = " ".join(got)
    for step in plan.steps:
        assert L.plain_text(step.headline or step.text) in joined
    assert "⅓ of the body" in joined  # DejaVu Sans draws the fraction itself
    # a font without it (Computer Modern, from matplotlib too) gets it spelled
    from h2s_print import fonts

    cm = fonts.default_spec().regular.with_name("cmr10.ttf")
    with fonts.using(fonts.FontSpec(cm, cm, cm, "cmr10")):
        assert L.plain_text("⅓ of the body") == "1/3 of the body"


def test_plain_text_is_each_character_spelled_for_the_font():
    """:func:`layout.plain_text` prints a text by a table of its characters, each worked out
    once a font: the text is the definition's, character by character (itself when the font
    draws it, else its spelling, else ``?``), in DejaVu Sans and in Computer Modern, which
    lacks the fractions, arrows and Cyrillic.  Seeded texts of ASCII, tabs and line breaks,
    the spelled characters and others no font here draws."""
    from h2s_print import fonts
    from h2s_print.glyphs import SPELL, printable, spelled

    rng = np.random.default_rng(15)
    alphabet = list("Ab 3.,'") + ["\t", "\n", "é", "Ж", "·", "–", "\u4e2d", "\U0001f600"]
    alphabet += list(SPELL)
    cm = fonts.default_spec().regular.with_name("cmr10.ttf")
    spelled_out = 0
    for spec in (None, fonts.FontSpec(cm, cm, cm, "cmr10")):
        with fonts.using(spec):
            for trial in range(300):
                text = "".join(rng.choice(alphabet, size=int(rng.integers(0, 12))))
                want = "".join(spelled(ch) if printable(ch) else "?" for ch in text)
                assert L.plain_text(text) == want, (spec, trial, text)
                spelled_out += want != text
    assert spelled_out > 100  # the cases are spelled


def test_headline_and_numbered_substeps_are_set_in_order():
    plan, pages = workbook("novice")
    step = replace(plan.steps[1], headline="Lens: a box.", substeps=(
        "Draw the diagonals AC and BD.", "Through E, draw FG toward the left vanishing point."))
    items, _ = L._instruction(10.0, 100.0, 120.0, step, 11.0)
    head = [t for t in items if t.role == "headline"]
    nums = [t for t in items if t.role == "substep_number"]
    subs = [t for t in items if t.role == "substep"]
    assert [t.string for t in head] == ["Lens: a box."] and head[0].font == "Helvetica-Bold"
    assert [t.string for t in nums] == ["1.", "2."]
    assert [t.string for t in subs] == list(step.substeps)
    # each number sits on its sub-step's first baseline, the text indented past it
    for n, t in zip(nums, subs):
        assert n.y_mm == pytest.approx(t.y_mm) and t.x_mm == pytest.approx(10.0 + L.SUBSTEP_INDENT_MM)
    assert head[0].y_mm > subs[0].y_mm > subs[1].y_mm


def test_vanishing_lines_head_for_the_vps():
    plan, pages = workbook("novice")
    page = pages[2]
    paper = _panel_of(page)
    s = paper.w_mm / plan.paper_mm[0]
    lines = polylines(page, "vanishing")
    finite = [vp for vp in plan.vanishing_points if not vp.at_infinity]
    assert len(finite) == 2 and len(lines) == 4  # two enclosing lines per finite VP
    for ln in lines:
        (ax, ay), (bx, by) = ln.points_mm
        # back to sheet mm, the line passes through one of the VPs
        a = ((ax - paper.x_mm) / s, (ay - paper.y_mm) / s)
        b = ((bx - paper.x_mm) / s, (by - paper.y_mm) / s)
        dists = []
        for vp in finite:
            v = vp.xy_mm
            cross = (b[0] - a[0]) * (v[1] - a[1]) - (b[1] - a[1]) * (v[0] - a[0])
            dists.append(abs(cross) / math.dist(a, b))
        assert min(dists) < 1e-6


def test_vanishing_lines_run_through_a_point_the_step_draws(examples):
    """Each grey line toward a vanishing point runs through a point of the step's new lines
    (mostly a corner of its box), along an edge it draws, not past the box (a read-through:
    through the corners of the strokes' bounding box they missed the handle's corners).
    Checked on the page: through a vertex of a line drawn "now"."""
    t, plan, views = examples["roller"]
    pages = L.lay_out_workbook("t", views[("front-left", "novice")], A4L, view_label="v")
    checked = 0
    for page in pages:
        pts = [p for ln in polylines(page, "stroke_new") for p in ln.points_mm]
        for ln in polylines(page, "vanishing"):
            a, b = ln.points_mm
            d = min(abs((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]))
                    / math.dist(a, b) for p in pts)
            assert d < 1e-6, (page.number if hasattr(page, "number") else None, d)
            checked += 1
    assert checked >= 20


def test_vp_inside_a_panel_is_marked():
    plan = make_plan("novice")
    vp = VanishingPoint(0, False, (250.0, 120.0), (1.0, 0.0))
    plan2 = ViewPlan(plan.name, plan.level, plan.paper_mm, plan.camera, (vp,), plan.steps)
    page = L.lay_out_workbook("t", plan2, A4L, view_label="v")[2]
    paper = _panel_of(page)
    s = paper.w_mm / plan.paper_mm[0]
    mark, = [c for c in page.items if isinstance(c, L.Circle) and c.role == "vp"]
    assert (mark.cx_mm, mark.cy_mm) == pytest.approx((paper.x_mm + 250 * s, paper.y_mm + 120 * s))
    # named as the step texts name it: from the sheet centre (148.5, 105) the VP is
    # dx = 101.5, dy = 15 away, |dx| >= |dy| and dx > 0 -> "right"
    assert [t.string for t in texts(page, "vp_label")] == ["right vanishing point"]


def test_estimated_time():
    plan = make_plan()
    steps = len(plan.steps)
    guides = sum(g.status == "new" for s in plan.steps for g in s.guides)
    boxes = len({st.part for s in plan.steps if s.kind == "primitive" for st in s.strokes})
    ellipses = sum(st.kind == "ellipse" for s in plan.steps for st in s.strokes)
    outlined = len({st.part for s in plan.steps if s.kind == "contour" for st in s.strokes})
    want = (0.25 * steps + guides / 6 + 0.75 * boxes + 0.5 * ellipses + 0.75 * outlined)
    assert (steps, guides) == (5, 3) and boxes >= 1 and outlined >= 1
    assert L.estimate_minutes(plan) == max(5, 5 * math.ceil(want / 5 - 1e-9))
    # more to draw takes longer: a copy of the plan with one more guide on a step
    more = replace(plan, steps=(replace(plan.steps[0], guides=plan.steps[0].guides + tuple(
        replace(g, id=g.id + "x", status="new") for g in plan.steps[1].guides)),)
                   + plan.steps[1:])
    assert sum(g.status == "new" for s in more.steps for g in s.guides) > guides
    assert L.estimate_minutes(more) >= L.estimate_minutes(plan)
    _, pages = workbook()
    m = L.estimate_minutes(plan)
    assert any(f"about {m} minutes" in t.string for t in texts(pages[0]))


def test_the_papers_objects_take_15_to_45_minutes(examples):
    """Issue 11 point 5: the paper's four objects (its §6: "each tutorial takes between 15
    and 45 minutes") are estimated within that range, every view and level built."""
    seen = set()
    for name, (t, plan, views) in examples.items():
        for (view, level), vp in views.items():
            seen.add(name)
            assert 15 <= L.estimate_minutes(vp) <= 45, (name, view, level)
    assert seen == {"camera", "mixer", "train", "roller"}


def test_basic_level_is_just_steps_without_guides():
    plan, pages = workbook("basic", guides=False)
    assert all(not p.role.startswith("guide") for page in pages for p in polylines(page))
    assert any("basic" in t.string for t in texts(pages[0]))


GUIDE_WORDS = ("guide", "erase", "blue", "primer", "construction")


def test_basic_workbook_carries_no_how2sketch_material():
    """The control condition of a study: no primer page and no word about guides anywhere."""
    _, basic = workbook("basic", guides=False)
    # cover + ceil(5 steps / 2) = 3 step pages + final + sheet = 6: no primer
    assert [p.kind for p in basic] == ["cover", "steps", "steps", "steps", "final", "sheet"]
    words = " ".join(t.string for p in basic for t in texts(p)).lower()
    assert [w for w in GUIDE_WORDS if w in words] == []
    assert "primer" not in [b.title.lower() for p in basic for b in p.bookmarks]
    # ... while the How2Sketch workbook on the same plan has all of them (the test can fail)
    _, novice = workbook("novice")
    words = " ".join(t.string for p in novice for t in texts(p)).lower()
    assert [w for w in GUIDE_WORDS if w in words] == list(GUIDE_WORDS)


# ----------------------------------------------------------------------------- primer


def _meet(a, b, c, d):
    """Intersection of lines ab and cd."""
    (x1, y1), (x2, y2), (x3, y3), (x4, y4) = a, b, c, d
    den = (x1 - x2) * (y3 - y4) - (y1 - y2) * (x3 - x4)
    t = ((x1 - x3) * (y3 - y4) - (y1 - y3) * (x3 - x4)) / den
    return (x1 + t * (x2 - x1), y1 + t * (y2 - y1))


def _on_line(p, a, b):
    return abs((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])) / math.dist(a, b)


def test_primer_constructions_are_projectively_exact():
    d = {x.key: x for x in L.primer_diagrams()}
    assert set(d) == {"half", "quarter", "third", "extend", "extend_half", "ellipse"}
    def part(key, role):
        return [s for s in d[key].segments if s[2] == role]
    # 1/2: the result passes through the diagonals' crossing, and stays vertical (two-point)
    (ac, bd), (res,) = part("half", "construction"), part("half", "result")
    assert _on_line(_meet(ac[0], ac[1], bd[0], bd[1]), res[0], res[1]) < 1e-6
    assert res[0][0] == pytest.approx(res[1][0], abs=1e-6)
    # 1/3 (paper Fig. 3c): C-E meets diagonal B-D on the 1/3 line; D-F meets A-C on the 2/3 line
    (ac, bd, cross, ce, df), (r13, r23) = part("third", "construction"), part("third", "result")
    assert _on_line(_meet(bd[0], bd[1], ce[0], ce[1]), r13[0], r13[1]) < 1e-6
    assert _on_line(_meet(ac[0], ac[1], df[0], df[1]), r23[0], r23[1]) < 1e-6
    # 1/4 and 3/4 share the diagonals and the halving line: drawn once
    assert len(part("quarter", "construction")) == 3 + 4 and len(part("quarter", "result")) == 2
    # extend 1x (Fig. 3d): D-F (F = cross line meets edge BC) reaches the new corner S2
    face = part("extend", "face")
    ac, bd, cross, ext, connect = part("extend", "construction")
    new_edge = part("extend", "result")[0]
    bc = face[1]
    f = _meet(cross[0], cross[1], bc[0], bc[1])
    assert _on_line(f, connect[0], connect[1]) < 1e-6
    assert math.dist(connect[1], new_edge[0]) < 1e-6 and math.dist(ext[1], new_edge[0]) < 1e-6
    # the ellipse: the middle lines cross where the diagonals do; the ellipse passes through
    # their four ends (the edges' perspective middles) and stays inside the face
    ac, bd, m1, m2 = part("ellipse", "construction")
    centre = _meet(ac[0], ac[1], bd[0], bd[1])
    assert _on_line(centre, *m1[:2]) < 1e-6 and _on_line(centre, *m2[:2]) < 1e-6
    ring = [s[0] for s in part("ellipse", "result")]
    for end in (m1[0], m1[1], m2[0], m2[1]):
        assert min(math.dist(end, r) for r in ring) < 1e-6
    quad = [s[0] for s in part("ellipse", "face")]
    for r in ring:  # inside the convex face: on the inner side of every edge (or on it)
        sides = [((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])) / math.dist(p, q)
                 for p, q in zip(quad, quad[1:] + quad[:1])]  # signed distances, mm
        assert min(sides) >= -1e-5 or max(sides) <= 1e-5  # (points rounded to 1e-6 mm)


def test_primer_page_has_every_diagram_and_caption():
    _, pages = workbook()
    primer = pages[1]
    diagrams = L.primer_diagrams()
    assert len(texts(primer, "primer_title")) == len(diagrams) == 6
    # every segment of every diagram is drawn, none lost to clipping at its cell's edge
    for role in ("face", "construction", "result"):
        want = sum(1 for d in diagrams for s in d.segments if s[2] == role)
        assert len(polylines(primer, f"primer_{role}")) == want, role


# ----------------------------------------------------------------------------- calibrated sheet


def test_sheet_is_true_scale():
    plan = make_plan()
    page = S.lay_out_sheet("Digital camera", plan, margin_mm=12.0)
    assert (page.width_mm, page.height_mm) == (297.0, 210.0)  # = plan.paper_mm, 1 mm : 1 mm
    ground = polylines(page, "ground")
    assert len(ground) == 1
    # bottom face of the body (z = 0): its projection_mm positions are the page positions
    corners = [(0, 0, 0), (200, 0, 0), (200, 120, 0), (0, 120, 0)]
    expected = plan.camera.project(corners)
    got = ground[0].points_mm
    for e in expected:
        assert min(math.dist(e, g) for g in got) < 1e-9
    bar, = polylines(page, "scale_bar")
    assert math.dist(*bar.points_mm) == pytest.approx(100.0, abs=1e-9)
    assert any("print at 100% (actual size)" in t.string for t in texts(page))
    assert len(polylines(page, "corner")) == 4 and {p.colour for p in polylines(page, "corner")} == {"green"}
    # corners sit on the frame: 12 mm inside the paper
    assert {p.points_mm[1] for p in polylines(page, "corner")} == {(12, 12), (285, 12), (285, 198), (12, 198)}
    assert len([c for c in page.items if isinstance(c, L.Circle) and c.role == "registration"]) == 4


def test_sheet_horizon_and_far_vanishing_points():
    plan = make_plan(el_deg=5.0)
    _, geo = make_camera(el_deg=5.0)
    page = S.lay_out_sheet("Digital camera", plan)
    # two-point camera: the horizon is the line y = cy (eye height) across the sheet
    hz, = polylines(page, "horizon")
    assert all(y == pytest.approx(geo["cy"], abs=1e-9) for _, y in hz.points_mm)
    assert 12 <= geo["cy"] <= 198
    labels = [t.string for t in texts(page, "vp_label")]
    finite = [vp for vp in plan.vanishing_points if not vp.at_infinity]
    arrows = polylines(page, "vp_arrow")
    for vp in finite:
        on_sheet = 0 <= vp.xy_mm[0] <= 297 and 0 <= vp.xy_mm[1] <= 210
        assert not on_sheet  # this camera puts both far off the paper
    # each finite VP: an arrow whose tip's distance to the VP is printed
    tips = [a.points_mm[1] for a in arrows[0::2]]
    # VP x at (-591, 150), VP y at (511, 150): from the centre (148.5, 105) each is farther
    # sideways than up, x to the left and y to the right
    names = {0: "left vanishing point", 1: "right vanishing point"}
    assert [vp.axis for vp in finite] == [0, 1]
    for vp, tip, label in zip(finite, tips, labels):
        assert label == f"{names[vp.axis]}: {math.dist(tip, vp.xy_mm):.0f} mm beyond the arrow's tip"
        # the arrow points at the VP
        d = np.subtract(vp.xy_mm, tip)
        shaft = np.subtract(tip, arrows[0::2][tips.index(tip)].points_mm[0])
        assert np.dot(d, shaft) / np.linalg.norm(d) / np.linalg.norm(shaft) > 0.99
    assert "vertical edges: keep them parallel (no vanishing point)" in labels
    # the offset from the nearest green corner locates the VP exactly (to the printed mm)
    detail = [t.string for t in texts(page, "vp_detail")]
    vx = [vp for vp in finite if vp.axis == 0][0].xy_mm
    assert detail[0].startswith(f"{abs(vx[0] - 12):.0f} mm left")  # VP x left of the left frame edge


def test_sheet_horizon_off_the_paper_is_stated():
    plan = make_plan(el_deg=12.0)
    _, geo = make_camera(el_deg=12.0)
    assert geo["cy"] > 198  # eye above the frame's top (210 - 12)
    page = S.lay_out_sheet("Digital camera", plan)
    assert polylines(page, "horizon") == []
    note, = texts(page, "horizon_label")
    assert note.string == f"horizon: {geo['cy'] - 198:.0f} mm above the frame"


def _project_plans():
    """Plans on cameras from the project stage (three-point: a finite z VP; close: VP x on the
    sheet), for layout checks beyond the factory's own camera."""
    from h2s_print.config import ViewSpec
    from h2s_print.project import make_camera as project_camera, vanishing_points as project_vps

    pts = [(x, y, z) for x in (-40, 200) for y in (-40, 120) for z in (0, 110)]
    for view in (ViewSpec("tp", 30, 35, 2.0, 50, "three-point"),
                 ViewSpec("close", 45, 10, 1.6, 50, "two-point")):
        for paper in (A4L, A4P):
            cam = project_camera(view, pts, paper)
            yield make_plan(paper_mm=(paper.width_mm, paper.height_mm), camera=cam,
                            vps=project_vps(cam))


def test_sheet_text_does_not_overlap():
    plans = [make_plan(paper_mm=paper, el_deg=el) for el in (5.0, 12.0, 30.0)
             for paper in ((297.0, 210.0), (210.0, 297.0))]
    for plan in plans + list(_project_plans()):
            page = S.lay_out_sheet("Digital camera", plan)
            boxes = [(t.string, t.box_mm) for t in texts(page)]
            for i, (sa, a) in enumerate(boxes):
                for sb, b in boxes[i + 1:]:
                    assert not (min(a[2], b[2]) > max(a[0], b[0]) and min(a[3], b[3]) > max(a[1], b[1])), (sa, sb)


def test_horizon_agrees_with_the_project_stage():
    from h2s_print.project import horizon_mm

    drawn = 0
    for plan in list(_project_plans()) + [make_plan(el_deg=5.0)]:
        page = S.lay_out_sheet("t", plan)
        (x0, y0), (x1, y1) = horizon_mm(plan.camera)
        for line in polylines(page, "horizon"):
            drawn += 1
            for x, y in line.points_mm:  # on the project stage's line through (x0,y0), (x1,y1)
                cross = (x1 - x0) * (y - y0) - (y1 - y0) * (x - x0)
                assert abs(cross) / math.dist((x0, y0), (x1, y1)) < 1e-6
    assert drawn >= 1  # el 5 deg: the horizon crosses the frame


def _with_vps(plan, *points):
    """``plan`` with finite VPs of axes 0, 1, ... at ``points`` (direction from the centre)."""
    c = (plan.paper_mm[0] / 2, plan.paper_mm[1] / 2)
    vps = tuple(VanishingPoint(i, False, p, ((p[0] - c[0]) / math.dist(p, c),
                                             (p[1] - c[1]) / math.dist(p, c)))
                for i, p in enumerate(points))
    return ViewPlan(plan.name, plan.level, plan.paper_mm, plan.camera, vps, plan.steps)


def test_sheet_names_vanishing_points_like_the_steps():
    plan = make_plan()
    # centre (148.5, 105): (148.5, 900) is 795 mm above -> "above"; (-500, 100) -> "left"
    page = S.lay_out_sheet("t", _with_vps(plan, (148.5, 900.0), (-500.0, 100.0)))
    names = [t.string.split(":")[0] for t in texts(page, "vp_label")]
    assert names == ["vanishing point above", "left vanishing point"]
    # two VPs right of the centre share the side: each adds its edges (steps.yaml `edges`)
    page = S.lay_out_sheet("t", _with_vps(plan, (700.0, 150.0), (900.0, 60.0)))
    names = [t.string.split(":")[0] for t in texts(page, "vp_label")]
    assert names == ["right vanishing point of the left-right edges",
                     "right vanishing point of the front-back edges"]
    assert not any("VP" in t.string for t in texts(page))


def test_sheet_writes_part_names_with_spaces():
    from dataclasses import replace

    plan = make_plan()
    steps = (replace(plan.steps[0], part="shutter_button"),) + plan.steps[1:]
    plan = ViewPlan(plan.name, plan.level, plan.paper_mm, plan.camera, plan.vanishing_points, steps)
    label, = texts(S.lay_out_sheet("t", plan), "ground_label")
    assert label.string == "bottom face of the shutter button (step 1)"


def test_vp_on_the_sheet_is_marked_where_it_is():
    plan = make_plan()
    vp = VanishingPoint(0, False, (250.0, 120.0), (1.0, 0.0))
    plan2 = ViewPlan(plan.name, plan.level, plan.paper_mm, plan.camera, (vp,), plan.steps)
    page = S.lay_out_sheet("t", plan2)
    mark, = [c for c in page.items if isinstance(c, L.Circle) and c.role == "vp"]
    assert (mark.cx_mm, mark.cy_mm) == (250.0, 120.0)


# ----------------------------------------------------------------------------- book


def test_book_contents_outline_and_page_numbers():
    plan_a, pages_a = workbook("novice")
    _, pages_b = workbook("master")
    book = L.lay_out_book("Sketching everyday objects", [
        ("Camera > front-left > novice", pages_a), ("Camera > front-left > master", pages_b)])
    # title + 1 contents page + 9 + 7
    assert len(book) == 1 + 1 + len(pages_a) + len(pages_b) == 18
    nums = [t.string for t in texts(book[1], "contents_page")]
    assert nums == ["3", "12"]  # first workbook starts after title and contents; 3 + 9 = 12
    assert book[2].kind == "cover" and book[11].kind == "cover"
    marks = [(b.title, b.level) for p in book for b in p.bookmarks]
    assert marks[:6] == [("Title page", 0), ("Contents", 0), ("Camera", 0), ("front-left", 1),
                         ("novice", 2), ("Cover", 3)]
    assert ("master", 2) in marks and marks.count(("Camera", 0)) == 1
    footers = [t.string for p in book for t in texts(p, "page_number")]
    assert footers[0].endswith("page 1 of 18")
    # sheets carry no footer: 2 sheets -> 16 footers
    assert len(footers) == 16


# ----------------------------------------------------------------------------- helpers


def test_clip_and_wrap():
    pieces = L.clip_polyline([(-5, 5), (5, 5), (5, 15), (5, 20), (8, 5)], (0, 0, 10, 10))
    assert pieces == [[(0.0, 5.0), (5.0, 5.0), (5.0, 10.0)], [(7.0, 10.0), (8.0, 5.0)]]
    lines = L.wrap("a b " + "word " * 40, 50.0, 10)
    assert all(L.text_width_mm(s, 10) <= 50.0 for s in lines) and len(lines) > 3
    # the page font's own advance of 'M' (read from its hmtx table by fontTools, not by the
    # code under test): at 10 pt, advance/em * 10 pt
    from fontTools.ttLib import TTFont

    from h2s_print import fonts

    tt = TTFont(str(fonts.default_spec().regular))
    em = tt["head"].unitsPerEm
    advance = tt["hmtx"][tt.getBestCmap()[ord("M")]][0]
    assert L.text_width_mm("M", 10) == pytest.approx(advance / em * 10 * 25.4 / 72)
    assert L.text_width_mm("Ж", 10) > 0


def test_key_explains_guides_only_when_the_workbook_has_guides():
    from h2s_print.templates import lookup

    legend = lookup("pages", "legend")

    def key_texts(guides: bool) -> set[str]:
        plan = make_plan("apprentice", (A4L.width_mm, A4L.height_mm), guides=guides)
        pages = L.lay_out_workbook("T", plan, A4L, view_label="v")
        return {it.string for pg in pages if pg.kind == "steps" for it in texts(pg)}

    with_guides, without = key_texts(True), key_texts(False)
    assert legend["guide_new"] in with_guides and legend["guide_reused"] in with_guides
    assert legend["guide_new"] not in without and legend["guide_reused"] not in without
    assert legend["earlier"] in without  # the rest of the key stays


def test_a_crowded_picture_still_places_every_label_without_overlap():
    """A big assembly's step can carry more labels round one spot than the near rings hold:
    the labels go further out (LABEL_RADII_FAR_MM), still inside the picture and on no other
    label or dot; a picture that cannot hold them at all is a RenderError, never overlap."""
    from h2s_print.types import Label
    view = L._View((0.0, 0.0, 100.0, 60.0), (10.0, 10.0, 110.0, 70.0))
    labels = [Label(f"part {k}", (0.0, 0.0, 0.0), (50.0 + 0.3 * (k % 5), 30.0 + 0.3 * (k // 5)),
                    "part") for k in range(25)]
    items = L.place_labels(view, labels, [])
    boxes = [it.box_mm for it in items if isinstance(it, L.Text)]
    assert len(boxes) == 25
    for i, a in enumerate(boxes):
        assert 10.0 <= a[0] and a[2] <= 110.0 and 10.0 <= a[1] and a[3] <= 70.0
        assert not any(L._boxes_overlap(a, b) for b in boxes[i + 1:])
    far = max(math.dist(((b[0] + b[2]) / 2, (b[1] + b[3]) / 2), view.map(lb.at_mm))
              for b, lb in zip(boxes, labels))
    assert far > L.LABEL_RADII_MM[-1] + 5.0  # some had to go beyond the near rings
    tiny = L._View((0.0, 0.0, 10.0, 6.0), (0.0, 0.0, 10.0, 6.0))
    with pytest.raises(RenderError, match="no room"):
        L.place_labels(tiny, labels, [])


def _crossing_labels(sheet, segs) -> list[str]:
    return [it.string for it in sheet.items
            if isinstance(it, L.Text) and it.role in ("vp_label", "vp_detail", "horizon_label",
                                                      "ground_label")
            and L._crossings(segs, it.box_mm)]


def test_sheet_labels_keep_off_the_drawing(examples):
    """The calibrated sheet's labels are placed off the drawing's lines, where a person will
    draw (and where scoring a scan could not see the pencil), wherever the frame has room:
    on the camera and roller no label crosses a line; over the four objects fewer than half
    as many as without the rule (the train fills its frame, the mixer's head nearly touches
    its top); and never a label on a label."""
    with_rule = without = 0
    for name, (t, plan, views) in examples.items():
        for (view, level), vp in views.items():
            if level != "novice":
                continue
            lines = [s.points_mm for st in vp.steps for s in st.strokes]
            segs = L._segments([L.Polyline(tuple(p)) for p in lines])
            kept = S.lay_out_sheet(t.title, vp, margin_mm=t.paper.margin_mm, drawing=lines)
            plain = S.lay_out_sheet(t.title, vp, margin_mm=t.paper.margin_mm)
            crossing = _crossing_labels(kept, segs)
            if name in ("camera", "roller"):
                assert crossing == [], (name, view)
            with_rule += len(crossing)
            without += len(_crossing_labels(plain, segs))
            texts = [it for it in kept.items if isinstance(it, L.Text) and it.string]
            assert not any(L._boxes_overlap(a.box_mm, b.box_mm)
                           for i, a in enumerate(texts) for b in texts[i + 1:]), (name, view)
    assert 2 * with_rule < without


def test_sheet_labels_keep_off_the_drawings_surfaces():
    """Between its lines a label still lies where a person will draw (a table top): a label
    whose middle is inside the drawing's convex outline does not fit where one outside
    does, and is moved out of it along the frame's edge when there is room."""
    frame = (0.0, 0.0, 200.0, 150.0)
    hull = S._hull([(40.0, 30.0), (160.0, 30.0), (160.0, 120.0), (40.0, 120.0), (100.0, 75.0)])
    assert len(hull) == 4 and S._in_convex(hull, (100.0, 75.0))
    assert not S._in_convex(hull, (20.0, 75.0))
    on_top = [L.Text(90.0, 74.0, "bottom face of the top (step 1)", 7, "Helvetica", "start",
                     "blue", "ground_label")]
    assert S._fits(on_top, [], frame)
    assert not S._fits(on_top, [], frame, None, hull)
    moved = S._clear_of_texts(on_top, [], frame, False, None, hull)
    assert moved is not None
    b = moved[0].box_mm
    assert not S._in_convex(hull, ((b[0] + b[2]) / 2, (b[1] + b[3]) / 2))


def test_sheet_shows_the_first_boxs_nearest_upright_edge(examples):
    """The sheet fixes the first box's height too: besides its footprint, one dashed blue
    line is a vertical edge of that box as step 1 draws it (a scaffold stroke, the same
    mm), standing on a footprint corner, and of its four vertical edges the nearest to the
    camera.  Step 1 says so."""
    checked = 0
    for name, (t, plan, views) in examples.items():
        vp = views[(t.views[0].name, "novice")]
        sheet = S.lay_out_sheet(t.title, vp, margin_mm=t.paper.margin_mm)
        blue = [it for it in sheet.items if isinstance(it, L.Polyline)
                and it.role == "ground_edge"]
        first = vp.steps[0]
        verticals = [st for st in first.strokes if np.allclose(
            np.asarray(st.points3d[0])[:2], np.asarray(st.points3d[-1])[:2])
            and st.points3d[0][2] != st.points3d[-1][2]]
        assert len(verticals) == 4, name
        edge = [it for it in blue if len(it.points_mm) == 2 and any(
            np.allclose(sorted(it.points_mm), sorted(map(tuple, st.points_mm)), atol=1e-6)
            for st in verticals)]
        assert len(edge) == 1, name
        eye = np.asarray(vp.camera.position)
        dist = {id(st): np.linalg.norm(np.asarray(st.points3d[0])[:2] - eye[:2])
                for st in verticals}
        mine = next(st for st in verticals if np.allclose(
            sorted(edge[0].points_mm), sorted(map(tuple, st.points_mm)), atol=1e-6))
        assert dist[id(mine)] == min(dist.values()), name
        heights = {lookup("steps", "substep.first_height"),
                   lookup("steps", "substep.first_height_floor")}
        assert heights & set(first.substeps)
        checked += 1
    assert checked == 4


def test_step_one_shows_the_lines_the_sheet_prints(examples):
    """The first box is drawn on the sheet's printed footprint and upright edge, not by eye:
    step 1 lists them as its guides (role ``sheet``) at novice and apprentice, each the
    projection of its 3D ends, the footprint the first box's bottom face (the box around the
    step's strokes) and the sheet's printed lines exactly (same mm); shown at step 1 only,
    drawn over the box in the sheet's style; never at master or in the control tutorial,
    which have no guides."""
    checked = 0
    for name, (t, plan, views) in examples.items():
        for (view, level), vp in views.items():
            printed = [(i, g) for i, st in enumerate(vp.steps) for g in st.guides
                       if g.role == "sheet"]
            if level in ("basic", "master"):  # no guides at all (DESIGN.md §2.6)
                assert not printed
                continue
            first = next(i for i, st in enumerate(vp.steps) if st.kind == "primitive")
            # the floor line below a first box above the floor is shown again where a step
            # stands a part on the floor ("Its bottom stands on the floor ...")
            floor = [(i, g) for i, g in printed if g.id == seq_drafts.SHEET_FLOOR]
            on_floor = (lookup("steps", "substep.on_floor"),
                        lookup("steps", "substep.on_floor_eye"))
            on_line = lookup("steps", "substep.on_floor_line").split("{")[0]
            side = lookup("steps", "substep.floor_side").split("}")[-1]  # " stands on it."
            # (a line drawn from the floor line's foot: the floor under the roller's handle)
            foot = lookup("steps", "substep.floor_line").split("}")[1].split("{")[0]
            assert {i for i, g in floor if i != first} == {
                i for i, st in enumerate(vp.steps) if any(
                    x in on_floor or x.startswith(on_line) or x.endswith(side) or foot in x
                    for x in st.substeps)}
            if floor:
                (_, g), = [(i, g) for i, g in floor if i == first]
                z0 = min(c.box[0][2] for c in plan.chosen().values())
                assert g.to3d[2] == z0 and g.from3d[:2] == g.to3d[:2]
                assert all(x.status == "reused" for i, x in floor if i != first)
            printed = [(i, g) for i, g in printed if g.id != seq_drafts.SHEET_FLOOR or i == first]
            assert {i for i, _ in printed} == {first}, (name, view, level)
            guides = [g for _, g in printed if g.id != seq_drafts.SHEET_FLOOR]
            assert all(g.status == "new" for g in guides)
            for g in guides:
                mm = vp.camera.project(np.array([g.from3d, g.to3d], dtype=float))
                assert np.allclose(mm, [g.from_mm, g.to_mm], atol=1e-9)
            pts = np.array([p for s in vp.steps[first].strokes for p in s.points3d])
            lo, hi = pts.min(axis=0), pts.max(axis=0)
            foot = [g for g in guides if g.from3d[2] == g.to3d[2]]
            assert len(foot) == 4
            corners = {tuple(np.round(g.from3d, 9)) for g in foot}
            assert corners == {(round(x, 9), round(y, 9), round(lo[2], 9))
                               for x in (lo[0], hi[0]) for y in (lo[1], hi[1])}
            upright = [g for g in guides if g.from3d[2] != g.to3d[2]]
            assert [(g.from3d[2], g.to3d[2]) for g in upright] == [(lo[2], hi[2])]
            later = vp.steps[first + 1]
            assert not any(g.id in later.alive for g in guides)
            # the sheet prints these very lines
            sheet = S.lay_out_sheet(t.title, vp, margin_mm=t.paper.margin_mm)
            quad = [it for it in sheet.items if isinstance(it, L.Polyline) and it.role == "ground"]
            edge = [it for it in sheet.items if isinstance(it, L.Polyline)
                    and it.role == "ground_edge"]
            assert len(quad) == 1 and len(edge) == 1 + bool(floor)
            ring = {(round(x, 6), round(y, 6)) for x, y in quad[0].points_mm}
            assert ring == {(round(x, 6), round(y, 6)) for x, y in (g.from_mm for g in foot)}
            assert np.allclose(sorted(edge[0].points_mm),
                               sorted([upright[0].from_mm, upright[0].to_mm]), atol=1e-9)
            for (_, g), line in zip(floor[:1], edge[1:]):  # the floor line, printed as shown
                assert np.allclose(sorted(line.points_mm), sorted([g.from_mm, g.to_mm]),
                                   atol=1e-9)
            # drawn after (over) the box's strokes, in the sheet's dashed blue
            page_items = L._drawing(L._View((0, 0, *vp.paper_mm), (0, 0, *vp.paper_mm)), vp,
                                    first)
            roles = [it.role for it in page_items if isinstance(it, L.Polyline)]
            assert "guide_sheet" in roles
            assert max(i for i, r in enumerate(roles) if r == "stroke_new") < min(
                i for i, r in enumerate(roles) if r == "guide_sheet")
            checked += 1
    assert checked >= 8


def test_the_control_tutorials_step_one_shows_the_lines_its_sheet_prints(examples):
    """The control tutorial has no guides, but its sheet prints the first box's footprint
    and nearest upright edge (and the floor line) like every sheet, and its step 1 says to
    draw on them: its picture shows those very lines (same mm as the sheet) in the sheet's
    dashed blue, at step 1 only, with their key, and not as guides (role ``printed``; a study
    designer's review: "Its bottom is the blue footprint on your sheet" beside a picture with
    no blue line)."""
    checked = 0
    ident = None
    for name, (t, plan, views) in examples.items():
        for view in t.views:
            vp = views[(view.name, "basic")]
            ident = L._View((0, 0, *vp.paper_mm), (0, 0, *vp.paper_mm))
            sheet = S.lay_out_sheet(t.title, vp, margin_mm=t.paper.margin_mm)
            lines = [it for it in sheet.items if isinstance(it, L.Polyline)
                     and it.role in ("ground", "ground_edge")]
            want = set()
            for it in lines:
                pts = list(it.points_mm) + ([it.points_mm[0]] if it.closed else [])
                want |= {tuple(sorted((tuple(np.round(a, 6)), tuple(np.round(b, 6)))))
                         for a, b in zip(pts, pts[1:])}
            assert len(want) >= 5, (name, view.name)
            for i, st in enumerate(vp.steps):
                items = L._drawing(ident, vp, i)
                got = {tuple(sorted((tuple(np.round(it.points_mm[0], 6)),
                                     tuple(np.round(it.points_mm[-1], 6)))))
                       for it in items if isinstance(it, L.Polyline) and it.role == "printed"}
                if i == 0:
                    assert got == want, (name, view.name)
                    assert "footprint" in st.text
                else:
                    assert not got, (name, view.name, i)
            assert not any(st.guides for st in vp.steps)  # still none in the plan
            assert "guide_sheet" in L._legend_keys(vp)
            checked += 1
    assert checked == 8


def _novice_sheets(examples):
    """(name, view, tutorial, view plan, drawing sheet) of every example's novice views."""
    for name, (t, plan, views) in examples.items():
        for (view, level), vp in views.items():
            if level == "novice":
                yield name, view, t, vp, S.lay_out_sheet(t.title, vp, margin_mm=t.paper.margin_mm)


def test_sheet_arrows_keep_off_the_printed_first_box_and_point_at_their_vanishing_points(examples):
    """A vanishing point's arrow on the sheet is never beside the first box's printed lines
    (the mixer's high-right arrow below ran 1 mm from the blue upright line, and a reader
    took one for the other): its shaft keeps 6 mm off them, and it still lies on a line
    through its vanishing point."""
    moved = 0
    for name, view, t, vp, sheet in _novice_sheets(examples):
        lines = [it for it in sheet.items if isinstance(it, L.Polyline)]
        ground = L._segments([it for it in lines if it.role in ("ground", "ground_edge")])
        shafts = [it for it in lines if it.role == "vp_arrow" and len(it.points_mm) == 2]
        for sh in shafts:
            tail, tip = (np.asarray(p) for p in sh.points_mm)
            d = tip - tail
            # it points at one of the view's vanishing points (or along one at infinity)
            ok = False
            for v in vp.vanishing_points:
                if v.at_infinity or v.xy_mm is None:
                    u = np.asarray(v.direction_mm, dtype=float)
                    ok |= abs(d[0] * u[1] - d[1] * u[0]) <= 1e-6 * np.linalg.norm(d) * np.linalg.norm(u)
                else:
                    w = np.asarray(v.xy_mm, dtype=float) - tip
                    ok |= (abs(d[0] * w[1] - d[1] * w[0]) <= 1e-6 * np.linalg.norm(d) * np.linalg.norm(w)
                           and np.dot(d, w) > 0)
            assert ok, (name, view)
            for k in np.linspace(0, 1, 7):
                p = tail + k * d
                for x0, y0, x1, y1 in ground:
                    a, b = np.array([x0, y0]), np.array([x1, y1])
                    t_ = np.clip(np.dot(p - a, b - a) / max(np.dot(b - a, b - a), 1e-12), 0, 1)
                    assert np.linalg.norm(p - (a + t_ * (b - a))) >= S.ARROW_CLEAR_MM - 1e-9, \
                        (name, view)
        moved += name == "mixer" and view == "high-right"
    assert moved


def test_sheet_ticks_of_one_name_lie_on_a_line_through_their_vanishing_point(examples):
    """A vanishing point off the sheet gets named tick pairs on the frame ("R3" twice): the
    line through a pair's two frame points passes through that vanishing point, so a ruler
    laid through them draws toward it with no taped-on paper (the read-throughs: the
    camera's right vanishing point is 392 mm off, the roller's left one 859 mm).  Each name
    is used twice, on the frame's border, and the sheet says what the ticks are for, by one
    pair ("the two marked R1"; a list "R1-R2" a read-through took for a line to draw)."""
    pairs = 0
    for name, view, t, vp, sheet in _novice_sheets(examples):
        frame = L._frame_box(vp.paper_mm, t.paper.margin_mm)
        items = list(sheet.items)
        ticks: dict[str, list] = {}
        for a, b in zip(items, items[1:]):
            if isinstance(a, L.Polyline) and a.role == "vp_tick":
                assert isinstance(b, L.Text) and b.role == "vp_tick_label"
                ticks.setdefault(b.string, []).append(np.asarray(a.points_mm[0]))
        far = [np.asarray(v.xy_mm, dtype=float) for v in vp.vanishing_points
               if not v.at_infinity and v.xy_mm is not None
               and not (frame[0] <= v.xy_mm[0] <= frame[2]
                        and frame[1] <= v.xy_mm[1] <= frame[3])]
        legend = [it for it in items if isinstance(it, L.Text) and it.role == "vp_tick_legend"]
        assert bool(ticks) == bool(legend), (name, view)
        marked = set()
        for tick_name, ends in ticks.items():
            assert len(ends) == 2, (name, view, tick_name)
            p, q = ends
            for e in ends:  # on the frame's border
                assert min(abs(e[0] - frame[0]), abs(e[0] - frame[2]), abs(e[1] - frame[1]),
                           abs(e[1] - frame[3])) < 1e-9
            d = q - p
            on = [k for k, v in enumerate(far) if abs(d[0] * (v - p)[1] - d[1] * (v - p)[0])
                  <= 1e-9 * np.linalg.norm(d) * np.linalg.norm(v - p)]
            assert on, (name, view, tick_name)
            marked.update(on)
            pairs += 1
        # every vanishing point off the sheet gets at least one pair (the desk's point below
        # had none: each of the first seven lines had a tick on that point's own label)
        if legend:
            assert marked == set(range(len(far))), (name, view)
            # the legend names one pair as its example, never a range of names ("R1-R2" read
            # as a line from R1 to R2)
            said = " ".join(it.string for it in legend)
            assert any(re.search(rf"(?<![A-Z0-9-]){n}(?![0-9-])", said) for n in ticks), said
            assert not re.search(r"[A-Z][0-9]+-[A-Z]?[0-9]", said), said
        # ticks keep apart, and no name lies on another's tick (the camera's L1 and R5 were
        # 3 mm apart, each name beside the other's tick)
        segs = [it for it in items if isinstance(it, L.Polyline) and it.role == "vp_tick"]
        ends = [np.asarray(it.points_mm[0]) for it in segs]
        for i, a in enumerate(ends):
            assert all(np.linalg.norm(a - b) >= S.TICK_GAP_MM - 1e-9 for b in ends[i + 1:]), \
                (name, view)
        names = [it for it in items if isinstance(it, L.Text) and it.role == "vp_tick_label"]
        for k, tx in enumerate(names):
            others = L._segments([sg for j, sg in enumerate(segs) if j != k])
            assert not L._crossings(others, tx.box_mm), (name, view, tx.string)
    assert pairs


def test_a_long_heading_or_stamp_keeps_left_of_the_ticks_line(examples):
    """The top band holds the heading (or a study's stamp) and the ticks' line: a long title
    shrinks to stay left of it; one too long for that keeps the band and the ticks' line
    shrinks after it, or the ticks are left out (a title never fails to fit because of
    them)."""
    from h2s_print.study import stamped

    t, plan, views = examples["camera"]
    vp = views[(t.views[0].name, "novice")]
    # too long to sit beside the ticks' line even at 5 pt: no ticks, and no error
    huge = S.lay_out_sheet("A very long title for a sketching workbook " * 4, vp,
                           margin_mm=t.paper.margin_mm)
    assert not [it for it in huge.items if getattr(it, "role", "").startswith("vp_tick")]
    sheet = S.lay_out_sheet("A long title for a sketching workbook " * 2, vp,
                            margin_mm=t.paper.margin_mm)
    legend = [it for it in sheet.items if isinstance(it, L.Text) and it.role == "vp_tick_legend"]
    assert legend
    for page, role in ((sheet, "sheet_title"),
                       (stamped(sheet, "X", (250.0, 2.0, 260.0, 12.0), "P01 · drawing 1 " * 3),
                        "stamp"),
                       (stamped(sheet, "X", (250.0, 2.0, 260.0, 12.0), "P01 · drawing 1 " * 14),
                        "stamp")):
        head = [it for it in page.items if isinstance(it, L.Text) and it.role == role]
        shown = [it for it in page.items if isinstance(it, L.Text) and it.role == "vp_tick_legend"]
        assert head and not any(L._boxes_overlap(head[0].box_mm, x.box_mm) for x in shown)


def test_every_line_style_of_a_step_picture_has_a_key(examples):
    """The key under a step explains every style its picture uses: the new part's hidden
    edges (dotted orange) were read as new guides when the key had no entry for them."""
    from h2s_print import layout

    for name, (_, _, views) in examples.items():
        for (view, level), vp in views.items():
            if level == "basic":
                continue
            keys = set(layout._legend_keys(vp))
            used = set()
            for step in vp.steps:
                for s in step.strokes:
                    if s.kind in ("scaffold_hidden", "ellipse_hidden"):
                        used.add("new_hidden")
                    elif s.kind in ("scaffold", "ellipse"):
                        used.add("new")
                used |= {"guide_sheet" if g.role == "sheet" else "guide_new" if g.status == "new"
                         else "guide_reused" for g in step.guides}
            assert used <= keys, (name, view, level, used - keys)
            assert "new_hidden" in used  # every example draws a box with hidden edges


def _arrows_clear_of_texts(name, view, sheet):
    arrows = [it for it in sheet.items if isinstance(it, L.Polyline)
              and it.role in ("vp_arrow", "horizon_arrow")]
    boxes = [it.box_mm for it in sheet.items if isinstance(it, L.Text) and it.string]
    assert not L._crossings_many(L._segments(arrows), boxes).any(), (name, view)


def test_no_sheet_arrow_runs_through_a_label(examples):
    """The drawing sheet's arrows (toward vanishing points, and the horizon's when it lies off
    the frame) cross no text.  A horizon note moved off its arrow goes without one: it says
    "above the frame"."""
    for name, view, _, _, sheet in _novice_sheets(examples):
        _arrows_clear_of_texts(name, view, sheet)


def test_the_desks_horizon_arrow_no_longer_runs_through_a_label(shared_models):
    """The read-through's case: the IKEA desk's high-right sheet drew the horizon's arrow
    through the left vanishing point's label."""
    from pathlib import Path

    from h2s_print import sequence as seq
    from h2s_print.config import load_tutorial
    from h2s_print.plan import build_plan

    t = load_tutorial(Path(__file__).resolve().parents[1] / "benchmarks" / "configs"
                      / "desk_fredrik.yaml")
    plan = build_plan(t.model, t.solver, t.views)
    for view in t.views:
        vp, = seq.sequence_views(plan, view, ("novice",), t.paper, t.sequence)
        _arrows_clear_of_texts("desk", view.name,
                               S.lay_out_sheet(t.title, vp, margin_mm=t.paper.margin_mm))


def test_an_apprentice_cover_says_to_draw_construction_lines_faintly(examples):
    from h2s_print import templates
    from h2s_print.layout import lay_out_workbook

    t, plan, views = examples["camera"]
    line = templates.text("pages", "cover.how_apprentice")
    for level in ("novice", "apprentice"):
        vp = views[(t.views[0].name, level)]
        cover = lay_out_workbook(t.title, vp, t.paper, view_label=vp.name)[0]
        said = " ".join(it.string for it in cover.items if getattr(it, "role", "") == "how")
        assert (line.split()[0] + " " + line.split()[1] in said) == (level == "apprentice")


def test_part_names_keep_a_gap_from_other_labels(examples):
    """A part's short name keeps PART_LABEL_GAP_MM from other labels where the near rings
    have room (a preference, so checked between parts' names, which the examples' pictures
    always have room to part): the train's "wheel 5" and "wheel 7" sat 0.25 mm apart and
    read as one."""
    from h2s_print.layout import lay_out_workbook

    checked = 0
    for name, (t, plan, views) in examples.items():
        for view in t.views:
            vp = views[(view.name, "apprentice")]
            for page in lay_out_workbook(t.title, vp, t.paper, view_label=vp.name):
                texts = [it for it in page.items if isinstance(it, L.Text)
                         and it.role == "part_label"]
                for i, a in enumerate(texts):
                    if a.role != "part_label":
                        continue
                    g = L.PART_LABEL_GAP_MM
                    ax = a.box_mm
                    grown = (ax[0] - g, ax[1] - g, ax[2] + g, ax[3] + g)
                    for b in texts:
                        if b is not a:
                            assert not L._boxes_overlap(grown, b.box_mm), (name, a.string, b.string)
                    checked += 1
    assert checked > 10


def test_an_arrow_toward_parallels_points_the_way_its_label_finds_room(examples):
    """Parallels run both ways: the label of the vertical edges (a point at infinity) and
    its arrow go where the finished drawing is not, the way the arrow may point either
    (the roller's "vertical edges: keep them parallel" sat where its front face is drawn,
    above it, while the bottom of the sheet was empty: a read-through of stop 27)."""
    t, plan, views = examples["roller"]
    vp = views[(t.views[0].name, "novice")]
    lines = [s.points_mm for st in vp.steps for s in st.strokes]
    hull = S._hull([q for p in lines for q in p])
    sheet = S.lay_out_sheet(t.title, vp, margin_mm=t.paper.margin_mm, drawing=lines)
    label, = [it for it in sheet.items if isinstance(it, L.Text) and it.role == "vp_label"
              and "parallel" in it.string]
    b = label.box_mm
    assert not S._in_convex(hull, ((b[0] + b[2]) / 2, (b[1] + b[3]) / 2))
    for arrow in (it for it in sheet.items if isinstance(it, L.Polyline) and it.role == "vp_arrow"):
        assert not S._in_convex_all(hull, np.asarray(arrow.points_mm, dtype=float)).any()


def test_no_sheet_arrow_lies_in_the_finished_drawing(examples):
    """Every arrow toward a vanishing point lies off the finished drawing (its convex outline),
    moved along the frame's edge where the middle one would not: the arrow toward the vertical
    edges sat in the camera's, the mixer's and the bottle's drawings (its lid), the train's
    left one in its chimney (read-throughs).  Labels keep off it where there is room."""
    checked = 0
    for name, (t, plan, views) in examples.items():
        for view in t.views:
            vp = views[(view.name, "novice")]
            lines = [s.points_mm for st in vp.steps for s in st.strokes]
            hull = S._hull([q for p in lines for q in p])
            sheet = S.lay_out_sheet(t.title, vp, margin_mm=t.paper.margin_mm, drawing=lines)
            arrows = [it for it in sheet.items
                      if isinstance(it, L.Polyline) and it.role == "vp_arrow"]
            for arrow in arrows:
                pts = np.asarray(arrow.points_mm, dtype=float)
                assert not S._in_convex_all(hull, pts).any(), (name, view.name)
                checked += 1
            if name != "train":  # the train fills its frame
                for it in sheet.items:
                    if isinstance(it, L.Text) and it.role in ("vp_label", "vp_detail"):
                        b = it.box_mm
                        assert not S._in_convex(hull, ((b[0] + b[2]) / 2, (b[1] + b[3]) / 2)), \
                            (name, view.name, it.string)
    assert checked >= 8


def test_ticks_keep_off_the_arrows_tips_and_parallels_get_a_double_headed_arrow(examples):
    """A tick on the frame keeps TICK_GAP_MM from every arrow's tip, where the distance "beyond
    the arrow's tip" starts (the train's B2 tick ran beside the tip of its arrow toward the
    point below, a read-through); the arrow toward parallels has a head at each end (a
    direction: with one head it read as pointing at a vanishing point)."""
    checked = 0
    for name, (t, plan, views) in examples.items():
        for view in t.views:
            vp = views[(view.name, "novice")]
            lines = [s.points_mm for st in vp.steps for s in st.strokes]
            sheet = S.lay_out_sheet(t.title, vp, margin_mm=t.paper.margin_mm, drawing=lines)
            polys = [it for it in sheet.items if isinstance(it, L.Polyline)]
            shafts = [it for it in polys if it.role == "vp_arrow" and len(it.points_mm) == 2]
            ticks = [it for it in polys if it.role == "vp_tick"]
            for tick in ticks:
                for shaft in shafts:
                    assert math.dist(tick.points_mm[0], shaft.points_mm[-1]) >= \
                        S.TICK_GAP_MM - 1e-9, (name, view.name)
                    checked += 1
            heads = [it for it in polys if it.role == "vp_arrow" and len(it.points_mm) == 3]
            n_heads = [sum(1 for h in heads for end in shaft.points_mm
                           if math.dist(h.points_mm[1], end) < 1e-9) for shaft in shafts]
            parallels = sum(1 for v in vp.vanishing_points if v.at_infinity)
            assert sorted(n_heads) == [1] * (len(shafts) - parallels) + [2] * parallels, (
                name, view.name)
    assert checked > 50


def test_a_close_ups_caption_is_not_printed_across_the_object(examples):
    """A close-up in the picture goes where it and its caption cross the fewest of the
    object's lines: "the small frame, enlarged (do not draw the frames)" ran across the
    roller's frame arm (a read-through).  On the roller's views no caption crosses one
    (over the four examples, 111 crossings before, 21 after).  Every caption is level with
    its picture."""
    checked = 0
    for name, (t, plan, views) in examples.items():
        for (view, level), vp in views.items():
            if level == "basic":
                continue
            for page in L.lay_out_workbook(t.title, vp, t.paper, view_label=view):
                caps = [it for it in page.items if isinstance(it, L.Text)
                        and it.role == "close_up_caption"]
                if not caps:
                    continue
                strokes = L._segments([it for it in page.items if isinstance(it, L.Polyline)
                                       and it.role.startswith("stroke")])
                # level with the picture it belongs to (a read-through: beside the picture,
                # a close-up as tall as it had its caption over the page's header)
                papers = [it for it in page.items if isinstance(it, L.Rect)
                          and it.role == "paper"]
                for cap in caps:
                    if name == "roller":
                        assert L._crossings(strokes, cap.box_mm) == 0, (view, level)
                    b = cap.box_mm
                    assert any(r.y_mm - 1e-6 <= b[1] and b[3] <= r.y_mm + r.h_mm + 1e-6
                               for r in papers), (name, view, level, page.kind)
                    checked += 1
    assert checked >= 20


def _own_arrow_distances(sheet):
    """(label, distance in mm from its box to its own arrow's shaft) for each vanishing point's
    label: its arrow is the one laid out just before it."""
    out, shaft = [], None
    for it in sheet.items:
        if isinstance(it, L.Polyline) and it.role == "vp_arrow" and len(it.points_mm) == 2:
            shaft = it.points_mm
        if isinstance(it, L.Text) and it.role == "vp_label" and shaft is not None:
            b = it.box_mm
            pts = [np.asarray(shaft[0]) + t * (np.asarray(shaft[1]) - np.asarray(shaft[0]))
                   for t in np.linspace(0.0, 1.0, 25)]
            out.append((it.string, min(math.hypot(max(b[0] - x, 0, x - b[2]),
                                                  max(b[1] - y, 0, y - b[3])) for x, y in pts)))
    return out


def test_a_vanishing_points_label_sits_beside_its_arrow(examples):
    """A vanishing point's label goes beside its arrow where an arrow along the frame allows
    it, before a label moved far from its arrow: the bottle's "vanishing point below" sat
    47 mm from its arrow, next to a tick it seemed to name (a read-through).  On the camera,
    mixer and train sheets every such label is within 20 mm of its own arrow (the roller's
    high view keeps the room for its ticks instead: laid out without the preference)."""
    checked = 0
    for name in ("camera", "mixer", "train"):
        t, plan, views = examples[name]
        for view in t.views:
            vp = views[(view.name, "novice")]
            lines = [s.points_mm for st in vp.steps for s in st.strokes]
            sheet = S.lay_out_sheet(t.title, vp, margin_mm=t.paper.margin_mm, drawing=lines)
            for label, d in _own_arrow_distances(sheet):
                assert d <= 20.0, (name, view.name, label, d)
                checked += 1
    assert checked >= 6


def test_crossings_many_is_the_definition_pair_by_pair():
    """Issue 13: the counts, worked out only for the pairs whose ranges overlap, are those of
    the definition, one (box, segment) pair at a time: the x and y ranges overlap and the
    box's four corners are not all strictly on one side of the segment's line.  Seeded
    boxes and segments on a coarse grid, so that touching, collinear and zero-length ones
    occur."""
    rng = np.random.default_rng(13)

    def meets(seg, box):
        sx0, sy0, sx1, sy1 = seg
        x0, y0, x1, y1 = box
        if not (min(sx0, sx1) <= x1 and max(sx0, sx1) >= x0
                and min(sy0, sy1) <= y1 and max(sy0, sy1) >= y0):
            return False
        dx, dy = sx1 - sx0, sy1 - sy0
        sides = [dx * (cy - sy0) - dy * (cx - sx0)
                 for cx, cy in ((x0, y0), (x1, y0), (x1, y1), (x0, y1))]
        return not (all(s > 0 for s in sides) or all(s < 0 for s in sides))

    touching = 0
    for trial in range(300):
        n, k = int(rng.integers(0, 40)), int(rng.integers(1, 10))
        segs = rng.integers(0, 8, size=(n, 4)).astype(float) * (0.5 if trial % 2 else 1.0)
        lo = rng.integers(0, 8, size=(k, 2)).astype(float)
        size = rng.integers(0, 4, size=(k, 2)).astype(float)
        boxes = [(a, b, a + w, b + h) for (a, b), (w, h) in zip(lo.tolist(), size.tolist())]
        want = [sum(meets(tuple(s), box) for s in segs.tolist()) for box in boxes]
        assert L._crossings_many(segs, boxes).tolist() == want, trial
        touching += sum(want)
    assert touching > 100  # the cases do meet


def test_line_segments_are_each_lines_consecutive_points():
    """:func:`layout._line_segments` puts every line's points in one array: its rows are those
    of the definition, line by line in order (each point with the next, a closed line's last
    with its first, none for a line of one point), each with its line's index; seeded lines
    of one to five points, open and closed, among items that are not lines."""
    rng = np.random.default_rng(14)
    for trial in range(200):
        lines = [L.Polyline(tuple(map(tuple, rng.normal(size=(int(rng.integers(1, 6)), 2))
                                      .round(int(rng.integers(0, 4))).tolist())),
                            closed=bool(rng.integers(0, 2)))
                 for _ in range(int(rng.integers(0, 8)))]
        want, owners = [], []
        for k, ln in enumerate(lines):
            if len(ln.points_mm) > 1:
                pts = (*ln.points_mm, ln.points_mm[0]) if ln.closed else ln.points_mm
                for a, b in zip(pts, pts[1:]):
                    want.append((a[0], a[1], b[0], b[1]))
                    owners.append(k)
        segs, owner = L._line_segments(lines)
        assert segs.shape == (len(want), 4) and segs.tolist() == [list(r) for r in want], trial
        assert owner.tolist() == owners, trial
        items = [L.Text(0.0, 0.0, "x", 7.0), *lines, L.Circle(0.0, 0.0, 1.0)]
        assert L._segments(items).tolist() == segs.tolist(), trial


def test_the_primer_says_sizes_compare_the_real_parts_where_a_step_compares_one(examples):
    """Where a sub-step compares a size with another part's ("Make its width about three
    quarters of the engine's"), the primer says the comparison is of the real parts, not of
    lengths on the paper (a read-through measured the train's nearer wagon against the engine
    with a ruler), or with another of its own sizes ("the same as its depth"), or a master's
    ratio words place a part at a fraction or multiple of another's size ("at a quarter of the
    body's width", a read-through of the masters); a workbook without any does not get it.  The comparisons are found here by
    their words, the step's "Make its ... about ...'s" or "... the same as its ..."."""
    from h2s_print import templates
    from h2s_print.layout import lay_out_workbook

    first = " ".join(templates.text("pages", "primer.sizes").split()[:4])
    said = {True: 0, False: 0}
    for name, (t, plan, views) in examples.items():
        for view in t.views:
            for level in ("novice", "master"):
                vp = views[(view.name, level)]
                compares = any(re.match(r"Make its [a-z ,]+ (?:about .+'s|the same as its)", x)
                               for st in vp.steps for x in st.substeps) or any(
                    # a master's ratio words: a fraction or a multiple of a part's size
                    re.search(r"\bat (?:a quarter|a third|half|two thirds|three quarters)"
                              r"(?: and [a-z ]+)? of .+'s (?:width|depth|height)"
                              r"|\b(?:one|half a) .+ (?:width|depth|height)\b", st.summary)
                    for st in vp.steps)
                primer = lay_out_workbook(t.title, vp, t.paper, view_label=view.name)[1]
                text = " ".join(" ".join(it.string for it in primer.items
                                         if getattr(it, "role", "") == "intro").split())
                assert (first in text) == compares, (name, view.name, level)
                said[compares] += 1
    # (every example compares one somewhere: the same steps with nothing compared)
    bare = replace(vp, steps=tuple(replace(st, substeps=(), summary="") for st in vp.steps))
    primer = lay_out_workbook(t.title, bare, t.paper, view_label=view.name)[1]
    assert first not in " ".join(" ".join(it.string for it in primer.items
                                          if getattr(it, "role", "") == "intro").split())
    assert said[True] >= 16, said


def test_the_primer_explains_away_from_and_upright_vanishing_points(examples):
    """The primer says what "away from" a vanishing point means, and, in a view whose upright
    edges run toward a vanishing point (seen from high or low: the axis-2 point finite on
    the sheet), names that point in the steps' words (a read-through of the high views met
    "toward the vanishing point below" nowhere explained); a view with vertical uprights
    does not get the sentence."""
    from h2s_print import templates
    from h2s_print.layout import lay_out_workbook
    from h2s_print.project import vp_side

    def words(s: str) -> str:  # the first words (the page wraps the text)
        return " ".join(s.split()[:4])

    said = {True: 0, False: 0}
    for name, (t, plan, views) in examples.items():
        for view in t.views:
            vp = views[(view.name, "novice")]
            primer = lay_out_workbook(t.title, vp, t.paper, view_label=view.name)[1]
            text = " ".join(it.string for it in primer.items
                            if getattr(it, "role", "") == "intro")
            assert words(templates.text("pages", "primer.away")) in text
            centre = (vp.camera.paper_mm[0] / 2, vp.camera.paper_mm[1] / 2)
            up = [vp_side(v, centre) for v in vp.vanishing_points
                  if v.axis == 2 and vp_side(v, centre) is not None]
            upright = words(templates.text("pages", "primer.upright", vp="x"))
            assert (upright in text) == bool(up), (name, view.name)
            if up:
                toward = templates.lookup("steps", f"vp.{up[0]}")
                assert toward in " ".join(text.split()), (name, view.name)
            said[bool(up)] += 1
    assert said[True] and said[False], said


def _places_one_by_one(dot, w, rings, near):
    """The free places round ``dot`` as place_labels once tested them, one at a time (the
    definition :func:`layout._scored_places` must keep): by ring, ``(direction, x, y,
    ambiguous, crowded, lines crossed)``."""
    dx, dy = dot
    pad, cap, desc = L._LABEL_PAD_MM, L._LABEL_CAP_MM, L._LABEL_DESC_MM
    x0, y0, x1, y1 = near.rect
    out = {}
    for ri, r in enumerate(rings):
        free = []
        for di, (ux, uy) in enumerate(L._LABEL_DIRS if r else ((0, 0),)):
            norm = math.hypot(ux, uy) or 1.0
            cx, cy = dx + r * ux / norm, dy + r * uy / norm
            bx0 = cx if ux > 0 else (cx - w if ux < 0 else cx - w / 2)
            by0 = cy if uy > 0 else (cy - cap - desc if uy < 0 else cy - (cap + desc) / 2)
            box = (bx0 - pad, by0 - pad, bx0 + w + pad, by0 + cap + desc + pad)
            if box[0] < x0 or box[1] < y0 or box[2] > x1 or box[3] > y1:
                continue
            if any(L._boxes_overlap(box, tuple(t)) for t in near.rest.tolist()):
                continue
            g = L.PART_LABEL_GAP_MM
            grown = (box[0] - g, box[1] - g, box[2] + g, box[3] + g)
            crowded = any(L._boxes_overlap(grown, tuple(t)) for t in near.gapped.tolist())
            mx, my = (box[0] + box[2]) / 2, (box[1] + box[3]) / 2
            own = math.hypot(mx - dx, my - dy)
            ambiguous = any(math.hypot(mx - ox, my - oy) < own for ox, oy in near.dots.tolist())
            n = int(L._crossings_many(near.segs, [box])[0])
            if len(near.corners):
                gap = float(np.hypot(mx - near.corners[:, 0], my - near.corners[:, 1]).min())
                n += gap < own
            if len(near.new):
                grow = L.STYLES["new"].width_mm / 2 + pad
                n += (L.NEW_LINE_WEIGHT - 1) * int(L._crossings_many(
                    near.new, [(box[0] - grow, box[1] - grow, box[2] + grow, box[3] + grow)])[0])
            free.append((di, bx0, by0, ambiguous, crowded, n))
        if free:
            out[ri] = free
    return out


def test_a_labels_places_at_once_are_its_places_one_by_one():
    """place_labels scores the places of several rings at once (:func:`layout._scored_places`):
    each ring's best place and every term of its score are those of the places tested one at
    a time (the first of the least score, in direction order).  Seeded pictures on a coarse grid, so that equal distances (a place as near
    another dot as its own), touching boxes and lines through corners occur."""
    rng = np.random.default_rng(20)
    ambiguous = crowded = 0
    for trial in range(200):
        grid = 0.5 if trial % 2 else 1.0

        def pts(n, cols=2, grid=grid):
            return rng.integers(0, 24, size=(n, cols)).astype(float) * grid

        rest = pts(int(rng.integers(0, 8)), 4)
        rest = np.hstack([np.minimum(rest[:, :2], rest[:, 2:]),
                          np.minimum(rest[:, :2], rest[:, 2:]) + 0.4 + rest[:, 2:] % 3])
        gapped = rest[: int(rng.integers(0, len(rest) + 1))]
        near = L._LabelSurroundings(rest=rest, gapped=gapped, dots=pts(int(rng.integers(0, 6))),
                                    corners=pts(int(rng.integers(0, 6))),
                                    segs=pts(int(rng.integers(0, 30)), 4),
                                    new=pts(int(rng.integers(0, 5)), 4),
                                    rect=(0.0, 0.0, 24.0 * grid, 20.0 * grid))
        dot = tuple(pts(1)[0].tolist())
        w = float(rng.choice([1.5, 2.5, 6.0]))
        for rings in ((0.0, *L.LABEL_RADII_MM), L.LABEL_RADII_MM, L.LABEL_RADII_FAR_MM):
            want = _places_one_by_one(dot, w, rings, near)
            # each ring's best as a scan in order keeps it (the first of the least score)
            best = {ri: min(ps, key=lambda p: (p[3], p[4], p[5], p[0]))
                    for ri, ps in want.items()}
            assert L._scored_places(dot, w, rings, near) == best, trial
            ambiguous += sum(p[3] for ps in want.values() for p in ps)
            crowded += sum(p[4] for ps in want.values() for p in ps)
    assert ambiguous > 50 and crowded > 50  # the cases occur


def test_nearer_other_is_math_hypot_pair_by_pair():
    """:func:`layout._nearer_other` measures only the pairs that can be nearer; its answers are
    those of math.hypot on every pair, ties (as near as its own dot: not nearer) included."""
    rng = np.random.default_rng(21)
    ties = 0
    for trial in range(300):
        points = rng.integers(-6, 7, size=(int(rng.integers(0, 12)), 2)).astype(float) * 0.5
        dots = rng.integers(-6, 7, size=(int(rng.integers(0, 8)), 2)).astype(float) * 0.5
        own = [math.hypot(*p) for p in rng.integers(-6, 7, size=(len(points), 2)) * 0.5]
        want = [any(math.hypot(px - dx, py - dy) < o for dx, dy in dots.tolist())
                for (px, py), o in zip(points.tolist(), own)]
        assert L._nearer_other(points, own, dots).tolist() == want, trial
        ties += sum(math.hypot(px - dx, py - dy) == o for dx, dy in dots.tolist()
                    for (px, py), o in zip(points.tolist(), own))
    assert ties > 20


def test_a_cover_keeps_every_part_name_on_the_page(shared_models):
    """The oven's cover listed its eleven parts' names down past the page's margin and lost
    the last (a read-through): the list takes columns side by side as it needs.  Every text of
    every cover of the oven's tutorials lies inside the margins (its descenders too), and each
    part's label is listed once."""
    from pathlib import Path

    from h2s_print.config import load_tutorial
    from h2s_print.pipeline import plan_tutorial

    t = load_tutorial(Path(__file__).resolve().parents[1] / "benchmarks" / "configs"
                      / "oven_101773.yaml")
    result = plan_tutorial(t)
    checked = 0
    for vp in result.views:
        cover = next(p for p in L.lay_out_workbook(t.title, vp, t.paper, view_label=vp.name)
                     if p.kind == "cover")
        for it in cover.items:
            if isinstance(it, L.Text):
                low = it.y_mm - 0.21 * it.size_pt * L.PT_MM
                assert low >= cover.margin_mm - 1e-6, (vp.name, vp.level, it.string)
                assert it.y_mm <= cover.height_mm - cover.margin_mm + 1e-6, it.string
        names = [it.string for it in cover.items
                 if isinstance(it, L.Text) and it.role == "part_name"]
        assert vp.part_names and len(names) == len(vp.part_names), (names, vp.part_names)
        for label, _ in vp.part_names:
            assert sum(x.startswith(f"{label}:") for x in names) == 1, (label, names)
        checked += 1
    assert checked >= 4


def test_an_erase_hint_names_whole_steps_only_when_all_their_guides_go():
    # a read-through counted "NP, XY, ZC, DE and 11 more guide lines" on the train's wheel
    # step: where the retiring guides are all the lines some steps drew (and still show),
    # the hint names those steps ("this step's guide lines", "the guide lines of steps 11
    # and 12"), checked against the plan: every guide those steps drew that is shown at
    # the step is gone at the next (none still needed is erased), and every guide gone
    # (but those along a scaffold edge, erased by no one) is one of theirs
    from pathlib import Path

    from h2s_print.config import load_tutorial
    from h2s_print.pipeline import plan_tutorial

    this = lookup("pages", "step")["erase_this"]
    forms = [re.compile(re.escape(v).replace(r"\{steps\}", r"(.+)") + "$")
             for v in lookup("pages", "step")["erase_steps"].values()]
    seen = 0
    for name in ("train", "camera"):
        t = load_tutorial(Path(__file__).resolve().parents[1] / "configs" / f"{name}.yaml")
        for vp in plan_tutorial(t).views:
            hints = L._erase_hints(vp)
            first: dict[str, int] = {}
            edges = []
            for i, step in enumerate(vp.steps):
                edges.append(L._step_edges(step))
                for g in step.guides:
                    if g.status == "new" and g.role != "sheet":
                        first.setdefault(g.id, i + 1)
                m = next((f.match(hints[i]) for f in forms if f.match(hints[i])), None)
                if hints[i] != this and m is None:
                    continue
                steps = ({i + 1} if m is None else
                         {int(n) for n in re.findall(r"\d+", m.group(1))})
                shown = {g.id: g for g, _ in L._step_guides(vp, i)}
                after = {g.id for g, _ in L._step_guides(vp, i + 1)}
                theirs = {g for g in shown if first.get(g) in steps}
                assert not theirs & after, (name, vp.name, vp.level, i + 1, hints[i])
                # (the scaffold edges so far and the next step's: a guide the next box is
                # drawn on is not erased)
                below = np.vstack(edges + [L._step_edges(s) for s in vp.steps[i + 1:i + 2]])
                gone = [g for g in shown if g not in after and L._off_edges(shown[g], below)]
                assert set(gone) <= theirs and gone, (name, vp.name, vp.level, i + 1)
                seen += 1
    assert seen >= 10



def test_an_erase_hint_never_counts_the_floor_line_printed_on_the_sheet():
    # the train's wheel step counted the printed floor line among "2 guide lines" to erase
    # (no one erases print): a step whose only guides gone are printed ones says nothing
    # of them, and a count is of guides the reader drew
    from pathlib import Path

    from h2s_print.config import load_tutorial
    from h2s_print.pipeline import plan_tutorial

    t = load_tutorial(Path(__file__).resolve().parents[1] / "configs" / "train.yaml")
    checked = 0
    for vp in plan_tutorial(t).views:
        hints = L._erase_hints(vp)
        for i in range(len(vp.steps) - 1):
            after = {g.id for g, _ in L._step_guides(vp, i + 1)}
            gone = [g for g, _ in L._step_guides(vp, i) if g.id not in after]
            drawn = [g for g in gone if g.role != "sheet"]
            if any(g.role == "sheet" for g in gone):
                checked += 1
                n = re.search(r"(\d+) (?:more )?guide line", hints[i])
                assert not n or int(n.group(1)) <= len(drawn), (vp.name, vp.level, i + 1)
                assert drawn or not hints[i], (vp.name, vp.level, i + 1, hints[i])
    assert checked >= 2


def test_sheet_ticks_bracket_the_drawing_toward_each_vanishing_point(examples):
    # the sheet's rule: a line toward a far vanishing point "runs between its two nearest
    # faint lines"; on the camera's high-right sheet both L lines passed below the whole
    # drawing (a read-through), so every line toward that point was guessed beyond the last.
    # Where a line just outside the drawing can cross the frame for a ruler (a chord as long
    # as the ticks need, its ends clear of the green corners), the ticks' lines pass on that
    # side of the finished drawing; checked from the angles at the vanishing point of the
    # ticks' lines and of the drawing's points
    import math

    from h2s_print.layout import _final_strokes, lay_out_workbook
    from h2s_print.sheet import _clip_segment

    possible = bracketed = 0
    for name, (t, plan, views) in examples.items():
        for (view, level), vp in views.items():
            if level != "novice":
                continue
            sheet = next(p for p in lay_out_workbook(t.title, vp, t.paper, view_label=view)
                         if p.kind == "sheet")
            frame = L._frame_box(vp.paper_mm, t.paper.margin_mm)
            corners = [(frame[0], frame[1]), (frame[2], frame[1]), (frame[2], frame[3]),
                       (frame[0], frame[3])]
            pts = np.array([q for s in _final_strokes(vp, None) for q in s.points_mm], float)
            items = list(sheet.items)
            ticks: dict[str, list] = {}
            for a, b in zip(items, items[1:]):
                if isinstance(a, L.Polyline) and a.role == "vp_tick":
                    ticks.setdefault(b.string, []).append(np.asarray(a.points_mm[0]))
            for v in vp.vanishing_points:
                if v.at_infinity or v.xy_mm is None:
                    continue
                o = np.asarray(v.xy_mm, float)
                if frame[0] <= o[0] <= frame[2] and frame[1] <= o[1] <= frame[3]:
                    continue
                mid = math.atan2(*(pts.mean(axis=0) - o)[::-1])

                def angle(p, o=o, mid=mid):
                    a = math.atan2(p[1] - o[1], p[0] - o[0]) - mid
                    return (a + math.pi) % (2 * math.pi) - math.pi

                def markable(a, o=o, mid=mid):  # a ruler's line at angle a (from mid)
                    d = (math.cos(mid + a), math.sin(mid + a))
                    hit = _clip_segment(tuple(o), (o[0] + 1e4 * d[0], o[1] + 1e4 * d[1]), frame)
                    return hit is not None and math.dist(*hit) >= S.TICK_CHORD * min(
                        frame[2] - frame[0], frame[3] - frame[1]) and all(
                        math.dist(p, c) >= S.TICK_CORNER_MM for p in hit for c in corners)

                lines = [angle((e[0] + e[1]) / 2) for e in ticks.values() if len(e) == 2
                         and abs(float(np.cross(np.append(e[1] - e[0], 0), np.append(o - e[0], 0))[2]))
                         <= 1e-9 * np.linalg.norm(e[1] - e[0]) * np.linalg.norm(o - e[0])]
                seen = [angle(p) for p in pts]
                for side, beyond in ((min(seen), lambda x, s=min(seen): x < s),
                                     (max(seen), lambda x, s=max(seen): x > s)):
                    out = side + (0.02 if beyond(side + 0.02) else -0.02)
                    if markable(out):
                        possible += 1
                        bracketed += any(beyond(x) for x in lines)
    # 2026-11-29: 17 of 20 sides where a ruler's line fits (before: 7); the others' ticks
    # would sit on the labels beside the arrows, which keep their place
    assert possible >= 15 and bracketed >= possible - 4, (bracketed, possible)


def test_an_erase_hint_leaves_the_guides_the_next_box_is_drawn_on():
    # the roller's front-left step 8 said "Afterwards you may erase 2 guide lines" where
    # step 9 draws the riser's edges on both (a read-through): a guide lying whole along an
    # edge the next step draws is not among the lines to erase; checked against the next
    # step's own strokes, every hint of the examples' novice and apprentice views
    from pathlib import Path

    from h2s_print.config import load_tutorial
    from h2s_print.pipeline import plan_tutorial

    def on(seg, edges):  # both ends of the guide within a pencil of one edge's segment
        a, b = np.asarray(seg[0], float), np.asarray(seg[1], float)
        for p, q in edges:
            d = q - p
            n = float(np.linalg.norm(d))
            if n == 0:
                continue
            if all(abs(np.cross(np.append(d, 0), np.append(x - p, 0))[2]) / n <= 0.05
                   and -0.05 <= np.dot(x - p, d) / n <= n + 0.05 for x in (a, b)):
                return True
        return False

    checked = 0
    for name in ("roller", "camera", "train", "mixer"):
        t = load_tutorial(Path(__file__).resolve().parents[1] / "configs" / f"{name}.yaml")
        for vp in plan_tutorial(t).views:
            if vp.level not in ("novice", "apprentice"):
                continue
            hints = L._erase_hints(vp)
            for i in range(len(vp.steps) - 1):
                after = {g.id for g, _ in L._step_guides(vp, i + 1)}
                nxt = [(np.asarray(s.points_mm[k], float), np.asarray(s.points_mm[k + 1], float))
                       for s in vp.steps[i + 1].strokes if s.kind in ("scaffold", "scaffold_hidden")
                       for k in range(len(s.points_mm) - 1)]
                gone = [g for g, _ in L._step_guides(vp, i) if g.id not in after
                        and g.role != "sheet"]
                under = [g for g in gone if on((g.from_mm, g.to_mm), nxt)]
                if under and len(under) == len(gone):
                    assert hints[i] == "", (name, vp.name, vp.level, i + 1, hints[i])
                    checked += 1
    assert checked >= 2


def test_a_vanishing_point_beyond_taped_paper_gets_two_tick_pairs(examples):
    # the train's front-left sheet gave its right vanishing point, 649 mm off, the single
    # pair R1, below its drawing: one line is none to aim between, and no taped-on sheet
    # reaches that far (a read-through). A point farther off the frame than an A4 sheet's
    # length gets two pairs at least on every example's novice sheet (its labels moving off
    # their arrows where they took the room)

    from h2s_print.pipeline import _workbook_pages, plan_tutorial

    far = 0
    for name in examples:
        t = examples[name][0]
        result = plan_tutorial(t)
        for k, vp in enumerate(result.views):  # the sheets as the workbooks print them
            if vp.level != "novice":
                continue
            sheet = next(p for p in _workbook_pages(result, k) if p.kind == "sheet")
            far += _far_pairs(name, vp, t, sheet)
    assert far >= 2


def _far_pairs(name, vp, t, sheet) -> int:
    """test_a_vanishing_point_beyond_taped_paper_gets_two_tick_pairs on one sheet: how many
    vanishing points it checked."""
    import math

    far = 0
    view = vp.name
    frame = L._frame_box(vp.paper_mm, t.paper.margin_mm)
    items = list(sheet.items)
    ticks: dict[str, int] = {}
    for a, b in zip(items, items[1:]):
        if isinstance(a, L.Polyline) and a.role == "vp_tick":
            ticks[b.string] = ticks.get(b.string, 0) + 1
    for v in vp.vanishing_points:
        if v.at_infinity or v.xy_mm is None:
            continue
        x, y = v.xy_mm
        off = math.hypot(max(frame[0] - x, 0.0, x - frame[2]),
                         max(frame[1] - y, 0.0, y - frame[3]))
        if off <= 297.0:
            continue
        o = np.asarray(v.xy_mm, float)
        pairs = 0
        for n, count in ticks.items():
            if count != 2:
                continue
            ends = [np.asarray(a.points_mm[0]) for a, b in zip(items, items[1:])
                    if isinstance(a, L.Polyline) and a.role == "vp_tick" and b.string == n]
            d = ends[1] - ends[0]
            pairs += abs(d[0] * (o - ends[0])[1] - d[1] * (o - ends[0])[0]) <= \
                1e-9 * np.linalg.norm(d) * np.linalg.norm(o - ends[0])
        assert pairs >= 2, (name, view, v.axis, off, pairs)
        far += 1
    return far
