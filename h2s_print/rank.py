"""Ranking a study's drawings by pairwise judgments (issue 14, point 3; How2Sketch §7, Fig. 12).

The paper showed raters two sketches of the same object, each overlaid on (registered to) its
condition's model, and asked which one is more accurate; it fitted a Bradley-Terry model to
the answers and plotted, per condition, each drawing's probability of being judged more
accurate than another.  This module does the same in four stages, each a function over
values, so the command line only reads inputs and writes the bytes and rows they return:

1. :func:`pairs`: every unordered pair of one object's scored drawings, in a seeded random
   order, sides (A on the left, B on the right) balanced, each with a stable id
   (``camera-007``).  :func:`pairs_csv` / :func:`read_pairs` keep them beside the pages, so
   judgments are checked against the pairs the raters really saw even if more scans are
   scored later.
2. :func:`pair_pages_pdf`: one page per pair, the two registered drawings side by side on
   their models' lines, the paper's question and the pair id; nothing on a page names a
   condition or a participant (raters are blind).  :func:`judgments_template` is the CSV
   raters fill in (``pair,object,a,b,winner``; several raters add rows).
3. :func:`read_judgments` / :func:`parse_judgments`: that CSV, checked line by line.
4. :func:`fit`: Bradley-Terry per object (``choix``), giving each drawing a strength and the
   probability of being judged more accurate than a random other drawing of its object;
   :func:`strengths_csv`, :func:`conditions_csv` and :func:`plot_png` present them.

Files in a study folder (the CLI's choice; these names are the defaults it is offered)::

    scores/drawings.csv          read   row,participant,object,condition,sheet,file
    scores/drawings/<row>.png    read   registered drawing, 8-bit grey, 255 = pencil
    rank/pairs.pdf               write  the pair pages
    rank/pairs.csv               write  pair,object,a,b (the pages' pairs, for checking)
    rank/judgments.csv           write  the template raters fill in; read back when filled
    rank/strengths.csv           write  one row per drawing
    rank/conditions.csv          write  mean probability per (object, condition)
    rank/<object>.png            write  the plot of one object

Heavy dependencies (reportlab, OpenCV, cairosvg, choix) are imported inside the functions
that use them.
"""

from __future__ import annotations

import csv
import io
import logging
import math
import textwrap
import zlib
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import escape

import numpy as np

from . import templates
from .studyfile import (
    DRAWINGS_CSV, DRAWINGS_HEADER, SCORES_DIR, STUDY_FILE, SheetKey, Study, StudyError, csv_rows,
    read_text,
)

log = logging.getLogger(__name__)

RANK_DIR = "rank"
SCORED_CSV = f"{SCORES_DIR}/{DRAWINGS_CSV}"
PAIRS_PDF = "pairs.pdf"
PAIRS_CSV = "pairs.csv"
JUDGMENTS_CSV = "judgments.csv"
STRENGTHS_CSV = "strengths.csv"
CONDITIONS_CSV = "conditions.csv"

SCORED_HEADER = DRAWINGS_HEADER
PAIRS_HEADER = ("pair", "object", "a", "b")
JUDGMENTS_HEADER = ("pair", "object", "a", "b", "winner")
STRENGTHS_HEADER = ("object", "rank", "row", "participant", "condition", "strength",
                    "p_better", "wins", "comparisons")
CONDITIONS_HEADER = ("object", "condition", "drawings", "mean_p_better")
#: ``object`` of a :data:`CONDITIONS_HEADER` row summarising a condition over all objects.
ALL_OBJECTS = "*"

#: Default Bradley-Terry regularisation (see :func:`fit`).
ALPHA = 0.01

#: Pair pages: A4 landscape, mm.
PAGE_MM = (297.0, 210.0)
MARGIN_MM = 12.0
GAP_MM = 10.0
#: Resolution of the drawing panels on the page (dots per inch).
PANEL_DPI = 200.0
#: Model lines on a panel: colour (RGB) and width on the page, mm.
MODEL_RGB = (110, 165, 235)
MODEL_WIDTH_MM = 0.45
#: Pencil on a panel: colour (RGB); a registered stroke pixel is drawn at this darkness.
PENCIL_RGB = (45, 45, 45)

#: Condition colours of the plot, in ``study.conditions`` order (Okabe-Ito, colour-blind safe).
PALETTE = ("#0072B2", "#E69F00", "#009E73", "#D55E00", "#CC79A7", "#56B4E9", "#F0E442",
           "#000000")
#: Plot size, px (the PNG is exactly this size).
PLOT_PX = (800, 480)


# ----------------------------------------------------------------------------- values


@dataclass(frozen=True, slots=True)
class ScoredDrawing:
    """One registered drawing listed in ``scores/drawings.csv``.

    Attributes:
        row: the drawing's row in study.json (and the assignment).
        participant, object, condition, sheet: as in study.json (checked).
        file: the registered drawing's PNG (absolute).
    """

    row: int
    participant: str
    object: str
    condition: str
    sheet: str
    file: Path


@dataclass(frozen=True, slots=True)
class Pair:
    """Two drawings of one object shown side by side on one page.

    Attributes:
        id: stable name, ``<object>-<NNN>`` numbered in page order within the object.
        object: the object both drawings show.
        a: row of the drawing on the left (labelled A).
        b: row of the drawing on the right (labelled B).
    """

    id: str
    object: str
    a: int
    b: int


