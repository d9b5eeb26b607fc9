"""Benchmark: how big an exact per-axis candidate space is (the anchoring issue's point 0).

Run: ``python3 benchmarks/bench_closure.py [--models camera,mixer] [--depth 2] [--cap 2000000]``

The anchoring issue asks for "a candidate design in which more options can only help": choices
per axis keyed to a parent part's distinct intervals, with no pruning that could remove the
optimum, on the grounds that "there are only ~5 distinct intervals per part and axis across
today's candidates".  This script measures the space such a design would have to hold.

For every part and axis it builds the **closure** of the intervals an anchor can produce, with
the generator's own rules (``h2s_print.candidates``) and no pruning at all:

* level 0: the input interval;
* level k: every interval of a part made from the level k-1 intervals of a related part (any
  relation: coplanar, bisector, coaxial) at the catalogue ratios (``ALIGN_ONLY`` for a flat
  parent): a pair of anchored ``lo``/``hi`` ends, one anchored end with the input length kept,
  one anchored end with the other end kept where it was, or an anchored mid-plane with the
  input length kept; an end within reach (1.5 x the change limit, the mid-plane within the
  change limit) of the input's; every interval within ``solver.max_change`` of the input (the
  same test, ``candidates._within_change``); the start part keeps its input only.

Depth ``k`` is the paper's level ``k`` (``solver.depth``, default 2).  The script prints, per
model and depth, the distinct intervals over all parts and axes (total, largest per part and
axis, median), and, for comparison, the distinct intervals per part and axis among today's
candidates (``generate_candidates`` with the config's settings, pruned).  A closure that passes
``--cap`` intervals is cut off and shown as ``>cap``.

Not a test: figures, printed as a table.
"""

from __future__ import annotations

import argparse
import datetime
import logging
import os
import platform
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from h2s_print.candidates import (DEGENERATE, _norm_length, _within_change,  # noqa: E402
                                  generate_candidates)
from h2s_print.config import load_tutorial  # noqa: E402
from h2s_print.fit import fit_primitives  # noqa: E402
from h2s_print.load import load_model  # noqa: E402
from h2s_print.order import start_part  # noqa: E402
from h2s_print.ratios import ALIGN_ONLY, CATALOGUE  # noqa: E402
from h2s_print.relate import detect_relations  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = ("camera", "mixer", "train", "roller")

Interval = tuple[float, float]


class Capped(Exception):
    """The closure passed the cap."""


def _level(prims, neighbours, intervals, start, max_change, cap):
    """One level of the closure: ``intervals`` (part, axis) -> set, extended."""
    out = {key: set(v) for key, v in intervals.items()}
    total = sum(len(v) for v in out.values())
    for part, prim in prims.items():
        if part == start or prim.type == "custom":
            continue
        box = prim.box
        for axis in range(3):
            lo0, hi0 = box[0][axis], box[1][axis]
            length, mid0 = hi0 - lo0, 0.5 * (lo0 + hi0)
            norm = _norm_length(box, axis)
            reach, reach_mid = 1.5 * max_change * norm * (1 + 1e-9), max_change * norm * (1 + 1e-9)
            los, his, mids = set(), set(), set()
            for other in neighbours.get(part, ()):
                for plo, phi in intervals[other, axis]:
                    big = max(abs(plo), abs(phi), 1e-300)
                    entries = ALIGN_ONLY if phi - plo <= DEGENERATE * big else CATALOGUE
                    for entry in entries:
                        v = plo + entry.ratio * (phi - plo)
                        if abs(v - lo0) <= reach:
                            los.add(v)
                        if abs(v - hi0) <= reach:
                            his.add(v)
                        if abs(v - mid0) <= reach_mid:
                            mids.add(v)
            made: set[Interval] = set()
            if length <= DEGENERATE * max(norm, 1e-300):
                made |= {(v, v) for v in los}
            else:
                for lo in los:
                    made |= {(lo, hi) for hi in his if hi > lo}
                    made |= {(lo, lo + length), (lo, hi0)}
                for hi in his:
                    made |= {(hi - length, hi), (lo0, hi)}
                made |= {(m - 0.5 * length, m + 0.5 * length) for m in mids}
            new = {iv for iv in made if _within_change(box, axis, iv[0], iv[1], max_change)}
            before = len(out[part, axis])
            out[part, axis] |= new
            total += len(out[part, axis]) - before
            if total > cap:
                raise Capped
    return out


