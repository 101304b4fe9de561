"""KUKA's BAS (the inline forms' motion parameters) and the spline inline forms' functions (SVEL_CP, STOOL2...)."""

from __future__ import annotations

from codegen.dialects.core.values import F32, Record, RunError, f32
from codegen.dialects.krl.builtins import UNINIT, frame, type_name_of, valid
from codegen.dialects.krl.numbered import SYSTEM_ARRAYS, fresh_values, fresh_warning
from codegen.dialects.krl.sysvars import read, set_tool, write

# What BAS(command, value) sets, as KUKA's BAS.SRC of KSS 8 does (R1/System/BAS.SRC: the routines INITMOV,
# VEL_PTP, ACC_PTP, VEL_CP, ACC_CP, TOOL, BASE, FRAMES, PTP_DAT, CP_DAT; the defaults are $config.dat's
# DEF_... values, read from the program's $config.dat: the built-in one or one given among its files):
# - #INITMOV: PTP acceleration and speed 100 % of DEF_ACC_PTP / DEF_VEL_PTP ($ACC_AXIS, $VEL_AXIS), path
#   acceleration DEF_ACC_CP, orientation speeds and accelerations, path speed DEF_VEL_CP ($VEL, $ACC),
#   approximation DEF_APO_CPTP / CDIS / CVEL / CORI ($APO), $ADVANCE = DEF_ADVANCE, $ORI_TYPE = #VAR,
#   $CIRC_TYPE = DEF_CIRC_TYP, and for a robot ($KINCLASS not #NONE) $BASE = $WORLD and $TOOL = TOOL_DATA[1]
#   (here only where TOOL_DATA[1] has a value: given by --input TOOL_DATA[1]=... or a $config.dat; else the
#   tool active when the program started stays, as the interpreter does not know TOOL_DATA[1]). The call also
#   stops the advance run (it ends the previous program's approximation).
# - #VEL_PTP p / #ACC_PTP p: $VEL_AXIS / $ACC_AXIS = p % of DEF_VEL_PTP / DEF_ACC_PTP (DEF_ at p > 100).
# - #VEL_CP v: $VEL.CP = v m/s (DEF_VEL_CP above it); #ACC_CP p: $ACC = p % of the DEF_ACC_ values.
# - #TOOL n: $TOOL = TOOL_DATA[n] ($NULLFRAME for n <= 0), $ACT_TOOL = n; #BASE n: $BASE = BASE_DATA[n]
#   ($WORLD for n <= 0), $ACT_BASE = n. (Tool and base corrections, TOOL_CORR_ON..., are not modelled.)
# - #PTP_PARAMS v: PDAT_ACT's acceleration and approximation (APO_MODE #CDIS: $APO.CDIS = APO_DIST, else
#   $APO.CPTP = APO_DIST up to 100), FDAT_ACT's tool and base (as #TOOL and #BASE), then #VEL_PTP v.
# - #CP_PARAMS v: LDAT_ACT's acceleration, $APO.CDIS = APO_DIST, $ORI_TYPE = ORI_TYP, FDAT_ACT's tool and
#   base, then #VEL_CP v. #PTP_DAT / #CP_DAT: the PDAT_ACT / LDAT_ACT part with its own VEL; #FRAMES: FDAT_ACT's.
# Not modelled (refused by name): #EX_BASE, #GROUP, #OUT_SYNC, #OUT_ASYNC, #ACC_GLUE; an IPO_FRAME #TCP
# (an external TCP).
REFUSED = {"#EX_BASE", "#GROUP", "#OUT_SYNC", "#OUT_ASYNC", "#ACC_GLUE"}
AXES = 6


def config(fr, name: str):
    """A DEF_ value of the program's $config.dat (a global: the built-in one declares every one BAS reads)."""
    value = fr.m.globals.get(name, UNINIT)
    if value is UNINIT:
        raise RunError(f"BAS: $config.dat's {name} has no value")
    return value


def _number(value, where: str, what: str) -> float:
    value = valid(value, where, what)
    if isinstance(value, bool) or not isinstance(value, int | float | F32):
        raise RunError(f"{where}: {what} must be a number, got {type_name_of(value)}")
    return float(value)


def _record(fr, name: str) -> Record:
    return read(fr, name, "", fr.m.program.compiler.structs).shallow()


def _set_fields(fr, name: str, where: str, **fields) -> None:
    record = _record(fr, name)
    for key, value in fields.items():
        record[key] = value if isinstance(value, int) else f32(value)
    write(fr, name, record, where)


def vel_ptp(fr, percent: float, where: str) -> None:
    if percent <= 0:
        raise RunError(f"{where}: BAS(#VEL_PTP, {percent:g}): a PTP at 0 % does not move")
    value = config(fr, "DEF_VEL_PTP") * (min(percent, 100.0) / 100.0)
    write(fr, "$VEL_AXIS", [round(value)] * AXES, where)
    fr.m.state.sysvars["VEL_PTP"] = float(value)


