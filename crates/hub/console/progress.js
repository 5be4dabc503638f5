// A patient's progress (issue 29): the latest session against the patient's own baseline and
// the earlier sessions of its kind, the charts grouped by exercise kind with an axis by
// session, and the sessions in words. Sessions ended early are shown, marked and left out of
// the trends and baselines unless the therapist ticks "Include sessions that ended early".
import { api, esc, when } from '/console/api.js';
import { numbersTable, sessionChart, sessionLabels } from '/console/sessionchart.js';
import { activeWords, endWords, kindWords, sessionWords, trendWords } from '/console/words.js';
import { bindNoteCells, noteCell } from '/console/notes.js';
import { scalesSection } from '/console/scales.js';

/** The measures a therapist follows across sessions, with their plain names and units;
 * `better` says which way is progress. */
const MEASURES = [
  ['pct_in_lane', 'time in lane', '%', 'up'],
  ['rms_lateral_m', 'lane keeping error (RMS lateral deviation)', 'm', 'down'],
  ['dial_rms_error_deg', 'dial tracking error (RMS)', '°', 'down'],
  ['strength_sustained_left_nm', 'strength pushing left (held 1 s)', 'N·m', 'up'],
  ['strength_sustained_right_nm', 'strength pushing right (held 1 s)', 'N·m', 'up'],
  ['wheel_rom_deg', 'wheel range of motion', '°', 'up'],
  ['shoulder_elevation_rom_deg', 'shoulder elevation range', '°', 'up'],
  ['elbow_flexion_rom_deg', 'elbow flexion range', '°', 'up'],
  ['sparc_median', 'movement smoothness (SPARC, closer to 0 is smoother)', '', 'up'],
  ['assist_level_mean', 'assistance level', '0–1', 'down'],
  // Robot-grade movement measures (issue 30; the metrics crate's `robot` module has their
  // definitions and references).
  ['speed_metric_median', 'speed metric (mean over peak speed of a movement)', '', 'up'],
  ['speed_peaks_median', 'speed peaks in a movement', '', 'down'],
  ['movement_time_s_median', 'movement time', 's', 'down'],
  ['reaction_time_s_median', 'reaction time to a step of the target or a lane shift (below 0: steered before it)', 's', 'down'],
  ['initial_direction_error_deg_mean', 'initial direction error (180° = every start the wrong way)', '°', 'down'],
  ['path_length_ratio_median', 'path length ratio (wheel path over the distance needed)', '', 'down'],
  ['movements_per_min', 'dose: movements per active minute', 'per min', 'up'],
  ['active_s', 'active time', 's', 'up'],
];

/** The progress charts, one unit each: [id, title, y axis, series [[key, label]], integer, y range]. A
 * key `prescribed_s` is the session's prescribed time, not a measure. */
