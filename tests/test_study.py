"""Drawing studies (issue 14): the design's counterbalancing, the packets, stamps and codes."""

from __future__ import annotations

import csv
import io
import itertools
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from h2s_print.cli import main
from h2s_print.studyfile import parse_code, read_study
from h2s_print.study import assign, balance_note, design_rows, williams_rows

from conftest import CONFIGS

OBJECTS = ("camera", "mixer")
CONDITIONS = ("novice", "basic")
PARTICIPANTS = tuple(f"P{i:02d}" for i in range(1, 7))


# ----------------------------------------------------------------------------- the design


@pytest.mark.parametrize("k", range(1, 8))
def test_williams_rows_are_a_balanced_latin_square(k):
    rows = williams_rows(k)
    assert len(rows) == (k if k % 2 == 0 else 2 * k) or k == 1
    for r in rows:
        assert sorted(r) == list(range(k))
    # every item at every position equally often
    for pos in range(k):
        counts = Counter(r[pos] for r in rows)
        assert len(set(counts.values())) == 1 and len(counts) == k
    # every ordered pair of neighbours equally often
    if k > 1:
        pairs = Counter((r[i], r[i + 1]) for r in rows for i in range(k - 1))
        assert len(pairs) == k * (k - 1) and len(set(pairs.values())) == 1


@pytest.mark.parametrize("design", ["fixed-first", "latin-square"])
def test_design_fills_every_cell_equally(design):
    n = design_rows(len(OBJECTS), len(CONDITIONS), design) * 3
    people = [f"P{i}" for i in range(n)]
    plan = assign(people, OBJECTS, CONDITIONS, design, "novice", seed=5)
    assert len(plan) == n * len(OBJECTS)
    # every participant draws every object once, in orders 1..k
    for p in people:
        mine = [a for a in plan if a.participant == p]
        assert sorted(a.object for a in mine) == sorted(OBJECTS)
        assert [a.order for a in mine] == list(range(1, len(OBJECTS) + 1))
        assert {a.condition for a in mine} == set(CONDITIONS)  # as many objects as conditions
    cells = Counter((a.object, a.condition) for a in plan)
    assert set(cells) == set(itertools.product(OBJECTS, CONDITIONS))
    assert len(set(cells.values())) == 1
    if design == "fixed-first":
        # the paper's rule: the guided tutorial always first
        assert all(a.condition == "novice" for a in plan if a.order == 1)
    else:
        # each object first equally often, each condition first equally often
        firsts = Counter(a.object for a in plan if a.order == 1)
        assert len(set(firsts.values())) == 1 and len(firsts) == len(OBJECTS)
        firsts = Counter(a.condition for a in plan if a.order == 1)
        assert len(set(firsts.values())) == 1 and len(firsts) == len(CONDITIONS)


def test_design_is_seeded():
    a = assign(PARTICIPANTS, OBJECTS, CONDITIONS, "fixed-first", "novice", seed=1)
    assert a == assign(PARTICIPANTS, OBJECTS, CONDITIONS, "fixed-first", "novice", seed=1)
    others = {assign(PARTICIPANTS, OBJECTS, CONDITIONS, "fixed-first", "novice", seed=s)
              for s in range(2, 8)}
    assert any(o != a for o in others)


def test_an_unbalanced_count_is_said():
    assert balance_note(6, 2, 2, "fixed-first") is None
    note = balance_note(7, 2, 2, "fixed-first")
    assert note is not None and "7 participants" in note and "8 participants" in note
    assert balance_note(6, 2, 2, "latin-square") is not None  # 4 a turn: 8 would balance


# ----------------------------------------------------------------------------- a built study


def _write_config(folder: Path, text: str) -> Path:
    path = folder / "trial.yaml"
    path.write_text(text.replace("@", str(CONFIGS)), encoding="utf-8")
    return path


STUDY = """title: Trial study
study:
  participants: 6
  objects: ["@/camera.yaml", {config: "@/mixer.yaml", view: front-left}]
  conditions: [novice, basic]
  design: fixed-first
  seed: 3
"""


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    folder = tmp_path_factory.mktemp("study")
    config = _write_config(folder, STUDY)
    out = folder / "out"
    assert main(["-q", "study", str(config), "-o", str(out)]) == 0
    return out / "trial"


def _pdf_pages(path: Path):
    from pypdf import PdfReader

    return [p.extract_text() for p in PdfReader(str(path)).pages]


