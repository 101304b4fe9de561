"""The arguments of a RAPID instruction compiled from its nodes: positional ones and optional \\Name[:=value]."""

from __future__ import annotations

from lark import Token, Tree

# The optional arguments that show the operator a message box while an instruction waits (RAPID Instructions,
# WaitDI, WaitDO and WaitUntil, RobotWare 6.08 and later, as recalled: [\Visualize] [\Header] [\Message] |
# [\MsgArray] [\Wrap] [\Icon] [\Image] [\VisualizeTime] [\UIActiveSignal]). They change what the FlexPendant
# shows, not the wait: accepted and not shown.
WAIT_DISPLAY = frozenset({"VISUALIZE", "HEADER", "MESSAGE", "MSGARRAY", "WRAP", "ICON", "IMAGE", "VISUALIZETIME",
                          "UIACTIVESIGNAL"})  # fmt: skip


def split_args(compiler, node, args_node, switches: set[str], refusal: str = "{name} has no argument \\{arg}"):
    """Positional argument nodes and optional ones by upper-case name (value node, or None for a switch);
    an optional argument not in switches fails with refusal (its {name} and {arg})."""
    positional, named = [], {}
    for arg in args_node.children if args_node is not None else []:
        if isinstance(arg, Tree) and arg.data == "opt_arg":
            key = str(arg.children[0]).upper()
            if key not in switches:
                compiler.fail(arg, refusal.format(name=node.children[0], arg=arg.children[0]))
            if isinstance(arg.children[1], Token):  # \\Name?Parameter
                shown = f"{node.children[0]}: a conditional argument (\\{arg.children[0]}?...)"
                compiler.fail(arg, f"{shown} is not modelled here", "unsupported")
            named[key] = arg.children[1]
        else:
            positional.append(arg)
    return positional, named
