"""Ellipse steps and outline steps (round parts' ends, the parts' outlines packed into steps)."""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Mapping, Sequence

import numpy as np

from .. import templates
from ..constructions import Face, ellipse_on_face
from ..instructions import Many, Pts, Spec, brief_fields, spec
from ..names import natural_key
from ..occlude import Solid, box_solid, cylinder_solid, hidden, hidden_spans, polyhedron, runs
from ..types import Box, Part, Stroke
from .drafts import MAX_STEP_WORDS, _Draft, _merged_outlines
from .geometry import (
    _box_corners,
    _end_faces,
    _front_facing,
    _Line,
    _polygon_area_mm2,
    _round,
    _solid,
    _stroke,
    _too_small,
)
from .hiding import _front_to_back
from .words import _cap, _join, _t, _the

#: A cylinder's sides are straight where each tenth of its length reaches this fraction of
#: its largest radius (:meth:`_Ellipses.straight_sides`).
STRAIGHT_SIDES = 0.9


#: Distinct shapes (a part and its copies count once) traced in one outline step, at most.
OUTLINE_SHAPES = 3

#: A scaffold edge counts as hidden by a part drawn before it where the line of sight runs
#: inside that part for more than this share of the model's diagonal (parts touching within
#: the fit's tolerances hide nothing of each other) ...
HIDE_DEPTH = 2e-3
#: ... over a stretch at least this long on the sheet (mm): shorter ones stay solid.
HIDE_MIN_MM = 0.5


