"""RAPID (ABB): printer, grammar and interpreter."""

from codegen.dialects import Dialect


class Rapid(Dialect):
    name = "rapid"
    suffixes = (".mod",)

    @classmethod
    def move_settings(cls, program: dict, kind: str, exact: bool, own_tool: bool = False) -> dict:
        """speeddata, zonedata and tooldata of MoveJ/MoveL as the facts name them; `fine` where the arm
        must stop at the pose (a zone there lets it cut the corner and never reach the pose). The cell's own
        tool is the program's tooldata (not predefined: "custom"), its TCP and load checked by verify."""
        zone = "FINE" if exact else program["zone"].upper()
        tool = "custom" if own_tool else program["tool"].upper()
        return {"speed": program["speed"].upper(), "zone": zone, "tool": tool}