def acc_ptp(fr, percent: float, where: str) -> None:
    value = config(fr, "DEF_ACC_PTP") * (min(percent, 100.0) / 100.0)
    write(fr, "$ACC_AXIS", [round(value)] * AXES, where)


def vel_cp(fr, speed: float, where: str) -> None:
    if speed <= 0:
        raise RunError(f"{where}: BAS(#VEL_CP, {speed:g}): a path speed must be positive (m/s)")
    top = float(config(fr, "DEF_VEL_CP"))
    _set_fields(fr, "$VEL", where, CP=min(speed, top))


def acc_cp(fr, percent: float, where: str) -> None:
    factor = 1.0 if percent > 100.0 else percent / 100.0
    _set_fields(
        fr,
        "$ACC",
        where,
        CP=float(config(fr, "DEF_ACC_CP")) * factor,
        ORI1=float(config(fr, "DEF_ACC_ORI1")) * factor,
        ORI2=float(config(fr, "DEF_ACC_ORI2")) * factor,
    )


def numbered(fr, array: str, n: int, where: str) -> Record:
    """TOOL_DATA[n] / BASE_DATA[n] (the controller's $config.dat: --input or a given $config.dat)."""
    size = SYSTEM_ARRAYS[array][1]
    if not 1 <= n <= size:
        raise RunError(f"{where}: {array}[{n}]: the number must be 1..{size}")
    value = fresh_values(fr.m, array)[n - 1]
    fresh_warning(fr.m, value)
    return value


def tool(fr, n: int, where: str) -> None:
    set_tool(fr, frame() if n <= 0 else numbered(fr, "TOOL_DATA", n, where), where)
    write(fr, "$ACT_TOOL", n, where)


def base(fr, n: int, where: str) -> None:
    fr.m.state.sysvars["$BASE"] = frame() if n <= 0 else numbered(fr, "BASE_DATA", n, where)
    write(fr, "$ACT_BASE", n, where)


def _act(fr, name: str, where: str) -> Record:
    value = fr.m.globals.get(name, UNINIT)
    if not isinstance(value, Record):
        raise RunError(f"{where}: BAS: {name} has no value (the inline form sets it before the call)")
    return value


def frames(fr, where: str) -> None:
    fdat = _act(fr, "FDAT_ACT", where)
    if str(fdat.get("IPO_FRAME", "#BASE")).upper() == "#TCP":
        raise RunError(f"{where}: BAS: FDAT_ACT.IPO_FRAME #TCP (an external TCP) is not modelled")
    tool(fr, int(_number(fdat["TOOL_NO"], where, "FDAT_ACT.TOOL_NO")), where)
    base(fr, int(_number(fdat["BASE_NO"], where, "FDAT_ACT.BASE_NO")), where)


def ptp_dat(fr, where: str) -> None:
    pdat = _act(fr, "PDAT_ACT", where)
    acc_ptp(fr, _number(pdat["ACC"], where, "PDAT_ACT.ACC"), where)
    distance = _number(pdat["APO_DIST"], where, "PDAT_ACT.APO_DIST")
    mode = pdat.get("APO_MODE", UNINIT)
    if isinstance(mode, str) and mode.upper() == "#CDIS":
        _set_fields(fr, "$APO", where, CDIS=distance)
    else:
        _set_fields(fr, "$APO", where, CPTP=int(min(distance, 100.0)))


def cp_dat(fr, where: str) -> None:
    ldat = _act(fr, "LDAT_ACT", where)
    acc_cp(fr, _number(ldat["ACC"], where, "LDAT_ACT.ACC"), where)
    _set_fields(fr, "$APO", where, CDIS=_number(ldat["APO_DIST"], where, "LDAT_ACT.APO_DIST"))
    ori = ldat.get("ORI_TYP", UNINIT)
    fr.m.state.sysvars["$ORI_TYPE"] = ori.upper() if isinstance(ori, str) else "#VAR"


INITMOV_DEFAULTS = (
    "DEF_VEL_PTP",
    "DEF_ACC_PTP",
    "DEF_VEL_CP",
    "DEF_VEL_ORI1",
    "DEF_VEL_ORI2",
    "DEF_ACC_CP",
    "DEF_ACC_ORI1",
    "DEF_ACC_ORI2",
    "DEF_APO_CPTP",
    "DEF_APO_CDIS",
    "DEF_APO_CVEL",
    "DEF_APO_CORI",
    "DEF_ADVANCE",
    "DEF_CIRC_TYP",
)


