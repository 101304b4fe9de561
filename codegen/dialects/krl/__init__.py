"""KRL (KUKA Robot Language, KSS 8): printer, grammar and interpreter."""

import re

from codegen.dialects import Dialect


class KRL(Dialect):
    """The interpreter models the language of the KSS 8 programming manual for system integrators (modules of a
    .src and a .dat, GLOBAL routines and PUBLIC data of other modules, EXT, ENUM/STRUC, arrays of up to three
    dimensions, GOTO, TRIGGER WHEN DISTANCE/PATH, PTP/LIN/CIRC and SPTP/SLIN/SCIRC with WITH, the inline forms'
    PDAT/LDAT/FDAT and their BAS calls), the controller's environment (a built-in $config.dat, BAS, the system
    variables of codegen/dialects/krl/sysvars.py, $IN/$OUT and SIGNAL names as simulated I/O) and refuses by
    name, with file:line, what it does not model. Texts are UTF-8 or Windows-1252 (the controller's backups).

    MoveEvent.settings of a KRL motion (codegen/dialects/krl/motion.py path_settings): "approx" (C_PTP, C_DIS,
    C_VEL, C_ORI, C_SPL or None), "load" ($LOAD as codegen.world.loads.Load.flat: mass, x, y, z, the tensor at the
    centre of gravity; or None), "cdis" ($APO.CDIS mm, with C_DIS),
    "ov_pro" ($OV_PRO %, None until the program sets it); a LIN or CIRC: "vel_cp" ($VEL.CP m/s), "acc_cp" ($ACC.CP
    m/s2); a PTP: "vel_ptp" and "acc_ptp" ($VEL_AXIS[1] / $ACC_AXIS[1] %: BAS(#VEL_PTP ...), BAS(#INITMOV)); a
    CIRC also "circ": True. Outputs: every $OUT[n] set (also by a SIGNAL name, PULSE or a TRIGGER) is a SignalEvent
    named $OUT[n]; messages (Set_KrlMsg, MsgNotify) are trace.messages.

    Assumed where the controller's state is not the program's (each marked where it is modelled): the tool and base
    active at the start are neither the flange nor the world; TOOL_DATA / BASE_DATA / LOAD_DATA are unknown unless
    given (--input, a $config.dat); $OV_PRO is 100 and $MODE_OP #AUT until the program sets them; timers stand at 0.
    """

    name = "krl"
    # the move settings (the keys above) by the names the controller gives them, for the messages a user reads
    # (KSS 8.1-8.3 System Variables, KUKA expert documentation: $VEL, $ACC, $APO, $OV_PRO, $VEL_AXIS, $ACC_AXIS,
    # $LOAD); a BAS(#VEL_PTP) sets all six $VEL_AXIS alike, the first stands for them
    setting_names = {
        "vel_cp": "$VEL.CP",
        "acc_cp": "$ACC.CP",
        "cdis": "$APO.CDIS",
        "ov_pro": "$OV_PRO",
        "vel_ptp": "$VEL_AXIS[1]",
        "acc_ptp": "$ACC_AXIS[1]",
        "load": "$LOAD",
    }
    # a .sub: a module of the submit interpreter (SPS.SUB), a .src's syntax with its .dat, run beside the robot
    # program (KSS 8 programming manual for system integrators, "Submit interpreter"; from secondary sources, not
    # confirmed in the manual's text)
    suffixes = (".src", ".sub")
    companions = (".dat",)  # the data list of a .src: declarations and initial values
    configurations = (".xml",)  # a KUKA.EthernetKRL channel's configuration (codegen/dialects/krl/eki.py)
    encodings = ("cp1252",)  # KUKA controllers write Windows-1252 (backups, WorkVisual projects)

    @classmethod
    def predefined(cls) -> frozenset[str]:
        """The built-in functions, the data types, the numbered system arrays (TOOL_DATA...) and every name of the
        built-in $config.dat (its types, enumerations and data); $ names cannot be a generated name."""
        from codegen.dialects.krl import builtins, environment, motion
        from codegen.dialects.krl.compiler import KRLCompiler  # lark: only when asked

        config = re.sub(r";[^\n]*", " ", environment.CONFIG_DAT)
        return frozenset(
            name.upper()
            for name in (
                *KRLCompiler("<names>").builtins,
                *builtins.STRUCTS,
                *builtins.SIMPLE,
                *builtins.CART,
                *motion.SYSTEM_ARRAYS,
                *re.findall(r"[A-Za-z_][A-Za-z0-9_]*", config),
            )
        )

    @classmethod
    def check(cls, text: str, filename: str) -> None:
        """A program or data file by the grammar; a channel's configuration as the option reads it."""
        if filename.lower().endswith(cls.configurations):
            return cls.module("eki").check_config(text, filename)
        return super().check(text, filename)

    @classmethod
    def move_settings(
        cls, program: dict, kind: str, exact: bool, own_tool=False, speed_mm_s=None, zone_mm=0.0, joint_percent=None
    ) -> dict:
        """LIN at the cell's path speed $VEL.CP (m/s); approximation C_DIS with $APO.CDIS = the cell's
        zone (mm) where the arm passes a pose, none where it must stop; a PTP stops (no C_PTP)."""
        blend = zone_mm > 0 and not exact
        out = {"approx": "C_DIS" if blend else None, "cdis": zone_mm if blend else None}
        if kind != "joint" and speed_mm_s is not None:
            out["vel_cp"] = speed_mm_s / 1000.0
        if kind == "joint" and joint_percent is not None:
            out["vel_ptp"] = joint_percent  # BAS(#VEL_PTP, n)
        return out

    @classmethod
    def zone_mm(cls, settings: dict) -> float:
        """C_DIS: $APO.CDIS (mm); the other approximations (C_PTP, C_VEL, C_ORI) give no radius in mm: 0."""
        return float(settings.get("cdis") or 0.0) if settings.get("approx") == "C_DIS" else 0.0

    @classmethod
    def circular(cls, kind: str, settings: dict) -> bool:
        return bool(settings.get("circ"))

    @classmethod
    def load(cls, text: str, filename: str, companions: dict[str, str] | None = None):
        return cls.module("interpreter").load(text, filename, (companions or {}).get(".dat"))

    @classmethod
    def programs(cls, files: list) -> list[list]:
        """Each .src none of whose routines another given module calls is a program: with its .dat, the other
        modules (their GLOBAL routines and PUBLIC data) and a $config.dat given (KRL's scope rules)."""
        return cls.module("modules").programs(files)

    @classmethod
    def beside(cls, path) -> list:
        """Its .dat, the data lists of the folder without a .src of their own that declare a name the program
        uses (a PUBLIC data list of global counters beside it) and the Ethernet KRL configuration of its name
        (codegen/dialects/krl/eki.py)."""
        suffix = cls.configurations[0]
        channels = [c for c in (path.with_suffix(suffix), path.with_suffix(suffix.upper())) if c.is_file()][:1]
        return [*super().beside(path), *cls.module("modules").data_lists_beside(path, cls.encodings), *channels]

    @classmethod
    def shared_among(cls, program, files: list) -> list:
        """The data lists among `files` (another program's of one folder) that the program uses: a PUBLIC data list
        of global counters without a .src of its own (codegen/dialects/krl/modules.py data_lists_used)."""
        return cls.module("modules").data_lists_used(program, files)

    @classmethod
    def load_files(cls, files: list):
        return cls.module("modules").load_files(files)

    @classmethod
    def check_files(cls, files: list) -> list:
        """The KRL files' findings (codegen/dialects/krl/check.py), an EKI_Init of a channel whose configuration is
        not among them included; a channel's configuration as the option reads it (one finding where it cannot)."""
        from codegen.dialects.core.files import finding_of
        from codegen.dialects.core.values import RunError

        configurations = [f for f in files if f.suffix in cls.configurations]
        findings = []
        for f in configurations:
            try:
                cls.check(f.text, f.name)
            except RunError as exc:
                findings.append(finding_of(exc, [f]))
        krl = [f for f in files if f.suffix not in cls.configurations]
        channels = frozenset(f.stem.upper() for f in configurations)
        return [*cls.module("check").check_files(krl, channels), *findings] if krl else findings
