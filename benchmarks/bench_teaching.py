"""Benchmark: how well the tutorials teach, on the example models and the public shared models.

Run: ``python3 benchmarks/bench_teaching.py [--models camera,chair_ingolf] [--json FILE]``

Models: the four examples (``configs/{camera,mixer,train,roller}.yaml``) and every config in
``benchmarks/configs/`` (public models under ``../shared/models``; a model whose file is absent
is skipped with one line).  For each: the plan (stages 1-5, :func:`h2s_print.plan.build_plan`,
as ``h2s plan`` without the cache) and, for every view of the config, the view plans at levels
``novice`` and ``master`` (:func:`h2s_print.sequence.sequence_views`, as the pipeline calls it).
Every figure below is computed from the novice view plans unless it says otherwise; the master
plans are built (their step counts and minutes go into ``--json``) so a failure there shows.

Columns (one row per model; "the selected candidate" of a part is ``plan.chosen()[part]``):

* **parts**: parts of the loaded model.
* **steps**: steps of the novice view plan of each view, per view, joined by ``/``.
* **anchored %**: over the selected candidates of all fitted parts (primitive type not
  ``custom``), per axis: an axis whose selected-box extent is zero (within
  ``candidates.DEGENERATE`` of the box's largest extent) has 1 degree of freedom, any other 2;
  the anchored count is the number of distinct ``anchor.end`` values on that axis (``lo``,
  ``hi``, and ``mid`` counting as one end), capped at the axis' degrees of freedom.
  100 × sum anchored / sum degrees of freedom.
* **by eye %**: over the primitive steps (kind ``primitive``) of every novice view plan except
  each plan's first primitive step, the share that are eyeballed (``step.eyeball``) or whose
  part's selected candidate has no anchors.
* **inv**: coarse-to-fine inversions, summed over the novice view plans: in the order of a
  plan's primitive steps, the pairs (A before B, A not the first primitive step) where
  size(B) > 4 × size(A) and neither part is an ancestor of the other in the anchoring graph
  (the parts of the selected candidates' ``parents``, transitively).  size is
  :func:`h2s_print.order.part_size` of the part's selected box (area of its largest face).
* **beyond**: parts whose fitted primitive box (``plan.primitives``) extends beyond the part
  mesh's own axis-aligned bounding box (``Part.box``) by more than 1 % of that bounding box's
  diagonal on any of its six sides.
* **start**: novice view plans whose first primitive step draws
  :func:`h2s_print.order.start_part` of ``plan.primitives``, over the number of views.
* **words med/max**: median and largest number of words (``text.split()``) of a step's text,
  over every step of every novice view plan.
* **new max**: the most guides with status ``new`` on one step, over the novice view plans.
* **minutes**: :func:`h2s_print.layout.estimate_minutes` of each novice view plan, lowest-highest.
* **plan s**: wall-clock seconds of ``build_plan`` (load, fit, relate, candidates, select);
  **select s**: SCIP's own solving time, ``plan.selection.seconds``.

A second table, **instructions** (issue 11): *shapes*, the distinct part shapes (parts grouped
by :meth:`h2s_print.sequence.repeats._Repeats.congruent` on their selected boxes); *steps* per view
(novice) against the *limit* 2.5 x shapes + 3; words per step (``text.split()``) of the novice
plans and of every level built; *id names*, steps whose text contains the raw name of a part
whose name :func:`h2s_print.names.display_names` does not keep; *minutes* as above.  Its last
line pools every step of every model.

A fourth table, **design**, prints DESIGN.md §5's figures as that section defines them,
computed from the plan.json document alone (``benchmarks/design_figures.py``, which does not
import h2s_print): first view, first guided level of the config, the first primitive step
counted in *by eye* (it has no guides), words of primitive steps only.

A third table, **pages** (issue 12), over the novice view plans of every view: *round*, the
parts fitted round (a cylinder, or a plane whose outline is round, ``detail["round"]``);
*ellipses*, the round parts drawn with ellipses per view summed, as ``constructed/by eye``
(a part in an ellipse step not eyeballed, or a part whose ellipses, seen or dotted, are only
sketched by eye: an eyeballed ellipse step or one joined to the outlines); *back-face*, anchors whose construction face
(:func:`h2s_print.sequence.geometry._anchor_face`) the view shows from behind (the camera position on
the inner side of the face's plane), over all anchors on faces; *hidden drawn*, parts a
primitive step draws that have no line in the finished drawing
(:func:`h2s_print.sequence.final_strokes`), summed over views, and how many of those a drawn
part's construction names as an anchor parent.

The totals row pools the ratios (sum of numerators over sum of denominators of all models that
planned) and sums inv, beyond and start.  A model whose plan or view plans fail gets a row with
the error instead (an ``H2SError`` by its message; anything else by its type, with the
traceback on stderr) and counts in no total.  Everything is sequential and, but for the
seconds, deterministic.
"""