@dataclass(frozen=True, slots=True)
class Judgment:
    """One rater's answer: ``winner`` was judged more accurate than ``loser`` (drawing rows)."""

    pair: str
    object: str
    winner: int
    loser: int
    line: int  #: line of the judgments file, for messages


@dataclass(frozen=True, slots=True)
class Judgments:
    """A checked judgments file.

    Attributes:
        source: the file's name, for messages.
        pairs: the pairs it was checked against (every drawing of every pair is ranked, judged
            or not).
        items: the answers, in file order.
        blank: rows whose winner was left blank (skipped).
    """

    source: str
    pairs: tuple[Pair, ...]
    items: tuple[Judgment, ...]
    blank: int


@dataclass(frozen=True, slots=True)
class DrawingStrength:
    """One drawing's Bradley-Terry result.

    Attributes:
        row, participant, object, condition: which drawing.
        rank: 1 for the object's strongest drawing.
        strength: Bradley-Terry log-strength, centred to mean 0 over the object's drawings; a
            difference d between two drawings means the first is judged more accurate with
            probability 1 / (1 + exp(-d)).
        p_better: probability of being judged more accurate than a random other drawing of the
            object: the mean, over the object's other drawings, of those probabilities (the
            paper's Fig. 12 axis; the object's drawings average 0.5).
        wins, comparisons: judgments it won, and judgments it was in.
    """

    row: int
    participant: str
    object: str
    condition: str
    rank: int
    strength: float
    p_better: float
    wins: int
    comparisons: int


@dataclass(frozen=True, slots=True)
class ConditionSummary:
    """Mean ``p_better`` of one condition's drawings of one object (or of all objects:
    ``object == ALL_OBJECTS``)."""

    object: str
    condition: str
    drawings: int
    mean_p_better: float


@dataclass(frozen=True, slots=True)
class Ranking:
    """The fit of a study's judgments.

    Attributes:
        alpha: the regularisation used.
        objects: the objects ranked (those with at least one judgment), study order.
        conditions: the study's conditions, in order (the plot's colours).
        drawings: per object, strongest first.
        summaries: per object and condition, then per condition over all objects.
        judgments: answers used; blank: rows left blank.
    """

    alpha: float
    objects: tuple[str, ...]
    conditions: tuple[str, ...]
    drawings: tuple[DrawingStrength, ...]
    summaries: tuple[ConditionSummary, ...]
    judgments: int
    blank: int

    def of(self, object: str) -> tuple[DrawingStrength, ...]:
        """The drawings of ``object``, strongest first."""
        return tuple(d for d in self.drawings if d.object == object)


# ----------------------------------------------------------------------------- CSV reading


def _int(value: str, name: str, line: int, field: str) -> int:
    try:
        return int(value)
    except ValueError:
        raise StudyError(f"{name}:{line}: {field}: expected a drawing row number, got "
                         f"{value!r}") from None


def read_scored(study: Study, path: str | Path | None = None) -> tuple[ScoredDrawing, ...]:
    """The registered drawings ``h2s score`` listed (``scores/drawings.csv`` by default),
    each checked against study.json; ``file`` is resolved against the CSV's folder.

    Raises:
        StudyError: missing file, bad header, a row that is not in the study or does not
            match it, a row listed twice (``file:line: field: ...``).
    """
    path = Path(path) if path is not None else study.folder / SCORED_CSV
    name = str(path)
    out: dict[int, ScoredDrawing] = {}
    for line, cells in csv_rows(read_text(path), name, SCORED_HEADER):
        row = _int(cells["row"], name, line, "row")
        if not 0 <= row < len(study.drawings):
            raise StudyError(f"{name}:{line}: row: {row} is not a drawing of this study "
                             f"(0..{len(study.drawings) - 1})")
        if row in out:
            raise StudyError(f"{name}:{line}: row: drawing {row} is listed twice")
        d = study.drawings[row]
        for field in ("participant", "object", "condition", "sheet"):
            if cells[field] != getattr(d, field):
                raise StudyError(f"{name}:{line}: {field}: {cells[field]!r} does not match "
                                 f"study.json ({getattr(d, field)!r} for row {row})")
        if not cells["file"]:
            raise StudyError(f"{name}:{line}: file: missing")
        out[row] = ScoredDrawing(row, d.participant, d.object, d.condition, d.sheet,
                                 (path.parent / cells["file"]).resolve())
    return tuple(out[r] for r in sorted(out))


def _check_image(sheet: SheetKey, image: np.ndarray, where: str) -> None:
    if image.ndim != 2 or image.dtype != np.uint8:
        raise StudyError(f"{where}: expected an 8-bit greyscale image, got "
                         f"{image.dtype} of shape {image.shape}")
    # the scorer rounds the sheet's size to whole pixels; allow either rounding
    want = (sheet.paper_mm[1] * sheet.px_per_mm, sheet.paper_mm[0] * sheet.px_per_mm)
    if any(abs(n - w) > 1.0 for n, w in zip(image.shape, want)):
        raise StudyError(f"{where}: {image.shape[1]} x {image.shape[0]} px is not sheet "
                         f"{sheet.sheet!r} at {sheet.px_per_mm:g} px/mm "
                         f"({want[1]:.0f} x {want[0]:.0f} px)")


