"""The words of a view's texts: templates, face and side names, vanishing points, lists."""

from __future__ import annotations

import functools
import re
from typing import Any, Callable, Iterable, Sequence

import numpy as np

from .. import templates
from ..constructions import Face
from ..instructions import Spec
from ..project import vp_side
from ..ratios import entry_for
from ..types import Box, Camera, VanishingPoint, Vec3

_XYZ = "xyz"


def _t(key: str, **fields: Any) -> str:
    for k in ("part", "parent", "other"):  # names are identifiers: "shutter_button" -> "shutter button"
        if isinstance(fields.get(k), str):
            fields[k] = fields[k].replace("_", " ")
            fields.setdefault(f"the_{k}", _the(fields[k]))
    return templates.text("steps", key, **fields)


_the = templates.the


def _guides_of(n: int, total: int, **fields: Any) -> str:
    """The headline of the ``n``-th of ``total`` guides steps for one part: "Second guides
    for the flash, on the lens." (by ordinal: "(2/3)" read as the primer's two thirds), past
    the ordinals "Guides for the flash (13 of 14), ..."."""
    ordinals = _raw("ordinals")
    if 1 <= n <= len(ordinals):
        return _t("headline.guides_of", nth=ordinals[n - 1], **fields)
    return _t("headline.guides_of_many", n=n, total=total, **fields)


def _raw(key: str) -> Any:
    return templates.lookup("steps", key)


class _Words:
    """Names of faces, sides, dimensions and vanishing points for this view's texts.

    Vanishing points: :func:`h2s_print.project.vp_side` seen from the sheet's centre (the rule
    the calibrated sheet's labels use, :func:`h2s_print.layout.vp_names`).  The x faces and
    sides are named by the picture: the one of ``x_lo`` / ``x_hi`` whose face centre (of the
    model's bounding box) projects further left is "left" (``swap_x`` when that is ``x_hi``).

    A line drawn *from* a point (or carried) moves one way along its edges: when that way
    leads away from the vanishing point on the sheet, it is said so ("From M, draw MN away
    from the vanishing point below"; a read-through of the high views drew MN downward where
    it rises: "toward the vanishing point below" said the opposite of the picture).
    """

    def __init__(self, camera: Camera, vps: Sequence[VanishingPoint], bounds: Box):
        edges = _raw("edges")
        centre_mm = (camera.paper_mm[0] / 2.0, camera.paper_mm[1] / 2.0)
        keys: dict[int, str] = {}
        for vp in vps:
            side = vp_side(vp, centre_mm)
            if side is not None:
                keys[vp.axis] = side
        self.camera = camera
        self.vps: dict[int, str] = {}
        self.away: dict[int, str] = {}  # the same vanishing points, for lines moving away
        self.at: dict[int, np.ndarray] = {vp.axis: np.asarray(vp.xy_mm, dtype=float)
                                          for vp in vps if vp.axis in keys}
        for vp in vps:
            if vp.axis not in keys:
                self.vps[vp.axis] = (_t("vp.vertical") if vp.axis == 2
                                     else _t("vp.infinite", edges=edges[vp.axis]))
                continue
            key = keys[vp.axis]
            clash = sum(1 for k in keys.values() if k == key) > 1
            for section, phrases in (("vp", self.vps), ("vp_away", self.away)):
                phrases[vp.axis] = (_t(f"{section}.{key}_of", edges=edges[vp.axis]) if clash
                                    else _t(f"{section}.{key}"))
        xs = [Face(bounds, 0, end) for end in ("lo", "hi")]
        cx = camera.project(np.array([np.mean(np.asarray(f.corners, dtype=float), axis=0)
                                      for f in xs]))[:, 0]
        self.swap_x = bool(cx[1] < cx[0])

    def vp(self, axis: int, start: Vec3 | None = None, end: Vec3 | None = None) -> str:
        """The phrase for lines along model axis ``axis``; for a line drawn from ``start``
        to ``end`` (3D), "away from ..." when on the sheet it moves away from the vanishing
        point."""
        if start is None or end is None or axis not in self.at:
            return self.vps[axis]
        s, e = self.camera.project(np.array([start, end], dtype=float))
        v = self.at[axis]
        return (self.away[axis] if float(np.linalg.norm(e - v)) > float(np.linalg.norm(s - v))
                else self.vps[axis])

    def _key(self, axis: int, end: str) -> str:
        if axis == 0 and self.swap_x and end != "mid":
            end = "hi" if end == "lo" else "lo"
        return f"{_XYZ[axis]}_{end}"

    def face(self, axis: int, end: str) -> str:
        return _raw("faces")[self._key(axis, end)]

    def face_label(self, axis: int, end: str) -> str:
        """A face's name on its own, on the picture ("front", "left")."""
        return _raw("face_labels")[self._key(axis, end)]

    def side(self, axis: int, end: str) -> str:
        return _raw("sides")[self._key(axis, end)]

    def beyond(self, axis: int, end: str) -> str:
        """Which way past the parent's ``end`` side ("below" its bottom)."""
        return _raw("beyond")[self._key(axis, end)]

    @staticmethod
    def dim(axis: int) -> str:
        return _raw("dims")[axis]

    @staticmethod
    def shape(kind: str) -> str:
        shapes = _raw("shapes")
        return shapes.get(kind, shapes["cuboid"])