from __future__ import annotations

import argparse
import datetime
import json
import logging
import os
import platform
import statistics
import sys
import time
import traceback
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from design_figures import HEADER as HEADER_DESIGN  # noqa: E402
from design_figures import figures as design_figures
from design_figures import row as design_row  # noqa: E402
from design_figures import total as design_total

from h2s_print import sequence as seq  # noqa: E402
from h2s_print.candidates import DEGENERATE  # noqa: E402
from h2s_print.config import TutorialConfig, load_tutorial  # noqa: E402
from h2s_print.errors import H2SError  # noqa: E402
from h2s_print.layout import estimate_minutes  # noqa: E402
from h2s_print.names import display_names  # noqa: E402
from h2s_print.order import part_size, start_part  # noqa: E402
from h2s_print.plan import Plan, build_plan, plan_json  # noqa: E402
from h2s_print.sequence import context as seq_context  # noqa: E402
from h2s_print.sequence import geometry as seq_geometry  # noqa: E402
from h2s_print.sequence import sequence_views  # noqa: E402
from h2s_print.types import ViewPlan  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = ("camera", "mixer", "train", "roller")
LEVELS = ("novice", "master")
#: An inversion: a later part more than this many times the size of an earlier one.
INVERSION_FACTOR = 4.0
#: A fitted box sticks out of its mesh's bounding box by more than this share of its diagonal.
BEYOND_FRACTION = 0.01


def config_paths() -> list[Path]:
    """The example configs, then the shared-model configs in name order."""
    return ([REPO / "configs" / f"{n}.yaml" for n in EXAMPLES]
            + sorted((REPO / "benchmarks" / "configs").glob("*.yaml")))


# ----------------------------------------------------------------------------- figures


def anchored_ends(plan: Plan) -> tuple[int, int]:
    """(anchored ends, degrees of freedom) over the selected candidates of fitted parts."""
    anchored = dof = 0
    for part, cand in plan.chosen().items():
        if plan.primitive(part).type == "custom":
            continue
        box = cand.box
        largest = max(float(box[1][a]) - float(box[0][a]) for a in range(3))
        for axis in range(3):
            flat = float(box[1][axis]) - float(box[0][axis]) <= DEGENERATE * largest
            free = 1 if flat else 2
            ends = {str(a.end) for a in cand.anchors if a.axis == axis}  # lo, hi, mid ...
            dof += free
            anchored += min(len(ends), free)
    return anchored, dof


def ancestors(plan: Plan) -> dict[str, frozenset[str]]:
    """Per part, every part it hangs off (selected candidates' parents, transitively)."""
    by_id = {c.id: c for c in plan.candidates}
    parents = {part: {by_id[p].part for p in cand.parents}
               for part, cand in plan.chosen().items()}
    out: dict[str, frozenset[str]] = {}

    def walk(part: str, seen: tuple[str, ...]) -> frozenset[str]:
        if part in out:
            return out[part]
        found: set[str] = set()
        for p in parents.get(part, ()):
            if p in seen:  # a cycle would be a selection bug; do not loop on it
                continue
            found.add(p)
            found |= walk(p, seen + (part,))
        out[part] = frozenset(found)
        return out[part]

    for part in sorted(parents):
        walk(part, ())
    return out


def primitive_parts(vp: ViewPlan) -> list[str]:
    """The parts of ``vp``'s primitive steps, in order."""
    return [s.part for s in vp.steps if s.kind == "primitive" and s.part is not None]


def inversions(order: list[str], sizes: dict[str, float],
               anc: dict[str, frozenset[str]]) -> int:
    """Pairs (A before B, A not first) with size(B) > 4 size(A), neither the other's ancestor."""
    count = 0
    for i in range(1, len(order)):
        a = order[i]
        for b in order[i + 1:]:
            if sizes[b] > INVERSION_FACTOR * sizes[a] and a not in anc.get(b, ()) \
                    and b not in anc.get(a, ()):
                count += 1
    return count


