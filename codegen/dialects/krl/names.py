"""KRL names by module: what one module sees of its own data and routines, the global ones and $config.dat's."""

from __future__ import annotations

from dataclasses import dataclass, field

from lark import Token, Tree

from codegen.dialects.core.source import LazyStore, Src
from codegen.dialects.core.values import RunError
from codegen.dialects.krl import dialogs, eki, sysvars
from codegen.dialects.krl.builtins import NOT_MODELLED, UNINIT, frame, valid
from codegen.dialects.krl.interrupts import pos_int
from codegen.dialects.krl.numbered import SYSTEM_ARRAYS, fresh_values
from codegen.dialects.krl.position import ACTIVE_BASE_AT_START
from codegen.dialects.krl.sysvars import REFUSED

# Scope rules (KSS 8 programming manual for system integrators, "Data lists" and "Subprograms"): a module is
# a .src with its .dat. Its routines and the data of its .dat are its own; a routine declared GLOBAL DEF /
# GLOBAL DEFFCT and a module's main routine (the first, named like the module) can be called from every
# module; data declared DECL GLOBAL in a data list made PUBLIC (DEFDAT name PUBLIC) is seen by every module;
# every name of $config.dat is global. A routine's own declarations come first (its locals and parameters).
# Storage: the program file's own names and the global ones keep their names in the machine's globals (what
# codegen run --input and the simulated devices name); another module's own data is stored as MODULE:NAME.


@dataclass
class Scope:
    """What the module being compiled sees: NAME -> the key of its storage (data) or of its routine."""

    module: str
    data: dict[str, str] = field(default_factory=dict)
    routines: dict[str, str] = field(default_factory=dict)
    signals: dict = field(default_factory=dict)  # NAME -> (bank, first, last, single)
    external: set[str] = field(default_factory=set)  # routines declared EXT here
    shared_signals: dict = field(default_factory=dict)  # GLOBAL SIGNAL of a data list: every module's


class ScopedStore(LazyStore):
    """A by-reference argument's setter compiled when first used, in the scope and file of its call."""

    __slots__ = ("filename", "scope")

    def __init__(self, compiler, node) -> None:
        super().__init__(compiler, node)
        self.scope, self.filename = compiler.scope, compiler.filename

    def __call__(self, fr, value) -> None:
        if self.fn is None:
            compiler = self.compiler
            saved = compiler.scope, compiler.filename
            compiler.scope, compiler.filename = self.scope, self.filename
            try:
                super().__call__(fr, value)
            finally:
                compiler.scope, compiler.filename = saved
            return
        self.fn(fr, value)


# the built-in functions with OUT parameters (positions) and those of them they write (a setter each)
OUT_PARAMETERS = {**dialogs.OUT_PARAMETERS, **eki.OUT_PARAMETERS}
WRITTEN = {**dialogs.WRITTEN, **eki.WRITTEN}
SPECIAL_READS = {"$NULLFRAME", "$WORLD", "$BASE", "$ROBROOT", "$POS_INT", "$ORI_TYPE", "$CIRC_TYPE", "$TOOL", "$LOAD"}


