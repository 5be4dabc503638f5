// The assistance of an exercise in the prescribe form: the mode in words (a select) and its
// level with the schema's bounds, written back to `[exercise.assist.mode]` (the mode's other
// settings kept as they were; edit them as TOML).

import { t } from '/console/i18n.js';

/** Each mode in the therapist's words: its catalogue message (`assist-mode-<kind>`), else the
 * kind itself. */
const modeWords = kind => { const id = `assist-mode-${kind}`; const w = t(id); return w === id ? kind : w; };

/** The field a mode's level is, `[path…]` inside the mode, and its words' message id. */
const LEVEL = {
  motion: [['authority'], 'assist-level-guidance'],
  hybrid: [['motion', 'authority'], 'assist-level-guidance'],
  force: [['fraction'], 'assist-level-effort'],
};

export { assistModes } from '/console/schema.js';

/** The level's spec of `kind` from `modes` (undefined when the mode has none). */
function levelSpec(modes, kind) {
  const m = modes.find(x => x.kind === kind);
  const level = LEVEL[kind];
  if (!m || !level) return undefined;
  const [path] = level;
  const fields = path.length === 2 ? m.motion : m.fields;
  const f = fields.find(([name]) => name === path[path.length - 1]);
  return f && f[1];
}

const levelOf = (mode, kind) => {
  const level = LEVEL[kind];
  if (!mode || !level) return undefined;
  return level[0].reduce((v, k) => (v == null ? undefined : v[k]), mode);
};

/** The assistance fields of exercise `i` (HTML): the mode and, for a mode with one, its level;
 * `numberField` and `esc` are the form's. */
export function assistFields(i, assist, modes, numberField, esc) {
  const kind = assist && assist.mode ? assist.mode.kind : '';
  const options = [['', t('assist-mode-station')],
    ...modes.map(m => [m.kind, modeWords(m.kind)])]
    .map(([k, w]) => `<option value="${esc(k)}"${k === kind ? ' selected' : ''}>${esc(w)}</option>`).join('');
  const spec = levelSpec(modes, kind);
  const level = spec ? numberField(`ex${i}-assist-level`, t(LEVEL[kind][1]), levelOf(assist.mode, kind), spec) : '';
  return `<label for="ex${i}-assist">${esc(t('assist-label'))}</label>
    <select id="ex${i}-assist" data-assist="${i}">${options}</select>
    ${level}`;
}

/** Reads exercise `i`'s assistance from the form into `e` (`num(sel)` the form's number
 * reader): the mode chosen, its level, its other settings kept when the mode is unchanged. */
export function readAssist(el, i, e, num) {
  const select = el.querySelector(`#ex${i}-assist`);
  if (!select) return;
  const kind = select.value;
  if (!kind) { delete e.assist; return; }
  const before = e.assist && e.assist.mode && e.assist.mode.kind === kind ? e.assist.mode : { kind };
  const mode = JSON.parse(JSON.stringify(before));
  const level = LEVEL[kind];
  const v = num(`#ex${i}-assist-level`);
  if (level) {
    const [path] = level;
    let at = mode;
    for (const k of path.slice(0, -1)) { at[k] = at[k] || {}; at = at[k]; }
    if (v === undefined) delete at[path[path.length - 1]]; else at[path[path.length - 1]] = v;
  }
  e.assist = { ...(e.assist || {}), mode };
}
