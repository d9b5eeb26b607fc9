"""Scoring scanned drawing sheets (issue 14): find the sheet in a scan or photo, register it,
extract the pencil strokes and measure them against the model's finished drawing.

The stages, each a pure function over arrays and frozen values (only :func:`read_scan` and
:func:`read_printed` touch files):

1. :func:`read_scan`: the file's pages as greyscale images (PNG, JPEG, ... through OpenCV;
   PDF through pypdfium2 at :data:`PDF_DPI`).
2. :func:`find_code`: the sheet's QR code (``H2S:<study id>:<row>``, :mod:`.studyfile`) and
   its four corners in the image.  OpenCV's reader needs about 3 pixels per QR module; at the
   sheet's 8 mm, 21-module code that is 200 dpi, so scan at **200 dpi or more** (300 dpi
   recommended).  When it fails (lower resolutions, blur, uneven light) the code is located
   alone and read again from an upscaled crop: 150 dpi scans usually read.
3. :func:`register`: the homography from sheet millimetres to image pixels.  The QR code's
   corners (known on the sheet: :attr:`SheetKey.code_box_mm`, and read in the symbol's own
   order, so any rotation, also upside down, is known) give a first affine guess; each
   registration mark is then found by template matching (OpenCV ``matchTemplate``, normalised
   correlation) of the printed mark, cut from the blank sheet's image, against the scan
   resampled onto the sheet around where the guess puts it; nearest mark first, each found
   mark improving the guess for the next.  A second pass, with the homography of the four
   marks, matches each mark again in a small window, to a fraction of a pixel (a parabola
   through the correlation peak).  The result is the homography of the four mark centres;
   :attr:`Registration.residual_mm` says how far it puts the QR code's corners from where the
   reader found them, a check that the four marks are this sheet's (a wrong mark moves them
   by millimetres; a right registration leaves a tenth of a millimetre or so).  No
   whole-sheet refinement (``findTransformECC``) follows: on synthetic scans the four marks
   already recover the frame to a few hundredths of a millimetre, and what they miss on real
   ones (lens distortion, a curled sheet) a homography cannot fix either.  Rotation,
   scale, skew and a phone photo's mild perspective are all homographies; lens distortion is
   not and is not corrected (flat-bed scans have none; a phone held square to the sheet has
   little).
4. :func:`strokes`: the scan resampled onto the blank sheet's pixel grid, its illumination
   flattened (each pixel divided by the local paper brightness, a grey dilation and blur of
   the image: photos are lit unevenly), ink where a pixel is darker than
   :data:`INK_RATIO` of the paper around it (pencil grey, not only black), minus the printed
   sheet (every pixel the blank sheet's image has ink on, grown by :data:`PRINTED_PAD_MM` to
   absorb registration error and blur), minus specks smaller than :data:`SPECK_MM2`, only
   inside the drawing frame.  A pencil line crossing a printed line loses that crossing.
5. :func:`measure`: figures per part and overall, in sheet millimetres (see :class:`Figures`),
   over the model lines a stroke could be seen on (not under the print, inside the frame:
   :func:`blind_mask`), so a perfect drawing scores 0 mm and covers 1.0.
6. :func:`overlay`: the registered drawing in grey with the model's lines in orange, PNG.

:func:`score_image` runs 2-5 on one image; :func:`score_scan` on every page of a file.  Errors
the user can fix are :class:`~h2s_print.studyfile.StudyError` with one line naming the scan
(and the page, for a PDF of several).

Not handled: a sheet printed at another scale than 100 % (the marks then do not sit where
the key says: the QR check fails), lens distortion, strokes outside the frame, erased lines
still visible as a grey smear (they count when darker than :data:`INK_RATIO`), construction
lines the participant left (they count as strokes, as they do for a rater).
"""

from __future__ import annotations

import itertools
import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np
from scipy import ndimage

from .studyfile import Drawing, SheetKey, Study, StudyError, parse_code

log = logging.getLogger(__name__)

#: A PDF page is rendered at this resolution, dots per inch.
PDF_DPI = 300.0
#: Ink: a pixel darker than this share of the local paper brightness.
INK_RATIO = 0.8
#: The printed marks are removed with this margin around them, mm.
PRINTED_PAD_MM = 0.6
#: Dark specks smaller than this (dust, noise) are not strokes, mm².
SPECK_MM2 = 0.15
#: A sheet with less ink than this inside its frame is blank, mm² (a 0.5 mm line 10 mm long).
MIN_INK_MM2 = 5.0
#: A model line is covered where a stroke is within this distance, mm.
COVER_MM = 2.0
#: The translation search for :attr:`Figures.offset_mm` spans this far each way, mm.
OFFSET_SEARCH_MM = 8.0
#: Distances are capped here in that search, so a line with no stroke near it does not
#: outweigh the lines that have one, mm.
OFFSET_CAP_MM = 3.0
#: Model lines are sampled this densely, mm.
SAMPLE_MM = 0.25
#: The registration is refused when the QR code's corners land farther than this from where
#: the reader found them, mm (a mark taken for another; a sheet printed scaled).
MAX_RESIDUAL_MM = 1.0
#: A registration mark's normalised correlation must reach this.
MIN_MARK_SCORE = 0.35
#: Overlay colours (BGR): the model's lines.
MODEL_BGR = (0, 128, 255)

