"""Ranking drawings by pairwise judgments (h2s_print/rank.py, issue 14 point 3).

A study is built by hand (no solver, no models): two objects, two conditions, small sheets;
registered drawings are synthesised by drawing the model's own lines, jittered, into a mask
at the sheet's resolution, as ``h2s score`` would write them.
"""

from __future__ import annotations

import csv
import io
import itertools
import math
import re
from collections import Counter
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np
import pytest
from pypdf import PdfReader
from scipy.stats import kendalltau, spearmanr

from h2s_print import rank as R
from h2s_print.studyfile import Drawing, SheetKey, Study, StudyError

PAPER = (120.0, 90.0)  # mm
FRAME = (10.0, 10.0, 110.0, 80.0)
PPM = 4.0  # px per mm: images are 360 x 480 px
CONDITIONS = ("novice", "basic")


def _lines(obj: str, cond: str):
    """A box and a diagonal (sheet mm, y up); the two conditions' models differ a little."""
    d = 5.0 if cond == "basic" else 0.0
    x0, y0, x1, y1 = (25.0 + d, 20.0, 95.0, 70.0 - d) if obj == "camera" else (30.0, 15.0, 90.0, 75.0)
    return (("body", (((x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0)),)),
            ("strap", (((x0, y0), (x1, y1)),)))


def make_study(per_object: int = 6, objects=("camera", "mixer"), folder: Path = Path("/tmp/s")):
    """``per_object`` participants draw every object, conditions alternating by participant."""
    sheets = {}
    for obj in objects:
        for cond in CONDITIONS:
            name = f"{obj}-{cond}"
            sheets[name] = SheetKey(name, obj, "front", cond, PAPER, FRAME,
                                    ((5, 5), (115, 5), (115, 85), (5, 85)), 2.0,
                                    (90, 82, 100, 88), folder / "sheets" / f"{name}.png", PPM,
                                    _lines(obj, cond))
    drawings = []
    participants = tuple(f"P{i + 1:02d}" for i in range(per_object))
    for i, p in enumerate(participants):
        for j, obj in enumerate(objects):
            cond = CONDITIONS[(i + j) % 2]
            row = len(drawings)
            drawings.append(Drawing(row, p, j + 1, obj, cond, f"{obj}-{cond}",
                                    f"H2S:1A2B3C4D:{row}"))
    return Study(folder, "1A2B3C4D", "test study", 7, "latin-square", participants, CONDITIONS,
                 tuple(objects), tuple(drawings), sheets)


