"""The whole job: config -> plan -> views -> pages -> files.

This is the only module besides the loader and the renderer that touches files: it decides
the output names, computes every output's bytes first and then writes them all through
:func:`h2s_print.files.write_many_atomic`.  Layout of the output folder (``-o DIR``, default
``output/``):

* tutorial config ``camera.yaml``: ``DIR/camera/plan.json`` and one workbook per (view, level)
  ``DIR/camera/camera-<view>-<level>.pdf``;
* book config ``book.yaml``: ``DIR/book/book.pdf`` (all workbooks, contents page, bookmarks)
  and ``DIR/book/<tutorial>/plan.json`` per tutorial;
* with ``output: {svg: true, png: true}`` in a tutorial's config, each step page of each
  workbook also as ``<tutorial folder>/<view>-<level>/step-NN.svg`` / ``.png`` named by the
  steps on it: ``step-03.svg`` for a page with step 3 alone, ``steps-03-04.svg`` for a page
  with steps 3 and 4 (numbers as in plan.json, from 01); stale step files of an earlier export
  in that folder are removed;
* ``DIR/.h2s-cache/``: solved plans (:mod:`h2s_print.cache`).

All or nothing: a build computes every file's bytes before writing any, so a user error or
Ctrl-C in tutorial 3 leaves tutorials 1-2's old outputs untouched (never a mix of new and old
from one run, never a partial file).  Only plan cache entries are written as soon as they are
solved, so the next run after fixing tutorial 3 does not solve 1-2 again.

Errors raised inside a stage are re-raised naming the config file and field the user can fix:
``camera.yaml: views[1]: a three-point camera at elevation ...``.

``jobs > 1`` builds a book's tutorials in that many worker processes (``spawn``); results are
byte-identical to ``jobs = 1``.  Progress is reported to an optional callback as
:class:`Event` values (this module never prints).
"""

from __future__ import annotations

import logging
import re
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

from .config import BookConfig, TutorialConfig, load_config
from .errors import ConfigError, H2SError, ModelError, SelectionError
from .files import check_writable, dumps_json, write_many_atomic
from .plan import Plan, build_plan, plan_json
from .types import Stroke, ViewPlan

log = logging.getLogger(__name__)

#: An exported step page holding one step (``step-03.svg``) ...
STEP_FILE = "step-{:02d}.{}"
#: ... or several, first and last (``steps-03-04.svg``).
STEPS_FILE = "steps-{:02d}-{:02d}.{}"
#: The name of any exported step page (both forms).
STEP_FILE_RE = re.compile(r"(step-\d+|steps-\d+-\d+)\.(svg|png)")


# ----------------------------------------------------------------------------- progress


@dataclass(frozen=True, slots=True)
class Event:
    """One piece of progress.

    Attributes:
        tutorial: the tutorial's name (config file stem), or the book's for book-level work.
        stage: ``plan``, ``views``, ``layout``, ``export``, ``pdf``, ``book`` or ``write``.
        text: what happened, for a person (``plan from cache``).
        units: work units this event completes (see :func:`work_units`); 0 for a notice.
        milestone: worth a line of its own when not on a terminal.
    """

    tutorial: str
    stage: str
    text: str
    units: int = 0
    milestone: bool = False


Progress = Callable[[Event], None]


def _quiet(event: Event) -> None:
    del event


def _n(count: int, noun: str) -> str:
    return f"{count} {noun}{'' if count == 1 else 's'}"


def work_units(cfg: TutorialConfig | BookConfig) -> int:
    """How many units the events of building ``cfg`` add up to (for a progress bar).

    Per tutorial: 1 for the plan, 1 per (view, level) for sequencing, 1 per workbook for its
    layout, 1 per workbook for step SVG/PNG export when asked; a tutorial config adds 1 per PDF, a
    book 1 for the book; 1 for writing the files.
    """
    tutorials = cfg.tutorials if isinstance(cfg, BookConfig) else (cfg,)
    total = 1
    for t in tutorials:
        n = len(t.views) * len(t.levels)
        total += 1 + 2 * n + (n if (t.output.svg or t.output.png) else 0)
        if isinstance(cfg, TutorialConfig):
            total += n
    if isinstance(cfg, BookConfig):
        total += 1
    return total


