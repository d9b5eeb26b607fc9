"""Robustness of `h2s` for real users (issue 7): every user mistake is one line and exit status 2
with nothing written; Ctrl-C leaves old outputs intact; edge-case models build; `--jobs 2` and
the plan cache give the same bytes; per-step SVG/PNG export (issue 6 item 6)."""

from __future__ import annotations

import io
import json
import re
import shutil
import signal
import subprocess
import sys
import threading
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Callable

import numpy as np
import pytest
import trimesh
import yaml

from h2s_print import cache as plan_cache
from h2s_print.cli import main
from h2s_print.config import load_config

from _meshfiles import box, obj_text
from conftest import REPO
from test_pipeline import files_under, run, tutorial_copy, without_seconds

pypdf = pytest.importorskip("pypdf")

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def one_error_line(err: str) -> str:
    """The single stderr line of a failed run (fails unless there is exactly one)."""
    lines = err.strip("\n").splitlines()
    assert len(lines) == 1, f"expected one line on stderr, got {len(lines)}:\n{err}"
    assert "Traceback" not in err
    return lines[0]


def outputs(out: Path) -> list[str]:
    """Files under ``out`` that are outputs (the plan cache is not one)."""
    return sorted(files_under(out)) if out.is_dir() else []


# ----------------------------------------------------------------------------- user mistakes


def _view(**kw) -> list[dict]:
    return [{"name": "v", **kw}]


def _obj_model(folder: Path, name: str, text: str) -> dict:
    (folder / name).write_text(text)
    return {"path": str(folder / name), "up": "z", "units": "mm"}


def _case_yaml_tag(tmp: Path) -> tuple[list[str], str]:
    marker = tmp / "EXECUTED"
    cfg = tmp / "c.yaml"
    cfg.write_text(f'title: !!python/object/apply:os.system ["touch {marker}"]\n'
                   "model: m.glb\nviews: [{name: v}]\n")
    return [str(cfg)], "h2s: error: c.yaml: line 1: invalid YAML: could not determine a constructor"


def _case_empty_config(tmp: Path):
    (tmp / "c.yaml").write_text("")
    return [str(tmp / "c.yaml")], "h2s: error: c.yaml: empty config"


def _case_missing_config(tmp: Path):
    return [str(tmp / "nope.yaml")], "nope.yaml: file not found"


def _case_empty_model(tmp: Path):
    (tmp / "empty.glb").write_bytes(b"")
    return [str(tutorial_copy(tmp, name="c", model=str(tmp / "empty.glb")))], \
        "h2s: error: c.yaml: model: empty.glb: no triangle mesh with faces in the file"


def _case_garbage_model(tmp: Path):
    (tmp / "junk.glb").write_bytes(np.random.default_rng(7).bytes(3000))
    return [str(tutorial_copy(tmp, name="c", model=str(tmp / "junk.glb")))], \
        "h2s: error: c.yaml: model: junk.glb: cannot read"


def _case_missing_model(tmp: Path):
    return [str(tutorial_copy(tmp, name="c", model=str(tmp / "nope.glb")))], \
        "h2s: error: c.yaml: model.path: "


def _case_nan_model(tmp: Path):
    model = _obj_model(tmp, "nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n")
    return [str(tutorial_copy(tmp, name="c", model=model))], \
        "h2s: error: c.yaml: model: nan.obj: part 'nan' has NaN or infinite coordinates"


def _case_folder_without_meshes(tmp: Path):
    (tmp / "parts").mkdir()
    (tmp / "parts" / "readme.txt").write_text("no meshes here\n")
    return [str(tutorial_copy(tmp, name="c", model=str(tmp / "parts")))], \
        "h2s: error: c.yaml: model: parts: folder holds no mesh files"


def _case_bad_number(tmp: Path):
    return [str(tutorial_copy(tmp, name="c", views=_view(elevation_deg="high")))], \
        "h2s: error: c.yaml: views[0].elevation_deg: expected a number, got 'high'"