def drawing_image(sheet: SheetKey, jitter_mm: float = 0.0, seed: int = 0,
                  shift_mm: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
    """A registered drawing: the sheet's model lines, each vertex moved by up to
    ``jitter_mm`` (seeded) and all by ``shift_mm``, 255 = pencil, contract orientation."""
    rng = np.random.default_rng(seed)
    h, w = round(PAPER[1] * PPM), round(PAPER[0] * PPM)
    mask = np.zeros((h, w), np.uint8)
    for _, lines in sheet.lines:
        for line in lines:
            pts = np.array(line) + np.array(shift_mm) + rng.uniform(-jitter_mm, jitter_mm,
                                                                    (len(line), 2))
            px = np.stack([pts[:, 0] * PPM - 0.5, (PAPER[1] - pts[:, 1]) * PPM - 0.5], axis=1)
            # antialiased, odd width: centred on the line (cv2's 2 px lines are not)
            cv2.polylines(mask, [np.round(px * 16).astype(np.int32)], False, 255, 3,
                          cv2.LINE_AA, 4)
    return mask


def images_for(study: Study, rows) -> dict[int, np.ndarray]:
    return {r: drawing_image(study.sheets[study.drawings[r].sheet], 1.5, seed=r) for r in rows}


# ----------------------------------------------------------------------------- pairs


@pytest.mark.parametrize("n", range(12))
def test_balanced_sides_every_pair_once_and_sides_within_one(n):
    sides = R.balanced_sides(n)
    assert sorted(tuple(sorted(p)) for p in sides) == list(itertools.combinations(range(n), 2))
    left = Counter(a for a, _ in sides)
    right = Counter(b for _, b in sides)
    for i in range(n):
        # each item is in n - 1 pairs: an even number splits evenly, an odd one within 1
        assert abs(left[i] - right[i]) == (0 if n % 2 else 1)


def test_pairs_cover_each_object_once_balanced_and_seeded():
    study = make_study(per_object=6)
    # camera: all 6 drawings scored (even); mixer: 5 of 6 (odd), one never scanned
    rows = [d.row for d in study.drawings if d.object == "camera"]
    rows += [d.row for d in study.drawings if d.object == "mixer"][:5]
    ps = R.pairs(study, rows, seed=3)
    assert len(ps) == 15 + 10  # C(6,2) + C(5,2)
    for obj, n in (("camera", 6), ("mixer", 5)):
        mine = [p for p in ps if p.object == obj]
        scored = sorted(r for r in rows if study.drawings[r].object == obj)
        assert sorted(tuple(sorted((p.a, p.b))) for p in mine) == \
            list(itertools.combinations(scored, 2))
        left, right = Counter(p.a for p in mine), Counter(p.b for p in mine)
        for r in scored:
            assert abs(left[r] - right[r]) <= (0 if n % 2 else 1)
        # ids: <object>-001 .. in page order
        assert [p.id for p in mine] == [f"{obj}-{k:03d}" for k in range(1, len(mine) + 1)]
    for p in ps:  # never across objects
        assert study.drawings[p.a].object == study.drawings[p.b].object == p.object
    assert [p.object for p in ps] == sorted((p.object for p in ps), key=study.objects.index)
    assert R.pairs(study, rows, seed=3) == ps  # deterministic
    # pages come in a shuffled order, not the construction's (whose first two pages always
    # share a drawing; in a random order two pairs of 6 drawings share one 8 times in 14)
    firsts = [R.pairs(study, rows, seed=s)[:2] for s in range(20)]
    assert not all({p.a, p.b} & {q.a, q.b} for p, q in firsts)
    other = R.pairs(study, rows, seed=4)
    assert other != ps
    assert {frozenset((p.a, p.b)) for p in other} == {frozenset((p.a, p.b)) for p in ps}


def test_pairs_need_two_drawings_and_known_rows():
    study = make_study(per_object=3)
    with pytest.raises(StudyError, match="no object has two scored drawings"):
        R.pairs(study, [0, 1], seed=1)  # one camera, one mixer
    with pytest.raises(StudyError, match="no drawing row 99"):
        R.pairs(study, [0, 99], seed=1)


def test_pairs_csv_round_trips():
    study = make_study()
    ps = R.pairs(study, range(len(study.drawings)), seed=1)
    assert R.parse_pairs(R.pairs_csv(ps), study) == ps
    bad = R.pairs_csv(ps).replace(f"{ps[0].id},camera,{ps[0].a},", f"{ps[0].id},mixer,{ps[0].a},")
    with pytest.raises(StudyError, match=r"pairs.csv:2: a: drawing \d+ is of 'camera'"):
        R.parse_pairs(bad, study)


# ----------------------------------------------------------------------------- pages


def test_pair_pages_one_per_pair_blind_and_deterministic():
    study = make_study(per_object=5)
    rows = range(len(study.drawings))
    ps = R.pairs(study, rows, seed=2)
    pdf = R.pair_pages_pdf(study, ps, images_for(study, rows))
    assert pdf == R.pair_pages_pdf(study, ps, images_for(study, rows))  # invariant=1
    reader = PdfReader(io.BytesIO(pdf))
    assert len(reader.pages) == len(ps) == 2 * 10
    forbidden = [*study.participants, *study.conditions]
    xobjects = set()
    for page, p in zip(reader.pages, ps):
        # A4 landscape: 297 x 210 mm = 841.89 x 595.28 pt
        box = page.mediabox
        assert (round(float(box.width), 1), round(float(box.height), 1)) == (841.9, 595.3)
        text = page.extract_text()
        assert p.id in text
        assert "more accurate to the underlying model" in text
        for word in forbidden:
            assert word not in text, f"page of {p.id} shows {word!r}"
        xobjects |= set(page["/Resources"]["/XObject"].keys())
    meta = " ".join(str(v) for v in (reader.metadata or {}).values())
    assert not any(w in meta for w in forbidden)
    # each drawing's panel is stored once, however many pages show it
    assert len(xobjects) == len(study.drawings)


def test_pair_pages_refuse_a_missing_or_wrong_sized_drawing():
    study = make_study(per_object=3)
    ps = R.pairs(study, range(6), seed=1)
    images = images_for(study, range(6))
    with pytest.raises(StudyError, match="no registered drawing for row"):
        R.pair_pages_pdf(study, ps, {r: im for r, im in images.items() if r != ps[0].a})
    images[ps[0].a] = images[ps[0].a][:-10]
    with pytest.raises(StudyError, match="is not sheet"):
        R.pair_pages_pdf(study, ps, images)


def _centroid_mm(weight: np.ndarray, k: float) -> np.ndarray:
    """Weighted centroid of a panel (frame FRAME at k px/mm) as sheet mm (x, y up)."""
    r, c = np.indices(weight.shape)
    col, row = (weight * c).sum() / weight.sum(), (weight * r).sum() / weight.sum()
    return np.array([FRAME[0] + (col + 0.5) / k, FRAME[3] - (row + 0.5) / k])


@pytest.mark.parametrize("k", [2.5, 4.0, 7.0])
def test_panel_puts_a_pencil_dot_at_its_sheet_point(k):
    """By definition: image pixel (r, c) is sheet point ((c + .5) / PPM, 90 - (r + .5) / PPM)."""
    sheet = replace(make_study().sheets["camera-novice"], lines=())
    for r, c in ((100, 200), (151, 301), (300, 77)):
        image = np.zeros((360, 480), np.uint8)
        image[r - 1:r + 2, c - 1:c + 2] = 255  # a 3 x 3 dot centred on pixel (r, c)
        panel = R.panel_image(sheet, image, k)
        got = _centroid_mm(255.0 - panel[..., 0], k)
        assert got == pytest.approx([(c + 0.5) / PPM, PAPER[1] - (r + 0.5) / PPM], abs=0.05)


@pytest.mark.parametrize("k", [2.5, 4.0, 7.0])
def test_panel_model_lines_and_pencil_agree(k):
    """A drawing of exactly the model's lines lands on them: same centroid within 0.1 mm."""
    sheet = make_study().sheets["camera-novice"]
    image = drawing_image(sheet)
    model = R.panel_image(sheet, np.zeros_like(image), k)[..., 0]
    pencil = R.panel_image(replace(sheet, lines=()), image, k)[..., 0]
    gap = _centroid_mm(255.0 - model, k) - _centroid_mm(255.0 - pencil, k)
    assert np.abs(gap).max() < 0.1


def _dark(panel: np.ndarray) -> np.ndarray:
    return panel.max(axis=2) < 128


def _overlap(sheet: SheetKey, image: np.ndarray, k: float) -> float:
    """Share of the panel's pencil pixels lying within 0.5 mm of its model lines' pixels."""
    model = R.panel_image(sheet, np.zeros_like(image), k).min(axis=2) < 250
    pencil = _dark(R.panel_image(replace(sheet, lines=()), image, k))
    reach = 2 * round(0.5 * k) + 1
    near = cv2.dilate(model.astype(np.uint8), np.ones((reach, reach), np.uint8)) > 0
    return float((pencil & near).sum() / max(1, pencil.sum()))


@pytest.mark.parametrize("k", [2.5, 4.0, 7.0])  # shrinking, same size, enlarging
def test_panel_overlays_the_drawing_on_its_model(k):
    sheet = make_study().sheets["camera-novice"]
    exact = drawing_image(sheet)
    assert _overlap(sheet, exact, k) > 0.9
    # the same drawing 3 mm off: the overlay must show it off the model
    assert _overlap(sheet, drawing_image(sheet, shift_mm=(3.0, -3.0)), k) < 0.3
    panel = R.panel_image(sheet, exact, k)
    # the frame only: 100 x 70 mm
    assert panel.shape == (round(70 * k), round(100 * k), 3)


# ----------------------------------------------------------------------------- judgments


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "judgments.csv"
    path.write_text(text, encoding="utf-8")
    return path


def test_judgments_template_reads_back_blank_then_filled(tmp_path):
    study = make_study(per_object=4)
    ps = R.pairs(study, range(len(study.drawings)), seed=5)
    template = R.judgments_template(ps)
    assert template.splitlines()[0] == "pair,object,a,b,winner"
    j = R.read_judgments(_write(tmp_path, template), ps)
    assert (len(j.items), j.blank) == (0, len(ps))
    # two raters: every pair twice, the second rater skipped one, a spreadsheet's BOM
    rows = list(csv.reader(io.StringIO(template)))
    body = [r[:4] + ["A"] for r in rows[1:]] + [r[:4] + ["b"] for r in rows[1:]]
    body[-1][4] = ""
    text = "\ufeff" + "\n".join(",".join(r) for r in [rows[0], *body]) + "\n"
    j = R.read_judgments(_write(tmp_path, text), ps)
    assert (len(j.items), j.blank) == (2 * len(ps) - 1, 1)
    first = j.items[0]
    assert (first.pair, first.winner, first.loser, first.line) == (ps[0].id, ps[0].a, ps[0].b, 2)
    assert j.items[len(ps)].winner == ps[0].b


@pytest.mark.parametrize("edit, where", [
    (lambda rows: rows.__setitem__(0, ["pair", "object", "left", "right", "winner"]),
     r":1: header: expected 'pair,object,a,b,winner'"),
    (lambda rows: rows[2].__setitem__(0, "camera-999"), r":3: pair: 'camera-999' is not one"),
    (lambda rows: rows[3].__setitem__(4, "c"), r":4: winner: expected a, b or blank, got 'c'"),
    (lambda rows: rows[2].__setitem__(2, rows[2][3]), r":3: a: expected \d+ for pair"),
    (lambda rows: rows[2].__setitem__(3, "x"), r":3: b: expected a drawing row number"),
    (lambda rows: rows[4].pop(), r":5: expected 5 fields"),
])
def test_bad_judgments_name_the_file_line_and_field(tmp_path, edit, where):
    study = make_study(per_object=4)
    ps = R.pairs(study, range(len(study.drawings)), seed=5)
    rows = [r[:4] + ["a"] for r in csv.reader(io.StringIO(R.judgments_template(ps)))]
    rows[0][4] = "winner"
    edit(rows)
    path = _write(tmp_path, "\n".join(",".join(r) for r in rows) + "\n")
    with pytest.raises(StudyError) as err:
        R.read_judgments(path, ps)
    message = str(err.value)
    assert message.startswith(str(path) + ":")
    assert len(message.splitlines()) == 1
    assert re.search(where, message), message


def test_empty_or_missing_judgments_file(tmp_path):
    ps = R.pairs(make_study(per_object=3), range(6), seed=1)
    with pytest.raises(StudyError, match=r"judgments.csv:1: header: .* the file is empty"):
        R.read_judgments(_write(tmp_path, ""), ps)
    with pytest.raises(StudyError, match="nope.csv: no such file"):
        R.read_judgments(tmp_path / "nope.csv", ps)


# ----------------------------------------------------------------------------- fit


def _judgments(ps, answers) -> R.Judgments:
    """Judgments from ``(pair, winner row)`` answers."""
    items = []
    for line, (p, w) in enumerate(answers, start=2):
        items.append(R.Judgment(p.id, p.object, w, p.b if w == p.a else p.a, line))
    return R.Judgments("judgments.csv", tuple(ps), tuple(items), 0)


def test_fit_two_drawings_by_hand():
    study = make_study(per_object=2, objects=("camera",))
    (p,) = R.pairs(study, [0, 1], seed=1)
    # A beats B 3 times of 4: the ML strengths differ by ln 3, so P(A > B) = 3/4
    j = _judgments([p], [(p, p.a)] * 3 + [(p, p.b)])
    r = R.fit(j, study, alpha=0.0)
    best, worst = r.of("camera")
    assert (best.row, worst.row) == (p.a, p.b)
    assert best.strength == pytest.approx(math.log(3) / 2, abs=1e-5)  # centred: +-ln3/2
    assert worst.strength == pytest.approx(-math.log(3) / 2, abs=1e-5)
    assert best.p_better == pytest.approx(0.75, abs=1e-6)
    assert (best.wins, best.comparisons, worst.wins, worst.comparisons) == (3, 4, 1, 4)
    assert (best.rank, worst.rank) == (1, 2)
    # the default regularisation barely moves it (documented: 0.7475)
    assert R.fit(j, study).of("camera")[0].p_better == pytest.approx(0.7475, abs=5e-4)
    # 4 of 4: no finite ML fit; regularised it stays finite and near 1 (documented: 0.995)
    allwin = _judgments([p], [(p, p.a)] * 4)
    assert R.fit(allwin, study).of("camera")[0].p_better == pytest.approx(0.995, abs=1e-3)
    with pytest.raises(StudyError, match="alpha > 0"):
        R.fit(allwin, study, alpha=0.0)


def test_fit_a_cycle_is_a_tie():
    study = make_study(per_object=3, objects=("camera",))
    ps = R.pairs(study, [0, 1, 2], seed=1)
    # x > y, y > z, z > x once each: by symmetry all strengths are 0 and every p is 1/2
    by = {frozenset((p.a, p.b)): p for p in ps}
    answers = [(by[frozenset((0, 1))], 0), (by[frozenset((1, 2))], 1), (by[frozenset((0, 2))], 2)]
    r = R.fit(_judgments(ps, answers), study, alpha=0.0)
    for d in r.of("camera"):
        assert d.strength == pytest.approx(0.0, abs=1e-6)
        assert d.p_better == pytest.approx(0.5, abs=1e-6)


def test_fit_recovers_simulated_strengths():
    """Ten drawings an object (the paper: 45 pairs), 15 raters, known strengths."""
    study = make_study(per_object=10)
    ps = R.pairs(study, range(len(study.drawings)), seed=11)
    rng = np.random.default_rng(2017)
    true = {r: s for r, s in zip(rng.permutation(len(study.drawings)),
                                 np.tile(np.linspace(-2.0, 2.0, 10), 2))}
    answers = []
    for _ in range(15):
        for p in ps:
            a_wins = rng.random() < R.win_probability(true[p.a], true[p.b])
            answers.append((p, p.a if a_wins else p.b))
    r = R.fit(_judgments(ps, answers), study)
    assert r.objects == ("camera", "mixer")
    for obj in r.objects:
        got = r.of(obj)
        assert len(got) == 10
        assert sum(d.p_better for d in got) / 10 == pytest.approx(0.5, abs=1e-9)
        assert sum(d.strength for d in got) == pytest.approx(0.0, abs=1e-9)
        est = [d.strength for d in got]
        ref = [true[d.row] for d in got]
        assert spearmanr(est, ref)[0] >= 0.9
        assert kendalltau(est, ref)[0] >= 0.8
        # p_better against the truth's own p_better: each drawing is in 9 x 15 = 135
        # judgments, so sampling alone moves a win rate by about sqrt(.25 / 135) = 0.043
        rows = [d.row for d in got]
        err = [d.p_better - np.mean([R.win_probability(true[d.row], true[o])
                                     for o in rows if o != d.row]) for d in got]
        assert np.mean(np.abs(err)) < 0.045 and np.max(np.abs(err)) < 0.1
        assert [d.rank for d in got] == list(range(1, 11))
        assert est == sorted(est, reverse=True)


def test_condition_summaries_are_means_of_p_better():
    study = make_study(per_object=4)
    ps = R.pairs(study, range(len(study.drawings)), seed=1)
    rng = np.random.default_rng(0)
    answers = [(p, p.a if rng.random() < 0.6 else p.b) for p in ps for _ in range(3)]
    r = R.fit(_judgments(ps, answers), study)
    for s in r.summaries:
        ds = [d for d in r.drawings if d.condition == s.condition
              and (s.object == R.ALL_OBJECTS or d.object == s.object)]
        assert s.drawings == len(ds) == (2 if s.object != R.ALL_OBJECTS else 4)
        assert s.mean_p_better == pytest.approx(np.mean([d.p_better for d in ds]))
    assert [(s.object, s.condition) for s in r.summaries] == [
        (o, c) for o in ("camera", "mixer", "*") for c in CONDITIONS]
    table = list(csv.DictReader(io.StringIO(R.conditions_csv(r))))
    assert list(table[0]) == list(R.CONDITIONS_HEADER) and len(table) == 6
    rows = list(csv.DictReader(io.StringIO(R.strengths_csv(r))))
    assert list(rows[0]) == list(R.STRENGTHS_HEADER) and len(rows) == 8
    assert {row["participant"] for row in rows} == set(study.participants)


def test_unjudged_objects_are_left_out_and_no_judgments_is_an_error():
    study = make_study(per_object=3)
    ps = R.pairs(study, range(6), seed=1)
    cam = [p for p in ps if p.object == "camera"]
    r = R.fit(_judgments(ps, [(cam[0], cam[0].a)]), study)
    assert r.objects == ("camera",)
    # the camera drawing never judged is still ranked, between the winner and the loser
    assert [d.comparisons for d in r.of("camera")] == [1, 0, 1]
    with pytest.raises(StudyError, match="no judgments"):
        R.fit(R.Judgments("j.csv", ps, (), 3), study)


# ----------------------------------------------------------------------------- plot


def test_plot_is_a_labelled_deterministic_png():
    study = make_study(per_object=6)
    ps = R.pairs(study, range(len(study.drawings)), seed=1)
    rng = np.random.default_rng(1)
    r = R.fit(_judgments(ps, [(p, p.a if rng.random() < 0.5 else p.b) for p in ps * 4]), study)
    svg = R.plot_svg(r, "camera")
    assert "camera: which drawings raters judged more accurate" in svg
    assert "Probability of being judged more accurate" in svg
    for c in CONDITIONS:
        mean = next(s.mean_p_better for s in r.summaries
                    if (s.object, s.condition) == ("camera", c))
        assert f"{c} (mean {mean:.2f})" in svg
    # one square per drawing, in its condition's colour
    for i, c in enumerate(CONDITIONS):
        n = sum(d.condition == c for d in r.of("camera"))
        assert svg.count(f'fill="{R.PALETTE[i]}" stroke="#ffffff"') == n
    png = R.plot_png(r, "camera")
    assert png == R.plot_png(r, "camera")
    image = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR)
    assert image.shape[:2] == (R.PLOT_PX[1], R.PLOT_PX[0])
    with pytest.raises(KeyError):
        R.plot_svg(r, "toaster")


