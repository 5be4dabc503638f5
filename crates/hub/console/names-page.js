// The Names page (#/names): import the clinic's list of names for its pseudonyms into this
// browser, see it, forget it. Nothing on this page is sent to the hub (names.js).
import { api, esc } from '/console/api.js';
import { allNames, forgetNames, keepNames, parseNamesCsv } from '/console/names.js';

/** The page, in `app`. */
export async function namesView(app) {
  const patients = await api('GET', '/api/patients').catch(() => []);
  const known = new Set(patients.map(p => p.pseudonym));
  const render = (message = '', problems = []) => {
    const names = allNames();
    const rows = names.map(([p, n]) => `<tr><th scope="row">${esc(p)}</th><td>${esc(n)}</td>
      <td>${known.has(p) ? 'in your caseload' : '<span class="note">not in your caseload</span>'}</td></tr>`).join('');
    app.innerHTML = `<h1>Your patients' names</h1>
      <section class="panel" aria-labelledby="names-how-h"><h2 id="names-how-h">Names stay on this computer</h2>
        <p>The hub knows your patients by pseudonym only. You can give this browser your clinic's own list of names for them:
          the list stays in this browser, on this computer, and is never sent to the hub.</p>
        <p>Use a spreadsheet file (CSV) with two columns: the pseudonym, then the name. Importing a file replaces the list.</p>
        <label for="names-file">Import a list of names (CSV file)</label>
        <input type="file" id="names-file" accept=".csv,.txt,text/csv,text/plain">
        <p id="names-result" role="status">${esc(message)}</p>
        ${problems.length ? `<ul id="names-problems" class="error">${problems.map(p => `<li>${esc(p)}</li>`).join('')}</ul>` : ''}
        <p class="note">On a computer others use too, forget the names when you finish.</p>
        <p><button type="button" id="names-forget" class="secondary"${names.length ? '' : ' disabled'}>Forget the names on this computer</button></p>
      </section>
      <section class="panel" aria-labelledby="names-list-h"><h2 id="names-list-h">Names in this browser</h2>
        ${names.length ? `<table id="names-table" data-names="${names.length}"><caption class="note">${names.length} name${names.length === 1 ? '' : 's'}, by pseudonym</caption>
          <thead><tr><th scope="col">Pseudonym</th><th scope="col">Name</th><th scope="col">Patient</th></tr></thead>
          <tbody>${rows}</tbody></table>` : '<p id="names-table" data-names="0">No names in this browser yet.</p>'}
      </section>`;
    app.querySelector('#names-file').addEventListener('change', async ev => {
      const file = ev.target.files[0];
      if (!file) return;
      const { pairs, problems: found } = parseNamesCsv(await file.text());
      if (!pairs.length) { render('No name could be read from the file; the list is unchanged.', found); return; }
      keepNames(pairs);
      render(`${pairs.length} name${pairs.length === 1 ? '' : 's'} kept in this browser.`, found);
    });
    app.querySelector('#names-forget').addEventListener('click', () => {
      forgetNames();
      render('The names are forgotten on this computer.');
    });
  };
  render();
}
