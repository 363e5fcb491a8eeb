'use strict';
// Grammar tests: the TextMate grammar loaded the way VS Code loads it (vscode-textmate on the
// vscode-oniguruma WebAssembly regex engine), constructs of SPEC §2-§4 checked token by token,
// and every line of every sample program tokenized.
const { describe, it, before } = require('node:test');
const assert = require('node:assert/strict');
const fs = require('node:fs');
const path = require('node:path');
const vsctm = require('vscode-textmate');
const oniguruma = require('vscode-oniguruma');

const ROOT = path.join(__dirname, '..');
const GRAMMAR = path.join(ROOT, 'syntaxes', 'sidac-iso.tmLanguage.json');
const SAMPLES = path.join(ROOT, '..', '..', 'samples');
const S = '.sidac-iso';

let grammar;

async function loadGrammar() {
  const wasmPath = path.join(path.dirname(require.resolve('vscode-oniguruma')), 'onig.wasm');
  const wasm = fs.readFileSync(wasmPath);
  await oniguruma.loadWASM(wasm.buffer.slice(wasm.byteOffset, wasm.byteOffset + wasm.byteLength));
  const registry = new vsctm.Registry({
    onigLib: Promise.resolve({
      createOnigScanner: (patterns) => new oniguruma.OnigScanner(patterns),
      createOnigString: (s) => new oniguruma.OnigString(s),
    }),
    loadGrammar: async (scopeName) =>
      scopeName === 'source.sidac-iso' ? vsctm.parseRawGrammar(fs.readFileSync(GRAMMAR, 'utf8'), GRAMMAR) : null,
  });
  const g = await registry.loadGrammar('source.sidac-iso');
  assert.ok(g, 'grammar source.sidac-iso loads');
  return g;
}

// Tokens of one line (or of the last of several lines, tokenized in sequence).
function tokenize(...lines) {
  let state = vsctm.INITIAL;
  let tokens;
  let line;
  for (line of lines) {
    const r = grammar.tokenizeLine(line, state);
    state = r.ruleStack;
    tokens = r.tokens.map((t) => ({ text: line.slice(t.startIndex, t.endIndex), start: t.startIndex, scopes: t.scopes }));
  }
  return tokens;
}

// Asserts that the nth token (0-based) whose text is exactly `text` carries `scope`.
function expectToken(line, text, scope, nth = 0) {
  const lines = Array.isArray(line) ? line : [line];
  const tokens = tokenize(...lines);
  const matching = tokens.filter((t) => t.text === text);
  const dump = tokens.map((t) => `${JSON.stringify(t.text)} ${t.scopes.slice(1).join(' ')}`).join('\n  ');
  assert.ok(matching.length > nth, `no token ${JSON.stringify(text)} (#${nth}) in ${JSON.stringify(lines.at(-1))}:\n  ${dump}`);
  assert.ok(matching[nth].scopes.includes(scope),
    `token ${JSON.stringify(text)} in ${JSON.stringify(lines.at(-1))} has ${matching[nth].scopes.join(' ')}, expected ${scope}`);
}

function expectNotScope(line, text, scopePrefix) {
  const t = tokenize(line).find((x) => x.text === text);
  assert.ok(t, `no token ${JSON.stringify(text)} in ${JSON.stringify(line)}`);
  assert.ok(!t.scopes.some((s) => s.startsWith(scopePrefix)),
    `token ${JSON.stringify(text)} in ${JSON.stringify(line)} should not be ${scopePrefix}: ${t.scopes.join(' ')}`);
}

function hasIllegal(line) {
  return tokenize(line).some((t) => t.scopes.some((s) => s.startsWith('invalid.illegal')));
}

before(async () => {
  grammar = await loadGrammar();
});

