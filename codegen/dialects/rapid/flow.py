"""RAPID GOTO and labels: a block with labels runs as segments between them, a GOTO is a signal to the label's block."""

from __future__ import annotations

from lark import Tree

from codegen.dialects.core.source import Inline

# Sources: ABB, "Technical reference manual - RAPID Instructions, Functions and Data types", GOTO, and "RAPID
# overview", labels; as recalled (the manual's text was not readable during this work): `Label:` marks a place in a
# routine; GOTO Label goes on there. A GOTO may go to a label of its own instruction list or of one around it
# (out of an IF, WHILE, FOR or TEST), forwards or backwards, but not into a compound statement it is not in, nor
# out of its routine. Here a jump counts one step (an endless GOTO loop ends at the step limit).


class Labels:
    """Compiler mixin: blocks with labels and GOTO."""

    def block(self, nodes):
        trees = [n for n in nodes if isinstance(n, Tree)]
        labels = {}
        for i, n in enumerate(trees):
            if n.data == "label":
                key = str(n.children[0]).upper()
                if key in labels or any(key in outer for outer in self.label_stack):
                    self.fail(n, f"label {n.children[0]} defined twice in the routine")
                labels[key] = i
        self.label_stack.append(set(labels))
        try:
            if not labels:
                return super().block(trees)
            return self._segments(trees, labels)
        finally:
            self.label_stack.pop()

    def _segments(self, trees, labels: dict):
        parts, index, current = [], {}, []
        for n in trees:
            if n.data == "label":
                parts.append(current)
                index[str(n.children[0]).upper()] = len(parts)
                current = []
            else:
                current.append(n)
        parts.append(current)
        compiled = [super(Labels, self).block(part) for part in parts]
        count, where = len(compiled), self.where(trees[0])

        def run(fr):
            i = 0
            while i < count:
                signal = compiled[i](fr)
                if signal is None:
                    i += 1
                    continue
                if signal.kind == "goto":
                    target = index.get(signal.value)
                    if target is not None:
                        fr.m.step(where)
                        i = target
                        continue
                return signal
            return None

        return run

    def s_label(self, node):
        return Inline(self, [])

    def s_goto_stmt(self, node):
        label = str(node.children[0]).upper()
        if not any(label in labels for labels in self.label_stack):
            label = node.children[0]
            self.fail(node, f"GOTO {label}: no label {label} in this instruction list or in one around it")
        return Inline(self, [f"return _Signal('goto', {label!r})"])
