"""KRL's interrupts, CIRC and constant-orientation LIN and their misuse, in the interpreter."""

from __future__ import annotations

import math

import numpy as np
import pytest

from codegen.dialects.core.values import RunError
from codegen.dialects.krl.interpreter import load

CYCLE = 0.012  # targets/kuka.toml signal_cycle_s
CELL = "codegen/examples/laser/laser_tcp.toml"


class Gate:
    """A switching input: $IN[5] on while the flange's x (robot's base) lies beyond x0."""

    def __init__(self, x0: float, name: str = "$IN[5]") -> None:
        self.x0, self.switches = x0, frozenset({name})

    def switch(self, name, t, flange2base):
        if name not in self.switches:
            return None
        return flange2base is not None and bool(flange2base[0, 3] > self.x0)

    def on_wait(self, machine, where) -> bool:
        return False


DAT = """DEFDAT T PUBLIC
DECL REAL XS[10]
DECL REAL ZS[10]
DECL INT WHO[10]
DECL INT N=0
DECL KRLMSG_T MSG={MODUL[] "T",NR 1,MSG_TXT[] " "}
DECL KRLMSGPAR_T PAR[3]
DECL KRLMSGOPT_T OPT={VL_STOP FALSE,CLEAR_P_RESET TRUE,CLEAR_P_SAW FALSE,LOG_TO_DB FALSE}
DECL INT H=0
ENDDAT
"""
# the handler: the interrupt's number into WHO, $POS_INT's y and z (the base below turns the robot's x into
# the base's -y) into XS and ZS, a notification (no advance-run stop) whose time is the cycle's
SEEN = """DEF SEEN(K:IN)
DECL INT K
N = N + 1
WHO[N] = K
XS[N] = $POS_INT.Y
ZS[N] = $POS_INT.Z
MSG.MSG_TXT[] = "seen"
H = SET_KRLMSG(#NOTIFY, MSG, PAR[], OPT)
END
"""
# $BASE: 1000 mm along the robot's x, turned 90 deg (its -y the robot's x); $TOOL 100 mm along the flange's z.
# The first LIN takes 1 s (its start unknown), the second 100 mm at 0.1 m/s: the robot's x 1000 + 100 (t - 1)
START = """$BASE = {X 1000, Y 0, Z 0, A 90, B 0, C 0}
$TOOL = {X 0, Y 0, Z 100, A 0, B 0, C 0}
$VEL.CP = 0.1
LIN {X 0, Y 0, Z 500, A 0, B 0, C 0}
WAIT SEC 0
"""
OUT_AND_BACK = """LIN {X 0, Y -100, Z 500, A 0, B 0, C 0}
LIN {X 0, Y 0, Z 500, A 0, B 0, C 0}
"""


GATE = (Gate(1042.0),)


def run(body: str, devices=GATE, routines: str = SEEN, keep=("XS", "ZS", "WHO", "N"), cycle=CYCLE):
    program = load(f"DEF T()\n{body}\nEND\n{routines}", "t.src", DAT)
    return program.run({}, devices=devices, signal_cycle_s=cycle, keep=keep)


def seen(trace) -> int:
    return trace.kept["N"]


ON_OFF = "INTERRUPT DECL 20 WHEN $IN[5]==TRUE DO SEEN(20)\nINTERRUPT DECL 21 WHEN $IN[5]==FALSE DO SEEN(21)\n"


def test_each_edge_runs_its_routine_at_the_cycle_it_is_seen_with_the_tcp_there_in_the_motions_base():
    """On at the first 12 ms cycle past x 1042 (t 1.428 s: x 1042.8), off going back at the first cycle at or
    below it (t 2.58 s: exactly 1042); $POS_INT is the TCP (z 500, not the flange's 400) in $BASE."""
    trace = run(ON_OFF + START + "INTERRUPT ON 20\nINTERRUPT ON 21\n" + OUT_AND_BACK + "WAIT SEC 0\nINTERRUPT OFF")
    assert seen(trace) == 2
    assert trace.kept["WHO"][:2] == [20, 21]
    assert trace.kept["XS"][:2] == pytest.approx([-42.8, -42.0], abs=2e-3)
    assert trace.kept["ZS"][:2] == pytest.approx([500.0, 500.0], abs=2e-3)
    assert trace.message_times == pytest.approx([119 * CYCLE, 215 * CYCLE])


def test_a_rising_only_interrupt_and_not_input():
    """NOT $IN[k] fires when the input goes off; $IN[k] alone when it goes on."""
    body = "INTERRUPT DECL 20 WHEN NOT $IN[5] DO SEEN(20)\nINTERRUPT DECL 21 WHEN $IN[5] DO SEEN(21)\n"
    trace = run(body + START + "INTERRUPT ON\n" + OUT_AND_BACK + "WAIT SEC 0")
    assert trace.kept["WHO"][:2] == [21, 20]


