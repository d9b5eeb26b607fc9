"""Drawing studies (issue 14): who draws what in which order, and the packets they draw from.

``h2s study CONFIG`` (a config with a ``study:`` section, README "Drawing studies") makes:

* ``study.json`` (:mod:`h2s_print.studyfile`): the assignment and, per printed sheet kind, what
  ``h2s score`` needs to read a scan of it;
* ``assignment.csv``: one row per drawing (participant, order, object, view, condition, sheet,
  code);
* ``packets/<participant>.pdf``: the participant's packet in drawing order;
* ``answer-keys.pdf``: per (object, condition), the finished drawing at true scale on the
  sheet's frame with its registration marks, to print on transparency and lay over a sheet;
* ``sheets/<object>-<condition>.png``: the blank sheet's printed marks, for ``h2s score``.

**The design** (:func:`assign`).  Every participant draws every object once, so an object is
never drawn twice by one person (the paper: two objects, two tutorial types).  Participants are
shuffled by ``seed`` onto the rows of the design:

* *conditions*: design row ``r`` gives object ``j`` the condition ``conditions[(j + r) mod m]``
  (a Latin rotation): every object × condition cell is drawn equally often when the number of
  participants is a multiple of the design's rows, and each participant meets the conditions
  as evenly as the number of objects allows (with as many objects as conditions: each once);
* *order*, ``fixed-first`` (the paper's: "participants always followed a How2Sketch tutorial
  first to disadvantage How2Sketch to any learning effect"): the drawings in condition
  ``first`` come first, the others after in the config's order of conditions; objects within
  a condition rotate with the row;
* *order*, ``latin-square``: the participant's drawings are ordered by a row of a balanced
  Latin square (Williams design: every drawing position holds every object equally often and
  every object follows every other equally often; ``2k`` rows for an odd number ``k`` of
  objects), crossed with the condition rotation, so ``m × rows`` participants balance both.

A participant count that is not a multiple of the design's rows is allowed (a study loses
participants) but said: the warning names the count that balances.

**A packet**: a cover with the participant ID and the schedule (what to draw, in which
order, on which pages); the primer once, before the first tutorial with guides (never in a
control-only packet); then per drawing the tutorial's pages (cover, steps, finished drawing),
its calibrated drawing sheet stamped in the top band with the participant, the drawing's
number, object and condition, and a QR code of ``H2S:<study id>:<row>`` in the bottom band
beside the registration marks (:func:`code_box`), then a questionnaire page (the paper's four
items, 1-5, and a free-text box); last, when the participant met two conditions or more, which
tutorial they preferred (the paper's closing question).

The study id is a hash of everything the sheets and the assignment depend on, so a sheet of
another study (or of an earlier version of this one) is recognised when scored.
"""

from __future__ import annotations

import csv
import hashlib
import io
import json
import logging
import math
import random
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Sequence

from . import fonts, templates
from .config import PaperSpec, StudyConfig
from .errors import ConfigError
from .layout import (
    Bookmark, Page, Polyline, Rect, Text, _Frame, _header, _paragraph,
    _with_footers, fit_line, plain_text, text_width_mm,
)
from .sheet import registration_marks
from .studyfile import Box, Drawing, SheetKey, Study, code_text, study_json
from .types import Stroke

log = logging.getLogger(__name__)

#: The QR code's error correction: ``M`` (15 % of the symbol may be lost to a pencil mark or
#: a fold and it still reads).
CODE_ERROR = "m"
#: Resolution of the blank-sheet images ``h2s score`` subtracts from a scan (203 dpi).
PX_PER_MM = 8.0
#: A study sheet's margin: the registration marks, the code and the stamp sit in the margin
#: band, all at least :data:`PRINT_INSET_MM` from the paper's edge.  A tutorial config with a
#: smaller margin is given this one for the study (said on the terminal).
STUDY_MARGIN_MM = 15.0
#: Most printers cannot print closer to the paper's edge than about 4.2 mm (laser) or 3 mm
#: (inkjet): nothing a scan needs is printed nearer than this, mm.
PRINT_INSET_MM = 4.5


def _t(key: str, **fields) -> str:
    return plain_text(templates.text("study", key, **fields))


