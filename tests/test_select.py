"""Stage 5: SCIP selection against brute force and an independent checker."""

from __future__ import annotations

import dataclasses
import itertools
import json
import math
import random

import pytest

from checker import (check_candidate, check_objective, check_selection, plan_from, relation_kept,
                     selection_cost)
from h2s_print.candidates import Candidate, generate_candidates
from h2s_print.config import SolverSettings
from h2s_print.errors import SelectionError
from h2s_print.select import build_selection_model, select_candidates
from h2s_print.types import Primitive, Relation
from test_candidates import camera, prim, rel

SETTINGS = SolverSettings()
QUAD = dataclasses.replace(SETTINGS, formulation="quadratic")
LIN = dataclasses.replace(SETTINGS, formulation="linear")


# --------------------------------------------------------------------------- brute force


def brute_force(plan) -> tuple[float, tuple[str, ...]]:
    """Least weighted cost over every valid assignment, validity decided by the checker."""
    by_part: dict[str, list[str]] = {}
    for c in plan["candidates"]:
        by_part.setdefault(c["part"], []).append(c["id"])
    best = (math.inf, ())
    for combo in itertools.product(*(by_part[p] for p in sorted(by_part))):
        if check_selection(plan, combo, contract=False, stand_in=True):
            continue
        cost = selection_cost(plan, combo)
        if cost < best[0] - 1e-12:
            best = (cost, tuple(sorted(combo)))
    return best


