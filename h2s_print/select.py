"""Stage 5: choose one candidate per part, validly and at least cost, with SCIP (paper §4.3).

One binary ``χ`` per candidate.  A selection is valid when (paper eq. 1-3):

1. exactly one candidate per part is selected;
2. every selected candidate's parents are selected, or *stood in for*: a parent may be
   replaced by another candidate of its part with exactly the same intervals along every axis
   the child anchors off it (:func:`substitutes`), because an anchor ties the child only to
   the parent's interval along that axis.  A stand-in never descends from a candidate of
   the child's own part, and the parts hang off each other without a cycle: a selected
   candidate hangs off its parents' *parts* whichever candidates stand in, so one order
   variable per part (``u``, continuous in ``[0, m - 1]``, ``m`` the parts of its strongly
   connected component of the part graph) and one row per edge ``A -> B`` of that graph,
   ``u(A) - u(B) >= 1 - m (1 - Σ χ(c))`` over the candidates ``c`` of ``A`` hanging off ``B``,
   make every selection acyclic (a topological order exists exactly when the graph of the
   selected parts' links has no cycle).  Only edges inside a strongly connected component can
   close a cycle; the others get no row.  The model is solved without them first: most
   selections close no cycle, and then that optimum is the optimum with them too (it
   satisfies them); only when its stand-ins close one is it solved again with the rows
   (measured, 2026-11-25: the rows every time cost gen80's plan 21.2 -> 27.1 s, solved
   first without them 22.0 s).  Until stop 29 a selection whose stand-ins closed a
   cycle was cut off and the model solved again, four times, and then with stand-ins no
   deeper than the parent they stand in for, which is not optimal: on a ring of three parts
   whose cheap selections all close a cycle, 13 against the optimum 8 (a test).  The
   answer names the stand-ins: a selected candidate whose parent was stood in for is reported
   as a copy (id + ``*``) hanging off the stand-in (:attr:`Selection.stand_ins`), so
   plan.json's parents and ratio equations hold as written.  In the quadratic formulation a
   parent with stand-ins is a product with their *any* binary (below); its order rows are
   the same linear rows.  Without stand-ins a
   part often stayed unguided because every one of its candidates hung off a version of a
   parent that was not selected.
3. no two selected candidates break a preserved relation of their parts
   (``candidates.relation_holds`` on their boxes, within the relation's tolerance).

Objective: ``min Σ χ(c) · (w_adjust E_d(c) + w_difficulty E_e(c))``.

Ties go nearest first (the paper's rule among parts of similar size).  Selections of equal
cost are common: identical parts in mirror image (the train's left and right wheels) cost the
same whichever is drawn by eye and whichever hangs off the other, and SCIP then picks one of
them by chance (the train's novice tutorials drew the hidden far wheel by eye and the near one
from it).  Given ``farness`` (part -> 0 for the part nearest the tutorial's eyes .. 1 for the
farthest, ``plan.part_farness``), each candidate's objective coefficient gets
``TIE_BREAK · t(c)``, ``t`` the part's own farness for an original (drawn by eye) and the mean
farness of its parents' parts for an anchored candidate; :data:`TIE_BREAK` is 1e-6, so it
decides only between selections whose costs differ by less than 1e-6 per part.  The reported
objective is the cost alone.

Two formulations of the same problem (``settings.formulation``):

* ``quadratic`` (the paper's): ``χ(c) χ(p) − χ(c) ≥ 0`` per parent and, per preserved
  relation, the paper's ``χ(a) χ(b) = 0`` for every relation-breaking pair, written as one
  native quadratic row per group of the linear formulation below:
  ``any(group) · any(S) = 0``.  ``any(X)`` is ``χ`` itself for one candidate, else a binary
  defined by the linear row ``any(X) = Σ_{c in X} χ(c)`` (binary, because ``X`` holds
  candidates of one part, of which one is picked); a parent's stand-ins enter the parent row
  the same way, ``χ(c) any(subs) − χ(c) ≥ 0``.  Exact: ``any(group) · any(S)`` is 0 exactly
  when no breaking pair is selected.  Every product is of two binaries, which SCIP takes
  natively (an AND).  Measured on 80 generated parts: one row per pair was 313k rows and
  timed out; the product of the two sums, ``(Σ group)(Σ S) = 0``, 12-30 s (SCIP expanded and
  factorised each product of sums); the *any* binaries, 3 s.
* ``linear``: ``χ(c) ≤ χ(p)`` per parent; per preserved relation ``(i, j)``, the candidates of
  ``i`` are grouped by the set ``S`` of candidates of ``j`` they conflict with, and one row
  ``Σ_{c in group} χ(c) + Σ_{d in S} χ(d) ≤ 1`` per group.  Exact (at most one candidate of a
  part is selected, so the row forbids exactly the conflicting pairs) and one row per distinct
  conflict set, which is the number of distinct face/centre positions, O(n) at worst.

Build and solve are separate (:func:`build_selection_model`, :func:`solve_selection_model`);
variables and constraints are added in sorted id order and named after ids (``pick[grip<body#3]``,
``parent[grip<body#3|body]``, ``keep[body-lens:bisector@0|...]``), so runs are reproducible and an
infeasibility names its relation.  The all-originals selection is valid by construction (input
relations hold between the input primitives) and is handed to SCIP as a start solution.
"""