def read_images(study: Study, drawings: Iterable[ScoredDrawing]) -> dict[int, np.ndarray]:
    """Row -> registered drawing (read-only ``(h, w)`` uint8, 255 = pencil), checked to be
    greyscale and the size of its sheet.

    Raises:
        StudyError: a file that is missing, unreadable, not greyscale or the wrong size.
    """
    import cv2

    out = {}
    for d in drawings:
        if not d.file.is_file():
            raise StudyError(f"{d.file}: no such file (registered drawing of row {d.row})")
        image = cv2.imread(str(d.file), cv2.IMREAD_UNCHANGED)
        if image is None:
            raise StudyError(f"{d.file}: cannot be read as an image")
        _check_image(study.sheets[d.sheet], image, str(d.file))
        image.setflags(write=False)
        out[d.row] = image
    return out


# ----------------------------------------------------------------------------- 1. pairs


def balanced_sides(n: int) -> list[tuple[int, int]]:
    """Every unordered pair of ``0..n-1`` once, as ``(left, right)``, so that each item is on
    the left and on the right equally often when ``n`` is odd (``(n-1)/2`` times each), and
    once more on one side than the other when ``n`` is even (it is in ``n-1`` pairs, an odd
    number: no better is possible).

    Method: a regular tournament on the odd number ``m`` (``n`` or ``n-1``) of items: item i
    is on the left against i+1 .. i+(m-1)/2 (mod m).  For even ``n`` the last item is then on
    the left against the even items of ``0..m-1`` and on the right against the odd ones.
    """
    if n < 2:
        return []
    m = n if n % 2 else n - 1
    out = [(i, (i + d) % m) for i in range(m) for d in range(1, (m - 1) // 2 + 1)]
    if n % 2 == 0:
        last = n - 1
        out += [(last, i) if i % 2 == 0 else (i, last) for i in range(m)]
    return out


def _rng(seed: int, object: str) -> np.random.Generator:
    # one stream per object: adding or removing an object does not reshuffle the others
    return np.random.default_rng([seed % 2**63, zlib.crc32(object.encode("utf-8"))])


def pairs(study: Study, drawings: Iterable[ScoredDrawing | int], seed: int) -> tuple[Pair, ...]:
    """The pairs to judge: per object, every unordered pair of its scored drawings once.

    Objects come in ``study.objects`` order; within an object the pairs are in a random order
    drawn from ``seed`` (and the object's name), and the drawings are placed on the sides by
    :func:`balanced_sides` after a random relabelling, so which drawing is on the left is
    random but every drawing is on each side equally often (within one).  Pair ids are
    ``<object>-<NNN>``, numbered from 001 in page order within the object: the same study,
    drawings and seed always give the same pairs and ids.  An object with fewer than two
    scored drawings has no pairs.

    Args:
        study: the study (for each drawing's object).
        drawings: the scored drawings, or their rows.
        seed: the shuffle's seed (the CLI passes the study's seed unless told otherwise).

    Raises:
        StudyError: a row that is not in the study or is given twice, or no pair at all.
    """
    rows: list[int] = []
    for d in drawings:
        row = d.row if isinstance(d, ScoredDrawing) else int(d)
        if not 0 <= row < len(study.drawings):
            raise StudyError(f"{study.folder / STUDY_FILE}: no drawing row {row}")
        if row in rows:
            raise StudyError(f"drawing row {row} is listed twice")
        rows.append(row)
    out: list[Pair] = []
    for obj in study.objects:
        mine = sorted(r for r in rows if study.drawings[r].object == obj)
        if len(mine) < 2:
            if mine:
                log.warning("%s: only one scored drawing, nothing to compare it with", obj)
            continue
        rng = _rng(seed, obj)
        label = [mine[i] for i in rng.permutation(len(mine))]
        sides = balanced_sides(len(mine))
        order = rng.permutation(len(sides))
        width = max(3, len(str(len(sides))))
        for k, i in enumerate(order, start=1):
            a, b = sides[i]
            out.append(Pair(f"{obj}-{k:0{width}d}", obj, label[a], label[b]))
    if not out:
        raise StudyError(f"{study.folder}: no object has two scored drawings to compare "
                         f"(score more sheets with 'h2s score')")
    return tuple(out)


def pairs_csv(pairs: Sequence[Pair]) -> str:
    """``pairs.csv``: ``pair,object,a,b``, one row per pair in page order."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(PAIRS_HEADER)
    w.writerows((p.id, p.object, p.a, p.b) for p in pairs)
    return buf.getvalue()


def parse_pairs(text: str, study: Study, name: str = PAIRS_CSV) -> tuple[Pair, ...]:
    """Pairs from the text of a ``pairs.csv`` (:func:`pairs_csv`), checked against ``study``.

    Raises:
        StudyError: ``name:line: field: ...`` for a bad header, a repeated pair id, a row not
            in the study, a drawing of another object, or a pair of one drawing with itself.
    """
    out: dict[str, Pair] = {}
    for line, cells in csv_rows(text, name, PAIRS_HEADER):
        pid = cells["pair"]
        if not pid:
            raise StudyError(f"{name}:{line}: pair: missing")
        if pid in out:
            raise StudyError(f"{name}:{line}: pair: {pid!r} is listed twice")
        ab = []
        for field in ("a", "b"):
            row = _int(cells[field], name, line, field)
            if not 0 <= row < len(study.drawings):
                raise StudyError(f"{name}:{line}: {field}: {row} is not a drawing of this study")
            if study.drawings[row].object != cells["object"]:
                raise StudyError(f"{name}:{line}: {field}: drawing {row} is of "
                                 f"{study.drawings[row].object!r}, not {cells['object']!r}")
            ab.append(row)
        if ab[0] == ab[1]:
            raise StudyError(f"{name}:{line}: b: a drawing cannot be compared with itself")
        out[pid] = Pair(pid, cells["object"], ab[0], ab[1])
    return tuple(out.values())


def read_pairs(path: str | Path, study: Study) -> tuple[Pair, ...]:
    """The pairs in the ``pairs.csv`` at ``path`` (see :func:`parse_pairs`)."""
    return parse_pairs(read_text(Path(path)), study, str(path))


# ----------------------------------------------------------------------------- 2. pages


def _object_scale(study: Study, obj: str, box_mm: tuple[float, float]) -> float:
    """Page mm per sheet mm for ``obj``'s panels: its largest frame fits the panel box.
    One scale per object, so both sides of a pair (and every page of the object) show the
    drawings at the same size."""
    frames = [k.frame_mm for k in study.sheets.values() if k.object == obj]
    fw = max(f[2] - f[0] for f in frames)
    fh = max(f[3] - f[1] for f in frames)
    return min(box_mm[0] / fw, box_mm[1] / fh)


def panel_image(sheet: SheetKey, image: np.ndarray, px_per_mm: float) -> np.ndarray:
    """One drawing as shown on a pair page: its sheet's frame, model lines in blue under the
    pencil in dark grey, resampled to ``px_per_mm`` pixels per sheet millimetre.

    Args:
        sheet: the drawing's sheet (frame and model lines, sheet mm, y up).
        image: the registered drawing, ``(h, w)`` uint8, 255 = pencil, at ``sheet.px_per_mm``.
        px_per_mm: output pixels per sheet mm.

    Returns:
        ``(rows, cols, 3)`` uint8 RGB, the frame only; row 0 at the frame's top.
    """
    import cv2

    x0, y0, x1, y1 = sheet.frame_mm
    h_mm = sheet.paper_mm[1]
    s = sheet.px_per_mm
    k = px_per_mm
    out_w = max(1, round((x1 - x0) * k))
    out_h = max(1, round((y1 - y0) * k))
    # Output pixel (R, C) shows sheet point x = x0 + (C + .5) / k, y = y1 - (R + .5) / k;
    # in the registered image that is pixel c = x s - .5, r = (h - y) s - .5 (the contract).
    c0 = max(0, math.floor(x0 * s) - 2)
    c1 = min(image.shape[1], math.ceil(x1 * s) + 2)
    r0 = max(0, math.floor((h_mm - y1) * s) - 2)
    r1 = min(image.shape[0], math.ceil((h_mm - y0) * s) + 2)
    crop = image[r0:r1, c0:c1].astype(np.float32) / 255.0
    sx = sy = 1.0
    if s > k and crop.size:
        # shrinking: area-average first, so thin strokes fade to grey instead of vanishing
        # between samples; resized pixel c' is centred on crop pixel (c' + .5) sx - .5
        size = (max(1, round(crop.shape[1] * k / s)), max(1, round(crop.shape[0] * k / s)))
        sx, sy = crop.shape[1] / size[0], crop.shape[0] / size[1]
        crop = cv2.resize(crop, size, interpolation=cv2.INTER_AREA)
    # output pixel -> crop (resized) pixel, for warpAffine's inverse map
    to_src = np.array([[s / (sx * k), 0.0, ((x0 + 0.5 / k) * s - c0) / sx - 0.5],
                       [0.0, s / (sy * k), ((h_mm - y1 + 0.5 / k) * s - r0) / sy - 0.5]])
    if crop.size:
        pencil = cv2.warpAffine(crop, to_src, (out_w, out_h),
                                flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                                borderMode=cv2.BORDER_CONSTANT, borderValue=0.0)
    else:
        pencil = np.zeros((out_h, out_w), np.float32)
    # a stroke thinned by resampling is still drawn dark: strengthen faint pixels
    alpha = np.clip(pencil * 1.8, 0.0, 1.0)[..., None]
    rgb = np.full((out_h, out_w, 3), 255, np.uint8)
    bits = 4  # cv2 fixed-point sub-pixel coordinates
    width_px = max(1, round(MODEL_WIDTH_MM * PANEL_DPI / 25.4))
    polys = []
    for _, lines in sheet.lines:
        for line in lines:
            if len(line) < 2:
                continue
            pts = np.array([((x - x0) * px_per_mm - 0.5, (y1 - y) * px_per_mm - 0.5)
                            for x, y in line])
            polys.append(np.round(pts * (1 << bits)).astype(np.int32))
    if polys:
        cv2.polylines(rgb, polys, False, MODEL_RGB, width_px, cv2.LINE_AA, bits)
    out = rgb.astype(np.float32) * (1.0 - alpha) + np.array(PENCIL_RGB, np.float32) * alpha
    return np.round(out).astype(np.uint8)


def pair_pages_pdf(study: Study, pairs: Sequence[Pair],
                   images: Mapping[int, np.ndarray]) -> bytes:
    """The pair pages: one A4 landscape page per pair, in ``pairs`` order.

    Each page has the pair id, the paper's question, the two drawings side by side labelled
    A (``pair.a``) and B (``pair.b``), each cropped to its sheet's frame and overlaid on its
    own sheet's model lines (the condition's finished drawing, so each sketch is compared
    with the model it was drawn from), both at one scale per object, and a line telling the
    rater where to write the answer.  No text names a condition, a participant or an order.
    Drawings are raster panels (:func:`panel_image`, :data:`PANEL_DPI`); reportlab stores
    each drawing's panel once however many pages show it.  Deterministic bytes
    (``invariant=1``).

    Args:
        study: the study (sheets: frames and model lines).
        pairs: from :func:`pairs` or :func:`read_pairs`.
        images: row -> registered drawing (:func:`read_images`).

    Raises:
        StudyError: no pairs, or a pair whose drawing has no (or a wrong-sized) image.
    """
    from PIL import Image
    from reportlab.lib.utils import ImageReader, simpleSplit
    from reportlab.pdfgen import canvas

    if not pairs:
        raise StudyError("no pairs to print")
    T = templates.load("rank")["pages"]
    pt = 72.0 / 25.4
    W, H = PAGE_MM
    M = MARGIN_MM
    from . import fonts

    spec = fonts.current()  # the study's language needs its script: the page font, embedded
    regular, bold = fonts.face(spec.regular).key, fonts.face(spec.bold).key
    question = simpleSplit(T["question"], regular, 12, (W - 2 * M) * pt)
    q_top = H - M - 15.0
    panel_top = q_top - 5.5 * len(question) - 9.0
    panel_bottom = M + 15.0
    box = ((W - 2 * M - GAP_MM) / 2.0, panel_top - panel_bottom)

    readers: dict[int, tuple[ImageReader, float, float]] = {}

    def panel(row: int, scale: float) -> tuple[ImageReader, float, float]:
        if row not in readers:
            d = study.drawings[row]
            sheet = study.sheets[d.sheet]
            if row not in images:
                raise StudyError(f"no registered drawing for row {row} ({d.object}) "
                                 f"among the scored drawings")
            _check_image(sheet, images[row], f"registered drawing of row {row}")
            rgb = panel_image(sheet, images[row], scale * PANEL_DPI / 25.4)
            fw, fh = sheet.frame_mm[2] - sheet.frame_mm[0], sheet.frame_mm[3] - sheet.frame_mm[1]
            readers[row] = (ImageReader(Image.fromarray(rgb, "RGB")), fw * scale, fh * scale)
        return readers[row]

    buf = io.BytesIO()
    c = canvas.Canvas(buf, pagesize=(W * pt, H * pt), invariant=1, pageCompression=1)
    c.setTitle(T["title"])
    c.setCreator("h2s-print")
    c.setProducer("h2s-print")
    c.setAuthor("")
    c.setSubject("")
    scales = {obj: _object_scale(study, obj, box) for obj in {p.object for p in pairs}}
    for n, p in enumerate(pairs, start=1):
        c.setFillColorRGB(0, 0, 0)
        c.setFont(bold, 18)
        c.drawString(M * pt, (H - M - 6.0) * pt, T["heading"].format(pair=p.id))
        c.setFont(regular, 12)
        for i, text in enumerate(question):
            c.drawString(M * pt, (q_top - 5.5 * i) * pt, text)
        for side, row, left in (("side_a", p.a, M), ("side_b", p.b, M + box[0] + GAP_MM)):
            reader, w_mm, h_mm = panel(row, scales[p.object])
            x = left + (box[0] - w_mm) / 2.0
            y = panel_top - h_mm
            c.drawImage(reader, x * pt, y * pt, w_mm * pt, h_mm * pt)
            c.setStrokeColorRGB(0.6, 0.6, 0.6)
            c.setLineWidth(0.5)
            c.rect(x * pt, y * pt, w_mm * pt, h_mm * pt, stroke=1, fill=0)
            c.setFillColorRGB(0, 0, 0)
            c.setFont(bold, 16)
            c.drawString(x * pt, (panel_top + 2.0) * pt, T[side])
        c.setFont(regular, 9)
        c.setFillColorRGB(0.3, 0.3, 0.3)
        c.drawString(M * pt, (M + 6.0) * pt, T["legend"])
        c.drawString(M * pt, (M + 1.5) * pt, T["answer"].format(pair=p.id))
        c.drawRightString((W - M) * pt, (M + 1.5) * pt,
                          T["footer"].format(pair=p.id, index=n, count=len(pairs)))
        c.showPage()
    c.save()
    return buf.getvalue()


def judgments_template(pairs: Sequence[Pair]) -> str:
    """The CSV raters fill in: ``pair,object,a,b,winner``, one row per pair in page order,
    ``winner`` blank (write ``a`` or ``b``).  Several raters: each fills a copy, and the
    copies' rows are put in one file (any number of rows per pair; rows left blank are
    skipped)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(JUDGMENTS_HEADER)
    w.writerows((p.id, p.object, p.a, p.b, "") for p in pairs)
    return buf.getvalue()


