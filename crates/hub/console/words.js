// Sessions and exercises in words, and trends like with like (issue 29): a session is named by
// its date and time and its exercises as the patient saw them (never its id), and a trend
// compares the latest session that ran as prescribed with earlier ones of the same exercise
// kind (road, dial, …) that did too, as the hub's caseload does (crates/hub/API.md).
import { esc, when } from '/console/api.js';

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
  return `${when(s.started_unix_ms)} · ${s.exercise_name || plainName(s.exercise)}`;
}

/** The kind of exercise in words, for "… sessions" ("road", "dial", "dial and road"). */
export function kindWords(kind) {
  return String(kind ?? '').split('+').join(' and ');
}

/** How a session ended, as HTML (escaped): ran as prescribed, still running, or ended early
 * with the station's reason, marked. */
export function endWords(s) {
  if (s.ran_as_prescribed) return 'ended: complete';
  if (!s.closed_at_ms && !s.end_reason) return 'running';
  return `<span class="badge warn">ended early</span> ${esc(s.end_reason || 'no reason given')}
    <span class="note">(not in the trends)</span>`;
}

/** The trend of `values` (newest first, numbers or undefined) as HTML: the latest against the
 * mean of the others; `better` is 'up' or 'down'. Empty without two values. */
export function trendWords(values, better) {
  const vs = values.filter(v => typeof v === 'number');
  if (vs.length < 2 || typeof values[0] !== 'number') return '';
  const [last, ...before] = vs;
  const mean = before.reduce((a, b) => a + b, 0) / before.length;
  if (Math.abs(last - mean) <= 0.02 * Math.max(1e-9, Math.abs(mean))) return '→ steady';
  const up = last > mean, good = up === (better === 'up');
  return `<span class="${good ? 'up' : 'down'}">${up ? '↑' : '↓'} ${good ? 'better' : 'worse'}</span>`;
}

/** Active time against the prescribed time, never better or worse: "540 s of 600 s
 * prescribed". */
export function activeWords(activeS, prescribedS) {
  if (typeof activeS !== 'number') return '—';
  const active = `${Math.round(activeS)} s`;
  return typeof prescribedS === 'number' ? `${active} of ${Math.round(prescribedS)} s prescribed` : active;
}