from __future__ import annotations

import dataclasses
import itertools
import logging
import math
from dataclasses import dataclass, field
from typing import Any, Mapping, Sequence

import numpy as np
from pyscipopt import Model, quicksum
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import connected_components

from .candidates import Candidate, preserved_relations, relation_holds, relation_holds_table
from .config import FORMULATIONS, SolverSettings
from .errors import SelectionError
from .types import Relation

log = logging.getLogger(__name__)

#: SCIP status strings mapped to the plan.json ``status`` words.
_STATUS = {"optimal": "optimal", "timelimit": "time_limit", "gaplimit": "gap_limit",
           "infeasible": "infeasible", "userinterrupt": "interrupted",
           "memlimit": "memory_limit", "nodelimit": "node_limit", "sollimit": "solution_limit"}


@dataclass(frozen=True, slots=True)
class Selection:
    """The chosen candidates and how the solve went (DESIGN.md §3 ``selection``).

    Attributes:
        chosen: selected candidate ids, one per part, sorted.
        objective: weighted cost of ``chosen`` (unit-free).
        status: ``optimal``, ``time_limit``, ``gap_limit`` ... (SCIP's status, snake_case).
        gap: SCIP's relative primal-dual gap (0 when proven optimal).
        seconds: SCIP solving time, seconds.
        formulation: ``quadratic`` or ``linear``.
        optimal: True only when SCIP proved optimality; callers must say so otherwise.
        n_vars: binary variables: one per candidate, and in the quadratic formulation one per
            set of candidates a product row multiplies (``any``, module docstring).
        n_constraints: constraints added to the model.
        weight_adjust, weight_difficulty: the objective's weights.
        max_change: the change limit the candidates were generated with.
        stand_ins: copies of selected candidates that hang off a stand-in parent (their ids
            end in ``*``; ``chosen`` names them instead of the originals they copy).
    """

    chosen: tuple[str, ...]
    objective: float
    status: str
    gap: float
    seconds: float
    formulation: str
    optimal: bool
    n_vars: int
    n_constraints: int
    weight_adjust: float = 1.0
    weight_difficulty: float = 1.0
    max_change: float = 0.10
    stand_ins: tuple[Candidate, ...] = ()

    def to_json(self) -> dict[str, Any]:
        """The plan.json ``selection`` object (plus ``gap``, ``optimal`` and model size)."""
        return {
            "solver": "scip",
            "formulation": self.formulation,
            "status": self.status,
            "optimal": self.optimal,
            "weights": {"adjust": self.weight_adjust, "difficulty": self.weight_difficulty},
            "max_change": self.max_change,
            "objective": self.objective,
            "gap": self.gap,
            "selected": list(self.chosen),
            "seconds": self.seconds,
            "n_vars": self.n_vars,
            "n_constraints": self.n_constraints,
        }