def initmov(fr, where: str) -> None:
    """BAS(#INITMOV): what it sets is worked out once per program and its $config.dat values (the same run after
    run: the verify engine's thousands of cases), then stored in one step."""
    m = fr.m
    m.arrive(where)
    values = tuple(map(m.globals.get, INITMOV_DEFAULTS))
    cache = m.program.compiler.__dict__.setdefault("initmov_cache", {})
    updates = cache.get(values)
    if updates is None:
        saved, m.state.sysvars = m.state.sysvars, {}
        try:
            _initmov(fr, where)
            updates = cache[values] = m.state.sysvars
        finally:
            m.state.sysvars = saved
    m.state.sysvars.update(updates)
    tools = m.state.sysvars.get("TOOL_DATA")
    if tools is not None and tools[0]["X"] is not UNINIT:
        set_tool(fr, tools[0], where)
        write(fr, "$ACT_TOOL", 1, where)


def _initmov(fr, where: str) -> None:
    m = fr.m
    acc_ptp(fr, 100.0, where)
    vel_ptp(fr, 100.0, where)
    acc_cp(fr, 100.0, where)
    _set_fields(
        fr,
        "$VEL",
        where,
        CP=float(config(fr, "DEF_VEL_CP")),
        ORI1=float(config(fr, "DEF_VEL_ORI1")),
        ORI2=float(config(fr, "DEF_VEL_ORI2")),
    )
    _set_fields(
        fr,
        "$APO",
        where,
        CPTP=int(config(fr, "DEF_APO_CPTP")),
        CDIS=float(config(fr, "DEF_APO_CDIS")),
        CVEL=int(config(fr, "DEF_APO_CVEL")),
        CORI=float(config(fr, "DEF_APO_CORI")),
    )
    write(fr, "$ADVANCE", int(config(fr, "DEF_ADVANCE")), where)
    m.state.sysvars["$ORI_TYPE"] = "#VAR"
    m.state.sysvars["$CIRC_TYPE"] = str(config(fr, "DEF_CIRC_TYP")).upper()
    m.state.sysvars["$BASE"] = frame()  # BASE(0): $WORLD
    write(fr, "$ACT_BASE", 0, where)


def bas(fr, args, kwargs, where):
    """BAS(command, value): see the table above."""
    command = str(valid(args[0], where, "BAS command")).upper()
    value = _number(args[1], where, f"BAS({command}) value") if len(args) > 1 and args[1] is not None else 0.0
    if command == "#INITMOV":
        initmov(fr, where)
    elif command == "#VEL_PTP":
        vel_ptp(fr, value, where)
    elif command == "#ACC_PTP":
        acc_ptp(fr, value, where)
    elif command == "#VEL_CP":
        vel_cp(fr, value, where)
    elif command == "#ACC_CP":
        acc_cp(fr, value, where)
    elif command == "#TOOL":
        tool(fr, int(value), where)
    elif command == "#BASE":
        base(fr, int(value), where)
    elif command == "#FRAMES":
        frames(fr, where)
    elif command == "#PTP_DAT":
        vel_ptp(fr, _number(_act(fr, "PDAT_ACT", where)["VEL"], where, "PDAT_ACT.VEL"), where)
        ptp_dat(fr, where)
    elif command == "#CP_DAT":
        vel_cp(fr, _number(_act(fr, "LDAT_ACT", where)["VEL"], where, "LDAT_ACT.VEL"), where)
        cp_dat(fr, where)
    elif command == "#PTP_PARAMS":
        ptp_dat(fr, where)
        frames(fr, where)
        vel_ptp(fr, value, where)
    elif command == "#CP_PARAMS":
        cp_dat(fr, where)
        frames(fr, where)
        vel_cp(fr, value, where)
    elif command in REFUSED:
        raise RunError(f"{where}: BAS({command}) is not modelled by this interpreter")
    else:
        raise RunError(f"{where}: BAS: unknown command {command}")
    return None


# --- the spline inline forms' functions (KSS 8.3: SPTP / SLIN ... WITH $VEL = SVEL_CP(...), ...) ------------
# KUKA's functions behind the spline inline forms, as their names and the inline forms' parameters say
# (recalled, not confirmed from the manual: the values below are the parameters' plain meaning; what they add,
# e.g. jerk limits, is not modelled because the trace has no dynamics).


def _arg(args, i: int, where: str, what: str):
    if len(args) <= i or args[i] is None:
        raise RunError(f"{where}: {what}: argument {i + 1} missing")
    return args[i]


def svel_joint(fr, args, kwargs, where):
    """SVEL_JOINT(percent): the axes' speed of an SPTP, % (stored in $VEL_AXIS[1], the inline form's way)."""
    percent = _number(_arg(args, 0, where, "SVEL_JOINT"), where, "SVEL_JOINT percent")
    return round(config(fr, "DEF_VEL_PTP") * min(percent, 100.0) / 100.0)


