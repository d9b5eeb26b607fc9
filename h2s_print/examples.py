"""The paper's four example objects, built as part-segmented GLB models.

How2Sketch (SIGGRAPH 2017) demonstrates its tutorials on a digital SLR camera, a kitchen stand
mixer, a toy train and a paint roller.  This module builds stand-ins for them from trimesh
primitives so that the example configs in ``configs/`` have models whose parts, proportions and
spatial relations look like the real objects:

* millimetres, uneven (measured-looking) sizes, never round numbers;
* curved parts tessellated (lens, wheels, boiler, roller, mixer head: cylinders; the mixer bowl
  and the roller handle: surfaces of revolution);
* real relations: faces flush (coplanar), rotational parts coaxial, parts centred on a common
  bisector plane, everything resting on the ground ``z = 0``;
* a few small details (shutter button, mixer knob) and one *tiny* part per object where it makes
  sense (a screw, a badge, a rivet) that the loader's small-part policy merges or the config drops.

Frames.  Every part is designed in the internal frame of :mod:`h2s_print.types` (right-handed,
Z up, the object's front facing -Y, resting on ``z = 0``, roughly centred on ``x = y = 0``).  glTF
is Y-up, so the GLB is written in glTF convention: internal ``(x, y, z)`` becomes file
``(x, z, -y)``; the loader's default glTF conversion ``(x, y, z) -> (x, -z, y)`` restores the
internal frame exactly (both are signed permutations).  Vertices are rounded to float32 (what a
GLB stores) when built, so a model built in memory equals the committed file to the bit.

Each part is one named node.  The toy train's eight wheels share one mesh ("wheel") and differ
only by their node transforms, which exercises a loader's instancing.

Regenerate the committed files with ``python -m h2s_print.examples [FOLDER]`` (default
``configs/models``).  The bytes are deterministic: the same trimesh version writes the same file.
"""

from __future__ import annotations

import logging
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
import trimesh

log = logging.getLogger(__name__)

#: Names of the example objects, in book order.
EXAMPLES = ("camera", "mixer", "train", "roller")

#: Internal Z-up frame -> glTF Y-up frame: (x, y, z) -> (x, z, -y).
Z_UP_TO_GLTF = np.array([[1.0, 0.0, 0.0],
                         [0.0, 0.0, 1.0],
                         [0.0, -1.0, 0.0]])

#: Segments around the big round parts (lens, wheels, roller ...): smooth enough to read as
#: round in a drawing, small enough to keep every GLB well under 300 KB.
ROUND = 48
#: Segments around small round parts (buttons, wire, chimney).
SMALL_ROUND = 24


@dataclass(frozen=True, slots=True)
class _Node:
    """One part of an example: a named node that places a (possibly shared) mesh.

    Attributes:
        name: node (part) name.
        mesh: the geometry's name; nodes naming the same mesh share one glTF mesh.
        transform: (4, 4) float, node placement in the internal Z-up frame, mm.
    """

    name: str
    mesh: str
    transform: np.ndarray


# --------------------------------------------------------------------------- shape helpers

# Signed permutation matrices taking a shape built along +Z to an axis; exact (0 and +-1 only),
# so no rounding noise enters the vertices.
_AXIS_FROM_Z = {
    0: np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]),  # z -> x
    1: np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]),  # z -> y
    2: np.eye(3),
}


def _place(mesh: trimesh.Trimesh, axis: int, centre: tuple[float, float, float]) -> trimesh.Trimesh:
    """Turn a mesh built along +Z onto ``axis`` and move its origin to ``centre`` (mm)."""
    vertices = mesh.vertices @ _AXIS_FROM_Z[axis].T + np.asarray(centre, dtype=float)
    return trimesh.Trimesh(vertices=vertices, faces=mesh.faces.copy(), process=False)


def _box(lo: tuple[float, float, float], hi: tuple[float, float, float]) -> trimesh.Trimesh:
    """Axis-aligned cuboid spanning ``lo`` to ``hi`` (mm)."""
    return trimesh.creation.box(bounds=np.array([lo, hi], dtype=float))


def _cylinder(axis: int, centre: tuple[float, float, float], radius: float, length: float,
              sections: int = ROUND) -> trimesh.Trimesh:
    """Closed cylinder along ``axis`` centred at ``centre``; radius and length in mm.

    ``sections`` is a multiple of 4, so the mesh reaches exactly ``radius`` along both
    cross-section axes and its box is a square across the axis.
    """
    return _place(trimesh.creation.cylinder(radius=radius, height=length, sections=sections),
                  axis, centre)


