"""KRL data types (FRAME, POS, UNINIT...) and builtin functions (trig in degrees, INV_POS, SET_KRLMSG)."""

from __future__ import annotations

import math
import operator
import re

import numpy as np

from codegen.dialects import posemath
from codegen.dialects.core.machine import pause
from codegen.dialects.core.values import Record, RunError, f32, format_general


class _Uninit:
    """A KRL variable or component that was declared but never given a value."""

    _instance = None

    def __new__(cls):
        if cls._instance is None:
            cls._instance = super().__new__(cls)
        return cls._instance

    def __repr__(self) -> str:
        return "UNINIT"

    def copy(self):
        return self


UNINIT = _Uninit()

XYZABC = [("X", "REAL"), ("Y", "REAL"), ("Z", "REAL"), ("A", "REAL"), ("B", "REAL"), ("C", "REAL")]
xyzabc = operator.itemgetter("X", "Y", "Z", "A", "B", "C")  # a cartesian record's six numbers
STRUCTS = {
    "FRAME": XYZABC,
    "POS": [*XYZABC, ("S", "INT"), ("T", "INT")],
    "E6POS": [*XYZABC, ("S", "INT"), ("T", "INT")] + [(f"E{i}", "REAL") for i in range(1, 7)],
    "AXIS": [(f"A{i}", "REAL") for i in range(1, 7)],
    "E6AXIS": [(f"A{i}", "REAL") for i in range(1, 7)] + [(f"E{i}", "REAL") for i in range(1, 7)],
    "LOAD": [("M", "REAL"), ("CM", "FRAME"), ("J", "INERTIA")],  # kg, mm and deg, kg m^2 (KUKA payload data)
    "INERTIA": [("X", "REAL"), ("Y", "REAL"), ("Z", "REAL")],
    "KRLMSG_T": [("MODUL", "CHAR"), ("NR", "INT"), ("MSG_TXT", "CHAR")],
    "KRLMSGPAR_T": [
        ("PAR_TYPE", "ENUM"),
        ("PAR_TXT", "CHAR"),
        ("PAR_INT", "INT"),
        ("PAR_REAL", "REAL"),
        ("PAR_BOOL", "BOOL"),
    ],
    "KRLMSGDLGSK_T": [("SK_TYPE", "ENUM"), ("SK_TXT", "CHAR")],  # a dialog's softkey (codegen/dialects/krl/dialogs.py)
    "KRLMSGOPT_T": [("VL_STOP", "BOOL"), ("CLEAR_P_RESET", "BOOL"), ("CLEAR_P_SAW", "BOOL"), ("LOG_TO_DB", "BOOL")],
    # the path and approximation parameters of the advance run ($VEL, $ACC, $APO: KSS 8.1-8.4 System Variables)
    "VEL_STRUC": [("CP", "REAL"), ("ORI1", "REAL"), ("ORI2", "REAL")],  # m/s, deg/s, deg/s
    "ACC_STRUC": [("CP", "REAL"), ("ORI1", "REAL"), ("ORI2", "REAL")],  # m/s2, deg/s2, deg/s2
    "APO_STRUC": [("CVEL", "INT"), ("CPTP", "INT"), ("CDIS", "REAL"), ("CORI", "REAL")],  # %, %, mm, deg
    # the state CREAD / CWRITE return (KSS 8 CREAD/CWRITE manual, as recalled: RET1 a CMD_STAT value, the number
    # of values read, the length read); the channel functions themselves are refused by name (NOT_MODELLED)
    "STATE_T": [("RET1", "ENUM"), ("HITS", "INT"), ("LENGTH", "INT")],
    # what every KUKA.EthernetKRL function returns (codegen/dialects/krl/eki.py): elements left in the memory, read,
    # the message number (0: no error), connected, the time stamp of the element taken out
    "EKI_STATUS": [("BUFF", "INT"), ("READ", "INT"), ("MSG_NO", "INT"), ("CONNECTED", "BOOL"), ("COUNTER", "INT")],
}
# The system's enumeration types a program may declare data of (KSS 8 programming manual, as recalled)
SYSTEM_ENUMS = {"VAR_STATE": frozenset({"#DECLARED", "#INITIALIZED", "#UNKNOWN"})}
# Message types the operator must acknowledge (KSS 8 system integrators manual, Set_KrlMsg: #QUIT, and
# #WAITING until the program clears it); #NOTIFY and #STATE need none.
ACKNOWLEDGED = frozenset({"#QUIT"})
_MSG_PARAM = re.compile(r"%([123])")  # a KrlMsg_T text's placeholders for its 3 parameters
STRUCT_FIELDS = {name: dict(fields) for name, fields in STRUCTS.items()}
SIMPLE = {"INT", "REAL", "BOOL", "CHAR", "ENUM"}
CART = ("FRAME", "POS", "E6POS")