# ----------------------------------------------------------------------------- files


def test_read_scored_and_images_check_against_the_study(tmp_path):
    study = make_study(per_object=3, folder=tmp_path)
    scores = tmp_path / "scores"
    (scores / "drawings").mkdir(parents=True)
    lines = ["row,participant,object,condition,sheet,file"]
    for d in study.drawings[:4]:
        cv2.imwrite(str(scores / "drawings" / f"{d.row}.png"),
                    drawing_image(study.sheets[d.sheet], 1.0, d.row))
        lines.append(f"{d.row},{d.participant},{d.object},{d.condition},{d.sheet},"
                     f"drawings/{d.row}.png")
    (scores / "drawings.csv").write_text("\n".join(lines) + "\n")
    scored = R.read_scored(study)
    assert [d.row for d in scored] == [0, 1, 2, 3]
    images = R.read_images(study, scored)
    assert images[2].shape == (360, 480) and images[2].dtype == np.uint8  # 90 x 120 mm at 4/mm
    # a row that does not match study.json
    lines[2] = lines[2].replace(",P01,", ",P02,")
    (scores / "drawings.csv").write_text("\n".join(lines) + "\n")
    with pytest.raises(StudyError, match=r"drawings.csv:3: participant: 'P02' does not match"):
        R.read_scored(study)
    # an image of the wrong size
    cv2.imwrite(str(scores / "drawings" / "0.png"), np.zeros((100, 100), np.uint8))
    with pytest.raises(StudyError, match=r"0.png: 100 x 100 px is not sheet"):
        R.read_images(study, scored)


def test_rank_wording_passes_its_check_and_pages_can_only_name_the_pair():
    import string

    from h2s_print import templates

    templates.load.cache_clear()
    wording = templates.load("rank")
    fields = {f for text in wording["pages"].values()
              for _, f, _, _ in string.Formatter().parse(text) if f}
    assert fields <= {"pair", "index", "count"}  # raters stay blind
    assert "Please ignore style or shading." in wording["pages"]["question"]
