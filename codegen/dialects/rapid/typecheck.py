"""Static types of RAPID expressions for `codegen check`: assignments, conditions, arguments, RETURN, fields."""

from __future__ import annotations

from lark import Token, Tree

from codegen.dialects.core.files import Finding
from codegen.dialects.rapid.names import CONSTANTS
from codegen.dialects.rapid.predefined import PREDEFINED
from codegen.dialects.rapid.types import ALIASES, SIGNAL_TYPES

# What a function of the manual returns (RAPID Instructions, Functions and Data types, chapter 2), by name.
_RETURNS = {
    "NUM": """ABS SIN COS TAN ACOS ASIN ATAN ATAN2 EXP POW SQRT ROUND TRUNC DIM DISTANCE DOTPROD VECTMAGN BITAND BITOR
              BITXOR BITNEG BITLSH BITRSH STRLEN STRFIND STRMATCH DINPUT DOUTPUT GINPUT GOUTPUT AINPUT AOUTPUT CLKREAD
              EULERZYX MAXROBSPEED OPMODE RUNMODE UIMESSAGEBOX""",
    "STRING": "NUMTOSTR STRPART STRMAP VALTOSTR CTIME CDATE",
    "BOOL": "TESTDI VALIDIO STRMEMB STRORDER STRTOVAL PRESENT BITCHECK",
    "ROBTARGET": "OFFS RELTOOL CROBT",
    "POS": "CPOS POSEVECT",
    "ORIENT": "ORIENTZYX NORIENT",
    "POSE": "POSEMULT POSEINV",
    "JOINTTARGET": "CJOINTT",
}
RETURNS = {name: kind for kind, names in _RETURNS.items() for name in names.split()}
# The types of the required parameters of some built-in routines (the same chapters), checked as a user routine's.
_N, _S = "NUM", "STRING"
PARAMETERS = {
    **{key: [_N] for key in ("ABS", "SIN", "COS", "TAN", "ACOS", "ASIN", "ATAN", "EXP", "SQRT", "ROUND", "TRUNC")},
    "WAITTIME": [_N],
    **{name: [_N, _N] for name in ["ATAN2", "POW", "NUMTOSTR", "ACCSET", "VELSET"]},
    "STRLEN": [_S], "STRPART": [_S, _N, _N], "STRFIND": [_S, _N, _S], "STRMATCH": [_S, _N, _S],
    "STRMEMB": [_S, _N, _S], "STRMAP": [_S, _S, _S], "STRORDER": [_S, _S, _S], "TPWRITE": [_S],
    "OFFS": ["ROBTARGET", _N, _N, _N], "RELTOOL": ["ROBTARGET", _N, _N, _N], "ORIENTZYX": [_N, _N, _N],
    "POSEMULT": ["POSE", "POSE"], "POSEINV": ["POSE"], "POSEVECT": ["POSE", "POS"], "DISTANCE": ["POS", "POS"],
}  # fmt: skip
NUMERIC = {"NUM", "DNUM"}


def shown(kind) -> str:
    if isinstance(kind, tuple) and kind[0] == "AGG":
        return f"an aggregate of {len(kind[1])}"
    if isinstance(kind, tuple):
        return f"an array of {shown(kind[0])}"
    return str(kind).lower()


