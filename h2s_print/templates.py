"""User-visible wording, read from the top-level ``templates/`` folder.

Every instruction sentence and page label lives in YAML files under ``templates/`` (one
place to reword or translate).  An installed wheel carries them as ``h2s_print/templates``
(hatchling ``force-include``); a source checkout reads the repository's folder.

Templates are ``str.format`` strings: ``text("steps", "primitive.first", part="body")``.
"""

from __future__ import annotations

import functools
import string
from importlib import resources
from pathlib import Path
from collections.abc import Iterator
from typing import Any

import yaml

from . import fonts
from .errors import H2SError
from .glyphs import describe, unprintable
from .yamlfile import DuplicateKey, read_yaml


def _folder() -> Path:
    packaged = resources.files("h2s_print") / "templates"
    if packaged.is_dir():
        return Path(str(packaged))
    return Path(__file__).resolve().parents[1] / "templates"


#: The fields the code fills in each template file: a placeholder not listed is a typo (a
#: translator's ``{prat}``), refused when the file is read rather than mid-build.
FIELDS: dict[str, frozenset[str]] = {
    "steps": frozenset((
        "Part", "Parts", "about", "amount", "counts", "dim", "dims", "edge", "edges", "end",
        "face", "faces", "first", "fraction", "half", "hi", "index", "kind", "label", "line",
        "lines", "lines2", "lo", "n", "new", "other", "parent", "part", "parts", "point",
        "points", "position", "pside", "psides", "directions", "reused", "second", "shape", "side", "sides", "start",
        "step", "text", "the_other", "the_parent", "the_parents", "the_part", "through", "vp",
        "vp2", "where", "words")),
    "pages": frozenset((
        "corner", "distance", "dx", "dy", "edges", "first", "full", "hdir", "index", "label",
        "last", "level", "minutes", "n", "page", "pages", "the_part", "title", "vdir", "view",
        "vp")),
    "rank": frozenset(("condition", "count", "index", "mean", "n", "object", "pair")),
    "study": frozenset((
        "condition", "config", "fill", "margin", "n", "n_drawings", "object", "page", "pages",
        "participant", "questionnaire", "rows", "sheet", "study", "title", "total", "view")),
}


def _validate(name: str, path: Path, node: Any, key: str = "") -> None:
    """Every text in ``node`` is a well-formed template whose placeholders are known."""
    if isinstance(node, dict):
        for k, v in node.items():
            _validate(name, path, v, f"{key}.{k}" if key else str(k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            _validate(name, path, v, f"{key}[{i}]")
    elif isinstance(node, str):
        try:
            parts = list(string.Formatter().parse(node))
        except ValueError as exc:
            raise H2SError(f"{path}: {key}: not a valid template ({exc}): {node!r}") from None
        fields = [f for _, f, _, _ in parts if f is not None]
        known = FIELDS.get(name)
        for f in fields:
            base = f.split(".")[0].split("[")[0]
            if not base or (known is not None and base not in known):
                raise H2SError(f"{path}: {key}: unknown placeholder {{{f}}} (known: "
                               f"{', '.join(sorted(known or ()))})")


@functools.lru_cache(maxsize=None)
def load(name: str) -> dict[str, Any]:
    """The parsed ``templates/<name>.yaml`` (cached; treat as read-only), every template in it
    checked: well-formed, and only the placeholders in :data:`FIELDS`."""
    path = _folder() / f"{name}.yaml"
    try:
        data = read_yaml(path.read_text(encoding="utf-8"))
    except (OSError, yaml.YAMLError, DuplicateKey) as exc:
        raise H2SError(f"{path}: cannot read template file: {exc}") from None
    if not isinstance(data, dict):
        raise H2SError(f"{path}: expected a mapping of template keys")
    _validate(name, path, data)
    return data


def _literals(node: Any, key: str = "") -> Iterator[tuple[str, str]]:
    """(key path, literal text) of every template in ``node``."""
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _literals(v, f"{key}.{k}" if key else str(k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _literals(v, f"{key}[{i}]")
    elif isinstance(node, str):
        yield key, "".join(lit for lit, _, _, _ in string.Formatter().parse(node))


@functools.lru_cache(maxsize=8)
def check_font(spec: fonts.FontSpec | None = None) -> None:
    """Every template's own text (placeholders aside) is printable in ``spec`` (default: the
    default page font), checked before any work so a translation in a script the font lacks
    is an error naming the file, key and character, never ``?`` on a page.

    Raises:
        H2SError: the first character the font cannot print.
    """
    with fonts.using(spec) as font:
        for name in FIELDS:
            path = _folder() / f"{name}.yaml"
            for key, literal in _literals(load(name)):
                ch = unprintable(literal)
                if ch is not None:
                    raise H2SError(f"{path}: {key}: character {describe(ch)} cannot be printed "
                                   f"in the page font ({font.name})")


def lookup(name: str, key: str) -> Any:
    """The raw value at dotted ``key`` in ``templates/<name>.yaml``."""
    node: Any = load(name)
    for piece in key.split("."):
        if not isinstance(node, dict) or piece not in node:
            raise KeyError(f"templates/{name}.yaml has no key {key!r}")
        node = node[piece]
    return node


def the(label: str) -> str:
    """A part's name with its article (``templates/steps.yaml`` ``article``): "the lens", but
    "part 3" (a name ending in a number takes none)."""
    key = "numbered" if label[-1:].isdigit() else "definite"
    return text("steps", f"article.{key}", label=label)


def text(name: str, key: str, **fields: Any) -> str:
    """Format the template string at ``key`` with ``fields``."""
    template = lookup(name, key)
    if not isinstance(template, str):
        raise KeyError(f"templates/{name}.yaml: {key!r} is not a text template")
    return template.format(**fields)
