"""Repeated parts: identical parts drawn as one step, copies, equally spaced rows."""

from __future__ import annotations

from dataclasses import replace
from typing import Sequence

import numpy as np

from ..constructions import Face, equal_spacing
from ..instructions import Many, Pts, Spec, spec
from ..names import natural_key
from ..types import Box
from .drafts import _Draft
from .geometry import (
    _extent,
    _front_facing,
    _Line,
    _mesh_area,
    _polygon_area_mm2,
    _too_small,
)
from .words import _cap, _join, _ratio_phrases, _raw, _substep_of, _t

#: Two parts are the same shape when their boxes' extents and mesh areas agree within this
#: fraction (and their primitive types and triangle counts are equal): drawn as one step.
REPEAT_TOL = 0.02


#: A copy's position is said in ratio words up to this many words; longer, it is placed as the
#: picture shows it (the words would outweigh the drawing).
REPEAT_WHERE_WORDS = 16


#: A copy whose box's centre lies this close to its original's on the sheet, moved along one
#: axis only, is said to lie "directly behind it" (or in front, above ...): where the picture
#: shows it, it can hardly be told apart (the desk's two modesty panels, 12 mm apart in depth,
#: read "Part 3: the same flat rectangle, where the picture shows it" over a double line), mm.
NEAR_COPY_MM = 5.0


#: Identical parts form an equally spaced row (:meth:`_Context.spaced_rows`) when their steps
#: along the row agree within this fraction of the step, and their other intervals within this
#: fraction of a part's largest extent.
SPACING_TOL = 0.005