@dataclass(eq=False)
class SelectionModel:
    """A built SCIP model of the selection problem (not yet solved).

    Attributes:
        scip: the pyscipopt ``Model``.
        pick: candidate id -> its binary variable, in sorted id order.
        formulation: ``quadratic`` or ``linear``.
        costs: candidate id -> weighted objective coefficient.
        start: ids of the start solution (all originals), empty when a part has no original.
        n_constraints: constraints added.
        n_vars: binary variables added.
        settings: the solver settings.
        candidates: the candidates, sorted by id.
        subs: (candidate, parent) -> the candidates that may stand in for the parent
            (:func:`substitutes`), as the parent rows were written.
    """

    scip: Model
    pick: dict[str, Any]
    formulation: str
    costs: dict[str, float]
    start: tuple[str, ...] = ()
    n_constraints: int = 0
    n_vars: int = 0
    settings: SolverSettings = field(default_factory=SolverSettings)
    candidates: tuple[Candidate, ...] = ()
    subs: dict[tuple[str, str], tuple[str, ...]] = field(default_factory=dict)


def _conflicts(rel: Relation, cands_a: Sequence[Candidate], cands_b: Sequence[Candidate],
               boxes_a: Any = None, boxes_b: Any = None) -> dict[str, tuple[str, ...]]:
    """For each candidate of ``rel.a``, the candidates of ``rel.b`` it breaks ``rel`` with
    (``boxes_a``, ``boxes_b``: their boxes as arrays, when the caller has them)."""
    out: dict[str, tuple[str, ...]] = {}
    holds = relation_holds_table(
        rel, [c.box for c in cands_a] if boxes_a is None else boxes_a,
        [c.box for c in cands_b] if boxes_b is None else boxes_b)
    ids_b = [c.id for c in cands_b]
    for ca, breaks in zip(cands_a, (~holds).tolist()):
        bad = tuple(itertools.compress(ids_b, breaks))
        if bad:
            out[ca.id] = bad
    return out


def _check(candidates: Sequence[Candidate], relations: Sequence[Relation],
           settings: SolverSettings) -> None:
    if settings.formulation not in FORMULATIONS:
        raise SelectionError(f"solver.formulation: expected one of {', '.join(FORMULATIONS)}, "
                             f"got {settings.formulation!r}")
    if not candidates:
        raise SelectionError("no candidates to select from (no parts?)")
    ids = [c.id for c in candidates]
    if len(set(ids)) != len(ids):
        dup = sorted({i for i in ids if ids.count(i) > 1})[0]
        raise SelectionError(f"candidates: id {dup!r} appears more than once")
    known = set(ids)
    for c in candidates:
        for p in c.parents:
            if p not in known:
                raise SelectionError(f"candidates: {c.id!r} hangs off unknown candidate {p!r}")
        for x in (c.cost_adjust, c.cost_difficulty):
            if not math.isfinite(x):
                raise SelectionError(f"candidates: {c.id!r} has a non-finite cost {x}")
    parts = {c.part for c in candidates}
    for r in relations:
        if r.a not in parts or r.b not in parts:
            raise SelectionError(f"relations: {r.type} {r.a}-{r.b} names a part with no candidate")


