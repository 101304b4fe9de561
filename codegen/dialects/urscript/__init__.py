"""URScript (Universal Robots): printer, grammar and interpreter."""

from codegen.dialects import Dialect


class URScript(Dialect):
    name = "urscript"
    suffixes = (".script",)

    @classmethod
    def predefined(cls) -> frozenset[str]:
        """The built-in functions the interpreter models (URScript manual)."""
        from codegen.dialects.urscript.interpreter import URScriptCompiler  # lark: only when asked

        return frozenset(URScriptCompiler("<names>").builtins)

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
