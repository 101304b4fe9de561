"""Compiler mixin for routines and calls: resolving names, compiled entries, by-reference arguments."""

from __future__ import annotations

from lark import Tree

from codegen.dialects.core.machine import Frame, Routine
from codegen.dialects.core.source import LazyStore, Src
from codegen.dialects.core.values import RunError


class Routines:
    """Calls of user routines and builtins; a routine's call compiled into one function."""

    def call_source(self, name: str, args: list[str], kwargs: dict[str, str], setters, where: str) -> Src:
        """A call of a routine or builtin; the name is resolved at the first call (routines may be
        defined after their callers), then the generated code calls the target directly."""
        key = self.norm(name)
        slot = f"_c{len(self.ns)}"
        if self.user_routines is not None and key not in self.user_routines:
            setters = None  # a builtin: arguments are never written back
        with_setters = setters is not None and any(setters)

        def resolve(fr, a, k, w, s=None):
            target = self.resolve_call(key, name, w, with_setters)
            self.ns[slot] = target
            return target(fr, a, k, w, s) if with_setters else target(fr, a, k, w)

        self.ns[slot] = resolve
        kw = "{" + ", ".join(f"{k!r}: {v}" for k, v in kwargs.items()) + "}"
        tail = f", {self.const(setters)}" if with_setters else ""
        return Src(f"{slot}(fr, [{', '.join(args)}], {kw}, {where!r}{tail})")

    def resolve_call(self, key: str, name: str, where: str, with_setters: bool):
        routine = self.routines.get(key)
        if routine is not None:
            return self.entry(routine)
        found = self.builtins.get(key if self.case_insensitive else name)
        if found is None:
            raise RunError(f"{where}: unknown routine {name}")

        def builtin(fr, a, k, w):
            try:
                return found(fr, a, k, w)
            except IndexError:  # a builtin reads its arguments by position
                raise RunError(f"{w}: {name}: too few arguments ({len(a)} given)") from None

        if with_setters:
            return lambda fr, a, k, w, s: builtin(fr, a, k, w)
        return builtin

    def call_routine(self, fr: Frame, name: str, args: list, kwargs: dict, where: str, arg_setters=None):
        key = self.norm(name)
        routine = self.routines.get(key)
        if routine is not None:
            return self.invoke(fr, routine, args, kwargs, where, arg_setters)
        builtin = self.builtins.get(key if self.case_insensitive else name)
        if builtin is None:
            raise RunError(f"{where}: unknown routine {name}")
        return builtin(fr, args, kwargs, where)

    def invoke(self, fr, routine: Routine, args, kwargs, where, arg_setters=None):
        return self.entry(routine)(fr, args, kwargs, where, arg_setters)

    BY_REFERENCE = ("OUT", "INOUT", "VAR", "PERS", "OUT_REF")
    KWARGS_ERROR: str | None = None  # message when a user routine is called with named arguments
    BIND_ARGUMENTS = False  # the language binds named arguments to parameters, and has default values

    @staticmethod
    def binder(routine: Routine):
        """(machine, args, kwargs, where) -> the arguments in parameter order: the positional ones, then
        each parameter's named argument, else its default value (Routine.defaults, evaluated at the call
        with the globals only), else an error naming the parameter."""
        names = [p[0] for p in routine.params]
        count, name, defaults = len(names), routine.name, routine.defaults

        def bind(m, a, k, w):
            if len(a) > count:
                raise RunError(f"{w}: {name} takes {count} arguments, got {len(a)}")
            for key in k:
                if key not in names:
                    raise RunError(f"{w}: {name} has no parameter {key}")
                if names.index(key) < len(a):
                    raise RunError(f"{w}: {name}: argument {key} given twice")
            out = list(a)
            for pname in names[len(a) :]:
                if pname in k:
                    out.append(k[pname])
                elif pname in defaults:
                    out.append(defaults[pname](Frame(m, m.globals, m.global_types)))
                else:
                    raise RunError(f"{w}: {name}: no value for its parameter {pname} (and it has no default)")
            return out

        return bind

    def entry(self, routine: Routine):
        """The routine's call as one compiled function (fr, args, kwargs, where, setters): count
        the step, check and coerce the arguments, make the locals, run the body, write
        by-reference arguments back, coerce the returned value."""
        if routine.entry is not None:
            return routine.entry
        name, count = routine.name, len(routine.params)
        lines = ["m = fr.m", "m.steps += 1", "if m.steps > m.step_limit: raise _steplimit(w, m)"]
        if self.BIND_ARGUMENTS:  # named arguments and default values: bound where the call is not plain
            lines += [f"if k or len(a) != {count}:", f"    a = {self.const(self.binder(routine))}(m, a, k, w)"]
        else:
            lines += [
                f"if len(a) != {count}:",
                f"    raise _RunError(f'{{w}}: {name} takes {count} arguments, got {{len(a)}}')",
            ]
        if self.KWARGS_ERROR:
            lines += ["if k:", f"    raise _RunError(f'{{w}}: {name} {self.KWARGS_ERROR}')"]
        lines += ["f = _Frame(m)", "V = f.vars", "T = f.types"]
        for i, (pname, _mode, ptype) in enumerate(routine.params):
            lines.append(f"_p = a[{i}]")
            lines.append(f"V[{pname!r}] = {self.coerce_source(ptype, '_p', 'w')}")
            if ptype:
                lines.append(f"T[{pname!r}] = {self.const(ptype)}")
        for dname, dtype, init in routine.decls:
            lines.append(f"T[{dname!r}] = {self.const(dtype)}")
            if hasattr(init, "value"):  # constant(): the same value for every call
                lines.append(f"V[{dname!r}] = {self.const(init.value)}")
            else:
                lines.append(f"V[{dname!r}] = {self.const(init)}(f)")
        lines.append(f"_s = {self.const(routine.body)}(f)")
        refs = [(i, p) for i, (p, mode, _t) in enumerate(routine.params) if mode in self.BY_REFERENCE]
        if refs:
            lines.append("if s:")
            for i, pname in refs:
                lines.append(f"    if s[{i}] is not None: s[{i}](fr, V[{pname!r}])")
        lines.append("if _s is not None and _s.kind == 'return':")
        if routine.return_type:
            lines += ["    _p = _s.value", f"    return {self.coerce_source(routine.return_type, '_p', 'w')}"]
            lines.append(f"raise _RunError(f'{{w}}: function {name} ended without RETURN')")
        else:
            lines += ["    return _s.value", "return None"]
        routine.entry = self.function(lines, "fr, a, k, w, s=None", f"{self.name}_{name}_call", prologue=False)
        return routine.entry

    def compile_routine_body(self, routine: Routine, statements, local_types: dict | None = None) -> None:
        """local_types: the routine's parameters and declared locals with their types, when the
        language declares them all before the first statement: then the generated
        code reads and stores them directly in the frame."""
        self.local_types, self.routine_name = local_types, routine.name
        try:
            routine.body = self.block(statements)
        finally:
            self.local_types, self.routine_name = None, "module"

    @staticmethod
    def routine_parts(children, returns: bool) -> tuple:
        """(return type or None, name, each parameter's children, body) of a routine definition's
        children: [return type,] name, parameters node or None, body."""
        return_type, (name, params_node, body) = (children[0], children[1:]) if returns else (None, children)
        return return_type, name, [p.children for p in (params_node.children if params_node is not None else [])], body

    def routine_statements(self, body_node, decl_rule: str, declare, message: str) -> list:
        """The statements of a routine's body; declare(node) is called, in order, for each
        declaration before the first statement, and a declaration after it fails with message."""
        statements = []
        for child in body_node.children:
            if not isinstance(child, Tree):
                continue
            if child.data == decl_rule:
                if statements:
                    self.fail(child, message)
                declare(child)
            else:
                statements.append(child)
        return statements

    def define_routine(
        self,
        key: str,
        name,
        params,
        return_type,
        node,
        statements,
        decls=None,
        local_types=None,
        unique=True,
        defaults=None,
    ) -> Routine:
        """Register a routine under key (a second definition fails when unique) and compile its
        body; params are (name, mode, type) and checked by check_params first; defaults: a parameter's
        default value (closure) by name, where the language has them (BIND_ARGUMENTS)."""
        if unique and key in self.routines:
            self.fail(name, f"routine {name} defined twice")
        self.check_params(node, name, params)
        routine = Routine(str(name), params, None, return_type, self.line(node), decls, defaults)
        self.routines[key] = routine
        self.compile_routine_body(routine, statements, local_types)
        return routine

    def check_params(self, node, name, params) -> None:
        """A dialect's checks of a routine's parameters once they are known (e.g. each needs a declaration)."""

    def ref_setters(self, callee: str, arg_nodes) -> list:
        """Setters for arguments that are variables, used if the callee takes them by reference."""
        if self.user_routines is not None and self.norm(callee) not in self.user_routines:
            return [None] * len(arg_nodes)  # a builtin: nothing is written back
        return [
            LazyStore(self, node)
            if isinstance(node, Tree) and node.data in ("var", "index", "field", "whole")
            else None
            for node in arg_nodes
        ]
