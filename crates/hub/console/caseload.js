// Needs attention today (issue 41): the caseload sorted by need, each patient with ONE plain
// reason first (the most pressing) and the rest behind "N more"; each alert can be
// acknowledged (quiet until something new happens) or snoozed until a day, with a note; a pain
// stop can be lifted for today; the clinic's alert thresholds (#/attention-settings, admins
// change them). The hub computes the alerts (crates/hub-care/src/attention/) and sends each as a
// catalogue id with its arguments; every word is in the console's catalogues
// (crates/i18n/console/<lang>/{caseload,attention}.ftl).
import { api, esc } from '/console/api.js';
import { t, locale } from '/console/i18n.js';
import { kindWords, measureWords, whenWords, endKindWords, measureName, numberIn } from '/console/words.js';
import { displayName } from '/console/names.js';

/** Severity → its mark (not colour alone) and its class; its word is `attention-severity-…`. */
export const SEVERITY = {
  urgent: { mark: '‼', cls: 'sev-urgent' },
  warning: { mark: '▲', cls: 'sev-warning' },
  notice: { mark: '●', cls: 'sev-notice' },
};

/** The alert kinds, in the hub's order (`attention::KIND_ORDER`). */
export const ALERT_KINDS = ['pain_high', 'pain_rising', 'station_revoked', 'no_session', 'decline',
  'safety_stop', 'ended_early', 'effort', 'low_activity', 'wheel_unplugged', 'sensor_unplugged', 'wheel_unseen',
  'sensors_lost', 'station_silent', 'torque_at_ceiling'];

/** The three measures the Trend column shows. */
const TREND_MEASURES = ['pct_in_lane', 'wheel_rom_deg', 'sparc_median'];

const kebab = s => String(s).replace(/_/g, '-');
const capitalFirst = s => s.charAt(0).toLocaleUpperCase(locale()) + s.slice(1);

/** An alert kind's name (the filter's): "Pain", "Getting worse", … */
export function kindName(kind) {
  return t(`attention-kind-${kebab(kind)}`);
}

/** A severity's word: "Urgent", "Look today", "Note". */
export function severityWord(severity) {
  return t(`attention-severity-${severity in SEVERITY ? severity : 'notice'}`);
}

/** The arguments of an alert's message made ready for its sentence: the evidence's time as
 * a date, a decline's measure and exercise kind in words and its numbers in the measure's
 * decimals and unit, an end kind in the one end-reason wording. */
function messageArgs(args, words) {
  const out = { ...args };
  if (args.at_ms != null) out.at = whenWords(args.at_ms);
  if (args.measure) {
    const m = words && words.measures.get(args.measure);
    out.measure = measureName(args.measure);
    for (const k of ['latest', 'usual']) if (typeof args[k] === 'number') out[k] = numberIn(m, args[k], true);
  }
  if (args.exercise_kind) out.exercise_kind = kindWords(args.exercise_kind);
  if (args.end) out.end = endKindWords(args.end);
  return out;
}

/** An alert in words, in the language in force (the hub's English sentence only for an
 * alert that came without a message id). */
export function alertWords(a, words) {
  if (a.message && a.message.id) return t(a.message.id, messageArgs(a.message.args || {}, words));
  return a.text || '';
}

/** The clinic's thresholds: each key's label and why-the-default are
 * `attention-setting-<key>` and its `.why` attribute. */
const settingLabel = key => t(`attention-setting-${kebab(key)}`);
const settingWhy = key => t(`attention-setting-${kebab(key)}.why`);

