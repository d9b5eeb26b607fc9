"""Stage 1, *load*: model file(s) to a :class:`~h2s_print.types.Model` (DESIGN.md §2.1).

This is the only stage that reads model files; trimesh does the parsing.  What becomes a part:

* **glTF / GLB** (``.glb``, ``.gltf``): every node that holds a mesh is one part named after the
  node, with the node's world transform applied.  A mesh used by several nodes (instancing)
  gives one part per node.  A node's several primitives are one part.  Unnamed nodes take their
  mesh's name, else ``node<index>``.
* **OBJ**: every ``o`` object and ``g`` group is a part (``<object>_<group>`` when a face has
  both, as trimesh names them); faces before any ``o``/``g`` form a part named after the file
  stem.  A file without groups is one part.
* **PLY, STL**: the file is one part named after its stem (an STL with several solids: one part
  per solid).
* **A folder of mesh files** (``.glb .gltf .obj .ply .stl``, not recursive, hidden files
  ignored): each file is *one* part named after its stem; all its nodes/groups are concatenated
  (load the file itself to get its sub-parts).  A folder holding exactly one mesh file is read
  as that file.
* **A PartNet folder** (it has ``result.json``): each leaf of the hierarchy is a part named
  ``<id>_<name>`` (as ``parts_leaf.glb`` names them), the concatenation of the OBJ pieces it
  lists (looked up in ``objs/`` then ``textured_objs/``).  PartNet is Y-up and roughly in metres,
  so a PartNet folder defaults to ``up: y`` and ``units: m`` (the same frame as its GLB export).

Part names are made safe for ids: every run of characters that are not letters or digits (of
any script: ``корпус`` stays), ``_``, ``.`` or ``-`` becomes ``_`` and leading ``_ . -`` are
stripped (``dowel#1:9`` -> ``dowel_1_9``).  Names that clash are numbered in reading order: ``dowel``, ``dowel.1``,
``dowel.2``.  The original node/group/file names stay in :attr:`Part.sources`.

Frame: glTF files (and PartNet folders) are Y-up by default and are rotated +90° about X,
``(x, y, z) -> (x, -z, y)``, which also takes glTF's front (+Z) to the internal front (-Y).
Other formats are Z-up by default.  ``up: x`` rotates -90° about Y, ``(x, y, z) -> (-z, y, x)``,
keeping Y (and so a -Y front) in place.  Coordinates are never rescaled: units are a label,
taken from the spec, else the glTF ``extras.units`` (scene, else every mesh), else ``m`` for
glTF and ``mm`` for other formats.

Regrouping (:class:`~h2s_print.config.PartsSpec`) runs in this order, with ``fnmatch`` globs over
part names: ``drop`` (original names), then ``merge`` groups in config order (each over the
parts left by the previous one), then ``rename`` (all at once; a key must match exactly one
part).  A pattern that matches nothing is a :class:`ConfigError`.  Then the small-part policy:
parts without area are always dropped; parts whose box diagonal is below ``min_size`` times the
model's are merged into the nearest remaining part (distance between boxes, ties by name),
dropped or kept.  Before that, a part made of two or more disconnected pieces of one shape (same
triangle count, box extents and area within :data:`PIECE_TOL`: the two wheels of an axle in
one mesh) becomes one part per piece, ``<name>_1``, ``<name>_2`` ... ordered by their box
centres (x, then y, then z); ``model.parts.split: false`` keeps such parts whole.  Pieces are
connected through shared vertex positions (exactly equal coordinates), so a mesh with seams
stays one piece.  Every such action is a line in :attr:`Model.notes`.

Meshes are cleaned only of unreferenced vertices (faces are kept as read, no trimesh
processing), vertices float64, faces int64; mirroring transforms flip face winding back.
"""

from __future__ import annotations

import fnmatch
import json
import logging
import math
import re
import struct
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterable, Sequence

import numpy as np

from .config import UNITS, ModelSpec, PartsSpec
from .errors import ConfigError, ModelError
from .types import Model, Part, readonly

log = logging.getLogger(__name__)

#: Extensions read as model files, lower case, with the dot.
MESH_EXTENSIONS = (".glb", ".gltf", ".obj", ".ply", ".stl")
_GLTF = (".glb", ".gltf")
#: Rotations from a file's frame to the internal Z-up frame, by the file's up axis.
_UP_ROTATION = {
    "z": np.eye(3),
    # +90 deg about X: (x, y, z) -> (x, -z, y); glTF front +Z -> -Y.
    "y": np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]),
    # -90 deg about Y: (x, y, z) -> (-z, y, x).
    "x": np.array([[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]]),
}
_UNIT_ALIASES = {
    "mm": "mm", "millimeter": "mm", "millimeters": "mm", "millimetre": "mm", "millimetres": "mm",
    "cm": "cm", "centimeter": "cm", "centimeters": "cm", "centimetre": "cm", "centimetres": "cm",
    "m": "m", "meter": "m", "meters": "m", "metre": "m", "metres": "m",
    "in": "in", "inch": "in", "inches": "in",
}
#: A part has no area when its total triangle area is below this times its box diagonal squared.
_AREA_EPS = 1e-12
_MAX_LISTED = 12


