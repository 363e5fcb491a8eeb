'use strict';
// VS Code client of isotools: for documents of the language `sidac-iso` (.mpf, .spf) it
// starts the language server `isolint --lsp` and talks to it over the child's stdin/stdout.
// Formatting (Format Document, Format Selection, editor.formatOnSave) is the server's too:
// vscode-languageclient registers it for the documents of the selector below.
// Settings: isotools.isolintPath (the executable, default `isolint`) and isotools.machine
// (a machine file passed as `--machine FILE`). Changing either restarts the server.
const path = require('path');
const vscode = require('vscode');
const { LanguageClient } = require('vscode-languageclient/node');

let client;

// The server's command line. `transport` is left unset on purpose: for an executable,
// vscode-languageclient then uses stdio without appending `--stdio` to the arguments.
function serverOptions(config, folder) {
  const command = config.get('isolintPath') || 'isolint';
  const args = ['--lsp'];
  let machine = config.get('machine');
  if (machine) {
    if (!path.isAbsolute(machine) && folder) machine = path.join(folder, machine);
    args.push('--machine', machine);
  }
  return folder ? { command, args, options: { cwd: folder } } : { command, args };
}

async function startClient() {
  const config = vscode.workspace.getConfiguration('isotools');
  const folders = vscode.workspace.workspaceFolders;
  const folder = folders && folders.length > 0 ? folders[0].uri.fsPath : undefined;
  const server = serverOptions(config, folder);
  const clientOptions = {
    documentSelector: [
      { scheme: 'file', language: 'sidac-iso' },
      { scheme: 'untitled', language: 'sidac-iso' },
    ],
  };
  client = new LanguageClient('isotools', 'isolint', server, clientOptions);
  try {
    await client.start();
  } catch (err) {
    vscode.window.showErrorMessage(
      `isotools: could not start "${server.command} --lsp": ${err && err.message ? err.message : err}. ` +
        'Set isotools.isolintPath to the isolint executable.');
  }
}

async function stopClient() {
  const running = client;
  client = undefined;
  if (running) {
    try {
      await running.stop();
    } catch (_) {
      // never started (isolint missing) or already gone: nothing to stop
    }
  }
}

function activate(context) {
  context.subscriptions.push(
    vscode.workspace.onDidChangeConfiguration(async (event) => {
      if (event.affectsConfiguration('isotools.isolintPath') || event.affectsConfiguration('isotools.machine')) {
        await stopClient();
        await startClient();
      }
    }));
  return startClient();
}

function deactivate() {
  return stopClient();
}

module.exports = { activate, deactivate, serverOptions };