def _revolved(profile: list[tuple[float, float]], centre: tuple[float, float, float],
              sections: int = ROUND) -> trimesh.Trimesh:
    """Surface of revolution about a vertical axis through ``centre``.

    Args:
        profile: closed outline as ``(radius, height)`` pairs in mm, from the axis back to the
            axis (first and last radius 0), heights relative to ``centre``'s z.
        centre: a point of the axis, mm.
        sections: segments around the axis.
    """
    mesh = trimesh.creation.revolve(np.array(profile, dtype=float), sections=sections)
    if mesh.volume < 0:  # profile traced the other way round: flip the faces outwards
        mesh.invert()
    return _place(mesh, 2, centre)


def _frustum(bottom: tuple[float, float, float, float], top: tuple[float, float, float, float],
             z0: float, z1: float) -> trimesh.Trimesh:
    """Truncated pyramid between two axis-aligned rectangles ``(x0, y0, x1, y1)`` at z0 < z1."""
    bx0, by0, bx1, by1 = bottom
    tx0, ty0, tx1, ty1 = top
    vertices = np.array([[bx0, by0, z0], [bx1, by0, z0], [bx1, by1, z0], [bx0, by1, z0],
                         [tx0, ty0, z1], [tx1, ty0, z1], [tx1, ty1, z1], [tx0, ty1, z1]])
    faces = np.array([[0, 2, 1], [0, 3, 2],            # bottom, facing -z
                      [4, 5, 6], [4, 6, 7],            # top, facing +z
                      [0, 1, 5], [0, 5, 4],            # front (-y)
                      [1, 2, 6], [1, 6, 5],            # right (+x)
                      [2, 3, 7], [2, 7, 6],            # back (+y)
                      [3, 0, 4], [3, 4, 7]])           # left (-x)
    return trimesh.Trimesh(vertices=vertices, faces=faces, process=False)


def _prism_xz(outline: list[tuple[float, float]], y0: float, y1: float) -> trimesh.Trimesh:
    """Convex polygon in the XZ plane (``(x, z)`` pairs, counter-clockwise seen from -y)
    extruded from ``y0`` to ``y1`` (mm).  Fan-triangulated, so the outline must be convex."""
    n = len(outline)
    front = [(x, y0, z) for x, z in outline]
    back = [(x, y1, z) for x, z in outline]
    faces = []
    for i in range(1, n - 1):
        faces.append([0, i + 1, i])              # front cap, normal -y
        faces.append([n, n + i, n + i + 1])      # back cap, normal +y
    for i in range(n):
        j = (i + 1) % n
        faces.append([i, j, n + j])
        faces.append([i, n + j, n + i])
    mesh = trimesh.Trimesh(vertices=np.array(front + back, dtype=float),
                           faces=np.array(faces), process=False)
    if mesh.volume < 0:
        mesh.invert()
    return mesh


# --------------------------------------------------------------------------- the objects

def _camera() -> tuple[list[_Node], dict[str, trimesh.Trimesh]]:
    """Digital SLR camera, 131.7 mm wide; body 82.4 mm tall; lens 61.3 mm long."""
    W, D, H = 131.7, 51.9, 82.4                          # body: width (x), depth (y), height (z)
    grip_w, grip_d, grip_h = 28.9, 24.6, 74.8
    lens_r, lens_l, lens_z = 32.45, 61.3, 43.7
    # Centred on x = 0; in y the whole camera (lens front to body back) is centred on y = 0,
    # which puts the body's front face at y = (61.3 - 51.9) / 2 = 4.7.
    front = (lens_l - D) / 2
    x0, x1, y0, y1 = -W / 2, W / 2, front, front + D
    prism_h = 22.3
    flash_w, flash_d, flash_h = 34.7, 13.7, 8.4
    button_r, button_h = 4.9, 3.1
    screw_r, screw_l = 0.6, 0.45
    # The grip hangs in front of the body on the photographer's right hand (-x): its back face
    # lies on the body's front face, its outer side and its bottom are flush with the body's.
    grip = _box((x0, front - grip_d, 0.0), (x0 + grip_w, front, grip_h))
    # The prism housing sits on top, centred across the body (common bisector plane x = 0),
    # its sloped front rising from the body's front edge.
    prism_top = (-19.7, front + 6.85, 19.7, front + 35.25)
    meshes = {
        "body": _box((x0, y0, 0.0), (x1, y1, H)),
        "grip": grip,
        # Lens axis along the viewing axis (y), on the body's mid-plane x = 0, its back on the
        # body's front face; 4.5 mm clear of the grip.
        "lens": _cylinder(1, (0.0, front - lens_l / 2, lens_z), lens_r, lens_l),
        "prism": _frustum((-30.65, front, 30.65, front + 43.75), prism_top, H, H + prism_h),
        # Pop-up flash on the prism, centred on x = 0, front flush with the prism top's front.
        "flash": _box((-flash_w / 2, prism_top[1], H + prism_h),
                      (flash_w / 2, prism_top[1] + flash_d, H + prism_h + flash_h)),
        # Shutter button: a small cylinder centred on the grip's top face.
        "shutter_button": _cylinder(2, (x0 + grip_w / 2, front - grip_d / 2,
                                        grip_h + button_h / 2),
                                    button_r, button_h, SMALL_ROUND),
        # A tiny screw on the front face (1.76 mm box diagonal, under 1% of the camera's
        # 207 mm diagonal): the loader's small-part policy merges it into the body.
        "screw": _cylinder(1, (48.3, front - screw_l / 2, 9.7), screw_r, screw_l, 8),
    }
    return [_Node(name, name, np.eye(4)) for name in meshes], meshes


