// The dose (issue 42): active training time and repetitions per day and per week against the
// prescription, as rehabilitation studies report a home programme's dose (ArmeoSenso: minutes a
// week; MindMotion GO: active training time; MusicGlove: repetitions a day). Active time is the
// sessions' `active_s` (pauses and rests not counted), repetitions their `movements` (discrete
// wheel movements). Weeks are the 7 local days ending today and the weeks before them, as the
// caseload's "last 7 days"; a week under 90 % of the prescribed minutes is marked, as the
// hub's adherence alert marks it. On the page and on its print.
import { esc } from '/console/api.js';
import { t } from '/console/i18n.js';
import { activeWords, dayWords } from '/console/words.js';

/** Weeks the dose table goes back, the current one included. */
export const DOSE_WEEKS = 8;

/** Share of the prescribed weekly minutes under which a week is marked (the hub's alert's). */
const BELOW_SHARE = 0.9;

/** Local midnight `days` days after the local day of `ms` (negative: before); calendar days,
 * so a change to or from summer time does not shift a day. */
function dayStart(ms, days = 0) {
  const d = new Date(ms);
  d.setHours(0, 0, 0, 0);
  d.setDate(d.getDate() + days);
  return d.getTime();
}

/** The dose per local day and per week: `sessions` (oldest first, each with
 * `started_unix_ms`) and their `metrics` (same order, name → value); a session without an
 * `active_s` did not train and is not counted. Days: the last 7, today first; weeks: the last
 * `weeks` windows of 7 days, the one ending today first, none wholly before the first
 * session. Each: `{ fromMs, toMs, sessions,
 * activeS, repetitions }` (`toMs` exclusive). */
export function doseTotals(sessions, metrics, nowMs, weeks = DOSE_WEEKS) {
  const window = (fromMs, toMs) => ({ fromMs, toMs, sessions: 0, activeS: 0, repetitions: 0 });
  const tomorrow = dayStart(nowMs, 1);
  const days = Array.from({ length: 7 }, (_, i) => window(dayStart(nowMs, -i), dayStart(nowMs, 1 - i)));
  // No week before the patient's first session: they had not started.
  const first = Math.min(...sessions.map(s => s.started_unix_ms).filter(ms => typeof ms === 'number'));
  const weekRows = Array.from({ length: weeks }, (_, w) => window(dayStart(nowMs, -7 * w - 6), dayStart(nowMs, 1 - 7 * w)))
    .filter((w, i) => i === 0 || w.toMs > first);
  sessions.forEach((s, i) => {
    const m = metrics[i] || {};
    const at = s.started_unix_ms;
    if (typeof m.active_s !== 'number' || typeof at !== 'number' || at >= tomorrow) return;
    const reps = typeof m.movements === 'number' ? m.movements : 0;
    for (const row of [...days, ...weekRows]) {
      if (at >= row.fromMs && at < row.toMs) {
        row.sessions += 1;
        row.activeS += m.active_s;
        row.repetitions += reps;
      }
    }
  });
  return { days, weeks: weekRows };
}

/** The dose section's HTML: `overview` is the caseload's row of the patient (its prescription:
 * `sessions_per_week_prescribed`, `minutes_per_week_prescribed`; may be absent). */
export function doseSection(sessions, metrics, overview, nowMs = Date.now()) {
  const { days, weeks } = doseTotals(sessions, metrics, nowMs);
  const perWeek = overview?.sessions_per_week_prescribed ?? null;
  const minutesPerWeek = overview?.minutes_per_week_prescribed ?? null;
  const prescribedS = minutesPerWeek == null ? undefined : minutesPerWeek * 60;
  const count = n => String(Math.round(n));
  const head = first => `<thead><tr><th scope="col">${esc(t(first))}</th><th scope="col">${esc(t('progress-dose-col-sessions'))}</th>
    <th scope="col">${esc(t('progress-dose-col-active'))}</th><th scope="col">${esc(t('progress-dose-col-repetitions'))}</th></tr></thead>`;
  const weekRows = weeks.map((w, i) => {
    const below = prescribedS != null && w.activeS < BELOW_SHARE * prescribedS;
    const sessionsWords = perWeek == null ? count(w.sessions) : t('words-of-prescribed', { done: count(w.sessions), prescribed: count(perWeek) });
    return `<tr data-week="${i}" data-sessions="${w.sessions}" data-active-s="${esc(Math.round(w.activeS))}" data-repetitions="${esc(Math.round(w.repetitions))}"${below ? ' data-below="1"' : ''}>
      <th scope="row">${esc(t('progress-dose-week-range', { from: dayWords(w.fromMs), to: dayWords(w.toMs - 1) }))}</th>
      <td>${esc(sessionsWords)}</td><td>${esc(activeWords(w.activeS, prescribedS))}${below ? ` <strong class="badge alert">${esc(t('progress-dose-below'))}</strong>` : ''}</td>
      <td class="num">${esc(count(w.repetitions))}</td></tr>`;
  }).join('');
  const dayRows = days.map((d, i) => `<tr data-day="${i}" data-active-s="${esc(Math.round(d.activeS))}" data-repetitions="${esc(Math.round(d.repetitions))}">
      <th scope="row">${esc(dayWords(d.fromMs))}</th><td>${esc(count(d.sessions))}</td><td>${esc(activeWords(d.activeS))}</td>
      <td class="num">${esc(count(d.repetitions))}</td></tr>`).join('');
  return `<h2 id="dose-h">${esc(t('progress-dose-title'))}</h2>
    <p class="note">${esc(t('progress-dose-explain'))}</p>
    <div class="summary-grid dose-grid">
    <table id="dose-weeks"><caption>${esc(t('progress-dose-weeks-caption', { weeks: weeks.length }))}</caption>${head('progress-dose-col-week')}<tbody>${weekRows}</tbody></table>
    <table id="dose-days"><caption>${esc(t('progress-dose-days-caption'))}</caption>${head('progress-dose-col-day')}<tbody>${dayRows}</tbody></table></div>`;
}
