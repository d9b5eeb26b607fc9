"""An independent validity checker for candidate selections.

It reads plain plan.json-shaped dicts (DESIGN.md §3) and shares no code with
``h2s_print.candidates`` or ``h2s_print.select``: every rule is re-derived from the contract and
the paper, so a bug in the generator or the solver cannot hide itself here.

A plan dict needs ``parts`` (``[{"name", "primitive": {"box"}}]``), ``relations``
(``[{"a", "b", "type", "axis", "tolerance", "detail"}]``), ``candidates`` (``Candidate.to_json``
entries) and ``selection`` (``{"selected", "max_change", "weights", "objective"}``).

Every function returns a list of human-readable violations; empty means valid.
"""

from __future__ import annotations

import math
from typing import Any, Iterable, Mapping

#: Zero-length axes (a plane's normal) are measured against this fraction of the part's
#: largest extent (the generator's documented rule, restated).
THIN = 0.05
SLACK = 1e-9
#: A cylinder stays round: its two extents across the axis keep the input's proportion within
#: this fraction (the input box of a fitted cylinder is square, so: equal within 1 %).
ROUND = 0.01


def _length(box, axis):
    return box[1][axis] - box[0][axis]


def _centre(box, axis):
    return (box[0][axis] + box[1][axis]) / 2.0


def _norm(box, axis):
    big = max(_length(box, a) for a in range(3))
    n = _length(box, axis)
    return THIN * big if n <= 1e-9 * big else n


def _near(x, y, tol):
    return abs(x - y) <= tol + SLACK * max(1.0, abs(x), abs(y))


def relation_kept(rel: Mapping[str, Any], box_a, box_b) -> bool:
    """Does relation ``rel`` (a plan.json relation dict) hold between a's and b's boxes?"""
    tol = rel["tolerance"]
    axis = rel["axis"]
    kind = rel["type"]
    if kind == "coplanar":
        ia = 0 if rel["detail"]["a_end"] == "lo" else 1
        ib = 0 if rel["detail"]["b_end"] == "lo" else 1
        return _near(box_a[ia][axis], box_b[ib][axis], tol)
    if kind == "bisector":
        return _near(_centre(box_a, axis), _centre(box_b, axis), tol)
    if kind == "coaxial":  # the box centre lines, Euclidean distance across the axis
        du, dv = (_centre(box_a, u) - _centre(box_b, u) for u in range(3) if u != axis)
        big = max([1.0] + [abs(x) for x in (*box_a[0], *box_a[1], *box_b[0], *box_b[1])])
        return math.sqrt(du * du + dv * dv) <= tol + SLACK * big
    raise ValueError(f"unknown relation type {kind!r}")


def preserved(plan: Mapping[str, Any]) -> list[Mapping[str, Any]]:
    """The relations marked ``preserved`` in ``plan``."""
    return [r for r in plan["relations"] if r.get("detail", {}).get("preserved")]


