// Clinical scales (issue 32; crates/hub/API.md, "clinical scales"): the Fugl-Meyer upper
// extremity motor score, the Action Research Arm Test and the Box and Block Test a therapist
// takes at the clinic, entered with the day they were taken and charted on ONE time axis beside
// the station's SPARC: SPARC on the left axis, the two point scores on the right, and the Box
// and Block Test in a small chart under it sharing the same dates. The numbers are in a table
// under the charts, and the entries in a table the one-page print keeps.
import uPlot from '/console/vendor/uplot-1.6.32/uPlot.esm.js';
import { COLOURS } from '/console/charts.js';
import { api, esc, when } from '/console/api.js';
import { cellNumber } from '/console/sessionchart.js';

/** Heights of the main and the Box and Block charts, px. */
const HEIGHT_PX = 200;
const BBT_HEIGHT_PX = 150;
const DAY_S = 86400;

/** The station measure charted beside the scales: [key, label, axis]. */
const STATION = ['sparc_median', 'SPARC, median of movements (session; closer to 0 is smoother)', 'SPARC (no unit)'];

const two = n => String(n).padStart(2, '0');
/** `YYYY-MM-DD` of a Date, local time. */
const isoDay = d => `${d.getFullYear()}-${two(d.getMonth() + 1)}-${two(d.getDate())}`;
/** Seconds since the epoch of local noon of day `YYYY-MM-DD` (its point on the time axis). */
const noonS = day => { const [y, m, d] = day.split('-').map(Number); return new Date(y, m - 1, d, 12).getTime() / 1000; };

/** An entry's numbers in words: "34 points", "affected 12, unaffected 45 blocks per minute". */
export function scoreWords(e) {
  if (e.score != null) return `${e.score} points`;
  return `affected side ${e.affected_blocks_per_min}, unaffected side ${e.unaffected_blocks_per_min} blocks per minute`;
}

/** The chart series: [label, axis scale, value of an entry or null, scale key]. */
const SCALE_SERIES = [
  ['Fugl-Meyer upper extremity motor (points, 0–66)', 'score', 'fugl_meyer_ue', e => e.score],
  ['Action Research Arm Test (points, 0–57)', 'score', 'arat', e => e.score],
  ['Box and Block, affected side (blocks per minute)', 'bbt', 'box_and_block', e => e.affected_blocks_per_min],
  ['Box and Block, unaffected side (blocks per minute)', 'bbt', 'box_and_block', e => e.unaffected_blocks_per_min],
];

/** The rows of the shared time axis: every session with the station measure and every day a
 * scale was taken, in time order: {x (s), label, station, scales[4]}. */
export function timeRows(sessions, metrics, entries) {
  const rows = [];
  sessions.forEach((s, i) => {
    const v = metrics[i] && metrics[i][STATION[0]];
    if (typeof v === 'number') rows.push({ x: s.started_unix_ms / 1000, label: when(s.started_unix_ms), station: v, scales: [null, null, null, null] });
  });
  entries.forEach(e => {
    const scales = SCALE_SERIES.map(([, , key, value]) => (e.scale === key ? value(e) : null));
    const x = noonS(e.assessed_on);
    const same = rows.find(r => r.x === x && r.station == null);
    if (same) same.scales = same.scales.map((v, j) => v ?? scales[j]);
    else rows.push({ x, label: `${e.assessed_on} (assessed)`, station: null, scales });
  });
  return rows.sort((a, b) => a.x - b.x);
}

/** A time chart in `el` over `range` [min, max] s: `axes` [{scale, label, side, range}] and
 * `series` [{label, scale, values}] on the rows' x. Returns the uPlot. */
function timeChart(el, { xs, range, height, axes, series, colours }) {
  const width = () => Math.max(280, el.clientWidth || 600);
  const scales = { x: { time: true, range: () => range } };
  axes.forEach(a => { if (!scales[a.scale]) scales[a.scale] = a.range ? { range: (u, min, max) => [Math.min(a.range[0], min ?? 0), Math.max(a.range[1], max ?? 0)] } : {}; });
  const chart = new uPlot({
    width: width(), height, scales, legend: { live: false },
    series: [{ label: 'date' }, ...series.map((s, i) => ({
      label: s.label, scale: s.scale, stroke: colours[i], width: 2, dash: i % 2 ? [6, 3] : undefined, spanGaps: true,
      points: { show: true, space: 0, size: 8, fill: colours[i], stroke: colours[i] } }))],
    axes: [{ label: 'date', size: 44 }, ...axes.map(a => ({ scale: a.scale, label: a.label, size: 60, ...(a.side ? { side: a.side, grid: { show: false } } : {}) }))],
  }, [xs, ...series.map(s => s.values)], el);
  const resize = () => chart.setSize({ width: width(), height });
  window.addEventListener('resize', resize);
  el.dataset.series = series.map(s => s.label).join('|');
  el.dataset.points = series.map(s => s.values.filter(v => v != null).length).join(' ');
  return { destroy() { window.removeEventListener('resize', resize); chart.destroy(); } };
}

