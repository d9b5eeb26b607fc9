"""Render stage: PDFs read back with pypdf (structure, not bytes), SVG and PNG exports."""

from __future__ import annotations

import ast
import io
import math
import os
import re
from pathlib import Path

import pypdf
import pytest

from h2s_print import layout as L
from h2s_print import render as R
from h2s_print.config import PaperSpec
from h2s_print.errors import RenderError

from test_layout import workbook  # the layout tests' factory

MM = 72 / 25.4  # PDF points per mm


def read(data: bytes) -> pypdf.PdfReader:
    return pypdf.PdfReader(io.BytesIO(data))


@pytest.fixture(scope="module")
def novice():
    plan, pages = workbook("novice")
    return plan, pages, R.pdf_bytes(pages)


@pytest.mark.parametrize("size, orientation, w_mm, h_mm", [
    ("A4", "landscape", 297.0, 210.0),
    ("A4", "portrait", 210.0, 297.0),
    ("Letter", "landscape", 279.4, 215.9),
    ("Letter", "portrait", 215.9, 279.4),
    ("A3", "landscape", 420.0, 297.0),
    ("A3", "portrait", 297.0, 420.0),
])
def test_mediabox_is_the_paper_in_points(size, orientation, w_mm, h_mm):
    paper = PaperSpec(size, orientation, 12.0)
    plan, pages = workbook("apprentice", paper, n_steps=3)
    reader = read(R.pdf_bytes(pages))
    # cover + primer + ceil(3 / 2) = 2 step pages + final + sheet = 6
    assert len(reader.pages) == len(pages) == 6
    for page in reader.pages:
        box = [float(v) for v in page.mediabox]
        # e.g. A4 landscape: 297 mm x 72 / 25.4 = 841.89 pt, 210 mm -> 595.28 pt
        assert box[0] == 0 and box[1] == 0
        assert box[2] == pytest.approx(w_mm * MM, abs=0.01)
        assert box[3] == pytest.approx(h_mm * MM, abs=0.01)


def test_page_count_and_instruction_text_on_every_step_page(novice):
    plan, pages, data = novice
    reader = read(data)
    assert len(reader.pages) == 9  # cover, primer, 5 novice step pages, final, sheet
    def squash(s):
        return re.sub(r"\s+", "", s)
    for i, step in enumerate(plan.steps):
        got = squash(reader.pages[2 + i].extract_text())
        assert squash(L.plain_text(step.text)) in got, step.index
        assert f"Step{step.index}" in got


def test_bookmarks_have_levels(novice):
    _, pages_a, _ = novice
    _, pages_b = workbook("master")
    book = L.lay_out_book("Sketching", [("Camera > front-left > novice", pages_a),
                                        ("Camera > front-left > master", pages_b)])
    reader = read(R.pdf_bytes(book))

    def walk(items, level, out):
        for it in items:
            if isinstance(it, list):
                walk(it, level + 1, out)
            else:
                out.append((it.title, level, reader.get_destination_page_number(it)))
        return out

    marks = walk(reader.outline, 0, [])
    assert marks[:7] == [("Title page", 0, 0), ("Contents", 0, 1), ("Camera", 0, 2),
                         ("front-left", 1, 2), ("novice", 2, 2), ("Cover", 3, 2), ("Primer", 3, 3)]
    assert ("master", 2, 11) in marks  # 2 + 9 novice pages
    assert ("Drawing sheet", 3, len(book) - 1) in marks
    assert reader.trailer["/Root"]["/PageMode"] == "/UseOutlines"


def test_print_scaling_none(novice):
    reader = read(novice[2])
    prefs = reader.trailer["/Root"]["/ViewerPreferences"]
    assert prefs["/PrintScaling"] == "/None"


