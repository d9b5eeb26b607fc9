"""The plan cache's entry format (issue 13): plain data only, exact round trip, every field
checked when read."""

from __future__ import annotations

import io
import json
import pickle

import numpy as np
import pytest

from h2s_print import cache, planfile
from h2s_print.config import load_tutorial
from h2s_print.plan import build_plan, plan_json

from conftest import CONFIGS

KEY = "a" * 64


@pytest.fixture(scope="module")
def camera_plan():  # the mixer: its relations' details carry contact and flush keys
    t = load_tutorial(CONFIGS / "mixer.yaml")
    return build_plan(t.model, t.solver, t.views)


def _same(a, b) -> None:
    assert json.dumps(plan_json(a)) == json.dumps(plan_json(b))  # key order included
    assert a.model.notes == b.model.notes and a.settings == b.settings
    assert a.selection == b.selection
    assert a.candidates == b.candidates and a.primitives == b.primitives
    assert a.relations == b.relations
    for p, q in zip(a.model.parts, b.model.parts):
        assert p.name == q.name and p.sources == q.sources
        assert p.vertices.dtype == q.vertices.dtype and np.array_equal(p.vertices, q.vertices)
        assert np.array_equal(p.faces, q.faces) and not q.vertices.flags.writeable


def test_a_plan_round_trips_exactly(camera_plan):
    back = planfile.decode(planfile.encode(camera_plan, KEY), KEY)
    _same(camera_plan, back)


def test_an_entry_holds_no_pickle_and_is_read_without_one(camera_plan, monkeypatch):
    data = planfile.encode(camera_plan, KEY)
    with np.load(io.BytesIO(data), allow_pickle=False) as arrays:  # readable with pickles off
        assert all(arrays[n].dtype != object for n in arrays.files)

    def refuse(*args, **kwargs):
        raise AssertionError("pickle used")
    monkeypatch.setattr(pickle, "loads", refuse)
    monkeypatch.setattr(pickle, "load", refuse)
    _same(camera_plan, planfile.decode(data, KEY))


def test_a_pickle_in_the_cache_is_never_run(tmp_path, camera_plan):
    """An entry made of a pickle that would run code when unpickled is ignored."""
    class Boom:
        def __reduce__(self):
            return (open, (str(tmp_path / "ran"), "w"))
    payload = pickle.dumps((KEY, Boom()))
    import hashlib
    entry = cache.entry_path(tmp_path, KEY)
    entry.write_bytes(cache.MAGIC + hashlib.sha256(payload).digest() + payload)
    assert cache.load_plan(tmp_path, KEY) is None
    assert not (tmp_path / "ran").exists()
    # an object array inside an .npz is refused too (allow_pickle=False)
    out = io.BytesIO()
    np.savez(out, doc=np.array([Boom()], dtype=object))
    with pytest.raises(ValueError):
        planfile.decode(out.getvalue(), KEY)
    assert not (tmp_path / "ran").exists()


def _tampered(data: bytes, edit) -> bytes:
    with np.load(io.BytesIO(data), allow_pickle=False) as arrays:
        items = {n: arrays[n] for n in arrays.files}
    doc = json.loads(items["doc"].tobytes().decode())
    edit(doc, items)
    items["doc"] = np.frombuffer(json.dumps(doc).encode(), dtype=np.uint8)
    out = io.BytesIO()
    np.savez(out, **items)
    return out.getvalue()


@pytest.mark.parametrize("edit, field", [
    (lambda d, a: d.__setitem__("key", "b" * 64), "key"),
    (lambda d, a: d.__setitem__("format", "other"), "format"),
    (lambda d, a: d["primitives"][0].__setitem__("box", [[0, 0], [1, 1]]), "primitives[0]"),
    (lambda d, a: d["primitives"][0].__setitem__("axis", 3), "primitives[0]"),
    (lambda d, a: d["candidates"][0].__setitem__("depth", "1"), "candidates[0]"),
    (lambda d, a: d["candidates"][0].__setitem__("extra", 1), "candidates[0]"),
    (lambda d, a: d["selection"].__setitem__("optimal", 1), "selection"),
    (lambda d, a: d["selection"].__setitem__("chosen", ["nobody"]), "selection.chosen"),
    (lambda d, a: d["settings"].__setitem__("depth", 2.5), "settings.depth"),
    (lambda d, a: d["model"]["parts"].pop(), "v5"),  # the last part's mesh, orphaned
    (lambda d, a: d["primitives"].pop(), "primitives"),
    (lambda d, a: a.__setitem__("v0", a["v0"].astype(np.float32)), "v0"),
    (lambda d, a: a.__setitem__("f0", a["f0"] + 10 ** 6), "f0"),
    (lambda d, a: a.pop("f1"), "f1"),
])
def test_a_field_of_the_wrong_type_or_shape_is_refused_by_name(camera_plan, edit, field):
    bad = _tampered(planfile.encode(camera_plan, KEY), edit)
    with pytest.raises(ValueError, match=field.replace("[", r"\[").replace("]", r"\]")):
        planfile.decode(bad, KEY)


def test_the_cache_ignores_an_entry_that_does_not_check_and_says_why(tmp_path, camera_plan,
                                                                     caplog):
    import hashlib
    payload = _tampered(planfile.encode(camera_plan, KEY),
                        lambda d, a: d["selection"].__setitem__("status", 7))
    cache.entry_path(tmp_path, KEY).write_bytes(
        cache.MAGIC + hashlib.sha256(payload).digest() + payload)
    assert cache.load_plan(tmp_path, KEY) is None
    assert "unusable cache entry ignored (selection: not a string)" in caplog.text
    assert cache.store_plan(tmp_path, KEY, camera_plan) is not None
    _same(camera_plan, cache.load_plan(tmp_path, KEY))


def test_the_cache_key_sees_every_source_file_subpackages_included(tmp_path):
    """An edited checkout never reads a stale plan: a change to a module in a subpackage (the
    sequence stage is one) changes the source hash, as a top-level module's does."""
    pkg = tmp_path / "pkg"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "a.py").write_text("A = 1\n")
    (pkg / "sub" / "b.py").write_text("B = 1\n")
    before = cache.source_hash(pkg)
    (pkg / "sub" / "b.py").write_text("B = 2\n")
    edited = cache.source_hash(pkg)
    assert edited != before
    (pkg / "a.py").write_text("A = 2\n")
    assert cache.source_hash(pkg) != edited
    # a file moved into a subpackage is a different source tree
    (pkg / "sub" / "b.py").rename(pkg / "b.py")
    moved = cache.source_hash(pkg)
    (pkg / "b.py").rename(pkg / "sub" / "b.py")
    assert cache.source_hash(pkg) != moved
