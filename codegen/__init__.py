"""codegen: vision-corrected robot programs, derived with sympy and verified by interpretation."""

__version__ = "0.1.0"
