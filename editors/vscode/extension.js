// The codegen language server (`codegen lsp`) as a VS Code extension: it starts the server and forwards the
// editor's documents; everything else is the server's (docs/editor.md).
"use strict";

const vscode = require("vscode");
const { LanguageClient } = require("vscode-languageclient/node");

let client;

function serverOptions(config) {
  const python = config.get("interpreter");
  return python ? { command: python, args: ["-m", "codegen", "lsp"] } : { command: "codegen", args: ["lsp"] };
}

function activeUri() {
  const editor = vscode.window.activeTextEditor;
  return editor ? editor.document.uri.toString() : undefined;
}

async function activate(context) {
  const config = vscode.workspace.getConfiguration("codegen");
  const languages = ["krl", "rapid", "urscript", "dtrans"];
  const clientOptions = {
    documentSelector: [
      ...languages.map((language) => ({ scheme: "file", language })),
      { scheme: "file", pattern: "**/*.toml" },
    ],
    initializationOptions: {
      cell: config.get("cell") || undefined,
      verifyCases: config.get("verifyCases"),
      debounce: config.get("debounce"),
    },
  };
  client = new LanguageClient("codegen", "codegen", serverOptions(config), clientOptions);
  // the server's own commands (codegen.verify, codegen.verifyCancel) are registered by the client; these two
  // give them the active editor's document
  context.subscriptions.push(
    vscode.commands.registerCommand("codegen.verifyActive", () =>
      vscode.commands.executeCommand("codegen.verify", activeUri()),
    ),
    vscode.commands.registerCommand("codegen.verifyCancelActive", () =>
      vscode.commands.executeCommand("codegen.verifyCancel", activeUri()),
    ),
  );
  await client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