def test_the_lower_priority_number_runs_first_in_the_same_cycle():
    body = "INTERRUPT DECL 30 WHEN $IN[5]==TRUE DO SEEN(30)\nINTERRUPT DECL 10 WHEN $IN[5]==TRUE DO SEEN(10)\n"
    trace = run(body + START + "INTERRUPT ON 30\nINTERRUPT ON 10\n" + OUT_AND_BACK + "WAIT SEC 0")
    assert trace.kept["WHO"][:2] == [10, 30]


def test_interrupt_off_after_an_advance_run_stop_keeps_the_edges_without_it_loses_them():
    """INTERRUPT OFF runs in the advance run: straight after the motion it is off before the arm moved."""
    on = ON_OFF + START + "INTERRUPT ON 20\nINTERRUPT ON 21\n" + OUT_AND_BACK
    assert seen(run(on + "WAIT SEC 0\nINTERRUPT OFF 20\nINTERRUPT OFF 21")) == 2
    assert seen(run(on + "INTERRUPT OFF 20\nINTERRUPT OFF 21\nWAIT SEC 0")) == 0
    # off between the two moves once the first has ended: the way back is not seen
    between = ON_OFF + START + "INTERRUPT ON 20\nINTERRUPT ON 21\nLIN {X 0, Y -100, Z 500, A 0, B 0, C 0}\n"
    trace = run(between + "WAIT SEC 0\nINTERRUPT OFF 21\nLIN {X 0, Y 0, Z 500, A 0, B 0, C 0}\nWAIT SEC 0")
    assert trace.kept["WHO"][: seen(trace)] == [20]


def test_an_input_already_true_at_interrupt_on_does_not_fire():
    """Edge-triggered: the gate is on where the arm stands when the interrupt goes on."""
    body = ON_OFF + START + "LIN {X 0, Y -100, Z 500, A 0, B 0, C 0}\nWAIT SEC 0\nINTERRUPT ON 20\n"
    trace = run(body + "LIN {X 0, Y -60, Z 500, A 0, B 0, C 0}\nWAIT SEC 0")
    assert seen(trace) == 0
    back_and_out = "LIN {X 0, Y 0, Z 500, A 0, B 0, C 0}\nLIN {X 0, Y -100, Z 500, A 0, B 0, C 0}\n"
    trace = run(body + "INTERRUPT ON 21\n" + back_and_out + "WAIT SEC 0")
    assert trace.kept["WHO"][: seen(trace)] == [21, 20]  # off going back, on again going out


def test_a_disabled_interrupt_keeps_its_event_for_enable():
    """DISABLE: the edge is saved with its $POS_INT; its routine runs at ENABLE (after the motion)."""
    body = ON_OFF + START + "INTERRUPT ON 20\nINTERRUPT DISABLE 20\n" + OUT_AND_BACK + "WAIT SEC 0\n"
    trace = run(body + "INTERRUPT ENABLE 20")
    assert seen(trace) == 1 and trace.kept["XS"][0] == pytest.approx(-42.8, abs=2e-3)
    assert trace.message_times[0] == pytest.approx(3.0)
    assert seen(run(body + "INTERRUPT OFF 20\nINTERRUPT ON 20\nINTERRUPT ENABLE 20")) == 0


def test_nothing_fires_without_a_switching_device_or_on_other_conditions():
    body = ON_OFF + START + "INTERRUPT ON 20\nINTERRUPT ON 21\n" + OUT_AND_BACK + "WAIT SEC 0"
    assert seen(run(body, devices=())) == 0
    assert seen(run(body, cycle=None)) == 0
    stop = "INTERRUPT DECL 20 WHEN $STOPMESS==TRUE DO SEEN(20)\nINTERRUPT DECL 21 WHEN $IN[6]==TRUE DO SEEN(21)\n"
    assert seen(run(stop + START + "INTERRUPT ON 20\nINTERRUPT ON 21\n" + OUT_AND_BACK + "WAIT SEC 0")) == 0


def test_circ_runs_the_arc_through_the_auxiliary_point_in_its_length_over_the_path_speed():
    """A half circle of radius 50 mm at 0.1 m/s: pi 50 / 100 s; the gate at robot x 1042 seen on the arc
    (x = 1050 + 50 cos(angle), y = 50 sin(angle): base y = -(x - 1000)); the start's orientation held."""
    body = (
        ON_OFF.replace("SEEN(21)", "SEEN(21)")
        + START.replace("LIN {X 0, Y 0,", "LIN {X 0, Y -100,")
        + (
            "$ORI_TYPE = #CONSTANT\n$CIRC_TYPE = #BASE\nINTERRUPT ON 21\n"
            "CIRC {X 50, Y -50, Z 500, A 0, B 0, C 0}, {X 0, Y 0, Z 500, A 45, B 0, C 0}\nWAIT SEC 0"
        )
    )
    trace = run(body)
    assert trace.moves[-1].end_time == pytest.approx(1.0 + math.pi * 50 / 100, abs=1e-6)
    assert np.allclose(trace.moves[-1].tcp2base[:3, :3], trace.moves[-2].tcp2base[:3, :3])
    # the first cycle at x <= 1042: 50 cos(a) <= -8 with a = (t - 1) 100 / 50
    k = math.ceil((1.0 + math.acos(-8 / 50) / 2.0) / CYCLE - 1e-9)
    a = (k * CYCLE - 1.0) * 2.0
    assert seen(trace) == 1
    assert trace.kept["XS"][0] == pytest.approx(-(50 + 50 * math.cos(a)), abs=2e-3)
    assert trace.message_times[0] == pytest.approx(k * CYCLE)