# ----------------------------------------------------------------------------- 3. judgments


def parse_judgments(text: str, pairs: Sequence[Pair], name: str = JUDGMENTS_CSV) -> Judgments:
    """The judgments in the text of a filled :func:`judgments_template`, checked line by line.

    A row's ``object``, ``a`` and ``b`` must be those of its pair (a row copied from another
    study's sheet, or a/b swapped by hand, would otherwise credit the wrong drawing); its
    ``winner`` is ``a``, ``b`` (either case) or blank.  Blank lines are ignored; rows with a
    blank winner are skipped and counted.

    Raises:
        StudyError: ``name:line: field: ...``: header, unknown pair, a row that does not match
            its pair, a winner that is not a, b or blank.
    """
    by_id = {p.id: p for p in pairs}
    items: list[Judgment] = []
    blank = 0
    for line, cells in csv_rows(text, name, JUDGMENTS_HEADER):
        p = by_id.get(cells["pair"])
        if p is None:
            raise StudyError(f"{name}:{line}: pair: {cells['pair']!r} is not one of the "
                             f"{len(by_id)} pairs printed")
        if cells["object"] != p.object:
            raise StudyError(f"{name}:{line}: object: {cells['object']!r} is not pair "
                             f"{p.id}'s ({p.object!r})")
        for field, want in (("a", p.a), ("b", p.b)):
            if _int(cells[field], name, line, field) != want:
                raise StudyError(f"{name}:{line}: {field}: expected {want} for pair {p.id}, "
                                 f"got {cells[field]!r}")
        winner = cells["winner"].lower()
        if winner == "":
            blank += 1
        elif winner in ("a", "b"):
            w, lo = (p.a, p.b) if winner == "a" else (p.b, p.a)
            items.append(Judgment(p.id, p.object, w, lo, line))
        else:
            raise StudyError(f"{name}:{line}: winner: expected a, b or blank, got "
                             f"{cells['winner']!r}")
    return Judgments(name, tuple(pairs), tuple(items), blank)


