"""No import circles among the modules of the shared interpreter and the URScript dialect."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

DIALECTS = Path(__file__).resolve().parents[3] / "codegen" / "dialects"


def imports_of(path: Path, package: str) -> set[str]:
    """Every codegen module the file imports, at any level (module, TYPE_CHECKING block, function)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.module:
            base = node.module if node.level == 0 else f"{package.rsplit('.', node.level - 1)[0]}.{node.module}"
            found.add(base)
            found.update(f"{base}.{alias.name}" for alias in node.names)
        elif isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
    return found


def graph(folder: str) -> dict[str, set[str]]:
    package = f"codegen.dialects.{folder}"
    modules = {f"{package}.{p.stem}": p for p in (DIALECTS / folder).glob("*.py") if p.stem != "__init__"}
    return {name: imports_of(path, package) & set(modules) for name, path in modules.items()}


def cycle(edges: dict[str, set[str]]) -> list[str] | None:
    """One import circle, as the modules along it, or None."""
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(edges[node]):
            if state.get(nxt) == 1:
                return [*stack[stack.index(nxt) :], nxt]
            if nxt not in state and (found := visit(nxt)) is not None:
                return found
        stack.pop()
        state[node] = 2
        return None

    for start in sorted(edges):
        if start not in state and (found := visit(start)) is not None:
            return found
    return None


def test_the_checker_sees_a_circle():
    assert cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert cycle({"a": {"b"}, "b": set()}) is None


@pytest.mark.parametrize("folder", ["core", "urscript"])
def test_no_import_circle(folder):
    edges = graph(folder)
    assert len(edges) > 3
    assert cycle(edges) is None, " -> ".join(cycle(edges))
