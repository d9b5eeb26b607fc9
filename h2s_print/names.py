"""What printed texts call each part: its own name when that reads as words, else a short label.

Part names come from the model file (glTF node names, OBJ groups, PartNet leaves ...) or from the
config's ``parts.rename``.  Many public models name parts by ids (``0_part0``,
``dowel_1_9_6_8_7``, ``mesh_0_3``, ``Node.004``); printed in a sentence they read as noise.  Such
a part is called by a short numbered label (``part 12``) drawn on the picture next to it, and the
cover lists every label with the part's full name.  Renaming the part in the config
(``parts.rename``) to a readable name gives it back a name.

Public verbs: :func:`readable` (one name) and :func:`display_names` (every part's
:class:`PartName`).  Pure functions, no I/O: the label wording is a ``str.format`` string with a
field ``{n}`` passed by the caller, read from ``templates/`` (the default ``"part {n}"`` is only a
fallback for tests and direct calls).

The rule (:func:`readable`), decisions kept in one place:

* **Tokens**: the name is split on whitespace, ``_``, ``-`` and ``.`` (empty pieces dropped):
  ``"shutter_button"`` -> ``shutter``, ``button``; ``"Node.004"`` -> ``Node``, ``004``.
* A name is **readable** when all of these hold:

  - at most :data:`ID_LIKE_TOKENS_MAX` tokens (``"bearing 1 23 2 16 4 13 10 12 11"`` has 10);
  - at least one **word**: a token of letters only, at least :data:`WORD_MIN_LETTERS` long;
  - at most one token holds a digit, and that token is the **last** one, a plain **number**:
    digits only, at most :data:`NUMBER_MAX_DIGITS` of them, no leading zero (``"wheel_1"``,
    ``"leg 12"``, ``"wheel_0"``; not ``"5_body"``, ``"mesh_0_3"``, ``"Node.004"``, whose
    zero-padded counter is what 3D tools append to copies, ``"Cube.001"``);
  - so no token looks like an **id**: a token mixing letters and digits (``a3f9``, ``part0``,
    ``node12``, ``polySurface3``) holds a digit without being a number.  Hex strings
    (``3f9a0c``, uuid pieces) mix letters and digits or, all digits, are longer than a number;
    an all-letter word that happens to be hex (``facade``, ``decade``) stays a word;
  - not every word is a **generic** word of 3D tools (:data:`GENERIC_WORDS`: ``mesh``, ``node``,
    ``object``, ``original`` ...): ``"original-12"`` or ``"mesh 3"`` name no thing.
    ``part`` is not generic: ``"part 2"`` reads exactly as a label would.

* **Labels** (:func:`display_names`): a readable part's label is its name with ``_`` shown as a
  space (``"shutter_button"`` -> ``"shutter button"``, as the step texts print it).  The
  unreadable names are sorted (plain string order) and numbered 1, 2, 3 ... in that order, so the
  numbering depends on the set of names, never on the order they come in.  A number whose label
  is already a readable name's label (``"part 2"`` literally) is skipped.
* **Words kept from ids**: an unreadable name that still carries words (PartNet's
  ``"10_base_body"``, a CAD export's ``"dowel_1_9_6_8_7"``) is called by those words
  (:func:`base_words`: ``"base body"``, ``"dowel"``), numbered when several parts share them
  (``"knob 1"``, ``"knob 2"`` ... in natural order of the names, ``2_knob`` before
  ``10_knob``); only names with no such words get a ``part N`` label.  Either way the label is
  not the part's own name (``PartName.readable`` False): it is drawn on the picture next to the
  part and listed on the cover.
* **Unique labels**: labels are compared case-insensitively, with runs of spaces as one
  (``"Part 2"`` and ``"part_2"`` would be read as the same thing).  When two readable names would
  show the same label (``"wheel_1"`` and ``"wheel 1"``), neither keeps it: both are numbered
  with the unreadable ones (and no number gets that label), so no text is ambiguous and no input
  order decides who wins.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Sequence

#: A readable name has at most this many tokens; more ("bearing 1 23 2 16 4 13 10 12 11",
#: "part 3 7 9") read as an id or a path, not as a thing's name.  Three allows "left door
#: hinge" and "frame shaft 2".
ID_LIKE_TOKENS_MAX = 3

#: A word is a token of at least this many letters; a readable name needs one ("leg" yes, the
#: lone "x" or "a" of "a 3" no).
WORD_MIN_LETTERS = 2

#: The one number a readable name may end with has at most this many digits ("leg 12",
#: "wheel 100"); longer ones ("bolt 4711", timestamps, ids) are catalogue numbers, not counts.
NUMBER_MAX_DIGITS = 3

#: Words that 3D tools and datasets put in generated names; a name whose every word is one of
#: these names no thing ("mesh_3", "Object.2", "original-12", "node").  Compared in lower case.
GENERIC_WORDS = frozenset({
    "component", "default", "geom", "geometry", "group", "instance", "mesh", "node", "obj",
    "object", "original", "polysurface", "primitive", "untitled",
})

#: Words that alone name no particular part when kept from an id ("part 3 7 9" is not "part").
LABEL_WORDS = frozenset({"part", "parts", "piece", "pieces", "item"})

_SEPARATORS = re.compile(r"[\s_.\-]+")
_NUMBER = re.compile(r"0|[1-9][0-9]*")


@dataclass(frozen=True, slots=True)
class PartName:
    """What texts call one part.

    Attributes:
        part: the part's name in the model and the plan (unchanged, the key of every lookup).
        label: what texts call it: the name with ``_`` shown as a space when :attr:`readable`,
            else the numbered label (``"part 3"``).
        readable: the label is the part's own name.  False for names :func:`readable` rejects,
            and for readable names whose label another part's label equals (``"wheel_1"`` and
            ``"wheel 1"``): those are numbered too.
    """

    part: str
    label: str
    readable: bool


def tokens(name: str) -> tuple[str, ...]:
    """``name`` split on whitespace, ``_``, ``-`` and ``.``, empty pieces dropped."""
    return tuple(t for t in _SEPARATORS.split(name) if t)


def _has_digit(token: str) -> bool:
    return any(c.isdigit() for c in token)


def _word(token: str) -> bool:
    return token.isalpha() and len(token) >= WORD_MIN_LETTERS


def readable(name: str) -> bool:
    """Whether ``name`` reads as words in a sentence (the rule is in the module docstring).

    >>> [readable(n) for n in ("shutter_button", "wheel_1", "0_part0", "original-12")]
    [True, True, False, False]
    """
    toks = tokens(name)
    if not toks or len(toks) > ID_LIKE_TOKENS_MAX:
        return False
    words = [t for t in toks if _word(t)]
    if not words or all(w.lower() in GENERIC_WORDS for w in words):
        return False
    numbered = [t for t in toks if _has_digit(t)]  # ids (mixed "a3f9") count here and fail
    if not numbered:
        return True
    last = toks[-1]  # the one numbered token must be the last, and a plain number
    return (len(numbered) == 1 and len(last) <= NUMBER_MAX_DIGITS
            and _NUMBER.fullmatch(last) is not None)


def base_words(name: str) -> str | None:
    """The words of an unreadable name, without its ids and numbers (``"10_base_body"`` ->
    ``"base body"``, ``"dowel_1_9_6_8_7"`` -> ``"dowel"``), or None when it has no word that
    names a thing (``"0_part0"``, ``"mesh_0_3"``) or too many to be a name."""
    words = [t for t in tokens(name) if _word(t)]
    if not words or len(words) > ID_LIKE_TOKENS_MAX or all(
            w.lower() in GENERIC_WORDS | LABEL_WORDS for w in words):
        return None
    return " ".join(words)


def stem(label: str) -> str | None:
    """A label without its trailing number (``"wheel 3"`` -> ``"wheel"``), or None when it has
    none: parts named alike but for their number are labelled on their steps' pictures."""
    m = re.fullmatch(r"(.*\D)\s*\d+", label)
    return m.group(1).strip() if m else None


