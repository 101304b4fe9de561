"""KUKA.EthernetKRL in the KRL interpreter: the EKI functions against the simulated channel (its configuration read
from the XML beside the program), and the generated station program's channel: what verify catches when it changes."""

from __future__ import annotations

import re
import shutil
from dataclasses import replace

import pytest

from codegen.controllers import get_target
from codegen.dialects.core.files import SourceFile
from codegen.dialects.core.values import RunError
from codegen.dialects.krl import eki
from codegen.kinds.station.cases import build_cases
from codegen.model.cell import EXAMPLES_DIR, load_cell
from codegen.sim.vision_pc import VisionPC
from codegen.verify.programs import fresh_sources
from codegen.verify.runner import run_cases

from .krl.helpers import DAT_HEAD, KRL

KUKA = get_target("kuka")
CONFIG = """<ETHERNETKRL>
  <CONFIGURATION><EXTERNAL><IP>10.0.0.5</IP><PORT>54600</PORT><TYPE>Server</TYPE></EXTERNAL></CONFIGURATION>
  <RECEIVE><XML>
    <ELEMENT Tag="Vision/Ack" Type="INT"/>
    <ELEMENT Tag="Vision/Command" Type="INT"/>
    <ELEMENT Tag="Vision/Station" Type="INT"/>
    <ELEMENT Tag="Vision/X" Type="REAL"/>
    <ELEMENT Tag="Vision/Y" Type="REAL"/>
    <ELEMENT Tag="Vision/Theta" Type="REAL"/>
  </XML></RECEIVE>
  <SEND><XML><ELEMENT Tag="Robot/Command"/><ELEMENT Tag="Robot/Request"/></XML></SEND>
</ETHERNETKRL>
"""
ASK = """RET = EKI_INIT("cam")
N[1] = RET.MSG_NO
RET = EKI_OPEN("cam")
N[2] = RET.MSG_NO
RET = EKI_SETINT("cam", "Robot/Command", 1)
RET = EKI_SETINT("cam", "Robot/Request", 7)
RET = EKI_SEND("cam", "Robot")
N[3] = RET.MSG_NO
RET = EKI_CHECKBUFFER("cam", "Vision/Ack")
WHILE RET.BUFF == 0
  WAIT SEC 0.05
  RET = EKI_CHECKBUFFER("cam", "Vision/Ack")
ENDWHILE
RET = EKI_GETINT("cam", "Vision/Ack", ACK)
N[4] = RET.MSG_NO
RET = EKI_GETREAL("cam", "{x_path}", X)
N[5] = RET.MSG_NO
RET = EKI_GETREAL("cam", "Vision/Theta", THETA)
N[6] = RET.MSG_NO
RET = EKI_GETREAL("cam", "Vision/Theta", THETA)
N[7] = RET.MSG_NO
RET = EKI_CLOSE("cam")
RET = EKI_CLEAR("cam")
"""
DATA = "DECL EKI_STATUS RET\nDECL INT N[7]\nDECL INT ACK=0\nDECL REAL X=-1.0\nDECL REAL THETA=-1.0\n"
READING = {"VIS_STATION": 3, "VIS_X": 612.5, "VIS_Y": -20.25, "VIS_THETA": 1.5}


def _run(config: str | None = CONFIG, x_path: str = "Vision/X", behaviour: str = "prompt", body: str = ASK):
    files = [
        SourceFile("t.src", "DEF T()\n" + body.format(x_path=x_path) + "END\n"),
        SourceFile("t.dat", DAT_HEAD.format(name="T") + DATA + "ENDDAT\n"),
    ]
    if config is not None:
        files.append(SourceFile("cam.xml", config))
    program = KRL.load_files(KRL.programs(files)[0])
    device = VisionPC.for_target(KUKA, READING, behaviour=behaviour)
    trace = program.run({}, devices=(device,), keep=("N", "ACK", "X", "THETA"))
    return trace.kept, device


def test_a_reading_arrives_at_the_paths_the_configuration_names():
    kept, device = _run()
    assert kept["N"] == [0, 0, 0, 0, 0, 0, eki.ERRORS["empty"]]  # the answer's theta taken: its memory is empty
    assert kept["ACK"] == 7
    assert kept["X"] == pytest.approx(612.5) and kept["THETA"] == pytest.approx(1.5)
    assert [link.connected for link in device.links] == [False]  # closed at the end


def test_a_path_the_configuration_does_not_name_reads_nothing():
    kept, _ = _run(x_path="Vision/Xpos")
    assert kept["N"][4] == eki.ERRORS["unknown_element"]
    assert kept["X"] == pytest.approx(-1.0)  # left as it was