def _segments(page: pypdf.PageObject):
    """(x0, y0, x1, y1) of every straight segment stroked in the page's content, in PDF units
    after the current transformation matrix (only translations/scales are expected)."""
    ops = pypdf.generic.ContentStream(page.get_contents(), page.pdf).operations
    ctm = [1.0, 0.0, 0.0, 1.0, 0.0, 0.0]
    stack, out, cur = [], [], None

    def apply(x, y):
        a, b, c, d, e, f = ctm
        return (a * x + c * y + e, b * x + d * y + f)

    for operands, op in ops:
        if op == b"q":
            stack.append(list(ctm))
        elif op == b"Q":
            ctm = stack.pop()
        elif op == b"cm":
            a2, b2, c2, d2, e2, f2 = (float(v) for v in operands)
            a, b, c, d, e, f = ctm
            ctm = [a2 * a + b2 * c, a2 * b + b2 * d, c2 * a + d2 * c, c2 * b + d2 * d,
                   e2 * a + f2 * c + e, e2 * b + f2 * d + f]
        elif op == b"m":
            cur = apply(*(float(v) for v in operands))
        elif op == b"l" and cur is not None:
            nxt = apply(*(float(v) for v in operands))
            out.append((*cur, *nxt))
            cur = nxt
    return out


def test_scale_bar_is_100_mm_in_pdf_units(novice):
    _, pages, data = novice
    reader = read(data)
    sheet = reader.pages[-1]
    bar, = [it for it in pages[-1].items if isinstance(it, L.Polyline) and it.role == "scale_bar"]
    (x0, y0), (x1, y1) = bar.points_mm
    segs = _segments(sheet)
    found = [s for s in segs if math.dist(s[:2], (x0 * MM, y0 * MM)) < 0.01
             and math.dist(s[2:], (x1 * MM, y1 * MM)) < 0.01]
    assert len(found) == 1
    # 100 mm = 100 x 72 / 25.4 = 283.4646 pt; within 0.1 mm = 0.2835 pt
    length_mm = math.dist(found[0][:2], found[0][2:]) / MM
    assert abs(length_mm - 100.0) < 0.1


def test_calibrated_sheet_lines_land_at_their_sheet_mm(novice):
    plan, pages, data = novice
    sheet = read(data).pages[-1]
    segs = _segments(sheet)
    # ground plane of the body: bottom face z = 0 projected; its first edge starts at corner 0
    p = plan.camera.project([(0, 0, 0), (200, 0, 0)])
    want = (p[0][0] * MM, p[0][1] * MM, p[1][0] * MM, p[1][1] * MM)
    assert any(math.dist(s[:2], want[:2]) < 0.01 and math.dist(s[2:], want[2:]) < 0.01 for s in segs)


def test_same_pages_give_identical_bytes(novice):
    _, pages, data = novice
    assert R.pdf_bytes(pages) == data
    _, again = workbook("novice")
    assert R.pdf_bytes(again) == data


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def test_render_pdf_writes_atomically(tmp_path, novice):
    _, pages, data = novice
    out = tmp_path / "camera.pdf"
    R.render_pdf(pages, out)
    assert out.read_bytes() == data
    assert sorted(os.listdir(tmp_path)) == ["camera.pdf"]  # no temp file left behind
    nested = tmp_path / "new" / "dir" / "camera.pdf"  # missing folders are created
    R.render_pdf(pages, nested)
    assert nested.read_bytes() == data
    assert oct(nested.stat().st_mode & 0o777) == oct(0o666 & ~_umask())  # not mkstemp's 0600
    under_file = tmp_path / "camera.pdf" / "x.pdf"  # a file where a folder should be
    with pytest.raises(RenderError, match=re.escape(str(tmp_path / "camera.pdf"))):
        R.render_pdf(pages, under_file)
    blocker = tmp_path / "taken"
    blocker.mkdir()
    with pytest.raises(RenderError, match="taken"):
        R.render_pdf(pages, blocker)  # a folder where the file should go
    assert sorted(os.listdir(tmp_path)) == ["camera.pdf", "new", "taken"]
    with pytest.raises(RenderError):
        R.pdf_bytes([])


