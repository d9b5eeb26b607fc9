"""Config loading: values, defaults, and one-line errors naming file and key path."""

from __future__ import annotations

from pathlib import Path

import pytest

from h2s_print.config import (BookConfig, PaperSpec, TutorialConfig, load_config,
                              load_tutorial)
from h2s_print.errors import ConfigError

from conftest import REPO

GOOD = """\
title: Digital SLR camera
model:
  path: models/camera.glb
  up: z
  units: mm
  parts:
    merge: {body: [body_top, body_bottom]}
    drop: [screw_*]
views:
  - name: front-left
    azimuth_deg: 35
    elevation_deg: 20
    distance: 3.0
    lens_mm: 50
    perspective: two-point
  - name: high
    elevation_deg: 40
    perspective: three-point
levels: [novice, apprentice, master]
paper: {size: A4, orientation: landscape, margin_mm: 12}
solver: {formulation: quadratic, time_limit_s: 60, max_change: 0.10}
"""


def write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def test_good_config_values(tmp_path):
    cfg = load_config(write(tmp_path, "camera.yaml", GOOD))
    assert isinstance(cfg, TutorialConfig)
    assert cfg.name == "camera" and cfg.title == "Digital SLR camera"
    # paths are relative to the config file, not the working directory
    assert cfg.model.path == (tmp_path / "models" / "camera.glb").resolve()
    assert cfg.model.source == "models/camera.glb"  # as written: plan.json is checkout-independent
    assert cfg.model.up == "z" and cfg.model.units == "mm"
    assert cfg.model.parts.merge == (("body", ("body_top", "body_bottom")),)
    assert cfg.model.parts.drop == ("screw_*",)
    assert [v.name for v in cfg.views] == ["front-left", "high"]
    assert cfg.views[0].azimuth_deg == 35.0 and cfg.views[0].perspective == "two-point"
    # unspecified view fields take their documented defaults
    assert cfg.views[1].azimuth_deg == 35.0 and cfg.views[1].lens_mm == 50.0
    assert cfg.levels == ("novice", "apprentice", "master")
    assert cfg.solver.max_change == pytest.approx(0.10)
    assert cfg.solver.formulation == "quadratic"


def test_values_are_frozen(tmp_path):
    cfg = load_tutorial(write(tmp_path, "camera.yaml", GOOD))
    with pytest.raises(AttributeError):
        cfg.title = "x"  # type: ignore[misc]


@pytest.mark.parametrize(
    "size, orientation, width, height",
    [
        ("A4", "landscape", 297.0, 210.0),  # ISO 216: 210 x 297 mm, turned
        ("A4", "portrait", 210.0, 297.0),
        ("A3", "landscape", 420.0, 297.0),  # A3 = two A4 side by side
        ("Letter", "portrait", 215.9, 279.4),  # 8.5 x 11 in * 25.4 mm/in
    ],
)
def test_paper_sizes(size, orientation, width, height):
    paper = PaperSpec(size=size, orientation=orientation)
    assert paper.width_mm == width and paper.height_mm == height


@pytest.mark.parametrize(
    "old, new, message",
    [
        ("elevation_deg: 40", "elevation_deg: high",
         "camera.yaml: views[1].elevation_deg: expected a number, got 'high'"),
        ("elevation_deg: 40", "elevation_deg: 95",
         "camera.yaml: views[1].elevation_deg: must be <= 89, got 95"),
        ("lens_mm: 50", "lense_mm: 50",
         "camera.yaml: views[0].lense_mm: unknown key"),
        ("perspective: three-point", "perspective: fisheye",
         "camera.yaml: views[1].perspective: expected one of two-point, three-point, got 'fisheye'"),
        ("levels: [novice, apprentice, master]", "levels: [novice, expert]",
         "camera.yaml: levels[1]: expected one of novice, apprentice, master, basic, got 'expert'"),
        ("size: A4", "size: A5", "camera.yaml: paper.size: expected one of A4, A3, Letter, got 'A5'"),
        ("margin_mm: 12", "margin_mm: 2", "camera.yaml: paper.margin_mm: must be >= 5, got 2"),
        ("max_change: 0.10", "max_change: -1", "camera.yaml: solver.max_change: must be > 0"),
        ("formulation: quadratic", "formulation: gurobi",
         "camera.yaml: solver.formulation: expected one of quadratic, linear"),
        ("  - name: high", "  - name: front-left", "views[1].name: duplicate view name"),
        ("distance: 3.0", "distance: 0.5", "camera.yaml: views[0].distance: must be > 1"),
        ("title: Digital SLR camera", "titel: x", "camera.yaml: titel: unknown key"),
        ("  up: z", "  up: w", "camera.yaml: model.up: expected one of x, y, z, got 'w'"),
        ("merge: {body:", "merge: {lens<body#1:",
         "camera.yaml: model.parts.merge.lens<body#1: expected a part name"),
    ],
)
def test_errors_name_file_and_key_path(tmp_path, old, new, message):
    assert old in GOOD
    path = write(tmp_path, "camera.yaml", GOOD.replace(old, new, 1))
    with pytest.raises(ConfigError) as info:
        load_config(path)
    text = str(info.value)
    assert message in text
    assert "\n" not in text  # one line


