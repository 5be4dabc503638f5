// Sessions, measures and dates in a clinician's words (issues 29, 40, 41). The measures' keys,
// units, meaningful decimals, axis ranges, noise and which way is better come from the ONE
// table of measure words (crates/metrics/src/words.rs), which the hub serves as
// GET /api/measures/words; their plain names and the end reasons' wording are messages of the
// console's catalogues (`words-measure-<key>`, `words-end-<kind>`, the ids the table gives). A
// session is named by its date and time and its exercises (never its id). Dates and numbers in
// ONE format per language: the language in force (`locale()`), through Intl.
import { api, esc } from '/console/api.js';
import { t, locale, onLanguageChange } from '/console/i18n.js';

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

let dateTime, dateOnly, dayMonth, time, timeSeconds;
const formats = new Map();

/** The date formats of the language in force (made again when it changes). */
function makeFormats() {
  const l = locale();
  dateTime = new Intl.DateTimeFormat(l, { dateStyle: 'medium', timeStyle: 'short' });
  dateOnly = new Intl.DateTimeFormat(l, { dateStyle: 'medium' });
  dayMonth = new Intl.DateTimeFormat(l, { day: 'numeric', month: 'short' });
  time = new Intl.DateTimeFormat(l, { hour: '2-digit', minute: '2-digit' });
  timeSeconds = new Intl.DateTimeFormat(l, { hour: '2-digit', minute: '2-digit', second: '2-digit' });
  formats.clear();
}
makeFormats();
onLanguageChange(makeFormats);

/** A number with exactly `decimals` decimals in the language in force ("0,42" in German);
 * never "-0". */
function fixed(v, decimals) {
  if (!formats.has(decimals)) {
    formats.set(decimals, new Intl.NumberFormat(locale(), { minimumFractionDigits: decimals, maximumFractionDigits: decimals, useGrouping: false }));
  }
  const s = v.toFixed(decimals);
  return formats.get(decimals).format(Number(s) === 0 ? 0 : Number(s));
}

const kebab = s => String(s).replace(/_/g, '-');

/** A measure's plain name in the language in force ("Time in lane"), by its key. */
export function measureName(key) {
  return t(`words-measure-${kebab(key)}`);
}

/** What a measure measures, for the clinician, in the language in force, by its key
 * (`words-definition-<key>`; the English and its source are docs/MEASURES.md). */
export function measureDefinition(key) {
  return t(`words-definition-${kebab(key)}`);
}

/** How a session ended, by its end kind (`wheel_unplugged`), in the one wording. */
export function endKindWords(kind) {
  return t(`words-end-${kebab(kind || 'other')}`);
}

/** `v` of measure `m` in its decimals, with its unit when `unit` ("268 °", "0,42"). */
export function numberIn(m, v, unit = false) {
  const n = numberWords(m, v);
  return unit && m && m.unit && n !== '—' ? `${n} ${m.unit}` : n;
}

/** A date and time: the language's medium date and short time ("27 Nov 2026, 09:30"). */
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

/** An exercise's name in the console's language, by its short name (`sine-road` → "Sine
 * road", `words-exercise-<short>`); one the catalogues do not know reads as its short name in
 * words. A regimen session (`regimen:2`) is "A regimen of 2 exercises". */
export function plainName(short) {
  const s = String(short ?? '');
  const regimen = s.match(/^regimen:(\d+)$/);
  if (regimen) return t('words-regimen', { count: Number(regimen[1]) });
  const id = `words-exercise-${s}`;
  const named = t(id);
  if (named !== id) return named;
  const spaced = s.replace(/-/g, ' ');
  return spaced.charAt(0).toUpperCase() + spaced.slice(1);
}

/** A session's exercises in the console's language, in order ("Dial sine, then Sine road"),
 * from the short names the hub gives; else by its one exercise or regimen. */
