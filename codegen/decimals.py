"""Fixed-decimal number texts: the one rule against '-0' (the ground floor: imports nothing of codegen)."""

from __future__ import annotations


def unsigned_zero(text: str) -> str:
    """The one rule against '-0': a fixed-decimal text that reads as zero loses its sign."""
    return text.lstrip("-") if text.lstrip("-").strip("0.") == "" else text


def format_literal(value: float, decimals: int) -> str:
    """Fixed decimals, no '-0', no exponent: the same bytes on every machine."""
    return unsigned_zero(f"{value:.{decimals}f}")