def check_candidate(plan: Mapping[str, Any], cand: Mapping[str, Any]) -> list[str]:
    """Contract facts of one candidate: anchors exact, changes within limits, E_d right, a
    cylinder's cross-section round (its input proportion kept within ``ROUND``)."""
    out: list[str] = []
    cands = {c["id"]: c for c in plan["candidates"]}
    original = {p["name"]: p["primitive"]["box"] for p in plan["parts"]}[cand["part"]]
    box = cand["box"]
    cid = cand["id"]
    limit = plan["selection"]["max_change"]
    anchored_ends: dict[int, set[str]] = {0: set(), 1: set(), 2: set()}
    for anchor in cand["anchors"]:
        parent = cands.get(anchor["parent"])
        if parent is None:
            out.append(f"{cid}: anchor parent {anchor['parent']} is not a candidate")
            continue
        if anchor["parent"] not in cand["parents"]:
            out.append(f"{cid}: anchor parent {anchor['parent']} missing from parents")
        ax = anchor["axis"]
        pbox = parent["box"]
        want = pbox[0][ax] + anchor["ratio"] * (pbox[1][ax] - pbox[0][ax])
        if anchor["end"] == "mid":  # the mid-plane: exact up to the rounding of the halving
            got = (box[0][ax] + box[1][ax]) / 2.0
            ok = abs(got - want) <= 4e-16 * max(1.0, abs(box[0][ax]), abs(box[1][ax]))
        else:
            got = box[0 if anchor["end"] == "lo" else 1][ax]
            ok = got == want  # the contract says ==, exactly
        if not ok:
            out.append(f"{cid}: {anchor['end']} of axis {ax} is {got!r}, anchor "
                       f"{anchor['ratio']} of {anchor['parent']} gives {want!r}")
        anchored_ends[ax].add(anchor["end"])
    e_d = 0.0
    for ax in range(3):
        n = _norm(original, ax)
        d_len = abs(_length(box, ax) - _length(original, ax))
        d_mid = abs(_centre(box, ax) - _centre(original, ax))
        free = 2 - len(anchored_ends[ax])
        if free == 2:
            e_d += 2.0
            if (ax in cand["unguided_axes"]) is False:
                out.append(f"{cid}: axis {ax} has no anchor but is not listed unguided")
        else:
            e_d += d_len / n + d_mid / n + free
            if ax in cand["unguided_axes"]:
                out.append(f"{cid}: axis {ax} is anchored but listed unguided")
        if not cand["original"]:
            cap = limit * n * (1 + 1e-9) + SLACK * max(1.0, abs(box[0][ax]), abs(box[1][ax]))
            if d_len > cap or d_mid > cap:
                out.append(f"{cid}: axis {ax} changes length by {d_len:.6g} and midpoint by "
                           f"{d_mid:.6g}, more than {limit} x {n:.6g}")
    if cand.get("primitive_type") == "cylinder" and cand.get("axis") in (0, 1, 2):
        u, v = (a for a in range(3) if a != cand["axis"])
        su = _length(box, u) * _length(original, v)  # Lu / Lv == Ou / Ov, cross-multiplied
        sv = _length(box, v) * _length(original, u)
        if abs(su - sv) > ROUND * max(su, sv) + SLACK:
            out.append(f"{cid}: cylinder cross-section {_length(box, u):.6g} x "
                       f"{_length(box, v):.6g} is not round (input {_length(original, u):.6g} x "
                       f"{_length(original, v):.6g})")
    if not math.isclose(e_d, cand["cost_adjust"], rel_tol=1e-9, abs_tol=1e-9):
        out.append(f"{cid}: cost_adjust {cand['cost_adjust']!r}, definition gives {e_d!r}")
    if cand["original"]:
        if cand["anchors"] or cand["parents"] or box != original:
            out.append(f"{cid}: an original must be the input box with no anchors or parents")
    return out


def _ancestor_parts(cands: Mapping[str, Any], cid: str) -> set[str]:
    out: set[str] = set()
    stack = list(cands[cid]["parents"])
    while stack:
        p = stack.pop()
        if cands[p]["part"] not in out:
            out.add(cands[p]["part"])
        stack.extend(cands[p]["parents"])
    return out


def _stood_in(cands: Mapping[str, Any], child: Mapping[str, Any], pid: str,
              chosen: Mapping[str, Mapping[str, Any]]) -> bool:
    """A parent may be stood in for (h2s_print.select's rule, restated): the selected candidate
    of the parent's part has the same interval along every axis the child anchors off the
    parent, and does not descend from a candidate of the child's part."""
    parent = cands[pid]
    axes = {a["axis"] for a in child["anchors"] if a["parent"] == pid}
    q = chosen.get(parent["part"])
    if not axes or q is None:
        return False
    if child["part"] in _ancestor_parts(cands, q["id"]):
        return False
    return all(q["box"][0][a] == parent["box"][0][a] and q["box"][1][a] == parent["box"][1][a]
               for a in axes)