def beyond(plan: Plan) -> list[str]:
    """Parts whose fitted box leaves the mesh's bounding box by more than 1 % of its diagonal."""
    out = []
    for prim in plan.primitives:
        mlo, mhi = plan.model.part(prim.part).box
        plo, phi = prim.box
        diag = sum((float(mhi[a]) - float(mlo[a])) ** 2 for a in range(3)) ** 0.5
        tol = BEYOND_FRACTION * diag
        if any(float(mlo[a]) - float(plo[a]) > tol or float(phi[a]) - float(mhi[a]) > tol
               for a in range(3)):
            out.append(prim.part)
    return out


def measure(tutorial: TutorialConfig) -> dict[str, Any]:
    """Every figure of one model (module docstring), raw."""
    t0 = time.perf_counter()
    plan = build_plan(tutorial.model, tutorial.solver, tutorial.views)
    plan_s = time.perf_counter() - t0
    views: dict[str, dict[str, ViewPlan]] = {}
    for view in tutorial.views:
        vps = sequence_views(plan, view, LEVELS, tutorial.paper, tutorial.sequence)
        views[view.name] = {vp.level: vp for vp in vps}
    novice = [v["novice"] for v in views.values()]
    # DESIGN.md §5, from plan.json alone: the first view at the config's first guided level
    first_level = next(lv for lv in tutorial.levels if lv != "basic")
    vp0 = views[tutorial.views[0].name].get(first_level) or sequence_views(
        plan, tutorial.views[0], (first_level,), tutorial.paper, tutorial.sequence)[0]
    design = design_figures(plan_json(plan, [vp0]))

    chosen = plan.chosen()
    sizes = {part: part_size(c.box) for part, c in chosen.items()}
    anc = ancestors(plan)
    start = start_part(plan.primitives)
    anchored, dof = anchored_ends(plan)
    eye = eye_total = inv = start_ok = 0
    firsts = []
    for vp in novice:
        order = primitive_parts(vp)
        firsts.append(order[0] if order else None)
        start_ok += bool(order) and order[0] == start
        inv += inversions(order, sizes, anc)
        prim_steps = [s for s in vp.steps if s.kind == "primitive" and s.part is not None]
        for step in prim_steps[1:]:
            eye_total += 1
            eye += bool(step.eyeball or not chosen[step.part].anchors)
    words = [len(s.text.split()) for vp in novice for s in vp.steps]
    new = [sum(1 for g in s.guides if g.status == "new") for vp in novice for s in vp.steps]
    out_of_box = beyond(plan)
    # Instructions (issue 11)
    ctx = seq_context._context(plan, tutorial.views[0], tutorial.paper, tutorial.sequence)
    boxes = {p: c.box for p, c in chosen.items()}
    classes: list[list[str]] = []
    for p in sorted(boxes):
        home = next((c for c in classes if ctx.congruent(c[0], p, boxes)), None)
        if home is None:
            classes.append([p])
        else:
            home.append(p)
    names = display_names([p.name for p in plan.model.parts])
    raw = [p for p, n in names.items() if not n.readable]
    id_steps = sum(1 for v in views.values() for vp in v.values() for s in vp.steps
                   if any(p in s.text or p.replace("_", " ") in s.text for p in raw))
    all_words = [len(s.text.split()) for v in views.values() for vp in v.values()
                 for s in vp.steps]
    # Pages (issue 12)
    round_parts = sorted(p.part for p in plan.primitives if p.type == "cylinder"
                         or (p.type == "plane" and p.detail.get("round")))
    by_id = {c.id: c for c in plan.candidates}
    constructed = eyeballed = back = on_faces = hidden = hidden_anchor = 0
    for view in tutorial.views:
        vp = views[view.name]["novice"]
        made: set[str] = set()
        sketched: set[str] = set()
        for s in vp.steps:
            parts = {st.part for st in s.strokes
                     if st.kind in ("ellipse", "ellipse_hidden")} & set(round_parts)
            (made if s.kind == "ellipse" and not s.eyeball else sketched).update(parts)
        constructed += len(made)
        eyeballed += len(sketched - made)
        for part, cand in chosen.items():
            for a in cand.anchors:
                if a.face_normal == a.axis:
                    continue
                face = seq_geometry._anchor_face(a, by_id[a.parent].box, vp.camera)
                outward = 1.0 if face.end == "hi" else -1.0
                on_faces += 1
                back += (vp.camera.position[face.normal] - face.coord) * outward <= 0
        final = {st.part for st in seq.final_strokes(plan, vp.camera, tutorial.sequence)}
        drawn = {st.part for s in vp.steps if s.kind == "primitive" for st in s.strokes}
        leads = {s.part for s in vp.steps if s.kind == "primitive"}
        for part in drawn - final:
            hidden += 1
            hidden_anchor += any(by_id[a.parent].part == part for q in leads
                                 for a in chosen[q].anchors)
    return {
        "round": len(round_parts), "round_parts": round_parts,
        "ellipses_constructed": constructed, "ellipses_by_eye": eyeballed,
        "back_face": back, "face_anchors": on_faces,
        "hidden_drawn": hidden, "hidden_anchors": hidden_anchor,
        "shapes": len(classes),
        "steps_max": max(len(vp.steps) for vp in novice),
        "step_limit": 2.5 * len(classes) + 3,
        "id_name_steps": id_steps,
        "renamed": {p: names[p].label for p in raw},
        "words_novice": words, "words_all": all_words,
        "words_all_median": statistics.median(all_words) if all_words else 0,
        "words_all_max": max(all_words, default=0),
        "parts": len(plan.model.parts),
        "custom": sorted(p.part for p in plan.primitives if p.type == "custom"),
        "steps": {name: {lv: len(vp.steps) for lv, vp in v.items()} for name, v in views.items()},
        "anchored": anchored, "dof": dof,
        "by_eye": eye, "by_eye_of": eye_total,
        "inversions": inv,
        "beyond": len(out_of_box), "beyond_parts": out_of_box,
        "start_part": start, "first_parts": firsts,
        "start_ok": start_ok, "start_of": len(novice),
        "words_median": statistics.median(words) if words else 0,
        "words_max": max(words, default=0),
        "new_guides_max": max(new, default=0),
        "minutes": {name: {lv: estimate_minutes(vp) for lv, vp in v.items()}
                    for name, v in views.items()},
        "plan_s": plan_s,
        "select_s": float(plan.selection.seconds),
        "selection_status": plan.selection.status,
        "candidates": len(plan.candidates),
        "design": design,
    }