def _case_looking_straight_down(tmp: Path):
    return [str(tutorial_copy(tmp, name="c", views=_view(elevation_deg=90,
                                                         perspective="three-point")))], \
        "h2s: error: c.yaml: views[0].elevation_deg: must be <= 89, got 90"


def _case_camera_inside_sphere(tmp: Path):
    return [str(tutorial_copy(tmp, name="c", views=_view(distance=0.5)))], \
        "h2s: error: c.yaml: views[0].distance: must be > 1, got 0.5"


def _case_camera_plane_cuts_model(tmp: Path):
    # 1.05 radii away and 70 degrees up, a level (two-point) camera's image plane cuts the model
    views = [{"name": "ok"}, {"name": "close", "distance": 1.05, "elevation_deg": 70}]
    return [str(tutorial_copy(tmp, name="c", views=views))], \
        "h2s: error: c.yaml: views[1]: "


def _case_unknown_level(tmp: Path):
    return [str(tutorial_copy(tmp, name="c", levels=("novice", "expert")))], \
        "h2s: error: c.yaml: levels[1]: expected one of novice, apprentice, master, basic, " \
        "got 'expert'"


def _case_unknown_paper(tmp: Path):
    return [str(tutorial_copy(tmp, name="c", paper={"size": "A5"}))], \
        "h2s: error: c.yaml: paper.size: expected one of A4, A3, Letter, got 'A5'"


def _case_unknown_key(tmp: Path):
    return [str(tutorial_copy(tmp, name="c", veiws=_view()))], \
        "h2s: error: c.yaml: veiws: unknown key"


def _case_too_many_candidates(tmp: Path):
    return [str(tutorial_copy(tmp, name="c", solver={"max_candidates": 10}))], \
        "h2s: error: c.yaml: solver.max_candidates: candidate generation made more than " \
        "solver.max_candidates = 10 candidates"


def _case_book_missing_tutorial(tmp: Path):
    tutorial_copy(tmp, name="a")
    (tmp / "b.yaml").write_text("tutorials: [a.yaml, missing.yaml]\n")
    return [str(tmp / "b.yaml")], "h2s: error: b.yaml: tutorials[1]: 'missing.yaml': file not found"


def _case_book_names_itself(tmp: Path):
    tutorial_copy(tmp, name="a")
    (tmp / "b.yaml").write_text("tutorials: [a.yaml, b.yaml]\n")
    return [str(tmp / "b.yaml")], \
        "h2s: error: b.yaml: tutorials[1]: 'b.yaml' names this book itself"


def _case_output_is_a_file(tmp: Path):
    (tmp / "out").write_text("precious\n")
    return [str(tutorial_copy(tmp, name="c")), "-o", str(tmp / "out")], \
        "cannot write outputs there: it is a file"


def _case_output_below_a_file(tmp: Path):
    # tests run as root, where chmod does not stop writes: a path below a FILE cannot be made
    (tmp / "out").write_text("precious\n")
    return [str(tutorial_copy(tmp, name="c")), "-o", str(tmp / "out" / "sub")], \
        "cannot write outputs there: it is below the file"


CASES: dict[str, Callable[[Path], tuple[list[str], str]]] = {
    name[len("_case_"):]: fn for name, fn in globals().items() if name.startswith("_case_")}


@pytest.mark.parametrize("case", sorted(CASES))
def test_user_mistake_is_one_line_exit_2_nothing_written(tmp_path, capsys, case):
    argv, expected = CASES[case](tmp_path)
    if "-o" not in argv:
        argv += ["-o", str(tmp_path / "out")]
    before = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    code, out, err = run(capsys, "-q", "build", *argv)
    assert code == 2, err
    line = one_error_line(err)
    assert line.startswith("h2s: error: ") and expected in line, line
    assert out == ""
    assert outputs(tmp_path / "out") == []
    # nothing else changed either (the -o file is intact, no YAML tag ran)
    after = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()
             and ".h2s-cache" not in p.parts}
    assert after == before