def _join(items: Sequence[str]) -> str:
    items = list(items)
    if len(items) <= 1:
        return "".join(items)
    # a list of items that say "and" themselves closes with "join_last_long" (English: a
    # serial comma, "CD for its front and top, and EF for its bottom")
    last = _raw("join_last")
    if any(last in x for x in items):
        last = _raw("join_last_long")
    return _raw("join").join(items[:-1]) + last + items[-1]


def _unique(items: Iterable[str]) -> list[str]:
    out: list[str] = []
    for s in items:
        if s not in out:
            out.append(s)
    return out


def _extension(entry: Any) -> str:
    """The amount an extrusion extends by, in words ("one", "half a")."""
    return _raw("primitive.amounts")["one" if entry.name.startswith("extend-1") else "half"]


def _position(words: _Words, anchor: Any, parent: str, about: bool) -> str:
    axis, r = anchor.axis, anchor.ratio
    side = words.side(axis, anchor.end)
    if anchor.face_normal == axis:
        return _t("primitive.position.flat", side=side, parent=parent)
    entry = entry_for(r)
    ab = _raw("about") if about else ""
    if entry.in_line:
        return _t("primitive.position.align", side=side, parent=parent,
                  pside=words.side(axis, "lo" if r < 0.5 else "hi"))
    if not entry.extrusion:
        return _t("primitive.position.inside", side=side, about=ab,
                  fraction=_raw("primitive.fractions")[entry.name], parent=parent,
                  lo=words.side(axis, "lo"), hi=words.side(axis, "hi"))
    amount = _extension(entry)
    end = "lo" if r < 0 else "hi"
    return _t("primitive.position.extend", side=side, about=ab, amount=amount, parent=parent,
              dim=words.dim(axis), pside=words.side(axis, end), beyond=words.beyond(axis, end))


