// Progress charts BY SESSION (issue 29): one step on the x axis per session, labelled with its
// date and time, so that sessions of one day never stack into a vertical line; one unit on the
// y axis; integer ticks for counts; sessions ended early drawn hollow (and joined to the line
// only when they count). Every chart's numbers are also given as a table (a canvas is not
// accessible).
import uPlot from '/console/vendor/uplot-1.6.32/uPlot.esm.js';
import { COLOURS } from '/console/charts.js';
import { esc } from '/console/api.js';

const MONTHS = ['Jan', 'Feb', 'Mar', 'Apr', 'May', 'Jun', 'Jul', 'Aug', 'Sep', 'Oct', 'Nov', 'Dec'];

/** Chart height, px (two charts side by side fit a printed page with the table). */
const HEIGHT_PX = 190;

/** Width an x axis label needs, px ("27 Nov" over "08:51"). */
const LABEL_PX = 64;

/** A session's date and time as an axis label: "27 Nov 08:51" (local time). */
export function shortWhen(ms) {
  const d = new Date(ms);
  const two = n => String(n).padStart(2, '0');
  return `${d.getDate()} ${MONTHS[d.getMonth()]} ${two(d.getHours())}:${two(d.getMinutes())}`;
}

/** Labels for sessions started at `msList` (shortWhen); two in the same minute get their
 * seconds too, so that no two sessions read alike. */
export function sessionLabels(msList) {
  const short = msList.map(shortWhen);
  return short.map((l, i) => (short.indexOf(l) !== short.lastIndexOf(l)
    ? `${l}:${String(new Date(msList[i]).getSeconds()).padStart(2, '0')}` : l));
}

/** A number for a table cell: two decimals, or an integer for counts; "—" when absent. */
export function cellNumber(v, integer = false) {
  if (typeof v !== 'number') return '—';
  return integer ? String(Math.round(v)) : v.toFixed(2);
}

/**
 * A chart in `el` with one point a session: `labels` names each session (shortWhen), `y` the
 * axis with its one unit, `series` [{label, values, early}] where `values` are the sessions
 * that count (null elsewhere; the line joins them) and `early` the sessions ended early (drawn
 * hollow, no line; null elsewhere). `integer` gives whole-number ticks (a count or a level);
 * `range` [min, max] fixes the y axis (grown to fit a value outside it). The title, if any,
 * is drawn above; a page usually names the chart in its own heading instead.
 * Returns `destroy()`.
 */
export function sessionChart(el, { title, y, labels, series, integer = false, range = null }) {
  const n = labels.length;
  const xs = labels.map((_, i) => i + 1);
  const width = () => Math.max(280, el.clientWidth || 600);
  const ticks = () => {
    const step = Math.max(1, Math.ceil(n / Math.max(1, Math.floor(width() / LABEL_PX))));
    return xs.filter((_, i) => (n - 1 - i) % step === 0); // the newest always labelled
  };
  const uSeries = [{ label: 'session', value: (u, v) => (v == null ? '' : labels[v - 1] || '') }];
  const data = [xs];
  series.forEach((s, i) => {
    const colour = COLOURS[i % COLOURS.length];
    uSeries.push({ label: s.label, stroke: colour, width: 2, dash: i % 2 ? [6, 3] : undefined, spanGaps: true,
                   points: { show: true, space: 0, size: 7, fill: colour, stroke: colour } });
    data.push(s.values);
    if (s.early && s.early.some(v => v != null)) {
      uSeries.push({ label: `${s.label}, ended early`, stroke: colour, width: 0, paths: () => null,
                     points: { show: true, space: 0, size: 11, width: 2, fill: '#ffffff', stroke: colour } });
      data.push(s.early);
    }
  });
  const yAxis = { label: y, size: 60 };
  if (integer) {
    yAxis.incrs = [1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000];
    yAxis.values = (u, splits) => splits.map(v => String(Math.round(v)));
  }
  const opts = {
    title,
    width: width(),
    height: HEIGHT_PX,
    scales: {
      x: { time: false, range: () => [0.5, n + 0.5] },
      y: integer ? { range: (u, min, max) => [0, Math.max(1, Math.ceil(max ?? 1))] }
        : range ? { range: (u, min, max) => [Math.min(range[0], min ?? range[0]), Math.max(range[1], max ?? range[1])] } : {},
    },
    series: uSeries,
    // The series by name (the values are in the table under the chart): no "--" placeholders.
    legend: { live: false },
    axes: [
      { label: 'session (date and time)', size: 58, splits: () => ticks(),
        values: (u, splits) => splits.map(v => (labels[v - 1] || '').replace(/ (\d\d:\d\d(:\d\d)?)$/, '\n$1')) },
      yAxis,
    ],
  };
  const chart = new uPlot(opts, data, el);
  const resize = () => chart.setSize({ width: width(), height: HEIGHT_PX });
  window.addEventListener('resize', resize);
  el.dataset.points = String(n);
  el.dataset.xs = xs.join(' ');
  el.dataset.labels = labels.join('|');
  el.dataset.yAxis = y;
  return {
    destroy() { window.removeEventListener('resize', resize); chart.destroy(); },
  };
}

/**
 * The numbers of a chart as a table under it, in a <details>: a row a session (its label, each
 * series' value, whether it counts); `status` [{counts, early}] a session.
 */
export function numbersTable(title, labels, columns, status, integer = false) {
  const word = st => (st.counts ? (st.early ? 'yes (ended early, included)' : 'yes')
    : st.early ? 'no: ended early' : 'no: still running');
  const head = columns.map(c => `<th scope="col">${esc(c.label)}</th>`).join('');
  const rows = labels.map((label, i) => `<tr${status[i].early ? ' data-early="1"' : ''}><th scope="row">${esc(label)}</th>
    ${columns.map(c => `<td class="num">${esc(cellNumber(c.values[i], integer))}</td>`).join('')}
    <td>${word(status[i])}</td></tr>`).join('');
  return `<details class="numbers print-hide"><summary>Numbers of this chart (${esc(title)})</summary>
    <table><caption>${esc(title)}, a row a session, oldest first</caption>
    <thead><tr><th scope="col">Session</th>${head}<th scope="col">Counted</th></tr></thead><tbody>${rows}</tbody></table></details>`;
}
