"""The compiler from lark trees to Python functions that dialects subclass with their tables."""

from __future__ import annotations

import builtins
import operator

from codegen.dialects.core.expressions import Expressions
from codegen.dialects.core.machine import Frame, Machine, Routine, step_limit_error
from codegen.dialects.core.routines import Routines
from codegen.dialects.core.runstate import RunState
from codegen.dialects.core.source import SourceBuilder
from codegen.dialects.core.statements import Statements
from codegen.dialects.core.stores import Stores
from codegen.dialects.core.values import (
    BREAK,
    CONTINUE,
    F32,
    Record,
    RunError,
    Signal,
    bad_index,
    f32,
    index_value,
    no_field,
    no_field_to_set,
    op_error,
)


class Compiler(SourceBuilder, Expressions, Stores, Statements, Routines):
    """Compile lark trees into Python source (closures where a rule has no source form); dialects
    override the class attributes (tables) and a few rules.

    Expressions and simple statements are compiled to Python source (`Src`, `Inline`) and a
    routine's block becomes one Python function; rules without a source form stay closures, which
    the generated code calls. Both share the same helpers (coercions, builtins, routine calls), so
    the semantics do not depend on which form a rule has.

    Each dialect module (`<dialect>/interpreter.py`) subclasses Compiler with its tables (builtins,
    comparison operators, index base, literal types) and the few rules its grammar has beyond the
    common ones. Numbers are held in the controller's precision (numpy float32 for 32-bit
    controllers); pose operations are computed in float64 and stored back in that precision, as
    the controller stores them in its variables."""

    name = "base"
    case_insensitive = False
    index_base = 0
    whole_indexes = False  # an index with a fraction is an error (True), or cut to a whole number (False)
    compare_ops = {
        "==": operator.eq,
        "!=": operator.ne,
        "<>": operator.ne,
        "<": operator.lt,
        "<=": operator.le,
        ">": operator.gt,
        ">=": operator.ge,
        "=": operator.eq,
    }
    int_division = False
    run_state: type[RunState] = RunState  # the dialect's state of a run (a dataclass in its package)

    def __init__(self, filename: str) -> None:
        self.filename = filename
        self.routines: dict[str, Routine] = {}
        self.builtins = self.make_builtins()
        self.ns: dict = {  # the globals of the generated Python source
            "__builtins__": builtins,
            "_Signal": Signal,
            "_BREAK": BREAK,
            "_CONTINUE": CONTINUE,
            "_operror": op_error,
            "_steplimit": step_limit_error,
            "_index": index_value,
            "_nofield": no_field,
            "_nofield_set": no_field_to_set,
            "_badindex": bad_index,
            "_Record": Record,
            "_F32": F32,
            "_Frame": Frame,
            "_RunError": RunError,
        }
        self.local_types: dict | None = None  # the routine being compiled: its variables' types
        self.routine_name = "module"
        self.user_routines: set[str] | None = None  # every routine of the program, when known up front
        self._consts: dict = {}  # id of a value (or a number's key) -> its name
        self._temps = 0
        self._source_depth = 0
        self._input_names: dict[str, tuple[str, int | None]] = {}

    def new_state(self) -> RunState:
        """The dialect's state at the start of a program's set-up (Machine.state)."""
        return self.run_state()

    # --- tables supplied by dialects ------------------------------------------------------

    def make_builtins(self) -> dict:
        return {}

    def number(self, text: str):
        if any(c in text for c in ".eE"):
            return f32(float(text))
        return int(text)

    def inject_inputs(self, machine: Machine) -> None:
        """Set injected inputs that are program variables (name or name[index])."""
        for name, value in machine.inputs.items():
            key, index = self._input_names.get(name) or self._input_name(name)
            if key not in machine.globals:
                continue
            if index is not None:
                i = index - self.index_base
                seq = machine.globals[key] = list(machine.globals[key])
                seq[i] = self.coerce(self.element_type(machine.global_types.get(key)), value, name)
            else:
                machine.globals[key] = self.coerce(machine.global_types.get(key), value, name)

    def kept(self, machine: Machine, name: str):
        """A name's value when the run ended (Program.run keep): a global variable or a written output."""
        return machine.globals.get(self.norm(name), machine.outputs.get(name))

    def accepts_input(self, name: str, globals_: dict) -> bool:
        """Whether an injected input names something the program has (a global variable, or an element
        of a global array within its bounds)."""
        try:
            key, index = self._input_names.get(name) or self._input_name(name)
        except ValueError:  # name[not a number]
            return False
        if key not in globals_:
            return False
        if index is None:
            return True
        value = globals_[key]
        return isinstance(value, list | tuple) and 0 <= index - self.index_base < len(value)

    def _input_name(self, name: str) -> tuple[str, int | None]:
        """An input's variable and element index, parsed once per name."""
        key, _, index = name.partition("[")
        parsed = (self.norm(key), int(index.rstrip("]")) if index else None)
        self._input_names[name] = parsed
        return parsed

    def element_type(self, type_name):
        return type_name

    # --- variables by name, for devices (Machine.read_variable / write_variable) ---------------
    def device_read(self, machine: Machine, name: str):
        """A global (name) or an element of one (name[index]) by its name in the program (None when it
        is not declared)."""
        key, index = self._input_names.get(name) or self._input_name(name)
        value = machine.globals.get(key)
        if index is None or not isinstance(value, list):
            return value if index is None else None
        i = index - self.index_base
        return value[i] if 0 <= i < len(value) else None

    def device_write(self, machine: Machine, name: str, value) -> bool:
        """Store into a declared global or an element of one, coerced to its type; False when there
        is no such global (arrays are copied, never changed in place)."""
        key, index = self._input_names.get(name) or self._input_name(name)
        if key not in machine.globals:
            return False
        if index is None:
            machine.globals[key] = self.coerce(machine.global_types.get(key), value, name)
            return True
        seq, i = machine.globals[key], index - self.index_base
        if not isinstance(seq, list) or not 0 <= i < len(seq):
            return False
        seq = machine.globals[key] = list(seq)
        seq[i] = self.coerce(self.element_type(machine.global_types.get(key)), value, name)
        return True
