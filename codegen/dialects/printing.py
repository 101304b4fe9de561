"""Shared sympy code printer for controller languages: dialects differ only in their tables."""

from __future__ import annotations

from sympy.printing.codeprinter import CodePrinter
from sympy.printing.precedence import precedence

from codegen.decimals import format_literal


class ControllerPrinter(CodePrinter):
    """Prints the cached closed forms; subclasses set the tables below."""

    printmethod = "_controller"
    language = "controller"
    known_functions: dict[str, str] = {}  # sympy function name -> controller function
    literal_decimals = 6
    _default_settings = {**CodePrinter._default_settings, "strict": True, "contract": False}

    def __init__(self, settings: dict | None = None) -> None:
        super().__init__(settings or {})
        self.known_functions = dict(type(self).known_functions)

    # CodePrinter hooks (statements are laid out by the templates, not here)
    def _get_statement(self, codestring: str) -> str:
        return codestring

    def _get_comment(self, text: str) -> str:
        return text

    def _declare_number_const(self, name, value) -> str:
        raise NotImplementedError("constants are declared by the templates")

    def _format_code(self, lines):
        return lines

    def _traverse_matrix_indices(self, mat):
        raise NotImplementedError("no matrices in controller code")

    def _print_Float(self, expr) -> str:
        return format_literal(float(expr), self.literal_decimals)

    def _print_Integer(self, expr) -> str:
        return str(int(expr))

    def _print_Rational(self, expr) -> str:
        return format_literal(float(expr), self.literal_decimals)

    def _print_Pow(self, expr) -> str:
        base, exp = expr.as_base_exp()
        if exp == 2:
            b = self.parenthesize(base, precedence(expr))
            return f"{b}*{b}"
        if exp == -1:
            return f"1.0/{self.parenthesize(base, precedence(expr))}"
        raise NotImplementedError(f"power {expr} has no controller form")
