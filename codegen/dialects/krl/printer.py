"""KRL printer: degrees (SIN/COS take degrees), upper-case intrinsic functions."""

from codegen.dialects.printing import ControllerPrinter


class Printer(ControllerPrinter):
    language = "KRL"
    known_functions = {"cos": "COS", "sin": "SIN", "atan2": "ATAN2", "sqrt": "SQRT", "Abs": "ABS"}
    literal_decimals = 6
