"""KRL GOTO and labels: a jump within a statement block or out of it, never into one (KSS 8)."""

from __future__ import annotations

from lark import Tree

from codegen.dialects.core.source import Inline
from codegen.dialects.core.values import Signal

# KSS 8 programming manual for system integrators, GOTO: an unconditional jump to a label (NAME:) of the same
# routine; it may not jump into a block (a loop, an IF branch, a SWITCH case) from outside it, nor from one
# branch of an IF or SWITCH into another. So a GOTO sees the labels of the blocks it stands in: a block with
# labels runs as segments, one per label, and a GOTO is a signal the nearest block holding its label takes
# (every loop and branch passes a signal it does not know on, as it does RETURN).


class GotoBlocks:
    """Compiler mixin: blocks with labels, and GOTO."""

    def labels_seen(self) -> list[set[str]]:
        stack = getattr(self, "_label_stack", None)
        if stack is None:
            stack = self._label_stack = []
        return stack

    def block(self, nodes):
        trees = [n for n in nodes if isinstance(n, Tree)]
        labels = [n for n in trees if n.data == "label"]
        if not labels:
            return super().block(nodes)
        names: dict[str, int] = {}
        segments: list[list] = [[]]
        for node in trees:
            if node.data == "label":
                name = str(node.children[0]).upper()
                if name in names or any(name in seen for seen in self.labels_seen()):
                    self.fail(node, f"label {node.children[0]} defined twice")
                segments.append([])
                names[name] = len(segments) - 1
            else:
                segments[-1].append(node)
        self.labels_seen().append(set(names))
        try:
            compiled = [super(GotoBlocks, self).block(segment) for segment in segments]
        finally:
            self.labels_seen().pop()
        where = self.where(trees[0])
        count = len(compiled)

        def run(fr):
            i = 0
            while i < count:
                signal = compiled[i](fr)
                if signal is None:
                    i += 1
                elif signal.kind == "goto" and signal.value in names:
                    fr.m.step(where)  # a jump back is a loop: it counts a step
                    i = names[signal.value]
                else:
                    return signal
            return None

        return run

    def s_goto_stmt(self, node):
        name = str(node.children[0]).upper()
        if not any(name in seen for seen in self.labels_seen()):
            self.fail(
                node,
                f"GOTO {node.children[0]}: no such label in this block or a block around it (a GOTO may not "
                "jump into a loop, an IF branch or a SWITCH case, nor out of its routine)",
            )
        return Inline(self, [f"return {self.const(Signal('goto', name))}"])

    def s_label(self, node):
        return self.s_pass_stmt(node)
