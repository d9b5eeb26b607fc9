"""The model-level plan (stages 1-5) and the ``plan.json`` contract (DESIGN.md §3).

Stages 1-5 depend on the model and the solver settings, and on the tutorial's views only to
break ties between selections of equal cost nearest first (:func:`part_farness`), so one
:class:`Plan` serves every view and level of a tutorial.  ``plan_json`` writes exactly the
contract's fields; other tools read them.

Determinism: a plan.json depends only on the config and the model files, except
``selection.seconds``, the measured solver wall time the contract asks for.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Any, Sequence

from .config import ModelSpec, SolverSettings, ViewSpec
from .types import Model, Primitive, Relation, ViewPlan

log = logging.getLogger(__name__)

SCHEMA = "h2s-plan/1"


@dataclass(frozen=True, slots=True, eq=False)
class Plan:
    """Everything stages 1-5 produce for one model.

    Attributes:
        model: the loaded model.
        primitives: one per part, in ``model.parts`` order.
        relations: every relation found (``detail["preserved"]`` marks the kept ones).
        candidates: every candidate (``h2s_print.candidates.Candidate``), sorted by id.
        selection: the solver's answer (``h2s_print.select.Selection``).
        settings: the solver settings used.
    """

    model: Model
    primitives: tuple[Primitive, ...]
    relations: tuple[Relation, ...]
    candidates: tuple[Any, ...]
    selection: Any
    settings: SolverSettings

    def primitive(self, part: str) -> Primitive:
        for p in self.primitives:
            if p.part == part:
                return p
        raise KeyError(part)

    def chosen(self) -> dict[str, Any]:
        """Selected candidate per part name."""
        by_id = {c.id: c for c in self.candidates}
        return {by_id[cid].part: by_id[cid] for cid in self.selection.chosen}


def build_plan(spec: ModelSpec, settings: SolverSettings,
               views: Sequence[ViewSpec] = ()) -> Plan:
    """Run stages 1-5: load, fit, relate, generate candidates, select (:func:`choose`); ties
    between selections of equal cost go nearest first in ``views`` (:func:`part_farness`)."""
    from .fit import fit_primitives
    from .load import load_model
    from .relate import detect_relations

    model = load_model(spec)
    primitives = fit_primitives(model)
    relations = detect_relations(primitives)
    candidates, selection = choose(primitives, relations, settings,
                                   part_farness(primitives, views))
    # selected candidates whose parents were stood in for (select docstring) join the list
    candidates = tuple(candidates) + tuple(selection.stand_ins)
    return Plan(model, primitives, relations, candidates, selection, settings)


#: Rounds of candidates made off the selection (:func:`choose`) at most.
REFINE_ROUNDS = 3


def part_farness(primitives: Sequence[Primitive], views: Sequence[ViewSpec]) -> dict[str, float]:
    """Part -> how far it is from the tutorial's eyes: 0 for the nearest part, 1 for the
    farthest, by the distance from each view's eye to the centre of the part's fitted box,
    averaged over ``views`` (empty without views).

    The eye is placed as ``project.make_camera`` places it, framing the fitted boxes (the
    drawing frames the adjusted ones, which the selection decides: this is the same eye up
    to those adjustments).  It breaks ties in the selection (``select``, module docstring).
    """
    import numpy as np

    from .project import view_direction

    if not views or not primitives:
        return {}
    boxes = np.array([p.box for p in primitives], dtype=float)  # (n, 2, 3)
    lo, hi = boxes[:, 0].min(axis=0), boxes[:, 1].max(axis=0)
    target, radius = (lo + hi) / 2, 0.5 * float(np.linalg.norm(hi - lo))
    centres = boxes.mean(axis=1)
    total = np.zeros(len(primitives))
    for view in views:
        eye = target + view.distance * radius * view_direction(view)  # as make_camera
        dist = np.linalg.norm(centres - eye, axis=1)
        span = float(dist.max() - dist.min())
        total += (dist - dist.min()) / span if span > 0 else 0.0
    return {p.part: float(f) for p, f in zip(primitives, total / len(views))}


def choose(primitives: Sequence[Primitive], relations: Sequence[Relation],
           settings: SolverSettings, farness: dict[str, float] | None = None
           ) -> tuple[tuple[Any, ...], Any]:
    """Stages 4-5: the candidates and the selection among them.

    Candidates are made off the originals and one is selected per part (stages 4, 5).  Then,
    up to :data:`REFINE_ROUNDS` times, more are made off the selected candidates alone
    (``candidates.extend_candidates``: pruning had cut them for ways off candidates never
    selected) and the selection is solved again over its *neighbourhood*: the originals, the
    selected candidates and the new ones, with every ancestor they need, and stand-ins of
    any depth, as in the first solve (``select``: its order rows keep them acyclic).  A
    candidate made off the selection often has the same box as the parent other selected
    candidates hang off, only anchored, and can stand in for it only if it may be deeper
    (the mixer's column, centred on the base, standing on it and flush with its back, for
    the column drawn by eye that the bowl, the head and the knob hang off).  Until stop 29
    the rounds allowed only stand-ins no deeper than their parent, two rounds: objectives
    (2026-11-25) mixer 22.52 -> 19.69, train 40.05 -> 36.10 (its third round finds 40.40 ->
    36.10; a fourth finds nothing on any benchmark model), every other benchmark model the
    same.
    The earlier selection's candidates are among them and it is SCIP's start; a round is kept
    only when it costs less, so the answer never costs more than the first selection, and a
    round that finds nothing cheaper is dropped and ends the search.

    Returned: the candidates of the last solve accepted, which is what the selection is
    proven optimal over (plan.json lists exactly those), and that selection.  Solving the
    neighbourhood rather than every candidate made keeps the solves small (the train's
    first round: 437 candidates, 0.21 s, against 845 and 1.3 s for the same optimum).

    ``farness`` (part -> [0, 1], :func:`part_farness`) breaks ties nearest first in every solve.
    """
    from .candidates import generate_candidates
    from .select import select_candidates

    candidates = generate_candidates(primitives, relations, settings)
    selection = select_candidates(candidates, relations, settings, farness=farness)
    return refine(primitives, relations, settings, candidates, selection, farness)


def refine(primitives: Sequence[Primitive], relations: Sequence[Relation],
           settings: SolverSettings, candidates: Sequence[Any], selection: Any,
           farness: dict[str, float] | None = None) -> tuple[tuple[Any, ...], Any]:
    """:func:`choose`'s rounds off the selection, from ``selection`` among ``candidates``."""
    from .candidates import extend_candidates
    from .select import select_candidates

    made = {c.id: c for c in candidates}  # every candidate made (ids stay unique)
    for _ in range(REFINE_ROUNDS):
        seeds = [cid.rstrip("*") for cid in selection.chosen]
        more = extend_candidates(primitives, relations, settings, tuple(made.values()), seeds)
        if not more:
            break
        made.update((c.id, c) for c in more)
        keep: set[str] = set()
        todo = [*seeds, *(c.id for c in more)]
        while todo:
            cid = todo.pop()
            if cid not in keep:
                keep.add(cid)
                todo.extend(made[cid].parents)
        near = _sorted_candidates([c for c in made.values() if c.original or c.id in keep])
        better = select_candidates(near, relations, settings, hint=seeds,
                                   farness=farness)
        if not better.objective < selection.objective - 1e-9 * max(1.0, selection.objective):
            break
        log.info("selection off the selection: objective %.6f -> %.6f (%d more candidates)",
                 selection.objective, better.objective, len(more))
        candidates, selection = near, better
    return tuple(candidates), selection


