"""The ``h2s`` command line (DESIGN.md §3b).

Only this module prints and chooses exit codes: 0 on success, 2 for a user's mistake
(an :class:`~h2s_print.errors.H2SError`, one line on stderr naming the file and field),
1 for a bug (anything else), 130 on Ctrl-C.
"""

from __future__ import annotations

import argparse
import json
import logging
import sys
from pathlib import Path
from typing import Sequence

from . import __version__
from .errors import H2SError

log = logging.getLogger("h2s_print")

CONFIG_SUFFIXES = (".yaml", ".yml")


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
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

    p = sub.add_parser("build", help="PDF workbooks (tutorial or book config) and plan.json")
    p.add_argument("config", type=Path)
    p.add_argument("-o", "--output", type=Path, default=Path("output"), help="output folder")
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    level = logging.WARNING if args.quiet else logging.DEBUG if args.verbose else logging.INFO
    logging.basicConfig(level=level, format="%(message)s", stream=sys.stderr)
    try:
        if args.command == "inspect":
            return _inspect(args)
        if args.command == "plan":
            return _plan(args)
        if args.command == "build":
            return _build(args)
    except H2SError as exc:
        print(f"h2s: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("h2s: interrupted", file=sys.stderr)
        return 130
    return 1  # pragma: no cover - argparse guarantees a command


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
    rows = [("a", "b", "type", "axis", "tolerance", "preserved")]
    for r in relations:
        rows.append((r.a, r.b, r.type, "xyz"[r.axis], f"{r.tolerance:.4g}",
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


def _plan(args: argparse.Namespace) -> int:
    from .config import load_tutorial
    from .pipeline import plan_tutorial, write_plan

    tutorial = load_tutorial(args.config)
    result = plan_tutorial(tutorial)
    path = write_plan(result, args.output / tutorial.name)
    sel = result.plan.selection
    note = "" if sel.optimal else "  (NOT proven optimal: time limit reached)"
    log.info("%s: %d parts, %d candidates, objective %.4f, SCIP %s in %.2f s%s",
             tutorial.name, len(result.plan.model.parts), len(result.plan.candidates),
             sel.objective, sel.status, sel.seconds, note)
    if args.text:
        from .pipeline import steps_text

        print(steps_text(result))
    log.info("wrote %s", path)
    return 0


def _build(args: argparse.Namespace) -> int:
    from .pipeline import build

    for path in build(args.config, args.output):
        log.info("wrote %s", path)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
