// Needs attention today (issue 41): the caseload sorted by need, each patient with ONE plain
// reason first (the most pressing) and the rest behind "N more"; each alert can be
// acknowledged (quiet until something new happens) or snoozed until a day, with a note; the
// clinic's alert thresholds (#/attention-settings, admins change them). The hub computes the
// alerts (crates/hub/src/attention/); every word a clinician reads is in the tables below.
import { api, esc, when } from '/console/api.js';
import { kindWords } from '/console/words.js';
import { displayName } from '/console/names.js';

/** Severity → its word, its mark (not colour alone) and its class. */
export const SEVERITY = {
  urgent: { word: 'Urgent', mark: '‼', cls: 'sev-urgent' },
  warning: { word: 'Look today', mark: '▲', cls: 'sev-warning' },
  notice: { word: 'Note', mark: '●', cls: 'sev-notice' },
};

/** The three measures a decline is told of, with their unit and rounding. */
const MEASURES = {
  pct_in_lane: { word: 'time in lane', unit: ' %', digits: 0 },
  wheel_rom_deg: { word: 'wheel range', unit: '°', digits: 0 },
  sparc_median: { word: 'smoothness', unit: '', digits: 2 },
};

const plural = (n, one, many) => `${n} ${n === 1 ? one : many}`;
const measure = (m, v) => { const d = MEASURES[m] || { unit: '', digits: 1 }; return `${Number(v).toFixed(d.digits)}${d.unit}`; };

/** Each alert kind in words: its name (the filter's) and its sentence from the hub's facts. */
export const ALERT_WORDS = {
  pain_high: ['Pain', (a, f) => `Pain ${f.pain_0_10}/10 after the session of ${when(a.at_ms)}`
    + (f.sessions_since === 1 ? ' (no pain answer after the next session)'
      : f.sessions_since ? ` (no pain answer in the ${f.sessions_since} sessions since)` : '')],
  pain_rising: ['Rising pain', (a, f) => `Pain rising: ${f.first_0_10}, then ${f.middle_0_10}, then ${f.pain_0_10}/10 after the session of ${when(a.at_ms)}`],
  station_revoked: ['Station withdrawn', a => `Station withdrawn on ${when(a.at_ms)}: the patient cannot train until a new one is paired`],
  no_session: ['No session', (a, f) => (a.fingerprint === 'none' ? `No session yet (added ${when(a.at_ms)})`
    : `No session for ${f.days} days (the last: ${when(a.at_ms)})`)],
  decline: ['Getting worse', (a, f) => `${cap(MEASURES[a.measure]?.word || 'a measure')} worse in ${kindWords(a.exercise_kind)} sessions: ${measure(a.measure, f.latest)} against ${measure(a.measure, f.usual)} before (${f.worse_percent} % worse)`],
  safety_stop: ['Safety stop', a => `Safety stop in the session of ${when(a.at_ms)}`],
  ended_early: ['Ended early', (a, f) => `${f.ended_early} of the last ${f.sessions} sessions ended early`],
  effort: ['Too tiring', (a, f) => (f.tiredness_0_10 !== undefined ? `Tiredness ${f.tiredness_0_10}/10 after the session of ${when(a.at_ms)}`
    : `"Too hard" after the last ${f.too_hard_sessions} sessions`)],
  low_activity: ['Little training', (a, f) => (f.sessions_prescribed !== undefined ? `${f.sessions} of ${f.sessions_prescribed} prescribed sessions this week`
    : f.minutes_prescribed !== undefined ? `${f.active_minutes} of ${f.minutes_prescribed} prescribed active minutes this week`
      : `${plural(f.active_minutes, 'active minute', 'active minutes')} this week; nothing prescribed yet (the clinic looks for at least ${f.minimum_minutes})`)],
  wheel_unplugged: ['Wheel unplugged', a => `The session of ${when(a.at_ms)} stopped: wheel unplugged`],
  wheel_unseen: ['Wheel not seen', (a, f) => `Wheel not seen for ${f.days} days while the station was on`],
  sensors_lost: ['Arm sensors lost', (a, f) => `Arm sensors lost in the last ${plural(f.sessions, 'session', 'sessions')}`],
  station_silent: ['Station silent', (a, f) => `Station not heard from for ${f.days} days (the last: ${when(a.at_ms)})`],
  torque_at_ceiling: ['Torque at its limit', a => `Torque held at its limit for 5 % or more of the session of ${when(a.at_ms)}`],
};