def _ratio_words(words: _Words, anchor: Any, parent: str) -> str:
    """Where one anchor puts the part, in ratio words (a master's text): "its left side at a
    quarter of the body's width (from its left side)" (counted from the parent's ``lo`` end,
    named by the picture; a read-through of the master pages could not tell which end "a
    quarter" counted from)."""
    axis, r = anchor.axis, anchor.ratio
    side = words.side(axis, anchor.end)
    if anchor.face_normal == axis:
        return _t("ratio_words.flat", side=side, parent=parent)
    entry = entry_for(r)
    if entry.in_line:
        return _t("ratio_words.align", side=side, parent=parent,
                  pside=words.side(axis, "lo" if r < 0.5 else "hi"))
    if not entry.extrusion:
        # half way is the same from either end: said without one
        return _t("ratio_words.middle" if entry.name == "half" else "ratio_words.inside",
                  side=side, parent=parent, dim=words.dim(axis),
                  fraction=_raw("primitive.fractions")[entry.name],
                  lo=words.side(axis, "lo"), hi=words.side(axis, "hi"))
    amount = _extension(entry)
    end = "lo" if r < 0 else "hi"
    return _t("ratio_words.extend", side=side, amount=amount, parent=parent,
              dim=words.dim(axis), pside=words.side(axis, end), beyond=words.beyond(axis, end))


def _inside_pairs(anchors: Sequence[Any]) -> dict[int, int]:
    """Both ends of an axis placed inside one parent's extent (a fraction of it each: "its
    left side at a quarter ..., its right side at two thirds ..."), by the index of the first
    of the two in ``anchors``: the other's index."""
    def inside(a: Any) -> bool:
        entry = entry_for(a.ratio)
        return (a.end != "mid" and a.face_normal != a.axis and not entry.in_line
                and not entry.extrusion)

    out: dict[int, int] = {}
    taken: set[int] = set()
    for i, a in enumerate(anchors):
        if i in taken or not inside(a):
            continue
        k = next((k for k, b in enumerate(anchors) if k > i and k not in taken and inside(b)
                  and b.axis == a.axis and b.parent == a.parent
                  and {a.end, b.end} == {"lo", "hi"}), None)
        if k is not None:
            out[i] = k
            taken.update((i, k))
    return out


def _outside_pairs(anchors: Sequence[Any]) -> dict[int, tuple[int, int]]:
    """An axis whose one end is in line with a side of the parent and whose other end lies
    beyond that same side by an extrusion ("its right side in line with part 7's left side,
    its left side half a part 7 width to the left of part 7's left side"): by the index of the
    first of the two in ``anchors``, (the extrusion's index, the in-line one's)."""
    out: dict[int, tuple[int, int]] = {}
    taken: set[int] = set()
    for i, a in enumerate(anchors):
        for k, b in enumerate(anchors):
            if (k == i or i in taken or k in taken or b.axis != a.axis or b.parent != a.parent
                    or {a.end, b.end} != {"lo", "hi"} or "mid" in (a.end, b.end)
                    or a.face_normal == a.axis or b.face_normal == b.axis):
                continue
            ea, eb = entry_for(a.ratio), entry_for(b.ratio)
            if not (ea.in_line and eb.extrusion):
                continue
            side = "lo" if a.ratio < 0.5 else "hi"  # the parent's side both ends are on
            if (b.ratio < 0) != (side == "lo") or a.end == side:
                continue
            first = min(i, k)
            out[first] = (k, i)
            taken.update((i, k))
    return out


def _outside(words: _Words, key: str, ext: Any, parent: str, about: str = "") -> str:
    """An axis from a side of ``parent`` out beyond it by extrusion ``ext``, said at once
    (``key``: ``ratio_words.outside`` or ``primitive.position.outside``): "its width half a
    part 7 width to the left of part 7's left side"."""
    end = "lo" if ext.ratio < 0 else "hi"
    return _t(key, dim=words.dim(ext.axis), amount=_extension(entry_for(ext.ratio)),
              parent=parent, pside=words.side(ext.axis, end), beyond=words.beyond(ext.axis, end),
              about=about)


