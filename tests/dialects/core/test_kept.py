"""The parse store (codegen/dialects/core/kept.py): a text of a file is parsed once; `codegen check` parses each file
once; the least recently used trees go beyond the budget."""

from __future__ import annotations

import sys
import threading
from collections import Counter
from pathlib import Path

import pytest
from lark import Tree

from codegen.checkfiles import check_files
from codegen.dialects.core import parsing
from codegen.dialects.core.kept import STORE, Kept
from codegen.dialects.core.values import RunError

ROOT = Path(__file__).resolve().parents[3]
GENERATED = ROOT / "generated"


@pytest.fixture
def counted(monkeypatch) -> Counter:
    """Each (file name, text) the parser is run on, counted; the store emptied first (what an earlier test parsed)."""
    seen: Counter = Counter()
    parse = parsing._parse

    def counting(interpreter_file, text, filename, postlex, positions):
        seen[(filename, text)] += 1
        return parse(interpreter_file, text, filename, postlex, positions)

    monkeypatch.setattr(parsing, "_parse", counting)
    STORE.clear()
    return seen


def test_a_tree_is_kept_and_a_syntax_error_too():
    kept = Kept(budget_chars=100)
    calls = []
    tree = Tree("start", [])

    def parse():
        calls.append(1)
        return tree

    assert kept.tree("p", "a.src", "text", parse) is tree
    assert kept.tree("p", "a.src", "text", parse) is tree
    assert kept.tree("p", "b.src", "text", parse) is tree  # another file of the same text: its own parse
    assert len(calls) == 2

    def refused():
        calls.append(1)
        raise RunError("a.src:1:1: syntax error")

    for _ in range(2):
        with pytest.raises(RunError, match="syntax error"):
            kept.tree("p", "a.src", "bad", refused)
    assert len(calls) == 3


def test_the_least_recently_used_go_beyond_the_budget():
    kept = Kept(budget_chars=10)
    for name, text in (("a", "12345"), ("b", "12345"), ("a", "12345"), ("c", "123")):  # a used again: b the oldest
        kept.tree("p", name, text, lambda: Tree("start", []))
    assert [key[1] for key in kept.entries] == ["a", "c"]
    assert kept.chars == 8


@pytest.mark.parametrize("target", ["kuka", "abb", "ur"])
def test_codegen_check_parses_each_text_once(counted: Counter, target: str):
    folder = GENERATED / "agv_machine_tending" / target
    result = check_files((str(folder),), None)
    assert result.groups and counted
    assert {key: n for key, n in counted.items() if n > 1} == {}
    assert not STORE.entries  # let go after the check
    with STORE.keeping():  # the language server's: a second check of the same files parses nothing again
        check_files((str(folder),), None)
        before = sum(counted.values())
        check_files((str(folder),), None)
    assert sum(counted.values()) == before


def test_nothing_is_kept_unless_asked(counted: Counter):
    """A run or a verify keeps no tree: its memory is the program's alone."""
    from codegen.dialects import get_dialect

    path = GENERATED / "agv_machine_tending" / "kuka" / "agv_machine_tending.src"
    text = path.read_text(encoding="utf-8")
    for _ in range(2):
        get_dialect("krl").parse(text, str(path))
    assert sum(counted.values()) == 2 and not STORE.entries


def test_threads_share_it():
    """Two threads (the language server's syntax check and whole check) asking for, parsing and pushing out trees at
    once: each gets its text's tree, and the characters kept add up."""
    kept = Kept(budget_chars=40)
    failures = []

    def ask(offset: int) -> None:
        try:
            for i in range(4000):
                text = str((i * 7 + offset) % 23) * 3
                tree = kept.tree("p", "f", text, lambda text=text: Tree(text, []))
                if tree.data != text:
                    failures.append((text, tree.data))
        except Exception as exc:  # a change of the table under another thread's feet
            failures.append(exc)

    threads = [threading.Thread(target=ask, args=(n,)) for n in range(4)]
    interval = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)  # threads switched as often as the interpreter can: a race shows
    try:
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
    finally:
        sys.setswitchinterval(interval)
    assert failures == []
    assert kept.chars == sum(len(key[2]) for key in kept.entries) <= 40


@pytest.mark.parametrize("target", ["kuka", "abb", "ur", "dtrans"])
def test_checking_and_loading_leave_the_kept_trees_as_parsed(target: str):
    """A kept tree is shared: `codegen check` (which loads the program: RAPID nests a{i, j} indexes) changes none."""
    from support.cells import is_configuration

    from codegen.cli_run import program_files, program_groups
    from tests.dialects.krl.test_units import shape

    folder = GENERATED / "agv_machine_tending" / target
    _target, dialect, all_files = program_files((str(folder),), None)
    sources = [f for f in all_files if not is_configuration(f.name)]  # a channel's XML: no tree kept
    with STORE.keeping():
        parsed = {f.name: shape(dialect.parse(f.text, f.name)) for f in sources}
        for group in program_groups(dialect, all_files):
            dialect.check_files(group)
        assert {f.name: shape(dialect.parse(f.text, f.name)) for f in sources} == parsed


GRID = """MODULE Grid
  VAR num grid{2, 3};
  PROC main()
    grid{1, 2} := 5;
    TPWrite "cell" \\Num:=grid{1, 2};
  ENDPROC
ENDMODULE
"""


def test_a_rapid_two_index_element_leaves_the_kept_tree_as_parsed():
    """RAPID's loader nests grid{1, 2} as (grid{1}){2}: on its own copy, not the kept tree."""
    from codegen.dialects import get_dialect
    from codegen.dialects.core.files import SourceFile
    from tests.dialects.krl.test_units import shape

    rapid = get_dialect("rapid")
    with STORE.keeping():
        parsed = shape(rapid.parse(GRID, "grid.mod"))
        assert rapid.check_files([SourceFile("grid.mod", GRID)]) == []
        assert shape(rapid.parse(GRID, "grid.mod")) == parsed