def _sorted_candidates(cands: Sequence[Any]) -> tuple[Any, ...]:
    """By part, the original first, then by id's generation count (ids per prefix count
    up, ``candidates.generate_candidates``'s order within a part)."""
    def key(c: Any) -> tuple:
        prefix, _, k = c.id.rpartition("#")
        return (c.part, not c.original, prefix if k else "", int(k) if k.isdigit() else 0)
    return tuple(sorted(cands, key=key))


# ----------------------------------------------------------------------------- JSON


def _vec(v: Sequence[float]) -> list[float]:
    return [float(x) for x in v]


def _box(box: Any) -> list[list[float]]:
    return [_vec(box[0]), _vec(box[1])]


def model_json(model: Model) -> dict[str, Any]:
    """The contract's ``model`` entry."""
    return {"source": model.source, "up": "z", "units": model.units,
            "bounds": _box(model.bounds)}


def part_json(primitive: Primitive, bounds: Any = None) -> dict[str, Any]:
    """One entry of the contract's ``parts`` (plus ``bounds``, the part mesh's own
    axis-aligned bounding box, when given: DESIGN.md §5's "beyond its part" needs it)."""
    out = {
        "name": primitive.part,
        "primitive": {"type": primitive.type, "axis": primitive.axis,
                      "box": _box(primitive.box)},
        "residual": float(primitive.residual),
    }
    if bounds is not None:
        out["bounds"] = _box(bounds)
    return out


