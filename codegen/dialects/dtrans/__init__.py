"""The Decompose/Trans dialect of source 000: printer, grammar and interpreter."""

from codegen.dialects import Dialect


class DTrans(Dialect):
    name = "dtrans"
    suffixes = (".prg",)

    @classmethod
    def predefined(cls) -> frozenset[str]:
        """The built-in functions the interpreter models."""
        from codegen.dialects.dtrans.interpreter import DTransCompiler  # lark: only when asked

        return frozenset(DTransCompiler("<names>").builtins)
