"""A number literal in a parse tree, negated or not, as the static checks read it (every grammar names them alike)."""

from __future__ import annotations

from collections.abc import Callable

from lark import Tree


def literal_number(node, read: Callable[[str], float] = float) -> float | None:
    """The value of a `number` node or of a `neg` of one (read: the dialect's reading of a literal's text), None for
    any other node or a text too long or too large to read."""
    if isinstance(node, Tree) and node.data == "number":
        try:
            return float(read(str(node.children[0])))
        except (ValueError, OverflowError):
            return None
    if isinstance(node, Tree) and node.data == "neg":
        inner = literal_number(node.children[0], read)
        return None if inner is None else -inner
    return None
