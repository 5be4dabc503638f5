// A patient's progress (issues 29, 41, 42), ordered as a clinician reads it: the standard
// assessment first (the same test for every patient, apart from the exercises: GET
// /api/patients/{id}/assessments, numbers as text); pain, adherence and alerts; then the assessment (the clinical scales); then the exercises — the latest
// session against the patient's own baseline, and each exercise kind's charts collapsed behind a
// one-line summary. Every measure is named, rounded and charted from the ONE table of measure
// words (words.js, GET /api/measures/words): one measure a chart, its axis from the measure's
// meaningful range, its noise as a band. Engineering names only behind "details". Sessions
// ended early are shown, marked and left out of the trends and baselines unless the therapist
// ticks "Include sessions that ended early". The one-page print: the clinic's name, the patient,
// the date range, pain, adherence with the week's repetitions, alerts, the scales and the
// latest table (the dose's tables by week and day, dose.js, stay on the screen).
import { api, esc } from '/console/api.js';
import { has, languageTag, t, locale } from '/console/i18n.js';
import { alertWords, SEVERITY } from '/console/caseload.js';
import { numbersTable, sessionChart, sessionLabels } from '/console/sessionchart.js';
import {
  activeWords, dayWords, endWords, exercisesWords, headerWords, kindWords, measureWords, noiseBand, numberIn, sessionWords,
  trendWords, valueWords, whenWords, measureName, measureDefinition,
} from '/console/words.js';
import { bindNoteCells, noteCell } from '/console/notes.js';
import { scalesSection } from '/console/scales.js';
import { doseSection } from '/console/dose.js';

/** The measures the latest table follows across sessions, in this order (their names, units,
 * decimals and which way is better come from the words table). */
const FOLLOWED = ['active_s', 'pct_in_lane', 'rms_lateral_m', 'dial_rms_error_deg', 'wheel_rom_deg',
  'shoulder_elevation_rom_deg', 'elbow_flexion_rom_deg', 'strength_sustained_left_nm', 'strength_sustained_right_nm',
  'sparc_median', 'speed_metric_median', 'speed_peaks_median', 'movement_time_s_median', 'reaction_time_s_median', 'anticipation_pct',
  'initial_direction_error_deg_mean', 'path_length_ratio_median', 'movements_per_min', 'assist_level_mean'];

/** The standard assessment's table: each part's measures, in the protocol's order
 * (`vehicle::assessment`); the part's words are `progress-assessment-part-<part>`, the
 * measure's name, unit and decimals the words table's. */
const ASSESSMENT_ROWS = [
  ['range', 'wheel_rom_deg'],
  ['tracking-slow', 'dial_rms_error_deg'],
  ['tracking-medium', 'dial_rms_error_deg'],
  ['tracking-fast', 'dial_rms_error_deg'],
  ['steps', 'reaction_time_s_median'],
  ['steps', 'movement_time_s_median'],
  ['steps', 'sparc_median'],
  ['steps', 'ldlj_median'],
  ['steps', 'path_length_ratio_median'],
  ['steps', 'initial_direction_error_deg_mean'],
  ['strength', 'strength_peak_left_nm'],
  ['strength', 'strength_peak_right_nm'],
];

/** How many assessments the table shows, newest first (the hub's page: its verdicts come from
 * the whole history whatever the page). */
const ASSESSMENTS_SHOWN = 4;

/** How many of them the one-page print shows, newest first. */
const ASSESSMENTS_PRINTED = 2;

/** The verdicts' marks beside their words (never colour alone) and their colour class. */
const VERDICT_MARK = { better: ['↑', 'up'], worse: ['↓', 'down'], changed: ['↕', ''], 'within-noise': ['≈', ''], 'no-noise-figure': ['', ''] };

/** `v` of measure `m` signed, rounded, with its unit ("+20 °", "−0.05 s", "0 °"). */
function signedIn(m, v) {
  const n = numberIn(m, Math.abs(v), true);
  const zero = Math.round(Math.abs(v) * 10 ** (m.decimals ?? 2)) === 0;
  return zero ? n : `${v > 0 ? '+' : '−'}${n}`;
}

/** The "change since the first" cell of a measure (HTML, every part escaped): the signed
 * change, the noise band and its source, the verdict in words with a mark; one sentence for
 * screen readers. `c` is the hub's change (`metrics::change`): absent before a second
 * assessment (`only`: there is one) or for a measure missing from the newest or the first. */
