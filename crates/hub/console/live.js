// The live view of a patient's running session: the arm in 3-D, the car from above, charts of
// the last 30 s and the safety state, fed by the hub's Server-Sent Events at the summaries'
// rate (10 Hz). The end-to-end delay is the summary's session time against the wall clock.
import { ArmView } from '/console/arm3d.js';
import { lineChart } from '/console/charts.js';
import { api, esc, when } from '/console/api.js';
import { plainName } from '/console/words.js';

const WINDOW_S = 30;

export function liveView(el, patientId) {
  el.innerHTML = `
    <p class="status" id="live-status" role="status" aria-live="polite">Waiting for a session to start…</p>
    <div class="grid">
      <section class="panel" aria-labelledby="arm-h"><h2 id="arm-h">Arm and wheel</h2>
        <canvas id="arm3d" tabindex="0" aria-label="3-D view of the patient's arm and the wheel; drag or use the arrow keys to turn it"></canvas>
        <p class="note" id="angles"></p></section>
      <section class="panel" aria-labelledby="road-h"><h2 id="road-h">Car from above (last 30 s)</h2>
        <canvas id="road" aria-label="The car's path from above"></canvas>
        <p class="note" id="road-note"></p></section>
      <section class="panel" aria-labelledby="c1-h"><h2 id="c1-h">Tracking</h2><div class="chart" id="chart-tracking"></div></section>
      <section class="panel" aria-labelledby="c2-h"><h2 id="c2-h">Torque and assistance</h2><div class="chart" id="chart-torque"></div></section>
      <section class="panel" aria-labelledby="c3-h"><h2 id="c3-h">Joint angles</h2><div class="chart" id="chart-joints"></div></section>
    </div>`;
  const arm = new ArmView(el.querySelector('#arm3d'));
  const charts = {
    tracking: lineChart(el.querySelector('#chart-tracking'), { title: 'Lateral deviation and dial error', x: 'session time (s)', y: 'deviation (m) / error (°)',
      series: [{ label: 'lateral deviation (m)' }, { label: 'dial tracking error (°)' }] }),
    torque: lineChart(el.querySelector('#chart-torque'), { title: 'Torque at the wheel', x: 'session time (s)', y: 'torque (N·m)',
      series: [{ label: 'motor torque (N·m)' }, { label: 'assistance torque (N·m)' }, { label: 'torque ceiling (N·m)' }] }),
    joints: lineChart(el.querySelector('#chart-joints'), { title: 'Joint angles', x: 'session time (s)', y: 'angle (°)',
      series: [{ label: 'shoulder elevation (°)' }, { label: 'elbow flexion (°)' }] }),
  };
  const cols = { t: [], lat: [], dial: [], torque: [], assist: [], ceiling: [], sh: [], el: [], x: [], y: [] };
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
        status.insertAdjacentHTML('beforeend', ` <span class="badge" data-ended="1">ended: ${esc(row.end_reason || 'no reason given')}</span>`);
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
    const t = s.t_s;
    cols.t.push(t);
    cols.lat.push(x.car_x_m === undefined ? null : s.lateral_m);
    cols.dial.push(x.car_x_m === undefined ? (x.wheel_target_rad - x.wheel_angle_rad) * 180 / Math.PI : null);
    cols.torque.push(x.torque_nm ?? null);
    cols.assist.push(x.assist_torque_nm ?? null);
    cols.ceiling.push(x.ceiling_nm ?? null);
    cols.sh.push(x.shoulder_elevation_deg ?? null);
    cols.el.push(x.elbow_flexion_deg ?? null);
    cols.x.push(x.car_x_m ?? null);
    cols.y.push(x.car_y_m ?? null);
    while (cols.t.length && cols.t[0] < t - WINDOW_S) Object.values(cols).forEach(c => c.shift());
    charts.tracking.set([cols.t, cols.lat, cols.dial]);
    charts.torque.set([cols.t, cols.torque, cols.assist, cols.ceiling]);
    charts.joints.set([cols.t, cols.sh, cols.el]);
    arm.pose(x);
    drawRoad(el.querySelector('#road'), cols, x);
    const start = started.get(session);
    const delay = start ? (Date.now() - (start + t * 1000)) / 1000 : null;
    const state = x.watchdog_fault ? '<span class="badge alert">safety fault: torque fading to zero</span>'
      : x.paused ? '<span class="badge warn">paused</span>' : '<span class="badge ok">running</span>';
    status.innerHTML = `Session of ${esc(start ? when(start) : 'just now')} · ${esc(plainName(s.exercise))} · ${t.toFixed(1)} s ${state}
      · torque ${fmt(x.torque_nm, 2)} of ${fmt(x.ceiling_nm, 2)} N·m ceiling
      · in lane ${fmt(s.pct_in_lane, 0)} %` + (delay == null ? '' : ` · delay ${delay.toFixed(2)} s`)
      + (x.recording_stopped_s === undefined ? '' : ` <span class="badge alert">recording stopped at ${fmt(x.recording_stopped_s, 1)} s</span>`);
    status.dataset.delayS = delay == null ? '' : delay.toFixed(3);
    status.dataset.summaries = String(Number(status.dataset.summaries || 0) + 1);
    el.querySelector('#angles').textContent = x.shoulder_elevation_deg === undefined ? 'No arm sensors in this session.'
      : `Shoulder elevation ${fmt(x.shoulder_elevation_deg, 0)}°, elbow flexion ${fmt(x.elbow_flexion_deg, 0)}°, forearm pronation ${fmt(x.forearm_pronation_deg, 0)}°`;
  });
  source.addEventListener('lagged', ev => { status.textContent = `The view fell behind and skipped ${ev.data} summaries.`; });
  // The hub ends the stream when the login ends or the patient is no longer this therapist's:
  // say so, and do not let the browser reconnect.
  source.addEventListener('ended', ev => {
    source.close();
    clearInterval(endCheck);
    status.textContent = `Live view stopped: ${ev.data}. Log in again to watch.`;
  });
  return () => { source.close(); clearInterval(endCheck); };
}

