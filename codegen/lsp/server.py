"""The language server: checks on open and edit (debounced), hover, outline, definitions, references,
completion, and verify in the background; pygls over stdio."""

from __future__ import annotations

import asyncio
import gc
from concurrent.futures import ThreadPoolExecutor
from importlib.metadata import version
from pathlib import Path

from lsprotocol import types
from pygls.lsp.server import LanguageServer
from pygls.uris import from_fs_path, to_fs_path

from codegen.dialects import dialects
from codegen.dialects.core.kept import STORE
from codegen.lsp import completion, diagnostics, hover, symbols, verifying
from codegen.lsp.cells import find_cell
from codegen.lsp.documents import CELL_SUFFIX, Program, dialect_of, is_cell_file, is_cell_text, program_of
from codegen.lsp.nominal import Move, nominal_moves

DEBOUNCE_S = 0.1  # quiet time after an edit before the file is checked: a burst of keystrokes is checked once
VERIFY = "codegen.verify"
VERIFY_CANCEL = "codegen.verifyCancel"
STATUS = "codegen.status"
WATCHERS = "codegen-files"  # the id of the registration of the files watched on disk


class CodegenServer(LanguageServer):
    """The server's state: the checks waiting or running per file, each file's check and verify diagnostics
    (published together), each program's last whole check (its files' texts and the diagnostics they gave), the
    verify runs per program and the nominal runs' moves per program."""

    def __init__(self) -> None:
        super().__init__("codegen", version("codegen"))
        self.debounce_s = DEBOUNCE_S
        self.verify_cases = verifying.DEFAULT_CASES
        self.cell_file: Path | None = None  # the client's choice of cell (initializationOptions "cell")
        self.edits: dict[str, int] = {}  # path -> how many times it was opened or changed: a stale check is dropped
        self.waiting: dict[str, asyncio.Task] = {}
        self.checked: dict[str, list[types.Diagnostic]] = {}
        # a program (its first file) -> its files' (name, text) at its last whole check, and that check's diagnostics
        self.programs: dict[str, tuple[tuple, dict[str, list[types.Diagnostic]]]] = {}
        self.checks = 0  # whole checks run (a program's unchanged texts are not checked again)
        self.collections = 0  # garbage collections after a check was published
        self.verified: dict[str, list[types.Diagnostic]] = {}
        self.verifies: dict[str, asyncio.Task] = {}
        self.nominal: dict[tuple, list[Move]] = {}
        self.cells: dict[str, Path | None] = {}  # a program folder -> its cell file (None: none found)
        self.worker = ThreadPoolExecutor(1, thread_name_prefix="codegen-check")  # whole checks one at a time, in order
        # a file's syntax, apart: never behind a whole check of an older text
        self.syntax_worker = ThreadPoolExecutor(1, thread_name_prefix="codegen-syntax")

    # --- documents ------------------------------------------------------------------------------------------

    def open_texts(self) -> dict[str, str]:
        return {doc.path: doc.source for doc in self.workspace.text_documents.values() if doc.path}

    def program(self, path: str) -> Program | None:
        return program_of(Path(path), self.open_texts())

    def markup(self, feature: str) -> types.MarkupKind:
        """Markdown where the client says it reads it for hover or completion documentation, else plain text."""
        document = self.client_capabilities.text_document
        if feature == "hover":
            formats = document and document.hover and document.hover.content_format
        else:
            item = document and document.completion and document.completion.completion_item
            formats = item and item.documentation_format
        return types.MarkupKind.Markdown if types.MarkupKind.Markdown in (formats or []) else types.MarkupKind.PlainText

    def roots(self) -> list[Path]:
        folders = [to_fs_path(f.uri) for f in self.workspace.folders.values()]
        return [Path(f) for f in folders if f] or ([Path(self.workspace.root_path)] if self.workspace.root_path else [])

    def publish(self, path: str) -> None:
        found = [*self.checked.get(path, []), *self.verified.get(path, [])]
        self.text_document_publish_diagnostics(
            types.PublishDiagnosticsParams(uri=from_fs_path(path), diagnostics=found)
        )

    # --- checks -------------------------------------------------------------------------------------------------

    def edited(self, uri: str) -> None:
        """Check the file (and its program) once edits stop for debounce_s; a newer edit replaces a waiting check."""
        path = to_fs_path(uri)
        if path is None or (dialect_of(Path(path)) is None and not is_cell_file(Path(path))):
            return
        self.edits[path] = self.edits.get(path, 0) + 1
        if path in self.verified:  # what verify said was of the text before this edit
            self.verified.pop(path)
        waiting = self.waiting.pop(path, None)
        if waiting is not None:
            waiting.cancel()
        self.waiting[path] = asyncio.get_running_loop().create_task(self.check_later(path, self.edits[path]))

    async def check_later(self, path: str, edit: int) -> None:
        await asyncio.sleep(self.debounce_s)
        try:
            await self._check(path, edit)
        except Exception as exc:  # a fault of the checker itself: said where the user looks, not lost in a task
            self.window_log_message(types.LogMessageParams(types.MessageType.Error, f"{path}: check failed: {exc!r}"))
            self.checked[path] = [
                types.Diagnostic(
                    range=types.Range(types.Position(0, 0), types.Position(0, 0)),
                    message=f"codegen's check failed on this file ({type(exc).__name__}: {exc}); please report it",
                    severity=types.DiagnosticSeverity.Error,
                    code="internal",
                    source=diagnostics.SOURCE,
                )
            ]
            self.publish(path)

    async def _check(self, path: str, edit: int) -> None:
        loop = asyncio.get_running_loop()
        if is_cell_file(Path(path)):
            text = self.open_texts().get(path, "")
            if not is_cell_text(text) and not self.checked.get(path):
                return
            found = await loop.run_in_executor(self.worker, diagnostics.cell_diagnostics, text, path)
            if self.edits.get(path) == edit:
                self.checked[path] = found
                self.publish(path)
            return
        # first this file's syntax (fast), with what the last whole check said of the rest, then the whole program's
        text = self.open_texts().get(path)
        dialect = dialect_of(Path(path))
        if text is not None and dialect is not None:
            syntax = await loop.run_in_executor(self.syntax_worker, diagnostics.syntax_findings, dialect, path, text)
            if self.edits.get(path) != edit:
                return
            kept = [d for d in self.checked.get(path, []) if d.code != "syntax"]
            self.checked[path] = [diagnostics.diagnostic(text, f) for f in syntax] + kept
            self.publish(path)
        program = await loop.run_in_executor(self.worker, self.program, path)
        if program is None or self.edits.get(path) != edit:
            return
        texts = tuple((f.name, f.text) for f in program.files)
        last = self.programs.get(program.files[0].name)
        if last is not None and last[0] == texts:  # a save, a file on disk touched: the same texts, the same findings
            found_by_file = last[1]
        else:
            findings = await loop.run_in_executor(self.worker, diagnostics.program_findings, program)
            self.checks += 1
            if self.edits.get(path) != edit:
                return
            found_by_file = diagnostics.by_file(program, findings)
            self.programs[program.files[0].name] = (texts, found_by_file)
        for file, found in found_by_file.items():
            self.checked[file] = found
            self.publish(file)
        if not any(not task.done() for task in self.waiting.values() if task is not asyncio.current_task()):
            await loop.run_in_executor(self.worker, self.collect)

    def collect(self) -> None:
        """Free what the check left (its compiled program's cycles) once its diagnostics are out and no edit waits:
        the collection then does not fall inside the next check."""
        gc.collect()
        self.collections += 1

    def changed_on_disk(self, paths: list[str]) -> None:
        """Files changed on disk (created, changed, deleted): the open files whose program reads them from there
        (a file of the same language in the same folder, not open itself) are checked again; a cell file: the cells
        found for the programs are looked for again."""
        open_texts = self.open_texts()
        dependents = set()
        for path in paths:
            if is_cell_file(Path(path)):
                self.cells.clear()
            dialect = dialect_of(Path(path))
            if dialect is None or path in open_texts:  # the editor's text is the one checked
                continue
            folder = Path(path).parent
            dependents.update(p for p in open_texts if Path(p).parent == folder and dialect_of(Path(p)) is dialect)
        for path in sorted(dependents):
            self.edited(from_fs_path(path))

    def watch_files(self) -> None:
        """Ask the client to report changes on disk of the files the server reads (where it takes such a request)."""
        workspace = self.client_capabilities.workspace
        watched = workspace and workspace.did_change_watched_files
        if not (watched and watched.dynamic_registration):
            return
        suffixes = {s.lstrip(".") for d in dialects().values() for s in (*d.suffixes, *d.companions, *d.configurations)}
        pattern = "**/*.{" + ",".join(sorted(suffixes | {CELL_SUFFIX.lstrip(".")})) + "}"
        watchers = [types.FileSystemWatcher(glob_pattern=pattern)]
        options = types.DidChangeWatchedFilesRegistrationOptions(watchers=watchers)
        registration = types.Registration(WATCHERS, types.WORKSPACE_DID_CHANGE_WATCHED_FILES, options)
        self.client_register_capability(types.RegistrationParams([registration]))

    # --- verify and the nominal run -------------------------------------------------------------------------------

    def cell_of(self, path: str) -> Path | None:
        """The program's cell file: the client's, else the workspace's of its name (looked for once per folder)."""
        if self.cell_file is not None:
            return self.cell_file
        folder = str(Path(path).parent)
        if folder not in self.cells or (self.cells[folder] is not None and not self.cells[folder].is_file()):
            self.cells[folder] = find_cell(Path(path), self.roots())
        return self.cells[folder]

    async def verify(self, path: str) -> str:
        """Verify the program of `path` against its cell in the background (a verify of it already running is
        cancelled first); its mismatches and EDIT lines become diagnostics. Returns what was started."""
        program = self.program(path)
        cell = self.cell_of(path)
        if program is None or cell is None:
            return f"{Path(path).name}: no cell file found whose [cell] name is this program's"
        main = program.files[0].name
        self.cancel_verify(main)
        self.verifies[main] = asyncio.get_running_loop().create_task(self._verify(program, cell))
        return f"verifying {Path(main).name} against {cell}"

    async def _verify(self, program: Program, cell: Path) -> None:
        files = [f.name for f in program.files]
        texts = {f.name: f.text for f in program.files}
        async with self.work_done("verify", f"{Path(files[0]).name} against {cell.name}"):
            result = await verifying.run_verify(cell, files, texts, self.verify_cases)
        for file, found in result.diagnostics.items():
            self.verified[file] = found
            self.publish(file)
        kind = types.MessageType.Info if result.ok else types.MessageType.Warning
        self.window_show_message(types.ShowMessageParams(type=kind, message=result.summary))

    def cancel_verify(self, main: str) -> bool:
        task = self.verifies.pop(main, None)
        if task is None or task.done():
            return False
        task.cancel()
        return True

    def work_done(self, title: str, message: str):
        return _Progress(self, title, message)

    async def moves_at(self, path: str, line: int) -> list[Move]:
        """The nominal run's moves commanded from a 1-based line of the file (the run computed once per program's
        files on disk and cell)."""
        cell = self.cell_of(path)
        program = self.program(path)
        if cell is None or program is None:
            return []
        main = Path(program.files[0].name)
        stamps = tuple(Path(f.name).stat().st_mtime_ns for f in program.files if Path(f.name).is_file())
        key = (str(cell), cell.stat().st_mtime_ns, str(main), stamps)
        if key not in self.nominal:
            loop = asyncio.get_running_loop()
            try:
                self.nominal[key] = await loop.run_in_executor(None, nominal_moves, cell, main)
            except Exception as exc:  # a program or cell that does not load: no pose to show, say why
                self.window_log_message(types.LogMessageParams(types.MessageType.Log, f"nominal run: {exc}"))
                self.nominal[key] = []
        name = Path(path).name
        return [m for m in self.nominal[key] if m.line == line and m.file == name]


