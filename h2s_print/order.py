"""The teacher's coarse-to-fine rules shared by selection and sequencing (paper §3 principle (ii)).

A drawing teacher blocks in the object from its biggest, steadiest part and adds detail after:

* **size** of a part is the area of its box's largest face (:func:`part_size`): a flat panel and
  a block of the same outline count alike, as they do on paper;
* the **start part** (:func:`start_part`) is the largest part, or, when a part standing on the
  ground (its box bottom within :data:`GROUND_FRACTION` of the model's height from the model's
  lowest point) is at least :data:`GROUNDED_SHARE` as large, the largest such grounded part: the
  calibrated sheet's ground plane is then the object's real ground (a mixer starts from its
  base, not from its head floating in the air).  Custom parts (nothing fitted) never start.

The selection stage makes the start part a root (it hangs off nothing); the sequence stage draws
it first and then bigger before smaller wherever the anchoring allows.
"""

from __future__ import annotations

from typing import Sequence

from .types import Box, Primitive

#: A part is grounded when its box bottom is within this fraction of the model's height of the
#: model's lowest point.
GROUND_FRACTION = 0.03
#: A grounded part starts when its size is at least this share of the largest part's.
GROUNDED_SHARE = 0.5


def part_size(box: Box) -> float:
    """Area of the box's largest face (model units squared)."""
    e = [float(box[1][a]) - float(box[0][a]) for a in range(3)]
    return max(e[0] * e[1], e[1] * e[2], e[0] * e[2])


def grounded(box: Box, floor: float, height: float) -> bool:
    """True when ``box`` stands on the model's floor (within :data:`GROUND_FRACTION`)."""
    return float(box[0][2]) - floor <= GROUND_FRACTION * max(height, 0.0)


def start_part(primitives: Sequence[Primitive]) -> str | None:
    """The part a teacher blocks in first (module docstring), or None without a fitted part.

    Ties go to the part name (deterministic).
    """
    fitted = [p for p in primitives if p.type != "custom" and part_size(p.box) > 0.0]
    if not fitted:
        return None
    floor = min(float(p.box[0][2]) for p in primitives)
    top = max(float(p.box[1][2]) for p in primitives)
    largest = max(fitted, key=lambda p: (part_size(p.box), _neg(p.part)))
    on_ground = [p for p in fitted if grounded(p.box, floor, top - floor)]
    if on_ground:
        best = max(on_ground, key=lambda p: (part_size(p.box), _neg(p.part)))
        if part_size(best.box) >= GROUNDED_SHARE * part_size(largest.box):
            return best.part
    return largest.part


def _neg(name: str) -> tuple[int, ...]:
    """A key that sorts names in reverse, so ``max`` breaks ties toward the smaller name."""
    return tuple(-ord(c) for c in name) + (0,)