function fmt(v, digits) { return v === undefined || v === null ? '—' : Number(v).toFixed(digits); }

export function drawRoad(canvas, cols, x) {
  const w = canvas.clientWidth || 400, h = canvas.clientHeight || 220;
  canvas.width = w; canvas.height = h;
  const g = canvas.getContext('2d');
  g.clearRect(0, 0, w, h);
  const pts = cols.x.map((px, i) => [px, cols.y[i]]).filter(p => p[0] !== null);
  const note = canvas.parentElement.querySelector('#road-note');
  if (!pts.length) { note.textContent = 'A dial exercise: no car on a road.'; return; }
  const xs = pts.map(p => p[0]), ys = pts.map(p => p[1]);
  const cx = (Math.min(...xs) + Math.max(...xs)) / 2, cy = (Math.min(...ys) + Math.max(...ys)) / 2;
  const span = Math.max(20, Math.max(...xs) - Math.min(...xs), Math.max(...ys) - Math.min(...ys)) * 1.1;
  const k = Math.min(w, h) / span;
  const at = (px, py) => [w / 2 + (px - cx) * k, h / 2 - (py - cy) * k];
  g.strokeStyle = '#0072b2'; g.lineWidth = 3; g.beginPath();
  pts.forEach((p, i) => { const [u, v] = at(p[0], p[1]); if (i) g.lineTo(u, v); else g.moveTo(u, v); });
  g.stroke();
  const [u, v] = at(x.car_x_m, x.car_y_m), yaw = x.car_yaw_rad || 0;
  g.fillStyle = '#d55e00'; g.beginPath();
  g.moveTo(u + 12 * Math.cos(yaw), v - 12 * Math.sin(yaw));
  g.lineTo(u + 7 * Math.cos(yaw + 2.5), v - 7 * Math.sin(yaw + 2.5));
  g.lineTo(u + 7 * Math.cos(yaw - 2.5), v - 7 * Math.sin(yaw - 2.5));
  g.closePath(); g.fill();
  note.textContent = `The car's path over the last ${WINDOW_S} s (scale ${span.toFixed(0)} m across).`;
}
