"""`h2s build` end to end: output files, determinism, book bookmarks (pipeline.py)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest
import yaml
from conftest import CONFIGS, REPO

from h2s_print.cli import main

pypdf = pytest.importorskip("pypdf")


def run(capsys, *argv: str) -> tuple[int, str, str]:
    """``main(argv)`` and its captured (status, stdout, stderr)."""
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def tutorial_copy(folder: Path, source: str = "camera.yaml", *, name: str | None = None,
                  n_views: int | None = 1, levels: tuple[str, ...] | None = ("master",),
                  **changes: Any) -> Path:
    """A copy of ``configs/<source>`` in ``folder`` with its model path made absolute, only its
    first ``n_views`` views and the given ``levels`` (None: keep all), and top-level keys
    replaced by ``changes`` (a key ``solver`` merges into the existing mapping)."""
    data = yaml.safe_load((CONFIGS / source).read_text())
    model = data["model"]
    if isinstance(model, str):
        model = {"path": model}
    model["path"] = str((CONFIGS / model["path"]).resolve())
    data["model"] = model
    if n_views is not None:
        data["views"] = data["views"][:n_views]
    if levels is not None:
        data["levels"] = list(levels)
    for key, value in changes.items():
        if key == "solver":
            data["solver"] = {**data.get("solver", {}), **value}
        else:
            data[key] = value
    path = folder / f"{name or Path(source).stem}.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def without_seconds(path: Path) -> dict:
    """plan.json without ``selection.seconds`` (measured wall time, the one varying field)."""
    doc = json.loads(path.read_text())
    del doc["selection"]["seconds"]
    return doc


def files_under(folder: Path) -> dict[str, bytes]:
    """Relative path -> bytes of every output file (the plan cache excluded)."""
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file() and ".h2s-cache" not in p.relative_to(folder).parts}


@pytest.fixture(scope="module")
def camera_builds(tmp_path_factory):
    """configs/camera.yaml built twice without the cache, into two folders."""
    outs = []
    for k in range(2):
        out = tmp_path_factory.mktemp(f"camera{k}")
        assert main(["-q", "build", str(CONFIGS / "camera.yaml"), "-o", str(out),
                     "--no-cache"]) == 0
        outs.append(out)
    return outs


def test_camera_build_writes_one_pdf_per_view_and_level_and_plan_json(camera_builds):
    out = camera_builds[0]
    cfg = yaml.safe_load((CONFIGS / "camera.yaml").read_text())
    expected = {f"camera/camera-{v['name']}-{lv}.pdf" for v in cfg["views"] for lv in cfg["levels"]}
    expected.add("camera/plan.json")
    # 2 views x 3 levels = 6 PDFs, plus plan.json
    assert set(files_under(out)) == expected and len(expected) == 2 * 3 + 1
    plan = json.loads((out / "camera" / "plan.json").read_text())
    assert [(v["name"], v["level"]) for v in plan["views"]] == [
        (v["name"], lv) for v in cfg["views"] for lv in cfg["levels"]]
    for name in expected - {"camera/plan.json"}:
        assert (out / name).read_bytes().startswith(b"%PDF-")
    assert not list(out.rglob("*.part")), "no temporary files left behind"


def test_same_config_built_twice_gives_identical_files(camera_builds):
    a, b = (files_under(out) for out in camera_builds)
    assert a.keys() == b.keys()
    for name in a:
        if name.endswith(".pdf"):
            assert a[name] == b[name], f"{name} differs between two builds"
    pa, pb = (without_seconds(out / "camera" / "plan.json") for out in camera_builds)
    assert pa == pb


def test_book_has_bookmarks_for_every_tutorial_view_and_level(tmp_path, capsys):
    cam = tutorial_copy(tmp_path, "camera.yaml", n_views=2, levels=("novice", "master"))
    mix = tutorial_copy(tmp_path, "mixer.yaml", n_views=1, levels=("apprentice",))
    book = tmp_path / "small.yaml"
    book.write_text(yaml.safe_dump({"title": "Two objects", "tutorials": [cam.name, mix.name]}))
    code, _, err = run(capsys, "build", str(book), "-o", str(tmp_path / "out"))
    assert code == 0, err
    reader = pypdf.PdfReader(tmp_path / "out" / "small" / "small.pdf")

    def tree(items, depth=0, out=None):
        out = [] if out is None else out
        for item in items:
            if isinstance(item, list):
                tree(item, depth + 1, out)
            else:
                out.append((depth, item.title))
        return out

    marks = tree(reader.outline)
    cam_cfg, mix_cfg = (yaml.safe_load(p.read_text()) for p in (cam, mix))
    top = [t for d, t in marks if d == 0]
    assert cam_cfg["title"] in top and mix_cfg["title"] in top
    # every (tutorial, view, level) appears as a nested path tutorial > view > level
    for cfg in (cam_cfg, mix_cfg):
        start = next(i for i, (d, t) in enumerate(marks) if d == 0 and t == cfg["title"])
        end = next((i for i in range(start + 1, len(marks)) if marks[i][0] == 0), len(marks))
        inside = marks[start:end]
        for view in cfg["views"]:
            vi = next(i for i, (d, t) in enumerate(inside) if d == 1 and t == view["name"])
            vend = next((i for i in range(vi + 1, len(inside)) if inside[i][0] <= 1),
                        len(inside))
            levels = {t.lower() for d, t in inside[vi:vend] if d == 2}
            for level in cfg["levels"]:
                assert level in levels, (cfg["title"], view["name"], level)
    # 2 views x 2 levels + 1 x 1 = 5 workbooks, each with its plan.json folder
    assert {p.name for p in (tmp_path / "out" / "small").iterdir()} == {
        "small.pdf", "camera", "mixer"}
    assert "book: " in err and "pages, 5 workbooks" in err


# ----------------------------------------------------------------------------- step files


def test_step_ranges_and_file_names():
    from h2s_print.pipeline import step_file_name, step_ranges

    # novice: one step a page; apprentice/master: two, the last page one when odd
    assert step_ranges(3, 3) == [(1, 1), (2, 2), (3, 3)]
    assert step_ranges(5, 3) == [(1, 2), (3, 4), (5, 5)]  # ceil(5 / 3) = 2 a page
    assert step_ranges(4, 2) == [(1, 2), (3, 4)]
    assert step_ranges(0, 0) == []
    for n_steps, n_pages in ((1, 2), (4, 3), (2, 0)):  # no even split: a layout bug
        with pytest.raises(RuntimeError):
            step_ranges(n_steps, n_pages)
    assert step_file_name(3, 3, "svg") == "step-03.svg"
    assert step_file_name(3, 4, "png") == "steps-03-04.png"
    assert step_file_name(9, 10, "svg") == "steps-09-10.svg"


# ----------------------------------------------------------------------------- plan cache


def _fake_plan(status: str, gap: float = 0.0) -> Any:
    """A one-cube plan whose selection ended with ``status`` (no solve)."""
    import numpy as np
    from _meshfiles import CUBE_F, CUBE_V

    from h2s_print.candidates import Candidate
    from h2s_print.config import SolverSettings
    from h2s_print.plan import Plan
    from h2s_print.select import Selection
    from h2s_print.types import Model, Part, Primitive, readonly

    box = ((0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
    part = Part("cube", readonly(CUBE_V, np.float64), readonly(CUBE_F, np.int64))
    cand = Candidate("cube", "cube", box, True, (), 0, (), (0, 1, 2), 6.0, 0.0)
    sel = Selection(("cube",), 6.0, status, gap, 0.1, "linear", status == "optimal", 1, 0)
    return Plan(Model("cube.glb", "mm", (part,)), (Primitive("cube", "cuboid", None, box, 0.0),),
                (), (cand,), sel, SolverSettings())


@pytest.mark.parametrize("status, kept", [("optimal", True), ("time_limit", True),
                                          ("interrupted", False), ("memory_limit", False),
                                          ("gap_limit", False)])
def test_only_optimal_or_time_limited_plans_are_cached(tmp_path, status, kept):
    from h2s_print import cache

    written = cache.store_plan(tmp_path, "k" * 64, _fake_plan(status))
    assert (written is not None) == kept
    assert cache.entry_path(tmp_path, "k" * 64).exists() == kept


@pytest.mark.parametrize("status", ["time_limit", "memory_limit"])
def test_not_optimal_plan_names_its_real_status(tmp_path, monkeypatch, status):
    from h2s_print import cache
    from h2s_print.config import load_tutorial
    from h2s_print.pipeline import get_plan

    tutorial = load_tutorial(tutorial_copy(tmp_path, name="c", solver={"time_limit_s": 7}))
    monkeypatch.setattr("h2s_print.pipeline.build_plan",
                        lambda model, solver, views: _fake_plan(status, gap=0.25))
    events = []
    plan, cached = get_plan(tutorial, cache_dir=tmp_path / "cache", progress=events.append)
    assert not cached and plan.selection.status == status
    text = events[-1].text
    assert f"SCIP {status} - NOT proven optimal (gap 0.25" in text
    # only the time limit is blamed on solver.time_limit_s (7 s here)
    assert ("solver.time_limit_s 7" in text) == (status == "time_limit")
    key = cache.plan_key(tutorial.model, tutorial.solver, tutorial.views)
    assert cache.entry_path(tmp_path / "cache", key).exists() == (status == "time_limit")


def test_the_main_job_needs_no_optional_package(tmp_path):
    """The README installs only the core dependencies: nothing on the default path may need
    rtree or embreex (trimesh's ray interface does).  Block both and plan a tutorial."""
    code = ("import sys; sys.modules['rtree'] = None; sys.modules['embreex'] = None\n"
            "from h2s_print.cli import main\n"
            f"sys.exit(main(['-q', 'plan', {str(REPO / 'configs' / 'camera.yaml')!r}, "
            f"'-o', {str(tmp_path)!r}, '--no-cache']))")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert (tmp_path / "camera" / "plan.json").is_file()


def test_plan_json_text_reads_back_equal_with_points_on_one_line():
    """plan.json is written by files.dumps_json: it reads back to the same document (keys in
    the contract's order, not sorted), a list of numbers (a point, a box, a polyline) sits on
    one line, everything else one item a line, and the text is the same every time."""
    import json

    from h2s_print.files import dumps_json

    doc = {"schema": "s", "b": 1, "a": [[0.1, 2, -3e-07], [1e300, 0, 5]], "empty": [],
           "steps": [{"text": "Draw — “AC”", "guides": [], "ok": True, "none": None}],
           "polyline": [[[0.5, 1.5], [2.5, 3.5]]], "n": 0.30000000000000004}
    text = dumps_json(doc)
    assert json.loads(text) == doc and list(json.loads(text)) == list(doc)
    assert ' "a": [[0.1, 2, -3e-07], [1e+300, 0, 5]],\n' in text
    assert ' "polyline": [[[0.5, 1.5], [2.5, 3.5]]],\n' in text
    assert '"text": "Draw — “AC”"' in text and text.endswith("}\n")
    assert dumps_json(doc) == text
    assert text.count("\n") == 16


def _reference_dumps_json(data) -> str:
    """dumps_json's definition, written plainly: every scalar and one-line list through the
    C encoder, flatness checked element by element."""
    from h2s_print.files import _FLAT

    def flat(value) -> bool:
        return isinstance(value, list) and all(
            (isinstance(x, (int, float)) and not isinstance(x, bool)) or flat(x) for x in value)

    def write(value, depth: int, out: list[str]) -> None:
        pad = "\n" + " " * (depth + 1)
        if isinstance(value, dict) and value:
            out.append("{")
            for i, (k, v) in enumerate(value.items()):
                out.append(("," if i else "") + pad + _FLAT.encode(str(k)) + ": ")
                write(v, depth + 1, out)
            out.append("\n" + " " * depth + "}")
        elif isinstance(value, list) and value and not flat(value):
            out.append("[")
            for i, v in enumerate(value):
                out.append(("," if i else "") + pad)
                write(v, depth + 1, out)
            out.append("\n" + " " * depth + "]")
        else:
            out.append(_FLAT.encode(value))

    out: list[str] = []
    write(data, 0, out)
    return "".join(out) + "\n"


def test_plan_json_text_is_its_plain_definition():
    """The shortcuts (exact types written directly, flatness by the set of element types)
    write what the plain definition writes, odd values included."""
    import enum

    import numpy as np

    from h2s_print.files import dumps_json

    class Axis(enum.IntEnum):
        Z = 2

    class Name(str):
        pass

    doc = {"f": -0.0, "big": 1e16, "tiny": 5e-324, "i": -7, "enum": Axis.Z, "np": np.float64(0.1),
           "bools": [True, False], "mixed": [1, 2.5, True], "np_list": [np.float64(1.5), 2.0],
           "enum_list": [Axis.Z, 1], "nested": [[], [[]], [[1.0, 2], []]], "empty": {},
           "tuple": (1, 2.0), "tuples": [(1, 2), (3, 4)], 3: "int key", None: [None],
           "name": Name("q\"uote\n"), Name("key"): "ü ✓ \u2028", "deep": [{"a": [[0.5]]}],
           "list_of_dicts": [{}, {"x": []}], "strs": ["a", 1.0], "top": [1.0, [2.0, "x"]],
           "zeros": [0.0, -0.0, [-0.0, 0.0], 0.0], "again": [[0.1, 1.0], [1, 0.1]],
           "ints_floats": [1, 1.0, [1.0, 1]], "deep_mixed": [[[0.5, 0.25]], [[0.5], {"k": 0.5}]]}
    assert dumps_json(doc) == _reference_dumps_json(doc)
    for bad in (float("nan"), [1.0, float("inf")], {"a": [[-float("inf")]]}):
        with pytest.raises(ValueError):
            _reference_dumps_json(bad)
        with pytest.raises(ValueError):
            dumps_json(bad)
