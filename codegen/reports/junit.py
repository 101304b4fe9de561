"""JUnit XML (the Ant/Jenkins/Surefire form CI systems read): a suite per cell, a test case per target x program."""

from __future__ import annotations

import re
from xml.etree import ElementTree as ET

from codegen.reports.findings import CellResult

# characters XML 1.0 does not allow in a document (its Char production); a program's text may hold them
NOT_XML = re.compile("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")


def junit(results: list[CellResult]) -> str:
    """The results as one <testsuites> document; a failing case's <failure> holds its mismatches or findings."""
    root = ET.Element("testsuites", name="codegen")
    total = failures = errors = 0
    seconds = 0.0
    for result in results:
        failed = sum(case.failed for case in result.cases)
        broken = sum(case.error is not None for case in result.cases)
        time = sum(case.seconds for case in result.cases)
        suite = ET.SubElement(
            root,
            "testsuite",
            name=f"{result.command} {result.cell}".strip(),
            tests=str(len(result.cases)),
            failures=str(failed),
            errors=str(broken),
            time=_seconds(time),
        )
        if result.cell_file is not None:
            suite.set("file", result.cell_file)
        for case in result.cases:
            element = ET.SubElement(
                suite,
                "testcase",
                name=case.program,
                classname=".".join(p for p in (result.command, case.cell, case.target) if p),
                time=_seconds(case.seconds),
            )
            if case.error is not None:  # it could not run: an error, not a failure (Surefire's distinction)
                first = case.error.splitlines()[0] if case.error else ""
                error = ET.SubElement(element, "error", message=_xml(first), type=_type(case))
                error.text = _xml(case.error)
            if case.failure is not None:
                first = case.failure.splitlines()[0] if case.failure else ""
                failure = ET.SubElement(element, "failure", message=_xml(first), type=_type(case))
                failure.text = _xml(case.failure)
            text = "\n".join(filter(None, [f"files: {', '.join(case.files)}" if case.files else "", case.output]))
            if case.cases:
                text = f"{case.cases} cases\n{text}"
            if text:
                ET.SubElement(element, "system-out").text = _xml(text)
        total += len(result.cases)
        failures += failed
        errors += broken
        seconds += time
    root.set("tests", str(total))
    root.set("failures", str(failures))
    root.set("errors", str(errors))
    root.set("time", _seconds(seconds))
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def _xml(text: str) -> str:
    """The text with each character XML 1.0 does not allow written as \\xNN (or \\uNNNN): the document stays XML."""
    return NOT_XML.sub(lambda m: _escaped(ord(m.group())), text)


def _escaped(code: int) -> str:
    return f"\\x{code:02x}" if code < 256 else f"\\u{code:04x}"


def _type(case) -> str:
    """The rules the case's findings break (the first few), as the failure's type."""
    rules = list(dict.fromkeys(f.rule for f in case.findings if f.level == "error")) or list(
        dict.fromkeys(f.rule for f in case.findings)
    )
    return " ".join(rules[:4]) or "failure"


def _seconds(value: float) -> str:
    return f"{value:.3f}"  # the Surefire time: at most three decimals