class _Progress:
    """A work-done progress shown by the client while verify runs (where the client accepts one)."""

    def __init__(self, server: CodegenServer, title: str, message: str) -> None:
        self.server, self.title, self.message = server, title, message
        self.token = f"codegen-{id(self)}"

    async def __aenter__(self):
        capabilities = self.server.client_capabilities.window
        self.shown = bool(capabilities and capabilities.work_done_progress)
        if self.shown:
            await self.server.work_done_progress.create_async(self.token)
            self.server.work_done_progress.begin(
                self.token, types.WorkDoneProgressBegin(title=self.title, message=self.message, cancellable=False)
            )
        return self

    async def __aexit__(self, *exc) -> None:
        if self.shown:
            self.server.work_done_progress.end(self.token, types.WorkDoneProgressEnd())


server = CodegenServer()


@server.feature(types.INITIALIZE)
def initialize(ls: CodegenServer, params: types.InitializeParams) -> None:
    options = params.initialization_options or {}
    if isinstance(options, dict):
        if options.get("cell"):
            ls.cell_file = Path(options["cell"])
        if isinstance(options.get("debounce"), int | float) and options["debounce"] >= 0:
            ls.debounce_s = float(options["debounce"])
        if isinstance(options.get("verifyCases"), int) and options["verifyCases"] > 0:
            ls.verify_cases = options["verifyCases"]


