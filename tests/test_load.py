"""Stage 1, load: every format from files written here, frames, units, regrouping, errors."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from _meshfiles import CUBE_F, CUBE_V, box, obj_text, write_glb, write_ply, write_stl
from h2s_print.config import ModelSpec, PartsSpec
from h2s_print.errors import ConfigError, ModelError
from h2s_print.load import load_model, read_path, safe_name


def _load(path: Path, **parts) -> object:
    up = parts.pop("up", None)
    units = parts.pop("units", None)
    return load_model(ModelSpec(path=path, up=up, units=units, parts=PartsSpec(**parts)))


def _box(part) -> list[list[float]]:
    return [list(part.box[0]), list(part.box[1])]


def _signed_volume(part) -> float:
    """Volume enclosed by a closed mesh; positive when its faces wind outward."""
    v = part.vertices[part.faces]
    return float(np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])).sum() / 6)


# ----------------------------------------------------------------------------- glTF / GLB


def _rot_z90() -> list[float]:
    # column-major 4x4 (glTF "matrix"): rotation +90 deg about Z, then translate (0, 5, 0)
    m = np.array([[0, -1, 0, 0], [1, 0, 0, 5], [0, 0, 1, 0], [0, 0, 0, 1]], float)
    return m.T.reshape(-1).tolist()


@pytest.fixture
def instanced_glb(tmp_path) -> Path:
    """A body, a cube mesh used by five nodes (three named 'wheel'), one nested, one mirrored."""
    body = box((0, 0, 0), (4, 1, 2))
    return write_glb(
        tmp_path / "cart.glb",
        meshes=[("cube", CUBE_V, CUBE_F), ("body_mesh", *body)],
        nodes=[
            {"name": "body", "mesh": 1},                                  # 0
            {"name": "wheel", "mesh": 0, "translation": [10, 0, 0]},      # 1
            {"name": "wheel", "mesh": 0, "matrix": _rot_z90()},           # 2
            {"name": "arm", "translation": [0, 0, 7], "children": [4]},   # 3
            {"name": "wheel", "mesh": 0, "scale": [2, 2, 2]},             # 4 (under arm)
            {"mesh": 0, "translation": [20, 0, 0]},                       # 5 unnamed
            {"name": "mirror", "mesh": 0, "scale": [-1, 1, 1]},           # 6
        ],
    )


def test_glb_instanced_nodes_are_parts_with_world_transforms(instanced_glb):
    model = read_path(instanced_glb, up="z")  # z: no frame change, transforms alone
    assert [p.name for p in model.parts] == [
        "body", "cube", "mirror", "wheel", "wheel.1", "wheel.2"]  # sorted; clashes numbered
    assert _box(model.part("body")) == [[0, 0, 0], [4, 1, 2]]
    assert _box(model.part("wheel")) == [[10, 0, 0], [11, 1, 1]]   # cube + (10, 0, 0)
    # Rz(90): (x, y, z) -> (-y, x, z) takes the cube to x in [-1, 0]; then + (0, 5, 0)
    assert _box(model.part("wheel.1")) == [[-1, 5, 0], [0, 6, 1]]
    # nested: arm translation (0, 0, 7) after the child's scale 2
    assert _box(model.part("wheel.2")) == [[0, 0, 7], [2, 2, 9]]
    assert _box(model.part("cube")) == [[20, 0, 0], [21, 1, 1]]    # unnamed node: mesh name
    assert model.part("wheel.1").sources == ("cart.glb:wheel",)
    assert model.units == "m"  # glTF default, no extras


def test_glb_mirroring_transform_keeps_faces_outward(instanced_glb):
    model = read_path(instanced_glb, up="z")
    assert _signed_volume(model.part("wheel")) == pytest.approx(1.0)   # unit cube, outward
    assert _box(model.part("mirror")) == [[-1, 0, 0], [0, 1, 1]]
    assert _signed_volume(model.part("mirror")) == pytest.approx(1.0)  # winding flipped back


def test_glb_primitives_of_a_node_are_one_part(tmp_path):
    # mesh 'm' has two primitives; a node named 'world' (trimesh's own root name) uses it twice
    two = ("m", [CUBE_V, CUBE_V + 3], [CUBE_F, CUBE_F])
    path = write_glb(tmp_path / "prims.glb", [two], [
        {"name": "world", "mesh": 0}, {"name": "x", "mesh": 0, "translation": [10, 0, 0]}])
    model = _load(path, up="z", split=False)  # (by default its two like cubes are split)
    assert [p.name for p in model.parts] == ["world", "x"]
    assert len(model.part("x").faces) == 24                       # 2 primitives x 12
    assert _box(model.part("x")) == [[10, 0, 0], [14, 4, 4]]      # [0, 4]^3 + (10, 0, 0)
    assert _signed_volume(model.part("world")) == pytest.approx(2.0)


def test_glb_default_up_is_y(instanced_glb):
    model = read_path(instanced_glb)
    # (x, y, z) -> (x, -z, y): glTF corner (11, 1, 1) of 'wheel' -> (11, -1, 1)
    wheel = model.part("wheel")
    assert any(np.array_equal(v, [11, -1, 1]) for v in wheel.vertices)
    assert _box(wheel) == [[10, -1, 0], [11, 0, 1]]
    # glTF box [0,2]x[0,2]x[7,9] of 'wheel.2': its front (+Z, z = 9) becomes y = -9
    assert _box(model.part("wheel.2")) == [[0, -9, 0], [2, -7, 2]]
    assert _signed_volume(wheel) == pytest.approx(1.0)  # a rotation keeps orientation


def test_glb_units_from_extras_and_spec(tmp_path):
    cube = ("cube", CUBE_V, CUBE_F)
    nodes = [{"name": "a", "mesh": 0}]
    scene_cm = write_glb(tmp_path / "s.glb", [cube], nodes, scene_extras={"units": "cm"})
    mesh_mm = write_glb(tmp_path / "m.glb", [cube], nodes, mesh_extras=[{"units": "millimeters"}])
    plain = write_glb(tmp_path / "p.glb", [cube], nodes)
    assert read_path(scene_cm).units == "cm"
    assert read_path(mesh_mm).units == "mm"
    assert read_path(plain).units == "m"
    assert read_path(mesh_mm, units="in").units == "in"  # the spec wins
    # a label only: coordinates are never rescaled
    assert _box(read_path(mesh_mm, up="z").part("a")) == [[0, 0, 0], [1, 1, 1]]


def test_glb_meshes_disagreeing_on_units(tmp_path):
    path = write_glb(tmp_path / "mixed.glb", [("a", CUBE_V, CUBE_F), ("b", CUBE_V + 2, CUBE_F)],
                     [{"name": "a", "mesh": 0}, {"name": "b", "mesh": 1}],
                     mesh_extras=[{"units": "mm"}, {"units": "m"}])
    with pytest.raises(ModelError, match=r"mixed\.glb: .*disagree on units"):
        read_path(path)
    assert read_path(path, units="mm").units == "mm"


def test_glb_names_made_safe_and_unique(tmp_path):
    path = write_glb(tmp_path / "n.glb", [("c", CUBE_V, CUBE_F)], [
        {"name": "dowel#1:9", "mesh": 0, "translation": [0, 0, 0]},
        {"name": "a b", "mesh": 0, "translation": [2, 0, 0]},
        {"name": "a_b", "mesh": 0, "translation": [4, 0, 0]},
    ])
    model = read_path(path, up="z")
    assert [p.name for p in model.parts] == ["a_b", "a_b.1", "dowel_1_9"]
    assert model.part("a_b").sources == ("n.glb:a b",)        # first in file order keeps it
    assert _box(model.part("a_b.1"))[0] == [4, 0, 0]
    assert any("renamed 3 parts" in n for n in model.notes)


def _mirror_rot() -> list[float]:
    # column-major: mirror x, rotate 30 deg about Z, translate (1.5, -2, 0.25)
    c, s = np.cos(np.pi / 6), np.sin(np.pi / 6)
    m = np.array([[-c, -s, 0, 1.5], [-s, c, 0, -2], [0, 0, 1, 0.25], [0, 0, 0, 1]], float)
    return m.T.reshape(-1).tolist()


def _same_groups(a, b) -> None:
    """Two readers' groups (load._Groups) alike bit for bit: keys, names, every array's
    dtype and bytes (zeros' signs included), the mesh units, the scene units."""
    (ga, la, ua), (gb, lb, ub) = a, b
    assert sorted(ga) == sorted(gb) and la == lb and ua == ub  # (the caller sorts them)
    for key in ga:
        assert len(ga[key]) == len(gb[key]) == 1
        (_, va, fa, ma, meta_a), (_, vb, fb, mb, meta_b) = ga[key][0], gb[key][0]
        for x, y in ((va, vb), (fa, fb), (ma, mb)):
            assert x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes()
        assert meta_a.get("units") == meta_b.get("units")


def test_plain_glb_reader_is_trimeshs(tmp_path):
    """The GLB reader without trimesh (load._plain_glb) makes what trimesh makes of a plain
    file: the example models, the generated and benchmark models when present, and files
    made here (unnamed and clashing nodes, instancing, a mirroring matrix, units in mesh and
    scene extras); the whole model loads the same either way.  Any other file is left to
    trimesh (None): children, translations, several primitives."""
    from h2s_print import load as L
    from conftest import CONFIGS, SHARED_MODELS

    cube, body = ("cube", CUBE_V, CUBE_F), ("body", *box((0, 0, 0), (4, 1, 2.5)))
    made = [
        write_glb(tmp_path / "a.glb", [cube, body], [
            {"name": "body", "mesh": 1}, {"name": "wheel", "mesh": 0},
            {"name": "wheel", "mesh": 0, "matrix": _rot_z90()}, {"mesh": 0},
            {"name": "", "mesh": 1, "matrix": _mirror_rot()}, {"name": "world", "mesh": 0}]),
        write_glb(tmp_path / "b.glb", [(None, CUBE_V * 0.1, CUBE_F)], [{"mesh": 0}],
                  scene_extras={"units": "cm"}),
        write_glb(tmp_path / "c.glb", [cube, body], [{"name": "a", "mesh": 0},
                                                     {"name": "b", "mesh": 1}],
                  mesh_extras=[{"units": "millimeters"}, None]),
    ]
    found = sorted(CONFIGS.glob("models/*.glb")) + sorted(SHARED_MODELS.glob("*/*.glb"))
    assert len(found) >= 4
    plain = 0
    for path in made + found:
        fast = L._plain_glb(path)
        if fast is None:
            assert path.parent != CONFIGS / "models", path  # the examples are plain
            continue
        plain += 1
        _same_groups(fast, L._trimesh_groups(path, path.name, split=True))
    assert plain >= len(made) + 4
    # the whole load: the same parts with trimesh alone
    for path in made[:1] + found[:4]:
        with_fast = read_path(path)
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(L, "_plain_glb", lambda p: None)
            slow = read_path(path)
        assert [p.name for p in with_fast.parts] == [p.name for p in slow.parts]
        assert with_fast.units == slow.units and with_fast.notes == slow.notes
        for p, q in zip(with_fast.parts, slow.parts):
            assert p.vertices.tobytes() == q.vertices.tobytes()
            assert p.faces.tobytes() == q.faces.tobytes() and p.sources == q.sources
    # not plain: trimesh reads them
    two = ("m", [CUBE_V, CUBE_V + 3], [CUBE_F, CUBE_F])
    for name, meshes, nodes in (
            ("kids.glb", [cube], [{"name": "p", "children": [1]}, {"name": "c", "mesh": 0}]),
            ("trs.glb", [cube], [{"name": "t", "mesh": 0, "translation": [1, 0, 0]}]),
            ("prims.glb", [two], [{"name": "x", "mesh": 0}])):
        assert L._plain_glb(write_glb(tmp_path / name, meshes, nodes)) is None


def test_safe_name():
    assert safe_name("dowel#1:9:6") == "dowel_1_9_6"
    assert safe_name("_hidden part") == "hidden_part"
    assert safe_name("##") == "part"
    assert safe_name("leg.L-2") == "leg.L-2"


# ----------------------------------------------------------------------------- OBJ


def test_obj_objects_are_parts(tmp_path):
    a, b = box((0, 0, 0), (1, 1, 1)), box((2, 0, 0), (3, 2, 1))
    path = tmp_path / "pair.obj"
    path.write_text(obj_text([("o seat", *a), ("o back", *b)]))
    model = read_path(path)
    assert [p.name for p in model.parts] == ["back", "seat"]
    assert _box(model.part("back")) == [[2, 0, 0], [3, 2, 1]]  # z-up: unchanged
    assert model.units == "mm"
    assert len(model.part("seat").faces) == 12


def test_obj_groups_are_parts_and_loose_faces_take_the_stem(tmp_path):
    loose, a, b, a2 = (box((0, 0, 0), (1, 1, 1)), box((2, 0, 0), (3, 1, 1)),
                       box((4, 0, 0), (5, 1, 1)), box((6, 0, 0), (7, 1, 1)))
    path = tmp_path / "shelf.obj"
    path.write_text(obj_text([(None, *loose), ("g left", *a), ("g right", *b), ("g left", *a2)]))
    model = _load(path, split=False)  # (by default the two like boxes of 'left' are split)
    assert [p.name for p in model.parts] == ["left", "right", "shelf"]
    # group 'left' appears twice in the file: one part of 2 x 12 faces, x from 2 to 7
    assert len(model.part("left").faces) == 24
    assert _box(model.part("left")) == [[2, 0, 0], [7, 1, 1]]
    assert model.part("shelf").sources == ("shelf.obj",)


def test_up_x_is_a_proper_rotation(tmp_path):
    path = tmp_path / "tilt.obj"
    path.write_text(obj_text([("o a", *box((1, 2, 3), (2, 4, 6)))]))
    part = read_path(path, up="x").part("a")
    # (x, y, z) -> (-z, y, x): x in [1,2] -> z; y stays; z in [3,6] -> x in [-6,-3]
    assert _box(part) == [[-6, 2, 1], [-3, 4, 2]]
    assert _signed_volume(part) == pytest.approx(1 * 2 * 3)  # orientation kept (det +1)


def test_unreferenced_vertices_removed_and_arrays_frozen(tmp_path):
    v, f = box((0, 0, 0), (1, 1, 1))
    # a first vertex (9, 9, 9) that no face uses (PLY keeps it, unlike trimesh's OBJ reader)
    path = write_ply(tmp_path / "a.ply", np.vstack([[9, 9, 9], v]), f + 1)
    part = read_path(path).part("a")
    assert part.vertices.shape == (8, 3) and part.faces.shape == (12, 3)
    assert part.vertices.dtype == np.float64 and part.faces.dtype == np.int64
    assert not part.vertices.flags.writeable and not part.faces.flags.writeable
    assert _box(part) == [[0, 0, 0], [1, 1, 1]]


def test_loading_is_deterministic(instanced_glb):
    a, b = read_path(instanced_glb), read_path(instanced_glb)
    assert [p.name for p in a.parts] == [p.name for p in b.parts]
    for p, q in zip(a.parts, b.parts):
        assert p.vertices.tobytes() == q.vertices.tobytes()
        assert p.faces.tobytes() == q.faces.tobytes()
    assert a.notes == b.notes


# ----------------------------------------------------------------------------- folders


def test_folder_of_part_files(tmp_path):
    folder = tmp_path / "kit"
    folder.mkdir()
    write_ply(folder / "top.ply", *box((0, 0, 1), (4, 2, 1.5)))
    write_stl(folder / "leg.stl", *box((0, 0, 0), (0.5, 0.5, 1)))
    (folder / "rail.obj").write_text(obj_text([("g a", *box((1, 0, 0), (2, 0.5, 0.5))),
                                               ("g b", *box((2, 0, 0), (3, 0.5, 0.5)))]))
    (folder / "notes.txt").write_text("not a mesh")
    model = read_path(folder)
    assert [p.name for p in model.parts] == ["leg", "rail", "top"]  # one part per file stem
    assert len(model.part("rail").faces) == 24                      # its two groups together
    assert _box(model.part("top")) == [[0, 0, 1], [4, 2, 1.5]]
    assert len(model.part("leg").faces) == 12
    assert model.units == "mm"
    assert model.part("leg").sources == ("leg.stl",)


def test_folder_with_one_file_reads_that_file(tmp_path, instanced_glb):
    model = read_path(instanced_glb.parent)
    assert len(model.parts) == 6
    assert model.notes[0] == "folder holds one mesh file: read cart.glb"


def test_folder_with_clashing_stems(tmp_path):
    write_ply(tmp_path / "a.ply", *box((0, 0, 0), (1, 1, 1)))
    write_stl(tmp_path / "a.stl", *box((0, 0, 0), (1, 1, 1)))
    with pytest.raises(ModelError, match=r"a\.ply and a\.stl both make part 'a'"):
        read_path(tmp_path)


def _partnet(folder: Path, tree) -> Path:
    (folder / "textured_objs").mkdir(parents=True)
    (folder / "objs").mkdir()
    for name, lo, hi, sub in [("original-1", (0, 0, 0), (2, 1, 1), "textured_objs"),
                              ("original-2", (0, 1, 0), (2, 2, 1), "textured_objs"),
                              ("original-3", (0, 2, 0), (1, 3, 1), "objs")]:
        (folder / sub / f"{name}.obj").write_text(obj_text([("o mesh", *box(lo, hi))]))
    (folder / "result.json").write_text(json.dumps(tree))
    return folder


PARTNET_TREE = [{"id": 0, "name": "thing", "text": "Thing", "children": [
    {"id": 1, "name": "body", "text": "Body", "objs": ["original-1", "original-2"]},
    {"id": 2, "name": "top", "children": [
        {"id": 3, "name": "lid", "objs": ["original-3"]},
        {"id": 4, "name": "empty", "objs": []}]}]}]


def test_partnet_folder_leaves_are_parts(tmp_path):
    model = read_path(_partnet(tmp_path / "pn", PARTNET_TREE))
    assert [p.name for p in model.parts] == ["1_body", "3_lid"]  # "<id>_<name>" of leaves
    assert len(model.part("1_body").faces) == 24                   # two 12-face pieces
    assert model.part("1_body").sources == ("pn/textured_objs/original-1.obj",
                                            "pn/textured_objs/original-2.obj")
    assert model.part("3_lid").sources == ("pn/objs/original-3.obj",)  # objs/ looked up first
    assert model.units == "m"
    # PartNet is Y-up: (x, y, z) -> (x, -z, y); body's y in [0, 2] becomes z, z in [0, 1] -> -y
    assert _box(model.part("1_body")) == [[0, -1, 0], [2, 0, 2]]
    assert "skipped leaf '4_empty': it lists no objs" in model.notes
    assert _box(read_path(tmp_path / "pn", up="z").part("3_lid")) == [[0, 2, 0], [1, 3, 1]]


@pytest.mark.parametrize("text, message", [
    ("{not json", r"pn/result\.json: cannot read"),
    ('{"id": 1}', r"pn/result\.json: node \[0\]: missing or bad 'name'"),
    ('[{"id": 1, "name": "a", "objs": "original-1"}]', r"'objs' must be a list"),
    ('[{"id": 1, "name": "a", "objs": ["original-9"]}]', r"'original-9' not found"),
    ('"leaf"', r"expected a list of part nodes"),
])
def test_partnet_malformed(tmp_path, text, message):
    folder = _partnet(tmp_path / "pn", PARTNET_TREE)
    (folder / "result.json").write_text(text)
    with pytest.raises(ModelError, match=message):
        read_path(folder)


# ----------------------------------------------------------------------------- regrouping


@pytest.fixture
def five_parts(tmp_path) -> Path:
    path = tmp_path / "m.obj"
    path.write_text(obj_text([
        ("o body_top", *box((0, 0, 5), (10, 10, 10))),
        ("o body_bottom", *box((0, 0, 0), (10, 10, 5))),
        ("o screw_1", *box((0, 0, 10), (1, 1, 11))),
        ("o screw_2", *box((9, 9, 10), (10, 10, 11))),
        ("o handle", *box((10, 4, 4), (12, 6, 6))),
    ]))
    return path


def test_merge_rename_drop(five_parts):
    model = _load(five_parts, merge=(("body", ("body_*",)),), rename=(("handle", "grip"),),
                  drop=("screw_*",))
    assert [p.name for p in model.parts] == ["body", "grip"]
    body = model.part("body")
    assert len(body.faces) == 24 and len(body.vertices) == 16   # 2 boxes concatenated
    assert _box(body) == [[0, 0, 0], [10, 10, 10]]
    assert body.sources == ("m.obj:body_bottom", "m.obj:body_top")  # members by name
    assert model.notes == (
        "dropped 2 parts matching 'screw_*': screw_1, screw_2",
        "merged 2 parts into body: body_bottom, body_top",
        "renamed handle to grip",
    )


def test_merge_groups_apply_in_order(five_parts):
    model = _load(five_parts, merge=(("body", ("body_*",)), ("all", ("body", "screw_?"))))
    assert [p.name for p in model.parts] == ["all", "handle"]
    assert len(model.part("all").faces) == 4 * 12


def test_pattern_matching_nothing_is_a_config_error(five_parts):
    with pytest.raises(ConfigError) as err:
        _load(five_parts, merge=(("body", ("lid_*",)),))
    assert str(err.value) == ("m.obj: model.parts.merge.body: 'lid_*' matches no part "
                              "(parts: body_bottom, body_top, handle, screw_1, screw_2)")
    with pytest.raises(ConfigError, match=r"m\.obj: model\.parts\.drop\[1\]: 'nut' matches no"):
        _load(five_parts, drop=("screw_1", "nut"))
    with pytest.raises(ConfigError, match=r"model\.parts\.rename\.knob: 'knob' matches no"):
        _load(five_parts, rename=(("knob", "k"),))


def test_bad_renames_and_merges(five_parts):
    with pytest.raises(ConfigError, match=r"rename\.screw_\*: matches 2 parts"):
        _load(five_parts, rename=(("screw_*", "s"),))
    with pytest.raises(ConfigError, match=r"'handle' would name two parts"):
        _load(five_parts, rename=(("screw_1", "handle"),))
    with pytest.raises(ConfigError, match=r"merge\.handle: 'handle' is already the name"):
        _load(five_parts, merge=(("handle", ("screw_*",)),))
    with pytest.raises(ConfigError, match=r"drops every part"):
        _load(five_parts, drop=("*",))
    # a swap is one simultaneous renaming, not a clash
    swapped = _load(five_parts, rename=(("screw_1", "screw_2"), ("screw_2", "screw_1")))
    assert _box(swapped.part("screw_1"))[0] == [9, 9, 10]


# ----------------------------------------------------------------------------- small parts


@pytest.fixture
def with_tiny(tmp_path) -> Path:
    path = tmp_path / "t.obj"
    path.write_text(obj_text([
        ("o body", *box((0, 0, 0), (10, 10, 10))),
        ("o other", *box((20, 0, 0), (30, 10, 10))),
        ("o screw_a", *box((10.5, 0, 0), (10.6, 0.1, 0.1))),    # 0.5 from body
        ("o screw_b", *box((19.5, 0, 0), (19.6, 0.1, 0.1))),    # 0.4 from other
        ("o mid", *box((14.95, 0, 0), (15.05, 0.1, 0.1))),      # 4.95 from both: tie
        ("o flat", np.array([[0, 0, 0], [1, 1, 1], [2, 2, 2.0]]), np.array([[0, 1, 2]])),
    ]))
    # model box over parts with area: [0,30]x[0,10]x[0,10], diagonal sqrt(1100) = 33.17;
    # 1 % of it is 0.33 > a screw's diagonal 0.1 * sqrt(3) = 0.17: the three small ones are tiny
    return path


def test_tiny_parts_merge_into_nearest(with_tiny):
    model = _load(with_tiny)  # defaults: small="merge", min_size=0.01
    assert [p.name for p in model.parts] == ["body", "other"]
    assert len(model.part("body").faces) == 36   # body + mid (tie -> 'body' by name) + screw_a
    assert len(model.part("other").faces) == 24  # other + screw_b
    assert model.notes == (
        "dropped degenerate part 'flat' (no area)",
        "merged 2 tiny parts into body: mid, screw_a",
        "merged 1 tiny part into other: screw_b",
    )


def test_tiny_parts_drop_and_keep(with_tiny):
    dropped = _load(with_tiny, small="drop")
    assert [p.name for p in dropped.parts] == ["body", "other"]
    assert len(dropped.part("body").faces) == 12
    assert dropped.notes[-1] == ("dropped 3 tiny parts (box diagonal below 0.01 of the "
                                 "model's): mid, screw_a, screw_b")
    kept = _load(with_tiny, small="keep")
    assert [p.name for p in kept.parts] == ["body", "mid", "other", "screw_a", "screw_b"]
    assert kept.notes[0] == "dropped degenerate part 'flat' (no area)"  # always dropped
    none_tiny = _load(with_tiny, min_size=0.0)
    assert len(none_tiny.parts) == 5


def test_every_part_tiny_or_flat(tmp_path):
    path = tmp_path / "spread.obj"
    path.write_text(obj_text([(f"o c{i}", *box((10 * i, 0, 0), (10 * i + 1, 1, 1)))
                              for i in range(3)]))
    # model diagonal ~ sqrt(21^2 + 1 + 1) = 21.05; half of it 10.5 > cube diagonal 1.73
    with pytest.raises(ModelError, match=r"spread\.obj: every part is tiny"):
        _load(path, min_size=0.5)
    flat = tmp_path / "flat.obj"
    flat.write_text("o a\nv 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")
    with pytest.raises(ModelError, match=r"flat\.obj: no part has any area"):
        read_path(flat)


# ----------------------------------------------------------------------------- errors


def _one_line(err) -> str:
    text = str(err.value)
    assert "\n" not in text and "Traceback" not in text
    return text


def test_missing_path(tmp_path):
    with pytest.raises(ModelError) as err:
        read_path(tmp_path / "nope.glb")
    assert "nope.glb: no such file or folder" in _one_line(err)


@pytest.mark.parametrize("name", ["bad.glb", "bad.ply", "bad.gltf"])
def test_corrupt_files(tmp_path, name):
    rng = np.random.default_rng(7)
    path = tmp_path / name
    path.write_bytes(rng.integers(0, 256, 300, dtype=np.uint8).tobytes())
    with pytest.raises(ModelError) as err:
        read_path(path)
    assert _one_line(err).startswith(f"{name}: cannot read")


@pytest.mark.parametrize("name, text", [
    ("empty.obj", ""),
    ("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"),
    ("empty.stl", "solid x\nendsolid x\n"),
])
def test_files_without_faces(tmp_path, name, text):
    (tmp_path / name).write_text(text)
    with pytest.raises(ModelError) as err:
        read_path(tmp_path / name)
    assert _one_line(err) == f"{name}: no triangle mesh with faces in the file"


def test_nan_coordinates_name_the_part(tmp_path):
    path = tmp_path / "nan.obj"
    path.write_text("o good\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
                    "o leg\nv 0 0 1\nv 1 0 nan\nv 0 1 1\nf 4 5 6\n")
    with pytest.raises(ModelError) as err:
        read_path(path)
    assert _one_line(err) == "nan.obj: part 'leg' has NaN or infinite coordinates"


def test_folder_without_meshes(tmp_path):
    folder = tmp_path / "docs"
    folder.mkdir()
    (folder / "readme.txt").write_text("hi")
    with pytest.raises(ModelError) as err:
        read_path(folder)
    assert _one_line(err).startswith("docs: folder holds no mesh files")


def test_unknown_extension(tmp_path):
    (tmp_path / "model.fbx").write_bytes(b"x")
    with pytest.raises(ModelError, match=r"model\.fbx: unknown model format '\.fbx'"):
        read_path(tmp_path / "model.fbx")


def test_bad_up_and_units_values(instanced_glb):
    with pytest.raises(ConfigError, match=r"cart\.glb: model\.up"):
        read_path(instanced_glb, up="w")
    with pytest.raises(ConfigError, match=r"cart\.glb: model\.units"):
        read_path(instanced_glb, units="ft")


# ----------------------------------------------------------------------------- shared models

SHARED = [  # (path under shared/models, up, parts, units) from its README table
    ("ikea_chair_ingolf/chair_ingolf_0650.glb", "z", 5, "m"),
    ("ikea_table_lack/table_lack_0825.glb", "z", 5, "m"),
    ("ikea_desk_fredrik/desk_fredrik_0430.glb", "z", 7, "m"),  # part4: two like pieces, split
    ("ikea_box_ivar/box_ivar_0666.glb", "z", 5, "m"),
    ("partnet_mobility_oven_101773", None, 10, "m"),
    ("partnet_mobility_oven_101773/parts_leaf.glb", None, 10, "m"),
    ("partnet_mobility_bottle_3763", None, 3, "m"),
    ("partnet_mobility_bottle_3763/parts_leaf.glb", None, 3, "m"),
    ("trimesh_pins_plate/pins.glb", "z", 7, "mm"),
]


@pytest.mark.parametrize("rel, up, count, units", SHARED)
def test_shared_models(shared_models, rel, up, count, units):
    model = read_path(shared_models / rel, up=up)
    assert len(model.parts) == count
    assert model.units == units
    for part in model.parts:
        assert len(part.faces) > 0 and np.isfinite(part.vertices).all()


def test_partnet_folder_matches_its_glb(shared_models):
    folder = read_path(shared_models / "partnet_mobility_oven_101773")
    glb = read_path(shared_models / "partnet_mobility_oven_101773" / "parts_leaf.glb")
    assert [p.name for p in folder.parts] == [p.name for p in glb.parts]
    assert np.allclose(folder.bounds, glb.bounds, atol=1e-5)  # GLB stores float32


def test_pins_dowels_are_instances(shared_models):
    model = read_path(shared_models / "trimesh_pins_plate" / "pins.glb", up="z")
    dowels = [p for p in model.parts if p.name.startswith("dowel")]
    assert len(dowels) == 6
    assert {len(p.faces) for p in dowels} == {314}  # one mesh, six placements
    assert len({p.box for p in dowels}) == 6
    assert dowels[0].sources[0].startswith("pins.glb:dowel#1:")


# ----------------------------------------------------------------------------- split pieces


def _axle(tmp_path: Path, second=((3.0, 0.0, 0.0), (4.0, 1.0, 1.0)), name="axle") -> Path:
    """One mesh holding two pieces: a unit cube and the box ``second``, plus a separate body."""
    a = box((0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
    b = box(*second)
    v = np.vstack([a[0], b[0]])
    f = np.vstack([a[1], b[1] + len(a[0])])
    body = box((-2.0, -2.0, 2.0), (6.0, 3.0, 4.0))
    return write_glb(
        tmp_path / f"{name}.glb", [("wheels", v, f), ("body", *body)],
        [{"name": "wheels", "mesh": 0}, {"name": "body", "mesh": 1}])


def test_a_part_of_like_pieces_is_split_and_said(tmp_path):
    model = _load(_axle(tmp_path), up="z", units="mm")
    names = [p.name for p in model.parts]
    assert names == ["body", "wheels_1", "wheels_2"]
    one, two = (model.part(n) for n in ("wheels_1", "wheels_2"))
    assert _box(one) == [[0, 0, 0], [1, 1, 1]] and _box(two) == [[3, 0, 0], [4, 1, 1]]
    assert len(one.faces) == len(two.faces) == 12
    assert any(n.startswith("split wheels into 2 pieces") for n in model.notes)


def test_unlike_pieces_and_split_false_stay_whole(tmp_path):
    unlike = _load(_axle(tmp_path, ((3.0, 0.0, 0.0), (5.0, 1.0, 1.0)), "unlike"),
                   up="z", units="mm")
    assert [p.name for p in unlike.parts] == ["body", "wheels"]
    whole = _load(_axle(tmp_path), up="z", units="mm", split=False)
    assert [p.name for p in whole.parts] == ["body", "wheels"]
    assert not any("split" in n for n in whole.notes)


def test_split_never_takes_another_parts_name(tmp_path):
    model = _load(_axle(tmp_path), up="z", units="mm", rename=(("body", "wheels_1"),))
    names = sorted(p.name for p in model.parts)
    assert names == ["wheels_1", "wheels_1_", "wheels_2"]
