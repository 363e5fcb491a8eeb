'use strict';
// VS Code client of isotools: for documents of the language `sidac-iso` (.mpf, .spf) it
// starts the language server `isolint --lsp` and talks to it over the child's stdin/stdout.
// Formatting (Format Document, Format Selection, editor.formatOnSave) is the server's too:
// vscode-languageclient registers it for the documents of the selector below.
// Settings: isotools.isolintPath (the executable, default `isolint`) and isotools.machine
// (a machine file passed as `--machine FILE`). Changing either restarts the server.
// The debugger of type `isosim` runs `isosim --dap` (isotools.isosimPath) over stdio: F5 on a
// .mpf without a launch.json dry-runs the file in the editor, stopped at its first block.
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

// The adapter of a debug session: `isosim --dap`, started in the first workspace folder.
function debugAdapterExecutable(config, folder) {
  const command = config.get('isosimPath') || 'isosim';
  return folder ? { command, args: ['--dap'], options: { cwd: folder } } : { command, args: ['--dap'] };
}

// F5 without a launch.json: run the active .mpf; a configuration without a program is refused.
function resolveDebugConfiguration(debugConfig, activeFile) {
  const c = Object.assign({}, debugConfig);
  if (!c.type && !c.request && !c.name) {
    if (!activeFile) return undefined;
    Object.assign(c, { type: 'isosim', request: 'launch', name: 'Dry run', program: activeFile, stopOnEntry: true });
  }
  if (!c.program) return undefined;
  return c;
}

function registerDebugger(context) {
  if (!vscode.debug) return;
  context.subscriptions.push(
    vscode.debug.registerDebugAdapterDescriptorFactory('isosim', {
      createDebugAdapterDescriptor() {
        const config = vscode.workspace.getConfiguration('isotools');
        const folders = vscode.workspace.workspaceFolders;
        const folder = folders && folders.length > 0 ? folders[0].uri.fsPath : undefined;
        const exe = debugAdapterExecutable(config, folder);
        return new vscode.DebugAdapterExecutable(exe.command, exe.args, exe.options);
      },
    }),
    vscode.debug.registerDebugConfigurationProvider('isosim', {
      resolveDebugConfiguration(_folder, debugConfig) {
        const editor = vscode.window.activeTextEditor;
        const active = editor && editor.document.languageId === 'sidac-iso' ? editor.document.uri.fsPath : undefined;
        const c = resolveDebugConfiguration(debugConfig, active);
        if (!c) vscode.window.showErrorMessage('isotools: open a .mpf program, or name one as "program" in launch.json.');
        return c;
      },
    }));
}

function activate(context) {
  registerDebugger(context);
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

module.exports = { activate, deactivate, serverOptions, debugAdapterExecutable, resolveDebugConfiguration };