@server.feature(types.INITIALIZED)
def initialized(ls: CodegenServer, params: types.InitializedParams) -> None:
    ls.watch_files()


@server.feature(types.WORKSPACE_DID_CHANGE_WATCHED_FILES)
def did_change_watched_files(ls: CodegenServer, params: types.DidChangeWatchedFilesParams) -> None:
    ls.changed_on_disk([path for path in (to_fs_path(change.uri) for change in params.changes) if path])


@server.feature(types.TEXT_DOCUMENT_DID_OPEN)
def did_open(ls: CodegenServer, params: types.DidOpenTextDocumentParams) -> None:
    ls.edited(params.text_document.uri)


@server.feature(types.TEXT_DOCUMENT_DID_CHANGE)
def did_change(ls: CodegenServer, params: types.DidChangeTextDocumentParams) -> None:
    ls.edited(params.text_document.uri)


@server.feature(types.TEXT_DOCUMENT_DID_SAVE)
def did_save(ls: CodegenServer, params: types.DidSaveTextDocumentParams) -> None:
    ls.edited(params.text_document.uri)


@server.feature(types.TEXT_DOCUMENT_HOVER)
async def on_hover(ls: CodegenServer, params: types.HoverParams) -> types.Hover | None:
    path = to_fs_path(params.text_document.uri)
    if path is None:
        return None
    position = params.position
    if is_cell_file(Path(path)):
        text = ls.workspace.get_text_document(params.text_document.uri).source
        found = hover.cell_text(text, position.line) if is_cell_text(text) else None
        return None if found is None else hover.shown(found, ls.markup("hover"))
    program = ls.program(path)
    if program is None:
        return None
    parts = []
    moves = await ls.moves_at(path, position.line + 1)
    if moves:
        parts.append(hover.move_text(moves))
    named = hover.symbol_text(program, path, position.line, position.character)
    if named:
        parts.append(named)
    return hover.shown("\n\n---\n\n".join(parts), ls.markup("hover")) if parts else None