/** The caseload (#/patients). */
export async function caseloadView(app, me, params = new URLSearchParams()) {
  const sort = params.get('sort') || 'need';
  const kind = params.get('alert') || '';
  const mine = params.get('mine') === 'true';
  const q = new URLSearchParams({ sort });
  if (kind) q.set('alert', kind);
  if (mine) q.set('mine', 'true');
  const [patients, words] = await Promise.all([api('GET', `/api/patients?${q}`), measureWords().catch(() => null)]);
  const option = (v, label, cur) => `<option value="${esc(v)}"${v === cur ? ' selected' : ''}>${esc(label)}</option>`;
  app.innerHTML = `<h1>${esc(t('caseload-title'))}</h1>
    <form id="caseload-controls" class="caseload-controls">
      <label for="cl-sort">${esc(t('caseload-order'))}</label>
      <select id="cl-sort">${option('need', t('caseload-order-need'), sort)}${option('last_session', t('caseload-order-last-session'), sort)}${option('pseudonym', t('caseload-order-pseudonym'), sort)}</select>
      <label for="cl-alert">${esc(t('caseload-show'))}</label>
      <select id="cl-alert">${option('', t('caseload-show-all'), kind)}${ALERT_KINDS.map(k => option(k, t('caseload-show-only', { kind: kindName(k) }), kind)).join('')}</select>
      ${me.role === 'admin' ? `<label class="inline"><input type="checkbox" id="cl-mine"${mine ? ' checked' : ''}> ${esc(t('caseload-mine'))}</label>` : ''}
    </form>
    <table id="caseload"><caption class="note">${esc(t(sort === 'need' ? 'caseload-caption-need' : 'caseload-caption-chosen'))}</caption>
    <thead><tr><th scope="col">${esc(t('caseload-col-patient'))}</th><th scope="col">${esc(t('caseload-col-needs'))}</th><th scope="col">${esc(t('caseload-col-last-session'))}</th><th scope="col">${esc(t('caseload-col-last-7-days'))}</th><th scope="col">${esc(t('caseload-col-trend'))}</th></tr></thead>
    <tbody>${patients.map(p => rowHtml(p, words)).join('') || `<tr><td colspan="5">${esc(t(kind ? 'caseload-none-with-alert' : 'caseload-none'))}</td></tr>`}</tbody></table>
    <p><a href="#/clinic">${esc(t('caseload-add-patient'))}</a> ${esc(t('caseload-add-patient-note'))} · <a href="#/attention-settings">${esc(t('caseload-thresholds-link'))}</a></p>`;
  const go = () => {
    const next = new URLSearchParams({ sort: app.querySelector('#cl-sort').value });
    const k = app.querySelector('#cl-alert').value;
    if (k) next.set('alert', k);
    const m = app.querySelector('#cl-mine');
    if (m && m.checked) next.set('mine', 'true');
    location.hash = `#/patients?${next}`;
  };
  const reload = () => caseloadView(app, me, params);
  app.querySelectorAll('#caseload-controls select, #cl-mine').forEach(el => el.addEventListener('change', go));
  app.querySelectorAll('[data-ack]').forEach(b => b.addEventListener('click', () => openAck(app, b, patients, words, reload)));
  app.querySelectorAll('[data-allow-training]').forEach(b => b.addEventListener('click', () => openAllow(app, b, patients, reload)));
}

/** The Trend column: every exercise kind's trends (the kind trained last first), so that a
 * decline in any kind stays visible. */
function trendHtml(p) {
  const kinds = p.trends_by_kind || (p.trend_exercise_kind ? [{ exercise_kind: p.trend_exercise_kind, trends: p.trends }] : []);
  const blocks = kinds.map(k => {
    const lines = TREND_MEASURES.filter(m => k.trends[m]).map(m => {
      const dir = k.trends[m];
      const [arrow, cls, word] = dir === 'up' ? ['↑', 'up', 'caseload-trend-better'] : dir === 'down' ? ['↓', 'down', 'caseload-trend-worse'] : ['→', '', 'caseload-trend-steady'];
      return `<span class="${cls}" data-trend="${esc(m)}" data-direction="${esc(dir)}">${esc(t(`caseload-trend-${kebab(m)}`))} ${arrow} ${esc(t(word))}</span>`;
    });
    if (!lines.length) return '';
    return `<div class="trend-kind" data-exercise-kind="${esc(k.exercise_kind)}"><span class="note">${esc(capitalFirst(t('caseload-trend-kind', { kind: kindWords(k.exercise_kind) })))}</span><br>${lines.join('<br>')}</div>`;
  }).filter(Boolean);
  return blocks.join('') || '—';
}

