// The therapist console: login, the caseload, and a patient's live view, progress and
// prescription. A hash router over the console API; no inline script or style (the hub's
// Content-Security-Policy forbids them), every value put into HTML escaped.
import { api, ApiError, esc, when } from '/console/api.js';
import { liveView } from '/console/live.js';
import { lineChart } from '/console/charts.js';
import { replayView } from '/console/replay.js';
import { exercisesView } from '/console/exercises.js';
import { difficultyFields, exerciseKinds, regimenLimits, regimenSchema } from '/console/schema.js';
import { messagesPanel, messageProblem, sendMessage } from '/console/messages.js';
import { clinicView } from '/console/clinic.js';
import { bindNoteCells, noteCell, notesSection } from '/console/notes.js';
import { assistModes, assistFields, readAssist } from '/console/assist.js';
import { wheelBounds } from '/console/wheel.js';
import { activeWords, endWords, kindWords, likeWithLike, sessionWords, trendWords } from '/console/words.js';

const app = document.getElementById('app');
let leave = () => {};
let me = null;

/** The measures a therapist follows across sessions, with their plain names and units;
 * `better` says which way is progress. */
const MEASURES = [
  ['pct_in_lane', 'time in lane', '%', 'up'],
  ['rms_lateral_m', 'lane keeping error (RMS lateral deviation)', 'm', 'down'],
  ['wheel_rom_deg', 'wheel range of motion', '°', 'up'],
  ['shoulder_elevation_rom_deg', 'shoulder elevation range', '°', 'up'],
  ['elbow_flexion_rom_deg', 'elbow flexion range', '°', 'up'],
  ['sparc_median', 'movement smoothness (SPARC, closer to 0 is smoother)', '', 'up'],
  ['assist_level_mean', 'assistance level', '0–1', 'down'],
  ['active_s', 'active time', 's', 'up'],
];