def build_selection_model(candidates: Sequence[Candidate], relations: Sequence[Relation],
                          settings: SolverSettings, *, hint: Sequence[str] = (),
                          farness: Mapping[str, float] | None = None,
                          order: bool = True) -> SelectionModel:
    """Build (do not solve) the SCIP model for ``settings.formulation``; ``hint``, a selection
    (candidate ids, one per part), is handed to SCIP as a start solution besides the
    all-originals one when it is one; ``farness`` (part -> [0, 1]) breaks ties nearest first
    (module docstring); without ``order``, no order rows (a selection may then close a
    cycle: :func:`select_candidates` tries that first).

    Raises:
        SelectionError: unknown formulation, duplicate ids, dangling parents.
    """
    _check(candidates, relations, settings)
    cands = sorted(candidates, key=lambda c: c.id)
    by_part: dict[str, list[Candidate]] = {}
    for c in cands:
        by_part.setdefault(c.part, []).append(c)
    quadratic = settings.formulation == "quadratic"

    scip = Model("h2s-selection")
    scip.hideOutput()
    pick = {c.id: scip.addVar(name=f"pick[{c.id}]", vtype="B") for c in cands}
    costs = {c.id: c.cost(settings.weight_adjust, settings.weight_difficulty) for c in cands}
    n = 0
    # (1) one candidate per part
    for part in sorted(by_part):
        scip.addCons(quicksum(pick[c.id] for c in by_part[part]) == 1, name=f"one[{part}]")
        n += 1
    # Quadratic rows multiply binaries: a set of one part's candidates (at most one of which
    # is picked) enters a product as one binary equal to their sum, so that every product is
    # of two binaries, which SCIP handles natively (an AND of two binaries).
    anys: dict[tuple[str, ...], Any] = {}

    def one_of(ids: Sequence[str]) -> Any:
        nonlocal n
        if len(ids) == 1:
            return pick[ids[0]]
        key = tuple(ids)
        if key not in anys:
            v = scip.addVar(name=f"any[{len(anys)}:{ids[0]}]", vtype="B")
            scip.addCons(v == quicksum(pick[i] for i in ids), name=f"anydef[{len(anys)}]")
            anys[key] = v
            n += 1
        return anys[key]

    # (2) parents selected with their children: the parent itself or a candidate of its part
    # with the same intervals along the axes the child anchors off it (module docstring)
    subs = substitutes(cands)
    for c in cands:
        for p in c.parents:
            name = f"parent[{c.id}|{p}]"
            if quadratic:  # the paper's product row
                scip.addCons(pick[c.id] * one_of(subs[c.id, p]) - pick[c.id] >= 0, name=name)
            else:
                scip.addCons(pick[c.id] <= quicksum(pick[q] for q in subs[c.id, p]), name=name)
            n += 1
    # (3) preserved relations kept; each part's boxes made an array once (a part has
    # several preserved relations: gen40, 40 parts and 234 relations)
    boxes: dict[str, np.ndarray] = {}
    for rel in preserved_relations(relations):
        for p in (rel.a, rel.b):
            if p not in boxes:
                boxes[p] = np.array([c.box for c in by_part[p]], dtype=float).reshape(-1, 2, 3)
        originals_a = [c for c in by_part[rel.a] if c.original]
        originals_b = [c for c in by_part[rel.b] if c.original]
        if originals_a and originals_b and not relation_holds(rel, originals_a[0].box,
                                                               originals_b[0].box):
            log.warning("relation %s %s-%s axis %d does not hold on the input primitives; "
                        "not preserved", rel.type, rel.a, rel.b, rel.axis)
            continue
        tag = f"{rel.a}-{rel.b}:{rel.type}@{rel.axis}"
        conflicts = _conflicts(rel, by_part[rel.a], by_part[rel.b], boxes[rel.a], boxes[rel.b])
        groups: dict[tuple[str, ...], list[str]] = {}
        for a_id in sorted(conflicts):
            groups.setdefault(conflicts[a_id], []).append(a_id)
        for bad, group in sorted(groups.items(), key=lambda g: g[1][0]):
            if quadratic:  # the paper's products, one row per group: (Σ mine)(Σ theirs) = 0
                scip.addCons(one_of(group) * one_of(bad) == 0, name=f"keep[{tag}|{group[0]}]")
            else:
                scip.addCons(quicksum(pick[i] for i in group) + quicksum(pick[j] for j in bad)
                             <= 1, name=f"keep[{tag}|{group[0]}]")
            n += 1
    # (4) no cycle of parts hanging off each other (module docstring)
    cyclic = _cyclic_edges(cands) if order else {}
    order_vars: dict[str, Any] = {}
    for (a, b), (m, users) in sorted(cyclic.items()):
        for part in (a, b):
            if part not in order_vars:
                order_vars[part] = scip.addVar(name=f"order[{part}]", vtype="C", lb=0.0,
                                               ub=m - 1)
        scip.addCons(order_vars[a] - order_vars[b] - m * quicksum(pick[i] for i in users)
                     >= 1 - m, name=f"order[{a}|{b}]")
        n += 1
    ties = tie_breaks(cands, farness or {})
    scip.setObjective(quicksum((costs[c.id] + ties[c.id]) * pick[c.id] for c in cands),
                      sense="minimize")

    def offer(ids: Sequence[str]) -> bool:
        """Hand SCIP a start solution; False when it is not one."""
        sol = scip.createSol()
        chosen = set(ids)
        for c in cands:
            scip.setSolVal(sol, pick[c.id], 1.0 if c.id in chosen else 0.0)
        for group, var in anys.items():
            scip.setSolVal(sol, var, 1.0 if chosen.intersection(group) else 0.0)
        rank = _rank(cyclic, chosen)
        if rank is None:
            scip.freeSol(sol)
            return False
        for part, var in order_vars.items():
            scip.setSolVal(sol, var, float(rank[part]))
        if not scip.checkSol(sol):
            scip.freeSol(sol)
            return False
        return bool(scip.addSol(sol, free=True))

    start: tuple[str, ...] = ()
    if all(any(c.original for c in by_part[p]) for p in by_part):
        start = tuple(c.id for c in cands if c.original)
        if not offer(start):  # a bug in the rows above, never the input's fault
            log.warning("the all-originals start is not a solution of the selection model")
    if hint and all(i in pick for i in hint):
        offer(hint)  # an earlier selection (plan.choose)
    return SelectionModel(scip=scip, pick=pick, formulation=settings.formulation, costs=costs,
                          start=start, n_constraints=n, n_vars=len(pick) + len(anys),
                          settings=settings,
                          candidates=tuple(cands), subs=subs)