/** One caseload row. */
function rowHtml(p, words) {
  const alerts = p.attention || [];
  const [first, ...rest] = alerts;
  const need = first
    ? `${alertHtml(p, first, 'reason-first', words)}${rest.length ? `<details class="more-reasons"><summary>${esc(t('caseload-more', { count: rest.length }))}</summary><ul class="reasons">${rest.map(a => `<li>${alertHtml(p, a, 'reason', words)}</li>`).join('')}</ul></details>` : ''}`
    : `<span class="badge ok">${esc(t('caseload-nothing-needed'))}</span>`;
  const quiet = (p.quieted || []).length
    ? `<details class="quieted"><summary>${esc(t('caseload-acknowledged', { count: p.quieted.length }))}</summary><ul class="reasons">${p.quieted.map(a => `<li data-kind="${esc(a.kind)}">${esc(alertWords(a, words))} — ${esc(quietWords(a.quieted))}</li>`).join('')}</ul></details>`
    : '';
  const week = t('caseload-week', {
    sessions: p.sessions_last_7_days,
    sessionsPrescribed: p.sessions_per_week_prescribed ?? 'none',
    minutes: Math.round(p.active_minutes_last_7_days),
    minutesPrescribed: p.minutes_per_week_prescribed == null ? 'none' : Math.round(p.minutes_per_week_prescribed),
  });
  // The dose's count beside its time (hubs older than it send none).
  const repetitions = typeof p.repetitions_last_7_days === 'number' ? p.repetitions_last_7_days : null;
  const repetitionWords = repetitions == null ? '' : `<br><span class="repetitions">${esc(t('caseload-repetitions', { repetitions }))}</span>`;
  return `<tr data-pseudonym="${esc(p.pseudonym)}" data-severity="${esc(first ? first.severity : 'none')}" data-alert-kinds="${esc(alerts.map(a => a.kind).join(' '))}">
    <td><a href="#/patients/${encodeURIComponent(p.id)}">${esc(displayName(p.pseudonym))}</a></td>
    <td class="needs">${need}${quiet}</td>
    <td>${esc(whenWords(p.last_session_started_ms))}</td><td class="week" data-sessions="${esc(p.sessions_last_7_days)}" data-sessions-prescribed="${esc(p.sessions_per_week_prescribed ?? '')}" data-minutes-prescribed="${esc(p.minutes_per_week_prescribed ?? '')}" data-repetitions="${esc(repetitions ?? '')}">${esc(week)}${repetitionWords}</td><td>${trendHtml(p)}</td></tr>`;
}

/** An alert with its severity word and mark, its "Acknowledge" button, and on a pain alert
 * "Allow training today" (or when training was allowed after it). */
function alertHtml(p, a, cls, words) {
  const s = SEVERITY[a.severity] || SEVERITY.notice;
  const who = `<span class="visually-hidden"> (${esc(displayName(p.pseudonym))})</span>`;
  let allow = '';
  if (a.kind === 'pain_high') {
    const cleared = p.pain_cleared_at_ms != null && (a.at_ms == null || p.pain_cleared_at_ms >= a.at_ms);
    allow = cleared
      ? `<span class="note pain-cleared" data-pain-cleared>${esc(t('caseload-training-allowed', { at: whenWords(p.pain_cleared_at_ms) }))}</span>`
      : ` <button type="button" class="small" data-allow-training data-patient="${esc(p.id)}">${esc(t('caseload-allow-training'))}${who}</button>`;
  }
  return `<div class="${cls} alert-line ${s.cls}" data-kind="${esc(a.kind)}" data-severity="${esc(a.severity)}"${a.message ? ` data-l10n-message="${esc(a.message.id)}"` : ''}>
    <span class="sev"><span aria-hidden="true">${s.mark}</span> ${esc(t('attention-severity-label', { severity: severityWord(a.severity) }))}</span> ${esc(alertWords(a, words))}
    <button type="button" class="secondary small" data-ack data-patient="${esc(p.id)}" data-key="${esc(a.key)}">${esc(t('caseload-acknowledge'))}${who}</button>${allow}</div>`;
}

