"""RAPID data types: the built-in records and aliases, zero values, and the helpers that read numbers and records."""

from __future__ import annotations

import operator

import numpy as np

from codegen.dialects.core.values import F32, Record, RunError, f32

# The data types of ABB, "Technical reference manual - RAPID Instructions, Functions and Data types" (RobotWare 6,
# 3HAC050917; the same in RobotWare 7's), chapter 3 "Data types": the records below by their components in order
# (aggregates [a, b, ...] are positional). Only the types the interpreter models are here; see NOT_MODELLED.
RECORDS = {
    "POS": [("X", "NUM"), ("Y", "NUM"), ("Z", "NUM")],
    "ORIENT": [("Q1", "NUM"), ("Q2", "NUM"), ("Q3", "NUM"), ("Q4", "NUM")],
    "POSE": [("TRANS", "POS"), ("ROT", "ORIENT")],
    "CONFDATA": [("CF1", "NUM"), ("CF4", "NUM"), ("CF6", "NUM"), ("CFX", "NUM")],
    "EXTJOINT": [(f"EAX_{c}", "NUM") for c in "ABCDEF"],
    "ROBTARGET": [("TRANS", "POS"), ("ROT", "ORIENT"), ("ROBCONF", "CONFDATA"), ("EXTAX", "EXTJOINT")],
    "LOADDATA": [("MASS", "NUM"), ("COG", "POS"), ("AOM", "ORIENT"), ("IX", "NUM"), ("IY", "NUM"), ("IZ", "NUM")],
    "TOOLDATA": [("ROBHOLD", "BOOL"), ("TFRAME", "POSE"), ("TLOAD", "LOADDATA")],
    "ROBJOINT": [(f"RAX_{i}", "NUM") for i in range(1, 7)],  # rax_1..rax_6 (robjoint)
    "JOINTTARGET": [("ROBAX", "ROBJOINT"), ("EXTAX", "EXTJOINT")],
    "WOBJDATA": [("ROBHOLD", "BOOL"), ("UFPROG", "BOOL"), ("UFMEC", "STRING"), ("UFRAME", "POSE"), ("OFRAME", "POSE")],
    "SPEEDDATA": [("V_TCP", "NUM"), ("V_ORI", "NUM"), ("V_LEAX", "NUM"), ("V_REAX", "NUM")],
    "ZONEDATA": [
        ("FINEP", "BOOL"),
        *((k, "NUM") for k in ("PZONE_TCP", "PZONE_ORI", "PZONE_EAX", "ZONE_ORI", "ZONE_LEAX", "ZONE_REAX")),
    ],
}
SCALARS = {"NUM", "DNUM", "BOOL", "STRING"}

# Alias types of the manual (each "is an alias data type for num", or for string): stored as that type.
ALIASES = {
    **dict.fromkeys(
        ("BYTE", "INTNUM", "ERRNUM", "ERRTYPE", "ERRDOMAIN", "TPNUM", "SYMNUM", "OPNUM", "DIONUM", "BTNRES"),
        "NUM",
    ),
    **dict.fromkeys(("BUTTONDATA", "ICONDATA"), "NUM"),
    **dict.fromkeys(("STRINGDIG", "ERRSTR"), "STRING"),
}
# Non-value types the interpreter models: a signal variable (connected with AliasIO), a clock.
SIGNAL_TYPES = {f"SIGNAL{kind}": kind for kind in ("DI", "DO", "GI", "GO", "AI", "AO")}
CLOCK = "CLOCK"
OPAQUE = {*SIGNAL_TYPES, CLOCK}

# Data types of the manual the interpreter does not model: a declaration of one is refused by name.
_NOT_MODELLED = """TRIGGDATA TRIGGIOS TRIGGIOSDNUM TRIGGSTRGO TRIGGFLAG IODEV RAWBYTES DIR SHAPEDATA WZSTATIONARY
    WZTEMPORARY
    STOPPOINTDATA SYNCIDENT TASKS TASKID IDENTNO MECUNIT SENSOR SENSORSTATE CORRDESCR LOADIDNUM LOADSESSION
    PARIDNUM PARIDVALIDNUM RESTARTDATA RMQHEADER RMQMESSAGE RMQSLOT SOCKETDEV SOCKETSTATUS TESTSIGNAL
    TRAPDATA CFGDOMAIN HANDLER_TYPE EVENT_TYPE UISHOWNUM CAMERADEV CAMERATARGET CAMERASTATUS EGMIDENT EGMSTATE
    EGM_MINMAX EGMFRAMETYPE EGMSTOPMODE"""  # the last line: Externally Guided Motion (an option's types)