def test_error_line_is_the_last_line_without_q(tmp_path, capsys):
    argv, expected = _case_camera_plane_cuts_model(tmp_path)
    code, _, err = run(capsys, "build", *argv, "-o", str(tmp_path / "out"))
    assert code == 2
    lines = err.strip().splitlines()
    assert expected in lines[-1] and "camera plane" in lines[-1]
    assert [ln for ln in lines if ln.startswith("h2s: error")] == [lines[-1]]
    assert "c: plan solved" in err  # progress before the failing view
    assert outputs(tmp_path / "out") == []


@pytest.mark.parametrize("argv, expected", [
    (["build"], "h2s: error: h2s build: the following arguments are required: config"),
    (["build", "x.yaml", "--jobs", "two"], "argument -j/--jobs: expected a whole number"),
    (["frobnicate"], "invalid choice: 'frobnicate'"),
])
def test_bad_command_line_is_one_line_exit_2(capsys, argv, expected):
    code, _, err = run(capsys, *argv)
    assert code == 2
    assert expected in one_error_line(err)


def test_a_bug_exits_1_with_traceback_and_says_so(tmp_path, capsys, monkeypatch):
    def broken(*args, **kwargs):
        raise ZeroDivisionError("simulated bug")

    monkeypatch.setattr("h2s_print.pipeline.build_plan", broken)
    code, _, err = run(capsys, "-q", "build", str(tutorial_copy(tmp_path)), "-o",
                       str(tmp_path / "out"))
    assert code == 1
    assert "Traceback" in err and "ZeroDivisionError: simulated bug" in err
    assert "bug" in err.strip().splitlines()[-1]
    assert outputs(tmp_path / "out") == []


def test_real_process_error_and_success(tmp_path):
    cfg = tutorial_copy(tmp_path, name="c", paper={"size": "A5"})
    cmd = [sys.executable, "-m", "h2s_print.cli", "build", str(cfg), "-o", str(tmp_path / "out")]
    proc = subprocess.run(cmd, capture_output=True, text=True, cwd=REPO)
    assert proc.returncode == 2
    assert proc.stderr == (
        "h2s: error: c.yaml: paper.size: expected one of A4, A3, Letter, got 'A5'\n")
    assert not (tmp_path / "out").exists()
    cfg = tutorial_copy(tmp_path, name="c")
    proc = subprocess.run(cmd, capture_output=True, text=True, cwd=REPO)
    assert proc.returncode == 0, proc.stderr
    assert outputs(tmp_path / "out") == ["c/c-front-left-master.pdf", "c/plan.json"]


# ----------------------------------------------------------------------------- Ctrl-C


@pytest.fixture
def built(tmp_path, capsys):
    """A small tutorial built once: (config, output folder, its files' bytes)."""
    cfg = tutorial_copy(tmp_path, name="c")
    out = tmp_path / "out"
    code, _, err = run(capsys, "-q", "build", str(cfg), "-o", str(out))
    assert code == 0, err
    return cfg, out, files_under(out)


def _retitle(cfg: Path) -> None:
    data = yaml.safe_load(cfg.read_text())
    data["title"] = "A different title"  # so a completed rebuild would change the PDF
    cfg.write_text(yaml.safe_dump(data))


def test_ctrl_c_while_computing_leaves_old_outputs(built, capsys, monkeypatch):
    cfg, out, old = built
    _retitle(cfg)

    def interrupted(pages):
        raise KeyboardInterrupt

    monkeypatch.setattr("h2s_print.render.pdf_bytes", interrupted)
    code, _, err = run(capsys, "-q", "build", str(cfg), "-o", str(out))
    assert code == 130
    assert one_error_line(err).startswith("h2s: interrupted")
    assert files_under(out) == old
    assert not [p for p in out.rglob("*") if p.name.endswith(".part")]


