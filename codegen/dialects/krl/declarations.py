"""KRL declarations: DECL (arrays of up to three dimensions), user types (STRUC, ENUM), data lists, types' checks."""

from __future__ import annotations

import math

import numpy as np
from lark import Token, Tree

from codegen.dialects.core.limits import array_size_problem
from codegen.dialects.core.values import F32, Record, RunError, constant, f32
from codegen.dialects.krl.builtins import (
    CART,
    SIMPLE,
    STRUCTS,
    SYSTEM_ENUMS,
    TYPES_NOT_MODELLED,
    UNINIT,
    new_value,
    type_name_of,
)
from codegen.dialects.krl.numbered import SYSTEM_ARRAYS
from codegen.dialects.krl.sysvars import SHARED_STRUCTS

# KSS 8 programming manual for system integrators, "Variables and declarations": arrays have up to three
# dimensions (DECL INT A[3,4]); a CHAR array holds a text (the last dimension of a CHAR array is its length:
# DECL CHAR NAMES[16,24] is 16 texts); STRUC name type field, ... and ENUM name value, ... declare types, in a
# routine's declaration section or a data list (GLOBAL in a PUBLIC one: every module's). "ANY" is the
# interpreter's type of a component it records as it is (the inline forms' circle modes, jerk limits).
DECLARATIONS = frozenset(
    {
        "decl",
        "signal_decl",
        "global_signal_decl",
        "ext_routine",
        "ext_function",
        "enum_decl",
        "struc_decl",
        "import_decl",
    }
)
MAX_DIMS = 3


class Char(str):
    """The type of a CHAR array's text with its declared length: "CHAR" wherever a type is compared, and coerce()
    refuses a longer text (DECL CHAR S[10] holds 10 characters)."""

    def __new__(cls, length: int) -> Char:
        text = super().__new__(cls, "CHAR")
        text.length = length
        return text

    def __getnewargs__(self) -> tuple[int]:
        return (self.length,)