class ScopedNames:
    """Compiler mixin: names resolved by the scope of the module being compiled, when compiled (an undefined
    name or a routine defined nowhere is refused with its file:line before the program runs)."""

    scope: Scope

    strict_names = True  # an undefined name fails the load (KRL's compiler refuses it), else the statement at run
    undefined_note = ""  # what an undefined name's message adds: the files read (codegen/dialects/krl/modules.py)

    def storage(self, token) -> str:
        """The globals' key of a data name this module sees; for one it does not: a compile error, or with
        strict_names off "?NAME", which no global has (its read and its store fail when they run)."""
        key = str(token).upper()
        found = self.scope.data.get(key)
        if found is None:
            self.note(token, f"undefined variable {token}{self.undefined_note}")
            return "?" + key
        return found

    def note(self, token, message: str) -> None:
        """A compile error: raised; for codegen check kept while the statement compiles on (so that every
        undefined name of it is found); without strict_names left to the statement when it runs."""
        if self.findings is not None:
            self.findings.append(RunError(f"{self.where(token)}: {message}"))
        elif self.strict_names:
            self.fail(token, message)

    def var_source(self, token) -> Src:
        """A routine's variables directly; a module's or global data through the globals; system variables."""
        name = str(token)
        key = name.upper()
        if self.local_types is not None and key in self.local_types:
            return Src(f"(V[{key!r}] if V[{key!r}] is not _UNINIT else {self.const(self.var_reader(token))}(fr))")
        if (key.startswith("$") or key in SYSTEM_ARRAYS) and key not in self.scope.data:
            return Src(f"{self.const(self.var_reader(token))}(fr)")
        store, reader = repr(self.storage(token)), self.const(self.var_reader(token))
        return Src(f"(G[{store}] if G.get({store}, _UNINIT) is not _UNINIT else {reader}(fr))")

    def var_reader(self, token):
        name = str(token)  # the reader keeps the name: a kept token keeps the parse tree's memory
        key = name.upper()
        where = self.where(token)
        if key.startswith("$") and key not in self.scope.data:
            return self.system_reader(token)
        if key in SYSTEM_ARRAYS and key not in self.scope.data:  # the controller's numbered data ($config.dat)

            def read_numbered(fr):
                return fresh_values(fr.m, key)

            return read_numbered
        if self.local_types is not None and key in self.local_types:

            def read_local(fr):
                return valid(fr.vars[key], where, name)

            return read_local
        store = self.storage(token)
        if store.startswith("?"):

            def undefined(fr):
                raise RunError(f"{where}: undefined variable {name}")

            return undefined

        def read(fr):
            return valid(fr.m.globals.get(store, UNINIT), where, name)

        return read

    def system_reader(self, token):
        """A system variable's reader ($ names); a compile error for one not modelled."""
        name = str(token)
        key, where = name.upper(), self.where(token)
        if key in ("$NULLFRAME", "$WORLD"):
            return lambda fr: frame()
        if key == "$BASE":
            return lambda fr: fr.m.state.sysvars.setdefault("$BASE", frame(ACTIVE_BASE_AT_START))
        if key == "$ROBROOT":  # the robot's base in the world (read-only)
            return lambda fr: fr.m.state.sysvars.get("$ROBROOT") or frame()
        if key == "$POS_INT":
            return lambda fr: pos_int(fr.m, where)
        if key in ("$ORI_TYPE", "$CIRC_TYPE", "$LOAD"):

            def read_set(fr):
                if key not in fr.m.state.sysvars:
                    raise RunError(f"{where}: {key} has no value here (the program sets it: no default is assumed)")
                return fr.m.state.sysvars[key]

            return read_set
        if key == "$TOOL":
            return lambda fr: sysvars.tool_of(fr, where)
        if key in ("$IN", "$OUT"):
            self.fail(token, f"{name} is read and set one signal at a time: {name}[n]")
        if key in REFUSED:
            self.fail(token, f"{name} is not modelled by this interpreter ({REFUSED[key]})")
        if not sysvars.known(key):
            self.fail(token, f"the system variable {name} is not modelled by this interpreter")
        structs = self.structs

        def read(fr):
            return valid(sysvars.read(fr, key, where, structs), where, name)

        return read

    def var_store_lines(self, node, value: str) -> list[str]:
        token = node if isinstance(node, Token) else node.children[0]
        key = str(token).upper()
        if self.local_types is not None and key in self.local_types:
            return super().var_store_lines(node, value)
        where = self.where(token)
        if key.startswith("$") and key not in self.scope.data:
            if key in REFUSED:
                self.fail(token, f"{token} is not modelled by this interpreter ({REFUSED[key]})")
            if not sysvars.known(key):
                self.fail(token, f"the system variable {token} is not modelled by this interpreter")
            if key in sysvars.READ_ONLY:
                self.fail(token, f"{token} is read-only")
            return [f"{self.const(sysvars.write)}(fr, {key!r}, {value}, {where!r})"]
        if key in SYSTEM_ARRAYS and key not in self.scope.data:
            return [f"{self.const(self.new_variable)}(fr, {key!r}, {value}, {where!r})"]
        store = self.storage(token)
        if store.startswith("?"):
            return [f"{self.const(self.new_variable)}(fr, {key!r}, {value}, {where!r})"]
        coerce = self.const(self.coerce)
        return [f"G[{store!r}] = {coerce}(m.global_types.get({store!r}), {value}, {where!r})"]

    # --- routines ----------------------------------------------------------------------------------
    def routine_key(self, token) -> str | None:
        """The key of a routine this module sees, None for a builtin; a compile error for one defined nowhere."""
        key = str(token).upper()
        found = self.scope.routines.get(key)
        if found is not None:
            return found
        if key in self.builtins:
            return None
        if key in NOT_MODELLED:
            self.fail(token, f"{token} ({NOT_MODELLED[key]}) is not modelled by this interpreter")
        if key in self.scope.external:
            self.note(token, f"unknown routine {token}: declared EXT, defined in none of the program's files")
        else:
            self.note(token, f"unknown routine {token}: defined in none of the program's files, nor one modelled here")
        return key  # not strict: the call fails when it runs (unknown routine)

    def e_call(self, node):
        name, args_node = node.children
        arg_nodes = args_node.children if args_node is not None else []
        routine = self.routine_key(name)
        args = [self.src(a) if a is not None else "None" for a in arg_nodes]
        if routine is None:
            key = str(name).upper()
            if key in OUT_PARAMETERS:
                return self.builtin_with_out(node, key, name, arg_nodes, args)
            return self.call_source(str(name), args, {}, [None] * len(args), self.where(node))
        params = self.signatures.get(routine)
        if params is not None and len(params) != len(arg_nodes):
            self.fail(node, f"{name} takes {len(params)} arguments, got {len(arg_nodes)}")
        if any(a is None for a in arg_nodes):
            self.fail(node, f"{name}: an argument left out (only KUKA's spline functions have optional ones)")
        setters = self.ref_setters(routine, arg_nodes)
        return self.call_source(routine, args, {}, setters, self.where(node))

    def builtin_with_out(self, node, key: str, name, arg_nodes, args: list[str]):
        """A call of a built-in function with OUT parameters (OUT_PARAMETERS): the arguments there are
        variables (a compile error names the line otherwise); those it writes (WRITTEN) get a setter."""
        setters = [None] * len(arg_nodes)
        for i in OUT_PARAMETERS[key]:
            arg = arg_nodes[i] if i < len(arg_nodes) else None
            if arg is None:
                continue  # too few arguments: the function says so when it runs
            if not (isinstance(arg, Tree) and arg.data in ("var", "index", "field", "whole")):
                self.fail(arg if isinstance(arg, Tree) else node, f"{name}: argument {i + 1} is OUT: give a variable")
            if i in WRITTEN.get(key, ()):
                setters[i], args[i] = ScopedStore(self, arg), "None"
        where = self.where(node)
        return Src(f"{self.const(self.builtins[key])}(fr, [{', '.join(args)}], {{}}, {where!r}, {self.const(setters)})")

    def ref_setters(self, callee: str, arg_nodes) -> list:
        if callee not in self.user_routines:
            return [None] * len(arg_nodes)
        return [
            ScopedStore(self, node)
            if isinstance(node, Tree) and node.data in ("var", "index", "field", "whole")
            else None
            for node in arg_nodes
        ]