def read_judgments(path: str | Path, pairs: Sequence[Pair]) -> Judgments:
    """The judgments file at ``path`` (UTF-8, with or without a byte-order mark), checked
    against ``pairs`` (see :func:`parse_judgments`)."""
    return parse_judgments(read_text(Path(path)), pairs, str(path))


# ----------------------------------------------------------------------------- 4. fit


def win_probability(strength_i: float, strength_j: float) -> float:
    """Bradley-Terry probability that drawing i is judged better than drawing j."""
    return 1.0 / (1.0 + math.exp(strength_j - strength_i))


def fit(judgments: Judgments, study: Study, alpha: float = ALPHA) -> Ranking:
    """Bradley-Terry strengths per object, and per-condition summaries.

    Model: drawing i is judged more accurate than drawing j with probability
    ``1 / (1 + exp(s_j - s_i))``.  Each object is fitted on its own (drawings of different
    objects are never compared), by ``choix.ilsr_pairwise`` (iterative Luce spectral
    ranking: the maximum-likelihood strengths when ``alpha`` is 0).  Every drawing in
    ``judgments.pairs`` is ranked, judged or not.

    Regularisation: ``alpha`` is added to every transition rate of I-LSR's Markov chain
    (choix's regularisation).  Without it, a drawing that won (or lost) every comparison has
    no finite maximum-likelihood strength, and drawings whose judged pairs fall into separate
    groups cannot be placed against each other; with it the fit always exists.  Its effect
    is small: with two drawings it acts like about ``2 * alpha`` extra wins for each (at the
    default 0.01, 3 wins of 4 give p = 0.7475 instead of 0.75, and 4 of 4 give 0.995 instead
    of 1).  Use ``alpha=0`` only when every drawing both won and lost.

    Strengths are centred to mean 0 per object.  ``p_better`` of a drawing is the mean of its
    win probabilities against the object's other drawings (How2Sketch Fig. 12's axis): 0.5
    is average; the object's drawings average exactly 0.5, so a condition's mean above 0.5
    means its drawings were judged more accurate than the others'.

    Args:
        judgments: from :func:`read_judgments`.
        study: for each drawing's participant and condition.
        alpha: regularisation, >= 0 (default :data:`ALPHA`).

    Raises:
        StudyError: no judgments at all, or a fit that does not converge (alpha 0 with a
            drawing that won or lost everything).
        ValueError: a negative alpha.
    """
    import choix

    if not alpha >= 0:
        raise ValueError(f"alpha must be >= 0, got {alpha}")
    if not judgments.items:
        raise StudyError(f"{judgments.source}: no judgments (every winner is blank)")
    drawings: list[DrawingStrength] = []
    objects = []
    for obj in dict.fromkeys([*study.objects, *(p.object for p in judgments.pairs)]):
        rows = sorted({r for p in judgments.pairs if p.object == obj for r in (p.a, p.b)})
        data = [(j.winner, j.loser) for j in judgments.items if j.object == obj]
        if not rows:
            continue
        if not data:
            log.warning("%s: no judgments, not ranked", obj)
            continue
        index = {r: i for i, r in enumerate(rows)}
        try:
            with np.errstate(all="ignore"):
                params = choix.ilsr_pairwise(len(rows), [(index[w], index[lo]) for w, lo in data],
                                             alpha=alpha, max_iter=10_000)
        except (RuntimeError, ValueError, np.linalg.LinAlgError) as exc:
            raise StudyError(f"{judgments.source}: the Bradley-Terry fit of {obj!r} failed "
                             f"({exc}); use a regularisation alpha > 0") from None
        s = np.asarray(params, float)
        if not np.all(np.isfinite(s)):
            raise StudyError(f"{judgments.source}: the Bradley-Terry fit of {obj!r} diverged "
                             f"(a drawing won or lost every comparison); use alpha > 0")
        s = s - s.mean()
        # P[i, j] = probability that i is judged better than j
        prob = 1.0 / (1.0 + np.exp(s[None, :] - s[:, None]))
        n = len(rows)
        p_better = (prob.sum(axis=1) - 0.5) / (n - 1)  # without the diagonal's 0.5
        wins = {r: 0 for r in rows}
        seen = {r: 0 for r in rows}
        for w, lo in data:
            wins[w] += 1
            seen[w] += 1
            seen[lo] += 1
        ordered = sorted(range(n), key=lambda i: (-s[i], rows[i]))
        for rank, i in enumerate(ordered, start=1):
            d = study.drawings[rows[i]]
            drawings.append(DrawingStrength(rows[i], d.participant, obj, d.condition, rank,
                                            float(s[i]), float(p_better[i]),
                                            wins[rows[i]], seen[rows[i]]))
        objects.append(obj)
    conditions = tuple(dict.fromkeys([*study.conditions, *(d.condition for d in drawings)]))
    summaries = []
    for obj in [*objects, ALL_OBJECTS]:
        for cond in conditions:
            ps = [d.p_better for d in drawings
                  if d.condition == cond and (obj == ALL_OBJECTS or d.object == obj)]
            if ps:
                summaries.append(ConditionSummary(obj, cond, len(ps), float(np.mean(ps))))
    return Ranking(alpha, tuple(objects), conditions, tuple(drawings), tuple(summaries),
                   len(judgments.items), judgments.blank)


