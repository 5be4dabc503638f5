// The live view of a patient's running session: the arm in 3-D, the car from above, charts of
// the last 30 s and the safety state, fed by the hub's Server-Sent Events at the summaries'
// rate (10 Hz). The end-to-end delay is the summary's session time against the wall clock.
import { ArmView } from '/console/arm3d.js';
import { lineChart } from '/console/charts.js';
import { legendShowsLatest } from '/console/legend.js';
import { drawDial, drawPath, drawRoad as drawLiveRoad } from '/console/live-road.js';
import { drawStrength, isStrength, strengthSides } from '/console/live-strength.js';
import { api, esc, when } from '/console/api.js';
import { endText, plainName } from '/console/words.js';
import { t, locale } from '/console/i18n.js';

const WINDOW_S = 30;
// The hub's LIVE_DELAYED_MS: data this late, or a running session silent this long, is
// "delayed" (the hub says so: `late_ms` on a summary, a `delayed` event while silent).
const DELAYED_MS = 2000;
const CHART_HEIGHT_PX = 160;

// The tracking chart and the second panel say what the exercise is about: the car in its lane
// on a road, the target and the wheel during the dial task (no lane there).
// Built when asked (the catalogue is loaded by then).
const TRACKING = () => ({
  road: { heading: t('live-tracking-road'), y: t('live-axis-deviation'), series: [{ label: t('live-series-deviation') }] },
  dial: { heading: t('live-tracking-dial'), y: t('live-axis-angle'), series: [{ label: t('live-series-wheel') }, { label: t('live-series-target') }] },
  strength: { heading: t('live-tracking-strength'), y: t('live-axis-torque'), series: [{ label: t('live-series-push') }, { label: t('live-series-peak') }, { label: t('live-series-ceiling') }] },
});
const SCENE = m => t(`live-scene-${m}`);

