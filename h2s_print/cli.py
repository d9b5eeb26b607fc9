"""The ``h2s`` command line (DESIGN.md §3b).

Only this module prints and chooses exit codes: 0 on success, 2 for a user's mistake
(an :class:`~h2s_print.errors.H2SError` or a bad command line: one line on stderr,
``h2s: error: <file>: <field>: <what>``), 1 for a bug (anything else: the traceback and a line
saying it is a bug), 130 on Ctrl-C.  Nothing is written when a build fails (see
:mod:`h2s_print.pipeline`).

Everything but the command's data (``inspect`` tables and JSON, ``plan --text``) goes to stderr:
log messages, warnings, and progress.  Progress is a bar redrawn in place when stderr is a
terminal, else one plain line per milestone (a tutorial's plan, views, layout ...); ``-q`` shows
errors only, ``-v`` adds debug messages and every progress step.
"""

from __future__ import annotations

import argparse
import gc
import json
import logging
import os
import shutil
import sys
import traceback
from pathlib import Path
from typing import IO, Sequence

from . import __version__
from .errors import H2SError

log = logging.getLogger("h2s_print")

CONFIG_SUFFIXES = (".yaml", ".yml")
#: Exit statuses.
EXIT_OK, EXIT_BUG, EXIT_USER, EXIT_INTERRUPTED = 0, 1, 2, 130


#: Commands run with Python's cyclic garbage collector off (on again after, if it was on).
#: The pipeline's objects live to the end of the run and make next to no reference cycles
#: (reference counting frees the rest at once), so the collector's passes, which walk every
#: object tracked (NumPy's and SciPy's modules, the plan's boxes and strokes) over and over,
#: free nothing.  Measured (2 cores, 2026-11-29): ``h2s plan`` of the camera spent 0.05 s in
#: them, the roller 0.08 s, the train 0.14 s, a generated 80-part model 1.9 s of 15.6 s; the
#: example book's build 0.4 s of 7.4 s.  Peak memory with it off: roller 124 -> 125 MB, the
#: 80 parts 325 -> 331 MB, the book 218 -> 223 MB.  ``study``, ``score`` and ``rank`` (scans,
#: images) keep it.
NO_GC_COMMANDS = frozenset(("plan", "build"))


class _UsageError(Exception):
    """A bad command line (argparse's complaint), reported like any user mistake."""


class _Parser(argparse.ArgumentParser):
    """argparse that reports a bad command line as one ``h2s: error:`` line (exit 2)."""

    def error(self, message: str):  # type: ignore[override]
        raise _UsageError(f"{self.prog}: {message} (see {self.prog} --help)")


def _jobs(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if n < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0 (0: one per CPU), got {n}")
    return n or (os.cpu_count() or 1)


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="h2s", description="Printable step-by-step sketching workbooks from 3D models.")
    parser.add_argument("--version", action="version", version=f"h2s {__version__}")
    verbosity = parser.add_mutually_exclusive_group()
    verbosity.add_argument("-q", "--quiet", action="store_true", help="only errors")
    verbosity.add_argument("-v", "--verbose", action="store_true", help="more detail")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = sub.add_parser("inspect", help="parts, primitives and relations of a model or config")
    p.add_argument("path", type=Path, help="a model file, a model folder or a config")
    p.add_argument("--json", action="store_true", help="print {parts, relations} as JSON")
    p.add_argument("--up", choices=("x", "y", "z"), help="the model file's up axis")
    p.add_argument("--units", choices=("mm", "cm", "m", "in"), help="the model's units")

    p = sub.add_parser("plan", help="stages 1-7 for every view and level: writes plan.json")
    p.add_argument("config", type=Path)
    p.add_argument("-o", "--output", type=Path, default=Path("output"), help="output folder")
    p.add_argument("--text", action="store_true", help="also print the steps as text")
    p.add_argument("--no-cache", action="store_true",
                   help="solve again; do not read or write DIR/.h2s-cache")

    p = sub.add_parser("build", help="PDF workbooks (tutorial or book config) and plan.json")
    p.add_argument("config", type=Path)
    p.add_argument("-o", "--output", type=Path, default=Path("output"), help="output folder")
    p.add_argument("-j", "--jobs", type=_jobs, default=1, metavar="N",
                   help="build a book's tutorials in N processes (default 1; 0: one per CPU)")
    p.add_argument("--no-cache", action="store_true",
                   help="solve every plan again; do not read or write DIR/.h2s-cache")

    p = sub.add_parser("study", help="a drawing study's packets, answer keys and study.json")
    p.add_argument("config", type=Path, help="a study config (a 'study:' section)")
    p.add_argument("-o", "--output", type=Path, default=Path("output"), help="output folder")
    p.add_argument("--no-cache", action="store_true",
                   help="solve every plan again; do not read or write DIR/.h2s-cache")

    p = sub.add_parser("score", help="score scanned drawing sheets of a study")
    p.add_argument("scans", type=Path, nargs="+", metavar="SCAN",
                   help="scans or photos of filled sheets: PNG, JPEG or PDF (200 dpi or more)")
    p.add_argument("--study", type=Path, required=True, metavar="DIR",
                   help="the study folder (made by 'h2s study')")

    p = sub.add_parser("rank", help="pair pages for raters; with --judgments, Bradley-Terry "
                                    "strengths")
    p.add_argument("study", type=Path, help="the study folder (made by 'h2s study')")
    p.add_argument("--judgments", type=Path, metavar="CSV",
                   help="the raters' filled judgments.csv: fit and write the strengths")
    return parser


