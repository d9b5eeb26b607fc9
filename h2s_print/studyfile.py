"""A study folder's ``study.json``: what ``h2s score`` and ``h2s rank`` need to know about the
sheets ``h2s study`` printed (issue 14).

``h2s study`` writes it; the other two only read it, and check it field by field when they
do, so a hand-edited or foreign file is a clear :class:`StudyError`, never a crash.

Coordinates are sheet millimetres with the origin at the sheet's bottom-left corner, y up
(as ``*_mm`` in plan.json, DESIGN.md §3).  Images (the printed-mark masks) are rows from the
top: pixel ``(row, col)`` covers sheet point ``x = (col + 0.5) / px_per_mm``,
``y = height_mm - (row + 0.5) / px_per_mm``.

Layout of ``study.json`` (``schema: h2s-study/1``)::

    {"schema": "h2s-study/1", "study_id": "1A2B3C4D", "title": str, "seed": int,
     "design": "fixed-first|latin-square", "participants": [str],
     "conditions": [str], "objects": [str],
     "drawings": [{"row": int, "participant": str, "order": int, "object": str,
                   "condition": str, "sheet": str, "code": "H2S:1A2B3C4D:7"}],
     "sheets": {sheet: {"object": str, "view": str, "condition": str,
                        "paper_mm": [w, h], "frame_mm": [x0, y0, x1, y1],
                        "marks_mm": [[x, y] x 4], "mark_radius_mm": float,
                        "code_box_mm": [x0, y0, x1, y1],
                        "printed": "sheets/<sheet>.png", "px_per_mm": float,
                        "lines": {part: [[[x, y], ...], ...]}}},
     "language": "en", "font": null | [regular, bold, oblique]}

``drawings[i].row == i``; ``code`` is what the sheet's QR code says (:func:`code_text`).
``sheets[s].printed`` is the blank sheet (every printed mark, no stamp) rendered at
``px_per_mm``, relative to the folder of study.json; ``lines`` is the finished drawing of that
(object, condition) on the sheet: each part's contour polylines.
"""

from __future__ import annotations

import csv
import io
import json
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .errors import H2SError

SCHEMA = "h2s-study/1"
STUDY_FILE = "study.json"
#: ``h2s score``'s folder inside a study folder, its list of registered drawings and columns.
SCORES_DIR = "scores"
DRAWINGS_CSV = "drawings.csv"
DRAWINGS_HEADER = ("row", "participant", "object", "condition", "sheet", "file")
CODE_PREFIX = "H2S"
DESIGNS = ("fixed-first", "latin-square")

Pt = tuple[float, float]
Box = tuple[float, float, float, float]


class StudyError(H2SError):
    """A study folder, scan or judgments file the user can fix (exit status 2)."""


@dataclass(frozen=True, slots=True)
class SheetKey:
    """One kind of printed drawing sheet: an (object, view, condition).

    Attributes:
        sheet: its name in study.json (``<object>-<condition>``).
        object, view, condition: what it is for.
        paper_mm: sheet width and height, mm.
        frame_mm: the drawing frame (x0, y0, x1, y1); strokes are looked for inside it.
        marks_mm: the four registration mark centres, bottom-left, bottom-right, top-right,
            top-left.
        mark_radius_mm: their circles' radius.
        code_box_mm: where the QR code's symbol (without its quiet zone) is printed.
        printed: path of the blank sheet's image (absolute once read).
        px_per_mm: that image's resolution.
        lines: per part (in drawing order), its polylines of the finished drawing, mm.
    """

    sheet: str
    object: str
    view: str
    condition: str
    paper_mm: Pt
    frame_mm: Box
    marks_mm: tuple[Pt, Pt, Pt, Pt]
    mark_radius_mm: float
    code_box_mm: Box
    printed: Path
    px_per_mm: float
    lines: tuple[tuple[str, tuple[tuple[Pt, ...], ...]], ...]


@dataclass(frozen=True, slots=True)
class Drawing:
    """One drawing a participant makes: row ``row`` of the assignment."""

    row: int
    participant: str
    order: int
    object: str
    condition: str
    sheet: str
    code: str


@dataclass(frozen=True, slots=True)
class Study:
    """A study folder's contents (study.json)."""

    folder: Path
    study_id: str
    title: str
    seed: int
    design: str
    participants: tuple[str, ...]
    conditions: tuple[str, ...]
    objects: tuple[str, ...]
    drawings: tuple[Drawing, ...]
    sheets: dict[str, SheetKey]
    language: str = "en"  #: the wording of the study's own pages (``h2s rank``'s too)
    font: tuple[str, str, str] | None = None  #: its font files (regular, bold, oblique)