Pt = tuple[float, float]


# ----------------------------------------------------------------------------- values


@dataclass(frozen=True, slots=True)
class Registration:
    """Where the sheet lies in an image.

    Attributes:
        sheet_to_image: (3, 3) homography, sheet mm (origin bottom-left, y up) to image
            pixels (x right, y down; pixel centres at integer coordinates), read-only.
        image_to_sheet: its inverse.
        marks_px: the four registration mark centres found in the image, in
            :attr:`SheetKey.marks_mm` order (bottom-left, bottom-right, top-right, top-left).
        mark_scores: their normalised correlation with the printed mark (1 is a perfect match).
        residual_mm: the largest distance on the sheet between where the homography puts the
            QR code's corners and where the code reader found them, mm.
        px_per_mm: the image's scale at the sheet's centre, pixels per mm (about dpi / 25.4).
    """

    sheet_to_image: np.ndarray
    image_to_sheet: np.ndarray
    marks_px: tuple[Pt, Pt, Pt, Pt]
    mark_scores: tuple[float, float, float, float]
    residual_mm: float
    px_per_mm: float

    def to_image(self, points_mm: np.ndarray) -> np.ndarray:
        """``points_mm`` (n, 2) sheet mm as image pixels (n, 2)."""
        return _apply(self.sheet_to_image, points_mm)

    def to_sheet(self, points_px: np.ndarray) -> np.ndarray:
        """``points_px`` (n, 2) image pixels as sheet mm (n, 2)."""
        return _apply(self.image_to_sheet, points_px)


@dataclass(frozen=True, slots=True)
class Figures:
    """How close a drawing (or one part of it) is to the model's lines, sheet mm.

    Attributes:
        to_drawing_mm: mean distance from the model's lines (sampled every
            :data:`SAMPLE_MM`) to the nearest stroke pixel: high when lines are missing or
            misplaced.
        to_model_mm: mean distance from the stroke pixels to the nearest model line: high
            when strokes are where the model has none.  For a part: over the stroke pixels
            whose nearest model line is that part's.  NaN when there are none.
        covered: share of the model's line samples within :data:`COVER_MM` of a stroke, 0-1.
        offset_mm: the length of the translation that best lays the model's lines on the
            strokes near them (the smallest mean of the stroke distance capped at
            :data:`OFFSET_CAP_MM`, searched :data:`OFFSET_SEARCH_MM` each way).  The two
            distances above cannot see a line moved along its own direction (it still lies
            on itself), nor tell a displaced part from a sloppy one; this can.  For the whole
            drawing: the mean over the parts that have strokes near them.  NaN when no stroke
            is near.
    """

    to_drawing_mm: float
    to_model_mm: float
    covered: float
    offset_mm: float


@dataclass(frozen=True, slots=True)
class Scores:
    """A drawing's figures: overall and per part (in the key's part order)."""

    overall: Figures
    parts: tuple[tuple[str, Figures], ...]

    def part(self, name: str) -> Figures:
        """The figures of part ``name``."""
        for p, f in self.parts:
            if p == name:
                return f
        raise KeyError(name)


@dataclass(frozen=True, slots=True)
class ScanResult:
    """One scored sheet.

    Attributes:
        source: the scan's name in messages (file, and page for a PDF of several).
        drawing: the assignment row the sheet's code names.
        key: that drawing's sheet.
        registration: where the sheet lies in the image.
        registered: the scan resampled onto the blank sheet's pixel grid (uint8 greyscale,
            flattened illumination), read-only.
        registered_drawing: the pencil strokes on that grid (bool), read-only.
        scores: the figures.
    """

    source: str
    drawing: Drawing
    key: SheetKey
    registration: Registration
    registered: np.ndarray
    registered_drawing: np.ndarray
    scores: Scores


#: Columns of :func:`score_rows`, for scores.csv.
CSV_FIELDS = ("scan", "participant", "object", "condition", "order", "part",
              "to_drawing_mm", "to_model_mm", "covered", "offset_mm", "residual_mm")


# ----------------------------------------------------------------------------- helpers


def _ro(a: np.ndarray) -> np.ndarray:
    a = np.array(a, copy=True)
    a.setflags(write=False)
    return a


def _apply(h: np.ndarray, pts: np.ndarray) -> np.ndarray:
    pts = np.asarray(pts, float).reshape(-1, 2)
    q = np.c_[pts, np.ones(len(pts))] @ np.asarray(h, float).T
    return q[:, :2] / q[:, 2:3]


def grid_matrix(key: SheetKey) -> np.ndarray:
    """(3, 3) affine map from sheet mm to the blank sheet image's pixels (the
    :mod:`.studyfile` convention: pixel (row, col) centred at ``x = (col + 0.5) / px_per_mm``,
    ``y = height_mm - (row + 0.5) / px_per_mm``)."""
    s = float(key.px_per_mm)
    return np.array([[s, 0.0, -0.5], [0.0, -s, key.paper_mm[1] * s - 0.5], [0.0, 0.0, 1.0]])


def _grid_shape(key: SheetKey) -> tuple[int, int]:
    return (round(key.paper_mm[1] * key.px_per_mm), round(key.paper_mm[0] * key.px_per_mm))