export function liveView(el, patientId) {
  el.innerHTML = `
    <p class="status" id="live-status" role="status" aria-live="polite">${esc(t('live-waiting'))}</p>
    <div class="live-grid">
      <section class="panel live-arm" aria-labelledby="arm-h"><h2 id="arm-h">${esc(t('live-arm-heading'))}</h2>
        <canvas id="arm3d" tabindex="0" aria-label="${esc(t('live-arm-canvas'))}"></canvas>
        <p class="note" id="angles"></p></section>
      <section class="panel live-scene" aria-labelledby="road-h"><h2 id="road-h">${esc(SCENE('road'))}</h2>
        <canvas id="road" aria-describedby="road-note"></canvas>
        <p class="note" id="road-note"></p><table id="strength-table" hidden></table></section>
      <section class="panel live-tracking" aria-labelledby="c1-h"><h2 id="c1-h">${esc(t('live-tracking'))}</h2><div class="chart" id="chart-tracking"></div></section>
      <section class="panel live-torque" aria-labelledby="c2-h"><h2 id="c2-h">${esc(t('live-torque-heading'))}</h2><div class="chart" id="chart-torque"></div></section>
      <section class="panel live-joints" aria-labelledby="c3-h"><h2 id="c3-h">${esc(t('live-joints-heading'))}</h2><div class="chart" id="chart-joints"></div></section>
    </div>`;
  const arm = new ArmView(el.querySelector('#arm3d'));
  const chart = (id, opts) => {
    const c = lineChart(el.querySelector(id), { x: t('live-axis-time'), height: CHART_HEIGHT_PX, ...opts });
    legendShowsLatest(c.chart);
    return c;
  };
  const charts = {
    tracking: null,
    torque: chart('#chart-torque', { y: t('live-axis-torque'),
      series: [{ label: t('live-series-motor') }, { label: t('live-series-assist') }, { label: t('live-series-ceiling') }] }),
    joints: chart('#chart-joints', { y: t('live-axis-angle'),
      series: [{ label: t('live-series-shoulder') }, { label: t('live-series-elbow') }] }),
  };
  let mode = null;
  // A session of a regimen may go from a road to the dial and back: the tracking chart and the
  // second panel follow the exercise running now.
  const setMode = m => {
    if (m === mode) return;
    mode = m;
    charts.tracking?.destroy();
    const tracking = TRACKING()[m];
    charts.tracking = chart('#chart-tracking', { y: tracking.y, series: tracking.series });
    el.querySelector('#c1-h').textContent = tracking.heading;
    el.querySelector('#road-h').textContent = SCENE(m);
  };
  const cols = { t: [], lat: [], target: [], wheel: [], torque: [], assist: [], ceiling: [], sh: [], el: [], x: [], y: [], push: [], peak: [] };
  const started = new Map();
  let session = null;
  const status = el.querySelector('#live-status');
  const source = new EventSource(`/api/patients/${encodeURIComponent(patientId)}/live`);
  // A session that stops sending is asked for its end: "ended: wheel unplugged", not "running"
  // for ever (the station's Bye reason, stored as the session's end_reason).
  let lastSummaryMs = 0, endShown = null;
  const endCheck = setInterval(async () => {
    if (!session || endShown === session || Date.now() - lastSummaryMs < 2000) return;
    try {
      const row = await api('GET', `/api/sessions/${encodeURIComponent(session)}`);
      if (row.closed_at_ms || row.end_reason) {
        endShown = session;
        status.querySelectorAll('.badge.ok, .badge.warn').forEach(b => b.remove());
        status.insertAdjacentHTML('beforeend', ` <span class="badge ended" data-ended="1" data-reason="${esc(row.end_reason || '')}">${esc(endedWords(row))}</span>`);
      }
    } catch { /* asked again at the next tick */ }
  }, 2000);
  source.addEventListener('summary', async ev => {
    lastSummaryMs = Date.now();
    const msg = JSON.parse(ev.data);
    const s = msg.summary, x = s.extra || {};
    if (session !== msg.session_id) {
      session = msg.session_id;
      Object.values(cols).forEach(c => c.length = 0);
      if (!started.has(session)) {
        try { started.set(session, (await api('GET', `/api/sessions/${encodeURIComponent(session)}`)).started_unix_ms); } catch { started.set(session, null); }
      }
    }
    const t_s = s.t_s;
    cols.t.push(t_s);
    const onRoad = x.car_x_m !== undefined, strength = !onRoad && isStrength(x);
    setMode(onRoad ? 'road' : strength ? 'strength' : 'dial');
    const deg = rad => (Number.isFinite(rad) ? rad * 180 / Math.PI : null);
    cols.lat.push(onRoad ? s.lateral_m : null);
    cols.target.push(onRoad ? null : deg(x.wheel_target_rad));
    cols.wheel.push(onRoad ? null : deg(x.wheel_angle_rad));
    cols.torque.push(x.torque_nm ?? null);
    cols.assist.push(x.assist_torque_nm ?? null);
    cols.ceiling.push(x.ceiling_nm ?? null);
    cols.sh.push(x.shoulder_elevation_deg ?? null);
    cols.el.push(x.elbow_flexion_deg ?? null);
    cols.x.push(x.car_x_m ?? null);
    cols.y.push(x.car_y_m ?? null);
    const pushing = strength ? strengthSides(x).find(s => s.active) : undefined;
    cols.push.push(strength ? x.strength_push_nm ?? null : null);
    cols.peak.push(pushing?.peak ?? null);
    while (cols.t.length && cols.t[0] < t_s - WINDOW_S) Object.values(cols).forEach(c => c.shift());
    charts.tracking.set(onRoad ? [cols.t, cols.lat] : strength ? [cols.t, cols.push, cols.peak, cols.ceiling] : [cols.t, cols.wheel, cols.target]);
    charts.torque.set([cols.t, cols.torque, cols.assist, cols.ceiling]);
    charts.joints.set([cols.t, cols.sh, cols.el]);
    arm.pose(x);
    const scene = el.querySelector('#road');
    const table = el.querySelector('#strength-table');
    table.hidden = !strength;
    el.querySelector('#road-note').textContent = onRoad ? drawLiveRoad(scene, cols, x, WINDOW_S)
      : strength ? drawStrength(scene, table, x) : drawDial(scene, x);
    const start = started.get(session);
    const delay = start ? (Date.now() - (start + t_s * 1000)) / 1000 : null;
    const state = x.watchdog_fault ? 'fault' : x.paused ? 'paused' : 'running';
    const badge = { fault: 'alert', paused: 'warn', running: 'ok' }[state];
    const late = Number.isFinite(msg.late_ms) && msg.late_ms >= DELAYED_MS;
    status.dataset.state = state;
    status.dataset.mode = onRoad ? 'road' : strength ? 'strength' : 'dial';
    status.dataset.ceilingNm = Number.isFinite(x.ceiling_nm) ? String(x.ceiling_nm) : '';
    const parts = [
      t('live-status-session', { when: start ? when(start) : t('live-just-now') }),
      plainName(s.exercise),
      t('live-status-seconds', { seconds: fmt(t_s, 1) }),
    ].map(esc).join(' · ');
    const measure = onRoad ? t('live-status-lane', { pct: fmt(s.pct_in_lane, 0) })
      : strength ? t('live-status-push', { nm: fmt(x.strength_push_nm, 2) })
        : t('live-status-dial-off', { degrees: fmt(Math.abs(deg(x.wheel_angle_rad - x.wheel_target_rad) ?? NaN), 0) });
    status.innerHTML = `${parts} <span class="badge ${badge}">${esc(t(`live-state-${state}`))}</span>
      · ${esc(t('live-status-torque', { nm: fmt(x.torque_nm, 2), ceiling: fmt(x.ceiling_nm, 2) }))}
      · ${esc(measure)}`
      + (delay == null ? '' : ` · ${esc(t('live-status-delay', { seconds: fmt(delay, 2) }))}`)
      + (x.recording_stopped_s === undefined ? '' : ` <span class="badge alert" data-recording-stopped="1">${esc(t('live-recording-stopped', { seconds: fmt(x.recording_stopped_s, 1) }))}</span>`)
      + (late ? ` <span class="badge warn" data-delayed="late">${esc(t('live-delayed-late', { seconds: fmt(msg.late_ms / 1000, 1) }))}</span>` : '');
    status.dataset.delayed = late ? 'late' : '';
    status.dataset.delayS = delay == null ? '' : delay.toFixed(3);
    status.dataset.summaries = String(Number(status.dataset.summaries || 0) + 1);
    el.querySelector('#angles').textContent = x.shoulder_elevation_deg === undefined ? t('live-no-arm-sensors')
      : t('live-angles', { shoulder: fmt(x.shoulder_elevation_deg, 0), elbow: fmt(x.elbow_flexion_deg, 0), forearm: fmt(x.forearm_pronation_deg, 0) });
  });
  // A running session silent on a home link that is down: not "running" on its last summary.
  source.addEventListener('delayed', ev => {
    const d = JSON.parse(ev.data);
    if (d.session_id !== session || endShown === session) return;
    status.querySelectorAll('.badge.ok, [data-delayed]').forEach(b => b.remove());
    status.insertAdjacentHTML('beforeend', ` <span class="badge warn" data-delayed="silent">${esc(t('live-delayed-silent', { seconds: fmt(d.silent_ms / 1000, 0) }))}</span>`);
    status.dataset.delayed = 'silent';
  });
  source.addEventListener('lagged', ev => { status.textContent = t('live-lagged', { count: Number(ev.data) }); });
  // The hub ends the stream when the login ends or the patient is no longer this therapist's:
  // say so, and do not let the browser reconnect.
  source.addEventListener('ended', ev => {
    source.close();
    clearInterval(endCheck);
    status.dataset.stopped = ev.data;
    status.textContent = t(`live-stopped-${ev.data}`);
  });
  return () => { source.close(); clearInterval(endCheck); };
}

/** How the session `row` (`GET /api/sessions/{id}`) ended as the status says it, in the
 * console's words from the hub's end kind: "ended: complete, as prescribed", "Stopped early:
 * wheel unplugged", "ended (how is not recorded)". */
export function endedWords(row) {
  const r = (row.end_reason || '').trim();
  if (r === 'complete') return t('live-ended-complete');
  if (!r || !row.end_kind || row.end_kind === 'unreported') return t('live-ended-unknown');
  return endText(row);
}

/** A number for people in the console's language with `digits` decimals, '—' when absent. */
function fmt(v, digits) {
  if (v === undefined || v === null || !Number.isFinite(Number(v))) return '—';
  return new Intl.NumberFormat(locale(), { minimumFractionDigits: digits, maximumFractionDigits: digits }).format(Number(v));
}

/** A replay's car from above (a recording carries no road): its path, fitted to the canvas. */
export function drawRoad(canvas, cols, x) {
  canvas.parentElement.querySelector('#road-note').textContent =
    drawPath(canvas, cols, x, t('live-path-note', { seconds: WINDOW_S }));
}
