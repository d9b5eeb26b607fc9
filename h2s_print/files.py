"""Writing outputs safely: the only place the pipeline creates files.

Every output is written to a temporary file in the destination folder and renamed over the
target only when complete (``os.replace`` is atomic on one file system), so an error or
Ctrl-C never leaves a half-written PDF or plan.json, and an existing output is only ever
replaced by a complete one.  :func:`write_many_atomic` writes a build's files together: all
complete temporary files first, then only renames.  :func:`check_writable` checks ``-o`` before
any work is done.
"""

from __future__ import annotations

import json
import math
import os
import tempfile
from pathlib import Path
from typing import Any, Sequence

from .errors import RenderError


def ensure_folder(folder: Path) -> Path:
    """Create ``folder`` (and parents) or raise RenderError naming it."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise RenderError(f"{folder}: cannot create output folder: {exc.strerror or exc}") from None
    if not os.access(folder, os.W_OK):
        raise RenderError(f"{folder}: output folder is not writable")
    return folder


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_bytes_atomic(path: Path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (temp file + rename).

    Raises:
        RenderError: naming ``path`` when its folder cannot be created or it cannot be written.
    """
    path = Path(path)
    ensure_folder(path.parent)
    tmp = _write_temp(path, data)
    try:
        os.replace(tmp, path)
        tmp = ""
    except OSError as exc:
        raise RenderError(f"{path}: cannot write: {exc.strerror or exc}") from None
    finally:
        if tmp and os.path.exists(tmp):
            os.unlink(tmp)
    return path


_FLAT = json.JSONEncoder(ensure_ascii=False, allow_nan=False, separators=(", ", ": "))
_NUMBER_TYPES = frozenset((int, float))


def _flat(value: Any) -> bool:
    """A list of numbers, or of such lists (a point, a box, a polyline): written on one line."""
    if not isinstance(value, list):
        return False
    # The common cases decided by the elements' exact types (C-level): a point's floats, a
    # polyline's points.  Anything else (a bool, a subclass) by the definition below.
    types = set(map(type, value))
    if types <= _NUMBER_TYPES:
        return True
    if types <= {int, float, list}:
        return all(_flat(x) for x in value if type(x) is list)
    return all((isinstance(x, (int, float)) and not isinstance(x, bool)) or _flat(x)
               for x in value)


def _scalar(value: Any) -> str:
    """``value`` as the C encoder writes it: ``_FLAT.encode`` made one encoder per call, the
    cost of a plan's 100 000 scalars and keys; exact str, float and int are what it writes
    for them (``encode_basestring``, ``float.__repr__`` of a finite float, ``int.__repr__``),
    anything else still goes through it."""
    kind = type(value)
    if kind is str:
        return json.encoder.encode_basestring(value)
    if kind is float and math.isfinite(value):
        return float.__repr__(value)
    if kind is int:
        return int.__repr__(value)
    return _FLAT.encode(value)


def _one_line(value: list, memo: dict[float, str]) -> str | None:
    """``value`` on one line, as the C encoder writes it, when it is :func:`_flat`; else None.

    A plan's floats are mostly a few, again and again (the example book's plans: 192 000
    floats, 22 000 different: corners shared by boxes, guides and strokes) and their repr
    was most of the writing, so each float's text is made once (``memo``).  A list of
    exact floats, or of such lists, is joined here; any other flat list goes to the encoder.
    """
    types = set(map(type, value))
    if types == {float}:
        texts = list(map(memo.get, value))
        if None in texts:
            for i, text in enumerate(texts):
                if text is None:
                    x = value[i]
                    texts[i] = text = _scalar(x)  # a non-finite float raises, as it did
                    if x:  # zeros never: 0.0 and -0.0 are one key but two texts
                        memo[x] = text
    elif types == {list}:
        texts = [_one_line(v, memo) for v in value]
        if None in texts:
            return None
    else:
        return _FLAT.encode(value) if _flat(value) else None
    return "[" + ", ".join(texts) + "]"