def _location(file: str, line: int, column: int, name: str) -> types.Location:
    start = types.Position(line - 1, column - 1)
    return types.Location(from_fs_path(file), types.Range(start, types.Position(line - 1, column - 1 + len(name))))


def _name_at(ls: CodegenServer, uri: str, position: types.Position) -> tuple[Program, str] | None:
    path = to_fs_path(uri)
    program = ls.program(path) if path else None
    if program is None:
        return None
    found = symbols.word_at(program.text_of(path) or "", position.line, position.character)
    return None if found is None else (program, found[0])


@server.feature(types.TEXT_DOCUMENT_DEFINITION)
def on_definition(ls: CodegenServer, params: types.DefinitionParams) -> list[types.Location] | None:
    found = _name_at(ls, params.text_document.uri, params.position)
    if found is None:
        return None
    program, name = found
    return [_location(s.file, s.line, s.column, s.name) for s in symbols.definitions(program, name)] or None


@server.feature(types.TEXT_DOCUMENT_REFERENCES)
def on_references(ls: CodegenServer, params: types.ReferenceParams) -> list[types.Location] | None:
    found = _name_at(ls, params.text_document.uri, params.position)
    if found is None:
        return None
    program, name = found
    uses = symbols.references(program, name)
    if not params.context.include_declaration:
        declared = {(s.file, s.line, s.column) for s in symbols.definitions(program, name)}
        uses = [u for u in uses if u not in declared]
    return [_location(file, line, column, name) for file, line, column in uses] or None


