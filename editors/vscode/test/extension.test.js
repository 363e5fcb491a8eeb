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
    // the debugger's factory and provider, the output channel, the status item and its editor listener,
    // the settings listener and the two commands
    assert.equal(context.subscriptions.length, 8);
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