const cap = s => s.charAt(0).toUpperCase() + s.slice(1);

/** An alert in words (the hub's own sentence for a kind this console does not know). */
export function alertWords(a) {
  const w = ALERT_WORDS[a.kind];
  return w ? w[1](a, a.facts || {}) : cap(a.text);
}

/** The clinic's thresholds in words: label (with unit) and why the default. */
export const SETTING_WORDS = {
  pain_threshold_0_10: ['Pain that is urgent, 0–10 (at or over)', 'Pain of 7 or more on the 0–10 scale is severe pain; a patient who reports it should not train on without the clinic.'],
  pain_rise_points: ['Rising pain: points over three check-ins', 'Two points is about the smallest change in pain a patient feels as real.'],
  no_session_days: ['Days without a session', 'Three days without training breaks the rhythm of a home programme; a prescription of fewer sessions a week waits its own gap (7 days for once a week).'],
  min_active_minutes_week: ['Active minutes a week when nothing is prescribed (at least)', 'Half an hour a week is far below what patients manage at home (about 2 hours a week on average); less means the station is hardly used.'],
  decline_percent: ['Getting worse: percent below the earlier sessions of the same kind', 'Movement measures vary by up to about 10 % from session to session; 15 % is beyond that noise.'],
  ended_early_sessions: ['Sessions ended early, of the last 5', 'Once can be a phone call; twice in five sessions is a pattern worth a question.'],
  effort_threshold_0_10: ['Tiredness that needs a look, 0–10 (at or over)', 'Home programmes lose patients whose training feels hard; 7 of 10 is well past "hard".'],
  devices_unseen_days: ['Days the station is on without its wheel', 'A wheel missing for three days usually means a cable or a power supply, not a choice.'],
  station_silent_days: ['Days a station may stay silent', 'A station that trains connects at every session; three silent days mean it is off, unplugged or offline.'],
};

/** The caseload (#/patients). */
export async function caseloadView(app, me, params = new URLSearchParams()) {
  const sort = params.get('sort') || 'need';
  const kind = params.get('alert') || '';
  const mine = params.get('mine') === 'true';
  const q = new URLSearchParams({ sort });
  if (kind) q.set('alert', kind);
  if (mine) q.set('mine', 'true');
  const patients = await api('GET', `/api/patients?${q}`);
  const option = (v, label, cur) => `<option value="${esc(v)}"${v === cur ? ' selected' : ''}>${esc(label)}</option>`;
  app.innerHTML = `<h1>Patients</h1>
    <form id="caseload-controls" class="caseload-controls">
      <label for="cl-sort">Order</label>
      <select id="cl-sort">${option('need', 'Who needs attention first', sort)}${option('last_session', 'Longest without a session first', sort)}${option('pseudonym', 'By pseudonym', sort)}</select>
      <label for="cl-alert">Show</label>
      <select id="cl-alert">${option('', 'Every patient', kind)}${Object.entries(ALERT_WORDS).map(([k, [name]]) => option(k, `Only: ${name}`, kind)).join('')}</select>
      ${me.role === 'admin' ? `<label class="inline"><input type="checkbox" id="cl-mine"${mine ? ' checked' : ''}> Only my own patients</label>` : ''}
    </form>
    <table id="caseload"><caption class="note">Your caseload, ${sort === 'need' ? 'who needs attention first' : 'in the order chosen'}. Open a patient to watch a running session, see progress or prescribe.</caption>
    <thead><tr><th scope="col">Patient</th><th scope="col">Needs attention</th><th scope="col">Last session</th><th scope="col">Last 7 days</th><th scope="col">Trend (last session)</th></tr></thead>
    <tbody>${patients.map(rowHtml).join('') || `<tr><td colspan="5">${kind ? 'No patient has this alert now.' : 'No patients yet.'}</td></tr>`}</tbody></table>
    <p><a href="#/clinic">Add a patient</a> (and print the pairing sheet) · <a href="#/attention-settings">Alert thresholds</a></p>`;
  const go = () => {
    const next = new URLSearchParams({ sort: app.querySelector('#cl-sort').value });
    const k = app.querySelector('#cl-alert').value;
    if (k) next.set('alert', k);
    const m = app.querySelector('#cl-mine');
    if (m && m.checked) next.set('mine', 'true');
    location.hash = `#/patients?${next}`;
  };
  app.querySelectorAll('#caseload-controls select, #cl-mine').forEach(el => el.addEventListener('change', go));
  app.querySelectorAll('[data-ack]').forEach(b => b.addEventListener('click', () => openAck(app, b, patients, () => caseloadView(app, me, params))));
}