@server.feature(types.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
def on_symbols(ls: CodegenServer, params: types.DocumentSymbolParams) -> list[types.DocumentSymbol] | None:
    path = to_fs_path(params.text_document.uri)
    program = ls.program(path) if path else None
    return None if program is None else symbols.outline(program, path)


@server.feature(types.TEXT_DOCUMENT_COMPLETION, types.CompletionOptions(trigger_characters=["$", "."]))
def on_completion(ls: CodegenServer, params: types.CompletionParams) -> types.CompletionList | None:
    path = to_fs_path(params.text_document.uri)
    if path is None:
        return None
    if is_cell_file(Path(path)):
        text = ls.workspace.get_text_document(params.text_document.uri).source
        kind = ls.markup("completion")
        items = completion.cell_items(text, params.position.line, kind) if is_cell_text(text) else []
        return types.CompletionList(is_incomplete=False, items=items)
    program = ls.program(path)
    if program is None:
        return None
    return types.CompletionList(is_incomplete=False, items=completion.program_items(program))


@server.feature(types.TEXT_DOCUMENT_CODE_ACTION)
def on_code_action(ls: CodegenServer, params: types.CodeActionParams) -> list[types.CodeAction] | None:
    uri = params.text_document.uri
    path = to_fs_path(uri)
    if path is None or dialect_of(Path(path)) is None:
        return None
    actions = [
        types.CodeAction(
            title="Verify against its cell (codegen verify)", command=types.Command("Verify", VERIFY, [uri])
        )
    ]
    running = any(not t.done() for t in ls.verifies.values())
    if running:
        actions.append(
            types.CodeAction(
                title="Cancel the running verify", command=types.Command("Cancel verify", VERIFY_CANCEL, [uri])
            )
        )
    return actions


@server.command(VERIFY)
async def verify_command(ls: CodegenServer, *args) -> str:
    path = to_fs_path(str(args[0])) if args else None
    if path is None:
        return "verify: give the program's URI"
    return await ls.verify(path)


@server.command(VERIFY_CANCEL)
def verify_cancel_command(ls: CodegenServer, *args) -> str:
    path = to_fs_path(str(args[0])) if args else None
    program = ls.program(path) if path else None
    if program is None:
        cancelled = [main for main in list(ls.verifies) if ls.cancel_verify(main)]
    else:
        cancelled = [program.files[0].name] if ls.cancel_verify(program.files[0].name) else []
    return f"cancelled {len(cancelled)} verify run{'s' if len(cancelled) != 1 else ''}"


@server.command(STATUS)
def status_command(ls: CodegenServer, *args) -> dict:
    """What the server holds and has done: parses and parsed_chars (texts parsed, each file or routine once for each
    text it has had), the parse store's trees and their texts' characters, whole checks run, garbage collections after
    publishing."""
    return {
        "parses": STORE.parses,
        "parsed_chars": STORE.parsed_chars,
        "kept": len(STORE.entries),
        "kept_chars": STORE.chars,
        "checks": ls.checks,
        "collections": ls.collections,
    }


def main() -> None:
    """Serve over stdin and stdout: the binary streams beneath codegen's printing door (JSON-RPC escapes every
    control character a program's text may hold, so nothing reaches the client's terminal raw)."""
    import sys

    from codegen.terminal import own_controls

    with STORE.keeping():  # for as long as the server runs: an edit parses what it changed
        server.start_io(sys.stdin.buffer, own_controls(sys.stdout).buffer)