# ----------------------------------------------------------------------------- design


@dataclass(frozen=True, slots=True)
class Assignment:
    """One drawing of the design: participant ``participant`` draws ``object`` as their
    ``order``-th drawing (from 1) with the tutorial of ``condition``."""

    participant: str
    order: int
    object: str
    condition: str


def williams_rows(k: int) -> tuple[tuple[int, ...], ...]:
    """The rows of a balanced Latin square (Williams design) over ``k`` items: each item once
    per row, each item at each position equally often, each ordered pair of neighbours equally
    often; ``k`` rows for even ``k``, ``2k`` (the rows and their reverses) for odd ``k``."""
    if k == 1:
        return ((0,),)
    first = [0]
    lo, hi = 1, k - 1
    while len(first) < k:
        first.append(lo)
        lo += 1
        if len(first) < k:
            first.append(hi)
            hi -= 1
    rows = [tuple((x + i) % k for x in first) for i in range(k)]
    if k % 2:
        rows += [tuple(reversed(r)) for r in rows]
    return tuple(rows)


def design_rows(n_objects: int, n_conditions: int, design: str) -> int:
    """How many participants one full turn of the design takes (a multiple balances it)."""
    rows = n_conditions
    if design == "latin-square":
        rows *= len(williams_rows(n_objects))
    return rows