def test_svg_has_every_line_of_the_layout(novice):
    _, pages, _ = novice
    for page in pages[2:4] + pages[-1:]:
        svg = R.render_svg(page)
        n_lines = sum(1 for it in page.items if isinstance(it, L.Polyline) and len(it.points_mm) >= 2)
        assert svg.count("<polyline ") + svg.count("<polygon ") == n_lines
        n_text = sum(1 for it in page.items if isinstance(it, L.Text) and it.string)
        assert svg.count("<text ") == n_text
        assert f'width="{page.width_mm:g}mm"' in svg


def test_png_export(novice):
    _, pages, _ = novice
    png = R.render_png(pages[3], dpi=50)
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    width = int.from_bytes(png[16:20], "big")
    # 297 mm at 50 dpi = 297 / 25.4 x 50 = 584.6 px
    assert abs(width - 297 / 25.4 * 50) <= 1


def test_reportlab_and_cairosvg_stay_in_render():
    """Heavy dependencies belong to one stage: layout imports neither."""
    src = (Path(L.__file__)).read_text(encoding="utf-8")
    names = {n.names[0].name.split(".")[0] for n in ast.walk(ast.parse(src))
             if isinstance(n, ast.Import)}
    names |= {(n.module or "").split(".")[0] for n in ast.walk(ast.parse(src))
              if isinstance(n, ast.ImportFrom)}
    assert not names & {"reportlab", "cairosvg", "pypdf", "pymupdf"}


def test_svg_text_keeps_the_layout_width_in_a_substituted_font(novice):
    _, pages, _ = novice
    page = pages[2]
    texts = [it for it in page.items if isinstance(it, L.Text) and it.string]
    # a rasteriser whose font is twice as wide as Helvetica: every text is squeezed to half
    svg = R.render_svg(page, measure=lambda it: 2 * L.text_width_mm(it.string, it.size_pt, it.font))
    assert svg.count("scale(0.5000 1)") == len(texts)
    # every text states its Helvetica width for viewers that honour textLength
    first = texts[0]
    width = L.text_width_mm(first.string, first.size_pt, first.font)
    assert f'textLength="{R._num(width)}"' in R.render_svg(page)
    # measured the way cairosvg picks its font, the real fallback font is rescaled too
    assert R._cairo_width_mm(first) > 0


# ----------------------------------------------------------------------------- same bytes


def _canvas_draw_page(c, page, *_):
    """The simple definition of drawing a page: reportlab's canvas methods, one call per
    operator (what ``render._draw_page`` writes faster and must match byte for byte)."""
    spec = page.font or R.fonts.current()
    c.setLineJoin(1)
    c.setLineCap(0)
    for item in page.items:
        if isinstance(item, L.Polyline):
            if len(item.points_mm) < 2:
                continue
            c.setStrokeColorRGB(*R._rgb(item.colour))
            c.setLineWidth(R._pt(item.width_mm))
            c.setDash([R._pt(d) for d in item.dash_mm], 0)
            path = c.beginPath()
            (x, y), *rest = item.points_mm
            path.moveTo(R._pt(x), R._pt(y))
            for x, y in rest:
                path.lineTo(R._pt(x), R._pt(y))
            if item.closed:
                path.close()
            c.drawPath(path, stroke=1, fill=0)
        elif isinstance(item, L.Text):
            if not item.string:
                continue
            c.setFillColorRGB(*R._rgb(item.colour))
            c.setFont(R.fonts.face(spec.path(item.font)).key, item.size_pt)
            draw = {"start": c.drawString, "middle": c.drawCentredString,
                    "end": c.drawRightString}[item.anchor]
            draw(R._pt(item.x_mm), R._pt(item.y_mm), item.string)
        elif isinstance(item, L.Rect):
            R._style_area(c, item.colour, item.line_mm, item.fill)
            c.rect(R._pt(item.x_mm), R._pt(item.y_mm), R._pt(item.w_mm), R._pt(item.h_mm),
                   stroke=int(item.colour is not None), fill=int(item.fill is not None))
        else:
            R._style_area(c, item.colour, item.line_mm, item.fill)
            c.circle(R._pt(item.cx_mm), R._pt(item.cy_mm), R._pt(item.r_mm),
                     stroke=int(item.colour is not None), fill=int(item.fill is not None))


