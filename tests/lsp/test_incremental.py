"""The language server's check on each edit, driven through its protocol: what it parses again (one KRL routine), what
it does not check again (an unchanged program), files changed on disk, the garbage collected after publishing, and the
suffixes beside codegen's own (a KRL .sub, a .urscript)."""

from __future__ import annotations

import asyncio
import re
import shutil
import sys
from pathlib import Path

import pytest
import pytest_lsp
from lsprotocol import types
from pytest_lsp import ClientServerConfig, LanguageClient

ROOT = Path(__file__).resolve().parents[2]
GENERATED = ROOT / "generated" / "agv_machine_tending"
CHECK_S = 60  # the first check imports the checker and builds the parser: seconds on a loaded machine
GOOD, BAD = "  VIS_STOPPED = FALSE", "  VIS_STOPED = FALSE"  # a line of the main routine of the generated .src
DEF_LINE = re.compile(r"^\s*(GLOBAL\s+)?(DEF|DEFFCT|DEFDAT)\b", re.IGNORECASE)  # where a KRL routine starts

pytestmark = pytest.mark.asyncio(loop_scope="module")


@pytest.fixture(scope="module")
def workspace(tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("lsp-incremental")
    for target in ("kuka", "ur"):
        shutil.copytree(GENERATED / target, root / target)
    return root


@pytest_lsp.fixture(
    config=ClientServerConfig(server_command=[sys.executable, "-m", "codegen", "lsp"]),
    scope="module",
)
async def client(lsp_client: LanguageClient, workspace: Path):
    lsp_client.registrations = []

    @lsp_client.feature(types.CLIENT_REGISTER_CAPABILITY)
    def registered(params: types.RegistrationParams) -> None:
        lsp_client.registrations.extend(params.registrations)

    params = types.InitializeParams(
        capabilities=types.ClientCapabilities(
            workspace=types.WorkspaceClientCapabilities(
                did_change_watched_files=types.DidChangeWatchedFilesClientCapabilities(dynamic_registration=True)
            )
        ),
        root_uri=workspace.as_uri(),
        workspace_folders=[types.WorkspaceFolder(uri=workspace.as_uri(), name="programs")],
        initialization_options={"debounce": 0.05},
    )
    await lsp_client.initialize_session(params)
    yield
    await lsp_client.shutdown_session()


async def _diagnostics_of(client: LanguageClient, uri: str, settled) -> list[types.Diagnostic]:
    async def wait():
        while True:
            await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
            found = client.diagnostics.get(uri)
            if found is not None and settled(found):
                return found

    return await asyncio.wait_for(wait(), CHECK_S)


async def _status(client: LanguageClient) -> dict:
    return await client.workspace_execute_command_async(types.ExecuteCommandParams(command="codegen.status"))


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


def _undefined(found) -> bool:
    return any(d.code == "undefined-name" for d in found)


async def _settled(client: LanguageClient, uri: str, settled) -> list[types.Diagnostic]:
    """The diagnostics once settled and the server has collected after publishing them (its last step of a check)."""
    found = await _diagnostics_of(client, uri, settled)
    before = (await _status(client))["collections"]
    for _ in range(100):
        if (await _status(client))["collections"] > before:
            break
        await asyncio.sleep(0.05)
    return found


async def test_an_edit_in_a_routine_parses_that_routine_again_not_the_file(client: LanguageClient, workspace: Path):
    src = workspace / "kuka" / "agv_machine_tending.src"
    text = src.read_text(encoding="utf-8")
    lines = text.split("\n")
    row = lines.index(GOOD)
    first = max(i for i in range(row + 1) if DEF_LINE.match(lines[i]))  # the edited routine: its DEF ...
    after = next((i for i in range(row, len(lines)) if DEF_LINE.match(lines[i])), len(lines))  # ... to the next
    routine = "\n".join(lines[first:after])
    assert len(routine) < len(text) / 2  # the file has more than this routine

    uri = _open(client, src, text, "krl")
    await _settled(client, uri, lambda found: not found)
    before = await _status(client)
    _replace_all(client, uri, text.replace(GOOD, BAD, 1), 2)
    await _settled(client, uri, _undefined)
    after_edit = await _status(client)
    # what was parsed: the routine's text (after as many line ends as the file has before it), nothing else
    parsed = after_edit["parsed_chars"] - before["parsed_chars"]
    assert 0 < parsed <= first + len(routine) + 1
    assert after_edit["checks"] == before["checks"] + 1

    _replace_all(client, uri, text, 3)
    await _settled(client, uri, lambda found: not found)
    back = await _status(client)
    assert back["parsed_chars"] == after_edit["parsed_chars"]  # the text before the edit: kept, not parsed again


async def test_an_unchanged_program_is_not_checked_again(client: LanguageClient, workspace: Path):
    src = workspace / "kuka" / "agv_machine_tending.src"
    text = src.read_text(encoding="utf-8").replace(GOOD, BAD, 1)
    uri = _open(client, src, text, "krl")
    await _settled(client, uri, _undefined)
    before = await _status(client)
    client.diagnostics.pop(uri, None)
    client.text_document_did_save(types.DidSaveTextDocumentParams(types.TextDocumentIdentifier(uri)))
    found = await _settled(client, uri, _undefined)  # published again, the same
    assert [d.code for d in found if d.code != "syntax"] == ["undefined-name"]
    assert (await _status(client))["checks"] == before["checks"]


async def test_garbage_is_collected_after_publishing(client: LanguageClient, workspace: Path):
    src = workspace / "kuka" / "agv_machine_tending.src"
    text = src.read_text(encoding="utf-8")
    uri = _open(client, src, text, "krl")
    await _settled(client, uri, lambda found: not found)
    before = (await _status(client))["collections"]
    _replace_all(client, uri, text.replace(GOOD, BAD, 1), 2)
    await _diagnostics_of(client, uri, _undefined)
    for _ in range(200):
        if (await _status(client))["collections"] > before:
            break
        await asyncio.sleep(0.05)
    assert (await _status(client))["collections"] == before + 1


async def test_a_data_list_changed_on_disk_checks_its_program_again(client: LanguageClient, workspace: Path):
    for _ in range(CHECK_S * 20):  # the server asks once the session is initialized
        if client.registrations:
            break
        await asyncio.sleep(0.05)
    (watched,) = [r for r in client.registrations if r.method == types.WORKSPACE_DID_CHANGE_WATCHED_FILES]
    pattern = watched.register_options["watchers"][0]["globPattern"]
    for suffix in ("src", "sub", "dat", "mod", "script", "urscript", "toml"):
        assert re.search(rf"[{{,]{suffix}[,}}]", pattern), (suffix, pattern)

    src = workspace / "kuka" / "agv_machine_tending.src"
    dat = src.with_suffix(".dat")
    declared = dat.read_text(encoding="utf-8")
    line = next(x for x in declared.split("\n") if x.startswith("DECL BOOL VIS_STOPPED"))
    uri = _open(client, src, src.read_text(encoding="utf-8"), "krl")
    await _settled(client, uri, lambda found: not found)
    try:
        dat.write_text(declared.replace(line + "\n", "", 1), encoding="utf-8")  # the .src's VIS_STOPPED: undeclared
        client.diagnostics.pop(uri, None)
        change = types.FileEvent(uri=dat.as_uri(), type=types.FileChangeType.Changed)
        client.workspace_did_change_watched_files(types.DidChangeWatchedFilesParams(changes=[change]))
        found = await _settled(client, uri, _undefined)
        assert all("VIS_STOPPED" in d.message for d in found if d.code == "undefined-name")
    finally:
        dat.write_text(declared, encoding="utf-8")
    client.diagnostics.pop(uri, None)
    change = types.FileEvent(uri=dat.as_uri(), type=types.FileChangeType.Changed)
    client.workspace_did_change_watched_files(types.DidChangeWatchedFilesParams(changes=[change]))
    assert not await _settled(client, uri, lambda found: not found)


SUB = "DEF SPS()\n  DECL INT TICKS\n  TICKS = 0\n  LOOP\n    TICKS = TICKS + 1\n    $OUT[1] = $IN[1]\n  ENDLOOP\nEND\n"


async def test_a_submit_interpreter_file_is_checked_as_krl(client: LanguageClient, workspace: Path):
    folder = workspace / "submit"
    folder.mkdir(exist_ok=True)
    (folder / "sps.dat").write_text("DEFDAT SPS\nENDDAT\n", encoding="utf-8")
    sub = folder / "sps.sub"
    sub.write_text(SUB, encoding="utf-8")
    uri = _open(client, sub, SUB.replace("TICKS + 1", "TICKZ + 1"), "krl")
    found = await _settled(client, uri, _undefined)
    (diagnostic,) = [d for d in found if d.code == "undefined-name"]
    assert diagnostic.range == types.Range(types.Position(4, 12), types.Position(4, 17))
    _replace_all(client, uri, SUB, 2)
    assert not await _settled(client, uri, lambda found: not found)


async def test_a_urscript_file_is_checked(client: LanguageClient, workspace: Path):
    script = workspace / "ur" / "agv_machine_tending.script"
    copy = workspace / "urscript" / "agv_machine_tending.urscript"
    copy.parent.mkdir(exist_ok=True)
    text = script.read_text(encoding="utf-8")
    copy.write_text(text, encoding="utf-8")
    broken = text.replace("textmsg(message)", "textmsg(mesage)", 1)
    row = next(i for i, line in enumerate(broken.split("\n")) if "textmsg(mesage)" in line)
    uri = _open(client, copy, broken, "urscript")
    found = await _settled(client, uri, _undefined)
    (diagnostic,) = [d for d in found if d.code == "undefined-name"]
    assert diagnostic.range.start.line == row
