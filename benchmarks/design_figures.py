"""DESIGN.md §5's teaching figures, computed from a plan.json document alone.

Run on files: ``python3 benchmarks/design_figures.py OUT/*/plan.json`` (what ``h2s plan``
writes); ``bench_teaching.py`` prints the same table for its models.  Nothing here imports
h2s_print: the figures are read off the contract (DESIGN.md §3) the way another tool would.

Per tutorial, on the first view at its first level that is not ``basic`` (plan.json lists the
views in config order, each view's levels in config order):

* **anchored ends**: over the selected candidates, the distinct (axis, end) pairs that carry an
  anchor (``lo``, ``hi``, ``mid``; at most two per axis, so a plane's normal anchored at both
  ends counts two), divided by 6 x parts.
* **by eye**: ``primitive`` steps with ``eyeball`` true or no guides, over all ``primitive``
  steps (the first step included: it has no guides).
* **inversions**: ``primitive`` steps after the first whose part is followed, later, by a part
  that does not descend from it in the anchoring (the selected candidates' parents, their
  parents ...) and whose selected box's largest face is over 4 x its own.
* **start**: the first ``primitive`` step's part is the largest (largest face of the selected
  box) of the drawn parts, or stands on the ground (box bottom within 3 % of the model's height
  of the model's bottom) and is at least half as large.
* **beyond**: parts whose primitive box leaves the part's own bounding box (``parts[].bounds``)
  by more than 1 % of that box's diagonal.
* **words**: whitespace-separated words of each ``primitive`` step's ``text``.
* **steps per shape**: all steps of the view over the distinct (primitive type, sorted box
  extents rounded to 1 % of the model's diagonal) among the parts.
"""

from __future__ import annotations

import json
import math
import statistics
import sys
from typing import Any


def _largest_face(box: list[list[float]]) -> float:
    e = sorted(box[1][a] - box[0][a] for a in range(3))
    return e[1] * e[2]


def _view(plan: dict[str, Any]) -> dict[str, Any] | None:
    return next((v for v in plan["views"] if v["level"] != "basic"), None)


def figures(plan: dict[str, Any]) -> dict[str, Any]:
    """The §5 figures of one plan.json document, raw counts (module docstring)."""
    cands = {c["id"]: c for c in plan["candidates"]}
    chosen = {cands[i]["part"]: cands[i] for i in plan["selection"]["selected"]}
    anchored = 0
    for c in chosen.values():
        per_axis: dict[int, set[str]] = {}
        for a in c["anchors"]:
            per_axis.setdefault(a["axis"], set()).add(a["end"])
        anchored += sum(min(2, len(ends)) for ends in per_axis.values())
    parents: dict[str, set[str]] = {p: {cands[q]["part"] for q in c["parents"]} - {p}
                                    for p, c in chosen.items()}

    def descends(b: str, a: str) -> bool:  # b hangs off a, directly or through others
        seen, todo = set(), [b]
        while todo:
            x = todo.pop()
            for p in parents.get(x, ()):
                if p == a:
                    return True
                if p not in seen:
                    seen.add(p)
                    todo.append(p)
        return False

    out: dict[str, Any] = {"parts": len(plan["parts"]), "anchored": anchored,
                           "ends": 6 * len(plan["parts"])}
    lo, hi = plan["model"]["bounds"]
    diag = math.dist(lo, hi)
    beyond = 0
    for p in plan["parts"]:
        b = p.get("bounds")
        if b is None:
            continue
        tol = 0.01 * math.dist(b[0], b[1])
        box = p["primitive"]["box"]
        beyond += any(b[0][a] - box[0][a] > tol or box[1][a] - b[1][a] > tol for a in range(3))
    out["beyond"] = beyond
    out["bounds_known"] = all("bounds" in p for p in plan["parts"])
    shapes = {(p["primitive"]["type"],
               tuple(sorted(round((p["primitive"]["box"][1][a] - p["primitive"]["box"][0][a])
                                  / (0.01 * diag)) for a in range(3))))
              for p in plan["parts"]}
    view = _view(plan)
    if view is None:
        return {**out, "view": None}
    prim = [s for s in view["steps"] if s["kind"] == "primitive"]
    order = [s["part"] for s in prim]
    size = {p: _largest_face(c["box"]) for p, c in chosen.items()}
    inv = 0
    for i, a in enumerate(order[1:], start=1):
        if any(size[b] > 4 * size[a] and not descends(b, a) for b in order[i + 1:] if b != a):
            inv += 1
    start = False
    if order:
        first = order[0]
        height = hi[2] - lo[2]
        grounded = chosen[first]["box"][0][2] - lo[2] <= 0.03 * height
        biggest = max(size[p] for p in order)
        start = size[first] >= biggest or (grounded and size[first] >= 0.5 * biggest)
    words = [len(s["text"].split()) for s in prim]
    out.update({
        "view": f"{view['name']}/{view['level']}",
        "by_eye": sum(1 for s in prim if s["eyeball"] or not s["guides"]), "primitive": len(prim),
        "inversions": inv, "start": start, "words": words,
        "steps": len(view["steps"]), "shapes": len(shapes),
    })
    return out


HEADER = (f"{'model':<14} {'view':<20} {'anchored%':>9} {'by eye':>7} {'inv':>4} {'start':>5} "
          f"{'beyond':>6} {'words med/max':>13} {'steps/shape':>11}")


def row(name: str, f: dict[str, Any]) -> str:
    if f.get("view") is None:
        return f"{name:<14} (no guided view)"
    words = f"{statistics.median(f['words']):g}/{max(f['words'])}" if f["words"] else "-"
    return (f"{name:<14} {f['view']:<20} {100 * f['anchored'] / f['ends']:>9.1f} "
            f"{f['by_eye']:>3}/{f['primitive']:<3} {f['inversions']:>4} "
            f"{'yes' if f['start'] else 'no':>5} {f['beyond']:>6} {words:>13} "
            f"{f['steps'] / f['shapes']:>11.2f}")


def total(rows: list[dict[str, Any]]) -> str:
    ok = [f for f in rows if f.get("view")]
    words = [w for f in ok for w in f["words"]]
    anchored = sum(f["anchored"] for f in ok) / max(1, sum(f["ends"] for f in ok))
    eye = sum(f["by_eye"] for f in ok) / max(1, sum(f["primitive"] for f in ok))
    return (f"{'all':<14} anchored {100 * anchored:.1f} %, by eye {100 * eye:.1f} %, inversions "
            f"{sum(f['inversions'] for f in ok)}, start {sum(f['start'] for f in ok)}/{len(ok)}, "
            f"beyond {sum(f['beyond'] for f in ok)}, words median "
            f"{statistics.median(words) if words else 0:g} max {max(words, default=0)}, "
            f"steps per shape max {max((f['steps'] / f['shapes'] for f in ok), default=0):.2f}")


def main(paths: list[str]) -> None:
    print(HEADER)
    print("-" * len(HEADER))
    rows = []
    for path in paths:
        with open(path, encoding="utf-8") as fh:
            f = figures(json.load(fh))
        rows.append(f)
        name = path.rstrip("/").split("/")[-2] if "/" in path else path
        print(row(name, f))
    print("-" * len(HEADER))
    print(total(rows))


if __name__ == "__main__":
    main(sys.argv[1:])
