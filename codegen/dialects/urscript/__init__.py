"""URScript (Universal Robots): printer, grammar and interpreter."""

from codegen.dialects import Dialect


class URScript(Dialect):
    name = "urscript"
    suffixes = (".script",)
