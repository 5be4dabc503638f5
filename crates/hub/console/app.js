// The therapist console: login, the caseload, and a patient's live view, progress and
// prescription. A hash router over the console API; no inline script or style (the hub's
// Content-Security-Policy forbids them), every value put into HTML escaped.
import { api, ApiError, esc, when } from '/console/api.js';
import { liveView } from '/console/live.js';
import { replayView } from '/console/replay.js';
import { replayList } from '/console/replays.js';
import { progressView } from '/console/progress.js';
import { exercisesView } from '/console/exercises.js';
import { difficultyFields, exerciseKinds, regimenLimits, regimenSchema } from '/console/schema.js';
import { messagesPanel, messageProblem, sendMessage } from '/console/messages.js';
import { clinicView } from '/console/clinic.js';
import { notesSection } from '/console/notes.js';
import { assistModes, assistFields, readAssist } from '/console/assist.js';
import { wheelBounds } from '/console/wheel.js';
import { caseloadView, settingsView } from '/console/caseload.js';

const app = document.getElementById('app');
let leave = () => {};
let me = null;

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
  if (hash === '#/attention-settings') return settingsView(app, me).catch(fail).then(() => app.focus());
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
      <label for="new-password">New password <span class="note">(at least 10 characters, not only spaces, not your e-mail, not a common password or pattern; a few unrelated words are best)</span></label>
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

/** The caseload, sorted by need (caseload.js); `#/patients?sort=…&alert=…&mine=true`. */
async function patientsView() {
  await caseloadView(app, me, new URLSearchParams((location.hash.split('?')[1]) || ''));
}

async function patientView(id, tab, sessionId) {
  const p = await api('GET', `/api/patients/${encodeURIComponent(id)}`);
  const link = (t, label) => `<a href="#/patients/${encodeURIComponent(id)}/${t}"${t === tab ? ' aria-current="page"' : ''}>${label}</a>`;
  app.innerHTML = `<h1>Patient ${esc(p.pseudonym)}</h1>
    <nav class="tabs" aria-label="Patient">${link('live', 'Live')}${link('progress', 'Progress')}${link('replay', 'Replay')}${link('prescribe', 'Prescribe')}<a href="#/clinic/patients/${encodeURIComponent(id)}">Stations and pairing</a></nav>
    <div id="tab"></div>
    <section id="messages"></section>`;
  const el = app.querySelector('#tab');
  const refreshMessages = await messagesPanel(app.querySelector('#messages'), id);
  if (tab === 'live') { el.id = 'live'; leave = liveView(el, id); }
  else if (tab === 'progress') leave = await progressView(el, id);
  else if (tab === 'replay') leave = sessionId ? await replayView(el, sessionId) : (await replayList(el, id), () => {});
  else if (tab === 'exercises') { await exercisesView(el, id, sessionId); await notesSection(el, sessionId); }
  else await prescribeView(el, id, refreshMessages);
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
/** An exercise kind's name for a therapist: the words before the colon of its schema
 * description ("Sine road: …"), else the kind itself. */
const kindName = k => (k && k.description.includes(':') ? k.description.split(':')[0] : (k ? k.kind : ''));

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
      <fieldset class="panel"><legend>Exercise ${i + 1}: ${esc(kindName(kindOf(e)) || e.kind)}</legend>
        ${fields}
        ${numberField(`ex${i}-ceiling`, 'Torque ceiling, N·m (empty: the station\'s)', e.haptic && e.haptic.ceiling_nm, wheel.torque({ ...limits.ceiling, default: undefined }))}
        ${['dial', 'strength', 'haptic-sweep'].includes(e.kind) ? '' : `<p><input type="checkbox" id="ex${i}-pedals"${e.pedals ? ' checked' : ''}>
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
        <select id="rx-add">${kinds.map(k => `<option value="${esc(k.kind)}" title="${esc(k.description)}">${esc(kindName(k))}</option>`).join('')}</select>
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
        <dt>Session</dt><dd>at most ${esc(limits.maxExercises)} exercises planned to last at most ${esc(Math.round(limits.maxPlannedS / 60))} min together, rests and the cards between exercises included</dd>
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
