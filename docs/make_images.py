"""Render one image of each page kind into docs/ (shown in the README).

Run: ``python3 docs/make_images.py`` (from the repository root).  Uses the project's own
renderer (``render_png``, through cairosvg) on the camera example, front-left view, novice.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from h2s_print.config import load_tutorial  # noqa: E402
from h2s_print.layout import lay_out_book, lay_out_workbook  # noqa: E402
from h2s_print.pipeline import plan_tutorial  # noqa: E402
from h2s_print.render import render_png  # noqa: E402

DPI = 60


def main() -> None:
    tutorial = load_tutorial(ROOT / "configs" / "camera.yaml")
    result = plan_tutorial(tutorial)
    view = result.views[0]  # front-left, novice: one step per page
    pages = lay_out_workbook(tutorial.title, view, tutorial.paper, view_label=view.name,
                             final=result.finals[0])
    steps = [p for p in pages if p.kind == "steps"]
    first = {}  # first step page of each step kind
    chosen = result.plan.chosen()
    for page, step in zip(steps, view.steps):
        first.setdefault(step.kind, page)
        if (step.kind == "primitive" and not step.eyeball and step.part and step.guides
                and chosen[step.part].anchors):  # (the first box's guides are the sheet's)
            if any(a.end == "mid" for a in chosen[step.part].anchors):
                first.setdefault("midplane", page)  # centred on a common bisector plane
            else:
                first.setdefault("anchored", page)  # ends at ratios and extensions only
    for page, step in zip(steps, view.steps):
        if step.kind == "guides":
            first.setdefault("guides", page)  # lettered construction sub-steps
    master = next(v for v in result.views if v.name == view.name and v.level == "master")
    master_pages = lay_out_workbook(tutorial.title, master, tutorial.paper,
                                    view_label=master.name)
    apprentice = next(v for v in result.views
                      if v.name == view.name and v.level == "apprentice")
    apprentice_pages = lay_out_workbook(tutorial.title, apprentice, tutorial.paper,
                                        view_label=apprentice.name)
    train = load_tutorial(ROOT / "configs" / "train.yaml")
    tres = plan_tutorial(train)
    tview = tres.views[0]
    tpages = lay_out_workbook(train.title, tview, train.paper, view_label=tview.name,
                              final=tres.finals[0])
    tsteps = [p for p in tpages if p.kind == "steps"]
    repeat = next(pg for pg, st in zip(tsteps, tview.steps)
                  if st.kind == "primitive" and len({s.part for s in st.strokes}) > 1)
    # a side in line with the sheet's floor line's foot, on a line drawn from the foot (the
    # wheels' backs, in the engine's front)
    floor = next(pg for pg, st in zip(tsteps, tview.steps)
                 if any(x.endswith("stands on it.") for x in st.substeps))
    wanted = {
        "page-step-first": steps[0],  # the first box on the sheet's printed lines
        "page-step-floor": floor,
        "page-step-guides": first["guides"],
        "page-step-master": [p for p in master_pages if p.kind == "steps"][1],
        # the grip's guides: the construction by name, the result line drawn
        "page-step-apprentice": [p for p in apprentice_pages if p.kind == "steps"][1],
        "page-step-repeat": repeat,
        "page-cover": next(p for p in pages if p.kind == "cover"),
        "page-primer": next(p for p in pages if p.kind == "primer"),
        "page-step-anchored": first["anchored"],
        "page-step-midplane": first["midplane"],
        "page-step-ellipse": first["ellipse"],
        "page-step-contour": first["contour"],
        "page-final": next(p for p in pages if p.kind == "final"),
        "page-sheet": next(p for p in pages if p.kind == "sheet"),
        "page-contents": lay_out_book("Sketching everyday objects",
                                      [(f"{tutorial.title} > {view.name} > {view.level}", pages)])[1],
    }
    wanted["page-step-spacing"] = _spacing_page()
    wanted["page-step-bowl"], wanted["page-step-close-up"] = _round_pages()
    wanted["page-step-crossing"] = _crossing_page()
    # the flash's sides carried over the lens's top and up the body's front, turning only
    # where drawn edges cross their planes (sequence.geometry._walk_carry)
    wanted["page-step-walk"] = next(pg for pg, st in zip(steps, view.steps)
                                    if any(", vertically to " in x for x in st.substeps))
    wanted["page-cyrillic"] = _cyrillic_page()
    cjk = _cjk_page()
    if cjk is not None:
        wanted["page-cjk"] = cjk
    for name, page in wanted.items():
        path = ROOT / "docs" / f"{name}.png"
        path.write_bytes(render_png(page, dpi=DPI))
        print(path.relative_to(ROOT))


def _spacing_page():
    """The equal-spacing step of a generated model: four identical knobs, evenly spaced, on
    a base (made here, like the examples, by the project's own code)."""
    import tempfile

    import numpy as np
    import trimesh

    from h2s_print.config import ModelSpec, PaperSpec, SequenceSettings, SolverSettings, ViewSpec
    from h2s_print.plan import build_plan
    from h2s_print.sequence import sequence_view

    scene = trimesh.Scene()
    base = trimesh.creation.box((400.0, 200.0, 40.0))
    knob = trimesh.creation.box((40.0, 30.0, 60.0))
    to_gltf = trimesh.transformations.rotation_matrix(-np.pi / 2, [1, 0, 0])  # z-up -> y-up
    scene.add_geometry(base, node_name="base", geom_name="base",
                       transform=to_gltf @ trimesh.transformations.translation_matrix((0, 0, 20)))
    for i, x in enumerate((-170.0, -90.0, -10.0, 70.0)):
        scene.add_geometry(knob, node_name=f"knob_{i + 1}", geom_name="knob",
                           transform=to_gltf @ trimesh.transformations.translation_matrix(
                               (x, 0.0, 70.0)))
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "knobs.glb"
        scene.export(path)
        plan = build_plan(ModelSpec(path, units="mm"), SolverSettings())
    view = ViewSpec("front-left", azimuth_deg=-35.0, elevation_deg=25.0, distance=3.0,
                    lens_mm=50.0, perspective="two-point")
    paper = PaperSpec("A4", "landscape", 12.0)
    vp = sequence_view(plan, view, "novice", paper, SequenceSettings())
    pages = [p for p in lay_out_workbook("A row of knobs", vp, paper, view_label=view.name)
             if p.kind == "steps"]
    last = max(k for k, st in enumerate(vp.steps) if st.kind == "primitive")
    return pages[last]  # knobs 3 and 4, spaced like knobs 1 and 2


def _crossing_page():
    """The roller's handle's guides (front-left, novice): its two centring lines carried until
    they cross on the roller's common bisector planes, and its top carried from where one of
    them crosses the line that places it ("Extend GF to NP, meeting it at R; ...")."""
    tutorial = load_tutorial(ROOT / "configs" / "roller.yaml")
    result = plan_tutorial(tutorial)
    view = next(v for v in result.views if v.name == "front-left" and v.level == "novice")
    pages = [p for p in lay_out_workbook(tutorial.title, view, tutorial.paper,
                                         view_label=view.name) if p.kind == "steps"]
    return next(pg for pg, st in zip(pages, view.steps)
                if any("until they cross at" in x for x in st.substeps)
                and any("meeting it at" in x for x in st.substeps))


def _round_pages():
    """The mixer's bowl (a round tapered part): the ellipse of its rim constructed in the top
    of its tapered box (front-left, novice); and the roller's handle, whose crowded letters
    get a close-up (high-right, novice)."""
    out = []
    for name, view_name, part in (("mixer", "front-left", "bowl"), ("roller", "high-right", "handle")):
        tutorial = load_tutorial(ROOT / "configs" / f"{name}.yaml")
        result = plan_tutorial(tutorial)
        view = next(v for v in result.views if v.name == view_name and v.level == "novice")
        pages = [p for p in lay_out_workbook(tutorial.title, view, tutorial.paper,
                                             view_label=view.name) if p.kind == "steps"]
        k = next(k for k, st in enumerate(view.steps) if st.kind == "ellipse" and st.part == part)
        out.append(pages[k])
    return tuple(out)


def _cyrillic_page():
    """A step page of the camera in Russian, with a Russian title and part names, in the
    default font."""
    return _camera_page("title: Зеркальный фотоаппарат\nlanguage: ru",
                        "{body: корпус, lens: объектив, grip: рукоятка}")


CJK_FONT = Path("/usr/share/fonts/truetype/wqy/wqy-microhei.ttc")  # Debian fonts-wqy-microhei


def _cjk_page():
    """A step page of the camera with a Chinese title and part names, in a CJK font given by
    ``font:`` (the wording stays English: no Chinese translation is shipped)."""
    if not CJK_FONT.is_file():
        print(f"skipped page-cjk.png: {CJK_FONT} not installed (Debian fonts-wqy-microhei)")
        return None
    return _camera_page(f"title: 单反相机\nfont: {CJK_FONT}", "{body: 机身, lens: 镜头, grip: 手柄}")


def _camera_page(title: str, rename: str):
    """The camera's third step page (novice, front-left) with ``title`` (and other top-level
    keys) and parts renamed by ``rename``."""
    import tempfile

    from h2s_print import fonts, templates

    text = (ROOT / "configs" / "camera.yaml").read_text(encoding="utf-8")
    text = text.replace("models/camera.glb", str(ROOT / "configs" / "models" / "camera.glb"))
    text = text.replace("title: Digital SLR camera", title)
    text = text.replace("  units: mm                 # the examples are modelled in millimetres",
                        f"  units: mm\n  parts: {{rename: {rename}}}")
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "camera.yaml"
        path.write_text(text, encoding="utf-8")
        tutorial = load_tutorial(path)
        result = plan_tutorial(tutorial)
    view = result.views[0]
    with fonts.using(tutorial.font), templates.using(tutorial.language):
        pages = lay_out_workbook(tutorial.title, view, tutorial.paper, view_label=view.name,
                                 final=result.finals[0])
    return [p for p in pages if p.kind == "steps"][2]


if __name__ == "__main__":
    main()
