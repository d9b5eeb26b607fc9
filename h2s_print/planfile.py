"""A :class:`~h2s_print.plan.Plan` as plain data: the plan cache's entry format.

A cache entry must never be able to run code when read (an output folder may be shared), so it
holds no pickle: it is an uncompressed NumPy ``.npz`` archive read with
``allow_pickle=False``, holding

* ``doc``: UTF-8 JSON (as a ``uint8`` array) with every value of the plan but the meshes:
  the key it was stored under, the model's source, units, notes and part names, the
  primitives, relations, candidates, the selection (stand-ins included) and the solver
  settings;
* ``v<i>`` (float64, (n, 3)) and ``f<i>`` (int64, (m, 3)): the vertices and faces of part
  ``i`` in ``doc``'s part order.

:func:`decode` checks every field's type and shape while rebuilding the frozen values and
raises ``ValueError`` on anything else, so a corrupt or foreign entry is ignored (and solved
again) by the caller, never half-used.  Floats round-trip exactly (JSON writes Python's
shortest repr; arrays are stored as they are), so a plan read back builds the same PDF bytes
and plan.json as the plan that was stored.
"""

from __future__ import annotations

import io
import json
import math
import zipfile
from dataclasses import asdict, fields
from typing import Any, Callable

import numpy as np

from .candidates import Anchor, Candidate
from .config import SolverSettings
from .select import Selection
from .types import Model, Part, Primitive, Relation, readonly

#: Written into ``doc``; a different value is not this format.
FORMAT = "h2s-plan/npz-1"


# ----------------------------------------------------------------------------- encode


def _box(box: Any) -> list[list[float]]:
    return [[float(x) for x in box[0]], [float(x) for x in box[1]]]


def _candidate(c: Candidate) -> dict[str, Any]:
    return {"id": c.id, "part": c.part, "box": _box(c.box), "original": c.original,
            "parents": list(c.parents), "depth": c.depth,
            "anchors": [[a.axis, a.end, a.parent, float(a.ratio), a.guide_lines, a.face_normal,
                         a.face_side] for a in c.anchors],
            "unguided_axes": list(c.unguided_axes), "cost_adjust": float(c.cost_adjust),
            "cost_difficulty": float(c.cost_difficulty), "primitive_type": c.primitive_type,
            "axis": c.axis}


def encode(plan: Any, key: str) -> bytes:
    """The entry bytes of ``plan`` stored under ``key`` (module docstring)."""
    model: Model = plan.model
    sel: Selection = plan.selection
    doc = {
        "format": FORMAT,
        "key": key,
        "model": {"source": model.source, "units": model.units, "notes": list(model.notes),
                  "parts": [{"name": p.name, "sources": list(p.sources)} for p in model.parts]},
        "primitives": [{"part": p.part, "type": p.type, "axis": p.axis, "box": _box(p.box),
                        "residual": float(p.residual), "detail": dict(p.detail)}
                       for p in plan.primitives],
        "relations": [{"a": r.a, "b": r.b, "type": r.type, "axis": r.axis,
                       "tolerance": float(r.tolerance), "detail": dict(r.detail)}
                      for r in plan.relations],
        "candidates": [_candidate(c) for c in plan.candidates],
        "selection": {"chosen": list(sel.chosen), "objective": float(sel.objective),
                      "status": sel.status, "gap": float(sel.gap), "seconds": float(sel.seconds),
                      "formulation": sel.formulation, "optimal": sel.optimal,
                      "n_vars": sel.n_vars, "n_constraints": sel.n_constraints,
                      "weight_adjust": float(sel.weight_adjust),
                      "weight_difficulty": float(sel.weight_difficulty),
                      "max_change": float(sel.max_change),
                      "stand_ins": [_candidate(c) for c in sel.stand_ins]},
        "settings": asdict(plan.settings),
    }
    # insertion order kept: plan.json writes ``detail`` mappings in the order they were made
    text = json.dumps(doc, separators=(",", ":"), allow_nan=True)
    arrays: dict[str, np.ndarray] = {"doc": np.frombuffer(text.encode("utf-8"), dtype=np.uint8)}
    for i, p in enumerate(model.parts):
        arrays[f"v{i}"] = np.ascontiguousarray(p.vertices, dtype=np.float64)
        arrays[f"f{i}"] = np.ascontiguousarray(p.faces, dtype=np.int64)
    out = io.BytesIO()
    np.savez(out, **arrays)
    return out.getvalue()


# ----------------------------------------------------------------------------- decode


def _fail(where: str, what: str) -> ValueError:
    return ValueError(f"{where}: {what}")