def test_ctrl_c_while_writing_leaves_old_outputs(built, capsys, monkeypatch):
    from h2s_print import files

    cfg, out, old = built
    _retitle(cfg)
    real = files._write_temp
    calls = []

    def interrupted_second(path, data):
        calls.append(path)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return real(path, data)

    monkeypatch.setattr(files, "_write_temp", interrupted_second)
    code, _, err = run(capsys, "-q", "build", str(cfg), "-o", str(out))
    assert code == 130 and len(calls) == 2
    # the first file's complete temporary copy was removed, nothing was renamed
    assert files_under(out) == old
    assert not [p for p in out.rglob("*") if p.name.endswith(".part")]


def test_ctrl_c_during_the_scip_solve_exits_130_and_caches_nothing(tmp_path):
    # SCIP catches SIGINT itself and returns status "userinterrupt"; h2s used to carry on with
    # the all-originals start solution, exit 0 and cache that plan.  The quadratic formulation
    # on a generated 80-box assembly (benchmarks/bench_select.py's model) makes the solve take
    # well over 10 s, so the signal, sent 3 s after the last line before the solve ("N
    # candidates for M parts"), lands inside SCIP.
    sys.path.insert(0, str(REPO / "benchmarks"))
    from bench_select import make_model
    scene = trimesh.Scene()
    for prim in make_model(80, 0):
        lo, hi = np.asarray(prim.box[0]), np.asarray(prim.box[1])
        mesh = trimesh.creation.box(extents=hi - lo)
        mesh.apply_translation((lo + hi) / 2)
        scene.add_geometry(mesh, node_name=prim.part, geom_name=prim.part)
    (tmp_path / "slow.glb").write_bytes(scene.export(file_type="glb"))
    cfg = tutorial_copy(tmp_path, "train.yaml", name="slow",
                        model={"path": str(tmp_path / "slow.glb"), "up": "z", "units": "mm",
                               "parts": {"small": "keep"}},
                        solver={"formulation": "quadratic", "max_change": 0.3})
    out = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-m", "h2s_print.cli", "-v", "build", str(cfg),
                             "-o", str(out)], cwd=REPO, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    seen = []
    try:
        for line in proc.stderr:  # the solve starts right after the candidates are made
            seen.append(line)
            if re.fullmatch(r"\d+ candidates for \d+ parts", line.strip()):
                break
        else:
            pytest.fail("the build ended before the solve:\n" + "".join(seen))
        threading.Timer(3.0, proc.send_signal, (signal.SIGINT,)).start()
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 130, "".join(seen) + err
    assert err.strip().splitlines()[-1] == "h2s: interrupted; nothing was written"
    assert "plan solved" not in err  # the interrupted solve went no further
    assert outputs(out) == []
    assert not list(out.rglob(".h2s-cache/*"))  # and no plan was cached


def test_plan_on_a_book_says_to_use_build(tmp_path, capsys):
    tutorial_copy(tmp_path, name="a")
    (tmp_path / "b.yaml").write_text("tutorials: [a.yaml]\n")
    code, out, err = run(capsys, "plan", str(tmp_path / "b.yaml"), "-o", str(tmp_path / "out"))
    assert code == 2 and out == ""
    assert one_error_line(err) == ("h2s: error: b.yaml: is a book config; `h2s plan` takes one "
                                   "tutorial config (use `h2s build` for books)")
    assert not (tmp_path / "out").exists()


# ----------------------------------------------------------------------------- edge cases


def test_one_part_model_builds(tmp_path, capsys):
    brick = box((0, 0, 0), (40, 30, 20))
    model = _obj_model(tmp_path, "brick.obj", obj_text([("o brick", *brick)]))
    cfg = tmp_path / "brick.yaml"
    cfg.write_text(yaml.safe_dump({"model": model, "views": [{"name": "v"}],
                                   "levels": ["novice"]}))
    code, _, err = run(capsys, "-q", "build", str(cfg), "-o", str(tmp_path / "out"))
    assert code == 0, err
    plan = json.loads((tmp_path / "out" / "brick" / "plan.json").read_text())
    assert [p["name"] for p in plan["parts"]] == ["brick"]
    assert plan["parts"][0]["primitive"]["type"] == "cuboid"
    assert len(plan["views"][0]["steps"]) >= 1