def _write(value: Any, depth: int, out: list[str], memo: dict[float, str]) -> None:
    pad = "\n" + " " * (depth + 1)
    if isinstance(value, dict) and value:
        out.append("{")
        sep = pad
        for k, v in value.items():
            out.append(sep + _scalar(str(k)) + ": ")
            _write(v, depth + 1, out, memo)
            sep = "," + pad
        out.append("\n" + " " * depth + "}")
    elif isinstance(value, list):
        text = _one_line(value, memo)  # numbers, or empty
        if text is not None:
            out.append(text)
            return
        out.append("[")
        sep = pad
        for v in value:
            out.append(sep)
            _write(v, depth + 1, out, memo)
            sep = "," + pad
        out.append("\n" + " " * depth + "]")
    else:  # a scalar, an empty dict, or another container (C encoder, one line)
        out.append(_scalar(value))


def dumps_json(data: Any) -> str:
    """Stable, readable JSON text: one key a line, indented by one space a level, but a list
    of numbers (a point, a box, a polyline of points) on one line.  Keys keep their order
    (the contract's field order, not sorted).  Written by :func:`_write`, each float's text
    made once and other one-line values by the C encoder: the stdlib's indenting encoder is
    pure Python (0.38 s for the example book's plans, which are mostly numbers); this takes
    0.16 s and a third of the bytes."""
    out: list[str] = []
    _write(data, 0, out, {})
    return "".join(out) + "\n"


def write_json_atomic(path: Path, data: Any) -> Path:
    """Write ``data`` as JSON to ``path`` atomically."""
    return write_bytes_atomic(path, dumps_json(data).encode("utf-8"))


def check_writable(folder: Path) -> Path:
    """Check, without creating anything, that ``folder`` can be created or written.

    Walks up to the nearest existing ancestor: it must be a folder and writable.  Catches ``-o``
    pointing at a file, or below one, before any work is done.

    Raises:
        RenderError: naming ``folder`` and what is wrong.
    """
    folder = Path(folder)
    probe = folder
    while not probe.exists():
        if probe.parent == probe:
            break
        probe = probe.parent
    if probe.exists() and not probe.is_dir():
        what = "is a file" if probe == folder else f"is below the file {probe}"
        raise RenderError(f"{folder}: cannot write outputs there: it {what} "
                          "(-o must name a folder)")
    if probe.exists() and not os.access(probe, os.W_OK | os.X_OK):
        raise RenderError(f"{folder}: cannot write outputs there: {probe} is not writable")
    return folder


def write_many_atomic(items: Sequence[tuple[Path, bytes]]) -> list[Path]:
    """Write several files as nearly all-or-nothing as one file system allows.

    Phase 1 writes every file's bytes to a temporary file next to it (fsynced); if any write
    fails, or the user presses Ctrl-C, every temporary file is removed and no target changes.
    Phase 2 renames each temporary file over its target (``os.replace``, atomic per file); only
    a failure or Ctrl-C inside these few renames can leave some targets new and others old,
    and each file is always complete.

    Args:
        items: ``(path, bytes)`` pairs; paths must be distinct.

    Returns:
        The paths written, in ``items`` order.

    Raises:
        RenderError: naming the first path that cannot be written.
    """
    temps: list[str] = []
    done = False
    try:
        for path, data in items:
            path = Path(path)
            if path.is_dir():  # found now, not halfway through the renames
                raise RenderError(f"{path}: cannot write: a folder of that name is in the way")
            ensure_folder(path.parent)
            temps.append(_write_temp(path, data))
        for (path, _), tmp in zip(items, temps):
            try:
                os.replace(tmp, path)
            except OSError as exc:
                raise RenderError(f"{path}: cannot write: {exc.strerror or exc}") from None
        done = True
    finally:
        if not done:
            for tmp in temps:
                if os.path.exists(tmp):
                    os.unlink(tmp)
    return [Path(p) for p, _ in items]


def _write_temp(path: Path, data: bytes) -> str:
    """``data`` in a complete, fsynced temporary file in ``path``'s folder; returns its name."""
    fd, tmp = -1, ""
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=path.parent)
        os.fchmod(fd, 0o666 & ~_umask())  # mkstemp makes 0600; outputs are ordinary files
        with os.fdopen(fd, "wb") as handle:
            fd = -1
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        name, tmp = tmp, ""
        return name
    except OSError as exc:
        raise RenderError(f"{path}: cannot write: {exc.strerror or exc}") from None
    finally:
        if fd >= 0:
            os.close(fd)
        if tmp and os.path.exists(tmp):
            os.unlink(tmp)
