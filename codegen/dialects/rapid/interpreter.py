"""RAPID interpreter: a program of one file or of a task's modules, parsed and compiled (compiler.py, task.py)."""

from __future__ import annotations

from codegen.dialects.core.files import SourceFile
from codegen.dialects.core.program import Program
from codegen.dialects.rapid.compiler import RAPIDCompiler, parse
from codegen.dialects.rapid.task import load_task

__all__ = ["RAPIDCompiler", "load", "parse"]


def load(text: str, filename: str = "<rapid>") -> Program:
    """A program of one file (its module, or the modules of an old-style .prg)."""
    return load_task([SourceFile(filename, text)])