# ----------------------------------------------------------------------------- table

HEADER = (f"{'model':<14} {'parts':>5} {'steps':>9} {'anchored%':>9} {'by eye%':>8} {'inv':>4} "
          f"{'beyond':>6} {'start':>5} {'words med/max':>13} {'new max':>7} {'minutes':>8} "
          f"{'plan s':>7} {'select s':>8}")


def _pct(num: int, den: int) -> str:
    return f"{100.0 * num / den:.1f}" if den else "-"


def row(name: str, r: dict[str, Any]) -> str:
    steps = "/".join(str(v["novice"]) for v in r["steps"].values())
    minutes = [v["novice"] for v in r["minutes"].values()]
    mins = f"{min(minutes)}-{max(minutes)}" if minutes else "-"
    words = f"{r['words_median']:g}/{r['words_max']}"
    return (f"{name:<14} {r['parts']:>5} {steps:>9} {_pct(r['anchored'], r['dof']):>9} "
            f"{_pct(r['by_eye'], r['by_eye_of']):>8} {r['inversions']:>4} {r['beyond']:>6} "
            f"{r['start_ok']}/{r['start_of']:<3} {words:>13} {r['new_guides_max']:>7} "
            f"{mins:>8} {r['plan_s']:>7.2f} {r['select_s']:>8.2f}")


def totals(results: dict[str, dict[str, Any]]) -> str:
    ok = [r for r in results.values() if "error" not in r]
    s = {k: sum(r[k] for r in ok) for k in ("parts", "anchored", "dof", "by_eye", "by_eye_of",
                                           "inversions", "beyond", "start_ok", "start_of")}
    start = f"{s['start_ok']}/{s['start_of']}"
    return (f"{'total':<14} {s['parts']:>5} {'':>9} {_pct(s['anchored'], s['dof']):>9} "
            f"{_pct(s['by_eye'], s['by_eye_of']):>8} {s['inversions']:>4} {s['beyond']:>6} "
            f"{start:<5}").rstrip()


HEADER_TEXT = (f"{'model':<14} {'shapes':>6} {'steps':>9} {'limit':>6} {'words med/max':>13} "
               f"{'all levels':>10} {'id names':>8} {'minutes':>8}")


def text_row(name: str, r: dict[str, Any]) -> str:
    """Issue 11's figures: steps against 2.5 per distinct part shape + 3, words per step
    (novice; and every level), steps naming a part by an id, estimated minutes (novice)."""
    steps = "/".join(str(v["novice"]) for v in r["steps"].values())
    minutes = [v["novice"] for v in r["minutes"].values()]
    mins = f"{min(minutes)}-{max(minutes)}" if minutes else "-"
    words = f"{r['words_median']:g}/{r['words_max']}"
    every = f"{r['words_all_median']:g}/{r['words_all_max']}"
    return (f"{name:<14} {r['shapes']:>6} {steps:>9} {r['step_limit']:>6g} {words:>13} "
            f"{every:>10} {r['id_name_steps']:>8} {mins:>8}")