function changeCell(c, m, only) {
  const none = only ? 'progress-assessment-change-none' : 'progress-assessment-change-missing';
  if (!c || !m) return `<td class="change"><span aria-hidden="true">—</span><span class="visually-hidden">${esc(t(none))}</span></td>`;
  const change = signedIn(m, c.change);
  const verdict = t(`progress-assessment-verdict-${c.verdict}`);
  const [mark, cls] = VERDICT_MARK[c.verdict] || ['', ''];
  if (c.band == null) {
    return `<td class="change" data-verdict="${esc(c.verdict)}"><span aria-hidden="true">${esc(change)}<br><span class="note">${esc(verdict)}</span></span>
      <span class="visually-hidden">${esc(t('progress-assessment-change-sr-none', { change }))}</span></td>`;
  }
  const band = numberIn(m, c.band, true);
  const source = t(`progress-assessment-source-${c.band_source}`, { repeats: c.repeats });
  const short = t(`progress-assessment-source-short-${c.band_source}`);
  return `<td class="change" data-verdict="${esc(c.verdict)}" data-band-source="${esc(c.band_source)}" title="${esc(source)}">
    <span aria-hidden="true">${esc(change)} <span class="band">${esc(t('progress-assessment-band', { band, source: short }))}</span><br>
    <strong class="verdict ${cls}">${mark ? `${esc(mark)} ` : ''}${esc(verdict)}</strong></span>
    <span class="visually-hidden">${esc(t('progress-assessment-change-sr', { change, band, source, verdict }))}</span></td>`;
}

/** The standard assessment's section (HTML, every part escaped): a table of the latest
 * assessments' numbers, newest first, each measure's change since the patient's first
 * assessment told from measurement noise, or a line saying there is none yet. */
function assessmentHtml(assessments, words) {
  const head = `<h2 id="assessment-h">${esc(t('progress-assessment-title'))}</h2>`;
  if (!assessments.length) return `${head}<p class="note">${esc(t('progress-assessment-none'))}</p>`;
  const shown = assessments.slice(0, ASSESSMENTS_SHOWN);
  const newest = shown[0];
  const part = (a, name) => a.parts.find(p => p.kind === `assessment-${name}`);
  // The print shows the newest ASSESSMENTS_PRINTED beside the change (style.css).
  const older = i => (i >= ASSESSMENTS_PRINTED ? ' class="older"' : '');
  const changeOf = (name, key) => (newest.changes || []).find(c => c.part === name && c.measure === key);
  const rows = ASSESSMENT_ROWS.map(([name, key]) => {
    const m = words.measures.get(key);
    const cells = shown.map((a, i) => {
      const v = part(a, name)?.scores?.[key];
      return `<td data-key="${esc(key)}"${older(i)}>${esc(v == null ? '—' : numberIn(m, v))}</td>`;
    }).join('');
    const label = t('progress-assessment-row', { part: t(`progress-assessment-part-${name}`), measure: m ? headerWords(m) : measureName(key) });
    return `<tr data-part="${esc(name)}" data-key="${esc(key)}"><th scope="row">${esc(label)}</th>${cells}${changeCell(changeOf(name, key), m, assessments.length === 1)}</tr>`;
  }).join('');
  const dates = shown.map((a, i) => `<th scope="col"${older(i)}>${esc(dayWords(a.started_unix_ms))}</th>`).join('');
  const first = (newest.changes || [])[0];
  const changeHead = first ? t('progress-assessment-col-change', { day: dayWords(first.baseline_started_unix_ms) }) : t('progress-assessment-col-change-none');
  return `${head}<p class="note">${esc(t('progress-assessment-intro', { protocol: newest.protocol }))}</p>
    <table id="assessment-table"><thead><tr><th scope="col">${esc(t('progress-assessment-col-measure'))}</th>${dates}<th scope="col" class="change">${esc(changeHead)}</th></tr></thead><tbody>${rows}</tbody></table>
    <p class="note" id="assessment-noise-note">${esc(t('progress-assessment-noise-note'))}</p>`;
}

/** What describes a session rather than the patient's progress: in the tables, not charted. */
const NOT_CHARTED = new Set(['session_s', 'paused_s', 'movements', 'discrete_movements']);

/** A kind's one-line summary names these (the ones its sessions have, at most three). */
const HEADLINE = ['pct_in_lane', 'dial_rms_error_deg', 'wheel_rom_deg', 'strength_sustained_left_nm', 'sparc_median', 'active_s'];

/** How many of a kind's first sessions make the patient's baseline. */
const BASELINE_SESSIONS = 3;

/** How many earlier sessions a trend compares the latest with (the hub's too). */
const TREND_SESSIONS = 4;

