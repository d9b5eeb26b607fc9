"""User-visible wording, read from the top-level ``templates/`` folder.

Every instruction sentence and page label lives in YAML files under ``templates/`` (one
place to reword or translate).  An installed wheel carries them as ``h2s_print/templates``
(hatchling ``force-include``); a source checkout reads the repository's folder.

Templates are ``str.format`` strings: ``text("steps", "primitive.first", part="body")``.

**Languages** (issue 15).  English is ``templates/<name>.yaml``; another language is a folder
``templates/<code>/`` with the same four files (``de``, ``fr`` ...: :data:`LANGUAGES` is
what the folder holds).  A translation has exactly the English file's keys (a missing or extra
key is an error naming the file and key, so nothing falls back to English unsaid), the same
placeholders (:data:`FIELDS`) and only characters the page font prints.  The language is
chosen per tutorial (config ``language:``) and set around its wording by :func:`using`; every
lookup reads the current one.  Plurals: a mapping whose keys are CLDR plural categories
(``one``, ``few``, ``many``, ``other`` ...) is chosen by count with the language's own rules
(Babel: Russian "1 линию, 2 линии, 5 линий"), :func:`plural`; a translation gives the
categories its language has.  Word order and grammar are the translation's: whole sentences are
templates, and names of faces, sides and dimensions are word lists in the same files.
"""

from __future__ import annotations

import contextlib
import contextvars
import functools
import re
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
        "Part", "Parts", "about", "amount", "beyond", "counts", "dim", "dims", "directions", "edge",
        "edges", "end", "face", "faces", "first", "fraction", "fractions", "half", "hi", "index",
        "kind", "label", "large", "line", "line2", "lines", "lines2", "lo", "n", "near", "new",
        "nth", "other", "other2", "others", "parent", "part", "parts", "point", "point2", "points",
        "position", "pside", "psides", "reused", "second", "shape", "shift", "side", "sides",
        "small", "start", "step", "text", "the_other", "the_others", "the_parent", "the_parents",
        "the_part", "through", "total", "turns", "turns2", "vp", "vp2", "vp3", "vp4", "where", "words")),
    "pages": frozenset((
        "corner", "distance", "dx", "dy", "edges", "example", "first", "full", "hdir", "index",
        "label", "last", "level", "lines", "minutes", "n", "names", "page", "pages", "steps",
        "the_part", "title", "vdir", "view", "vp")),
    "rank": frozenset(("condition", "count", "index", "mean", "n", "object", "pair")),
    "study": frozenset((
        "condition", "config", "fill", "margin", "n", "n_drawings", "named", "object", "page",
        "pages", "participant", "questionnaire", "rows", "sheet", "study", "title", "total",
        "view")),
}


def _validate(name: str, path: Path, node: Any, key: str = "") -> None:
    """Every text in ``node`` is a well-formed template whose placeholders are known."""
    known = FIELDS.get(name)
    for where, node_text in _texts(node, key):
        try:
            parts = list(string.Formatter().parse(node_text))
        except ValueError as exc:
            raise H2SError(f"{path}: {where}: not a valid template ({exc}): "
                           f"{node_text!r}") from None
        for _, f, _, _ in parts:
            if f is None:
                continue
            base = f.split(".")[0].split("[")[0]
            if not base or (known is not None and base not in known):
                raise H2SError(f"{path}: {where}: unknown placeholder {{{f}}} (known: "
                               f"{', '.join(sorted(known or ()))})")


