"""SARIF 2.1.0 (OASIS): one run, a rule per check with its help text, each finding at the program file's line and,
where it comes from the cell, the cell file's line of the key as a related location."""

from __future__ import annotations

import json
from pathlib import Path

from codegen import __version__
from codegen.reports.findings import CellResult, Finding, Location
from codegen.reports.paths import relative
from codegen.reports.rules import CHECK, EDIT, VERIFY, rule

SCHEMA = "https://docs.oasis-open.org/sarif/sarif/v2.1.0/errata01/os/schemas/sarif-schema-2.1.0.json"
ROOT = "SRCROOT"  # the uriBaseId of every repository file: a consumer resolves it to its checkout
KNOWN = {"verify": [r for r, _, _ in VERIFY] + [EDIT.id], "check": [f"check/{code}" for code in CHECK]}


def sarif(results: list[CellResult], root: Path) -> str:
    """The results as one SARIF log (JSON text, keys in a fixed order: the same results give the same bytes)."""
    used = [f.rule for r in results for f in r.findings]
    ids = list(dict.fromkeys([i for r in results for i in KNOWN.get(r.command, [])] + used))
    index = {rule_id: i for i, rule_id in enumerate(ids)}
    run = {
        "tool": {
            "driver": {
                "name": "codegen",
                "version": __version__,
                "rules": [_rule(rule_id) for rule_id in ids],
            }
        },
        "originalUriBaseIds": {ROOT: {"description": {"text": "The root of the repository the files are in."}}},
        "results": [_result(f, index, root, r.cell) for r in results for f in r.findings],
        "columnKind": "unicodeCodePoints",
    }
    log = {"$schema": SCHEMA, "version": "2.1.0", "runs": [run]}
    return json.dumps(log, indent=2, ensure_ascii=False) + "\n"


def _rule(rule_id: str) -> dict:
    r = rule(rule_id)
    out = {
        "id": r.id,
        "name": r.name,
        "shortDescription": {"text": r.name},
        "fullDescription": {"text": r.help},
        "help": {"text": r.help},
    }
    if rule_id in KNOWN["verify"]:  # a mismatch fails verify; a hand edit is worth a look (check: per finding)
        out["defaultConfiguration"] = {"level": "warning" if rule_id == EDIT.id else "error"}
    return out


def _result(finding: Finding, index: dict, root: Path, cell: str) -> dict:
    out = {
        "ruleId": finding.rule,
        "ruleIndex": index[finding.rule],
        "level": finding.level,
        "message": {"text": finding.message},
    }
    primary = finding.program or finding.cell
    if primary is not None:
        out["locations"] = [_location(primary, root)]
    related = [(loc, "the hand-edited line") for loc in finding.related]
    if finding.cell is not None and finding.program is not None:
        related.insert(0, (finding.cell, f"the cell file's key {finding.key}"))
    if related:
        out["relatedLocations"] = [
            {"id": i, **_location(loc, root), "message": {"text": text}} for i, (loc, text) in enumerate(related)
        ]
    if cell:
        out["properties"] = {"cell": cell}
    return out


def _location(where: Location, root: Path) -> dict:
    path = relative(where.file, root)
    artifact = {"uri": path, "uriBaseId": ROOT} if path is not None else {"uri": _uri(where.file)}
    physical: dict = {"artifactLocation": artifact}
    if where.line > 0:
        region = {"startLine": where.line}
        if where.column > 0:
            region["startColumn"] = where.column
        physical["region"] = region
    return {"physicalLocation": physical}


def _uri(file: str) -> str:
    if file.startswith("<"):
        return file.strip("<>").replace(">", "")  # a name without a place (verify's <fresh>/...)
    return Path(file).resolve().as_uri()