# ----------------------------------------------------------------------------- console


class _Console(logging.Handler):
    """Log messages and progress on stderr: a bar on a terminal, plain lines elsewhere."""

    def __init__(self, stream: IO[str], level: int, tty: bool):
        super().__init__(level)
        self.stream = stream
        self.tty = tty
        self.total = 0
        self.done = 0
        self.shown = False  # a bar is on the current line

    # logging -----------------------------------------------------------------------
    def emit(self, record: logging.LogRecord) -> None:
        try:
            msg = record.getMessage()
            if record.levelno >= logging.WARNING:
                msg = f"h2s: warning: {msg}"
            self._line(msg)
        except Exception:  # noqa: BLE001 - logging must never raise
            self.handleError(record)

    def _line(self, text: str) -> None:
        bar = self.shown
        self.clear()
        self.stream.write(text + "\n")
        if bar:
            self._draw(self._last)
        self.stream.flush()

    # progress ----------------------------------------------------------------------
    _last = ""

    def start(self, total: int) -> None:
        self.total, self.done = max(1, total), 0

    def progress(self, event) -> None:
        self.done = min(self.total, self.done + event.units)
        line = f"{event.tutorial}: {event.text}"
        if event.milestone:
            log.info("%s", line)
        else:
            log.debug("%s", line)
        if self.tty and self.level <= logging.INFO:
            self._draw(line)
            self.stream.flush()

    def _draw(self, text: str) -> None:
        self._last = text
        width = shutil.get_terminal_size((80, 24)).columns
        frac = self.done / self.total if self.total else 0.0
        cells = 20
        fill = int(round(frac * cells))
        head = f"[{'#' * fill}{'.' * (cells - fill)}] {100 * frac:3.0f}% "
        line = (head + text)[: max(10, width - 1)]
        self.stream.write("\r\x1b[K" + line)
        self.shown = True

    def clear(self) -> None:
        if self.shown:
            self.stream.write("\r\x1b[K")
            self.stream.flush()
            self.shown = False


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``h2s`` with ``argv`` (default ``sys.argv[1:]``); returns the exit status."""
    stderr = sys.stderr
    try:
        args = _parser().parse_args(argv)
    except _UsageError as exc:
        print(f"h2s: error: {_one_line(exc)}", file=stderr)
        return EXIT_USER
    level = logging.ERROR if args.quiet else logging.DEBUG if args.verbose else logging.INFO
    tty = bool(getattr(stderr, "isatty", lambda: False)())
    console = _Console(stderr, level, tty)
    root = logging.getLogger()
    root.addHandler(console)
    old_level = log.level
    log.setLevel(level)
    collecting = gc.isenabled()
    if args.command in NO_GC_COMMANDS:
        gc.disable()
    try:
        if args.command == "inspect":
            return _inspect(args)
        if args.command in ("plan", "build", "study", "rank"):
            from . import templates
            for name in templates.FIELDS:  # wording checked before any work is done
                templates.load(name)
            templates.check_font()
        if args.command == "plan":
            return _plan(args, console)
        if args.command == "build":
            return _build(args, console)
        if args.command == "study":
            return _study(args, console)
        if args.command == "rank":
            return _rank(args)
        if args.command == "score":
            return _score(args)
        return EXIT_BUG  # pragma: no cover - argparse guarantees a command
    except H2SError as exc:
        console.clear()
        print(f"h2s: error: {_one_line(exc)}", file=stderr)
        return EXIT_USER
    except KeyboardInterrupt:
        console.clear()
        print("h2s: interrupted; nothing was written", file=stderr)
        return EXIT_INTERRUPTED
    except Exception as exc:  # noqa: BLE001 - anything else is a bug: say so, with the trace
        console.clear()
        traceback.print_exc(file=stderr)
        print(f"h2s: internal error (this is a bug in h2s {__version__}, please report it with "
              f"the traceback above): {type(exc).__name__}: {_one_line(exc)}", file=stderr)
        return EXIT_BUG
    finally:
        if collecting:
            gc.enable()
        console.clear()
        root.removeHandler(console)
        log.setLevel(old_level)


# ----------------------------------------------------------------------------- inspect


def _inspect(args: argparse.Namespace) -> int:
    from .config import BookConfig, ModelSpec, load_config
    from .fit import fit_primitives
    from .load import load_model
    from .plan import inspect_json
    from .relate import detect_relations

    path: Path = args.path
    if path.suffix.lower() in CONFIG_SUFFIXES:
        cfg = load_config(path)
        tutorials = cfg.tutorials if isinstance(cfg, BookConfig) else (cfg,)
        specs = [(t.title, t.model) for t in tutorials]
    else:
        specs = [(path.name, ModelSpec(path=path.resolve(), up=args.up, units=args.units))]

    reports = []
    for title, spec in specs:
        model = load_model(spec)
        primitives = fit_primitives(model)
        relations = detect_relations(primitives)
        reports.append((title, model, primitives, relations))

    if args.json:
        docs = [inspect_json(p, r) for _, _, p, r in reports]
        print(json.dumps(docs[0] if len(docs) == 1 else docs, indent=1))
        return 0
    for title, model, primitives, relations in reports:
        print(_inspect_table(title, model, primitives, relations))
    return 0


def _inspect_table(title, model, primitives, relations) -> str:
    from .types import box_size

    lines = [f"{title}: {len(model.parts)} parts, units {model.units}, source {model.source}"]
    for note in model.notes:
        lines.append(f"  note: {note}")
    rows = [("part", "triangles", "primitive", "axis", "size (x y z)", "residual")]
    for part, prim in zip(model.parts, primitives):
        size = " ".join(f"{s:.4g}" for s in box_size(prim.box))
        axis = "-" if prim.axis is None else "xyz"[prim.axis]
        rows.append((part.name, str(len(part.faces)), prim.type, axis, size,
                     f"{prim.residual:.4f}"))
    lines += _table(rows)
    kept = [r for r in relations if r.detail.get("preserved")]
    lines.append(f"relations: {len(relations)} found, {len(kept)} preserved")
    rows = [("a", "b", "type", "axis", "faces", "tolerance", "preserved")]
    for r in relations:
        # which faces meet: a's end and b's end along the axis (coplanar only)
        faces = (f"{r.detail['a_end']}={r.detail['b_end']}" if r.type == "coplanar" else "")
        rows.append((r.a, r.b, r.type, "xyz"[r.axis], faces, f"{r.tolerance:.4g}",
                     "yes" if r.detail.get("preserved") else ""))
    if len(rows) > 1:
        lines += _table(rows)
    return "\n".join(lines) + "\n"


def _table(rows: list[tuple[str, ...]]) -> list[str]:
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    out = []
    for k, row in enumerate(rows):
        out.append("  " + "  ".join(cell.ljust(w) for cell, w in zip(row, widths)).rstrip())
        if k == 0:
            out.append("  " + "  ".join("-" * w for w in widths))
    return out


# ----------------------------------------------------------------------------- plan, build


def _plan(args: argparse.Namespace, console: _Console) -> int:
    from .cache import cache_folder
    from .config import BookConfig, load_config
    from .errors import ConfigError
    from .files import check_writable, write_many_atomic
    from .pipeline import plan_bytes, plan_tutorial

    tutorial = load_config(args.config)
    if isinstance(tutorial, BookConfig):
        raise ConfigError(f"{args.config.name}: is a book config; `h2s plan` takes one tutorial "
                          f"config (use `h2s build` for books)")
    check_writable(args.output)
    n = len(tutorial.views) * len(tutorial.levels)
    console.start(1 + n)
    result = plan_tutorial(tutorial, cache_dir=None if args.no_cache else cache_folder(args.output),
                           progress=console.progress)
    text = None
    if args.text:
        from .pipeline import steps_text

        text = steps_text(result)
    (path,) = write_many_atomic([(args.output / tutorial.name / "plan.json", plan_bytes(result))])
    console.clear()
    if text is not None:
        print(text)
    log.info("wrote %s", path)
    return EXIT_OK


def _build(args: argparse.Namespace, console: _Console) -> int:
    from .config import load_config
    from .pipeline import STEP_FILE_RE, build, work_units

    console.start(work_units(load_config(args.config)))
    written = build(args.config, args.output, jobs=args.jobs, cache=not args.no_cache,
                    progress=console.progress)
    console.clear()
    steps = [p for p in written if STEP_FILE_RE.fullmatch(p.name)]
    for path in written:
        if path not in steps:
            log.info("wrote %s", path)
    if steps:
        folders = sorted({p.parent for p in steps})
        log.info("wrote %d step files in %d folders (%s ...)", len(steps), len(folders), folders[0])
    return EXIT_OK


def _study(args: argparse.Namespace, console: _Console) -> int:
    from .pipeline import build_study

    written, note = build_study(args.config, args.output, cache=not args.no_cache,
                                progress=console.progress)
    console.clear()
    folders = sorted({p.parent for p in written})
    log.info("wrote %d files in %s", len(written), ", ".join(str(f) for f in folders))
    if note:
        log.warning("%s", note)
    return EXIT_OK


def _score(args: argparse.Namespace) -> int:
    from .pipeline import score_study

    written = score_study(args.scans, args.study)
    for path in written:
        log.info("wrote %s", path)
    return EXIT_OK


def _rank(args: argparse.Namespace) -> int:
    from .pipeline import rank_study

    written, kept = rank_study(args.study, args.judgments)
    for path in written:
        log.info("wrote %s", path)
    for what in kept:
        log.info("kept %s", what)
    return EXIT_OK


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
