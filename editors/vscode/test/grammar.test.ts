// grammar.test.ts: runs the extension's TextMate grammar (syntaxes/nome.tmLanguage.json)
// with the engine VS Code uses (vscode-textmate + vscode-oniguruma) over hand-written
// snippets and every examples/*.nome file, and asserts the scopes of keywords, end keywords,
// numbers, `$bank.param` parameters, `{expr …}`, comments (nested `(* *)`) and strings.
//
// Usage: node out/test/grammar.test.js     (NOME_GRAMMAR_EXTRA_DIRS=dir:dir adds more files,
// e.g. the corpus, checked with the same file-wide invariants as the examples)
import { test } from "node:test";
import * as assert from "node:assert/strict";
import * as fs from "node:fs";
import * as path from "node:path";
import * as oniguruma from "vscode-oniguruma";
import * as vsctm from "vscode-textmate";

const extensionRoot = path.resolve(__dirname, "..", "..");
const repoRoot = path.resolve(extensionRoot, "..", "..");

interface Token {
  line: number;
  text: string;
  scopes: string[];
}

let grammarPromise: Promise<vsctm.IGrammar> | undefined;

function loadGrammar(): Promise<vsctm.IGrammar> {
  grammarPromise ??= (async () => {
    const wasm = fs.readFileSync(require.resolve("vscode-oniguruma/release/onig.wasm"));
    await oniguruma.loadWASM(wasm.buffer.slice(wasm.byteOffset, wasm.byteOffset + wasm.byteLength));
    const registry = new vsctm.Registry({
      onigLib: Promise.resolve({
        createOnigScanner: (patterns: string[]) => new oniguruma.OnigScanner(patterns),
        createOnigString: (s: string) => new oniguruma.OnigString(s),
      }),
      loadGrammar: async (scopeName: string) => {
        if (scopeName !== "source.nome") return null;
        const file = path.join(extensionRoot, "syntaxes", "nome.tmLanguage.json");
        return vsctm.parseRawGrammar(fs.readFileSync(file, "utf8"), file);
      },
    });
    const grammar = await registry.loadGrammar("source.nome");
    if (!grammar) throw new Error("source.nome did not load");
    return grammar;
  })();
  return grammarPromise;
}

async function tokenize(text: string): Promise<Token[]> {
  const grammar = await loadGrammar();
  const out: Token[] = [];
  let stack = vsctm.INITIAL;
  text.split(/\r?\n/).forEach((line, i) => {
    const r = grammar.tokenizeLine(line, stack, 1000);
    assert.ok(!r.stoppedEarly, `line ${i + 1} took too long to tokenize`);
    for (const t of r.tokens) out.push({ line: i, text: line.slice(t.startIndex, t.endIndex), scopes: t.scopes });
    stack = r.ruleStack;
  });
  return out;
}

// The scopes of the `occurrence`-th token whose text is exactly `text`.
function scopesOf(tokens: Token[], text: string, occurrence = 0): string[] {
  const found = tokens.filter((t) => t.text === text);
  assert.ok(found.length > occurrence, `no token ${JSON.stringify(text)} #${occurrence}; tokens: ${tokens.map((t) => t.text).join("|")}`);
  return found[occurrence].scopes;
}

function hasScope(scopes: string[], prefix: string): boolean {
  return scopes.some((s) => s === prefix || s.startsWith(prefix + "."));
}

function expectScope(tokens: Token[], text: string, scope: string, occurrence = 0): void {
  const scopes = scopesOf(tokens, text, occurrence);
  assert.ok(hasScope(scopes, scope), `${JSON.stringify(text)} #${occurrence} has ${scopes.join(" ")}, expected ${scope}`);
}

function expectNotScope(tokens: Token[], text: string, scope: string, occurrence = 0): void {
  const scopes = scopesOf(tokens, text, occurrence);
  assert.ok(!hasScope(scopes, scope), `${JSON.stringify(text)} #${occurrence} has ${scopes.join(" ")}, expected no ${scope}`);
}

test("bank, set, numbers and end keywords", async () => {
  const tokens = await tokenize(
    ["bank fp", "    set n 8 3 10 1", "    set ratio -0.2 -.5 1e-3 0.1", "endbank"].join("\n")
  );
  expectScope(tokens, "bank", "keyword.control.block.nome");
  expectScope(tokens, "fp", "entity.name.definition.nome");
  expectScope(tokens, "set", "keyword.other.command.nome");
  expectScope(tokens, "n", "variable.other.parameter.definition.nome");
  for (const n of ["8", "3", "10", "1", "-0.2", "-.5", "1e-3", "0.1"]) expectScope(tokens, n, "constant.numeric.nome");
  expectScope(tokens, "endbank", "keyword.control.end.nome");
});

