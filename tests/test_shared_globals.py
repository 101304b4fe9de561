"""A large program's globals are shared by its runs: each run starts from the data, whatever the last one stored."""

from __future__ import annotations

import pytest

from codegen.dialects.core.shared import SHARE_FROM, SharedGlobals
from codegen.dialects.core.values import RunError
from codegen.dialects.krl.interpreter import load as load_krl


def test_undo_puts_back_every_value_a_run_replaced_and_drops_what_it_made():
    g = SharedGlobals({"a": 1, "b": [1, 2], "c": "x"})
    before = dict(g)
    g["a"] = 2
    g["a"] = 3  # the first replaced value is the one kept
    g["b"] = [9]
    g["new"] = 5
    del g["c"]
    g.setdefault("d", 4)
    g.update({"e": 6, "a": 7})
    assert g.pop("new") == 5
    g.undo()
    assert dict(g) == before and g.log == {}


def _program(lines: int):
    decls = "".join(f"  DECL INT A{i} = {i}\n" for i in range(lines))
    dat = f"DEFDAT t\n{decls}  DECL INT COUNT = 0\n  DECL INT BAD = 1\nENDDAT\n"
    src = "DEF t()\n  COUNT = COUNT + 1\n  A5 = A5 + 100\n  A1 = A1 / BAD\nEND\n"
    return load_krl(src, "t.src", dat)


@pytest.mark.parametrize("lines", [10, SHARE_FROM + 10])
def test_every_run_starts_from_the_data_small_and_large(lines):
    """COUNT and A5 are stored each run: the next run sees the data's values again, whether the program's
    globals are copied (small) or shared and undone (large); a run that fails undoes its stores too."""
    program = _program(lines)
    for _ in range(3):
        trace = program.run({}, keep=("COUNT", "A5"))
        assert trace.kept == {"COUNT": 1, "A5": 105}
    assert isinstance(program._snapshot[0], SharedGlobals) == (lines >= SHARE_FROM)
    with pytest.raises(RunError, match=r"zero|division"):
        program.run({"BAD": 0}, keep=("COUNT",))  # fails after its stores
    assert program.run({}, keep=("COUNT", "A5")).kept == {"COUNT": 1, "A5": 105}
