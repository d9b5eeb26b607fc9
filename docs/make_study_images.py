"""Render the README's drawing-study images into docs/ (issue 14).

Run: ``python docs/make_study_images.py`` (from the repository root; a minute).  Builds
``configs/study.yaml`` in a temporary folder, then plays a study through: six camera sheets
are "scanned" (rendered from their packets, pencilled with the model's lines moved by known
amounts, rotated and noised: the synthetic scans of the tests, ``tests/_scans.py``), scored
with ``h2s score``, paired with ``h2s rank`` and ranked from judgments that prefer the smaller
error.  Writes ``study-cover.png``, ``study-sheet-stamp.png``, ``study-questionnaire.png``,
``study-overlay.png``, ``study-pair.png`` and ``study-strengths.png``.
"""

from __future__ import annotations

import csv
import io
import math
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

import cv2  # noqa: E402
import numpy as np  # noqa: E402
import pypdfium2 as pdfium  # noqa: E402

from _scans import RENDER_DPI, pencil, scan  # noqa: E402
from h2s_print.cli import main as h2s  # noqa: E402
from h2s_print.studyfile import read_study  # noqa: E402

DOCS = ROOT / "docs"
ERRORS_MM = (0.5, 1.0, 1.5, 2.5, 3.5, 5.0)


def _page(pdf: Path, index: int, dpi: float) -> np.ndarray:
    page = pdfium.PdfDocument(str(pdf))[index]
    return np.asarray(page.render(scale=dpi / 72, grayscale=True).to_pil().convert("L"))


def _save(name: str, img: np.ndarray, width: int) -> None:
    h, w = img.shape[:2]
    small = cv2.resize(img, (width, round(h * width / w)), interpolation=cv2.INTER_AREA)
    cv2.imwrite(str(DOCS / name), small, [cv2.IMWRITE_PNG_COMPRESSION, 9])


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp)
        assert h2s(["-q", "study", str(ROOT / "configs" / "study.yaml"), "-o", str(out)]) == 0
        folder = out / "study"
        study = read_study(folder)
        cams = [d for d in study.drawings if d.object == "camera"][:6]
        first = folder / "packets" / f"{cams[0].participant}.pdf"
        doc = pdfium.PdfDocument(str(first))
        texts = [doc[i].get_textpage().get_text_range() for i in range(len(doc))]
        sheets = [i for i, t in enumerate(texts) if "this bar measures 100 mm" in t]
        quest = next(i for i, t in enumerate(texts) if t.startswith("After drawing"))
        _save("study-cover.png", _page(first, 0, 60), 420)
        _save("study-questionnaire.png", _page(first, quest, 60), 420)
        scans = []
        for d, err in zip(cams, ERRORS_MM):
            pdf = folder / "packets" / f"{d.participant}.pdf"
            doc = pdfium.PdfDocument(str(pdf))
            idx = [i for i in range(len(doc))
                   if "this bar measures 100 mm" in doc[i].get_textpage().get_text_range()
                   ][d.order - 1]
            page = _page(pdf, idx, RENDER_DPI)
            if d is cams[0]:
                h, w = page.shape
                _save("study-sheet-stamp.png", page[int(h * 0.93):, int(w * 0.45):], 700)
            key = study.sheets[d.sheet]
            rng = np.random.default_rng(d.row)
            moves = {p: (err * math.cos(a), err * math.sin(a))
                     for p, a in ((p, rng.uniform(0, 2 * math.pi)) for p, _ in key.lines)}
            img, _ = scan(pencil(page, key, moves, jitter_mm=0.3, seed=d.row), key,
                          angle_deg=-4.0 + 3 * d.row, dpi=220, perspective=0.03, noise=3.0,
                          light=0.25, jpeg=85, seed=d.row)
            path = out / f"scan-{d.participant}.jpg"
            path.write_bytes(cv2.imencode(".jpg", img, [cv2.IMWRITE_JPEG_QUALITY, 85])[1])
            scans.append(path)
        del sheets
        assert h2s(["-q", "score", *map(str, scans), "--study", str(folder)]) == 0
        d = cams[2]
        overlay = cv2.imread(str(folder / "scores" / "overlays"
                                 / f"{d.row}-{d.participant}-camera.png"))
        _save("study-overlay.png", overlay, 700)
        assert h2s(["-q", "rank", str(folder)]) == 0
        _save("study-pair.png", _page(folder / "rank" / "pairs.pdf", 0, 60), 600)
        rows = list(csv.DictReader(io.StringIO(
            (folder / "rank" / "judgments.csv").read_text())))
        error = {d.row: e for d, e in zip(cams, ERRORS_MM)}
        rng = np.random.default_rng(1)
        for r in rows:  # raters who mostly prefer the smaller error
            a, b = error[int(r["a"])], error[int(r["b"])]
            p_a = 1 / (1 + math.exp(a - b))
            r["winner"] = "a" if rng.random() < p_a else "b"
        filled = out / "judged.csv"
        with filled.open("w", newline="") as fh:
            writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows * 5)
        assert h2s(["-q", "rank", str(folder), "--judgments", str(filled)]) == 0
        plot = cv2.imread(str(folder / "rank" / "camera.png"))
        _save("study-strengths.png", plot, 600)
        print((folder / "scores" / "scores.csv").read_text())
        print((folder / "rank" / "conditions.csv").read_text())


if __name__ == "__main__":
    main()
