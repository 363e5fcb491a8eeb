'use strict';
// VS Code client of isotools: for documents of the language `sidac-iso` (.mpf, .spf) it
// starts the language server `isolint --lsp` and talks to it over the child's stdin/stdout.
// Formatting (Format Document, Format Selection, editor.formatOnSave) is the server's too:
// vscode-languageclient registers it for the documents of the selector below.
// Settings: isotools.isolintPath (the executable, default `isolint`), isotools.machine
// (`--machine FILE`), isotools.settingsFile (`--config FILE`), isotools.dialect (`--dialect`)
// and isotools.cycleTime.* (the server's initializationOptions). Changing any of them, or the
// command isotools.restartServer, restarts the server.
// A status bar item, shown for sidac-iso editors, says whether the server is starting, ready
// or failed, and the cycle time of the active program from the notification isotools/dryRun.
// The debugger of type `isosim` runs `isosim --dap` (isotools.isosimPath) over stdio: F5 on a
// .mpf without a launch.json dry-runs the file in the editor, stopped at its first block.
const path = require('path');
const vscode = require('vscode');
const { LanguageClient, State } = require('vscode-languageclient/node');

const DIALECTS = ['sidac', 'z32'];
// The settings whose change restarts the server.
const RESTART_SETTINGS = [
  'isotools.isolintPath',
  'isotools.machine',
  'isotools.settingsFile',
  'isotools.dialect',
  'isotools.cycleTime.enabled',
  'isotools.cycleTime.budgetSeconds',
  'isotools.cycleTime.inlayHints',
  'isotools.cycleTime.inlayHintsMaxLines',
];

let client;
let outputChannel;
let status; // the status bar item's model, see createStatus
let queue = Promise.resolve(); // restarts run one after the other

// A file setting: an absolute path as it is, a relative one from the first workspace folder.
function fromFolder(file, folder) {
  return !path.isAbsolute(file) && folder ? path.join(folder, file) : file;
}

// The server's command line. `transport` is left unset on purpose: for an executable,
// vscode-languageclient then uses stdio without appending `--stdio` to the arguments.
function serverOptions(config, folder) {
  const command = config.get('isolintPath') || 'isolint';
  const args = ['--lsp'];
  const settingsFile = config.get('settingsFile');
  if (settingsFile) args.push('--config', fromFolder(settingsFile, folder));
  const machine = config.get('machine');
  if (machine) args.push('--machine', fromFolder(machine, folder));
  const dialect = config.get('dialect');
  if (DIALECTS.includes(dialect)) args.push('--dialect', dialect);
  return folder ? { command, args, options: { cwd: folder } } : { command, args };
}

// What the server reads from `initialize`: the cycle-time features (a dry run of the program
// in the background, its time in the status item and as inlay hints).
function initializationOptions(config) {
  const bool = (key, fallback) => {
    const v = config.get(key);
    return typeof v === 'boolean' ? v : fallback;
  };
  const number = (key, fallback, min, max) => {
    const v = config.get(key);
    return typeof v === 'number' && Number.isFinite(v) ? Math.min(Math.max(v, min), max) : fallback;
  };
  return {
    cycleTime: {
      enabled: bool('cycleTime.enabled', true),
      budgetSeconds: number('cycleTime.budgetSeconds', 5, 0.1, 3600),
      inlayHints: bool('cycleTime.inlayHints', true),
      inlayHintsMaxLines: Math.floor(number('cycleTime.inlayHintsMaxLines', 5000, 0, 4294967295)),
    },
  };
}

// The status item's text, tooltip and click for the server's state and the dry run of the
// active document: `server` is {state: 'starting'|'ready'|'error', reason}, `run` the
// isotools/dryRun params shown for the document (or undefined). The server's dry-run states:
// running, ok, error, emergency, failed, over budget, cancelled and none (nothing ran).
function statusView(server, run) {
  if (server.state === 'starting') return { text: 'isolint: starting', tooltip: 'The isolint language server is starting' };
  if (server.state === 'error') {
    return { text: 'isolint: error', tooltip: `isolint: ${server.reason}. Click to show the output.`,
             command: 'isotools.showOutput', error: true };
  }
  const ready = { text: 'isolint: ready', tooltip: 'The isolint language server is running' };
  if (!run) return ready;
  const title = typeof run.title === 'string' ? run.title : '';
  const short = title.split(' · ')[0];
  switch (run.state) {
    case 'running':
      return { text: '$(sync~spin) dry run…', tooltip: 'isolint: dry run of the program for its cycle time' };
    case 'ok':
      return { text: `$(clock) ${short}`, tooltip: `isolint dry run: ${title}` };
    case 'error':
    case 'emergency':
    case 'failed':
      return { text: `$(error) ${short || run.state}`, tooltip: `isolint dry run (${run.state}): ${title}` };
    case 'none':
    case 'cancelled':
      return ready;
    default: // over budget, or a state this extension does not know
      return title ? { text: `$(warning) ${short}`, tooltip: `isolint dry run (${run.state}): ${title}` } : ready;
  }
}

