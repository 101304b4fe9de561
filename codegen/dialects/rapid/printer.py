"""RAPID printer: degrees (Sin/Cos take degrees), capitalised functions."""

from codegen.dialects.printing import ControllerPrinter


class Printer(ControllerPrinter):
    language = "RAPID"
    known_functions = {"cos": "Cos", "sin": "Sin", "atan2": "ATan2", "sqrt": "Sqrt", "Abs": "Abs"}
    literal_decimals = 6
