"""Frozen value types that flow between the pipeline stages.

Conventions (used by every stage):

* The internal frame is right-handed and Z-up; the model's *front* faces -Y.
* Axes are integers 0, 1, 2 for x, y, z.
* A ``Box`` is ``(lo, hi)``, two 3-tuples of floats in model units with ``lo <= hi``.
* Bulk arrays are read-only numpy copies; small vectors are tuples.
* Objects refer to each other by string id (part names, candidate ids).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping

import numpy as np

Vec3 = tuple[float, float, float]
Box = tuple[Vec3, Vec3]

PRIMITIVE_TYPES = ("plane", "cuboid", "cylinder", "frustum", "custom")
#: Order used by the fit tie rule: simpler first.
SIMPLICITY = {"plane": 0, "cuboid": 1, "cylinder": 2, "frustum": 3, "custom": 4}
RELATION_TYPES = ("coplanar", "coaxial", "bisector")
#: Preference when one relation per pair is kept for preservation (paper §4.1).
RELATION_PREFERENCE = {"bisector": 0, "coaxial": 1, "coplanar": 2}


def readonly(array: Any, dtype: Any) -> np.ndarray:
    """Return a C-contiguous read-only copy of ``array`` as ``dtype``."""
    out = np.array(array, dtype=dtype, copy=True, order="C")
    out.setflags(write=False)
    return out


def as_box(lo: Any, hi: Any) -> Box:
    """Build a ``Box`` of plain floats from two 3-vectors."""
    return (
        (float(lo[0]), float(lo[1]), float(lo[2])),
        (float(hi[0]), float(hi[1]), float(hi[2])),
    )


def box_size(box: Box) -> Vec3:
    """Extent of ``box`` along x, y, z, model units."""
    lo, hi = box
    return (hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2])


def box_centre(box: Box) -> Vec3:
    """Centre of ``box``, model units."""
    lo, hi = box
    return ((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2)


def box_diagonal(box: Box) -> float:
    """Length of the box's space diagonal, model units."""
    return float(np.linalg.norm(box_size(box)))


@dataclass(frozen=True, slots=True, eq=False)
class Part:
    """One named part of a model: a triangle mesh in the internal Z-up frame.

    Attributes:
        name: unique part name (a glTF node name, an OBJ group, a file stem ...).
        vertices: (n, 3) float64, model units, read-only.
        faces: (m, 3) int64 indices into ``vertices``, read-only.
        sources: where the geometry came from (node names, file names), for messages.
    """

    name: str
    vertices: np.ndarray
    faces: np.ndarray
    sources: tuple[str, ...] = ()

    @property
    def box(self) -> Box:
        """Axis-aligned bounding box of the vertices that faces use."""
        used = self.vertices[np.unique(self.faces)] if len(self.faces) else self.vertices
        return as_box(used.min(axis=0), used.max(axis=0))

    def to_trimesh(self):  # -> trimesh.Trimesh (imported lazily: trimesh belongs to geometry stages)
        """A (mutable) trimesh copy of this part's mesh."""
        import trimesh

        return trimesh.Trimesh(
            vertices=np.array(self.vertices), faces=np.array(self.faces), process=False
        )


@dataclass(frozen=True, slots=True, eq=False)
class Model:
    """A part-segmented model in the internal frame (Z up).

    Attributes:
        source: the path it was loaded from, as given.
        units: ``mm``, ``cm``, ``m`` or ``in``: the unit of all coordinates.
        parts: parts in a stable order (sorted by name).
        notes: human-readable lines on what loading did (merged/dropped parts ...).
    """

    source: str
    units: str
    parts: tuple[Part, ...]
    notes: tuple[str, ...] = ()

    @property
    def bounds(self) -> Box:
        """Axis-aligned box over all parts, model units."""
        los = np.array([p.box[0] for p in self.parts])
        his = np.array([p.box[1] for p in self.parts])
        return as_box(los.min(axis=0), his.max(axis=0))

    def part(self, name: str) -> Part:
        """The part called ``name`` (``KeyError`` if absent)."""
        for p in self.parts:
            if p.name == name:
                return p
        raise KeyError(name)


