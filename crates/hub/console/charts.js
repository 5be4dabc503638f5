// Time-series charts (uPlot), colour-blind-safe series colours and a unit on every axis;
// numbers and dates on the axes and in the legend in the console's language (`locale()`), not
// uPlot's English month names or the browser's number format.
import uPlot from '/console/vendor/uplot-1.6.32/uPlot.esm.js';
import { locale } from '/console/i18n.js';

/** uPlot's date template (`{MMM} {D}`, `{h}:{mm}{aa}`, `{YYYY}`, …) as an Intl format of the
 * language in force. */
export function dateFormat(tpl) {
  const has = s => tpl.includes(s);
  const o = {};
  if (has('{YYYY}') || has('{YY}')) o.year = 'numeric';
  if (has('{MMMM}') || has('{MMM}')) o.month = 'short';
  else if (has('{MM}') || has('{M}')) o.month = '2-digit';
  if (has('{DD}') || has('{D}')) o.day = 'numeric';
  if (has('{h}') || has('{HH}') || has('{H}')) { o.hour = '2-digit'; o.minute = '2-digit'; }
  if (has('{ss}')) o.second = '2-digit';
  const f = new Intl.DateTimeFormat(locale(), Object.keys(o).length ? o : { dateStyle: 'medium', timeStyle: 'short' });
  return d => f.format(d);
}

/** A legend's value in the language's number format (up to 3 decimals); "—" when absent. */
function legendValue(u, v) {
  return v == null ? '—' : new Intl.NumberFormat(locale(), { maximumFractionDigits: 3 }).format(v);
}

/** Axis values in the language's number format, with the decimals the ticks need. */
function numberValues(u, splits, axisIdx, space, incr) {
  const decimals = Math.max(0, Math.min(6, -Math.floor(Math.log10(Math.abs(incr) || 1))));
  const f = new Intl.NumberFormat(locale(), { minimumFractionDigits: decimals, maximumFractionDigits: decimals });
  return splits.map(v => (v == null ? '' : f.format(v)));
}

export const COLOURS = ['#0072b2', '#e69f00', '#009e73', '#d55e00', '#cc79a7', '#56b4e9'];

/**
 * A line chart in `el`: `x` names the x axis (with unit), `series` are [{label, unit}], `y`
 * names the y axis (with unit). `time` makes the x axis dates (seconds since the epoch);
 * `height` is the plot's, px.
 */
export function lineChart(el, { title, x, y, series, time = false, height = 220 }) {
  const width = () => Math.max(280, el.clientWidth || 600);
  const opts = {
    title,
    width: width(),
    height,
    scales: { x: { time } },
    series: [
      { label: x },
      ...series.map((s, i) => ({ label: s.label, stroke: COLOURS[i % COLOURS.length], width: 2, value: legendValue,
                                  dash: i % 2 ? [6, 3] : undefined, points: { show: time } })),
    ],
    axes: [time ? { label: x } : { label: x, values: numberValues }, { label: y, values: numberValues }],
    fmtDate: dateFormat,
  };
  const data = [[], ...series.map(() => [])];
  const chart = new uPlot(opts, data, el);
  const resize = () => chart.setSize({ width: width(), height });
  window.addEventListener('resize', resize);
  return {
    chart,
    /** Remove the chart (and its resize listener). */
    destroy() { window.removeEventListener('resize', resize); chart.destroy(); },
    /** Replace the data: columns [xs, ys1, ys2, …]. */
    set(columns) {
      chart.setData(columns);
      el.dataset.points = String(columns[0].length);
      // Sessions less than a day apart (or one alone) still get a readable date axis: three
      // days either side of them.
      const xs = columns[0];
      if (time && xs.length && xs[xs.length - 1] - xs[0] < 86400) {
        chart.setScale('x', { min: xs[0] - 3 * 86400, max: xs[xs.length - 1] + 3 * 86400 });
      }
    },
  };
}