def _mixer() -> tuple[list[_Node], dict[str, trimesh.Trimesh]]:
    """Kitchen stand mixer, 359.8 mm tall, head pointing forward (-y) over the bowl."""
    base_w, base_y0, base_y1, base_h = 172.9, -148.6, 156.3, 36.7
    col_w, col_d, col_top = 95.3, 88.4, 241.3
    head_r, head_y0, head_sink = 61.4, -112.8, 4.3
    bowl_y = -41.9                                       # bowl and beater axis: x = 0, y = -41.9
    col_y0 = base_y1 - col_d                             # column front face, y = 67.9
    head_z = col_top + head_r - head_sink                # head axis height, z = 298.4
    head_bottom = head_z - head_r                        # 237.0
    # Bowl: a closed thin-walled profile (outer wall up, rim, inner wall down), revolved.
    bowl_profile = [(0.0, 0.0), (48.9, 0.0), (53.2, 4.7), (71.3, 38.6), (88.2, 86.1),
                    (99.7, 131.9), (104.6, 163.8), (101.9, 163.8), (97.0, 132.3),
                    (85.6, 87.0), (68.8, 41.2), (50.6, 7.9), (0.0, 3.4)]
    paddle = [(-17.2, 52.6), (17.2, 52.6), (33.6, 84.2), (38.9, 131.3), (-38.9, 131.3),
              (-33.6, 84.2)]
    meshes = {
        "base": _box((-base_w / 2, base_y0, 0.0), (base_w / 2, base_y1, base_h)),
        # Column at the back: back face flush with the base's, centred on x = 0.
        "column": _box((-col_w / 2, col_y0, base_h), (col_w / 2, base_y1, col_top)),
        # Motor head: a cylinder along y resting in the column top, back flush with the column.
        "head": _cylinder(1, (0.0, (head_y0 + base_y1) / 2, head_z), head_r,
                          base_y1 - head_y0),
        # Bowl: surface of revolution standing on the base, coaxial with the beater.
        "bowl": _revolved(bowl_profile, (0.0, bowl_y, base_h), sections=64),
        # Flat beater in two nodes (the config merges them): a shaft up into the head and a
        # flat paddle, both on the bowl's axis.
        "beater_shaft": _cylinder(2, (0.0, bowl_y, (125.0 + head_bottom + 3.0) / 2), 5.1,
                                  head_bottom + 3.0 - 125.0, SMALL_ROUND),
        "beater_paddle": _prism_xz(paddle, bowl_y - 4.15, bowl_y + 4.15),
        # Speed knob on the column's right (+x) side, centred on the column's depth.
        "knob": _cylinder(0, (col_w / 2 + 12.3 / 2, (col_y0 + base_y1) / 2, 203.7), 10.85, 12.3,
                          SMALL_ROUND),
        # Maker's badge on the head's front: 4.4 mm diagonal, under 1% of the 516 mm model
        # diagonal; the config drops it.
        "badge": _box((-1.85, head_y0 - 0.4, head_z + 31.2), (1.85, head_y0, head_z + 33.5)),
    }
    return [_Node(name, name, np.eye(4)) for name in meshes], meshes