const CHARTS = [
  ['lane', 'Time in lane', 'time in lane (%)', [['pct_in_lane', 'time in lane (%)']], false, [0, 100]],
  ['lateral', 'Lane keeping error', 'RMS deviation (m)', [['rms_lateral_m', 'lane keeping error (m)']]],
  ['dial', 'Dial tracking error', 'RMS error (°)', [['dial_rms_error_deg', 'dial tracking error (°)']]],
  ['strength', 'Strength (torque on the wheel)', 'torque (N·m)', [['strength_peak_left_nm', 'peak, left (N·m)'], ['strength_sustained_left_nm', 'held 1 s, left (N·m)'], ['strength_peak_right_nm', 'peak, right (N·m)'], ['strength_sustained_right_nm', 'held 1 s, right (N·m)']]],
  ['rom', 'Ranges of motion', 'range (°)', [['wheel_rom_deg', 'wheel (°)'], ['shoulder_elevation_rom_deg', 'shoulder elevation (°)'], ['elbow_flexion_rom_deg', 'elbow flexion (°)']]],
  ['sparc', 'Movement smoothness (SPARC)', 'SPARC (no unit)', [['sparc_median', 'SPARC, median of movements']]],
  ['active', 'Active time against the prescribed time', 'time (s)', [['active_s', 'active time (s)'], ['prescribed_s', 'prescribed time (s)']]],
  ['assist', 'Assistance level', 'level (0–1)', [['assist_level_mean', 'assistance level (0–1)']], false, [0, 1]],
  ['cones', 'Cones hit', 'cones (count)', [['cone_hits', 'cones hit']], true],
  ['speedmetric', 'Speed metric (mean over peak speed)', 'speed metric (0–1)', [['speed_metric_median', 'speed metric, median of movements']], false, [0, 1]],
  ['peaks', 'Speed peaks in a movement', 'peaks (count)', [['speed_peaks_median', 'speed peaks, median of movements']]],
  ['times', 'Movement and reaction times', 'time (s)', [['movement_time_s_median', 'movement time, median (s)'], ['reaction_time_s_median', 'reaction time to a target step or lane shift, median (s)']]],
  ['direction', 'Initial direction error', 'error (°)', [['initial_direction_error_deg_mean', 'initial direction error, mean (°)']], false, [0, 180]],
  ['pathratio', 'Path length ratio', 'ratio (no unit)', [['path_length_ratio_median', 'path length ratio, median']]],
  ['dose', 'Dose: movements and steering reversals per active minute', 'count per minute', [['movements_per_min', 'movements per minute'], ['reversals_per_min', 'steering reversals per minute']]],
];

/** How many of a kind's first sessions make the patient's baseline. */
const BASELINE_SESSIONS = 3;

/** How many earlier sessions a trend compares the latest with (words.js, the hub's). */
const TREND_SESSIONS = 4;

const ended = s => !!(s.closed_at_ms || s.end_reason);
/** A session that ended before its prescription ran out. */
const early = s => !s.ran_as_prescribed && ended(s);
/** Whether a session counts in trends and baselines. */
const counts = (s, includeEarly) => s.ran_as_prescribed || (includeEarly && early(s));
const mean = vs => (vs.length ? vs.reduce((a, b) => a + b, 0) / vs.length : undefined);
const capital = s => s.charAt(0).toUpperCase() + s.slice(1);

/** A session's check-in in a few words (HTML, every part escaped); pain of 7 or more marked. */
function checkinWords(c) {
  if (!c) return '—';
  const difficulty = { too_easy: 'too easy', about_right: 'about right', too_hard: 'too hard' };
  const parts = [];
  if (c.pain_0_10 != null) parts.push(`<span class="${c.pain_0_10 >= 7 ? 'badge alert' : ''}">pain ${esc(String(c.pain_0_10))}/10</span>`);
  if (c.tiredness_0_10 != null) parts.push(`tiredness ${esc(String(c.tiredness_0_10))}/10`);
  if (c.difficulty != null) parts.push(esc(difficulty[c.difficulty] || c.difficulty));
  return parts.length ? parts.join(', ') : 'skipped';
}

/** The difficulty history (oldest first): a chart and a table of each change and its reason,
 * the station's words escaped; nothing when no session adapted. */
