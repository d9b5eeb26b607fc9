"""Benchmark: candidate generation and SCIP selection on the example models and on generated models of 10-80 parts.

Run: ``python3 benchmarks/bench_select.py [--sizes 10 20 40 80] [--seed 1] [--time-limit 30]``

The example models (``configs/*.yaml``, loaded and fitted as ``h2s plan`` does) come first,
then the generated ones.

Models are generated (seeded) the way man-made objects are built: boxes, cylinders and frusta
attached to a face of an earlier part, flush with it, spanning roughly easy fractions of it with
some noise, sometimes flush with its edges, so coplanar and bisector relations exist.
Relations come from ``h2s_print.relate.detect_relations``.  Prints one row per size and
formulation: parts, relations (preserved), candidates, constraints, generation and solver
seconds, objective, status, and how many parts were drawn anchored.
"""

from __future__ import annotations

import argparse
import dataclasses
import logging
import random
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from h2s_print.candidates import generate_candidates  # noqa: E402
from h2s_print.config import SolverSettings  # noqa: E402
from h2s_print.relate import detect_relations  # noqa: E402
from h2s_print.select import build_selection_model, solve_selection_model  # noqa: E402
from h2s_print.types import Primitive  # noqa: E402

EASY_LO = (0.0, 0.25, 1 / 3, 0.5)
EASY_HI = (0.5, 2 / 3, 0.75, 1.0)


def make_model(n_parts: int, seed: int) -> list[Primitive]:
    """``n_parts`` primitives attached face to face (seeded)."""
    rng = random.Random(seed)
    size = (rng.uniform(8, 12), rng.uniform(4, 8), rng.uniform(5, 9))
    prims = [Primitive("p00", "cuboid", None, ((0.0, 0.0, 0.0), size), 0.0)]
    while len(prims) < n_parts:
        # larger, earlier parts carry more attachments
        parent = prims[min(int(rng.expovariate(1.0 / max(1.0, len(prims) / 3))), len(prims) - 1)]
        plo, phi = parent.box
        ext = [phi[a] - plo[a] for a in range(3)]
        n = rng.randrange(3)
        side = rng.randrange(2)
        lo, hi = [0.0] * 3, [0.0] * 3
        depth = ext[n] * rng.choice((0.25, 0.5, 1.0)) * rng.uniform(0.93, 1.07)
        if side == 0:
            lo[n], hi[n] = plo[n] - depth, plo[n]
        else:
            lo[n], hi[n] = phi[n], phi[n] + depth
        for a in range(3):
            if a == n:
                continue
            flo, fhi = rng.choice(EASY_LO), rng.choice(EASY_HI)
            if fhi - flo < 0.2:
                flo, fhi = 0.25, 0.75
            noise = 0.0 if rng.random() < 0.3 else 0.03
            lo[a] = plo[a] + (flo + rng.uniform(-noise, noise)) * ext[a]
            hi[a] = plo[a] + (fhi + rng.uniform(-noise, noise)) * ext[a]
        kind = rng.choices(("cuboid", "cylinder", "frustum"), (0.7, 0.2, 0.1))[0]
        axis = None
        detail: dict = {}
        if kind != "cuboid":
            axis = n
            u, v = (a for a in range(3) if a != n)
            r = min(hi[u] - lo[u], hi[v] - lo[v]) / 2
            cu, cv = (lo[u] + hi[u]) / 2, (lo[v] + hi[v]) / 2
            lo[u], hi[u], lo[v], hi[v] = cu - r, cu + r, cv - r, cv + r
            detail = {"centre": [cu, cv]}
        prims.append(Primitive(f"p{len(prims):02d}", kind, axis, (tuple(lo), tuple(hi)), 0.0,
                               detail))
    return prims


EXAMPLES = ("camera", "mixer", "train", "roller")


def example_primitives(name: str) -> list[Primitive]:
    """The fitted primitives of an example config's model."""
    from h2s_print.config import load_tutorial
    from h2s_print.fit import fit_primitives
    from h2s_print.load import load_model

    tutorial = load_tutorial(Path(__file__).resolve().parents[1] / "configs" / f"{name}.yaml")
    return list(fit_primitives(load_model(tutorial.model)))


def run(sizes: list[int], seed: int, time_limit: float) -> None:
    header = (f"{'model':>8} {'parts':>5} {'rels':>9} {'cands':>6} {'gen s':>6} {'formulation':>11} "
              f"{'constr':>7} {'build s':>7} {'solve s':>7} {'objective':>10} {'status':>10} "
              f"{'anchored':>8}")
    print(header)
    print("-" * len(header))
    cases = [(name, lambda name=name: example_primitives(name)) for name in EXAMPLES]
    cases += [(f"gen{n}", lambda n=n: make_model(n, seed + n)) for n in sizes]
    for label, make in cases:
        prims = make()
        n = len(prims)
        rels = detect_relations(prims)
        n_pres = sum(1 for r in rels if r.detail.get("preserved"))
        settings = SolverSettings(time_limit_s=time_limit)
        t0 = time.perf_counter()
        cands = generate_candidates(prims, rels, settings)
        gen_s = time.perf_counter() - t0
        by_id = {c.id: c for c in cands}
        for form in ("linear", "quadratic"):
            s = dataclasses.replace(settings, formulation=form)
            t1 = time.perf_counter()
            model = build_selection_model(cands, rels, s)
            build_s = time.perf_counter() - t1
            sel = solve_selection_model(model)
            known = {**by_id, **{c.id: c for c in sel.stand_ins}}
            anchored = sum(1 for i in sel.chosen if known[i].anchors)
            print(f"{label:>8} {n:>5} {len(rels):>4}({n_pres:>3}) {len(cands):>6} {gen_s:>6.2f} {form:>11} "
                  f"{sel.n_constraints:>7} {build_s:>7.2f} {sel.seconds:>7.2f} "
                  f"{sel.objective:>10.3f} {sel.status:>10} {anchored:>4}/{n:<3}", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10, 20, 40, 80])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--time-limit", type=float, default=30.0,
                        help="SCIP time limit per solve, seconds")
    args = parser.parse_args()
    logging.basicConfig(level=logging.ERROR)
    run(args.sizes, args.seed, args.time_limit)


if __name__ == "__main__":
    main()