HEADER_PAGES = (f"{'model':<14} {'round':>5} {'ellipses':>9} {'back-face':>10} "
                f"{'hidden drawn':>12}")


def pages_row(name: str, r: dict[str, Any]) -> str:
    """Issue 12's figures (module docstring, *pages*)."""
    ell = f"{r['ellipses_constructed']}/{r['ellipses_by_eye']}"
    back = f"{r['back_face']}/{r['face_anchors']}"
    hidden = f"{r['hidden_drawn']} ({r['hidden_anchors']} anchor)"
    return f"{name:<14} {r['round']:>5} {ell:>9} {back:>10} {hidden:>12}"


def table(title: str, header: str, make_row: Any, results: dict[str, dict[str, Any]]) -> None:
    """A second table: its title, header and one row per model that planned, then the rule
    under which the caller prints its totals (when any model planned)."""
    print()
    print(title)
    print(header)
    print("-" * len(header))
    ok = {name: r for name, r in results.items() if "error" not in r}
    for name, r in ok.items():
        print(make_row(name, r))
    if ok:
        print("-" * len(header))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", help="comma-separated config names (e.g. camera,chair_ingolf)")
    ap.add_argument("--json", type=Path, help="write the raw per-model figures to this file")
    args = ap.parse_args()
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")

    paths = config_paths()
    if args.models:
        wanted = [n.strip() for n in args.models.split(",") if n.strip()]
        known = {p.stem for p in paths}
        unknown = [n for n in wanted if n not in known]
        if unknown:
            ap.error(f"unknown model(s) {', '.join(unknown)}; known: {', '.join(sorted(known))}")
        paths = [p for p in paths if p.stem in wanted]

    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    print(f"date: {datetime.date.today().isoformat()}  machine: {platform.machine()}, "
          f"{cores} cores (nproc), Python {platform.python_version()}, {platform.system()}")
    print(HEADER)
    print("-" * len(HEADER), flush=True)
    results: dict[str, dict[str, Any]] = {}
    for path in paths:
        name = path.stem
        tutorial = load_tutorial(path)
        if not tutorial.model.path.exists():
            print(f"{name:<14} skipped: {tutorial.model.path} is absent", flush=True)
            continue
        try:
            results[name] = measure(tutorial)
        except H2SError as exc:
            results[name] = {"error": str(exc)}
        except Exception as exc:  # a bug: say so and go on with the other models
            traceback.print_exc()
            results[name] = {"error": f"{type(exc).__name__}: {exc}"}
        r = results[name]
        print(f"{name:<14} FAILED: {r['error']}" if "error" in r else row(name, r), flush=True)
    print("-" * len(HEADER))
    print(totals(results))
    ok = [r for r in results.values() if "error" not in r]
    table("instructions", HEADER_TEXT, text_row, results)
    if ok:
        novice = [w for r in ok for w in r["words_novice"]]
        every = [w for r in ok for w in r["words_all"]]
        print(f"{'all':<14} models over the step limit: "
              f"{sum(r['steps_max'] > r['step_limit'] for r in ok)}; words per step, novice: "
              f"median {statistics.median(novice):g}, max {max(novice)}, over 70: "
              f"{sum(w > 70 for w in novice)} of {len(novice)}; every level: median "
              f"{statistics.median(every):g}, max {max(every)}; steps naming an id: "
              f"{sum(r['id_name_steps'] for r in ok)}")
    table("pages", HEADER_PAGES, pages_row, results)
    if ok:
        total = {k: sum(r[k] for r in ok) for k in (
            "round", "ellipses_constructed", "ellipses_by_eye", "back_face", "face_anchors",
            "hidden_drawn", "hidden_anchors")}
        print(pages_row("total", total))
    print()
    print("design (DESIGN.md §5, from plan.json alone: benchmarks/design_figures.py)")
    print(HEADER_DESIGN)
    print("-" * len(HEADER_DESIGN))
    for name, r in results.items():
        if "error" not in r:
            print(design_row(name, r["design"]))
    if ok:
        print("-" * len(HEADER_DESIGN))
        print(design_total([r["design"] for r in ok]))
    if args.json:
        args.json.write_text(json.dumps(results, indent=1, sort_keys=True) + "\n")


if __name__ == "__main__":
    main()
