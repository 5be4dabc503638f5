// The Names page (#/names): import the clinic's list of names for its pseudonyms into this
// browser, see it, forget it. Nothing on this page is sent to the hub (names.js).
import { api, esc } from '/console/api.js';
import { allNames, forgetNames, keepNames, parseNamesCsv } from '/console/names.js';
import { t } from '/console/i18n.js';

const h = (id, args) => esc(t(id, args));

/** The page, in `app`. */
export async function namesView(app) {
  const patients = await api('GET', '/api/patients').catch(() => []);
  const known = new Set(patients.map(p => p.pseudonym));
  const render = (message = '', problems = []) => {
    const names = allNames();
    const rows = names.map(([p, n]) => `<tr><th scope="row">${esc(p)}</th><td>${esc(n)}</td>
      <td>${known.has(p) ? h('names-in-caseload') : `<span class="note">${h('names-not-in-caseload')}</span>`}</td></tr>`).join('');
    app.innerHTML = `<h1>${h('names-heading')}</h1>
      <section class="panel" aria-labelledby="names-how-h"><h2 id="names-how-h">${h('names-stay-heading')}</h2>
        <p>${h('names-stay-text')}</p>
        <p>${h('names-csv-text')}</p>
        <label for="names-file">${h('names-file-label')}</label>
        <input type="file" id="names-file" accept=".csv,.txt,text/csv,text/plain">
        <p id="names-result" role="status">${esc(message)}</p>
        ${problems.length ? `<ul id="names-problems" class="error">${problems.map(p => `<li>${esc(p)}</li>`).join('')}</ul>` : ''}
        <p class="note">${h('names-shared-computer')}</p>
        <p><button type="button" id="names-forget" class="secondary"${names.length ? '' : ' disabled'}>${h('names-forget')}</button></p>
      </section>
      <section class="panel" aria-labelledby="names-list-h"><h2 id="names-list-h">${h('names-list-heading')}</h2>
        ${names.length ? `<table id="names-table" data-names="${names.length}"><caption class="note">${h('names-caption', { count: names.length })}</caption>
          <thead><tr><th scope="col">${h('names-col-pseudonym')}</th><th scope="col">${h('names-col-name')}</th><th scope="col">${h('names-col-patient')}</th></tr></thead>
          <tbody>${rows}</tbody></table>` : `<p id="names-table" data-names="0">${h('names-none')}</p>`}
      </section>`;
    app.querySelector('#names-file').addEventListener('change', async ev => {
      const file = ev.target.files[0];
      if (!file) return;
      const { pairs, problems: found } = parseNamesCsv(await file.text());
      if (!pairs.length) { render(t('names-none-read'), found); return; }
      keepNames(pairs);
      render(t('names-kept', { count: pairs.length }), found);
    });
    app.querySelector('#names-forget').addEventListener('click', () => {
      forgetNames();
      render(t('names-forgotten'));
    });
  };
  render();
}