test("parameters and {expr …}", async () => {
  const tokens = await tokenize("funnel fun ({expr $fp_n} {expr $fp.ro * 2} {expr sin($a.b) - 1} $time) endfunnel");
  expectScope(tokens, "funnel", "keyword.control.block.generator.nome");
  expectScope(tokens, "fun", "entity.name.definition.nome");
  expectScope(tokens, "expr", "keyword.other.expr.nome", 0);
  expectScope(tokens, "expr", "meta.expression.nome", 1);
  expectScope(tokens, "{", "punctuation.section.braces.begin.nome");
  for (const p of ["fp_n", "fp.ro", "a.b", "time"]) expectScope(tokens, p, "variable.other.parameter.nome");
  expectScope(tokens, "$", "punctuation.definition.variable.nome");
  expectScope(tokens, "2", "constant.numeric.nome");
  expectScope(tokens, "sin", "support.function.math.nome");
  expectScope(tokens, "*", "keyword.operator.arithmetic.nome");
  expectScope(tokens, "endfunnel", "keyword.control.end.nome");
});

test("comments: # and nested (* *)", async () => {
  const tokens = await tokenize(
    ["# a line comment: mesh 1 $x", "(* outer (* inner mesh *) still comment 3 *) mesh m1", "(* spans", "lines endmesh *) endmesh"].join("\n")
  );
  expectScope(tokens, "#", "punctuation.definition.comment.nome");
  assert.ok(tokens.filter((t) => t.line === 0).every((t) => hasScope(t.scopes, "comment.line.number-sign.nome")));
  // Everything up to the outer `*)` is comment, including the text after the inner `*)`.
  const line1 = tokens.filter((t) => t.line === 1);
  const close = line1.findIndex((t, i) => t.text === "*)" && i > 0 && line1.slice(0, i).filter((u) => u.text === "*)").length === 1);
  assert.ok(close > 0, line1.map((t) => t.text).join("|"));
  assert.ok(line1.slice(0, close + 1).every((t) => hasScope(t.scopes, "comment.block.nome")), "nested comment stays a comment");
  const still = line1.find((t) => t.text.includes("still comment"));
  assert.ok(still && hasScope(still.scopes, "comment.block.nome"));
  expectScope(tokens, "mesh", "keyword.control.block.nome", 0);
  assert.ok(line1.slice(close + 1).some((t) => t.text === "mesh" && !hasScope(t.scopes, "comment")), "after the comment, mesh is a keyword");
  const spanned = tokens.filter((t) => t.line === 3 && t.text.includes("lines endmesh"));
  assert.ok(spanned.length === 1 && hasScope(spanned[0].scopes, "comment.block.nome"), "a block comment spans lines");
  const lastEnd = tokens.filter((t) => t.text === "endmesh").pop()!;
  assert.ok(hasScope(lastEnd.scopes, "keyword.control.end.nome"));
});

test("strings, instances, commands and names", async () => {
  const tokens = await tokenize(
    ['include "viewing.slf"', "instance fun1 fun translate (0 0 {expr $fp_z}) rotate (1 0 0) (-90) endinstance", "group endgroupx myendgroup endgroup", "instance lonely endinstance", "mesh endcap endmesh"].join("\n")
  );
  expectScope(tokens, "include", "keyword.control.import.nome");
  expectScope(tokens, "viewing.slf", "string.quoted.double.nome");
  expectScope(tokens, "instance", "keyword.control.block.nome");
  expectScope(tokens, "fun1", "entity.name.instance.nome");
  expectScope(tokens, "fun", "entity.name.type.reference.nome");
  expectScope(tokens, "translate", "keyword.other.command.nome");
  expectScope(tokens, "rotate", "keyword.other.command.nome");
  expectScope(tokens, "-90", "constant.numeric.nome");
  expectScope(tokens, "fp_z", "variable.other.parameter.nome");
  expectScope(tokens, "(", "punctuation.section.parens.begin.nome");
  expectScope(tokens, "endinstance", "keyword.control.end.nome");
  // End keywords only as whole words.
  expectNotScope(tokens, "endgroupx", "keyword");
  expectNotScope(tokens, "myendgroup", "keyword");
  expectScope(tokens, "endgroup", "keyword.control.end.nome");
  // An end keyword right after a name is not taken for a second name (SLIDE's
  // `instance NAME endinstance`), but a name that merely starts with "end" is a name.
  expectScope(tokens, "lonely", "entity.name.instance.nome");
  expectScope(tokens, "endinstance", "keyword.control.end.nome", 1);
  expectScope(tokens, "endcap", "entity.name.definition.nome");
  expectScope(tokens, "endmesh", "keyword.control.end.nome");
});

const END_KEYWORD = /^end[a-z]+$/;

