// Sessions, measures and dates in a clinician's words (issues 29, 41). The measures' plain
// names, units, meaningful decimals, axis ranges, noise and which way is better come from the
// ONE table of measure words (crates/metrics/src/words.rs), which the hub serves as
// GET /api/measures/words: nothing here re-types them. A session is named by its date and time
// and its exercises as the patient saw them (never its id); how it ended in the one wording the
// hub gives (`end_words`). Dates in ONE format per locale: the browser's, through
// Intl.DateTimeFormat.
import { api, esc } from '/console/api.js';

let table = null;

/** The words table ({measures: Map key → words, endReasons: Map kind → words}), fetched once
 * per page. */
export async function measureWords() {
  if (!table) {
    table = api('GET', '/api/measures/words').then(w => ({
      measures: new Map(w.measures.map(m => [m.key, m])),
      list: w.measures,
      endReasons: new Map(w.end_reasons.map(e => [e.kind, e.words])),
    })).catch(e => { table = null; throw e; });
  }
  return table;
}

const dateTime = new Intl.DateTimeFormat(undefined, { dateStyle: 'medium', timeStyle: 'short' });
const dateOnly = new Intl.DateTimeFormat(undefined, { dateStyle: 'medium' });
const dayMonth = new Intl.DateTimeFormat(undefined, { day: 'numeric', month: 'short' });
const time = new Intl.DateTimeFormat(undefined, { hour: '2-digit', minute: '2-digit' });
const timeSeconds = new Intl.DateTimeFormat(undefined, { hour: '2-digit', minute: '2-digit', second: '2-digit' });

/** A date and time: the browser locale's medium date and short time ("27 Nov 2026, 09:30"). */
export function whenWords(ms) {
  return ms == null ? '—' : dateTime.format(new Date(ms));
}

/** A date alone, the same format ("27 Nov 2026"). */
export function dayWords(ms) {
  return ms == null ? '—' : dateOnly.format(new Date(ms));
}

/** A day `YYYY-MM-DD` (a clinical scale's) in the same format, at local noon. */
export function isoDayWords(day) {
  const [y, m, d] = String(day).split('-').map(Number);
  return y ? dateOnly.format(new Date(y, m - 1, d, 12)) : String(day);
}

/** A session on a chart's axis: day and month, then the time ("27 Nov 09:30"); `seconds`
 * adds them (two sessions in one minute). */
export function shortWords(ms, seconds = false) {
  const d = new Date(ms);
  return `${dayMonth.format(d)} ${(seconds ? timeSeconds : time).format(d)}`;
}

/** An exercise's short name as the patient sees it (`sine-road` → `Sine road`; the station's
 * `screen::plain_name`); a regimen session (`regimen:2`) as "A regimen of 2 exercises". */
export function plainName(short) {
  const s = String(short ?? '');
  const regimen = s.match(/^regimen:(\d+)$/);
  if (regimen) return `A regimen of ${regimen[1]} exercise${regimen[1] === '1' ? '' : 's'}`;
  const spaced = s.replace(/-/g, ' ');
  return spaced.charAt(0).toUpperCase() + spaced.slice(1);
}

/** A session in words: "27 Nov 2026, 09:30 · Sine road". */
export function sessionWords(s) {
  return `${whenWords(s.started_unix_ms)} · ${s.exercise_name || plainName(s.exercise)}`;
}

/** The kind of exercise in words, for "… sessions" ("road", "dial", "dial and road"). */
export function kindWords(kind) {
  return String(kind ?? '').split('+').join(' and ');
}

/** How a session ended, as HTML (escaped): the hub's one wording, an early end marked. */
export function endWords(s) {
  const words = s.end_words || (s.ran_as_prescribed ? 'Completed' : s.end_reason ? 'Stopped early' : 'Still running');
  if (s.ran_as_prescribed || s.end_kind === 'running' || (!s.end_kind && !s.closed_at_ms && !s.end_reason)) return esc(words);
  return `<span class="badge warn">${esc(words)}</span> <span class="note">(not in the trends)</span>`;
}

/** `v` of measure `m` (the table's words) rounded to its meaningful decimals, without unit;
 * "—" when absent; never "-0". */
export function numberWords(m, v) {
  if (typeof v !== 'number' || !Number.isFinite(v)) return '—';
  const decimals = m ? m.decimals : 2;
  const s = v.toFixed(decimals);
  return Number(s) === 0 ? (0).toFixed(decimals) : s;
}

/** `v` of measure `m` rounded, with its unit ("268 °", "97 %", "0.42"). */
export function valueWords(m, v) {
  const n = numberWords(m, v);
  return n === '—' || !m || !m.unit ? n : `${n} ${m.unit}`;
}

/** A measure's plain name with its unit: "Time in lane (%)". */
export function headerWords(m) {
  return m.unit ? `${m.name} (${m.unit})` : m.name;
}

/** Whether the change from `base` to `last` is beyond measure `m`'s noise (always, when its
 * noise is unknown). */
export function beyondNoise(m, last, base) {
  if (!m || !m.noise) return true;
  const half = m.noise.kind === 'relative' ? Math.abs(m.noise.value * base) : m.noise.value;
  return Math.abs(last - base) > half;
}

/** The noise band around `base` ([low, high]), or null when the measure's noise is unknown. */
export function noiseBand(m, base) {
  if (!m || !m.noise || typeof base !== 'number') return null;
  const half = m.noise.kind === 'relative' ? Math.abs(m.noise.value * base) : m.noise.value;
  return [base - half, base + half];
}

/** The trend of `values` (newest first, numbers or undefined) as HTML: the latest against the
 * mean of the others; `m` the measure's words (its `better` and `noise`). A change within the
 * measure's noise (or 2 % when unknown) is steady. Empty without two values. */
export function trendWords(values, m) {
  const vs = values.filter(v => typeof v === 'number');
  if (vs.length < 2 || typeof values[0] !== 'number') return '';
  const [last, ...before] = vs;
  const mean = before.reduce((a, b) => a + b, 0) / before.length;
  const within = m && m.noise ? !beyondNoise(m, last, mean)
    : Math.abs(last - mean) <= 0.02 * Math.max(1e-9, Math.abs(mean));
  if (within || !m || m.better === 'neither') return '→ steady';
  const up = last > mean, good = up === (m.better === 'higher');
  return `<span class="${good ? 'up' : 'down'}">${up ? '↑' : '↓'} ${good ? 'better' : 'worse'}</span>`;
}

/** Active time against the prescribed time, never better or worse: in minutes ("9 min of 10
 * min prescribed"), in seconds when the prescription is under two minutes ("45 s of 60 s"). */
export function activeWords(activeS, prescribedS) {
  if (typeof activeS !== 'number') return '—';
  const seconds = Math.max(activeS, typeof prescribedS === 'number' ? prescribedS : 0) < 120;
  const t = s => (seconds ? `${Math.round(s)} s` : `${Math.round(s / 60)} min`);
  return typeof prescribedS === 'number' ? `${t(activeS)} of ${t(prescribedS)} prescribed` : t(activeS);
}

/** A station by when it was paired, never its internal id: "station paired 3 Dec 2026". */
export function stationWords(s) {
  return `station paired ${dayWords(s.paired_at_ms)}`;
}