def _page_gray(path: Path, index: int, dpi: float = 300) -> np.ndarray:
    import pypdfium2 as pdfium

    page = pdfium.PdfDocument(str(path))[index]
    return np.asarray(page.render(scale=dpi / 72, grayscale=True).to_pil().convert("L"))


def test_study_writes_its_files(built):
    names = sorted(p.relative_to(built).as_posix() for p in built.rglob("*") if p.is_file())
    assert names == sorted(
        ["study.json", "assignment.csv", "answer-keys.pdf", "responses.csv", "preferences.csv"]
        + [f"packets/{p}.pdf" for p in PARTICIPANTS]
        + [f"sheets/{o}-{c}.png" for o in OBJECTS for c in CONDITIONS])
    study = read_study(built)
    rows = list(csv.DictReader(io.StringIO((built / "assignment.csv").read_text())))
    assert len(rows) == len(study.drawings) == 12
    for row, d in zip(rows, study.drawings):
        assert (row["participant"], row["object"], row["condition"], row["code"]) == (
            d.participant, d.object, d.condition, d.code)
        assert parse_code(d.code) == (study.study_id, d.row)
    cells = Counter((d.object, d.condition) for d in study.drawings)
    assert sorted(cells.values()) == [3, 3, 3, 3]
    assert all(d.condition == "novice" for d in study.drawings if d.order == 1)


def test_the_answers_have_a_data_sheet_and_the_times_a_place(built):
    """responses.csv has a row per drawing (as assignment.csv) with the times the
    experimenter writes on the questionnaire page and a column per question, empty;
    preferences.csv a row per participant; every questionnaire page asks for the times; no
    tutorial cover in a packet gives an estimated time, which differed between the
    conditions (a study designer's review: a cue, a pace, and no time recorded)."""
    from h2s_print import templates

    study = read_study(built)
    rows = list(csv.DictReader(io.StringIO((built / "responses.csv").read_text())))
    items = templates.lookup("study", "questionnaire.items")
    assert len(rows) == len(study.drawings)
    for row, d in zip(rows, study.drawings):
        assert (int(row["row"]), row["participant"], int(row["order"]), row["object"],
                row["condition"]) == (d.row, d.participant, d.order, d.object, d.condition)
        assert [row[f"q{k + 1}"] for k in range(len(items))] == [""] * len(items)
        assert row["started"] == row["finished"] == row["comments"] == ""
    prefs = list(csv.DictReader(io.StringIO((built / "preferences.csv").read_text())))
    assert [r["participant"] for r in prefs] == list(study.participants)
    time_words = " ".join(templates.text("study", "questionnaire.time").split()[:3])
    estimate = templates.text("pages", "cover.time", minutes=0).split("0")[0].strip()
    for participant in PARTICIPANTS:
        texts = _pdf_pages(built / "packets" / f"{participant}.pdf")
        quests = [t for t in texts if items[0]["question"] in t]
        assert len(quests) == 2 and all(time_words in " ".join(t.split()) for t in quests)
        assert not any(estimate in t for t in texts), participant
    # each answer key names its condition as the sheets' stamps do, to be matched to them
    keys = _pdf_pages(built / "answer-keys.pdf")
    stamped = {"novice": "with guides", "basic": "without guides"}
    assert len(keys) == 4
    for text in keys:
        flat = " ".join(text.split())
        said = [c for c, words in stamped.items() if f'the tutorial {words}"' in flat]
        assert len(said) == 1 and f"condition {said[0]}" in flat, flat


def test_every_sheet_is_stamped_and_its_code_reads_back(built):
    """Each packet's drawing sheets: the stamp names participant, object and condition, and the
    QR code decoded from the rendered page is that drawing's code (and nothing else is)."""
    import cv2

    study = read_study(built)
    titles = {"camera": "Digital SLR camera", "mixer": "Kitchen stand mixer"}
    names = {"novice": "with guides", "basic": "without guides"}
    for participant in PARTICIPANTS:
        path = built / "packets" / f"{participant}.pdf"
        texts = _pdf_pages(path)
        mine = [d for d in study.drawings if d.participant == participant]
        sheets = [i for i, t in enumerate(texts) if "this bar measures 100 mm" in t]
        assert len(sheets) == len(mine)
        for index, d in zip(sheets, mine):
            text = texts[index]
            assert participant in text and titles[d.object] in text
            assert names[d.condition] in text and f"drawing {d.order} of 2" in text
            gray = _page_gray(path, index)
            found, _, _ = cv2.QRCodeDetector().detectAndDecode(gray)
            assert found == d.code, (participant, d.order)