/** Pain (0–10) at or above which an answer is marked (the hub's `PAIN_ALERT_AT`). */
const PAIN_MARKED = 7;

const ended = s => !!(s.closed_at_ms || s.end_reason);
/** A session that ended before its prescription ran out. */
const early = s => !s.ran_as_prescribed && ended(s);
/** Whether a session counts in trends and baselines. */
const counts = (s, includeEarly) => s.ran_as_prescribed || (includeEarly && early(s));
const mean = vs => (vs.length ? vs.reduce((a, b) => a + b, 0) / vs.length : undefined);
/** `s` with its first letter a capital ("road sessions" → "Road sessions"). */
const capitalFirst = s => s.charAt(0).toLocaleUpperCase(locale()) + s.slice(1);
/** How hard the session felt, in words (`progress-felt-too-easy`, …). */
const felt = d => (['too_easy', 'about_right', 'too_hard'].includes(d) ? t(`progress-felt-${d.replace(/_/g, '-')}`) : d);

/** A session's check-in in a few words (HTML, every part escaped); high pain marked. */
function checkinWords(c) {
  if (!c) return '—';
  const parts = [];
  if (c.pain_0_10 != null) parts.push(`<span class="${c.pain_0_10 >= PAIN_MARKED ? 'badge alert' : ''}">${esc(t('progress-checkin-pain', { pain: c.pain_0_10 }))}</span>`);
  // The check-in's second answer is effort (Borg CR10); the wire calls it tiredness_0_10.
  if (c.tiredness_0_10 != null) parts.push(esc(t('progress-checkin-effort', { effort: c.tiredness_0_10 })));
  if (c.difficulty != null) parts.push(esc(felt(c.difficulty)));
  return parts.length ? parts.join(t('progress-list-separator')) : esc(t('progress-checkin-skipped'));
}

/** The first section: pain, adherence and alerts (HTML), from the check-ins (newest first),
 * the sessions (oldest first), the caseload's overview of the patient (may be absent) and the
 * measure words (a decline's numbers in their measure's decimals and unit). */
function summaryHtml(checkins, sessions, overview, words) {
  const answered = checkins.filter(c => c.pain_0_10 != null);
  const last = answered[0];
  const pain = last
    ? `<p id="pain-latest" data-pain="${esc(last.pain_0_10)}"><strong class="${last.pain_0_10 >= PAIN_MARKED ? 'badge alert' : ''}">${esc(t('progress-pain-latest', { pain: last.pain_0_10 }))}</strong>
        ${esc(t('progress-pain-after', { at: whenWords(last.started_unix_ms) }))}
        ${answered.length > 1 ? esc(t('progress-pain-before', { list: answered.slice(1, 6).map(c => `${c.pain_0_10}/10`).join(t('progress-list-separator')) })) : ''}</p>`
    : `<p id="pain-latest">${esc(t('progress-pain-none'))}</p>`;
  const lastCheckin = checkins[0];
  const feltWords = lastCheckin && (lastCheckin.tiredness_0_10 != null || lastCheckin.difficulty)
    ? `<p id="last-effort">${esc(t('progress-after-last', {
      answers: [lastCheckin.tiredness_0_10 != null ? t('progress-checkin-effort', { effort: lastCheckin.tiredness_0_10 }) : '',
        lastCheckin.difficulty ? t('progress-felt', { felt: felt(lastCheckin.difficulty) }) : ''].filter(Boolean).join(t('progress-list-separator')),
    }))}</p>` : '';
  let week = '';
  if (overview) {
    week = `<p id="adherence">${esc(t('progress-week', {
      sessions: overview.sessions_last_7_days,
      sessionsPrescribed: overview.sessions_per_week_prescribed ?? 'none',
      minutes: Math.round(overview.active_minutes_last_7_days),
      minutesPrescribed: overview.minutes_per_week_prescribed == null ? 'none' : Math.round(overview.minutes_per_week_prescribed),
    }))}</p>`;
    // The week's repetitions beside its time (the dose's tables are on the page, this line
    // on the print too).
    if (typeof overview.repetitions_last_7_days === 'number') {
      week += `<p id="adherence-repetitions">${esc(t('progress-week-repetitions', { repetitions: overview.repetitions_last_7_days }))}</p>`;
    }
  }
  const recent = sessions.slice(-10);
  const stopped = recent.filter(early).length;
  const stoppedWords = `<p>${esc(t('progress-stopped-early', { stopped, count: recent.length }))}</p>`;
  // The caseload's alerts, each with its severity (mark and colour, caseload.js's).
  const alerts = overview ? (overview.attention || []).filter(a => alertWords(a, words)) : [];
  const alertList = alerts.length ? `<ul id="alerts" class="reasons">${alerts.map(a => {
    const s = SEVERITY[a.severity] || SEVERITY.notice;
    return `<li class="alert-line ${s.cls}" data-kind="${esc(a.kind)}"><span aria-hidden="true">${s.mark}</span> ${esc(alertWords(a, words))}</li>`;
  }).join('')}</ul>`
    : `<p id="alerts">${esc(t('progress-alerts-none'))}</p>`;
  return `<h2 id="summary-h">${esc(t('progress-summary-title'))}</h2>
    <div class="summary-grid"><div><h3>${esc(t('progress-pain-title'))}</h3>${pain}${feltWords}
      <div class="chart" id="p-pain" role="img" aria-label="${esc(t('progress-pain-chart-label'))}"></div></div>
    <div><h3>${esc(t('progress-adherence-title'))}</h3>${week}${stoppedWords}<h3>${esc(t('progress-alerts-title'))}</h3>${alertList}</div></div>`;
}