@pytest.mark.parametrize("perspective", ["three-point", "two-point"])
def test_steep_view_works_or_says_why(tmp_path_factory, capsys, perspective):
    folder = tmp_path_factory.mktemp("steep")
    cfg = tutorial_copy(folder, name="steep", views=[{
        "name": "top", "azimuth_deg": 30, "elevation_deg": 85, "perspective": perspective}])
    code, _, err = run(capsys, "-q", "build", str(cfg), "-o", str(folder / "out"))
    if perspective == "three-point":
        assert code == 0, err  # a tilted camera sees the model from (almost) above
        plan = json.loads((folder / "out" / "steep" / "plan.json").read_text())
        assert plan["views"][0]["camera"]["perspective"] == "three-point"
    else:
        # A two-point camera keeps its axis level.  At elevation 85 deg and distance 3 (bounding
        # sphere radii, the default) it stands 3 sin 85 = 2.99 radii above the centre but only
        # 3 cos 85 = 0.26 radii beside it, so its vertical image plane through the eye cuts the
        # model: part of it is behind the camera and cannot be drawn.  A user error, not a bug.
        assert code == 2, err
        line = one_error_line(err)
        assert line.startswith("h2s: error: steep.yaml: views[0]: ") and "camera plane" in line


def test_speck_and_degenerate_parts_next_to_real_parts(tmp_path, capsys):
    speck = box((49.99, 29.99, 80.0), (50.01, 30.01, 80.02))  # 0.035 mm diagonal
    sliver = (np.array([[0.0, 0, 10], [50, 0, 10], [100, 0, 10]]), np.array([[0, 1, 2]]))
    text = obj_text([("o base", *box((0, 0, 0), (100, 60, 10))),
                     ("o post", *box((40, 20, 10), (60, 40, 80))),
                     ("o speck", *speck), ("o sliver", *sliver)])
    cfg = tmp_path / "specks.yaml"
    cfg.write_text(yaml.safe_dump({"model": _obj_model(tmp_path, "specks.obj", text),
                                   "views": [{"name": "v"}], "levels": ["novice"]}))
    code, _, err = run(capsys, "build", str(cfg), "-o", str(tmp_path / "out"))
    assert code == 0, err
    plan = json.loads((tmp_path / "out" / "specks" / "plan.json").read_text())
    # the speck is tiny and the sliver has no area: both merged into a real part
    assert sorted(p["name"] for p in plan["parts"]) == ["base", "post"]
    assert "speck" in err and "sliver" in err  # the loader says what it merged


# ----------------------------------------------------------------------------- jobs and cache


@pytest.fixture(scope="module")
def small_book(tmp_path_factory):
    """Two one-workbook tutorials in a book, built once with --jobs 1 (cold cache)."""
    folder = tmp_path_factory.mktemp("book")
    tutorial_copy(folder, "camera.yaml")
    tutorial_copy(folder, "mixer.yaml")
    book = folder / "duo.yaml"
    book.write_text("title: Two objects\ntutorials: [camera.yaml, mixer.yaml]\n")
    out = folder / "out1"
    stream = io.StringIO()
    old, sys.stderr = sys.stderr, stream
    try:
        code = main(["build", str(book), "-o", str(out), "--jobs", "1"])
    finally:
        sys.stderr = old
    assert code == 0, stream.getvalue()
    return folder, book, out, stream.getvalue()


def test_jobs_2_gives_the_same_bytes_as_jobs_1(small_book):
    folder, book, out1, err1 = small_book
    out2 = folder / "out2"
    proc = subprocess.run([sys.executable, "-m", "h2s_print.cli", "build", str(book), "-o",
                           str(out2), "--jobs", "2"], capture_output=True, text=True, cwd=REPO)
    assert proc.returncode == 0, proc.stderr
    a, b = files_under(out1), files_under(out2)
    assert sorted(a) == sorted(b) == ["duo/camera/plan.json", "duo/duo.pdf", "duo/mixer/plan.json"]
    assert a["duo/duo.pdf"] == b["duo/duo.pdf"]
    for name in ("camera", "mixer"):
        # identical but for selection.seconds, the measured solver time
        assert without_seconds(out1 / "duo" / name / "plan.json") == \
            without_seconds(out2 / "duo" / name / "plan.json")
        assert f"{name}: plan solved" in err1 and f"{name}: plan solved" in proc.stderr


