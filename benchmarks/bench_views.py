"""Benchmark: the novice tutorials from views nobody tuned, on the teaching benchmark's models.

Run: ``python3 benchmarks/bench_views.py [--models camera,desk_fredrik]``

The configs name one or two views each, and every teaching figure of ``bench_teaching.py`` is
measured there.  Here each model (the four examples, then ``benchmarks/configs/``; a model
whose file is absent is skipped) is planned once for a sweep of 16 views (azimuth -150, -100,
-60, -20, 20, 60, 100, 150 degrees; elevation 12 degrees two-point and 35 degrees three-point;
the config's first view's distance, a 50 mm lens) and its novice tutorial sequenced in each.
The benchmark's generated assemblies (``bench_pipeline``'s boxes, ``--generated 10,20`` by
default; ``--generated ""`` for none) follow, written to a temporary folder.
Printed per model: steps, words per step (the step's text, headline and numbered sub-steps:
``len(text.split())``) median and max, steps over ``MAX_STEP_WORDS``, turns said "(by eye)"
and steps placing a part by eye.  Not a test: a table to read (README, *Teaching*).
"""

from __future__ import annotations

import argparse
import datetime
import logging
import os
import platform
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from h2s_print import sequence as seq  # noqa: E402
from h2s_print.config import ViewSpec, load_tutorial  # noqa: E402
from h2s_print.errors import H2SError  # noqa: E402
from h2s_print.plan import build_plan  # noqa: E402
from h2s_print.sequence.drafts import MAX_STEP_WORDS  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = ("camera", "mixer", "train", "roller")
AZIMUTHS = (-150, -100, -60, -20, 20, 60, 100, 150)
ELEVATIONS = ((12, "two-point"), (35, "three-point"))


def sweep(first: ViewSpec) -> tuple[ViewSpec, ...]:
    """The 16 views of the sweep (module docstring)."""
    return tuple(ViewSpec(f"a{az}e{el}", az, el, first.distance, 50.0, persp)
                 for az in AZIMUTHS for el, persp in ELEVATIONS)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--models", default="", help="comma-separated config names")
    parser.add_argument("--generated", default="10,20",
                        help="comma-separated part counts of generated assemblies")
    args = parser.parse_args()
    logging.disable(logging.WARNING)
    configs = ([REPO / "configs" / f"{n}.yaml" for n in EXAMPLES]
               + sorted((REPO / "benchmarks" / "configs").glob("*.yaml")))
    if args.models:
        keep = set(args.models.split(","))
        configs = [c for c in configs if c.stem in keep]
    folder = tempfile.TemporaryDirectory()
    if args.generated:
        sys.path.insert(0, str(REPO / "benchmarks"))
        from bench_pipeline import _write_generated
        configs += [_write_generated(int(n), Path(folder.name))
                    for n in args.generated.split(",")]
    print(f"date: {datetime.date.today()}  machine: {platform.machine()}, {os.cpu_count()} cores"
          f" (nproc), Python {platform.python_version()}, {platform.system()}")
    print(f"{len(AZIMUTHS) * len(ELEVATIONS)} views a model, novice, limit {MAX_STEP_WORDS} words")
    head = f"{'model':14} {'steps':>6} {'words med':>10} {'max':>4} {'over':>5} " \
           f"{'by-eye turns':>13} {'by-eye parts':>13}"
    print(head)
    print("-" * len(head))
    every: list[int] = []
    total_over = total_turns = total_eyed = 0
    for config in configs:
        try:
            t = load_tutorial(config)
        except H2SError as exc:  # a public model not at hand
            print(f"{config.stem:14} skipped: {exc}")
            continue
        views = sweep(t.views[0])
        plan = build_plan(t.model, t.solver, views)
        words: list[int] = []
        turns = eyed = 0
        for view in views:
            vp = seq.sequence_view(plan, view, "novice", t.paper, t.sequence)
            for s in vp.steps:
                words.append(len(s.text.split()))
                turns += s.text.count("(by eye), then")
                eyed += s.kind == "primitive" and s.eyeball
        over = sum(w > MAX_STEP_WORDS for w in words)
        every += words
        total_over, total_turns, total_eyed = total_over + over, total_turns + turns, \
            total_eyed + eyed
        print(f"{config.stem:14} {len(words):6d} {statistics.median(words):10g} {max(words):4d} "
              f"{over:5d} {turns:13d} {eyed:13d}", flush=True)
    print("-" * len(head))
    print(f"{'all':14} {len(every):6d} {statistics.median(every):10g} {max(every):4d} "
          f"{total_over:5d} {total_turns:13d} {total_eyed:13d}")


if __name__ == "__main__":
    main()