/** Why the station chose difficulty `d`, in the console's words from its `why`; the station's
 * own English words from a station older than the why. */
function difficultyReason(d) {
  const w = d.why;
  const id = w && `progress-difficulty-why-${w.code}`;
  if (!id || !has(id)) return d.reason;
  const main = t(id, { success: w.success_pct ?? 0, target: w.target_pct ?? 0 });
  const held = w.held_at && `progress-difficulty-held-${w.held_at}`;
  return held && has(held) ? `${main} ${t(held)}` : main;
}

/** The difficulty history (oldest first): a chart and a table of each change and its reason,
 * the station's words escaped, behind a summary; nothing when no session adapted. */
function difficultyPanel(history) {
  if (!history.length) return '';
  const nf = new Intl.NumberFormat(locale(), { minimumFractionDigits: 2, maximumFractionDigits: 2 });
  const signed = x => (x < -0.0005 ? `−${nf.format(-x)}` : `+${nf.format(Math.abs(x))}`);
  const rows = history.slice().reverse().map(d => `<tr><td>${esc(whenWords(d.started_unix_ms))}</td>
    <td class="num">${esc(nf.format(d.difficulty))}</td><td class="num">${esc(signed(d.change))}</td>
    <td>${d.success_rate == null ? '—' : esc(t('progress-percent', { n: Math.round(d.success_rate * 100) }))}</td><td class="reason">${esc(difficultyReason(d))}</td></tr>`).join('');
  const latest = history[history.length - 1];
  return `<details class="panel print-hide" id="difficulty"><summary><h3 id="difficulty-h" class="inline">${esc(t('progress-difficulty-title'))}</h3>${esc(t('progress-difficulty-now', { now: nf.format(latest.difficulty) }))}</summary>
      <p class="note">${esc(t('progress-difficulty-explain'))}</p>
      <div class="chart" id="p-difficulty"></div>
      <table id="difficulty-table"><caption class="note">${esc(t('progress-numbers-caption'))}</caption><thead><tr><th scope="col">${esc(t('progress-col-started'))}</th><th scope="col">${esc(t('progress-col-difficulty'))}</th><th scope="col">${esc(t('progress-col-change'))}</th><th scope="col">${esc(t('progress-col-success'))}</th><th scope="col">${esc(t('progress-col-why'))}</th></tr></thead><tbody>${rows}</tbody></table></details>`;
}

/** What the latest table compares (indices into `sessions`, oldest first): the latest session
 * that counts, up to four earlier ones of its kind (newest first) and the first up to three of
 * its kind (the baseline). */
export function compared(sessions, includeEarly) {
  const done = [];
  for (let i = sessions.length - 1; i >= 0; i--) if (counts(sessions[i], includeEarly)) done.push(i);
  if (!done.length) return { latest: null, trend: [], baseline: [] };
  const kind = sessions[done[0]].exercise_kind;
  const same = done.filter(i => sessions[i].exercise_kind === kind);
  return { latest: sessions[done[0]], trend: same.slice(0, 1 + TREND_SESSIONS), baseline: same.slice(-BASELINE_SESSIONS).reverse() };
}

/** The latest table's rows: latest value, baseline and trend of every followed measure the
 * compared sessions have; active time against the prescribed time. */
