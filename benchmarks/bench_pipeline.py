"""Benchmark: seconds per pipeline stage and peak memory, per model (not a test).

Run: ``python3 benchmarks/bench_pipeline.py [--models camera,gen40] [--json FILE]``

Models: the four examples (``configs/{camera,mixer,train,roller}.yaml``), every config in
``benchmarks/configs/`` (public models under ``../shared/models``; absent ones are skipped with
one line), generated assemblies of 10, 20, 40 and 80 boxes (``gen10`` ... ``gen80``: the
seeded face-to-face models of ``bench_select.make_model``, written as GLB) and ``dense``, a
generated 8-part model of about 130 000 triangles (finely tessellated cylinders and subdivided
boxes).  Generated models get two views (front-left two-point, high-right three-point) and
the novice level.

Each model runs in a fresh Python process, so its *peak MB* (the process's maximum resident
set size) is its own.  Stages, timed with ``time.perf_counter`` around each stage function:

* **load** ``load.load_model``; **fit** ``fit.fit_primitives``; **relate**
  ``relate.detect_relations``; **cand** ``candidates.generate_candidates``; **select**
  ``select.select_candidates``; **refine** ``plan.refine`` (the rounds off the
  selection; these stages are the plan, as ``h2s plan`` without the cache);
* **seq** ``sequence.sequence_views`` for every view at the config's levels, plus the finished
  drawing per workbook (``sequence.sequence_workbooks``, as the pipeline calls it), *less* the
  time spent in contour tracing and hidden-line removal called from there (the sequence
  module's ``final_contours`` and ``own_contours`` and the occlusion tests the latter returns),
  which is
  **contours**;
* **layout** ``layout.lay_out_workbook`` per workbook; **render** ``render.pdf_bytes`` per
  workbook.

*total* is their sum.  Everything is sequential (one core of the machine's two).
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))
sys.path.insert(0, str(REPO / "benchmarks"))

EXAMPLES = ("camera", "mixer", "train", "roller")
GENERATED = (10, 20, 40, 80)
STAGES = ("load", "fit", "relate", "cand", "select", "refine", "seq", "contours", "layout",
          "render")
VIEWS = """views:
  - {name: front-left, azimuth_deg: -35, elevation_deg: 20, distance: 3.0, lens_mm: 50,
     perspective: two-point}
  - {name: high-right, azimuth_deg: 40, elevation_deg: 30, distance: 3.2, lens_mm: 50,
     perspective: three-point}
