"""Python printer for the cached closed form (float64, radians, module `math`)."""

from __future__ import annotations

from sympy.printing.pycode import PythonCodePrinter


class Printer(PythonCodePrinter):
    """sympy's own Python printer; only the settings are ours."""

    def __init__(self) -> None:
        super().__init__({"standard": "python3", "fully_qualified_modules": True})
