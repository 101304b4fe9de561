"""URScript printer: radians, lower-case math functions."""

from codegen.dialects.printing import ControllerPrinter


class Printer(ControllerPrinter):
    language = "URScript"
    known_functions = {"cos": "cos", "sin": "sin", "atan2": "atan2", "sqrt": "sqrt", "Abs": "norm"}
    literal_decimals = 9