def _to_gray(img: np.ndarray) -> np.ndarray:
    """Any OpenCV-decoded image as uint8 greyscale, transparency composited on white."""
    if img.dtype != np.uint8:
        top = float(np.iinfo(img.dtype).max) if np.issubdtype(img.dtype, np.integer) else 1.0
        img = np.clip(img.astype(np.float64) / top * 255.0 + 0.5, 0, 255).astype(np.uint8)
    if img.ndim == 2:
        return img
    if img.shape[2] == 4:
        a = img[..., 3:4].astype(np.float32) / 255.0
        rgb = img[..., :3].astype(np.float32) * a + 255.0 * (1.0 - a)
        img = np.clip(rgb + 0.5, 0, 255).astype(np.uint8)
    if img.shape[2] == 1:
        return img[..., 0]
    return cv2.cvtColor(img[..., :3], cv2.COLOR_BGR2GRAY)


# ----------------------------------------------------------------------------- files


def read_scan(path: str | Path) -> list[np.ndarray]:
    """The pages of a scan as uint8 greyscale images (one for an image file, one per page of
    a PDF, rendered at :data:`PDF_DPI`).

    Raises:
        StudyError: the file is missing, empty, or neither an image OpenCV reads nor a PDF.
    """
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise StudyError(f"{path}: cannot be read ({exc.strerror or exc})") from None
    if data[:5] == b"%PDF-":
        return _pdf_pages(path, data)
    img = None
    if data:
        # imdecode from bytes, so a path OpenCV's own reader would mangle (non-ASCII) works
        img = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED)
    if img is None or img.size == 0:
        raise StudyError(f"{path}: cannot be read as an image or PDF")
    return [_to_gray(img)]


def _pdf_pages(path: Path, data: bytes) -> list[np.ndarray]:
    import pypdfium2 as pdfium

    try:
        pdf = pdfium.PdfDocument(data)
        try:
            pages = []
            for i in range(len(pdf)):
                bitmap = pdf[i].render(scale=PDF_DPI / 72.0, grayscale=True)
                pages.append(_to_gray(np.array(bitmap.to_numpy(), copy=True)))
        finally:
            pdf.close()
    except pdfium.PdfiumError as exc:
        raise StudyError(f"{path}: cannot be read as an image or PDF ({exc})") from None
    if not pages:
        raise StudyError(f"{path}: the PDF has no pages")
    return pages


def read_printed(key: SheetKey) -> np.ndarray:
    """The blank sheet's image (:attr:`SheetKey.printed`) as uint8 greyscale, checked against
    the key's paper size and resolution.

    Raises:
        StudyError: missing, unreadable or of the wrong size.
    """
    try:
        data = Path(key.printed).read_bytes()
    except OSError as exc:
        raise StudyError(f"{key.printed}: cannot be read ({exc.strerror or exc})") from None
    img = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED) if data else None
    if img is None:
        raise StudyError(f"{key.printed}: cannot be read as an image")
    gray = _to_gray(img)
    want = _grid_shape(key)
    if abs(gray.shape[0] - want[0]) > 1 or abs(gray.shape[1] - want[1]) > 1:
        raise StudyError(f"{key.printed}: {gray.shape[1]} x {gray.shape[0]} pixels, expected "
                         f"{want[1]} x {want[0]} ({key.paper_mm[0]:g} x {key.paper_mm[1]:g} mm "
                         f"at {key.px_per_mm:g} px/mm)")
    if gray.shape != want:
        gray = cv2.resize(gray, (want[1], want[0]), interpolation=cv2.INTER_AREA)
    return gray


# ----------------------------------------------------------------------------- code


def find_code(gray: np.ndarray) -> tuple[str, np.ndarray] | None:
    """The QR code on a sheet image: its text and its corners (4, 2) in image pixels, in the
    symbol's own order (top-left, top-right, bottom-right, bottom-left as the code is read,
    whatever the image's rotation); ``None`` when no code reads.

    OpenCV's reader is tried on the image first.  It needs about 3 pixels per module (200
    dpi for the sheet's 8 mm code) and sharp edges; when it fails, the code is located alone
    (OpenCV's locators find a code they cannot read, also on a binarised image) and read
    again from that corner of the image upscaled to about 8 pixels per module, as is, lightly
    blurred and binarised against its local brightness (uneven light, JPEG, blur).
    """
    reader = cv2.QRCodeDetector()
    got = _decode(reader, gray)
    if got is not None:
        return got
    binary = _binarised(gray)
    boxes: list[np.ndarray] = []
    for locator, img in ((cv2.QRCodeDetectorAruco(), gray), (reader, binary),
                         (cv2.QRCodeDetectorAruco(), binary)):
        try:
            ok, pts = locator.detect(img)
        except cv2.error:
            continue
        if ok and pts is not None and pts.size == 8:
            quad = pts.reshape(4, 2).astype(np.float64)
            if not any(np.abs(quad - b).max() < 3 for b in boxes):
                boxes.append(quad)
    for quad in boxes:
        side = max(float(np.linalg.norm(quad[k] - quad[(k + 1) % 4])) for k in range(4))
        if side < 8:
            continue
        lo = np.maximum(np.floor(quad.min(axis=0) - 0.6 * side), 0).astype(int)
        hi = np.minimum(np.ceil(quad.max(axis=0) + 0.6 * side),
                        (gray.shape[1], gray.shape[0])).astype(int)
        crop = gray[lo[1]:hi[1], lo[0]:hi[0]]
        scale = max(1.0, min(8.0, 170.0 / side))
        big = cv2.resize(crop, None, fx=scale, fy=scale, interpolation=cv2.INTER_CUBIC)
        for attempt in (big, cv2.GaussianBlur(big, (0, 0), 0.3 * scale), _binarised(big)):
            for det in (reader, cv2.QRCodeDetectorAruco()):
                got = _decode(det, attempt)
                if got is not None:
                    return got[0], got[1] / scale + lo
    return None


