"""RAPID (ABB): printer, grammar and interpreter."""

from codegen.dialects import Dialect


class Rapid(Dialect):
    name = "rapid"
    suffixes = (".mod",)
