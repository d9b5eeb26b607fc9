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
it first and then bigger before smaller wherever the anchoring allows (:func:`drawing_order`):

* a part is **ready** when its parents in the anchoring graph are drawn (parents first);
* a part's **reach** is the largest :func:`part_size` over itself and the parts not yet drawn
  that wait for it (its descendants in the anchoring graph, and free parts resting on it, below):
  a small parent of a big part is drawn early, to get to the big part;
* among the ready parts, the ones whose reach is within :data:`SIMILAR_FACTOR` of the largest
  reach are kept, of those the ones whose own size is within :data:`SIMILAR_FACTOR` of the
  largest own size, and of those the nearest to the camera is drawn (the paper's rule for ties,
  §5 (i); then the name).  So big comes before small and tiny details come last, and parts of
  similar size go front to back;
* a **free** part (hangs off nothing) **rests on** the parts its box touches; after the first
  step it waits until one of those it rests on is drawn (placed by eye next to what it sits on,
  as a chimney on its boiler), but only on parts at most :data:`COARSER_FACTOR` times smaller
  than itself and not anchored off it: a big part is not held back for a small one.  Free parts
  that only wait on each other are all ready;
* the **first** part is the start part when it is a root; when it hangs off other parts (the
  selection did not make it a root), its ancestors are drawn first, by the same rules, then it
  (nothing on this way waits for a part to rest on).
"""

from __future__ import annotations

from typing import Collection, Mapping, Sequence

from .types import Box, Primitive

#: A part is grounded when its box bottom is within this fraction of the model's height of the
#: model's lowest point.
GROUND_FRACTION = 0.03
#: A grounded part starts when its size is at least this share of the largest part's.
GROUNDED_SHARE = 0.5
#: Parts whose sizes (or reaches) are within this factor are "of similar size": among them the
#: nearest to the camera goes first.  At most :data:`COARSER_FACTOR`, so that nearest-first
#: never draws a part before a ready one over 4x its size.
SIMILAR_FACTOR = 2.0
#: A part whose largest face is over this many times another's is coarser: it is drawn before
#: the other unless the anchoring forbids (the issue's coarse-to-fine inversion test).
COARSER_FACTOR = 4.0


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
    largest = min(fitted, key=lambda p: (-part_size(p.box), p.part))
    on_ground = [p for p in fitted if grounded(p.box, floor, top - floor)]
    if on_ground:
        best = min(on_ground, key=lambda p: (-part_size(p.box), p.part))
        if part_size(best.box) >= GROUNDED_SHARE * part_size(largest.box):
            return best.part
    return largest.part


def drawing_order(sizes: Mapping[str, float], parents: Mapping[str, Collection[str]],
                  distance: Mapping[str, float], first: str | None = None,
                  rests_on: Mapping[str, Collection[str]] | None = None) -> list[str]:
    """The coarse-to-fine drawing order of the parts (module docstring).

    Args:
        sizes: part -> :func:`part_size` of its drawn box (model units squared); the parts to
            order are its keys.
        parents: part -> the parts it is anchored on (missing or empty: a root, a free part).
            Parents outside ``sizes`` are ignored.
        distance: part -> distance from the camera position to its box centre (model units).
        first: the part to draw first (:func:`start_part`); when it is not a root its
            ancestors come first.  None or not in ``sizes``: the rules alone pick the first.
        rests_on: free part -> the parts its box touches (only free parts' entries are used).

    Returns:
        Every key of ``sizes`` once, parents before children.

    Raises:
        ValueError: the anchoring graph has a cycle.
    """
    names = sorted(sizes)
    par = {p: {q for q in parents.get(p, ()) if q in sizes and q != p} for p in names}
    kids: dict[str, set[str]] = {p: set() for p in names}
    for p in names:
        for q in par[p]:
            kids[q].add(p)
    below = {p: _closure(p, kids) for p in names}
    rests_on = rests_on or {}
    # a free part waits only for parts it rests on that are not much smaller and not its own
    # descendants (waiting on a descendant would never end)
    waits = {p: {q for q in rests_on.get(p, ()) if q in sizes and q != p and q not in below[p]
                 and COARSER_FACTOR * sizes[q] >= sizes[p]}
             for p in names if not par[p]}
    chain = (_closure(first, par) | {first}) if first in sizes else set()
    done: set[str] = set()
    out: list[str] = []
    while len(out) < len(names):
        left = [p for p in names if p not in done]
        roots = [p for p in left if par[p] <= done]
        if not roots:
            raise ValueError(f"the anchoring graph has a cycle among {left}")
        if first in sizes and first not in done:  # the start part's ancestors, then it
            ready = [p for p in roots if p in chain] or roots
        elif not out:
            ready = roots
        else:
            ready = [p for p in roots if p not in waits or not waits[p] or waits[p] & done]
            ready = ready or roots  # free parts waiting only on each other
        waiting = {p: waits[p] for p in left if p in waits and waits[p] and not waits[p] & done}
        reach = {p: _reach(p, kids, waiting, done, sizes) for p in ready}
        top = max(reach.values())
        near = [p for p in ready if SIMILAR_FACTOR * reach[p] >= top]
        big = max(sizes[p] for p in near)
        near = [p for p in near if SIMILAR_FACTOR * sizes[p] >= big]
        nxt = min(near, key=lambda p: (distance[p], p))
        out.append(nxt)
        done.add(nxt)
    return out


def _closure(part: str, edges: Mapping[str, Collection[str]]) -> set[str]:
    """Every part reachable from ``part`` along ``edges`` (not ``part`` itself unless a cycle)."""
    seen: set[str] = set()
    stack = list(edges.get(part, ()))
    while stack:
        q = stack.pop()
        if q not in seen:
            seen.add(q)
            stack.extend(edges.get(q, ()))
    return seen


def _reach(part: str, kids: Mapping[str, Collection[str]], waiting: Mapping[str, set[str]],
           done: set[str], sizes: Mapping[str, float]) -> float:
    """The largest size over ``part`` and the undrawn parts that wait for it, directly or not:
    its children in the anchoring graph and the free parts still waiting to rest on it."""
    best = sizes[part]
    seen = {part}
    stack = [part]
    while stack:
        q = stack.pop()
        nxt = [c for c in kids[q] if c not in done]
        nxt += [f for f, on in waiting.items() if q in on]
        for c in nxt:
            if c not in seen:
                seen.add(c)
                best = max(best, sizes[c])
                stack.append(c)
    return best
