"""An independent checker of the plan.json contract (DESIGN.md §3).

It reads a plan as plain JSON (a ``dict`` from ``json.load``) and re-derives every fact with
numpy alone: it imports nothing from ``h2s_print``, so a bug in the code that wrote the file
cannot hide itself here.  Each ``check_*`` function raises ``AssertionError`` whose message
names the offending entry, e.g. ``candidates[grip<body#3].anchors[1]``, and returns a small
dict of what it measured (for reports).

Where DESIGN.md is silent, the rules below restate the generator's own documentation (each
marked "documented in ..."), never its code:

* zero-length axes (a plane's normal) are measured against ``THIN_FRACTION`` (0.05) of the
  part's largest extent, both for the change limit and for ``cost_adjust`` (documented in
  ``h2s_print/candidates.py``);
* ``cost_adjust`` per axis: both ends anchored ``|dL|/L + |dmid|/L``, one end anchored the same
  ``+ 1``, unguided ``2`` (DESIGN.md §2.4 plus the one-end rule documented in candidates.py);
* ``depth`` is 0 for originals and ``1 + max(parent depths)`` otherwise (candidates.py);
* levels: ``novice`` any guide role, ``apprentice`` no ``construction`` lines, ``master`` and
  ``basic`` no guides at all (DESIGN.md §2.6 and the paper's control condition);
* guide lifetime (``alive``, an extra key): a guide is alive from the step that introduces it
  to its last use, inclusive (DESIGN.md §2.6 "disappears after its last use").
"""

from __future__ import annotations

import math
import re
from typing import Any, Iterable, Mapping

import numpy as np

SCHEMA = "h2s-plan/1"
PRIMITIVE_TYPES = ("plane", "cuboid", "cylinder", "frustum", "custom")
RELATION_TYPES = ("coplanar", "coaxial", "bisector")
LEVELS = ("novice", "apprentice", "master", "basic")
#: How far a ``*_mm`` point may be from the projection of its 3D point (DESIGN.md §4).
MM_TOL = 0.05
#: Anchors are exact: within this fraction of the model size (box diagonal).
RATIO_TOL = 1e-9
#: Part boxes inside the model bounds: within this fraction of the model size.
BOUNDS_TOL = 1e-6
#: Objective equals the weighted sum of the selected costs within this (absolute).
OBJECTIVE_TOL = 1e-6
#: A zero-length axis is measured against this fraction of the part's largest extent.
THIN_FRACTION = 0.05
#: An extent at most this fraction of the box's largest extent counts as zero.
DEGENERATE = 1e-9
#: A vanishing point is at infinity when |w| is below this fraction of |row 3 of P[:, :3]|.
INFINITY_TOL = 1e-9

# --------------------------------------------------------------------------- small helpers