def _cyclic_edges(cands: Sequence[Candidate]) -> dict[tuple[str, str], tuple[int, tuple[str, ...]]]:
    """The edges ``(A, B)`` of the part graph (a candidate of ``A`` hangs off a candidate of
    ``B``) that lie in a strongly connected component, each with that component's size and
    the candidates of ``A`` hanging off ``B`` (sorted): the edges that could close a cycle."""
    part_of = {c.id: c.part for c in cands}
    users: dict[tuple[str, str], list[str]] = {}
    for c in cands:
        for b in sorted({part_of[p] for p in c.parents}):
            users.setdefault((c.part, b), []).append(c.id)
    parts = sorted({c.part for c in cands})
    index = {p: i for i, p in enumerate(parts)}
    if not users:
        return {}
    rows, cols = zip(*((index[a], index[b]) for a, b in users))
    graph = csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(len(parts), len(parts)))
    _, label = connected_components(graph, directed=True, connection="strong")
    size = np.bincount(label)
    return {(a, b): (int(size[label[index[a]]]), tuple(sorted(ids)))
            for (a, b), ids in users.items() if label[index[a]] == label[index[b]]}


def _rank(cyclic: Mapping[tuple[str, str], tuple[int, Sequence[str]]],
          chosen: set[str]) -> dict[str, int] | None:
    """Order values for a selection (candidate ids ``chosen``) that satisfy the order rows of
    ``cyclic`` (:func:`_cyclic_edges`): per part, the longest chain of selected links inside
    its component below it; None when those links close a cycle."""
    below: dict[str, list[str]] = {}
    for (a, b), (_, users) in cyclic.items():
        below.setdefault(a, [])
        below.setdefault(b, [])
        if chosen.intersection(users):
            below[a].append(b)
    rank: dict[str, int] = {}
    visiting: set[str] = set()

    def walk(part: str) -> bool:
        stack = [(part, iter(below[part]))]
        visiting.add(part)
        while stack:
            node, it = stack[-1]
            nxt = next(it, None)
            if nxt is None:
                stack.pop()
                visiting.discard(node)
                rank[node] = 1 + max((rank[x] for x in below[node]), default=-1)
            elif nxt in visiting:
                return False
            elif nxt not in rank:
                visiting.add(nxt)
                stack.append((nxt, iter(below[nxt])))
        return True

    for part in sorted(below):
        if part not in rank and not walk(part):
            return None
    return rank


#: SCIP's nonlinear handlers the quadratic formulation turns off (:func:`solve_selection_model`).
_NLHDLRS_OFF = ("convex", "concave", "bilinear", "perspective", "quadratic", "quotient",
                "signomial", "soc")


