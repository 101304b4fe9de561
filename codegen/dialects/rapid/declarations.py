"""RAPID data declarations and routines compiled: a datum's type and value, a routine's data and ERROR handler."""

from __future__ import annotations

from lark import Tree

from codegen.dialects.core.limits import array_size_problem
from codegen.dialects.core.values import RunError, constant
from codegen.dialects.rapid.types import OPAQUE, num


class Declarations:
    """The RAPID compiler's declarations and routines (a part of RAPIDCompiler)."""

    def decl(self, node, key: str | None = None):
        """(key, make): make(fr) -> (type, initial value) of a data declaration."""
        _local, _task, storage, type_name, name, dims, init = node.children
        where = self.where(node)
        size_exprs = [self.expr(d) for d in dims.children] if dims is not None else []
        base = self.resolve_type(type_name)
        value = self.expr(init) if init is not None else None
        if value is not None and base in OPAQUE:
            self.fail(node, f"{type_name} data takes no initial value")
        if str(storage).upper() == "CONST" and value is None:
            self.fail(node, f"CONST {name} needs a value")

        def make(fr):
            full_type = base
            sizes = [num(s(fr), where) for s in size_exprs]
            if problem := array_size_problem(sizes):
                raise RunError(f"{where}: {problem}")
            for size in reversed([int(size) for size in sizes]):
                full_type = (full_type, size)
            if value is None:
                return full_type, self.zero_of(full_type)
            return full_type, self.coerce(full_type, value(fr), where)

        return key or str(name).upper(), make

    def static_type(self, node):
        """A declaration's type when it is known without running (array sizes as literals)."""
        _local, _task, _storage, type_name, _name, dims, _init = node.children
        full = self.resolve_type(type_name)
        sizes = []
        for size in dims.children if dims is not None else []:
            if not (isinstance(size, Tree) and size.data == "number"):
                return None
            sizes.append(float(str(size.children[0])))
        if problem := array_size_problem(sizes):
            self.fail(dims, problem)
        for size in reversed(sizes):
            full = (full, int(size))
        return full

    def static_type_of(self, node):
        """The type of a variable node (a routine's or module's datum), when known."""
        if isinstance(node, Tree) and node.data == "var":
            upper = str(node.children[0]).upper()
            if self.local_types is not None and upper in self.local_types:
                return self.local_types[upper]
            return self.data_types.get(self.data_key(upper))
        return None

    def routine(self, node, key: str) -> None:
        """Compile a PROC, FUNC or TRAP whose parameters task.py has read (routine_decls)."""
        c = node.children
        clauses = {x.data: x for x in c if isinstance(x, Tree) and x.data.endswith("_clause")}
        if "undo_clause" in clauses:
            self.fail(clauses["undo_clause"], "an UNDO handler is not modelled by the interpreter", "unsupported")
        self.handler_node = clauses.get("error_clause")  # BACKWARD: only backward execution runs it (never here)
        if node.data == "func":
            _local, return_type, name, _params, body = c[:5]
        elif node.data == "trap":
            (_local, name, body), return_type = c[:3], None
        else:
            (_local, name, _params, body), return_type = c[:4], None
        required, spec = self.routine_decls[key][:2]
        decls, storage = [], {}

        def declare(child):
            dkey, make = self.decl(child)
            if dkey in storage:  # as task.py refuses a name declared twice in a module
                self.fail(child, f"{child.children[4]} declared twice in the routine (names ignore case)", "duplicate")
            static_type = self.static_type(child)
            storage[dkey] = str(child.children[2]).upper()
            decls.append((dkey, static_type, self._local_init(child, static_type, make)))

        message = "declarations are only allowed at the start of a routine"
        statements = self.routine_statements(body, "data_decl", declare, message)
        optional = spec.params if spec is not None else {}
        local_types = {p: t for p, _m, t in required} | {p: t for p, (t, _m) in optional.items()}
        local_types |= {k: t for k, t, _init in decls}
        return_type = self.resolve_type(return_type) if return_type is not None else None
        self.current_optional, self.local_storage = frozenset(optional), storage
        try:
            routine = self.define_routine(key, name, required, return_type, node, statements, decls, local_types)
        finally:
            self.current_optional, self.local_storage = frozenset(), {}
        if spec is not None:
            self.optional[routine] = spec

    def compile_routine_body(self, routine, statements, local_types=None) -> None:
        """The body, and its ERROR handler first (in the routine's scope: its data covers the handler)."""
        self.local_types, self.routine_name = local_types, routine.name
        try:
            clause = self.handler_node
            if clause is not None:
                numbers_node, body = clause.children
                self.in_handler = True
                try:
                    handler = self.body_block(body)
                    errnos = None
                    if numbers_node is not None:
                        exprs = [self.expr(e) for e in numbers_node.children]

                        def errnos(fr, exprs=exprs):
                            return {int(float(e(fr))) for e in exprs}

                finally:
                    self.in_handler = False
                self.handler = (handler, errnos)
            routine.body = self.block(statements)
        finally:
            self.local_types, self.routine_name = None, "module"
            self.handler, self.handler_node = None, None

    def _local_init(self, node, static_type, make):
        """A local's initialiser: its zero value shared by every call when it has no initial
        value and a known size (values are never changed in place)."""
        if node.children[-1] is None and static_type is not None:
            return constant(self.zero_of(static_type))
        return lambda fr: make(fr)[1]