def test_error_in_a_worker_is_one_line_exit_2(tmp_path, capsys):
    tutorial_copy(tmp_path, "mixer.yaml")
    tutorial_copy(tmp_path, name="bad", views=[
        {"name": "close", "distance": 1.05, "elevation_deg": 70}])
    book = tmp_path / "b.yaml"
    book.write_text("tutorials: [mixer.yaml, bad.yaml]\n")
    code, _, err = run(capsys, "-q", "build", str(book), "-o", str(tmp_path / "out"),
                       "--jobs", "2")
    assert code == 2
    assert one_error_line(err).startswith("h2s: error: bad.yaml: views[0]: ")
    assert outputs(tmp_path / "out") == []


def test_cache_reuses_plans_and_resolves_only_the_changed_tutorial(small_book, tmp_path, capsys):
    src, _, out1, _ = small_book
    for name in ("camera.yaml", "mixer.yaml", "duo.yaml"):
        shutil.copy(src / name, tmp_path / name)
    out = tmp_path / "out"
    shutil.copytree(out1, out)
    old = files_under(out)

    code, _, err = run(capsys, "build", str(tmp_path / "duo.yaml"), "-o", str(out))
    assert code == 0, err
    assert "camera: plan from cache" in err and "mixer: plan from cache" in err
    assert files_under(out) == old  # plan.json too: the cached plan keeps its seconds

    data = yaml.safe_load((tmp_path / "mixer.yaml").read_text())
    data["solver"]["max_change"] = 0.12
    (tmp_path / "mixer.yaml").write_text(yaml.safe_dump(data))
    code, _, err = run(capsys, "build", str(tmp_path / "duo.yaml"), "-o", str(out))
    assert code == 0, err
    assert "camera: plan from cache" in err and "mixer: plan solved" in err

    # a corrupt entry is ignored, solved again and rewritten
    camera = load_config(tmp_path / "camera.yaml")
    key = plan_cache.plan_key(camera.model, camera.solver, camera.views)
    entry = plan_cache.entry_path(out / plan_cache.CACHE_DIR, key)
    blob = bytearray(entry.read_bytes())
    blob[len(blob) // 2] ^= 0xFF
    entry.write_bytes(bytes(blob))
    assert plan_cache.load_plan(out / plan_cache.CACHE_DIR, key) is None
    code, _, err = run(capsys, "build", str(tmp_path / "duo.yaml"), "-o", str(out))
    assert code == 0, err
    assert "corrupt cache entry ignored" in err and "camera: plan solved" in err
    assert "mixer: plan from cache" in err
    assert plan_cache.load_plan(out / plan_cache.CACHE_DIR, key) is not None


def test_cache_key_follows_model_bytes_and_settings(tmp_path):
    cfg = load_config(tutorial_copy(tmp_path, name="c"))
    key = plan_cache.plan_key(cfg.model, cfg.solver)
    assert key is not None and len(key) == 64
    assert plan_cache.plan_key(cfg.model, cfg.solver) == key
    from dataclasses import replace

    assert plan_cache.plan_key(cfg.model, replace(cfg.solver, depth=1)) != key
    assert plan_cache.plan_key(replace(cfg.model, units="cm"), cfg.solver) != key
    # the views' eyes break the selection's ties (plan.part_farness); their names do not
    views = tuple(cfg.views)
    with_views = plan_cache.plan_key(cfg.model, cfg.solver, views)
    assert with_views != key
    assert plan_cache.plan_key(cfg.model, cfg.solver,
                               tuple(replace(v, name=v.name + "x") for v in views)) == with_views
    assert plan_cache.plan_key(cfg.model, cfg.solver,
                               (replace(views[0], azimuth_deg=views[0].azimuth_deg + 90),)
                               + views[1:]) != with_views
    copy = tmp_path / "copy.glb"
    copy.write_bytes(cfg.model.path.read_bytes())
    moved = replace(cfg.model, path=copy)
    k1 = plan_cache.plan_key(moved, cfg.solver)
    copy.write_bytes(cfg.model.path.read_bytes() + b"\0")
    assert plan_cache.plan_key(moved, cfg.solver) != k1
    assert plan_cache.plan_key(replace(cfg.model, path=tmp_path / "none.glb"), cfg.solver) is None


# ----------------------------------------------------------------------------- progress


class _Tty(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_progress_plain_lines_quiet_and_bar(built, capsys, monkeypatch):
    cfg, out, _ = built
    code, _, err = run(capsys, "build", str(cfg), "-o", str(out))
    assert code == 0
    assert "c: plan from cache" in err and "c: laid out 1 workbook" in err
    assert "\r" not in err  # not a terminal: plain lines
    code, _, err = run(capsys, "-q", "build", str(cfg), "-o", str(out))
    assert code == 0 and err == ""
    tty = _Tty()
    monkeypatch.setattr(sys, "stderr", tty)
    assert main(["build", str(cfg), "-o", str(out)]) == 0
    text = tty.getvalue()
    assert "\r\x1b[K[" in text and "100%" in text
    assert text.endswith("\n")  # the bar is cleared before the last lines


# ----------------------------------------------------------------------------- SVG / PNG


def test_step_pages_exported_as_svg_and_png(tmp_path, capsys):
    cfg = tutorial_copy(tmp_path, name="c", output={"svg": True, "png": True, "png_dpi": 30})
    out = tmp_path / "out"
    code, _, err = run(capsys, "-q", "build", str(cfg), "-o", str(out))
    assert code == 0, err
    folder = out / "c" / "front-left-master"
    n_pages = len(pypdf.PdfReader(out / "c" / "c-front-left-master.pdf").pages)
    n_step_pages = n_pages - 4  # cover, primer, finished drawing and drawing sheet are not steps
    n = len(json.loads((out / "c" / "plan.json").read_text())["views"][0]["steps"])
    # master puts two steps on a page: pages hold steps 1-2, 3-4, ... and the last one step
    # when n is odd; each file is named by the steps it holds (plan.json's numbers)
    assert n >= 2 and n_step_pages == (n + 1) // 2
    stems = [f"steps-{k:02d}-{k + 1:02d}" if k < n else f"step-{k:02d}" for k in range(1, n + 1, 2)]
    svgs, pngs = sorted(folder.glob("*.svg")), sorted(folder.glob("*.png"))
    assert [p.name for p in svgs] == sorted(f"{stem}.svg" for stem in stems)
    assert [p.name for p in pngs] == sorted(f"{stem}.png" for stem in stems)
    for p in svgs:
        assert ET.parse(p).getroot().tag == "{http://www.w3.org/2000/svg}svg"
    for p in pngs:
        head = p.read_bytes()[:24]
        assert head[:8] == PNG_MAGIC
        width = int.from_bytes(head[16:20], "big")
        # A4 landscape 297 mm at 30 dpi: 297 / 25.4 * 30 = 350.8 px
        assert abs(width - 297 / 25.4 * 30) <= 1
    # a rebuild removes step files that no longer exist (either name form), and only those
    for stale in ("step-99.png", "steps-97-98.svg"):
        (folder / stale).write_bytes(b"stale")
    (folder / "notes.txt").write_text("mine")
    assert main(["-q", "build", str(cfg), "-o", str(out)]) == 0
    assert not (folder / "step-99.png").exists() and not (folder / "steps-97-98.svg").exists()
    assert (folder / "notes.txt").exists()
    assert len(list(folder.glob("step*"))) == 2 * n_step_pages
