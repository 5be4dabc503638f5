// Clinical scales (issues 32, 41; crates/hub/API.md, "clinical scales"): the Fugl-Meyer upper
// extremity motor score, the Action Research Arm Test and the Box and Block Test a therapist
// takes at the clinic, entered with the day they were taken. ONE chart a scale (never a
// station measure on a second axis beside it), one step an assessment, the axis the scale's own
// range (0–66 points for Fugl-Meyer) from the hub's definitions. The numbers are in a table the
// one-page print keeps. A second score of a scale on a day that already has one is asked about
// before saving: replace it, or keep both.
import { api, esc } from '/console/api.js';
import { numbersTable, sessionChart } from '/console/sessionchart.js';
import { isoDayWords } from '/console/words.js';
import { t } from '/console/i18n.js';

const h = (id, args) => esc(t(id, args));
/** A catalogue message, else `fallback` (the hub's English for a scale the catalogue lacks). */
const tOr = (id, fallback) => { const w = t(id); return w === id ? fallback : w; };

/** The hub's scale definitions in the console's language (names, field labels and units). */
function localScales(scales) {
  return scales.map(s => ({
    ...s,
    name: tOr(`scales-name-${s.key}`, s.name),
    fields: s.fields.map(f => ({
      ...f,
      label: tOr(`scales-field-${s.key}-${f.field}`, f.label),
      unit: tOr(`scales-unit-${String(f.unit).replace(/ /g, '-')}`, f.unit),
    })),
  }));
}

const two = n => String(n).padStart(2, '0');
/** `YYYY-MM-DD` of a Date, local time. */
const isoDay = d => `${d.getFullYear()}-${two(d.getMonth() + 1)}-${two(d.getDate())}`;

/** An entry's numbers in words: "34 points", "affected side 12, unaffected side 45 blocks per
 * minute". */
export function scoreWords(e) {
  if (e.score != null) return t('scales-points', { score: e.score });
  return t('scales-blocks', { affected: e.affected_blocks_per_min, unaffected: e.unaffected_blocks_per_min });
}

/** Labels of `entries` (oldest first) by their day; two of one day numbered. */
function dayLabels(entries) {
  const words = entries.map(e => isoDayWords(e.assessed_on));
  return words.map((w, i) => (words.indexOf(w) !== words.lastIndexOf(w) ? `${w} (${words.slice(0, i + 1).filter(x => x === w).length})` : w));
}

/** The charts (HTML and what to draw): one a scale with entries, its fields its series. */
function scaleCharts(scales, entries) {
  const draws = [];
  const html = scales.map(s => {
    const own = entries.filter(e => e.scale === s.key);
    if (!own.length) return '';
    const labels = dayLabels(own);
    const max = Math.max(...s.fields.map(f => f.max));
    const unit = s.fields[0].unit;
    const columns = s.fields.map(f => ({ key: f.field, label: s.fields.length > 1 ? `${f.label.replace(`${s.name}, `, '')} (${f.unit})` : `${s.name} (${f.unit})`, values: own.map(e => e[f.field] ?? null) }));
    const id = `p-scale-${s.key}`;
    const status = own.map(() => ({ counts: true, early: false }));
    draws.push([id, { y: `${unit}`, labels, integer: true, range: [0, max], decimals: 0,
      series: columns.map(c => ({ label: c.label, values: c.values })) }]);
    return `<div class="panel"><h3 id="${id}-h">${esc(s.name)} (${esc(unit)}, 0–${esc(max)})</h3>
      <div class="chart" id="${id}" data-scale="${esc(s.key)}" role="img" aria-label="${h('scales-chart-label', { scale: s.name })}"></div>
      ${numbersTable(s.name, labels, columns, status, true)}</div>`;
  }).join('');
  return { html: html ? `<div class="grid">${html}</div>` : '', draws };
}

/** The entries' table (printed), newest first, each with a button deleting a mistaken one. */
function entriesTable(entries) {
  if (!entries.length) return `<p id="scales-none">${h('scales-none')}</p>`;
  const rows = entries.slice().reverse().map(e => `<tr data-scale="${esc(e.scale)}"><td>${esc(isoDayWords(e.assessed_on))}</td>
    <td>${esc(e.scale_name)}</td><td class="num">${esc(scoreWords(e))}</td><td>${esc(e.therapist_email || t('scales-by-gone'))}</td>
    <td class="print-hide"><button type="button" class="secondary delete-scale" data-id="${esc(e.id)}">${h('scales-delete', { scale: e.scale_name, day: isoDayWords(e.assessed_on) })}</button></td></tr>`).join('');
  return `<table id="scales-table"><caption>${h('scales-caption')}</caption>
    <thead><tr><th scope="col">${h('scales-col-day')}</th><th scope="col">${h('scales-col-scale')}</th><th scope="col">${h('scales-col-score')}</th><th scope="col">${h('scales-col-by')}</th><th scope="col" class="print-hide">${h('scales-col-mistaken')}</th></tr></thead>
    <tbody>${rows}</tbody></table>`;
}

/** The form: the scale, its day, and its numbers with their bounds (min, max, required) from
 * the hub's own definitions, so the browser refuses an out-of-range score before the hub does. */