def solve_selection_model(model: SelectionModel) -> Selection:
    """Solve a built model within ``settings.time_limit_s``.

    Raises:
        SelectionError: SCIP found no solution (infeasible, or no solution in time).
        KeyboardInterrupt: Ctrl-C during the solve (SCIP status ``userinterrupt``).
    """
    scip, settings = model.scip, model.settings
    scip.setParam("limits/time", float(settings.time_limit_s))
    scip.setParam("randomization/randomseedshift", 0)
    # No restarts: after the root's fixings SCIP would presolve and solve again from scratch,
    # which on some small models repeated the whole root (the IKEA table, 121 candidates:
    # 2.6 s a solve, 0.3 s without; no benchmark model got slower; same optima).
    scip.setParam("presolving/maxrestarts", 0)
    if model.formulation == "quadratic":
        # Probing during presolve fixes each binary in turn and propagates: over the AND
        # constraints of the products it cost more than it found (bench_select, quadratic:
        # gen80 3.4 -> 2.3 s, the train 0.44 -> 0.21 s, the camera 0.05 -> 0.03 s; the
        # linear model gains nothing from it being off, so keeps SCIP's default).
        scip.setParam("propagating/probing/maxprerounds", 0)
        # Every product is of two binaries, which presolve turns into AND constraints and
        # then linear rows: the nonlinear handlers that look for convex, quadratic, bilinear
        # ... structure (for spatial branching and cuts) find nothing to do, at a cost
        # (bench_select, quadratic, 2026-11-24: the roller 0.047 -> 0.029 s, gen20 0.28 ->
        # 0.19 s, gen80 1.92 -> 1.73 s; same optima).  ``default`` stays: it handles any
        # expression the others do not.
        for handler in _NLHDLRS_OFF:
            scip.setParam(f"nlhdlr/{handler}/enabled", False)
    # Ctrl-C: SCIP's handler stops the solve at once with status "userinterrupt" (with
    # catchctrlc off, Python would only see the signal after the whole solve, measured 26 s
    # late); that is not a selection, so it becomes the KeyboardInterrupt Ctrl-C means.
    scip.setParam("misc/catchctrlc", True)
    scip.optimize()
    raw = scip.getStatus()
    if raw == "userinterrupt":
        raise KeyboardInterrupt("SCIP solve interrupted (Ctrl-C)")
    status = _STATUS.get(raw, raw)
    if scip.getNSols() == 0:
        hint = ("; raise solver.time_limit_s or lower solver.depth" if status == "time_limit"
                else "")
        raise SelectionError(f"SCIP ended {status!r} with no valid selection "
                             f"({len(model.pick)} candidates, formulation {model.formulation})"
                             f"{hint}")
    best = scip.getBestSol()
    chosen = tuple(sorted(cid for cid, var in model.pick.items()
                          if scip.getSolVal(best, var) > 0.5))
    objective = math.fsum(model.costs[c] for c in chosen)
    chosen, stand_ins = _stand_in(model.candidates, model.subs, chosen)
    optimal = raw == "optimal"
    gap = 0.0 if optimal else float(scip.getGap())
    if not optimal:
        log.warning("selection not proven optimal: SCIP status %s, gap %.3g", status, gap)
    return Selection(chosen=chosen, objective=objective, status=status, gap=gap,
                     seconds=float(scip.getSolvingTime()), formulation=model.formulation,
                     optimal=optimal, n_vars=model.n_vars, n_constraints=model.n_constraints,
                     weight_adjust=settings.weight_adjust,
                     weight_difficulty=settings.weight_difficulty,
                     max_change=settings.max_change, stand_ins=stand_ins)


#: Weight of the nearest-first tie-break per candidate (module docstring).
TIE_BREAK = 1e-6


def tie_breaks(cands: Sequence[Candidate], farness: Mapping[str, float]) -> dict[str, float]:
    """Each candidate's tie-break term: :data:`TIE_BREAK` times its part's farness for an
    original, the mean farness of its parents' parts for an anchored one (0 without
    ``farness``)."""
    if not farness:
        return {c.id: 0.0 for c in cands}
    part_of = {c.id: c.part for c in cands}
    out = {}
    for c in cands:
        far = ([farness.get(c.part, 0.0)] if not c.parents
               else [farness.get(part_of.get(p, ""), 0.0) for p in c.parents])
        out[c.id] = TIE_BREAK * math.fsum(far) / len(far)
    return out