/** One caseload row. */
function rowHtml(p) {
  const alerts = p.attention || [];
  const [first, ...rest] = alerts;
  const need = first
    ? `${alertHtml(p, first, 'reason-first')}${rest.length ? `<details class="more-reasons"><summary>${esc(plural(rest.length, 'more', 'more'))}</summary><ul class="reasons">${rest.map(a => `<li>${alertHtml(p, a, 'reason')}</li>`).join('')}</ul></details>` : ''}`
    : '<span class="badge ok">Nothing needs attention</span>';
  const quiet = (p.quieted || []).length
    ? `<details class="quieted"><summary>${esc(plural(p.quieted.length, 'alert acknowledged', 'alerts acknowledged'))}</summary><ul class="reasons">${p.quieted.map(a => `<li data-kind="${esc(a.kind)}">${esc(alertWords(a))} — ${esc(quietWords(a.quieted))}</li>`).join('')}</ul></details>`
    : '';
  const sessions = p.sessions_per_week_prescribed == null ? plural(p.sessions_last_7_days, 'session', 'sessions')
    : `${p.sessions_last_7_days} of ${p.sessions_per_week_prescribed} prescribed sessions`;
  const minutes = p.minutes_per_week_prescribed == null ? `${Math.round(p.active_minutes_last_7_days)} active min`
    : `${Math.round(p.active_minutes_last_7_days)} of ${Math.round(p.minutes_per_week_prescribed)} prescribed active min`;
  const trends = [['pct_in_lane', 'time in lane'], ['wheel_rom_deg', 'wheel range'], ['sparc_median', 'smoothness']]
    .filter(([k]) => p.trends[k])
    .map(([k, label]) => {
      const t = p.trends[k];
      const [arrow, cls, word] = t === 'up' ? ['↑', 'up', 'better'] : t === 'down' ? ['↓', 'down', 'worse'] : ['→', '', 'steady'];
      return `<span class="${cls}">${esc(label)} ${arrow} ${word}</span>`;
    }).join('<br>') || '—';
  const trendsOf = p.trend_exercise_kind && trends !== '—' ? `<span class="note">${esc(kindWords(p.trend_exercise_kind))} sessions:</span><br>${trends}` : trends;
  return `<tr data-pseudonym="${esc(p.pseudonym)}" data-severity="${esc(first ? first.severity : 'none')}" data-alert-kinds="${esc(alerts.map(a => a.kind).join(' '))}">
    <td><a href="#/patients/${encodeURIComponent(p.id)}">${esc(displayName(p.pseudonym))}</a></td>
    <td class="needs">${need}${quiet}</td>
    <td>${esc(when(p.last_session_started_ms))}</td><td>${esc(`${sessions}, ${minutes}`)}</td><td>${trendsOf}</td></tr>`;
}

/** An alert with its severity word and mark, and its "Acknowledge" button. */
function alertHtml(p, a, cls) {
  const s = SEVERITY[a.severity] || SEVERITY.notice;
  return `<div class="${cls} alert-line ${s.cls}" data-kind="${esc(a.kind)}" data-severity="${esc(a.severity)}">
    <span class="sev"><span aria-hidden="true">${s.mark}</span> ${esc(s.word)}:</span> ${esc(alertWords(a))}
    <button type="button" class="secondary small" data-ack data-patient="${esc(p.id)}" data-key="${esc(a.key)}">Acknowledge<span class="visually-hidden"> (${esc(displayName(p.pseudonym))})</span></button></div>`;
}

/** Who acknowledged or snoozed an alert, when, until when, and their note. */
function quietWords(q) {
  if (!q) return '';
  const who = q.by_email || 'a therapist no longer at the clinic';
  const until = q.until_ms ? `snoozed until ${when(q.until_ms)}` : 'acknowledged (quiet until something new)';
  return `${until} by ${who} on ${when(q.at_ms)}: ${q.note}`;
}

