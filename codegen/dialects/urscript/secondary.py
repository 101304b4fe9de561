"""URScript secondary programs (`sec name(): ... end`): refused where they would take physical time."""

# URScript manual (e-Series SW 5.25), Secondary Programs (STATED): a secondary program "is executed by the robot
# controller concurrently and simultaneously with the primary script program"; it "should not use any 'physical'
# time. In particular, it cannot contain sleep, or move statements" and "must be simple enough to be executed in a
# single controller step"; "Exceptions on secondary program do not stop execution of the primary program"; it is
# defined with the keyword `sec`. Secondary Program Limitations (SW 5.19, STATED): movej, movel, servoj and the
# other motion commands "will cause an error of 'Runtime is too much behind'", sleep too; "Threads in secondary
# programs are not supported".
# Modelled so: a call that takes physical time (PHYSICAL_TIME) in a `sec` body, or in a function the body calls
# (at any depth), and a thread started there, are refused when the program is loaded, naming the call and the
# reason. A file that is one `sec` is that secondary program: a run executes its body once, to its end (the
# primary program is not in the file: nothing here stops or moves it); one that reaches the run's step limit
# (a loop that never ends) is stopped with the same reason (one_step). A `sec` inside a program is checked the
# same way and called like a function (assumed: the manuals at hand do not say what a nested `sec` does).

from __future__ import annotations

from lark import Tree

from codegen.dialects.core.values import RunError, StepLimitError
from codegen.dialects.urscript.check import PHYSICAL_TIME

REASON = (
    "a secondary program runs within one controller step, beside the primary, and may not use physical time "
    '(motion, sleep, sync); the controller stops it with "Runtime is too much behind" (URScript manual, '
    "Secondary Programs)"
)


def refusal(sec: Tree, functions: dict[str, Tree]) -> tuple[object, str] | None:
    """The first call or thread in the `sec` (and the functions it calls) that a secondary program may not hold:
    (its node, the message), else None. functions: the program's `def`s by name."""
    name = str(sec.children[0])
    seen: set[str] = set()
    todo: list[tuple[Tree, str]] = [(sec.children[2], "")]
    while todo:
        body, via = todo.pop()
        for node in body.iter_subtrees_topdown():
            if node.data in ("threaddef", "run_thread"):
                return node, f"a thread in secondary program {name}{via}: threads are not supported there ({REASON})"
            if node.data != "call" or not (isinstance(node.children[0], Tree) and node.children[0].data == "var"):
                continue
            callee = str(node.children[0].children[0])
            if callee in PHYSICAL_TIME:
                return node, f"{callee} in secondary program {name}{via}: {REASON}"
            if callee in functions and callee not in seen:
                seen.add(callee)
                todo.append((functions[callee].children[2], f" (in {callee}, which it calls)"))
    return None


def one_step(name: str, body):
    """The body of a file that is the secondary program `name`: a runaway loop stopped with UR's reason."""

    def run(fr):
        try:
            return body(fr)
        except StepLimitError as exc:
            where = str(exc).split(": step limit")[0]
            raise RunError(f"{where}: secondary program {name} does not end: {REASON}") from None

    return run
