"""The contour steps' order: front to back, by which part hides which."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..config import SequenceSettings
from ..contours import own_contours
from ..types import Camera, Part

#: Samples per part's own visible contours for the occlusion test of the contour order.
_OCCLUSION_SAMPLES = 160


def _hidden_counts(parts: Sequence[Part], camera: Camera, settings: SequenceSettings) -> np.ndarray:
    """``h[i, j]``: how many samples of part ``j``'s own visible contours (hidden by itself only)
    part ``i`` hides (the contours' exact occlusion test against ``i``'s triangles)."""
    n = len(parts)
    own, tests = own_contours(parts, camera, crease_deg=settings.crease_deg,
                              suggestive=settings.suggestive)
    samples: list[np.ndarray] = []
    for cs in own:
        pts = [np.asarray(pl, dtype=float) for pl in cs.polylines3d if len(pl) >= 2]
        allp = np.vstack(pts) if pts else np.zeros((0, 3))
        if len(allp) > _OCCLUSION_SAMPLES:
            allp = allp[np.linspace(0, len(allp) - 1, _OCCLUSION_SAMPLES).round().astype(int)]
        samples.append(allp)
    proj = [camera.project(np.asarray(p.vertices, dtype=float)) for p in parts]
    h = np.zeros((n, n), dtype=int)
    for j in range(n):
        if not len(samples[j]):
            continue
        sj = camera.project(samples[j])
        for i in range(n):
            if i == j or not len(proj[i]):
                continue
            lo, hi = proj[i].min(axis=0), proj[i].max(axis=0)
            inside = np.all((sj >= lo) & (sj <= hi), axis=1)
            if not inside.any():
                continue
            # the contours' own exact occlusion test, on the engine that traced part i
            seen = tests[i](samples[j][inside])
            h[i, j] = int(np.count_nonzero(~seen))
    return h


def _front_to_back(parts: Sequence[Part], camera: Camera, settings: SequenceSettings) -> list[str]:
    """Contour order: a part that hides some of another's lines comes before it; among the
    parts nothing left hides, the nearest (box centre to the camera position), then the name;
    mutual hiding (a cycle) starts with the part the remaining ones hide least."""
    names = [p.name for p in parts]
    h = _hidden_counts(parts, camera, settings)
    cam = np.asarray(camera.position, dtype=float)
    dist = {}
    for p in parts:
        lo, hi = p.box
        dist[p.name] = float(np.linalg.norm((np.asarray(lo) + np.asarray(hi)) / 2 - cam))
    left = list(range(len(parts)))
    out: list[str] = []
    while left:
        blocked = {j: int(sum(h[i, j] for i in left if i != j)) for j in left}
        nxt = min(left, key=lambda j: (blocked[j], dist[names[j]], names[j]))
        out.append(names[nxt])
        left.remove(nxt)
    return out