def test_primer_once_and_never_for_control_only(tmp_path):
    """One object, two conditions: half the participants draw only the control tutorial and
    their packets carry no primer and no word of guides; the others get the primer once."""
    config = _write_config(tmp_path, STUDY.replace(
        ', {config: "@/mixer.yaml", view: front-left}', "").replace("participants: 6",
                                                                     "participants: 4"))
    out = tmp_path / "out"
    assert main(["-q", "study", str(config), "-o", str(out)]) == 0
    study = read_study(out / "trial")
    kinds = Counter()
    for participant in study.participants:
        texts = _pdf_pages(out / "trial" / "packets" / f"{participant}.pdf")
        (d,) = [d for d in study.drawings if d.participant == participant]
        primers = sum("Primer: constructions in perspective" in t for t in texts)
        if d.condition == "basic":
            assert primers == 0
            assert not any("guide" in t.lower().replace("without guides", "") for t in texts)
        else:
            assert primers == 1
        kinds[d.condition] += 1
    assert kinds == {"novice": 2, "basic": 2}


def test_a_packet_with_two_guided_drawings_has_one_primer(tmp_path):
    config = _write_config(tmp_path, STUDY.replace("conditions: [novice, basic]",
                                                   "conditions: [novice]"))
    out = tmp_path / "out"
    assert main(["-q", "study", str(config), "-o", str(out)]) == 0
    texts = _pdf_pages(out / "trial" / "packets" / "P01.pdf")
    assert sum("Primer: constructions in perspective" in t for t in texts) == 1
    assert not any("Which tutorial did you prefer?" in t for t in texts)  # one condition


def test_answer_keys_are_the_finished_drawings_at_true_scale(built):
    from pypdf import PdfReader

    study = read_study(built)
    pages = PdfReader(str(built / "answer-keys.pdf")).pages
    assert len(pages) == len(study.sheets)
    for page, key in zip(pages, study.sheets.values()):
        w_mm = float(page.mediabox.width) * 25.4 / 72
        h_mm = float(page.mediabox.height) * 25.4 / 72
        assert (round(w_mm, 1), round(h_mm, 1)) == (round(key.paper_mm[0], 1),
                                                  round(key.paper_mm[1], 1))
        assert f"condition {key.condition}" in page.extract_text()


def test_study_is_deterministic(built, tmp_path):
    config = _write_config(tmp_path, STUDY)
    out = tmp_path / "again"
    assert main(["-q", "study", str(config), "-o", str(out), "--no-cache"]) == 0
    for path in built.rglob("*"):
        if path.is_file():
            assert (out / "trial" / path.relative_to(built)).read_bytes() == path.read_bytes(), path