def relation_json(relation: Relation) -> dict[str, Any]:
    """One entry of the contract's ``relations``."""
    return {"a": relation.a, "b": relation.b, "type": relation.type, "axis": relation.axis,
            "tolerance": float(relation.tolerance), "detail": dict(relation.detail)}


def view_json(view: ViewPlan) -> dict[str, Any]:
    """One entry of the contract's ``views``."""
    return {
        "name": view.name,
        "level": view.level,
        "paper_mm": _vec(view.paper_mm),
        "camera": {
            "projection_mm": [_vec(row) for row in view.camera.projection_mm],
            "position": _vec(view.camera.position),
            "perspective": view.camera.perspective,
        },
        "vanishing_points": [
            {"axis": vp.axis, "at_infinity": vp.at_infinity,
             "xy_mm": None if vp.xy_mm is None else _vec(vp.xy_mm),
             "direction_mm": _vec(vp.direction_mm)}
            for vp in view.vanishing_points
        ],
        "steps": [_step_json(step) for step in view.steps],
    }


def _step_json(step: Any) -> dict[str, Any]:
    out: dict[str, Any] = {
        "index": step.index, "part": step.part, "kind": step.kind, "text": step.text,
        "eyeball": step.eyeball,
        "guides": [
            {"id": g.id, "status": g.status, "role": g.role,
             "from3d": _vec(g.from3d), "to3d": _vec(g.to3d),
             "from_mm": _vec(g.from_mm), "to_mm": _vec(g.to_mm)}
            for g in step.guides
        ],
        "alive": list(step.alive),
        "headline": step.headline,
        "substeps": list(step.substeps),
        "summary": step.summary,
        "labels": [{"name": lb.name, "kind": lb.kind, "at3d": _vec(lb.at3d),
                    "at_mm": _vec(lb.at_mm)} for lb in step.labels],
    }
    strokes = [s for s in step.strokes if s.kind != "contour"]
    contours = [s for s in step.strokes if s.kind == "contour"]
    out["strokes"] = [{"kind": s.kind, "part": s.part,
                       "points3d": [_vec(p) for p in s.points3d],
                       "points_mm": [_vec(p) for p in s.points_mm]} for s in strokes]
    if step.kind == "contour":
        out["polylines3d"] = [[_vec(p) for p in s.points3d] for s in contours]
        out["polylines_mm"] = [[_vec(p) for p in s.points_mm] for s in contours]
    return out


def plan_json(plan: Plan, views: Sequence[ViewPlan] = ()) -> dict[str, Any]:
    """The whole ``plan.json`` document (DESIGN.md §3)."""
    return {
        "schema": SCHEMA,
        "model": model_json(plan.model),
        "parts": [part_json(p, plan.model.part(p.part).box) for p in plan.primitives],
        "relations": [relation_json(r) for r in plan.relations],
        "candidates": [c.to_json() for c in plan.candidates],
        "selection": plan.selection.to_json(),
        "views": [view_json(v) for v in views],
    }


def inspect_json(primitives: Sequence[Primitive], relations: Sequence[Relation]) -> dict[str, Any]:
    """``h2s inspect --json``: the contract's ``parts`` and ``relations`` fields only."""
    return {"parts": [part_json(p) for p in primitives],
            "relations": [relation_json(r) for r in relations]}