class _Repeats:
    """Repeated parts, mixed into :class:`~h2s_print.sequence.context._Context` (whose
    fields these methods read)."""

    def congruent(self, a: str, b: str, boxes: dict[str, Box]) -> bool:
        """Two parts are the same shape: same primitive type and axis, box extents within
        :data:`REPEAT_TOL` of the larger box's largest extent, and meshes with the same number
        of triangles and surface areas within ``REPEAT_TOL`` (instances of one mesh)."""
        pa, pb = self.plan.primitive(a), self.plan.primitive(b)
        if (pa.type, pa.axis) != (pb.type, pb.axis) or pa.type == "custom":
            return False
        ea = np.subtract(boxes[a][1], boxes[a][0])
        eb = np.subtract(boxes[b][1], boxes[b][0])
        scale = max(float(ea.max()), float(eb.max()), 1e-300)
        if float(np.abs(ea - eb).max()) > REPEAT_TOL * scale:
            return False
        ma, mb = self.originals[a], self.originals[b]
        if len(ma.faces) != len(mb.faces):
            return False
        area_a, area_b = _mesh_area(ma), _mesh_area(mb)
        return abs(area_a - area_b) <= REPEAT_TOL * max(area_a, area_b)

    def repeat_groups(self, order: Sequence[str], boxes: dict[str, Box],
                      parents: dict[str, set[str]]) -> list[list[str]]:
        """Parts in drawing order, identical ones (:meth:`congruent`) drawn as one group at the
        first one's place: a later part joins when every part it hangs off is drawn by then
        (before the group, or in it)."""
        groups: list[list[str]] = []
        placed: set[str] = set()
        for i, p in enumerate(order):
            if p in placed:
                continue
            group = [p]
            before = set(order[:i]) - placed | placed
            for q in order[i + 1:]:
                if q in placed or not self.congruent(p, q, boxes):
                    continue
                if parents.get(q, set()) <= before | set(group):
                    group.append(q)
            placed.update(group)
            groups.append(group)
        return groups

    def copy_anchors(self, q: str, first: str | None) -> tuple:
        """The anchors of copy ``q`` that say where it lies: with the group's ``first`` part,
        those on the axes along which ``q``'s box is moved from ``first``'s when anchors place
        all of them (on the others it lies as ``first``, the same box: the IVAR box's second
        side panel, "its middle (front to back) in line with part 1's back", had been placed
        "where the picture shows it", its full words too long, a read-through); else all."""
        anchors = tuple(self.chosen[q].anchors)
        if first is None:
            return anchors
        a = np.asarray(self.chosen[first].box, dtype=float)
        b = np.asarray(self.chosen[q].box, dtype=float)
        moved = {k for k in range(3) if np.abs(a[:, k] - b[:, k]).max() > self.tol}
        if not moved or not moved <= {x.axis for x in anchors}:
            return anchors
        return tuple(x for x in anchors if x.axis in moved)

    def copy_parents(self, q: str, first: str | None) -> set[str]:
        """The parts copy ``q``'s words (:meth:`copy_anchors`) name."""
        return {self.by_id[x.parent].part for x in self.copy_anchors(q, first)}

    def copy_places(self, members: Sequence[str], keep: set[str],
                    first: str | None = None) -> dict[str, str]:
        """Per copy of a group, the words placing it by its parents ("its back in line with the
        body's front"; by :meth:`copy_anchors`), or "" when it is placed where the picture
        shows it: when the words are too long to read (:data:`REPEAT_WHERE_WORDS`), name a
        part not in ``keep`` (left out), or the copies are placed differently."""
        where = {}
        for q in members:
            anchors = self.copy_anchors(q, first)
            w = _join(_ratio_phrases(self.words, anchors, self.parent_name))
            short = len(w.split()) <= REPEAT_WHERE_WORDS
            where[q] = w if short and self.copy_parents(q, first) <= keep else ""
        if len(set(where.values())) > 1:
            return {q: "" for q in members}
        return where

    def same_sentence(self, members: Sequence[str], shape: str, keep: set[str],
                      first: str | None = None) -> list[Spec]:
        """"Knob 2 and knob 3: the same box, its back in line with the body's front." for the
        group's other members, those placed alike said together (:meth:`copy_places`); a
        copy the picture would place right over ``first`` (:data:`NEAR_COPY_MM`) is said to
        lie "directly behind it" (:meth:`near_shift`)."""
        if not members:
            return []
        places = self.copy_places(members, keep, first)
        # (a copy right over ``first`` on the sheet that its full words would not place is
        # "directly behind it", whatever the words of its moved axes: the picture shows one
        # double line there, a read-through of the desk's modesty panels)
        whole = self.copy_places(members, keep)
        by_where: dict[str, list[str]] = {}
        for q in sorted(members, key=lambda q: natural_key(self.say(q))):
            shift = self.near_shift(first, q) if first is not None and not whole[q] else None
            key = places[q] if shift is None else "\0" + shift
            by_where.setdefault(key, []).append(q)

        def mirror(q: str) -> tuple[str, tuple, tuple] | None:
            # (said where the step has room: _Context.copies_pictured)
            return self.mirror_words(first, q) if first is not None else None

        out = []
        for where, qs in by_where.items():
            who = _cap(_join([self.say(q) for q in qs]))
            if where.startswith("\0"):
                out.append(spec("repeat_shift", parts=who, shape=shape,
                                shift=_raw("shifts")[where[1:]]))
            elif where:
                # an axis no anchor places: by the picture (a read-through: the desk's "Part 7:
                # the same box, its middle (front to back) at half of part 1's depth" said
                # nothing of where along the desk)
                # (said where the step has room: _Context.copies_pictured)
                # (a copy said by its moved axes only lies as ``first`` on the others)
                open_ = any(self.open_axes(q, first) for q in qs)
                pictured = ("repeat_pictured" if len(qs) > 1 else "repeat_pictured_one") \
                    if open_ else ""
                # (mirrored across a part's middle: said so where the words leave an axis to
                # the picture or have no room)
                out.append(spec("repeat", parts=who, shape=shape, where=where,
                                pictured=pictured, many=len(qs) > 1,
                                names=tuple(self.say(q) for q in qs),
                                mirror=(mirror(qs[0]) or ()) if len(qs) == 1 else ()))
            elif (corner := self.at_corners(first, qs)) is not None:
                out.append(spec("repeat_corners" if len(qs) > 1 else "repeat_corners_one",
                                parts=who, shape=shape, parent=self.say(corner)))
            else:
                out.append(spec("repeat_free" if len(qs) > 1 else "repeat_free_one", parts=who,
                                shape=shape, names=tuple(self.say(q) for q in qs),
                                mirrors=tuple(mirror(q) for q in qs)))
        # a copy "directly to its left" first, next to the part "its" is (the oven's "Button
        # 4: the same box, directly to its left." after "Button 1, button 2 and button 3:
        # ..." read as button 3's left, a read-through)
        return sorted(out, key=lambda x: x.key != "repeat_shift")

    def at_corners(self, first: str | None, copies: Sequence[str]) -> str | None:
        """The part drawn before whose upright corners ``first`` and each of ``copies``
        stand at, each at another one (flush with the two sides that meet there), or None:
        "Part 2, part 4 and part 5: the same box, at part 1's other corners." (the table's
        legs read "where the picture shows them", a read-through, where each is in line with
        two of the top's sides)."""
        if first is None or not copies:
            return None
        parts = [first, *copies]
        boxes = [np.asarray(self.chosen[q].box, dtype=float) for q in parts]
        for other in sorted(self.parents_of(first)):
            o = np.asarray(self.chosen[other].box, dtype=float)
            at: set[tuple[int, int]] = set()
            for b in boxes:
                # the corner (x end, y end) of ``other`` the box has: both its sides there flush
                ends = [next((e for e in (0, 1) if abs(b[e, k] - o[e, k]) <= self.tol), None)
                        for k in (0, 1)]
                if None in ends:
                    break
                at.add((ends[0], ends[1]))
            else:
                if len(at) == len(parts):
                    return other
        return None

    def open_axes(self, q: str, first: str | None) -> bool:
        """Do copy ``q``'s words (:meth:`copy_anchors`) leave an axis to the picture: all its
        anchors said, and not on every axis?"""
        said = self.copy_anchors(q, first)
        return {a.axis for a in said} != {0, 1, 2} and len(said) == len(self.chosen[q].anchors)

    def mirrored(self, first: str, q: str) -> tuple[str, int] | None:
        """(a part ``first`` hangs off, an axis) when copy ``q``'s box is ``first``'s mirrored
        across that part's middle along the axis, the same on the other axes, or None (said by
        :meth:`mirror_words`; a read-through: the desk's second foot said only where it lies
        front to back, and the IVAR box's second side "where the picture shows it"; a side, a
        foot, a dowel across the middle of what carries it is where a drawing teacher would
        say it is)."""
        a = np.asarray(self.chosen[first].box, dtype=float)
        b = np.asarray(self.chosen[q].box, dtype=float)
        tol = 10.0 * self.tol
        moved = [k for k in range(3) if np.abs(a[:, k] - b[:, k]).max() > tol]
        if len(moved) != 1:
            return None
        k = moved[0]
        for other in sorted(self.parents_of(first)):
            o = np.asarray(self.chosen[other].box, dtype=float)
            mid = 0.5 * (o[0, k] + o[1, k])
            if abs(2 * mid - a[1, k] - b[0, k]) <= tol and abs(2 * mid - a[0, k] - b[1, k]) <= tol:
                return other, k
        return None

    def mirror_words(self, first: str, q: str) -> tuple[str, tuple, tuple] | None:
        """How copy ``q``, ``first`` mirrored across a part's middle (:meth:`mirrored`), is
        said: (template key, its fields, the fields of the shorter "mirrored left to right
        across part 1's middle") from where ``first`` lies at that part's side
        nearer it: its middle on the side ("its middle on part 2's right side"),
        its outer side in line with it ("its right side in line with part 1's"), or in from
        it or out beyond it ("as far in from part 1's right side as part 6 is from its left
        side").  A read-through: "mirrored ... across the middle of part 1" left the reader
        to find that middle, drawn nowhere yet, and to mirror on the floor."""
        got = self.mirrored(first, q)
        if got is None:
            return None
        other, k = got
        a = np.asarray(self.chosen[first].box, dtype=float)
        o = np.asarray(self.chosen[other].box, dtype=float)
        near = "lo" if a[:, k].mean() < o[:, k].mean() else "hi"
        far = "hi" if near == "lo" else "lo"
        s = o[0 if near == "lo" else 1, k]  # the parent's side nearer ``first``
        outer = a[0 if near == "lo" else 1, k]  # first's side facing it
        tol = 10.0 * self.tol
        fields = {"parent": self.say(other), "side": self.words.side(k, far),
                  "pside": self.words.side(k, near), "first": self.say(first)}
        if abs(a[:, k].mean() - s) <= tol:
            key = "repeat_mirror_mid"
        elif abs(outer - s) <= tol:
            key = "repeat_mirror_flush"
        else:
            inside = (outer - s) * (1 if near == "lo" else -1) > 0
            key = "repeat_mirror" if inside else "repeat_mirror_out"
        short = (("directions", _raw("directions")[k]), ("parent", self.say(other)))
        return key, tuple(sorted(fields.items())), short

    def near_shift(self, first: str, q: str) -> str | None:
        """The ``shifts`` key ("y_hi": behind it) of copy ``q`` from ``first`` when it is moved
        along one axis only and its centre lies within :data:`NEAR_COPY_MM` of ``first``'s on
        the sheet; else None."""
        a = np.asarray(self.chosen[first].box, dtype=float)
        b = np.asarray(self.chosen[q].box, dtype=float)
        moved = [k for k in range(3) if np.abs(a[:, k] - b[:, k]).max() > self.tol]
        if len(moved) != 1:
            return None
        ca, cb = self.camera.project(np.array([a.mean(axis=0), b.mean(axis=0)]))
        if float(np.hypot(*(cb - ca))) >= NEAR_COPY_MM:
            return None
        k = moved[0]
        return f"{'xyz'[k]}_{'hi' if b[:, k].mean() > a[:, k].mean() else 'lo'}"

    def spaced_rows(self, group: Sequence[str], boxes: dict[str, Box]
                    ) -> list[tuple[list[str], int, Face]]:
        """Rows of identical parts at equal spacing, each to be placed by the equal-spacing
        construction (:func:`h2s_print.constructions.equal_spacing`) from its first two: (the
        row's parts in order, its axis, the face the construction is drawn on).

        A row is 3 or more of the group's parts with the same intervals on two axes and, along
        the third, the same step from one to the next (within :data:`SPACING_TOL`), no two
        overlapping.  The group's first part (constructed from its parents) starts its row:
        when it lies inside one, the row is split there and each side runs away from it.
        Rows are taken longest first, a part in one row only.  A row whose faces the view
        shows edge-on or too small for its lines (the eyeball rule) is left to the copies'
        sentences ("the same box, where the picture shows it")."""
        if len(group) < 3:
            return []
        free = list(group)
        rows: list[tuple[list[str], int, Face]] = []
        while True:
            found = [(r, axis, face) for axis in range(3) for r in self._runs(free, boxes, axis)
                     for face in [self._spacing_face(r, boxes, axis)] if face is not None]
            if not found:
                return rows
            best = max(found, key=lambda f: (len(f[0]), [-group.index(q) for q in f[0]]))
            rows.append(best)
            free = [q for q in free if q not in best[0][2:]]

    def _runs(self, members: Sequence[str], boxes: dict[str, Box], axis: int
              ) -> list[list[str]]:
        """Equally spaced runs of ``members`` along ``axis`` (:meth:`spaced_rows`), each
        starting from the group's first part when it holds it."""
        others = [a for a in range(3) if a != axis]
        lines: list[list[str]] = []
        for q in members:  # parts on one line along ``axis``
            box = boxes[q]
            tol = SPACING_TOL * max(_extent(box, a) for a in range(3))
            for line in lines:
                ref = boxes[line[0]]
                if all(abs(box[e][a] - ref[e][a]) <= tol for a in others for e in (0, 1)):
                    line.append(q)
                    break
            else:
                lines.append([q])
        lead = members[0] if members else None
        out: list[list[str]] = []
        for line in lines:
            line.sort(key=lambda q: boxes[q][0][axis])
            lo = [boxes[q][0][axis] for q in line]
            length = _extent(boxes[line[0]], axis)
            i = 0
            while i + 2 < len(line):
                step = lo[i + 1] - lo[i]
                j = i + 1
                if step > 0 and step >= length * (1 - SPACING_TOL):  # apart, not overlapping
                    while j + 1 < len(line) and abs(lo[j + 1] - lo[j] - step) <= SPACING_TOL * step:
                        j += 1
                run = line[i:j + 1]
                if len(run) >= 3:
                    k = run.index(lead) if lead in run else 0
                    if k >= 2:  # the group's first part inside: each side runs away from it
                        out += [r for r in (run[:k + 1][::-1], run[k:]) if len(r) >= 3]
                    else:
                        out.append(run)
                i = j
        return out

    def _spacing_face(self, row: Sequence[str], boxes: dict[str, Box], axis: int
                      ) -> Face | None:
        """The face of the row's first part the construction is drawn on: turned toward the
        camera, containing the row's ``axis``, the largest on the sheet; None when every such
        face (or the row's whole band) is too small for its lines under the eyeball rule."""
        first = boxes[row[0]]
        lo = [min(boxes[q][0][a] for q in row) for a in range(3)]
        hi = [max(boxes[q][1][a] for q in row) for a in range(3)]
        n_lines = 3 + 2 * (len(row) - 2)
        best: tuple[float, Face] | None = None
        for normal in (a for a in range(3) if a != axis):
            for end in ("lo", "hi"):
                face = Face(first, normal, end)
                if not _front_facing(face, self.camera):
                    continue
                band = Face((tuple(lo), tuple(hi)), normal, end)
                if (_too_small(self.camera, face.corners, 3, self.settings.eyeball_mm2)
                        or _too_small(self.camera, band.corners, n_lines,
                                      self.settings.eyeball_mm2)):
                    continue
                area = _polygon_area_mm2(self.camera, face.corners)
                if best is None or area > best[0]:
                    best = (area, face)
        return None if best is None else best[1]

    def spacing_draft(self, row: Sequence[str], axis: int, face: Face, boxes: dict[str, Box],
                      shape: str) -> _Draft:
        """The step placing a row's parts after its first two by equal spacing
        (:class:`h2s_print.constructions.Spacing`, along ``axis`` on ``face``:
        :meth:`spaced_rows`): its sub-steps, lines and the parts' boxes."""
        sp = equal_spacing(face, axis, [(boxes[q][0][axis], boxes[q][1][axis]) for q in row])
        (a, c), (b, d) = sp.diagonals
        placed = [self.say(q) for q in row[2:]]
        specs = [spec("diagonals", first=Pts((a, c)), second=Pts((b, d)),
                      point=Pts((sp.centre,)), parent=self.say(row[0]),
                      face=self.words.face(face.normal, face.end)),
                 spec("through", point=Pts((sp.centre,)),
                      line=Pts((sp.middle.start, sp.middle.end)), vp=self.words.vp(axis)),
                 spec("row_edges", lines=Many((Pts((sp.top.start, sp.top.end)),
                                               Pts((sp.bottom.start, sp.bottom.end)))),
                      vp=self.words.vp(axis))]
        for q, (lo_end, hi_end) in zip(row[2:], sp.ends):
            specs.append(spec("space", lines=Many((Pts((lo_end.start, lo_end.end)),
                                                   Pts((hi_end.start, hi_end.end)))),
                              points=Many((Pts((lo_end.through,)), Pts((hi_end.through,)))),
                              part=self.say(q)))
        specs.append(spec("space_place", parts=_join(placed), shape=shape))
        pair = _join([self.say(q) for q in row[:2]])
        strokes = tuple(st for q in row[2:] for st in self.scaffold(q))  # (boxes: selected)
        return _Draft(row[2], "primitive", False,
                      tuple(_Line(ln.role, ln.start, ln.end) for ln in sp.lines), strokes,
                      _t("headline.spaced", Parts=_cap(_join(placed)), shape=shape, first=pair),
                      self.lettered(specs), _t("substep.space_summary", first=pair),
                      group=tuple(row[2:]))

    def merge_group(self, first: _Draft, members: Sequence[str], extra: Sequence[_Draft],
                    sentences: Sequence[Spec]) -> _Draft:
        """``first`` (whose sub-steps end with ``sentences``) with the other members' strokes
        (and guides), and ``sentences`` in a master's summary too."""
        return replace(first, strokes=first.strokes + tuple(s for d in extra for s in d.strokes),
                       lines=first.lines + tuple(ln for d in extra for ln in d.lines),
                       summary=" ".join(x for x in (first.summary, *map(_substep_of, sentences))
                                        if x),
                       group=tuple(members))
