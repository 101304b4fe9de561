"""RAPID's instructions on the task's modules: Save."""

from __future__ import annotations

import copy

from codegen.dialects.core.values import RunError

# Save [\TaskRef | \TaskName] ModuleName [\FilePath] [\File]: writes a module of the task, its data as they are
# now, to its file (public RAPID programs write `Save "Module" \FilePath:="HOME:/Module.mod";` after changing a
# module's persistents; ABB, Technical reference manual - RAPID Instructions, Save: recalled, the manual's text not
# found here). A module the task does not have: ERR_MODULE, a stop here.
SAVE_ARGS = {"TASKREF", "TASKNAME", "FILEPATH", "FILE"}


def save(fr, args, kwargs, where: str) -> None:
    if len(args) != 1 or not isinstance(args[0], str) or set(kwargs) - SAVE_ARGS:
        raise RunError(f"{where}: Save takes a module's name, and \\TaskRef or \\TaskName, \\FilePath, \\File")
    data = fr.m.program.compiler.module_data.get(args[0].upper())
    if data is None:
        raise RunError(f"{where}: Save: the task has no module {args[0]} (ERR_MODULE)")
    fr.m.state.saved[args[0].upper()] = {name: copy.deepcopy(fr.m.globals.get(key)) for name, key in data.items()}
