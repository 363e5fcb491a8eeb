'use strict';
// isosim --dap driven by VS Code's own adapter test client (DebugClient of
// @vscode/debugadapter-testsupport). ISOSIM names the isosim executable (CTest sets it); the
// samples come from the repository. Without ISOSIM the tests are skipped.
const { describe, it, before, after, beforeEach, afterEach } = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { execFileSync } = require('node:child_process');

const isosim = process.env.ISOSIM;
const root = path.resolve(__dirname, '..', '..', '..');
const samples = path.join(root, 'samples');
let DebugClient;
try {
  ({ DebugClient } = require('@vscode/debugadapter-testsupport'));
} catch (_) {
  DebugClient = undefined;
}
const skip = !isosim ? 'ISOSIM is not set' : !DebugClient ? '@vscode/debugadapter-testsupport is missing' : false;

const drilling = path.join(samples, 'drilling_when', 'foratura_piastra.mpf');
const drillingSub = path.join(samples, 'drilling_when', 'foratura.spf');
const flange = path.join(samples, 'z32_toolchange', 'fresatura_flangia.mpf');
const toolChange = path.join(samples, 'z32_toolchange', 'cambio_utensile.spf');

function summaryOf(program) {
  return execFileSync(isosim, ['--summary', program], { encoding: 'utf8' });
}

// The output events of a category, collected from now on.
function collect(dc, category) {
  const text = { value: '' };
  dc.on('output', (e) => {
    if (e.body.category === category) text.value += e.body.output;
  });
  return text;
}

async function topFrame(dc, threadId = 1) {
  const st = await dc.stackTraceRequest({ threadId });
  return st.body.stackFrames[0];
}

async function variablesOf(dc, frameId, scopeName) {
  const scopes = await dc.scopesRequest({ frameId });
  const scope = scopes.body.scopes.find((s) => s.name === scopeName);
  assert.ok(scope, `scope ${scopeName}`);
  const vars = await dc.variablesRequest({ variablesReference: scope.variablesReference });
  return vars.body.variables;
}

// launch with these breakpoints (file -> [{line, condition?, hitCondition?}]) and run to the first stop
async function start(dc, launchArgs, breakpoints = {}) {
  const stopped = dc.waitForEvent('stopped');
  await Promise.all([
    dc.waitForEvent('initialized').then(async () => {
      for (const [file, bps] of Object.entries(breakpoints))
        await dc.setBreakpointsRequest({ source: { path: file }, breakpoints: bps });
      return dc.configurationDoneRequest();
    }),
    dc.launch(launchArgs),
  ]);
  return stopped;
}