# ----------------------------------------------------------------------------- outputs


def _num(x: float) -> str:
    text = f"{x:.4f}"
    return "0.0000" if text == "-0.0000" else text


def strength_rows(ranking: Ranking) -> list[dict[str, object]]:
    """``strengths.csv``'s rows as dicts (:data:`STRENGTHS_HEADER` keys)."""
    return [{"object": d.object, "rank": d.rank, "row": d.row, "participant": d.participant,
             "condition": d.condition, "strength": _num(d.strength),
             "p_better": _num(d.p_better), "wins": d.wins, "comparisons": d.comparisons}
            for d in ranking.drawings]


def strengths_csv(ranking: Ranking) -> str:
    """``strengths.csv``: one row per drawing (:data:`STRENGTHS_HEADER`), per object strongest
    first; ``strength`` and ``p_better`` as in :class:`DrawingStrength`, 4 decimals."""
    buf = io.StringIO()
    w = csv.DictWriter(buf, STRENGTHS_HEADER, lineterminator="\n")
    w.writeheader()
    w.writerows(strength_rows(ranking))
    return buf.getvalue()


def conditions_csv(ranking: Ranking) -> str:
    """``conditions.csv``: mean ``p_better`` per (object, condition), then per condition over
    all objects (``object`` = ``*``)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(CONDITIONS_HEADER)
    w.writerows((s.object, s.condition, s.drawings, _num(s.mean_p_better))
                for s in ranking.summaries)
    return buf.getvalue()


def plot_svg(ranking: Ranking, object: str) -> str:
    """The plot of one object as SVG text (:data:`PLOT_PX` user units).

    A histogram of ``p_better`` over 0..1 in bins of 0.1, as the paper's Fig. 12, drawn with
    one square per drawing stacked in its bin and coloured by condition (so a bin shows how
    many drawings of each condition fell there); below the axis a tick per drawing at its
    exact value; a dashed vertical line at each condition's mean, and a legend naming each
    condition with that mean.

    Raises:
        KeyError: ``object`` was not ranked.
    """
    if object not in ranking.objects:
        raise KeyError(f"{object!r} was not ranked")
    T = templates.load("rank")["plot"]
    mine = ranking.of(object)
    colour = {c: PALETTE[i % len(PALETTE)] for i, c in enumerate(ranking.conditions)}
    present = [c for c in ranking.conditions if any(d.condition == c for d in mine)]
    means = {s.condition: s.mean_p_better for s in ranking.summaries if s.object == object}
    W, H = PLOT_PX
    left, right, top, bottom = 70.0, 30.0, 56.0, 150.0
    pw, ph = W - left - right, H - top - bottom
    bins = [[] for _ in range(10)]
    order = {c: i for i, c in enumerate(ranking.conditions)}
    for d in sorted(mine, key=lambda d: (order[d.condition], d.p_better, d.row)):
        bins[min(9, int(d.p_better * 10.0))].append(d)
    tallest = max(len(b) for b in bins)
    y_max = max(4, tallest)
    bw = pw / 10.0
    unit = ph / y_max

    def fx(p: float) -> float:
        return left + p * pw

    def fy(count: float) -> float:
        return top + ph - count * unit

    from . import fonts

    family = fonts.face(fonts.current().regular).family.replace("'", "")
    out = [(f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" '
            f'viewBox="0 0 {W} {H}" font-family="\'{escape(family)}\', sans-serif">'),
           f'<rect x="0" y="0" width="{W}" height="{H}" fill="#ffffff"/>',
           (f'<text x="{W / 2:.1f}" y="30" font-size="18" font-weight="bold" '
            f'text-anchor="middle">{escape(T["title"].format(object=object))}</text>')]
    # grid and y axis (whole numbers of drawings)
    step = max(1, math.ceil(y_max / 8))
    for k in range(0, y_max + 1, step):
        y = fy(k)
        out.append(f'<line x1="{left:.1f}" y1="{y:.1f}" x2="{left + pw:.1f}" y2="{y:.1f}" '
                   f'stroke="#e4e4e4" stroke-width="1"/>')
        out.append(f'<text x="{left - 8:.1f}" y="{y + 4:.1f}" font-size="12" '
                   f'text-anchor="end">{k}</text>')
    out.append(f'<text x="18" y="{top + ph / 2:.1f}" font-size="13" text-anchor="middle" '
               f'transform="rotate(-90 18 {top + ph / 2:.1f})">{escape(T["axis_y"])}</text>')
    # the squares
    for i, b in enumerate(bins):
        size = min(bw * 0.8, unit)
        for k, d in enumerate(b):
            x = fx(i / 10.0) + (bw - size) / 2.0
            y = fy(k + 1) + (unit - size)
            out.append(f'<rect x="{x:.2f}" y="{y:.2f}" width="{size:.2f}" height="{size:.2f}" '
                       f'fill="{colour[d.condition]}" stroke="#ffffff" stroke-width="1.5"/>')
    # x axis, ticks every 0.1, and a tick per drawing below it
    base = top + ph
    out.append(f'<line x1="{left:.1f}" y1="{base:.1f}" x2="{left + pw:.1f}" y2="{base:.1f}" '
               f'stroke="#000000" stroke-width="1.2"/>')
    for k in range(11):
        x = fx(k / 10.0)
        label = "0" if k == 0 else "1" if k == 10 else f"0.{k}"
        out.append(f'<line x1="{x:.1f}" y1="{base:.1f}" x2="{x:.1f}" y2="{base + 5:.1f}" '
                   f'stroke="#000000" stroke-width="1"/>')
        out.append(f'<text x="{x:.1f}" y="{base + 34:.1f}" font-size="12" '
                   f'text-anchor="middle">{label}</text>')
    for d in mine:
        x = fx(d.p_better)
        out.append(f'<line x1="{x:.2f}" y1="{base + 7:.1f}" x2="{x:.2f}" y2="{base + 19:.1f}" '
                   f'stroke="{colour[d.condition]}" stroke-width="2"/>')
    for c in present:
        x = fx(means[c])
        out.append(f'<line x1="{x:.2f}" y1="{top:.1f}" x2="{x:.2f}" y2="{base:.1f}" '
                   f'stroke="{colour[c]}" stroke-width="2" stroke-dasharray="6 4"/>')
    out.append(f'<text x="{left + pw / 2:.1f}" y="{base + 56:.1f}" font-size="13" '
               f'text-anchor="middle">{escape(T["axis_x"])}</text>')
    # legend: one entry per condition, in a row
    x = left
    y = base + 84
    for c in present:
        label = escape(T["legend"].format(condition=c, mean=f"{means[c]:.2f}"))
        out.append(f'<rect x="{x:.1f}" y="{y - 11:.1f}" width="14" height="14" '
                   f'fill="{colour[c]}"/>')
        out.append(f'<text x="{x + 20:.1f}" y="{y + 1:.1f}" font-size="13">{label}</text>')
        x += 40 + 7.5 * len(label)
    n = sum(d.wins for d in mine)
    # about 6 px a character at 11 px: wrap the note to the plot's width
    note = textwrap.wrap(T["note"].format(n=n), width=int((W - left - 10) / 6.0))
    for i, text in enumerate(note):
        out.append(f'<text x="{left:.1f}" y="{base + 112 + 15 * i:.1f}" font-size="11" '
                   f'fill="#555555">{escape(text)}</text>')
    out.append("</svg>")
    return "\n".join(out) + "\n"


def plot_png(ranking: Ranking, object: str) -> bytes:
    """:func:`plot_svg` rasterised by cairosvg: a :data:`PLOT_PX` PNG (same bytes each run)."""
    import cairosvg

    from . import fonts

    for style in fonts.STYLES:  # cairo draws in the page font's own files
        fonts.fontconfig_add(fonts.current().path(style))
    return cairosvg.svg2png(bytestring=plot_svg(ranking, object).encode("utf-8"),
                            output_width=PLOT_PX[0], output_height=PLOT_PX[1])


def plot_file(object: str) -> str:
    """The plot's file name for ``object`` (in :data:`RANK_DIR`)."""
    return f"{object}.png"