function formHtml(scales) {
  const options = scales.map(s => `<option value="${esc(s.key)}">${esc(s.name)}</option>`).join('');
  const inputs = scales.map(s => `<fieldset class="scale-fields" data-scale="${esc(s.key)}"><legend>${esc(s.name)}</legend>
    ${s.fields.map(f => `<label for="scale-${esc(s.key)}-${esc(f.field)}">${h('scales-field-label', { label: f.label, min: f.min, max: f.max, unit: f.unit })}</label>
      <input type="number" id="scale-${esc(s.key)}-${esc(f.field)}" name="${esc(f.field)}" min="${esc(f.min)}" max="${esc(f.max)}" step="1" required inputmode="numeric">`).join('')}</fieldset>`).join('');
  return `<details class="print-hide" id="scale-form-details"><summary>${h('scales-record')}</summary><form id="scale-form">
    <label for="scale-kind">${h('scales-col-scale')}</label><select id="scale-kind" name="scale" required>${options}</select>
    <label for="scale-day">${h('scales-col-day')}</label><input type="date" id="scale-day" name="assessed_on" required min="1990-01-01">
    ${inputs}<p><button type="submit">${h('scales-save')}</button></p>
    <div id="scale-duplicate" role="alertdialog" aria-labelledby="scale-duplicate-q" hidden></div>
    <p id="scale-result" role="status"></p></form></details>`;
}

/** Shows only the chosen scale's numbers (the others disabled: not required, not sent). */
function showFields(form) {
  const key = form.querySelector('#scale-kind').value;
  form.querySelectorAll('fieldset.scale-fields').forEach(f => {
    f.hidden = f.dataset.scale !== key;
    f.disabled = f.hidden;
  });
}

/** The clinical scales section of patient `id` into `box`; returns what undoes its charts. */
export async function scalesSection(box, id) {
  const url = `/api/patients/${encodeURIComponent(id)}/scales`;
  let undo = () => {};
  let entries = [];
  box.innerHTML = `<h2 id="scales-h">${h('scales-heading')}</h2>
    <div id="scales-charts"></div><div id="scales-list"></div><div id="scales-form-box"></div>`;
  const refresh = async () => {
    const answer = await api('GET', url);
    answer.scales = localScales(answer.scales);
    const names = new Map(answer.scales.map(sc => [sc.key, sc.name]));
    entries = answer.entries.map(e => ({ ...e, scale_name: names.get(e.scale) || e.scale_name }));
    undo();
    const charts = scaleCharts(answer.scales, entries);
    box.querySelector('#scales-charts').innerHTML = charts.html;
    box.querySelector('#scales-list').innerHTML = entriesTable(entries);
    const drawn = charts.draws.map(([chartId, opts]) => sessionChart(box.querySelector(`#${chartId}`), opts));
    undo = () => drawn.forEach(c => c.destroy());
    box.dataset.entries = String(entries.length);
    box.querySelectorAll('button.delete-scale').forEach(b => b.addEventListener('click', async () => {
      if (!window.confirm(`${b.textContent}?`)) return;
      try {
        await api('DELETE', `${url}/${encodeURIComponent(b.dataset.id)}`);
        await refresh();
      } catch (e) {
        box.querySelector('#scales-list').insertAdjacentHTML('afterbegin',
          `<p class="error" role="alert">${h('scales-not-deleted', { reason: String(e.message || e) })}</p>`);
      }
    }));
    return answer.scales;
  };
  const scales = await refresh();
  const formBox = box.querySelector('#scales-form-box');
  formBox.innerHTML = formHtml(scales);
  const form = formBox.querySelector('form');
  const day = form.querySelector('#scale-day');
  day.max = isoDay(new Date());
  day.value = day.max;
  showFields(form);
  form.querySelector('#scale-kind').addEventListener('change', () => showFields(form));
  const result = form.querySelector('#scale-result');
  const duplicate = form.querySelector('#scale-duplicate');
  const save = async (body, replacing) => {
    try {
      if (replacing) await api('DELETE', `${url}/${encodeURIComponent(replacing.id)}`);
      await api('POST', url, body);
      form.querySelectorAll('fieldset.scale-fields input').forEach(i => { i.value = ''; });
      result.className = '';
      result.textContent = t(replacing ? 'scales-saved-replacing' : 'scales-saved');
      result.dataset.saved = '1';
      await refresh();
    } catch (e) { result.className = 'error'; result.textContent = e.message; }
  };
  form.addEventListener('submit', async ev => {
    ev.preventDefault();
    const body = { scale: form.scale.value, assessed_on: day.value };
    form.querySelectorAll('fieldset.scale-fields:not([disabled]) input').forEach(i => { body[i.name] = i.value === '' ? null : Number(i.value); });
    const same = entries.filter(e => e.scale === body.scale && e.assessed_on === body.assessed_on);
    if (!same.length) { await save(body, null); return; }
    // Already one of this scale on this day: ask before saving a second.
    const earlier = same[same.length - 1];
    duplicate.hidden = false;
    duplicate.innerHTML = `<p id="scale-duplicate-q"><strong>${h('scales-duplicate', { scale: earlier.scale_name, day: isoDayWords(earlier.assessed_on) })}</strong> (${esc(scoreWords(earlier))}). ${h('scales-duplicate-ask')}</p>
      <p><button type="button" id="scale-replace">${h('scales-replace')}</button> <button type="button" class="secondary" id="scale-keep-both">${h('scales-keep-both')}</button>
      <button type="button" class="secondary" id="scale-cancel">${h('scales-cancel')}</button></p>`;
    const close = () => { duplicate.hidden = true; duplicate.innerHTML = ''; };
    duplicate.querySelector('#scale-replace').addEventListener('click', async () => { close(); await save(body, earlier); });
    duplicate.querySelector('#scale-keep-both').addEventListener('click', async () => { close(); await save(body, null); });
    duplicate.querySelector('#scale-cancel').addEventListener('click', () => { close(); result.className = ''; result.textContent = t('scales-not-saved'); });
    duplicate.querySelector('#scale-replace').focus();
  });
  return () => undo();
}