def natural_key(name: str) -> tuple:
    """Sort key reading digit runs as numbers (``2_knob`` before ``10_base``)."""
    return tuple((0, int(t), "") if t.isdigit() else (1, 0, t.casefold())
                 for t in re.split(r"(\d+)", name) if t)


def _key(label: str) -> str:
    """How two labels are compared: case-insensitive, runs of spaces as one."""
    return " ".join(label.split()).casefold()


def display_names(parts: Sequence[str], *, label_format: str = "part {n}",
                  order: Sequence[str] = ()) -> dict[str, PartName]:
    """The :class:`PartName` of every part, keyed by part name, in the order of ``parts``.

    ``label_format`` is the ``str.format`` template of a numbered label, with the field ``{n}``
    (the caller reads it from ``templates/``).  Repeated names count once.  Every label is
    unique (compared as :func:`_key` does), and the result does not depend on the order of
    ``parts`` beyond the order of the keys.  Numbered labels follow ``order`` (the parts
    coarse to fine: "Part 1: the first box", where a read-through met "Part 5: the first
    box"), parts it leaves out after them by name.

    Raises:
        ValueError: ``label_format`` gives the same label for two numbers (no ``{n}``), or has
            other fields.
    """
    try:
        same = _key(label_format.format(n=1)) == _key(label_format.format(n=2))
    except (KeyError, IndexError, ValueError) as exc:
        raise ValueError(f"label format {label_format!r}: {exc!r} (the only field is {{n}})") \
            from None
    if same:
        raise ValueError(f"label format {label_format!r} must number labels with {{n}}")
    names = list(dict.fromkeys(parts))
    own = {p: p.replace("_", " ") for p in names if readable(p)}
    holders: dict[str, int] = {}
    for label in own.values():
        holders[_key(label)] = holders.get(_key(label), 0) + 1
    kept = {p: label for p, label in own.items() if holders[_key(label)] == 1}
    taken = set(holders)  # also the labels two readable names share: no number shows them
    # Unreadable names that carry words ("10_base_body", "dowel_1_9_6_8_7"): those words, and a
    # count when several parts share them ("knob 1", "knob 2"), in natural order of the names.
    derived: dict[str, str] = {}
    groups: dict[str, list[str]] = {}
    for p in names:
        if p not in kept and (base := base_words(p)) is not None:
            groups.setdefault(_key(base), []).append(p)
    for key in sorted(groups):
        members = sorted(groups[key], key=natural_key)
        base = base_words(members[0]) or key
        labels = ([base] if len(members) == 1
                  else [f"{base} {k}" for k in range(1, len(members) + 1)])
        if _key(base) in taken or any(_key(x) in taken for x in labels):
            continue  # would read like another part's name: numbered below instead
        for p, label in zip(members, labels):
            derived[p] = label
            taken.add(_key(label))
    numbered: dict[str, str] = dict(derived)
    n = 0
    rank = {q: k for k, q in enumerate(dict.fromkeys(order))}
    for p in sorted((p for p in names if p not in kept and p not in derived),
                    key=lambda q: (rank.get(q, len(rank)), q)):
        n += 1
        while _key(label_format.format(n=n)) in taken:
            n += 1
        numbered[p] = label_format.format(n=n)
        taken.add(_key(numbered[p]))
    return {p: PartName(p, kept[p], True) if p in kept else PartName(p, numbered[p], False)
            for p in names}
