"""Reading YAML: the safe loader only, and a key given twice is an error.

PyYAML's ``safe_load`` keeps the last of two equal keys in one mapping (``title: A`` then
``title: B`` reads as ``B``) without a word.  :func:`read_yaml` parses with the safe loader
too, and walks the composed document before building it: a mapping that holds the same key twice raises
:class:`DuplicateKey`, naming the key path and both lines, so the config loader (and the
template loader) can report it like any other typo.  YAML merge keys (``<<``) may override
keys, as the YAML spec allows; only keys written twice in one mapping are refused.
"""

from __future__ import annotations

from typing import Any

import yaml


class DuplicateKey(ValueError):
    """A key given twice in one mapping.

    Attributes:
        path: the key path, as the config messages write it (``views[1].name``).
        lines: the 1-based lines of the first and the second occurrence.
    """

    def __init__(self, path: str, lines: tuple[int, int]):
        super().__init__(f"{path}: key given twice (lines {lines[0]} and {lines[1]})")
        self.path = path
        self.lines = lines


def _join(path: str, key: Any) -> str:
    return f"{path}.{key}" if path else str(key)


def _check(node: yaml.Node, path: str) -> None:
    if isinstance(node, yaml.MappingNode):
        seen: dict[Any, int] = {}
        for key_node, value_node in node.value:
            if key_node.tag == "tag:yaml.org,2002:merge":
                continue
            key = key_node.value if isinstance(key_node, yaml.ScalarNode) else repr(key_node)
            line = key_node.start_mark.line + 1
            if key in seen:
                raise DuplicateKey(_join(path, key), (seen[key], line))
            seen[key] = line
            _check(value_node, _join(path, key))
    elif isinstance(node, yaml.SequenceNode):
        for i, item in enumerate(node.value):
            _check(item, f"{path}[{i}]")


#: LibYAML's safe loader when PyYAML was built with it: the same documents (the same
#: constructors and resolvers on the parsed nodes) about 10x faster (the templates: 68 ms ->
#: 7 ms).  Its error messages say less ("found character that cannot start any token"
#: without naming it), so a text it refuses is read again by the pure Python loader, whose
#: error is the one raised.
_FAST = getattr(yaml, "CSafeLoader", None)


def read_yaml(text: str) -> Any:
    """The document in ``text``, read with ``yaml.safe_load``.

    Raises:
        DuplicateKey: a mapping holds the same key twice.
        yaml.YAMLError: the text is not valid YAML.
    """
    if _FAST is not None:
        try:
            return _read(_FAST(text))
        except yaml.YAMLError:
            pass  # said by the pure Python loader below, in its words
    return _read(yaml.SafeLoader(text))


def _read(loader: Any) -> Any:
    """What ``safe_load`` does with ``loader``, with the duplicate-key check between its
    steps."""
    try:
        node = loader.get_single_node()
        if node is None:
            return None
        _check(node, "")
        return loader.construct_document(node)
    finally:
        loader.dispose()
