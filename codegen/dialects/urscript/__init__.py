"""URScript (Universal Robots): printer, grammar and interpreter."""

from codegen.dialects import Dialect


class URScript(Dialect):
    name = "urscript"
    suffixes = (".script",)

    @classmethod
    def move_settings(cls, program: dict, kind: str, exact: bool, own_tool: bool = False) -> dict:
        """The facts' "a=1.2, v=0.25" of movej/movel, and blend radius r = 0: the generated programs
        stop at every pose (a blend on a work pose would cut its corner)."""
        text = program["joint_move" if kind == "joint" else "linear_move"]
        settings = {key.strip(): float(value) for key, value in (part.split("=") for part in text.split(","))}
        return {**settings, "r": 0.0}