# ------------------------------------------------------------------------------ public verbs


def load_model(spec: ModelSpec) -> Model:
    """Read the model that ``spec`` names into named parts in the internal Z-up frame.

    Args:
        spec: where the model is (file or folder) and how to read and regroup it.

    Returns:
        The model, parts sorted by name, with notes on what loading changed.

    Raises:
        ModelError: the path is missing, unreadable, of an unknown kind, or holds no usable
            geometry (one line naming the file).
        ConfigError: ``up``/``units`` are invalid or a merge/rename/drop pattern fails.
    """
    path = Path(spec.path)
    cfg = path.name or str(path)
    if spec.up is not None and spec.up not in _UP_ROTATION:
        raise ConfigError(f"{cfg}: model.up: expected one of x, y, z, got {spec.up!r}")
    if spec.units is not None and spec.units not in UNITS:
        raise ConfigError(f"{cfg}: model.units: expected one of {', '.join(UNITS)}, "
                          f"got {spec.units!r}")
    if not path.exists():
        raise ModelError(f"{path}: no such file or folder")
    raw = _read_any(path, spec.up, units_given=spec.units is not None)
    notes = list(raw.notes)
    units = spec.units or raw.units
    parts = _finite(raw.parts, raw.where)
    parts = _regroup(parts, spec.parts, cfg, notes)
    if spec.parts.split:
        parts = _split_pieces(parts, notes)
    parts = _small_parts(parts, spec.parts, raw.where, notes)
    for line in notes:
        log.info("%s: %s", raw.where, line)
    return Model(source=spec.source or str(spec.path), units=units,
                 parts=tuple(sorted(parts, key=lambda p: p.name)), notes=tuple(notes))


def read_path(path: Path | str, up: str | None = None, units: str | None = None) -> Model:
    """Read a bare model file or folder with default regrouping (for ``h2s inspect PATH``).

    Args:
        path: model file or folder.
        up: the file's up axis (``x``, ``y``, ``z``) or ``None`` for the format's default.
        units: ``mm``, ``cm``, ``m``, ``in`` or ``None`` for the file's own.
    """
    return load_model(ModelSpec(path=Path(path).resolve(), up=up, units=units))


# ------------------------------------------------------------------------------ raw reading


@dataclass(frozen=True, slots=True)
class _Piece:
    """One named mesh straight from a file, already in the internal frame."""

    name: str          # raw name (node, group, file stem, PartNet leaf)
    vertices: np.ndarray
    faces: np.ndarray
    sources: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class _Raw:
    where: str         # how messages name the model
    units: str         # the file's own units (or the format default)
    parts: tuple[Part, ...]
    notes: tuple[str, ...]


def _read_any(path: Path, up: str | None, units_given: bool) -> _Raw:
    if path.is_dir():
        if (path / "result.json").is_file():
            return _read_partnet(path, up)
        return _read_folder(path, up, units_given)
    ext = path.suffix.lower()
    if ext not in MESH_EXTENSIONS:
        raise ModelError(f"{path.name}: unknown model format {ext or '(no extension)'!r} "
                         f"(expected a folder or one of {', '.join(MESH_EXTENSIONS)})")
    pieces, units, notes = _read_file(path, up, path.name, split=True,
                                      units_given=units_given)
    names, renamed = _part_names([p.name for p in pieces])
    if renamed:
        notes.append(renamed)
    parts = tuple(Part(n, p.vertices, p.faces, p.sources) for n, p in zip(names, pieces))
    return _Raw(path.name, units, parts, tuple(notes))


def _read_folder(path: Path, up: str | None, units_given: bool) -> _Raw:
    files = sorted((f for f in path.iterdir()
                    if f.is_file() and not f.name.startswith(".")
                    and f.suffix.lower() in MESH_EXTENSIONS), key=lambda f: f.name)
    where = path.name
    if not files:
        raise ModelError(f"{where}: folder holds no mesh files "
                         f"({', '.join(MESH_EXTENSIONS)}) and no result.json")
    if len(files) == 1:
        raw = _read_any(files[0], up, units_given)
        note = f"folder holds one mesh file: read {files[0].name}"
        return _Raw(f"{where}/{raw.where}", raw.units, raw.parts, (note,) + raw.notes)
    stems: dict[str, str] = {}
    pieces: list[_Piece] = []
    unit_of: dict[str, str] = {}
    notes: list[str] = []
    for f in files:
        if f.stem in stems:
            raise ModelError(f"{where}: {stems[f.stem]} and {f.name} both make part {f.stem!r}")
        stems[f.stem] = f.name
        got, units, file_notes = _read_file(f, up, f"{where}/{f.name}", split=False,
                                            units_given=units_given)
        notes.extend(f"{f.name}: {n}" for n in file_notes)
        unit_of[f.name] = units
        pieces.append(_concat_pieces(f.stem, got, (f.name,)))
    if all(f.suffix.lower() in _GLTF for f in files):
        found = sorted(set(unit_of.values()))
        if len(found) > 1 and not units_given:
            raise ModelError(f"{where}: files disagree on units ({_listing(found)}); "
                             "set model.units")
        units = found[0]
    else:
        units = "mm"
    names, renamed = _part_names([p.name for p in pieces])
    if renamed:
        notes.append(renamed)
    parts = tuple(Part(n, p.vertices, p.faces, p.sources) for n, p in zip(names, pieces))
    return _Raw(where, units, parts, tuple(notes))