def new_value(type_name: str, structs: dict = STRUCTS):
    """A declared variable's value before it is given one: UNINIT, a record of UNINIT components (a
    component of a user-defined structure type that is itself a user structure: its record)."""
    fields = structs.get(type_name)
    if fields is None:
        return UNINIT
    return Record(
        type_name,
        {k: (new_value(t, structs) if t in structs and t not in STRUCTS else UNINIT) for k, t in fields},
    )


def shown(value) -> str:
    """A value as a message shows it: a number as KRL writes it, a text quoted, else its KRL type."""
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(value, int | float | np.number):
        return format_general(value)
    if isinstance(value, str):
        return value if value.startswith("#") else f'"{value}"'
    return type_name_of(value)


def type_name_of(value) -> str:
    """A value's KRL type as a message names it (never a Python type name)."""
    if isinstance(value, bool):
        return "BOOL"
    if isinstance(value, int | np.integer):
        return "INT"
    if isinstance(value, float | np.floating):
        return "REAL"
    if isinstance(value, str):
        return "an ENUM value" if value.startswith("#") else "CHAR"
    if isinstance(value, Record):
        return value.type or "an aggregate"
    if isinstance(value, list):
        return "an array"
    if value is UNINIT:
        return "no value"
    return "a value of no KRL type"


def frame(values=(0, 0, 0, 0, 0, 0)) -> Record:
    return Record("FRAME", {k: f32(v) for (k, _), v in zip(XYZABC, values, strict=True)})


def valid(value, where: str, what: str):
    if value is UNINIT:
        raise RunError(f"{where}: {what} has no value (KRL: variable value invalid)")
    return value


def cart(value, where: str) -> Record:
    if not isinstance(value, Record) or value.type not in CART:
        raise RunError(f"{where}: expected FRAME, POS or E6POS, got {type_name_of(value)}")
    v = value
    if (
        v["X"] is UNINIT
        or v["Y"] is UNINIT
        or v["Z"] is UNINIT
        or v["A"] is UNINIT
        or v["B"] is UNINIT
        or v["C"] is UNINIT
    ):
        for key, _ in XYZABC:
            valid(value[key], where, f"{value.type}.{key}")
    return value


def cart_matrix(value: Record) -> np.ndarray:
    return posemath.matrix_from_xyzabc(xyzabc(value))


def message_text(msg, params, where: str) -> str:
    """A KrlMsg_T's text as the operator sees it: %1 to %3 replaced by the KrlMsgPar_T parameters' values (#EMPTY
    or none: left as written); a parameter with other than one value is refused."""
    text = valid(msg["MSG_TXT"], where, "KrlMsg_T.Msg_txt")

    def param(match):
        i = int(match.group(1))
        par = params[i - 1] if isinstance(params, list) and i <= len(params) else None
        if par is None or par["PAR_TYPE"] in (UNINIT, "#EMPTY"):
            return match.group(0)
        values = [(k, par[k]) for k in ("PAR_TXT", "PAR_INT", "PAR_REAL", "PAR_BOOL") if par[k] is not UNINIT]
        if len(values) != 1:
            raise RunError(f"{where}: KrlMsgPar_T[{i}] needs exactly one value, has {len(values)}")
        return format_general(values[0][1]) if values[0][0] != "PAR_TXT" else values[0][1]

    return _MSG_PARAM.sub(param, text)


# KUKA's functions the interpreter does not model: a call is refused by name (not "unknown routine")
NOT_MODELLED = {
    name: what
    for what, names in {
        "string functions": "STRLEN STRCLEAR STRCOPY STRADD STRCOMP STRFIND STRDECLLEN SWRITE SREAD",
        "channel I/O": "CWRITE CREAD COPEN CCLOSE CIOCTL",
        "Ethernet KRL (the functions of codegen/dialects/krl/eki.py are)": "EKI_SETREAL EKI_SETSTRING EKI_GETSTRING "
        "EKI_SETBOOL EKI_CHECK EKI_LOCK EKI_UNLOCK",
        "error handling": "ERR_RAISE ERR_CLEAR",
        "kinematics functions": "INVERSE FORWARD",
        "KUKA's Automatic External module: the program number a PLC sends": "P00 P00_SUBM",
        "KUKA's technology packages": "H50 USER_GRP USERSPOT A20 A10",
        "messages of KSS 5": "MSG_SEND",
        "the message buffer": "GET_MSGBUFFER",
    }.items()
    for name in names.split()
}
# KUKA's types the interpreter does not model: a declaration is refused by name (not "unknown type"). MSGBUF_T, what
# Get_MsgBuffer fills with the pending messages: its components were not confirmed in a manual, and no message is
# ever pending here. GRP_TYP, SPOT_TYPE and S_COMMAND: the GripperTech and SpotTech packages' parameter types, as the
# data lists of the inline forms (H50, USERSPOT) declare them (the packages' manuals were not read: unconfirmed).
TYPES_NOT_MODELLED = {
    "MSGBUF_T": "the message buffer (Get_MsgBuffer)",
    **dict.fromkeys(
        ("GRP_TYP", "SPOT_TYPE", "S_COMMAND"), "a type of KUKA's technology packages (GripperTech, SpotTech)"
    ),
}