def _decode(detector, img: np.ndarray) -> tuple[str, np.ndarray] | None:
    try:
        text, pts, _ = detector.detectAndDecode(img)
    except cv2.error:
        return None
    if text and pts is not None and pts.size == 8:
        return text, pts.reshape(4, 2).astype(np.float64)
    return None


def _binarised(gray: np.ndarray) -> np.ndarray:
    """Black and white against the local brightness (a window of about a tenth of a
    typical code's side at 200-300 dpi)."""
    return cv2.adaptiveThreshold(gray, 255, cv2.ADAPTIVE_THRESH_GAUSSIAN_C, cv2.THRESH_BINARY,
                                 51, 10)


def code_corners_mm(key: SheetKey) -> np.ndarray:
    """The QR code's corners on the sheet (4, 2) mm, in :func:`find_code`'s order: the
    symbol is printed upright, its first row at the box's top."""
    x0, y0, x1, y1 = key.code_box_mm
    return np.array([(x0, y1), (x1, y1), (x1, y0), (x0, y0)], float)


# ----------------------------------------------------------------------------- registration


def _affine(src: np.ndarray, dst: np.ndarray) -> np.ndarray:
    """Least-squares affine map src -> dst as a (3, 3) matrix."""
    a = np.c_[src, np.ones(len(src))]
    sol, *_ = np.linalg.lstsq(a, dst, rcond=None)
    return np.vstack([sol.T, [0.0, 0.0, 1.0]])


def _rectify(gray: np.ndarray, sheet_to_image: np.ndarray, key: SheetKey,
             box_px: tuple[int, int, int, int]) -> np.ndarray:
    """The part of ``gray`` that lies on the blank-sheet grid pixels ``box_px`` (c0, r0, c1,
    r1; end exclusive), resampled (bilinear; outside the image: white)."""
    c0, r0, c1, r1 = box_px
    shift = np.array([[1.0, 0, c0], [0, 1.0, r0], [0, 0, 1.0]])
    m = sheet_to_image @ np.linalg.inv(grid_matrix(key)) @ shift
    return cv2.warpPerspective(gray, m, (c1 - c0, r1 - r0),
                               flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                               borderMode=cv2.BORDER_CONSTANT, borderValue=255)


def _peak(score: np.ndarray) -> tuple[float, float, float]:
    """The maximum of a correlation map (x, y, value), refined by a parabola each way."""
    _, best, _, (x, y) = cv2.minMaxLoc(score)
    fx, fy = float(x), float(y)
    if 0 < x < score.shape[1] - 1:
        a, b, c = score[y, x - 1], score[y, x], score[y, x + 1]
        d = a - 2 * b + c
        if d < 0:
            fx += 0.5 * (a - c) / d
    if 0 < y < score.shape[0] - 1:
        a, b, c = score[y - 1, x], score[y, x], score[y + 1, x]
        d = a - 2 * b + c
        if d < 0:
            fy += 0.5 * (a - c) / d
    return fx, fy, float(best)


def _find_mark(gray: np.ndarray, guess: np.ndarray, key: SheetKey, printed: np.ndarray,
               i: int, search_mm: float, blur_px: float) -> tuple[np.ndarray, float]:
    """Mark ``i`` in the image: (its centre in image px, correlation).  The image around the
    mark is resampled onto the sheet grid with ``guess`` (sheet mm -> image px) and the
    printed mark (cut from ``printed``) matched over ``search_mm`` each way."""
    s = key.px_per_mm
    g = grid_matrix(key)
    centre = _apply(g, np.array([key.marks_mm[i]]))[0]
    half_t = math.ceil((key.mark_radius_mm + 1.6) * s)
    half_w = half_t + math.ceil(search_mm * s)
    cx, cy = round(centre[0]), round(centre[1])
    h, w = printed.shape
    tc0, tr0 = max(cx - half_t, 0), max(cy - half_t, 0)
    templ = printed[tr0:min(cy + half_t + 1, h), tc0:min(cx + half_t + 1, w)]
    window = _rectify(gray, guess, key, (cx - half_w, cy - half_w, cx + half_w + 1,
                                         cy + half_w + 1))
    if blur_px > 0:
        templ = cv2.GaussianBlur(templ, (0, 0), blur_px)
        window = cv2.GaussianBlur(window, (0, 0), blur_px)
    if float(templ.std()) < 1.0 or float(window.std()) < 1.0:
        return centre, 0.0
    score = cv2.matchTemplate(window.astype(np.float32), templ.astype(np.float32),
                              cv2.TM_CCOEFF_NORMED)
    fx, fy, best = _peak(np.nan_to_num(score, nan=-1.0))
    # where the template's top-left landed -> how far the mark is from where guess put it
    found_grid = np.array([[fx + (cx - half_w) + (centre[0] - tc0),
                            fy + (cy - half_w) + (centre[1] - tr0)]])
    found_mm = _apply(np.linalg.inv(g), found_grid)
    return _apply(guess, found_mm)[0], best