def _read_partnet(path: Path, up: str | None) -> _Raw:
    where = f"{path.name}/result.json"
    try:
        tree = json.loads((path / "result.json").read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ModelError(f"{where}: cannot read: {_short(exc)}") from None
    leaves = _partnet_leaves(tree, where)
    if not leaves:
        raise ModelError(f"{where}: the hierarchy has no leaves")
    rot = _UP_ROTATION[up or "y"]
    pieces: list[_Piece] = []
    notes: list[str] = []
    for node_id, name, objs in leaves:
        label = f"{node_id}_{name}"
        if not objs:
            notes.append(f"skipped leaf {label!r}: it lists no objs")
            continue
        got: list[_Piece] = []
        for obj in objs:
            f = _partnet_obj(path, obj, where)
            rel = f"{f.parent.name}/{f.name}"
            meshes, _ = _scene_meshes(f, f"{path.name}/{rel}", split=False)
            got.extend(_Piece(label, v @ rot.T, fc, (rel,)) for _, v, fc, _ in meshes)
        pieces.append(_concat_pieces(label, got, tuple(dict.fromkeys(f"{path.name}/{s}"
                                                                     for p in got
                                                                     for s in p.sources))))
    if not pieces:
        raise ModelError(f"{where}: no leaf lists any objs")
    names, renamed = _part_names([p.name for p in pieces])
    if renamed:
        notes.append(renamed)
    parts = tuple(Part(n, p.vertices, p.faces, p.sources) for n, p in zip(names, pieces))
    return _Raw(path.name, "m", parts, tuple(notes))


def _partnet_leaves(tree: Any, where: str) -> list[tuple[str, str, list[str]]]:
    """(id, name, objs) of every leaf, depth first in file order."""
    if not isinstance(tree, list):
        tree = [tree] if isinstance(tree, dict) else None
    if tree is None:
        raise ModelError(f"{where}: expected a list of part nodes")
    out: list[tuple[str, str, list[str]]] = []
    stack: list[tuple[Any, str]] = [(n, f"[{i}]") for i, n in reversed(list(enumerate(tree)))]
    while stack:
        node, at = stack.pop()
        if not isinstance(node, dict):
            raise ModelError(f"{where}: node {at}: expected a mapping")
        children = node.get("children") or []
        if not isinstance(children, list):
            raise ModelError(f"{where}: node {at}: 'children' must be a list")
        if children:
            stack.extend((c, f"{at}.children[{i}]")
                         for i, c in reversed(list(enumerate(children))))
            continue
        node_id, name = node.get("id"), node.get("name", node.get("text"))
        if isinstance(node_id, bool) or not isinstance(node_id, (int, str)):
            raise ModelError(f"{where}: node {at}: missing or bad 'id'")
        if not isinstance(name, str) or not name:
            raise ModelError(f"{where}: node {at}: missing or bad 'name'")
        objs = node.get("objs") or []
        if not isinstance(objs, list) or not all(isinstance(o, str) and o for o in objs):
            raise ModelError(f"{where}: node {at}: 'objs' must be a list of names")
        out.append((str(node_id), name, list(objs)))
    return out


def _partnet_obj(folder: Path, obj: str, where: str) -> Path:
    stem = obj[:-4] if obj.lower().endswith(".obj") else obj
    if "/" in stem or "\\" in stem or stem in (".", ".."):
        raise ModelError(f"{where}: obj name {obj!r} is not a plain file name")
    for sub in ("objs", "textured_objs"):
        f = folder / sub / f"{stem}.obj"
        if f.is_file():
            return f
    raise ModelError(f"{where}: {obj!r} not found in objs/ or textured_objs/")


def _read_file(path: Path, up: str | None, where: str, split: bool,
               units_given: bool = False) -> tuple[list[_Piece], str, list[str]]:
    """Pieces (internal frame), units and notes of one model file.

    With ``units_given`` (the spec sets units) the file's own units are not checked.
    """
    ext = path.suffix.lower()
    gltf = ext in _GLTF
    rot = _UP_ROTATION[up or ("y" if gltf else "z")]
    meshes, labels = _scene_meshes(path, where, split)
    notes: list[str] = []
    if gltf and not units_given:
        units, note = _gltf_units(labels, where)
        if note:
            notes.append(note)
    else:
        units = "m" if gltf else "mm"
    pieces = [_Piece(name, v @ rot.T, f, (src,)) for name, v, f, src in meshes]
    return pieces, units, notes


def _scene_meshes(path: Path, where: str, split: bool
                  ) -> tuple[list[tuple[str, np.ndarray, np.ndarray, str]], list[str]]:
    """Every triangle mesh in a file, and the units its extras state.

    Returns:
        ``(raw name, world vertices, faces, source)`` per mesh node (glTF: per node, its
        primitives together, in the file's node order; others: per object/group, by name;
        points and lines are skipped), and the sorted distinct ``units`` labels of the file's
        scene extras (or, when the scene has none, of its meshes' extras).

    Everything trimesh may raise while reading is turned into a :class:`ModelError` here.
    A plain GLB (:func:`_plain_glb`) is read without trimesh, to the same arrays.
    """
    gltf = path.suffix.lower() in _GLTF
    read = _plain_glb(path) if path.suffix.lower() == ".glb" else None
    groups, labels, scene_units = read if read is not None else _trimesh_groups(path, where,
                                                                                split)
    if not groups:
        raise ModelError(f"{where}: no triangle mesh with faces in the file")
    out = []
    mesh_units: set[str] = set()
    for key in sorted(groups):
        name = labels[key]
        pieces = []
        for geom_name, vertices, faces, matrix, meta in sorted(groups[key], key=lambda g: g[0]):
            if faces.min() < 0 or faces.max() >= len(vertices):
                raise ModelError(f"{where}: mesh {geom_name!r}: face index out of range")
            if np.linalg.det(matrix[:3, :3]) < 0:
                faces = faces[:, ::-1]  # a mirroring transform turns the winding inside out
            pieces.append((vertices @ matrix[:3, :3].T + matrix[:3, 3], faces))
            if isinstance(meta, dict) and meta.get("units") is not None:
                mesh_units.add(str(meta["units"]))
        world, faces = _concat(pieces)
        source = path.name if name == path.stem and not gltf else f"{path.name}:{name}"
        out.append((name, world, faces, source))
    return out, sorted(scene_units or mesh_units)


#: What :func:`_trimesh_groups` and :func:`_plain_glb` read: per part key (glTF: node index
#: and name), its meshes as ``(geometry name, vertices, faces, world matrix, metadata)``; the
#: key's raw part name; the units the scene's extras state (a set of at most one).
_Groups = tuple[dict[Any, list[tuple[str, np.ndarray, np.ndarray, np.ndarray, Any]]],
                dict[Any, str], set[str]]


def _trimesh_groups(path: Path, where: str, split: bool) -> _Groups:
    """A model file's meshes as trimesh reads them (see :data:`_Groups`)."""
    import trimesh  # the loader's heavy dependency, kept to this module

    ext = path.suffix.lower()
    gltf = ext in _GLTF
    kwargs: dict[str, Any] = {"process": False}
    if ext == ".obj":
        kwargs.update(split_objects=split, split_groups=split, group_material=False,
                      skip_materials=True)
    # glTF: trimesh's merge_primitives fails on primitives without a material, so primitives
    # stay apart here: trimesh hangs them under their node with random frame names, and they
    # are grouped back by that parent node below.
    try:
        if path.stat().st_size == 0:  # some parsers fail on it with an obscure IndexError
            raise ModelError(f"{where}: no triangle mesh with faces in the file")
        scene = trimesh.load_scene(str(path), file_type=ext[1:], **kwargs)
        node_names = _gltf_node_names(path) if gltf else {}
        parents = scene.graph.transforms.parents
        groups: dict[Any, list[tuple[str, np.ndarray, np.ndarray, np.ndarray, Any]]] = {}
        labels: dict[Any, str] = {}
        for frame in scene.graph.nodes_geometry:
            matrix, geom_name = scene.graph[frame]
            geom = scene.geometry.get(geom_name)
            if not isinstance(geom, trimesh.Trimesh):
                continue  # points and lines are not parts
            faces = np.asarray(geom.faces, dtype=np.int64).reshape(-1, 3)
            if len(faces) == 0:
                continue
            if gltf:
                node = node_names.get(frame) or node_names.get(parents.get(frame))
                key: Any = node if node else (math.inf, str(frame))
                labels[key] = key[1]
            else:
                key = (0, str(frame))
                labels[key] = path.stem if frame == path.name else str(frame)
            groups.setdefault(key, []).append(
                (str(geom_name), np.asarray(geom.vertices, dtype=np.float64), faces,
                 np.asarray(matrix, dtype=np.float64), geom.metadata))
        scene_meta = scene.metadata
    except ModelError:
        raise
    except Exception as exc:  # noqa: BLE001 - the IO edge: any parser failure is the file's
        raise ModelError(f"{where}: cannot read: {_short(exc)}") from None
    scene_units = ({str(scene_meta["units"])} if isinstance(scene_meta, dict)
                   and scene_meta.get("units") is not None else set())
    return groups, labels, scene_units


#: glTF index component types a plain GLB may use (unsigned 8, 16, 32 bits), as numpy types.
_GLB_INDICES = {5121: "<u1", 5123: "<u2", 5125: "<u4"}
#: The keys a plain GLB's parts may have (anything else: trimesh reads the file).
_GLB_NODE_KEYS = frozenset(("name", "mesh", "matrix"))
_GLB_MESH_KEYS = frozenset(("name", "primitives", "extras"))
_GLB_PRIMITIVE_KEYS = frozenset(("attributes", "indices", "mode"))
_GLB_ACCESSOR_KEYS = frozenset(("bufferView", "byteOffset", "componentType", "count", "type",
                                "min", "max", "name"))


def _plain_glb(path: Path) -> _Groups | None:
    """The meshes of a *plain* GLB, read without trimesh to exactly what
    :func:`_trimesh_groups` makes of it, or None for any other file (trimesh reads it, and says
    what is wrong with a broken one).

    Plain: glTF 2 with one binary chunk, the one buffer, no extensions; the scene's root nodes
    (``scene``'s, else the first) each a mesh without children or camera, placed by a
    ``matrix`` or by nothing; each of their meshes one primitive of triangles (mode 4), its
    positions float32 triples and its indices unsigned integers, all in range, both packed
    (no stride, no sparse accessor), and no other attribute or material.  The example models,
    the generated ones and the benchmark's IKEA models are plain.  Read as trimesh reads them:
    float32 positions as float64, indices as int64, the node's matrix transposed (glTF
    stores columns), the identity without one; units ``meters`` but for the mesh's extras,
    the scene's extras' units only when the file names its ``scene``.

    Why: importing trimesh (which brings scipy.ndimage along for its voxels) took 0.09 s of a
    1.1 s ``h2s plan`` of the camera; such a file is a few array views.
    tests/test_load.py compares the two readers on every model at hand and on made files.
    """
    try:
        data = path.read_bytes()
        if len(data) < 28 or data[:4] != b"glTF":
            return None
        version, _, n_json, kind = struct.unpack_from("<II I4s", data, 4)
        at = 20 + n_json
        if version != 2 or kind != b"JSON" or len(data) < at + 8:
            return None
        header = json.loads(data[20:at].decode("utf-8"))
        n_bin, kind = struct.unpack_from("<I4s", data, at)
        if kind != b"BIN\x00" or at + 8 + n_bin != len(data) or not isinstance(header, dict):
            return None
        blob = memoryview(data)[at + 8:]
        buffers = header.get("buffers", [])
        if ("extensions" in header
                or header.get("extensionsUsed") or header.get("extensionsRequired")
                or len(buffers) != 1 or "uri" in buffers[0]):
            return None
        scene = header.get("scene", 0)
        roots = header["scenes"][scene].get("nodes", [])
        if len(set(roots)) != len(roots):
            return None
        nodes, meshes = header.get("nodes", []), header.get("meshes", [])
        accessors, views = header.get("accessors", []), header.get("bufferViews", [])

        def array(index: int, kinds: dict[int, str], shape: str, width: int) -> np.ndarray:
            a = accessors[index]
            view = views[a["bufferView"]]
            if (a.keys() - _GLB_ACCESSOR_KEYS or a["componentType"] not in kinds
                    or a["type"] != shape or "byteStride" in view or view["buffer"] != 0):
                raise ValueError("not plain")
            dtype = np.dtype(kinds[a["componentType"]])
            start, length = view.get("byteOffset", 0), view["byteLength"]
            offset, size = a.get("byteOffset", 0), a["count"] * width * dtype.itemsize
            if start + length > n_bin or offset + size > length:
                raise ValueError("out of the buffer")
            return np.frombuffer(blob[start + offset:start + offset + size], dtype=dtype)

        groups: dict[Any, list[tuple[str, np.ndarray, np.ndarray, np.ndarray, Any]]] = {}
        labels: dict[Any, str] = {}
        for i in roots:
            node = nodes[i]
            if node.keys() - _GLB_NODE_KEYS or "mesh" not in node:
                return None
            mesh = meshes[node["mesh"]]
            (prim,) = mesh["primitives"]
            if (mesh.keys() - _GLB_MESH_KEYS or prim.keys() - _GLB_PRIMITIVE_KEYS
                    or prim.get("mode", 4) != 4 or prim["attributes"].keys() != {"POSITION"}):
                return None
            vertices = array(prim["attributes"]["POSITION"], {5126: "<f4"}, "VEC3", 3)
            faces = array(prim["indices"], _GLB_INDICES, "SCALAR", 1)
            if len(faces) == 0 or len(faces) % 3 or int(faces.max()) >= len(vertices) // 3:
                return None
            matrix = (np.array(node["matrix"], dtype=np.float64).reshape((4, 4)).T
                      if "matrix" in node else np.eye(4))
            meta: dict[str, Any] = {"units": "meters"}
            if isinstance(mesh.get("extras"), dict):
                meta.update(mesh["extras"])
            own = node.get("name") or mesh.get("name") or f"node{i}"
            groups[(i, own)] = [(str(mesh.get("name", "GLTF")),
                                 vertices.reshape(-1, 3).astype(np.float64),
                                 faces.reshape(-1, 3).astype(np.int64), matrix, meta)]
            labels[(i, own)] = own
        extras = (header["scenes"][header["scene"]].get("extras") if "scene" in header
                  else None)
        units = extras.get("units") if isinstance(extras, dict) else None
        return groups, labels, (set() if units is None else {str(units)})
    except (ValueError, KeyError, IndexError, TypeError, AttributeError, struct.error,
            UnicodeDecodeError):
        return None


def _gltf_header(path: Path) -> dict[str, Any]:
    """The JSON header of a .gltf or .glb file."""
    data = path.read_bytes()
    if path.suffix.lower() == ".glb":
        if len(data) < 20 or data[:4] != b"glTF":
            raise ValueError("not a GLB file")
        length, kind = struct.unpack("<I4s", data[12:20])
        if kind != b"JSON":
            raise ValueError("GLB without a JSON chunk")
        data = data[20:20 + length]
    header = json.loads(data.decode("utf-8"))
    if not isinstance(header, dict):
        raise ValueError("glTF header is not a JSON object")
    return header


def _gltf_node_names(path: Path) -> dict[str, tuple[int, str]]:
    """trimesh frame name -> (node index, node's own name) for the file's nodes.

    trimesh renames clashing node names its own way; this repeats its naming to get back to the
    nodes so that parts carry the names the file gives (numbered by :func:`_part_names`).
    """
    from trimesh.scene.transforms import DEFAULT_BASE_FRAME
    from trimesh.util import unique_name

    header = _gltf_header(path)
    nodes = header.get("nodes", [])
    meshes = header.get("meshes", [])
    name_index: dict[str, int] = {}
    counts: dict[Any, int] = {}
    for i, n in enumerate(nodes):
        name_index[unique_name(n.get("name", str(i)), name_index, counts=counts)] = i
    names = {v: k for k, v in name_index.items()}
    world = name_index.get(DEFAULT_BASE_FRAME)
    if world is not None:
        names[world] = unique_name(DEFAULT_BASE_FRAME, set(names.values()))
    out: dict[str, tuple[int, str]] = {}
    for i, frame in names.items():
        node = nodes[i]
        own = node.get("name")
        if not own:
            mesh = node.get("mesh")
            own = (meshes[mesh].get("name") if isinstance(mesh, int) and 0 <= mesh < len(meshes)
                   else None) or f"node{i}"
        out[frame] = (i, own)
    return out


def _gltf_units(names: Sequence[str], where: str) -> tuple[str, str | None]:
    """Units of a glTF file from its extras' labels (see :func:`_scene_meshes`), else ``m``."""
    if not names:
        return "m", None
    if len(names) > 1:
        raise ModelError(f"{where}: meshes disagree on units ({_listing(names)}); "
                         "set model.units")
    units = _UNIT_ALIASES.get(names[0].strip().lower())
    if units is None:
        return "m", f"unknown units {names[0]!r} in the file's extras: using m"
    return units, None


def _concat_pieces(name: str, pieces: Sequence[_Piece], sources: tuple[str, ...]) -> _Piece:
    vertices, faces = _concat([(p.vertices, p.faces) for p in pieces])
    return _Piece(name, vertices, faces, sources)


def _concat(meshes: Iterable[tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
    vs, fs, offset = [], [], 0
    for v, f in meshes:
        vs.append(np.asarray(v, dtype=np.float64).reshape(-1, 3))
        fs.append(np.asarray(f, dtype=np.int64).reshape(-1, 3) + offset)
        offset += len(vs[-1])
    if not vs:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    return np.concatenate(vs), np.concatenate(fs)


# ------------------------------------------------------------------------------ names

_UNSAFE = re.compile(r"[^\w.-]+")


def safe_name(raw: str) -> str:
    """A part name of letters and digits of any script, ``_``, ``.`` and ``-``, starting with a
    letter or digit (a Cyrillic or Chinese name stays as it is)."""
    name = _UNSAFE.sub("_", raw).lstrip("_.-")
    return name or "part"


def _part_names(raw: Sequence[str]) -> tuple[list[str], str | None]:
    """Safe, unique part names for ``raw`` (in reading order) and a note if any changed.

    The first holder of a name keeps it; later ones get ``.1``, ``.2`` ... skipping names that
    are taken or that another part has of its own.
    """
    safe = [safe_name(r) for r in raw]
    reserved = set(safe)
    used: set[str] = set()
    out: list[str] = []
    for name in safe:
        if name in used:
            k = 1
            while f"{name}.{k}" in used or f"{name}.{k}" in reserved:
                k += 1
            name = f"{name}.{k}"
        used.add(name)
        out.append(name)
    changed = [(r, n) for r, n in zip(raw, out) if r != n]
    if not changed:
        return out, None
    shown = ", ".join(f"{r!r} -> {n}" for r, n in changed[:3])
    more = f" (and {len(changed) - 3} more)" if len(changed) > 3 else ""
    return out, f"renamed {len(changed)} part{_s(changed)} to safe unique names: {shown}{more}"


# ------------------------------------------------------------------------------ cleaning


def _clean(name: str, vertices: np.ndarray, faces: np.ndarray,
           sources: tuple[str, ...]) -> Part:
    """A part with only the vertices its faces use (order kept), as read-only arrays."""
    faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    vertices = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    used, inverse = np.unique(faces, return_inverse=True)
    return Part(name=name, vertices=readonly(vertices[used], np.float64),
                faces=readonly(inverse.reshape(-1, 3), np.int64), sources=sources)


def _finite(parts: Sequence[Part], where: str) -> list[Part]:
    out = []
    for p in parts:
        part = _clean(p.name, p.vertices, p.faces, p.sources)
        if not np.isfinite(part.vertices).all():
            raise ModelError(f"{where}: part {p.name!r} has NaN or infinite coordinates")
        out.append(part)
    return out


def _merge(name: str, members: Sequence[Part]) -> Part:
    vertices, faces = _concat([(m.vertices, m.faces) for m in members])
    sources = tuple(s for m in members for s in m.sources)
    return _clean(name, vertices, faces, sources)


# ------------------------------------------------------------------------------ regrouping


def _matches(parts: Sequence[Part], pattern: str) -> list[Part]:
    return [p for p in parts if fnmatch.fnmatchcase(p.name, pattern)]


def _no_match(cfg: str, key: str, pattern: str, parts: Sequence[Part]) -> ConfigError:
    return ConfigError(f"{cfg}: model.parts.{key}: {pattern!r} matches no part "
                       f"(parts: {_listing(sorted(p.name for p in parts))})")


def _regroup(parts: list[Part], spec: PartsSpec, cfg: str, notes: list[str]) -> list[Part]:
    """Apply ``drop``, then ``merge`` groups in order, then ``rename``."""
    for i, pattern in enumerate(spec.drop):
        hit = _matches(parts, pattern)
        if not hit:
            raise _no_match(cfg, f"drop[{i}]", pattern, parts)
        gone = {p.name for p in hit}
        parts = [p for p in parts if p.name not in gone]
        notes.append(f"dropped {len(gone)} part{_s(gone)} matching {pattern!r}: "
                     f"{_listing(sorted(gone))}")
    if not parts:
        raise ConfigError(f"{cfg}: model.parts.drop: drops every part")
    for new, patterns in spec.merge:
        members: dict[str, Part] = {}
        for pattern in patterns:
            hit = _matches(parts, pattern)
            if not hit:
                raise _no_match(cfg, f"merge.{new}", pattern, parts)
            members.update((p.name, p) for p in hit)
        rest = [p for p in parts if p.name not in members]
        if any(p.name == new for p in rest):
            raise ConfigError(f"{cfg}: model.parts.merge.{new}: {new!r} is already the name of "
                              "a part not in the group")
        group = [members[n] for n in sorted(members)]
        parts = rest + [_merge(new, group)]
        notes.append(f"merged {len(group)} part{_s(group)} into {new}: "
                     f"{_listing([p.name for p in group])}")
    if spec.rename:
        mapping: dict[str, str] = {}
        for old, new in spec.rename:
            hit = _matches(parts, old)
            if not hit:
                raise _no_match(cfg, f"rename.{old}", old, parts)
            if len(hit) > 1:
                raise ConfigError(f"{cfg}: model.parts.rename.{old}: matches {len(hit)} parts "
                                  f"({_listing(sorted(p.name for p in hit))}); a rename needs "
                                  "exactly one")
            if hit[0].name in mapping:
                raise ConfigError(f"{cfg}: model.parts.rename.{old}: part {hit[0].name!r} "
                                  "is renamed twice")
            mapping[hit[0].name] = new
        final = [mapping.get(p.name, p.name) for p in parts]
        for old, new in spec.rename:
            if final.count(new) > 1:
                raise ConfigError(f"{cfg}: model.parts.rename.{old}: {new!r} would name two "
                                  "parts")
        parts = [Part(mapping[p.name], p.vertices, p.faces, p.sources) if p.name in mapping
                 else p for p in parts]
        for old in sorted(mapping):
            notes.append(f"renamed {old} to {mapping[old]}")
    return parts


#: Pieces of one part are "of one shape" when their box extents and areas agree within this
#: fraction (and their triangle counts are equal).
PIECE_TOL = 0.02


def _pieces(part: Part) -> list[np.ndarray]:
    """The face index arrays of a part's connected pieces (faces sharing a vertex position)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    v = np.asarray(part.vertices, dtype=float)
    f = np.asarray(part.faces, dtype=np.int64)
    _, weld = np.unique(v, axis=0, return_inverse=True)
    w = weld.reshape(-1)[f]
    n = int(w.max()) + 1
    rows = np.concatenate([w[:, 0], w[:, 1]])
    cols = np.concatenate([w[:, 1], w[:, 2]])
    graph = coo_matrix((np.ones(len(rows), dtype=np.int8), (rows, cols)), shape=(n, n))
    _, labels = connected_components(graph, directed=False)
    face_label = labels[w[:, 0]]
    return [np.flatnonzero(face_label == k) for k in np.unique(face_label)]


def _split_pieces(parts: list[Part], notes: list[str]) -> list[Part]:
    """Split each part made of several disconnected pieces of one shape (module docstring)."""
    out: list[Part] = []
    names = {p.name for p in parts}
    for part in parts:
        pieces = _pieces(part) if len(part.faces) >= 2 else []
        if len(pieces) < 2 or len({len(x) for x in pieces}) != 1:
            out.append(part)
            continue
        subs = []
        for faces in pieces:
            used = np.unique(part.faces[faces])
            remap = np.full(len(part.vertices), -1, dtype=np.int64)
            remap[used] = np.arange(len(used))
            subs.append(Part("", readonly(part.vertices[used], np.float64),
                             readonly(remap[part.faces[faces]], np.int64), part.sources))
        ext = np.array([np.subtract(*s.box[::-1]) for s in subs])
        area = np.array([_area(s) for s in subs])
        scale = max(float(ext.max()), 1e-300)
        if (float(np.ptp(ext, axis=0).max()) > PIECE_TOL * scale or area.min() <= 0
                or float(np.ptp(area)) > PIECE_TOL * float(area.max())):
            out.append(part)
            continue
        subs.sort(key=lambda s: tuple(np.add(*s.box) / 2))
        new = []
        for k, s in enumerate(subs, start=1):
            name = f"{part.name}_{k}"
            while name in names:  # never take another part's name
                name += "_"
            names.add(name)
            new.append(Part(name, s.vertices, s.faces, s.sources))
        out += new
        notes.append(f"split {part.name} into {len(new)} pieces of one shape: "
                     f"{_listing([p.name for p in new])} (model.parts.split: false keeps it "
                     "whole)")
    return out


def _area(part: Part) -> float:
    v = part.vertices[part.faces]
    return float(np.linalg.norm(np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), axis=1).sum() / 2)


def _diagonal(lo: np.ndarray, hi: np.ndarray) -> float:
    return float(np.linalg.norm(hi - lo))


def _box_gap(a: Part, b: Part) -> float:
    """Distance between the axis-aligned boxes of two parts (0 when they touch or overlap)."""
    alo, ahi = np.array(a.box[0]), np.array(a.box[1])
    blo, bhi = np.array(b.box[0]), np.array(b.box[1])
    gap = np.maximum(0.0, np.maximum(blo - ahi, alo - bhi))
    return float(np.linalg.norm(gap))


def _small_parts(parts: list[Part], spec: PartsSpec, where: str,
                 notes: list[str]) -> list[Part]:
    """Drop parts without area; merge, drop or keep tiny parts (``spec.small``)."""
    kept = []
    for p in sorted(parts, key=lambda p: p.name):
        lo, hi = np.array(p.box[0]), np.array(p.box[1])
        if len(p.faces) == 0 or _area(p) <= _AREA_EPS * max(_diagonal(lo, hi), 1e-300) ** 2:
            notes.append(f"dropped degenerate part {p.name!r} (no area)")
            continue
        kept.append(p)
    if not kept:
        raise ModelError(f"{where}: no part has any area")
    los = np.array([p.box[0] for p in kept])
    his = np.array([p.box[1] for p in kept])
    model_diag = _diagonal(los.min(axis=0), his.max(axis=0))
    limit = spec.min_size * model_diag
    tiny = [p for p in kept if _diagonal(np.array(p.box[0]), np.array(p.box[1])) < limit]
    if not tiny:
        return kept
    names = [p.name for p in tiny]
    rule = f"box diagonal below {spec.min_size:g} of the model's"
    if spec.small == "keep":
        notes.append(f"kept {len(tiny)} tiny part{_s(tiny)} ({rule}): {_listing(names)}")
        return kept
    big = [p for p in kept if p.name not in set(names)]
    if not big:
        raise ModelError(f"{where}: every part is tiny ({rule}); lower model.parts.min_size "
                         "or set model.parts.small: keep")
    if spec.small == "drop":
        notes.append(f"dropped {len(tiny)} tiny part{_s(tiny)} ({rule}): {_listing(names)}")
        return big
    into: dict[str, list[Part]] = {}
    for t in tiny:
        target = min(big, key=lambda b: (_box_gap(t, b), b.name))
        into.setdefault(target.name, []).append(t)
    out = []
    for b in big:
        if b.name in into:
            group = into[b.name]
            out.append(_merge(b.name, [b] + group))
            notes.append(f"merged {len(group)} tiny part{_s(group)} into {b.name}: "
                         f"{_listing([p.name for p in group])}")
        else:
            out.append(b)
    return out


# ------------------------------------------------------------------------------ text helpers


def _s(items: Any) -> str:
    return "" if len(items) == 1 else "s"


def _listing(names: Sequence[str]) -> str:
    names = list(names)
    if len(names) <= _MAX_LISTED:
        return ", ".join(names)
    return ", ".join(names[:_MAX_LISTED]) + f" ... ({len(names) - _MAX_LISTED} more)"


def _short(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    first = text[0] if text else ""
    return f"{type(exc).__name__}: {first}" if first else type(exc).__name__
