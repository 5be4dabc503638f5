// The therapist console: login, the caseload, and a patient's live view, progress and
// prescription. A hash router over the console API; no inline script or style (the hub's
// Content-Security-Policy forbids them), every value put into HTML escaped.
import { api, ApiError, esc } from '/console/api.js';
import { liveView } from '/console/live.js';
import { replayView } from '/console/replay.js';
import { replayList } from '/console/replays.js';
import { progressView } from '/console/progress.js';
import { exercisesView } from '/console/exercises.js';
import { messagesPanel } from '/console/messages.js';
import { clinicView } from '/console/clinic.js';
import { notesSection } from '/console/notes.js';
import { caseloadView, settingsView } from '/console/caseload.js';
import { prescribeView } from '/console/prescribe.js';
import { displayName } from '/console/names.js';
import { namesView } from '/console/names-page.js';
import { auditView } from '/console/audit.js';
import { t, startLanguage, useLanguage, chooseLanguage, languages, languageTag } from '/console/i18n.js';

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
  document.getElementById('who').textContent = t('app-who', { email: me.email, role: me.role });
  document.getElementById('logout').hidden = false;
  document.getElementById('change-password').hidden = false;
  if (me.must_change_password) return passwordView(true);
  if (hash === '#/password') return passwordView(false);
  document.getElementById('clinic-link').hidden = false;
  document.getElementById('names-link').hidden = false;
  document.getElementById('audit-link').hidden = me.role !== 'admin';
  if (hash === '#/names') return namesView(app).catch(fail).then(() => app.focus());
  if (hash.startsWith('#/audit')) return auditView(app, me).catch(fail).then(() => app.focus());
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
  app.innerHTML = `<p class="error" role="alert">${esc(e.message || e)}</p><p><a href="#/patients">${esc(t('app-back-to-patients'))}</a></p>`;
}

/** The change-password screen; `forced` for a one-time password, which the hub lets do
 * nothing else until it is changed. */
function passwordView(forced) {
  app.innerHTML = `
    <h1>${esc(t(forced ? 'app-password-title-forced' : 'app-password-title'))}</h1>
    ${forced ? `<p id="password-forced">${esc(t('app-password-forced'))}</p>` : ''}
    <form id="password-form" novalidate>
      <label for="current-password">${esc(t(forced ? 'app-password-one-time' : 'app-password-current'))}</label>
      <input id="current-password" type="password" autocomplete="current-password" required>
      <label for="new-password">${esc(t('app-password-new'))} <span class="note">${esc(t('app-password-rules'))}</span></label>
      <input id="new-password" type="password" autocomplete="new-password" minlength="10" required>
      <label for="repeat-password">${esc(t('app-password-repeat'))}</label>
      <input id="repeat-password" type="password" autocomplete="new-password" minlength="10" required>
      <p><button type="submit">${esc(t('app-password-submit'))}</button></p>
      <p class="error" id="password-error" role="alert"></p>
    </form>`;
  const form = app.querySelector('#password-form');
  const error = app.querySelector('#password-error');
  form.addEventListener('submit', async ev => {
    ev.preventDefault();
    const current = form.querySelector('#current-password').value;
    const next = form.querySelector('#new-password').value;
    if (next !== form.querySelector('#repeat-password').value) { error.textContent = t('app-password-differ'); return; }
    try {
      // The hub ends every login of this account and answers with a new session cookie.
      await api('POST', '/api/me/password', { current, new: next });
      me = await api('GET', '/api/me');
      await startLanguage();
      languageMenu();
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
  document.getElementById('names-link').hidden = true;
  document.getElementById('audit-link').hidden = true;
  document.getElementById('who').textContent = '';
  app.innerHTML = `
    <h1>${esc(t('app-login-title'))}</h1>
    <form id="login" novalidate>
      <label for="email">${esc(t('app-login-email'))}</label><input id="email" type="email" autocomplete="username" required>
      <label for="password">${esc(t('app-login-password'))}</label><input id="password" type="password" autocomplete="current-password" required>
      <p><button type="submit">${esc(t('app-login-submit'))}</button></p>
      <p class="error" id="login-error" role="alert"></p>
    </form>`;
  const form = app.querySelector('#login');
  form.addEventListener('submit', async ev => {
    ev.preventDefault();
    try {
      me = await api('POST', '/api/login', { email: form.email.value, password: form.password.value });
      await startLanguage();
      languageMenu();
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
  const link = name => `<a href="#/patients/${encodeURIComponent(id)}/${name}" data-tab="${name}"${name === tab ? ' aria-current="page"' : ''}>${esc(t(`app-tab-${name}`))}</a>`;
  app.innerHTML = `<h1>${esc(t('app-patient-title', { name: displayName(p.pseudonym) }))}</h1>
    <nav class="tabs" aria-label="${esc(t('app-tabs-label'))}">${link('live')}${link('progress')}${link('replay')}${link('prescribe')}<a href="#/clinic/patients/${encodeURIComponent(id)}" data-tab="stations">${esc(t('app-tab-stations'))}</a></nav>
    <div id="tab"></div>
    <section id="messages"></section>`;
  const el = app.querySelector('#tab');
  const refreshMessages = await messagesPanel(app.querySelector('#messages'), id);
  if (tab === 'live') { el.id = 'live'; leave = liveView(el, id); }
  else if (tab === 'progress') leave = await progressView(el, id);
  else if (tab === 'replay') leave = sessionId ? await replayView(el, sessionId) : (await replayList(el, id), () => {});
  else if (tab === 'exercises') { await exercisesView(el, id, sessionId); await notesSection(el, sessionId); }
  else await prescribeView(el, id, refreshMessages, me);
}

document.getElementById('change-password').addEventListener('click', () => {
  location.hash = '#/password';
});
document.getElementById('logout').addEventListener('click', async () => {
  try { await api('POST', '/api/logout'); } catch { /* logged out either way */ }
  me = null;
  location.hash = '#/patients';
  await startLanguage({ signedIn: false });
  languageMenu();
  loginView();
});

/** The header's language menu: the languages on offer, each in its own language. A choice is
 * kept on the hub for the therapist logged in (the login page's only for this page). */
function languageMenu() {
  const menu = document.getElementById('language');
  const tag = languageTag();
  const offered = languages();
  const extra = offered.some(l => l.tag === tag) ? [] : [{ tag, name: tag }];
  menu.innerHTML = [...offered, ...extra].map(l => `<option value="${esc(l.tag)}" lang="${esc(l.tag)}"${l.tag === tag ? ' selected' : ''}>${esc(l.name)}</option>`).join('');
}

document.getElementById('language').addEventListener('change', async ev => {
  const tag = ev.target.value;
  try {
    if (me) await chooseLanguage(tag); else await useLanguage(tag);
  } catch (e) { return fail(e); }
  languageMenu();
  route();
});

/** The first screen: who is logged in (if anyone), their language, then the route. */
async function boot() {
  let refused = false;
  try { me = await api('GET', '/api/me'); } catch (e) { me = null; refused = e instanceof ApiError && e.status === 401; }
  await startLanguage({ signedIn: me !== null });
  languageMenu();
  window.addEventListener('hashchange', route);
  if (refused) loginView(); else await route();
  // The first screen is drawn: a later change of address draws over it, never under it.
  document.documentElement.dataset.booted = 'true';
}

boot();
