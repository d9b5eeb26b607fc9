"""Scoring scanned sheets (h2s_print/score.py): synthetic scans with known answers.

A real calibrated sheet (configs/camera.yaml, front-left, novice) is rendered with its QR
stamp, a known drawing is pencilled on it (the model's own lines, or the same lines moved
by known amounts) and the page is moved into a "scan" by a known homography (rotation,
scale, skew, perspective) and degraded (blur, noise, uneven light, JPEG).  Registration is
checked against that homography, the figures against the known displacements.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import pytest

from h2s_print import score
from h2s_print.study import STUDY_MARGIN_MM
from h2s_print.studyfile import Drawing, SheetKey, Study, StudyError, code_text

from _scans import RENDER_DPI, _gray, pencil, scan

REPO = Path(__file__).resolve().parents[1]
STUDY_ID = "1A2B3C4D"
MARGIN_MM = STUDY_MARGIN_MM  # a study sheet's (h2s study raises smaller ones to it)
#: The blank sheet's image in the key: 8 px/mm (203 dpi).
KEY_PX_MM = 8.0


# ----------------------------------------------------------------------------- fixtures


@pytest.fixture(scope="module")
def sheet(tmp_path_factory):
    """(key, stamped page rendered at RENDER_DPI as greyscale, study) for one sheet: the
    camera's front-left view, novice."""
    from h2s_print.config import load_tutorial
    from h2s_print.sheet import lay_out_sheet, registration_marks
    from h2s_print.pipeline import plan_tutorial
    from h2s_print.render import render_png
    from h2s_print.study import code_box, stamped

    tutorial = load_tutorial(REPO / "configs" / "camera.yaml")
    tutorial = replace(tutorial, paper=replace(tutorial.paper, margin_mm=MARGIN_MM))
    result = plan_tutorial(tutorial)
    vp, final = result.views[0], result.finals[0]
    page = lay_out_sheet(tutorial.title, vp, margin_mm=MARGIN_MM)
    w, h = (float(v) for v in vp.paper_mm)
    box = code_box((w, h), MARGIN_MM)
    folder = tmp_path_factory.mktemp("study")
    printed = folder / "sheet.png"
    printed.write_bytes(render_png(page, KEY_PX_MM * 25.4))
    lines: dict[str, list] = {}
    for stroke in final:
        lines.setdefault(stroke.part, []).append(tuple((float(x), float(y))
                                                       for x, y in stroke.points_mm))
    marks, r = registration_marks((w, h), MARGIN_MM)
    key = SheetKey(
        sheet="camera-novice", object="camera", view=vp.name, condition="novice",
        paper_mm=(w, h), frame_mm=(MARGIN_MM, MARGIN_MM, w - MARGIN_MM, h - MARGIN_MM),
        marks_mm=marks, mark_radius_mm=r, code_box_mm=box, printed=printed,
        px_per_mm=KEY_PX_MM, lines=tuple((p, tuple(v)) for p, v in lines.items()))
    drawings = tuple(Drawing(i, f"P{i + 1}", 1, "camera", "novice", key.sheet,
                             code_text(STUDY_ID, i)) for i in range(3))
    study = Study(folder, STUDY_ID, "test", 1, "fixed-first", ("P1", "P2", "P3"),
                  ("novice",), ("camera",), drawings, {key.sheet: key})
    rendered = _gray(render_png(stamped(page, code_text(STUDY_ID, 1), box), RENDER_DPI))
    return key, rendered, study


@pytest.fixture(scope="module")
def printed(sheet):
    key, _, _ = sheet
    return score.read_printed(key)


def frame_error_mm(reg: score.Registration, truth: np.ndarray, key: SheetKey) -> float:
    """Largest distance on the sheet (mm) between the recovered and the true homography's
    images of the frame's corners and centre."""
    x0, y0, x1, y1 = key.frame_mm
    pts = np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1), ((x0 + x1) / 2, (y0 + y1) / 2)])
    back = reg.to_sheet(score._apply(truth, pts))
    return float(np.max(np.linalg.norm(back - pts, axis=1)))