def _texts(node: Any, key: str = "") -> Iterator[tuple[str, str]]:
    """(key path, text) of every template in ``node``: ``headline.first``, ``cover.how[2]``."""
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _texts(v, f"{key}.{k}" if key else str(k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _texts(v, f"{key}[{i}]")
    elif isinstance(node, str):
        yield key, node


#: CLDR plural categories: a mapping with only these keys is a plural (:func:`plural`).
PLURAL_CATEGORIES = frozenset(("zero", "one", "two", "few", "many", "other"))
ENGLISH = "en"


def languages() -> tuple[str, ...]:
    """The languages shipped: English and every folder of ``templates/`` holding a
    translation (``steps.yaml``)."""
    found = sorted(p.name for p in _folder().iterdir() if (p / "steps.yaml").is_file())
    return (ENGLISH, *found)


_language: contextvars.ContextVar[str] = contextvars.ContextVar("h2s_language",
                                                                default=ENGLISH)


def current_language() -> str:
    return _language.get()


@contextlib.contextmanager
def using(language: str | None) -> Iterator[str]:
    """Read the wording in ``language`` (``None``: English) inside the ``with`` block."""
    token = _language.set(language or ENGLISH)
    try:
        yield _language.get()
    finally:
        _language.reset(token)


def _path(name: str, language: str) -> Path:
    return _folder() / f"{name}.yaml" if language == ENGLISH else _folder() / language / f"{name}.yaml"


def _read(path: Path) -> dict[str, Any]:
    try:
        data = read_yaml(path.read_text(encoding="utf-8"))
    except (OSError, yaml.YAMLError, DuplicateKey) as exc:
        raise H2SError(f"{path}: cannot read template file: {exc}") from None
    if not isinstance(data, dict):
        raise H2SError(f"{path}: expected a mapping of template keys")
    return data


def _is_plural(node: Any) -> bool:
    return isinstance(node, dict) and bool(node) and set(node) <= PLURAL_CATEGORIES


def _same_keys(path: Path, english: Any, other: Any, language: str, key: str = "") -> None:
    """``other`` (a translation) has exactly ``english``'s keys, and each plural the
    categories its language needs."""
    where = f"{path}: {key}: " if key else f"{path}: "
    if _is_plural(english):
        if not isinstance(other, dict) or not set(other) <= PLURAL_CATEGORIES:
            raise H2SError(f"{where}expected plural forms ({', '.join(sorted(PLURAL_CATEGORIES))})")
        need = set(_plural_tags(language))
        if not need <= set(other):
            raise H2SError(f"{where}missing plural forms {', '.join(sorted(need - set(other)))} "
                           f"(the language has {', '.join(sorted(need))})")
        return
    if isinstance(english, dict):
        if not isinstance(other, dict):
            raise H2SError(f"{where}expected a mapping of keys, as in English")
        for k in english:
            if k not in other:
                raise H2SError(f"{path}: {key + '.' if key else ''}{k}: missing (the English "
                               f"file has it)")
        for k in other:
            if k not in english:
                raise H2SError(f"{path}: {key + '.' if key else ''}{k}: unknown key (not in "
                               f"the English file)")
        for k in english:
            _same_keys(path, english[k], other[k], language, f"{key}.{k}" if key else str(k))
    elif isinstance(english, list):
        if key == "orthography" and isinstance(other, list):  # a language may need no rule
            return
        if not isinstance(other, list) or not other:
            raise H2SError(f"{where}expected a list, as in English")
        if len({type(v) for v in english}) == 1 and isinstance(english[0], dict):
            for i, v in enumerate(other):
                _same_keys(path, english[0], v, language, f"{key}[{i}]")
    elif not isinstance(other, str):
        raise H2SError(f"{where}expected a text, as in English")


@functools.lru_cache(maxsize=None)
def _plural_tags(language: str) -> tuple[str, ...]:
    from babel import Locale

    return tuple(sorted(Locale.parse(language).plural_form.tags | {"other"}))


@functools.lru_cache(maxsize=None)
def _load(name: str, language: str) -> dict[str, Any]:
    path = _path(name, language)
    data = _read(path)
    _validate(name, path, data)
    if name == "steps":
        _check_orthography(path, data.get("orthography", []))
    if language != ENGLISH:
        _same_keys(path, _load(name, ENGLISH), data, language)
    return data


def load(name: str, language: str | None = None) -> dict[str, Any]:
    """The parsed ``templates/[<language>/]<name>.yaml`` (default: the current language;
    cached, treat as read-only), every template in it checked: well-formed, only the
    placeholders in :data:`FIELDS`, and (a translation) exactly the English file's keys."""
    language = language or current_language()
    if language != ENGLISH and language not in languages():
        raise H2SError(f"no wording in language {language!r} (shipped: "
                       f"{', '.join(languages())})")
    return _load(name, language)


load.cache_clear = _load.cache_clear  # type: ignore[attr-defined]


def plural(name: str, key: str, n: int, **fields: Any) -> str:
    """The plural template at ``key`` for count ``n`` in the current language's plural rules,
    formatted with ``n`` and ``fields``."""
    forms = lookup(name, key)
    if not _is_plural(forms):
        raise KeyError(f"templates/{name}.yaml: {key!r} is not a plural mapping")
    from babel import Locale

    category = Locale.parse(current_language()).plural_form(n)
    template = forms.get(category, forms["other"])
    return spelled(template.format(n=n, **fields))


def check_font(spec: fonts.FontSpec | None = None) -> None:
    """Every template's own text (placeholders aside) is printable in ``spec`` (default: the
    default page font), checked before any work so a translation in a script the font lacks
    is an error naming the file, key and character, never ``?`` on a page.

    Raises:
        H2SError: the first character the font cannot print.
    """
    _check_font(spec, current_language())


@functools.lru_cache(maxsize=16)
def _check_font(spec: fonts.FontSpec | None, language: str) -> None:
    with fonts.using(spec) as font:
        for name in FIELDS:
            path = _path(name, language)
            for key, template in _texts(load(name, language)):
                literal = "".join(lit for lit, _, _, _ in string.Formatter().parse(template))
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
    """Format the template string at ``key`` with ``fields``, then spell it by the language's
    rules (:func:`spelled`)."""
    template = lookup(name, key)
    if not isinstance(template, str):
        raise KeyError(f"templates/{name}.yaml: {key!r} is not a text template")
    return spelled(template.format(**fields))


def spelled(sentence: str) -> str:
    """``sentence`` with the current language's spelling rules applied (``orthography`` in
    ``templates/steps.yaml``: regular expression, replacement): English writes a plural
    name's possessive with the apostrophe alone, "the sides' top face", where the templates'
    ``{the_parent}'s`` gave "the sides's"."""
    for pattern, replacement in load("steps").get("orthography", ()):
        sentence = re.sub(pattern, replacement, sentence)  # re caches the compiled pattern
    return sentence


def _check_orthography(path: Path, rules: Any) -> None:
    """``orthography`` is a list of [regular expression, replacement] pairs."""
    for i, rule in enumerate(rules if isinstance(rules, list) else [rules]):
        try:
            if not (isinstance(rule, list) and len(rule) == 2
                    and all(isinstance(x, str) for x in rule)):
                raise ValueError(f"not a pair of texts: {rule!r}")
            pattern, replacement = rule
            re.compile(pattern)
            re.sub(pattern, replacement, "")
        except (re.error, TypeError, ValueError) as exc:
            raise H2SError(f"{path}: orthography[{i}]: expected a regular expression and its "
                           f"replacement ({exc})") from None


check_font.cache_clear = _check_font.cache_clear  # type: ignore[attr-defined]