def register(gray: np.ndarray, key: SheetKey, printed: np.ndarray, code_corners: np.ndarray,
             *, source: str = "scan") -> Registration:
    """Where sheet ``key`` lies in ``gray``: the homography from sheet mm to image pixels.

    Args:
        gray: the scan, uint8 greyscale.
        key: the sheet the code names.
        printed: the blank sheet's image (:func:`read_printed`).
        code_corners: (4, 2) the QR code's corners from :func:`find_code`, image px.
        source: the scan's name for messages.

    Raises:
        StudyError: a registration mark is not found (cut off, covered, not this sheet), or
            the four found do not agree with the QR code.
    """
    code_mm = code_corners_mm(key)
    code_px = np.asarray(code_corners, float).reshape(4, 2)
    marks_mm = np.array(key.marks_mm, float)
    side_mm = key.code_box_mm[2] - key.code_box_mm[0]
    px_per_mm = float(np.mean([np.linalg.norm(code_px[k] - code_px[(k + 1) % 4])
                               for k in range(4)]) / side_mm)
    if not px_per_mm > 0:
        raise StudyError(f"{source}: the sheet code's corners are degenerate")
    # Work blurred at about the scan's resolution: finer than the scan adds no detail and
    # a thin printed line is more forgiving blurred.
    blur = max(0.6, 0.5 * key.px_per_mm / px_per_mm)
    centre = code_mm.mean(axis=0)
    order = sorted(range(4), key=lambda k: float(np.linalg.norm(marks_mm[k] - centre)))
    found: dict[int, np.ndarray] = {}
    scores: dict[int, float] = {}
    names = ("bottom-left", "bottom-right", "top-right", "top-left")
    for k in order:
        known = list(found)
        if len(known) >= 3:
            # three marks and the code: enough for a homography (a phone's perspective)
            guess = cv2.findHomography(np.r_[code_mm, marks_mm[known]],
                                       np.r_[code_px, [found[j] for j in known]], 0)[0]
            if guess is None:
                guess = _affine(marks_mm[known], np.array([found[j] for j in known]))
        else:
            guess = _affine(np.r_[code_mm, marks_mm[known]],
                            np.r_[code_px, np.array([found[j] for j in known]).reshape(-1, 2)])
        dist = min(float(np.min(np.linalg.norm(code_mm - marks_mm[k], axis=1))),
                   min((float(np.linalg.norm(marks_mm[j] - marks_mm[k])) for j in known),
                       default=math.inf))
        search = 3.0 + 0.15 * dist
        found[k], scores[k] = _find_mark(gray, guess, key, printed, k, search, 2.0 * blur)
        if scores[k] < MIN_MARK_SCORE:
            raise StudyError(f"{source}: no registration marks found (the {names[k]} mark is "
                             f"missing or cut off: scan the whole sheet, at 200 dpi or more)")
    # Second pass: each mark again, near where the four-mark homography puts it.
    for _ in range(2):
        h = cv2.findHomography(marks_mm, np.array([found[k] for k in range(4)]), 0)[0]
        if h is None:
            break
        for k in range(4):
            found[k], scores[k] = _find_mark(gray, h, key, printed, k, 1.0, blur)
    h = cv2.findHomography(marks_mm, np.array([found[k] for k in range(4)]), 0)[0]
    if h is None or min(scores.values()) < MIN_MARK_SCORE:
        raise StudyError(f"{source}: no registration marks found (the marks do not read: "
                         f"scan the whole sheet, at 200 dpi or more)")
    inv = np.linalg.inv(h)
    residual = float(np.max(np.linalg.norm(_apply(inv, code_px) - code_mm, axis=1)))
    if residual > MAX_RESIDUAL_MM:
        raise StudyError(f"{source}: no registration marks found where the sheet code says "
                         f"(off by {residual:.1f} mm: was the sheet printed at 100 %?)")
    mid = np.array([[key.paper_mm[0] / 2, key.paper_mm[1] / 2]])
    scale = float(np.linalg.norm(_apply(h, mid + [1.0, 0.0]) - _apply(h, mid)))
    marks = tuple((float(found[k][0]), float(found[k][1])) for k in range(4))
    return Registration(_ro(h), _ro(inv), marks,  # type: ignore[arg-type]
                        tuple(float(scores[k]) for k in range(4)),  # type: ignore[arg-type]
                        residual, scale)


# ----------------------------------------------------------------------------- strokes


