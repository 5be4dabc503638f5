// The live view's second panel during a strength test (issue 30): two bars, pushing left and
// pushing right, each with the patient's push now (blue), the highest push so far of that side
// (an orange mark) and the ceiling the test stops at (a green line), in N·m — the colours of
// the tracking chart beside it, which draws the same three — and the
// same numbers in a table under it (a canvas is not read by screen readers). From the
// station's summaries (`strength_side`, `strength_push_nm`, `strength_peak_{left,right}_nm`,
// and the `ceiling_nm` every summary has; PROTOCOL.md).

import { COLOURS } from '/console/charts.js';
import { fit } from '/console/live-road.js';
import { t, locale } from '/console/i18n.js';

const SIDES = [['left', 1], ['right', -1]];
const sideLabel = side => t(`live-strength-${side}`);

/** Whether a summary's `extra` is of a strength test running now. */
export function isStrength(x) { return Number.isFinite(x.strength_side); }

const nm = v => (Number.isFinite(v)
  ? `${new Intl.NumberFormat(locale(), { minimumFractionDigits: 2, maximumFractionDigits: 2 }).format(v)} N·m` : '—');

/** Each side's figures from a summary's `extra`: [{side, label, active, now, peak}]. */
export function strengthSides(x) {
  return SIDES.map(([side, sign]) => {
    const label = sideLabel(side);
    const active = x.strength_side === sign;
    return { side, label, active, now: active ? x.strength_push_nm : undefined, peak: x[`strength_peak_${side}_nm`] };
  });
}

/** Draws the strength panel for a summary and fills `table` (a <table> element); returns what
 * the note under it says. */
export function drawStrength(canvas, table, x) {
  canvas.dataset.mode = 'strength';
  canvas.dataset.road = '';
  canvas.dataset.laneWidthM = '';
  const [g, w, h] = fit(canvas);
  const ceiling = Number(x.ceiling_nm);
  const sides = strengthSides(x);
  const top = Math.max(...sides.map(s => (Number.isFinite(s.peak) ? s.peak : 0)), Number.isFinite(ceiling) ? ceiling : 0, 0.5);
  const left = 16, right = w - 16, span = right - left;
  const u = v => left + span * Math.min(Math.max(v, 0), top) / top;
  sides.forEach((s, i) => {
    const y = 30 + i * (h - 40) / 2, bar = Math.min(36, (h - 40) / 2 - 26);
    g.fillStyle = '#1b1b1b'; g.font = '14px system-ui, sans-serif';
    g.fillText(s.active ? t('live-strength-now-label', { side: s.label }) : s.label, left, y - 6);
    g.fillStyle = '#f2f2f2'; g.strokeStyle = '#4a4a4a'; g.lineWidth = 1;
    g.fillRect(left, y, span, bar); g.strokeRect(left, y, span, bar);
    if (Number.isFinite(s.now)) { g.fillStyle = COLOURS[0]; g.fillRect(left, y, u(s.now) - left, bar); }
    if (Number.isFinite(s.peak)) {
      g.fillStyle = COLOURS[1]; g.fillRect(u(s.peak) - 2, y - 4, 4, bar + 8);
    }
    if (Number.isFinite(ceiling)) {
      g.strokeStyle = COLOURS[2]; g.lineWidth = 3;
      g.beginPath(); g.moveTo(u(ceiling), y - 6); g.lineTo(u(ceiling), y + bar + 6); g.stroke();
    }
  });
  fillTable(table, sides, ceiling);
  const active = sides.find(s => s.active);
  if (!active) return t('live-strength-resting', { ceiling: nm(ceiling) });
  const share = Number.isFinite(active.now) && ceiling > 0 ? ` ${t('live-strength-share', { pct: Math.round(100 * active.now / ceiling) })}` : '';
  return t('live-strength-note', { side: active.side, now: nm(active.now), share, peak: nm(active.peak), ceiling: nm(ceiling) });
}

/** The numbers under the bars. The table is built once and its cells updated in place at each
 * summary, so a screen reader reading it keeps its place. */
function fillTable(table, sides, ceiling) {
  if (!table.querySelector('tbody tr[data-side]')) {
    table.innerHTML = `<caption class="note">${t('live-strength-caption')}</caption>
      <thead><tr><th scope="col">${t('live-strength-col-side')}</th><th scope="col">${t('live-strength-col-now')}</th><th scope="col">${t('live-strength-col-peak')}</th><th scope="col">${t('live-strength-col-ceiling')}</th></tr></thead>
      <tbody>${SIDES.map(([side]) => `<tr data-side="${side}"><th scope="row">${sideLabel(side)}</th><td class="num" data-now=""></td>
        <td class="num" data-peak=""></td><td class="num"></td></tr>`).join('')}</tbody>`;
  }
  sides.forEach(s => {
    const [now, peak, top] = table.querySelectorAll(`tr[data-side="${s.side}"] td`);
    now.dataset.now = Number.isFinite(s.now) ? s.now : '';
    now.textContent = s.active ? nm(s.now) : '—';
    peak.dataset.peak = Number.isFinite(s.peak) ? s.peak : '';
    peak.textContent = Number.isFinite(s.peak) ? nm(s.peak) : t('live-strength-not-yet');
    top.textContent = nm(ceiling);
  });
}
