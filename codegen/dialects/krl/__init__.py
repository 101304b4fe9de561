"""KRL (KUKA Robot Language, KSS 8): printer, grammar and interpreter."""

from codegen.dialects import Dialect


class KRL(Dialect):
    name = "krl"
    suffixes = (".src",)
    companions = (".dat",)  # the data list of a .src: declarations and initial values

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
    def load(cls, text: str, filename: str, companions: dict[str, str] | None = None):
        return cls.module("interpreter").load(text, filename, (companions or {}).get(".dat"))