def code_text(study_id: str, row: int) -> str:
    """The text of a sheet's QR code: ``H2S:<study id>:<row>`` (QR alphanumeric mode, so a
    version 1 symbol holds it)."""
    return f"{CODE_PREFIX}:{study_id}:{row}"


def parse_code(text: str) -> tuple[str, int] | None:
    """``(study id, row)`` of a code's text, or ``None`` when it is not an h2s sheet code."""
    m = re.fullmatch(rf"{CODE_PREFIX}:([0-9A-F]{{8}}):(\d{{1,6}})", text.strip())
    return (m.group(1), int(m.group(2))) if m else None


# ----------------------------------------------------------------------------- writing


def study_json(study: Study) -> dict[str, Any]:
    """``study`` as the plain data of study.json (paths relative to ``study.folder``)."""
    sheets = {}
    for name, k in study.sheets.items():
        try:
            printed = k.printed.relative_to(study.folder).as_posix()
        except ValueError:
            printed = k.printed.as_posix()
        sheets[name] = {
            "object": k.object, "view": k.view, "condition": k.condition,
            "paper_mm": list(k.paper_mm), "frame_mm": list(k.frame_mm),
            "marks_mm": [list(p) for p in k.marks_mm], "mark_radius_mm": k.mark_radius_mm,
            "code_box_mm": list(k.code_box_mm), "printed": printed,
            "px_per_mm": k.px_per_mm,
            "lines": {part: [[[round(x, 3), round(y, 3)] for x, y in line] for line in lines]
                      for part, lines in k.lines},
        }
    return {
        "schema": SCHEMA, "study_id": study.study_id, "title": study.title, "seed": study.seed,
        "design": study.design, "participants": list(study.participants),
        "conditions": list(study.conditions), "objects": list(study.objects),
        "drawings": [{"row": d.row, "participant": d.participant, "order": d.order,
                      "object": d.object, "condition": d.condition, "sheet": d.sheet,
                      "code": d.code} for d in study.drawings],
        "sheets": sheets,
        "language": study.language,
        "font": list(study.font) if study.font else None,
    }


# ----------------------------------------------------------------------------- reading


def csv_rows(text: str, name: str, header: Sequence[str]) -> Iterable[tuple[int, dict[str, str]]]:
    """``(line, {column: stripped text})`` of each non-blank data row of CSV ``text``.

    Raises:
        StudyError: ``name:line: header: ...`` or a row of the wrong length.
    """
    reader = csv.reader(io.StringIO(text))
    want = ",".join(header)
    seen_header = False
    try:
        for fields in reader:
            line = reader.line_num
            cells = [f.strip() for f in fields]
            if not any(cells):
                continue
            if not seen_header:
                if [c.lower() for c in cells] != list(header):
                    raise StudyError(f"{name}:{line}: header: expected {want!r}, got "
                                     f"{','.join(cells)!r}")
                seen_header = True
                continue
            if len(cells) != len(header):
                raise StudyError(f"{name}:{line}: expected {len(header)} fields ({want}), got "
                                 f"{len(cells)}")
            yield line, dict(zip(header, cells))
    except csv.Error as exc:
        raise StudyError(f"{name}:{reader.line_num}: not valid CSV ({exc})") from None
    if not seen_header:
        raise StudyError(f"{name}:1: header: expected {want!r}, the file is empty")


def read_text(path: Path) -> str:
    """A CSV file's text (a spreadsheet's byte-order mark dropped).

    Raises:
        StudyError: missing or unreadable, naming it.
    """
    try:
        # utf-8-sig: a spreadsheet's "CSV UTF-8" starts with a byte-order mark
        return Path(path).read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise StudyError(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise StudyError(f"{path}: cannot be read ({exc})") from None


class _Bad(Exception):
    pass


def _get(obj: Any, key: str, kind: type | tuple[type, ...], where: str) -> Any:
    if not isinstance(obj, dict) or key not in obj:
        raise _Bad(f"{where}.{key}: missing")
    value = obj[key]
    if kind is float:
        ok = isinstance(value, (int, float)) and not isinstance(value, bool)
    elif kind is int:
        ok = isinstance(value, int) and not isinstance(value, bool)
    else:
        ok = isinstance(value, kind)
    if not ok:
        raise _Bad(f"{where}.{key}: expected {getattr(kind, '__name__', kind)}")
    return value


def _numbers(value: Any, n: int, where: str) -> tuple[float, ...]:
    if (not isinstance(value, list) or len(value) != n
            or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)):
        raise _Bad(f"{where}: expected {n} numbers")
    return tuple(float(v) for v in value)