def test_missing_required_keys(tmp_path):
    with pytest.raises(ConfigError, match=r"^x\.yaml: views: missing \(required\)$"):
        load_config(write(tmp_path, "x.yaml", "model: m.glb\n"))
    with pytest.raises(ConfigError, match=r"^x\.yaml: empty config"):
        load_config(write(tmp_path, "x.yaml", ""))


def test_bad_yaml_and_missing_file(tmp_path):
    with pytest.raises(ConfigError, match=r"^x\.yaml: line 2: invalid YAML"):
        load_config(write(tmp_path, "x.yaml", "a: [1, 2\nb: c: d\n"))
    with pytest.raises(ConfigError, match="file not found"):
        load_config(tmp_path / "nope.yaml")


def test_yaml_tags_are_never_executed(tmp_path):
    evil = "title: !!python/object/apply:os.system ['touch pwned']\nmodel: m.glb\nviews: []\n"
    with pytest.raises(ConfigError, match="invalid YAML"):
        load_config(write(tmp_path, "x.yaml", evil))
    assert not (tmp_path / "pwned").exists()


def test_book_resolves_tutorials_and_rejects_itself(tmp_path):
    write(tmp_path, "camera.yaml", GOOD)
    book = load_config(write(tmp_path, "book.yaml", "title: B\ntutorials: [camera.yaml]\n"))
    assert isinstance(book, BookConfig)
    assert [t.name for t in book.tutorials] == ["camera"]
    with pytest.raises(ConfigError, match=r"book\.yaml: tutorials\[0\]: 'book\.yaml' names this book"):
        load_config(write(tmp_path, "book.yaml", "tutorials: [book.yaml]\n"))
    with pytest.raises(ConfigError, match=r"tutorials\[1\]: 'mixer\.yaml': file not found"):
        load_config(write(tmp_path, "book.yaml", "tutorials: [camera.yaml, mixer.yaml]\n"))
    # errors inside a tutorial name that tutorial's file
    write(tmp_path, "bad.yaml", GOOD.replace("lens_mm: 50", "lens_mm: fifty"))
    with pytest.raises(ConfigError, match=r"^bad\.yaml: views\[0\]\.lens_mm"):
        load_config(write(tmp_path, "book.yaml", "tutorials: [bad.yaml]\n"))


def test_sheet_grid_option(tmp_path):
    assert load_config(write(tmp_path, "a.yaml", GOOD)).sheet.grid is False
    cfg = load_config(write(tmp_path, "b.yaml", GOOD + "sheet: {grid: true}\n"))
    assert cfg.sheet.grid is True
    with pytest.raises(ConfigError, match=r"^c\.yaml: sheet\.grid: "):
        load_config(write(tmp_path, "c.yaml", GOOD + "sheet: {grid: often}\n"))
    with pytest.raises(ConfigError, match=r"^d\.yaml: sheet\.grd: unknown key"):
        load_config(write(tmp_path, "d.yaml", GOOD + "sheet: {grd: true}\n"))


def test_parts_split_option(tmp_path):
    assert load_config(write(tmp_path, "a.yaml", GOOD)).model.parts.split is True
    text = GOOD.replace("    drop: [screw_*]", "    drop: [screw_*]\n    split: false", 1)
    assert text != GOOD
    assert load_config(write(tmp_path, "b.yaml", text)).model.parts.split is False
    bad = GOOD.replace("    drop: [screw_*]", "    drop: [screw_*]\n    split: sometimes", 1)
    with pytest.raises(ConfigError, match=r"^c\.yaml: model\.parts\.split: "):
        load_config(write(tmp_path, "c.yaml", bad))


@pytest.mark.parametrize("edit, message", [
    (lambda t: t + "title: Another camera\n",
     "camera.yaml: title: key given twice (lines 1 and 22)"),
    (lambda t: t.replace("    elevation_deg: 40\n", "    elevation_deg: 40\n    elevation_deg: 45\n"),
     "camera.yaml: views[1].elevation_deg: key given twice (lines 17 and 18)"),
    (lambda t: t.replace("  up: z\n", "  up: z\n  units: m\n"),
     "camera.yaml: model.units: key given twice (lines 5 and 6)"),
    (lambda t: t.replace("{size: A4, orientation", "{size: A4, size: A3, orientation"),
     "camera.yaml: paper.size: key given twice (lines 20 and 20)"),
])
def test_a_key_given_twice_is_an_error_naming_it(tmp_path, edit, message):
    """Plain YAML keeps the last of two equal keys without a word; a config must not (issue
    15): the same typo guard as unknown keys, with the key path and both lines."""
    with pytest.raises(ConfigError) as exc:
        load_config(write(tmp_path, "camera.yaml", edit(GOOD)))
    assert str(exc.value) == message


