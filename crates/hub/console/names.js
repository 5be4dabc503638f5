// Who is who without the hub knowing names (issue 41; docs/DESIGN.md, "Who is who"): the
// clinic's own names for its pseudonyms, imported from a spreadsheet file into this browser
// (localStorage) and never sent anywhere. Every page that shows a pseudonym calls
// `displayName(pseudonym)`: "Anna Berg (P-0042)" when this browser has a name for it, else the
// pseudonym alone.

import { t } from '/console/i18n.js';

/** Where the list is kept in this browser. */
const KEY = 'telerehab.names.v1';
/** Longest name kept, characters. */
export const MAX_NAME_CHARS = 100;
/** Most names kept (a clinic's whole list, with room). */
export const MAX_NAMES = 5000;

let cache = null;

function load() {
  if (cache) return cache;
  try {
    const stored = JSON.parse(localStorage.getItem(KEY) || '{}');
    cache = new Map(Object.entries(stored).filter(([, v]) => typeof v === 'string'));
  } catch {
    cache = new Map();
  }
  return cache;
}

/** The name this browser holds for `pseudonym`, or undefined. */
export function nameOf(pseudonym) {
  return load().get(String(pseudonym ?? ''));
}

/** How a pseudonym is shown: "Anna Berg (P-0042)", or "P-0042" when no name is held here. */
export function displayName(pseudonym) {
  const p = String(pseudonym ?? '');
  const name = nameOf(p);
  return name ? t('names-display', { name, pseudonym: p }) : p;
}

/** Every name held here as [pseudonym, name], by pseudonym. */
export function allNames() {
  return [...load().entries()].sort(([a], [b]) => a.localeCompare(b));
}

/** Replaces the names held here with `pairs` ([pseudonym, name]). */
export function keepNames(pairs) {
  cache = new Map(pairs);
  localStorage.setItem(KEY, JSON.stringify(Object.fromEntries(cache)));
}

/** Forgets every name held here. */
export function forgetNames() {
  cache = new Map();
  localStorage.removeItem(KEY);
}

/** One CSV line's cells (commas, semicolons or tabs; "quoted" cells may hold them). */
function cells(line) {
  const sep = line.includes('\t') ? '\t' : (line.includes(';') && !line.includes(',') ? ';' : ',');
  const out = [];
  let cell = '', quoted = false;
  for (let i = 0; i < line.length; i++) {
    const c = line[i];
    if (quoted) {
      if (c === '"' && line[i + 1] === '"') { cell += '"'; i++; } else if (c === '"') quoted = false; else cell += c;
    } else if (c === '"') quoted = true;
    else if (c === sep) { out.push(cell.trim()); cell = ''; } else cell += c;
  }
  out.push(cell.trim());
  return out;
}

/** The pairs of a CSV text (the pseudonym, then the name; a first line naming the columns is
 * skipped), and each line that could not be read, in words. */
export function parseNamesCsv(text) {
  const pairs = new Map();
  const problems = [];
  const lines = String(text).replace(/^\uFEFF/, '').split(/\r?\n/);
  lines.forEach((line, i) => {
    if (!line.trim()) return;
    const [pseudonym = '', name = ''] = cells(line);
    if (i === 0 && /pseudonym/i.test(pseudonym)) return;
    const lineNo = i + 1;
    if (!pseudonym || !name) { problems.push(t('names-problem-cells', { line: lineNo })); return; }
    if ([...name].length > MAX_NAME_CHARS) { problems.push(t('names-problem-long', { line: lineNo, max: MAX_NAME_CHARS })); return; }
    if (pairs.has(pseudonym)) { problems.push(t('names-problem-twice', { line: lineNo, pseudonym })); return; }
    if (pairs.size >= MAX_NAMES) { problems.push(t('names-problem-many', { line: lineNo, max: MAX_NAMES })); return; }
    pairs.set(pseudonym, name);
  });
  return { pairs: [...pairs.entries()], problems };
}
