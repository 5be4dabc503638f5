// Replay of a stored session from its uploaded recording: the same 3-D arm, car and charts
// as the live view, driven by a time cursor with play/pause, seek and speed, the charts'
// cursors linked to it. The hub streams the recording as NDJSON lines at 20 frames per second
// of session time (crates/hub/API.md): the view draws the first second at once and grows as
// the frames arrive; playback runs up to the frames received.
import { ArmView } from '/console/arm3d.js';
import { lineChart } from '/console/charts.js';
import { drawRoad } from '/console/live.js';
import { ApiError, api, esc, refusal, when } from '/console/api.js';
import { plainName } from '/console/words.js';
import { t, locale } from '/console/i18n.js';

/** A number for people in the console's language with one decimal. */
const s1 = v => new Intl.NumberFormat(locale(), { minimumFractionDigits: 1, maximumFractionDigits: 1 }).format(v);

const SPEEDS = [0.25, 0.5, 1, 2, 4, 8];

/** Charts redrawn at most this often while frames arrive, ms. */
const REDRAW_MS = 500;

/** The answer's lines, parsed, as they arrive. */
async function* lines(res) {
  const reader = res.body.getReader();
  const decoder = new TextDecoder();
  let text = '';
  for (;;) {
    const { value, done } = await reader.read();
    if (done) break;
    text += decoder.decode(value, { stream: true });
    let at;
    while ((at = text.indexOf('\n')) >= 0) {
      const line = text.slice(0, at);
      text = text.slice(at + 1);
      if (line.trim()) yield JSON.parse(line);
    }
  }
  if (text.trim()) yield JSON.parse(text);
}

/** The replay's request: its lines, or the hub's refusal as the API's other calls give it. */
async function request(sessionId, signal) {
  const res = await fetch(`/api/sessions/${encodeURIComponent(sessionId)}/replay`, { credentials: 'same-origin', signal });
  if (!res.ok) throw await refusal(res);
  return lines(res);
}