export function exercisesWords(s) {
  const shorts = s.exercise_shorts || [];
  if (!shorts.length) return plainName(s.exercise);
  return shorts.map(plainName).reduce((first, next) => t('words-exercises-then', { first, next }));
}

/** A session in words: "27 Nov 2026, 09:30 · Sine road". */
export function sessionWords(s) {
  return `${whenWords(s.started_unix_ms)} · ${exercisesWords(s)}`;
}

/** The kind of exercise in words, for "… sessions" ("road", "dial", "dial and road"); a
 * kind the catalogues do not know (an exercise's own short name) as it is. */
export function kindWords(kind) {
  const parts = String(kind ?? '').split('+').filter(Boolean).map(k => {
    const w = t(`words-kind-${kebab(k)}`);
    return w === `words-kind-${kebab(k)}` ? k : w;
  });
  return parts.length > 1 ? t('words-kinds-and', { first: parts.slice(0, -1).join(', '), last: parts[parts.length - 1] }) : (parts[0] || '');
}

/** How a session ended, in the one wording: the hub's end kind, "; the recording stopped
 * early" when it did. */
export function endText(s) {
  const kind = s.end_kind || (s.ran_as_prescribed || s.end_reason === 'complete' ? 'complete' : s.end_reason ? 'other' : 'running');
  const words = endKindWords(kind);
  return s.recording_stopped_early ? t('words-end-recording-stopped', { end: words }) : words;
}

/** How a session ended, as HTML (escaped): the one wording, an early end marked. */
export function endWords(s) {
  const words = endText(s);
  if (s.ran_as_prescribed || s.end_kind === 'running' || (!s.end_kind && !s.closed_at_ms && !s.end_reason)) return esc(words);
  return `<span class="badge warn" data-end-kind="${esc(s.end_kind || '')}">${esc(words)}</span> <span class="note">${esc(t('words-not-in-trends'))}</span>`;
}

/** `v` of measure `m` (the table's words) rounded to its meaningful decimals, without unit;
 * "—" when absent; never "-0". */
export function numberWords(m, v) {
  if (typeof v !== 'number' || !Number.isFinite(v)) return '—';
  return fixed(v, m ? m.decimals : 2);
}

/** `v` of measure `m` rounded, with its unit ("268 °", "97 %", "0.42"). */
export function valueWords(m, v) {
  const n = numberWords(m, v);
  return n === '—' || !m || !m.unit ? n : `${n} ${m.unit}`;
}

/** A measure's plain name with its unit: "Time in lane (%)". */
export function headerWords(m) {
  const name = measureName(m.key);
  return m.unit ? t('words-name-unit', { name, unit: m.unit }) : name;
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
  if (within || !m || m.better === 'neither') return `→ ${esc(t('words-trend-steady'))}`;
  const up = last > mean, good = up === (m.better === 'higher');
  return `<span class="${good ? 'up' : 'down'}" data-direction="${good ? 'better' : 'worse'}">${up ? '↑' : '↓'} ${esc(t(good ? 'words-trend-better' : 'words-trend-worse'))}</span>`;
}

/** Active time against the prescribed time, never better or worse: in minutes ("9 min of 10
 * min prescribed"), in seconds when the prescription is under two minutes ("45 s of 60 s"). */
export function activeWords(activeS, prescribedS) {
  if (typeof activeS !== 'number') return '—';
  const seconds = Math.max(activeS, typeof prescribedS === 'number' ? prescribedS : 0) < 120;
  const span = s => (seconds ? t('words-seconds', { n: Math.round(s) }) : t('words-minutes', { n: Math.round(s / 60) }));
  return typeof prescribedS === 'number' ? t('words-of-prescribed', { done: span(activeS), prescribed: span(prescribedS) }) : span(activeS);
}

/** A station by when it was paired, never its internal id: "station paired 3 Dec 2026". */
export function stationWords(s) {
  return t('words-station-paired', { day: dayWords(s.paired_at_ms) });
}
