// Chart legends that show numbers: while the cursor is off a chart, each series' latest value
// (uPlot shows "--" there by default); on the chart, the values under the cursor as usual.

function lastIndex(column) {
  for (let i = column.length - 1; i >= 0; i--) if (column[i] !== null && column[i] !== undefined) return i;
  return null;
}

function showLatest(u) {
  if (u.cursor.idx !== null && u.cursor.idx !== undefined) return;
  u.setLegend({ idxs: u.data.map(lastIndex) }, false);
}

/** Makes `u` (a uPlot chart) show its series' latest values whenever the cursor is off it. */
export function legendShowsLatest(u) {
  for (const hook of ['setLegend', 'setData']) (u.hooks[hook] ||= []).push(showLatest);
  return u;
}
