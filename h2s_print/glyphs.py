"""What the page font can print.

Pages are set in one embedded Unicode font (:mod:`h2s_print.fonts`: DejaVu Sans by default,
Latin, Greek, Cyrillic and more; or a config's ``font:``).  A character the font lacks is
spelled the way the font can print it when :data:`SPELL` knows a spelling (``⅓`` -> ``1/3``,
``−`` -> ``-``, thin spaces -> spaces); any other is :func:`unprintable`.  User text (config
titles, part names) and the wording in ``templates/`` are checked against the font before
any layout, so such a character is an error naming the field and the character, never a
silent ``?`` on the page.
"""

from __future__ import annotations

import string
import unicodedata

from . import fonts

#: Characters printed as another text when the font lacks them.
SPELL: dict[str, str] = {
    "⅓": "1/3", "⅔": "2/3", "⅛": "1/8", "⅜": "3/8", "⅝": "5/8", "⅞": "7/8", "⅕": "1/5",
    "→": "->", "←": "<-", "↑": "^", "↓": "v", "≈": "~", "≤": "<=", "≥": ">=", "−": "-",
    "×": "x", "\u2009": " ", "\u00a0": " ", "\u202f": " ", "\t": " ", "\n": " ",
}


def _draws(text: str) -> bool:
    return fonts.missing(text) is None


def spelled(ch: str) -> str:
    """``ch`` as the current font prints it: itself when the font has it, else its
    :data:`SPELL` spelling (when the font has that), else itself."""
    if ch in "\t\n":
        return " "
    if _draws(ch):
        return ch
    alt = SPELL.get(ch)
    return alt if alt is not None and _draws(alt) else ch


def printable(ch: str) -> bool:
    """Can the current page font print ``ch`` (after :func:`spelled`)?"""
    return _draws(spelled(ch))


def unprintable(text: str) -> str | None:
    """The first character of ``text`` the current page font cannot print, or None."""
    text = str(text)
    have = fonts.coverage(fonts.current())
    if all(ord(ch) in have or ch in "\t\n" for ch in set(text)):
        return None  # every character drawn as it is (the usual case, checked once each)
    for ch in text:
        if not printable(ch):
            return ch
    return None


def ascii_font() -> bool:
    """Does the current font draw every printable ASCII character (so ASCII text needs no
    per-character check)?"""
    return _ascii(fonts.current())


_ASCII_SEEN: dict[fonts.FontSpec, bool] = {}


def _ascii(spec: fonts.FontSpec) -> bool:
    if spec not in _ASCII_SEEN:
        _ASCII_SEEN[spec] = fonts.missing(string.printable.strip() + " ", spec) is None
    return _ASCII_SEEN[spec]


def describe(ch: str) -> str:
    """``'Ф' (U+0424 CYRILLIC CAPITAL LETTER EF)``: a character named for an error message."""
    name = unicodedata.name(ch, "")
    return f"{ch!r} (U+{ord(ch):04X}{' ' + name if name else ''})"