def _both_inside(words: _Words, key: str, a: Any, b: Any, parent: str, about: str = "") -> str:
    """Both ends of an axis inside ``parent`` said at once, the lower end first (``key``:
    ``ratio_words.inside_both`` or ``primitive.position.inside_both``): "its left side and
    right side at a quarter and two thirds of part 7's width (from part 7's left side)"
    (each said apart, a master's step of an unseen model ran to 85 words)."""
    lo, hi = (a, b) if a.end == "lo" else (b, a)
    fractions = _raw("primitive.fractions")
    return _t(key, sides=_join([words.side(lo.axis, "lo"), words.side(lo.axis, "hi")]),
              fractions=_join([fractions[entry_for(x.ratio).name] for x in (lo, hi)]),
              parent=parent, dim=words.dim(lo.axis), about=about,
              lo=words.side(lo.axis, "lo"), hi=words.side(lo.axis, "hi"))


def _same_sides(anchors: Sequence[Any]) -> dict[int, list[int]]:
    """Anchors placing sides each in line with the parent's side of the same name, by
    parent, two or more: the first one's index -> all of theirs (said at once: "its back,
    front, top and bottom in line with the engine's")."""
    same: dict[str, list[int]] = {}
    for i, a in enumerate(anchors):
        if (a.end != "mid" and a.face_normal != a.axis
                and entry_for(a.ratio).in_line
                and a.end == ("lo" if a.ratio < 0.5 else "hi")):
            same.setdefault(a.parent, []).append(i)
    return {ids[0]: ids for ids in same.values() if len(ids) > 1}


def _positions(words: _Words, anchors: Sequence[Any], name_of: Callable[[Any], str],
               about: bool) -> list[str]:
    """:func:`_position` of each anchor, both ends of an axis inside one parent said at once
    (:func:`_both_inside`), and sides in line with the parent's sides of the same name said
    at once ("Put its front, top and bottom in line with wheel 1's.": the train's wheel 5,
    placed by eye from the right, said each in a sentence of its own, 95 words a step)."""
    pairs = _inside_pairs(anchors)
    outside = _outside_pairs(anchors)
    second = set(pairs.values()) | {k for pair in outside.values() for k in pair} - set(outside)
    taken = set(pairs) | second | set(outside)
    first = {i: ids for i, ids in _same_sides(anchors).items() if taken.isdisjoint(ids)}
    later = {k for ids in first.values() for k in ids[1:]}
    # both ends of an axis extended alike beyond one parent, said once ("Put its left side and
    # right side about half a column width beyond the column's, one on each side.": the
    # mixer's bowl placed by eye from the side, 109 words a step)
    twins: dict[int, int] = {}
    for i, a in enumerate(anchors):
        if i in taken or i in first or i in later or i in twins.values():
            continue
        k = _extended_twin(anchors, i, taken | set(first) | later | set(twins.values()))
        if k is not None:
            twins[i] = k
    ab = _raw("about") if about else ""
    return [_both_inside(words, "primitive.position.inside_both", a, anchors[pairs[i]],
                         name_of(a), ab) if i in pairs
            else _outside(words, "primitive.position.outside", anchors[outside[i][0]],
                          name_of(a), ab) if i in outside
            else _t("primitive.position.align_same", parent=name_of(a), sides=_join(
                [words.side(anchors[k].axis, anchors[k].end) for k in first[i]])) if i in first
            else _t("primitive.position.extend_both", parent=name_of(a), about=ab,
                    amount=_extension(entry_for(a.ratio)), dim=words.dim(a.axis),
                    sides=_join([words.side(a.axis, "lo"), words.side(a.axis, "hi")]))
            if i in twins
            else _position(words, a, name_of(a), about)
            for i, a in enumerate(anchors)
            if i not in second and i not in later and i not in twins.values()]


def _extended_twin(anchors: Sequence[Any], i: int, done: set[int]) -> int | None:
    """The anchor extending the other end of anchor ``i``'s axis beyond the same parent by
    the same amount (both ends of the axis extended alike), or None."""
    a = anchors[i]
    return next((k for k, b in enumerate(anchors) if k > i and k not in done
                 and b.axis == a.axis and b.parent == a.parent
                 and {a.end, b.end} == {"lo", "hi"} and a.face_normal != a.axis
                 and b.face_normal != b.axis
                 and entry_for(a.ratio).extrusion and entry_for(b.ratio).extrusion
                 and abs((a.ratio if a.end == "hi" else b.ratio) - 1.0
                         + (b.ratio if a.end == "hi" else a.ratio)) <= 1e-9), None)


