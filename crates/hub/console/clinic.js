// The clinic's daily work from the browser (what `telerehab hub patient add`, `hub patient
// code`, `hub therapist add` and `hub station revoke` do): add a patient and print their
// pairing sheet, a new pairing code, a patient's stations and revoking one, and — for
// administrators — the therapists and adding one. Routes under #/clinic; every value put into
// HTML escaped; the hub decides who may do what (API.md) and audits every change.
import { api, esc, when } from '/console/api.js';
import { stationWords } from '/console/words.js';

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
    ? `<label for="np-therapist">Therapist in charge</label>
       <select id="np-therapist"><option value="">Nobody yet (only administrators see them)</option>
         ${therapists.map(t => `<option value="${esc(t.email)}">${esc(t.email)}${t.role === 'admin' ? ' (administrator)' : ''}</option>`).join('')}</select>`
    : '<p class="note">The patient will be in your care.</p>';
  app.innerHTML = `<h1>Clinic</h1>
    <section class="panel" aria-labelledby="np-h"><h2 id="np-h">Add a patient</h2>
      <form id="new-patient" novalidate>
        <label for="np-pseudonym">Pseudonym <span class="note">(the clinic's reference, e.g. P-0042; never a name: letters, digits, . _ -)</span></label>
        <input id="np-pseudonym" type="text" maxlength="64" autocomplete="off">
        ${careOf}
        <p><button type="submit">Add the patient and make a pairing sheet</button></p>
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
  const rows = therapists.map(t => `<tr><td>${esc(t.email)}</td><td>${t.role === 'admin' ? 'administrator' : 'therapist'}</td>
    <td>${esc(when(t.created_at_ms))}</td><td>${t.must_change_password ? 'not logged in yet (one-time password)' : 'own password'}</td></tr>`).join('');
  return `<section class="panel" aria-labelledby="th-h"><h2 id="th-h">Therapists</h2>
      <table id="therapists"><thead><tr><th scope="col">E-mail</th><th scope="col">Role</th><th scope="col">Added</th><th scope="col">Password</th></tr></thead>
      <tbody>${rows}</tbody></table>
      <h3>Add a therapist</h3>
      <form id="new-therapist" novalidate>
        <label for="nt-email">E-mail <span class="note">(their login)</span></label>
        <input id="nt-email" type="email" autocomplete="off">
        <p><input type="checkbox" id="nt-admin"><label for="nt-admin" class="inline">Administrator (sees every patient, adds therapists, reads the audit log)</label></p>
        <p><button type="submit">Add the therapist</button></p>
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
      body.insertAdjacentHTML('beforeend', `<tr><td>${esc(added.therapist.email)}</td>
        <td>${added.therapist.role === 'admin' ? 'administrator' : 'therapist'}</td><td>just now</td><td>not logged in yet (one-time password)</td></tr>`);
      app.querySelector('#nt-result').innerHTML = `<p><strong>${esc(added.therapist.email)}</strong> added. Their one-time password:
        <code id="nt-password" class="code">${esc(added.one_time_password)}</code></p>
        <p class="note">Shown once (only its hash is stored): give it to them in person. At their first login they must choose their own.</p>`;
      form.reset();
    } catch (e) { error.textContent = e.message; }
  });
}