def synthetic(seed: int, n_parts: int = 4, per_part: int = 4):
    """Random candidate sets: random parents (acyclic), boxes on a coarse grid so preserved
    relations hold for some pairs and break for others; all originals share one box, so the
    all-originals selection is valid."""
    rng = random.Random(seed)
    parts = [f"p{i}" for i in range(n_parts)]
    base = ((0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
    prims = [Primitive(p, "cuboid", None, base, 0.0) for p in parts]
    cands: list[Candidate] = []
    for p in parts:
        cands.append(Candidate(p, p, base, True, (), 0, (), (0, 1, 2), 6.0, 0.0))
    order: list[Candidate] = list(cands)
    for k in range(1, per_part):
        for p in parts:
            lo = tuple(rng.choice((-0.5, 0.0, 0.5)) for _ in range(3))
            box = (lo, tuple(x + 1.0 for x in lo))
            pool = [c for c in order if c.part != p]
            parents = tuple(sorted({c.id for c in rng.sample(pool, rng.choice((0, 1, 1, 2)))}))
            if len({c.part for c in order if c.id in parents}) != len(parents):
                parents = parents[:1]
            c = Candidate(f"{p}<#{k}", p, box, False, parents, 1, (), (0, 1, 2),
                          round(rng.uniform(0.0, 5.0), 3), round(rng.uniform(0.0, 2.0), 3))
            cands.append(c)
            order.append(c)
    rels = []
    for a, b in itertools.combinations(parts, 2):
        if rng.random() < 0.6:
            kind = rng.choice(("coplanar", "bisector", "coaxial"))
            rels.append(Relation(a, b, kind, rng.randrange(3), 0.1,
                                 {"a_end": rng.choice(("lo", "hi")),
                                  "b_end": "lo", "preserved": True} if kind == "coplanar"
                                 else {"preserved": True}))
    # coplanar a_end/b_end must hold on the originals: use equal ends
    rels = [Relation(r.a, r.b, r.type, r.axis, r.tolerance, {**r.detail, "b_end":
                     r.detail["a_end"]}) if r.type == "coplanar" else r for r in rels]
    return prims, rels, cands


@pytest.mark.parametrize("seed", range(12))
def test_selection_equals_brute_force(seed):
    prims, rels, cands = synthetic(seed)
    plan = plan_from(prims, rels, cands, [], SETTINGS)
    want_cost, _ = brute_force(plan)
    for settings in (QUAD, LIN):
        sel = select_candidates(cands, rels, settings)
        assert sel.optimal and sel.status == "optimal"
        assert not sel.stand_ins  # no anchors here: nothing can stand in for a parent
        assert check_selection(plan, sel.chosen, contract=False) == []
        assert sel.objective == pytest.approx(want_cost, abs=1e-9)


def test_camera_selection_matches_brute_force_and_checker():
    prims, rels = camera()
    cands = generate_candidates(prims, rels, dataclasses.replace(SETTINGS, depth=1))
    plan = plan_from(prims, rels, cands, [], SETTINGS)
    want_cost, _ = brute_force(plan)
    sel = select_candidates(cands, rels, SETTINGS)
    assert sel.objective == pytest.approx(want_cost, abs=1e-9)
    plan["candidates"] += [c.to_json() for c in sel.stand_ins]
    plan["selection"].update(sel.to_json())
    assert check_selection(plan) == [] and check_objective(plan) == []


def test_camera_chooses_anchored_candidates():
    prims, rels = camera()
    cands = generate_candidates(prims, rels, SETTINGS)
    by_id = {c.id: c for c in cands}
    for settings in (QUAD, LIN):
        sel = select_candidates(cands, rels, settings)
        assert sel.optimal
        plan = plan_from(prims, rels, [*cands, *sel.stand_ins], [], settings)
        plan["selection"].update(sel.to_json())
        assert check_selection(plan) == [] and check_objective(plan) == []
        by_id.update({c.id: c for c in sel.stand_ins})
        chosen = [by_id[i] for i in sel.chosen]
        anchored = [c for c in chosen if c.anchors]
        assert len(anchored) >= 3  # of 4 parts: the first one drawn has nothing to hang off
        assert {c.part for c in chosen} == {"body", "grip", "lens", "prism"}
        # the grip sticks out 1/2 of the body's depth in front of it
        grip = next(c for c in chosen if c.part == "grip")
        assert grip.box[0][1] == -2.0 and grip.box[1][1] == 0.0


def _jittered_camera(seed: int):
    rng = random.Random(seed)
    prims, rels = camera()
    out = []
    for p in prims:
        if p.part == "body":
            out.append(p)
            continue
        dx = rng.uniform(-0.15, 0.15)
        s = rng.uniform(0.97, 1.03)
        lo, hi = p.box
        c0 = (lo[0] + hi[0]) / 2 + dx
        half = (hi[0] - lo[0]) / 2 * s
        out.append(dataclasses.replace(p, box=((c0 - half, lo[1], lo[2]), (c0 + half, hi[1], hi[2]))))
    # bisector relations only where they still hold on the jittered boxes
    boxes = {p.part: p.box for p in out}
    kept = []
    for r in rels:
        d = {"type": r.type, "axis": r.axis, "tolerance": r.tolerance, "detail": dict(r.detail)}
        if r.type == "coplanar" and r.axis == 0:
            continue
        if relation_kept(d, boxes[r.a], boxes[r.b]):
            kept.append(r)
    return out, kept


@pytest.mark.parametrize("seed", range(6))
def test_formulations_agree_on_random_instances(seed):
    prims, rels = _jittered_camera(seed)
    cands = generate_candidates(prims, rels, SETTINGS)
    q = select_candidates(cands, rels, QUAD)
    lin = select_candidates(cands, rels, LIN)
    assert q.optimal and lin.optimal
    assert q.objective == pytest.approx(lin.objective, abs=1e-9)
    for sel in (q, lin):
        plan = plan_from(prims, rels, [*cands, *sel.stand_ins], [], SETTINGS)
        plan["selection"].update(sel.to_json())
        assert check_selection(plan) == []


@pytest.mark.parametrize("seed", range(4))
def test_formulations_agree_on_bigger_synthetic_instances(seed):
    prims, rels, cands = synthetic(100 + seed, n_parts=8, per_part=6)
    q = select_candidates(cands, rels, QUAD)
    lin = select_candidates(cands, rels, LIN)
    assert q.objective == pytest.approx(lin.objective, abs=1e-9)


# --------------------------------------------------------------------------- the checker can fail


def test_checker_catches_broken_selections():
    prims, rels = camera()
    cands = generate_candidates(prims, rels, SETTINGS)
    sel = select_candidates(cands, rels, SETTINGS)
    plan = plan_from(prims, rels, [*cands, *sel.stand_ins], sel.chosen, SETTINGS, sel.objective)
    assert check_selection(plan) == []
    chosen = list(sel.chosen)

    # two candidates for one part
    extra = next(c.id for c in cands if c.part == "lens" and c.id not in chosen)
    assert any("both" in v for v in check_selection(plan, chosen + [extra]))
    # a part left out
    assert any("no candidate" in v for v in check_selection(plan, chosen[1:]))
    # a child without its parent: swap a selected parent for another candidate of its part
    # (the body is the start part: it has only its original)
    by_id = {c.id: c for c in cands}
    gone, other = next((p, o.id) for cid in chosen for p in by_id[cid].parents for o in cands
                       if o.part == by_id[p].part and o.id != p)
    swapped = [other if i == gone else i for i in chosen]
    assert any("not selected" in v for v in check_selection(plan, swapped))
    # a preserved relation broken: the selected prism slid 0.3 along x, off the body's
    # mid-plane x = 5 (bisector tolerance 0.05)
    moved = json.loads(json.dumps(plan))
    prism = next(c for c in moved["candidates"] if c["id"] in chosen and c["part"] == "prism")
    prism["box"][0][0] += 0.3
    prism["box"][1][0] += 0.3
    problems = check_selection(moved)
    assert any("bisector body-prism axis 0 broken" in v for v in problems)
    # an anchor off its ratio: nudge the selected grip's box by 1e-6
    grip = next(c for c in plan["candidates"] if c["id"] in chosen and c["part"] == "grip")
    grip["box"][0][1] += 1e-6
    assert any("anchor" in v for v in check_selection(plan))
    # a wrong objective
    plan["selection"]["objective"] = sel.objective + 1.0
    assert check_objective(plan)


# --------------------------------------------------------------------------- model and reporting


def test_model_size_and_names(caplog):
    prims, rels = camera()
    cands = generate_candidates(prims, rels, SETTINGS)
    q = build_selection_model(cands, rels, QUAD)
    lin = build_selection_model(cands, rels, LIN)
    assert list(q.pick) == sorted(c.id for c in cands)
    assert q.pick["body"].name == "pick[body]"
    assert lin.n_constraints <= q.n_constraints
    assert q.start == ("body", "grip", "lens", "prism")
    # the all-originals start is a solution of both (the quadratic model's "any" binaries set)
    assert lin.scip.getNSols() == 1 and q.scip.getNSols() == 1
    assert not [r for r in caplog.records if "start" in r.getMessage()]
    assert q.n_vars > lin.n_vars == len(cands)


def test_selection_json_and_determinism():
    prims, rels = camera()
    cands = generate_candidates(prims, rels, SETTINGS)
    a = select_candidates(cands, rels, SETTINGS)
    b = select_candidates(cands, rels, SETTINGS)
    assert a.chosen == b.chosen and a.objective == b.objective
    data = json.loads(json.dumps(a.to_json()))
    assert data["solver"] == "scip" and data["formulation"] == SETTINGS.formulation == "linear"
    assert data["status"] == "optimal" and data["optimal"] is True and data["gap"] == 0.0
    assert data["weights"] == {"adjust": 1.0, "difficulty": 1.0} and data["max_change"] == 0.1
    assert data["selected"] == list(a.chosen) and data["seconds"] >= 0


def test_weights_change_the_choice():
    prims, rels = camera()
    cands = generate_candidates(prims, rels, SETTINGS)
    # With difficulty 1000x more expensive than adjustment, guides are not worth it: the
    # originals (E_e = 0) win.
    heavy = dataclasses.replace(SETTINGS, weight_difficulty=1000.0)
    sel = select_candidates(cands, rels, heavy)
    assert sel.chosen == ("body", "grip", "lens", "prism")
    assert sel.objective == pytest.approx(4 * 6.0)  # four originals, E_d = 6 each


def test_errors():
    prims, rels = camera()
    cands = list(generate_candidates(prims, rels, SETTINGS))
    with pytest.raises(SelectionError, match="more than once"):
        select_candidates(cands + [cands[0]], rels, SETTINGS)
    with pytest.raises(SelectionError, match="formulation"):
        select_candidates(cands, rels, dataclasses.replace(SETTINGS, formulation="magic"))
    with pytest.raises(SelectionError, match="unknown candidate"):
        select_candidates([dataclasses.replace(cands[1], parents=("nobody",))] + cands[2:],
                          rels, SETTINGS)
    # infeasible: the only candidates of two parts always break their preserved relation
    a = Candidate("a<b#1", "a", ((0, 0, 0), (1, 1, 1)), False, (), 1, (), (0, 1, 2), 1.0, 0.0)
    b = Candidate("b<a#1", "b", ((5, 0, 0), (6, 1, 1)), False, (), 1, (), (0, 1, 2), 1.0, 0.0)
    r = Relation("a", "b", "bisector", 0, 0.1, {"preserved": True})
    with pytest.raises(SelectionError, match="no valid selection") as info:
        select_candidates([a, b], [r], SETTINGS)
    assert "time_limit_s" not in str(info.value)  # infeasible: more time would not help


def test_interrupted_solve_raises_keyboard_interrupt():
    # Ctrl-C in SCIP ends the solve with status "userinterrupt" and the start solution still
    # loaded: that must stop h2s like any Ctrl-C, not become a selection.
    from h2s_print.select import solve_selection_model

    class Interrupted:
        def __init__(self, scip):
            self.scip, self.params = scip, {}

        def setParam(self, name, value):
            self.params[name] = value
            self.scip.setParam(name, value)

        def getStatus(self):
            return "userinterrupt"

        def __getattr__(self, name):
            return getattr(self.scip, name)

    _, rels, cands = synthetic(0)
    model = build_selection_model(cands, rels, SETTINGS)
    model.scip = fake = Interrupted(model.scip)
    with pytest.raises(KeyboardInterrupt):
        solve_selection_model(model)
    assert fake.params["misc/catchctrlc"] is True  # SCIP stops at once on Ctrl-C


def test_plane_on_body_is_selected_flat():
    prims = [prim("body", (0, 0, 0), (10, 4, 6)),
             prim("plate", (2.6, 1.05, 6), (7.4, 3.0, 6), "plane", 2)]
    rels = [rel("body", "plate", "coplanar", 2, a_end="hi", b_end="lo", coord=6.0,
                preserved=True)]
    cands = generate_candidates(prims, rels, SETTINGS)
    sel = select_candidates(cands, rels, SETTINGS)
    plan = plan_from(prims, rels, [*cands, *sel.stand_ins], sel.chosen, SETTINGS, sel.objective)
    assert check_selection(plan) == [] and check_objective(plan) == []
    plate = next(c for c in cands if c.id in sel.chosen and c.part == "plate")
    assert plate.anchors and plate.box[0][2] == plate.box[1][2] == 6.0


# --------------------------------------------------------------------------- real inputs


def _stages_1_to_4(spec, settings):
    from h2s_print.fit import fit_primitives
    from h2s_print.load import load_model
    from h2s_print.relate import detect_relations

    prims = fit_primitives(load_model(spec))
    rels = detect_relations(prims)
    return prims, rels, generate_candidates(prims, rels, settings)


@pytest.mark.parametrize("name", ["camera", "mixer", "roller", "train"])
def test_formulations_agree_on_the_examples(name):
    from conftest import CONFIGS
    from h2s_print.config import load_tutorial

    cfg = load_tutorial(CONFIGS / f"{name}.yaml")
    prims, rels, cands = _stages_1_to_4(cfg.model, cfg.solver)
    sels = [select_candidates(cands, rels, dataclasses.replace(cfg.solver, formulation=f))
            for f in ("linear", "quadratic")]
    assert all(s.optimal and s.status == "optimal" for s in sels)
    # equal to SCIP's optimality tolerance (two optimal selections of the train differ by
    # 2e-7 in 55: within numerics/epsilon relative to the objective's 15 terms)
    assert sels[0].objective == pytest.approx(sels[1].objective, rel=1e-8)
    for sel in sels:
        plan = plan_from(prims, rels, [*cands, *sel.stand_ins], sel.chosen, cfg.solver, sel.objective)
        assert check_selection(plan) == [] and check_objective(plan) == []


SHARED = [("partnet_mobility_oven_101773", "y", 5), ("partnet_mobility_bottle_3763", "y", 1),
          ("trimesh_pins_plate/pins.glb", "z", 3),
          ("ikea_chair_ingolf/chair_ingolf_0650.glb", "z", 2),
          ("ikea_table_lack/table_lack_0825.glb", "z", 2),
          ("ikea_desk_fredrik/desk_fredrik_0430.glb", "z", 1),
          ("ikea_box_ivar/box_ivar_0666.glb", "z", 2)]


@pytest.mark.parametrize("path, up, min_anchored", SHARED, ids=[s[0].split("/")[0] for s in SHARED])
def test_shared_model_plans_pass_the_checker(shared_models, path, up, min_anchored):
    from h2s_print.config import ModelSpec

    prims, rels, cands = _stages_1_to_4(ModelSpec(shared_models / path, up=up), SETTINGS)
    sel = select_candidates(cands, rels, SETTINGS)
    assert sel.optimal
    plan = plan_from(prims, rels, [*cands, *sel.stand_ins], sel.chosen, SETTINGS, sel.objective)
    assert check_selection(plan) == [] and check_objective(plan) == []
    assert [p for c in plan["candidates"] for p in check_candidate(plan, c)] == []
    by_id = {c.id: c for c in [*cands, *sel.stand_ins]}
    # measured: oven 9 of 10 parts anchored (0 before its body's box enclosed the body),
    # bottle 1/3, pins 6/7, chair 3/5, table 4/5, desk 2/6, Ivar 4/5
    assert sum(1 for i in sel.chosen if by_id[i].anchors) >= min_anchored


@pytest.mark.parametrize("seed", range(5))
def test_more_candidates_never_raise_the_optimum(seed):
    # Dropping candidates (with everything that hangs off them) can only remove options: the
    # optimum of the full set is never above a subset's.  (Before stand-ins a child could use
    # only the exact parent box it was generated off; measured on a 29-part assembly, 286 of
    # 290 adjusted candidates of unanchored parts hung off a parent box that was not chosen.)
    prims, rels = _jittered_camera(seed)
    cands = generate_candidates(prims, rels, SETTINGS)
    rng = random.Random(seed)
    dropped = {c.id for c in cands if not c.original and rng.random() < 0.4}
    keep = []
    for c in sorted(cands, key=lambda c: c.depth):
        if c.id in dropped or any(p not in {k.id for k in keep} for p in c.parents):
            continue
        keep.append(c)
    full = select_candidates(cands, rels, SETTINGS)
    part = select_candidates(keep, rels, SETTINGS)
    assert full.optimal and part.optimal
    assert full.objective <= part.objective + 1e-9
    plan = plan_from(prims, rels, [*cands, *full.stand_ins], full.chosen, SETTINGS,
                     full.objective)
    assert check_selection(plan) == [] and check_objective(plan) == []


def test_a_parent_is_stood_in_for_by_an_equal_interval_candidate():
    # The camera example: its selection uses stand-ins (measured: the prism hangs off a lens
    # candidate equal to the chosen one along x), reported as copies ('*') whose parents are
    # the selected candidates, with the anchors' ratio equations exact on them.
    from conftest import CONFIGS
    from h2s_print.config import load_tutorial

    cfg = load_tutorial(CONFIGS / "camera.yaml")
    prims, rels, cands = _stages_1_to_4(cfg.model, cfg.solver)
    sel = select_candidates(cands, rels, cfg.solver)
    assert sel.stand_ins
    by_id = {c.id: c for c in [*cands, *sel.stand_ins]}
    for copy in sel.stand_ins:
        assert copy.id.endswith("*") and copy.id in sel.chosen
        source = by_id[copy.id[:-1]]
        assert copy.box == source.box and copy.cost_adjust == source.cost_adjust
        for a, b in zip(copy.anchors, source.anchors):
            p, q = by_id[a.parent].box, by_id[b.parent].box
            assert a.parent in sel.chosen
            assert (p[0][a.axis], p[1][a.axis]) == (q[0][b.axis], q[1][b.axis])


def _ring_of_stand_ins(copies: int):
    """Three parts, each with ``copies`` anchored candidates (cost 1) hanging off the next
    part's original (a off b, b off c, c off a), all with the originals' box (cost 6): any
    anchored candidate of the next part may stand in for its original, so every selection of
    three anchored candidates closes a cycle."""
    from h2s_print.candidates import Anchor

    base = ((0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
    parts = ("a", "b", "c")
    prims = [Primitive(p, "cuboid", None, base, 0.0) for p in parts]
    cands = [Candidate(p, p, base, True, (), 0, (), (0, 1, 2), 6.0, 0.0) for p in parts]
    for p, q in zip(parts, parts[1:] + parts[:1]):
        for k in range(1, copies + 1):
            cands.append(Candidate(f"{p}<{q}#{k}", p, base, False, (q,), 1,
                                   (Anchor(0, "lo", q, 0.0, 1, 1),), (1, 2), 1.0, 0.0))
    return prims, cands


@pytest.mark.parametrize("copies", [1, 2])
def test_stand_ins_never_close_a_cycle_and_the_optimum_is_the_brute_forces(copies):
    # Every cheap selection closes a cycle (a off b's stand-in, b off c's, c off a's): the
    # answer is the least-cost acyclic one, 1 + 1 + 6 (brute force over every assignment,
    # validity and cycles decided by the checker).  Until stop 29 a cyclic selection was cut
    # off and the model solved again up to four times, then solved with stand-ins no deeper
    # than their parent: with two copies (eight cyclic selections) that gave 1 + 6 + 6.
    prims, cands = _ring_of_stand_ins(copies)
    plan = plan_from(prims, [], cands, [], SETTINGS)
    want, _ = brute_force(plan)
    assert want == pytest.approx(8.0)
    for settings in (QUAD, LIN):
        sel = select_candidates(cands, [], settings)
        assert sel.optimal and sel.objective == pytest.approx(want, abs=1e-9)
        assert check_selection(plan, [c.rstrip("*") for c in sel.chosen], contract=False,
                               stand_in=True) == []
        done = plan_from(prims, [], [*cands, *sel.stand_ins], sel.chosen, settings,
                         sel.objective)
        assert check_selection(done, contract=False) == []  # copies hang off what is chosen


def test_order_rows_take_an_acyclic_start_and_refuse_a_cyclic_one():
    # With the order rows on, an earlier selection handed to SCIP as a start is accepted when
    # its parts hang off each other without a cycle (order values exist for it) and refused
    # when its stand-ins close one; without the rows both are accepted.
    prims, cands = _ring_of_stand_ins(1)
    acyclic, cyclic = ("a<b#1", "b<c#1", "c"), ("a<b#1", "b<c#1", "c<a#1")
    for order, want in ((True, (2, 1)), (False, (2, 2))):
        got = tuple(build_selection_model(cands, [], LIN, hint=h, order=order).scip.getNSols()
                    for h in (acyclic, cyclic))
        assert got == want, (order, got)  # the all-originals start and the hint


# ----------------------------------------------------------------------------- off the selection


def _extended(prims, rels):
    from h2s_print.candidates import extend_candidates

    cands = generate_candidates(prims, rels, SETTINGS)
    sel = select_candidates(cands, rels, SETTINGS)
    seeds = [c.rstrip("*") for c in sel.chosen]
    return cands, seeds, extend_candidates(prims, rels, SETTINGS, cands, seeds)


def test_candidates_made_off_a_selection_are_new_and_hang_off_it(shared_models):
    # extend_candidates: ids never clash with the candidates given, every new candidate
    # satisfies the contract (its ratio equations), and hangs off the seeds or off other new
    # candidates only (the selection is what it is made off).  The IKEA table: its first
    # candidates miss ways off the selected top (test below).
    from h2s_print.config import ModelSpec

    prims, rels, _ = _stages_1_to_4(
        ModelSpec(shared_models / "ikea_table_lack/table_lack_0825.glb", up="z"), SETTINGS)
    cands, seeds, more = _extended(prims, rels)
    assert more
    known = {c.id for c in cands}
    assert not known & {c.id for c in more} and len({c.id for c in more}) == len(more)
    new = {c.id for c in more}
    by_id = {c.id: c for c in [*cands, *more]}
    def off_seeds(cid):  # cid is a seed or hangs off seeds (through any candidates)
        return cid in seeds or (bool(by_id[cid].parents)
                                and all(off_seeds(p) for p in by_id[cid].parents))

    for c in more:
        assert not c.original
        # a parent is a seed, a new candidate, or one made before and again off seeds
        assert all(p in seeds or p in new or off_seeds(p) for p in c.parents), c.id
        assert off_seeds(c.id), c.id
    # the first candidates are not all off the seeds (what the test could miss)
    assert any(not off_seeds(c.id) for c in cands)
    plan = plan_from(prims, rels, [*cands, *more], [], SETTINGS)
    assert [p for c in plan["candidates"] for p in check_candidate(plan, c)] == []


def _choose_checked(prims, rels, settings):
    """plan.choose's answer, checked by the independent checker over the candidates it
    returns (what plan.json lists), and the first selection's objective."""
    from h2s_print.plan import choose

    first = select_candidates(generate_candidates(prims, rels, settings), rels, settings)
    cands, sel = choose(prims, rels, settings)
    assert sel.optimal
    plan = plan_from(prims, rels, [*cands, *sel.stand_ins], sel.chosen, settings, sel.objective)
    assert check_selection(plan) == [] and check_objective(plan) == []
    assert [p for c in plan["candidates"] for p in check_candidate(plan, c)] == []
    return first.objective, cands, sel


@pytest.mark.parametrize("seed", range(4))
def test_choosing_off_the_selection_never_costs_more(seed):
    prims, rels = _jittered_camera(seed)
    before, _, sel = _choose_checked(prims, rels, SETTINGS)
    assert sel.objective <= before + 1e-9


def test_the_table_hangs_every_leg_off_the_top(shared_models):
    # The IKEA table: pruning kept, for a leg's top end, only pairs off other legs'
    # originals, so one leg stayed unanchored ("a box, by eye") and the others hung off it.
    # Made off the selection, a leg's top at the top's underside (ratio 0) off the top alone
    # survives: measured objective 17.16 -> 14.40, every leg anchored.
    from h2s_print.config import ModelSpec

    prims, rels, cands = _stages_1_to_4(
        ModelSpec(shared_models / "ikea_table_lack/table_lack_0825.glb", up="z"), SETTINGS)
    before, cands, sel = _choose_checked(prims, rels, SETTINGS)
    assert sel.objective < before - 1.0
    by_id = {c.id: c for c in [*cands, *sel.stand_ins]}
    top = max(prims, key=lambda p: p.box[1][2]).part
    legs = [by_id[i] for i in sel.chosen if by_id[i].part != top]
    assert len(legs) == 4 and all(c.anchors for c in legs)
    hung = [c for c in legs if any(a.axis == 2 and a.end == "hi" and by_id[a.parent].part == top
                                   and a.ratio == 0.0 for a in c.anchors)]
    assert hung


def test_a_candidate_made_off_the_selection_stands_in_for_the_parent_it_equals():
    # The mixer: the column was drawn by eye (its original) because the bowl, the head and
    # the knob hang off that original; the column centred on the base, standing on it and
    # flush with its back has the same box, and it is made only off the selection.  The
    # rounds off the selection let it stand in whatever its depth (until stop 29 only a
    # stand-in no deeper than the parent: objective 22.52, the column by eye).
    from conftest import CONFIGS
    from h2s_print.config import load_tutorial

    cfg = load_tutorial(CONFIGS / "mixer.yaml")
    prims, rels, _ = _stages_1_to_4(cfg.model, cfg.solver)
    _, cands, sel = _choose_checked(prims, rels, cfg.solver)
    by_id = {c.id: c for c in [*cands, *sel.stand_ins]}
    chosen = {by_id[i].part: by_id[i] for i in sel.chosen}
    column, base = chosen["column"], chosen["base"]
    assert {by_id[a.parent].part for a in column.anchors} == {"base"}
    assert column.box == next(p for p in prims if p.part == "column").box
    ends = {(a.axis, a.end, a.ratio) for a in column.anchors}
    assert {(0, "mid", 0.5), (1, "hi", 1.0), (2, "lo", 1.0)} <= ends  # centred, flush, on it
    assert sum(c.parents == () for c in chosen.values()) == 1  # the base alone by eye
    assert not base.anchors and sel.objective < 22.5


def _mirror_pair():
    """Two identical parts, each drawable by eye (original, cost 6) or off the other (cost
    3): two selections cost 9, mirror images of each other."""
    box = ((0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
    cands = []
    for me, other in (("near", "far"), ("far", "near")):
        cands.append(Candidate(me, me, box, True, (), 0, (), (0, 1, 2), 6.0, 0.0))
        cands.append(Candidate(f"{me}<{other}#1", me, box, False, (other,), 1, (), (1, 2),
                               3.0, 0.0))
    return cands


@pytest.mark.parametrize("settings", [LIN, QUAD], ids=["linear", "quadratic"])
def test_ties_go_nearest_first(settings):
    # equal costs: the part nearer the tutorial's eyes is drawn by eye and the other hangs
    # off it, whichever part the names or the solver's order would put first
    cands = _mirror_pair()
    for near, far in (("near", "far"), ("far", "near")):
        sel = select_candidates(cands, [], settings, farness={near: 0.0, far: 1.0})
        assert set(sel.chosen) == {near, f"{far}<{near}#1"}
        assert sel.objective == 9.0  # the reported objective is the cost alone
    # a real cost difference is never outweighed by the tie-break
    dearer = [dataclasses.replace(c, cost_adjust=6.0 + 1e-4) if c.id == "far" else c
              for c in cands]
    sel = select_candidates(dearer, [], settings, farness={"near": 1.0, "far": 0.0})
    assert set(sel.chosen) == {"near", "far<near#1"}


def test_part_farness_is_the_distance_from_the_views_eyes():
    from h2s_print.config import ViewSpec
    from h2s_print.plan import part_farness

    def box(y):
        return Primitive(f"y{y:+d}", "cuboid", None, ((0.0, y - 0.5, 0.0), (1.0, y + 0.5, 1.0)),
                         0.0)

    prims = [box(-2), box(0), box(2)]
    front = ViewSpec("front", azimuth_deg=0.0, elevation_deg=0.0)  # the eye on -y
    back = ViewSpec("back", azimuth_deg=180.0, elevation_deg=0.0)
    assert part_farness(prims, [front]) == pytest.approx({"y-2": 0.0, "y+0": 0.5, "y+2": 1.0})
    assert part_farness(prims, [back]) == pytest.approx({"y-2": 1.0, "y+0": 0.5, "y+2": 0.0})
    assert part_farness(prims, [front, back]) == pytest.approx(
        {"y-2": 0.5, "y+0": 0.5, "y+2": 0.5})
    assert part_farness(prims, []) == {}