/** Who acknowledged or snoozed an alert, when, until when, and their note. */
function quietWords(q) {
  if (!q) return '';
  const who = q.by_email || t('caseload-quiet-former');
  return q.until_ms
    ? t('caseload-quiet-snoozed', { until: whenWords(q.until_ms), who, at: whenWords(q.at_ms), note: q.note })
    : t('caseload-quiet-acknowledged', { who, at: whenWords(q.at_ms), note: q.note });
}

/** The acknowledge / snooze form under the alert of button `b`. */
function openAck(app, b, patients, words, reload) {
  app.querySelectorAll('.ack-form').forEach(f => f.remove());
  const p = patients.find(x => x.id === b.dataset.patient);
  const a = p && p.attention.find(x => x.key === b.dataset.key);
  if (!a) return;
  const form = document.createElement('form');
  form.className = 'ack-form panel';
  form.noValidate = true;
  const tomorrow = new Date(Date.now() + 86400000).toISOString().slice(0, 10);
  form.innerHTML = `<p><strong>${esc(displayName(p.pseudonym))}:</strong> ${esc(alertWords(a, words))}</p>
    <fieldset><legend>${esc(t('caseload-ack-legend'))}</legend>
      <label class="inline"><input type="radio" name="ack-how" value="ack" checked> ${esc(t('caseload-ack-until-new'))}</label>
      <label class="inline"><input type="radio" name="ack-how" value="snooze"> ${esc(t('caseload-ack-until-day'))}</label>
      <label for="ack-until" class="visually-hidden">${esc(t('caseload-ack-snooze-until'))}</label><input type="date" id="ack-until" min="${tomorrow}" value="${tomorrow}">
    </fieldset>
    <label for="ack-note">${esc(t('caseload-ack-note'))} <span class="note">${esc(t('caseload-ack-note-hint'))}</span></label>
    <textarea id="ack-note" rows="2" maxlength="2000"></textarea>
    <p><button type="submit">${esc(t('caseload-save'))}</button> <button type="button" class="secondary" id="ack-cancel">${esc(t('caseload-cancel'))}</button></p>
    <p class="error" id="ack-error" role="alert"></p>`;
  b.closest('td').appendChild(form);
  form.querySelector('#ack-note').focus();
  form.querySelector('#ack-cancel').addEventListener('click', () => form.remove());
  form.addEventListener('submit', async ev => {
    ev.preventDefault();
    const body = { key: a.key, fingerprint: a.fingerprint, note: form.querySelector('#ack-note').value };
    if (form.querySelector('input[name=ack-how]:checked').value === 'snooze') {
      const day = form.querySelector('#ack-until').value;
      if (!day) { form.querySelector('#ack-error').textContent = t('caseload-ack-no-day'); return; }
      body.snooze_until_ms = new Date(`${day}T00:00`).getTime();
    }
    try {
      await api('POST', `/api/patients/${encodeURIComponent(p.id)}/alerts/ack`, body);
      await reload();
    } catch (e) { form.querySelector('#ack-error').textContent = e.message; }
  });
}

/** "Allow training today" after a pain stop: a confirmation saying what it does, then
 * POST /api/patients/{id}/pain-clearance, and the result in words. */
