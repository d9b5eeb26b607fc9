"""The page font (issue 15): an embedded Unicode font, measured as drawn, in any script it has.

The CJK case needs a font with Chinese glyphs; none is installed here, so the test builds one
with fontTools: a box glyph for every character the templates use plus 相 and 机.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from h2s_print import fonts
from h2s_print.cli import main

from conftest import CONFIGS

CJK_TITLE = "相机"


def _box_font(path: Path, extra: str = "", without: str = "") -> Path:
    """A TrueType font whose every glyph is a box, for the printable ASCII, Latin-1, general
    punctuation, arrows, number forms and ``extra`` characters, but not ``without``."""
    from fontTools.fontBuilder import FontBuilder
    from fontTools.pens.ttGlyphPen import TTGlyphPen

    codes = [*range(0x20, 0x7F), *range(0xA0, 0x180), *range(0x2000, 0x2070),
             *range(0x2150, 0x2190), *range(0x2190, 0x2200), *range(0x2200, 0x2300),
             *map(ord, extra)]
    codes = [c for c in codes if chr(c) not in without]
    fb = FontBuilder(1000, isTTF=True)
    fb.setupGlyphOrder([".notdef", "box", "space"])
    fb.setupCharacterMap({c: ("space" if c == 0x20 else "box") for c in codes})
    pen = TTGlyphPen(None)
    pen.moveTo((50, 0))
    pen.lineTo((50, 700))
    pen.lineTo((550, 700))
    pen.lineTo((550, 0))
    pen.closePath()
    box = pen.glyph()
    fb.setupGlyf({".notdef": box, "box": box, "space": TTGlyphPen(None).glyph()})
    fb.setupHorizontalMetrics({".notdef": (600, 50), "box": (600, 50), "space": (300, 0)})
    fb.setupHorizontalHeader(ascent=800, descent=-200)
    fb.setupNameTable({"familyName": "H2S Box", "styleName": "Regular"})
    fb.setupOS2(sTypoAscender=800, usWinAscent=800, usWinDescent=200)
    fb.setupPost()
    fb.save(str(path))
    return path


def _camera(tmp_path: Path, text: str) -> Path:
    """configs/camera.yaml edited by ``text`` (appended / replaced), the model path absolute."""
    src = (CONFIGS / "camera.yaml").read_text().replace(
        "models/camera.glb", str(CONFIGS / "models" / "camera.glb"))
    path = tmp_path / "camera.yaml"
    path.write_text(text(src), encoding="utf-8")
    return path


def _pdf_text(path: Path) -> str:
    from pypdf import PdfReader

    return "\n".join(p.extract_text() for p in PdfReader(str(path)).pages)


def test_widths_are_the_font_files_own():
    """Layout measures in the font's own advance widths (read here by fontTools, not by the
    code under test), Cyrillic and Greek included."""
    from fontTools.ttLib import TTFont

    spec = fonts.default_spec()
    tt = TTFont(str(spec.bold))
    em, cmap, hmtx = tt["head"].unitsPerEm, tt.getBestCmap(), tt["hmtx"]
    text = "Камера Ψ 12"
    want = sum(hmtx[cmap[ord(c)]][0] for c in text) / em * 9 * 25.4 / 72
    assert fonts.width_mm(text, 9, "Helvetica-Bold") == pytest.approx(want)


def test_a_width_is_the_sum_of_its_advances_in_order_exactly():
    """The summing shortcut adds the same advances in the same order (a lacking character
    counts the default advance), so widths, and the layout they place, are the same floats."""
    spec = fonts.default_spec()
    face = fonts.face(spec.path("Helvetica"))
    text = "Step 12: Камера Ψ — ½ \U0001F600 x"
    want = 0
    for ch in text:
        want += face.widths.get(ord(ch), face.default_width)
    assert fonts._em_width.__wrapped__(spec, "Helvetica", text) == want


def test_code_points_read_from_the_cmap_are_reportlabs(tmp_path):
    """The cmap reader (fonts._cmap_points, what ``h2s plan`` checks the wording with) gives
    exactly the code points ReportLab's loaded face has widths for, on every font matplotlib
    ships (cmap formats 4, 12 and 13, Macintosh and Windows records, maxp limits) and the box
    font built here; a font it does not read still gets ReportLab's set."""
    folder = fonts.default_spec().regular.parent
    files = sorted(folder.glob("*.ttf")) + [_box_font(tmp_path / "box.ttf", extra="相机")]
    assert len(files) > 30
    for path in files:
        fast = fonts._cmap_points(path.read_bytes())
        assert fast is not None, path.name
        assert fast == frozenset(fonts.face(path).widths), path.name
    assert fonts._cmap_points(b"OTTO" + bytes(64)) is None  # PostScript outlines: ReportLab's
    spec = fonts.default_spec()
    assert fonts.coverage(spec) == frozenset.intersection(
        *(frozenset(fonts.face(spec.path(s)).widths) for s in fonts.STYLES))


def test_specs_that_differ_only_in_paths_stay_apart():
    """A spec hashes by its name alone: equal specs hash alike, and specs of one name but
    other files are still different keys."""
    a = fonts.default_spec()
    b = fonts.FontSpec(a.bold, a.bold, a.bold, a.name)
    assert hash(a) == hash(fonts.FontSpec(a.regular, a.bold, a.oblique, a.name))
    assert a != b and len({a: 1, b: 2}) == 2