def _train() -> tuple[list[_Node], dict[str, trimesh.Trimesh]]:
    """Wooden toy train: an engine with cab, boiler and chimney, and a wagon; 247 mm long."""
    wheel_r, wheel_w = 14.35, 7.9
    half_w = 26.3                                        # carriages 52.6 mm wide (y)
    car_z0, car_z1 = 9.6, 41.8                           # both carriages: common bottom and top
    engine_x, wagon_x = (-123.5, 4.9), (19.8, 123.5)
    cab_x0, cab_top = -36.4, 89.4
    boiler_r, boiler_x0 = 21.9, -117.4
    boiler_z = car_z1 + boiler_r                         # boiler rests on the engine, z = 63.7
    meshes = {
        "engine": _box((engine_x[0], -half_w, car_z0), (engine_x[1], half_w, car_z1)),
        "wagon": _box((wagon_x[0], -half_w, car_z0), (wagon_x[1], half_w, car_z1)),
        # Coupling bar between the carriages, touching both end faces.
        "coupling": _box((engine_x[1], -4.15, 18.7), (wagon_x[0], 4.15, 24.8)),
        # Cab on the engine's rear end: rear and sides flush with the engine's.
        "cab": _box((cab_x0, -half_w, car_z1), (engine_x[1], half_w, cab_top)),
        "roof": _box((cab_x0 - 2.7, -half_w - 2.9, cab_top),
                     (engine_x[1] + 2.7, half_w + 2.9, cab_top + 5.3)),
        # Boiler: a cylinder along x on the engine's mid-plane, from near the nose to the cab.
        "boiler": _cylinder(0, ((boiler_x0 + cab_x0) / 2, 0.0, boiler_z), boiler_r,
                            cab_x0 - boiler_x0),
        # Chimney stands in the boiler (4.1 mm sunk into its top), on its mid-plane y = 0.
        "chimney": _cylinder(2, (-99.6, 0.0, (boiler_z + boiler_r - 4.1 + 112.9) / 2), 8.45,
                             112.9 - (boiler_z + boiler_r - 4.1), SMALL_ROUND),
        # One wheel mesh, centred on its own origin, axle along y; eight nodes place it.
        "wheel": _cylinder(1, (0.0, 0.0, 0.0), wheel_r, wheel_w),
    }
    nodes = [_Node(name, name, np.eye(4)) for name in meshes if name != "wheel"]
    # Two axles per carriage, a wheel on each side (coaxial pairs), touching the carriage
    # sides and the ground (axle height = wheel radius).
    axles = (-101.9, -16.7, 39.2, 104.1)
    number = 0
    for x in axles:
        for y in (-(half_w + wheel_w / 2), half_w + wheel_w / 2):
            number += 1
            nodes.append(_Node(f"wheel_{number}", "wheel",
                               trimesh.transformations.translation_matrix((x, y, wheel_r))))
    return nodes, meshes


def _roller() -> tuple[list[_Node], dict[str, trimesh.Trimesh]]:
    """Paint roller standing on its handle: 231.7 mm roller, 227.1 mm tall."""
    wire_r = 3.1
    arm_z, axle_z = 166.2, 202.8                         # wire's horizontal runs
    riser_x, axle_end = -137.6, -96.4                    # wire riser; axle end inside the roller
    roller_r, roller_l = 24.3, 231.7
    handle_profile = [(0.0, 0.0), (11.2, 0.0), (13.9, 1.6), (15.3, 5.2), (16.1, 22.7),
                      (17.9, 58.4), (16.4, 96.3), (12.7, 112.1), (9.7, 121.9), (8.1, 126.8),
                      (0.0, 126.8)]

    def wire(a: tuple[float, float, float], b: tuple[float, float, float]) -> trimesh.Trimesh:
        # A straight wire run from a to b, lengthened by the wire radius at both ends so that
        # consecutive runs overlap into solid corners.
        axis = next(i for i in range(3) if a[i] != b[i])
        lo, hi = min(a[axis], b[axis]) - wire_r, max(a[axis], b[axis]) + wire_r
        centre = list(a)
        centre[axis] = (lo + hi) / 2
        return _cylinder(axis, tuple(centre), wire_r, hi - lo, 16)

    meshes = {
        # Handle: a bulged grip, revolved about the z axis, standing on the ground.
        "handle": _revolved(handle_profile, (0.0, 0.0, 0.0)),
        "ferrule": _cylinder(2, (0.0, 0.0, (124.3 + 139.7) / 2), 8.6, 139.7 - 124.3, SMALL_ROUND),
        # A rivet through the ferrule's front (2.6 mm diagonal, under 1% of the 346 mm model
        # diagonal): merged into the ferrule by the loader's small-part policy.
        "rivet": _cylinder(1, (0.0, -8.8, 132.0), 0.85, 1.0, 8),
        # Wire frame in four straight runs, each its own part (each fits a cylinder):
        # up out of the handle, sideways past the roller's end, up, and into the roller.
        "frame_shaft": wire((0.0, 0.0, 134.0), (0.0, 0.0, arm_z)),
        "frame_arm": wire((0.0, 0.0, arm_z), (riser_x, 0.0, arm_z)),
        "frame_riser": wire((riser_x, 0.0, arm_z), (riser_x, 0.0, axle_z)),
        "frame_axle": wire((riser_x, 0.0, axle_z), (axle_end, 0.0, axle_z)),
        # Roller: coaxial with the frame's axle run, centred over the handle (x = 0).
        "roller": _cylinder(0, (0.0, 0.0, axle_z), roller_r, roller_l),
    }
    return [_Node(name, name, np.eye(4)) for name in meshes], meshes