describe('comments (SPEC §2)', () => {
  it('";" comments to the end of the line, "$" included', () => {
    expectToken('N10 G90 ; assoluto $aa_out[3]', ';', 'punctuation.definition.comment' + S);
    expectToken('N10 G90 ; assoluto $aa_out[3]', ' assoluto $aa_out[3]', 'comment.line.semicolon' + S);
    expectNotScope('N10 G90 ; assoluto', 'G90', 'comment');
  });
  it('a comment line "( … )", nested parentheses inside it', () => {
    expectToken('( TAGLIO PLASMA - PIASTRA )', ' TAGLIO PLASMA - PIASTRA ', 'comment.line.parenthesis' + S);
    expectToken('( CONTORNO: attacco a (150, 50), senso antiorario )', ' CONTORNO: attacco a (150, 50), senso antiorario ',
      'comment.line.parenthesis' + S);
    expectToken('N20 ( dopo il numero )', ' dopo il numero ', 'comment.line.parenthesis' + S);
  });
  it('an inline "( … )" after a block item, up to the first ")"', () => {
    expectToken('N6 G1 X138.79 (CUT)', 'CUT', 'comment.block.parenthesis' + S);
    expectToken('R1 = 5 (nota) X10', 'X', 'variable.parameter.axis' + S);
  });
  it('a "(" after an operator or IF/AND/NOT groups instead', () => {
    expectToken('IF ($aa_in[3] == 0) AND (R20 < R90) GOTOB Wait', '(', 'punctuation.section.parens.begin' + S);
    expectToken('IF ($aa_in[3] == 0) AND (R20 < R90) GOTOB Wait', 'R20', 'variable.other.r-parameter' + S);
    expectToken('R12 = -(R10 + 1) * R2', 'R10', 'variable.other.r-parameter' + S);
    expectToken('IF NOT ($aa_marker[5] == 0)', 'NOT', 'keyword.operator.logical' + S);
  });
});

describe('line prefixes and labels (SPEC §2, §4.1)', () => {
  it('line number N123, also N132,5 and glued to words', () => {
    expectToken('N123 G0 X0', 'N123', 'constant.other.line-number' + S);
    expectToken('N132,5 G0', 'N132,5', 'constant.other.line-number' + S);
    expectToken('N12G0X0', 'N12', 'constant.other.line-number' + S);
    expectToken('N12G0X0', 'G0', 'keyword.other.g-code' + S);
    expectToken('N12G0X0', '0', 'constant.numeric' + S);
  });
  it('block skip "/" and tape marker "%"', () => {
    expectToken('/N10 G0 X0', '/', 'keyword.control.block-skip' + S);
    expectToken('/ G0 X0', '/', 'keyword.control.block-skip' + S);
    expectToken('%', '%', 'keyword.other.tape-marker' + S);
    expectToken('R1 = R2 / 4', '/', 'keyword.operator.arithmetic' + S);
  });
  it('labels "Name:" at the line start, after the prefixes, before a statement', () => {
    expectToken('Foro:', 'Foro', 'entity.name.label' + S);
    expectToken('Foro:', ':', 'punctuation.separator.label' + S);
    expectToken('N40 A1: G0 X0', 'A1', 'entity.name.label' + S);
    expectToken('Wait: IF $aa_in[3] == 0 GOTOB Wait', 'Wait', 'entity.name.label' + S, 0);
  });
});

describe('keywords (SPEC §4)', () => {
  it('IF ELSE ENDIF THEN', () => {
    expectToken('IF R1 == 0 THEN R1 = 2', 'IF', 'keyword.control.conditional' + S);
    expectToken('IF R1 == 0 THEN R1 = 2', 'THEN', 'keyword.control.conditional' + S);
    expectToken('ELSE', 'ELSE', 'keyword.control.conditional' + S);
    expectToken('  endif', 'endif', 'keyword.control.conditional' + S);
  });
  it('GOTOF GOTOB GOTO and their label, whatever it looks like', () => {
    expectToken('GOTOF Fine', 'GOTOF', 'keyword.control.goto' + S);
    expectToken('GOTOF Fine', 'Fine', 'entity.name.label' + S);
    expectToken('IF R50 < R51 gotob Foro', 'gotob', 'keyword.control.goto' + S);
    expectToken('GOTO X10', 'X10', 'entity.name.label' + S);
  });
  it('CASE … OF … DEFAULT', () => {
    const line = 'CASE R1 OF 1 GOTOF Rec1 2 GOTOF Rec2 DEFAULT GOTOF Errore';
    expectToken(line, 'CASE', 'keyword.control.switch' + S);
    expectToken(line, 'OF', 'keyword.control.switch' + S);
    expectToken(line, 'DEFAULT', 'keyword.control.switch' + S);
    expectToken(line, '2', 'constant.numeric' + S);
    expectToken(line, 'Rec2', 'entity.name.label' + S);
  });
  it('WHEN … DO … CANCEL', () => {
    expectToken('WHEN $aa_iw[Z] < -150 DO', 'WHEN', 'keyword.control.when' + S);
    expectToken('WHEN $aa_iw[Z] < -150 DO', 'DO', 'keyword.control.when' + S);
    expectToken('CANCEL', 'CANCEL', 'keyword.control.when' + S);
  });
  it('PROC name SAVE, SEMI "name", calls', () => {
    expectToken('PROC Foratura SAVE', 'PROC', 'storage.type.proc' + S);
    expectToken('PROC Foratura SAVE', 'Foratura', 'entity.name.function' + S);
    expectToken('proc Foratura save', 'save', 'storage.modifier.save' + S);
    expectToken('SEMI "Cambio utensile; $ manuale"', 'SEMI', 'storage.type.semi' + S);
    expectToken('SEMI "Cambio utensile; $ manuale"', 'Cambio utensile; $ manuale', 'string.quoted.double' + S);
    expectToken('  Esegui_marcatura', 'Esegui_marcatura', 'entity.name.function.call' + S);
  });
  it('AND OR NOT', () => {
    expectToken('IF (R1 > 2) OR (R2 < 3)', 'OR', 'keyword.operator.logical' + S);
    expectToken('IF (R1 > 2) and not (R2 < 3)', 'and', 'keyword.operator.logical' + S);
  });
});