function difficultyPanel(history) {
  if (!history.length) return '';
  const signed = x => (x < -0.0005 ? `−${(-x).toFixed(2)}` : `+${x.toFixed(2)}`);
  const rows = history.slice().reverse().map(d => `<tr><td>${esc(when(d.started_unix_ms))}</td>
    <td class="num">${esc(d.difficulty.toFixed(2))}</td><td class="num">${esc(signed(d.change))}</td>
    <td>${d.success_rate == null ? '—' : `${esc(Math.round(d.success_rate * 100))} %`}</td><td class="reason">${esc(d.reason)}</td></tr>`).join('');
  return `<section class="panel" id="difficulty" aria-labelledby="difficulty-h"><h2 id="difficulty-h">Difficulty that follows the patient</h2>
      <p class="note">0: half the prescribed speed and shape with all its assistance; 1: the regimen as written. Set by the station within the regimen's [difficulty] bounds.</p>
      <div class="chart" id="p-difficulty"></div>
      <table id="difficulty-table"><caption class="note">The numbers of the chart, newest first</caption><thead><tr><th scope="col">Started</th><th scope="col">Difficulty</th><th scope="col">Change</th><th scope="col">Success</th><th scope="col">Why</th></tr></thead><tbody>${rows}</tbody></table></section>`;
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

/** The latest table's rows: latest value, baseline and trend of every measure the compared
 * sessions have; active time against the prescribed time. */
function latestRows(sessions, metrics, c) {
  const num = (i, key) => (key === 'prescribed_s' ? sessions[i].prescribed_s : metrics[i][key]);
  const numbers = (idx, key) => idx.map(i => num(i, key)).filter(v => typeof v === 'number');
  return MEASURES.filter(([key]) => key === 'active_s' || numbers(c.trend, key).length).map(([key, label, unit, better]) => {
    const values = c.trend.map(i => metrics[i][key]);
    const last = values[0];
    const base = mean(numbers(c.baseline, key));
    const head = `<tr data-key="${esc(key)}"><th scope="row">${esc(label)}</th>`;
    const withUnit = v => (typeof v === 'number' ? `${esc(v.toFixed(2))} ${esc(unit)}` : '—');
    if (key === 'active_s') {
      const prescribed = c.baseline.every(i => typeof sessions[i].prescribed_s === 'number') ? mean(numbers(c.baseline, 'prescribed_s')) : undefined;
      return `${head}<td>${esc(activeWords(last, c.latest.prescribed_s))}</td><td data-baseline="${esc(base ?? '')}">${esc(activeWords(base, prescribed))}</td><td class="note">against the prescription, not a trend</td></tr>`;
    }
    return `${head}<td>${typeof last === 'number' ? withUnit(last) : '—'}</td><td data-baseline="${esc(base ?? '')}">${withUnit(base)}</td><td>${trendWords(values, better)}</td></tr>`;
  }).join('');
}

/** The latest-table panel's inner HTML. */
function latestPanel(sessions, metrics, includeEarly) {
  const c = compared(sessions, includeEarly);
  const kind = c.latest && kindWords(c.latest.exercise_kind);
  const which = includeEarly ? 'that ended (as prescribed or early: sessions ended early are included)' : 'that ran as prescribed';
  const note = c.latest
    ? `The latest session ${which} (${esc(sessionWords(c.latest))}) against the patient's baseline, the mean of the first ${esc(c.baseline.length)} ${esc(kind)} session${c.baseline.length === 1 ? '' : 's'} ${which}, and against up to four earlier ${esc(kind)} sessions for the trend${includeEarly ? '' : '; sessions ended early are shown below, not compared'}.`
    : 'No session has run as prescribed yet: nothing to compare.';
  return `<h2 id="latest-h">${c.latest ? `Latest ${esc(kind)} session against the earlier ones` : 'Latest session against the earlier ones'}</h2>
      <p class="note print-hide" id="compared">${note}</p>
      ${c.latest ? `<table id="latest-table"><thead><tr><th scope="col">Measure</th><th scope="col">Latest</th><th scope="col">Baseline <span class="note">(mean of the first ${esc(c.baseline.length)})</span></th><th scope="col">Trend</th></tr></thead>
      <tbody>${latestRows(sessions, metrics, c)}</tbody></table>` : ''}`;
}

/** The kinds of exercise the patient has done, newest first. */
function kindsNewestFirst(sessions) {
  const kinds = [];
  for (let i = sessions.length - 1; i >= 0; i--) if (!kinds.includes(sessions[i].exercise_kind)) kinds.push(sessions[i].exercise_kind);
  return kinds;
}

/** One kind's charts (HTML and what to draw into it): only charts with a number to show. */
function kindGroup(sessions, metrics, kind, includeEarly) {
  const idx = sessions.map((s, i) => i).filter(i => sessions[i].exercise_kind === kind);
  const slug = String(kind).replace(/[^a-z0-9]+/gi, '-');
  const labels = sessionLabels(idx.map(i => sessions[i].started_unix_ms));
  const status = idx.map(i => ({ counts: counts(sessions[i], includeEarly), early: early(sessions[i]) }));
  const value = (i, key) => { const v = key === 'prescribed_s' ? sessions[i].prescribed_s : metrics[i][key]; return typeof v === 'number' ? v : null; };
  const draws = [];
  const panels = CHARTS.map(([id, title, y, series, integer = false, range = null]) => {
    const columns = series.map(([key, label]) => ({ key, label, values: idx.map(i => value(i, key)) }))
      .filter(c => c.values.some(v => v != null));
    if (!columns.some(c => c.key !== 'prescribed_s')) return '';
    const chartId = `p-${slug}-${id}`;
    draws.push([chartId, { y, labels, integer, range, series: columns.map(c => ({
      label: c.label,
      values: c.values.map((v, j) => (status[j].counts ? v : null)),
      early: c.values.map((v, j) => (status[j].early ? v : null)),
    })) }, status]);
    return `<div class="panel"><h3 id="${chartId}-h">${esc(title)}</h3>
      <div class="chart" id="${chartId}" data-kind="${esc(kind)}" role="img" aria-label="${esc(title)} by session: the numbers are in the table below"></div>
      ${numbersTable(title, labels, columns, status, integer)}</div>`;
  }).join('');
  const names = [...new Set(idx.map(i => sessions[i].exercise_name || sessions[i].exercise))];
  const earlyCount = status.filter(s => s.early).length;
  const html = `<section class="panel kind-group" data-kind="${esc(kind)}" aria-labelledby="kind-${slug}-h">
    <h2 id="kind-${slug}-h">${esc(capital(kindWords(kind)))} sessions (${idx.length})</h2>
    <p class="note">${esc(names.join('; '))}. One step a session, oldest on the left.${earlyCount ? ` Hollow points: ${earlyCount} session${earlyCount === 1 ? '' : 's'} ended early (${includeEarly ? 'included' : 'not joined to the line'}).` : ''}</p>
    <div class="grid">${panels || '<p>No measures recorded for these sessions.</p>'}</div></section>`;
  return { html, draws };
}

/** Draws the latest table and the charts; returns what undoes the charts. */
function render(el, sessions, metrics, includeEarly) {
  el.querySelector('#latest').innerHTML = latestPanel(sessions, metrics, includeEarly);
  const groups = kindsNewestFirst(sessions).map(k => kindGroup(sessions, metrics, k, includeEarly));
  const charts = el.querySelector('#charts');
  charts.innerHTML = groups.map(g => g.html).join('');
  // The printed summary: the newest kind's charts only.
  charts.querySelectorAll('.kind-group').forEach((g, i) => g.classList.toggle('print-hide', i > 0));
  const drawn = groups.flatMap(g => g.draws).map(([id, opts, status]) => {
    const node = el.querySelector(`#${id}`);
    node.dataset.counted = status.map((s, i) => (s.counts ? i + 1 : '')).filter(Boolean).join(' ');
    node.dataset.early = status.map((s, i) => (s.early ? i + 1 : '')).filter(Boolean).join(' ');
    return sessionChart(node, opts);
  });
  return () => drawn.forEach(c => c.destroy());
}

/** The Progress tab of patient `id` in `el`; returns what to undo on leaving it. */
export async function progressView(el, id) {
  const sessions = (await api('GET', `/api/patients/${encodeURIComponent(id)}/sessions`)).slice().reverse();
  const metrics = await Promise.all(sessions.map(s => api('GET', `/api/sessions/${encodeURIComponent(s.session_id)}/metrics`).catch(() => ({}))));
  // The patient's own answers on each session's end screen (plain text, escaped).
  const checkins = new Map((await api('GET', `/api/patients/${encodeURIComponent(id)}/checkins`).catch(() => []))
    .map(c => [c.session_id, c]));
  // The difficulty each adapted session ran at and why (newest first from the hub).
  const difficulty = (await api('GET', `/api/patients/${encodeURIComponent(id)}/difficulty`).catch(() => [])).slice().reverse();
  const pid = encodeURIComponent(id);
  const list = sessions.slice().reverse().map(s => `<tr${s.ran_as_prescribed ? '' : ' data-early="1"'}><td>${esc(when(s.started_unix_ms))}</td><td>${esc(s.exercise_name || s.exercise)}</td>
    <td>${endWords(s)}</td>
    <td class="checkin">${checkinWords(checkins.get(s.session_id))}</td>
    <td><a href="#/patients/${pid}/exercises/${encodeURIComponent(s.session_id)}">Each exercise</a>
      · <a href="#/patients/${pid}/replay/${encodeURIComponent(s.session_id)}">Replay</a></td>
    <td>${noteCell(s.session_id, `the session of ${when(s.started_unix_ms)}`, esc)}</td></tr>`).join('');
  const anyEarly = sessions.some(early);
  el.innerHTML = `
    <p class="print-hide"><button type="button" id="print" class="secondary">Print a one-page summary</button>
      <a id="measures-csv" href="/api/patients/${pid}/measures.csv" download>Download spreadsheet (CSV)</a></p>
    <p class="print-hide"><input type="checkbox" id="include-early"${anyEarly ? '' : ' disabled'}>
      <label for="include-early" class="inline">Include sessions that ended early${anyEarly ? '' : ' (none did)'}</label></p>
    <section class="panel" id="latest" aria-labelledby="latest-h"></section>
    <section class="panel" id="scales" aria-labelledby="scales-h"></section>
    <div id="charts"></div>
    ${difficultyPanel(difficulty)}
    <section class="panel print-hide" aria-labelledby="sessions-h"><h2 id="sessions-h">Sessions (${sessions.length})</h2>
      <table><thead><tr><th scope="col">Started</th><th scope="col">Exercise</th><th scope="col">End</th><th scope="col">Patient's check-in</th><th scope="col">Results and recording</th><th scope="col">Therapist's notes</th></tr></thead><tbody>${list}</tbody></table></section>`;
  el.querySelector('#print').addEventListener('click', () => window.print());
  bindNoteCells(el);
  const box = el.querySelector('#include-early');
  let undo = render(el, sessions, metrics, false);
  box.addEventListener('change', () => {
    undo();
    undo = render(el, sessions, metrics, box.checked);
    el.dataset.includeEarly = box.checked ? '1' : '0';
  });
  el.dataset.includeEarly = '0';
  let undoDifficulty = () => {};
  if (difficulty.length) {
    // By adapted session, each labelled with its date and time: a change reads the same a day
    // or a week apart, and sessions of one day stay apart.
    const labels = sessionLabels(difficulty.map(d => d.started_unix_ms));
    const chart = sessionChart(el.querySelector('#p-difficulty'), { title: 'Difficulty and success', y: 'level (0–1)', labels, range: [0, 1],
      series: [{ label: 'difficulty (0–1)', values: difficulty.map(d => d.difficulty) },
               { label: 'success rate (0–1)', values: difficulty.map(d => d.success_rate ?? null) }] });
    undoDifficulty = () => chart.destroy();
  }
  // The clinical scales taken at the clinic, beside the station's SPARC (scales.js).
  // A failure there says so in its own place and leaves the rest of the view working.
  let undoScales = () => {};
  try {
    undoScales = await scalesSection(el.querySelector('#scales'), id, sessions, metrics);
  } catch (e) {
    el.querySelector('#scales').innerHTML =
      `<p class="error" role="alert">The clinical scales could not be shown: ${esc(e.message || e)}</p>`;
  }
  el.dataset.sessions = String(sessions.length);
  return () => { undo(); undoDifficulty(); undoScales(); };
}
