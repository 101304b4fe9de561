"""The Decompose/Trans dialect of source 000: printer, grammar and interpreter."""

from codegen.dialects import Dialect


class DTrans(Dialect):
    name = "dtrans"
    suffixes = (".prg",)
