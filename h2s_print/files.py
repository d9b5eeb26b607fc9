"""Writing outputs safely: the only place the pipeline creates files.

Every output is written to a temporary file in the destination folder and renamed over the
target only when complete (``os.replace`` is atomic on one file system), so an error or
Ctrl-C never leaves a half-written PDF or plan.json, and an existing output is only ever
replaced by a complete one.
"""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path
from typing import Any

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
    """Write ``data`` to ``path`` atomically (temp file + rename)."""
    path = Path(path)
    ensure_folder(path.parent)
    fd, tmp = -1, ""
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=path.parent)
        os.fchmod(fd, 0o666 & ~_umask())  # mkstemp makes 0600; outputs are ordinary files
        with os.fdopen(fd, "wb") as handle:
            fd = -1
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp, path)
        tmp = ""
    except OSError as exc:
        raise RenderError(f"{path}: cannot write: {exc.strerror or exc}") from None
    finally:
        if fd >= 0:
            os.close(fd)
        if tmp and os.path.exists(tmp):
            os.unlink(tmp)
    return path


def dumps_json(data: Any) -> str:
    """Stable, readable JSON text (sorted keys are NOT used: field order is the contract's)."""
    return json.dumps(data, indent=1, ensure_ascii=False, allow_nan=False) + "\n"


def write_json_atomic(path: Path, data: Any) -> Path:
    """Write ``data`` as JSON to ``path`` atomically."""
    return write_bytes_atomic(path, dumps_json(data).encode("utf-8"))