levels: [novice]
paper: {size: A4, orientation: landscape, margin_mm: 12}
"""


# ----------------------------------------------------------------------------- models


def _write_generated(n: int, folder: Path) -> Path:
    import numpy as np
    import trimesh

    from bench_select import make_model

    scene = trimesh.Scene()
    for prim in make_model(n, 0):
        lo, hi = np.asarray(prim.box[0]), np.asarray(prim.box[1])
        mesh = trimesh.creation.box(extents=hi - lo)
        mesh.apply_translation((lo + hi) / 2)
        scene.add_geometry(mesh, node_name=prim.part, geom_name=prim.part)
    glb = folder / f"gen{n}.glb"
    glb.write_bytes(scene.export(file_type="glb"))
    cfg = folder / f"gen{n}.yaml"
    cfg.write_text(f"title: generated {n}\nmodel: {{path: {glb.name}, up: z, units: mm,"
                   f" parts: {{small: keep}}}}\n{VIEWS}solver: {{max_change: 0.3}}\n")
    return cfg


def _write_dense(folder: Path) -> Path:
    """A table-top machine of about 130k triangles: a subdivided base and housing, drums and
    rollers tessellated finely."""
    import numpy as np
    import trimesh

    def box(ext, at, size):
        m = trimesh.creation.box(ext)
        v, f = trimesh.remesh.subdivide_to_size(m.vertices, m.faces, size)
        m = trimesh.Trimesh(v, f, process=False)
        m.apply_translation(at)
        return m

    def cyl(r, h, at, axis, sections):
        m = trimesh.creation.cylinder(r, h, sections=sections)
        if axis == "x":
            m.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [0, 1, 0]))
        if axis == "y":
            m.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
        m.apply_translation(at)
        return m

    parts = {
        "base": box((600, 400, 60), (0, 0, 30), 12),
        "housing": box((300, 300, 250), (-100, 0, 185), 12),
        "drum": cyl(120, 200, (200, 0, 180), "y", 6000),
        "roller_front": cyl(40, 380, (120, -100, 100), "y", 4000),
        "roller_back": cyl(40, 380, (120, 100, 100), "y", 4000),
        "knob": cyl(30, 40, (-100, -170, 250), "y", 3000),
        "lid": box((320, 320, 20), (-100, 0, 320), 10),
        "chute": box((80, 120, 150), (300, 0, 335), 8),
    }
    scene = trimesh.Scene()
    for name, mesh in parts.items():
        scene.add_geometry(mesh, node_name=name, geom_name=name)
    glb = folder / "dense.glb"
    glb.write_bytes(scene.export(file_type="glb"))
    cfg = folder / "dense.yaml"
    cfg.write_text(f"title: dense\nmodel: {{path: {glb.name}, up: z, units: mm}}\n{VIEWS}")
    return cfg


def model_configs(folder: Path, wanted: set[str] | None) -> list[tuple[str, Path]]:
    out = [(n, REPO / "configs" / f"{n}.yaml") for n in EXAMPLES]
    out += [(p.stem, p) for p in sorted((REPO / "benchmarks" / "configs").glob("*.yaml"))]
    names = [f"gen{n}" for n in GENERATED] + ["dense"]
    for name in names:
        if wanted is None or name in wanted:
            out.append((name, _write_dense(folder) if name == "dense"
                        else _write_generated(int(name[3:]), folder)))
    return [(n, p) for n, p in out if wanted is None or n in wanted]


# ----------------------------------------------------------------------------- one model


def measure(config: Path) -> dict[str, Any]:
    """Every stage of one config, in this process (module docstring)."""
    from h2s_print import sequence as seq
    from h2s_print.candidates import generate_candidates
    from h2s_print.config import load_tutorial
    from h2s_print.fit import fit_primitives
    from h2s_print.layout import lay_out_workbook
    from h2s_print.load import load_model
    from h2s_print.plan import Plan, part_farness, refine
    from h2s_print.relate import detect_relations
    from h2s_print.render import pdf_bytes
    from h2s_print.select import select_candidates

    t = load_tutorial(config)
    if not t.model.path.exists():
        return {"skipped": f"{t.model.path} is absent"}
    secs = dict.fromkeys(STAGES, 0.0)

    def timed(stage: str, fn, *args, **kwargs):
        start = time.perf_counter()
        out = fn(*args, **kwargs)
        secs[stage] += time.perf_counter() - start
        return out

    model = timed("load", load_model, t.model)
    prims = timed("fit", fit_primitives, model)
    rels = timed("relate", detect_relations, prims)
    cands = timed("cand", generate_candidates, prims, rels, t.solver)
    far = part_farness(prims, t.views)  # ties nearest first, as build_plan
    sel = timed("select", select_candidates, cands, rels, t.solver, farness=far)
    cands, sel = timed("refine", refine, prims, rels, t.solver, cands, sel, far)
    plan = Plan(model, prims, rels, tuple(cands) + tuple(sel.stand_ins), sel, t.solver)

    # contour work called from the sequence stage, timed apart
    contour_s = [0.0]
    originals = {}
    def clocked(fn):
        def wrapped(*args, **kwargs):
            start = time.perf_counter()
            try:
                out = fn(*args, **kwargs)
            finally:
                contour_s[0] += time.perf_counter() - start
            if fn is originals.get("own_contours"):  # its occlusion tests are contour work too
                sets, tests = out
                return sets, tuple(clocked(t) for t in tests)
            return out
        return wrapped

    # the sequence package's modules that call them, each patched where it looks them up
    import importlib
    import pkgutil
    modules = [seq] + [importlib.import_module(f"{seq.__name__}.{m.name}")
                       for m in pkgutil.iter_modules(seq.__path__)]
    patched = []  # (module, name, original)
    for name in ("final_contours", "own_contours"):
        for mod in modules:
            if hasattr(mod, name):
                originals[name] = getattr(mod, name)
                patched.append((mod, name, originals[name]))
    for mod, name, fn in patched:
        setattr(mod, name, clocked(fn))
    try:
        start = time.perf_counter()
        views, finals = [], []
        for view in t.views:
            for vp, final in seq.sequence_workbooks(plan, view, t.levels, t.paper, t.sequence):
                views.append(vp)
                finals.append(final)
        secs["seq"] = time.perf_counter() - start - contour_s[0]
        secs["contours"] = contour_s[0]
    finally:
        for mod, name, fn in patched:
            setattr(mod, name, fn)
    books = [timed("layout", lay_out_workbook, t.title, vp, t.paper, view_label=vp.name,
                   final=final, grid=t.sheet.grid) for vp, final in zip(views, finals)]
    for pages in books:
        timed("render", pdf_bytes, pages)
    return {
        "parts": len(model.parts),
        "triangles": int(sum(len(p.faces) for p in model.parts)),
        "candidates": len(plan.candidates),
        "workbooks": len(views),
        "seconds": secs,
        "total": sum(secs.values()),
        "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
        "status": sel.status,
    }


# ----------------------------------------------------------------------------- table


def header() -> str:
    cols = "".join(f"{s:>8}" for s in STAGES)
    return f"{'model':<14}{'parts':>6}{'tris':>8}{cols}{'total':>8}{'peak MB':>9}"


def row(name: str, r: dict[str, Any]) -> str:
    if "skipped" in r or "error" in r:
        return f"{name:<14} {r.get('skipped') or r.get('error')}"
    cols = "".join(f"{r['seconds'][s]:>8.2f}" for s in STAGES)
    return (f"{name:<14}{r['parts']:>6}{r['triangles']:>8}{cols}{r['total']:>8.2f}"
            f"{r['peak_mb']:>9.0f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", help="comma-separated names (camera, chair_ingolf, gen40, dense)")
    ap.add_argument("--json", type=Path, help="write the raw figures to this file")
    ap.add_argument("--one", type=Path, help=argparse.SUPPRESS)  # child process: one config
    args = ap.parse_args()
    if args.one is not None:
        import logging

        logging.basicConfig(level=logging.ERROR)
        try:
            out = measure(args.one)
        except Exception as exc:  # noqa: BLE001 - reported as the model's row
            out = {"error": f"{type(exc).__name__}: {exc}"}
        print(json.dumps(out))
        return
    wanted = None if not args.models else {m.strip() for m in args.models.split(",")}
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    print(f"date: {datetime.date.today().isoformat()}  machine: {platform.machine()}, "
          f"{cores} cores (nproc), Python {platform.python_version()}, {platform.system()}")
    print(header())
    print("-" * len(header()), flush=True)
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, cfg in model_configs(Path(tmp), wanted):
            proc = subprocess.run([sys.executable, __file__, "--one", str(cfg)],
                                  capture_output=True, text=True, cwd=REPO)
            try:
                results[name] = json.loads(proc.stdout.strip().splitlines()[-1])
            except (IndexError, json.JSONDecodeError):
                results[name] = {"error": (proc.stderr.strip().splitlines() or ["failed"])[-1]}
            print(row(name, results[name]), flush=True)
    if args.json:
        args.json.write_text(json.dumps(results, indent=1, sort_keys=True) + "\n")


if __name__ == "__main__":
    main()