def registered_image(gray: np.ndarray, registration: Registration, key: SheetKey) -> np.ndarray:
    """The scan resampled onto the blank sheet's pixel grid, its illumination flattened:
    paper white (255), ink as dark as it is against the paper around it; uint8."""
    rows, cols = _grid_shape(key)
    warped = _rectify(gray, registration.sheet_to_image, key, (0, 0, cols, rows))
    # The paper's brightness: a grey dilation wider than any pencil line, then smoothed;
    # computed at a quarter of the resolution (it varies slowly).
    small = cv2.resize(warped, None, fx=0.25, fy=0.25, interpolation=cv2.INTER_AREA)
    k = max(3, round(4.0 * key.px_per_mm / 4) | 1)
    paper = cv2.dilate(small, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (k, k)))
    paper = cv2.GaussianBlur(paper, (0, 0), k / 2)
    paper = cv2.resize(paper, (cols, rows), interpolation=cv2.INTER_LINEAR)
    flat = warped.astype(np.float32) / np.maximum(paper.astype(np.float32), 16.0) * 255.0
    return np.clip(flat + 0.5, 0, 255).astype(np.uint8)


def printed_mask(printed: np.ndarray, key: SheetKey) -> np.ndarray:
    """The blank sheet's ink (anything not white, the light grey frame too), grown by
    :data:`PRINTED_PAD_MM`: where pencil cannot be told from print (bool, sheet grid)."""
    ink = (printed < 235).astype(np.uint8)
    r = max(1, round(PRINTED_PAD_MM * key.px_per_mm))
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    return cv2.dilate(ink, disk).astype(bool)


def frame_mask(key: SheetKey) -> np.ndarray:
    """The drawing frame's inside on the sheet grid (bool), :data:`PRINTED_PAD_MM` in from
    its line."""
    rows, cols = _grid_shape(key)
    x0, y0, x1, y1 = key.frame_mm
    pad = PRINTED_PAD_MM
    (c0, r1), (c1, r0) = _apply(grid_matrix(key), np.array([[x0 + pad, y0 + pad],
                                                            [x1 - pad, y1 - pad]]))
    mask = np.zeros((rows, cols), bool)
    mask[max(0, math.ceil(r0)):max(0, int(r1) + 1),
         max(0, math.ceil(c0)):max(0, int(c1) + 1)] = True
    return mask


def blind_mask(printed: np.ndarray, key: SheetKey) -> np.ndarray:
    """Where a pencil stroke cannot be seen (bool, sheet grid): on the printed marks
    (:func:`printed_mask`) and outside the frame (:func:`frame_mask`)."""
    return printed_mask(printed, key) | ~frame_mask(key)


def ink_mask(registered: np.ndarray, key: SheetKey, printed: np.ndarray) -> np.ndarray:
    """The pencil strokes in a registered image (:func:`registered_image`): bool, sheet grid."""
    s = key.px_per_mm
    smooth = cv2.GaussianBlur(registered, (0, 0), max(0.5, 0.08 * s))
    ink = smooth < INK_RATIO * 255
    ink &= ~blind_mask(printed, key)
    _n, labels, stats, _ = cv2.connectedComponentsWithStats(ink.astype(np.uint8), connectivity=8)
    keep = stats[:, cv2.CC_STAT_AREA] >= SPECK_MM2 * s * s
    keep[0] = False
    return keep[labels]


def strokes(gray: np.ndarray, registration: Registration, key: SheetKey, printed: np.ndarray,
            *, source: str = "scan") -> tuple[np.ndarray, np.ndarray]:
    """The pencil strokes of a registered scan: (registered image, stroke mask), both on the
    blank sheet's pixel grid (``key.px_per_mm``), read-only.

    Raises:
        StudyError: no pencil inside the frame (a blank sheet).
    """
    reg = registered_image(gray, registration, key)
    mask = ink_mask(reg, key, printed)
    if mask.sum() < MIN_INK_MM2 * key.px_per_mm ** 2:
        raise StudyError(f"{source}: no pencil strokes found inside the frame (a blank sheet?)")
    return _ro(reg), _ro(mask)


# ----------------------------------------------------------------------------- measures


def _samples(lines: Sequence[Sequence[Pt]]) -> np.ndarray:
    """Points every :data:`SAMPLE_MM` along polylines (n, 2) mm."""
    out = []
    for line in lines:
        p = np.asarray(line, float).reshape(-1, 2)
        if len(p) == 1:
            out.append(p)
        for a, b in itertools.pairwise(p):
            n = max(1, math.ceil(np.linalg.norm(b - a) / SAMPLE_MM))
            t = np.arange(n)[:, None] / n
            out.append(a + t * (b - a))
        if len(p) > 1:
            out.append(p[-1:])
    return np.concatenate(out) if out else np.zeros((0, 2))


def _draw_lines(img: np.ndarray, lines: Sequence[Sequence[Pt]], key: SheetKey, value,
                thickness: int = 1, aa: bool = False) -> None:
    g = grid_matrix(key)
    pts = [np.round(_apply(g, np.asarray(line, float)) * 16).astype(np.int32)
           for line in lines if len(line) >= 2]
    if pts:
        cv2.polylines(img, pts, False, value, thickness, cv2.LINE_AA if aa else cv2.LINE_8,
                      shift=4)


def _bilinear(img: np.ndarray, pts_px: np.ndarray) -> np.ndarray:
    return ndimage.map_coordinates(img, [pts_px[:, 1], pts_px[:, 0]], order=1, mode="nearest")


