"""What the page font can print.

Pages are set in Helvetica, whose PDF encoding covers Windows-1252 (Latin-1 and a few more).
A handful of characters are spelled the way the font can print them (``⅓`` -> ``1/3``,
``−`` -> ``-``, thin spaces -> spaces: :data:`SPELL`); any other character outside the font is
:func:`unprintable`.  User text (config titles) and the wording in ``templates/`` are checked
when read, so such a character is an error naming the field and the character, never a
silent ``?`` on the page.  (Scripts beyond Latin need an embedded Unicode font: the languages
issue.)
"""

from __future__ import annotations

import unicodedata

#: Characters printed as another text the font has.
SPELL: dict[str, str] = {
    "⅓": "1/3", "⅔": "2/3", "⅛": "1/8", "⅜": "3/8", "⅝": "5/8", "⅞": "7/8", "⅕": "1/5",
    "→": "->", "←": "<-", "↑": "^", "↓": "v", "≈": "~", "≤": "<=", "≥": ">=", "−": "-",
    "×": "x", "\u2009": " ", "\u00a0": " ", "\u202f": " ", "\t": " ", "\n": " ",
}
#: The font's encoding.
ENCODING = "cp1252"


def spelled(ch: str) -> str:
    """``ch`` as the font prints it (:data:`SPELL`), or ``ch`` itself."""
    return SPELL.get(ch, ch)


def printable(ch: str) -> bool:
    """Can the page font print ``ch`` (after :func:`spelled`)?"""
    try:
        spelled(ch).encode(ENCODING)
    except UnicodeEncodeError:
        return False
    return True


def unprintable(text: str) -> str | None:
    """The first character of ``text`` the page font cannot print, or None."""
    for ch in str(text):
        if not printable(ch):
            return ch
    return None


def describe(ch: str) -> str:
    """``'Ф' (U+0424 CYRILLIC CAPITAL LETTER EF)``: a character named for an error message."""
    name = unicodedata.name(ch, "")
    return f"{ch!r} (U+{ord(ch):04X}{' ' + name if name else ''})"
