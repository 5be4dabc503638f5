// Time-series charts (uPlot), colour-blind-safe series colours and a unit on every axis.
import uPlot from '/console/vendor/uplot-1.6.32/uPlot.esm.js';

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
      ...series.map((s, i) => ({ label: s.label, stroke: COLOURS[i % COLOURS.length], width: 2,
                                  dash: i % 2 ? [6, 3] : undefined, points: { show: time } })),
    ],
    axes: [{ label: x }, { label: y }],
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