# ----------------------------------------------------------------------------- error context

#: A config field path at the start of a message, followed by ": " (``views[1].lens_mm: ``).
_FIELD_START = re.compile(
    r"(model(\.(path|up|units|parts)[\w.\[\]]*)?|views(\[\d+\](\.\w+)?)?|levels(\[\d+\])?"
    r"|(paper|solver|sequence|output)(\.\w+)?|title|tutorials(\[\d+\])?): ")
_VIEW_PREFIX = re.compile(r"view '[^']*'(?: \(([a-z]+)\))?: ")
_SOLVER_FIELD = re.compile(r"\bsolver\.[a-z_]+")


def in_config(exc: H2SError, config: Path, field: str) -> H2SError:
    """``exc`` re-made to name ``config`` (and ``field`` unless it already names a field).

    A message already starting with the config's file name is kept.  A leading
    ``view 'name': `` is replaced by the field (``views[1]``).  A model loader message
    ``model.glb: model.parts...: ...`` is moved onto the config's own field.
    """
    name = Path(config).name
    msg = str(exc)
    if msg.startswith(f"{name}:"):
        return exc
    msg = _VIEW_PREFIX.sub(lambda m: f"level {m.group(1)}: " if m.group(1) else "", msg, count=1)
    head, sep, rest = msg.partition(": ")
    if sep and _FIELD_START.match(rest) and not _FIELD_START.match(head):
        msg = rest  # "<model file>: model.parts.drop[0]: ..." -> the config's field
    if not _FIELD_START.match(msg):
        msg = f"{field}: {msg}"
    return type(exc)(f"{name}: {msg}")


def _plan_field(exc: H2SError) -> str:
    if isinstance(exc, SelectionError):
        found = _SOLVER_FIELD.search(str(exc))
        return found.group(0) if found else "solver"
    if isinstance(exc, (ModelError, ConfigError)) and "no such file or folder" in str(exc):
        return "model.path"
    return "model"


# ----------------------------------------------------------------------------- one tutorial


@dataclass(frozen=True, slots=True, eq=False)
class TutorialResult:
    """A tutorial's plan and its view plans (one per view and level, config order).

    Attributes:
        tutorial: the config.
        plan: stages 1-5.
        views: one per (view, level), views outer, levels inner.
        finals: finished drawing per entry of ``views``.
        cached: the plan came from the cache.
    """

    tutorial: TutorialConfig
    plan: Plan
    views: tuple[ViewPlan, ...]
    finals: tuple[tuple[Stroke, ...], ...]
    cached: bool = False


def _plan_text(plan: Plan, cached: bool, seconds: float, tutorial: TutorialConfig) -> str:
    sel = plan.selection
    where = "from cache" if cached else f"solved in {seconds:.2f} s"
    text = (f"plan {where}: {len(plan.model.parts)} parts, {len(plan.candidates)} candidates, "
            f"SCIP {sel.status}")
    if not sel.optimal:
        text += f" - NOT proven optimal (gap {sel.gap:.3g}{_limit_note(sel, tutorial)})"
    return text


def _limit_note(sel: Any, tutorial: TutorialConfig) -> str:
    """``, solver.time_limit_s 60`` when the time limit stopped SCIP, else nothing."""
    if sel.status == "time_limit":
        return f", solver.time_limit_s {tutorial.solver.time_limit_s:g}"
    return ""


def get_plan(tutorial: TutorialConfig, *, cache_dir: Path | None = None,
             progress: Progress | None = None) -> tuple[Plan, bool]:
    """Stages 1-5 of ``tutorial``, from the cache in ``cache_dir`` when there (else solved and
    stored there).  Returns ``(plan, cached)``.

    Raises:
        H2SError: naming the config file and field (``model...`` or ``solver...``).
    """
    from . import cache

    progress = progress or _quiet
    key = (cache.plan_key(tutorial.model, tutorial.solver, tutorial.views)
           if cache_dir is not None else None)
    plan = cache.load_plan(cache_dir, key) if key is not None else None
    cached = plan is not None
    start = time.perf_counter()
    if plan is None:
        progress(Event(tutorial.name, "plan", "solving the plan (load, fit, relate, candidates, "
                       "select)"))
        try:
            plan = build_plan(tutorial.model, tutorial.solver, tutorial.views)
        except H2SError as exc:
            raise in_config(exc, tutorial.path, _plan_field(exc)) from None
        if key is not None:
            cache.store_plan(cache_dir, key, plan)
    sel = plan.selection
    if cached and not sel.optimal:  # a fresh solve's warning comes from the select stage
        log.warning("%s: selection NOT proven optimal (SCIP status %s, gap %.3g%s); using the "
                    "best selection found", tutorial.name, sel.status, sel.gap,
                    _limit_note(sel, tutorial))
    progress(Event(tutorial.name, "plan",
                   _plan_text(plan, cached, time.perf_counter() - start, tutorial), 1, True))
    return plan, cached