def _odd_page() -> L.Page:
    """Lines and texts at the edges of what the fast path must get right: two points, closed,
    dashed, tiny, negative and large coordinates; texts again at other anchors, sizes, fonts
    and colours, and characters first met late in the document."""
    items = [
        L.Polyline(((0.0, 0.0), (1e-9, -3.25))),
        L.Polyline(((10.0, 10.0), (20.5, 10.0), (20.5, 30.125)), "blue", 0.35, (2.4, 0.9),
                   closed=True),
        L.Polyline(((-5.0, 1234.5678), (0.1, 0.01), (1e-7, 99999.0), (3.0, 4.0)), "orange",
                   0.25, (1.6, 1.0, 0.5, 1.0)),
        L.Polyline(((5.0, 5.0),)),  # one point: not drawn
        L.Text(10, 20, "Step 3", 9.0),
        L.Text(50, 20, "Step 3", 9.0, anchor="end", colour="grey"),
        L.Text(90, 20, "Step 3", 11.0, "Helvetica-Bold", anchor="middle"),
        L.Text(90, 40, "Step 3", 9.0, "Helvetica-Oblique", anchor="middle", colour="blue"),
        L.Text(10, 60, "", 9.0),
        L.Rect(5, 5, 20, 10, "black", 0.2, "lightgrey"),
        L.Circle(30, 30, 4, None, 0.2, "orange"),
        L.Polyline(((1.0, 2.0), (3.0, 4.0)), "green", 0.8),
        L.Text(10, 80, "Ωμέγα ½ Jörg", 8.5),
        L.Text(60, 80, "Ωμέγα ½ Jörg", 8.5, anchor="end"),
        L.Text(10, 100, "Step 3", 9.0),
    ]
    return L.Page(210.0, 297.0, tuple(items))


def test_pdf_bytes_equal_the_canvas_methods(novice, monkeypatch):
    """The page drawn through the canvas methods gives the very same file."""
    _, pages, _ = novice
    pages = [*pages, _odd_page(), _odd_page()]
    fast = R.pdf_bytes(pages)
    monkeypatch.setattr(R, "_draw_page", _canvas_draw_page)
    assert R.pdf_bytes(pages) == fast


def test_path_ops_equal_one_fp_str_per_point():
    """Paths written from remembered coordinate texts are the path object's: numbers met
    again (in one line or another), both zeros, ints among floats, tiny and large values."""
    from reportlab.lib.rl_accel import fp_str

    rng = __import__("random").Random(7)
    values = [0.0, -0.0, 1, 1.0, -2, 1e-9, -1e-9, 3.3e-8, 123456.789, -0.5, 25.4]
    values += [rng.uniform(-1e4, 1e4) * rng.choice((1, 1e-6, 1e-9)) for _ in range(30)]
    numbers: dict[float, str] = {}
    for n in (2, 3, 50, 2, 7, 200):
        points = tuple((rng.choice(values), rng.choice(values)) for _ in range(n))
        want = " ".join(["n", f"{fp_str(points[0][0] * MM, points[0][1] * MM)} m"]
                        + [f"{fp_str(x * MM, y * MM)} l" for x, y in points[1:]] + ["h"])
        assert R._path_ops(points, True, numbers) == want
        assert R._path_ops(points, False, numbers) == want[:-2]
        assert R._path_ops(points, False, {}) == want[:-2]