function latestRows(words, sessions, metrics, c) {
  const numbers = (idx, key) => idx.map(i => (key === 'prescribed_s' ? sessions[i].prescribed_s : metrics[i][key])).filter(v => typeof v === 'number');
  return FOLLOWED.map(key => words.measures.get(key)).filter(m => m && (m.key === 'active_s' || numbers(c.trend, m.key).length)).map(m => {
    const values = c.trend.map(i => metrics[i][m.key]);
    const last = values[0];
    const base = mean(numbers(c.baseline, m.key));
    const head = `<tr data-key="${esc(m.key)}"><th scope="row" title="${esc(measureDefinition(m.key))}">${esc(measureName(m.key))}</th>`;
    if (m.key === 'active_s') {
      const prescribed = c.baseline.every(i => typeof sessions[i].prescribed_s === 'number') ? mean(numbers(c.baseline, 'prescribed_s')) : undefined;
      return `${head}<td>${esc(activeWords(last, c.latest.prescribed_s))}</td><td data-baseline="${esc(base ?? '')}">${esc(activeWords(base, prescribed))}</td><td class="note">${esc(t('progress-against-prescription'))}</td></tr>`;
    }
    return `${head}<td>${esc(valueWords(m, last))}</td><td data-baseline="${esc(base ?? '')}">${esc(valueWords(m, base))}</td><td>${trendWords(values, m)}</td></tr>`;
  }).join('');
}

/** The latest-table panel's inner HTML. */
function latestPanel(words, sessions, metrics, includeEarly) {
  const c = compared(sessions, includeEarly);
  const kind = c.latest && kindWords(c.latest.exercise_kind);
  const note = c.latest
    ? t('progress-compared', { early: includeEarly ? 'included' : 'left-out', session: sessionWords(c.latest), kind, baseline: c.baseline.length, earlier: TREND_SESSIONS })
    : t('progress-compared-none');
  return `<h2 id="latest-h">${esc(c.latest ? t('progress-latest-title-kind', { kind }) : t('progress-latest-title'))}</h2>
      <p class="note print-hide" id="compared">${esc(note)}</p>
      ${c.latest ? `<table id="latest-table"><thead><tr><th scope="col">${esc(t('progress-col-measure'))}</th><th scope="col">${esc(t('progress-col-latest'))}</th><th scope="col">${esc(t('progress-col-baseline'))}</th><th scope="col">${esc(t('progress-col-trend'))}</th></tr></thead>
      <tbody>${latestRows(words, sessions, metrics, c)}</tbody></table>` : ''}`;
}

/** The kinds of exercise the patient has done, newest first. */
function kindsNewestFirst(sessions) {
  const kinds = [];
  for (let i = sessions.length - 1; i >= 0; i--) if (!kinds.includes(sessions[i].exercise_kind)) kinds.push(sessions[i].exercise_kind);
  return kinds;
}

/** One kind's charts behind a one-line summary (HTML and what to draw into it when opened):
 * one chart a measure its sessions have, in the words table's order. */