/** Draws the charts of `rows` into `box`; returns what undoes them. */
function drawCharts(box, rows) {
  const xs = rows.map(r => r.x);
  const pad = xs.length && xs[xs.length - 1] - xs[0] < 7 * DAY_S ? 3 * DAY_S : DAY_S;
  const range = xs.length ? [xs[0] - pad, xs[xs.length - 1] + pad] : [0, 1];
  const column = j => rows.map(r => r.scales[j]);
  const has = j => column(j).some(v => v != null);
  const main = [{ label: STATION[1], scale: 'y', values: rows.map(r => r.station) }];
  const colours = [COLOURS[0]];
  [0, 1].filter(has).forEach(j => { main.push({ label: SCALE_SERIES[j][0], scale: 'score', values: column(j) }); colours.push(COLOURS[j + 1]); });
  const charts = [timeChart(box.querySelector('#p-scales'), { xs, range, height: HEIGHT_PX, series: main, colours,
    axes: [{ scale: 'y', label: STATION[2] }, { scale: 'score', label: 'score (points)', side: 1, range: [0, 66] }] })];
  const bbt = box.querySelector('#p-scales-bbt');
  bbt.hidden = !has(2);
  if (has(2)) {
    charts.push(timeChart(bbt, { xs, range, height: BBT_HEIGHT_PX, colours: [COLOURS[3], COLOURS[4]],
      series: [2, 3].map(j => ({ label: SCALE_SERIES[j][0], scale: 'bbt', values: column(j) })),
      // Both sides, as the chart above: the plots share their width and so their dates.
      axes: [{ scale: 'bbt', label: 'blocks/min', range: [0, 60] }, { scale: 'bbt', label: 'blocks/min', side: 1 }] }));
  }
  return () => charts.forEach(c => c.destroy());
}

/** The numbers of the charts as a table (a row per date). */
function numbersTable(rows) {
  const head = [STATION[1], ...SCALE_SERIES.map(s => s[0])].map(h => `<th scope="col">${esc(h)}</th>`).join('');
  const body = rows.map(r => `<tr><th scope="row">${esc(r.label)}</th><td class="num">${esc(cellNumber(r.station))}</td>
    ${r.scales.map(v => `<td class="num">${esc(cellNumber(v, true))}</td>`).join('')}</tr>`).join('');
  return `<details class="numbers print-hide" id="scales-numbers"><summary>Numbers of these charts (SPARC and the clinical scales by date)</summary>
    <table><caption>SPARC by session and the clinical scales by the day taken, oldest first</caption>
    <thead><tr><th scope="col">Date</th>${head}</tr></thead><tbody>${body}</tbody></table></details>`;
}

/** The entries' table (printed), newest first, each with a button deleting a mistaken one. */
function entriesTable(entries) {
  if (!entries.length) return '<p id="scales-none">No clinical scale recorded yet.</p>';
  const rows = entries.slice().reverse().map(e => `<tr data-scale="${esc(e.scale)}"><td>${esc(e.assessed_on)}</td>
    <td>${esc(e.scale_name)}</td><td class="num">${esc(scoreWords(e))}</td><td>${esc(e.therapist_email || 'a therapist no longer at the clinic')}</td>
    <td class="print-hide"><button type="button" class="secondary delete-scale" data-id="${esc(e.id)}">Delete the ${esc(e.scale_name)} of ${esc(e.assessed_on)}</button></td></tr>`).join('');
  return `<table id="scales-table"><caption>Clinical scales taken at the clinic, newest first</caption>
    <thead><tr><th scope="col">Day taken</th><th scope="col">Scale</th><th scope="col">Score</th><th scope="col">Recorded by</th><th scope="col" class="print-hide">Mistaken entry</th></tr></thead>
    <tbody>${rows}</tbody></table>`;
}

/** The form: the scale, its day, and its numbers with their bounds (min, max, required) from
 * the hub's own definitions, so the browser refuses an out-of-range score before the hub does. */
