// Progress charts BY SESSION (issue 29): one step on the x axis per session, labelled with its
// date and time, so that sessions of one day never stack into a vertical line; one unit on the
// y axis; integer ticks for counts; sessions ended early drawn hollow (and joined to the line
// only when they count). Every chart's numbers are also given as a table (a canvas is not
// accessible).
import uPlot from '/console/vendor/uplot-1.6.32/uPlot.esm.js';
import { COLOURS } from '/console/charts.js';
import { esc } from '/console/api.js';
import { shortWords } from '/console/words.js';
import { t, locale } from '/console/i18n.js';

/** Chart height, px (two charts side by side fit a printed page with the table). */
const HEIGHT_PX = 190;

/** Width an x axis label needs, px ("27 Nov" over "08:51:02 AM"). */
const LABEL_PX = 96;

/** A session's date and time as an axis label: "27 Nov 08:51" (the browser's locale). */
export function shortWhen(ms) {
  return shortWords(ms);
}

/** Labels for sessions started at `msList` (shortWhen); two in the same minute get their
 * seconds too, so that no two sessions read alike. */
export function sessionLabels(msList) {
  const short = msList.map(ms => shortWords(ms));
  return short.map((l, i) => (short.indexOf(l) !== short.lastIndexOf(l) ? shortWords(msList[i], true) : l));
}

/** A number for a table cell: `decimals` decimals (two by default), an integer for counts;
 * "—" when absent. */
export function cellNumber(v, integer = false, decimals = 2) {
  if (typeof v !== 'number') return '—';
  const digits = integer ? 0 : decimals;
  // Rounded first, so that -0.001 reads as 0 rather than -0.00.
  const rounded = Number(v.toFixed(digits)) || 0;
  return new Intl.NumberFormat(locale(), { minimumFractionDigits: digits, maximumFractionDigits: digits, useGrouping: false }).format(rounded);
}

/** Tick steps of at least 10^-decimals (a tick finer than the measure's resolution would
 * repeat its label once rounded). */
export function incrsFor(decimals) {
  const out = [];
  for (let e = -decimals; e <= 5; e++) for (const m of [1, 2, 5]) out.push(Number((m * 10 ** e).toFixed(Math.max(0, -e))));
  return out;
}

/** The y range to draw: the measure's meaningful `range`, grown to fit any value outside it
 * (never shrunk to the data). */
export function yRange(range, values) {
  const vs = values.filter(v => typeof v === 'number' && Number.isFinite(v));
  if (!range) return vs.length ? [Math.min(...vs), Math.max(...vs)] : [0, 1];
  return [Math.min(range[0], ...vs), Math.max(range[1], ...vs)];
}

/**
 * A chart in `el` with one point a session: `labels` names each session (shortWhen), `y` the
 * axis with its one unit, `series` [{label, values, early}] where `values` are the sessions
 * that count (null elsewhere; the line joins them) and `early` the sessions ended early (drawn
 * hollow, no line; null elsewhere). `integer` gives whole-number ticks (a count or a level);
 * `range` [min, max] is the measure's meaningful axis (grown to fit a value outside it, never
 * zoomed to the data); `decimals` the measure's resolution (no tick finer: no repeated tick
 * labels); `band` [low, high] a shaded band of measurement noise around the baseline. The
 * title, if any, is drawn above; a page usually names the chart in its own heading instead.
 * The ticks drawn are written to `data-ticks` and the y range to `data-y-range`.
 * Returns `destroy()`.
 */
export function sessionChart(el, { title, y, labels, series, integer = false, range = null, decimals = 2, band = null }) {
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
      uSeries.push({ label: t('sessionchart-ended-early', { series: s.label }), stroke: colour, width: 0, paths: () => null,
                     points: { show: true, space: 0, size: 11, width: 2, fill: '#ffffff', stroke: colour } });
      data.push(s.early);
    }
  });
  const all = series.flatMap(s => [...s.values, ...(s.early || [])]);
  const [lo, hi] = yRange(integer && !range ? [0, 1] : range, all);
  const places = integer ? 0 : decimals;
  const yAxis = {
    label: y, size: 60, incrs: integer ? incrsFor(0).filter(i => i >= 1) : incrsFor(places),
    values: (u, splits) => {
      const step = splits.length > 1 ? Math.abs(splits[1] - splits[0]) : 1;
      const shown = Math.max(0, Math.min(places, Math.ceil(-Math.log10(step) - 1e-9)));
      const out = splits.map(v => cellNumber(v, false, shown));
      el.dataset.ticks = out.join('|');
      return out;
    },
  };
  const opts = {
    title,
    width: width(),
    height: HEIGHT_PX,
    scales: {
      x: { time: false, range: () => [0.5, n + 0.5] },
      y: { range: () => [lo, hi] },
    },
    hooks: band ? { drawClear: [u => {
      // The measurement noise around the baseline: a change inside it is not a change.
      const ctx = u.ctx, top = u.valToPos(band[1], 'y', true), bottom = u.valToPos(band[0], 'y', true);
      ctx.save();
      ctx.fillStyle = 'rgba(0, 114, 178, 0.12)';
      ctx.fillRect(u.bbox.left, Math.max(u.bbox.top, top), u.bbox.width, Math.min(u.bbox.top + u.bbox.height, bottom) - Math.max(u.bbox.top, top));
      ctx.restore();
    }] } : {},
    series: uSeries,
    // The series by name (the values are in the table under the chart): no "--" placeholders;
    // none for one measure (its name is the chart's heading).
    legend: { live: false, show: series.length > 1 },
    axes: [
      { label: t('sessionchart-axis-session'), size: 58, splits: () => ticks(),
        values: (u, splits) => splits.map(v => (labels[v - 1] || '').replace(/ (\d{1,2}:\d\d.*)$/, '\n$1')) },
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
  el.dataset.yRange = `${lo} ${hi}`;
  if (band) el.dataset.band = band.map(v => v.toFixed(places + 1)).join(' ');
  return {
    destroy() { window.removeEventListener('resize', resize); chart.destroy(); },
  };
}

/**
 * The numbers of a chart as a table under it, in a <details>: a row a session (its label, each
 * series' value, whether it counts); `status` [{counts, early}] a session.
 */
export function numbersTable(title, labels, columns, status, integer = false, decimals = 2) {
  const word = st => esc(t(st.counts ? (st.early ? 'sessionchart-counted-early' : 'sessionchart-counted')
    : st.early ? 'sessionchart-not-counted-early' : 'sessionchart-not-counted-running'));
  const head = columns.map(c => `<th scope="col">${esc(c.label)}</th>`).join('');
  const rows = labels.map((label, i) => `<tr${status[i].early ? ' data-early="1"' : ''}><th scope="row">${esc(label)}</th>
    ${columns.map(c => `<td class="num">${esc(cellNumber(c.values[i], integer, decimals))}</td>`).join('')}
    <td>${word(status[i])}</td></tr>`).join('');
  return `<details class="numbers print-hide"><summary>${esc(t('sessionchart-numbers', { title }))}</summary>
    <table><caption>${esc(t('sessionchart-caption', { title }))}</caption>
    <thead><tr><th scope="col">${esc(t('sessionchart-col-session'))}</th>${head}<th scope="col">${esc(t('sessionchart-col-counted'))}</th></tr></thead><tbody>${rows}</tbody></table></details>`;
}
