"""A content-addressed cache of model-level plans (stages 1-5) under the output folder.

Stages 1-5 (load, fit, relate, candidates, select) depend only on the model files and the
settings that read and solve them, never on a view, level or paper; they are also the slow part
when SCIP works hard.  ``h2s build`` and ``h2s plan`` keep each solved :class:`~h2s_print.plan.Plan`
in ``DIR/.h2s-cache/<key>.h2splan`` so a rebuild after changing one tutorial re-solves only it.

The key (:func:`plan_key`) is the SHA-256 of a canonical JSON document holding:

* the bytes of the model file, or of every file under a model folder (relative path and
  SHA-256 of each, sorted; names starting with ``.`` skipped);
* the :class:`~h2s_print.config.ModelSpec` (absolute path, ``up``, ``units``, ``parts``: the
  path is in the plan's ``model.source``);
* every field of :class:`~h2s_print.config.SolverSettings`;
* the h2s version, a hash of the package's own source files (so an edited checkout never reads
  a stale plan), and the versions of numpy, scipy, trimesh and pyscipopt.

An entry is ``MAGIC`` + SHA-256 of the payload + the payload: the plan as plain data
(:mod:`h2s_print.planfile`: JSON and NumPy arrays in an ``.npz`` read with
``allow_pickle=False``), never a pickle, so reading an entry from a shared output folder cannot
run code.  An entry that is truncated, altered, unreadable, of another format, for another key,
or whose fields do not check (types, shapes, cross-references) is ignored, with a warning, and
rewritten by the caller.  Entries are written atomically.  Entries of the older pickle format
(``<key>.pickle``) are never read.
"""

from __future__ import annotations

import functools
import hashlib
import json
import logging
from dataclasses import asdict
from pathlib import Path
from typing import Any, Sequence

from . import __version__
from .config import ModelSpec, SolverSettings, ViewSpec
from .errors import H2SError
from .files import write_bytes_atomic
from .planfile import decode, encode

log = logging.getLogger(__name__)

#: The cache folder's name inside the output folder.
CACHE_DIR = ".h2s-cache"
#: First bytes of every entry; bump the number when the entry layout changes.
MAGIC = b"h2s-plan-cache/2\n"
_DIGEST = 32  # bytes of a SHA-256 digest
_CHUNK = 1 << 20


def cache_folder(out_dir: Path) -> Path:
    """Where ``h2s`` keeps plans for outputs under ``out_dir``."""
    return Path(out_dir) / CACHE_DIR


def _file_sha(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as handle:
        for chunk in iter(lambda: handle.read(_CHUNK), b""):
            h.update(chunk)
    return h.hexdigest()


def model_files(path: Path) -> list[tuple[str, Path]]:
    """``(name, file)`` for a model file, or for every file under a model folder (sorted).

    Names are paths relative to the folder (POSIX style); files and folders whose name starts
    with ``.`` are skipped.
    """
    path = Path(path)
    if path.is_file():
        return [(path.name, path)]
    out = []
    for f in sorted(path.rglob("*")):
        rel = f.relative_to(path)
        if any(part.startswith(".") for part in rel.parts) or not f.is_file():
            continue
        out.append((rel.as_posix(), f))
    return out


@functools.lru_cache(maxsize=1)
def _code_identity() -> dict[str, Any]:
    from importlib import metadata

    libs = {}
    for name in ("numpy", "scipy", "trimesh", "pyscipopt"):
        try:
            libs[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            libs[name] = None
    return {"h2s": __version__, "source": source_hash(Path(__file__).resolve().parent),
            "libs": libs}


def source_hash(package: Path) -> str:
    """A hash of every ``.py`` file under ``package``, subpackages included (the sequence
    stage is one), by path and contents."""
    h = hashlib.sha256()
    for f in sorted(package.rglob("*.py")):
        h.update(f.relative_to(package).as_posix().encode() + b"\0" + f.read_bytes() + b"\0")
    return h.hexdigest()


def plan_key(spec: ModelSpec, settings: SolverSettings,
             views: Sequence[ViewSpec] = ()) -> str | None:
    """The content hash (64 hex digits) of everything stages 1-5 read (of the views, the eyes
    that break the selection's ties: ``plan.part_farness``); ``None`` when the model files
    cannot be read (then nothing is cached and the loader reports the problem)."""
    try:
        files = [[name, _file_sha(f)] for name, f in model_files(spec.path)]
    except OSError:
        return None
    if not files:
        return None
    doc = {
        "code": _code_identity(),
        "model": {"path": str(spec.path), "up": spec.up, "units": spec.units,
                  "parts": asdict(spec.parts)},
        "solver": asdict(settings),
        "eyes": [[v.azimuth_deg, v.elevation_deg, v.distance] for v in views],
        "files": files,
    }
    text = json.dumps(doc, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def entry_path(folder: Path, key: str) -> Path:
    """The file of cache entry ``key`` in ``folder``."""
    return Path(folder) / f"{key}.h2splan"


def load_plan(folder: Path, key: str) -> Any | None:
    """The plan cached under ``key``, or ``None`` when absent, corrupt or not a plan."""
    path = entry_path(folder, key)
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        return None
    except OSError as exc:
        log.warning("%s: cache entry unreadable (%s); solving again", path, exc.strerror or exc)
        return None
    head = len(MAGIC) + _DIGEST
    payload = data[head:]
    if (len(data) <= head or not data.startswith(MAGIC)
            or hashlib.sha256(payload).digest() != data[len(MAGIC):head]):
        log.warning("%s: corrupt cache entry ignored; solving again", path)
        return None
    try:
        return decode(payload, key)
    except ValueError as exc:
        log.warning("%s: unusable cache entry ignored (%s); solving again", path, exc)
        return None


#: Selection statuses worth keeping: proven optimal, or the best found within
#: ``solver.time_limit_s`` (a longer limit changes the key).  Anything else (interrupted,
#: memory or node limit ...) is solved again next time.
CACHEABLE_STATUSES = ("optimal", "time_limit")


def cacheable(plan: Any) -> bool:
    """Whether ``plan``'s selection may be cached (its status is in ``CACHEABLE_STATUSES``)."""
    return plan.selection.status in CACHEABLE_STATUSES


def store_plan(folder: Path, key: str, plan: Any) -> Path | None:
    """Write ``plan`` as entry ``key`` (atomically); ``None`` when it cannot be written or is
    not :func:`cacheable`.

    A cache that cannot be written is not an error: the build goes on without it.
    """
    if not cacheable(plan):
        log.info("plan not cached: its selection ended with SCIP status %s",
                 plan.selection.status)
        return None
    try:
        payload = encode(plan, key)
    except (TypeError, ValueError) as exc:  # a value plain data cannot hold: a bug, not fatal
        log.warning("plan cache not written: %s", exc)
        return None
    data = MAGIC + hashlib.sha256(payload).digest() + payload
    try:
        return write_bytes_atomic(entry_path(folder, key), data)
    except H2SError as exc:
        log.warning("plan cache not written: %s", exc)
        return None