// File-wide invariants, checked against a simple independent scan of the text.
async function checkFile(file: string): Promise<{ keywords: number; numbers: number; params: number; comments: number }> {
  const text = fs.readFileSync(file, "utf8");
  const tokens = await tokenize(text);
  const inCommentOrString = (t: Token) => hasScope(t.scopes, "comment") || hasScope(t.scopes, "string");
  const where = (t: Token) => `${path.basename(file)}:${t.line + 1}: ${JSON.stringify(t.text)} has ${t.scopes.join(" ")}`;
  const counts = { keywords: 0, numbers: 0, params: 0, comments: 0 };

  // Lines whose first non-blank character is `#` are entirely comment (outside block comments).
  for (const t of tokens) {
    if (inCommentOrString(t)) {
      if (hasScope(t.scopes, "comment")) counts.comments++;
      continue;
    }
    if (END_KEYWORD.test(t.text) && hasScope(t.scopes, "keyword.control.end.nome")) counts.keywords++;
    if (hasScope(t.scopes, "keyword.control.block")) counts.keywords++;
    // A `$` starts a parameter, and the name after it is one.
    if (t.text === "$") assert.ok(hasScope(t.scopes, "variable.other.parameter.nome"), where(t));
    if (hasScope(t.scopes, "variable.other.parameter.nome") && t.text !== "$") counts.params++;
    // Numbers are numbers, and nothing that is not a number is scoped as one.
    if (/^[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?$/.test(t.text.trim()) && t.text.trim() !== "") {
      assert.ok(hasScope(t.scopes, "constant.numeric.nome"), where(t));
    }
    if (hasScope(t.scopes, "constant.numeric.nome")) {
      assert.match(t.text, /^[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?$/, where(t));
      counts.numbers++;
    }
  }
  // Every `#` line comment outside a `(* *)` comment: the whole rest of its line is comment.
  for (const t of tokens.filter((u) => u.text === "#" && hasScope(u.scopes, "punctuation.definition.comment.nome"))) {
    const rest = tokens.filter((u) => u.line === t.line && tokens.indexOf(u) > tokens.indexOf(t));
    for (const u of rest) assert.ok(hasScope(u.scopes, "comment"), where(u));
  }
  // Each end keyword as a whole word outside comments and strings is scoped as one.
  for (const t of tokens) {
    if (!inCommentOrString(t) && END_KEYWORD.test(t.text.trim()) && /^end(bank|mesh|group|instance|funnel|tunnel|face|surface|point|polyline|subdivision|offset|consolidate|savedparameter)$/.test(t.text.trim())) {
      assert.ok(hasScope(t.scopes, "keyword.control.end.nome"), where(t));
    }
  }
  return counts;
}

test("every examples/*.nome file", async () => {
  const dir = path.join(repoRoot, "examples");
  const files = fs.readdirSync(dir).filter((f) => f.endsWith(".nome")).map((f) => path.join(dir, f));
  assert.ok(files.length >= 3, `examples found: ${files.join(", ")}`);
  for (const file of files) {
    const c = await checkFile(file);
    assert.ok(c.keywords > 0 && c.numbers > 0 && c.params > 0 && c.comments > 0, `${path.basename(file)}: ${JSON.stringify(c)}`);
  }
  // The funnel cube, exactly: 5 set lines, 6 instances + 1, 6 uses of $fp_z.
  const tokens = await tokenize(fs.readFileSync(path.join(dir, "funnel_cube.nome"), "utf8"));
  assert.equal(tokens.filter((t) => t.text === "set" && hasScope(t.scopes, "keyword.other.command.nome")).length, 5);
  assert.equal(tokens.filter((t) => t.text === "endinstance" && hasScope(t.scopes, "keyword.control.end.nome")).length, 7);
  assert.equal(tokens.filter((t) => t.text === "fp_z" && hasScope(t.scopes, "variable.other.parameter.nome")).length, 6);
  assert.equal(tokens.filter((t) => t.text === "funnel" && hasScope(t.scopes, "keyword.control.block.generator.nome")).length, 1);
});

// Only when asked (CTest passes the corpus): every file there, with the same invariants.
const extraDirs = (process.env.NOME_GRAMMAR_EXTRA_DIRS ?? "").split(path.delimiter).filter((d) => d !== "");
if (extraDirs.length > 0) {
  test(`every NOME file under ${extraDirs.join(", ")}`, async () => {
    const files: string[] = [];
    const walk = (d: string) => {
      for (const e of fs.readdirSync(d, { withFileTypes: true })) {
        const p = path.join(d, e.name);
        if (e.isDirectory()) walk(p);
        else if (/\.(nome|nom|slf|anom)$/.test(e.name)) files.push(p);
      }
    };
    extraDirs.forEach(walk);
    assert.ok(files.length > 0, `no NOME files under ${extraDirs.join(", ")}`);
    for (const file of files) await checkFile(file);
  });
}
