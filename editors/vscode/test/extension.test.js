'use strict';
// The client without VS Code: `vscode` and `vscode-languageclient/node` are replaced by fakes,
// and the test checks the server command line and initializationOptions, the restart on a
// settings change and by command, and the status bar item.
const { describe, it, beforeEach } = require('node:test');
const assert = require('node:assert/strict');
const Module = require('node:module');
const path = require('node:path');

const FOLDER = path.resolve('/work/project');
const settings = {};
const created = [];
const commands = {};
const statusItems = [];
const State = { Stopped: 1, Running: 2, Starting: 3 };
let configListener;
let editorListener;
let closeListener;
let failStart; // the error the next client's start() rejects with
let outputShown = 0;

class FakeLanguageClient {
  constructor(id, name, serverOptions, clientOptions) {
    Object.assign(this, { id, name, serverOptions, clientOptions, started: false, stopped: false });
    this.stateListeners = [];
    this.notifications = {};
    this.failWith = failStart;
    failStart = undefined;
    created.push(this);
  }
  onDidChangeState(listener) {
    this.stateListeners.push(listener);
    return { dispose() {} };
  }
  setState(newState) {
    for (const l of this.stateListeners) l({ oldState: State.Running, newState });
  }
  onNotification(method, handler) {
    this.notifications[method] = handler;
    return { dispose() {} };
  }
  async start() {
    this.setState(State.Starting);
    this.statusWhileStarting = statusItems[statusItems.length - 1].text;
    if (this.failWith) {
      this.setState(State.Stopped);
      throw this.failWith;
    }
    this.started = true;
    this.setState(State.Running);
  }
  async stop() {
    this.stopped = true;
    this.setState(State.Stopped);
  }
}

class FakeStatusBarItem {
  constructor(id, alignment, priority) {
    Object.assign(this, { id, alignment, priority, text: '', visible: false });
    statusItems.push(this);
  }
  show() { this.visible = true; }
  hide() { this.visible = false; }
  dispose() {}
}

const editor = (file, languageId = 'sidac-iso') => ({
  document: { languageId, uri: { fsPath: file, toString: () => `file://${file}` } },
});

const fakeVscode = {
  workspace: {
    workspaceFolders: [{ uri: { fsPath: FOLDER } }],
    getConfiguration: (section) => {
      assert.equal(section, 'isotools');
      return { get: (key) => settings[key] };
    },
    onDidChangeConfiguration: (listener) => {
      configListener = listener;
      return { dispose() {} };
    },
    onDidCloseTextDocument: (listener) => {
      closeListener = listener;
      return { dispose() {} };
    },
  },
  window: {
    showErrorMessage: () => {},
    activeTextEditor: undefined,
    createStatusBarItem: (id, alignment, priority) => new FakeStatusBarItem(id, alignment, priority),
    createOutputChannel: (name) => ({ name, show() { outputShown++; }, dispose() {} }),
    onDidChangeActiveTextEditor: (listener) => {
      editorListener = listener;
      return { dispose() {} };
    },
  },
  commands: {
    registerCommand: (id, fn) => {
      commands[id] = fn;
      return { dispose() {} };
    },
  },
  StatusBarAlignment: { Left: 1, Right: 2 },
  debug: {
    registerDebugAdapterDescriptorFactory: (type, factory) => {
      debugFactories[type] = factory;
      return { dispose() {} };
    },
    registerDebugConfigurationProvider: (type, provider) => {
      debugProviders[type] = provider;
      return { dispose() {} };
    },
  },
  DebugAdapterExecutable: class {
    constructor(command, args, options) {
      Object.assign(this, { command, args, options });
    }
  },
};
const debugFactories = {};
const debugProviders = {};

const originalLoad = Module._load;
Module._load = function load(request, parent, isMain) {
  if (request === 'vscode') return fakeVscode;
  if (request === 'vscode-languageclient/node') return { LanguageClient: FakeLanguageClient, State };
  return originalLoad.call(this, request, parent, isMain);
};
const extension = require('../src/extension.js');
Module._load = originalLoad;

