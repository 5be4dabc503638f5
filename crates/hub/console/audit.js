// The audit page (#/audit, administrators only): who did what, when, in plain words, newest
// first, filtered by patient, therapist or kind, a page at a time (GET /api/audit). Patients
// are shown by the names this browser holds (names.js), therapists by e-mail, never by id.
import { api, ApiError, esc, when } from '/console/api.js';
import { displayName } from '/console/names.js';
import { t } from '/console/i18n.js';

const h = (id, args) => esc(t(id, args));

/** Entries on one page. */
const PAGE = 50;

/** Each kind of entry, in the order the filter offers them; its words are the catalogue's
 * `audit-kind-<kind>`. */
const KINDS = [
  'login', 'logout', 'login_failed', 'login_throttled', 'password_changed',
  'password_change_refused', 'list_patients', 'read_patient', 'show_patient', 'read_sessions',
  'read_session', 'read_summaries', 'read_metrics', 'read_exercises', 'read_replay', 'watch_live',
  'live_ended', 'read_checkins', 'read_difficulty', 'read_assessments', 'read_regimen', 'put_regimen',
  'regimen_rejected', 'read_messages', 'post_message', 'message_rejected', 'message_seen',
  'read_notes', 'post_note', 'note_rejected', 'read_scales', 'post_scale', 'delete_scale',
  'scale_rejected', 'export_measures_csv', 'export_caseload_csv', 'export_assessments_csv', 'export_fhir', 'export_patient',
  'add_patient', 'pairing_code', 'station_paired', 'pairing_failed', 'revoke_station',
  'station_refused', 'add_therapist', 'list_therapists', 'read_audit', 'refusals_suppressed',
  'hub_init', 'backup', 'change_language', 'read_attention', 'acknowledge_alert', 'snooze_alert', 'read_settings',
  'change_setting', 'pain_clearance', 'erase_patient', 'recording_uploaded',
];
const KNOWN = new Set(KINDS);

/** What an entry's action says. */
function what(action) {
  if (KNOWN.has(action)) return t(`audit-kind-${action}`);
  const refused = action.match(/^refused_(\d{3})$/);
  if (refused) return ['401', '403', '404', '429'].includes(refused[1]) ? t(`audit-refused-${refused[1]}`) : t('audit-refused');
  return action.replace(/_/g, ' ');
}

/** The audit page in `app` for `me`; a therapist who is not an administrator is told so. */
export async function auditView(app, me) {
  if (me.role !== 'admin') {
    app.innerHTML = `<h1>${h('audit-heading')}</h1><p id="audit-refused" class="error" role="alert">${h('audit-admins-only')}</p>`;
    return;
  }
  const [therapists, patients] = await Promise.all([api('GET', '/api/therapists'), api('GET', '/api/patients')]);
  const emails = new Map(therapists.map(th => [`therapist:${th.id}`, th.email]));
  const pseudonyms = new Map(patients.map(p => [p.id, p.pseudonym]));
  const who = actor => {
    if (emails.has(actor)) return emails.get(actor);
    if (actor.startsWith('therapist:')) return t('audit-who-gone');
    if (actor.startsWith('station:')) return t('audit-who-station');
    if (actor === 'cli') return t('audit-who-cli');
    if (actor === 'hub') return t('audit-who-hub');
    return t('audit-who-anonymous');
  };
  const about = target => {
    if (pseudonyms.has(target)) return displayName(pseudonyms.get(target));
    const th = therapists.find(x => x.id === target);
    if (th) return th.email;
    if (target === 'audit_log') return t('audit-about-log');
    return '';
  };
  const option = (v, label) => `<option value="${esc(v)}">${esc(label)}</option>`;
  const capital = w => w.charAt(0).toLocaleUpperCase(document.documentElement.lang || undefined) + w.slice(1);
  app.innerHTML = `<h1>${h('audit-heading')}</h1>
    <p class="note">${h('audit-intro')}</p>
    <form id="audit-filter" class="panel" novalidate>
      <div><label for="audit-patient">${h('audit-patient')}</label>
      <select id="audit-patient">${option('', t('audit-patient-all'))}${patients.map(p => option(p.id, displayName(p.pseudonym))).join('')}</select></div>
      <div><label for="audit-therapist">${h('audit-therapist')}</label>
      <select id="audit-therapist">${option('', t('audit-therapist-all'))}${therapists.map(th => option(`therapist:${th.id}`, th.email)).join('')}</select></div>
      <div><label for="audit-kind">${h('audit-kind')}</label>
      <select id="audit-kind">${option('', t('audit-kind-all'))}${KINDS.map(k => option(k, capital(what(k)))).join('')}</select></div>
      <div><button type="submit">${h('audit-show')}</button></div>
    </form>
    <section class="panel" aria-labelledby="audit-h"><h2 id="audit-h">${h('audit-entries')}</h2>
      <div id="audit-entries"></div>
      <p><button type="button" id="audit-newest" class="secondary">${h('audit-newest')}</button>
        <button type="button" id="audit-older" class="secondary">${h('audit-older')}</button></p>
      <p id="audit-error" class="error" role="alert"></p>
    </section>`;
  const list = app.querySelector('#audit-entries');
  const older = app.querySelector('#audit-older');
  const error = app.querySelector('#audit-error');
  let next = null, page = 0;
  const show = async cursor => {
    const q = new URLSearchParams({ limit: String(PAGE) });
    const filters = { target: '#audit-patient', actor: '#audit-therapist', action: '#audit-kind' };
    for (const [name, sel] of Object.entries(filters)) { const v = app.querySelector(sel).value; if (v) q.set(name, v); }
    if (cursor) { q.set('before_ms', String(cursor.before_ms)); q.set('before_id', cursor.before_id); }
    try {
      const answer = await api('GET', `/api/audit?${q}`);
      error.textContent = '';
      next = answer.next;
      page = cursor ? page + 1 : 1;
      const rows = answer.entries.map(e => `<tr data-action="${esc(e.action)}"><td>${esc(when(e.at_ms))}</td><td>${esc(who(e.actor))}</td>
        <td>${esc(what(e.action))}</td><td>${esc(about(e.target))}</td></tr>`).join('');
      list.innerHTML = answer.entries.length
        ? `<table id="audit-table" data-entries="${answer.entries.length}" data-page="${page}"><caption class="note">${h('audit-caption', { page })}</caption>
          <thead><tr><th scope="col">${h('audit-col-when')}</th><th scope="col">${h('audit-col-who')}</th><th scope="col">${h('audit-col-what')}</th><th scope="col">${h('audit-col-about')}</th></tr></thead>
          <tbody>${rows}</tbody></table>`
        : `<p id="audit-table" data-entries="0">${h('audit-no-entry')}</p>`;
      older.disabled = !next;
    } catch (e) {
      error.textContent = e instanceof ApiError && e.status === 403 ? t('audit-admins-only') : e.message;
    }
  };
  app.querySelector('#audit-filter').addEventListener('submit', ev => { ev.preventDefault(); show(null); });
  app.querySelector('#audit-newest').addEventListener('click', () => show(null));
  older.addEventListener('click', () => { if (next) show(next); });
  await show(null);
}
