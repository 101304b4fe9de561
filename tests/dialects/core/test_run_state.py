"""A dialect's run state (Machine.state): typed per dialect, each run starting from the set-up's, none leaking."""

from __future__ import annotations

from dataclasses import dataclass, field

import pytest

from codegen.dialects import dialects
from codegen.dialects.core.compiler import Compiler
from codegen.dialects.core.runstate import RunState
from codegen.dialects.urscript.interpreter import load


@dataclass
class _Toy(RunState):
    count: int = 0
    seen: dict = field(default_factory=dict)
    order: list = field(default_factory=list)


def test_a_copy_has_its_own_containers():
    state = _Toy(3, {"a": 1}, [1])
    copied = state.copy()
    copied.count += 1
    copied.seen["b"] = 2
    copied.order.append(2)
    assert (state.count, state.seen, state.order) == (3, {"a": 1}, [1])
    assert (copied.count, copied.seen, copied.order) == (4, {"a": 1, "b": 2}, [1, 2])
    assert type(copied) is _Toy


@pytest.mark.parametrize("name", ["krl", "rapid", "urscript"])
def test_each_dialect_declares_its_state_in_its_package(name):
    module = dialects()[name].module("interpreter")
    classes = vars(module).values()
    (compiler,) = {c for c in classes if isinstance(c, type) and issubclass(c, Compiler) and c is not Compiler}
    state = compiler.run_state
    assert state is not RunState and issubclass(state, RunState)
    assert state.__module__ == f"codegen.dialects.{name}.state"


def test_a_runs_flags_and_settings_do_not_reach_the_next_run():
    program = load(
        "def prog():\n"
        '  textmsg("", get_flag(3))\n'
        "  set_flag(3, True)\n"
        "  set_payload(2.5)\n"
        "  movel(p[0.4, 0.1, 0.3, 0, 3.0, 0])\n"
        "end\n",
        "t.script",
    )
    first, second = program.run({}), program.run({})
    assert first.messages == second.messages == ["False"]
    assert first.moves[0].settings["load"] == second.moves[0].settings["load"]
