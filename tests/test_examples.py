"""The example models (h2s_print/examples.py) and their configs in configs/."""

from __future__ import annotations

import json
import struct

import numpy as np
import pytest
import trimesh

from h2s_print.config import BookConfig, TutorialConfig, load_config
from h2s_print.examples import EXAMPLES, build_example, example_glb, main, write_examples

from conftest import CONFIGS

MODELS = CONFIGS / "models"
#: glTF Y-up file frame -> internal Z-up frame, the loader's default: (x, y, z) -> (x, -z, y).
GLTF_TO_Z_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])


def _parts(scene: trimesh.Scene) -> dict[str, tuple[str, np.ndarray, np.ndarray]]:
    """node name -> (mesh name, world vertices in the internal Z-up frame, faces)."""
    out = {}
    for node in scene.graph.nodes_geometry:
        transform, geometry = scene.graph[node]
        mesh = scene.geometry[geometry]
        world = trimesh.transform_points(mesh.vertices, transform)
        out[node] = (geometry, world @ GLTF_TO_Z_UP.T, np.asarray(mesh.faces))
    return out


def _box(vertices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return vertices.min(axis=0), vertices.max(axis=0)


@pytest.fixture(scope="module")
def built() -> dict[str, dict[str, tuple[str, np.ndarray, np.ndarray]]]:
    return {name: _parts(build_example(name)) for name in EXAMPLES}


@pytest.fixture(scope="module")
def committed() -> dict[str, dict[str, tuple[str, np.ndarray, np.ndarray]]]:
    return {name: _parts(trimesh.load(MODELS / f"{name}.glb", force="scene"))
            for name in EXAMPLES}


# --------------------------------------------------------------------------- files


@pytest.mark.parametrize("name", EXAMPLES)
def test_committed_glb_equals_a_fresh_build(name, built, committed):
    fresh, stored = built[name], committed[name]
    assert sorted(fresh) == sorted(stored)
    for node in fresh:
        _, v_fresh, f_fresh = fresh[node]
        _, v_stored, f_stored = stored[node]
        assert v_fresh.shape == v_stored.shape, node
        np.testing.assert_allclose(v_stored, v_fresh, rtol=0, atol=1e-9, err_msg=node)
        np.testing.assert_array_equal(f_stored, f_fresh, err_msg=node)


@pytest.mark.parametrize("name", EXAMPLES)
def test_glb_bytes_are_deterministic_and_small(name):
    first, second = example_glb(name), example_glb(name)
    assert first == second
    assert len(first) < 300_000


def test_glb_declares_millimetres_in_extras():
    data = (MODELS / "camera.glb").read_bytes()
    length = struct.unpack("<I", data[12:16])[0]  # JSON chunk length after the 12-byte header
    tree = json.loads(data[20:20 + length])
    assert tree["scenes"][0]["extras"]["units"] == "mm"
    assert {node["name"] for node in tree["nodes"]} >= {"body", "grip", "lens", "prism"}


def test_write_examples_and_main_write_the_same_bytes(tmp_path):
    paths = write_examples(tmp_path / "a")
    assert [p.name for p in paths] == [f"{n}.glb" for n in EXAMPLES]
    assert main([str(tmp_path / "b")]) == 0
    for path in paths:
        assert path.read_bytes() == (tmp_path / "b" / path.name).read_bytes()


def test_unknown_example_is_refused():
    with pytest.raises(ValueError, match="unknown example 'chair'"):
        build_example("chair")


# --------------------------------------------------------------------------- configs


@pytest.mark.parametrize("name", EXAMPLES)
def test_config_loads_and_points_at_its_model(name):
    cfg = load_config(CONFIGS / f"{name}.yaml")
    assert isinstance(cfg, TutorialConfig)
    assert cfg.model.path == (MODELS / f"{name}.glb").resolve()
    assert cfg.model.path.is_file()
    assert cfg.model.units == "mm" and cfg.model.up is None  # GLB default: Y-up
    assert cfg.levels == ("novice", "apprentice", "master")
    assert len(cfg.views) == 2
    for view in cfg.views:
        assert 20 <= abs(view.azimuth_deg) <= 60
        assert 15 <= view.elevation_deg <= 35
    assert {v.perspective for v in cfg.views} == {"two-point", "three-point"}
    assert (cfg.paper.size, cfg.paper.orientation, cfg.paper.margin_mm) == ("A4", "landscape", 12)
    assert (cfg.solver.formulation, cfg.solver.time_limit_s, cfg.solver.max_change) == (
        "linear", 60, 0.10)  # linear is the default formulation


def test_book_lists_the_four_tutorials():
    book = load_config(CONFIGS / "book.yaml")
    assert isinstance(book, BookConfig)
    assert book.title == "Sketching everyday objects"
    assert [t.name for t in book.tutorials] == list(EXAMPLES)


def test_config_regrouping_names_existing_nodes(built):
    mixer = load_config(CONFIGS / "mixer.yaml")
    nodes = set(built["mixer"])
    for _, patterns in mixer.model.parts.merge:
        assert set(patterns) <= nodes
    assert set(mixer.model.parts.drop) <= nodes


# --------------------------------------------------------------------------- geometry


@pytest.mark.parametrize("name", EXAMPLES)
def test_objects_rest_on_the_ground_roughly_centred(name, built):
    vertices = np.vstack([v for _, v, _ in built[name].values()])
    lo, hi = _box(vertices)
    assert lo[2] == 0.0  # float32-rounded parts still touch z = 0 exactly
    centre = (lo + hi) / 2
    size = hi - lo
    # "roughly centred": the box centre within a quarter of the size from x = y = 0
    assert abs(centre[0]) < size[0] / 4 and abs(centre[1]) < size[1] / 4


@pytest.mark.parametrize("name,tiny", [("camera", {"screw"}), ("mixer", {"badge"}),
                                       ("train", set()), ("roller", {"rivet"})])
def test_only_the_intended_details_are_below_the_small_part_threshold(name, tiny, built):
    # The loader's default: a part is tiny when its box diagonal < 0.01 of the model's.
    parts = built[name]
    model_lo, model_hi = _box(np.vstack([v for _, v, _ in parts.values()]))
    threshold = 0.01 * np.linalg.norm(model_hi - model_lo)
    small = {n for n, (_, v, _) in parts.items()
             if np.linalg.norm(np.ptp(v, axis=0)) < threshold}
    assert small == tiny


def test_camera_lens_is_a_cylinder_along_y_on_the_body_front(built):
    parts = built["camera"]
    body_lo, body_hi = _box(parts["body"][1])
    lens_lo, lens_hi = _box(parts["lens"][1])
    size = lens_hi - lens_lo
    assert size[0] == pytest.approx(size[2], abs=1e-4)  # diameter across x equals across z
    assert size[0] == pytest.approx(64.9, abs=1e-4)     # 2 x 32.45 mm
    assert size[1] == pytest.approx(61.3, abs=1e-4)     # length along the viewing axis
    assert lens_hi[1] == body_lo[1]                      # its back sits on the front face
    assert (lens_lo[0] + lens_hi[0]) / 2 == pytest.approx((body_lo[0] + body_hi[0]) / 2, abs=1e-5)


def test_camera_prism_and_flash_share_the_body_bisector(built):
    parts = built["camera"]
    body_lo, body_hi = _box(parts["body"][1])
    body_mid = (body_lo[0] + body_hi[0]) / 2
    for name in ("prism", "flash"):
        lo, hi = _box(parts[name][1])
        assert (lo[0] + hi[0]) / 2 == pytest.approx(body_mid, abs=1e-5), name
    prism_lo, _ = _box(parts["prism"][1])
    assert prism_lo[2] == body_hi[2]  # on top of the body


def test_camera_grip_is_flush_with_body_front_side_and_bottom(built):
    parts = built["camera"]
    body_lo, _ = _box(parts["body"][1])
    grip_lo, grip_hi = _box(parts["grip"][1])
    assert grip_hi[1] == body_lo[1]  # back face on the body's front face (y = 4.7)
    assert grip_lo[2] == body_lo[2] == 0.0
    assert grip_lo[0] == body_lo[0]
    button_lo, button_hi = _box(parts["shutter_button"][1])
    assert button_lo[2] == grip_hi[2]  # the button sits on the grip
    assert np.ptp(parts["shutter_button"][1], axis=0)[0] < 0.1 * np.ptp(parts["body"][1], axis=0)[0]


def test_train_wheels_are_instances_of_one_mesh(built, committed):
    for scene in (built["train"], committed["train"]):
        wheels = {n: g for n, (g, _, _) in scene.items() if n.startswith("wheel_")}
        assert sorted(wheels) == [f"wheel_{i}" for i in range(1, 9)]
        assert len(set(wheels.values())) == 1  # one mesh, eight nodes
    data = (MODELS / "train.glb").read_bytes()
    tree = json.loads(data[20:20 + struct.unpack("<I", data[12:16])[0]])
    meshes = {node["mesh"] for node in tree["nodes"] if node["name"].startswith("wheel_")}
    assert len(meshes) == 1


def test_train_wheels_pair_on_axles_and_carriages_share_the_ground(built):
    parts = built["train"]
    for left, right in ((1, 2), (3, 4), (5, 6), (7, 8)):
        a_lo, a_hi = _box(parts[f"wheel_{left}"][1])
        b_lo, b_hi = _box(parts[f"wheel_{right}"][1])
        # coaxial: same axle line (x, z centre), on opposite sides (y)
        np.testing.assert_allclose((a_lo + a_hi)[[0, 2]], (b_lo + b_hi)[[0, 2]], atol=1e-9)
        assert a_hi[1] < 0 < b_lo[1]
        assert a_lo[2] == 0.0
    engine_lo, engine_hi = _box(parts["engine"][1])
    wagon_lo, wagon_hi = _box(parts["wagon"][1])
    assert engine_lo[2] == wagon_lo[2] and engine_hi[2] == wagon_hi[2]


def test_mixer_bowl_is_coaxial_with_the_beater_under_the_head(built):
    parts = built["mixer"]
    bowl_lo, bowl_hi = _box(parts["bowl"][1])
    head_lo, _ = _box(parts["head"][1])
    for name in ("beater_shaft", "beater_paddle"):
        lo, hi = _box(parts[name][1])
        np.testing.assert_allclose(((lo + hi) / 2)[:2], ((bowl_lo + bowl_hi) / 2)[:2], atol=1e-4)
    assert bowl_hi[2] < head_lo[2]
    base_hi = _box(parts["base"][1])[1]
    assert bowl_lo[2] == base_hi[2]  # the bowl stands on the base
    size = bowl_hi - bowl_lo
    assert size[0] == pytest.approx(size[1], abs=1e-4)  # round in plan


def test_roller_is_coaxial_with_the_frame_axle(built):
    parts = built["roller"]
    roller_lo, roller_hi = _box(parts["roller"][1])
    axle_lo, axle_hi = _box(parts["frame_axle"][1])
    np.testing.assert_allclose(((roller_lo + roller_hi) / 2)[1:], ((axle_lo + axle_hi) / 2)[1:],
                               atol=1e-5)
    handle_lo, handle_hi = _box(parts["handle"][1])
    assert handle_lo[2] == 0.0 and roller_lo[2] > handle_hi[2]
