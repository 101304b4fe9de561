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
        """The findings every language has (syntax, what loading refuses), then, where the files parse, what run
        would stop on that the text shows (codegen/dialects/dtrans/check.py)."""
        findings = super().check_files(files, options)
        if any(f.code == "syntax" for f in findings):
            return findings
        from codegen.dialects.dtrans.check import check_file  # lark: only when asked

        found = [f for source in files for f in check_file(source)]
        return findings + [f for f in found if (f.file, f.line) not in {(g.file, g.line) for g in findings}]