/** The acknowledge / snooze form under the alert of button `b`. */
function openAck(app, b, patients, reload) {
  app.querySelectorAll('.ack-form').forEach(f => f.remove());
  const p = patients.find(x => x.id === b.dataset.patient);
  const a = p && p.attention.find(x => x.key === b.dataset.key);
  if (!a) return;
  const form = document.createElement('form');
  form.className = 'ack-form panel';
  form.noValidate = true;
  const tomorrow = new Date(Date.now() + 86400000).toISOString().slice(0, 10);
  form.innerHTML = `<p><strong>${esc(displayName(p.pseudonym))}:</strong> ${esc(alertWords(a))}</p>
    <fieldset><legend>Keep it quiet</legend>
      <label class="inline"><input type="radio" name="ack-how" value="ack" checked> Until something new happens</label>
      <label class="inline"><input type="radio" name="ack-how" value="snooze"> Until a day:</label>
      <label for="ack-until" class="visually-hidden">Snooze until</label><input type="date" id="ack-until" min="${tomorrow}" value="${tomorrow}">
    </fieldset>
    <label for="ack-note">Note <span class="note">(what was done, e.g. "Called: resting, sees the GP Monday")</span></label>
    <textarea id="ack-note" rows="2" maxlength="2000"></textarea>
    <p><button type="submit">Save</button> <button type="button" class="secondary" id="ack-cancel">Cancel</button></p>
    <p class="error" id="ack-error" role="alert"></p>`;
  b.closest('td').appendChild(form);
  form.querySelector('#ack-note').focus();
  form.querySelector('#ack-cancel').addEventListener('click', () => form.remove());
  form.addEventListener('submit', async ev => {
    ev.preventDefault();
    const body = { key: a.key, fingerprint: a.fingerprint, note: form.querySelector('#ack-note').value };
    if (form.querySelector('input[name=ack-how]:checked').value === 'snooze') {
      const day = form.querySelector('#ack-until').value;
      if (!day) { form.querySelector('#ack-error').textContent = 'Choose the day the alert may come back.'; return; }
      body.snooze_until_ms = new Date(`${day}T00:00`).getTime();
    }
    try {
      await api('POST', `/api/patients/${encodeURIComponent(p.id)}/alerts/ack`, body);
      await reload();
    } catch (e) { form.querySelector('#ack-error').textContent = e.message; }
  });
}

/** The clinic's alert thresholds (#/attention-settings): everyone sees them and why; an
 * administrator changes them. */
export async function settingsView(app, me) {
  const settings = await api('GET', '/api/clinic/settings');
  const admin = me.role === 'admin';
  const rows = settings.map(s => {
    const [label, why] = SETTING_WORDS[s.key] || [s.key, ''];
    const changed = s.updated_at_ms ? `Changed by ${s.updated_by_email || 'a former colleague'} on ${when(s.updated_at_ms)}.` : 'Not changed by the clinic: the default.';
    return `<div class="setting" data-key="${esc(s.key)}">
      <label for="set-${esc(s.key)}">${esc(label)} <span class="note">(${esc(s.min)}–${esc(s.max)}; default ${esc(s.default)})</span></label>
      <input id="set-${esc(s.key)}" type="number" min="${esc(s.min)}" max="${esc(s.max)}" step="1" value="${esc(s.value)}"${admin ? '' : ' readonly'} data-setting="${esc(s.key)}">
      <p class="note">${esc(why)} ${esc(changed)}</p></div>`;
  }).join('');
  app.innerHTML = `<h1>Alert thresholds</h1>
    <p>When the caseload says a patient needs attention. ${admin ? 'Changes apply to every therapist of the clinic at once and are recorded in the audit log.' : 'An administrator can change them.'}</p>
    <form id="settings-form" class="panel" novalidate>${rows}
      ${admin ? '<p><button type="submit">Save the thresholds</button></p>' : ''}
      <p id="settings-result" role="alert"></p></form>
    <p><a href="#/patients">Back to the patients</a></p>`;
  if (!admin) return;
  const form = app.querySelector('#settings-form');
  form.addEventListener('submit', async ev => {
    ev.preventDefault();
    const out = app.querySelector('#settings-result');
    if (!form.checkValidity()) { out.className = 'error'; out.textContent = 'A value is outside its range (shown beside it).'; return; }
    const body = {};
    form.querySelectorAll('[data-setting]').forEach(i => {
      const s = settings.find(x => x.key === i.dataset.setting);
      if (Number(i.value) !== s.value) body[s.key] = Number(i.value);
    });
    try {
      await api('PUT', '/api/clinic/settings', body);
      await settingsView(app, me);
      app.querySelector('#settings-result').textContent = 'Saved.';
    } catch (e) { out.className = 'error'; out.textContent = e.message; }
  });
}
