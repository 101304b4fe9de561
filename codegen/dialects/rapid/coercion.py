"""RAPID values stored by type: declared types resolved (aliases, RECORDs), zero values and coercions."""

from __future__ import annotations

from codegen.dialects.core.values import F32, Record, RunError, f32
from codegen.dialects.rapid import dataops
from codegen.dialects.rapid.types import (
    ALIASES,
    CLOCK,
    NOT_MODELLED,
    OPAQUE,
    SCALARS,
    SIGNAL_TYPES,
    num,
    type_text,
    zero,
)


class Coercions:
    """Compiler mixin: a declared type's name resolved, its zero value, and a value stored as that type."""

    def resolve_type(self, token, conformant=None, dims: int = 0):
        """A declared type by name (aliases resolved): refused when the language has no such type, or the
        interpreter does not model it; an array type (element, size or None) for conformant or dims."""
        upper = str(token).upper()
        seen = set()
        while upper in self.aliases and upper not in ALIASES and upper not in seen:  # a program's own ALIAS
            seen.add(upper)
            upper = self.aliases[upper]
        if upper not in SCALARS and upper not in self.records and upper not in OPAQUE and upper not in ALIASES:
            if upper in NOT_MODELLED:
                self.fail(token, f"data type {token} is not modelled by the interpreter", "unsupported")
            self.fail(token, f"unknown data type {token}", "unknown-type")
        for _ in conformant.children if conformant is not None else ():  # one conformant_dim per dimension
            upper = (upper, None)
        return upper

    def zero_of(self, type_name):
        if isinstance(type_name, tuple):
            element, size = type_name
            return [self.zero_of(element) for _ in range(size or 0)]
        if type_name in SIGNAL_TYPES:
            return Record(type_name, {"NAME": ""})
        if type_name == CLOCK:
            return dataops.clock_zero()
        if type_name in ALIASES:
            return zero(ALIASES[type_name])
        return zero(type_name, self.records)

    def coerce(self, type_name, value, where):
        if type_name is None:
            return value
        if type_name == "NUM":
            return value if type(value) is F32 else f32(num(value, where))
        if isinstance(type_name, tuple):  # (element type, size) array
            element = type_name[0]
            while isinstance(element, tuple):
                element = element[0]
            return self.coerce_array(type_name, value, where, str(element).lower())
        if type_name == "DNUM":
            return float(num(value, where))
        if type_name in ("BOOL", "SWITCH"):
            if not isinstance(value, bool):
                raise RunError(f"{where}: expected a bool, got {type_text(value)}")
            return value
        if type_name == "STRING":
            if not isinstance(value, str):
                raise RunError(f"{where}: expected a string, got {type_text(value)}")
            if len(value) > 80:
                raise RunError(f"{where}: string longer than 80 characters")
            return value
        fields = self.records.get(type_name)
        if fields is not None:
            if isinstance(value, Record):
                if value.type != type_name:
                    raise RunError(f"{where}: expected {type_name.lower()}, got {str(value.type).lower()}")
                return value
            if isinstance(value, list):
                if len(value) != len(fields):
                    raise RunError(f"{where}: {type_name.lower()} has {len(fields)} components, got {len(value)}")
                return Record(type_name, {k: self.coerce(t, v, where) for (k, t), v in zip(fields, value, strict=True)})
            raise RunError(f"{where}: expected {type_name.lower()}, got {type_text(value)}")
        if type_name in ALIASES:  # the manual's aliases (intnum, errnum, byte...): stored as their type
            return self.coerce(ALIASES[type_name], value, where)
        if type_name in OPAQUE:
            if not (isinstance(value, Record) and value.type == type_name):
                raise RunError(f"{where}: expected {type_name.lower()}, got {type_text(value)}")
            return value
        return value

    def element_type(self, type_name):
        return type_name[0] if isinstance(type_name, tuple) else type_name

    def coerce_like(self, old, value, where):
        if isinstance(old, Record):
            return self.coerce(old.type, value, where)
        if isinstance(old, bool):
            return self.coerce("BOOL", value, where)
        if isinstance(old, str):
            return self.coerce("STRING", value, where)
        return super().coerce_like(old, value, where)