def _offset(cost: np.ndarray, part_lines: Sequence[Sequence[Pt]], key: SheetKey,
            seen: np.ndarray | None = None) -> float:
    """The translation length (mm) that minimises the mean of ``cost`` (capped stroke
    distance, mm, sheet grid) along ``part_lines``: correlation of the lines' raster with
    the cost map over every shift of up to :data:`OFFSET_SEARCH_MM`, refined by a parabola."""
    s = key.px_per_mm
    rows, cols = cost.shape
    g = grid_matrix(key)
    pts = np.concatenate([_apply(g, np.asarray(line, float)) for line in part_lines])
    pad = 2
    c0, r0 = np.floor(pts.min(axis=0)).astype(int) - pad
    c1, r1 = np.ceil(pts.max(axis=0)).astype(int) + pad
    templ = np.zeros((r1 - r0 + 1, c1 - c0 + 1), np.float32)
    shifted = [[(x - c0, y - r0) for x, y in _apply(g, np.asarray(line, float))]
               for line in part_lines]
    pts16 = [np.round(np.asarray(p) * 16).astype(np.int32) for p in shifted if len(p) >= 2]
    cv2.polylines(templ, pts16, False, 1.0, 1, cv2.LINE_AA, shift=4)
    if seen is not None:  # the lines where a stroke could not be seen do not vote
        part = np.zeros_like(templ, dtype=bool)
        a0, b0 = max(r0, 0), max(c0, 0)
        a1, b1 = min(r1 + 1, rows), min(c1 + 1, cols)
        if a1 > a0 and b1 > b0:
            part[a0 - r0:a1 - r0, b0 - c0:b1 - c0] = seen[a0:a1, b0:b1]
        templ[~part] = 0
    if templ.sum() <= 0:
        return math.nan
    reach = math.ceil(OFFSET_SEARCH_MM * s)
    big = np.full((r1 - r0 + 1 + 2 * reach, c1 - c0 + 1 + 2 * reach), OFFSET_CAP_MM, np.float32)
    sr0, sc0 = r0 - reach, c0 - reach
    a0, b0 = max(sr0, 0), max(sc0, 0)
    a1, b1 = min(sr0 + big.shape[0], rows), min(sc0 + big.shape[1], cols)
    if a1 > a0 and b1 > b0:
        big[a0 - sr0:a1 - sr0, b0 - sc0:b1 - sc0] = cost[a0:a1, b0:b1]
    mean = cv2.matchTemplate(big, templ, cv2.TM_CCORR) / float(templ.sum())
    if float(mean.min()) >= OFFSET_CAP_MM * 0.98:
        return math.nan
    # a hair of preference for the smaller shift, so that ties go to no displacement
    yy, xx = np.mgrid[-reach:reach + 1, -reach:reach + 1]
    fx, fy, _ = _peak(-(mean + 1e-4 * np.hypot(xx, yy) / s))
    return float(math.hypot(fx - reach, fy - reach) / s)


def measure(mask: np.ndarray, key: SheetKey, blind: np.ndarray | None = None) -> Scores:
    """The figures of a stroke mask (:func:`strokes`) against the key's model lines.

    ``blind`` (bool, sheet grid; :func:`blind_mask`) is where no stroke can be seen (on the
    printed marks, outside the frame): model line samples there are left out of
    ``to_drawing_mm``, ``covered`` and the offset search, so a perfect drawing covers 1.0
    however much of it the print crosses.

    Distances come from Euclidean distance transforms of the stroke mask and of the model's
    lines rasterised on the same grid (so they are exact to about half a pixel); strokes are
    taken as drawn, a few pixels wide, which adds about a quarter of their width to
    ``to_model_mm``.
    """
    s = float(key.px_per_mm)
    mask = np.asarray(mask, bool)
    g = grid_matrix(key)
    parts = [(name, lines) for name, lines in key.lines if any(len(ln) >= 2 for ln in lines)]
    if mask.any():
        to_stroke = cv2.distanceTransform((~mask).astype(np.uint8), cv2.DIST_L2,
                                          cv2.DIST_MASK_PRECISE) / s
    else:
        to_stroke = np.full(mask.shape, np.inf, np.float32)
    labels = np.zeros(mask.shape, np.int32)
    for i, (_, lines) in enumerate(parts):
        _draw_lines(labels, lines, key, i + 1)
    if parts:
        d_model, (ri, ci) = ndimage.distance_transform_edt(labels == 0, return_indices=True)
        nearest = labels[ri, ci]
        stroke_d = d_model[mask] / s
        stroke_part = nearest[mask]
    else:
        stroke_d = np.zeros(0)
        stroke_part = np.zeros(0, np.int32)
    cost = np.minimum(to_stroke, OFFSET_CAP_MM).astype(np.float32)
    per: list[tuple[str, Figures]] = []
    all_d: list[np.ndarray] = []
    offsets: list[float] = []
    seen = None if blind is None else ~np.asarray(blind, bool)
    for i, (name, lines) in enumerate(parts):
        pts = _apply(g, _samples(lines))
        if seen is not None and len(pts):
            rc = np.clip(np.round(pts).astype(int), 0, [mask.shape[1] - 1, mask.shape[0] - 1])
            pts = pts[seen[rc[:, 1], rc[:, 0]]]
        d = _bilinear(to_stroke, pts) if len(pts) else np.zeros(0)
        all_d.append(d)
        mine = stroke_d[stroke_part == i + 1]
        off = _offset(cost, lines, key, seen) if mask.any() else math.nan
        if not math.isnan(off):
            offsets.append(off)
        per.append((name, Figures(_mean(d), _mean(mine), _share(d), off)))
    d = np.concatenate(all_d) if all_d else np.zeros(0)
    overall = Figures(_mean(d), _mean(stroke_d), _share(d),
                      float(np.mean(offsets)) if offsets else math.nan)
    return Scores(overall, tuple(per))


