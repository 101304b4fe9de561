"""Compiler mixin for statements: blocks, assignment, control flow and waiting."""

from __future__ import annotations

import re
from collections.abc import Callable

import numpy as np
from lark import Tree

from codegen.dialects.core.machine import halt, pause
from codegen.dialects.core.source import Inline, indent
from codegen.dialects.core.values import RunError

# a SWITCH / TEST selector looked up in its table of CASE values (bool is no number here: it takes the scan)
NUMBER_TYPES = frozenset({int, float, np.float32, np.float64, np.int32, np.int64})
# an elif chain's subject looked up in its table: True == 1 in a comparison, and in the table's hashing
CHAIN_TYPES = NUMBER_TYPES | {bool}

LEAVE_ON_BREAK = frozenset({"break"})
SKIP_ON_CONTINUE = frozenset({"continue"})


class Statements:
    """Statements compiled into lines of Python source or closures."""

    def stmt(self, node):
        method = getattr(self, f"s_{node.data}", None)
        if method is None:
            self.fail(node, f"unsupported statement {node.data}")
        return method(node)

    def block(self, nodes) -> callable:
        """Statements in order, compiled into one function; each counts one step (charged when the
        block starts). The function returns a Signal (return, break, ...) or None; `.inline`
        holds its lines for inlining into an enclosing block."""
        trees = [n for n in nodes if isinstance(n, Tree)]
        compiled = [self.stmt(n) for n in trees]
        where = self.where(trees[0]) if trees else self.filename
        lines = [f"m.steps += {len(compiled)}", f"if m.steps > m.step_limit: raise _steplimit({where!r}, m)"]
        for statement in compiled:
            lines.extend(self.body_lines(statement))
        fn = self.function([*lines, "return None"])
        fn.inline = lines
        return fn

    def s_assign(self, node):
        target, value_node = node.children
        lines = [f"_v = {self.src(value_node)}", *self.store_lines(target, "_v")]
        return Inline(self, self.guarded(lines, self.where(node)))

    # Types whose coerce() returns a value of this exact Python type unchanged (dialect table).
    halt_resumes = False  # the halt statement pauses and the controller resumes after it

    def s_halt_stmt(self, node):
        """halt / HALT / Halt: the program stops (or pauses, halt_resumes); its last message is the
        operator's message."""
        return (lambda fr: pause(fr)) if self.halt_resumes else (lambda fr: halt(fr))

    def s_expr_stmt(self, node):
        return Inline(self, self.guarded([self.src(node.children[0])], self.where(node)))

    def s_return_stmt(self, node):
        if node.children and node.children[0] is not None:
            value = self.src(node.children[0])
            return Inline(self, self.guarded([f"return _Signal('return', {value})"], self.where(node)))
        return Inline(self, ["return _Signal('return', None)"])

    def s_break_stmt(self, node):
        return Inline(self, ["return _BREAK"])

    def s_continue_stmt(self, node):
        return Inline(self, ["return _CONTINUE"])

    def s_pass_stmt(self, node):
        return Inline(self, [])

    def body_block(self, body_node):
        """A body node's statements as one block (a dialect may check them first)."""
        return self.block(body_node.children)

    def s_if_stmt(self, node):
        return self.if_elif(node, self.body_block)

    def s_call_stmt(self, node):
        """A routine called as a statement: the call expression with the same children."""
        call = self.e_call(Tree("call", node.children, node.meta))
        return Inline(self, self.guarded([call], self.where(node)))

    def s_while_stmt(self, node):
        cond, body = node.children
        test = self.expr(cond)
        return self.loop(self.where(node), self.body_block(body), test=test)

    def loop(
        self,
        where: str,
        body: Callable,
        test: Callable | None = None,
        until: Callable | None = None,
        leave: frozenset[str] = LEAVE_ON_BREAK,
        skip: frozenset[str] = SKIP_ON_CONTINUE,
    ) -> Callable:
        """WHILE test / LOOP / REPEAT ... UNTIL: each pass counts one step. A signal whose kind is in
        leave ends the loop, one in skip goes on with the next pass; any other is passed on."""

        def run(fr):
            while test is None or test(fr):
                fr.m.step(where)
                signal = body(fr)
                if signal is not None:
                    if signal.kind in leave:
                        return None
                    if signal.kind not in skip:
                        return signal
                if until is not None and until(fr):
                    return None
            return None

        return run

    def for_loop(
        self,
        node: Tree,
        start: Tree,
        stop: Tree,
        step: Tree | None,
        body: Tree,
        *,
        number: Callable,
        store: Callable,
        read: Callable | None = None,
        leave: frozenset[str] = frozenset(),
    ) -> Callable:
        """FOR counter = start TO stop [STEP step]: bounds inclusive, each pass one step, STEP 0 an
        error; number converts the bounds and the step (int, float) and store(fr, value) sets the
        counter. With read the counter is the program's variable: set once, then tested and
        incremented as it stands (the body may change it). Without, the loop keeps its own count
        and stores it at the start of each pass. A signal whose kind is in leave ends the loop."""
        start, stop = self.expr(start), self.expr(stop)
        step = self.expr(step) if step is not None else (lambda fr: 1)
        body = self.body_block(body)
        where = self.where(node)

        def run(fr):
            i, end, inc = number(start(fr)), number(stop(fr)), number(step(fr))
            if inc == 0:
                raise RunError(f"{where}: FOR with STEP 0")
            if read is not None:
                store(fr, i)
            while True:
                if read is not None:
                    i = read(fr)
                if not ((i <= end) if inc > 0 else (i >= end)):
                    return None
                fr.m.step(where)
                if read is None:
                    store(fr, i)
                signal = body(fr)
                if signal is not None:
                    return None if signal.kind in leave else signal
                if read is None:
                    i += inc
                else:
                    store(fr, read(fr) + inc)

        return run

    def if_elif(self, node, body_of):
        """IF cond body [ELSEIF cond body]* [ELSE body]: children cond, body, then clauses."""
        cond, body, *rest = node.children
        branches = [(self.expr(cond), body_of(body))]
        else_body = None
        for clause in rest:
            if clause is None:
                continue
            if len(clause.children) == 2:  # elseif / elif clause: condition and body
                branches.append((self.expr(clause.children[0]), body_of(clause.children[1])))
            else:
                else_body = body_of(clause.children[0])
        return self.if_chain(branches, else_body, self.where(node))

    def switch(self, node, body_of):
        """SWITCH / TEST: the first CASE whose value equals the selector, else DEFAULT. Where every CASE value
        is a number literal (a dispatch over a cell's stations), a table from value to body finds it at once
        (the first CASE with a value wins, as the scan; a selector that is no number takes the scan)."""
        selector, *clauses = node.children
        select = self.expr(selector)
        cases, default, table = [], None, {}
        for clause in clauses:
            if clause is None:
                continue
            if clause.data == "case_clause":
                *values, body = clause.children
                compiled = body_of(body)
                cases.append(([self.expr(v) for v in values], compiled))
                for v in values:
                    if table is not None and isinstance(v, Tree) and v.data == "number":
                        table.setdefault(self.number(str(v.children[0])), compiled)
                    else:
                        table = None
            else:
                default = body_of(clause.children[0])

        def scan(fr, value):
            for values, body in cases:
                if any(value == v(fr) for v in values):
                    return body(fr)
            return default(fr) if default is not None else None

        if table is None:
            return lambda fr: scan(fr, select(fr))

        def run(fr):
            value = select(fr)
            if type(value) not in NUMBER_TYPES:
                return scan(fr, value)
            body = table.get(value)
            if body is not None:
                return body(fr)
            return default(fr) if default is not None else None

        return run

    def wait_until(self, cond_node, where_node, keyword: str, arrive: bool = False):
        """WAIT FOR / WaitUntil without a time limit: here only a device (the vision PC answering a
        request) can change a condition; the clock runs to its answer, and a condition that no device
        will make true is an error (the controller would wait forever). arrive: the wait first waits
        for the arm (a wait that stops an advance run)."""
        cond = self.expr(cond_node)
        where = self.where(where_node)

        def run(fr):
            m = fr.m
            if arrive:
                m.arrive(where)
            if not cond(fr):
                m.wait_for(lambda: cond(fr), where, None, keyword)

        return run

    # Python compiles an elif chain as nested else-ifs: one chain of thousands (a dispatch over a cell's
    # stations) would exceed its compiler's nesting limit, so a longer chain continues in a function of
    # its own from its else branch.
    CHAIN_MAX = 400

    def if_chain(self, branches, else_body, where: str | None = None) -> Inline:
        """branches: [(condition, body)] as expr() and block() return them; else_body or None."""
        table = self.dispatch_table(branches)
        if table is not None:
            return self.table_chain(table, branches, else_body, where)
        if len(branches) > self.CHAIN_MAX:
            rest = self.if_chain(branches[self.CHAIN_MAX :], else_body, where)

            def rest_of_chain(fr, rest=rest):  # called, not inlined: the chain's next segment
                return rest(fr)

            branches, else_body = branches[: self.CHAIN_MAX], rest_of_chain
        lines = []
        for i, (cond, body) in enumerate(branches):
            lines.append(f"{'if' if i == 0 else 'elif'} {self.source_of(cond)}:")
            lines.extend(indent(self.body_lines(body) or ["pass"]))
        if else_body is not None:
            lines.append("else:")
            lines.extend(indent(self.body_lines(else_body) or ["pass"]))
        return Inline(self, self.guarded(lines, where or self.filename))

    # A chain of `x == number` over one variable (a dispatch over a cell's stations) is looked up in a table
    # of its numbers (the first branch with a number wins, as the chain) instead of comparing in turn.
    DISPATCH_MIN = 8
    _EQUALS = re.compile(r"\(True if (.+) == (_k\d+) else False\)")
    _FALLBACK = re.compile(r"_k\d+\(fr\)")

    def dispatch_table(self, branches) -> dict | None:
        if len(branches) < self.DISPATCH_MIN:
            return None
        subject, shape, table = None, None, {}
        for cond, body in branches:
            match = self._EQUALS.fullmatch(self.source_of(cond))
            # one variable in every branch: its reads differ only in the closure each registers for a name
            # not defined (the first branch's, where the chain would have stopped first)
            read = None if match is None else self._FALLBACK.sub("_", match.group(1))
            if match is None or (shape is not None and read != shape) or not self._plain_read(read):
                return None
            if subject is None:
                subject, shape = match.group(1), read
            value = self.ns.get(match.group(2))
            if type(value) not in NUMBER_TYPES:
                return None
            table.setdefault(value, body)
        return {"subject": subject, "bodies": table}

    @staticmethod
    def _plain_read(read: str) -> bool:
        """A variable's read and nothing else: no call (a function's result may differ from branch to
        branch, or act), no other registered value."""
        return ("V[" in read or "G[" in read) and "_k" not in read and "(fr" not in read and "(" + "m." not in read

    def table_chain(self, table, branches, else_body, where: str | None) -> Inline:
        bodies = {value: body if callable(body) else Inline(self, body) for value, body in table["bodies"].items()}
        v, b, sig = self.temp(), self.temp(), self.temp()
        lines = [
            f"{v} = {table['subject']}",
            f"{b} = {self.const(bodies)}.get({v}) if type({v}) in {self.const(CHAIN_TYPES)} else None",
            f"if {b} is not None:",
            f"    {sig} = {b}(fr)",
            f"    if {sig} is not None:",
            f"        return {sig}",
        ]
        if else_body is not None:
            lines.append("else:")
            lines.extend(indent(self.body_lines(else_body) or ["pass"]))
        return Inline(self, self.guarded(lines, where or self.filename))
