// The clinic's daily work from the browser (what `telerehab hub patient add`, `hub patient
// code`, `hub therapist add` and `hub station revoke` do): add a patient and print their
// pairing sheet, a new pairing code, a patient's stations and revoking one, and — for
// administrators — the therapists and adding one. Routes under #/clinic; every value put into
// HTML escaped; the hub decides who may do what (API.md) and audits every change.
import { api, esc, when } from '/console/api.js';
import { stationWords } from '/console/words.js';
import { t } from '/console/i18n.js';

/** A catalogue message, escaped for HTML. */
const h = (id, args) => esc(t(id, args));

// Where stations at home reach the hub is the hub's to say (`hub serve
// --public-station-address`): each pairing code comes with it, or with why there is none.

/** Shows the clinic screen `hash` (#/clinic or #/clinic/patients/{id}) in `app`. */
export async function clinicView(app, hash, me) {
  const m = hash.match(/^#\/clinic\/patients\/([^/]+)$/);
  if (m) return stationsView(app, decodeURIComponent(m[1]));
  return clinicHome(app, me);
}

async function clinicHome(app, me) {
  const therapists = me.role === 'admin' ? await api('GET', '/api/therapists') : [];
  const careOf = me.role === 'admin'
    ? `<label for="np-therapist">${h('clinic-in-charge')}</label>
       <select id="np-therapist"><option value="">${h('clinic-in-charge-nobody')}</option>
         ${therapists.map(th => `<option value="${esc(th.email)}">${th.role === 'admin' ? h('clinic-email-admin', { email: th.email }) : esc(th.email)}</option>`).join('')}</select>`
    : `<p class="note" id="np-in-your-care">${h('clinic-in-your-care')}</p>`;
  app.innerHTML = `<h1>${h('clinic-heading')}</h1>
    <section class="panel" aria-labelledby="np-h"><h2 id="np-h">${h('clinic-add-patient')}</h2>
      <form id="new-patient" novalidate>
        <label for="np-pseudonym">${h('clinic-pseudonym')} <span class="note">${h('clinic-pseudonym-note')}</span></label>
        <input id="np-pseudonym" type="text" maxlength="64" autocomplete="off">
        ${careOf}
        <p><button type="submit">${h('clinic-add-patient-button')}</button></p>
        <p class="error" id="np-error" role="alert"></p>
      </form>
    </section>
    ${me.role === 'admin' ? therapistsPanel(therapists) : ''}`;
  const form = app.querySelector('#new-patient');
  form.addEventListener('submit', async ev => {
    ev.preventDefault();
    const body = { pseudonym: form.querySelector('#np-pseudonym').value.trim() };
    const who = form.querySelector('#np-therapist');
    if (who && who.value) body.therapist_email = who.value;
    app.querySelector('#np-error').textContent = '';
    try {
      const added = await api('POST', '/api/patients', body);
      pairingSheet(app, added.patient, added.pairing);
    } catch (e) { app.querySelector('#np-error').textContent = e.message; }
  });
  if (me.role === 'admin') bindTherapists(app);
  form.querySelector('#np-pseudonym').focus();
}

function therapistsPanel(therapists) {
  const rows = therapists.map(th => `<tr data-role="${esc(th.role)}"><td>${esc(th.email)}</td><td>${h(th.role === 'admin' ? 'clinic-role-admin' : 'clinic-role-therapist')}</td>
    <td>${esc(when(th.created_at_ms))}</td><td>${h(th.must_change_password ? 'clinic-password-one-time' : 'clinic-password-own')}</td></tr>`).join('');
  return `<section class="panel" aria-labelledby="th-h"><h2 id="th-h">${h('clinic-therapists')}</h2>
      <table id="therapists"><thead><tr><th scope="col">${h('clinic-col-email')}</th><th scope="col">${h('clinic-col-role')}</th><th scope="col">${h('clinic-col-added')}</th><th scope="col">${h('clinic-col-password')}</th></tr></thead>
      <tbody>${rows}</tbody></table>
      <h3>${h('clinic-add-therapist')}</h3>
      <form id="new-therapist" novalidate>
        <label for="nt-email">${h('clinic-col-email')} <span class="note">${h('clinic-email-note')}</span></label>
        <input id="nt-email" type="email" autocomplete="off">
        <p><input type="checkbox" id="nt-admin"><label for="nt-admin" class="inline">${h('clinic-admin-label')}</label></p>
        <p><button type="submit">${h('clinic-add-therapist-button')}</button></p>
        <p class="error" id="nt-error" role="alert"></p>
      </form>
      <div id="nt-result" role="status"></div>
    </section>`;
}

function bindTherapists(app) {
  const form = app.querySelector('#new-therapist');
  form.addEventListener('submit', async ev => {
    ev.preventDefault();
    const error = app.querySelector('#nt-error');
    error.textContent = '';
    try {
      const added = await api('POST', '/api/therapists', {
        email: form.querySelector('#nt-email').value.trim(), admin: form.querySelector('#nt-admin').checked });
      const body = app.querySelector('#therapists tbody');
      body.insertAdjacentHTML('beforeend', `<tr data-role="${esc(added.therapist.role)}"><td>${esc(added.therapist.email)}</td>
        <td>${h(added.therapist.role === 'admin' ? 'clinic-role-admin' : 'clinic-role-therapist')}</td><td>${h('clinic-just-now')}</td><td>${h('clinic-password-one-time')}</td></tr>`);
      app.querySelector('#nt-result').innerHTML = `<p>${h('clinic-therapist-added', { email: added.therapist.email })}
        <code id="nt-password" class="code">${esc(added.one_time_password)}</code></p>
        <p class="note">${h('clinic-one-time-note')}</p>`;
      form.reset();
    } catch (e) { error.textContent = e.message; }
  });
}

/** This computer's own address: a station at a patient's home can never reach it. */
const isLoopback = a => /^(\[?::1\]?|127(\.\d+){3}|localhost|0\.0\.0\.0)(:\d+)?$/i.test(a || '');

/** The clinic's pairing card as a file to put on a USB stick (`telerehab-pairing.toml`, the
 * station's `front_door::pairing_file`): with it in the computer, the patient pairs with one
 * press of a wheel button and types nothing. */
function cardHref(address, code) {
  const card = `# telerehab: the clinic's pairing card. Put it on a USB stick for the patient.\n`
    + `clinic_address = ${JSON.stringify(address)}\ncode = ${JSON.stringify(code)}\n`;
  return `data:application/toml;charset=utf-8,${encodeURIComponent(card)}`;
}

/** The printable pairing sheet: the hub's station address, the code, until when it pairs,
 * and the patient's steps; refused (saying why) when the hub has no address a station at
 * home can reach. */
function pairingSheet(app, patient, pairing) {
  // A hash of its own, so that links back to the screen it replaced navigate (the code itself
  // is not kept: reloading shows the clinic screen).
  history.replaceState(null, '', '#/clinic/sheet');
  const address = pairing.station_address;
  if (!address || isLoopback(address)) {
    const why = pairing.station_address_problem
      || t('clinic-loopback', { address: address || '' });
    app.innerHTML = `<section id="sheet-refused" class="panel" aria-labelledby="refused-h">
        <h1 id="refused-h">${h('clinic-sheet-refused')}</h1>
        <p class="error" role="alert">${esc(why)}</p>
        <p>${h('clinic-code-still-valid', { pseudonym: patient.pseudonym, until: when(pairing.expires_at_ms) })} <strong class="code">${esc(pairing.code)}</strong></p>
        <p><a href="#/clinic/patients/${encodeURIComponent(patient.id)}">${h('clinic-stations-link')}</a> · <a href="#/clinic">${h('clinic-back')}</a></p>
      </section>`;
    return;
  }
  app.innerHTML = `
    <section id="pairing-sheet" class="sheet" aria-labelledby="sheet-h">
      <h1 id="sheet-h">${h('clinic-sheet-heading')}</h1>
      <p>${h('clinic-sheet-for')} <strong id="sheet-patient">${esc(patient.pseudonym)}</strong> <span class="note">${h('clinic-sheet-reference')}</span></p>
      <dl class="sheet-facts">
        <dt>${h('clinic-sheet-address')}</dt><dd id="sheet-address">${esc(address)}</dd>
        <dt>${h('clinic-sheet-code')}</dt><dd id="sheet-code" class="code">${esc(pairing.code)}</dd>
        <dt>${h('clinic-sheet-valid')}</dt><dd id="sheet-expiry" data-expires-ms="${esc(pairing.expires_at_ms)}">${h('clinic-sheet-valid-until', { until: when(pairing.expires_at_ms) })}</dd>
      </dl>
      <h2>${h('clinic-sheet-steps')}</h2>
      <ol class="steps">
        <li>${h('clinic-sheet-step-plug')}</li>
        <li>${h('clinic-sheet-step-open')}</li>
        <li>${h('clinic-sheet-step-card')}</li>
        <li>${h('clinic-sheet-step-address')}</li>
        <li>${h('clinic-sheet-step-code')}</li>
        <li>${h('clinic-sheet-step-start')}</li>
      </ol>
      <p>${h('clinic-sheet-help')}</p>
    </section>
    <p class="print-hide">
      <button type="button" id="print-sheet">${h('clinic-print')}</button>
      <a id="pairing-card" download="telerehab-pairing.toml" href="${esc(cardHref(address, pairing.code))}">${h('clinic-card-save')}</a>
      ·
      <a href="#/patients/${encodeURIComponent(patient.id)}">${h('clinic-open-patient', { pseudonym: patient.pseudonym })}</a>
      · <a href="#/clinic/patients/${encodeURIComponent(patient.id)}">${h('clinic-stations-link')}</a>
      · <a href="#/clinic">${h('clinic-add-another')}</a>
    </p>`;
  app.querySelector('#print-sheet').addEventListener('click', () => window.print());
  app.querySelector('#print-sheet').focus();
}

/** A patient's stations, each revocable, and a new pairing code. */
async function stationsView(app, id) {
  const p = await api('GET', `/api/patients/${encodeURIComponent(id)}`);
  const rows = p.stations.map(s => `<tr><td>${esc(stationWords(s))}</td><td>${esc(when(s.paired_at_ms))}</td>
    <td>${esc(when(s.last_seen_ms))}</td>
    <td>${s.revoked_at_ms == null ? `<span class="badge ok" data-state="active">${h('clinic-station-active')}</span>` : `<span class="badge alert" data-state="revoked">${h('clinic-station-revoked', { when: when(s.revoked_at_ms) })}</span>`}</td>
    <td>${s.revoked_at_ms == null ? `<button type="button" class="secondary" data-revoke="${esc(s.station_id)}" data-words="${esc(stationWords(s))}">${h('clinic-revoke-button', { station: stationWords(s) })}</button>` : ''}</td></tr>`).join('');
  app.innerHTML = `<h1>${h('clinic-stations-of', { pseudonym: p.pseudonym })}</h1>
    <p><a href="#/patients/${encodeURIComponent(id)}">${h('clinic-back-to', { pseudonym: p.pseudonym })}</a></p>
    <section class="panel" aria-labelledby="st-h"><h2 id="st-h">${h('clinic-stations')}</h2>
      <table id="stations"><thead><tr><th scope="col">${h('clinic-col-station')}</th><th scope="col">${h('clinic-col-paired')}</th><th scope="col">${h('clinic-col-last-contact')}</th><th scope="col">${h('clinic-col-state')}</th><th scope="col">${h('clinic-col-action')}</th></tr></thead>
      <tbody>${rows || `<tr><td colspan="5">${h('clinic-no-station')}</td></tr>`}</tbody></table>
      <div id="revoke-confirm"></div>
      <p class="note">${h('clinic-revoked-note')}</p>
    </section>
    <section class="panel" aria-labelledby="code-h"><h2 id="code-h">${h('clinic-new-code')}</h2>
      <p>${h('clinic-new-code-note')}</p>
      <p><button type="button" id="new-code">${h('clinic-make-sheet')}</button></p>
      <p class="error" id="code-error" role="alert"></p>
    </section>`;
  app.querySelector('#new-code').addEventListener('click', async () => {
    try {
      const pairing = await api('POST', `/api/patients/${encodeURIComponent(id)}/pairing-code`);
      pairingSheet(app, p, pairing);
    } catch (e) { app.querySelector('#code-error').textContent = e.message; }
  });
  app.querySelectorAll('[data-revoke]').forEach(b => b.addEventListener('click', () => confirmRevoke(app, id, b.dataset.revoke, b.dataset.words)));
}

/** Asks once more before revoking: a revoked station cannot be un-revoked. */
function confirmRevoke(app, patientId, stationId, words) {
  const box = app.querySelector('#revoke-confirm');
  box.innerHTML = `<div class="panel" role="alertdialog" aria-labelledby="rv-h" aria-describedby="rv-d">
      <h3 id="rv-h">${h('clinic-revoke-ask', { station: words })}</h3>
      <p id="rv-d">${h('clinic-revoke-explain')}</p>
      <p><button type="button" id="rv-yes">${h('clinic-revoke-yes')}</button> <button type="button" class="secondary" id="rv-no">${h('clinic-revoke-cancel')}</button></p>
      <p class="error" id="rv-error" role="alert"></p></div>`;
  box.querySelector('#rv-no').addEventListener('click', () => { box.innerHTML = ''; });
  box.querySelector('#rv-yes').addEventListener('click', async () => {
    try {
      await api('POST', `/api/stations/${encodeURIComponent(stationId)}/revoke`);
      await stationsView(app, patientId);
      app.querySelector('#stations').insertAdjacentHTML('beforebegin', `<p role="status" id="revoked">${h('clinic-revoked', { station: words })}</p>`);
    } catch (e) { box.querySelector('#rv-error').textContent = e.message; }
  });
  box.querySelector('#rv-no').focus();
}