function kindGroup(words, sessions, metrics, kind, includeEarly) {
  const idx = sessions.map((s, i) => i).filter(i => sessions[i].exercise_kind === kind);
  const slug = String(kind).replace(/[^a-z0-9]+/gi, '-');
  const labels = sessionLabels(idx.map(i => sessions[i].started_unix_ms));
  const status = idx.map(i => ({ counts: counts(sessions[i], includeEarly), early: early(sessions[i]) }));
  const value = (i, key) => { const v = metrics[i][key]; return typeof v === 'number' ? v : null; };
  const draws = [];
  const shown = words.list.filter(m => !NOT_CHARTED.has(m.key) && idx.some(i => value(i, m.key) != null));
  const panels = shown.map(m => {
    const values = idx.map(i => value(i, m.key));
    const columns = [{ key: m.key, label: headerWords(m), values }];
    const prescribed = m.key === 'active_s' ? idx.map(i => (typeof sessions[i].prescribed_s === 'number' ? sessions[i].prescribed_s : null)) : null;
    if (prescribed && prescribed.some(v => v != null)) columns.push({ key: 'prescribed_s', label: t('progress-prescribed-time', { unit: m.unit }), values: prescribed });
    const chartId = `p-${slug}-${m.key}`;
    const counted = values.filter((v, j) => v != null && status[j].counts);
    const base = mean(counted.slice(0, BASELINE_SESSIONS));
    draws.push([chartId, {
      y: headerWords(m), labels, integer: m.decimals === 0 && !m.unit, range: m.range, decimals: m.decimals,
      band: noiseBand(m, base),
      series: columns.map(c => ({
        label: c.label,
        values: c.values.map((v, j) => (status[j].counts ? v : null)),
        early: c.values.map((v, j) => (status[j].early ? v : null)),
      })),
    }, status]);
    const noise = m.noise ? t('progress-noise-band') : '';
    return `<div class="panel"><h4 id="${chartId}-h">${esc(headerWords(m))}</h4>
      <div class="chart" id="${chartId}" data-kind="${esc(kind)}" data-key="${esc(m.key)}" role="img" aria-label="${esc(t('progress-chart-label', { measure: measureName(m.key) }))}"></div>
      ${noise ? `<p class="note">${esc(noise)}</p>` : ''}
      ${numbersTable(measureName(m.key), labels, columns, status, false, m.decimals)}</div>`;
  }).join('');
  const names = [...new Set(idx.map(i => exercisesWords(sessions[i])))];
  const earlyCount = status.filter(s => s.early).length;
  const lastCounted = idx.filter((i, j) => status[j].counts).pop();
  const headline = lastCounted == null ? [] : HEADLINE.map(k => words.measures.get(k))
    .filter(m => m && typeof metrics[lastCounted][m.key] === 'number').slice(0, 3)
    .map(m => t('progress-headline-item', { measure: measureName(m.key).replace(/ [(（].*[)）]$/, ''), value: valueWords(m, metrics[lastCounted][m.key]) }));
  const html = `<details class="panel kind-group" data-kind="${esc(kind)}">
    <summary><h3 id="kind-${slug}-h" class="inline">${esc(capitalFirst(t('progress-kind-title', { kind: kindWords(kind), count: idx.length })))}</h3>${headline.length ? esc(t('progress-kind-latest', { list: headline.join(t('progress-list-separator')) })) : ''}</summary>
    <p class="note">${esc(t('progress-kind-note', { names: names.join('; ') }))}${earlyCount ? ` ${esc(t('progress-kind-hollow', { count: earlyCount, early: includeEarly ? 'included' : 'left-out' }))}` : ''}</p>
    <div class="grid">${panels || `<p>${esc(t('progress-kind-no-measures'))}</p>`}</div></details>`;
  return { html, draws };
}

/** Draws the latest table and the kinds' groups (each group's charts when it is opened);
 * returns what undoes the charts. */
function render(el, words, sessions, metrics, includeEarly) {
  el.querySelector('#latest').innerHTML = latestPanel(words, sessions, metrics, includeEarly);
  const groups = kindsNewestFirst(sessions).map(k => kindGroup(words, sessions, metrics, k, includeEarly));
  const charts = el.querySelector('#charts');
  const open = new Set([...charts.querySelectorAll('details.kind-group[open]')].map(g => g.dataset.kind));
  charts.innerHTML = groups.map(g => g.html).join('');
  let drawn = [];
  charts.querySelectorAll('details.kind-group').forEach((g, gi) => {
    const draw = () => {
      if (g.dataset.drawn) return;
      g.dataset.drawn = '1';
      drawn = drawn.concat(groups[gi].draws.map(([id, opts, status]) => {
        const node = el.querySelector(`#${CSS.escape(id)}`);
        node.dataset.counted = status.map((s, i) => (s.counts ? i + 1 : '')).filter(Boolean).join(' ');
        node.dataset.early = status.map((s, i) => (s.early ? i + 1 : '')).filter(Boolean).join(' ');
        return sessionChart(node, opts);
      }));
    };
    g.addEventListener('toggle', () => { if (g.open) draw(); });
    if (open.has(g.dataset.kind)) g.open = true;
  });
  return () => drawn.forEach(c => c.destroy());
}

/** What each measure the page shows measures and where it comes from (issue 42): the
 * definitions are the console's catalogues' (`words-definition-<key>`), the sources the words
 * table's citations (left in English, as published). */
function definitionsDetails(words, metrics) {
  const keys = new Set(metrics.flatMap(m => Object.keys(m || {})));
  const rows = words.list.filter(m => keys.has(m.key)).map(m => `<tr data-key="${esc(m.key)}"><th scope="row">${esc(measureName(m.key))}</th><td class="definition">${esc(measureDefinition(m.key))}</td><td lang="en" translate="no" class="note">${esc(m.source)}</td></tr>`).join('');
  return `<details class="print-hide" id="definitions"><summary>${esc(t('progress-definitions-summary'))}</summary>
    <table><thead><tr><th scope="col">${esc(t('progress-col-measure'))}</th><th scope="col">${esc(t('progress-col-definition'))}</th><th scope="col">${esc(t('progress-col-source'))}</th></tr></thead><tbody>${rows}</tbody></table></details>`;
}

