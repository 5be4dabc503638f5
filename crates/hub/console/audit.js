// The audit page (#/audit, administrators only): who did what, when, in plain words, newest
// first, filtered by patient, therapist or kind, a page at a time (GET /api/audit). Patients
// are shown by the names this browser holds (names.js), therapists by e-mail, never by id.
import { api, ApiError, esc, when } from '/console/api.js';
import { displayName } from '/console/names.js';

/** Entries on one page. */
const PAGE = 50;

/** Each kind of entry in words, in the order the filter offers them. */
const KINDS = [
  ['login', 'logged in'], ['logout', 'logged out'], ['login_failed', 'failed to log in'],
  ['login_throttled', 'was slowed down after failed logins'], ['password_changed', 'changed their password'],
  ['password_change_refused', 'had a new password refused'],
  ['list_patients', 'opened the caseload'], ['read_patient', 'opened the patient'],
  ['show_patient', 'opened the patient\'s stations'],
  ['read_sessions', 'looked at the sessions'], ['read_session', 'looked at a session'],
  ['read_summaries', 'looked at a session\'s charts'], ['read_metrics', 'looked at a session\'s measures'],
  ['read_exercises', 'looked at a session exercise by exercise'], ['read_replay', 'replayed a session'],
  ['watch_live', 'watched a session live'], ['live_ended', 'stopped watching live'],
  ['read_checkins', 'looked at the check-ins'], ['read_difficulty', 'looked at the difficulty'],
  ['read_regimen', 'opened the prescription'], ['put_regimen', 'prescribed a new version'],
  ['regimen_rejected', 'had a prescription refused'],
  ['read_messages', 'read the messages'], ['post_message', 'sent a message'], ['message_rejected', 'had a message refused'],
  ['message_seen', 'showed a message to the patient'],
  ['read_notes', 'read the session notes'], ['post_note', 'wrote a session note'], ['note_rejected', 'had a note refused'],
  ['read_scales', 'read the clinical scales'], ['post_scale', 'recorded a clinical scale'],
  ['delete_scale', 'deleted a clinical scale'], ['scale_rejected', 'had a clinical scale refused'],
  ['export_measures_csv', 'downloaded the patient\'s spreadsheet'], ['export_caseload_csv', 'downloaded the caseload spreadsheet'],
  ['export_fhir', 'exported the patient\'s record'], ['export_patient', 'exported the patient\'s data'],
  ['add_patient', 'added a patient'], ['pairing_code', 'made a pairing code'], ['station_paired', 'paired a station'],
  ['pairing_failed', 'failed to pair a station'], ['revoke_station', 'revoked a station'], ['station_refused', 'was refused as a station'],
  ['add_therapist', 'added an account'], ['list_therapists', 'listed the accounts'],
  ['read_audit', 'opened the audit log'], ['refusals_suppressed', 'had further refusals counted, not written'],
  ['hub_init', 'set up the hub'],
];
const KIND_WORDS = new Map(KINDS);

/** What an entry's action says. */
function what(action) {
  if (KIND_WORDS.has(action)) return KIND_WORDS.get(action);
  const refused = action.match(/^refused_(\d{3})$/);
  if (refused) return { 401: 'was refused: not logged in', 403: 'was refused: not allowed', 404: 'asked for something not there or not theirs', 429: 'was refused: too many requests' }[refused[1]] || 'was refused';
  return action.replace(/_/g, ' ');
}

/** The audit page in `app` for `me`; a therapist who is not an administrator is told so. */
export async function auditView(app, me) {
  if (me.role !== 'admin') {
    app.innerHTML = '<h1>Audit log</h1><p id="audit-refused" class="error" role="alert">The audit log is for the clinic\'s administrators.</p>';
    return;
  }
  const [therapists, patients] = await Promise.all([api('GET', '/api/therapists'), api('GET', '/api/patients')]);
  const emails = new Map(therapists.map(t => [`therapist:${t.id}`, t.email]));
  const pseudonyms = new Map(patients.map(p => [p.id, p.pseudonym]));
  const who = actor => {
    if (emails.has(actor)) return emails.get(actor);
    if (actor.startsWith('therapist:')) return 'an account no longer at the clinic';
    if (actor.startsWith('station:')) return 'a patient\'s station';
    if (actor === 'cli') return 'the hub\'s administrator (command line)';
    if (actor === 'hub') return 'the hub';
    return 'someone not logged in';
  };
  const about = target => {
    if (pseudonyms.has(target)) return displayName(pseudonyms.get(target));
    const t = therapists.find(x => x.id === target);
    if (t) return t.email;
    if (target === 'audit_log') return 'the audit log';
    return '';
  };
  const option = (v, label) => `<option value="${esc(v)}">${esc(label)}</option>`;
  app.innerHTML = `<h1>Audit log</h1>
    <p class="note">Every look at a patient's data and every change, newest first. Only administrators see this page.</p>
    <form id="audit-filter" class="panel" novalidate>
      <div><label for="audit-patient">Patient</label>
      <select id="audit-patient">${option('', 'Every patient')}${patients.map(p => option(p.id, displayName(p.pseudonym))).join('')}</select></div>
      <div><label for="audit-therapist">Therapist</label>
      <select id="audit-therapist">${option('', 'Everyone')}${therapists.map(t => option(`therapist:${t.id}`, t.email)).join('')}</select></div>
      <div><label for="audit-kind">What</label>
      <select id="audit-kind">${option('', 'Everything')}${KINDS.map(([k, w]) => option(k, w.charAt(0).toUpperCase() + w.slice(1))).join('')}</select></div>
      <div><button type="submit">Show</button></div>
    </form>
    <section class="panel" aria-labelledby="audit-h"><h2 id="audit-h">Entries</h2>
      <div id="audit-entries"></div>
      <p><button type="button" id="audit-newest" class="secondary">Newest entries</button>
        <button type="button" id="audit-older" class="secondary">Older entries</button></p>
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
        ? `<table id="audit-table" data-entries="${answer.entries.length}" data-page="${page}"><caption class="note">Page ${page}, newest first</caption>
          <thead><tr><th scope="col">When</th><th scope="col">Who</th><th scope="col">What</th><th scope="col">About</th></tr></thead>
          <tbody>${rows}</tbody></table>`
        : '<p id="audit-table" data-entries="0">No entry matches.</p>';
      older.disabled = !next;
    } catch (e) {
      error.textContent = e instanceof ApiError && e.status === 403 ? 'The audit log is for the clinic\'s administrators.' : e.message;
    }
  };
  app.querySelector('#audit-filter').addEventListener('submit', ev => { ev.preventDefault(); show(null); });
  app.querySelector('#audit-newest').addEventListener('click', () => show(null));
  older.addEventListener('click', () => { if (next) show(next); });
  await show(null);
}
