'use strict';
// Manifest consistency: package.json, language-configuration.json, the grammar and the lock file
// agree with each other and name files that exist.
const { describe, it } = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const path = require('node:path');

const ROOT = path.join(__dirname, '..');
const readJson = (rel) => JSON.parse(fs.readFileSync(path.join(ROOT, rel), 'utf8'));
const pkg = readJson('package.json');
const LANG = 'sidac-iso';

describe('package.json', () => {
  it('names the extension', () => {
    assert.equal(pkg.name, 'isotools-iso');
    assert.equal(pkg.publisher, 'isotools');
    assert.equal(pkg.engines.vscode, '^1.75.0');
    assert.match(pkg.version, /^\d+\.\d+\.\d+$/);
  });
  it('declares the language sidac-iso for .mpf and .spf in both cases', () => {
    const langs = pkg.contributes.languages.filter((l) => l.id === LANG);
    assert.equal(langs.length, 1);
    for (const ext of ['.mpf', '.spf', '.MPF', '.SPF']) assert.ok(langs[0].extensions.includes(ext), ext);
    assert.ok(fs.existsSync(path.join(ROOT, langs[0].configuration)), langs[0].configuration);
  });
  it('contributes the grammar source.sidac-iso for that language, at a path that exists', () => {
    const grammars = pkg.contributes.grammars;
    assert.equal(grammars.length, 1);
    assert.equal(grammars[0].language, LANG);
    assert.equal(grammars[0].scopeName, 'source.sidac-iso');
    const grammar = readJson(grammars[0].path);
    assert.equal(grammar.scopeName, grammars[0].scopeName);
  });
  it('activates on the language (and for the debugger) and starts from a file that exists', () => {
    assert.deepEqual(pkg.activationEvents,
                     [`onLanguage:${LANG}`, 'onDebugResolve:isosim', 'onDebugDynamicConfigurations:isosim']);
    assert.ok(fs.existsSync(path.join(ROOT, pkg.main)), pkg.main);
  });
  it('has the settings isotools.isolintPath and isotools.machine', () => {
    const props = pkg.contributes.configuration.properties;
    assert.equal(props['isotools.isolintPath'].type, 'string');
    assert.equal(props['isotools.isolintPath'].default, 'isolint');
    assert.equal(props['isotools.machine'].type, 'string');
    assert.equal(props['isotools.machine'].default, '');
    for (const key of pkg.capabilities.untrustedWorkspaces.restrictedConfigurations) assert.ok(props[key], key);
  });
  it('has the settings isotools.settingsFile and isotools.dialect, the settings file restricted like the machine', () => {
    const props = pkg.contributes.configuration.properties;
    assert.equal(props['isotools.settingsFile'].type, 'string');
    assert.equal(props['isotools.settingsFile'].default, '');
    assert.equal(props['isotools.settingsFile'].scope, props['isotools.machine'].scope);
    assert.deepEqual(props['isotools.dialect'].enum, ['', 'sidac', 'z32']);
    assert.equal(props['isotools.dialect'].enumDescriptions.length, props['isotools.dialect'].enum.length);
    assert.equal(props['isotools.dialect'].default, '');
    const restricted = pkg.capabilities.untrustedWorkspaces.restrictedConfigurations;
    assert.ok(restricted.includes('isotools.machine'));
    assert.ok(restricted.includes('isotools.settingsFile'));
  });
  it('has the cycle-time settings with the server\'s defaults', () => {
    const props = pkg.contributes.configuration.properties;
    const expect = {
      'isotools.cycleTime.enabled': ['boolean', true],
      'isotools.cycleTime.budgetSeconds': ['number', 5],
      'isotools.cycleTime.inlayHints': ['boolean', true],
      'isotools.cycleTime.inlayHintsMaxLines': ['integer', 5000],
    };
    for (const [key, [type, def]] of Object.entries(expect)) {
      assert.equal(props[key].type, type, key);
      assert.equal(props[key].default, def, key);
      assert.ok(props[key].description, key);
    }
    assert.equal(props['isotools.cycleTime.budgetSeconds'].minimum, 0.1);
    assert.equal(props['isotools.cycleTime.budgetSeconds'].maximum, 3600);
    assert.equal(props['isotools.cycleTime.inlayHintsMaxLines'].minimum, 0);
  });
  it('every setting the extension reads is contributed, and every contributed one is read', () => {
    const props = Object.keys(pkg.contributes.configuration.properties);
    const source = fs.readFileSync(path.join(ROOT, pkg.main), 'utf8');
    const read = [...source.matchAll(/(?:config\.get|bool|number)\('([\w.]+)'/g)].map((m) => `isotools.${m[1]}`);
    assert.deepEqual([...new Set(read)].sort(), [...props].sort());
  });
  it('contributes the command isotools.restartServer, which the extension registers', () => {
    assert.deepEqual(pkg.contributes.commands,
                     [{ command: 'isotools.restartServer', title: 'Restart the language server', category: 'isotools' }]);
    const source = fs.readFileSync(path.join(ROOT, pkg.main), 'utf8');
    assert.match(source, /registerCommand\('isotools\.restartServer'/);
  });
  it('makes the extension the default formatter of sidac-iso, and leaves format-on-save to the user', () => {
    const defaults = pkg.contributes.configurationDefaults;
    assert.deepEqual(defaults, { [`[${LANG}]`]: { 'editor.defaultFormatter': `${pkg.publisher}.${pkg.name}` } });
    assert.ok(!JSON.stringify(defaults).includes('formatOnSave'), 'editor.formatOnSave stays opt-in');
  });
  it('depends on vscode-languageclient (a version for VS Code 1.75), tests on vscode-textmate and vscode-oniguruma', () => {
    assert.match(pkg.dependencies['vscode-languageclient'], /^\^8\./);
    assert.ok(pkg.devDependencies['vscode-textmate']);
    assert.ok(pkg.devDependencies['vscode-oniguruma']);
  });
  it('package-lock.json matches package.json', () => {
    const lock = readJson('package-lock.json');
    assert.equal(lock.name, pkg.name);
    assert.equal(lock.version, pkg.version);
    assert.deepEqual(lock.packages[''].dependencies, pkg.dependencies);
    assert.deepEqual(lock.packages[''].devDependencies, pkg.devDependencies);
    for (const dep of [...Object.keys(pkg.dependencies), ...Object.keys(pkg.devDependencies)]) {
      assert.ok(lock.packages[`node_modules/${dep}`], `${dep} is locked`);
    }
  });
});

describe('language-configuration.json', () => {
  const conf = readJson('language-configuration.json');
  it('comments: ";" to the end of the line, "( … )" as block', () => {
    assert.equal(conf.comments.lineComment, ';');
    assert.deepEqual(conf.comments.blockComment, ['(', ')']);
  });
  it('brackets [] and ()', () => {
    assert.deepEqual(conf.brackets, [['[', ']'], ['(', ')']]);
  });
  it('its regular expressions compile and indent IF/ELSE/WHEN … DO blocks', () => {
    const re = (r) => new RegExp(r.pattern, r.flags);
    const inc = re(conf.indentationRules.increaseIndentPattern);
    const dec = re(conf.indentationRules.decreaseIndentPattern);
    assert.ok(inc.test('IF R45 > 0'));
    assert.ok(inc.test('when $aa_iw[Z] < R41 do'));
    assert.ok(!inc.test('IF R50 < R51 GOTOB Foro'));
    assert.ok(!inc.test('WHEN $aa_iw[Z] > R41 DO $aa_out[12] = 0'));
    assert.ok(dec.test('  ENDIF'));
    assert.ok(dec.test('CANCEL'));
    assert.equal(new RegExp(conf.wordPattern).exec('  $aa_iw[X]')[0], '$aa_iw');
  });
});

describe('grammar file', () => {
  const grammar = readJson(pkg.contributes.grammars[0].path);
  it('every #include names a repository rule, and every rule is used', () => {
    const used = new Set();
    const walk = (node) => {
      if (Array.isArray(node)) node.forEach(walk);
      else if (node && typeof node === 'object') {
        if (typeof node.include === 'string') {
          assert.match(node.include, /^#/, `only local includes: ${node.include}`);
          const name = node.include.slice(1);
          assert.ok(grammar.repository[name], `#${name} is defined`);
          used.add(name);
        }
        Object.values(node).forEach(walk);
      }
    };
    walk(grammar);
    for (const name of Object.keys(grammar.repository)) assert.ok(used.has(name), `#${name} is used`);
  });
  it('every scope name ends in .sidac-iso', () => {
    const names = [];
    const walk = (node) => {
      if (Array.isArray(node)) node.forEach(walk);
      else if (node && typeof node === 'object') {
        for (const key of ['name', 'contentName']) if (typeof node[key] === 'string') names.push(...node[key].split(' '));
        Object.entries(node).forEach(([k, v]) => k !== 'name' && walk(v));
      }
    };
    walk(grammar.repository);
    walk(grammar.patterns);
    assert.ok(names.length > 30);
    for (const n of names) assert.match(n, /\.sidac-iso$/, n);
  });

  it('contributes the debugger isosim for sidac-iso, with breakpoints, launch attributes and a snippet', () => {
    assert.deepEqual(pkg.contributes.breakpoints, [{ language: LANG }]);
    const dbg = pkg.contributes.debuggers;
    assert.equal(dbg.length, 1);
    assert.equal(dbg[0].type, 'isosim');
    assert.deepEqual(dbg[0].languages, [LANG]);
    const launch = dbg[0].configurationAttributes.launch;
    assert.deepEqual(launch.required, ['program']);
    for (const k of ['program', 'machine', 'settings', 'entry', 'dialect', 'search', 'stopOnEntry'])
      assert.ok(launch.properties[k], k);
    assert.equal(dbg[0].initialConfigurations[0].type, 'isosim');
    assert.equal(dbg[0].configurationSnippets[0].body.type, 'isosim');
    assert.ok(pkg.activationEvents.includes('onDebugResolve:isosim'));
    const props = pkg.contributes.configuration.properties;
    assert.equal(props['isotools.isosimPath'].default, 'isosim');
    assert.ok(pkg.capabilities.untrustedWorkspaces.restrictedConfigurations.includes('isotools.isosimPath'));
    assert.ok(pkg.devDependencies['@vscode/debugadapter-testsupport']);
  });
});