class Declarations:
    """Compiler mixin: the program's types, declarations and data lists."""

    def init_types(self) -> None:
        self.structs: dict[str, list] = {**STRUCTS, **SHARED_STRUCTS}
        self.struct_fields = {name: dict(fields) for name, fields in self.structs.items()}
        self.enums: dict[str, frozenset] = dict(SYSTEM_ENUMS)
        self.RECORD_TYPES = frozenset(self.structs)
        self.data_decls: list = []
        self.static_types: dict = {}  # a data list's names (storage key) -> declared type, for the static checks

    def known_type(self, name: str) -> bool:
        return name in SIMPLE or name in self.structs or name in self.enums or name == "ANY"

    # --- user types (declared before anything is compiled: every module's) -------------------------------
    def declare_types(self, node) -> None:
        if node.data == "enum_decl":
            _global, name, *values = node.children
            self.enums[str(name).upper()] = frozenset("#" + str(v).upper() for v in values)
        elif node.data == "struc_decl":
            _global, name, *items = node.children
            fields, last = [], None
            for item in items:
                type_token, field_name, _dims = item.children
                if field_name is None:  # one name: the type of the field before
                    type_token, field_name = None, type_token
                last = str(type_token).upper() if type_token is not None else last
                if last is None:
                    self.fail(item, f"STRUC {name}: the first component needs a type")
                fields.append((str(field_name).upper(), "CHAR" if last == "CHAR" else last))
            key = str(name).upper()
            self.structs[key] = fields
            self.struct_fields[key] = dict(fields)
            self.RECORD_TYPES = frozenset(self.structs)

    def check_types(self) -> None:
        """A component of a type no module declares is one of the controller's own types (ESYS, a technology
        package's): the interpreter records it as it is (ANY). A variable of such a type is refused."""
        for name, fields in self.structs.items():
            if any(not self.known_type(t) for _f, t in fields):
                self.structs[name] = [(f, t if self.known_type(t) else "ANY") for f, t in fields]
                self.struct_fields[name] = dict(self.structs[name])

    # --- values of a type -------------------------------------------------------------------------
    def coerce(self, type_name, value, where):
        if type_name is None or isinstance(type_name, tuple) or value is UNINIT:
            return value
        if type_name == "REAL":
            if type(value) is F32:
                return value
            if isinstance(value, bool) or not isinstance(value, int | float | np.number):
                raise RunError(f"{where}: cannot assign {type_name_of(value)} to REAL")
            return f32(value)
        if type_name == "INT":
            if isinstance(value, bool) or not isinstance(value, int | float | np.number):
                raise RunError(f"{where}: cannot assign {type_name_of(value)} to INT")
            if not math.isfinite(float(value)):
                raise RunError(f"{where}: cannot assign a non-finite value to INT")
            rounded = math.floor(float(value) + 0.5) if not isinstance(value, int) else value
            low, high = self.INT_RANGE
            if not low <= rounded <= high:
                raise RunError(f"{where}: value {value:.6g} out of the INT range {low}..{high} (32-bit)")
            return rounded
        if type(value) is Record and value.type == type_name:  # a record of its own type: as it is
            return value
        if type_name == "BOOL":
            if not isinstance(value, bool):
                raise RunError(f"{where}: cannot assign {type_name_of(value)} to BOOL")
            return value
        if type_name == "CHAR":
            if not isinstance(value, str) or value.startswith("#"):
                raise RunError(f"{where}: cannot assign {type_name_of(value)} to CHAR")
            length = getattr(type_name, "length", None)
            if length is not None and len(value) > length:
                raise RunError(f"{where}: a text of {len(value)} characters does not fit CHAR[{length}]")
            return value
        if type_name in ("ENUM", "ANY"):
            return value
        if type_name in self.enums:
            if not isinstance(value, str) or value.upper() not in self.enums[type_name]:
                shown = value if isinstance(value, str) and value.startswith("#") else type_name_of(value)
                values = ", ".join(sorted(self.enums[type_name]))
                raise RunError(f"{where}: {shown} is not a value of {type_name} ({values})")
            return value.upper()
        if type_name in self.structs:
            return self.coerce_record(type_name, value, where)
        raise RunError(f"{where}: unknown type {type_name}")

    def coerce_record(self, type_name: str, value, where: str):
        if not isinstance(value, Record):
            raise RunError(f"{where}: cannot assign {type_name_of(value)} to {type_name}")
        if value.type == type_name:
            return value
        fields = self.struct_fields[type_name]
        if value.type is None or (value.type in CART and type_name in CART):
            out = new_value(type_name, self.structs)
            for key, v in value.items():
                if key in fields:
                    out[key] = self.coerce(fields[key], v, where)
                elif value.type is None:
                    raise RunError(f"{where}: {type_name} has no component {key}")
            return out
        raise RunError(f"{where}: cannot assign {value.type} to {type_name}")

    def element_type(self, type_name):
        return type_name[0] if isinstance(type_name, tuple) else type_name

    # --- DECL --------------------------------------------------------------------------------------
    def decl_items(self, node):
        """[(name, type, init closure)] for one DECL line."""
        children = [c for c in node.children if c is not None]
        tokens = [c for c in children if isinstance(c, Token)]
        type_token = next(t for t in tokens if t.type == "NAME")
        type_name = str(type_token).upper()
        if type_name in TYPES_NOT_MODELLED:
            self.fail(type_token, f"{type_token}: {TYPES_NOT_MODELLED[type_name]} is not modelled by this interpreter")
        if not self.known_type(type_name) or type_name == "ANY":
            self.fail(type_token, f"unknown type {type_token}")
        out = []
        for item in (c for c in children if isinstance(c, Tree) and c.data == "decl_item"):
            name, dims, init = item.children
            key = str(name).upper()
            where = self.where(item)
            if self.known_type(key):  # e.g. AXIS, FRAME: KSS's own structure types (whether KSS refuses: unconfirmed)
                self.fail(name, f"{name} is the name of a data type: a variable named so is refused or misread on KSS")
            if isinstance(dims, Token):  # NAME[]: an array parameter, sized by the caller's array
                out.append((key, "CHAR" if type_name == "CHAR" else (type_name, None), constant(UNINIT)))
                continue
            if dims is not None:
                sizes = [int(str(t)) for t in dims.children]
                if problem := array_size_problem(sizes):
                    self.fail(dims, problem)
                text_type = Char(sizes[-1]) if type_name == "CHAR" else None
                if type_name == "CHAR":  # the last dimension is the text's length
                    sizes = sizes[:-1]
                if len(sizes) > MAX_DIMS:
                    self.fail(dims, f"an array has up to {MAX_DIMS} dimensions")
                if any(size < 1 for size in sizes):
                    self.fail(dims, "an array's dimension must be at least 1")
                if not sizes:
                    value_init = self.expr(init) if init is not None else None
                    if value_init is not None:
                        self.check_static(init, text_type, item)
                    text = lambda fr, v=value_init, w=where, t=text_type: self.coerce(t, v(fr), w) if v else UNINIT  # noqa: E731
                    out.append((key, text_type, text))
                    continue
                if init is not None:
                    self.fail(init, "an array is declared without a value (its elements are set one by one)")
                element = text_type or type_name
                out.append((key, (element, sizes[0]), constant(self.new_array(element, sizes))))
                continue
            if init is None:
                out.append((key, type_name, constant(new_value(type_name, self.structs))))
            else:
                self.check_static(init, type_name, item)
                value = self.expr(init)
                out.append((key, type_name, (lambda fr, t=type_name, v=value, w=where: self.coerce(t, v(fr), w))))
        return out

    def declared_once(self, node, seen: dict[str, int]) -> None:
        """A name a DECL line declares that an earlier one of the same routine or data list declared: refused, as
        KSS's compiler refuses a name declared twice (seen: name -> its line, filled here)."""
        for item in (c for c in node.children if isinstance(c, Tree) and c.data == "decl_item"):
            name = item.children[0]
            key = str(name).upper()
            if key in seen:
                self.fail(name, f"{name} is declared twice (first on line {seen[key]})")
            seen[key] = name.line

    def new_array(self, element: str, sizes: list[int]) -> list:
        """A new array: one shared initial value per dimension (values are never changed in place)."""
        inner = [new_value(element, self.structs) for _ in range(sizes[-1])]
        for size in reversed(sizes[:-1]):
            inner = [inner] * size
        return inner

    def static_type(self, target):
        """The declared type of an assignment's target (a variable, a component, an element), None if unknown."""
        if isinstance(target, Tree) and target.data == "var":
            key = str(target.children[0]).upper()
            if self.local_types is not None and key in self.local_types:
                return self.local_types[key]
            store = self.scope.data.get(key)
            return self.static_types.get(store) if store is not None else None
        if isinstance(target, Tree) and target.data == "whole":  # S[] = "...": the CHAR array's text
            return self.static_type(target.children[0])
        if isinstance(target, Tree) and target.data == "field":
            outer = self.static_type(target.children[0])
            fields = self.struct_fields.get(outer, {}) if isinstance(outer, str) else {}
            return fields.get(str(target.children[1]).upper())
        if isinstance(target, Tree) and target.data == "index":
            outer = self.static_type(target.children[0])
            return outer[0] if isinstance(outer, tuple) and len(target.children) == 2 else None
        return None

    def check_static(self, node, type_name, where_node) -> None:
        """A literal of another type assigned or declared (DECL INT N = "abc"): the controller's compiler
        refuses it, so does the interpreter, before the program runs."""
        literal = {"string": "CHAR", "true": "BOOL", "false": "BOOL", "number": "number", "enum": "an ENUM value"}
        have = literal.get(node.data) if isinstance(node, Tree) else None
        if have is None or isinstance(type_name, tuple) or type_name in ("ANY", "ENUM"):
            return
        number = type_name in ("INT", "REAL")
        ok = (
            (have == "number" and number)
            or (have == "CHAR" and type_name == "CHAR")
            or (have == "BOOL" and type_name == "BOOL")
            or (
                have == "an ENUM value"
                and type_name in self.enums
                and "#" + str(node.children[0]).upper() in self.enums[type_name]
            )
        )
        if have == "an ENUM value" and type_name in self.enums and not ok:
            self.fail(where_node, f"type error: #{node.children[0]} is not a value of {type_name}")
        if not ok:
            shown = "a number" if have == "number" else have
            self.fail(where_node, f"type error: cannot assign {shown} to {type_name}")
        length = getattr(type_name, "length", None)
        if have == "CHAR" and length is not None and len(self.string_value(str(node.children[0]))) > length:
            text = self.string_value(str(node.children[0]))
            self.fail(where_node, f"type error: a text of {len(text)} characters does not fit CHAR[{length}]")

    # --- data lists ----------------------------------------------------------------------------
    def data_list(self, node, storage: dict[str, str]) -> None:
        """A DEFDAT's declarations and assignments, run once when the program is loaded (storage: NAME ->
        the globals' key of this module's data)."""
        seen: dict[str, int] = {}
        for child in node.children[-1].children:
            if not isinstance(child, Tree):
                continue
            try:
                if child.data == "decl":
                    self.declared_once(child, seen)
                self.data_item(child, storage)
            except RunError as exc:
                if self.findings is None:
                    raise
                self.findings.append(exc)

    def data_item(self, child, storage: dict[str, str]) -> None:
        if child.data == "decl":
            items = []
            for key, type_name, init in self.decl_items(child):
                if key in SYSTEM_ARRAYS:  # TOOL_DATA...: the interpreter's own (its values: --input, assignments)
                    if self.element_type(type_name) != SYSTEM_ARRAYS[key][0]:
                        self.fail(child, f"{key} is an array of {SYSTEM_ARRAYS[key][0]} (KUKA's $config.dat)")
                    continue
                items.append((storage.get(key, key), type_name, init))
                self.static_types[storage.get(key, key)] = type_name
            self.data_decls.append(("decl", items))
        elif child.data == "signal_decl":
            self.s_signal_decl(child)
        elif child.data == "global_signal_decl":
            self.s_global_signal_decl(child)
        elif child.data == "import_decl":
            self.fail(child, "IMPORT is not modelled: declare the data DECL GLOBAL in a PUBLIC data list")
        elif child.data in DECLARATIONS:  # types and EXT: declared before compiling
            pass
        else:
            self.data_decls.append(("assign", self.s_assign(child)))

    def init_data(self, fr) -> None:
        for kind, payload in self.data_decls:
            if kind == "decl":
                for key, type_name, init in payload:
                    fr.m.global_types[key] = type_name
                    fr.m.globals[key] = init(fr)
            else:
                payload(fr)

    def s_decl(self, node):
        self.fail(node, "DECL after the first statement of a routine (KRL: declarations come first)")

    def s_import_decl(self, node):
        self.fail(node, "IMPORT is not modelled: declare the data DECL GLOBAL in a PUBLIC data list")
