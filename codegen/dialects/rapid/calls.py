"""RAPID routine calls: resolution by scope, optional parameters (\\switch, \\opt, Present, a | b), late binding."""

from __future__ import annotations

from lark import Token, Tree

from codegen.dialects.core.machine import Frame
from codegen.dialects.core.source import Inline, Src
from codegen.dialects.core.values import RunError
from codegen.dialects.rapid import errors
from codegen.dialects.rapid.catalogue import NOT_MODELLED

# Sources: ABB, "RAPID Reference Manual - Basic Characteristics RAPID", 3.2 Parameters and 7.6 Using function calls
# in expressions (read at yumpu.com/en/document/view/5679047, pages 88, 105, 106):
# - "An optional parameter is denoted by a backslash" (PROC routine2 (num required_par \num optional_par)); "the
#   value of an optional parameter that is omitted in a routine call may not be referenced"; optional arguments
#   "may be declared to exclude each other" (joined by | here): only one of them may be present;
# - an argument \Name?Par (ReadBin (File \Time?Maxtime)) is passed on only where the caller's optional parameter
#   Par is present itself, and "simply considered to be omitted" otherwise.
# As recalled (the text was not found): Present(Name) tells whether an optional parameter was given; `\switch Name`
# takes no value (\Name in the call);
# - %expression% Arguments: the procedure whose name the string expression gives (late binding); no such procedure
#   is the error ERR_REFUNKPRC, wrong arguments ERR_CALLPROC (both recoverable in an ERROR handler).
ABSENT = object()  # a conditional argument whose parameter is not present: as if not given


class OptionalSpec:
    """A routine's optional parameters: name -> (type or "SWITCH", mode), and the alternative groups."""

    __slots__ = ("groups", "params")

    def __init__(self) -> None:
        self.params: dict[str, tuple] = {}
        self.groups: list[set[str]] = []


