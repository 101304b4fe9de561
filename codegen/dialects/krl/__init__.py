"""KRL (KUKA Robot Language, KSS 8): printer, grammar and interpreter."""

from codegen.dialects import Dialect


class KRL(Dialect):
    name = "krl"
    suffixes = (".src",)
    companions = (".dat",)  # the data list of a .src: declarations and initial values

    @classmethod
    def move_settings(cls, program: dict, kind: str, exact: bool, own_tool: bool = False) -> dict:
        """No approximation (C_PTP, C_DIS, ...): the generated programs stop at every pose."""
        return {"approx": None}

    @classmethod
    def load(cls, text: str, filename: str, companions: dict[str, str] | None = None):
        return cls.module("interpreter").load(text, filename, (companions or {}).get(".dat"))
