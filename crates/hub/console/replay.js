// Replay of a stored session from its uploaded recording: the same 3-D arm, car and charts
// as the live view, driven by a time cursor with play/pause, seek and speed, the charts'
// cursors linked to it. The hub sends the recording at 20 frames per second of session time.
import { ArmView } from '/console/arm3d.js';
import { lineChart } from '/console/charts.js';
import { drawRoad } from '/console/live.js';
import { api, esc } from '/console/api.js';

const SPEEDS = [0.25, 0.5, 1, 2, 4, 8];

export async function replayView(el, sessionId) {
  el.innerHTML = '<p role="status">Loading the recording…</p>';
  const r = await api('GET', `/api/sessions/${encodeURIComponent(sessionId)}/replay`);
  const c = r.columns, n = c.t_s.length;
  el.innerHTML = `
    <h2>Replay of session ${esc(sessionId)} (${esc(r.exercise)}, ${r.duration_s.toFixed(1)} s)</h2>
    <div class="tabs" role="group" aria-label="Playback">
      <button type="button" id="play">Play</button>
      <label for="seek" class="sr">Position</label>
      <input id="seek" type="range" min="0" max="${r.duration_s}" step="0.05" value="0" aria-valuetext="0 s">
      <span id="clock" aria-live="off">0.0 / ${r.duration_s.toFixed(1)} s</span>
      <label for="speed">Speed</label>
      <select id="speed">${SPEEDS.map(s => `<option value="${s}"${s === 1 ? ' selected' : ''}>×${s}</option>`).join('')}</select>
    </div>
    <div class="grid">
      <section class="panel"><h2>Arm and wheel</h2>
        <canvas id="arm3d" tabindex="0" aria-label="3-D view of the patient's arm and the wheel; drag or use the arrow keys to turn it"></canvas></section>
      <section class="panel"><h2>Car from above (30 s before the cursor)</h2><canvas id="road" aria-label="The car's path from above"></canvas>
        <p class="note" id="road-note"></p></section>
      <section class="panel"><h2>Tracking</h2><div class="chart" id="r-tracking"></div></section>
      <section class="panel"><h2>Torque and assistance</h2><div class="chart" id="r-torque"></div></section>
      <section class="panel"><h2>Joint angles</h2><div class="chart" id="r-joints"></div></section>
    </div>`;
  el.dataset.frames = String(n);
  const col = name => c[name] || new Array(n).fill(null);
  const dial = c.t_s.map((_, i) => (c.car_x_m && c.car_x_m[i] !== null ? null
    : ((col('wheel_target_rad')[i] ?? 0) - (col('wheel_angle_rad')[i] ?? 0)) * 180 / Math.PI));
  const charts = [
    lineChart(el.querySelector('#r-tracking'), { title: 'Lateral deviation and dial error', x: 'session time (s)', y: 'deviation (m) / error (°)',
      series: [{ label: 'lateral deviation (m)' }, { label: 'dial tracking error (°)' }] }),
    lineChart(el.querySelector('#r-torque'), { title: 'Torque at the wheel', x: 'session time (s)', y: 'torque (N·m)',
      series: [{ label: 'motor torque (N·m)' }, { label: 'assistance torque (N·m)' }, { label: 'torque ceiling (N·m)' }] }),
    lineChart(el.querySelector('#r-joints'), { title: 'Joint angles', x: 'session time (s)', y: 'angle (°)',
      series: [{ label: 'shoulder elevation (°)' }, { label: 'elbow flexion (°)' }] }),
  ];
  charts[0].set([c.t_s, col('lateral_m'), dial]);
  charts[1].set([c.t_s, col('torque_nm'), col('assist_torque_nm'), col('ceiling_nm')]);
  charts[2].set([c.t_s, col('shoulder_elevation_deg'), col('elbow_flexion_deg')]);
  const arm = new ArmView(el.querySelector('#arm3d'));
  const play = el.querySelector('#play'), seek = el.querySelector('#seek'), clock = el.querySelector('#clock');
  const speed = el.querySelector('#speed');
  let position = 0, playing = false, last = null, raf = 0;

  const show = () => {
    const i = Math.min(n - 1, Math.max(0, Math.round(position * r.rate_hz)));
    const frame = {};
    for (const [name, values] of Object.entries(c)) if (values[i] !== null) frame[name] = values[i];
    arm.pose(frame);
    const from = Math.max(0, i - Math.round(30 * r.rate_hz));
    drawRoad(el.querySelector('#road'), { x: col('car_x_m').slice(from, i + 1), y: col('car_y_m').slice(from, i + 1) }, frame);
    for (const ch of charts) ch.chart.setCursor({ left: ch.chart.valToPos(c.t_s[i], 'x'), top: 10 });
    seek.value = String(position);
    seek.setAttribute('aria-valuetext', `${position.toFixed(1)} s`);
    clock.textContent = `${position.toFixed(1)} / ${r.duration_s.toFixed(1)} s`;
    el.dataset.position = position.toFixed(2);
  };
  const tick = now => {
    if (last !== null) position = Math.min(r.duration_s, position + (now - last) / 1000 * Number(speed.value));
    last = now;
    show();
    if (position >= r.duration_s) setPlaying(false);
    else if (playing) raf = requestAnimationFrame(tick);
  };
  const setPlaying = on => {
    playing = on;
    play.textContent = on ? 'Pause' : 'Play';
    cancelAnimationFrame(raf);
    last = null;
    if (on) {
      if (position >= r.duration_s) position = 0;
      raf = requestAnimationFrame(tick);
    }
  };
  play.addEventListener('click', () => setPlaying(!playing));
  seek.addEventListener('input', () => { position = Number(seek.value); show(); });
  show();
  return () => cancelAnimationFrame(raf);
}