def test_an_element_the_xml_leaves_out_is_never_stored():
    kept, _ = _run(config=CONFIG.replace('    <ELEMENT Tag="Vision/X" Type="REAL"/>\n', ""))
    assert kept["N"][4] == eki.ERRORS["unknown_element"]  # the program asks for what the configuration lacks
    assert kept["THETA"] == pytest.approx(1.5)


def test_an_incomplete_answer_leaves_an_empty_memory():
    kept, _ = _run(behaviour="incomplete")  # the answer's last value (theta) missing
    assert kept["N"][5] == eki.ERRORS["empty"]
    assert kept["THETA"] == pytest.approx(-1.0)


def test_an_incomplete_answer_lacks_a_value_the_channel_receives():
    """A channel configured for a read's station alone (a program of frame-mode stations): the value the
    incomplete answer leaves out is the station, not the theta the option would drop anyway."""
    config = re.sub(r'    <ELEMENT Tag="Vision/(X|Y|Theta)" Type="REAL"/>\n', "", CONFIG)
    body = ASK.split("RET = EKI_GETREAL")[0] + 'RET = EKI_GETINT("cam", "Vision/Station", ACK)\nN[5] = RET.MSG_NO\n'
    kept, _ = _run(config=config, body=body)
    assert kept["N"][4] == 0 and kept["ACK"] == READING["VIS_STATION"]  # complete: the station read
    kept, _ = _run(config=config, behaviour="incomplete", body=body)
    assert kept["N"][4] == eki.ERRORS["empty"] and kept["ACK"] == 7  # left as the answer's number


def test_a_send_on_a_dropped_connection_is_refused():
    body = ASK.split("RET = EKI_CHECKBUFFER")[0] + 'RET = EKI_SEND("cam", "Robot")\nN[4] = RET.MSG_NO\n'
    body += 'RET = EKI_CHECKBUFFER("cam", "Vision/Ack")\nN[5] = RET.MSG_NO\nWAIT SEC 0.1\n'
    body += 'RET = EKI_SEND("cam", "Robot")\nN[6] = RET.MSG_NO\n'
    kept, _ = _run(behaviour="dropped", body=body)
    assert kept["N"][3:6] == [0, 0, eki.ERRORS["not_connected"]]


def test_init_twice_and_functions_before_init_give_their_numbers():
    body = 'RET = EKI_OPEN("cam")\nN[1] = RET.MSG_NO\nRET = EKI_INIT("cam")\nRET = EKI_INIT("cam")\nN[2] = RET.MSG_NO\n'
    kept, _ = _run(body=body)
    assert kept["N"][:2] == [eki.ERRORS["not_initialised"], eki.ERRORS["already_initialised"]]


def test_a_program_without_its_configuration_is_told_so():
    with pytest.raises(RunError, match=r"t\.src:2:\d+: EKI_Init: the channel's configuration cam\.xml is missing"):
        _run(config=None)


def test_a_configuration_that_is_not_the_options_structure_is_refused():
    with pytest.raises(RunError, match="CONFIGURATION/EXTERNAL has no IP and PORT"):
        _run(config="<ETHERNETKRL><RECEIVE/></ETHERNETKRL>")


def test_the_message_numbers_the_programs_name_are_the_interpreters():
    named = {number for number, _text in KUKA.program["channel"]["messages"]}
    assert named == set(eki.ERRORS.values()) - {0}


# --- the generated station program ------------------------------------------------------------------------------
CELL = EXAMPLES_DIR / "thermometer_bench.toml"  # a point and a frame station: both commands' answers


@pytest.fixture(scope="module")
def station():
    cell = load_cell(CELL)
    (source,) = [s for s in fresh_sources(cell, ["kuka"]) if s.kind == "station"]
    cases = build_cases(cell, 1, 0)
    picked = {c.category: c for c in reversed(cases)}  # each category's first case
    chosen = [picked[c] for c in ("vision_never", "vision_dropped", "vision_incomplete", "vision_twice")]
    chosen.append(next(c for c in cases if c.vision == "prompt" and c.category != "unknown_station"))
    return cell, source, chosen


def _mismatches(cell, source, cases, edit) -> int:
    src = source.files[0]
    text = edit(src.text)
    assert text != src.text, "the edit changed nothing"
    edited = replace(source, files=(SourceFile(src.name, text), *source.files[1:]))
    return run_cases(cell, edited, cases, 200_000).mismatches