def _ratio_phrases(words: _Words, anchors: Sequence[Any],
                   name_of: Callable[[Any], str]) -> list[str]:
    """:func:`_ratio_words` of each anchor (``name_of(anchor)``: its parent part's name, as
    said), but sides in line with the parent's sides of the same name said together, and
    both ends of an axis extended alike beyond one parent said once: "its width the column's,
    with half a column width more on each side" (the mixer's master bowl said each side
    apart, 75 words)."""
    out: list[str] = []
    done: set[int] = set()
    # sides each in line with the parent's side of the same name, said once: "its back,
    # front, top and bottom in line with the engine's" (the train's master wagon named the
    # engine four times in 32 words)
    first = _same_sides(anchors)
    pairs = _inside_pairs(anchors)
    outside = _outside_pairs(anchors)
    for i, a in enumerate(anchors):
        if i in done:
            continue
        if i in pairs:  # both ends inside the parent: said at once
            done.add(pairs[i])
            out.append(_both_inside(words, "ratio_words.inside_both", a, anchors[pairs[i]],
                                    name_of(a)))
            continue
        if i in outside:  # from a side of the parent out beyond it: said at once
            done.update(outside[i])
            out.append(_outside(words, "ratio_words.outside", anchors[outside[i][0]],
                                name_of(a)))
            continue
        if i in first:
            done.update(first[i])
            out.append(_t("ratio_words.align_same", parent=name_of(a), sides=_join(
                [words.side(anchors[k].axis, anchors[k].end) for k in first[i]])))
            continue
        twin = _extended_twin(anchors, i, done)
        if twin is None:
            out.append(_ratio_words(words, a, name_of(a)))
            continue
        done.add(twin)
        out.append(_t("ratio_words.extend_both", amount=_extension(entry_for(a.ratio)),
                      parent=name_of(a), dim=words.dim(a.axis)))
    return out


_DRAWN_FIELD = re.compile(r"(?i)\bdraw (?:diagonals |the diagonals of halves )?\{(\w+)\}"
                          r"(?: and \{(\w+)\})?")


@functools.lru_cache(maxsize=None)
def drawn_fields(key: str) -> frozenset[str]:
    """The fields naming lines that sub-step ``key``'s sentence draws: those right after
    "draw" in its English template ("Through {point}, draw {line} ...", "Draw diagonals
    {first} and {second} ..."), and :data:`~.drafts._DRAWS`'s; every language's template
    draws the same lines (``templates`` checks the fields match)."""
    from .drafts import _DRAWS

    text = templates.load("steps", "en")["substep"].get(key)
    found = {n for m in _DRAWN_FIELD.finditer(text) for n in m.groups() if n} \
        if isinstance(text, str) else set()
    return frozenset(found | set(_DRAWS.get(key, ())))


def _substep(key: str, fields: dict[str, Any]) -> str:
    """A sub-step's sentence from ``templates/steps.yaml`` (section ``substep``)."""
    return _t(f"substep.{key}", **fields)


def _substep_of(s: Spec) -> str:
    """A sub-step that names no point, formatted (a master's summary reuses it)."""
    return _substep(s.key, dict(s.fields))


def _plural(key: str) -> str:
    """The template key of a sub-step said for two twins at once (``edge`` -> ``edge_two``)."""
    return f"{key}_two" if isinstance(_raw("substep").get(f"{key}_two"), str) else key


def _cap(text: str) -> str:
    """``text`` with its first letter a capital (a headline starts with the part's name)."""
    return text[:1].upper() + text[1:]