def test_png_text_is_drawn_in_the_same_font():
    """cairo (the PNG pages) is given the page font's files, so the width it measures for a
    text is the layout's (within 1 %), not a substitute's."""
    from h2s_print.layout import Text
    from h2s_print.render import _cairo_width_mm

    spec = fonts.default_spec()
    for style in fonts.STYLES:
        fonts.fontconfig_add(spec.path(style))
        item = Text(0, 0, "Фотоаппарат: the body's front face", 10, style)
        assert _cairo_width_mm(item, spec) == pytest.approx(
            fonts.width_mm(item.string, 10, style), rel=0.01)


def test_cyrillic_title_and_part_names_print_in_the_default_font(tmp_path):
    config = _camera(tmp_path, lambda s: s.replace(
        "title: Digital SLR camera", "title: Зеркальный фотоаппарат").replace(
        "  units: mm                 # the examples are modelled in millimetres",
        "  units: mm\n  parts: {rename: {body: корпус, lens: объектив}}"))
    out = tmp_path / "out"
    assert main(["-q", "build", str(config), "-o", str(out)]) == 0
    pdf = out / "camera" / "camera-front-left-novice.pdf"
    text = _pdf_text(pdf)
    assert "Зеркальный фотоаппарат" in text and "корпус" in text and "объектив" in text
    assert "?" not in text.replace("?)", "")  # nothing substituted
    from pypdf import PdfReader

    fonts_used = {f["/BaseFont"] for p in PdfReader(str(pdf)).pages
                  for f in p["/Resources"]["/Font"].values()}
    assert any(str(f).endswith("+DejaVuSans") for f in fonts_used)  # embedded subset


def test_a_cjk_title_needs_a_font_that_has_it(tmp_path, capsys):
    config = _camera(tmp_path, lambda s: s.replace("title: Digital SLR camera",
                                                   f"title: {CJK_TITLE}"))
    assert main(["build", str(config), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0
    assert "camera.yaml: title: character '相' (U+76F8" in err
    assert "cannot be printed in the page font (DejaVu Sans)" in err
    assert not (tmp_path / "out" / "camera").exists()


def test_a_cjk_title_prints_with_a_font_that_has_it(tmp_path):
    _box_font(tmp_path / "box.ttf", CJK_TITLE + "·–…’“”")
    config = _camera(tmp_path, lambda s: s.replace(
        "title: Digital SLR camera", f"title: {CJK_TITLE}\nfont: box.ttf"))
    out = tmp_path / "out"
    assert main(["-q", "build", str(config), "-o", str(out)]) == 0
    text = _pdf_text(out / "camera" / "camera-front-left-novice.pdf")
    assert CJK_TITLE in text


def test_a_font_lacking_a_character_is_named(tmp_path, capsys):
    """A font without a character the wording uses (the footers' middle dot): the error names
    the template file, key and character before any work, never '?' on a page; a font
    without a title's character names the title."""
    font = _box_font(tmp_path / "latin.ttf")
    shutil.copy(font, tmp_path / "latin2.ttf")
    config = _camera(tmp_path, lambda s: s + "font: {regular: latin.ttf, bold: latin2.ttf}\n")
    out = tmp_path / "out"
    assert main(["-q", "plan", str(config), "-o", str(out)]) == 0  # it has all the wording
    _box_font(tmp_path / "nodot.ttf", without="·")
    config = _camera(tmp_path, lambda s: s + "font: nodot.ttf\n")
    assert main(["-q", "plan", str(config), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "templates" in err
    assert "character '·' (U+00B7 MIDDLE DOT) cannot be printed in the page font (nodot.ttf)" in err
    bad = _camera(tmp_path, lambda s: s.replace("title: Digital SLR camera",
                                                "title: Kamera Ж\nfont: latin.ttf"))
    assert main(["plan", str(bad), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "title: character 'Ж'" in err and "(latin.ttf)" in err


@pytest.mark.parametrize("value, message", [
    ("nothere.ttf", "font: 'nothere.ttf': file not found"),
    ("{bold: a.ttf}", "font.regular: missing"),
    ("not_a_font.ttf", "font: 'not_a_font.ttf': cannot be used as the page font"),
])
def test_bad_font_keys_say_where(tmp_path, capsys, value, message):
    (tmp_path / "not_a_font.ttf").write_bytes(b"this is not a font")
    config = _camera(tmp_path, lambda s: s + f"font: {value}\n")
    assert main(["plan", str(config), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and f"camera.yaml: {message}" in err, err


def _installed_cjk_font() -> Path | None:
    """A TrueType-outlined CJK font fontconfig knows (ReportLab embeds TrueType outlines only:
    Noto CJK's PostScript outlines are refused), or None."""
    import subprocess

    try:
        out = subprocess.run(["fc-list", ":lang=zh", "file"], capture_output=True, text=True,
                             timeout=20).stdout
    except (OSError, subprocess.SubprocessError):
        return None
    for line in sorted(out.splitlines()):
        path = Path(line.split(":")[0].strip())
        try:
            if fonts.face(path).has("相"):
                return path
        except fonts.FontError:
            continue
    return None


def test_a_real_cjk_font_prints_a_chinese_title_and_part_names(tmp_path):
    path = _installed_cjk_font()
    if path is None:
        pytest.skip("no TrueType-outlined CJK font installed (Debian: fonts-wqy-microhei); "
                    "the box font above covers the mechanism")
    config = _camera(tmp_path, lambda s: s.replace(
        "title: Digital SLR camera", f"title: 单反{CJK_TITLE}\nfont: {path}").replace(
        "  units: mm                 # the examples are modelled in millimetres",
        "  units: mm\n  parts: {rename: {body: 机身, lens: 镜头}}"))
    out = tmp_path / "out"
    assert main(["-q", "build", str(config), "-o", str(out)]) == 0
    text = _pdf_text(out / "camera" / "camera-front-left-novice.pdf")
    assert f"单反{CJK_TITLE}" in text and "机身" in text and "镜头" in text
