"""RAPID (ABB): printer, grammar and interpreter."""

from codegen.dialects import Dialect


class Rapid(Dialect):
    name = "rapid"
    suffixes = (".mod",)

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
