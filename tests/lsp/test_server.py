"""The language server driven through its protocol, as an editor drives it: one server for the module, a copy of a
generated KRL program and of its cell in a folder of their own."""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import ClientServerConfig, LanguageClient

ROOT = Path(__file__).resolve().parents[2]
GENERATED = ROOT / "generated" / "agv_machine_tending" / "kuka"
CELL = ROOT / "codegen" / "examples" / "agv_machine_tending.toml"
CHECK_S = 60  # the first check imports the checker and builds the KRL parser: seconds on a loaded machine

pytestmark = pytest.mark.asyncio(loop_scope="module")


@pytest.fixture(scope="module")
def workspace(tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("lsp")
    programs = root / "generated" / "agv_machine_tending" / "kuka"
    programs.mkdir(parents=True)
    for f in GENERATED.iterdir():
        shutil.copy(f, programs / f.name)
    shutil.copy(CELL, root / CELL.name)
    return root


@pytest_lsp.fixture(
    config=ClientServerConfig(server_command=[sys.executable, "-m", "codegen", "lsp"]),
    scope="module",
)
async def client(lsp_client: LanguageClient, workspace: Path):
    params = types.InitializeParams(
        capabilities=types.ClientCapabilities(
            window=types.WindowClientCapabilities(work_done_progress=True),
            text_document=types.TextDocumentClientCapabilities(
                hover=types.HoverClientCapabilities(content_format=[types.MarkupKind.Markdown]),
                completion=types.CompletionClientCapabilities(
                    completion_item=types.ClientCompletionItemOptions(documentation_format=[types.MarkupKind.Markdown])
                ),
            ),
        ),
        root_uri=workspace.as_uri(),
        workspace_folders=[types.WorkspaceFolder(uri=workspace.as_uri(), name="cells")],
        initialization_options={"debounce": 0.05, "verifyCases": 1},
    )
    await lsp_client.initialize_session(params)
    yield
    await lsp_client.shutdown_session()


def _src(workspace: Path) -> Path:
    return workspace / "generated" / "agv_machine_tending" / "kuka" / "agv_machine_tending.src"


async def _diagnostics_of(client: LanguageClient, uri: str, settled=lambda found: True) -> list[types.Diagnostic]:
    """The diagnostics published for uri once `settled` holds (the whole program's check follows the fast syntax
    check of the file)."""
    import asyncio

    async def wait():
        while True:
            await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
            found = client.diagnostics.get(uri)
            if found is not None and settled(found):
                return found

    return await asyncio.wait_for(wait(), CHECK_S)


def _open(client: LanguageClient, path: Path, text: str, language: str) -> str:
    uri = path.as_uri()
    client.diagnostics.pop(uri, None)
    item = types.TextDocumentItem(uri=uri, language_id=language, version=1, text=text)
    client.text_document_did_open(types.DidOpenTextDocumentParams(text_document=item))
    return uri


def _replace_all(client: LanguageClient, uri: str, text: str, version: int) -> None:
    client.diagnostics.pop(uri, None)
    change = types.TextDocumentContentChangeWholeDocument(text=text)
    document = types.VersionedTextDocumentIdentifier(uri=uri, version=version)
    client.text_document_did_change(types.DidChangeTextDocumentParams(text_document=document, content_changes=[change]))


async def test_undefined_name_at_its_range_then_gone(client: LanguageClient, workspace: Path):
    text = _src(workspace).read_text(encoding="utf-8")
    good = "  VIS_STOPPED = FALSE"
    assert good in text.split("\n")
    broken = text.replace(good, "  VIS_STOPED = FALSE", 1)
    row = broken.split("\n").index("  VIS_STOPED = FALSE")
    uri = _open(client, _src(workspace), broken, "krl")
    found = await _diagnostics_of(client, uri, lambda found: any(d.code == "undefined-name" for d in found))
    (diagnostic,) = [d for d in found if d.code == "undefined-name"]
    assert diagnostic.severity == types.DiagnosticSeverity.Error
    assert "VIS_STOPED" in diagnostic.message
    assert diagnostic.range == types.Range(types.Position(row, 2), types.Position(row, 2 + len("VIS_STOPED")))

    _replace_all(client, uri, text, 2)
    assert list(await _diagnostics_of(client, uri, lambda found: not found)) == []


async def test_syntax_error_of_an_edit_at_its_line(client: LanguageClient, workspace: Path):
    text = _src(workspace).read_text(encoding="utf-8")
    lines = text.split("\n")
    row = lines.index("  VIS_STOPPED = FALSE")
    lines[row] = "  VIS_STOPPED = = FALSE"
    uri = _open(client, _src(workspace), text, "krl")
    _replace_all(client, uri, "\n".join(lines), 3)
    found = await _diagnostics_of(client, uri, lambda found: any(d.code == "syntax" for d in found))
    assert [d.range.start.line for d in found if d.code == "syntax"] == [row]
    _replace_all(client, uri, text, 4)
    assert list(await _diagnostics_of(client, uri, lambda found: not found)) == []


async def test_definition_of_a_src_name_is_in_the_dat(client: LanguageClient, workspace: Path):
    src = _src(workspace)
    text = src.read_text(encoding="utf-8")
    row = text.split("\n").index("  SWITCH VIS_STATION")
    _open(client, src, text, "krl")
    result = await client.text_document_definition_async(
        types.DefinitionParams(
            text_document=types.TextDocumentIdentifier(uri=src.as_uri()), position=types.Position(row, 12)
        )
    )
    dat = src.with_suffix(".dat")
    declared = dat.read_text(encoding="utf-8").split("\n")
    dat_row = next(i for i, line in enumerate(declared) if line.startswith("DECL INT VIS_STATION"))
    assert result is not None and len(result) == 1
    assert result[0].uri == dat.as_uri()
    assert result[0].range.start == types.Position(dat_row, declared[dat_row].index("VIS_STATION"))

    uses = await client.text_document_references_async(
        types.ReferenceParams(
            text_document=types.TextDocumentIdentifier(uri=src.as_uri()),
            position=types.Position(row, 12),
            context=types.ReferenceContext(include_declaration=True),
        )
    )
    in_code = [
        (path, i)
        for path in (src, dat)
        for i, line in enumerate(path.read_text(encoding="utf-8").split("\n"))
        if "VIS_STATION" in line.split(";")[0].upper()
    ]
    assert sorted((u.uri, u.range.start.line) for u in uses) == sorted((p.as_uri(), i) for p, i in in_code)


async def test_hover_on_the_home_move_shows_the_cell_home_joints(client: LanguageClient, workspace: Path):
    src = _src(workspace)
    text = src.read_text(encoding="utf-8")
    row = text.split("\n").index("  PTP VIS_HOME")
    _open(client, src, text, "krl")
    hover = await client.text_document_hover_async(
        types.HoverParams(text_document=types.TextDocumentIdentifier(uri=src.as_uri()), position=types.Position(row, 2))
    )
    assert hover is not None
    # the cell's [cell.robot] home for kuka: where the arm stands after the program's first move
    assert "joints (deg): `0.00 -90.00 90.00 0.00 90.00 30.00`" in hover.contents.value
    assert "joint move" in hover.contents.value


async def test_hover_on_a_name_shows_its_declaration(client: LanguageClient, workspace: Path):
    src = _src(workspace)
    text = src.read_text(encoding="utf-8")
    row = text.split("\n").index("  SWITCH VIS_STATION")
    _open(client, src, text, "krl")
    hover = await client.text_document_hover_async(
        types.HoverParams(
            text_document=types.TextDocumentIdentifier(uri=src.as_uri()), position=types.Position(row, 14)
        )
    )
    assert hover is not None
    assert "DECL INT VIS_STATION=0" in hover.contents.value
    assert "agv_machine_tending.dat:" in hover.contents.value


async def test_outline_lists_the_routines(client: LanguageClient, workspace: Path):
    src = _src(workspace)
    text = src.read_text(encoding="utf-8")
    _open(client, src, text, "krl")
    found = await client.text_document_document_symbol_async(
        types.DocumentSymbolParams(text_document=types.TextDocumentIdentifier(uri=src.as_uri()))
    )
    names = {s.name for s in found if s.kind == types.SymbolKind.Function}
    heads = [line for line in text.split("\n") if line.lstrip().startswith(("DEF ", "GLOBAL DEF "))]
    declared = {line.split("(")[0].split()[-1] for line in heads}
    assert declared and names >= declared


async def test_cell_with_a_typo_key(client: LanguageClient, workspace: Path):
    cell = workspace / CELL.name
    text = cell.read_text(encoding="utf-8")
    assert "\nmax_shift_mm = " in text
    broken = text.replace("\nmax_shift_mm = ", "\nmax_shft_mm = ", 1)
    row = broken.split("\n").index(next(line for line in broken.split("\n") if line.startswith("max_shft_mm")))
    uri = _open(client, cell, broken, "toml")
    found = await _diagnostics_of(client, uri, lambda found: bool(found))
    assert len(found) == 1
    assert found[0].range.start == types.Position(row, 0)
    assert found[0].range.end == types.Position(row, len("max_shft_mm"))
    assert "max_shft_mm" in found[0].message and "unknown key" in found[0].message

    _replace_all(client, uri, text, 2)
    assert list(await _diagnostics_of(client, uri, lambda found: not found)) == []


async def test_hover_and_completion_of_cell_keys(client: LanguageClient, workspace: Path):
    cell = workspace / CELL.name
    text = cell.read_text(encoding="utf-8")
    lines = text.split("\n")
    row = next(i for i, line in enumerate(lines) if line.startswith("max_shift_mm"))
    uri = _open(client, cell, text, "toml")
    hover = await client.text_document_hover_async(
        types.HoverParams(text_document=types.TextDocumentIdentifier(uri=uri), position=types.Position(row, 3))
    )
    assert hover is not None
    assert "cell.limits.max_shift_mm" in hover.contents.value and "unit: mm" in hover.contents.value

    # a new line at the end of [cell.tool]: the keys its published schema lists that the table does not write
    tool = next(i for i, line in enumerate(lines) if line.startswith("[cell.tool]"))
    last = tool + 1
    while last < len(lines) and "=" in lines[last]:
        last += 1
    written = {line.split("=")[0].strip() for line in lines[tool + 1 : last]}
    lines.insert(last, "")
    _replace_all(client, uri, "\n".join(lines), 2)
    items = await client.text_document_completion_async(
        types.CompletionParams(text_document=types.TextDocumentIdentifier(uri=uri), position=types.Position(last, 0))
    )
    schema = json.loads((ROOT / "codegen" / "examples" / "cell.schema.json").read_text(encoding="utf-8"))
    keys = set(schema["properties"]["cell"]["properties"]["tool"]["properties"])
    assert written and written < keys
    assert {item.label for item in items.items} == keys - written


async def test_completion_offers_the_controller_builtins(client: LanguageClient, workspace: Path):
    src = _src(workspace)
    text = src.read_text(encoding="utf-8")
    uri = _open(client, src, text, "krl")
    items = await client.text_document_completion_async(
        types.CompletionParams(text_document=types.TextDocumentIdentifier(uri=uri), position=types.Position(26, 2))
    )
    labels = {item.label for item in items.items}
    # KSS 8 built-ins (programming manual: SIN, ATAN2, ABS) and the program's own routines
    assert {"SIN", "ATAN2", "ABS"} <= labels
    assert "VIS_GRIPPER_START" in labels


def _edited_copy(workspace: Path, folder: str) -> Path:
    """A copy of the program in a folder of its own, with its blending zone changed on disk (verify reads files)."""
    programs = workspace / folder / "agv_machine_tending" / "kuka"
    programs.mkdir(parents=True, exist_ok=True)
    for f in GENERATED.iterdir():
        shutil.copy(f, programs / f.name)
    src = programs / "agv_machine_tending.src"
    text = src.read_text(encoding="utf-8")
    assert "$APO.CDIS = 10.0" in text
    src.write_text(text.replace("$APO.CDIS = 10.0", "$APO.CDIS = 20.0", 1), encoding="utf-8")
    return src


def _running(path: Path) -> list[str]:
    """The command lines of processes that name the path (Linux /proc)."""
    out = []
    for cmdline in Path("/proc").glob("[0-9]*/cmdline"):
        try:
            text = cmdline.read_bytes().replace(b"\0", b" ").decode(errors="replace")
        except OSError:
            continue
        if str(path) in text and " verify " in text:
            out.append(text)
    return out


async def test_verify_is_cancelled_with_its_process(client: LanguageClient, workspace: Path):
    import asyncio

    src = _edited_copy(workspace, "cancelled")
    started = await client.workspace_execute_command_async(
        types.ExecuteCommandParams(command="codegen.verify", arguments=[src.as_uri()])
    )
    assert started.startswith("verifying agv_machine_tending.src against")
    for _ in range(100):  # the child process starts
        if _running(src):
            break
        await asyncio.sleep(0.05)
    assert _running(src)
    said = await client.workspace_execute_command_async(
        types.ExecuteCommandParams(command="codegen.verifyCancel", arguments=[src.as_uri()])
    )
    assert said == "cancelled 1 verify run"
    for _ in range(100):
        if not _running(src):
            break
        await asyncio.sleep(0.05)
    assert _running(src) == []
    # the client was shown verify's progress, begun and, once cancelled, ended
    token = next(reversed(client.progress_reports))
    for _ in range(100):
        if len(client.progress_reports[token]) > 1:
            break
        await asyncio.sleep(0.05)
    kinds = [type(value).__name__ for value in client.progress_reports[token]]
    assert kinds == ["WorkDoneProgressBegin", "WorkDoneProgressEnd"]


@pytest.mark.slow
async def test_verify_shows_the_edit_and_its_mismatches(client: LanguageClient, workspace: Path):
    src = _edited_copy(workspace, "verified")
    lines = src.read_text(encoding="utf-8").split("\n")
    row = next(i for i, line in enumerate(lines) if "$APO.CDIS = 20.0" in line)
    uri = src.as_uri()
    client.diagnostics.pop(uri, None)
    await client.workspace_execute_command_async(types.ExecuteCommandParams(command="codegen.verify", arguments=[uri]))
    found = await _diagnostics_of(client, uri, lambda found: any(str(d.code).startswith("verify") for d in found))
    edits = [d for d in found if d.code == "verify-edit" and "changed" in d.message]
    assert [d.range.start.line for d in edits] == [row]
    mismatches = [d for d in found if d.code == "verify-mismatch"]
    assert mismatches
    # a zone of 20 mm where the cell says 10: each mismatch is of a move, at its motion statement
    assert all(lines[d.range.start.line].split()[0] in ("LIN", "PTP", "CIRC") for d in mismatches)


@pytest.mark.parametrize(
    ("target", "file", "language", "good", "bad"),
    [
        ("abb", "agv_machine_tending.mod", "rapid", "TEST vis_station", "TEST vis_statoin"),
        ("ur", "agv_machine_tending.script", "urscript", "textmsg(message)", "textmsg(mesage)"),
    ],
)
async def test_an_undefined_name_in_rapid_and_urscript(client, workspace, target, file, language, good, bad):
    path = workspace / "generated" / "agv_machine_tending" / target / file
    path.parent.mkdir(parents=True, exist_ok=True)
    shutil.copy(ROOT / "generated" / "agv_machine_tending" / target / file, path)
    text = path.read_text(encoding="utf-8")
    broken = text.replace(good, bad, 1)
    row = next(i for i, line in enumerate(broken.split("\n")) if bad in line)
    name = bad.split("(")[-1].split()[-1].rstrip(")")
    column = broken.split("\n")[row].index(name)
    uri = _open(client, path, broken, language)
    found = await _diagnostics_of(client, uri, lambda found: any(d.code == "undefined-name" for d in found))
    (diagnostic,) = [d for d in found if d.code == "undefined-name"]
    assert diagnostic.range == types.Range(types.Position(row, column), types.Position(row, column + len(name)))


async def test_a_urscript_variable_is_defined_where_it_is_first_assigned(client: LanguageClient, workspace: Path):
    path = workspace / "generated" / "agv_machine_tending" / "ur" / "agv_machine_tending.script"
    path.parent.mkdir(parents=True, exist_ok=True)
    shutil.copy(ROOT / "generated" / "agv_machine_tending" / "ur" / path.name, path)
    lines = path.read_text(encoding="utf-8").split("\n")
    first = next(i for i, line in enumerate(lines) if line.strip().startswith("vis_x = "))
    used = next(i for i, line in enumerate(lines) if i > first and "vis_x" in line.split("#")[0])
    uri = _open(client, path, "\n".join(lines), "urscript")
    found = await client.text_document_definition_async(
        types.DefinitionParams(
            text_document=types.TextDocumentIdentifier(uri=uri),
            position=types.Position(used, lines[used].index("vis_x") + 1),
        )
    )
    assert [(d.uri, d.range.start) for d in found] == [(uri, types.Position(first, lines[first].index("vis_x")))]