def check_printable(tutorial: TutorialConfig, plan: Plan) -> None:
    """Every part's name is printable in the tutorial's font (a name from the model file in a
    script the font lacks is an error naming it, never ``?`` on the pages; the wording in
    templates/ is checked before the plan, :func:`h2s_print.templates.check_font`).

    Raises:
        ConfigError: naming the config and the part.
    """
    from . import fonts
    from .glyphs import describe, unprintable

    with fonts.using(tutorial.font) as spec:
        for part in plan.model.parts:
            ch = unprintable(part.name.replace("_", " "))
            if ch is not None:
                raise ConfigError(
                    f"{tutorial.path.name}: model: part {part.name!r}: character {describe(ch)} "
                    f"cannot be printed in the page font ({spec.name}): rename the part "
                    f"(model.parts.rename) or give a font that has it (font:)")


def plan_tutorial(tutorial: TutorialConfig, *, cache_dir: Path | None = None,
                  progress: Progress | None = None) -> TutorialResult:
    """Stages 1-8 for every view and level of one tutorial.

    Args:
        tutorial: the config.
        cache_dir: plan cache folder (:mod:`h2s_print.cache`); ``None``: always solve.
        progress: called with an :class:`Event` per stage done.

    Raises:
        H2SError: naming the config file and field (``camera.yaml: views[1]: ...``).
    """
    from . import templates
    from .sequence import sequence_workbooks

    progress = progress or _quiet
    with templates.using(tutorial.language):
        templates.check_font(tutorial.font)  # the wording, before any work
    plan, cached = get_plan(tutorial, cache_dir=cache_dir, progress=progress)
    check_printable(tutorial, plan)
    views: list[ViewPlan] = []
    finals: list[tuple[Stroke, ...]] = []
    for i, view in enumerate(tutorial.views):
        try:
            # one call per view: its levels share the camera and the contour work
            with templates.using(tutorial.language):  # the steps' wording
                made = sequence_workbooks(plan, view, tutorial.levels, tutorial.paper,
                                          tutorial.sequence)
        except H2SError as exc:
            raise in_config(exc, tutorial.path, f"views[{i}]") from None
        for vp, final in made:
            views.append(vp)
            finals.append(final)
            progress(Event(tutorial.name, "views", f"sequenced {view.name}/{vp.level}: "
                           f"{len(vp.steps)} steps", 1))
    progress(Event(tutorial.name, "views", f"sequenced {_n(len(views), 'workbook')}: "
                   f"{sum(len(v.steps) for v in views)} steps", 0, True))
    return TutorialResult(tutorial, plan, tuple(views), tuple(finals), cached)


def plan_bytes(result: TutorialResult) -> bytes:
    """The bytes of the tutorial's ``plan.json``."""
    return dumps_json(plan_json(result.plan, result.views)).encode("utf-8")


def steps_text(result: TutorialResult) -> str:
    """Every view's steps as readable text (``h2s plan --text``)."""
    from . import templates
    from .sequence import steps_text as view_text

    with templates.using(result.tutorial.language):
        return "\n".join(f"== {result.tutorial.title}: view {vp.name}, level {vp.level} ==\n"
                         + view_text(vp) for vp in result.views)


def _view_index(tutorial: TutorialConfig, index: int) -> int:
    return index // len(tutorial.levels)