@pytest.fixture(scope="module")
def drawn(sheet):
    """The sheet with the model's own lines pencilled on it (a perfect drawing)."""
    key, rendered, _ = sheet
    return pencil(rendered, key)


def _score(img: np.ndarray, key: SheetKey, printed: np.ndarray):
    """(registration, stroke mask, scores) of a scan image, stage by stage."""
    _text, corners = score.find_code(img)
    reg = score.register(img, key, printed, corners)
    _, mask = score.strokes(img, reg, key, printed)
    return reg, mask, score.measure(mask, key, score.blind_mask(printed, key))


def _write_png(path: Path, img: np.ndarray) -> Path:
    path.write_bytes(cv2.imencode(".png", img)[1].tobytes())
    return path


# ----------------------------------------------------------------------------- code


def test_code_corners_come_in_the_symbols_order_whatever_the_rotation(sheet, drawn):
    key, _, _ = sheet
    for angle in (0.0, 90.0, 200.0):
        img, truth = scan(drawn, key, angle_deg=angle, dpi=200)
        text, corners = score.find_code(img)
        assert text == code_text(STUDY_ID, 1)
        # corner k is code_corners_mm(key)[k] through the true homography (within a pixel
        # or so: 1 px = 0.13 mm at 200 dpi)
        expected = score._apply(truth, score.code_corners_mm(key))
        assert np.linalg.norm(corners - expected, axis=1).max() < 2.0


def test_code_reads_below_200_dpi(sheet, drawn):
    key, _, _ = sheet
    img, _ = scan(drawn, key, angle_deg=-20, dpi=150, noise=4, jpeg=75)
    assert score.find_code(img)[0] == code_text(STUDY_ID, 1)


# ----------------------------------------------------------------------------- registration

SCANS = {
    "flat-bed": {"dpi": 300},
    "upside down": {"angle_deg": 180, "dpi": 200},
    "quarter turn": {"angle_deg": 90, "dpi": 220},
    "rotated and skewed": {"angle_deg": 37, "dpi": 240, "skew": 0.04},
    "150 dpi": {"angle_deg": 3, "dpi": 150, "noise": 4, "jpeg": 80},
    "phone photo": {"angle_deg": 172, "dpi": 260, "skew": 0.03, "perspective": 0.10,
                    "blur_px": 1.4, "light": 0.5, "noise": 8, "jpeg": 60, "border": 60},
}


@pytest.mark.parametrize("case", SCANS)
def test_registration_recovers_the_sheet_within_half_a_millimetre(sheet, drawn, printed, case):
    key, _, _ = sheet
    img, truth = scan(drawn, key, seed=3, **SCANS[case])
    reg, _mask, scores = _score(img, key, printed)
    assert frame_error_mm(reg, truth, key) < 0.5
    assert reg.residual_mm < 0.5
    # the perfect drawing is found as such: every visible model line has a stroke on it
    assert scores.overall.covered > 0.99
    assert scores.overall.to_drawing_mm < 0.2
    assert scores.overall.offset_mm < 0.3


def test_printed_marks_are_not_strokes(sheet, drawn, printed):
    key, _, _ = sheet
    img, _truth = scan(drawn, key, angle_deg=12, dpi=220, light=0.3, noise=5, jpeg=80)
    _, mask, _ = _score(img, key, printed)
    # the known drawing alone, on the key's grid
    known = np.zeros(mask.shape, np.uint8)
    for _, lines in key.lines:
        score._draw_lines(known, lines, key, 1)
    dist = cv2.distanceTransform(1 - known, cv2.DIST_L2, cv2.DIST_MASK_PRECISE) / KEY_PX_MM
    near = dist[mask] <= 0.6  # the line's half width (0.25 mm) and blur
    assert near.mean() > 0.995
    # and the print itself (its text, arrows, marks, frame) yields no strokes
    blank, _ = scan(sheet[1], key, angle_deg=12, dpi=220, light=0.3, noise=5, jpeg=80)
    reg = score.register(blank, key, printed, score.find_code(blank)[1])
    flat = score.registered_image(blank, reg, key)
    assert not score.ink_mask(flat, key, printed).any()