describe('isosim --dap with DebugClient', { skip }, () => {
  let dc;
  beforeEach(async () => {
    dc = new DebugClient(isosim, '--dap', 'isosim');
    dc.defaultTimeout = 10000;
    await dc.start();
  });
  afterEach(async () => {
    if (dc) await dc.stop();
  });

  it('answers initialize with its capabilities', async () => {
    const r = await dc.initializeRequest();
    assert.equal(r.body.supportsConfigurationDoneRequest, true);
    assert.equal(r.body.supportsConditionalBreakpoints, true);
    assert.equal(r.body.supportsHitConditionalBreakpoints, true);
    assert.equal(r.body.supportsFunctionBreakpoints, true);
    assert.deepEqual(r.body.exceptionBreakpointFilters.map((f) => f.filter), ['error', 'emergency']);
  });

  it('stops on entry and runs to the end with the summary of isosim --summary', async () => {
    const console = collect(dc, 'console');
    const ev = await start(dc, { program: drilling, stopOnEntry: true });
    assert.equal(ev.body.reason, 'entry');
    const f = await topFrame(dc);
    assert.equal(f.source.path, drilling);
    assert.equal(f.line, 13); // the first statement: R40 = -190
    const exited = dc.waitForEvent('exited');
    const terminated = dc.waitForEvent('terminated');
    await dc.continueRequest({ threadId: 1 });
    assert.equal((await exited).body.exitCode, 0);
    await terminated;
    assert.equal(console.value, summaryOf(drilling));
  });

  it('hits a line breakpoint in a subprogram, with the call chain', async () => {
    await dc.hitBreakpoint({ program: drilling }, { path: drillingSub, line: 17 });
    const st = await dc.stackTraceRequest({ threadId: 1 });
    const frames = st.body.stackFrames;
    assert.deepEqual(frames.map((f) => f.name), ['Foratura', 'foratura_piastra']);
    assert.equal(frames[1].source.path, drilling);
    assert.equal(frames[1].line, 53); // the call line
  });

  it('moves a breakpoint on a comment to the next statement', async () => {
    await dc.launch({ program: drilling });
    const r = await dc.setBreakpointsRequest({ source: { path: drilling }, breakpoints: [{ line: 1 }, { line: 500 }] });
    assert.equal(r.body.breakpoints[0].verified, true);
    assert.equal(r.body.breakpoints[0].line, 13);
    assert.equal(r.body.breakpoints[1].verified, false);
  });

  it('stops at a conditional breakpoint only when the condition holds, and counts hits', async () => {
    // line 51: R52 = R[101 + R50], once per hole (R50 = 0..5)
    const ev = await start(dc, { program: drilling }, { [drilling]: [{ line: 51, condition: 'R50 == 3' }] });
    assert.equal(ev.body.reason, 'breakpoint');
    const f = await topFrame(dc);
    assert.equal(f.line, 51);
    const r = await dc.evaluateRequest({ expression: 'R50', frameId: f.id, context: 'watch' });
    assert.equal(r.body.result, '3');
    // a new breakpoint with a hit count: its 2nd hit, counted from now
    await dc.setBreakpointsRequest({ source: { path: drilling }, breakpoints: [{ line: 51, hitCondition: '2' }] });
    const again = dc.waitForEvent('stopped');
    await dc.continueRequest({ threadId: 1 });
    await again;
    const f2 = await topFrame(dc);
    const r2 = await dc.evaluateRequest({ expression: 'R50', frameId: f2.id, context: 'watch' });
    assert.equal(r2.body.result, '5'); // R50 = 4 is its first hit
  });

  it('steps over, into and out of a call', async () => {
    const ev = await start(dc, { program: drilling }, { [drilling]: [{ line: 53 }] });
    assert.equal(ev.body.reason, 'breakpoint');
    await dc.setBreakpointsRequest({ source: { path: drilling }, breakpoints: [] });
    // stepIn enters Foratura
    let stopped = dc.waitForEvent('stopped');
    await dc.stepInRequest({ threadId: 1 });
    assert.equal((await stopped).body.reason, 'step');
    let f = await topFrame(dc);
    assert.equal(f.source.path, drillingSub);
    assert.equal(f.name, 'Foratura');
    // next stays in Foratura: the next statement
    const line = f.line;
    stopped = dc.waitForEvent('stopped');
    await dc.nextRequest({ threadId: 1 });
    await stopped;
    f = await topFrame(dc);
    assert.equal(f.source.path, drillingSub);
    assert.ok(f.line > line);
    // stepOut returns to the line after the call
    stopped = dc.waitForEvent('stopped');
    await dc.stepOutRequest({ threadId: 1 });
    await stopped;
    f = await topFrame(dc);
    assert.equal(f.source.path, drilling);
    assert.equal(f.line, 54);
    // next over the next call: from line 57 (the loop) back to 51, never inside Foratura
    for (let i = 0; i < 6; ++i) {
      stopped = dc.waitForEvent('stopped');
      await dc.nextRequest({ threadId: 1 });
      await stopped;
      f = await topFrame(dc);
      assert.equal(f.source.path, drilling, `step ${i} stays in the main program`);
    }
  });

  it('steps into and over a special M (z32)', async () => {
    const ev = await start(dc, { program: flange }, { [flange]: [{ line: 18 }] });
    assert.equal(ev.body.reason, 'breakpoint');
    let stopped = dc.waitForEvent('stopped');
    await dc.stepInRequest({ threadId: 1 });
    await stopped;
    const st = await dc.stackTraceRequest({ threadId: 1 });
    assert.equal(st.body.stackFrames[0].source.path, toolChange);
    assert.match(st.body.stackFrames[0].name, /CAMBIO_UTENSILE \(special M\)/);
    assert.equal(st.body.stackFrames[1].line, 18);
    // out of the special M: the line after N100 T1 M6
    stopped = dc.waitForEvent('stopped');
    await dc.stepOutRequest({ threadId: 1 });
    await stopped;
    let f = await topFrame(dc);
    assert.equal(f.source.path, flange);
    assert.ok(f.line > 18);
    const machine = await variablesOf(dc, f.id, 'Machine functions');
    assert.equal(machine.find((v) => v.name === 'tool').value, 'T1');
    // next over the second tool change (line 49) never stops in the subprogram
    await dc.setBreakpointsRequest({ source: { path: flange }, breakpoints: [{ line: 49 }] });
    stopped = dc.waitForEvent('stopped');
    await dc.continueRequest({ threadId: 1 });
    await stopped;
    await dc.setBreakpointsRequest({ source: { path: flange }, breakpoints: [] });
    stopped = dc.waitForEvent('stopped');
    await dc.nextRequest({ threadId: 1 });
    await stopped;
    f = await topFrame(dc);
    assert.equal(f.source.path, flange);
    assert.ok(f.line > 49);
  });

  it('shows R parameters, axes, the modal state and evaluates expressions', async () => {
    await start(dc, { program: drilling }, { [drillingSub]: [{ line: 17 }] });
    const f = await topFrame(dc);
    const r = await variablesOf(dc, f.id, 'R parameters');
    assert.equal(r.find((v) => v.name === 'R40').value, '-190');
    assert.equal(r.find((v) => v.name === 'R51').value, '6');
    const axes = await variablesOf(dc, f.id, 'Axes');
    const x = axes.find((v) => v.name === 'X');
    assert.equal(x.value, '120');
    const xs = await dc.variablesRequest({ variablesReference: x.variablesReference });
    assert.deepEqual(xs.body.variables.map((v) => v.name), ['position', 'target', 'velocity', 'state']);
    const modal = await variablesOf(dc, f.id, 'Modal state');
    assert.equal(modal.find((v) => v.name === 'F').value, '5 mm/s');
    const run = await variablesOf(dc, f.id, 'Run');
    assert.match(run.find((v) => v.name === 'time').value, /^[0-9.]+ s$/);
    const e = await dc.evaluateRequest({ expression: '($aa_iw[Z] < R41) AND (R43 == 5)', frameId: f.id });
    assert.equal(e.body.result, 'true'); // the drill is down at Z -215, below R41 = -198
    const sum = await dc.evaluateRequest({ expression: 'R40 + R43 * 2', frameId: f.id });
    assert.equal(sum.body.result, '-370'); // strictly left to right, as the controller computes: (-190 + 5) * 2
    await assert.rejects(dc.evaluateRequest({ expression: 'R40 +', frameId: f.id }), /operand/);
    await assert.rejects(dc.evaluateRequest({ expression: 'R1 / 0', frameId: f.id }), /division by zero/);
  });

  it('reports an emergency as an exception where it happens', async () => {
    const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'isosim-dap-'));
    const prog = path.join(dir, 'limite.mpf');
    fs.writeFileSync(prog, 'G90 G60\nG00 X=100\nG00 X=5000\nM30\n');
    try {
      const ev = await start(dc, { program: prog });
      assert.equal(ev.body.reason, 'exception');
      assert.match(ev.body.text, /emergency/);
      const info = await dc.exceptionInfoRequest({ threadId: 1 });
      assert.equal(info.body.exceptionId, 'emergency');
      const f = await topFrame(dc);
      assert.equal(f.line, 3);
      const exited = dc.waitForEvent('exited');
      await dc.continueRequest({ threadId: 1 });
      assert.equal((await exited).body.exitCode, 3);
    } finally {
      fs.rmSync(dir, { recursive: true, force: true });
    }
  });

  it('runs to a simulated time, and stops at a time breakpoint', async () => {
    const ev = await start(dc, { program: drilling, stopOnEntry: true });
    assert.equal(ev.body.reason, 'entry');
    await dc.setFunctionBreakpointsRequest({ breakpoints: [{ name: 't=20' }] });
    let stopped = dc.waitForEvent('stopped');
    await dc.customRequest('runToTime', { time: 10 });
    let s = await stopped;
    assert.equal(s.body.reason, 'time');
    let f = await topFrame(dc);
    let run = await variablesOf(dc, f.id, 'Run');
    assert.equal(run.find((v) => v.name === 'time').value, '10 s');
    await assert.rejects(dc.customRequest('runToTime', { time: 5 }), /not after/);
    stopped = dc.waitForEvent('stopped');
    await dc.continueRequest({ threadId: 1 });
    s = await stopped;
    assert.equal(s.body.reason, 'function breakpoint');
    f = await topFrame(dc);
    run = await variablesOf(dc, f.id, 'Run');
    assert.equal(run.find((v) => v.name === 'time').value, '20 s');
    const t = await dc.evaluateRequest({ expression: 'time', frameId: f.id });
    assert.equal(t.body.result, '20');
  });

  it('stops at a subprogram named as a function breakpoint', async () => {
    await dc.launch({ program: drilling });
    const r = await dc.setFunctionBreakpointsRequest({ breakpoints: [{ name: 'Foratura' }, { name: 'Nessuno' }] });
    assert.equal(r.body.breakpoints[0].verified, true);
    assert.equal(r.body.breakpoints[1].verified, false);
    const stopped = dc.waitForEvent('stopped');
    await dc.configurationDoneRequest();
    assert.equal((await stopped).body.reason, 'breakpoint');
    const f = await topFrame(dc);
    assert.equal(f.name, 'Foratura');
    assert.equal(f.source.path, drillingSub);
  });

  it('disconnects while stopped and ends', async () => {
    await start(dc, { program: drilling, stopOnEntry: true });
    const proc = dc._adapterProcess;
    const exit = new Promise((resolve) => proc.once('exit', (code) => resolve(code)));
    await dc.disconnectRequest({});
    assert.equal(await exit, 0);
    dc = undefined; // gone: nothing to stop
  });

  it('refuses a program with errors at launch, with its diagnostics', async () => {
    const dir = fs.mkdtempSync(path.join(os.tmpdir(), 'isosim-dap-'));
    const prog = path.join(dir, 'errato.mpf');
    fs.writeFileSync(prog, 'G00 X=\nM30\n');
    try {
      const stderr = collect(dc, 'stderr');
      await dc.initializeRequest();
      await assert.rejects(dc.launchRequest({ program: prog }), /errato\.mpf:1/);
      assert.match(stderr.value, /errato\.mpf:1:/);
    } finally {
      fs.rmSync(dir, { recursive: true, force: true });
    }
  });
});
