"""plan.json against its contract (DESIGN.md §3), checked without trusting the code that wrote it.

``h2s plan`` runs through the CLI entry point (the only import from ``h2s_print``) once per
config and module, on every example config (not the book) and on two public IKEA models from
``../shared/models`` through configs written here.  The facts are re-derived from the JSON with
numpy alone by ``tests/contract.py``; ``test_the_checker_can_fail`` proves each family rejects a
plan broken on purpose.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
import yaml

import contract
from conftest import CONFIGS
from h2s_print.cli import main

EXAMPLES = sorted(p.stem for p in CONFIGS.glob("*.yaml") if p.stem not in ("book", "study"))

#: (name, model file under ../shared/models, view) - IKEA GLBs are z-up, in metres.
SHARED = {
    "chair_ingolf": ("ikea_chair_ingolf/chair_ingolf_0650.glb",
                     {"name": "front-left", "azimuth_deg": -35, "elevation_deg": 20,
                      "distance": 3.0, "lens_mm": 50, "perspective": "two-point"}),
    "table_lack": ("ikea_table_lack/table_lack_0825.glb",
                   {"name": "high-right", "azimuth_deg": 40, "elevation_deg": 30,
                    "distance": 3.2, "lens_mm": 50, "perspective": "three-point"}),
}


def _shared_config(folder: Path, models: Path, name: str) -> Path:
    rel, view = SHARED[name]
    model = models / rel
    if not model.is_file():
        pytest.skip(f"{model} is not present")
    doc = {"title": name, "model": {"path": str(model.resolve()), "up": "z", "units": "m"},
           "views": [view],
           # novice (every guide) and basic (the control tutorial: no guides, no anchoring).
           "levels": ["novice", "basic"],
           "paper": {"size": "A4", "orientation": "landscape", "margin_mm": 12},
           "solver": {"time_limit_s": 60, "max_change": 0.10}}
    path = folder / f"{name}.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


@pytest.fixture(scope="module", params=[f"example:{n}" for n in EXAMPLES]
                + [f"shared:{n}" for n in SHARED])
def planned(request, tmp_path_factory) -> dict:
    """``h2s plan`` on one config: {"config": dict, "path": plan.json path, "plan": dict}."""
    kind, name = request.param.split(":")
    out = tmp_path_factory.mktemp(f"plan_{name}")
    if kind == "example":
        config = CONFIGS / f"{name}.yaml"
    else:
        models = request.getfixturevalue("shared_models")
        config = _shared_config(out, models, name)
    rc = main(["-q", "plan", str(config), "-o", str(out)])
    assert rc == 0, f"h2s plan {config} exited {rc}"
    path = out / config.stem / "plan.json"
    assert path.is_file(), f"h2s plan {config} wrote no {path}"
    return {"config": yaml.safe_load(config.read_text()), "path": path,
            "plan": json.loads(path.read_text())}


def _fresh(planned: dict) -> dict:
    """A private copy of the plan to mutate."""
    return json.loads(planned["path"].read_text())


# --------------------------------------------------------------------------- the families


def test_schema(planned):
    contract.check_schema(planned["plan"])
    cfg, plan = planned["config"], planned["plan"]
    assert plan["model"]["units"] == cfg["model"]["units"], \
        f"model.units {plan['model']['units']!r}, the config says {cfg['model']['units']!r}"
    # `h2s plan` is stages 1-7 "for every view and level" (DESIGN.md §3b).
    want = sorted((v["name"], lv) for v in cfg["views"] for lv in cfg["levels"])
    got = sorted((v["name"], v["level"]) for v in plan["views"])
    assert got == want, f"views {got}, the config asks for {want}"


def test_parts(planned):
    contract.check_parts(planned["plan"])


def test_parts_carry_their_own_bounds_and_no_primitive_leaves_them(planned):
    """``parts[].bounds`` (a field this project adds) is the part mesh's bounding box: DESIGN
    §5's "beyond its part" is read off plan.json with it, and no fitted primitive leaves its
    part by more than 1 % of the part's diagonal (issue 10 point 2)."""
    for part in planned["plan"]["parts"]:
        lo, hi = (np.asarray(x, dtype=float) for x in part["bounds"])
        assert np.all(lo <= hi), part["name"]
        box = np.asarray(part["primitive"]["box"], dtype=float)
        tol = 0.01 * float(np.linalg.norm(hi - lo))
        assert np.all(lo - box[0] <= tol) and np.all(box[1] - hi <= tol), part["name"]