class Calls:
    """Compiler mixin: parameters and calls of RAPID routines."""

    # --- parameters ------------------------------------------------------------------------------
    def parameters(self, params_node) -> tuple[list, OptionalSpec | None]:
        """The required parameters [(name, mode, type)] and the optional ones of a routine's parameter list."""
        required, spec = [], OptionalSpec()
        after_optional = False
        for item in params_node.children if params_node is not None else []:
            alternative = item.data == "alt_param"
            param = item.children[0] if alternative else item  # a param or an opt_param: the same children
            optional, mode, ptype, pname, conformant = param.children
            key = str(pname).upper()
            mode_key = str(mode).upper() if mode else "IN"
            if alternative and not after_optional:
                self.fail(item, "only optional parameters (\\name) are alternatives (|)")
            # the backslash of a group of alternatives stands before its first one: \switch on | switch off
            # (RAPID kernel manual, parameter declarations); one before each of them is read the same way
            after_optional = optional is not None or alternative
            if not after_optional:
                full = self.resolve_type(ptype, conformant)
                required.append((key, mode_key, full))
                continue
            if str(ptype).upper() == "SWITCH":
                full = "SWITCH"
            else:
                full = self.resolve_type(ptype, conformant)
                if mode_key != "IN":
                    self.fail(param, f"optional {mode_key} parameter {pname}: not modelled (optional ones are IN)")
            spec.params[key] = (full, mode_key)
            if alternative and spec.groups:
                spec.groups[-1].add(key)
            else:
                spec.groups.append({key})
        spec.groups = [g for g in spec.groups if len(g) > 1]
        return required, (spec if spec.params else None)

    # --- calls -----------------------------------------------------------------------------------
    def call_args(self, args_node):
        positional, named = [], {}
        for arg in args_node.children if args_node is not None else []:
            if isinstance(arg, Tree) and arg.data == "opt_arg":
                name, value = arg.children
                key = str(name).upper()
                if isinstance(value, Token):  # \Name?Parameter: passed on where present
                    param = str(value).upper()
                    if param not in self.current_optional:
                        self.fail(arg, f"\\{name}?{value}: {value} is not an optional parameter of this routine")
                    named[key] = f"(V[{param!r}] if {param!r} in V else _ABSENT)"
                else:
                    named[key] = self.src(value) if value is not None else "True"
            else:
                positional.append(arg)
        return positional, named

    def call_source(self, name, args, kwargs, setters, where):
        """As the base's; a conditional argument that is not present is left out of the call."""
        source = super().call_source(name, args, kwargs, setters, where)
        if not any("_ABSENT" in v for v in kwargs.values()):
            return source
        kw = "{" + ", ".join(f"{k!r}: {v}" for k, v in kwargs.items()) + "}"
        filtered = f"{{_k: _v for _k, _v in {kw}.items() if _v is not _ABSENT}}"
        return Src(source.replace(kw, filtered, 1))

    def resolved_call(self, node, name: str, args_node, as_function: bool = False) -> Src:
        """A call of a user routine or built-in by name (checked now: a name no routine has is an error)."""
        positional, named = self.call_args(args_node)
        key = self.data_key(name)
        upper = name.upper()
        if key in self.user_routines:
            self.check_call(node, key, name, positional, named, as_function)
            target = key
        elif upper in self.builtins:
            target = upper
        else:
            self.unknown_routine(node, name)
            target = upper
        args = [self.src(a) for a in positional]
        setters = self.ref_setters(target, positional)
        return self.call_source(target, args, named, setters, self.where(node))

    def check_call(self, node, key: str, name: str, positional, named, as_function: bool) -> None:
        routine = self.routine_decls.get(key)
        if routine is None:
            return
        required, spec, returns = routine
        if returns != as_function:
            what = "a FUNC: its value is used in an expression" if returns else "a PROC: it is called as an instruction"
            self.report(node, f"{name} is {what}", "type")
        if len(positional) != len(required):
            self.report(node, f"{name} takes {len(required)} arguments, got {len(positional)}", "arguments")
        known = spec.params if spec is not None else {}
        if named and spec is None:
            self.report(node, f"{name} has no optional parameters", "arguments")
            return
        for arg in named:
            if arg not in known:
                self.report(node, f"{name} has no optional parameter \\{arg.title()}", "arguments")
        if spec is not None:
            for group in spec.groups:
                given = sorted(group & set(named))
                if len(given) > 1:
                    shown = " and ".join("\\" + g.title() for g in given)
                    self.report(node, f"{name}: {shown} are alternatives (one of them)", "arguments")

    def unknown_routine(self, node, name: str) -> None:
        if name.upper() in NOT_MODELLED:
            self.fail(node, f"{name} is not modelled by the interpreter", "unsupported")
        self.report(node, f"unknown routine {name}: defined in none of the program's modules", "undefined-routine")

    def present(self, node, args_node) -> Src:
        positional, named = self.call_args(args_node)
        arg = positional[0] if len(positional) == 1 and not named else None
        if not (isinstance(arg, Tree) and arg.data == "var"):
            self.fail(node, "Present takes one optional parameter's name")
        key = str(arg.children[0]).upper()
        if key not in self.current_optional:
            self.fail(node, f"Present({arg.children[0]}): not an optional parameter of this routine")
        return Src(f"({key!r} in V)")

    # --- entries of routines with optional parameters ---------------------------------------------
    def entry(self, routine):
        spec = self.optional.get(routine)
        if routine.entry is not None or spec is None:
            return super().entry(routine)
        compiler, name, required = self, routine.name, routine.params
        refs = [(i, p) for i, (p, mode, _t) in enumerate(required) if mode in self.BY_REFERENCE]

        def call(fr, a, k, w, s=None):
            m = fr.m
            m.step(w)
            if len(a) != len(required):
                raise RunError(f"{w}: {name} takes {len(required)} arguments, got {len(a)}")
            f = Frame(m)
            V, T = f.vars, f.types
            for (pname, _mode, ptype), value in zip(required, a, strict=True):
                V[pname] = compiler.coerce(ptype, value, w)
                T[pname] = ptype
            for key, value in k.items():
                if value is ABSENT:
                    continue
                found = spec.params.get(key)
                if found is None:
                    raise RunError(f"{w}: {name} has no optional parameter \\{key.title()}")
                ptype = found[0]
                V[key] = True if ptype == "SWITCH" else compiler.coerce(ptype, value, w)
                T[key] = ptype
            for group in spec.groups:
                if len(group & V.keys()) > 1:
                    raise RunError(f"{w}: {name}: at most one of {', '.join(sorted(group))} (alternatives)")
            for dname, dtype, init in routine.decls:
                T[dname] = dtype
                V[dname] = init(f)
            signal = routine.body(f)
            if s:
                for i, pname in refs:
                    if s[i] is not None:
                        s[i](fr, V[pname])
            if signal is not None and signal.kind == "return":
                if routine.return_type:
                    return compiler.coerce(routine.return_type, signal.value, w)
                return signal.value
            if routine.return_type:
                raise RunError(f"{w}: function {name} ended without RETURN")
            return None

        routine.entry = call
        return call

    # --- late binding ----------------------------------------------------------------------------
    def s_late_call(self, node):
        name_node, args_node = node.children
        positional, named = self.call_args(args_node)
        scope, where = dict(self.scope), self.where(node)
        compiler = self

        def late(fr, a, k, w):
            name = a[0]
            if not isinstance(name, str):
                raise RunError(f"{w}: late binding: the procedure's name is a string")
            upper = name.upper()
            routine = compiler.routines.get(scope.get(upper, upper))
            if routine is None or routine.return_type is not None:
                raise errors.RapidError(errors.ERROR_NUMBERS["ERR_REFUNKPRC"], f"{w}: no procedure {name}")
            if any(mode in compiler.BY_REFERENCE for _p, mode, _t in routine.params):
                what = "a routine with VAR, PERS or INOUT parameters is not modelled"
                raise RunError(f"{w}: late binding of {name}: {what}")
            if len(a) - 1 != len(routine.params) and routine not in compiler.optional:
                raise errors.RapidError(
                    errors.ERROR_NUMBERS["ERR_CALLPROC"], f"{w}: {name} takes {len(routine.params)} arguments"
                )
            return compiler.entry(routine)(fr, a[1:], {key: v for key, v in k.items() if v is not ABSENT}, w)

        args = ", ".join([self.src(name_node), *(self.src(a) for a in positional)])
        kw = "{" + ", ".join(f"{key!r}: {v}" for key, v in named.items()) + "}"
        return Inline(self, self.guarded([f"{self.const(late)}(fr, [{args}], {kw}, {where!r})"], where))