@dataclass(frozen=True, slots=True)
class Primitive:
    """The scaffolding primitive fitted to one part (paper §4.1).

    Attributes:
        part: the part's name.
        type: one of ``PRIMITIVE_TYPES``.
        axis: the primitive's axis (0, 1, 2): a plane's normal, a cylinder's or frustum's axis;
            ``None`` for cuboids and custom parts.
        box: the primitive's axis-aligned box, model units (cylinders and frusta included:
            anchoring works on boxes).
        residual: RMS distance of surface samples to the surface of the reported primitive
            (whose box encloses the part) divided by the part's bounding-box diagonal
            (unit-free).  The type itself is chosen by the least-squares fit's score.
        detail: type-specific parameters, plain JSON values, for example a frustum's
            ``{"lo_half": [a, b], "hi_half": [c, d]}`` half-sizes of its end rectangles across the axis.
    """

    part: str
    type: str
    axis: int | None
    box: Box
    residual: float
    detail: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True, slots=True)
class Relation:
    """A geometric relation between two primitives, found within ``tolerance`` (paper §4.1).

    Attributes:
        a, b: part names, ``a < b``.
        type: ``coplanar`` (a face of a and a face of b lie in one plane normal to ``axis``,
            within half the larger box diagonal of each other in that plane), ``coaxial`` (one
            rotational about ``axis``, the other too or a cuboid; their axis lines, box centre
            lines for a cuboid, within ``tolerance`` Euclidean distance) or
            ``bisector`` (their mid-planes normal to ``axis`` coincide).
        axis: 0, 1 or 2.
        tolerance: the distance, model units, within which it was accepted.
        detail: plain JSON values; coplanar: ``{"a_end": "lo"|"hi", "b_end": ..., "coord": float}``;
            coaxial: ``{"line": [u, v]}`` (the axis line's two other coordinates);
            bisector: ``{"coord": float}``. ``detail["preserved"]`` is True on the one relation
            per pair that selection must keep (bisector > coaxial > coplanar).
    """

    a: str
    b: str
    type: str
    axis: int
    tolerance: float
    detail: Mapping[str, Any] = field(default_factory=dict)


@dataclass(frozen=True, slots=True, eq=False)
class Camera:
    """A pinhole camera already fitted to a sheet of paper (the *project* stage's value).

    Attributes:
        position: camera centre, model units.
        projection_mm: (3, 4) float64, read-only: homogeneous model coordinates ``(x, y, z, 1)``
            to homogeneous sheet coordinates in mm, origin at the sheet's bottom-left corner,
            x to the right, y up.  Its third row is scaled so that the third homogeneous
            coordinate ``w`` is the depth in front of the camera along the optical axis, in model
            units (positive in front).
        paper_mm: (width, height) of the sheet in mm.
        perspective: ``two-point`` or ``three-point``.
    """

    position: Vec3
    projection_mm: np.ndarray
    paper_mm: tuple[float, float]
    perspective: str = "two-point"

    def project(self, points: Any) -> np.ndarray:
        """Project (n, 3) model points to (n, 2) sheet mm (points must be in front)."""
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        h = pts @ self.projection_mm[:, :3].T + self.projection_mm[:, 3]
        return h[:, :2] / h[:, 2:3]

    def depth(self, points: Any) -> np.ndarray:
        """(n,) depth of model points along the optical axis, model units."""
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        return pts @ self.projection_mm[2, :3] + self.projection_mm[2, 3]


# ----------------------------------------------------------------- per-view values (stages 6-8)


@dataclass(frozen=True, slots=True)
class VanishingPoint:
    """Where the lines of one model axis meet on the sheet.

    Attributes:
        axis: 0, 1 or 2.
        at_infinity: True when the axis is parallel to the sheet (its lines stay parallel).
        xy_mm: the point on the sheet (may lie far outside it), ``None`` at infinity.
        direction_mm: unit 2D direction of the axis's lines on the sheet (always set; for a
            finite VP it points from the sheet's centre toward the VP).
    """

    axis: int
    at_infinity: bool
    xy_mm: tuple[float, float] | None
    direction_mm: tuple[float, float]