# ----------------------------------------------------------------------------- measures


def _mask_of(key: SheetKey, moves: dict[str, tuple[float, float]], width_px: int = 3):
    """A stroke mask on the key's grid: the model's lines moved part by part (mm)."""
    mask = np.zeros(score._grid_shape(key), np.uint8)
    for part, lines in key.lines:
        dx, dy = moves.get(part, (0.0, 0.0))
        score._draw_lines(mask, [np.asarray(ln) + (dx, dy) for ln in lines], key, 1, width_px)
    return mask.astype(bool)


def test_measure_of_the_model_itself_is_zero(sheet):
    key, _, _ = sheet
    s = score.measure(_mask_of(key, {}), key)
    assert s.overall.to_drawing_mm < 0.05
    assert s.overall.to_model_mm < 0.15  # the strokes are 3 px = 0.375 mm wide
    assert s.overall.covered == 1.0
    assert all(f.offset_mm < 0.1 for _, f in s.parts)


def test_measure_finds_a_part_moved_along_its_own_lines(sheet):
    key, _, _ = sheet
    # the body (a box) moved 3 mm along x: its horizontal-ish lines barely move off
    # themselves, so chamfer distances stay small but the offset sees the whole 3 mm
    s = score.measure(_mask_of(key, {"body": (3.0, 0.0)}), key)
    assert s.part("body").offset_mm == pytest.approx(3.0, abs=0.25)
    assert s.part("body").to_drawing_mm < 3.0
    for name, f in s.parts:
        if name != "body":
            assert f.offset_mm < 0.3, name


def test_a_3_mm_displacement_of_one_part_is_measured_on_that_part(sheet, printed):
    key, rendered, _ = sheet
    moved = "lens"
    page = pencil(rendered, key, {moved: (1.8, -2.4)})  # |(1.8, -2.4)| = 3 mm
    img, _ = scan(page, key, angle_deg=-150, dpi=230, skew=0.02, perspective=0.05,
                  blur_px=1.0, noise=6, jpeg=70, seed=5)
    _, _, scores = _score(img, key, printed)
    assert scores.part(moved).offset_mm == pytest.approx(3.0, abs=0.5)
    for name, f in scores.parts:
        if name != moved:
            assert f.offset_mm < 0.5, name


def test_larger_errors_score_worse_in_order(sheet, printed):
    key, rendered, _ = sheet
    rng = np.random.default_rng(11)
    angles = {p: rng.uniform(0, 2 * math.pi) for p, _ in key.lines}
    figures = []
    for size in (0.0, 1.5, 3.0, 6.0):
        moves = {p: (size * math.cos(a), size * math.sin(a)) for p, a in angles.items()}
        page = pencil(rendered, key, moves, jitter_mm=size / 6, seed=2)
        img, _ = scan(page, key, angle_deg=25, dpi=200, noise=5, jpeg=75)
        figures.append(_score(img, key, printed)[2].overall)
    d = [f.to_drawing_mm for f in figures]
    m = [f.to_model_mm for f in figures]
    c = [f.covered for f in figures]
    o = [f.offset_mm for f in figures]
    assert d == sorted(d) and len(set(d)) == 4
    assert m == sorted(m) and len(set(m)) == 4
    assert c == sorted(c, reverse=True) and c[0] > c[-1]
    assert o == sorted(o) and len(set(o)) == 4


# ----------------------------------------------------------------------------- errors


