"""URScript (Universal Robots): printer, grammar and interpreter.

A move's settings (MoveEvent.settings, what the verify engine compares): "a", "v", "r" (the manual's
acceleration, speed and blend radius, the manual's defaults where the program leaves them out; movej rad/s^2,
rad/s; movel, movep, movec m/s^2, m/s; r m), "t" (movej/movel's time, s; 0: none; speedl/speedj: how long the
speed was held), "load" (mass kg, centre of gravity x, y, z mm, the inertia tensor at it in flange axes
Ixx, Iyy, Izz, Ixy, Ixz, Iyz kg m2: codegen.world.loads.Load.flat, from set_target_payload / set_payload; None: not
set), "tcp" (the TCP set_tcp made active, p[x, y, z, rx, ry, rz] in m and rad; None: the installation's),
"move" (the function: movej, movel, movep, speedl, speedj, servoj), movec's "mode", speedl's "xd" and speedj's
"qd" (the commanded speeds). Every digital output set is a SignalEvent named standard_digital_out[n],
configurable_digital_out[n] or tool_digital_out[n]; textmsg and popup write trace.messages.
"""

from codegen.dialects import Dialect


class URScript(Dialect):
    name = "urscript"
    suffixes = (".script", ".urscript")  # .urscript: the suffix editors' URScript extensions give the same language

    @classmethod
    def predefined(cls) -> frozenset[str]:
        """The built-in functions the interpreter models (URScript manual)."""
        from codegen.dialects.urscript.interpreter import URScriptCompiler  # lark: only when asked

        return frozenset(URScriptCompiler("<names>").builtins)

    @classmethod
    def zone_mm(cls, settings: dict) -> float:
        """The blend radius r (m) in mm."""
        return 1000.0 * float(settings.get("r") or 0.0)

    @classmethod
    def circular(cls, kind: str, settings: dict) -> bool:
        return kind == "circular"

    @classmethod
    def move_settings(
        cls, program: dict, kind: str, exact: bool, own_tool=False, speed_mm_s=None, zone_mm=0.0, joint_percent=None
    ) -> dict:
        """movej: the facts' "a=1.4, v=1.05" (rad/s^2, rad/s); movel: the facts' acceleration and the
        cell's TCP speed v (m/s); blend radius r the cell's zone (m), 0 where the arm must stop (a blend
        on a work pose would cut its corner)."""
        text = program["joint_move" if kind == "joint" else "linear_move"]
        settings = {key.strip(): float(value) for key, value in (part.split("=") for part in text.split(","))}
        if kind != "joint" and speed_mm_s is not None:
            settings["v"] = speed_mm_s / 1000.0
        return {**settings, "r": 0.0 if exact else zone_mm / 1000.0}

    @classmethod
    def check(cls, text: str, filename: str) -> None:
        """As parse would raise (line ends inside brackets continue the line: the interpreter's postlex)."""
        from codegen.dialects.core.parsing import check_with_grammar

        interpreter = cls.module("interpreter")
        check_with_grammar(interpreter.__file__, text, filename, postlex=interpreter.BRACKETS)

    @classmethod
    def check_files(cls, files: list, options=None) -> list:
        """Syntax, unsupported built-ins and undefined names (all of them), a wait on an input without a
        timeout, motion before set_tcp, joint speeds over the arm's (codegen/dialects/urscript/check.py)."""
        from codegen.dialects.urscript.check import check_files

        return check_files(cls, files, options)