@dataclass(frozen=True, slots=True)
class Guide:
    """One straight guide line, defined in 3D and projected (DESIGN.md §3 ``guides``).

    Attributes:
        id: stable id; equivalent guides share one id (merged).
        status: ``new`` (drawn orange) in the step that introduces it, ``reused`` (blue) when a
            later step uses it again.
        from3d, to3d: end points, model units.
        from_mm, to_mm: their projections on the sheet, mm.
        role: ``construction`` (intermediate line, novice only), ``guide`` (the resulting guide
            line, novice and apprentice) or ``vanishing`` (a line toward a vanishing point,
            also carrying a result line over to the child's face; novice and apprentice) or
            ``sheet`` (printed on the calibrated sheet: the first box's footprint and nearest
            upright edge, on the first scaffold step at novice and apprentice).
    """

    id: str
    status: str
    from3d: Vec3
    to3d: Vec3
    from_mm: tuple[float, float]
    to_mm: tuple[float, float]
    role: str = "guide"


@dataclass(frozen=True, slots=True)
class Stroke:
    """A line of the drawing itself (not a guide): scaffold edge, ellipse or contour.

    Attributes:
        kind: ``scaffold`` (primitive edge with a face toward the camera),
            ``scaffold_hidden`` (a back edge, drawn dotted), ``ellipse`` (a run of an
            ellipse the drawn primitives leave seen), ``ellipse_hidden`` (a run they hide,
            drawn dotted: :mod:`h2s_print.occlude`) or ``contour``.
        part: the part it belongs to.
        points3d: polyline vertices, model units.
        points_mm: their projections on the sheet, mm.
    """

    kind: str
    part: str
    points3d: tuple[Vec3, ...]
    points_mm: tuple[tuple[float, float], ...]


@dataclass(frozen=True, slots=True)
class Label:
    """A lettered point on a step's picture, named by the step's sub-steps (issue 11).

    Attributes:
        name: the letter(s), e.g. ``A`` or ``B'``.
        at3d: the point, model units.
        at_mm: its projection on the sheet, mm.
        kind: ``point`` (a lettered construction point) or ``part`` (the short name of a part
            whose own name is not readable words, at the centre of its box).
    """

    name: str
    at3d: Vec3
    at_mm: tuple[float, float]
    kind: str = "point"


@dataclass(frozen=True, slots=True)
class Step:
    """One instruction of a tutorial (DESIGN.md §3 ``steps``).

    Attributes:
        index: 1-based position in the tutorial.
        part: the part drawn, or ``None`` for steps not about one part (e.g. the horizon).
        kind: ``primitive``, ``ellipse``, ``contour`` (and ``basic`` in the control tutorial).
        text: the instruction sentence (from ``templates/``).
        eyeball: True when the part is placed by eye, without intermediate guides.
        guides: guides shown in this step: new ones and earlier ones reused here.
        strokes: the new drawing lines of this step.
        alive: ids of every guide still shown at this step (earlier guides not yet retired),
            including this step's.
        headline: the step's headline ("Lens: a box placed with guides on the body.").
        substeps: the numbered sub-steps (novice, apprentice and basic), one construction
            each, naming points by the letters of ``labels``; empty at master.
        summary: the ratio words a master reads after the headline (empty at other levels).
        labels: the lettered points ``substeps`` name, drawn on the step's picture.

    ``text`` is the headline followed by the numbered sub-steps (or the summary).
    """

    index: int
    part: str | None
    kind: str
    text: str
    eyeball: bool
    guides: tuple[Guide, ...]
    strokes: tuple[Stroke, ...]
    alive: tuple[str, ...] = ()
    headline: str = ""
    substeps: tuple[str, ...] = ()
    summary: str = ""
    labels: tuple[Label, ...] = ()


@dataclass(frozen=True, slots=True, eq=False)
class ViewPlan:
    """Everything about one (view, level): the camera and the ordered steps."""

    name: str
    level: str
    paper_mm: tuple[float, float]
    camera: Camera
    vanishing_points: tuple[VanishingPoint, ...]
    steps: tuple[Step, ...]
    part_names: tuple[tuple[str, str], ...] = ()  # (label, full name) of renamed parts
    floor_z: float | None = None  # the floor: lowest z of the drawn boxes, model units