def test_score_scan_of_a_png_and_a_pdf(sheet, drawn, tmp_path):
    from PIL import Image

    key, _, study = sheet
    img, _ = scan(drawn, key, angle_deg=180, dpi=200)
    png = _write_png(tmp_path / "feuille-é.png", img)  # a non-ASCII name reads too
    (res,) = score.score_scan(png, study)
    assert res.drawing == study.drawings[1]
    assert res.source == str(png)
    assert res.registered_drawing.shape == score._grid_shape(key)
    pdf = tmp_path / "scans.pdf"
    page = Image.fromarray(img)
    page.save(pdf, "PDF", resolution=200.0, save_all=True, append_images=[page])
    results = score.score_scan(pdf, study)
    assert [r.source for r in results] == [f"{pdf} page 1", f"{pdf} page 2"]
    assert results[0].scores.overall.covered > 0.99
    rows = score.score_rows(res)
    assert tuple(rows[0]) == score.CSV_FIELDS
    assert [r["part"] for r in rows] == ["*"] + [p for p, _ in key.lines]
    assert rows[0]["participant"] == "P2"


def _error(path: Path, study: Study) -> str:
    with pytest.raises(StudyError) as err:
        score.score_scan(path, study)
    message = str(err.value)
    assert "\n" not in message
    assert message.startswith(str(path))
    return message


def test_a_blank_sheet_is_an_error(sheet, tmp_path):
    key, rendered, study = sheet
    img, _ = scan(rendered, key, angle_deg=5, dpi=200, noise=5, jpeg=80)
    assert "no pencil strokes" in _error(_write_png(tmp_path / "blank.png", img), study)


def test_an_image_without_a_sheet_is_an_error(sheet, tmp_path):
    _, _, study = sheet
    rng = np.random.default_rng(0)
    photo = cv2.GaussianBlur(rng.uniform(0, 255, (600, 800)).astype(np.float32), (0, 0), 9)
    photo = cv2.normalize(photo, None, 0, 255, cv2.NORM_MINMAX).astype(np.uint8)
    assert "no sheet code" in _error(_write_png(tmp_path / "photo.png", photo), study)


def test_a_sheet_with_a_mark_cut_off_is_an_error(sheet, drawn, tmp_path):
    key, _, study = sheet
    img, truth = scan(drawn, key, dpi=200)
    # cut the scan 20 mm in from the sheet's left edge: the two left marks are gone
    left = int(score._apply(truth, np.array([[20.0, 100.0]]))[0, 0])
    cut = np.ascontiguousarray(img[:, left:])
    assert "no registration marks" in _error(_write_png(tmp_path / "cut.png", cut), study)


def test_a_sheet_of_another_study_is_an_error(sheet, drawn, tmp_path):
    key, _, study = sheet
    img, _ = scan(drawn, key, dpi=200)
    other = replace(study, study_id="0BADBEEF")
    message = _error(_write_png(tmp_path / "other.png", img), other)
    assert STUDY_ID in message and "0BADBEEF" in message


@pytest.mark.parametrize("content", [b"", b"\x89PNG\r\n\x1a\n garbage", b"%PDF-1.7 garbage"])
def test_an_unreadable_file_is_an_error(sheet, tmp_path, content):
    _, _, study = sheet
    path = tmp_path / "scan.png"
    path.write_bytes(content)
    assert "cannot be read" in _error(path, study)


def test_a_missing_file_is_an_error(sheet, tmp_path):
    assert "cannot be read" in _error(tmp_path / "nothing.png", sheet[2])


# ----------------------------------------------------------------------------- overlay


def test_overlay_is_the_sheet_with_the_model_in_orange(sheet, drawn, printed):
    key, _, _ = sheet
    img, _ = scan(drawn, key, angle_deg=30, dpi=200)
    reg = score.register(img, key, printed, score.find_code(img)[1])
    flat, mask = score.strokes(img, reg, key, printed)
    for base in (flat, mask):
        png = score.overlay(base, key)
        assert png == score.overlay(base, key)
        out = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR)
        assert out.shape[:2] == score._grid_shape(key)
        orange = np.all(out == score.MODEL_BGR, axis=2)
        model = _mask_of(key, {}, 1)
        assert orange[model].mean() > 0.5 and not orange[~_mask_of(key, {}, 5)].any()
