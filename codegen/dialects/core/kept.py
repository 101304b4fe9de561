"""The parse store: each parse tree (or syntax error) kept by parser, file name and text: a text is parsed once."""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import Callable, Hashable, Iterator
from contextlib import contextmanager

from lark import Tree

from codegen.dialects.core.values import RunError

# Characters of text whose trees are kept (the least recently used go first): a tree takes some 170 times its
# text's memory (8 MB for a 2,000-line program of 51,000 characters), so this keeps about 80 MB of trees.
BUDGET_CHARS = 500_000
# Results of walks over kept trees (about 11 a routine), the least recently used going first: each keeps its routine's
# tree alive (some 130 kB for a routine of a 2,000-line program), so this holds at most some 60 MB of them.
RESULTS_MAX = 5_000


class Kept:
    """Trees by (parser, file name, text), least recently used first, while keeping (`codegen check`, the language
    server); else nothing is kept (a verify worker lets each program go: its memory is the next one's). A tree is
    shared: whoever reads one from here must not change it (copy it first). Every tree is built with positions (a
    caller that asked for none gets one with them: the same tree, its starts besides), so one parse serves the syntax
    check, the loader and the field checks. A syntax error is kept as its message and raised again as a new RunError.
    Threads may share it (the language server checks a file's syntax and its whole program in two): the table changes
    under a lock, the parse outside."""

    def __init__(self, budget_chars: int = 0) -> None:
        self.budget_chars = budget_chars  # 0: keeping nothing
        self.entries: OrderedDict[tuple, Tree | str] = OrderedDict()
        self.chars = 0
        self.parses = 0  # texts parsed (not found kept) and their characters: what the language server reports
        self.parsed_chars = 0
        self.lock = threading.Lock()
        self.results: OrderedDict[tuple, tuple] = OrderedDict()  # (id of a node, key) -> (the node, its result)

    def tree(self, parser: Hashable, filename: str, text: str, parse: Callable[[], Tree]) -> Tree:
        """The tree of `text` as `parse()` gives it (called only when this text of this file was not kept)."""
        key = (parser, filename, text)
        with self.lock:
            found = self.entries.get(key)
            if found is not None:
                self.entries.move_to_end(key)
        if found is None:
            try:
                found = parse()
            except RunError as exc:
                found = str(exc)
            with self.lock:
                self.parses += 1
                self.parsed_chars += len(text)
                self._keep(key, found)
        if isinstance(found, str):
            raise RunError(found)
        return found

    def result(self, node: Tree, key: Hashable, compute: Callable[[], list]) -> list:
        """`compute()`'s result for a node of a kept tree, kept beside it: a node of a kept tree stands for its
        text, so a walk over an unchanged routine is not done again. `key` names the walk and whatever else its
        result depends on (the declarations it reads); the node itself is kept with the result, so its id is not
        reused while the entry lives. Nothing is kept while no trees are."""
        if not self.shares:
            return compute()
        slot = (id(node), key)
        with self.lock:
            found = self.results.get(slot)
            if found is not None and found[0] is node:
                self.results.move_to_end(slot)
                return list(found[1])
        value = compute()
        with self.lock:
            self.results[slot] = (node, list(value))
            while len(self.results) > RESULTS_MAX:
                self.results.popitem(last=False)
        return value

    def by_unit(self, walk: Callable, name: str, tree: Tree, *args, key: Hashable = ()) -> list:
        """`walk(name, tree, *args)` done on each top child of the file's tree (a routine, a data list, a module)
        alone, the results joined in their order: a child kept unchanged gives its kept result (see result)."""
        out = []
        for unit in tree.children:
            if isinstance(unit, Tree):
                out.extend(
                    self.result(unit, (walk, name, key), lambda unit=unit: walk(name, Tree(tree.data, [unit]), *args))
                )
        return out

    def _keep(self, key: tuple, found: Tree | str) -> None:
        size = len(key[2])
        if size > self.budget_chars or key in self.entries:  # too big, or parsed meanwhile by another thread
            return
        self.entries[key] = found
        self.chars += size
        while self.chars > self.budget_chars:
            old, _tree = self.entries.popitem(last=False)
            self.chars -= len(old[2])

    @property
    def shares(self) -> bool:
        """Whether the trees parse_with_grammar hands out now are shared (kept): a caller changing one copies it."""
        return self.budget_chars > 0

    @contextmanager
    def keeping(self, budget_chars: int = BUDGET_CHARS) -> Iterator[Kept]:
        """Keep trees within the block (what it kept let go at its end, unless an outer block keeps too)."""
        outer = self.budget_chars
        self.budget_chars = max(outer, budget_chars)
        try:
            yield self
        finally:
            self.budget_chars = outer
            if not outer:
                self.clear()

    def clear(self) -> None:
        with self.lock:
            self.entries.clear()
            self.results.clear()
            self.chars = 0


STORE = Kept()
