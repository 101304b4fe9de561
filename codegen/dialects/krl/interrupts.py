"""KRL interrupts: INTERRUPT DECL ... WHEN ... DO and INTERRUPT ON / OFF / ENABLE / DISABLE (KSS 8)."""

from __future__ import annotations

from codegen.dialects.core.values import RunError

# KSS 8 programming manual, interrupt programming: priorities 1..128 (KUKA's own routines use 3, 19
# and 40..80), at most 32 interrupts declared and 16 switched on at a time. Interrupt 3 is the
# template's: WHEN $STOPMESS (a stop message, e.g. an EMERGENCY STOP) DO IR_STOPM(), KUKA's routine in
# R1/System that stops the arm and keeps the position for the restart.
PRIORITIES = range(1, 129)
MAX_DECLARED = 32
MAX_ON = 16
SYSTEM_HANDLERS = frozenset({"IR_STOPM"})
ACTIONS = frozenset({"ON", "OFF", "ENABLE", "DISABLE"})


class InterruptStatements:
    """Compiler mixin. The interpreter has no stop messages ($STOPMESS stays FALSE), so a declared
    interrupt never fires; what it checks is what the controller refuses when the program runs: a
    priority out of range, a handler that is neither the program's nor KUKA's, too many interrupts,
    and switching on one never declared."""

    def s_interrupt_decl(self, node):
        _global, priority, _condition, handler = node.children[:4]
        number, name, where = int(str(priority)), str(handler).upper(), self.where(node)
        if number not in PRIORITIES:
            self.fail(node, f"INTERRUPT DECL {number}: the priority must be in 1..128")
        if self.user_routines is not None and name not in self.user_routines and name not in SYSTEM_HANDLERS:
            self.fail(node, f"INTERRUPT DECL {number}: no routine {handler} to call")

        def run(fr):
            declared = fr.m.extra.setdefault("interrupts", {})
            if number not in declared and len(declared) >= MAX_DECLARED:
                raise RunError(f"{where}: more than {MAX_DECLARED} interrupts declared")
            declared[number] = "OFF"

        return run

    def s_interrupt_stmt(self, node):
        action, priority = str(node.children[0]).upper(), node.children[1]
        number, where = (int(str(priority)) if priority is not None else None), self.where(node)
        if action not in ACTIONS:
            self.fail(node, f"INTERRUPT {action}: expected ON, OFF, ENABLE or DISABLE")

        def run(fr):
            declared = fr.m.extra.setdefault("interrupts", {})
            for n in [number] if number is not None else list(declared):
                if n not in declared:
                    raise RunError(f"{where}: INTERRUPT {action} {n}: interrupt {n} is not declared")
                if action == "ON" and declared[n] == "OFF" and sum(s != "OFF" for s in declared.values()) >= MAX_ON:
                    raise RunError(f"{where}: INTERRUPT ON {n}: more than {MAX_ON} interrupts on")
                if action in ("ON", "OFF") or declared[n] != "OFF":  # ENABLE/DISABLE act on one that is on
                    declared[n] = {"ON": "ON", "OFF": "OFF", "ENABLE": "ON", "DISABLE": "DISABLED"}[action]

        return run