_BUILDERS: dict[str, Callable[[], tuple[list[_Node], dict[str, trimesh.Trimesh]]]] = {
    "camera": _camera, "mixer": _mixer, "train": _train, "roller": _roller,
}


# --------------------------------------------------------------------------- scene and files

def build_example(name: str) -> trimesh.Scene:
    """Build one example object as a glTF-convention (Y-up) trimesh scene.

    Args:
        name: one of :data:`EXAMPLES`.

    Returns:
        A scene with one named node per part; mesh vertices in mm, already rounded to float32
        and expressed in the glTF Y-up frame (internal ``(x, y, z)`` -> ``(x, z, -y)``), node
        transforms likewise.  Scene and mesh extras carry ``units: mm``.

    Raises:
        ValueError: for an unknown name.
    """
    if name not in _BUILDERS:
        raise ValueError(f"unknown example {name!r}; expected one of {', '.join(EXAMPLES)}")
    nodes, meshes = _BUILDERS[name]()
    rot = np.eye(4)
    rot[:3, :3] = Z_UP_TO_GLTF
    scene = trimesh.Scene()
    scene.metadata["units"] = "mm"
    added: set[str] = set()
    for node in nodes:
        # Node placement in the file frame: R T R^-1 (R is orthonormal, R^-1 = R^T).
        transform = rot @ node.transform @ rot.T
        # Rounded to float32 like the vertices, so that placed wheels touch z = 0 exactly.
        transform = transform.astype(np.float32).astype(np.float64)
        if node.mesh not in added:
            local = meshes[node.mesh]
            vertices = (local.vertices @ Z_UP_TO_GLTF.T).astype(np.float32).astype(np.float64)
            mesh = trimesh.Trimesh(vertices=vertices, faces=np.asarray(local.faces, dtype=np.int64),
                                   process=False)
            mesh.metadata.clear()
            mesh.metadata["units"] = "mm"
            scene.add_geometry(mesh, node_name=node.name, geom_name=node.mesh,
                               transform=transform)
            added.add(node.mesh)
        else:
            scene.graph.update(frame_to=node.name, frame_from=scene.graph.base_frame,
                               matrix=transform, geometry=node.mesh)
    return scene


def example_glb(name: str) -> bytes:
    """The GLB bytes of one example (deterministic for a given trimesh version)."""
    return build_example(name).export(file_type="glb")


def write_examples(folder: Path) -> list[Path]:
    """Write every example as ``folder/<name>.glb`` and return the paths, in :data:`EXAMPLES` order.

    Files whose bytes would not change are left untouched.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for name in EXAMPLES:
        path = folder / f"{name}.glb"
        data = example_glb(name)
        if not path.is_file() or path.read_bytes() != data:
            path.write_bytes(data)
            log.info("wrote %s (%d bytes)", path, len(data))
        paths.append(path)
    return paths


def main(argv: list[str] | None = None) -> int:
    """``python -m h2s_print.examples [FOLDER]``: regenerate the example GLBs."""
    args = sys.argv[1:] if argv is None else argv
    if len(args) > 1:
        sys.stderr.write("usage: python -m h2s_print.examples [FOLDER]\n")
        return 2
    folder = Path(args[0]) if args else Path("configs") / "models"
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    write_examples(folder)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
