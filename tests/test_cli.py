"""The command line: `h2s inspect` on every example and public model, and its error contract."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from h2s_print.cli import main

from conftest import CONFIGS, REPO

EXAMPLE_CONFIGS = sorted(p for p in CONFIGS.glob("*.yaml") if p.name not in ("book.yaml", "study.yaml"))

#: (path inside ../shared/models, up axis, expected part count) from its README table.
SHARED = [
    ("ikea_chair_ingolf/chair_ingolf_0650.glb", "z", 5),
    ("ikea_table_lack/table_lack_0825.glb", "z", 5),
    ("ikea_desk_fredrik/desk_fredrik_0430.glb", "z", 7),  # part4: two like pieces, split
    ("ikea_box_ivar/box_ivar_0666.glb", "z", 5),
    ("partnet_mobility_oven_101773", None, 10),
    ("partnet_mobility_oven_101773/parts_leaf.glb", None, 10),
    ("partnet_mobility_bottle_3763", None, 3),
    ("trimesh_pins_plate/pins.glb", "z", 7),
]


def run(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def contract_fields(doc: dict) -> None:
    """Check inspect --json against plan.json's `parts` and `relations` fields (DESIGN.md §3)."""
    assert set(doc) == {"parts", "relations"}
    for part in doc["parts"]:
        assert set(part) == {"name", "primitive", "residual"}
        prim = part["primitive"]
        assert set(prim) == {"type", "axis", "box"}
        assert prim["type"] in ("plane", "cuboid", "cylinder", "frustum", "custom")
        assert prim["axis"] in (0, 1, 2, None)
        lo, hi = prim["box"]
        assert len(lo) == len(hi) == 3 and all(a <= b for a, b in zip(lo, hi))
        assert part["residual"] >= 0
    names = {p["name"] for p in doc["parts"]}
    for rel in doc["relations"]:
        assert set(rel) == {"a", "b", "type", "axis", "tolerance", "detail"}
        assert rel["a"] in names and rel["b"] in names and rel["a"] < rel["b"]
        assert rel["type"] in ("coplanar", "coaxial", "bisector")
        assert rel["axis"] in (0, 1, 2) and rel["tolerance"] > 0


@pytest.mark.parametrize("config", EXAMPLE_CONFIGS, ids=lambda p: p.stem)
def test_inspect_example_configs(capsys, config):
    code, out, _ = run(capsys, "inspect", str(config), "--json")
    assert code == 0
    doc = json.loads(out)
    contract_fields(doc)
    assert all(p["primitive"]["type"] != "custom" for p in doc["parts"])


def test_camera_lens_is_a_cylinder_along_the_viewing_axis(capsys):
    code, out, _ = run(capsys, "inspect", str(CONFIGS / "camera.yaml"), "--json")
    parts = {p["name"]: p for p in json.loads(out)["parts"]}
    # the camera looks along the model's Y axis (front is -Y)
    assert parts["lens"]["primitive"]["type"] == "cylinder"
    assert parts["lens"]["primitive"]["axis"] == 1
    assert parts["body"]["primitive"]["type"] == "cuboid"


def test_inspect_table_lists_parts_and_relations(capsys):
    code, out, _ = run(capsys, "inspect", str(CONFIGS / "mixer.yaml"))
    assert code == 0
    assert "part" in out and "primitive" in out and "residual" in out
    assert "bowl" in out and "beater" in out
    # the bowl and beater share their vertical axis, and that relation is kept
    line = next(ln for ln in out.splitlines() if ln.split()[:3] == ["beater", "bowl", "coaxial"])
    assert line.split()[3] == "z" and line.rstrip().endswith("yes")


@pytest.mark.parametrize("rel, up, count", SHARED, ids=[s[0].split("/")[0] for s in SHARED])
def test_inspect_every_shared_model(capsys, shared_models, rel, up, count):
    argv = ["inspect", str(shared_models / rel), "--json"] + (["--up", up] if up else [])
    code, out, _ = run(capsys, *argv)
    assert code == 0
    doc = json.loads(out)
    contract_fields(doc)
    assert len(doc["parts"]) == count


@pytest.mark.parametrize(
    "argv, message",
    [
        (["inspect", "no/such/model.glb"], "model.glb"),
        (["inspect", "no/such/config.yaml"], "config.yaml: file not found"),
    ],
)
def test_user_errors_are_one_line_exit_2(capsys, argv, message):
    code, out, err = run(capsys, *argv)
    assert code == 2
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and message in lines[0]
    assert "Traceback" not in err


def test_a_key_given_twice_through_a_real_process(tmp_path):
    bad = tmp_path / "camera.yaml"
    bad.write_text((CONFIGS / "camera.yaml").read_text() + "title: Another title\n")
    proc = subprocess.run([sys.executable, "-m", "h2s_print.cli", "plan", str(bad), "-o",
                           str(tmp_path / "out")], capture_output=True, text=True, cwd=REPO)
    assert proc.returncode == 2
    assert proc.stderr.startswith("h2s: error: camera.yaml: title: key given twice (lines ")
    assert len(proc.stderr.strip().splitlines()) == 1 and "Traceback" not in proc.stderr
    assert not (tmp_path / "out").exists()


def test_bad_config_through_a_real_process(tmp_path):
    bad = tmp_path / "camera.yaml"
    bad.write_text((CONFIGS / "camera.yaml").read_text().replace("elevation_deg: 18",
                                                                  "elevation_deg: high"))
    proc = subprocess.run([sys.executable, "-m", "h2s_print.cli", "inspect", str(bad)],
                          capture_output=True, text=True, cwd=REPO)
    assert proc.returncode == 2
    assert proc.stderr.strip() == (
        "h2s: error: camera.yaml: views[0].elevation_deg: expected a number, got 'high'")
    assert "Traceback" not in proc.stderr
