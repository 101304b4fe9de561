"""The one module that reaches into Jinja's internals: a code generator whose templates mark their own text."""

from __future__ import annotations

from collections.abc import Callable

import jinja2
from jinja2.compiler import CodeGenerator

# What this module relies on, by Jinja's own names (tests/test_jinjadoor.py checks each against the installed
# Jinja; pyproject.toml bounds Jinja to the minor version where they hold):
#   Environment.code_generator_class    the class that compiles a template's nodes to Python source
#   Environment.concat                  joins the parts of a template's, a macro's or a block's output
#   CodeGenerator.visit_Const / visit_Concat(node, frame), .write(source), .name (the template's name),
#   .visit(node, frame); nodes.Const.as_const(frame.eval_ctx); nodes.Concat.nodes
#   generated source reaches the environment as `environment`


def marking_environment(mark: Callable[[str], str], checked: Callable[[object, str], str]) -> type[jinja2.Environment]:
    """A Jinja Environment class whose templates pass their own text (every string constant) through mark, the
    parts of every `~` through checked(part, template name), and join their output with mark (a template's, a
    macro's, a block's): with a finalize that checks what `{{ }}` prints, a template's output is marked text made
    of marked parts only."""

    class MarkingCodeGenerator(CodeGenerator):
        def visit_Const(self, node, frame) -> None:
            value = node.as_const(frame.eval_ctx)
            if isinstance(value, str):  # the template's own text
                self.write(f"environment.literal({value!r})")
            else:
                super().visit_Const(node, frame)

        def visit_Concat(self, node, frame) -> None:  # `~`: printable parts only
            self.write(f"environment.joined({self.name!r}, (")
            for part in node.nodes:
                self.visit(part, frame)
                self.write(", ")
            self.write("))")

    class MarkingEnvironment(jinja2.Environment):
        code_generator_class = MarkingCodeGenerator

        @staticmethod
        def concat(parts) -> str:
            return mark("".join(parts))

        @staticmethod
        def literal(text: str) -> str:
            return mark(text)

        @staticmethod
        def joined(where: str, parts) -> str:
            return mark("".join(checked(part, where) for part in parts))

    return MarkingEnvironment