NOT_MODELLED = frozenset(_NOT_MODELLED.split())

STRING_MAX = 80  # characters of a RAPID string (RAPID kernel manual, string; targets/abb.toml string_max)
IDENTIFIER_MAX = 32  # characters of a RAPID name (RAPID kernel manual, identifiers; targets/abb.toml)


def _zero(type_name: str, records: dict):
    if type_name in records:
        return Record(type_name, {k: _zero(t, records) for k, t in records[type_name]})
    return {"NUM": f32(0), "DNUM": 0.0, "BOOL": False, "STRING": ""}.get(type_name, f32(0))


_ZEROS = {name: _zero(name, RECORDS) for name in [*RECORDS, *SCALARS]}


def zero(type_name: str, records: dict | None = None):
    """The value RAPID gives a declared variable without an initial value (records: the program's record types
    besides the built-in ones); shared: values are never changed in place."""
    found = _ZEROS.get(type_name)
    if found is not None:
        return found
    if isinstance(type_name, tuple):  # an array (element type, size)
        element, size = type_name
        return [zero(element, records) for _ in range(size or 0)]
    if records is not None and type_name in records:
        return _zero(type_name, records)
    return _ZEROS["NUM"]


def type_text(value) -> str:
    """A value's RAPID data type, for messages."""
    if isinstance(value, Record):
        return str(value.type).lower()
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, str):
        return "string"
    if isinstance(value, list):
        return "array"
    if isinstance(value, int | float | np.number):
        return "num"
    return "a value of no RAPID type"


def num(value, where: str) -> float:
    if type(value) is F32:  # the common case first
        return float(value)
    if isinstance(value, bool) or not isinstance(value, int | float | np.number):
        raise RunError(f"{where}: expected a num, got {type_text(value)}")
    return float(value)


def text(value, where: str, what: str = "a string") -> str:
    if not isinstance(value, str):
        raise RunError(f"{where}: expected {what}, got {type_text(value)}")
    return value


def rec(value, type_name: str, where: str) -> Record:
    """value as a record of type_name: the record itself, or an aggregate of its components (nums, records)."""
    if isinstance(value, list) and type_name in RECORDS and len(value) == len(RECORDS[type_name]):
        fields = RECORDS[type_name]
        out = {}
        for (key, kind), item in zip(fields, value, strict=True):
            out[key] = rec(item, kind, where) if kind in RECORDS else (f32(num(item, where)) if kind == "NUM" else item)
        return Record(type_name, out)
    if not isinstance(value, Record) or value.type != type_name:
        raise RunError(f"{where}: expected {type_name.lower()}, got {type_text(value)}")
    return value


QUAT_KEYS = ("Q1", "Q2", "Q3", "Q4")
_xyz = operator.itemgetter("X", "Y", "Z")  # a pos record's numbers
_quat = operator.itemgetter(*QUAT_KEYS)  # an orient record's numbers


def vec(record: Record, keys) -> list[float]:
    if keys == "XYZ":
        return list(map(float, _xyz(record)))
    if keys == QUAT_KEYS:
        return list(map(float, _quat(record)))
    return [float(record[k]) for k in keys]


def pos_record(xyz) -> Record:
    x, y, z = xyz
    return Record("POS", {"X": f32(x), "Y": f32(y), "Z": f32(z)})


def orient_record(quat) -> Record:
    return Record("ORIENT", dict(zip(QUAT_KEYS, (f32(v) for v in quat), strict=True)))


def pose_record(trans, quat) -> Record:
    return Record("POSE", {"TRANS": pos_record(trans), "ROT": orient_record(quat)})
