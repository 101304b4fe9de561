"""RAPID (ABB): printer, grammar and interpreter."""

from codegen.dialects import Dialect


class Rapid(Dialect):
    name = "rapid"
    suffixes = (".mod",)

    @classmethod
    def move_settings(cls, program: dict, kind: str, exact: bool) -> dict:
        """speeddata, zonedata and tooldata of MoveJ/MoveL as the facts name them; `fine` where the arm
        must stop at the pose (a zone there lets it cut the corner and never reach the pose)."""
        zone = "FINE" if exact else program["zone"].upper()
        return {"speed": program["speed"].upper(), "zone": zone, "tool": program["tool"].upper()}