/** This computer's own address: a station at a patient's home can never reach it. */
const isLoopback = a => /^(\[?::1\]?|127(\.\d+){3}|localhost|0\.0\.0\.0)(:\d+)?$/i.test(a || '');

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
      || `${address} is this computer's own address: a station at a patient's home cannot reach it.`;
    app.innerHTML = `<section id="sheet-refused" class="panel" aria-labelledby="refused-h">
        <h1 id="refused-h">The pairing sheet cannot be printed yet</h1>
        <p class="error" role="alert">${esc(why)}</p>
        <p>The code <strong class="code">${esc(pairing.code)}</strong> for ${esc(patient.pseudonym)} stays valid until ${esc(when(pairing.expires_at_ms))}. Make a new sheet once the address is set.</p>
        <p><a href="#/clinic/patients/${encodeURIComponent(patient.id)}">Stations and pairing</a> · <a href="#/clinic">Back to the clinic</a></p>
      </section>`;
    return;
  }
  app.innerHTML = `
    <section id="pairing-sheet" class="sheet" aria-labelledby="sheet-h">
      <h1 id="sheet-h">Connecting your telerehab station to the clinic</h1>
      <p>For <strong id="sheet-patient">${esc(patient.pseudonym)}</strong> <span class="note">(the clinic's reference for you)</span></p>
      <dl class="sheet-facts">
        <dt>Clinic address</dt><dd id="sheet-address">${esc(address)}</dd>
        <dt>Pairing code</dt><dd id="sheet-code" class="code">${esc(pairing.code)}</dd>
        <dt>Valid until</dt><dd id="sheet-expiry">${esc(when(pairing.expires_at_ms))}, for one station only</dd>
      </dl>
      <h2>What to do</h2>
      <ol class="steps">
        <li>Plug the wheel into the computer and into the mains; plug in the arm sensors too if the clinic gave you some.</li>
        <li>Open <strong>telerehab</strong> from the applications menu (or type <strong>telerehab</strong> and press Enter).</li>
        <li>Type the clinic address above and press Enter.</li>
        <li>Type the pairing code above (letters and digits, the dash is optional) and press Enter.</li>
        <li>The screen then says it is connected and shows today's session. Press Space, or a button on the wheel, to start driving.</li>
      </ol>
      <p>If the code is refused or has expired, call your therapist: they will give you a new one. Keep this sheet until your station is connected; the code works only once.</p>
    </section>
    <p class="print-hide">
      <button type="button" id="print-sheet">Print the pairing sheet</button>
      <a href="#/patients/${encodeURIComponent(patient.id)}">Open ${esc(patient.pseudonym)}</a>
      · <a href="#/clinic/patients/${encodeURIComponent(patient.id)}">Stations and pairing</a>
      · <a href="#/clinic">Add another patient</a>
    </p>`;
  app.querySelector('#print-sheet').addEventListener('click', () => window.print());
  app.querySelector('#print-sheet').focus();
}

/** A patient's stations, each revocable, and a new pairing code. */
async function stationsView(app, id) {
  const p = await api('GET', `/api/patients/${encodeURIComponent(id)}`);
  const rows = p.stations.map(s => `<tr><td>${esc(stationWords(s))}</td><td>${esc(when(s.paired_at_ms))}</td>
    <td>${esc(when(s.last_seen_ms))}</td>
    <td>${s.revoked_at_ms == null ? `<span class="badge ok">active</span>` : `<span class="badge alert">revoked ${esc(when(s.revoked_at_ms))}</span>`}</td>
    <td>${s.revoked_at_ms == null ? `<button type="button" class="secondary" data-revoke="${esc(s.station_id)}" data-words="${esc(stationWords(s))}">Revoke the ${esc(stationWords(s))}</button>` : ''}</td></tr>`).join('');
  app.innerHTML = `<h1>Stations of ${esc(p.pseudonym)}</h1>
    <p><a href="#/patients/${encodeURIComponent(id)}">Back to ${esc(p.pseudonym)}</a></p>
    <section class="panel" aria-labelledby="st-h"><h2 id="st-h">Stations</h2>
      <table id="stations"><thead><tr><th scope="col">Station</th><th scope="col">Paired</th><th scope="col">Last contact</th><th scope="col">State</th><th scope="col">Action</th></tr></thead>
      <tbody>${rows || '<tr><td colspan="5">No station paired yet.</td></tr>'}</tbody></table>
      <div id="revoke-confirm"></div>
      <p class="note">A revoked station is refused from its next connection on (a lost or replaced computer); pair a new one with a new code.</p>
    </section>
    <section class="panel" aria-labelledby="code-h"><h2 id="code-h">A new pairing code</h2>
      <p>For a new or replaced station: single use, valid 72 hours.</p>
      <p><button type="button" id="new-code">Make a pairing sheet</button></p>
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
      <h3 id="rv-h">Revoke the ${esc(words)}?</h3>
      <p id="rv-d">It will be refused from its next connection on, for good. The patient needs a new pairing code for another station.</p>
      <p><button type="button" id="rv-yes">Yes, revoke it</button> <button type="button" class="secondary" id="rv-no">Cancel</button></p>
      <p class="error" id="rv-error" role="alert"></p></div>`;
  box.querySelector('#rv-no').addEventListener('click', () => { box.innerHTML = ''; });
  box.querySelector('#rv-yes').addEventListener('click', async () => {
    try {
      await api('POST', `/api/stations/${encodeURIComponent(stationId)}/revoke`);
      await stationsView(app, patientId);
      app.querySelector('#stations').insertAdjacentHTML('beforebegin', `<p role="status" id="revoked">The ${esc(words)} is revoked.</p>`);
    } catch (e) { box.querySelector('#rv-error').textContent = e.message; }
  });
  box.querySelector('#rv-no').focus();
}