def test_relations(planned):
    contract.check_relations(planned["plan"])


def test_candidates(planned):
    stats = contract.check_candidates(planned["plan"])
    # Each part has its original plus something to choose from.
    assert stats["candidates"] > len(planned["plan"]["parts"])


def test_selection(planned):
    stats = contract.check_selection(planned["plan"])
    # DESIGN.md §4: "the selection is valid and proven optimal" on every example.
    assert stats["status"] == "optimal", f"selection.status {stats['status']!r}"


def test_views(planned):
    plan = planned["plan"]
    if not plan["views"]:
        pytest.skip("no views in plan.json yet")
    stats = contract.check_views(plan)
    # 0.05 mm is the contract; the writer projects exactly, so errors are rounding only.
    assert stats["max_mm_error"] <= contract.MM_TOL
    # The drawing stays on the sheet; the configs' 12 mm margins are not in plan.json.
    assert stats["min_margin_mm"] >= 0, stats


# --------------------------------------------------------------------------- the checker fails


def _anchored(plan: dict) -> tuple[dict, dict, dict]:
    by_id = {c["id"]: c for c in plan["candidates"]}
    for c in plan["candidates"]:
        for a in c["anchors"]:
            p = by_id[a["parent"]]["box"]
            if p[1][a["axis"]] - p[0][a["axis"]] > 0:
                return c, a, by_id[a["parent"]]
    raise AssertionError("no anchored candidate on a parent of non-zero extent")


def test_the_checker_can_fail(planned):
    # 1. Move an anchored end outward by 1% of the parent's extent: the ratio fact breaks
    #    (outward keeps lo <= hi, so the anchor check is what must catch it).
    plan = _fresh(planned)
    cand, anc, parent = _anchored(plan)
    ax, e = anc["axis"], 0 if anc["end"] == "lo" else 1
    extent = parent["box"][1][ax] - parent["box"][0][ax]
    cand["box"][e][ax] += (0.01 if e else -0.01) * extent
    with pytest.raises(AssertionError, match=re.escape(f"candidates[{cand['id']}].anchors[")):
        contract.check_candidates(plan)

    # 2. Deselect a parent: swap it for another candidate of its part.
    plan = _fresh(planned)
    by_id = {c["id"]: c for c in plan["candidates"]}
    sel = plan["selection"]["selected"]
    # (a parent whose part has another candidate: the start part has only its original)
    gone, others = next(
        (p, alt) for c in sel for p in by_id[c]["parents"]
        if (alt := [o["id"] for o in plan["candidates"]
                    if o["part"] == by_id[p]["part"] and o["id"] != p]))
    sel[sel.index(gone)] = next((o for o in others if by_id[o]["original"]), others[0])
    with pytest.raises(AssertionError, match="is selected but its parent"):
        contract.check_selection(plan)

    # 3. A wrong objective (1e-3 > the 1e-6 tolerance).
    plan = _fresh(planned)
    plan["selection"]["objective"] += 1e-3
    with pytest.raises(AssertionError, match=r"selection\.objective"):
        contract.check_selection(plan)

    # 4. A guide's from_mm off by 0.1 mm (twice the 0.05 mm tolerance).
    plan = _fresh(planned)
    if not any(s["guides"] for v in plan["views"] for s in v["steps"]):
        pytest.skip("no guides in plan.json")
    guide = next(g for v in plan["views"] for s in v["steps"] for g in s["guides"])
    guide["from_mm"][0] += 0.1
    with pytest.raises(AssertionError, match=r"from_mm: .*off by 0\.1 mm"):
        contract.check_views(plan)

    # 5. A broken preserved relation on the input boxes.
    plan = _fresh(planned)
    rel = next(r for r in plan["relations"] if r["detail"].get("preserved"))
    boxes = {p["name"]: p["primitive"]["box"] for p in plan["parts"]}
    # Shift b by 2 tolerances: along the axis (coplanar faces, bisector mid-planes) or, for a
    # coaxial pair, across it (the axis lines part).
    shift = rel["axis"] if rel["type"] != "coaxial" else (rel["axis"] + 1) % 3
    for end in (0, 1):
        boxes[rel["b"]][end][shift] += 2 * rel["tolerance"]
    with pytest.raises(AssertionError, match="does not hold on the input boxes"):
        contract.check_relations(plan)