def _workbook_pages(result: TutorialResult, index: int):
    from .layout import lay_out_workbook

    vp = result.views[index]
    tutorial = result.tutorial
    # cover, primer, steps, finished drawing and the calibrated sheet
    try:
        return lay_out_workbook(tutorial.title, vp, tutorial.paper, view_label=vp.name,
                                final=result.finals[index], grid=tutorial.sheet.grid)
    except H2SError as exc:
        raise in_config(exc, tutorial.path, f"views[{_view_index(tutorial, index)}]") from None


def step_ranges(n_steps: int, n_pages: int) -> list[tuple[int, int]]:
    """The ``(first, last)`` step numbers (from 1) on each of ``n_pages`` step pages.

    The layout puts the steps on the pages in order, the same number on each page but the
    last, so a page holds ``ceil(n_steps / n_pages)`` steps (1 at novice, 2 above).

    Raises:
        RuntimeError: ``n_pages`` cannot hold ``n_steps`` that way (a bug in the layout).
    """
    if n_pages == 0:
        if n_steps:
            raise RuntimeError(f"{n_steps} steps but no step pages")
        return []
    per = -(-n_steps // n_pages)
    if n_steps < n_pages or -(-n_steps // per) != n_pages:
        raise RuntimeError(f"{n_steps} steps do not fill {n_pages} step pages evenly")
    return [(k * per + 1, min(n_steps, (k + 1) * per)) for k in range(n_pages)]


def step_file_name(first: int, last: int, ext: str) -> str:
    """``step-03.svg`` (one step) or ``steps-03-04.svg`` (steps 3 to 4)."""
    return STEP_FILE.format(first, ext) if first == last else STEPS_FILE.format(first, last, ext)


@dataclass(frozen=True, slots=True, eq=False)
class TutorialBuild:
    """Everything one tutorial contributes to a build.

    Attributes:
        result: plan and view plans.
        workbooks: laid-out pages per entry of ``result.views``.
        files: ``(path, bytes)`` to write: plan.json, exported steps, and (tutorial configs)
            the workbook PDFs.
    """

    result: TutorialResult
    workbooks: tuple[tuple[Any, ...], ...]
    files: tuple[tuple[Path, bytes], ...]


def build_tutorial(tutorial: TutorialConfig, folder: Path, *, pdfs: bool,
                   cache_dir: Path | None = None,
                   progress: Progress | None = None) -> TutorialBuild:
    """Plan, lay out and render one tutorial into ``folder`` (nothing written but the cache).

    Args:
        tutorial: the config.
        folder: the tutorial's output folder (plan.json, PDFs, step exports go there).
        pdfs: render one PDF per workbook (tutorial configs; a book renders its own).
        cache_dir: plan cache folder, or ``None``.
        progress: called with an :class:`Event` per stage done.
    """
    from . import fonts, templates

    progress = progress or _quiet
    result = plan_tutorial(tutorial, cache_dir=cache_dir, progress=progress)
    # measured and drawn in the tutorial's font, worded in its language
    with fonts.using(tutorial.font), templates.using(tutorial.language):
        return _lay_out_and_render(result, folder, pdfs, progress)


def _lay_out_and_render(result: TutorialResult, folder: Path, pdfs: bool,
                        progress: Progress) -> TutorialBuild:
    from .render import pdf_bytes, render_png, render_svg

    tutorial = result.tutorial
    name = tutorial.name
    workbooks = []
    for i, vp in enumerate(result.views):
        workbooks.append(_workbook_pages(result, i))
        progress(Event(name, "layout", f"laid out {vp.name}/{vp.level}: "
                       f"{len(workbooks[-1])} pages", 1))
    progress(Event(name, "layout", f"laid out {_n(len(workbooks), 'workbook')}: "
                   f"{sum(len(w) for w in workbooks)} pages", 0, True))
    files: list[tuple[Path, bytes]] = []
    out = tutorial.output
    if out.svg or out.png:
        n_steps = 0
        for vp, pages in zip(result.views, workbooks):
            sub = folder / f"{vp.name}-{vp.level}"
            steps = [p for p in pages if p.kind == "steps"]
            for (first, last), page in zip(step_ranges(len(vp.steps), len(steps)), steps):
                if out.svg:
                    files.append((sub / step_file_name(first, last, "svg"),
                                  render_svg(page).encode("utf-8")))
                if out.png:
                    files.append((sub / step_file_name(first, last, "png"),
                                  render_png(page, out.png_dpi)))
            n_steps += len(steps)
            progress(Event(name, "export", f"exported {vp.name}/{vp.level}: "
                           f"{len(steps)} step pages", 1))
        kinds = " and ".join(k for k, on in (("SVG", out.svg), ("PNG", out.png)) if on)
        progress(Event(name, "export", f"exported {n_steps} step pages as {kinds}", 0, True))
    if pdfs:
        for vp, pages in zip(result.views, workbooks):
            files.append((folder / f"{name}-{vp.name}-{vp.level}.pdf", pdf_bytes(pages)))
            progress(Event(name, "pdf", f"rendered {vp.name}/{vp.level}", 1))
    files.append((folder / "plan.json", plan_bytes(result)))
    return TutorialBuild(result, tuple(workbooks), tuple(files))


# ----------------------------------------------------------------------------- workers


class _RemoteTraceback(Exception):
    """The traceback of an exception raised in a worker process (shown as its cause)."""

    def __str__(self) -> str:
        return str(self.args[0])


def _portable(exc: BaseException) -> BaseException:
    """``exc`` if it survives pickling, else a RuntimeError saying what it was."""
    import pickle

    try:
        pickle.loads(pickle.dumps(exc))
        return exc
    except Exception:  # noqa: BLE001 - any pickling failure: send a description instead
        return RuntimeError(f"{type(exc).__name__}: {exc}")


def _worker_main(tasks: Any, channel: Any, level: int, pdfs: bool,
                 cache_dir: Path | None) -> None:
    """A worker process: build the tutorials from ``tasks`` until ``None``; everything it has to
    say (log records, :class:`Event`, results, errors) goes to ``channel`` in order."""
    import logging.handlers
    import signal
    import traceback

    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    root = logging.getLogger()
    for handler in list(root.handlers):
        root.removeHandler(handler)
    root.addHandler(logging.handlers.QueueHandler(channel))
    logging.getLogger("h2s_print").setLevel(level)
    while True:
        task = tasks.get()
        if task is None:
            return
        index, tutorial, folder = task
        try:
            built = build_tutorial(tutorial, folder, pdfs=pdfs, cache_dir=cache_dir,
                                   progress=channel.put)
        except BaseException as exc:  # noqa: BLE001 - reported to the parent, which decides
            channel.put(("error", index, _portable(exc), traceback.format_exc()))
            return
        channel.put(("done", index, built))


def _build_parallel(jobs: list[tuple[TutorialConfig, Path]], pdfs: bool, cache_dir: Path | None,
                    workers: int, progress: Progress) -> list[TutorialBuild]:
    """``build_tutorial`` for each job in ``workers`` spawned processes (config order kept).

    Worker processes are plain ``multiprocessing`` processes fed from a task queue (not a
    ProcessPoolExecutor, whose shutdown waits for running tasks): the first failure, a worker
    that dies, or Ctrl-C stops every worker at once and is raised here.
    """
    import multiprocessing
    import queue as queue_mod

    ctx = multiprocessing.get_context("spawn")
    tasks, channel = ctx.Queue(), ctx.Queue()
    for index, (tutorial, folder) in enumerate(jobs):
        tasks.put((index, tutorial, folder))
    for _ in range(workers):
        tasks.put(None)
    level = logging.getLogger("h2s_print").getEffectiveLevel()
    procs = [ctx.Process(target=_worker_main, args=(tasks, channel, level, pdfs, cache_dir),
                         name=f"h2s-worker-{k}", daemon=True) for k in range(workers)]
    results: dict[int, TutorialBuild] = {}
    ok = False
    try:
        for proc in procs:
            proc.start()
        while len(results) < len(jobs):
            try:
                item = channel.get(timeout=0.1)
            except queue_mod.Empty:
                dead = [p for p in procs if p.exitcode not in (None, 0)]
                if dead:
                    raise RuntimeError(f"worker process {dead[0].name} died "
                                       f"(exit code {dead[0].exitcode})") from None
                continue
            if isinstance(item, Event):
                progress(item)
            elif isinstance(item, logging.LogRecord):
                logging.getLogger(item.name).handle(item)
            elif item[0] == "done":
                results[item[1]] = item[2]
            else:
                _, index, exc, text = item
                if not isinstance(exc, H2SError):
                    exc.__cause__ = _RemoteTraceback(text)
                raise exc
        for proc in procs:
            proc.join()
        ok = True
    finally:
        if not ok:
            for proc in procs:
                if proc.is_alive():
                    proc.terminate()
            for proc in procs:
                if proc.pid is not None:
                    proc.join(timeout=5)
        for q in (tasks, channel):
            q.cancel_join_thread()
            q.close()
    return [results[i] for i in range(len(jobs))]


# ----------------------------------------------------------------------------- build


def build_files(cfg: TutorialConfig | BookConfig, out_dir: Path, *, jobs: int = 1,
                cache: bool = True, progress: Progress | None = None
                ) -> list[tuple[Path, bytes]]:
    """Every output of ``h2s build`` as ``(path, bytes)``, nothing written but plan cache entries.

    Args:
        cfg: a tutorial or book config (:func:`h2s_print.config.load_config`).
        out_dir: the output folder (``-o``).
        jobs: worker processes for a book's tutorials (1: in this process).
        cache: use and fill the plan cache ``out_dir/.h2s-cache``.
        progress: called with an :class:`Event` per stage done.

    Raises:
        H2SError: naming the config file and field.
    """
    from .cache import cache_folder

    progress = progress or _quiet
    out_dir = Path(out_dir)
    cache_dir = cache_folder(out_dir) if cache else None
    if isinstance(cfg, TutorialConfig):
        built = build_tutorial(cfg, out_dir / cfg.name, pdfs=True, cache_dir=cache_dir,
                               progress=progress)
        return list(built.files)

    from .layout import OUTLINE_SEP, lay_out_book
    from .render import pdf_bytes

    folder = out_dir / cfg.name
    jobs_list = [(t, folder / t.name) for t in cfg.tutorials]
    workers = max(1, min(int(jobs), len(jobs_list)))
    if workers == 1:
        builds = [build_tutorial(t, f, pdfs=False, cache_dir=cache_dir, progress=progress)
                  for t, f in jobs_list]
    else:
        builds = _build_parallel(jobs_list, False, cache_dir, workers, progress)
    workbooks = []
    for built in builds:
        result = built.result
        for vp, pages in zip(result.views, built.workbooks):
            label = OUTLINE_SEP.join((result.tutorial.title, vp.name, vp.level))
            workbooks.append((label, pages))
    from . import fonts, templates

    try:
        # the title and contents pages; workbooks keep theirs
        with fonts.using(cfg.font), templates.using(cfg.language):
            pages = lay_out_book(cfg.title, workbooks)
    except H2SError as exc:
        raise in_config(exc, cfg.path, "tutorials") from None
    progress(Event(cfg.name, "book", f"rendering the book PDF ({len(pages)} pages)"))
    data = pdf_bytes(pages)
    progress(Event(cfg.name, "book", f"{len(pages)} pages, {len(workbooks)} workbooks",
                   1, True))
    files = [(folder / f"{cfg.name}.pdf", data)]
    for built in builds:
        files.extend(built.files)
    return files


def _remove_stale_steps(files: Sequence[Path]) -> None:
    """Delete ``step-NN.svg/png`` left in an export folder by an earlier, longer export."""
    by_folder: dict[Path, set[str]] = {}
    for path in files:
        if STEP_FILE_RE.fullmatch(path.name):
            by_folder.setdefault(path.parent, set()).add(path.name)
    for folder, names in by_folder.items():
        for old in folder.iterdir():
            if STEP_FILE_RE.fullmatch(old.name) and old.name not in names:
                try:
                    old.unlink()
                except OSError as exc:
                    log.warning("%s: stale step file not removed: %s", old, exc.strerror or exc)


def build(config_path: Path, out_dir: Path, *, jobs: int = 1, cache: bool = True,
          progress: Progress | None = None) -> list[Path]:
    """``h2s build``: PDFs and plan.json for a tutorial or a book config; returns paths written.

    Checks that ``out_dir`` can be written before any work, computes every output, then writes
    them all (:func:`h2s_print.files.write_many_atomic`).

    Raises:
        H2SError: a user's mistake, naming the file and field; nothing is written then (but
            plan cache entries of tutorials that were solved).
    """
    progress = progress or _quiet
    cfg = load_config(config_path)
    out_dir = Path(out_dir)
    check_writable(out_dir)
    files = build_files(cfg, out_dir, jobs=jobs, cache=cache, progress=progress)
    written = write_many_atomic(files)
    _remove_stale_steps(written)
    progress(Event(cfg.name, "write", f"wrote {len(written)} files under {out_dir}", 1, True))
    return written


def build_study(config_path: Path, out_dir: Path, *, cache: bool = True,
                progress: Progress | None = None) -> tuple[list[Path], str | None]:
    """``h2s study``: a drawing study's packets, answer keys, sheets and study.json
    (:mod:`h2s_print.study`) under ``out_dir/<config name>/``.

    Returns:
        The paths written and the design's balance warning (or ``None``).

    Raises:
        H2SError: a user's mistake, naming the file and field; nothing is written then.
    """
    from .cache import cache_folder
    from .config import load_study
    from .study import make_study, with_study_margins

    progress = progress or _quiet
    cfg, notes = with_study_margins(load_study(config_path))
    for note in notes:
        log.info("%s", note)
    out_dir = Path(out_dir)
    check_writable(out_dir)
    cache_dir = cache_folder(out_dir) if cache else None
    results = [plan_tutorial(o.tutorial, cache_dir=cache_dir, progress=progress)
               for o in cfg.objects]
    progress(Event(cfg.name, "study", f"laying out {len(cfg.participants)} packets"))
    built = make_study(cfg, results, out_dir / cfg.name)
    written = write_many_atomic(list(built.files))
    progress(Event(cfg.name, "write", f"wrote {len(written)} files under {out_dir}", 1, True))
    return written, built.note


def rank_study(folder: Path, judgments: Path | None = None
               ) -> tuple[list[Path], list[str]]:
    """``h2s rank``: pair pages for raters, or (``judgments`` given) the Bradley-Terry fit
    (:mod:`h2s_print.rank`), under ``folder/rank/``.

    Without ``judgments``: ``pairs.pdf`` and ``pairs.csv`` from the drawings ``h2s score``
    registered, and the blank ``judgments.csv`` raters fill in (never over a filled one).  An
    existing ``pairs.csv`` with other pairs (more scans scored since) is an error rather than
    replaced: judgments already collected refer to it.  With ``judgments``: that file checked
    against ``pairs.csv``, then ``strengths.csv``, ``conditions.csv`` and ``<object>.png``.

    Returns:
        The paths written and what was left alone (to say on the terminal).

    Raises:
        H2SError: a user's mistake, naming the file (and line); nothing is written then.
    """
    from . import fonts, templates
    from .studyfile import read_study

    study = read_study(folder)
    font = None if study.font is None else fonts.FontSpec(
        *(Path(f) for f in study.font), name=Path(study.font[0]).name)
    with templates.using(study.language), fonts.using(font):  # the study's own wording
        return _rank_files(study, folder, judgments)


def _rank_files(study, folder: Path, judgments: Path | None) -> tuple[list[Path], list[str]]:
    from . import rank
    from .studyfile import StudyError

    out = Path(folder) / rank.RANK_DIR
    kept: list[str] = []
    if judgments is None:
        scored = rank.read_scored(study)
        pairs = rank.pairs(study, scored, study.seed)
        pairs_path = out / rank.PAIRS_CSV
        if pairs_path.exists() and rank.read_pairs(pairs_path, study) != pairs:
            raise StudyError(f"{pairs_path}: holds other pairs than the scored drawings make now "
                             f"(more scans were scored since); judgments refer to it, so it is "
                             f"not replaced: move the rank folder away to make new pair pages")
        images = rank.read_images(study, scored)
        files = [(out / rank.PAIRS_PDF, rank.pair_pages_pdf(study, pairs, images)),
                 (pairs_path, rank.pairs_csv(pairs).encode("utf-8"))]
        template = out / rank.JUDGMENTS_CSV
        if template.exists():
            kept.append(f"{template} (exists; not replaced)")
        else:
            files.append((template, rank.judgments_template(pairs).encode("utf-8")))
    else:
        pairs = rank.read_pairs(out / rank.PAIRS_CSV, study)
        ranking = rank.fit(rank.read_judgments(judgments, pairs), study)
        files = [(out / rank.STRENGTHS_CSV, rank.strengths_csv(ranking).encode("utf-8")),
                 (out / rank.CONDITIONS_CSV, rank.conditions_csv(ranking).encode("utf-8"))]
        files += [(out / rank.plot_file(obj), rank.plot_png(ranking, obj))
                  for obj in ranking.objects]
    check_writable(out)
    return write_many_atomic(files), kept


def _csv_bytes(header: Sequence[str], rows: Sequence[dict]) -> bytes:
    import csv
    import io

    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=list(header), lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return buf.getvalue().encode("utf-8")


def score_study(scans: Sequence[Path], folder: Path) -> list[Path]:
    """``h2s score``: score scanned sheets of the study in ``folder`` (:mod:`h2s_print.score`).

    Writes under ``folder/scores/``: ``scores.csv`` (one row per drawing and part, ``*`` the
    whole drawing), ``drawings.csv`` and ``drawings/<row>.png`` (each registered drawing,
    255 where a pencil stroke is: what ``h2s rank`` shows raters), and
    ``overlays/<row>-<participant>-<object>.png`` (the registered scan with the model's lines
    in orange, to check by eye).  Scores add up over runs: a drawing scored again replaces
    its earlier rows, others stay.  Two scans of one drawing in one run are an error.

    Raises:
        H2SError: a scan that cannot be scored or a study folder that does not check, naming
            the file (and page); nothing is written then.
    """
    import cv2
    import numpy as np

    from .score import CSV_FIELDS, overlay, score_rows, score_scan
    from .studyfile import (
        DRAWINGS_CSV, DRAWINGS_HEADER, SCORES_DIR, StudyError, csv_rows, read_study, read_text,
    )

    study = read_study(folder)
    out = Path(folder) / SCORES_DIR
    cache: dict = {}
    results = [r for path in scans for r in score_scan(path, study, cache)]
    seen: dict[int, str] = {}
    for r in results:
        if r.drawing.row in seen:
            raise StudyError(f"{r.source}: drawing {r.drawing.row} ({r.drawing.participant}, "
                             f"{r.drawing.object}) was scanned twice: also {seen[r.drawing.row]}")
        seen[r.drawing.row] = r.source

    def earlier(name: str, header: Sequence[str]) -> list[dict[str, str]]:
        """The rows of an earlier run's file (none on the first run)."""
        path = out / name
        return ([cells for _, cells in csv_rows(read_text(path), str(path), header)]
                if path.exists() else [])

    rescored = {(r.drawing.participant, str(r.drawing.order)) for r in results}
    scores: list[dict] = [row for row in earlier("scores.csv", CSV_FIELDS)
                          if (row["participant"], row["order"]) not in rescored]
    drawings: list[dict] = [row for row in earlier(DRAWINGS_CSV, DRAWINGS_HEADER)
                            if int(row["row"]) not in seen]
    files: list[tuple[Path, bytes]] = []
    for r in results:
        d = r.drawing
        ok, png = cv2.imencode(".png", np.where(r.registered_drawing, 255, 0).astype(np.uint8))
        if not ok:  # pragma: no cover - OpenCV always encodes a uint8 image
            raise RuntimeError("PNG encoding failed")
        name = f"drawings/{d.row}.png"
        files.append((out / name, png.tobytes()))
        files.append((out / "overlays" / f"{d.row}-{d.participant}-{d.object}.png",
                      overlay(r.registered, r.key)))
        drawings.append({"row": d.row, "participant": d.participant, "object": d.object,
                         "condition": d.condition, "sheet": d.sheet, "file": name})
        scores += score_rows(r)
    drawings.sort(key=lambda row: int(row["row"]))
    order = {(d.participant, str(d.order)): d.row for d in study.drawings}
    scores.sort(key=lambda row: (order.get((row["participant"], str(row["order"])), -1),
                                 row["part"] != "*"))
    files.append((out / "scores.csv", _csv_bytes(CSV_FIELDS, scores)))
    files.append((out / DRAWINGS_CSV, _csv_bytes(DRAWINGS_HEADER, drawings)))
    check_writable(out)
    return write_many_atomic(files)