describe('words and items (SPEC §2, §3, §4.2-§4.5)', () => {
  it('G words G0 G01 g90', () => {
    expectToken('G0 X0', 'G0', 'keyword.other.g-code' + S);
    expectToken('N10 G01 X1', 'G01', 'keyword.other.g-code' + S);
    expectToken('g90 g64', 'g90', 'keyword.other.g-code' + S);
  });
  it('M words M30 and M=NB(23)', () => {
    expectToken('M30', 'M30', 'support.function.m-code' + S);
    expectToken('M=NB(23)', 'M', 'support.function.m-code' + S);
    expectToken('M=NB(23)', 'NB', 'support.function.nb' + S);
    expectToken('m=nb(23)', '23', 'constant.numeric' + S);
  });
  it('axis words X-10.5, Y,5, X -5, Z=expr', () => {
    expectToken('G01 X-10.5 Y,5', 'X', 'variable.parameter.axis' + S);
    expectToken('G01 X-10.5 Y,5', '-10.5', 'constant.numeric' + S);
    expectToken('G01 X-10.5 Y,5', ',5', 'constant.numeric' + S);
    expectToken('X -5', '-5', 'constant.numeric' + S);
    expectToken('G00 z=R40', 'z', 'variable.parameter.axis' + S);
    expectToken('G00 Z=R40', '=', 'keyword.operator.assignment' + S);
  });
  it('F, arcs I J K CR', () => {
    expectToken('G04 F0.4', 'F', 'variable.parameter.feed' + S);
    expectToken('G04 F0.4', '0.4', 'constant.numeric' + S);
    expectToken('N20 F=40', 'F', 'variable.parameter.feed' + S);
    expectToken('G03 X=100 Y=130 CR=20', 'CR', 'variable.parameter.arc' + S);
    expectToken('G02 X160 Y70 I0 J30', 'J', 'variable.parameter.arc' + S);
  });
  it('R parameters R12 and R[…]', () => {
    expectToken('R12 = R13 + 1', 'R12', 'variable.other.r-parameter' + S);
    expectToken('R52 = R[101 + R50]', 'R', 'variable.other.r-parameter' + S);
    expectToken('R52 = R[101 + R50]', 'R50', 'variable.other.r-parameter' + S);
    expectToken('R52 = R[101 + R50]', '[', 'punctuation.section.brackets.begin' + S);
  });
  it('system variables, case-insensitive', () => {
    for (const name of ['$aa_iw', '$aa_fw', '$aa_in', '$aa_out', '$aa_marker', '$MAX_VELO', '$POS_LIMIT_PLUS',
      '$POS_LIMIT_MINUS', '$AA_IW', '$max_velo']) {
      expectToken(`R1 = ${name}[X]`, name, 'variable.language.system' + S);
    }
    expectToken('IF $aa_iw[C] <> $aa_fw[C] GOTOB AttesaC', 'C', 'variable.parameter.axis' + S);
    expectToken('$aa_out[3] = 1', '3', 'constant.numeric' + S);
  });
  it('Pos[X], Posa[X], Fa[X]', () => {
    expectToken('G01 Pos[X] = R20', 'Pos', 'support.function.builtin' + S);
    expectToken('G00 posa[c]=90', 'posa', 'support.function.builtin' + S);
    expectToken('G00 posa[c]=90', 'c', 'variable.parameter.axis' + S);
    expectToken('G01 Pos[A]=-45 Fa[A]=25', 'Fa', 'support.function.builtin' + S);
  });
  it('numbers .5, 53., ,5 and operators', () => {
    expectToken('R1 = .5', '.5', 'constant.numeric' + S);
    expectToken('R1 = 53.', '53.', 'constant.numeric' + S);
    expectToken('R1 = ,5 * 2', ',5', 'constant.numeric' + S);
    expectToken('R1 = ,5 * 2', '*', 'keyword.operator.arithmetic' + S);
    for (const op of ['==', '<>', '>=', '<=', '<', '>']) {
      expectToken(`IF R1 ${op} 2 GOTOF L`, op, 'keyword.operator.comparison' + S);
    }
  });
});

