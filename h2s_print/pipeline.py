"""The whole job: config -> plan -> views -> pages -> files.

This is the only module besides the loader and the renderer that touches files: it decides
the output names and writes each through :mod:`h2s_print.files` (atomic).  Layout of the
output folder (``-o DIR``, default ``output/``):

* tutorial config ``camera.yaml``: ``DIR/camera/plan.json`` and one workbook per (view, level)
  ``DIR/camera/camera-<view>-<level>.pdf``;
* book config ``book.yaml``: ``DIR/book/book.pdf`` (all workbooks, contents page, bookmarks)
  and ``DIR/book/<tutorial>/plan.json`` per tutorial.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from pathlib import Path

from .config import BookConfig, TutorialConfig, load_config
from .files import write_json_atomic
from .plan import Plan, build_plan, plan_json
from .types import Stroke, ViewPlan

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True, eq=False)
class TutorialResult:
    """A tutorial's plan and its view plans (one per view and level, config order)."""

    tutorial: TutorialConfig
    plan: Plan
    views: tuple[ViewPlan, ...]
    finals: tuple[tuple[Stroke, ...], ...]  #: finished drawing per entry of ``views``


def plan_tutorial(tutorial: TutorialConfig) -> TutorialResult:
    """Stages 1-8 for every view and level of one tutorial."""
    from .sequence import final_strokes, sequence_view

    plan = build_plan(tutorial.model, tutorial.solver)
    sel = plan.selection
    if not sel.optimal:
        log.warning("%s: selection NOT proven optimal (SCIP status %s, gap %.3g) - time limit "
                    "%.0f s reached; using the best selection found", tutorial.name, sel.status,
                    sel.gap, tutorial.solver.time_limit_s)
    views: list[ViewPlan] = []
    finals: list[tuple[Stroke, ...]] = []
    for view in tutorial.views:
        for level in tutorial.levels:
            vp = sequence_view(plan, view, level, tutorial.paper, tutorial.sequence)
            views.append(vp)
            finals.append(final_strokes(plan, vp.camera, tutorial.sequence, level=level))
    return TutorialResult(tutorial, plan, tuple(views), tuple(finals))


def write_plan(result: TutorialResult, folder: Path) -> Path:
    """Write ``folder/plan.json`` atomically; returns its path."""
    return write_json_atomic(Path(folder) / "plan.json", plan_json(result.plan, result.views))


def steps_text(result: TutorialResult) -> str:
    """Every view's steps as readable text (``h2s plan --text``)."""
    from .sequence import steps_text as view_text

    blocks = []
    for vp in result.views:
        blocks.append(f"== {result.tutorial.title}: view {vp.name}, level {vp.level} ==\n"
                      + view_text(vp))
    return "\n".join(blocks)


def _workbook_pages(result: TutorialResult, index: int):
    from .layout import lay_out_workbook

    vp = result.views[index]
    tutorial = result.tutorial
    # cover, primer, steps, finished drawing and the calibrated sheet
    return lay_out_workbook(tutorial.title, vp, tutorial.paper, view_label=vp.name,
                            final=result.finals[index])


def build(config_path: Path, out_dir: Path) -> list[Path]:
    """``h2s build``: PDFs and plan.json for a tutorial or a book config; returns paths written."""
    from .render import render_pdf

    cfg = load_config(config_path)
    out_dir = Path(out_dir)
    written: list[Path] = []
    if isinstance(cfg, TutorialConfig):
        result = plan_tutorial(cfg)
        folder = out_dir / cfg.name
        for i, vp in enumerate(result.views):
            path = folder / f"{cfg.name}-{vp.name}-{vp.level}.pdf"
            render_pdf(_workbook_pages(result, i), path)
            written.append(path)
        written.append(write_plan(result, folder))
        return written

    assert isinstance(cfg, BookConfig)
    from .layout import OUTLINE_SEP, lay_out_book

    folder = out_dir / cfg.name
    results = [plan_tutorial(t) for t in cfg.tutorials]
    workbooks = []
    for result in results:
        for i, vp in enumerate(result.views):
            label = OUTLINE_SEP.join((result.tutorial.title, vp.name, vp.level))
            workbooks.append((label, _workbook_pages(result, i)))
    pages = lay_out_book(cfg.title, workbooks)
    path = folder / f"{cfg.name}.pdf"
    render_pdf(pages, path)
    written.append(path)
    for result in results:
        written.append(write_plan(result, folder / result.tutorial.name))
    return written