class Checker:
    """The types of one module's routines, reported as findings."""

    def __init__(self, compiler, file: str, scope: dict, findings: list) -> None:
        self.c, self.file, self.scope, self.findings = compiler, file, scope, findings
        self.env: dict = {}
        self.returns = None
        self.in_func = False

    def report(self, node, message: str) -> None:
        line, column = self.c.position(node)
        self.findings.append(Finding(self.file, line, column, "error", "type", message))

    # --- types ------------------------------------------------------------------------------------
    def base(self, kind):
        if isinstance(kind, str):
            seen = set()
            while kind in self.c.aliases and kind not in seen:
                seen.add(kind)
                kind = self.c.aliases[kind]
            return ALIASES.get(kind, kind)
        return kind

    def declared(self, type_token, dims=None):
        upper = self.base(str(type_token).upper())
        if upper not in self.c.records and upper not in NUMERIC | {"BOOL", "STRING"}:
            return None
        for _ in dims.children if dims is not None else []:
            upper = (upper, None)
        return upper

    def fits(self, target, value) -> bool:
        target, value = self.base(target), self.base(value)
        if target is None or value is None or target == value:
            return True
        if target in NUMERIC and value in NUMERIC:
            return True
        if isinstance(value, tuple) and value[0] == "AGG":
            items = value[1]
            if isinstance(target, tuple):
                return (target[1] is None or target[1] == len(items)) and all(self.fits(target[0], i) for i in items)
            fields = self.c.records.get(target)
            if fields is None:
                return False
            return len(fields) == len(items) and all(self.fits(t, i) for (_k, t), i in zip(fields, items, strict=True))
        if isinstance(target, tuple) and isinstance(value, tuple):
            return self.fits(target[0], value[0])
        return False

    def why(self, target, value, path: str) -> str:
        """Where an aggregate does not fit its type: the innermost component that does not (for messages)."""
        target, value = self.base(target), self.base(value)
        if isinstance(value, tuple) and value[0] == "AGG":
            items = value[1]
            fields = self.c.records.get(target) if isinstance(target, str) else None
            if fields is not None and len(fields) == len(items):
                for (key, kind), item in zip(fields, items, strict=True):
                    if not self.fits(kind, item):
                        return self.why(kind, item, f"{path}.{key.lower()}")
            if fields is not None:
                return f"{path} is {shown(target)} of {len(fields)} components, the aggregate has {len(items)}"
        return f"{path} is {shown(target)}, not {shown(value)}"

    # --- routines and statements ------------------------------------------------------------------
    def routine(self, node) -> None:
        c = node.children
        if node.data == "func":
            params, body, self.returns, self.in_func = c[3], c[4], self.declared(c[1]), True
        elif node.data == "trap":
            params, body, self.returns, self.in_func = None, c[2], None, False
        else:
            params, body, self.returns, self.in_func = c[2], c[3], None, False
        self.env = {}
        for item in params.children if isinstance(params, Tree) else []:
            param = item.children[0] if item.data == "alt_param" else item
            _opt, _mode, ptype, pname, conformant = param.children
            self.env[str(pname).upper()] = self.declared(ptype, conformant)
        for clause in [body, *(x.children[-1] for x in c if isinstance(x, Tree) and x.data.endswith("_clause"))]:
            self.block(clause)

    def block(self, body) -> None:
        for stmt in body.children if isinstance(body, Tree) else []:
            if isinstance(stmt, Tree):
                self.stmt(stmt)

    def stmt(self, node) -> None:
        kind = node.data
        if kind == "data_decl":
            _l, _t, _s, type_name, name, dims, init = node.children
            self.env[str(name).upper()] = declared = self.declared(type_name, dims)
            if init is not None and not self.fits(declared, value := self.expr(init)):
                self.report(init, f"initial value: {self.why(declared, value, str(name))}")
        elif kind == "assign":
            target, value_node = node.children
            have, value = self.expr(target), self.expr(value_node)
            if not self.fits(have, value):
                self.report(value_node, f"assignment: {self.why(have, value, 'the target')}")
        elif kind in ("if_stmt", "elseif_clause", "while_stmt", "compact_if"):
            self.condition(node.children[0])
            for child in node.children[1:]:
                if isinstance(child, Tree):
                    self.block(child) if child.data == "body" else self.stmt(child)
        elif kind == "else_clause":
            self.block(node.children[0])
        elif kind == "for_stmt":
            name, *bounds, body = node.children
            for bound in bounds:
                if bound is not None and not self.fits("NUM", found := self.expr(bound)):
                    self.report(bound, f"a FOR loop's bound is a num, not {shown(found)}")
            saved, self.env = self.env, {**self.env, str(name).upper(): "NUM"}
            self.block(body)
            self.env = saved
        elif kind == "test_stmt":
            self.expr(node.children[0])
            for clause in node.children[1:]:
                if isinstance(clause, Tree):
                    self.block(clause.children[-1])
        elif kind == "return_stmt":
            self.return_stmt(node)
        elif kind in ("proc_call", "late_call", "raise_stmt", "connect_stmt"):
            for child in node.children:
                if isinstance(child, Tree):
                    self.args(child) if child.data == "call_args" else self.expr(child)
            if kind == "proc_call":
                self.call_types(node, str(node.children[0]).upper())
        elif kind == "error_clause":
            self.block(node.children[-1])

    def condition(self, node) -> None:
        found = self.expr(node)
        if not self.fits("BOOL", found):
            self.report(node, f"a condition is a bool, not {shown(found)}")

    def return_stmt(self, node) -> None:
        value_node = node.children[0]
        if value_node is None:
            if self.in_func:
                self.report(node, "RETURN in a FUNC needs a value")
            return
        value = self.expr(value_node)
        if not self.in_func:
            self.report(node, "RETURN with a value outside a FUNC")
        elif not self.fits(self.returns, value):
            self.report(value_node, f"the function returns {shown(self.returns)}, not {shown(value)}")

    def args(self, args_node) -> None:
        for arg in args_node.children:
            if isinstance(arg, Tree) and arg.data == "opt_arg":
                if isinstance(arg.children[1], Tree):
                    self.expr(arg.children[1])
            elif isinstance(arg, Tree):
                self.expr(arg)

    def call_types(self, node, upper: str) -> None:
        key = self.scope.get(upper, upper)
        decl = self.c.routine_decls.get(key)
        if node.children[1] is None:
            return
        if decl is not None:
            required = decl[0]
        elif upper in PARAMETERS:
            required = [(f"{i + 1}", "IN", kind) for i, kind in enumerate(PARAMETERS[upper])]
        else:
            return
        positional = [a for a in node.children[1].children if not (isinstance(a, Tree) and a.data == "opt_arg")]
        for arg, (pname, _mode, ptype) in zip(positional, required, strict=False):
            found = self.expr(arg)
            if not self.fits(self._param(ptype), found):
                what = f"argument {pname}" if pname.isdigit() else f"parameter {pname.lower()}"
                self.report(arg, f"{what} of {node.children[0]} is {shown(ptype)}, not {shown(found)}")

    def _param(self, ptype):
        return ptype if not (isinstance(ptype, str) and ptype in ALIASES) else ALIASES[ptype]

    # --- expressions ------------------------------------------------------------------------------
    def expr(self, node):
        if isinstance(node, Token):
            return self.name(node)
        method = getattr(self, f"e_{node.data}", None)
        return method(node) if method is not None else None

    def name(self, token):
        upper = str(token).upper()
        if upper in self.env:
            return self.env[upper]
        key = self.scope.get(upper, upper)
        if key in self.c.data_types:
            kind = self.c.data_types[key]
            return "NUM" if kind in SIGNAL_TYPES else self.base(kind)
        if upper in PREDEFINED:
            return PREDEFINED[upper].type
        if upper in CONSTANTS:
            return "STRING" if isinstance(CONSTANTS[upper], str) else "NUM"
        if upper == "ERRNO" or upper in self.c.signal_kinds:
            return "NUM"
        return None

    def e_var(self, node):
        return self.name(node.children[0])

    def e_number(self, node):
        return "NUM"

    def e_string(self, node):
        return "STRING"

    def e_true(self, node):
        return "BOOL"

    e_false = e_true

    def e_aggregate(self, node):
        return ("AGG", [self.expr(c) for c in node.children])

    def e_field(self, node):
        base, name = self.base(self.expr(node.children[0])), str(node.children[1]).upper()
        fields = self.c.records.get(base) if isinstance(base, str) else None
        if fields is None:
            if base is not None and not isinstance(base, tuple) and base not in SIGNAL_TYPES:
                self.report(node, f"{shown(base)} has no components (.{node.children[1]})")
            return None
        for key, kind in fields:
            if key == name:
                return kind
        self.report(node, f"{shown(base)} has no component {node.children[1]}")
        return None

    def e_index(self, node):
        kind = self.expr(node.children[0])
        for index in node.children[1:]:
            if not self.fits("NUM", found := self.expr(index)):
                self.report(index, f"an index is a num, not {shown(found)}")
            if kind is None:
                return None
            if not isinstance(kind, tuple):
                self.report(node, f"{shown(kind)} is not an array")
                return None
            kind = kind[0]
        return kind

    def e_call(self, node):
        name, args_node = node.children
        if args_node is not None:
            self.args(args_node)
        upper = str(name).upper()
        key = self.scope.get(upper, upper)
        routine = self.c.routines.get(key)
        self.call_types(node, upper)
        if routine is not None:
            return routine.return_type
        return RETURNS.get(upper)

    def e_add(self, node):
        left, right = (self.base(self.expr(c)) for c in node.children)
        if "POS" in (left, right) and (self.fits("POS", left) and self.fits("POS", right)):
            return "POS"  # an aggregate of three nums beside a pos is one
        if isinstance(left, tuple) or isinstance(right, tuple):
            if None not in (left, right):
                self.report(node, f"+ of {shown(left)} and {shown(right)}")
            return None
        if left in NUMERIC and right in NUMERIC:
            return "NUM" if "DNUM" not in (left, right) else "DNUM"
        if left == right and left in ("STRING", "POS"):
            return left
        if None not in (left, right):
            self.report(node, f"+ of {shown(left)} and {shown(right)}")
        return None

    def _arithmetic(self, node):
        operands = [c for c in node.children if isinstance(c, Tree | Token) and not _operator(c)]
        kinds = [self.base(self.expr(c)) for c in operands]
        if all(k in NUMERIC for k in kinds):
            return "NUM"
        if "STRING" in kinds or "BOOL" in kinds:
            self.report(node, "arithmetic on " + " and ".join(shown(k) for k in kinds if k is not None))
        return None

    e_sub = e_mul = e_div = e_intdiv = e_mod = e_neg = _arithmetic

    def e_compare(self, node):
        left_node, op, right_node = node.children
        left, right = self.base(self.expr(left_node)), self.base(self.expr(right_node))
        if str(op) in ("=", "<>"):
            if not (self.fits(left, right) or self.fits(right, left)):
                self.report(node, f"{op} compares {shown(left)} with {shown(right)}")
        elif any(k is not None and k not in NUMERIC for k in (left, right)):
            self.report(node, f"{op} compares nums, not {shown(left)} and {shown(right)}")
        return "BOOL"

    def _logic(self, node):
        for child in node.children:
            if isinstance(child, Tree) or (isinstance(child, Token) and child.type == "NAME"):
                found = self.base(self.expr(child))
                if found is not None and found != "BOOL":
                    self.report(child, f"AND, OR, XOR and NOT take bools, not {shown(found)}")
        return "BOOL"

    e_and_ = e_or_ = e_xor = e_not_ = _logic


def _operator(token) -> bool:
    return isinstance(token, Token) and token.type in ("DIV", "MOD", "AND", "OR", "XOR", "NOT", "COMP_OP")


def check(compiler, trees) -> list[Finding]:
    """Type errors of every routine of the task's modules (files parsed: [(file name, tree)])."""
    findings: list[Finding] = []
    for file, tree in trees:
        for module in tree.children:
            if not (isinstance(module, Tree) and module.data == "module"):
                continue
            scope = compiler.scopes.get(str(module.children[0]).upper(), {})
            checker = Checker(compiler, file, scope, findings)
            for item in module.children[2:]:
                if isinstance(item, Tree) and item.data in ("proc", "func", "trap"):
                    checker.routine(item)
                elif isinstance(item, Tree) and item.data == "data_decl":
                    checker.stmt(item)
                    checker.env = {}
    return findings