describe('src/extension.js', () => {
  beforeEach(() => {
    created.length = 0;
    statusItems.length = 0;
    for (const k of Object.keys(settings)) delete settings[k];
    fakeVscode.window.activeTextEditor = undefined;
    failStart = undefined;
    outputShown = 0;
  });

  it('starts "isolint --lsp" over stdio for sidac-iso documents', async () => {
    const context = { subscriptions: [] };
    await extension.activate(context);
    assert.equal(created.length, 1);
    const client = created[0];
    assert.ok(client.started);
    assert.equal(client.serverOptions.command, 'isolint');
    assert.deepEqual(client.serverOptions.args, ['--lsp']);
    assert.equal(client.serverOptions.transport, undefined, 'no transport: stdio without an added --stdio');
    assert.ok(client.clientOptions.documentSelector.every((s) => s.language === 'sidac-iso'));
    // the debugger's factory and provider, the output channel, the status item and its editor and
    // close listeners, the settings listener and the two commands
    assert.equal(context.subscriptions.length, 9);
    await extension.deactivate();
    assert.ok(client.stopped);
  });

  it('uses isotools.isolintPath and passes isotools.machine as --machine', async () => {
    settings.isolintPath = '/opt/isotools/bin/isolint';
    settings.machine = 'machines/banco.json';
    await extension.activate({ subscriptions: [] });
    const { command, args } = created[0].serverOptions;
    assert.equal(command, '/opt/isotools/bin/isolint');
    assert.deepEqual(args, ['--lsp', '--machine', path.join(FOLDER, 'machines/banco.json')]);
    await extension.deactivate();
  });

  it('restarts the server when a setting of isotools changes', async () => {
    await extension.activate({ subscriptions: [] });
    settings.machine = path.resolve('/abs/machine.json');
    await configListener({ affectsConfiguration: (key) => key === 'isotools.machine' });
    assert.equal(created.length, 2);
    assert.ok(created[0].stopped);
    assert.deepEqual(created[1].serverOptions.args, ['--lsp', '--machine', path.resolve('/abs/machine.json')]);
    await configListener({ affectsConfiguration: () => false });
    assert.equal(created.length, 2, 'other settings do not restart it');
    await extension.deactivate();
  });

  it('passes isotools.settingsFile as --config (from the first workspace folder) and isotools.dialect as --dialect', async () => {
    settings.settingsFile = 'cfg/isotools.toml';
    settings.machine = 'machines/banco.json';
    settings.dialect = 'z32';
    await extension.activate({ subscriptions: [] });
    assert.deepEqual(created[0].serverOptions.args, [
      '--lsp',
      '--config', path.join(FOLDER, 'cfg/isotools.toml'),
      '--machine', path.join(FOLDER, 'machines/banco.json'),
      '--dialect', 'z32',
    ]);
    assert.equal(created[0].serverOptions.options.cwd, FOLDER);
    await extension.deactivate();
  });

  it('an absolute settings file stays as it is; an empty or unknown dialect is not passed', () => {
    const config = (values) => ({ get: (key) => values[key] });
    const abs = path.resolve('/etc/isotools.toml');
    assert.deepEqual(extension.serverOptions(config({ settingsFile: abs, dialect: '' }), FOLDER).args,
                     ['--lsp', '--config', abs]);
    assert.deepEqual(extension.serverOptions(config({ dialect: 'sidac' }), FOLDER).args, ['--lsp', '--dialect', 'sidac']);
    assert.deepEqual(extension.serverOptions(config({ dialect: 'fanuc' }), FOLDER).args, ['--lsp']);
    // without a workspace folder a relative path is passed as it is, and no cwd is set
    const none = extension.serverOptions(config({ settingsFile: 'isotools.toml' }), undefined);
    assert.deepEqual(none.args, ['--lsp', '--config', 'isotools.toml']);
    assert.equal(none.options, undefined);
  });

  it('sends the cycle-time settings as initializationOptions', async () => {
    await extension.activate({ subscriptions: [] });
    assert.deepEqual(created[0].clientOptions.initializationOptions,
                     { cycleTime: { enabled: true, budgetSeconds: 5, inlayHints: true, inlayHintsMaxLines: 5000 } });
    await extension.deactivate();
    settings['cycleTime.enabled'] = false;
    settings['cycleTime.budgetSeconds'] = 12.5;
    settings['cycleTime.inlayHints'] = false;
    settings['cycleTime.inlayHintsMaxLines'] = 800;
    await extension.activate({ subscriptions: [] });
    assert.deepEqual(created[1].clientOptions.initializationOptions,
                     { cycleTime: { enabled: false, budgetSeconds: 12.5, inlayHints: false, inlayHintsMaxLines: 800 } });
    await extension.deactivate();
  });

  it('keeps the budget from 0.1 s to 3600 s and the line limit unsigned, and falls back to the defaults for values of the wrong type', () => {
    const opts = (values) => extension.initializationOptions({ get: (key) => values[key] }).cycleTime;
    assert.equal(opts({ 'cycleTime.budgetSeconds': 0.01 }).budgetSeconds, 0.1);
    assert.equal(opts({ 'cycleTime.budgetSeconds': -3 }).budgetSeconds, 0.1);
    assert.equal(opts({ 'cycleTime.budgetSeconds': 7200 }).budgetSeconds, 3600, 'the server takes at most an hour');
    assert.equal(opts({ 'cycleTime.inlayHintsMaxLines': -1 }).inlayHintsMaxLines, 0);
    assert.equal(opts({ 'cycleTime.budgetSeconds': '7' }).budgetSeconds, 5);
    assert.equal(opts({ 'cycleTime.budgetSeconds': NaN }).budgetSeconds, 5);
    assert.equal(opts({ 'cycleTime.enabled': 'no' }).enabled, true);
    assert.equal(opts({ 'cycleTime.inlayHintsMaxLines': 99.7 }).inlayHintsMaxLines, 99);
  });

  it('restarts the server on a change of each of its settings, with the new values', async () => {
    await extension.activate({ subscriptions: [] });
    const changes = [
      ['isotools.isolintPath', 'isolintPath', '/opt/bin/isolint', (c) => c.serverOptions.command === '/opt/bin/isolint'],
      ['isotools.machine', 'machine', 'm.json', (c) => c.serverOptions.args.includes(path.join(FOLDER, 'm.json'))],
      ['isotools.settingsFile', 'settingsFile', 'a.toml', (c) => c.serverOptions.args.includes(path.join(FOLDER, 'a.toml'))],
      ['isotools.dialect', 'dialect', 'z32', (c) => c.serverOptions.args.join(' ').endsWith('--dialect z32')],
      ['isotools.cycleTime.enabled', 'cycleTime.enabled', false,
       (c) => c.clientOptions.initializationOptions.cycleTime.enabled === false],
      ['isotools.cycleTime.budgetSeconds', 'cycleTime.budgetSeconds', 2,
       (c) => c.clientOptions.initializationOptions.cycleTime.budgetSeconds === 2],
      ['isotools.cycleTime.inlayHints', 'cycleTime.inlayHints', false,
       (c) => c.clientOptions.initializationOptions.cycleTime.inlayHints === false],
      ['isotools.cycleTime.inlayHintsMaxLines', 'cycleTime.inlayHintsMaxLines', 100,
       (c) => c.clientOptions.initializationOptions.cycleTime.inlayHintsMaxLines === 100],
    ];
    for (const [section, key, value, check] of changes) {
      const before = created.length;
      settings[key] = value;
      await configListener({ affectsConfiguration: (s) => s === section });
      assert.equal(created.length, before + 1, section);
      assert.ok(created[before - 1].stopped, `${section}: the old server is stopped`);
      assert.ok(created[before].started, `${section}: a new one started`);
      assert.ok(check(created[before]), `${section}: the new server has the new value`);
    }
    await configListener({ affectsConfiguration: (s) => s === 'isotools.isosimPath' });
    assert.equal(created.length, changes.length + 1, 'the debugger\'s setting does not restart it');
    await extension.deactivate();
  });

  it('the command isotools.restartServer stops the server and starts a new one', async () => {
    await extension.activate({ subscriptions: [] });
    assert.equal(typeof commands['isotools.restartServer'], 'function');
    await commands['isotools.restartServer']();
    assert.equal(created.length, 2);
    assert.ok(created[0].stopped);
    assert.ok(created[1].started);
    assert.equal(statusItems[0].text, 'isolint: ready', 'a stop asked for is no error');
    // two restarts at once run one after the other: one server is left running
    await Promise.all([commands['isotools.restartServer'](), commands['isotools.restartServer']()]);
    assert.equal(created.length, 4);
    assert.deepEqual(created.map((c) => c.stopped), [true, true, true, false]);
    await extension.deactivate();
  });

  it('the status item: "isolint: starting" while the client starts, then "isolint: ready", shown for sidac-iso editors', async () => {
    fakeVscode.window.activeTextEditor = editor('/work/project/main.mpf');
    await extension.activate({ subscriptions: [] });
    assert.equal(statusItems.length, 1);
    const item = statusItems[0];
    assert.equal(created[0].statusWhileStarting, 'isolint: starting');
    assert.equal(item.text, 'isolint: ready');
    assert.equal(item.command, undefined);
    assert.ok(item.visible);
    fakeVscode.window.activeTextEditor = editor('/work/project/notes.txt', 'plaintext');
    editorListener(fakeVscode.window.activeTextEditor);
    assert.ok(!item.visible, 'hidden for other languages');
    fakeVscode.window.activeTextEditor = undefined;
    editorListener(undefined);
    assert.ok(!item.visible, 'hidden without an editor');
    await extension.deactivate();
  });

  it('the status item: "isolint: error" with the reason when the server cannot start; a click shows the output', async () => {
    fakeVscode.window.activeTextEditor = editor('/work/project/main.mpf');
    failStart = new Error('spawn isolint ENOENT');
    await extension.activate({ subscriptions: [] });
    const item = statusItems[0];
    assert.equal(item.text, 'isolint: error');
    assert.match(item.tooltip, /could not start "isolint --lsp": spawn isolint ENOENT/);
    assert.equal(item.command, 'isotools.showOutput');
    assert.equal(created[0].clientOptions.outputChannel.name, 'isolint');
    commands[item.command]();
    assert.equal(outputShown, 1);
    assert.equal(created[0].notifications['isotools/dryRun'], undefined, 'no handler on a client that did not start');
    // a restart that works clears the error
    await commands['isotools.restartServer']();
    assert.equal(item.text, 'isolint: ready');
    assert.equal(item.command, undefined);
    assert.equal(created[1].clientOptions.outputChannel, created[0].clientOptions.outputChannel, 'one output channel');
    await extension.deactivate();
  });

  it('the status item: "isolint: error" when the running server stops on its own', async () => {
    fakeVscode.window.activeTextEditor = editor('/work/project/main.mpf');
    await extension.activate({ subscriptions: [] });
    const item = statusItems[0];
    created[0].setState(State.Stopped);
    assert.equal(item.text, 'isolint: error');
    assert.match(item.tooltip, /the language server stopped/);
    created[0].setState(State.Starting); // vscode-languageclient restarts a crashed server
    assert.equal(item.text, 'isolint: starting');
    created[0].setState(State.Running);
    assert.equal(item.text, 'isolint: ready');
    await extension.deactivate();
  });

  it('the status item shows the dry run of the active document for each isotools/dryRun state', async () => {
    fakeVscode.window.activeTextEditor = editor('/work/project/main.mpf');
    await extension.activate({ subscriptions: [] });
    const item = statusItems[0];
    const dryRun = created[0].notifications['isotools/dryRun'];
    assert.equal(typeof dryRun, 'function', 'registered with onNotification after start');
    const uri = 'file:///work/project/main.mpf';
    dryRun({ uri, state: 'running', title: '' });
    assert.equal(item.text, '$(sync~spin) dry run…');
    dryRun({ uri, state: 'ok', title: 'cycle 39.276 s · 148 blocks' });
    assert.equal(item.text, '$(clock) cycle 39.276 s');
    assert.match(item.tooltip, /cycle 39\.276 s · 148 blocks/);
    dryRun({ uri, state: 'error', title: 'E502 at line 12: division by zero' });
    assert.equal(item.text, '$(error) E502 at line 12: division by zero');
    dryRun({ uri, state: 'emergency', title: 'emergency at 3.500 s: axis X over its limit' });
    assert.equal(item.text, '$(error) emergency at 3.500 s: axis X over its limit');
    assert.match(item.tooltip, /emergency/);
    dryRun({ uri, state: 'failed', title: 'cannot read machines/mill.json' });
    assert.equal(item.text, '$(error) cannot read machines/mill.json');
    dryRun({ uri, state: 'over budget', title: 'over the budget of 5 s at 812.000 s simulated' });
    assert.equal(item.text, '$(warning) over the budget of 5 s at 812.000 s simulated');
    dryRun({ uri, state: 'none', title: '' });
    assert.equal(item.text, 'isolint: ready', 'none: no run shows for the document');
    dryRun({ uri, state: 'cancelled', title: 'cancelled' });
    assert.equal(item.text, 'isolint: ready', 'cancelled before any run finished');
    dryRun({ uri, state: 'ok', title: 'cycle 39.276 s · 148 blocks' });
    dryRun({ uri, state: 'running', title: 'dry run…' });
    assert.equal(item.text, '$(sync~spin) dry run…');
    dryRun({ uri, state: 'cancelled', title: 'cancelled' });
    assert.equal(item.text, '$(clock) cycle 39.276 s', 'cancelled: the last finished run again');
    dryRun({ uri, state: 'none', title: '' });
    dryRun({ uri: 'file:///work/project/other.mpf', state: 'ok', title: 'cycle 1.000 s · 3 blocks' });
    assert.equal(item.text, 'isolint: ready', 'another document\'s run does not change it');
    dryRun(undefined);
    assert.equal(item.text, 'isolint: ready', 'params without a uri are ignored');
    await extension.deactivate();
  });

  it('the status item follows the active editor between documents, and a restart forgets the runs', async () => {
    fakeVscode.window.activeTextEditor = editor('/work/project/main.mpf');
    await extension.activate({ subscriptions: [] });
    const item = statusItems[0];
    const dryRun = created[0].notifications['isotools/dryRun'];
    dryRun({ uri: 'file:///work/project/main.mpf', state: 'ok', title: 'cycle 39.276 s · 148 blocks' });
    dryRun({ uri: 'file:///work/project/sub.mpf', state: 'running', title: '' });
    assert.equal(item.text, '$(clock) cycle 39.276 s');
    fakeVscode.window.activeTextEditor = editor('/work/project/sub.mpf');
    editorListener(fakeVscode.window.activeTextEditor);
    assert.equal(item.text, '$(sync~spin) dry run…');
    fakeVscode.window.activeTextEditor = editor('/work/project/new.mpf');
    editorListener(fakeVscode.window.activeTextEditor);
    assert.equal(item.text, 'isolint: ready');
    fakeVscode.window.activeTextEditor = editor('/work/project/main.mpf');
    editorListener(fakeVscode.window.activeTextEditor);
    assert.equal(item.text, '$(clock) cycle 39.276 s');
    closeListener(editor('/work/project/main.mpf').document);
    assert.equal(item.text, 'isolint: ready', 'a closed document\'s run is forgotten');
    fakeVscode.window.activeTextEditor = editor('/work/project/sub.mpf');
    editorListener(fakeVscode.window.activeTextEditor);
    assert.equal(item.text, '$(sync~spin) dry run…');
    await commands['isotools.restartServer']();
    assert.equal(item.text, 'isolint: ready');
    assert.equal(typeof created[1].notifications['isotools/dryRun'], 'function');
    await extension.deactivate();
  });

  it('formats through the server: every sidac-iso document, saved or untitled, and no middleware in between', async () => {
    await extension.activate({ subscriptions: [] });
    const { clientOptions } = created[0];
    assert.deepEqual(clientOptions.documentSelector, [
      { scheme: 'file', language: 'sidac-iso' },
      { scheme: 'untitled', language: 'sidac-iso' },
    ]);
    const middleware = clientOptions.middleware || {};
    for (const hook of ['provideDocumentFormattingEdits', 'provideDocumentRangeFormattingEdits', 'willSaveWaitUntil'])
      assert.equal(middleware[hook], undefined, hook);
    await extension.deactivate();
  });

  it('the real vscode-languageclient registers the document and range formatting features', () => {
    // The client asks the server for edits when the server advertises documentFormattingProvider
    // and documentRangeFormattingProvider; VS Code's editor.formatOnSave then calls it.
    const fs = require('node:fs');
    const root = path.join(path.dirname(require.resolve('vscode-languageclient/node')), 'lib', 'common');
    const client = fs.readFileSync(path.join(root, 'client.js'), 'utf8');
    assert.match(client, /registerFeature\(new formatting_1\.DocumentFormattingFeature\(this\)\)/);
    assert.match(client, /registerFeature\(new formatting_1\.DocumentRangeFormattingFeature\(this\)\)/);
    const formatting = fs.readFileSync(path.join(root, 'formatting.js'), 'utf8');
    assert.match(formatting, /capabilities\.documentFormattingProvider/);
    assert.match(formatting, /capabilities\.documentRangeFormattingProvider/);
  });

  it('the real vscode-languageclient/node is installed and exports LanguageClient', () => {
    // It cannot be loaded without VS Code (it requires `vscode`): read its entry point instead.
    const fs = require('node:fs');
    const entry = require.resolve('vscode-languageclient/node');
    assert.match(fs.readFileSync(entry, 'utf8'), /require\('\.\/lib\/node\/main'\)/);
    const main = path.join(path.dirname(entry), 'lib', 'node', 'main.js');
    assert.match(fs.readFileSync(main, 'utf8'), /exports\.LanguageClient = LanguageClient;/);
  });

  it('registers the debugger isosim: "isosim --dap" from isotools.isosimPath, in the workspace folder', async () => {
    await extension.activate({ subscriptions: [] });
    const factory = debugFactories.isosim;
    assert.ok(factory, 'a debug adapter factory for type isosim');
    let exe = factory.createDebugAdapterDescriptor({});
    assert.equal(exe.command, 'isosim');
    assert.deepEqual(exe.args, ['--dap']);
    assert.equal(exe.options.cwd, FOLDER);
    settings.isosimPath = '/opt/iso/bin/isosim';
    exe = factory.createDebugAdapterDescriptor({});
    assert.equal(exe.command, '/opt/iso/bin/isosim');
  });

  it('F5 without a launch.json dry-runs the active program, stopped at its first block', () => {
    const c = extension.resolveDebugConfiguration({}, '/work/project/main.mpf');
    assert.deepEqual(c, { type: 'isosim', request: 'launch', name: 'Dry run', program: '/work/project/main.mpf',
                          stopOnEntry: true });
    assert.equal(extension.resolveDebugConfiguration({}, undefined), undefined);
    const given = { type: 'isosim', request: 'launch', name: 'x', program: 'a.mpf' };
    assert.deepEqual(extension.resolveDebugConfiguration(given, '/other.mpf'), given);
    assert.equal(extension.resolveDebugConfiguration({ type: 'isosim', request: 'launch', name: 'x' }, '/b.mpf'),
                 undefined);
  });
});
