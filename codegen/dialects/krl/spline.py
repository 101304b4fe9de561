"""KRL motion statements of KSS 8.3: SPTP / SLIN / SCIRC, and WITH $var = value, ... for one motion."""

from __future__ import annotations

from lark import Token, Tree

# KSS 8.3 programming manual for system integrators, spline motions: SPTP, SLIN and SCIRC are single spline
# motions; their path between the points is what the conventional PTP, LIN and CIRC do (a joint-interpolated
# move, a straight line, a circle), which is all the trace records (the spline's smoother velocity profile is
# not modelled: the trace has no dynamics). C_SPL approximates one (recorded as the motion's approximation).
# WITH $var = value, ...: the system variables the inline form sets for this motion; they apply to this
# motion only (recalled from the manual, not confirmed here): the interpreter sets them, moves, and restores
# the values they had. The relative motions PTP_REL / LIN_REL / SPTP_REL / SLIN_REL: codegen/dialects/krl/relative.py;
# a relative circle (CIRC_REL, SCIRC_REL) is not modelled.
KINDS = {"PTP": "joint", "SPTP": "joint", "LIN": "linear", "SLIN": "linear"}
WITH_ALLOWED = frozenset(
    {
        "$VEL",
        "$ACC",
        "$APO",
        "$VEL_AXIS",
        "$ACC_AXIS",
        "$TOOL",
        "$BASE",
        "$LOAD",
        "$IPO_MODE",
        "$ORI_TYPE",
        "$CIRC_TYPE",
        "$GEAR_JERK",
        "$COLLMON_TOL_PRO",
        "$JERK",
        "$EX_AX_IGNORE",
        "$CIRC_MODE",
        "$SPL_ORI_JOINT_AUTO",
    }
)


def motion_parts(children) -> tuple:
    """([keyword, target] or [keyword, aux, end, CA name or None, CA value or None], approximation token or
    None, WITH clause or None) of a motion_stmt or circ_stmt, whichever side of WITH its approximation stands."""
    approx = next((c for c in children if isinstance(c, Tree) and c.data == "approx"), None)
    with_clause = next((c for c in children if isinstance(c, Tree) and c.data == "with_clause"), None)
    rest = [c for c in children if c is None or (c is not approx and c is not with_clause)]
    while len(rest) > (2 if isinstance(children[0], Token) and children[0].type == "MOTION" else 5):
        rest.pop()  # the placeholders of the approximation and WITH left out
    return rest, approx.children[0] if approx is not None else None, with_clause


def _root(node):
    while isinstance(node, Tree) and node.data in ("index", "field", "whole"):
        node = node.children[0]
    return node


class WithClauses:
    """Compiler mixin: a motion's WITH clause, run around the motion."""

    def with_statements(self, with_clause) -> list:
        """The WITH clause's assignments compiled as statements (system variables only)."""
        out = []
        for item in with_clause.children:
            target, value = item.children
            root = _root(target)
            name = str(root.children[0]).upper() if isinstance(root, Tree) and root.data == "var" else None
            if name not in WITH_ALLOWED:
                allowed = ", ".join(sorted(WITH_ALLOWED))
                self.fail(item, f"WITH {name or 'this'}: the interpreter models WITH for {allowed}")
            out.append(self.s_assign(Tree("assign", [target, value], item.meta)))
        return out

    def around(self, statements: list, motion):
        """fr -> None: the WITH assignments, the motion, then the system variables back as they were."""
        if not statements:
            return motion

        def run(fr):
            m = fr.m
            before, tool = dict(m.state.sysvars), m.arm.tcp2flange
            for statement in statements:
                statement(fr)
            changed = [k for k, v in m.state.sysvars.items() if before.get(k, run) is not v]
            set_tool = m.arm.tcp2flange
            motion(fr)
            for key in changed:
                if key in before:
                    m.state.sysvars[key] = before[key]
                else:
                    m.state.sysvars.pop(key, None)
            if m.arm.tcp2flange is set_tool:
                m.arm.tcp2flange = tool

        return run

    def refuse_relative(self, node, keyword: str) -> None:
        if keyword.endswith("_REL"):
            self.fail(node, f"{keyword} (a relative motion) is not modelled by this interpreter")