def _is_num(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _is_int(x: Any) -> bool:
    return isinstance(x, int) and not isinstance(x, bool)


def _need(obj: Any, keys: Mapping[str, Any], where: str) -> None:
    """``obj`` is a dict with every key of ``keys`` of the given type(s) (extra keys allowed).

    A type is a Python type or tuple, ``"num"`` (finite int/float, not bool), ``"int"``,
    ``"axis"`` (0|1|2), ``"axis?"`` (0|1|2|None), ``"vec3"``, ``"vec2"``, ``"box"``.
    """
    assert isinstance(obj, dict), f"{where}: expected an object, got {type(obj).__name__}"
    for key, kind in keys.items():
        assert key in obj, f"{where}: missing key {key!r}"
        _type(obj[key], kind, f"{where}.{key}")


def _type(value: Any, kind: Any, where: str) -> None:
    if kind == "num":
        assert _is_num(value), f"{where}: expected a finite number, got {value!r}"
    elif kind == "int":
        assert _is_int(value), f"{where}: expected an integer, got {value!r}"
    elif kind == "axis":
        assert _is_int(value) and value in (0, 1, 2), f"{where}: expected 0|1|2, got {value!r}"
    elif kind == "axis?":
        assert value is None or (_is_int(value) and value in (0, 1, 2)), \
            f"{where}: expected 0|1|2|null, got {value!r}"
    elif kind in ("vec3", "vec2"):
        n = 3 if kind == "vec3" else 2
        assert isinstance(value, list) and len(value) == n and all(_is_num(v) for v in value), \
            f"{where}: expected {n} numbers, got {value!r}"
    elif kind == "box":
        assert isinstance(value, list) and len(value) == 2, f"{where}: expected [[3],[3]]"
        _type(value[0], "vec3", f"{where}[0]")
        _type(value[1], "vec3", f"{where}[1]")
        for a in range(3):
            assert value[0][a] <= value[1][a], \
                f"{where}: lo > hi on axis {a}: {value[0][a]!r} > {value[1][a]!r}"
    else:
        assert isinstance(value, kind), \
            f"{where}: expected {getattr(kind, '__name__', kind)}, got {type(value).__name__}"


def model_size(plan: Mapping[str, Any]) -> float:
    """Diagonal of ``model.bounds`` (model units), the scale of the relative tolerances."""
    lo, hi = (np.asarray(v, float) for v in plan["model"]["bounds"])
    return float(np.linalg.norm(hi - lo)) or 1.0


def _extent(box, axis: int) -> float:
    return box[1][axis] - box[0][axis]


def _mid(box, axis: int) -> float:
    return (box[0][axis] + box[1][axis]) / 2.0


def norm_length(box, axis: int) -> float:
    """``L`` of the change limit and of ``cost_adjust`` for ``axis`` of the original ``box``."""
    big = max(_extent(box, a) for a in range(3))
    length = _extent(box, axis)
    return THIN_FRACTION * big if length <= DEGENERATE * big else length


def relation_gap(rel: Mapping[str, Any], box_a, box_b) -> float:
    """How far apart the related features are (model units); the relation holds iff <= tolerance.

    coplanar: the ``detail.a_end`` face of a and ``detail.b_end`` face of b along ``axis``;
    bisector: the mid-planes along ``axis``; coaxial: the box centres across ``axis`` (the
    largest of the two across-axis differences).
    """
    axis, kind = rel["axis"], rel["type"]
    if kind == "coplanar":
        ea = 0 if rel["detail"]["a_end"] == "lo" else 1
        eb = 0 if rel["detail"]["b_end"] == "lo" else 1
        return abs(box_a[ea][axis] - box_b[eb][axis])
    if kind == "bisector":
        return abs(_mid(box_a, axis) - _mid(box_b, axis))
    if kind == "coaxial":
        return max(abs(_mid(box_a, u) - _mid(box_b, u)) for u in range(3) if u != axis)
    raise AssertionError(f"unknown relation type {kind!r}")


def _rel_name(i: int, rel: Mapping[str, Any]) -> str:
    return f"relations[{i}]({rel.get('type')} {rel.get('a')}-{rel.get('b')} axis {rel.get('axis')})"


def project(P: np.ndarray, points3d: Iterable[Iterable[float]]) -> tuple[np.ndarray, np.ndarray]:
    """``P · (x, y, z, 1)``: the homogeneous (n, 3) images and the (n, 2) sheet points in mm."""
    pts = np.asarray(list(points3d), float).reshape(-1, 3)
    h = np.c_[pts, np.ones(len(pts))] @ P.T
    return h, h[:, :2] / h[:, 2:3]


def _check_projection(P, points3d, points_mm, where: str, stats: dict) -> None:
    p3 = np.asarray(points3d, float).reshape(-1, 3)
    pm = np.asarray(points_mm, float).reshape(-1, 2)
    assert len(p3) == len(pm), f"{where}: {len(p3)} 3D points but {len(pm)} mm points"
    if not len(p3):
        return
    h, want = project(P, p3)
    behind = np.flatnonzero(h[:, 2] <= 0)
    assert not len(behind), f"{where}[{behind[0]}]: point {p3[behind[0]].tolist()} is not in " \
                            f"front of the camera (w = {h[behind[0], 2]!r})"
    err = np.linalg.norm(want - pm, axis=1)
    k = int(np.argmax(err))
    stats["max_mm_error"] = max(stats.get("max_mm_error", 0.0), float(err[k]))
    at = f"{where}[{k}]" if len(p3) > 1 else where
    assert err[k] <= MM_TOL, (f"{at}: {pm[k].tolist()} mm but projection_mm·"
                              f"({p3[k].tolist()}, 1) = {want[k].tolist()} mm "
                              f"(off by {err[k]:.4g} mm > {MM_TOL})")


# --------------------------------------------------------------------------- schema


def check_schema(plan: Mapping[str, Any]) -> dict:
    """Every field of DESIGN.md §3 present with its JSON type (extra keys allowed)."""
    _need(plan, {"schema": str, "model": dict, "parts": list, "relations": list,
                 "candidates": list, "selection": dict, "views": list}, "plan")
    assert plan["schema"] == SCHEMA, f"plan.schema: {plan['schema']!r}, expected {SCHEMA!r}"
    _need(plan["model"], {"source": str, "up": str, "units": str, "bounds": "box"}, "model")
    assert plan["model"]["up"] == "z", f"model.up: {plan['model']['up']!r}, expected 'z'"
    for i, part in enumerate(plan["parts"]):
        where = f"parts[{part.get('name', i) if isinstance(part, dict) else i}]"
        _need(part, {"name": str, "primitive": dict, "residual": "num"}, where)
        _need(part["primitive"], {"type": str, "axis": "axis?", "box": "box"},
              f"{where}.primitive")
    for i, rel in enumerate(plan["relations"]):
        _need(rel, {"a": str, "b": str, "type": str, "axis": "axis", "tolerance": "num",
                    "detail": dict}, f"relations[{i}]")
    for i, cand in enumerate(plan["candidates"]):
        where = f"candidates[{cand.get('id', i) if isinstance(cand, dict) else i}]"
        _need(cand, {"id": str, "part": str, "box": "box", "original": bool, "parents": list,
                     "depth": "int", "anchors": list, "unguided_axes": list,
                     "cost_adjust": "num", "cost_difficulty": "num"}, where)
        for j, p in enumerate(cand["parents"]):
            _type(p, str, f"{where}.parents[{j}]")
        for j, a in enumerate(cand["anchors"]):
            _need(a, {"axis": "axis", "end": str, "parent": str, "ratio": "num",
                      "guide_lines": "int"}, f"{where}.anchors[{j}]")
        for j, a in enumerate(cand["unguided_axes"]):
            _type(a, "axis", f"{where}.unguided_axes[{j}]")
    sel = plan["selection"]
    _need(sel, {"solver": str, "formulation": str, "status": str, "weights": dict,
                "max_change": "num", "objective": "num", "selected": list, "seconds": "num"},
          "selection")
    _need(sel["weights"], {"adjust": "num", "difficulty": "num"}, "selection.weights")
    for j, s in enumerate(sel["selected"]):
        _type(s, str, f"selection.selected[{j}]")
    for i, view in enumerate(plan["views"]):
        where = f"views[{i}]"
        _need(view, {"name": str, "level": str, "paper_mm": "vec2", "camera": dict,
                     "vanishing_points": list, "steps": list}, where)
        where = f"views[{i}:{view['name']}/{view['level']}]"
        _need(view["camera"], {"projection_mm": list}, f"{where}.camera")
        P = view["camera"]["projection_mm"]
        assert len(P) == 3 and all(isinstance(r, list) and len(r) == 4 and
                                   all(_is_num(x) for x in r) for r in P), \
            f"{where}.camera.projection_mm: expected a 3x4 matrix of numbers, got {P!r}"
        for j, vp in enumerate(view["vanishing_points"]):
            _need(vp, {"axis": "axis", "at_infinity": bool}, f"{where}.vanishing_points[{j}]")
            assert "xy_mm" in vp, f"{where}.vanishing_points[{j}]: missing key 'xy_mm'"
            if vp["xy_mm"] is not None:
                _type(vp["xy_mm"], "vec2", f"{where}.vanishing_points[{j}].xy_mm")
        for j, step in enumerate(view["steps"]):
            sw = f"{where}.steps[{j}]"
            _need(step, {"index": "int", "kind": str, "text": str, "eyeball": bool,
                         "guides": list}, sw)
            assert "part" in step, f"{sw}: missing key 'part'"
            assert step["part"] is None or isinstance(step["part"], str), \
                f"{sw}.part: expected a part name or null, got {step['part']!r}"
            for k, g in enumerate(step["guides"]):
                _need(g, {"id": str, "status": str, "from3d": "vec3", "to3d": "vec3",
                          "from_mm": "vec2", "to_mm": "vec2"}, f"{sw}.guides[{k}]")
    return {}


# --------------------------------------------------------------------------- parts


def check_parts(plan: Mapping[str, Any]) -> dict:
    """Unique names, known types and axes, residual >= 0, boxes inside ``model.bounds``."""
    names = [p["name"] for p in plan["parts"]]
    assert names, "parts: empty"
    dup = sorted({n for n in names if names.count(n) > 1})
    assert not dup, f"parts: duplicate names {dup}"
    lo, hi = plan["model"]["bounds"]
    tol = BOUNDS_TOL * model_size(plan)
    for part in plan["parts"]:
        where = f"parts[{part['name']}]"
        prim = part["primitive"]
        assert prim["type"] in PRIMITIVE_TYPES, f"{where}.primitive.type: {prim['type']!r}"
        assert prim["axis"] in (0, 1, 2, None), f"{where}.primitive.axis: {prim['axis']!r}"
        assert part["residual"] >= 0, f"{where}.residual: {part['residual']!r} < 0"
        box = prim["box"]
        for a in range(3):
            assert box[0][a] <= box[1][a], f"{where}.primitive.box: lo > hi on axis {a}"
            assert box[0][a] >= lo[a] - tol and box[1][a] <= hi[a] + tol, (
                f"{where}.primitive.box axis {a} [{box[0][a]!r}, {box[1][a]!r}] is outside "
                f"model.bounds [{lo[a]!r}, {hi[a]!r}] (tolerance {tol:.3g})")
    return {"parts": len(names)}


# --------------------------------------------------------------------------- relations


def check_relations(plan: Mapping[str, Any]) -> dict:
    """a < b, both parts, known type, tolerance > 0, holds on the input boxes; one preferred
    preserved relation per pair at most (DESIGN.md §2.3), plus the coplanar relations of
    touching faces (``detail.contact`` / ``detail.flush``), which are always preserved."""
    boxes = {p["name"]: p["primitive"]["box"] for p in plan["parts"]}
    slack = 1e-12 * model_size(plan)
    kept_pairs: dict[tuple[str, str], int] = {}
    worst = 0.0
    n_touch = 0
    for i, rel in enumerate(plan["relations"]):
        where = _rel_name(i, rel)
        assert rel["a"] in boxes, f"{where}.a: {rel['a']!r} is not a part"
        assert rel["b"] in boxes, f"{where}.b: {rel['b']!r} is not a part"
        assert rel["a"] < rel["b"], f"{where}: a {rel['a']!r} is not before b {rel['b']!r}"
        assert rel["type"] in RELATION_TYPES, f"{where}.type: {rel['type']!r}"
        assert rel["axis"] in (0, 1, 2), f"{where}.axis: {rel['axis']!r}"
        assert rel["tolerance"] > 0, f"{where}.tolerance: {rel['tolerance']!r} <= 0"
        if rel["type"] == "coplanar":
            for key in ("a_end", "b_end"):
                assert rel["detail"].get(key) in ("lo", "hi"), \
                    f"{where}.detail.{key}: {rel['detail'].get(key)!r}, expected lo|hi"
        gap = relation_gap(rel, boxes[rel["a"]], boxes[rel["b"]])
        worst = max(worst, gap / rel["tolerance"])
        assert gap <= rel["tolerance"] + slack, (
            f"{where}: does not hold on the input boxes: gap {gap:.6g} > tolerance "
            f"{rel['tolerance']:.6g}")
        touching = rel["detail"].get("contact") or rel["detail"].get("flush")
        if touching:  # touching faces are preserved besides the pair's preferred relation
            assert rel["type"] == "coplanar", f"{where}: contact/flush on a {rel['type']}"
            assert rel["detail"].get("preserved"), f"{where}: touching but not preserved"
            n_touch += 1
        elif rel["detail"].get("preserved"):
            pair = (rel["a"], rel["b"])
            assert pair not in kept_pairs, (
                f"{where}: a second preserved relation for pair {pair} (first: "
                f"{_rel_name(kept_pairs[pair], plan['relations'][kept_pairs[pair]])})")
            kept_pairs[pair] = i
    return {"relations": len(plan["relations"]), "preserved": len(kept_pairs) + n_touch,
            "worst_gap_over_tolerance": worst}


# --------------------------------------------------------------------------- candidates


def check_candidates(plan: Mapping[str, Any]) -> dict:
    """Ids, originals, parents, depth, exact anchors, unguided axes, costs, change limit."""
    parts = {p["name"]: p["primitive"]["box"] for p in plan["parts"]}
    cands = plan["candidates"]
    ids = [c["id"] for c in cands]
    dup = sorted({i for i in ids if ids.count(i) > 1})
    assert not dup, f"candidates: duplicate ids {dup}"
    by_id = {c["id"]: c for c in cands}
    size = model_size(plan)
    limit = plan["selection"]["max_change"]
    originals: dict[str, list[str]] = {name: [] for name in parts}
    for c in cands:
        assert c["part"] in parts, f"candidates[{c['id']}].part: {c['part']!r} is not a part"
        if c["original"]:
            originals[c["part"]].append(c["id"])
    for name, found in originals.items():
        assert len(found) == 1, f"parts[{name}]: {len(found)} original candidates {found}"
        orig = by_id[found[0]]
        assert orig["box"] == parts[name], (
            f"candidates[{orig['id']}].box {orig['box']} differs from parts[{name}].primitive"
            f".box {parts[name]}")
    worst_anchor = 0.0
    worst_change = 0.0
    for c in cands:
        where = f"candidates[{c['id']}]"
        box, orig = c["box"], parts[c["part"]]
        for a in range(3):
            assert box[0][a] <= box[1][a], f"{where}.box: lo > hi on axis {a}"
        assert c["cost_adjust"] >= 0, f"{where}.cost_adjust: {c['cost_adjust']!r} < 0"
        assert c["cost_difficulty"] >= 0, \
            f"{where}.cost_difficulty: {c['cost_difficulty']!r} < 0"
        for p in c["parents"]:
            assert p in by_id, f"{where}.parents: {p!r} is not a candidate"
            assert by_id[p]["part"] != c["part"], \
                f"{where}.parents: {p!r} belongs to the candidate's own part {c['part']!r}"
        assert len(set(c["parents"])) == len(c["parents"]), f"{where}.parents: duplicates"
        if c["original"]:
            assert not c["parents"] and not c["anchors"], \
                f"{where}: an original with parents {c['parents']} or anchors"
            assert c["depth"] == 0, f"{where}.depth: {c['depth']} for an original, expected 0"
        else:
            assert c["parents"], f"{where}: not original and no parents"
            want = 1 + max(by_id[p]["depth"] for p in c["parents"])
            assert c["depth"] == want, (f"{where}.depth: {c['depth']}, expected 1 + max "
                                        f"parent depth = {want}")
        ends: dict[int, set[str]] = {0: set(), 1: set(), 2: set()}
        for j, anc in enumerate(c["anchors"]):
            aw = f"{where}.anchors[{j}]"
            assert anc["parent"] in c["parents"], \
                f"{aw}.parent {anc['parent']!r} is not in parents {c['parents']}"
            assert anc["axis"] in (0, 1, 2), f"{aw}.axis: {anc['axis']!r}"
            assert anc["end"] in ("lo", "hi", "mid"), f"{aw}.end: {anc['end']!r}"
            assert anc["guide_lines"] >= 0, f"{aw}.guide_lines: {anc['guide_lines']} < 0"
            ax = anc["axis"]
            pbox = by_id[anc["parent"]]["box"]
            want = pbox[0][ax] + anc["ratio"] * (pbox[1][ax] - pbox[0][ax])
            # "mid": the child's mid-plane lies at the ratio (README, plan.json additions)
            got = (_mid(box, ax) if anc["end"] == "mid"
                   else box[0 if anc["end"] == "lo" else 1][ax])
            e = anc["end"]
            err = abs(got - want)
            worst_anchor = max(worst_anchor, err / size)
            assert err <= RATIO_TOL * size, (
                f"{aw}: the {e} of axis {ax} = {got!r} but {anc['parent']} at ratio "
                f"{anc['ratio']!r} gives {pbox[0][ax]!r} + {anc['ratio']!r} * "
                f"({pbox[1][ax]!r} - {pbox[0][ax]!r}) = {want!r} (off by {err:.3g})")
            ends[ax].add(anc["end"])
        anchored = {a for a in range(3) if ends[a]}
        unguided = set(c["unguided_axes"])
        assert not (anchored & unguided), \
            f"{where}: axes {sorted(anchored & unguided)} are both anchored and unguided"
        assert anchored | unguided == {0, 1, 2}, (
            f"{where}: axes {sorted({0, 1, 2} - anchored - unguided)} neither anchored nor "
            f"listed in unguided_axes")
        e_d = 0.0
        for a in range(3):
            L = norm_length(orig, a)
            d_len = abs(_extent(box, a) - _extent(orig, a))
            d_mid = abs(_mid(box, a) - _mid(orig, a))
            worst_change = max(worst_change, d_len / L, d_mid / L)
            cap = limit * L * (1 + 1e-9) + 1e-12 * size
            assert d_len <= cap, (f"{where}: axis {a} length changes by {d_len:.6g}, more than "
                                  f"max_change {limit} x L {L:.6g}")
            assert d_mid <= cap, (f"{where}: axis {a} midpoint moves by {d_mid:.6g}, more than "
                                  f"max_change {limit} x L {L:.6g}")
            n_free = 2 - len(ends[a])
            e_d += 2.0 if n_free == 2 else d_len / L + d_mid / L + n_free
        assert math.isclose(e_d, c["cost_adjust"], rel_tol=1e-9, abs_tol=1e-9), \
            f"{where}.cost_adjust: {c['cost_adjust']!r}, the definition gives {e_d!r}"
    return {"candidates": len(cands), "max_depth": max(c["depth"] for c in cands),
            "worst_anchor_error_over_size": worst_anchor,
            "worst_change_over_L": worst_change}


# --------------------------------------------------------------------------- selection


def check_selection(plan: Mapping[str, Any]) -> dict:
    """One candidate per part, parents selected (acyclic), preserved relations kept, objective."""
    sel = plan["selection"]
    assert sel["solver"] == "scip", f"selection.solver: {sel['solver']!r}"
    assert sel["status"], "selection.status: empty"
    if "optimal" in sel:
        assert sel["optimal"] == (sel["status"] == "optimal"), \
            f"selection.optimal {sel['optimal']!r} but status {sel['status']!r}"
    assert sel["seconds"] >= 0, f"selection.seconds: {sel['seconds']!r} < 0"
    assert 0 < sel["max_change"], f"selection.max_change: {sel['max_change']!r}"
    for key in ("adjust", "difficulty"):
        assert sel["weights"][key] >= 0, f"selection.weights.{key}: {sel['weights'][key]!r}"
    by_id = {c["id"]: c for c in plan["candidates"]}
    chosen: dict[str, dict] = {}
    for j, cid in enumerate(sel["selected"]):
        assert cid in by_id, f"selection.selected[{j}]: {cid!r} is not a candidate"
        part = by_id[cid]["part"]
        assert part not in chosen, \
            f"selection.selected: part {part} has both {chosen[part]['id']} and {cid}"
        chosen[part] = by_id[cid]
    missing = [p["name"] for p in plan["parts"] if p["name"] not in chosen]
    assert not missing, f"selection.selected: no candidate for parts {missing}"
    ids = set(sel["selected"])
    for cid in sel["selected"]:
        for p in by_id[cid]["parents"]:
            assert p in ids, f"selection.selected: {cid} is selected but its parent {p} is not"
    # Acyclic: peel off candidates whose parents are all placed (Kahn).
    placed: set[str] = set()
    todo = list(sel["selected"])
    while todo:
        ready = [c for c in todo if all(p in placed for p in by_id[c]["parents"])]
        assert ready, f"selection.selected: the anchoring graph has a cycle among {todo}"
        placed.update(ready)
        todo = [c for c in todo if c not in placed]
    slack = 1e-12 * model_size(plan)
    kept = 0
    for i, rel in enumerate(plan["relations"]):
        if not rel["detail"].get("preserved"):
            continue
        a, b = chosen[rel["a"]], chosen[rel["b"]]
        gap = relation_gap(rel, a["box"], b["box"])
        assert gap <= rel["tolerance"] + slack, (
            f"{_rel_name(i, rel)}: preserved but broken by the selection {a['id']} and "
            f"{b['id']}: gap {gap:.6g} > tolerance {rel['tolerance']:.6g}")
        kept += 1
    w = sel["weights"]
    want = math.fsum(w["adjust"] * by_id[c]["cost_adjust"]
                     + w["difficulty"] * by_id[c]["cost_difficulty"] for c in sel["selected"])
    assert abs(sel["objective"] - want) <= OBJECTIVE_TOL, (
        f"selection.objective: {sel['objective']!r}, Σ weights·costs of the selected "
        f"candidates = {want!r}")
    return {"selected": len(ids), "preserved_kept": kept, "objective": sel["objective"],
            "status": sel["status"]}


# --------------------------------------------------------------------------- views


def _selected_boxes(plan: Mapping[str, Any]) -> tuple[dict, dict]:
    by_id = {c["id"]: c for c in plan["candidates"]}
    chosen = {by_id[c]["part"]: by_id[c] for c in plan["selection"]["selected"] if c in by_id}
    return chosen, by_id


def check_view(plan: Mapping[str, Any], i: int) -> dict:
    """One entry of ``views``: camera, vanishing points, steps, guides, strokes, paper."""
    view = plan["views"][i]
    where = f"views[{i}:{view['name']}/{view['level']}]"
    stats: dict[str, Any] = {"max_mm_error": 0.0}
    level = view["level"]
    assert level in LEVELS, f"{where}.level: {level!r}, expected one of {LEVELS}"
    w_mm, h_mm = view["paper_mm"]
    assert w_mm > 0 and h_mm > 0, f"{where}.paper_mm: {view['paper_mm']}"
    P = np.asarray(view["camera"]["projection_mm"], float)
    assert P.shape == (3, 4), f"{where}.camera.projection_mm: shape {P.shape}"

    # Vanishing points: P·(d, 0), d the model axis.
    axes = [vp["axis"] for vp in view["vanishing_points"]]
    assert sorted(axes) == [0, 1, 2], f"{where}.vanishing_points: axes {axes}, expected 0, 1, 2"
    row3 = float(np.linalg.norm(P[2, :3]))
    for j, vp in enumerate(view["vanishing_points"]):
        vw = f"{where}.vanishing_points[{j}](axis {vp['axis']})"
        x, y, w = P[:, vp["axis"]]
        at_inf = abs(w) <= INFINITY_TOL * row3
        assert vp["at_infinity"] == at_inf, (
            f"{vw}.at_infinity: {vp['at_infinity']!r} but projection_mm·(d, 0) has w = {w!r}")
        if at_inf:
            assert vp["xy_mm"] is None, f"{vw}.xy_mm: {vp['xy_mm']} for a point at infinity"
            if vp.get("direction_mm") is not None:  # extra key: parallel to (x, y)
                dx, dy = vp["direction_mm"]
                cross = abs(dx * y - dy * x) / (math.hypot(x, y) * math.hypot(dx, dy))
                assert cross <= 1e-6, f"{vw}.direction_mm {vp['direction_mm']} not ∥ ({x}, {y})"
        else:
            assert vp["xy_mm"] is not None, f"{vw}.xy_mm: null for a finite vanishing point"
            want = np.array([x / w, y / w])
            err = float(np.linalg.norm(want - np.asarray(vp["xy_mm"], float)))
            # A far VP may carry floating error relative to its distance.
            assert err <= MM_TOL + 1e-9 * float(np.linalg.norm(want)), (
                f"{vw}.xy_mm: {vp['xy_mm']} but projection_mm·(d, 0) = {want.tolist()}")

    # Steps.
    parts = {p["name"] for p in plan["parts"]}
    chosen, by_id = _selected_boxes(plan)
    steps = view["steps"]
    assert steps, f"{where}.steps: empty"
    indices = [s["index"] for s in steps]
    assert indices == list(range(1, len(steps) + 1)), \
        f"{where}.steps: indices {indices}, expected 1..{len(steps)} in order"
    size = model_size(plan)
    new_at: dict[str, int] = {}
    uses: dict[str, list[int]] = {}
    first_primitive: dict[str, int] = {}
    min_margin = math.inf
    guide_min_margin = math.inf
    n_guides = 0
    for step in steps:
        sw = f"{where}.steps[{step['index']}]({step['kind']} {step['part']})"
        assert step["part"] is None or step["part"] in parts, \
            f"{sw}.part: {step['part']!r} is not a part"
        assert step["text"].strip(), f"{sw}.text: empty"
        if level in ("master", "basic"):
            assert not step["guides"], f"{sw}.guides: {len(step['guides'])} at level {level}"
        ids_here = [g["id"] for g in step["guides"]]
        assert len(set(ids_here)) == len(ids_here), f"{sw}.guides: duplicate ids {ids_here}"
        for k, g in enumerate(step["guides"]):
            gw = f"{sw}.guides[{k}:{g['id']}]"
            n_guides += 1
            assert g["status"] in ("new", "reused"), f"{gw}.status: {g['status']!r}"
            if level == "apprentice" and "role" in g:
                assert g["role"] != "construction", f"{gw}: a construction line at apprentice"
            if g["status"] == "new":
                assert g["id"] not in new_at, \
                    f"{gw}: new again (first new at step {new_at[g['id']]})"
                new_at[g["id"]] = step["index"]
            else:
                assert g["id"] in new_at, f"{gw}: reused before (or without) a step making it new"
                assert new_at[g["id"]] < step["index"], f"{gw}: reused in its own new step"
            uses.setdefault(g["id"], []).append(step["index"])
            _check_projection(P, [g["from3d"]], [g["from_mm"]], f"{gw}.from_mm", stats)
            _check_projection(P, [g["to3d"]], [g["to_mm"]], f"{gw}.to_mm", stats)
            for pt in (g["from_mm"], g["to_mm"]):
                guide_min_margin = min(guide_min_margin, pt[0], pt[1],
                                       w_mm - pt[0], h_mm - pt[1])
        # Lettered points (extra key ``labels``): each at the projection of its 3D point, each
        # letter named in the sub-steps drawn, letters unique within the step.
        labels = step.get("labels", [])
        names = [lb["name"] for lb in labels if lb.get("kind", "point") == "point"]
        assert len(names) == len(set(names)), f"{sw}.labels: a letter twice: {names}"
        for k, lb in enumerate(labels):
            _check_projection(P, [lb["at3d"]], [lb["at_mm"]], f"{sw}.labels[{k}:{lb['name']}]",
                              stats)
        for x in step.get("substeps", []):
            for token in re.findall(r"(?<![A-Za-z'])(?:[A-Z]'*)+(?![a-z])", x):
                for letter in re.findall(r"[A-Z]'*", token):
                    assert letter in names, f"{sw}.substeps: {letter} is named but not drawn"
        drawn: list[tuple[str, list, list]] = []
        for k, s in enumerate(step.get("strokes", [])):
            drawn.append((f"{sw}.strokes[{k}:{s.get('kind')}].points_mm", s["points3d"],
                          s["points_mm"]))
            if s.get("kind", "").startswith("scaffold") and step["kind"] in ("primitive",
                                                                                "basic"):
                _check_on_box(plan, step, s, chosen, f"{sw}.strokes[{k}]", size)
        if step["kind"] == "contour":
            assert "polylines3d" in step and "polylines_mm" in step, \
                f"{sw}: a contour step without polylines3d/polylines_mm"
        if "polylines3d" in step or "polylines_mm" in step:
            p3, pm = step.get("polylines3d", []), step.get("polylines_mm", [])
            assert len(p3) == len(pm), \
                f"{sw}: {len(p3)} polylines3d but {len(pm)} polylines_mm"
            for k, (a, b) in enumerate(zip(p3, pm)):
                assert len(a) == len(b), \
                    f"{sw}.polylines[{k}]: {len(a)} 3D points but {len(b)} mm points"
                drawn.append((f"{sw}.polylines_mm[{k}]", a, b))
        for name, p3, pm in drawn:
            _check_projection(P, p3, pm, name, stats)
            if len(pm):
                arr = np.asarray(pm, float)
                margin = float(min(arr[:, 0].min(), arr[:, 1].min(),
                                   w_mm - arr[:, 0].max(), h_mm - arr[:, 1].max()))
                min_margin = min(min_margin, margin)
                assert margin >= 0, f"{name}: drawing leaves the sheet (margin {margin:.3g} mm)"
        if step["kind"] in ("primitive", "basic") and step["part"] is not None:
            assert step["part"] not in first_primitive, \
                f"{sw}: a second primitive step for {step['part']}"
            first_primitive[step["part"]] = step["index"]
    # Guide lifetime (extra key ``alive``): alive from its new step to its last use.
    if all("alive" in s for s in steps) and new_at:
        for step in steps:
            want = {g for g in new_at if new_at[g] <= step["index"] <= max(uses[g])}
            got = set(step["alive"])
            assert got == want, (f"{where}.steps[{step['index']}].alive: extra "
                                 f"{sorted(got - want)}, missing {sorted(want - got)}")
    # Parents' primitive steps come first (not for the control tutorial, which has no anchors).
    if level != "basic":
        for part, idx in first_primitive.items():
            for p in chosen[part]["parents"]:
                pp = by_id[p]["part"]
                assert pp in first_primitive, (f"{where}: {part} (step {idx}) hangs off {p} "
                                               f"but {pp} has no primitive step")
                assert first_primitive[pp] < idx, (
                    f"{where}: {part}'s primitive step {idx} comes before its parent {pp}'s "
                    f"step {first_primitive[pp]}")
    stats.update(steps=len(steps), guides=n_guides, min_margin_mm=min_margin,
                 guide_min_margin_mm=guide_min_margin)
    return stats


def _check_on_box(plan, step, stroke, chosen, where: str, size: float) -> None:
    """A primitive step's scaffold lies on (inside) the part's selected box; basic: input box."""
    part = stroke.get("part") or step["part"]
    if part is None:
        return
    if step["kind"] == "basic":
        box = next(p["primitive"]["box"] for p in plan["parts"] if p["name"] == part)
    else:
        box = chosen[part]["box"]
    pts = np.asarray(stroke["points3d"], float).reshape(-1, 3)
    tol = 1e-9 * size
    lo, hi = np.asarray(box[0]), np.asarray(box[1])
    out = np.flatnonzero(((pts < lo - tol) | (pts > hi + tol)).any(axis=1))
    assert not len(out), (f"{where}: scaffold point {pts[out[0]].tolist()} outside {part}'s "
                          f"{'input' if step['kind'] == 'basic' else 'selected'} box {box}")


def check_views(plan: Mapping[str, Any]) -> dict:
    """Every view; returns the smallest drawing margin and largest projection error seen."""
    stats = [check_view(plan, i) for i in range(len(plan["views"]))]
    if not stats:
        return {"views": 0}
    return {"views": len(stats),
            "min_margin_mm": min(s["min_margin_mm"] for s in stats),
            "guide_min_margin_mm": min(s["guide_min_margin_mm"] for s in stats),
            "max_mm_error": max(s["max_mm_error"] for s in stats),
            "guides": sum(s["guides"] for s in stats)}


FAMILIES = {"schema": check_schema, "parts": check_parts, "relations": check_relations,
            "candidates": check_candidates, "selection": check_selection, "views": check_views}


def check_plan(plan: Mapping[str, Any]) -> dict:
    """Every family, in dependency order; returns their stats keyed by family."""
    return {name: fn(plan) for name, fn in FAMILIES.items()}