def _mean(a: np.ndarray) -> float:
    return float(np.mean(a)) if len(a) else math.nan


def _share(d: np.ndarray) -> float:
    return float(np.mean(d <= COVER_MM)) if len(d) else math.nan


# ----------------------------------------------------------------------------- output


def overlay(registered: np.ndarray, key: SheetKey) -> bytes:
    """PNG bytes (RGB, sheet-sized at ``key.px_per_mm``): the registered drawing in grey, the
    model's lines in orange over it.  ``registered`` is a registered image (uint8, drawn
    lighter so the orange reads) or a stroke mask (bool, strokes dark grey on white).
    The same input gives the same bytes."""
    if registered.dtype == bool:
        grey = np.where(registered, 90, 255).astype(np.uint8)
    else:
        grey = (128 + registered.astype(np.uint16) // 2).astype(np.uint8)
    img = cv2.cvtColor(grey, cv2.COLOR_GRAY2BGR)
    width = max(1, round(0.3 * key.px_per_mm))
    for _, lines in key.lines:
        _draw_lines(img, lines, key, MODEL_BGR, width, aa=True)
    ok, buf = cv2.imencode(".png", img, [cv2.IMWRITE_PNG_COMPRESSION, 6])
    if not ok:  # pragma: no cover - OpenCV always encodes a uint8 BGR image
        raise RuntimeError("PNG encoding failed")
    return buf.tobytes()


def score_rows(result: ScanResult) -> list[dict[str, object]]:
    """The rows of scores.csv for one sheet (:data:`CSV_FIELDS`): the whole drawing
    (``part`` ``*``), then each part; figures rounded (mm to 0.01, shares to 0.001), a
    missing figure as ``""``."""
    d = result.drawing

    def row(part: str, f: Figures) -> dict[str, object]:
        return {"scan": result.source, "participant": d.participant, "object": d.object,
                "condition": d.condition, "order": d.order, "part": part,
                "to_drawing_mm": _r(f.to_drawing_mm, 2), "to_model_mm": _r(f.to_model_mm, 2),
                "covered": _r(f.covered, 3), "offset_mm": _r(f.offset_mm, 2),
                "residual_mm": _r(result.registration.residual_mm, 2)}

    return [row("*", result.scores.overall)] + [row(p, f) for p, f in result.scores.parts]


def _r(v: float, n: int) -> object:
    return "" if v is None or not math.isfinite(v) else round(float(v), n)


# ----------------------------------------------------------------------------- together


def score_image(gray: np.ndarray, study: Study, source: str,
                printed: dict[str, np.ndarray] | None = None) -> ScanResult:
    """Score one sheet image of ``study``.

    Args:
        gray: the image, uint8 greyscale.
        study: the study (its sheets' blank images are read on first need).
        source: the image's name in messages (the scan file, and page).
        printed: cache of blank sheet images by sheet name, filled as read.

    Raises:
        StudyError: no code, a code of another study or row, no marks, no strokes.
    """
    found = find_code(gray)
    if found is None:
        raise StudyError(f"{source}: no sheet code found (no h2s sheet in the image, or "
                         f"scanned under 200 dpi)")
    text, corners = found
    parsed = parse_code(text)
    if parsed is None:
        raise StudyError(f"{source}: the QR code says {text[:40]!r}, not an h2s sheet code")
    study_id, row = parsed
    if study_id != study.study_id:
        raise StudyError(f"{source}: a sheet of study {study_id}, not of study "
                         f"{study.study_id} ({study.folder})")
    if not 0 <= row < len(study.drawings):
        raise StudyError(f"{source}: the sheet code names drawing {row}, but study "
                         f"{study.study_id} has {len(study.drawings)}")
    drawing = study.drawings[row]
    key = study.sheets[drawing.sheet]
    cache = {} if printed is None else printed
    if drawing.sheet not in cache:
        cache[drawing.sheet] = read_printed(key)
    blank = cache[drawing.sheet]
    reg = register(gray, key, blank, corners, source=source)
    registered, mask = strokes(gray, reg, key, blank, source=source)
    scores = measure(mask, key, blind_mask(blank, key))
    return ScanResult(source, drawing, key, reg, registered, mask, scores)


def score_scan(path: str | Path, study: Study,
               printed: dict[str, np.ndarray] | None = None) -> tuple[ScanResult, ...]:
    """Score every page of a scan file (one sheet per page).

    Raises:
        StudyError: the first page that cannot be scored, naming the file (and page).
    """
    pages = read_scan(path)
    cache = {} if printed is None else printed
    return tuple(score_image(g, study, str(path) if len(pages) == 1 else f"{path} page {i + 1}",
                             cache)
                 for i, g in enumerate(pages))