export async function replayView(el, sessionId) {
  el.innerHTML = `<p role="status">${esc(t('replay-loading'))}</p>`;
  const abort = new AbortController();
  // Named by its date and time, never by its id.
  const row = await api('GET', `/api/sessions/${encodeURIComponent(sessionId)}`).catch(() => null);
  const stream = await request(sessionId, abort.signal);
  const first = await stream.next();
  if (first.done) throw new ApiError(502, t('replay-none-sent'));
  const head = first.value;
  let rateHz = head.rate_hz, duration = 0, n = 0, complete = false;
  const expected = head.expected_duration_s || 0;
  const c = { t_s: [] };
  el.innerHTML = `
    <h2 id="replay-h">${esc(t('replay-heading', { when: row ? when(row.started_unix_ms) : t('replay-unknown-time'), exercise: plainName(head.exercise) }))} (<span id="length">${s1(expected)}</span> s)</h2>
    <p class="note" id="loading" role="status">${esc(t('replay-receiving'))}</p>
    <div class="tabs" role="group" aria-label="${esc(t('replay-playback'))}">
      <button type="button" id="play" data-playing="0">${esc(t('replay-play'))}</button>
      <label for="seek" class="sr">${esc(t('replay-position'))}</label>
      <span class="seek-wrap"><input id="seek" type="range" min="0" max="${expected}" step="0.05" value="0" aria-valuetext="${esc(s1(0))} s">
        <span id="timeline-marks" class="timeline-marks" aria-hidden="true"></span></span>
      <span id="clock" aria-live="off">${s1(0)} / ${s1(expected)} s</span>
      <label for="speed">${esc(t('replay-speed'))}</label>
      <select id="speed">${SPEEDS.map(v => `<option value="${v}"${v === 1 ? ' selected' : ''}>×${new Intl.NumberFormat(locale()).format(v)}</option>`).join('')}</select>
    </div>
    <nav id="marks" aria-label="${esc(t('replay-marks-label'))}" hidden><ol id="marks-list" class="marks"></ol></nav>
    <div class="grid">
      <section class="panel"><h2>${esc(t('live-arm-heading'))}</h2>
        <canvas id="arm3d" tabindex="0" aria-label="${esc(t('live-arm-canvas'))}"></canvas></section>
      <section class="panel" id="road-panel" hidden><h2>${esc(t('replay-car-heading'))}</h2><canvas id="road" aria-label="${esc(t('replay-car-canvas'))}"></canvas>
        <p class="note" id="road-note"></p></section>
      <section class="panel"><h2>${esc(t('live-tracking'))}</h2><div class="chart" id="r-tracking"></div></section>
      <section class="panel"><h2>${esc(t('live-torque-heading'))}</h2><div class="chart" id="r-torque"></div></section>
      <section class="panel"><h2>${esc(t('live-joints-heading'))}</h2><div class="chart" id="r-joints"></div></section>
    </div>`;
  const col = name => c[name] || new Array(n).fill(null);
  // The exercises' names by their place in the session (none: numbered only).
  const names = new Map();
  api('GET', `/api/sessions/${encodeURIComponent(sessionId)}/exercises`)
    .then(list => { for (const e of list) names.set(e.index, plainName(e.kind)); drawMarks(); }).catch(() => {});
  const charts = [
    lineChart(el.querySelector('#r-tracking'), { title: t('replay-chart-tracking'), x: t('live-axis-time'), y: t('replay-axis-tracking'),
      series: [{ label: t('live-series-deviation') }, { label: t('replay-series-dial-error') }] }),
    lineChart(el.querySelector('#r-torque'), { title: t('replay-chart-torque'), x: t('live-axis-time'), y: t('live-axis-torque'),
      series: [{ label: t('replay-series-motor') }, { label: t('replay-series-assist') }, { label: t('replay-series-ceiling') }] }),
    lineChart(el.querySelector('#r-joints'), { title: t('live-joints-heading'), x: t('live-axis-time'), y: t('live-axis-angle'),
      series: [{ label: t('live-series-shoulder') }, { label: t('live-series-elbow') }] }),
  ];
  const arm = new ArmView(el.querySelector('#arm3d'));
  const play = el.querySelector('#play'), seek = el.querySelector('#seek'), clock = el.querySelector('#clock');
  const speed = el.querySelector('#speed'), loading = el.querySelector('#loading');
  let position = 0, playing = false, last = null, raf = 0, drawn = 0;
  // The whole length once known; meanwhile the configured one, or what has arrived.
  const length = () => (complete ? duration : Math.max(expected, duration));

  /** Marks on the timeline where each exercise ends and the next follows (the recording's
   * `exercise_index` changes; a rest between them comes after the mark), each also a button
   * that seeks there. */
  let marksAt = [];
  const drawMarks = () => {
    const index = c.exercise_index || [];
    const starts = [];
    for (let i = 1; i < index.length; i++) {
      if (index[i] !== null && index[i - 1] !== null && index[i] !== index[i - 1]) starts.push([c.t_s[i], index[i]]);
    }
    marksAt = starts;
    const line = el.querySelector('#timeline-marks'), list = el.querySelector('#marks-list');
    const total = length() || 1;
    line.replaceChildren(...starts.map(([atS]) => {
      const tick = document.createElement('span');
      tick.className = 'timeline-mark';
      tick.style.left = `${Math.min(100, 100 * atS / total)}%`;
      return tick;
    }));
    list.replaceChildren(...starts.map(([atS, k]) => {
      const item = document.createElement('li');
      const go = document.createElement('button');
      go.type = 'button';
      go.className = 'secondary';
      go.dataset.markS = atS.toFixed(2);
      const name = names.get(k);
      // The index moves on when an exercise ends: the rest or card before the next is after it.
      go.textContent = t('replay-mark', { seconds: s1(atS), ended: k, next: k + 1, name: name || '', named: name ? 'yes' : 'no' });
      go.addEventListener('click', () => { position = Math.min(atS, duration); show(); });
      item.append(go);
      return item;
    }));
    el.querySelector('#marks').hidden = !starts.length;
    el.dataset.marks = String(starts.length);
    // The car's panel only for a recording with a car (a dial session has none).
    const car = (c.car_x_m || []).some(v => v !== null);
    el.querySelector('#road-panel').hidden = !car;
    el.dataset.car = car ? '1' : '0';
  };

  const redraw = () => {
    drawn = performance.now();
    drawMarks();
    const dial = c.t_s.map((_, i) => (c.car_x_m && c.car_x_m[i] !== null ? null
      : ((col('wheel_target_rad')[i] ?? 0) - (col('wheel_angle_rad')[i] ?? 0)) * 180 / Math.PI));
    charts[0].set([c.t_s, col('lateral_m'), dial]);
    charts[1].set([c.t_s, col('torque_nm'), col('assist_torque_nm'), col('ceiling_nm')]);
    charts[2].set([c.t_s, col('shoulder_elevation_deg'), col('elbow_flexion_deg')]);
    seek.max = String(length());
    el.querySelector('#length').textContent = s1(length());
  };
  const show = () => {
    if (!n) return;
    const i = Math.min(n - 1, Math.max(0, Math.round(position * rateHz)));
    const frame = {};
    for (const [name, values] of Object.entries(c)) if (values[i] !== null) frame[name] = values[i];
    arm.pose(frame);
    const from = Math.max(0, i - Math.round(30 * rateHz));
    drawRoad(el.querySelector('#road'), { x: col('car_x_m').slice(from, i + 1), y: col('car_y_m').slice(from, i + 1) }, frame);
    for (const ch of charts) ch.chart.setCursor({ left: ch.chart.valToPos(c.t_s[i], 'x'), top: 10 });
    seek.value = String(position);
    seek.setAttribute('aria-valuetext', `${s1(position)} s`);
    clock.textContent = `${s1(position)} / ${s1(length())} s`;
    el.dataset.position = position.toFixed(2);
  };
  const tick = now => {
    if (last !== null) position = Math.min(duration, position + (now - last) / 1000 * Number(speed.value));
    last = now;
    show();
    if (complete && position >= duration) setPlaying(false);
    else if (playing) raf = requestAnimationFrame(tick);
  };
  const setPlaying = on => {
    playing = on;
    play.textContent = t(on ? 'replay-pause' : 'replay-play');
    play.dataset.playing = on ? '1' : '0';
    cancelAnimationFrame(raf);
    last = null;
    if (on) {
      if (complete && position >= duration) position = 0;
      raf = requestAnimationFrame(tick);
    }
  };
  play.addEventListener('click', () => setPlaying(!playing));
  seek.addEventListener('input', () => { position = Math.min(Number(seek.value), duration); show(); });

  // One line of the answer taken in.
  const take = line => {
    if (line.frames !== undefined) {
      for (const [name, values] of Object.entries(line.columns)) {
        const column = c[name] || (c[name] = new Array(n).fill(null));
        column.push(...values);
      }
      n += line.frames;
      for (const column of Object.values(c)) while (column.length < n) column.push(null);
      duration = c.t_s[n - 1] ?? 0;
    } else if (line.end) {
      complete = true;
      duration = line.duration_s;
    } else if (line.error) {
      throw new ApiError(422, line.error);
    } else if (line.rate_hz !== undefined) {
      // The rate halved: keep the even frames, as the hub has.
      for (const name of Object.keys(c)) c[name] = c[name].filter((_, i) => i % 2 === 0);
      n = Math.ceil(n / 2);
      rateHz = line.rate_hz;
    }
  };
  (async () => {
    try {
      for await (const line of stream) {
        take(line);
        if (complete || performance.now() - drawn > REDRAW_MS) { redraw(); show(); }
      }
      if (!complete) throw new ApiError(502, t('replay-cut-short'));
      loading.textContent = t('replay-frames', { frames: n, rate: rateHz });
      el.dataset.frames = String(n);
    } catch (e) {
      if (e.name === 'AbortError') return;
      loading.className = 'error';
      loading.textContent = t('replay-stopped', { reason: e.message });
    }
  })();
  return () => { abort.abort(); cancelAnimationFrame(raf); };
}