describe('continuation and errors (SPEC §2)', () => {
  it('"$" not followed by a letter or "_" continues the line; its tail is ignored', () => {
    const line = 'N150 G64 G01 Pos[X] = R20 $ segue sulla riga successiva';
    expectToken(line, '$', 'constant.character.escape.line-continuation' + S);
    expectToken(line, ' segue sulla riga successiva', 'comment.line.continuation' + S);
    expectToken('X10$', '$', 'constant.character.escape.line-continuation' + S);
    expectToken([line, '     Pos[Y] = R21 - R22 F=R23'], 'Pos', 'support.function.builtin' + S);
    expectNotScope('$aa_out[3] = 1', '$aa_out', 'constant.character.escape');
  });
  it('errors are marked invalid.illegal', () => {
    assert.ok(hasIllegal('( a $ in a comment )'), '"$" inside ( ) is an error');
    assert.ok(hasIllegal('R1 = $aa_pippo[1]'), 'unknown system variable');
    assert.ok(hasIllegal('G0 X10 velocità'), 'bytes >= 0x80 outside comments');
    assert.ok(hasIllegal('X10 )'), 'unbalanced ")"');
    assert.ok(!hasIllegal('; velocità $ ( ) è'), 'anything goes in a ";" comment');
    assert.ok(!hasIllegal('SEMI "Perché? $ ;"'), 'anything but a quote goes in the SEMI string');
  });
});

// --- every line of every sample ----------------------------------------------------------

function sampleFiles() {
  const files = [];
  for (const set of fs.readdirSync(SAMPLES, { withFileTypes: true })) {
    if (!set.isDirectory()) continue;
    for (const f of fs.readdirSync(path.join(SAMPLES, set.name))) {
      if (/\.(mpf|spf)$/i.test(f)) files.push(path.join(SAMPLES, set.name, f));
    }
  }
  return files.sort();
}

// Where the ";" comment starts by SPEC §2 step 1: the first ";" outside a string and outside
// parentheses (the samples hold no ";" inside a group), or -1.
function semicolonComment(line) {
  let inString = false;
  let depth = 0;
  for (let i = 0; i < line.length; i++) {
    const c = line[i];
    if (inString) {
      if (c === '"') inString = false;
    } else if (c === '"') inString = true;
    else if (c === '(') depth++;
    else if (c === ')') depth = Math.max(0, depth - 1);
    else if (c === ';' && depth === 0) return i;
  }
  return -1;
}

describe('samples', () => {
  const files = sampleFiles();
  it('finds the sample programs', () => {
    assert.ok(files.length >= 10, `samples in ${SAMPLES}: ${files.length}`);
  });
  for (const file of files) {
    it(path.relative(SAMPLES, file), () => {
      const lines = fs.readFileSync(file, 'utf8').replace(/^\uFEFF/, '').split(/\r?\n/);
      let state = vsctm.INITIAL;
      lines.forEach((line, i) => {
        const where = `${path.relative(SAMPLES, file)}:${i + 1}: ${line}`;
        const r = grammar.tokenizeLine(line, state);
        state = r.ruleStack;
        const scopesAt = (col) => r.tokens.find((t) => t.startIndex <= col && col < t.endIndex).scopes;
        for (const t of r.tokens) {
          const bad = t.scopes.find((s) => s.startsWith('invalid.illegal'));
          assert.ok(!bad, `${where}\n  ${bad} on ${JSON.stringify(line.slice(t.startIndex, t.endIndex))}`);
        }
        for (let col = 0; col < line.length; col++) {
          if (/\s/.test(line[col])) continue;
          assert.ok(scopesAt(col).length > 1, `${where}\n  column ${col + 1} (${line[col]}) has no scope`);
        }
        const start = semicolonComment(line);
        if (start >= 0) {
          for (let col = start; col < line.length; col++) {
            assert.ok(scopesAt(col).some((s) => s.startsWith('comment.')),
              `${where}\n  column ${col + 1} after ";" is not a comment: ${scopesAt(col).join(' ')}`);
          }
        }
        assert.equal(state.depth, 1, `${where}\n  a region stays open past the end of the line`);
      });
    });
  }
});