function formHtml(scales) {
  const options = scales.map(s => `<option value="${esc(s.key)}">${esc(s.name)}</option>`).join('');
  const inputs = scales.map(s => `<fieldset class="scale-fields" data-scale="${esc(s.key)}"><legend>${esc(s.name)}</legend>
    ${s.fields.map(f => `<label for="scale-${esc(s.key)}-${esc(f.field)}">${esc(f.label)} (${esc(f.min)} to ${esc(f.max)} ${esc(f.unit)})</label>
      <input type="number" id="scale-${esc(s.key)}-${esc(f.field)}" name="${esc(f.field)}" min="${esc(f.min)}" max="${esc(f.max)}" step="1" required inputmode="numeric">`).join('')}</fieldset>`).join('');
  return `<form id="scale-form" class="print-hide"><h3>Record a clinical scale</h3>
    <label for="scale-kind">Scale</label><select id="scale-kind" name="scale" required>${options}</select>
    <label for="scale-day">Day taken</label><input type="date" id="scale-day" name="assessed_on" required min="1990-01-01">
    ${inputs}<p><button type="submit">Save the score</button></p><p id="scale-result" role="status"></p></form>`;
}

/** Shows only the chosen scale's numbers (the others disabled: not required, not sent). */
function showFields(form) {
  const key = form.querySelector('#scale-kind').value;
  form.querySelectorAll('fieldset.scale-fields').forEach(f => {
    f.hidden = f.dataset.scale !== key;
    f.disabled = f.hidden;
  });
}

/** The clinical scales section of patient `id` into `box` (the progress view's `sessions`
 * oldest first and their `metrics`); returns what undoes its charts. */
export async function scalesSection(box, id, sessions, metrics) {
  const url = `/api/patients/${encodeURIComponent(id)}/scales`;
  let undo = () => {};
  box.innerHTML = `<h2 id="scales-h">Clinical scales beside the station's measures</h2>
    <p class="note">SPARC of each session (left axis) and the scores taken at the clinic (right axis) on one time axis; the Box and Block Test under it, on the same dates.</p>
    <div class="chart" id="p-scales" role="img" aria-label="SPARC by session and the clinical scales by the day taken: the numbers are in the table below"></div>
    <div class="chart" id="p-scales-bbt" role="img" aria-label="Box and Block Test by the day taken, on the same dates: the numbers are in the table below" hidden></div>
    <div id="scales-numbers-box"></div><div id="scales-list"></div><div id="scales-form-box"></div>`;
  const refresh = async () => {
    const { entries, scales } = await api('GET', url);
    undo();
    const rows = timeRows(sessions, metrics, entries);
    box.querySelector('#scales-numbers-box').innerHTML = numbersTable(rows);
    box.querySelector('#scales-list').innerHTML = entriesTable(entries);
    undo = drawCharts(box, rows);
    box.dataset.entries = String(entries.length);
    box.querySelectorAll('button.delete-scale').forEach(b => b.addEventListener('click', async () => {
      if (!window.confirm(`${b.textContent}?`)) return;
      try {
        await api('DELETE', `${url}/${encodeURIComponent(b.dataset.id)}`);
        await refresh();
      } catch (e) {
        box.querySelector('#scales-list').insertAdjacentHTML('afterbegin',
          `<p class="error" role="alert">Not deleted: ${esc(e.message || e)}</p>`);
      }
    }));
    return scales;
  };
  const scales = await refresh();
  const formBox = box.querySelector('#scales-form-box');
  formBox.innerHTML = formHtml(scales);
  const form = formBox.querySelector('form');
  const day = form.querySelector('#scale-day');
  day.max = isoDay(new Date());
  day.value = day.max;
  showFields(form);
  form.querySelector('#scale-kind').addEventListener('change', () => showFields(form));
  const result = form.querySelector('#scale-result');
  form.addEventListener('submit', async ev => {
    ev.preventDefault();
    const body = { scale: form.scale.value, assessed_on: day.value };
    form.querySelectorAll('fieldset.scale-fields:not([disabled]) input').forEach(i => { body[i.name] = i.value === '' ? null : Number(i.value); });
    try {
      await api('POST', url, body);
      form.querySelectorAll('fieldset.scale-fields input').forEach(i => { i.value = ''; });
      result.className = '';
      result.textContent = 'Score saved.';
      await refresh();
    } catch (e) { result.className = 'error'; result.textContent = e.message; }
  });
  return () => undo();
}
