"""Synthetic scans of drawing sheets, for the scoring tests (test_score.py, test_study.py).

A sheet page rendered at :data:`RENDER_DPI` gets a known drawing in pencil (:func:`pencil`)
and is moved into a "scan" by a known homography and degraded (:func:`scan`).
"""

from __future__ import annotations

import math

import cv2
import numpy as np

from h2s_print import score
from h2s_print.studyfile import SheetKey

#: The sheet is rendered at this resolution before it is moved into a scan.
RENDER_DPI = 300.0
RENDER_PX_MM = RENDER_DPI / 25.4


def _gray(png: bytes) -> np.ndarray:
    img = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_UNCHANGED)
    a = img[..., 3:4].astype(np.float32) / 255.0
    rgb = img[..., :3].astype(np.float32) * a + 255.0 * (1 - a)
    return cv2.cvtColor(np.clip(rgb + 0.5, 0, 255).astype(np.uint8), cv2.COLOR_BGR2GRAY)


def _render_matrix(h_mm: float) -> np.ndarray:
    """Sheet mm -> rendered page pixels (pixel centres at integers, rows from the top)."""
    s = RENDER_PX_MM
    return np.array([[s, 0, -0.5], [0, -s, h_mm * s - 0.5], [0, 0, 1.0]])


def pencil(rendered: np.ndarray, key: SheetKey,
           moves: dict[str, tuple[float, float]] | None = None, jitter_mm: float = 0.0,
           grey: int = 110, width_mm: float = 0.5, seed: int = 0) -> np.ndarray:
    """``rendered`` with the key's lines drawn in pencil ``grey``, each part moved by
    ``moves[part]`` (mm, sheet axes) and every vertex by a seeded random ``jitter_mm``."""
    if moves is None:
        moves = {}
    rng = np.random.default_rng(seed)
    m = _render_matrix(key.paper_mm[1])
    layer = np.zeros(rendered.shape, np.float32)
    for part, lines in key.lines:
        dx, dy = moves.get(part, (0.0, 0.0))
        for line in lines:
            p = np.asarray(line, float) + (dx, dy)
            if jitter_mm:
                dense = score._samples([p])[:: max(1, int(6 / score.SAMPLE_MM))]
                p = np.r_[dense, p[-1:]] + rng.normal(0, jitter_mm, (len(dense) + 1, 2))
            px = score._apply(m, p)
            cv2.polylines(layer, [np.round(px * 16).astype(np.int32)], False, 1.0,
                          max(1, round(width_mm * RENDER_PX_MM)), cv2.LINE_AA, shift=4)
    dark = np.clip(layer, 0, 1) * (1 - grey / 255.0)
    return np.clip(rendered.astype(np.float32) * (1 - dark) + 0.5, 0, 255).astype(np.uint8)


def scan(page: np.ndarray, key: SheetKey, *, angle_deg: float = 0.0, dpi: float = 250.0,
         skew: float = 0.0, perspective: float = 0.0, blur_px: float = 0.0,
         noise: float = 0.0, light: float = 0.0, jpeg: int = 0, seed: int = 0,
         border: int = 255) -> tuple[np.ndarray, np.ndarray]:
    """(scan image, true homography sheet mm -> scan px): ``page`` (rendered at RENDER_DPI)
    rotated by ``angle_deg``, scaled to ``dpi``, sheared by ``skew`` (x += skew * y), with a
    keystone ``perspective`` (the far edge this much shorter), on a canvas with a margin,
    then blurred, lit unevenly (``light``: the darkest corner this much darker), noised
    (Gaussian, ``noise`` grey levels) and JPEG-compressed (quality ``jpeg``)."""
    rng = np.random.default_rng(seed)
    h, w = page.shape
    k = dpi / RENDER_DPI
    # perspective: the page's top edge (row 0) shrinks by `perspective` about its middle
    src = np.float32([[0, 0], [w, 0], [w, h], [0, h]])
    d = perspective * w / 2
    dst = np.float32([[d, 0], [w - d, 0], [w, h], [0, h]])
    persp = cv2.getPerspectiveTransform(src, dst).astype(float)
    a = math.radians(angle_deg)
    lin = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
    lin = lin @ np.array([[k, k * skew, 0], [0, k, 0], [0, 0, 1]])
    t = lin @ persp
    corners = score._apply(t, src.astype(float))
    lo = corners.min(axis=0) - 0.04 * k * w
    hi = corners.max(axis=0) + 0.04 * k * w
    t = np.array([[1, 0, -lo[0]], [0, 1, -lo[1]], [0, 0, 1]]) @ t
    size = tuple(int(v) for v in np.ceil(hi - lo))
    pre = cv2.GaussianBlur(page, (0, 0), 0.45 / k) if k < 1 else page
    out = cv2.warpPerspective(pre, t, size, flags=cv2.INTER_LINEAR, borderValue=border)
    out = out.astype(np.float32)
    if blur_px:
        out = cv2.GaussianBlur(out, (0, 0), blur_px)
    if light:
        yy, xx = np.mgrid[0:out.shape[0], 0:out.shape[1]]
        out *= 1 - light * (0.6 * xx / out.shape[1] + 0.4 * yy / out.shape[0])
    if noise:
        out += rng.normal(0, noise, out.shape)
    out = np.clip(out + 0.5, 0, 255).astype(np.uint8)
    if jpeg:
        out = cv2.imdecode(cv2.imencode(".jpg", out, [cv2.IMWRITE_JPEG_QUALITY, jpeg])[1],
                           cv2.IMREAD_GRAYSCALE)
    return out, t @ _render_matrix(key.paper_mm[1])