def closure_sizes(prims, relations, max_change, depth, cap):
    """Per depth 1..``depth``: the sorted closure sizes per (part, axis), or None past ``cap``."""
    by_name = {p.part: p for p in prims}
    neighbours: dict[str, set[str]] = {}
    for r in relations:
        neighbours.setdefault(r.a, set()).add(r.b)
        neighbours.setdefault(r.b, set()).add(r.a)
    intervals = {(p.part, a): {(p.box[0][a], p.box[1][a])} for p in prims for a in range(3)}
    start = start_part(prims)
    out: list[list[int] | None] = []
    for _ in range(depth):
        try:
            intervals = _level(by_name, neighbours, intervals, start, max_change, cap)
        except Capped:
            out += [None] * (depth - len(out))
            break
        out.append(sorted(len(v) for v in intervals.values()))
    return out


def today_sizes(prims, relations, settings) -> list[int]:
    """Distinct intervals per (part, axis) among today's (pruned) candidates."""
    seen: dict[tuple[str, int], set[Interval]] = {}
    for c in generate_candidates(prims, relations, settings):
        for a in range(3):
            seen.setdefault((c.part, a), set()).add((c.box[0][a], c.box[1][a]))
    return sorted(len(v) for v in seen.values())


def _cell(sizes: list[int] | None, cap: int) -> str:
    if sizes is None:
        return f"{'>' + format(cap, ','):>12} {'':>9} {'':>7}"
    return f"{sum(sizes):>12,} {sizes[-1]:>9,} {statistics.median(sizes):>7g}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", help="comma-separated config names (default: all)")
    ap.add_argument("--depth", type=int, default=2)
    ap.add_argument("--cap", type=int, default=2_000_000)
    args = ap.parse_args()
    logging.basicConfig(level=logging.ERROR)
    paths = ([REPO / "configs" / f"{n}.yaml" for n in EXAMPLES]
             + sorted((REPO / "benchmarks" / "configs").glob("*.yaml")))
    if args.models:
        wanted = {n.strip() for n in args.models.split(",")}
        paths = [p for p in paths if p.stem in wanted]
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    print(f"date: {datetime.date.today().isoformat()}  machine: {platform.machine()}, "
          f"{cores} cores, Python {platform.python_version()}")
    head = f"{'model':<14} {'parts':>5} {'depth':>5} {'intervals':>12} {'max/axis':>9} {'median':>7}"
    print(head + f" {'seconds':>7}")
    print("-" * (len(head) + 8), flush=True)
    for path in paths:
        tutorial = load_tutorial(path)
        if not tutorial.model.path.exists():
            print(f"{path.stem:<14} skipped: {tutorial.model.path} is absent", flush=True)
            continue
        prims = fit_primitives(load_model(tutorial.model))
        relations = detect_relations(prims)
        sizes = today_sizes(prims, relations, tutorial.solver)
        print(f"{path.stem:<14} {len(prims):>5} {'today':>5} {_cell(sizes, args.cap)}", flush=True)
        t0 = time.perf_counter()
        rows = closure_sizes(prims, relations, tutorial.solver.max_change, args.depth, args.cap)
        seconds = time.perf_counter() - t0
        for k, row in enumerate(rows, 1):
            print(f"{'':<14} {'':>5} {k:>5} {_cell(row, args.cap)}"
                  + (f" {seconds:>7.1f}" if k == len(rows) else ""), flush=True)


if __name__ == "__main__":
    main()
