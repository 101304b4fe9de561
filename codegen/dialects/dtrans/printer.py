"""Decompose/Trans printer: degrees (assumed), lower-case functions as in source 000's listing."""

from codegen.dialects.printing import ControllerPrinter


class Printer(ControllerPrinter):
    language = "dtrans"
    known_functions = {"cos": "cos", "sin": "sin", "atan2": "atan2", "sqrt": "sqrt", "Abs": "abs"}
    literal_decimals = 6