def substitutes(cands: Sequence[Candidate]) -> dict[tuple[str, str], tuple[str, ...]]:
    """For each (candidate, parent): the candidates that may stand in for the parent.

    An anchor ties the child to the parent's interval along the anchored axis, never to its
    other axes; so any candidate of the parent's part with exactly the same intervals along
    every axis the child anchors off that parent keeps every anchor's ratio equation (and the
    construction, on the stand-in's face).  A stand-in never descends from a candidate of
    the child's own part (the order rows keep the rest acyclic, module docstring).  A
    parent the child does not anchor off (a
    relation-restoring parent) has no stand-in.
    """
    by_id = {c.id: c for c in cands}
    by_part: dict[str, list[Candidate]] = {}
    for c in cands:
        by_part.setdefault(c.part, []).append(c)
    index: dict[tuple, dict[tuple, list[str]]] = {}
    out: dict[tuple[str, str], tuple[str, ...]] = {}
    ancestors: dict[str, frozenset[str]] = {}
    for c in sorted(cands, key=lambda c: c.depth):  # parents are shallower: already known
        ancestors[c.id] = frozenset(x for p in c.parents if p in ancestors
                                    for x in ancestors[p] | {by_id[p].part})
    for c in cands:
        for p in c.parents:
            axes = tuple(sorted({a.axis for a in c.anchors if a.parent == p}))
            if not axes:
                out[c.id, p] = (p,)
                continue
            part = by_id[p].part
            table = index.get((part, axes))
            if table is None:
                table = {}
                for q in by_part[part]:
                    key = tuple((q.box[0][a], q.box[1][a]) for a in axes)
                    table.setdefault(key, []).append(q.id)
                index[(part, axes)] = table
            key = tuple((by_id[p].box[0][a], by_id[p].box[1][a]) for a in axes)
            out[c.id, p] = tuple(sorted(
                q for q in table[key]
                if q == p or c.part not in ancestors[q]))
    return out


def _stand_in(cands: Sequence[Candidate], subs: dict[tuple[str, str], tuple[str, ...]],
              chosen: Sequence[str]) -> tuple[tuple[str, ...], tuple[Candidate, ...]]:
    """The selection with every parent replaced by its selected stand-in (``subs``: the
    model's :func:`substitutes`).

    A selected candidate whose parent was stood in for (or was itself copied) becomes a copy
    with the stand-in as its parent and ``*`` appended to its id; the copies are returned to
    be added to the plan's candidates.
    """
    by_id = {c.id: c for c in cands}
    picked = set(chosen)
    selected = {by_id[c].part: by_id[c] for c in chosen}
    final: dict[str, Candidate] = {}
    copies: list[Candidate] = []
    todo = sorted(selected)
    while todo:
        progressed = False
        for part in list(todo):
            c = selected[part]
            stand = {}
            for p in c.parents:
                q = next(q for q in subs[c.id, p] if q in picked)
                stand[p] = by_id[q].part
            if not all(pp in final for pp in stand.values()):
                continue
            parents = {p: final[pp] for p, pp in stand.items()}
            if all(parents[p].id == p for p in parents):
                final[part] = c
            else:
                depth = 1 + max(x.depth for x in parents.values())
                new = dataclasses.replace(
                    c, id=f"{c.id}*", parents=tuple(sorted(x.id for x in parents.values())),
                    depth=depth,
                    anchors=tuple(dataclasses.replace(a, parent=parents[a.parent].id)
                                  for a in c.anchors))
                final[part] = new
                copies.append(new)
            todo.remove(part)
            progressed = True
        if not progressed:  # solved without the order rows (select_candidates solves
            # again with them); with them, a bug, never the input's fault
            raise _Cycle(f"the anchoring graph has a cycle among {sorted(todo)}")
    return tuple(sorted(x.id for x in final.values())), tuple(sorted(copies, key=lambda c: c.id))


def select_candidates(candidates: Sequence[Candidate], relations: Sequence[Relation],
                      settings: SolverSettings, *, hint: Sequence[str] = (),
                      farness: Mapping[str, float] | None = None) -> Selection:
    """Choose one candidate per part: valid (eq. 1-3) and of least weighted cost.

    Args:
        candidates: every candidate (``generate_candidates``), originals included.
        relations: all relations; those with ``detail["preserved"]`` must be kept.
        settings: ``formulation``, ``time_limit_s``, weights, ``max_change`` (reported).
        hint: an earlier selection, handed to SCIP as a start (``plan.choose``).
        farness: part -> [0, 1], ties nearest first (module docstring); none without.

    Returns:
        the selection; ``optimal`` is False when SCIP stopped before proving it.

    Raises:
        SelectionError: bad input or no valid selection found.
    """
    try:  # most selections close no cycle: the order rows cost time only where one does
        return solve_selection_model(build_selection_model(candidates, relations, settings,
                                                           hint=hint, farness=farness,
                                                           order=False))
    except _Cycle as cycle:
        log.info("%s; solving again with order rows", cycle)
    return solve_selection_model(build_selection_model(candidates, relations, settings,
                                                       hint=hint, farness=farness))


class _Cycle(SelectionError):
    """A selection's stand-ins closed a cycle (internal: :func:`select_candidates` solves
    again with order rows; with them it is a bug)."""
