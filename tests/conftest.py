"""Shared test helpers: where the public test models live, and small factories."""

from __future__ import annotations

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
CONFIGS = REPO / "configs"
#: Real segmented models from public sources (never copied into this repository).
SHARED_MODELS = REPO.parent / "shared" / "models"


def pytest_addoption(parser):
    parser.addoption("--update-golden", action="store_true", default=False,
                     help="rewrite golden files under tests/golden instead of comparing")


@pytest.fixture
def update_golden(request) -> bool:
    return bool(request.config.getoption("--update-golden"))


#: The example tutorials (every config but the book and the study): the paper's four objects.
EXAMPLES = sorted(p.stem for p in CONFIGS.glob("*.yaml") if p.stem not in ("book", "study"))
#: The levels with guides, and all levels a tutorial can have.
GUIDED = ("novice", "apprentice", "master")


@pytest.fixture(scope="session")
def examples():
    """name -> (tutorial, plan, {(view name, level): ViewPlan}) for the four examples, every
    view at the config's levels, the guided ones and ``basic``; built once per test run."""
    from h2s_print import sequence as seq
    from h2s_print.config import load_tutorial
    from h2s_print.plan import build_plan

    out = {}
    for name in EXAMPLES:
        t = load_tutorial(CONFIGS / f"{name}.yaml")
        plan = build_plan(t.model, t.solver, t.views)
        views = {}
        for view in t.views:
            levels = tuple(dict.fromkeys(tuple(t.levels) + GUIDED + ("basic",)))
            for vp in seq.sequence_views(plan, view, levels, t.paper, t.sequence):
                views[(view.name, vp.level)] = vp
        out[name] = (t, plan, views)
    return out


@pytest.fixture(scope="session")
def shared_models() -> Path:
    """Folder of the public test models; tests using it skip when it is absent."""
    if not SHARED_MODELS.is_dir():
        pytest.skip("../shared/models is not present")
    return SHARED_MODELS


def side_names(tutorial, plan, view, ends=("lo", "hi", "mid")) -> dict[str, tuple[int, str]]:
    """A view's words for a part's sides ("left side", "back", "middle (left to right)") ->
    ``(axis, end)``: the picture decides which side is left (``words.side``)."""
    from h2s_print.sequence import context as seq_context

    words = seq_context._context(plan, view, tutorial.paper, tutorial.sequence).words
    return {words.side(a, e): (a, e) for a in range(3) for e in ends}


def check_carries_from_on(steps) -> int:
    """Each "Carry XY from A on LM ..." sentence of ``steps``: A lies on the carried line XY
    and on the segment LM, from the letters' 3D points (``_Context.crossing_lines``; a
    read-through found "Carry XY from V' ..." with nothing saying what V' was).  Returns how
    many it checked."""
    import re

    import numpy as np

    cite = r"(?: \(step \d+\))?"  # a line of an earlier step says which (cite_earlier)
    pattern = re.compile(rf"Carry ([A-Z]'?)([A-Z]'?){cite} from ([A-Z]'?) on ([A-Z]'?)([A-Z]'?)"
                         rf"{cite} ")

    def on_line(p, a, b) -> bool:
        d = b - a
        return float(np.linalg.norm(np.cross(d, p - a))) <= 1e-6 * max(1.0, float(np.dot(d, d)))

    seen = 0
    for s in steps:
        at = {lb.name: np.asarray(lb.at3d, dtype=float) for lb in s.labels}
        for x in s.substeps:
            m = pattern.match(x)
            if not m:
                continue
            a, b, p, c, d = (at[k] for k in m.groups())
            assert on_line(p, a, b), x
            assert on_line(p, c, d) and min(np.dot(p - c, d - c), np.dot(p - d, c - d)) >= -1e-9, x
            seen += 1
    return seen