def sacc_joint(fr, args, kwargs, where):
    """SACC_JOINT(pdat): the axes' acceleration %, PDAT.ACC."""
    return round(_number(_arg(args, 0, where, "SACC_JOINT")["ACC"], where, "PDAT.ACC"))


def stool2(fr, args, kwargs, where):
    """STOOL2(fdat): TOOL_DATA[fdat.TOOL_NO] ($NULLFRAME for 0)."""
    n = int(_number(_arg(args, 0, where, "STOOL2")["TOOL_NO"], where, "FDAT.TOOL_NO"))
    return frame() if n <= 0 else numbered(fr, "TOOL_DATA", n, where)


def sbase(fr, args, kwargs, where):
    """SBASE(n): BASE_DATA[n] ($WORLD for 0)."""
    n = int(_number(_arg(args, 0, where, "SBASE"), where, "SBASE number"))
    return frame() if n <= 0 else numbered(fr, "BASE_DATA", n, where)


def sipo_mode(fr, args, kwargs, where):
    return _arg(args, 0, where, "SIPO_MODE")


def sload(fr, args, kwargs, where):
    """SLOAD(n): LOAD_DATA[n] (the load of tool n)."""
    n = int(_number(_arg(args, 0, where, "SLOAD"), where, "SLOAD number"))
    size = SYSTEM_ARRAYS["LOAD_DATA"][1]
    if not 1 <= n <= size:
        raise RunError(f"{where}: SLOAD({n}): the number must be 1..{size}")
    value = fresh_values(fr.m, "LOAD_DATA")[n - 1]
    fresh_warning(fr.m, value)
    return value


def sapo_ptp(fr, args, kwargs, where):
    """SAPO_PTP(pdat): $APO with CPTP (or CDIS by APO_MODE) = PDAT.APO_DIST."""
    pdat = _arg(args, 0, where, "SAPO_PTP")
    record = _record(fr, "$APO")
    distance = _number(pdat["APO_DIST"], where, "PDAT.APO_DIST")
    mode = pdat.get("APO_MODE", UNINIT)
    if isinstance(mode, str) and mode.upper() == "#CDIS":
        record["CDIS"] = f32(distance)
    else:
        record["CPTP"] = int(min(distance, 100.0))
    return record


def sapo(fr, args, kwargs, where):
    """SAPO(ldat): $APO with CDIS = LDAT.APO_DIST."""
    record = _record(fr, "$APO")
    record["CDIS"] = f32(_number(_arg(args, 0, where, "SAPO")["APO_DIST"], where, "LDAT.APO_DIST"))
    return record


def svel_cp(fr, args, kwargs, where):
    """SVEL_CP(v, [name], ldat): $VEL with CP = v m/s (up to DEF_VEL_CP)."""
    record = _record(fr, "$VEL")
    speed = _number(_arg(args, 0, where, "SVEL_CP"), where, "SVEL_CP speed")
    if speed <= 0:
        raise RunError(f"{where}: SVEL_CP({speed:g}): a path speed must be positive (m/s)")
    record["CP"] = f32(min(speed, float(config(fr, "DEF_VEL_CP"))))
    return record


def sacc_cp(fr, args, kwargs, where):
    """SACC_CP(ldat): the path acceleration, LDAT.ACC % of DEF_ACC_CP."""
    percent = _number(_arg(args, 0, where, "SACC_CP")["ACC"], where, "LDAT.ACC")
    return f32(float(config(fr, "DEF_ACC_CP")) * min(percent, 100.0) / 100.0)


def sori_typ(fr, args, kwargs, where):
    value = _arg(args, 0, where, "SORI_TYP")["ORI_TYP"]
    return value if value is not UNINIT else "#VAR"


def recorded_only(name: str):
    """A function whose value only sets what the trace does not show (jerk, collision detection)."""

    def call(fr, args, kwargs, where):
        return 0

    call.__doc__ = f"{name}: recorded only (no dynamics in the trace)"
    return call


FUNCTIONS = {  # the procedures of KUKA's BAS.SRC the interpreter provides, by upper-case name
    "BAS": bas,
    "SVEL_JOINT": svel_joint,
    "SACC_JOINT": sacc_joint,
    "STOOL2": stool2,
    "SBASE": sbase,
    "SIPO_MODE": sipo_mode,
    "SLOAD": sload,
    "SAPO_PTP": sapo_ptp,
    "SAPO": sapo,
    "SVEL_CP": svel_cp,
    "SACC_CP": sacc_cp,
    "SORI_TYP": sori_typ,
    "SGEAR_JERK": recorded_only("SGEAR_JERK"),
    "SJERK": recorded_only("SJERK"),
    "USE_CM_PRO_VALUES": recorded_only("USE_CM_PRO_VALUES"),
    "SET_CD_PARAMS": recorded_only("SET_CD_PARAMS"),  # the inline forms' collision detection: none here
}
