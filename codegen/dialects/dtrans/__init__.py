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

    @classmethod
    def check_files(cls, files: list, options=None) -> list:
        """Each file parsed once: its syntax error, else what loading refuses and what run would stop on that the
        text shows (codegen/dialects/dtrans/check.py); a program is one file."""
        from codegen.dialects.dtrans.check import check_file  # lark: only when asked

        return [f for source in files for f in check_file(source)]