class _Ellipses:
    """Ellipse and outline drafts, mixed into
    :class:`~h2s_print.sequence.context._Context` (whose fields these methods read)."""

    def solids(self, basic: bool) -> list[tuple[str, Solid]]:
        """The drawn primitives as solids (:mod:`h2s_print.occlude`), by part: the guided
        tutorial's kept parts in their selected boxes, or (``basic``) the visible parts in
        their fitted ones."""
        key = "basic" if basic else "guided"
        if key not in self._solids:
            if basic:
                names = sorted(self.visible(self.originals))
            else:
                names = sorted(self.guided_parts()[1])
            out = []
            for name in names:
                prim = self.plan.primitive(name)
                box = prim.box if basic else self.chosen[name].box
                if prim.type == "cylinder" and prim.axis is not None:
                    out.append((name, cylinder_solid(box, prim.axis)))
                elif prim.type == "frustum":
                    pts, faces, _ = _solid(prim, box)
                    out.append((name, polyhedron(pts, faces)))
                else:  # a cuboid, a plane (its slab), a custom part: its box
                    out.append((name, box_solid(box)))
            self._solids[key] = out
        return self._solids[key]

    def hide_depth(self) -> float:
        """:data:`HIDE_DEPTH` of the model's diagonal, model units (remembered: the model's
        bounds take every part's box, each a ``np.unique`` of its faces, each time asked)."""
        if self._hide_depth is None:
            lo, hi = self.plan.model.bounds
            self._hide_depth = HIDE_DEPTH * float(np.linalg.norm(np.subtract(hi, lo)))
        return self._hide_depth

    def reach(self, name: str, basic: bool) -> tuple[np.ndarray, np.ndarray, float]:
        """The solid of ``name`` (:meth:`solids`) on the sheet: its box's lowest and highest
        corner there (mm) and its nearest depth; a solid can hide only what lies behind it
        and under its box on the sheet.  Remembered per part (and ``basic``): every later
        box's :meth:`behind` asks again of the parts drawn before it."""
        key = (name, basic)
        if key not in self._reach:
            box = self.plan.primitive(name).box if basic else self.chosen[name].box
            corners = _box_corners(box)
            mm = self.camera.project(corners)
            self._reach[key] = (mm.min(axis=0), mm.max(axis=0),
                                float(self.camera.depth(corners).min()))
        return self._reach[key]

    def behind(self, strokes: Sequence[Stroke], drawn: Sequence[str],
               basic: bool = False) -> tuple[Stroke, ...]:
        """``strokes`` (a box's edges, drawn in its step) with the stretches that the parts
        ``drawn`` before it hide (:func:`occlude.hidden_spans`, in their selected boxes; for
        the control tutorial, ``basic``, in their fitted ones) made
        ``scaffold_hidden``, drawn dotted like the box's own back edges: a read-through met a
        desk's leg drawn solid across the desk top it stands under, and a plate's dowels, sunk
        in the plate, drawn solid as posts standing on it.  An edge hidden nowhere is kept as
        it is; a hidden stretch under :data:`HIDE_MIN_MM` on the sheet is not split off."""
        names = set(drawn)
        solids = [(name, sd) for name, sd in self.solids(basic) if name in names]
        if not solids:
            return tuple(strokes)
        depth = self.hide_depth()
        eye = self.camera.position
        reach = {name: self.reach(name, basic) for name, _ in solids}
        out: list[Stroke] = []
        for st in strokes:
            if st.kind != "scaffold" or len(st.points3d) != 2:
                out.append(st)
                continue
            a, b = (np.asarray(p, dtype=float) for p in st.points3d)
            pa, pb = (np.asarray(p, dtype=float) for p in st.points_mm)
            far = float(self.camera.depth(np.array([a, b])).max())
            lo2, hi2 = np.minimum(pa, pb), np.maximum(pa, pb)
            near = [sd for name, sd in solids
                    if reach[name][2] < far and np.all(reach[name][0] <= hi2)
                    and np.all(lo2 <= reach[name][1])]
            page = float(np.linalg.norm(pb - pa))
            spans = [(s0, s1) for s0, s1 in hidden_spans(a, b, eye, near, depth)
                     if (s1 - s0) * page >= HIDE_MIN_MM]
            if not spans:
                out.append(st)
                continue
            cuts = [0.0]
            kinds = []
            for s0, s1 in spans:
                if s0 > cuts[-1]:
                    kinds.append("scaffold")
                    cuts.append(s0)
                kinds.append("scaffold_hidden")
                cuts.append(s1)
            if cuts[-1] < 1.0:
                kinds.append("scaffold")
                cuts.append(1.0)
            for kind, s0, s1 in zip(kinds, cuts, cuts[1:]):
                out.append(_stroke(kind, st.part, np.array([a + s0 * (b - a), a + s1 * (b - a)]),
                                   self.camera))
        # visible edges first, as the scaffold orders them
        return tuple(sorted(out, key=lambda s: s.kind != "scaffold"))

    def ellipse_strokes(self, part: str, fe: Any, basic: bool) -> list[Stroke]:
        """The ellipse ``fe`` of ``part`` as strokes, ``ellipse`` where the drawn primitives
        leave it seen and ``ellipse_hidden`` where they hide it (:func:`occlude.hidden`; a
        round plate's ellipse lies inside its own slab, which does not count)."""
        flat = self.plan.primitive(part).type == "plane"
        solids = [sd for name, sd in self.solids(basic) if not (flat and name == part)]
        pts = np.vstack([fe.points3d, fe.points3d[:1]])
        mask = hidden(pts, self.camera.position, solids)
        return [_stroke("ellipse_hidden" if off else "ellipse", part, run, self.camera)
                for off, run in runs(pts, mask)]

    def ellipse_drafts(self, part: str, box: Box, basic: bool,
                       copies: Sequence[tuple[str, Box]] = ()) -> list[_Draft]:
        """The ellipse steps of a round part (and of its identical ``copies``).

        A round plate has one ellipse, a cylinder and a round frustum two, each its own step
        (one ellipse a page): the ellipse of the end face turned toward the camera (the *near*
        one) is constructed in that face (diagonals for its centre, lines through the centre
        toward the vanishing points, the ellipse through the four points where they meet the
        edges), its points lettered.  A cylinder's far end face, which the view shows from
        behind, is never constructed on: lines carried from the four points toward the axis'
        vanishing point meet its edges where its ellipse touches them.  A round frustum's
        (a bowl's) ends differ in size, so nothing carries: its far end rectangle, which its
        scaffold draws, gets the same construction as the near one (or, under the eyeball
        rule, its ellipse by eye).  Copies get the same lines and ellipses, said once.
        The construction is shown on the copy whose near face the picture shows largest; that
        face under the eyeball rule (``k = 4``), or ``basic``, makes one step "by eye" for both
        ellipses (it joins the part's outline step in a guided tutorial).
        """
        prim = self.plan.primitive(part)
        axis = prim.axis
        members = [(part, box), *copies]
        names = sorted((self.say(q) for q, _ in members), key=natural_key)
        who = _cap(_join(names))
        # per copy: its near ellipse and (a cylinder, a round frustum) its far one
        ends: list[tuple[str, Any, Any]] = []
        for q, b in members:
            if prim.type == "plane":  # a round plate: its ellipse in the rectangle drawn
                mid = 0.5 * (b[0][axis] + b[1][axis])
                lo, hi = list(b[0]), list(b[1])
                lo[axis] = hi[axis] = mid
                ends.append((q, ellipse_on_face(Face((tuple(lo), tuple(hi)), axis, "lo"),
                                                self.camera), None))
                continue
            faces = sorted(_end_faces(prim, b),
                           key=lambda f: (not _front_facing(f, self.camera), f.end))
            ends.append((q, ellipse_on_face(faces[0], self.camera),
                         ellipse_on_face(faces[1], self.camera)))
        one = not copies
        # the construction is shown on the copy whose near face the picture shows largest
        show = max(range(len(ends)), key=lambda k: (
            _polygon_area_mm2(self.camera, ends[k][1].face.corners), -k))
        ends.insert(0, ends.pop(show))
        near = [(q, fe) for q, fe, _ in ends]
        far = [(q, fe, be) for q, fe, be in ends if be is not None]
        if basic or _too_small(self.camera, near[0][1].face.corners, 4,
                               self.settings.eyeball_mm2):
            head = _t("headline.ellipse_eyeball" if one else "headline.ellipse_many_eyeball",
                      Part=_cap(self.say(part)), Parts=who)
            strokes = [st for q, fe in near for st in self.ellipse_strokes(q, fe, basic)]
            strokes += [st for q, _, be in far for st in self.ellipse_strokes(q, be, basic)]
            return [_Draft(part, "ellipse", True, (), tuple(strokes), head,
                           self.lettered([spec("ellipse_by_eye")]))]
        same = [spec("ellipse_copies")] if copies else []
        key = "ellipse_plate" if not far else "ellipse_end"
        # the copies named each, or, where that makes the step too long, the one its lines
        # are drawn on and a count (the train's six wheels seen from behind: 72 words)
        short = None if one else _cap(templates.plural(
            "steps", "headline.and_more", len(copies), Part=self.say(near[0][0])))

        def named(d: _Draft, key: str, face: str) -> _Draft:
            if one or self.step_words(d.specs, d.headline) <= MAX_STEP_WORDS:
                return d
            return replace(d, headline=_t(f"headline.{key}_many", Parts=short, face=face))

        strokes = tuple(st for q, e in near for st in self.ellipse_strokes(q, e, basic))
        face = self.words.face(axis, near[0][1].face.end)
        out = [named(_Draft(part, "ellipse", False,
                            tuple(_Line(ln.role, ln.start, ln.end)
                                  for _, e in near for ln in e.lines),
                            strokes,
                            _t(f"headline.{key}" + ("" if one else "_many"),
                               Part=_cap(self.say(part)), Parts=who, face=face),
                            self.lettered(self.ellipse_specs(near[0][0], near[0][1], bool(far),
                                                             strokes) + same)), key, face)]
        if not far:
            return out
        face = self.words.face(axis, far[0][2].face.end)
        head = _t("headline.ellipse_end" + ("" if one else "_many"), Part=_cap(self.say(part)),
                  Parts=who, face=face)
        strokes = tuple(st for q, _, be in far for st in self.ellipse_strokes(q, be, basic))
        if prim.type == "frustum":  # its own construction on the far end rectangle
            be = far[0][2]
            if _too_small(self.camera, be.face.corners, 4, self.settings.eyeball_mm2):
                out.append(_Draft(part, "ellipse", True, (), strokes, head,
                                  self.lettered([spec("ellipse_by_eye_end")])))
            else:
                out.append(named(_Draft(
                    part, "ellipse", False,
                    tuple(_Line(ln.role, ln.start, ln.end) for _, _, e in far for ln in e.lines),
                    strokes, head,
                    self.lettered(self.ellipse_specs(far[0][0], be, True, strokes) + same)),
                    "ellipse_end", face))
            return out
        fe, be = near[0][1], far[0][2]
        around = Many(tuple(Pts((x,)) for x in fe.touch))
        # the carried points where they meet the far face's edges, lettered
        reached = Many(tuple(Pts((x,)) for x in be.touch))
        out.append(named(_Draft(
            part, "ellipse", False,
            tuple(_Line("vanishing", x, y) for _, e, be in far for x, y in zip(e.touch, be.touch)),
            strokes, head,
            # the far face by its name, as the headline names the end ("the far face" read as
            # jargon)
            self.lettered([spec("ellipse_carry", points=around, new=reached,
                                vp=self.words.vp(axis, fe.touch[0], be.touch[0]),
                                face=self.words.face(axis, be.face.end)), *same])),
            "ellipse_end", face))
        return out

    def ellipse_key(self, d: _Draft) -> tuple:
        """An ellipse step's ellipse, as the rectangle its strokes span (3D, rounded to the
        merge tolerance): two steps drawing the same ellipse have the same key."""
        pts = np.array([p for st in d.strokes for p in st.points3d], dtype=float).reshape(-1, 3)
        if not len(pts):
            return ()
        q = np.round(np.vstack([pts.min(axis=0), pts.max(axis=0)]) / (100.0 * self.tol))
        return tuple(int(x) for x in q.ravel())

    def ellipse_face(self, d: _Draft) -> str:
        """The end face (``top`` ...) of its part that an ellipse step's ellipse lies on."""
        prim = self.plan.primitive(d.part)
        box = self.chosen[d.part].box
        c = float(np.mean([p[prim.axis] for st in d.strokes for p in st.points3d]))
        end = "lo" if abs(c - box[0][prim.axis]) <= abs(c - box[1][prim.axis]) else "hi"
        return self.words.face(prim.axis, end)

    def ellipse_specs(self, part: str, fe: Any, solid: bool,
                      strokes: Sequence[Stroke]) -> list[Spec]:
        """The sub-steps constructing ellipse ``fe`` of ``part`` in its face: diagonals for the
        centre, the lines through it toward the vanishing points, the ellipse through the four
        points (``dotted where hidden`` when ``strokes`` has hidden runs)."""
        u, v = fe.face.in_axes
        a, b, c, d = fe.face.corners
        t = fe.touch  # the middles of the edges: (u hi, v hi, u lo, v lo), round the face
        around = Many(tuple(Pts((x,)) for x in t))
        hidden_runs = any(st.kind == "ellipse_hidden" for st in strokes)
        # (an apprentice, whose picture shows no diagonals, reads "Through the centre of
        # the lens's front face, draw ..." for the lines through it: brief_specs)
        face = self.words.face(fe.face.normal, fe.face.end)
        centre = dict(brief_fields("centre" if solid else "centre_plate", self.say(part), face),
                      role="guide")
        return [spec("ellipse_diagonals", first=Pts((a, c)), second=Pts((b, d)),
                     point=Pts((fe.centre,)), part=self.say(part), face=face,
                     role="construction")
                if solid else  # a plate is drawn as one rectangle
                spec("ellipse_diagonals_plate", first=Pts((a, c)), second=Pts((b, d)),
                     point=Pts((fe.centre,)), part=self.say(part), role="construction"),
                spec("through", point=Pts((fe.centre,)), line=Pts((t[2], t[0])),
                     vp=self.words.vp(u), **centre),
                spec("through", point=Pts((fe.centre,)), line=Pts((t[3], t[1])),
                     vp=self.words.vp(v), **centre),
                spec("ellipse_draw_hidden" if hidden_runs else "ellipse_draw", points=around)]

    def contour_drafts(self, order: Sequence[str], parts: dict[str, Part]) -> list[_Draft]:
        """Contour steps, front to back (:func:`_front_to_back`); each part's lines are its
        lines in the finished drawing, so the steps add up to exactly the finished drawing."""
        finals = self.finals(parts)
        order = _front_to_back([parts[p] for p in order], self.camera, self.settings)
        out: list[_Draft] = []
        for part in order:
            if not finals[part]:
                continue
            key = "contour_first" if not out else "contour_next"
            out.append(_Draft(part, "contour", False, (), finals[part],
                              _t("headline.contour", Part=_cap(self.say(part))),
                              (spec(key),)))
        return out

    def hidden_drawn(self, order: Sequence[str], parts: dict[str, Part]) -> list[str]:
        """Parts of ``order`` (drawn as boxes) with no line in the finished drawing: kept
        because a part that shows hangs off them (the chair's part 5, under its seat)."""
        finals = self.finals(parts)
        return [p for p in order if not finals[p]]

    def pack_outlines(self, drafts: Sequence[_Draft], lead: Mapping[str, str],
                      unseen: Sequence[str] = ()) -> list[_Draft]:
        """Consecutive outline drafts packed into steps while the text stays within
        :data:`MAX_STEP_WORDS` and a step traces at most :data:`OUTLINE_SHAPES` distinct
        shapes (a part and its copies are one): a drawing teacher does not give each small
        part a page of its own (before stop 24: two to a step, whatever their length; the
        roller's high-right view took four outline steps for seven parts), nor the whole
        object at once (a read-through: the oven's ten parts, twenty grill bars among them,
        in one step from a 155 mm picture).  The last step ends by erasing the
        scaffold (:meth:`finish`), within the same limit: where it would not fit, the last
        outline draft is a step of its own."""
        out = self._packed(drafts, lead)
        if not out:
            return out

        def over(d: _Draft, hidden: Sequence[str]) -> bool:
            return self.step_words(self.finish(d, unseen=hidden).specs,
                                   d.headline) > MAX_STEP_WORDS

        if over(out[-1], unseen):
            out = self._packed(drafts[:-1], lead) + self._packed(drafts[-1:], lead)
        if unseen and over(out[-1], unseen) and not over(out[-1], ()):
            # the hidden parts said in the latest outline step before with room (the train's
            # chimney from the right: its outlines, "Wheel 1, wheel 5 and wheel 3 are hidden
            # ..." and the erasing, 78 words in one step)
            for i in range(len(out) - 2, -1, -1):
                said = self.hidden_said(out[i], unseen)
                if self.step_words(said.specs, said.headline) <= MAX_STEP_WORDS:
                    out[i], unseen = said, ()
                    break
        return out[:-1] + [self.finish(out[-1], unseen=unseen)]

    def hidden_said(self, d: _Draft, unseen: Sequence[str]) -> _Draft:
        """``d`` saying that the parts ``unseen``, drawn as boxes, have no outlines to trace
        (a read-through: the chair's part 5 was built, then never named again)."""
        names = [self.say(p) for p in unseen]
        said = ((spec("hidden_part", Part=_cap(names[0])),) if len(names) == 1 else
                (spec("hidden_parts", Parts=_cap(_join(names))),) if names else ())
        return replace(d, specs=d.specs + said)

    def finish(self, d: _Draft, basic: bool = False, unseen: Sequence[str] = ()) -> _Draft:
        """The tutorial's last step, with its last sub-steps: the parts drawn as boxes that
        the finished drawing hides, said to have no outlines (:meth:`hidden_said`; where
        they do not fit, an outline step before says them: :meth:`pack_outlines`), and erase
        the boxes and guides round the outlines (a read-through: no step said so, and the
        finished drawing kept its scaffold); the control tutorial (``basic``) has boxes only,
        and no word of guides."""
        d = self.hidden_said(d, unseen)
        return replace(d, specs=d.specs + (spec("erase_boxes" if basic else "erase_scaffold"),))

    def _packed(self, drafts: Sequence[_Draft], lead: Mapping[str, str]) -> list[_Draft]:
        out: list[_Draft] = []
        for d in drafts:
            if out and out[-1].kind == d.kind:
                both = _merged_outlines(out[-1], d, self.say)
                shapes = {lead.get(q, q) for q in both.group}
                if (len(shapes) <= OUTLINE_SHAPES
                        and self.step_words(self.round_sides(both, lead).specs,
                                            both.headline) <= MAX_STEP_WORDS):
                    out[-1] = both
                    continue
            out.append(d)
        return [self.round_sides(d, lead) for d in out]

    def straight_sides(self, part: str) -> bool:
        """Are cylinder ``part``'s sides straight: does every tenth of its length (along its
        axis, on the selected box) that holds vertices of its adjusted mesh reach within
        :data:`STRAIGHT_SIDES` of its largest radius?  A tenth whose vertices all lie further
        in is a waist or a taper the outline follows (the roller's handle, a bulging grip:
        "Join the two ellipses ... with two straight lines" while the picture drew a
        curved grip, a read-through)."""
        prim, box = self.plan.primitive(part), np.asarray(self.chosen[part].box, dtype=float)
        axis = prim.axis
        v = np.asarray(self.adjusted[part].vertices, dtype=float)
        u, w = (k for k in range(3) if k != axis)
        centre = box.mean(axis=0)
        r = np.hypot(v[:, u] - centre[u], v[:, w] - centre[w])
        length = float(box[1, axis] - box[0, axis])
        if not len(v) or length <= 0.0 or float(r.max()) <= 0.0:
            return True
        at = np.clip(((v[:, axis] - box[0, axis]) / length * 10).astype(int), 0, 9)
        reach = np.zeros(10)
        np.maximum.at(reach, at, r)
        held = np.bincount(at, minlength=10) > 0
        return bool(np.all(reach[held] >= STRAIGHT_SIDES * float(r.max())))

    def sides_show(self, part: str) -> bool:
        """Does the finished drawing show a side line of cylinder ``part``: visible line
        along its axis over a third of its length, in all?  (A read-through of stop 27: the pins
        plate's dowels, sunk in the plate, show their top ellipses only, and "Join the two
        ellipses ... with two straight lines" drew what the picture hides.)"""
        prim = self.plan.primitive(part)
        box = self.chosen[part].box
        axis = prim.axis
        length = float(box[1][axis] - box[0][axis])
        along = 0.0  # visible line running along the axis, in all
        for st in self.finals(self.adjusted).get(part, ()):
            d = np.diff(np.asarray(st.points3d, dtype=float).reshape(-1, 3), axis=0)
            n = np.linalg.norm(d, axis=1)
            along += float(n[np.abs(d[:, axis]) >= 0.95 * n].sum())
        return along >= length / 3.0

    def round_sides(self, d: _Draft, lead: Mapping[str, str]) -> _Draft:
        """An outline draft with the sentence joining its round parts' ellipses: the two
        lines touching both, which no scaffold line gives (the read-through: "trace" did not
        say to draw them); one sentence for the step's cylinders, after their ellipses,
        before the tracing, and one for its tapered round parts, whose sides follow the
        picture (a read-through: the mixer's bowl curves, "two straight lines" did not)."""
        cylinders = [q for q in d.group if _round(self.plan.primitive(q))
                     and self.plan.primitive(q).type == "cylinder" and self.sides_show(q)]
        rounds = [q for q in cylinders if self.straight_sides(q)]
        # (a cylinder whose sides are not straight: along the sides the picture shows)
        tapers = [q for q in d.group if (_round(self.plan.primitive(q))
                                         and self.plan.primitive(q).type == "frustum")
                  or (q in cylinders and q not in rounds)]
        joins: list[Spec] = []
        if rounds:
            leads = list(dict.fromkeys(lead.get(q, q) for q in rounds))
            if len(leads) == 1 and len(rounds) > 1:  # one part and its copies
                joins.append(spec("round_sides_copies", the_parents=_the(self.say(leads[0]))))
            else:
                joins.append(spec("round_sides_many" if len(rounds) > 1 else "round_sides",
                                  the_parents=_join([_the(self.say(q)) for q in rounds])))
        if tapers:  # a bowl's sides curve: "two straight lines" contradicted its picture
            joins.append(spec("round_sides_taper",
                              the_parents=_join([_the(self.say(q)) for q in tapers])))
        if not joins:
            return d
        at = next(i for i, x in enumerate(d.specs) if x.key.startswith("contour"))
        return replace(d, specs=d.specs[:at] + tuple(joins) + d.specs[at:])