def _texts(value: Any, where: str) -> tuple[str, ...]:
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise _Bad(f"{where}: expected a list of text")
    return tuple(value)


def _sheet(name: str, data: Any, folder: Path) -> SheetKey:
    w = f"sheets.{name}"
    lines_data = _get(data, "lines", dict, w)
    lines = []
    for part, polylines in lines_data.items():
        where = f"{w}.lines.{part}"
        if not isinstance(polylines, list) or not all(isinstance(x, list) for x in polylines):
            raise _Bad(f"{where}: expected a list of polylines (lists of points)")
        lines.append((part, tuple(tuple(_numbers(p, 2, where) for p in line)
                                  for line in polylines)))
    marks = _get(data, "marks_mm", list, w)
    if len(marks) != 4:
        raise _Bad(f"{w}.marks_mm: expected 4 points")
    printed = folder / _get(data, "printed", str, w)
    return SheetKey(
        sheet=name, object=_get(data, "object", str, w), view=_get(data, "view", str, w),
        condition=_get(data, "condition", str, w),
        paper_mm=_numbers(_get(data, "paper_mm", list, w), 2, f"{w}.paper_mm"),  # type: ignore[arg-type]
        frame_mm=_numbers(_get(data, "frame_mm", list, w), 4, f"{w}.frame_mm"),  # type: ignore[arg-type]
        marks_mm=tuple(_numbers(p, 2, f"{w}.marks_mm") for p in marks),  # type: ignore[arg-type]
        mark_radius_mm=float(_get(data, "mark_radius_mm", float, w)),
        code_box_mm=_numbers(_get(data, "code_box_mm", list, w), 4, f"{w}.code_box_mm"),  # type: ignore[arg-type]
        printed=printed, px_per_mm=float(_get(data, "px_per_mm", float, w)),
        lines=tuple(lines),
    )


def read_study(folder: str | Path) -> Study:
    """The study in ``folder`` (its study.json), checked field by field.

    Raises:
        StudyError: no study.json there, or one that does not check (naming the field).
    """
    folder = Path(folder)
    path = folder / STUDY_FILE
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise StudyError(f"{folder}: not a study folder (no {STUDY_FILE}; make one with "
                         f"'h2s study CONFIG')") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise StudyError(f"{path}: cannot be read ({exc})") from None
    try:
        if not isinstance(data, dict) or data.get("schema") != SCHEMA:
            raise _Bad(f"schema: expected {SCHEMA!r}")
        sheets_data = _get(data, "sheets", dict, "study")
        sheets = {name: _sheet(name, s, folder) for name, s in sheets_data.items()}
        drawings = []
        for i, d in enumerate(_get(data, "drawings", list, "study")):
            w = f"drawings[{i}]"
            dr = Drawing(_get(d, "row", int, w), _get(d, "participant", str, w),
                         _get(d, "order", int, w), _get(d, "object", str, w),
                         _get(d, "condition", str, w), _get(d, "sheet", str, w),
                         _get(d, "code", str, w))
            if dr.row != i:
                raise _Bad(f"{w}.row: expected {i}")
            if dr.sheet not in sheets:
                raise _Bad(f"{w}.sheet: {dr.sheet!r} is not in sheets")
            drawings.append(dr)
        study_id = _get(data, "study_id", str, "study")
        if not re.fullmatch(r"[0-9A-F]{8}", study_id):
            raise _Bad("study_id: expected 8 hexadecimal digits")
        design = _get(data, "design", str, "study")
        if design not in DESIGNS:
            raise _Bad(f"design: expected one of {', '.join(DESIGNS)}")
        language = data.get("language", "en")
        if not isinstance(language, str):
            raise _Bad("language: expected text")
        font = data.get("font")
        if font is not None:
            font = _texts(font, "font")
            if len(font) != 3:
                raise _Bad("font: expected 3 font files (regular, bold, oblique)")
        return Study(folder, study_id, _get(data, "title", str, "study"),
                     _get(data, "seed", int, "study"), design,
                     _texts(_get(data, "participants", list, "study"), "participants"),
                     _texts(_get(data, "conditions", list, "study"), "conditions"),
                     _texts(_get(data, "objects", list, "study"), "objects"),
                     tuple(drawings), sheets, language, font)
    except _Bad as exc:
        raise StudyError(f"{path}: {exc}") from None