def assign(participants: Sequence[str], objects: Sequence[str], conditions: Sequence[str],
           design: str, first: str, seed: int) -> tuple[Assignment, ...]:
    """The study's drawings, participant by participant in the given order, each
    participant's in drawing order (module docstring: the design).

    Args:
        participants: IDs.
        objects: object names; every participant draws each once.
        conditions: the conditions (tutorial levels).
        design: ``fixed-first`` or ``latin-square``.
        first: the condition drawn first under ``fixed-first``.
        seed: shuffles which participant takes which row of the design.
    """
    n, k, m = len(participants), len(objects), len(conditions)
    rows = list(range(n))
    random.Random(seed).shuffle(rows)
    squares = williams_rows(k)
    out: list[Assignment] = []
    for p, participant in enumerate(participants):
        r = rows[p]
        cond = [conditions[(j + r) % m] for j in range(k)]
        if design == "latin-square":
            order = list(squares[(r // m) % len(squares)])
        else:
            rank = {c: (0 if c == first else 1 + i) for i, c in enumerate(conditions)}
            order = sorted(range(k), key=lambda j: (rank[cond[j]], (j - r) % k))
        for i, j in enumerate(order, start=1):
            out.append(Assignment(participant, i, objects[j], cond[j]))
    return tuple(out)


def balance_note(n_participants: int, n_objects: int, n_conditions: int,
                 design: str) -> str | None:
    """A warning when the participants do not fill whole turns of the design, else None."""
    rows = design_rows(n_objects, n_conditions, design)
    if n_participants % rows == 0:
        return None
    fill = rows * math.ceil(n_participants / rows)
    return _t("warning.unbalanced", n=n_participants, rows=rows, fill=fill)


# ----------------------------------------------------------------------------- sheets


def code_box(paper_mm: tuple[float, float], margin_mm: float) -> Box:
    """Where a sheet's QR code goes: in the bottom margin band, left of the bottom-right
    registration mark, from :data:`PRINT_INSET_MM` above the paper's edge to 1.5 mm below the
    frame (9 mm at the study's 15 mm margin: version-1 modules of 0.43 mm, which a 200 dpi
    scan or a phone photo of the page resolves)."""
    marks, r = registration_marks(paper_mm, margin_mm)
    side = float(margin_mm) - 1.5 - PRINT_INSET_MM
    x1 = marks[1][0] - r - 3.0  # left of the bottom-right mark
    return (x1 - side, PRINT_INSET_MM, x1, PRINT_INSET_MM + side)


def code_items(text: str, box: Box) -> list[Rect]:
    """A QR code of ``text`` filling ``box`` (sheet mm): one black rectangle per run of dark
    modules in a row (segno makes the symbol; no quiet zone is drawn, the sheet around it is
    blank)."""
    import segno

    qr = segno.make(text, error=CODE_ERROR, micro=False, boost_error=False)
    rows = [list(r) for r in qr.matrix]
    n = len(rows)
    x0, y0, x1, y1 = box
    cell = min(x1 - x0, y1 - y0) / n
    items: list[Rect] = []
    for i, row in enumerate(rows):
        y = y1 - (i + 1) * cell
        j = 0
        while j < n:
            if row[j]:
                k = j
                while k < n and row[k]:
                    k += 1
                items.append(Rect(x0 + j * cell, y, (k - j) * cell, cell, None, 0.0, "black",
                                  "code"))
                j = k
            else:
                j += 1
    return items


def stamped(sheet: Page, code: str, box: Box, stamp: str = "") -> Page:
    """A calibrated sheet with the QR code of ``code`` in ``box`` and, when given, ``stamp``
    (participant, drawing, object, condition) as its heading in the top band (the plain
    heading names the level, which participants are not told)."""
    items = []
    legend = next((it for it in sheet.items
                   if isinstance(it, Text) and it.role == "vp_tick_legend"), None)
    for it in sheet.items:
        if stamp and isinstance(it, Text) and it.role == "sheet_title":
            stamp = plain_text(stamp)
            x1 = sheet.width_mm - sheet.margin_mm / 2 - 6.0
            if legend is not None:  # left of the ticks' line in the top band, if it fits
                beside = legend.box_mm[0] - 4.0 - it.x_mm
                if text_width_mm(stamp, 5.0, it.font) <= beside:
                    x1 = legend.box_mm[0] - 4.0
                else:  # the stamp matters more: the ticks stay, unexplained on this sheet
                    legend = None
            it = replace(it, string=stamp, size_pt=fit_line(stamp, x1 - it.x_mm, it.size_pt,
                                                            it.font), colour="black",
                         role="stamp")
        items.append(it)
    if stamp and legend is None:
        items = [it for it in items if not (isinstance(it, Text) and it.role == "vp_tick_legend")]
    return replace(sheet, items=tuple(items) + tuple(code_items(code, box)))


def _sheet_lines(final: Sequence[Stroke], parts: Sequence[str]
                 ) -> tuple[tuple[str, tuple[tuple[tuple[float, float], ...], ...]], ...]:
    by_part: dict[str, list[tuple[tuple[float, float], ...]]] = {p: [] for p in parts}
    for st in final:
        if len(st.points_mm) >= 2 and not st.kind.endswith("hidden"):
            by_part.setdefault(st.part, []).append(tuple((float(x), float(y))
                                                         for x, y in st.points_mm))
    return tuple((p, tuple(lines)) for p, lines in by_part.items() if lines)


def answer_key(sheet: Page, key: SheetKey, heading: str, mark: str, title: str) -> Page:
    """The finished drawing of ``key`` at true scale on the sheet's frame, corners,
    registration marks and 100 mm scale bar (check the transparency printed at 100 %), to
    print on transparency and lay over a drawn sheet; ``heading`` (bold, in the top band)
    says which key it is, ``mark`` is its outline entry, ``title`` the document's."""
    keep = ("frame", "registration", "scale_bar", "scale_tick", "scale_label")
    items: list = [it for it in sheet.items if getattr(it, "role", "") in keep
                   or (isinstance(it, Polyline) and it.colour == "green")]
    for _, lines in key.lines:
        for line in lines:
            items.append(Polyline(line, "black", 0.4, (), False, "key"))
    band = sheet.margin_mm / 2
    x0 = band + 6.0
    heading = plain_text(heading)
    size = fit_line(heading, sheet.width_mm - 2 * x0, 10, "Helvetica-Bold")
    items.append(Text(x0, sheet.height_mm - band - 1.5, heading, size, "Helvetica-Bold", "start",
                      "black", "key_heading"))
    return Page(sheet.width_mm, sheet.height_mm, tuple(items), (Bookmark(mark),), "sheet",
                title, sheet.margin_mm, sheet.font)


# ----------------------------------------------------------------------------- pages


def _frame(paper: PaperSpec) -> _Frame:
    return _Frame(paper.width_mm, paper.height_mm, paper.margin_mm)


def condition_name(condition: str) -> str:
    """What participants read for a condition (``templates/study.yaml`` ``conditions``)."""
    return _t(f"conditions.{condition}")


def cover_page(paper: PaperSpec, title: str, participant: str,
               schedule: Sequence[tuple[int, str, str, int, int, int]]) -> Page:
    """A packet's cover: participant ID, what to do, and the schedule rows
    ``(order, object title, condition, first page, sheet page, questionnaire page)``."""
    f = _frame(paper)
    x0, _, x1, _ = f.box
    items, top = _header(f, title, _t("cover.participant", participant=participant))
    para, top = _paragraph(x0, top - 4, x1 - x0, _t("cover.kicker"), 18, font="Helvetica-Bold")
    items += para
    big, top = _paragraph(x0, top - 6, x1 - x0, participant, 40, font="Helvetica-Bold",
                          role="participant")
    items += big
    top -= 8
    for line in templates.lookup("study", "cover.how"):
        para, top = _paragraph(x0 + 4, top, x1 - x0 - 4,
                               plain_text(line.format(n_drawings=len(schedule))), 10)
        items.append(Text(x0, para[0].y_mm, "-", 10))
        items += para
        top -= 2.5
    top -= 4
    para, top = _paragraph(x0, top, x1 - x0, _t("cover.schedule"), 12, font="Helvetica-Bold")
    items += para
    top -= 3
    for order, obj, cond, start, sheet, quest in schedule:
        line = _t("cover.row", n=order, object=obj, condition=condition_name(cond),
                  page=start, sheet=sheet, questionnaire=quest)
        para, top = _paragraph(x0, top, x1 - x0, line, 10, role="schedule")
        items += para
        top -= 2.5
    return Page(f.width, f.height, tuple(items), (Bookmark(_t("cover.bookmark")),), "cover",
                title, f.margin)


def _scale(x0: float, y: float, width: float, low: str, high: str) -> list:
    """Five numbered boxes (1-5) across ``width`` with the end labels under 1 and 5."""
    items: list = []
    step = width / 5
    side = 6.0
    for i in range(5):
        cx = x0 + step * (i + 0.5)
        items.append(Rect(cx - side / 2, y, side, side, "black", 0.3, None, "answer_box"))
        items.append(Text(cx, y + side + 1.5, str(i + 1), 10, "Helvetica", "middle"))
    items.append(Text(x0 + step * 0.5 - side / 2, y - 4.0, low, 8, "Helvetica", "start", "grey"))
    items.append(Text(x0 + step * 4.5 + side / 2, y - 4.0, high, 8, "Helvetica", "end", "grey"))
    return items


def questionnaire_page(paper: PaperSpec, title: str, participant: str, order: int,
                       obj: str) -> Page:
    """After a drawing: the paper's four questions on a 1-5 scale and a free-text box."""
    f = _frame(paper)
    x0, y0, x1, _ = f.box
    heading = _t("questionnaire.heading", n=order, object=obj)
    items, top = _header(f, heading, _t("cover.participant", participant=participant))
    para, top = _paragraph(x0, top - 2, x1 - x0, _t("questionnaire.intro"), 10)
    items += para
    # the drawing's start and end, written by the experimenter (responses.csv's columns)
    para, top = _paragraph(x0, top - 2, x1 - x0, _t("questionnaire.time"), 10,
                           role="experimenter", colour="grey")
    items += para
    top -= 6
    for q in templates.lookup("study", "questionnaire.items"):
        para, top = _paragraph(x0, top, x1 - x0, plain_text(q["question"]), 11,
                               font="Helvetica-Bold", role="question")
        items += para
        y = top - 12.0
        items += _scale(x0, y, min(x1 - x0, 120.0), plain_text(q["low"]), plain_text(q["high"]))
        top = y - 10.0
    para, top = _paragraph(x0, top, x1 - x0, _t("questionnaire.free"), 11,
                           font="Helvetica-Bold", role="question")
    items += para
    bottom = y0 + 10.0
    if top - 3 - bottom > 20:
        items.append(Rect(x0, bottom, x1 - x0, top - 3 - bottom, "grey", 0.3, None,
                          "answer_box"))
    return Page(f.width, f.height, tuple(items),
                (Bookmark(_t("questionnaire.bookmark", n=order), 1),), "questionnaire", title,
                f.margin)


def preference_page(paper: PaperSpec, title: str, participant: str,
                    met: Sequence[tuple[str, str]]) -> Page:
    """At the end: which tutorial the participant preferred, and why; ``met`` lists each
    condition with the drawings the participant made with it ("Kitchen stand mixer, drawing
    1"), so the question can be answered from memory."""
    f = _frame(paper)
    x0, y0, x1, _ = f.box
    items, top = _header(f, _t("preference.heading"),
                         _t("cover.participant", participant=participant))
    para, top = _paragraph(x0, top - 2, x1 - x0, _t("preference.question"), 11,
                           font="Helvetica-Bold", role="question")
    items += para
    top -= 6
    for c, drawings in met:
        items.append(Rect(x0, top - 5, 5, 5, "black", 0.3, None, "answer_box"))
        items.append(Text(x0 + 8, top - 4.2, _t("preference.option", condition=condition_name(c),
                                                 object=drawings), 11))
        top -= 10
    para, top = _paragraph(x0, top - 4, x1 - x0, _t("preference.why"), 11,
                           font="Helvetica-Bold", role="question")
    items += para
    bottom = y0 + 10.0
    items.append(Rect(x0, bottom, x1 - x0, top - 3 - bottom, "grey", 0.3, None, "answer_box"))
    return Page(f.width, f.height, tuple(items), (Bookmark(_t("preference.bookmark")),),
                "preference", title, f.margin)


# ----------------------------------------------------------------------------- the study


@dataclass(frozen=True, slots=True)
class Workbook:
    """One (object, condition)'s laid-out workbook and its sheet's data for scoring."""

    object: str
    title: str
    view: str
    condition: str
    pages: tuple[Page, ...]
    key: SheetKey


@dataclass(frozen=True, slots=True)
class StudyBuild:
    """Everything ``h2s study`` writes, as bytes (nothing written yet)."""

    study: Study
    files: tuple[tuple[Path, bytes], ...]
    note: str | None


def with_study_margins(cfg: StudyConfig) -> tuple[StudyConfig, tuple[str, ...]]:
    """``cfg`` with every object's paper margin at least :data:`STUDY_MARGIN_MM`, and a note
    for each one raised (the tutorial is then fitted to the narrower frame)."""
    objects, notes = [], []
    for obj in cfg.objects:
        paper = obj.tutorial.paper
        if paper.margin_mm < STUDY_MARGIN_MM:
            notes.append(_t("warning.margin", config=obj.tutorial.path.name,
                            margin=f"{paper.margin_mm:g}", study=f"{STUDY_MARGIN_MM:g}"))
            obj = replace(obj, tutorial=replace(obj.tutorial, paper=replace(
                paper, margin_mm=STUDY_MARGIN_MM)))
        objects.append(obj)
    return replace(cfg, objects=tuple(objects)), tuple(notes)


def workbooks(cfg: StudyConfig, results: Sequence, folder: Path) -> dict[tuple[str, str], Workbook]:
    """Each object's workbook per condition, laid out once and shared by every packet.

    ``results[i]`` is :func:`h2s_print.pipeline.plan_tutorial` of ``cfg.objects[i].tutorial``
    (one view, the study's conditions as levels)."""
    from .layout import lay_out_workbook

    out = {}
    for obj, result in zip(cfg.objects, results):
        t = obj.tutorial
        parts = [p.name for p in result.plan.model.parts]
        for vp, final in zip(result.views, result.finals):
            with fonts.using(t.font), templates.using(t.language):  # each in its own
                how = [plain_text(line) for line in templates.lookup(
                    "study", "tutorial.how_basic" if vp.level == "basic" else "tutorial.how")]
                pages = lay_out_workbook(t.title, vp, t.paper, view_label=vp.name,
                                         final=final, grid=t.sheet.grid,
                                         level_label=condition_name(vp.level), how=how,
                                         cover_level=False, cover_time=False)
            sheet = pages[-1]
            m = t.paper.margin_mm
            w, h = sheet.width_mm, sheet.height_mm
            marks, r = registration_marks((w, h), m)
            name = f"{obj.name}-{vp.level}"
            key = SheetKey(
                sheet=name, object=obj.name, view=vp.name, condition=vp.level,
                paper_mm=(w, h), frame_mm=(m, m, w - m, h - m), marks_mm=marks,
                mark_radius_mm=r,
                code_box_mm=code_box((w, h), m), printed=folder / "sheets" / f"{name}.png",
                px_per_mm=PX_PER_MM, lines=_sheet_lines(final, parts))
            out[(obj.name, vp.level)] = Workbook(obj.name, t.title, vp.name, vp.level, pages, key)
    return out


def packet(cfg: StudyConfig, study_id: str, rows: Sequence[tuple[int, Assignment]],
           books: dict[tuple[str, str], Workbook]) -> tuple[Page, ...]:
    """One participant's pages in drawing order (module docstring), footers numbered."""
    participant = rows[0][1].participant
    n = len(rows)
    body: list[Page] = []
    schedule = []
    primer_done = False
    for row, a in rows:
        wb = books[(a.object, a.condition)]
        start = len(body) + 2  # the cover is page 1
        for page in wb.pages[:-1]:
            if page.kind == "primer":
                if primer_done:
                    continue  # the primer once, before the first tutorial with guides
                primer_done = True
            marks = tuple(replace(b, level=b.level + 1) for b in page.bookmarks)
            if page.kind == "cover":  # the drawing's own outline entry, its pages below
                marks = (Bookmark(_t("drawing.bookmark", n=a.order, object=wb.title)), *marks)
            body.append(replace(page, bookmarks=marks))
        stamp = _t("sheet.stamp", participant=participant, n=a.order, total=n,
                   object=wb.title, condition=condition_name(a.condition))
        sheet = replace(wb.pages[-1], bookmarks=tuple(
            replace(b, level=b.level + 1) for b in wb.pages[-1].bookmarks))
        body.append(stamped(sheet, code_text(study_id, row), wb.key.code_box_mm, stamp))
        sheet_page = len(body) + 1
        body.append(questionnaire_page(cfg.paper, cfg.title, participant, a.order, wb.title))
        schedule.append((a.order, wb.title, a.condition, start, sheet_page, len(body) + 1))
    met = [(c, "; ".join(_t("preference.drawing", object=books[(a.object, c)].title, n=a.order)
                         for _, a in rows if a.condition == c)) for c in cfg.conditions]
    met = [(c, drawings) for c, drawings in met if drawings]
    if len(met) > 1:
        body.append(preference_page(cfg.paper, cfg.title, participant, met))
    pages = [cover_page(cfg.paper, cfg.title, participant, schedule)] + body
    return _with_footers(pages, lambda k, total: _t("footer", participant=participant,
                                                    title=cfg.title, page=k, pages=total))


def _study_id(data: dict) -> str:
    blob = json.dumps(data, sort_keys=True, separators=(",", ":")).encode("utf-8")
    return hashlib.sha256(blob).hexdigest()[:8].upper()


def _assignment_csv(study: Study, books: dict[tuple[str, str], Workbook]) -> bytes:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["row", "participant", "order", "object", "view", "condition", "sheet", "code"])
    for d in study.drawings:
        w.writerow([d.row, d.participant, d.order, d.object,
                    books[(d.object, d.condition)].view, d.condition, d.sheet, d.code])
    return buf.getvalue().encode("utf-8")


def _responses_csv(study: Study) -> bytes:
    """The questionnaires' data sheet, to be filled in by hand: a row per drawing (as
    ``assignment.csv``), the times the experimenter writes on the questionnaire page, one
    column per question (``q1`` ... in the questionnaire's order, 1-5) and the free text;
    then, one row per participant, their preferred tutorial (a study designer's review: no
    template to enter the answers in, and completion time recorded nowhere)."""
    n = len(templates.lookup("study", "questionnaire.items"))
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["row", "participant", "order", "object", "condition", "started", "finished",
                *[f"q{k + 1}" for k in range(n)], "comments"])
    for d in study.drawings:
        w.writerow([d.row, d.participant, d.order, d.object, d.condition, "", "",
                    *([""] * n), ""])
    return buf.getvalue().encode("utf-8")


def _preferences_csv(study: Study) -> bytes:
    """One row per participant: the condition they preferred (the last page's answer, in the
    condition's id as ``assignment.csv`` has it) and why, to be filled in by hand."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["participant", "preferred", "why"])
    for participant in study.participants:
        w.writerow([participant, "", ""])
    return buf.getvalue().encode("utf-8")


def make_study(cfg: StudyConfig, results: Sequence, folder: Path) -> StudyBuild:
    """Every file of the study in ``folder``, as bytes (module docstring).

    Args:
        cfg: the study config.
        results: the planned tutorials, one per ``cfg.objects`` entry, in that order.
        folder: the study's output folder (paths in the returned files are under it).

    Raises:
        ConfigError: a drawing sheet margin too small for the code.
    """
    from .render import pdf_bytes, render_png

    for obj in cfg.objects:
        if obj.tutorial.paper.margin_mm < STUDY_MARGIN_MM:
            raise ConfigError(f"{obj.tutorial.path.name}: paper.margin_mm: a study sheet needs "
                              f"{STUDY_MARGIN_MM:g} mm (with_study_margins)")
    books = workbooks(cfg, results, folder)
    plan = assign(cfg.participants, [o.name for o in cfg.objects], cfg.conditions, cfg.design,
                  cfg.first, cfg.seed)
    draft = [Drawing(i, a.participant, a.order, a.object, a.condition,
                     f"{a.object}-{a.condition}", "") for i, a in enumerate(plan)]
    sheets = {wb.key.sheet: wb.key for wb in books.values()}
    font = None if cfg.font is None else (str(cfg.font.regular), str(cfg.font.bold),
                                           str(cfg.font.oblique))
    study = Study(folder, "00000000", cfg.title, cfg.seed, cfg.design, cfg.participants,
                  cfg.conditions, tuple(o.name for o in cfg.objects), tuple(draft), sheets,
                  cfg.language, font)
    study_id = _study_id(study_json(study))
    study = replace(study, study_id=study_id, drawings=tuple(
        replace(d, code=code_text(study_id, d.row)) for d in draft))
    files: list[tuple[Path, bytes]] = []
    for participant in cfg.participants:
        rows = [(i, a) for i, a in enumerate(plan) if a.participant == participant]
        with fonts.using(cfg.font), templates.using(cfg.language):  # the study's own
            pages = packet(cfg, study_id, rows, books)
        files.append((folder / "packets" / f"{participant}.pdf", pdf_bytes(pages)))
    keys = []
    for wb in books.values():
        with fonts.using(wb.pages[-1].font), templates.using(cfg.language):
            keys.append(answer_key(wb.pages[-1], wb.key, _t(
                "key.heading", object=wb.title, view=wb.view, condition=wb.condition,
                named=condition_name(wb.condition)),
                _t("key.bookmark", object=wb.title, condition=wb.condition), cfg.title))
    files.append((folder / "answer-keys.pdf", pdf_bytes(keys)))
    for wb in books.values():
        files.append((wb.key.printed, render_png(_blank(wb.pages[-1]), PX_PER_MM * 25.4)))
    files.append((folder / "assignment.csv", _assignment_csv(study, books)))
    with templates.using(cfg.language):
        files.append((folder / "responses.csv", _responses_csv(study)))
    files.append((folder / "preferences.csv", _preferences_csv(study)))
    from .files import dumps_json
    files.append((folder / "study.json", dumps_json(study_json(study)).encode("utf-8")))
    note = balance_note(len(cfg.participants), len(cfg.objects), len(cfg.conditions),
                        cfg.design)
    return StudyBuild(study, tuple(files), note)


def _blank(sheet: Page) -> Page:
    """The sheet as ``h2s score`` subtracts it: every printed mark, on white (no stamp)."""
    white = Rect(0.0, 0.0, sheet.width_mm, sheet.height_mm, None, 0.0, "white", "paper")
    return replace(sheet, items=(white, *sheet.items), bookmarks=())