@pytest.mark.parametrize("edit, message", [
    (("design: fixed-first", "design: random"), "study.design: expected one of"),
    (("participants: 6", "participants: [A, B, A]"), "study.participants[2]: participant 'A' is listed twice"),
    (("conditions: [novice, basic]", "conditions: [novice, expert]"), "study.conditions[1]: expected one of"),
    (("seed: 3", "seed: 3\n  colour: red"), "study.colour: unknown key"),
    (("seed: 3", "seed: 3\n  seed: 4"), "study.seed: key given twice"),
    (("@/camera.yaml", "@/nothere.yaml"), "study.objects[0]: '"),
    (("view: front-left", "view: side"), "study.objects[1].view: "),
])
def test_bad_study_configs_say_where(tmp_path, capsys, edit, message):
    config = _write_config(tmp_path, STUDY.replace(*edit))
    out = tmp_path / "out"
    assert main(["study", str(config), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "trial.yaml" in err[0] and message in err[0], err
    assert not out.exists() or not any(out.rglob("*.pdf"))


def test_build_refuses_a_study_and_study_refuses_a_tutorial(capsys):
    assert main(["build", str(CONFIGS / "study.yaml"), "-o", "/nonexistent/x"]) == 2
    assert "make it with 'h2s study'" in capsys.readouterr().err
    assert main(["study", str(CONFIGS / "camera.yaml"), "-o", "/nonexistent/x"]) == 2
    assert "study: missing" in capsys.readouterr().err


def test_a_narrow_margin_is_widened_and_said(tmp_path, caplog):
    """A tutorial config with an 8 mm margin: its study sheets get 15 mm (said), so the
    marks, code and stamp are printed at least 4.5 mm from the paper's edge."""
    import logging

    from h2s_print.study import PRINT_INSET_MM, STUDY_MARGIN_MM

    narrow = tmp_path / "narrow.yaml"
    narrow.write_text((CONFIGS / "camera.yaml").read_text().replace(
        "margin_mm: 12", "margin_mm: 8").replace("models/camera.glb",
                                                 str(CONFIGS / "models" / "camera.glb")))
    config = _write_config(tmp_path, STUDY.replace("@/camera.yaml", str(narrow)))
    with caplog.at_level(logging.INFO, logger="h2s_print"):
        assert main(["study", str(config), "-o", str(tmp_path / "out")]) == 0
    assert "narrow.yaml: paper.margin_mm 8 -> 15 for the study's sheets" in caplog.text
    for key in read_study(tmp_path / "out" / "trial").sheets.values():
        w, h = key.paper_mm
        assert key.frame_mm == (STUDY_MARGIN_MM, STUDY_MARGIN_MM, w - STUDY_MARGIN_MM,
                                h - STUDY_MARGIN_MM)
        x0, y0, x1, y1 = key.code_box_mm
        assert min(x0, y0, w - x1, h - y1) >= PRINT_INSET_MM
        assert y1 <= STUDY_MARGIN_MM - 1.5  # clear of the frame line


def test_packets_never_name_a_level(built):
    """Participants are blind to the design: no page of a packet says novice or basic (the
    tutorials' covers, headers and footers name the condition neutrally)."""
    for participant in PARTICIPANTS:
        words = " ".join(_pdf_pages(built / "packets" / f"{participant}.pdf")).lower()
        assert "novice" not in words and "basic" not in words, participant
        assert "with guides" in words


# ----------------------------------------------------------------------------- scored and ranked


#: Per camera drawing (participant order), how far its parts are moved, mm: growing errors.
ERRORS_MM = (0.0, 0.8, 1.6, 2.4, 3.2, 4.8)


def _sheet_scan(study, drawing, error_mm: float, angle: float):
    """A scan of ``drawing``'s stamped sheet (rendered from its packet) pencilled with the
    model's lines, every part moved ``error_mm`` in a seeded direction, rotated ``angle``."""
    import math

    from _scans import RENDER_DPI, pencil, scan

    path = study.folder / "packets" / f"{drawing.participant}.pdf"
    texts = _pdf_pages(path)
    index = [i for i, t in enumerate(texts) if "this bar measures 100 mm" in t][
        drawing.order - 1]
    page = _page_gray(path, index, RENDER_DPI)
    key = study.sheets[drawing.sheet]
    rng = np.random.default_rng(drawing.row)
    moves = {}
    for part, _ in key.lines:
        a = rng.uniform(0, 2 * math.pi)
        moves[part] = (error_mm * math.cos(a), error_mm * math.sin(a))
    img, _ = scan(pencil(page, key, moves), key, angle_deg=angle, dpi=220, noise=2.0,
                  seed=drawing.row)
    return img


@pytest.fixture(scope="module")
def scored(built, tmp_path_factory):
    """A copy of the built study with its six camera drawings scanned and scored."""
    import shutil

    import cv2

    folder = tmp_path_factory.mktemp("scored") / "trial"
    shutil.copytree(built, folder)
    study = read_study(folder)
    cams = [d for d in study.drawings if d.object == "camera"]
    scans = []
    for d, err in zip(cams, ERRORS_MM):
        p = folder.parent / f"scan-{d.participant}.png"
        p.write_bytes(cv2.imencode(".png", _sheet_scan(study, d, err, 7.0 * d.row - 20))[1])
        scans.append(p)
    assert main(["-q", "score", *map(str, scans), "--study", str(folder)]) == 0
    return study, cams, scans


def test_score_writes_figures_drawings_and_overlays(scored):
    study, cams, _ = scored
    out = study.folder / "scores"
    rows = list(csv.DictReader(io.StringIO((out / "scores.csv").read_text())))
    overall = {r["participant"]: r for r in rows if r["part"] == "*"}
    assert sorted(overall) == sorted(d.participant for d in cams)
    err = [float(overall[d.participant]["to_drawing_mm"]) for d in cams]
    assert err == sorted(err) and err[0] < 0.3 < err[-1]  # larger known errors score worse
    offsets = [float(overall[d.participant]["offset_mm"]) for d in cams]
    for measured, true in zip(offsets, ERRORS_MM):
        assert abs(measured - true) < 0.5, (offsets, ERRORS_MM)
    listed = list(csv.DictReader(io.StringIO((out / "drawings.csv").read_text())))
    assert [int(r["row"]) for r in listed] == sorted(d.row for d in cams)
    for d in cams:
        assert (out / "drawings" / f"{d.row}.png").is_file()
        assert (out / "overlays" / f"{d.row}-{d.participant}-camera.png").is_file()


def test_scoring_again_replaces_that_drawings_rows(scored):
    study, cams, scans = scored
    out = study.folder / "scores"
    before = (out / "scores.csv").read_text()
    assert main(["-q", "score", str(scans[0]), "--study", str(study.folder)]) == 0
    assert (out / "scores.csv").read_text() == before  # same scan: same rows, none doubled


@pytest.mark.parametrize("content", [b"", b"not an image at all"])
def test_a_bad_scan_stops_everything(scored, tmp_path, capsys, content):
    study, _, scans = scored
    bad = tmp_path / "bad.png"
    bad.write_bytes(content)
    stamp = {p: p.stat().st_mtime_ns for p in (study.folder / "scores").rglob("*")}
    assert main(["score", str(scans[1]), str(bad), "--study", str(study.folder)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "bad.png" in err[0]
    assert {p: p.stat().st_mtime_ns for p in (study.folder / "scores").rglob("*")} == stamp


def test_the_same_drawing_twice_in_one_run_is_an_error(scored, capsys):
    study, _, scans = scored
    assert main(["score", str(scans[2]), str(scans[2]), "--study", str(study.folder)]) == 2
    assert "was scanned twice" in capsys.readouterr().err


def test_rank_pages_then_strengths_follow_the_judgments(scored, tmp_path):
    """Pair pages for every pair of the six scored camera drawings; raters who always pick
    the drawing with the smaller error give strengths in that order."""
    study, cams, _ = scored
    out = study.folder / "rank"
    assert main(["-q", "rank", str(study.folder)]) == 0
    assert len(_pdf_pages(out / "pairs.pdf")) == 15
    template = list(csv.DictReader(io.StringIO((out / "judgments.csv").read_text())))
    assert len(template) == 15 and all(r["winner"] == "" for r in template)
    error = {d.row: e for d, e in zip(cams, ERRORS_MM)}
    for r in template:
        r["winner"] = "a" if error[int(r["a"])] < error[int(r["b"])] else "b"
    filled = tmp_path / "filled.csv"
    with filled.open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(template[0]))
        w.writeheader()
        w.writerows(template * 3)
    assert main(["-q", "rank", str(study.folder), "--judgments", str(filled)]) == 0
    strengths = list(csv.DictReader(io.StringIO((out / "strengths.csv").read_text())))
    ranked = [int(r["row"]) for r in strengths if r["object"] == "camera"]
    assert ranked == [d.row for d in cams]  # strongest first = smallest error first
    assert (out / "camera.png").is_file()
    # a second 'h2s rank' keeps the raters' file
    (out / "judgments.csv").write_text("kept")
    assert main(["-q", "rank", str(study.folder)]) == 0
    assert (out / "judgments.csv").read_text() == "kept"


def test_a_study_in_german_words_the_whole_packet(tmp_path):
    """The study config's language: covers, questionnaires and the tutorials themselves."""
    config = _write_config(tmp_path, STUDY.replace(
        ', {config: "@/mixer.yaml", view: front-left}', "").replace(
        "participants: 6", "participants: 2") + "language: de\n")
    out = tmp_path / "out"
    assert main(["-q", "study", str(config), "-o", str(out)]) == 0
    words = " ".join(_pdf_pages(out / "trial" / "packets" / "P01.pdf"))
    assert "Deine Zeichenmappe" in words  # the packet's cover
    assert "Arbeitsheft Skizzieren" in words  # the tutorial's own cover
    assert "Step " not in words and "Schritt " in words
    assert read_study(out / "trial").language == "de"