function openAllow(app, b, patients, reload) {
  app.querySelectorAll('.ack-form').forEach(f => f.remove());
  const p = patients.find(x => x.id === b.dataset.patient);
  if (!p) return;
  const form = document.createElement('form');
  form.className = 'ack-form panel allow-form';
  form.noValidate = true;
  form.innerHTML = `<p id="allow-question"><strong>${esc(displayName(p.pseudonym))}:</strong> ${esc(t('caseload-allow-question'))}</p>
    <p class="note">${esc(t('caseload-allow-explain'))}</p>
    <p><button type="submit" data-allow-confirm>${esc(t('caseload-allow-confirm'))}</button> <button type="button" class="secondary" id="allow-cancel">${esc(t('caseload-cancel'))}</button></p>
    <p id="allow-result" role="alert"></p>`;
  b.closest('td').appendChild(form);
  form.querySelector('[data-allow-confirm]').focus();
  form.querySelector('#allow-cancel').addEventListener('click', () => form.remove());
  form.addEventListener('submit', async ev => {
    ev.preventDefault();
    const out = form.querySelector('#allow-result');
    try {
      const r = await api('POST', `/api/patients/${encodeURIComponent(p.id)}/pain-clearance`, {});
      await reload();
      const row = app.querySelector(`tr[data-pseudonym="${CSS.escape(p.pseudonym)}"] td.needs`);
      if (row) {
        const done = document.createElement('p');
        done.id = 'allow-done';
        done.setAttribute('role', 'status');
        done.dataset.clearedAtMs = String(r.cleared_at_ms);
        done.textContent = t('caseload-allow-done', { at: whenWords(r.cleared_at_ms) });
        row.appendChild(done);
      }
    } catch (e) { out.className = 'error'; out.textContent = e.message; }
  });
}

/** The clinic's alert thresholds (#/attention-settings): everyone sees them and why; an
 * administrator changes them. */
export async function settingsView(app, me) {
  const settings = await api('GET', '/api/clinic/settings');
  const admin = me.role === 'admin';
  const rows = settings.map(s => {
    const changed = s.updated_at_ms
      ? t('attention-setting-changed', { who: s.updated_by_email || t('caseload-quiet-former'), at: whenWords(s.updated_at_ms) })
      : t('attention-setting-default');
    return `<div class="setting" data-key="${esc(s.key)}">
      <label for="set-${esc(s.key)}">${esc(settingLabel(s.key))} <span class="note">${esc(t('attention-setting-range', { min: s.min, max: s.max, default: s.default }))}</span></label>
      <input id="set-${esc(s.key)}" type="number" min="${esc(s.min)}" max="${esc(s.max)}" step="1" value="${esc(s.value)}"${admin ? '' : ' readonly'} data-setting="${esc(s.key)}">
      <p class="note">${esc(settingWhy(s.key))} ${esc(changed)}</p></div>`;
  }).join('');
  app.innerHTML = `<h1>${esc(t('attention-settings-title'))}</h1>
    <p>${esc(t('attention-settings-intro'))} ${esc(t(admin ? 'attention-settings-admin' : 'attention-settings-not-admin'))}</p>
    <form id="settings-form" class="panel" novalidate>${rows}
      ${admin ? `<p><button type="submit">${esc(t('attention-settings-save'))}</button></p>` : ''}
      <p id="settings-result" role="alert"></p></form>
    <p><a href="#/patients">${esc(t('app-back-to-patients'))}</a></p>`;
  if (!admin) return;
  const form = app.querySelector('#settings-form');
  form.addEventListener('submit', async ev => {
    ev.preventDefault();
    const out = app.querySelector('#settings-result');
    if (!form.checkValidity()) { out.className = 'error'; out.textContent = t('attention-settings-out-of-range'); return; }
    const body = {};
    form.querySelectorAll('[data-setting]').forEach(i => {
      const s = settings.find(x => x.key === i.dataset.setting);
      if (Number(i.value) !== s.value) body[s.key] = Number(i.value);
    });
    try {
      await api('PUT', '/api/clinic/settings', body);
      await settingsView(app, me);
      const done = app.querySelector('#settings-result');
      done.dataset.saved = 'true';
      done.textContent = t('attention-settings-saved');
    } catch (e) { out.className = 'error'; out.textContent = e.message; }
  });
}