def _str(x: Any, where: str) -> str:
    if not isinstance(x, str):
        raise _fail(where, "not a string")
    return x


def _bool(x: Any, where: str) -> bool:
    if not isinstance(x, bool):
        raise _fail(where, "not true or false")
    return x


def _int(x: Any, where: str) -> int:
    if isinstance(x, bool) or not isinstance(x, int):
        raise _fail(where, "not an integer")
    return x


def _float(x: Any, where: str) -> float:
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        raise _fail(where, "not a number")
    return float(x)


def _number(x: Any, where: str) -> int | float:
    """A number kept as written (a setting given as ``60`` stays an int, as in the config)."""
    _float(x, where)
    return x


def _opt(read: Callable[[Any, str], Any]) -> Callable[[Any, str], Any]:
    return lambda x, where: None if x is None else read(x, where)


def _axis(x: Any, where: str) -> int:
    if _int(x, where) not in (0, 1, 2):
        raise _fail(where, "not an axis")
    return x


def _end(x: Any, where: str) -> str:
    if _str(x, where) not in ("lo", "hi", "mid"):
        raise _fail(where, "not lo, hi or mid")
    return x


def _list(x: Any, where: str, read: Callable[[Any, str], Any]) -> tuple:
    if not isinstance(x, list):
        raise _fail(where, "not a list")
    return tuple(read(v, f"{where}[{i}]") for i, v in enumerate(x))


def _obj(x: Any, where: str, keys: set[str]) -> dict[str, Any]:
    if not isinstance(x, dict) or set(x) != keys:
        raise _fail(where, f"not an object with keys {sorted(keys)}")
    return x


def _json_value(x: Any, where: str) -> Any:
    """A plain JSON value (what ``detail`` mappings hold), rebuilt as read."""
    if x is None or isinstance(x, (bool, int, float, str)):
        return x
    if isinstance(x, list):
        return [_json_value(v, where) for v in x]
    if isinstance(x, dict):
        return {_str(k, where): _json_value(v, f"{where}.{k}") for k, v in x.items()}
    raise _fail(where, "not a JSON value")


def _detail(x: Any, where: str) -> dict[str, Any]:
    if not isinstance(x, dict):
        raise _fail(where, "not an object")
    return _json_value(x, where)


def _rbox(x: Any, where: str) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    pair = _list(x, where, lambda c, w: _list(c, w, _float))
    if len(pair) != 2 or any(len(c) != 3 for c in pair):
        raise _fail(where, "not a box")
    return pair[0], pair[1]


_CANDIDATE_KEYS = {"id", "part", "box", "original", "parents", "depth", "anchors",
                   "unguided_axes", "cost_adjust", "cost_difficulty", "primitive_type", "axis"}


def _anchor(x: Any, where: str) -> Anchor:
    if not isinstance(x, list) or len(x) != 7:
        raise _fail(where, "not an anchor")
    axis, end, parent, ratio, lines, normal, side = x
    return Anchor(_axis(axis, where), _end(end, where), _str(parent, where),
                  _float(ratio, where), _int(lines, where), _axis(normal, where),
                  _opt(_end)(side, where))


def _rcandidate(x: Any, where: str) -> Candidate:
    d = _obj(x, where, _CANDIDATE_KEYS)
    return Candidate(_str(d["id"], where), _str(d["part"], where), _rbox(d["box"], where),
                     _bool(d["original"], where), _list(d["parents"], where, _str),
                     _int(d["depth"], where), _list(d["anchors"], where, _anchor),
                     _list(d["unguided_axes"], where, _axis),
                     _float(d["cost_adjust"], where), _float(d["cost_difficulty"], where),
                     _str(d["primitive_type"], where), _opt(_axis)(d["axis"], where))


def _array(arrays: Any, name: str, dtype: Any) -> np.ndarray:
    if name not in arrays.files:
        raise _fail(name, "missing")
    a = arrays[name]
    if a.dtype != np.dtype(dtype) or a.ndim != 2 or a.shape[1] != 3:
        raise _fail(name, f"not an (n, 3) {np.dtype(dtype).name} array")
    return a