def test_the_generated_program_meets_every_channel_case(station):
    cell, source, cases = station
    assert run_cases(cell, source, cases, 200_000).mismatches == 0
    xml = next(f for f in source.files if f.name.endswith(".xml"))
    config = eki.parse_config(xml.text)
    assert (config.ip, config.port) == (cell.vision.ip, cell.vision.port)
    program = source.files[0].text
    for path in config.receive:  # every element the configuration names, the program reads, and no other
        assert f'"{path}"' in program
    assert set(re.findall(r'EKI_GET\w+\("\w+", "([\w/]+)"', program)) == set(config.receive)


MUTATIONS = {
    # a path renamed in the program only: the configuration does not name it
    "path renamed": lambda t: t.replace('"Vision/Theta", VIS_THETA)', '"Vision/Angle2", VIS_THETA)'),
    # the status check after the last value of a read's answer removed: an incomplete answer passes
    "status check removed": lambda t: re.sub(
        r'(EKI_GETREAL\("\w+", "Vision/Theta", VIS_THETA\)\n)    IF NOT VIS_EKI\(RET\) THEN\n      RETURN FALSE\n'
        r"    ENDIF\n",
        r"\1",
        t,
    ),
    # the timeout removed: a vision PC that never answers holds the program forever
    "timeout removed": lambda t: re.sub(r"      IF POLLS >= VIS_POLLS THEN\n(.*\n){4}      ENDIF\n", "", t),
    # the connection's state not looked at: a lost connection ends as a silent vision PC's timeout
    "connection not checked": lambda t: t.replace("IF NOT RET.CONNECTED THEN", "IF FALSE THEN"),
}


@pytest.mark.parametrize("name", MUTATIONS)
def test_verify_catches_a_channel_edit(station, name):
    cell, source, cases = station
    assert _mismatches(cell, source, cases, MUTATIONS[name]) >= 1


def test_check_reads_a_configuration_as_the_option_does():
    program = [SourceFile("t.src", "DEF T()\nEND\n"), SourceFile("t.dat", DAT_HEAD.format(name="T") + "ENDDAT\n")]
    assert KRL.check_files([*program, SourceFile("cam.xml", CONFIG)]) == []
    (finding,) = KRL.check_files([*program, SourceFile("cam.xml", "<ETHERNETKRL/>")])
    assert finding.file == "cam.xml" and "CONFIGURATION/EXTERNAL has no IP and PORT" in finding.message


def test_a_frame_mode_program_meets_the_incomplete_answer(tmp_path):
    """A cell of frame-mode stations alone (`codegen init frame`): its program reads a read's station and no mark;
    the incomplete answer misses the station, and the program stops at home as every target's does."""
    from click.testing import CliRunner

    from codegen.cli import main

    out = tmp_path / "frame.toml"
    assert CliRunner().invoke(main, ["init", "frame", "--target", "kuka", "--out", str(out)]).exit_code == 0
    cell = load_cell(out)
    (source,) = [s for s in fresh_sources(cell, ["kuka"]) if s.kind == "station"]
    incomplete = [c for c in build_cases(cell, 1, 0) if c.category == "vision_incomplete"]
    assert incomplete and run_cases(cell, source, incomplete, 200_000).mismatches == 0


def test_a_folder_without_the_configuration_is_told_so(tmp_path):
    """The generated program's .src and .dat without its .xml: check names the missing file at the EKI_Init that
    reads it (exit 2); run stops there with the option's error (exit 1); with the .xml beside, both pass."""
    from click.testing import CliRunner

    from codegen.cli import main

    generated = EXAMPLES_DIR.parents[1] / "generated" / "agv_machine_tending" / "kuka"
    for suffix in (".src", ".dat"):
        shutil.copy(generated / f"agv_machine_tending{suffix}", tmp_path)
    inputs = ["--input=VIS_STATION=1", "--input=VIS_X=612.4", "--input=VIS_Y=-285", "--input=VIS_THETA=1.8"]
    missing = "EKI_Init: the channel's configuration agv_machine_tending.xml is missing"
    check = CliRunner().invoke(main, ["check", str(tmp_path)])
    assert check.exit_code == 2 and missing in check.output and "[missing-file]" in check.output, check.output
    assert check.output.count("error") == 2  # the finding and the count: nothing else
    run = CliRunner().invoke(main, ["run", str(tmp_path / "agv_machine_tending.src"), *inputs])
    assert run.exit_code == 1 and re.search(rf"agv_machine_tending\.src:\d+:\d+: {missing}", run.output), run.output
    shutil.copy(generated / "agv_machine_tending.xml", tmp_path)
    assert CliRunner().invoke(main, ["check", str(tmp_path)]).exit_code == 0
    assert CliRunner().invoke(main, ["run", str(tmp_path / "agv_machine_tending.src"), *inputs]).exit_code == 0