def check_selection(plan: Mapping[str, Any], selected: Iterable[str] | None = None,
                    contract: bool = True, stand_in: bool = False) -> list[str]:
    """Validity of a selection (paper eq. 1-3) and, with ``contract``, of its candidates.

    Args:
        plan: plan.json-shaped dict.
        selected: ids to check; default ``plan["selection"]["selected"]``.
        contract: also check each selected candidate (``check_candidate``).
        stand_in: a parent that is not selected is satisfied by a selected candidate of its
            part with the same intervals along the axes the child anchors off it that does
            not descend from the child's part (the selection's stand-in rule); the part graph
            must then be acyclic.
    """
    out: list[str] = []
    sel = list(plan["selection"]["selected"] if selected is None else selected)
    cands = {c["id"]: c for c in plan["candidates"]}
    parts = [p["name"] for p in plan["parts"]]
    chosen: dict[str, Mapping[str, Any]] = {}
    for cid in sel:
        if cid not in cands:
            out.append(f"selected {cid} is not a candidate")
            continue
        part = cands[cid]["part"]
        if part in chosen:
            out.append(f"part {part}: both {chosen[part]['id']} and {cid} selected")
        chosen[part] = cands[cid]
    for part in parts:
        if part not in chosen:
            out.append(f"part {part}: no candidate selected")
    ids = set(sel)
    for cid in sel:
        for p in cands.get(cid, {}).get("parents", ()):
            if p in ids:
                continue
            if stand_in and _stood_in(cands, cands[cid], p, chosen):
                continue
            out.append(f"{cid}: parent {p} not selected")
    if stand_in:  # the part graph (with stand-ins) must be acyclic
        edges = {part: {cands[p]["part"] for p in c.get("parents", ())}
                 for part, c in chosen.items()}
        placed: set[str] = set()
        while len(placed) < len(edges):
            ready = [q for q in edges if q not in placed and edges[q] <= placed]
            if not ready:
                out.append(f"cycle among {sorted(set(edges) - placed)}")
                break
            placed.update(ready)
    for rel in preserved(plan):
        a, b = chosen.get(rel["a"]), chosen.get(rel["b"])
        if a is not None and b is not None and not relation_kept(rel, a["box"], b["box"]):
            out.append(f"{rel['type']} {rel['a']}-{rel['b']} axis {rel['axis']} broken by "
                       f"{a['id']} and {b['id']}")
    if contract:
        for cid in sel:
            if cid in cands:
                out.extend(check_candidate(plan, cands[cid]))
    return out


def selection_cost(plan: Mapping[str, Any], selected: Iterable[str]) -> float:
    """Weighted cost of ``selected`` under ``plan["selection"]["weights"]``."""
    w = plan["selection"]["weights"]
    cands = {c["id"]: c for c in plan["candidates"]}
    return math.fsum(w["adjust"] * cands[i]["cost_adjust"] + w["difficulty"] *
                     cands[i]["cost_difficulty"] for i in selected)


def check_objective(plan: Mapping[str, Any]) -> list[str]:
    """The reported objective equals the weighted cost of the selected candidates."""
    got = plan["selection"]["objective"]
    want = selection_cost(plan, plan["selection"]["selected"])
    if not math.isclose(got, want, rel_tol=1e-9, abs_tol=1e-9):
        return [f"objective {got!r} but the selected candidates cost {want!r}"]
    return []


def plan_from(primitives, relations, candidates, selected, settings,
              objective: float | None = None) -> dict[str, Any]:
    """A plan-shaped dict from pipeline values (attribute access only, no pipeline code)."""
    return {
        "parts": [{"name": p.part, "primitive": {"type": p.type, "axis": p.axis,
                                                 "box": [list(p.box[0]), list(p.box[1])]}}
                  for p in primitives],
        "relations": [{"a": r.a, "b": r.b, "type": r.type, "axis": r.axis,
                       "tolerance": r.tolerance, "detail": dict(r.detail)} for r in relations],
        "candidates": [c.to_json() for c in candidates],
        "selection": {"selected": list(selected), "max_change": settings.max_change,
                      "weights": {"adjust": settings.weight_adjust,
                                  "difficulty": settings.weight_difficulty},
                      "objective": objective},
    }