def decode(data: bytes, key: str) -> Any:
    """The plan stored in entry bytes ``data`` under ``key``.

    Raises:
        ValueError: ``data`` is not this format, is for another key, or any field has the
            wrong type or shape (the message names it).
    """
    from .plan import Plan

    try:
        arrays = np.load(io.BytesIO(data), allow_pickle=False)
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        raise ValueError(f"not an .npz archive ({exc})") from None
    if "doc" not in arrays.files or arrays["doc"].dtype != np.uint8:
        raise _fail("doc", "missing")
    try:
        doc = json.loads(arrays["doc"].tobytes().decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise _fail("doc", f"not JSON ({exc})") from None
    doc = _obj(doc, "doc", {"format", "key", "model", "primitives", "relations", "candidates",
                            "selection", "settings"})
    if doc["format"] != FORMAT:
        raise _fail("format", f"not {FORMAT}")
    if doc["key"] != key:
        raise _fail("key", "another plan's")
    m = _obj(doc["model"], "model", {"source", "units", "notes", "parts"})
    parts = []
    for i, p in enumerate(_list(m["parts"], "model.parts", lambda x, w: x)):
        p = _obj(p, f"model.parts[{i}]", {"name", "sources"})
        v = _array(arrays, f"v{i}", np.float64)
        f = _array(arrays, f"f{i}", np.int64)
        if len(f) and (int(f.min()) < 0 or int(f.max()) >= len(v)):
            raise _fail(f"f{i}", "a face index out of range")
        parts.append(Part(_str(p["name"], f"model.parts[{i}].name"), readonly(v, np.float64),
                          readonly(f, np.int64),
                          _list(p["sources"], f"model.parts[{i}].sources", _str)))
    if f"v{len(parts)}" in arrays.files:
        raise _fail(f"v{len(parts)}", "a mesh for no part")
    model = Model(_str(m["source"], "model.source"), _str(m["units"], "model.units"),
                  tuple(parts), _list(m["notes"], "model.notes", _str))

    def primitive(x: Any, where: str) -> Primitive:
        d = _obj(x, where, {"part", "type", "axis", "box", "residual", "detail"})
        return Primitive(_str(d["part"], where), _str(d["type"], where),
                         _opt(_axis)(d["axis"], where), _rbox(d["box"], where),
                         _float(d["residual"], where), _detail(d["detail"], where))

    def relation(x: Any, where: str) -> Relation:
        d = _obj(x, where, {"a", "b", "type", "axis", "tolerance", "detail"})
        return Relation(_str(d["a"], where), _str(d["b"], where), _str(d["type"], where),
                        _axis(d["axis"], where), _float(d["tolerance"], where),
                        _detail(d["detail"], where))

    s = _obj(doc["selection"], "selection", {
        "chosen", "objective", "status", "gap", "seconds", "formulation", "optimal", "n_vars",
        "n_constraints", "weight_adjust", "weight_difficulty", "max_change", "stand_ins"})
    selection = Selection(
        _list(s["chosen"], "selection.chosen", _str), _float(s["objective"], "selection"),
        _str(s["status"], "selection"), _float(s["gap"], "selection"),
        _float(s["seconds"], "selection"), _str(s["formulation"], "selection"),
        _bool(s["optimal"], "selection"), _int(s["n_vars"], "selection"),
        _int(s["n_constraints"], "selection"), _float(s["weight_adjust"], "selection"),
        _float(s["weight_difficulty"], "selection"), _float(s["max_change"], "selection"),
        _list(s["stand_ins"], "selection.stand_ins", _rcandidate))
    known = {f.name: f.type for f in fields(SolverSettings)}
    st = _obj(doc["settings"], "settings", set(known))
    readers = {"str": _str, "int": _int, "float": _number}
    settings = SolverSettings(**{k: readers[str(known[k])](v, f"settings.{k}")
                                 for k, v in st.items()})
    plan = Plan(model, _list(doc["primitives"], "primitives", primitive),
                _list(doc["relations"], "relations", relation),
                _list(doc["candidates"], "candidates", _rcandidate), selection, settings)
    _check(plan)
    return plan


def _check(plan: Any) -> None:
    """Cross-references: one primitive per part, in part order; every selected, parent and
    anchor id a candidate; every number finite where a box is."""
    names = [p.name for p in plan.model.parts]
    if [p.part for p in plan.primitives] != names:
        raise _fail("primitives", "not one per part in part order")
    ids = {c.id for c in plan.candidates}
    for c in plan.candidates:
        if c.part not in names:
            raise _fail(f"candidate {c.id}", "of no part")
        if any(p not in ids for p in c.parents) or any(a.parent not in ids for a in c.anchors):
            raise _fail(f"candidate {c.id}", "hangs off no candidate")
        if not all(math.isfinite(x) for v in c.box for x in v):
            raise _fail(f"candidate {c.id}", "box not finite")
    if any(cid not in ids for cid in plan.selection.chosen):
        raise _fail("selection.chosen", "names no candidate")