def test_a_key_given_twice_in_a_books_tutorial_is_an_error(tmp_path):
    write(tmp_path, "camera.yaml", GOOD.replace("  up: z\n", "  up: z\n  up: y\n"))
    book = write(tmp_path, "book.yaml", "title: Book\ntutorials: [camera.yaml]\n")
    with pytest.raises(ConfigError, match=r"camera.yaml: model.up: key given twice"):
        load_config(book)


def test_yaml_merge_keys_may_still_override():
    from h2s_print.yamlfile import read_yaml
    data = read_yaml("base: &b {size: A4, margin_mm: 12}\npaper:\n  <<: *b\n  size: A3\n")
    assert data["paper"] == {"size": "A3", "margin_mm": 12}


def test_the_fast_yaml_reader_reads_what_the_pure_one_reads():
    """LibYAML (when PyYAML has it) reads every shipped YAML file as the pure Python loader
    does, and a text it refuses is reported in the pure loader's words."""
    import yaml

    from h2s_print import yamlfile

    root = Path(__file__).resolve().parents[1]
    files = sorted(root.glob("templates/**/*.yaml")) + sorted(root.glob("configs/*.yaml")) \
        + sorted(root.glob("benchmarks/configs/*.yaml"))
    assert len(files) > 20
    for f in files:
        text = f.read_text(encoding="utf-8")
        assert yamlfile.read_yaml(text) == yaml.load(text, Loader=yaml.SafeLoader), f
    with pytest.raises(yaml.YAMLError, match=r"found character '\\t' that cannot start"):
        yamlfile.read_yaml("\t a: 1\n")


def test_the_shipped_templates_pass_their_own_check():
    from h2s_print import templates
    templates.load.cache_clear()
    assert templates.load("steps") and templates.load("pages")


@pytest.mark.parametrize("title, ok", [("Appareil photo reflex numérique", True),
                                       ("Kamera – Übung 1 ½", True),
                                       ("Фотоаппарат", True), ("Φωτογραφική μηχανή", True),
                                       ("相机", False)])
def test_a_title_the_page_font_cannot_print_is_an_error_not_question_marks(tmp_path, title, ok):
    """Before, a Cyrillic title printed as '???????????' on every page with no word.  The
    default font (DejaVu Sans) prints Latin, Greek and Cyrillic; a character it lacks (Chinese)
    is an error naming the field, the character and the remedy (the brief: a character that
    cannot be printed, say so)."""
    path = write(tmp_path, "camera.yaml", GOOD.replace("Digital SLR camera", title))
    if ok:
        assert load_config(path).title == title
        return
    with pytest.raises(ConfigError) as exc:
        load_config(path)
    assert str(exc.value).startswith(f"camera.yaml: title: character {title[0]!r} (U+")
    assert "cannot be printed in the page font (DejaVu Sans)" in str(exc.value)
    assert "config 'font:'" in str(exc.value)


@pytest.mark.parametrize("text, message", [
    # a translator's duplicated key is named, not silently replaced
    ("headline:\n  first: A\n  first: B\n",
     r"headline.first: key given twice \(lines 2 and 3\)"),
    # a typo in a placeholder is a clear error when the wording is read, not a KeyError in
    # the middle of a build (issue 15)
    ("headline:\n  first: \"{Prat}: the first {shape}.\"\n",
     r"headline.first: unknown placeholder \{Prat\}"),
    ("headline:\n  first: \"{Part: the first {shape}.\"\n", r"headline.first: not a valid template"),
    ("substep:\n  edge: \"Use the edge {}.\"\n", r"substep.edge: unknown placeholder \{\}"),
    # a character the page font cannot print
    ("headline:\n  first: \"{Part}: 第一 {shape}.\"\n",
     r"headline.first: character '第' \(U\+7B2C .*\) cannot be printed in the page font "
     r"\(DejaVu Sans\)"),
])
def test_a_bad_template_file_is_refused_when_read(tmp_path, monkeypatch, text, message):
    import shutil

    from h2s_print import templates
    from h2s_print.errors import H2SError

    for other in (REPO / "templates").glob("*.yaml"):
        shutil.copy(other, tmp_path)
    (tmp_path / "steps.yaml").write_text(text)
    monkeypatch.setattr(templates, "_folder", lambda: tmp_path)
    templates.load.cache_clear()
    templates.check_font.cache_clear()
    try:
        with pytest.raises(H2SError, match=message):
            templates.load("steps")
            templates.check_font()  # what the command line runs before any work
    finally:
        templates.load.cache_clear()
        templates.check_font.cache_clear()