async function route() {
  leave(); leave = () => {};
  const hash = location.hash || '#/patients';
  try {
    me = me || await api('GET', '/api/me');
  } catch (e) {
    if (e instanceof ApiError && e.status === 401) return loginView();
    return fail(e);
  }
  document.getElementById('who').textContent = `${me.email} (${me.role})`;
  document.getElementById('logout').hidden = false;
  document.getElementById('change-password').hidden = false;
  if (me.must_change_password) return passwordView(true);
  if (hash === '#/password') return passwordView(false);
  document.getElementById('clinic-link').hidden = false;
  if (hash.startsWith('#/clinic')) return clinicView(app, hash, me).catch(fail).then(() => app.focus());
  const m = hash.match(/^#\/patients\/([^/]+)(?:\/(live|progress|prescribe|replay|exercises)(?:\/([^/]+))?)?$/);
  try {
    if (m) await patientView(decodeURIComponent(m[1]), m[2] || 'live', m[3] && decodeURIComponent(m[3]));
    else await patientsView();
  } catch (e) { fail(e); }
  app.focus();
}

function fail(e) {
  app.innerHTML = `<p class="error" role="alert">${esc(e.message || e)}</p><p><a href="#/patients">Back to the patients</a></p>`;
}

/** The change-password screen; `forced` for a one-time password, which the hub lets do
 * nothing else until it is changed. */
function passwordView(forced) {
  app.innerHTML = `
    <h1>${forced ? 'Choose your own password' : 'Change your password'}</h1>
    ${forced ? '<p id="password-forced">You logged in with a one-time password. Choose your own before you continue.</p>' : ''}
    <form id="password-form" novalidate>
      <label for="current-password">${forced ? 'One-time password' : 'Current password'}</label>
      <input id="current-password" type="password" autocomplete="current-password" required>
      <label for="new-password">New password <span class="note">(at least 10 characters, not only spaces, not your e-mail, not a common password)</span></label>
      <input id="new-password" type="password" autocomplete="new-password" minlength="10" required>
      <label for="repeat-password">New password again</label>
      <input id="repeat-password" type="password" autocomplete="new-password" minlength="10" required>
      <p><button type="submit">Change the password</button></p>
      <p class="error" id="password-error" role="alert"></p>
    </form>`;
  const form = app.querySelector('#password-form');
  const error = app.querySelector('#password-error');
  form.addEventListener('submit', async ev => {
    ev.preventDefault();
    const current = form.querySelector('#current-password').value;
    const next = form.querySelector('#new-password').value;
    if (next !== form.querySelector('#repeat-password').value) { error.textContent = 'The two new passwords differ.'; return; }
    try {
      // The hub ends every login of this account and answers with a new session cookie.
      await api('POST', '/api/me/password', { current, new: next });
      me = await api('GET', '/api/me');
      location.hash = '#/patients';
      route();
    } catch (e) { error.textContent = e.message; }
  });
  form.querySelector('#current-password').focus();
}

function loginView() {
  document.getElementById('logout').hidden = true;
  document.getElementById('change-password').hidden = true;
  document.getElementById('clinic-link').hidden = true;
  document.getElementById('who').textContent = '';
  app.innerHTML = `
    <h1>Log in</h1>
    <form id="login" novalidate>
      <label for="email">E-mail</label><input id="email" type="email" autocomplete="username" required>
      <label for="password">Password</label><input id="password" type="password" autocomplete="current-password" required>
      <p><button type="submit">Log in</button></p>
      <p class="error" id="login-error" role="alert"></p>
    </form>`;
  const form = app.querySelector('#login');
  form.addEventListener('submit', async ev => {
    ev.preventDefault();
    try {
      me = await api('POST', '/api/login', { email: form.email.value, password: form.password.value });
      location.hash = '#/patients';
      route();
    } catch (e) { app.querySelector('#login-error').textContent = e.message; }
  });
  app.querySelector('#email').focus();
}

async function patientsView() {
  const patients = await api('GET', '/api/patients');
  const rows = patients.map(p => {
    const alerts = p.alerts.length ? p.alerts.map(a => `<span class="badge alert">${esc(a)}</span>`).join(' ')
      : '<span class="badge ok">none</span>';
    const sessions = p.sessions_per_week_prescribed == null ? `${p.sessions_last_7_days} sessions`
      : `${p.sessions_last_7_days} of ${p.sessions_per_week_prescribed} prescribed sessions`;
    const minutes = p.minutes_per_week_prescribed == null ? `${Math.round(p.active_minutes_last_7_days)} active min`
      : `${Math.round(p.active_minutes_last_7_days)} of ${Math.round(p.minutes_per_week_prescribed)} prescribed active min`;
    const week = `${sessions}, ${minutes}`;
    const trends = [['pct_in_lane', 'time in lane'], ['wheel_rom_deg', 'wheel range'], ['sparc_median', 'smoothness']]
      .filter(([k]) => p.trends[k])
      .map(([k, label]) => {
        const t = p.trends[k];
        const [arrow, cls, word] = t === 'up' ? ['↑', 'up', 'better'] : t === 'down' ? ['↓', 'down', 'worse'] : ['→', '', 'steady'];
        return `<span class="${cls}">${esc(label)} ${arrow} ${word}</span>`;
      }).join('<br>') || '—';
    const trendsOf = p.trend_exercise_kind && trends !== '—' ? `<span class="note">${esc(kindWords(p.trend_exercise_kind))} sessions:</span><br>${trends}` : trends;
    return `<tr><td><a href="#/patients/${encodeURIComponent(p.id)}">${esc(p.pseudonym)}</a></td>
      <td>${esc(when(p.last_session_started_ms))}</td><td>${esc(week)}</td><td>${trendsOf}</td><td>${alerts}</td></tr>`;
  }).join('');
  app.innerHTML = `<h1>Patients</h1>
    <table><caption class="note">Your caseload. Open a patient to watch a running session, see progress or prescribe.</caption>
    <thead><tr><th scope="col">Patient</th><th scope="col">Last session</th><th scope="col">Last 7 days</th><th scope="col">Trend (last session)</th><th scope="col">Alerts</th></tr></thead>
    <tbody>${rows || '<tr><td colspan="5">No patients yet.</td></tr>'}</tbody></table>
    <p><a href="#/clinic">Add a patient</a> (and print the pairing sheet)</p>`;
}

async function patientView(id, tab, sessionId) {
  const p = await api('GET', `/api/patients/${encodeURIComponent(id)}`);
  const link = (t, label) => `<a href="#/patients/${encodeURIComponent(id)}/${t}"${t === tab ? ' aria-current="page"' : ''}>${label}</a>`;
  app.innerHTML = `<h1>Patient ${esc(p.pseudonym)}</h1>
    <nav class="tabs" aria-label="Patient">${link('live', 'Live')}${link('progress', 'Progress')}${link('prescribe', 'Prescribe')}<a href="#/clinic/patients/${encodeURIComponent(id)}">Stations and pairing</a></nav>
    <div id="tab"></div>
    <section id="messages"></section>`;
  const el = app.querySelector('#tab');
  const refreshMessages = await messagesPanel(app.querySelector('#messages'), id);
  if (tab === 'live') { el.id = 'live'; leave = liveView(el, id); }
  else if (tab === 'progress') await progressView(el, id, p);
  else if (tab === 'replay') leave = await replayView(el, sessionId);
  else if (tab === 'exercises') { await exercisesView(el, id, sessionId); await notesSection(el, sessionId); }
  else await prescribeView(el, id, refreshMessages);
}

/** A session's check-in in a few words (HTML, every part escaped); pain of 7 or more marked. */
function checkinWords(c) {
  if (!c) return '—';
  const difficulty = { too_easy: 'too easy', about_right: 'about right', too_hard: 'too hard' };
  const parts = [];
  if (c.pain_0_10 != null) parts.push(`<span class="${c.pain_0_10 >= 7 ? 'badge alert' : ''}">pain ${esc(String(c.pain_0_10))}/10</span>`);
  if (c.tiredness_0_10 != null) parts.push(`tiredness ${esc(String(c.tiredness_0_10))}/10`);
  if (c.difficulty != null) parts.push(esc(difficulty[c.difficulty] || c.difficulty));
  return parts.length ? parts.join(', ') : 'skipped';
}

/** The difficulty history (oldest first): a chart and a table of each change and its reason,
 * the station's words escaped; nothing when no session adapted. */
function difficultyPanel(history) {
  if (!history.length) return '';
  const signed = x => (x < -0.0005 ? `−${(-x).toFixed(2)}` : `+${x.toFixed(2)}`);
  const rows = history.slice().reverse().map(d => `<tr><td>${esc(when(d.started_unix_ms))}</td>
    <td class="num">${esc(d.difficulty.toFixed(2))}</td><td class="num">${esc(signed(d.change))}</td>
    <td>${d.success_rate == null ? '—' : `${esc(Math.round(d.success_rate * 100))} %`}</td><td class="reason">${esc(d.reason)}</td></tr>`).join('');
  return `<section class="panel" id="difficulty" aria-labelledby="difficulty-h"><h2 id="difficulty-h">Difficulty that follows the patient</h2>
      <p class="note">0: half the prescribed speed and shape with all its assistance; 1: the regimen as written. Set by the station within the regimen's [difficulty] bounds.</p>
      <div class="chart" id="p-difficulty"></div>
      <table id="difficulty-table"><thead><tr><th scope="col">Started</th><th scope="col">Difficulty</th><th scope="col">Change</th><th scope="col">Success</th><th scope="col">Why</th></tr></thead><tbody>${rows}</tbody></table></section>`;
}

async function progressView(el, id, patient) {
  const sessions = (await api('GET', `/api/patients/${encodeURIComponent(id)}/sessions`)).slice().reverse();
  const metrics = await Promise.all(sessions.map(s => api('GET', `/api/sessions/${encodeURIComponent(s.session_id)}/metrics`).catch(() => ({}))));
  // The patient's own answers on each session's end screen (plain text, escaped).
  const checkins = new Map((await api('GET', `/api/patients/${encodeURIComponent(id)}/checkins`).catch(() => []))
    .map(c => [c.session_id, c]));
  // The difficulty each adapted session ran at and why (newest first from the hub).
  const difficulty = (await api('GET', `/api/patients/${encodeURIComponent(id)}/difficulty`).catch(() => [])).slice().reverse();
  const t = sessions.map(s => s.started_unix_ms / 1000);
  // Like with like: the latest session that ran as prescribed against earlier ones of its kind.
  const like = likeWithLike(sessions);
  const latest = like.length ? sessions[like[0]] : null;
  const rows = MEASURES.map(([key, label, unit, better]) => {
    const values = like.map(i => metrics[i][key]);
    const last = values[0];
    const head = `<tr data-key="${esc(key)}"><th scope="row">${esc(label)}</th>`;
    if (key === 'active_s') return `${head}<td>${esc(activeWords(last, latest && latest.prescribed_s))}</td><td class="note">against the prescription, not a trend</td></tr>`;
    return `${head}<td>${last === undefined ? '—' : `${esc(Number(last).toFixed(2))} ${esc(unit)}`}</td><td>${trendWords(values, better)}</td></tr>`;
  }).join('');
  const compared = latest ? `The latest session that ran as prescribed (${esc(sessionWords(latest))}) against up to four earlier ${esc(kindWords(latest.exercise_kind))} sessions that did too; sessions ended early are shown below, not compared.`
    : 'No session has run as prescribed yet: nothing to compare.';
  const list = sessions.slice().reverse().map(s => `<tr${s.ran_as_prescribed ? '' : ' data-early="1"'}><td>${esc(when(s.started_unix_ms))}</td><td>${esc(s.exercise_name || s.exercise)}</td>
    <td>${endWords(s)}</td>
    <td class="checkin">${checkinWords(checkins.get(s.session_id))}</td>
    <td><a href="#/patients/${encodeURIComponent(id)}/exercises/${encodeURIComponent(s.session_id)}">Each exercise</a>
      · <a href="#/patients/${encodeURIComponent(id)}/replay/${encodeURIComponent(s.session_id)}">Replay</a></td>
    <td>${noteCell(s.session_id, `the session of ${when(s.started_unix_ms)}`, esc)}</td></tr>`).join('');
  el.innerHTML = `
    <p class="print-hide"><button type="button" id="print" class="secondary">Print a one-page summary</button></p>
    <section class="panel" aria-labelledby="latest-h"><h2 id="latest-h">${latest ? `Latest ${esc(kindWords(latest.exercise_kind))} session against the earlier ones` : 'Latest session against the earlier ones'}</h2>
      <p class="note print-hide" id="compared">${compared}</p>
      <table id="latest-table"><thead><tr><th scope="col">Measure</th><th scope="col">Latest</th><th scope="col">Trend</th></tr></thead><tbody>${rows}</tbody></table></section>
    <div class="grid">
      <section class="panel"><h2>Lane keeping</h2><div class="chart" id="p-lane"></div></section>
      <section class="panel"><h2>Ranges of motion</h2><div class="chart" id="p-rom"></div></section>
      <section class="panel"><h2>Movement smoothness</h2><div class="chart" id="p-sparc"></div></section>
      <section class="panel"><h2>Active time and assistance</h2><div class="chart" id="p-active"></div></section>
    </div>
    ${difficultyPanel(difficulty)}
    <section class="panel print-hide" aria-labelledby="sessions-h"><h2 id="sessions-h">Sessions (${sessions.length})</h2>
      <table><thead><tr><th scope="col">Started</th><th scope="col">Exercise</th><th scope="col">End</th><th scope="col">Patient's check-in</th><th scope="col">Results and recording</th><th scope="col">Therapist's notes</th></tr></thead><tbody>${list}</tbody></table></section>`;
  el.querySelector('#print').addEventListener('click', () => window.print());
  bindNoteCells(el);
  const col = key => metrics.map(m => (typeof m[key] === 'number' ? m[key] : null));
  const chart = (sel, title, y, series) => lineChart(el.querySelector(sel), { title, x: 'session date', y, time: true,
    series: series.map(([, label]) => ({ label })) }).set([t, ...series.map(([key]) => col(key))]);
  chart('#p-lane', 'Time in lane and lane keeping error', '% / m', [['pct_in_lane', 'time in lane (%)'], ['rms_lateral_m', 'lane keeping error (m)']]);
  chart('#p-rom', 'Ranges of motion', 'range (°)', [['wheel_rom_deg', 'wheel (°)'], ['shoulder_elevation_rom_deg', 'shoulder elevation (°)'], ['elbow_flexion_rom_deg', 'elbow flexion (°)']]);
  chart('#p-sparc', 'Smoothness (SPARC)', 'SPARC (dimensionless)', [['sparc_median', 'SPARC, median of movements']]);
  chart('#p-active', 'Active time and assistance', 's / level', [['active_s', 'active time (s)'], ['assist_level_mean', 'assistance level (0–1)']]);
  if (difficulty.length) {
    // By session (1: the first adapted one): a change reads the same a day or a week apart.
    lineChart(el.querySelector('#p-difficulty'), { title: 'Difficulty and success', x: 'adapted session', y: '0–1', time: false,
      series: [{ label: 'difficulty (0–1)' }, { label: 'success rate (0–1)' }] })
      .set([difficulty.map((_, i) => i + 1), difficulty.map(d => d.difficulty), difficulty.map(d => d.success_rate ?? null)]);
  }
  el.dataset.sessions = String(sessions.length);
  void patient;
}

/** A number input with its bounds from the regimen's schema (enforced by the browser, shown
 * beside it; the hub checks the whole regimen again with the station's own validator). An empty
 * field leaves the setting at its default, shown as the placeholder. */
function numberField(id, label, value, spec) {
  const range = spec.min === undefined && spec.max === undefined ? ''
    : `<span class="note">(${spec.min ?? '…'}–${spec.max ?? '…'})</span>`;
  const attr = (name, v) => (v === undefined ? '' : ` ${name}="${esc(v)}"`);
  return `<label for="${id}">${esc(label)} ${range}</label>
    <input id="${id}" type="number"${attr('min', spec.min)}${attr('max', spec.max)} step="${spec.integer ? 1 : 'any'}"
      value="${esc(value ?? '')}"${attr('placeholder', spec.default)} inputmode="decimal" data-field>`;
}

/** The prescribe form's `[difficulty]` fields: adapt on or off, the bounds (from the schema),
 * and what the difficulty changes. */
function difficultyForm(d, adapt) {
  const on = !!d;
  const fields = adapt.fields.map(([name, spec]) => numberField(`rx-d-${name}`, labelOf(name, spec), d && d[name], spec)).join('');
  const changes = d && d.changes ? d.changes : adapt.aspects;
  const boxes = adapt.aspects.map(a => `<label><input type="checkbox" id="rx-d-change-${esc(a)}" data-aspect="${esc(a)}"${changes.includes(a) ? ' checked' : ''}> ${esc(a)}</label>`).join(' ');
  return `<fieldset class="panel" id="rx-difficulty"><legend>Difficulty that follows the patient</legend>
    <label><input type="checkbox" id="rx-d-adapt"${on && d.adapt !== false ? ' checked' : ''}> Adapt each session's difficulty to the patient (aiming at the target success rate, honouring "too easy / too hard")</label>
    ${fields}
    <p>Changes: ${boxes}</p>
    <p class="note">Difficulty 1 is the regimen as written; 0 is half its speed and shape with all its assistance. Never beyond the prescription; the torque ceiling never changes.</p>
  </fieldset>`;
}

/** Reads the `[difficulty]` fields into `model` (none when adaptation is off and no bound set). */
function readDifficulty(el, model, adapt, num) {
  const on = el.querySelector('#rx-d-adapt').checked;
  const d = {};
  for (const [name] of adapt.fields) { const v = num(`#rx-d-${name}`); if (v !== undefined) d[name] = v; }
  const changes = [...el.querySelectorAll('[data-aspect]')].filter(b => b.checked).map(b => b.dataset.aspect);
  if (!on && !Object.keys(d).length) { delete model.difficulty; return; }
  d.adapt = on;
  if (changes.length !== adapt.aspects.length) d.changes = changes;
  model.difficulty = d;
}

/** A field's label: its description's first sentence (it names the unit). */
const labelOf = (name, spec) => (spec.description.split(/\.\s|\n/)[0] || name).replace(/\.$/, '').replace(/[`[\]]/g, '');

async function prescribeView(el, id, refreshMessages) {
  const [r, schema, patient] = await Promise.all([
    api('GET', `/api/patients/${encodeURIComponent(id)}/regimen`), regimenSchema(),
    api('GET', `/api/patients/${encodeURIComponent(id)}`)]);
  // The patient's own bounds: their wheel's ceiling, never above the schema's device maximum.
  const wheel = wheelBounds(patient.wheel);
  const modes = assistModes(schema);
  const kinds = exerciseKinds(schema);
  const limits = regimenLimits(schema);
  const adapt = difficultyFields(schema);
  const cur = r.current;
  const model = r.current_fields || { exercise: [] };
  if (!Array.isArray(model.exercise)) model.exercise = [];
  el.id = 'prescribe';
  const kindOf = e => kinds.find(k => k.kind === e.kind);
  const render = () => {
    const rows = model.exercise.map((e, i) => {
      const k = kindOf(e);
      const fields = k ? k.fields.map(([name, spec]) => numberField(`ex${i}-${name}`, labelOf(name, spec), e[name], spec)).join('')
        : '<p class="note">An exercise kind this hub does not know: edit it as TOML.</p>';
      return `
      <fieldset class="panel"><legend>Exercise ${i + 1}: ${esc(e.kind)}</legend>
        ${fields}
        ${numberField(`ex${i}-ceiling`, 'Torque ceiling, N·m (empty: the station\'s)', e.haptic && e.haptic.ceiling_nm, wheel.torque({ ...limits.ceiling, default: undefined }))}
        ${e.kind === 'dial' ? '' : `<p><input type="checkbox" id="ex${i}-pedals"${e.pedals ? ' checked' : ''}>
          <label for="ex${i}-pedals" class="inline">The patient sets the speed with the pedals (needs a duration; leave unticked for automatic speed)</label></p>`}
        ${assistFields(i, e.assist, modes, numberField, esc)}
        <p><button type="button" class="secondary" data-remove="${i}">Remove exercise ${i + 1}</button></p>
      </fieldset>`;
    }).join('');
    const full = model.exercise.length >= limits.maxExercises;
    el.innerHTML = `
    <section class="panel" aria-labelledby="rx-h"><h2 id="rx-h">Regimen</h2>
      <p id="rx-version">${cur ? `Version ${esc(cur.version)}, prescribed by ${esc(r.current_prescribed_by_email || 'a therapist no longer at the clinic')} on ${esc(when(cur.prescribed_at_ms))}.` : 'Nothing prescribed yet: the station runs its default exercise.'}</p>
      ${wheel.line}
      <form id="rx-form" novalidate>
        ${numberField('rx-sessions', 'Sessions a week', model.sessions_per_week, { ...limits.sessionsPerWeek, default: undefined })}
        ${adapt ? difficultyForm(model.difficulty, adapt) : ''}
        ${rows || '<p>No exercise yet: add one.</p>'}
        <label for="rx-add">Add an exercise</label>
        <select id="rx-add">${kinds.map(k => `<option value="${esc(k.kind)}" title="${esc(k.description)}">${esc(k.kind)}</option>`).join('')}</select>
        <button type="button" class="secondary" id="rx-add-btn"${full ? ' disabled' : ''}>Add</button>
        ${full ? `<p class="note">At most ${esc(limits.maxExercises)} exercises in a regimen.</p>` : ''}
        <label for="rx-note">A note for the patient with this prescription <span class="note">(optional, at most 500 characters, shown when their next session starts)</span></label>
        <textarea id="rx-note" maxlength="500" rows="2"></textarea>
        <p><button type="submit">Save as a new version</button></p>
      </form>
      <p id="rx-result" role="alert"></p>
      <details><summary>Edit as TOML (every setting, as in the station's <code>regimens/</code>)</summary>
        <form id="rx">
          <label for="toml">Regimen (TOML)</label>
          <textarea id="toml" spellcheck="false">${esc(cur ? cur.toml : '')}</textarea>
          <p><button type="submit">Save the TOML as a new version</button></p>
        </form>
      </details>
      <h3>Safety bounds the station enforces</h3>
      <dl class="bounds" id="bounds">
        <dt>Torque ceiling</dt><dd>at most ${esc(wheel.ceiling ?? limits.ceiling.max)} N·m in a prescription (${wheel.ceiling == null ? 'the strongest consumer wheel' : 'what this patient\'s wheel can give'}), refused above; the station then caps it at its own wheel's ceiling (a prescription can lower the patient's ceiling, never raise it)</dd>
        <dt>Torque changes</dt><dd>slew-limited by the station's safety chain whatever the prescription</dd>
        <dt>Session</dt><dd>at most ${esc(limits.maxExercises)} exercises planned to last at most ${esc(Math.round(limits.maxPlannedS / 60))} min together</dd>
        <dt>Every other setting</dt><dd>within the range shown beside it</dd>
      </dl>
      <p class="note">The form's ranges come from the regimen's schema, which the hub derives from the station's own validator; the hub checks the whole regimen with that validator before storing it, and the station picks the new version up at its next session.</p>
    </section>`;
    bind();
  };
  const out = () => el.querySelector('#rx-result');
  const save = async (body, note = '') => {
    out().className = ''; out().textContent = 'Saving…';
    const problem = note && messageProblem(note);
    if (problem) { out().className = 'error'; out().textContent = `The note: ${problem}`; return; }
    try {
      const v = await api('PUT', `/api/patients/${encodeURIComponent(id)}/regimen`, body);
      if (note) { await sendMessage(id, note); await refreshMessages(); }
      const again = await api('GET', `/api/patients/${encodeURIComponent(id)}/regimen`);
      Object.assign(model, again.current_fields);
      render();
      out().textContent = `Saved as version ${v.version}${note ? ', with the note' : ''}.`;
      el.querySelector('#rx-version').textContent = `Version ${v.version}, prescribed by ${me.email} just now.`;
    } catch (e) {
      out().className = 'error';
      out().textContent = e.message;
    }
  };
  const readForm = () => {
    const num = sel => { const v = el.querySelector(sel); return v && v.value !== '' ? Number(v.value) : undefined; };
    const sessions = num('#rx-sessions');
    if (sessions === undefined) delete model.sessions_per_week; else model.sessions_per_week = sessions;
    if (adapt) readDifficulty(el, model, adapt, num);
    model.exercise.forEach((e, i) => {
      const k = kindOf(e);
      for (const [name] of k ? k.fields : []) {
        const v = num(`#ex${i}-${name}`);
        if (v === undefined) delete e[name]; else e[name] = v;
      }
      const ceiling = num(`#ex${i}-ceiling`);
      if (ceiling === undefined) { if (e.haptic) delete e.haptic.ceiling_nm; } else { e.haptic = { ...(e.haptic || {}), ceiling_nm: ceiling }; }
      if (e.haptic && !Object.keys(e.haptic).length) delete e.haptic;
      readAssist(el, i, e, num);
      const pedals = el.querySelector(`#ex${i}-pedals`);
      if (pedals && pedals.checked) e.pedals = true; else delete e.pedals;
    });
  };
  const bind = () => {
    el.querySelector('#rx-form').addEventListener('submit', ev => {
      ev.preventDefault();
      const form = ev.target;
      if (!form.checkValidity()) { form.reportValidity(); out().className = 'error'; out().textContent = 'A value is outside its bounds (shown beside it).'; return; }
      readForm();
      save({ fields: model }, el.querySelector('#rx-note').value);
    });
    el.querySelector('#rx-add-btn').addEventListener('click', () => {
      readForm();
      model.exercise.push({ kind: el.querySelector('#rx-add').value });
      render();
    });
    el.querySelectorAll('[data-assist]').forEach(s => s.addEventListener('change', () => { readForm(); render(); }));
    el.querySelectorAll('[data-remove]').forEach(b => b.addEventListener('click', () => {
      readForm();
      model.exercise.splice(Number(b.dataset.remove), 1);
      render();
    }));
    el.querySelector('#rx').addEventListener('submit', ev => {
      ev.preventDefault();
      save({ toml: el.querySelector('#toml').value });
    });
  };
  render();
}

document.getElementById('change-password').addEventListener('click', () => {
  location.hash = '#/password';
});
document.getElementById('logout').addEventListener('click', async () => {
  try { await api('POST', '/api/logout'); } catch { /* logged out either way */ }
  me = null;
  location.hash = '#/patients';
  loginView();
});
window.addEventListener('hashchange', route);
route();
