"""RAPID (ABB): printer, grammar and interpreter; a program is the modules of one task.

MoveEvent.settings of a RAPID move: "speed", "zone", "tool" (a predefined datum's name in upper case, e.g. "V100",
"FINE", "TOOL0", else "custom"), "load" (codegen.world.loads.Load.flat at the flange: mass kg, cog x, y, z mm, the
tensor at the cog kg m2; the move's tooldata's, with the payload of a GripLoad in force; None for tool0),
"tcp_mm_s" (the programmed TCP speed), "zone_mm" (the zone's pzone_tcp, 0 at a stop point), "circle_point"
(MoveC); and from the instruction on, on every later move (codegen/dialects/rapid/motionset.py): "accset" {"acc",
"ramp", "line"}, "velset" {"override", "max", "line"}, "singarea" {"mode", "line"}, "confj" / "confl" {"on",
"line"}, "gripload" {"mass", "cog", "aom", "moments", "line"}; Trace.motion_settings (an attribute set once the
program ran one of these instructions): those settings as in force when the run ended. Trace.simulated_io (an
attribute set on the trace of a program that uses signals it does not declare): signal name -> "digital input",
"digital output", ... (simulated I/O).
"""

from __future__ import annotations

import re
from pathlib import Path

from codegen.dialects import Dialect

# Where a controller backup keeps a task's modules: RAPID/<task>/PROGMOD/*.mod and RAPID/<task>/SYSMOD/*.sys
# (ABB, "Operating manual - IRC5 with FlexPendant", backup; as recalled).
TASK_SUBFOLDERS = {"PROGMOD", "SYSMOD"}


class Rapid(Dialect):
    name = "rapid"
    suffixes = (".mod", ".sys", ".modx")  # .modx: RobotWare 7 module (same syntax); .prg (RobotWare 5): dtrans
    encodings = ("cp1252",)  # RobotWare's text files: Windows-1252 (Latin-1) where not UTF-8
    entry_routines = "PP to Routine"  # a global PROC without parameters (the task then needs no main)

    @classmethod
    def predefined(cls) -> frozenset[str]:
        """The instructions and functions (modelled or by the manual's name), the predefined data (v100, z10, fine,
        tool0, wobj0, load0...), the predefined constants and the data types, in upper case."""
        from codegen.dialects.rapid import catalogue, names, predefined, types
        from codegen.dialects.rapid.compiler import SPECIAL, RAPIDCompiler  # lark: only when asked

        return frozenset(
            name.upper()
            for name in (
                *RAPIDCompiler("<names>").builtins,
                *SPECIAL,
                *catalogue.NOT_MODELLED,
                *predefined.PREDEFINED,
                *predefined.USER_DATA,
                *names.CONSTANTS,
                *types.RECORDS,
                *types.SCALARS,
                *types.ALIASES,
                *types.OPAQUE,
                *types.NOT_MODELLED,
            )
        )

    @classmethod
    def zone_mm(cls, settings: dict) -> float:
        """The zonedata's pzone_tcp (mm), 0 at a stop point."""
        return float(settings.get("zone_mm") or 0.0)

    @classmethod
    def circular(cls, kind: str, settings: dict) -> bool:
        return "circle_point" in settings

    @classmethod
    def move_settings(
        cls, program: dict, kind: str, exact: bool, own_tool=False, speed_mm_s=None, zone_mm=0.0, joint_percent=None
    ) -> dict:
        """speeddata, zonedata and tooldata of MoveJ/MoveL as the facts name them; `fine` where the arm
        must stop at the pose (a zone there lets it cut the corner and never reach the pose). The cell's own
        tool is the program's tooldata (not predefined: "custom"), its TCP and load checked by verify."""
        tool = "custom" if own_tool else program["tool"].upper()
        if speed_mm_s is None:
            zone = "FINE" if exact else program["zone"].upper()
            return {"speed": program["speed"].upper(), "zone": zone, "tool": tool}
        # the cell's speeds and zone ([cell.motion]) as the program's own speeddata and zonedata
        blend = zone_mm > 0 and not exact
        return {"tcp_mm_s": speed_mm_s, "zone_mm": zone_mm if blend else 0.0, "tool": tool}

    @classmethod
    def load(cls, text: str, filename: str, companions: dict[str, str] | None = None):
        return cls.module("interpreter").load(text, filename)

    @classmethod
    def programs(cls, files: list) -> list[list]:
        """The modules given together are one task's program (all .mod and .sys files of a folder, or files named
        together), the file with PROC main first; files from several tasks of a controller backup (RAPID/<task>/
        PROGMOD and SYSMOD) make one program per task. A task whose files define main twice is refused (RunError)."""
        from codegen.dialects.core.values import RunError

        groups: dict[str, list] = {}
        for f in files:
            groups.setdefault(_task_of(f.name), []).append(f)
        if len(groups) > 1 and not all(_in_backup(f.name) for f in files):
            groups = {"": list(files)}
        out = []
        for group in groups.values():
            mains = [f for f in group if _has_main(f.text)]
            if len(mains) > 1:
                both = f"{mains[0].name} and {mains[1].name}"
                raise RunError(f"{both} both define PROC main: give the modules of one task")
            out.append(mains + [f for f in group if f not in mains])
        return out

    @classmethod
    def load_files(cls, files: list, entry: str | None = None):
        """One program from a task's modules (SourceFile, as programs() groups them); entry: a global routine
        without parameters the run starts at instead of main (as after PP to Routine; the task needs no main)."""
        from codegen.dialects.rapid.task import load_task

        return load_task(list(files), entry=entry)

    @classmethod
    def check_files(cls, files: list, max_tcp_mm_s: float | None = None, options=None) -> list:
        """Every finding of `codegen check` in a task's files: syntax errors, refusals, undefined names and routines,
        type errors, and the field checks (a wait on an input without \\MaxTime, a move with a tool or work object
        without a value or with tool0 where the program has its own tool, names over 32 characters, speeds over
        max_tcp_mm_s where given); options.entry: the task starts at that routine (PP to Routine), not at main."""
        from codegen.dialects.rapid.check import check_task

        return check_task(list(files), max_tcp_mm_s, getattr(options, "entry", None))


def _task_of(name: str) -> str:
    parent = Path(name).parent
    if parent.name.upper() in TASK_SUBFOLDERS:
        parent = parent.parent
    return str(parent)


def _in_backup(name: str) -> bool:
    return Path(name).parent.name.upper() in TASK_SUBFOLDERS


def _has_main(text: str) -> bool:
    return re.search(r"^\s*PROC\s+main\s*\(", text, re.IGNORECASE | re.MULTILINE) is not None
