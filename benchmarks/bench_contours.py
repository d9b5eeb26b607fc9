"""Benchmark of the contours stage: a ~100k-triangle scene, one view, each phase and HLR engine.

Run: ``python3 benchmarks/bench_contours.py [--triangles N] [--seed S]``.  Prints a table of
seconds per phase (weld + edge table, edge classification, hidden-line removal and chaining,
suggestive contours) for the z-buffer and the ray engine, and the polyline counts of each so
their results can be compared.  Target: under 5 s in total for one view on two cores.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from h2s_print import contours as C  # noqa: E402
from h2s_print.config import PaperSpec, ViewSpec  # noqa: E402
from h2s_print.project import make_camera  # noqa: E402
from h2s_print.types import Camera, Part, readonly  # noqa: E402


def view_camera(parts) -> Camera:
    """The project stage's own camera on ``parts``: a three-point view fitted to A4 landscape."""
    view = ViewSpec("bench", azimuth_deg=24.0, elevation_deg=17.0, distance=3.0,
                    perspective="three-point")
    return make_camera(view, np.concatenate([p.vertices for p in parts]), PaperSpec())


def scene(triangles: int, seed: int) -> list[Part]:
    """Seeded spheres and cylinders in front of each other, about ``triangles`` faces in total."""
    import trimesh

    rng = np.random.default_rng(seed)
    parts = []
    per = triangles // 6
    for i in range(6):
        centre = np.array([rng.uniform(-1.5, 1.5), -1.2 + 0.6 * i, rng.uniform(-0.5, 0.5)])
        if i % 2 == 0:
            sub = max(1, int(round(np.log(per / 20) / np.log(4))))  # 20 * 4**sub faces
            mesh = trimesh.creation.icosphere(subdivisions=sub, radius=rng.uniform(0.5, 0.9))
        else:
            mesh = trimesh.creation.cylinder(radius=rng.uniform(0.3, 0.6), height=rng.uniform(1.0, 2.0),
                                             sections=max(8, per // 64)).subdivide().subdivide()  # 4 * sections * 16 faces
        mesh.apply_translation(centre)
        parts.append(Part(f"p{i}", readonly(mesh.vertices, float), readonly(mesh.faces, np.int64)))
    return parts


def run(parts, camera, engine: str, suggestive: bool) -> dict[str, float]:
    cs = C.ContourSettings(engine=engine, suggestive=suggestive)
    times = {}
    t = time.perf_counter()
    meshes = [C._Mesh.of(p) for p in parts]
    times["weld+edges"] = time.perf_counter() - t
    t = time.perf_counter()
    for m in meshes:
        C._classify(m, camera, cs.crease_deg)
    times["classify"] = time.perf_counter() - t
    t = time.perf_counter()
    eng = C._make_engine(cs, camera, meshes)
    times["build engine"] = time.perf_counter() - t
    if suggestive:
        t = time.perf_counter()
        for m in meshes:
            C._suggestive(m, camera, cs)
        times["suggestive"] = time.perf_counter() - t
    t = time.perf_counter()
    sets = [C._trace_one(m, camera, cs, eng) for m in meshes]
    times["trace+HLR+chain"] = time.perf_counter() - t
    t = time.perf_counter()
    C.trace_contours(parts, camera, settings=cs, suggestive=suggestive)
    times["trace_contours total"] = time.perf_counter() - t
    times["polylines"] = sum(len(s.polylines3d) for s in sets)
    times["points"] = sum(len(p) for s in sets for p in s.polylines3d)
    times["visible mm"] = sum(float(np.linalg.norm(np.diff(np.asarray(p), axis=0), axis=1).sum())
                              for s in sets for p in s.polylines_mm)
    return times


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--triangles", type=int, default=100_000)
    ap.add_argument("--seed", type=int, default=7)
    args = ap.parse_args()
    parts = scene(args.triangles, args.seed)
    camera = view_camera(parts)
    nfaces = sum(len(p.faces) for p in parts)
    rows = {}
    for engine in ("grid", "zbuffer", "ray"):
        rows[engine] = run(parts, camera, engine, suggestive=False)
    rows["grid+sugg"] = run(parts, camera, "grid", suggestive=True)
    keys = list(dict.fromkeys(k for r in rows.values() for k in r))
    out = [f"scene: {len(parts)} parts, {nfaces} triangles, one view",
           f"{'phase':<22}" + "".join(f"{name:>14}" for name in rows)]
    for k in keys:
        cells = []
        for r in rows.values():
            v = r.get(k)
            cells.append(f"{'-':>14}" if v is None else (f"{v:>14.1f}" if k in ("polylines", "points", "visible mm")
                                                          else f"{v:>13.3f}s"))
        out.append(f"{k:<22}" + "".join(cells))
    sys.stdout.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
