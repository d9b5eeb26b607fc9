"""Write tiny model files for loader tests, byte for byte under the test's control.

GLB files are assembled by hand (JSON chunk + binary chunk) so tests can set node names
(including clashing ones), transforms, hierarchy, instancing and extras exactly.
"""

from __future__ import annotations

import json
import struct
from pathlib import Path
from typing import Any, Sequence

import numpy as np

#: A unit cube [0, 1]^3, 8 vertices, 12 outward-facing triangles.
CUBE_V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                   [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], dtype=float)
CUBE_F = np.array([[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
                   [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]])


def box(lo: Sequence[float], hi: Sequence[float]) -> tuple[np.ndarray, np.ndarray]:
    """Vertices and faces of the axis-aligned box [lo, hi]."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    return lo + CUBE_V * (hi - lo), CUBE_F.copy()


def write_glb(path: Path, meshes: Sequence[tuple[str | None, np.ndarray, np.ndarray]],
              nodes: Sequence[dict[str, Any]], roots: Sequence[int] | None = None,
              scene_extras: dict | None = None,
              mesh_extras: Sequence[dict | None] | None = None) -> Path:
    """Write a GLB.

    Args:
        meshes: (name or None, vertices (n, 3), faces (m, 3)) per glTF mesh; lists of
            vertices and faces make a mesh of several primitives.
        nodes: glTF node dicts as they go into the file (``name``, ``mesh``, ``matrix``,
            ``translation``, ``children`` ...).
        roots: scene root node indices (default: every node that is nobody's child).
    """
    blob = bytearray()
    accessors, views, gl_meshes = [], [], []
    for i, (name, vs, fs) in enumerate(meshes):
        if not isinstance(vs, (list, tuple)):
            vs, fs = [vs], [fs]
        primitives = []
        for v, f in zip(vs, fs):
            v = np.asarray(v, dtype="<f4")
            f = np.asarray(f, dtype="<u4").reshape(-1)
            for arr, target in ((f, 34963), (v, 34962)):
                while len(blob) % 4:
                    blob.append(0)
                views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": arr.nbytes,
                              "target": target})
                blob.extend(arr.tobytes())
            accessors.append({"bufferView": len(views) - 2, "componentType": 5125,
                              "count": int(f.size), "type": "SCALAR"})
            accessors.append({"bufferView": len(views) - 1, "componentType": 5126,
                              "count": int(len(v)), "type": "VEC3",
                              "min": v.min(axis=0).tolist(), "max": v.max(axis=0).tolist()})
            primitives.append({"attributes": {"POSITION": len(accessors) - 1},
                               "indices": len(accessors) - 2, "mode": 4})
        mesh: dict[str, Any] = {"primitives": primitives}
        if name is not None:
            mesh["name"] = name
        if mesh_extras and mesh_extras[i]:
            mesh["extras"] = mesh_extras[i]
        gl_meshes.append(mesh)
    while len(blob) % 4:
        blob.append(0)
    if roots is None:
        children = {c for n in nodes for c in n.get("children", ())}
        roots = [i for i in range(len(nodes)) if i not in children]
    scene: dict[str, Any] = {"nodes": list(roots)}
    if scene_extras:
        scene["extras"] = scene_extras
    header = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [scene], "nodes": list(nodes),
              "meshes": gl_meshes, "accessors": accessors, "bufferViews": views,
              "buffers": [{"byteLength": len(blob)}]}
    text = json.dumps(header, sort_keys=True).encode()
    text += b" " * (-len(text) % 4)
    body = struct.pack("<I4s", len(text), b"JSON") + text
    body += struct.pack("<I4s", len(blob), b"BIN\x00") + bytes(blob)
    path.write_bytes(struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body)
    return path


def obj_text(groups: Sequence[tuple[str | None, np.ndarray, np.ndarray]]) -> str:
    """OBJ text; each group is (``"o name"``/``"g name"``/None, vertices, faces)."""
    lines, offset = [], 0
    for tag, v, f in groups:
        if tag:
            lines.append(tag)
        lines += [f"v {x!r} {y!r} {z!r}" for x, y, z in np.asarray(v, float).tolist()]
        lines += [f"f {a + offset + 1} {b + offset + 1} {c + offset + 1}"
                  for a, b, c in np.asarray(f).tolist()]
        offset += len(v)
    return "\n".join(lines) + "\n"


def write_ply(path: Path, v: np.ndarray, f: np.ndarray) -> Path:
    """ASCII PLY."""
    head = ["ply", "format ascii 1.0", f"element vertex {len(v)}", "property float x",
            "property float y", "property float z", f"element face {len(f)}",
            "property list uchar int vertex_indices", "end_header"]
    body = [f"{x!r} {y!r} {z!r}" for x, y, z in np.asarray(v, float).tolist()]
    body += [f"3 {a} {b} {c}" for a, b, c in np.asarray(f).tolist()]
    path.write_text("\n".join(head + body) + "\n")
    return path


def write_stl(path: Path, v: np.ndarray, f: np.ndarray) -> Path:
    """Binary STL."""
    tri = np.asarray(v, dtype="<f4")[np.asarray(f)]
    out = bytearray(b"\0" * 80) + struct.pack("<I", len(tri))
    for t in tri:
        out += struct.pack("<3f", 0, 0, 0) + t.tobytes() + b"\0\0"
    path.write_bytes(bytes(out))
    return path
