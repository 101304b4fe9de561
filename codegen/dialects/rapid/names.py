"""RAPID name resolution at compile time: routine data, the task's module data by scope, predefined data, signals."""

from __future__ import annotations

import re

from lark import Tree

from codegen.dialects.core.source import Src
from codegen.dialects.core.values import RunError, f32
from codegen.dialects.rapid import cycle, errors, signals, tracking
from codegen.dialects.rapid.functions import STRINGS
from codegen.dialects.rapid.messages import PREDEFINED_VALUES
from codegen.dialects.rapid.predefined import PREDEFINED
from codegen.dialects.rapid.types import SIGNAL_TYPES

# Scope rules (ABB, "Technical reference manual - RAPID overview", Basic characteristics, Scope rules; as
# recalled, the text was not readable during this work): a routine's parameters and data hide the module's data
# of the same name; data and routines declared LOCAL are seen only in their own module and hide a global one of
# the same name there; all other (global) data and routines of the task's modules share one namespace, so a
# global name is declared once in the task. TASK PERS data are global within their task (one task here). The
# predefined data of the system modules (tool0, v100, ...) are global data the program may not redeclare (a
# program's own declaration is used, and `codegen check` warns).
CONSTANTS = {**PREDEFINED_VALUES, **cycle.PREDEFINED_VALUES, **errors.ERROR_CONSTANTS, **STRINGS, **tracking.MECUNITS}
# A name a program reads as a value without declaring it, and that no signal instruction names, is taken as a signal
# of the I/O configuration when it is spelt as signals usually are (the EIO's names are not in the program: the
# manual's examples and public programs name them di1, DI10_1, diPartReady, DO_Lamp, gi_Recipe, gI_ProgNum...): the
# prefix di, do, gi, go, ai or ao in any case, then a digit, an underscore or (after a lower-case prefix) an
# upper-case letter. A guess, so `codegen check` warns of each one; any other undeclared name is an error.
_SIGNAL_NAME = re.compile(r"^(?:(di|do|gi|go|ai|ao)[0-9_A-Z]|([dDgGaA][iIoO])[0-9_])")


def implicit_signal_kind(name: str) -> str | None:
    match = _SIGNAL_NAME.match(name)
    return None if match is None else (match.group(1) or match.group(2)).upper()


def read_errno(fr):
    """The system variable ERRNO: the most recent error's number."""
    errno = fr.m.state.errno
    return f32(0) if errno is None else errno


class Names:
    """Compiler mixin: where a name used in a routine or module lives, decided when the program is compiled."""

    def data_key(self, name: str) -> str:
        """The key of a module datum or routine as the current module sees it (a LOCAL one of a module whose
        name another module also declares is kept under its own key)."""
        upper = name.upper()
        key = self.scope.get(upper, upper)
        owner = self.local_owner.get(key)
        return key if owner is None or owner == self.module_name else f"{upper}@{owner}:hidden"

    def named_constant(self, upper: str):
        """Predefined data, error numbers and the UIMsgBox and string constants by name; None if not one."""
        found = PREDEFINED.get(upper)
        return found if found is not None else CONSTANTS.get(upper)

    def var_source(self, token) -> Src:
        name = str(token)
        upper = name.upper()
        where = self.where(token)
        local_types = self.local_types
        if local_types is not None and upper in local_types:
            if upper in self.current_optional:
                absent = self.const(_absent(name, where))
                return Src(f"(V[{upper!r}] if {upper!r} in V else {absent}(fr))")
            return Src(f"V[{upper!r}]")
        key = self.data_key(upper)
        kind = self.data_types.get(key)
        if kind is not None:
            if kind in SIGNAL_TYPES:  # a signal variable read as a value: the signal's value
                ref = signals.signal_ref(self, token, Tree("var", [token]))
                return Src(f"{self.const(signals.reader(SIGNAL_TYPES[kind], ref))}(fr)")
            k = repr(key)
            fallback = self.const(_undefined(name, where))
            prefix = "" if local_types is not None else f"V[{k}] if {k} in V else "
            return Src(f"({prefix}G[{k}] if {k} in G else {fallback}(fr))")
        constant = self.named_constant(upper)
        if constant is not None:
            return Src(self.const(constant))
        if upper == "ERRNO":
            return Src(f"{self.const(read_errno)}(fr)")
        if upper in self.signal_kinds:
            spelled = self.signal_names[upper]
            reader = signals.reader(self.signal_kinds[upper], lambda fr: spelled)
            return Src(f"{self.const(reader)}(fr)")
        if upper in self.routine_keys():
            self.fail(token, f"{name} is a routine, not data")
        kind = implicit_signal_kind(name)
        if kind is not None:
            self.signal_names[upper], self.signal_kinds[upper] = name, kind
            what = signals.KIND_NAMES[kind]
            message = f"{name} is not declared: taken as the {what} {name} of the I/O configuration (simulated)"
            self.report(token, message, "implicit-signal", "warning")
            return Src(f"{self.const(signals.reader(kind, lambda fr: name))}(fr)")
        self.report(token, f"undefined variable {name}", "undefined-name")
        return Src(f"{self.const(_undefined(name, where))}(fr)")

    def var_store_lines(self, node, value: str) -> list[str]:
        token = node if not hasattr(node, "children") else node.children[0]
        name = str(token)
        upper = name.upper()
        where = repr(self.where(token))
        if self.local_types is not None and upper in self.local_types:
            if upper in self.for_counters:
                self.fail(token, f"{name} is a FOR loop's counter: the loop sets it")
            if self.local_storage.get(upper) == "CONST":
                self.fail(token, f"{name} is a CONST: it cannot be assigned")
            return [f"V[{upper!r}] = {self.coerce_source(self.local_types[upper], value, where)}"]
        key = self.data_key(upper)
        if key in self.data_types:
            if self.storage.get(key) == "CONST":
                self.fail(token, f"{name} is a CONST: it cannot be assigned")
            if self.data_types[key] in SIGNAL_TYPES:
                self.fail(token, f"{name} is a signal variable: AliasIO connects it, it is not assigned")
            coerce = self.const(self.coerce)
            return [f"G[{key!r}] = {coerce}(m.global_types.get({key!r}), {value}, {where})"]
        if upper in self.signal_kinds:
            self.fail(token, f"{name} is a signal: Set, Reset, SetDO... write it, not an assignment")
        if self.named_constant(upper) is not None:
            self.fail(token, f"{name} is predefined data: declare data of your own to change it")
        self.report(token, f"assignment to undeclared variable {name}", "undefined-name")
        return ["pass"]

    def routine_keys(self) -> set[str]:
        return (self.user_routines or set()) | self.trap_names


def _undefined(name: str, where: str):
    def read(fr):
        raise RunError(f"{where}: undefined variable {name}")

    return read


def _absent(name: str, where: str):
    def read(fr):
        raise errors.RapidError(
            errors.ERROR_NUMBERS["ERR_ARGNOTPRESENT"], f"{where}: optional parameter {name} is not present"
        )

    return read