def trig(fn):
    def call(fr, args, kwargs, where):
        return f32(fn(math.radians(float(valid(args[0], where, "argument")))))

    return call


def arc(fn):
    def call(fr, args, kwargs, where):
        value = float(valid(args[0], where, "argument"))
        if not -1.0 <= value <= 1.0:
            raise RunError(f"{where}: ACOS / ASIN of {value:g}: the argument must be in -1..1")
        return f32(math.degrees(fn(value)))

    return call


def atan2(fr, args, kwargs, where):
    y, x = (float(valid(a, where, "argument")) for a in args)
    return f32(math.degrees(math.atan2(y, x)))


def sqrt(fr, args, kwargs, where):
    value = float(valid(args[0], where, "argument"))
    if value < 0:
        raise RunError(f"{where}: SQRT of a negative number")
    return f32(math.sqrt(value))


def abs_(fr, args, kwargs, where):
    value = valid(args[0], where, "argument")
    return abs(value)


def inv_pos(fr, args, kwargs, where):
    from codegen.poses import invert

    value = cart(args[0], where)
    out = value.copy()
    for (key, _), v in zip(XYZABC, posemath.xyzabc_from_matrix(invert(cart_matrix(value))), strict=True):
        out[key] = f32(v)
    return out


def set_krlmsg(fr, args, kwargs, where):
    kind, msg, params, opt = args
    if isinstance(opt, Record) and opt["VL_STOP"] is True:  # KrlMsgOpt_T.VL_Stop: an advance-run stop
        fr.m.arrive(where)
    fr.m.message(message_text(msg, params, where))
    state = fr.m.state
    handle = state.handle = state.handle + 1
    if str(kind).upper() in ACKNOWLEDGED:  # shown until the operator acknowledges it
        state.waiting = {**state.waiting, handle: fr.m.trace.messages[-1]}
    return handle


def exists_krlmsg(fr, args, kwargs, where):
    """Exists_KrlMsg(handle): TRUE while the message is shown. The interpreter's operator reads an
    acknowledgement message the first time the program looks for it and acknowledges it: the
    program stood stopped with that message until then (recorded as the run's stop)."""
    waiting = fr.m.state.waiting
    handle = int(valid(args[0], where, "message handle"))
    if handle in waiting:
        trace = fr.m.trace
        if not trace.halted:
            trace.halted, trace.halt_message = True, waiting[handle]
        fr.m.state.waiting = {k: v for k, v in waiting.items() if k != handle}
    return False


def msg(kind: str):
    """MsgNotify / MsgQuit (KSS 8.3's MsgLib, recalled: the text first, then the module and the number):
    a notification, or a message the operator acknowledges (the program stands until then: the run's stop)."""

    def call(fr, args, kwargs, where):
        text = valid(args[0], where, f"{kind} text")
        if not isinstance(text, str):
            raise RunError(f"{where}: {kind}: the text is a CHAR array")
        fr.m.message(text)
        if kind == "MsgQuit":
            fr.m.arrive(where)
            pause(fr)
        return None

    return call


def varstate(fr, args, kwargs, where):
    """VARSTATE(name): #UNKNOWN where no variable of that name is declared, #DECLARED where it has no value yet,
    #INITIALIZED where it has one (KSS 8 programming manual for system integrators, VARSTATE(), as recalled; a
    structure counts as initialized where its components all have values, assumed). The name is looked up in the
    routine's own variables, then in every module's data (the scope rules of a name given as text: assumed)."""
    if len(args) != 1 or not isinstance(args[0], str):
        raise RunError(f"{where}: VARSTATE takes the variable's name as a CHAR array")
    key = args[0].strip().upper()
    if key in fr.vars:
        value = fr.vars[key]
    else:
        stores = [k for k in fr.m.global_types if k == key or k.endswith(":" + key)]
        if not stores:
            return "#UNKNOWN"
        value = fr.m.globals.get(stores[0], UNINIT)
    return "#INITIALIZED" if _has_value(value) else "#DECLARED"


def _has_value(value) -> bool:
    if isinstance(value, Record):
        return all(_has_value(v) for v in value.values())
    if isinstance(value, list):
        return all(_has_value(v) for v in value)
    return value is not UNINIT


BUILTINS = {  # the KRL functions and procedures the interpreter provides, by upper-case name
    "ACOS": arc(math.acos),
    "ASIN": arc(math.asin),
    "MSGNOTIFY": msg("MsgNotify"),
    "MSGQUIT": msg("MsgQuit"),
    "SIN": trig(math.sin),
    "COS": trig(math.cos),
    "TAN": trig(math.tan),
    "ATAN2": atan2,
    "SQRT": sqrt,
    "ABS": abs_,
    "INV_POS": inv_pos,
    "SET_KRLMSG": set_krlmsg,
    "EXISTS_KRLMSG": exists_krlmsg,
    "VARSTATE": varstate,
}