// The status bar item, shown while the active editor holds a sidac-iso document.
function createStatus(context) {
  const alignment = vscode.StatusBarAlignment ? vscode.StatusBarAlignment.Left : 1;
  const item = vscode.window.createStatusBarItem('isotools.status', alignment, 0);
  item.name = 'isolint';
  context.subscriptions.push(item);
  const model = { item, server: { state: 'starting' }, runs: new Map() };
  model.update = () => {
    const editor = vscode.window.activeTextEditor;
    const doc = editor && editor.document;
    const entry = doc ? model.runs.get(doc.uri.toString()) : undefined;
    const view = statusView(model.server, entry && entry.shown);
    item.text = view.text;
    item.tooltip = view.tooltip;
    item.command = view.command;
    item.backgroundColor = view.error && vscode.ThemeColor ? new vscode.ThemeColor('statusBarItem.errorBackground') : undefined;
    if (doc && doc.languageId === 'sidac-iso') item.show();
    else item.hide();
  };
  model.setServer = (state, reason) => {
    model.server = { state, reason };
    model.update();
  };
  model.dryRun = (params) => {
    if (!params || typeof params.uri !== 'string') return;
    const uri = vscode.Uri && vscode.Uri.parse ? vscode.Uri.parse(params.uri).toString() : params.uri;
    // `settled` is the last finished run: a cancelled run (the editor sent something) shows it again
    const entry = model.runs.get(uri) || {};
    const run = { state: params.state, title: params.title };
    if (run.state === 'running') entry.shown = run;
    else if (run.state === 'cancelled') entry.shown = entry.settled;
    else entry.shown = entry.settled = run;
    model.runs.set(uri, entry);
    model.update();
  };
  context.subscriptions.push(vscode.window.onDidChangeActiveTextEditor(() => model.update()));
  if (vscode.workspace.onDidCloseTextDocument) {
    context.subscriptions.push(vscode.workspace.onDidCloseTextDocument((doc) => {
      model.runs.delete(doc.uri.toString());
      model.update();
    }));
  }
  model.update();
  return model;
}

function errorText(err) {
  return err && err.message ? err.message : String(err);
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
    initializationOptions: initializationOptions(config),
    outputChannel,
  };
  const started = new LanguageClient('isotools', 'isolint', server, clientOptions);
  client = started;
  if (status) {
    status.runs.clear();
    status.setServer('starting');
  }
  started.onDidChangeState((event) => {
    // A stop this extension asked for (restart, deactivate) has replaced `client` already.
    if (client !== started || !status) return;
    if (event.newState === State.Running) status.setServer('ready');
    else if (event.newState === State.Starting) status.setServer('starting');
    else if (event.newState === State.Stopped && status.server.state !== 'error') {
      status.setServer('error', 'the language server stopped');
    }
  });
  try {
    await started.start();
  } catch (err) {
    const reason = `could not start "${server.command} --lsp": ${errorText(err)}`;
    if (client === started && status) status.setServer('error', reason);
    vscode.window.showErrorMessage(`isotools: ${reason}. Set isotools.isolintPath to the isolint executable.`);
    return;
  }
  if (client !== started) return;
  started.onNotification('isotools/dryRun', (params) => status && status.dryRun(params));
  if (status) status.setServer('ready');
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

function restartClient() {
  queue = queue.catch(() => {}).then(async () => {
    await stopClient();
    await startClient();
  });
  return queue;
}

function activate(context) {
  registerDebugger(context);
  outputChannel = vscode.window.createOutputChannel('isolint');
  context.subscriptions.push(outputChannel);
  status = createStatus(context);
  context.subscriptions.push(
    vscode.workspace.onDidChangeConfiguration((event) => {
      if (RESTART_SETTINGS.some((key) => event.affectsConfiguration(key))) return restartClient();
      return undefined;
    }),
    vscode.commands.registerCommand('isotools.restartServer', () => restartClient()),
    vscode.commands.registerCommand('isotools.showOutput', () => outputChannel.show(true)));
  queue = startClient();
  return queue;
}

function deactivate() {
  status = undefined;
  return stopClient();
}

module.exports = {
  activate,
  deactivate,
  serverOptions,
  initializationOptions,
  statusView,
  debugAdapterExecutable,
  resolveDebugConfiguration,
};