def test_lin_with_constant_orientation_keeps_the_start_orientation():
    trace = run(
        "$BASE = $NULLFRAME\nLIN {X 0, Y 0, Z 500, A 0, B 0, C 0}\n$ORI_TYPE = #CONSTANT\n"
        "LIN {X 10, Y 0, Z 500, A 30, B 0, C 0}",
        devices=(),
    )
    assert np.allclose(trace.moves[1].tcp2base[:3, :3], np.eye(3))
    assert np.allclose(trace.moves[1].tcp2base[:3, 3], [10, 0, 500], atol=1e-4)


CIRC_ON = "$BASE = $NULLFRAME\n$VEL.CP = 0.1\nLIN {X 0, Y 0, Z 500, A 0, B 0, C 0}\n"


@pytest.mark.parametrize(
    ("body", "says"),
    [
        ("INTERRUPT DECL 20 WHEN $IN[5] AND $IN[6] DO SEEN(1)", r"t\.src:2:\d+: .*a condition on one input"),
        ("INTERRUPT DECL 20 WHEN $IN[N]==TRUE DO SEEN(1)", "with a constant k"),
        ("INTERRUPT DECL 20 WHEN $IN[5000] DO SEEN(1)", r"constant k in 1\.\.4096"),
        ("INTERRUPT DECL 20 WHEN $IN[5] DO SEEN()", "SEEN takes 1 arguments, got 0"),
        ("INTERRUPT DECL 20 WHEN $IN[5] DO SEEN(N)", "passes constants"),
        ("INTERRUPT DECL 20 WHEN $IN[5] DO F(1)", "F is a function"),
        ("INTERRUPT DECL 20 WHEN $IN[5] DO BACK(1)", "BACK has an OUT parameter"),
        ("INTERRUPT DECL 20 WHEN $IN[5] DO NOWHERE(1)", "no routine NOWHERE"),
        ("N = $POS_INT.X", r"t\.src:2:\d+: \$POS_INT has no value: no interrupt has fired"),
        (
            "INTERRUPT DECL 20 WHEN $IN[5]==TRUE DO MOVES(1)\n"
            + START
            + "INTERRUPT ON 20\n"
            + OUT_AND_BACK
            + "WAIT SEC 0",
            r"t\.src:\d+: a motion in the interrupt routine MOVES",
        ),
        (
            "INTERRUPT DECL 20 WHEN $IN[5]==TRUE DO WAITS(1)\n"
            + START
            + "INTERRUPT ON 20\n"
            + OUT_AND_BACK
            + "WAIT SEC 0",
            r"t\.src:\d+:\d+: an advance-run stop in the interrupt routine WAITS",
        ),
        (
            CIRC_ON + "CIRC {X 10, Y 10, Z 500, A 0, B 0, C 0}, {X 20, Y 0, Z 500, A 0, B 0, C 0}",
            r"t\.src:5:\d+: CIRC with \$ORI_TYPE not set",
        ),
        (
            CIRC_ON
            + "$ORI_TYPE = #CONSTANT\nCIRC {X 10, Y 10, Z 500, A 0, B 0, C 0}, {X 20, Y 0, Z 500, A 0, B 0, C 0}",
            r"CIRC with \$CIRC_TYPE not set",
        ),
        (
            CIRC_ON + "$ORI_TYPE = #CONSTANT\n$CIRC_TYPE = #BASE\n"
            "CIRC {X 10, Y 0, Z 500, A 0, B 0, C 0}, {X 20, Y 0, Z 500, A 0, B 0, C 0}",
            "lie on one line",
        ),
        (
            CIRC_ON + "CIRC {X 10, Y 10, Z 500, A 0, B 0, C 0}, {X 20, Y 0, Z 500, A 0, B 0, C 0}, CA 90",
            "CA .* not modelled",
        ),
        ("$ORI_TYPE = #SIDEWAYS", r"\$ORI_TYPE takes #CONSTANT, #JOINT, #VAR,"),
    ],
)
def test_misuse_is_refused_naming_the_line(body, says):
    routines = SEEN + (
        "DEFFCT INT F(K:IN)\nDECL INT K\nRETURN K\nENDFCT\n"
        "DEF BACK(K:OUT)\nDECL INT K\nK = 1\nEND\n"
        "DEF MOVES(K:IN)\nDECL INT K\nLIN {X 0, Y 0, Z 400, A 0, B 0, C 0}\nEND\n"
        "DEF WAITS(K:IN)\nDECL INT K\nWAIT SEC 0\nEND\n"
    )
    with pytest.raises(RunError, match=says):
        run(body, routines=routines)
