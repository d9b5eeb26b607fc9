"""Config files (DESIGN.md §3b) read into frozen values.

YAML is read with ``yaml.safe_load`` only, so tags never execute.  Every problem is a
:class:`ConfigError` whose message names the file and the key path, e.g.
``camera.yaml: views[1].elevation_deg: expected a number, got 'high'``.  Unknown keys are
errors: a typo in a 40-page print job must not silently fall back to a default.  So is a key
given twice in one mapping (``camera.yaml: title: key given twice (lines 1 and 9)``), which
plain YAML would read as its last value (:mod:`h2s_print.yamlfile`).

Paths inside a config are relative to the config file.

Defaults chosen where DESIGN.md is silent (documented in README "Config reference"):

* ``model.up``: ``y`` for glTF/GLB files, ``z`` otherwise; ``model.units``: the file's own
  (glTF: ``m`` unless its extras say otherwise; other formats: ``mm``).
* ``model.parts.small``: parts whose box diagonal is below ``min_size`` (default 0.01) of the
  model's, or that have no area, are ``merge``\\ d into the nearest part (default), ``drop``\\ ped,
  or ``keep``\\ t.
* PartNet folders (``result.json``): ``up: y`` and ``units: m`` like their GLB exports.
* Regrouping runs drop -> merge -> rename; part names are made id-safe (characters other than
  letters and digits of any script, ``_ . -`` become ``_``; clashes are numbered ``wheel``,
  ``wheel.1`` ...).
* ``levels``: ``[novice, apprentice, master]``; ``basic`` is the paper's control tutorial.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Callable

import yaml

from .errors import ConfigError
from . import fonts
from .fonts import FontError, FontSpec
from .glyphs import describe, unprintable
from .yamlfile import DuplicateKey, read_yaml

LEVELS = ("novice", "apprentice", "master", "basic")
PERSPECTIVES = ("two-point", "three-point")
UNITS = ("mm", "cm", "m", "in")
#: Millimetres per model unit.
UNIT_MM = {"mm": 1.0, "cm": 10.0, "m": 1000.0, "in": 25.4}
#: Portrait (width, height) in mm, ISO 216 and ANSI.
PAPER_SIZES_MM = {"A4": (210.0, 297.0), "A3": (297.0, 420.0), "Letter": (215.9, 279.4)}
FORMULATIONS = ("quadratic", "linear")
SMALL_PART_POLICIES = ("merge", "drop", "keep")
MIN_MARGIN_MM = 5.0


# --------------------------------------------------------------------------- values


@dataclass(frozen=True, slots=True)
class PartsSpec:
    """How to regroup a model's parts before fitting.

    Attributes:
        merge: ``(new_name, (pattern, ...))`` pairs; glob patterns over part names.
        rename: ``(old_name, new_name)`` pairs, applied after merging.
        drop: glob patterns of parts to leave out.
        small: policy for tiny or degenerate parts: ``merge``, ``drop`` or ``keep``.
        min_size: a part is tiny when its box diagonal is below this fraction of the model's.
        split: a part made of several disconnected pieces of one shape (the two wheels of an
            axle in one mesh) becomes one part per piece (reported); False keeps it whole.
    """

    merge: tuple[tuple[str, tuple[str, ...]], ...] = ()
    rename: tuple[tuple[str, str], ...] = ()
    drop: tuple[str, ...] = ()
    small: str = "merge"
    min_size: float = 0.01
    split: bool = True


@dataclass(frozen=True, slots=True)
class ModelSpec:
    """Where the model is and how to read it.

    Attributes:
        path: the model file or folder (absolute, resolved against the config's folder).
        up: ``x``, ``y`` or ``z``: the model file's up axis; ``None`` means the format default.
        units: ``mm``, ``cm``, ``m`` or ``in``; ``None`` means the file's own (glTF extras
            ``units`` when present, else ``m`` for glTF by its specification and ``mm`` otherwise).
        parts: regrouping of parts.
        source: the path as the config wrote it (relative to the config), for plan.json, so
            the plan does not depend on where the checkout lives; ``None``: ``str(path)``.
    """

    path: Path
    up: str | None = None
    units: str | None = None
    parts: PartsSpec = field(default_factory=PartsSpec)
    source: str | None = None


@dataclass(frozen=True, slots=True)
class ViewSpec:
    """One viewpoint (DESIGN.md §3b).

    Attributes:
        name: a file-name-safe identifier.
        azimuth_deg: 0 = camera in front of the model (-Y), +90 = on +X.
        elevation_deg: camera height angle above the object's centre, in (-90, 90).
        distance: camera distance in bounding-sphere radii (> 1: outside the object).
        lens_mm: 35 mm-equivalent focal length.
        perspective: ``two-point`` (level optical axis, shifted window) or ``three-point``.
    """

    name: str
    azimuth_deg: float = 35.0
    elevation_deg: float = 20.0
    distance: float = 3.0
    lens_mm: float = 50.0
    perspective: str = "two-point"


@dataclass(frozen=True, slots=True)
class PaperSpec:
    """Sheet size and margins.

    Attributes:
        size: ``A4``, ``A3`` or ``Letter``.
        orientation: ``landscape`` or ``portrait``.
        margin_mm: blank border on every side; at least 5 mm so printers do not trim content.
    """

    size: str = "A4"
    orientation: str = "landscape"
    margin_mm: float = 12.0

    @property
    def width_mm(self) -> float:
        w, h = PAPER_SIZES_MM[self.size]
        return h if self.orientation == "landscape" else w

    @property
    def height_mm(self) -> float:
        w, h = PAPER_SIZES_MM[self.size]
        return w if self.orientation == "landscape" else h


@dataclass(frozen=True, slots=True)
class SolverSettings:
    """Candidate generation and selection settings (DESIGN.md §2.4-§2.5).

    Attributes:
        formulation: ``linear`` (default: parent rows chi_c <= chi_p and aggregated relation
            conflict rows; 3-10x faster than quadratic on benchmarks/bench_select.py, same optimum)
            or ``quadratic`` (the paper's eq. (1)-(3) with SCIP's native quadratic rows).
        time_limit_s: SCIP wall-clock limit per solve, seconds.
        max_change: drop a candidate whose axis length or midpoint moves by more than this
            fraction of the input axis length.
        depth: levels of anchoring (1: anchored off original primitives only; 2: the paper's).
        weight_adjust: weight of E_adjust in the objective.
        weight_difficulty: weight of E_difficulty in the objective.
        guide_cost: lambda in E_e = lambda * guide_lines * A_ref / A_parent_face.
        max_candidates: guard rail; generation stops with a clear error beyond this many.
    """

    formulation: str = "linear"
    time_limit_s: float = 60.0
    max_change: float = 0.10
    depth: int = 2
    weight_adjust: float = 1.0
    weight_difficulty: float = 1.0
    guide_cost: float = 0.02
    max_candidates: int = 20000


@dataclass(frozen=True, slots=True)
class SequenceSettings:
    """Per-view sequencing settings (DESIGN.md §2.6).

    Attributes:
        eyeball_mm2: a primitive whose projected face area per guide line is below this (mm² on
            the sheet) becomes an "eyeball it" step.
        crease_deg: dihedral angle above which a mesh edge is drawn as a crease contour.
        suggestive: draw suggestive contours on smooth parts.
    """

    eyeball_mm2: float = 60.0
    crease_deg: float = 35.0
    suggestive: bool = False


@dataclass(frozen=True, slots=True)
class OutputSettings:
    """Extra outputs.

    Attributes:
        svg: also write one SVG per step.
        png: also write one PNG per step (through cairosvg).
        png_dpi: resolution of those PNGs.
    """

    svg: bool = False
    png: bool = False
    png_dpi: int = 150


@dataclass(frozen=True, slots=True)
class SheetSettings:
    """The calibrated drawing sheet.

    Attributes:
        grid: print a light perspective grid: lines converging toward each vanishing point
            across the frame (off-sheet vanishing points then still give a ruler line anywhere).
    """

    grid: bool = False


@dataclass(frozen=True, slots=True)
class TutorialConfig:
    """One tutorial: a model, its views, levels and paper (DESIGN.md §3b)."""

    path: Path
    name: str
    title: str
    model: ModelSpec
    views: tuple[ViewSpec, ...]
    levels: tuple[str, ...] = ("novice", "apprentice", "master")
    paper: PaperSpec = field(default_factory=PaperSpec)
    solver: SolverSettings = field(default_factory=SolverSettings)
    sequence: SequenceSettings = field(default_factory=SequenceSettings)
    output: OutputSettings = field(default_factory=OutputSettings)
    sheet: SheetSettings = field(default_factory=SheetSettings)
    font: FontSpec | None = None  #: the page font (``font:``); None: DejaVu Sans
    language: str = "en"  #: the wording's language (``language:``, templates/<code>/)


@dataclass(frozen=True, slots=True)
class BookConfig:
    """Many tutorials in one PDF (each workbook in its tutorial's font; the title and
    contents pages in the book's ``font:``)."""

    path: Path
    name: str
    title: str
    tutorials: tuple[TutorialConfig, ...]
    paper: PaperSpec = field(default_factory=PaperSpec)
    font: FontSpec | None = None
    language: str = "en"


@dataclass(frozen=True, slots=True)
class StudyObject:
    """One object of a study: a tutorial config and the view every participant draws.

    Attributes:
        name: the object's name in the study (file names, assignment.csv, the sheet code).
        tutorial: its tutorial config, with ``views`` the one view drawn and ``levels`` the
            study's conditions.
    """

    name: str
    tutorial: TutorialConfig


@dataclass(frozen=True, slots=True)
class StudyConfig:
    """A drawing study (issue 14, README "Drawing studies").

    Attributes:
        path, name, title: the config file, its stem, the study's title.
        participants: participant IDs (``participants: 6`` gives ``P01`` .. ``P06``).
        objects: the objects drawn; every participant draws each once.
        conditions: the tutorial levels compared (e.g. ``novice`` and the control ``basic``).
        design: ``fixed-first`` (the paper: ``first``'s drawing always comes first, the
            objects counterbalanced across conditions) or ``latin-square`` (each participant's
            drawings in the order of a row of a balanced Latin square).
        first: the condition drawn first under ``fixed-first``.
        seed: which participant gets which row of the design (a seeded shuffle).
        paper: the paper of the packet's cover and questionnaire pages.
    """

    path: Path
    name: str
    title: str
    participants: tuple[str, ...]
    objects: tuple[StudyObject, ...]
    conditions: tuple[str, ...]
    design: str = "fixed-first"
    first: str = ""
    seed: int = 0
    paper: PaperSpec = field(default_factory=PaperSpec)
    #: the packets' font and wording: covers and questionnaires, and, when the study config
    #: sets them, its tutorials too (else each tutorial keeps its config's)
    font: FontSpec | None = None
    language: str = "en"


# --------------------------------------------------------------------------- reading


class _Node:
    """A YAML value with its key path, for error messages."""

    __slots__ = ("file", "path", "value")

    def __init__(self, file: str, path: str, value: Any):
        self.file, self.path, self.value = file, path, value

    def fail(self, message: str) -> ConfigError:
        where = f"{self.file}: {self.path}: " if self.path else f"{self.file}: "
        return ConfigError(where + message)

    def child(self, key: str | int) -> "_Node":
        if isinstance(key, int):
            path = f"{self.path}[{key}]"
            return _Node(self.file, path, self.value[key])
        path = f"{self.path}.{key}" if self.path else key
        return _Node(self.file, path, self.value.get(key))

    # typed readers -----------------------------------------------------------------
    def mapping(self, allowed: tuple[str, ...], required: tuple[str, ...] = ()) -> "_Node":
        if not isinstance(self.value, dict):
            raise self.fail(f"expected a mapping, got {_show(self.value)}")
        for key in self.value:
            if not isinstance(key, str):
                raise self.fail(f"keys must be text, got {_show(key)}")
            if key not in allowed:
                raise _Node(self.file, f"{self.path}.{key}" if self.path else key, None).fail(
                    f"unknown key (allowed: {', '.join(allowed)})"
                )
        for key in required:
            if key not in self.value:
                raise self.child(key).fail("missing (required)")
        return self

    def has(self, key: str) -> bool:
        return isinstance(self.value, dict) and key in self.value

    def number(self, low: float | None = None, high: float | None = None,
               low_open: bool = False, high_open: bool = False) -> float:
        v = self.value
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise self.fail(f"expected a number, got {_show(v)}")
        v = float(v)
        if not math.isfinite(v):
            raise self.fail(f"expected a finite number, got {v}")
        if low is not None and (v < low or (low_open and v == low)):
            raise self.fail(f"must be {'>' if low_open else '>='} {_num(low)}, got {_num(v)}")
        if high is not None and (v > high or (high_open and v == high)):
            raise self.fail(f"must be {'<' if high_open else '<='} {_num(high)}, got {_num(v)}")
        return v

    def integer(self, low: int | None = None, high: int | None = None) -> int:
        v = self.value
        if isinstance(v, bool) or not isinstance(v, int):
            raise self.fail(f"expected a whole number, got {_show(v)}")
        if low is not None and v < low:
            raise self.fail(f"must be >= {low}, got {v}")
        if high is not None and v > high:
            raise self.fail(f"must be <= {high}, got {v}")
        return v

    def boolean(self) -> bool:
        if not isinstance(self.value, bool):
            raise self.fail(f"expected true or false, got {_show(self.value)}")
        return self.value

    def text(self, pattern: str | None = None, what: str = "") -> str:
        v = self.value
        if not isinstance(v, str) or not v.strip():
            raise self.fail(f"expected text, got {_show(v)}")
        if pattern is not None and not re.fullmatch(pattern, v):
            raise self.fail(f"expected {what}, got {_show(v)}")
        return v

    def printed_text(self, font: FontSpec | None = None) -> str:
        """:meth:`text` that goes on the pages: every character printable in the page font
        (``font``, default DejaVu Sans: :mod:`h2s_print.glyphs`), else an error naming it."""
        v = self.text()
        with fonts.using(font) as spec:
            ch = unprintable(v)
        if ch is not None:
            raise self.fail(f"character {describe(ch)} cannot be printed in the page font "
                            f"({spec.name}): give a font that has it (config 'font:')")
        return v

    def choice(self, options: tuple[str, ...]) -> str:
        v = self.value
        if not isinstance(v, str) or v not in options:
            raise self.fail(f"expected one of {', '.join(options)}, got {_show(v)}")
        return v

    def items(self) -> list["_Node"]:
        if not isinstance(self.value, list):
            raise self.fail(f"expected a list, got {_show(self.value)}")
        return [self.child(i) for i in range(len(self.value))]

    def text_list(self) -> tuple[str, ...]:
        if isinstance(self.value, str):
            return (self.text(),)
        return tuple(item.text() for item in self.items())

    def get(self, key: str, read: Callable[["_Node"], Any], default: Any) -> Any:
        return read(self.child(key)) if self.has(key) else default


def _show(value: Any) -> str:
    if value is None:
        return "nothing"
    if isinstance(value, dict):
        return "a mapping"
    if isinstance(value, list):
        return "a list"
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def _num(v: float) -> str:
    return f"{v:g}"


#: Part and view names: no '<', '+', '#' or ':' (they structure candidate ids like "grip<body#3").
_NAME = r"[A-Za-z0-9][A-Za-z0-9_.-]*"
#: Part names (merge and rename targets): letters and digits of any script too, as model
#: files' names are kept (:func:`h2s_print.load.safe_name`).
_PART_NAME = r"[^\W_][\w.-]*"


def _read_yaml(path: Path) -> Any:
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ConfigError(f"{path}: file not found") from None
    except IsADirectoryError:
        raise ConfigError(f"{path}: is a folder, expected a YAML config file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ConfigError(f"{path}: cannot read: {exc}") from None
    try:
        return read_yaml(text)
    except DuplicateKey as exc:
        raise ConfigError(f"{path.name}: {exc}") from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"line {mark.line + 1}: " if mark is not None else ""
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise ConfigError(f"{path.name}: {where}invalid YAML: {problem}") from None


def is_book(data: Any) -> bool:
    """True when a parsed config is a book (it lists ``tutorials``)."""
    return isinstance(data, dict) and "tutorials" in data


def is_study(data: Any) -> bool:
    """True when a parsed config is a drawing study (it has a ``study`` section)."""
    return isinstance(data, dict) and "study" in data


def load_config(path: str | Path) -> TutorialConfig | BookConfig:
    """Read a tutorial or book config file.

    Raises:
        ConfigError: naming the file and key path of the first problem (a study config
            too: it is made with ``h2s study``).
    """
    path = Path(path)
    data = _read_yaml(path)
    if is_study(data):
        raise ConfigError(f"{path.name}: study: a study config; make it with 'h2s study'")
    if is_book(data):
        return _book(path, data, stack=())
    return _tutorial(path, data)


def load_study(path: str | Path) -> StudyConfig:
    """Read a drawing-study config (a ``study:`` section; README "Drawing studies").

    Raises:
        ConfigError: naming the file and key path of the first problem.
    """
    path = Path(path)
    data = _read_yaml(path)
    if not is_study(data):
        raise ConfigError(f"{path.name}: study: missing (a study config has a 'study:' "
                          f"section; tutorials and books are made with 'h2s build')")
    return _study(path, data)


def load_tutorial(path: str | Path) -> TutorialConfig:
    """Read a config that must be a single tutorial."""
    cfg = load_config(path)
    if isinstance(cfg, BookConfig):
        raise ConfigError(f"{Path(path).name}: tutorials: expected a tutorial config, got a book")
    return cfg


_TUTORIAL_KEYS = ("title", "model", "views", "levels", "paper", "solver", "sequence", "output",
                  "sheet", "font", "language")


def _tutorial(path: Path, data: Any) -> TutorialConfig:
    root = _Node(path.name, "", data)
    if data is None:
        raise root.fail("empty config (expected title, model, views ...)")
    root.mapping(_TUTORIAL_KEYS, required=("model", "views"))
    name = path.stem
    font = root.get("font", lambda n: _font(n, path.parent), None)
    title = root.get("title", lambda n: n.printed_text(font), name)
    model = _model(root.child("model"), path.parent)
    views = tuple(_view(n) for n in root.child("views").items())
    if not views:
        raise root.child("views").fail("expected at least one view")
    names = [v.name for v in views]
    for i, v in enumerate(names):
        if names.index(v) != i:
            raise root.child("views").child(i).child("name").fail(f"duplicate view name {v!r}")
    levels = root.get("levels", lambda n: tuple(x.choice(LEVELS) for x in n.items()),
                      ("novice", "apprentice", "master"))
    if not levels:
        raise root.child("levels").fail(f"expected at least one of {', '.join(LEVELS)}")
    if len(set(levels)) != len(levels):
        raise root.child("levels").fail("a level is listed twice")
    return TutorialConfig(
        path=path.resolve(),
        name=name,
        title=title,
        model=model,
        views=views,
        levels=levels,
        paper=root.get("paper", _paper, PaperSpec()),
        solver=root.get("solver", _solver, SolverSettings()),
        sequence=root.get("sequence", _sequence, SequenceSettings()),
        output=root.get("output", _output, OutputSettings()),
        sheet=root.get("sheet", _sheet, SheetSettings()),
        font=font,
        language=root.get("language", _language, "en"),
    )


def _language(node: _Node) -> str:
    from . import templates

    return node.choice(templates.languages())


def _font(node: _Node, base: Path) -> FontSpec:
    """``font: file.ttf`` (every style) or ``font: {regular: a.ttf, bold: b.ttf, oblique:
    c.ttf}`` (bold and oblique default to regular), relative to the config."""
    if isinstance(node.value, str):
        files = {"regular": node}
    else:
        node.mapping(("regular", "bold", "oblique"), required=("regular",))
        files = {k: node.child(k) for k in ("regular", "bold", "oblique") if node.has(k)}
    paths = {}
    for style, n in files.items():
        path = (base / n.text()).resolve()
        if not path.is_file():
            raise n.fail(f"{n.value!r}: file not found")
        try:
            fonts.face(path)
        except FontError as exc:
            raise n.fail(str(exc).replace(str(path), repr(n.value))) from None
        paths[style] = path
    regular = paths["regular"]
    return FontSpec(regular, paths.get("bold", regular), paths.get("oblique", regular),
                    name=regular.name)


def _model(node: _Node, base: Path) -> ModelSpec:
    if isinstance(node.value, str):  # shorthand: model: path/to/file.glb
        return ModelSpec(path=(base / node.text()).resolve(), source=node.value)
    node.mapping(("path", "up", "units", "parts"), required=("path",))
    rel = node.child("path").text()
    return ModelSpec(
        path=(base / rel).resolve(),
        up=node.get("up", lambda n: n.choice(("x", "y", "z")), None),
        units=node.get("units", lambda n: n.choice(UNITS), None),
        parts=node.get("parts", _parts, PartsSpec()),
        source=rel,
    )


def _parts(node: _Node) -> PartsSpec:
    node.mapping(("merge", "rename", "drop", "small", "min_size", "split"))
    merge: tuple[tuple[str, tuple[str, ...]], ...] = ()
    if node.has("merge"):
        m = node.child("merge").mapping(tuple(node.value["merge"] or ()))
        for k in m.value:
            if not re.fullmatch(_PART_NAME, k):
                raise m.child(k).fail("expected a part name of letters, digits, '-', '_' or '.'")
        merge = tuple((k, m.child(k).text_list()) for k in m.value)
    rename: tuple[tuple[str, str], ...] = ()
    if node.has("rename"):
        r = node.child("rename").mapping(tuple(node.value["rename"] or ()))
        rename = tuple((k, r.child(k).text(_PART_NAME, "a part name")) for k in r.value)
    return PartsSpec(
        merge=merge,
        rename=rename,
        drop=node.get("drop", lambda n: n.text_list(), ()),
        small=node.get("small", lambda n: n.choice(SMALL_PART_POLICIES), "merge"),
        min_size=node.get("min_size", lambda n: n.number(0.0, 0.5), 0.01),
        split=node.get("split", lambda n: n.boolean(), True),
    )


def _view(node: _Node) -> ViewSpec:
    node.mapping(("name", "azimuth_deg", "elevation_deg", "distance", "lens_mm", "perspective"),
                 required=("name",))
    return ViewSpec(
        name=node.child("name").text(_NAME, "a name of letters, digits, '-', '_' or '.'"),
        azimuth_deg=node.get("azimuth_deg", lambda n: n.number(-360, 360), 35.0),
        elevation_deg=node.get(
            "elevation_deg", lambda n: n.number(-89, 89), 20.0),
        distance=node.get("distance", lambda n: n.number(1.0, 1000.0, low_open=True), 3.0),
        lens_mm=node.get("lens_mm", lambda n: n.number(8.0, 1200.0), 50.0),
        perspective=node.get("perspective", lambda n: n.choice(PERSPECTIVES), "two-point"),
    )


def _paper(node: _Node) -> PaperSpec:
    node.mapping(("size", "orientation", "margin_mm"))
    return PaperSpec(
        size=node.get("size", lambda n: n.choice(tuple(PAPER_SIZES_MM)), "A4"),
        orientation=node.get("orientation", lambda n: n.choice(("landscape", "portrait")),
                             "landscape"),
        margin_mm=node.get("margin_mm", lambda n: n.number(MIN_MARGIN_MM, 50.0), 12.0),
    )


def _solver(node: _Node) -> SolverSettings:
    node.mapping(("formulation", "time_limit_s", "max_change", "depth", "weights",
                  "guide_cost", "max_candidates"))
    weights = (1.0, 1.0)
    if node.has("weights"):
        w = node.child("weights").mapping(("adjust", "difficulty"))
        weights = (w.get("adjust", lambda n: n.number(0.0, 1e6), 1.0),
                   w.get("difficulty", lambda n: n.number(0.0, 1e6), 1.0))
    return SolverSettings(
        formulation=node.get("formulation", lambda n: n.choice(FORMULATIONS), "linear"),
        time_limit_s=node.get("time_limit_s", lambda n: n.number(0.0, 86400.0, low_open=True),
                              60.0),
        max_change=node.get("max_change", lambda n: n.number(0.0, 1.0, low_open=True), 0.10),
        depth=node.get("depth", lambda n: n.integer(1, 3), 2),
        weight_adjust=weights[0],
        weight_difficulty=weights[1],
        guide_cost=node.get("guide_cost", lambda n: n.number(0.0, 1e3), 0.02),
        max_candidates=node.get("max_candidates", lambda n: n.integer(10, 10_000_000), 20000),
    )


def _sequence(node: _Node) -> SequenceSettings:
    node.mapping(("eyeball_mm2", "crease_deg", "suggestive"))
    return SequenceSettings(
        eyeball_mm2=node.get("eyeball_mm2", lambda n: n.number(0.0, 1e5), 60.0),
        crease_deg=node.get("crease_deg", lambda n: n.number(0.0, 180.0), 35.0),
        suggestive=node.get("suggestive", lambda n: n.boolean(), False),
    )


def _sheet(node: _Node) -> SheetSettings:
    node.mapping(("grid",))
    return SheetSettings(grid=node.get("grid", lambda n: n.boolean(), False))


def _output(node: _Node) -> OutputSettings:
    node.mapping(("svg", "png", "png_dpi"))
    return OutputSettings(
        svg=node.get("svg", lambda n: n.boolean(), False),
        png=node.get("png", lambda n: n.boolean(), False),
        png_dpi=node.get("png_dpi", lambda n: n.integer(30, 1200), 150),
    )


#: Participant IDs: printed on packets and sheets, used in file names.
_PARTICIPANT = r"[A-Za-z0-9][A-Za-z0-9_.-]{0,23}"
STUDY_DESIGNS = ("fixed-first", "latin-square")


def _study(path: Path, data: Any) -> StudyConfig:
    root = _Node(path.name, "", data)
    root.mapping(("title", "study", "paper", "font", "language"), required=("study",))
    font = root.get("font", lambda n: _font(n, path.parent), None)
    node = root.child("study")
    node.mapping(("participants", "objects", "conditions", "design", "first", "seed"),
                 required=("participants", "objects", "conditions"))
    pnode = node.child("participants")
    if isinstance(pnode.value, int) and not isinstance(pnode.value, bool):
        count = pnode.integer(1, 999)
        participants = tuple(f"P{i + 1:0{max(2, len(str(count)))}d}" for i in range(count))
    else:
        participants = tuple(n.text(_PARTICIPANT, "an ID of letters, digits, '_', '.' or '-' "
                                    "(at most 24)") for n in pnode.items())
        if not participants:
            raise pnode.fail("expected a count or a list of IDs")
        for i, p in enumerate(participants):
            if participants.index(p) != i:
                raise pnode.child(i).fail(f"participant {p!r} is listed twice")
    cnode = node.child("conditions")
    conditions = tuple(n.choice(LEVELS) for n in cnode.items())
    if not conditions:
        raise cnode.fail(f"expected at least one of {', '.join(LEVELS)}")
    if len(set(conditions)) != len(conditions):
        raise cnode.fail("a condition is listed twice")
    design = node.get("design", lambda n: n.choice(STUDY_DESIGNS), "fixed-first")
    first = node.get("first", lambda n: n.choice(conditions), conditions[0])
    if node.has("first") and design != "fixed-first":
        raise node.child("first").fail("only for design: fixed-first")
    objects: list[StudyObject] = []
    onode = node.child("objects")
    for entry in onode.items():
        if isinstance(entry.value, str):
            rel, view_name, name = entry.text(), None, None
            at = entry
        else:
            entry.mapping(("config", "view", "name"), required=("config",))
            at = entry.child("config")
            rel = at.text()
            view_name = entry.get("view", lambda n: n.text(), None)
            name = entry.get("name", lambda n: n.text(_NAME, "a file-name-safe name"), None)
        target = (path.parent / rel).resolve()
        if not target.is_file():
            raise at.fail(f"{rel!r}: file not found")
        sub = _read_yaml(target)
        if is_book(sub) or is_study(sub):
            raise at.fail(f"{rel!r} is not a tutorial config")
        tutorial = _tutorial(target, sub)
        views = tutorial.views
        if view_name is not None:
            views = tuple(v for v in views if v.name == view_name)
            if not views:
                raise entry.child("view").fail(
                    f"{rel!r} has no view {view_name!r} (it has "
                    f"{', '.join(v.name for v in tutorial.views)})")
        tutorial = replace(tutorial, views=views[:1], levels=conditions)
        if root.has("language"):  # the study's wording is the whole packet's
            tutorial = replace(tutorial, language=root.get("language", _language, "en"))
        if font is not None:
            tutorial = replace(tutorial, font=font)
        objects.append(StudyObject(name or tutorial.name, tutorial))
    if not objects:
        raise onode.fail("expected at least one tutorial config")
    names = [o.name for o in objects]
    for i, n in enumerate(names):
        if names.index(n) != i:
            raise onode.child(i).fail(f"object name {n!r} appears twice (give one a 'name:')")
    return StudyConfig(
        path=path.resolve(), name=path.stem,
        title=root.get("title", lambda n: n.printed_text(font), path.stem),
        participants=participants, objects=tuple(objects), conditions=conditions,
        design=design, first=first if design == "fixed-first" else "",
        seed=node.get("seed", lambda n: n.integer(0, 2**31 - 1), 0),
        paper=root.get("paper", _paper, PaperSpec()), font=font,
        language=root.get("language", _language, "en"))


def _book(path: Path, data: Any, stack: tuple[Path, ...]) -> BookConfig:
    root = _Node(path.name, "", data)
    root.mapping(("title", "tutorials", "paper", "font", "language"), required=("tutorials",))
    font = root.get("font", lambda n: _font(n, path.parent), None)
    entries = root.child("tutorials").items()
    if not entries:
        raise root.child("tutorials").fail("expected at least one tutorial")
    here = path.resolve()
    tutorials: list[TutorialConfig] = []
    for entry in entries:
        rel = entry.text()
        target = (path.parent / rel).resolve()
        if target == here or target in stack:
            raise entry.fail(f"{rel!r} names this book itself")
        if not target.is_file():
            raise entry.fail(f"{rel!r}: file not found")
        sub = _read_yaml(target)
        if is_book(sub):
            raise entry.fail(f"{rel!r} is a book; a book lists tutorial configs")
        tutorials.append(_tutorial(target, sub))
    names = [t.name for t in tutorials]
    for i, n in enumerate(names):
        if names.index(n) != i:
            raise entries[i].fail(f"tutorial name {n!r} appears twice")
    paper = root.get("paper", _paper, tutorials[0].paper)
    return BookConfig(path=here, name=path.stem, title=root.get(
                      "title", lambda n: n.printed_text(font), path.stem),
                      tutorials=tuple(tutorials), paper=paper, font=font,
                      language=root.get("language", _language, "en"))