/** The technical names of the measures the page shows, behind "details". */
function technicalDetails(words, metrics) {
  const keys = new Set(metrics.flatMap(m => Object.keys(m || {})));
  const rows = words.list.filter(m => keys.has(m.key)).map(m => `<tr><th scope="row">${esc(measureName(m.key))}</th><td><code>${esc(m.key)}</code></td><td lang="en" translate="no">${esc(m.technical)}</td></tr>`).join('');
  return `<details class="print-hide" id="technical"><summary>${esc(t('progress-technical-summary'))}</summary>
    <table><caption class="note">${esc(t('progress-technical-caption'))}</caption>
    <thead><tr><th scope="col">${esc(t('progress-col-measure'))}</th><th scope="col">${esc(t('progress-col-data-name'))}</th><th scope="col">${esc(t('progress-col-technical'))}</th></tr></thead><tbody>${rows}</tbody></table></details>`;
}

/** The Progress tab of patient `id` in `el`; returns what to undo on leaving it. */
export async function progressView(el, id) {
  const pid = encodeURIComponent(id);
  const [words, sessionsNewest, checkinList, difficultyNewest, overviews, clinic, patient, assessments] = await Promise.all([
    measureWords(),
    api('GET', `/api/patients/${pid}/sessions`),
    // The patient's own answers on each session's end screen (plain text, escaped).
    api('GET', `/api/patients/${pid}/checkins`).catch(() => []),
    // The difficulty each adapted session ran at and why (newest first from the hub).
    api('GET', `/api/patients/${pid}/difficulty`).catch(() => []),
    // The caseload's overview of the patient: adherence and alerts.
    api('GET', '/api/patients').catch(() => []),
    api('GET', '/api/clinic/name').catch(() => ({ name: null })),
    api('GET', `/api/patients/${pid}`).catch(() => ({ pseudonym: '' })),
    // The standard assessments (newest first), apart from the exercise sessions, each
    // measure's change since the first told from noise by the hub (metrics::change).
    api('GET', `/api/patients/${pid}/assessments?limit=${ASSESSMENTS_SHOWN}`).catch(() => []),
  ]);
  const sessions = sessionsNewest.slice().reverse();
  const metrics = await Promise.all(sessions.map(s => api('GET', `/api/sessions/${encodeURIComponent(s.session_id)}/metrics`).catch(() => ({}))));
  const checkins = new Map(checkinList.map(c => [c.session_id, c]));
  const checkinsNewest = checkinList.slice().sort((a, b) => b.started_unix_ms - a.started_unix_ms);
  const difficulty = difficultyNewest.slice().reverse();
  const overview = overviews.find(p => p.id === id);
  const list = sessions.slice().reverse().map(s => `<tr${s.ran_as_prescribed ? '' : ' data-early="1"'}><td>${esc(whenWords(s.started_unix_ms))}</td><td>${esc(exercisesWords(s))}</td>
    <td data-end-kind="${esc(s.end_kind || '')}">${endWords(s)}</td>
    <td class="checkin" data-pain="${esc(checkins.get(s.session_id)?.pain_0_10 ?? '')}">${checkinWords(checkins.get(s.session_id))}</td>
    <td><a href="#/patients/${pid}/exercises/${encodeURIComponent(s.session_id)}" data-link="exercises">${esc(t('progress-each-exercise'))}</a>
      · <a href="#/patients/${pid}/replay/${encodeURIComponent(s.session_id)}" data-link="replay">${esc(t('progress-replay'))}</a></td>
    <td>${noteCell(s.session_id, t('progress-note-session', { at: whenWords(s.started_unix_ms) }), esc)}</td></tr>`).join('');
  const anyEarly = sessions.some(early);
  const range = sessions.length
    ? t('progress-range', { from: dayWords(sessions[0].started_unix_ms), to: dayWords(sessions[sessions.length - 1].started_unix_ms) })
    : t('progress-range-none');
  const tz = Intl.DateTimeFormat().resolvedOptions().timeZone || 'UTC';
  const zoneWords = tz === 'UTC' ? t('progress-zone-utc') : t('progress-zone', { zone: tz });
  el.innerHTML = `
    <p id="print-head" data-clinic="${esc(clinic.name || '')}"><strong>${esc(clinic.name || t('progress-clinic-unnamed'))}</strong>
      · ${esc(t('progress-print-of', { name: patient.pseudonym || '' }))} · <span id="date-range">${esc(range)}</span> · ${esc(t('progress-printed', { day: dayWords(Date.now()) }))}</p>
    <p class="print-hide"><button type="button" id="print" class="secondary">${esc(t('progress-print'))}</button>
      <a id="measures-csv" href="/api/patients/${pid}/measures.csv?tz=${encodeURIComponent(tz)}&amp;lang=${encodeURIComponent(languageTag())}" download>${esc(t('progress-download', { zone: zoneWords }))}</a>${assessments.length ? `
      · <a id="assessments-csv" href="/api/patients/${pid}/assessments.csv?tz=${encodeURIComponent(tz)}&amp;lang=${encodeURIComponent(languageTag())}" download>${esc(t('progress-download-assessments', { zone: zoneWords }))}</a>` : ''}</p>
    <section class="panel${assessments.length ? '' : ' print-hide'}" id="assessment" aria-labelledby="assessment-h">${assessmentHtml(assessments, words)}</section>
    <section class="panel" id="summary" aria-labelledby="summary-h">${summaryHtml(checkinsNewest, sessions, overview, words)}</section>
    <section class="panel print-hide" id="dose" aria-labelledby="dose-h">${doseSection(sessions, metrics, overview)}</section>
    <section class="panel" id="scales" aria-labelledby="scales-h"></section>
    <p class="print-hide"><input type="checkbox" id="include-early"${anyEarly ? '' : ' disabled'}>
      <label for="include-early" class="inline">${esc(t(anyEarly ? 'progress-include-early' : 'progress-include-early-none'))}</label></p>
    <section class="panel" id="latest" aria-labelledby="latest-h"></section>
    <div id="charts" class="print-hide"></div>
    ${difficultyPanel(difficulty)}
    ${definitionsDetails(words, metrics)}
    ${technicalDetails(words, metrics)}
    <section class="panel print-hide" aria-labelledby="sessions-h"><h2 id="sessions-h">${esc(t('progress-sessions-title', { count: sessions.length }))}</h2>
      <table><thead><tr><th scope="col">${esc(t('progress-col-started'))}</th><th scope="col">${esc(t('progress-col-exercise'))}</th><th scope="col">${esc(t('progress-col-ended'))}</th><th scope="col">${esc(t('progress-col-checkin'))}</th><th scope="col">${esc(t('progress-col-results'))}</th><th scope="col">${esc(t('progress-col-notes'))}</th></tr></thead><tbody>${list}</tbody></table></section>`;
  el.querySelector('#print').addEventListener('click', () => window.print());
  bindNoteCells(el);
  const box = el.querySelector('#include-early');
  let undo = render(el, words, sessions, metrics, false);
  box.addEventListener('change', () => {
    undo();
    undo = render(el, words, sessions, metrics, box.checked);
    el.dataset.includeEarly = box.checked ? '1' : '0';
  });
  el.dataset.includeEarly = '0';
  const undoCharts = [];
  // Pain after each session (0–10), by session: the sessions with an answer.
  const painIdx = sessions.map((s, i) => i).filter(i => checkins.get(sessions[i].session_id)?.pain_0_10 != null);
  if (painIdx.length) {
    const labels = sessionLabels(painIdx.map(i => sessions[i].started_unix_ms));
    undoCharts.push(sessionChart(el.querySelector('#p-pain'), { y: t('progress-pain-axis'), labels, integer: true, range: [0, 10], decimals: 0,
      series: [{ label: t('progress-pain-axis'), values: painIdx.map(i => checkins.get(sessions[i].session_id).pain_0_10) }] }));
  } else el.querySelector('#p-pain').hidden = true;
  if (difficulty.length) {
    // By adapted session, each labelled with its date and time, drawn when opened.
    const details = el.querySelector('#difficulty');
    details.addEventListener('toggle', () => {
      if (!details.open || details.dataset.drawn) return;
      details.dataset.drawn = '1';
      const labels = sessionLabels(difficulty.map(d => d.started_unix_ms));
      undoCharts.push(sessionChart(el.querySelector('#p-difficulty'), { y: t('progress-difficulty-axis'), labels, range: [0, 1], decimals: 2,
        series: [{ label: t('progress-difficulty-axis'), values: difficulty.map(d => d.difficulty) }] }));
    });
  }
  // The clinical scales taken at the clinic (scales.js): one chart a scale. A failure there
  // says so in its own place and leaves the rest of the view working.
  let undoScales = () => {};
  try {
    undoScales = await scalesSection(el.querySelector('#scales'), id);
  } catch (e) {
    el.querySelector('#scales').innerHTML =
      `<p class="error" role="alert">${esc(t('progress-scales-failed', { error: e.message || e }))}</p>`;
  }
  el.dataset.sessions = String(sessions.length);
  return () => { undo(); undoCharts.forEach(c => c.destroy()); undoScales(); };
}
