// The prescribe form in clinical terms (issue 41): each exercise in minutes, sets and a rest
// after each set, at an easy / medium / hard level (GET /api/regimen/presets, defined in the
// regimen crate beside the validator) whose engineering settings sit under "details"; the
// dial's range and pace in degrees and seconds with words. Every bound comes from the
// regimen's schema (GET /api/regimen/schema); the hub checks the whole regimen again with the
// station's validator. Sets are the same exercise repeated: saved as that many exercises, each
// with the rest after it, and read back as one row when consecutive exercises are the same.
import { api, esc, when } from '/console/api.js';
import { difficultyFields, exerciseKinds, regimenLimits, regimenSchema, entryFields, dialSineFields } from '/console/schema.js';
import { messageProblem, sendMessage } from '/console/messages.js';
import { assistModes, assistFields, readAssist } from '/console/assist.js';
import { wheelBounds } from '/console/wheel.js';
import { displayName } from '/console/names.js';
import { t, locale } from '/console/i18n.js';
import { patientFieldset, readPatient, patientWords } from '/console/patient-settings.js';
import { patientFields } from '/console/schema.js';

/** Most sets of one exercise the form offers. */
const MAX_SETS = 10;
/** Longest pace of a dial swing the form offers, s. */
const MAX_PACE_S = 120;
const LEVELS = ['easy', 'medium', 'hard'];
/** A catalogue message, else `fallback` (words the hub sent that the catalogue lacks). */
const tOr = (id, fallback, args) => { const w = t(id, args); return w === id ? fallback : w; };
/** A preset's words in the console's language (the hub's English when the catalogue lacks it). */
const presetWords = p => tOr(`prescribe-preset-${p.kind}-${p.level}`, p.words);
/** A number for people in the console's language. */
const number = (x, digits = 1) => new Intl.NumberFormat(locale(), { maximumFractionDigits: digits }).format(x);

let presetsCache = null;
/** The presets, fetched once per page. */
function regimenPresets() {
  if (!presetsCache) presetsCache = api('GET', '/api/regimen/presets').catch(e => { presetsCache = null; throw e; });
  return presetsCache;
}

const clone = v => JSON.parse(JSON.stringify(v));
/** Whether two JSON values are the same (objects compared key by key, in any order). */
function same(a, b) {
  if (a === b) return true;
  if (typeof a !== 'object' || typeof b !== 'object' || a === null || b === null) return false;
  if (Array.isArray(a) !== Array.isArray(b)) return false;
  const ka = Object.keys(a), kb = Object.keys(b);
  return ka.length === kb.length && ka.every(k => same(a[k], b[k]));
}

/** The regimen's exercises as the form's rows: consecutive identical exercises are one row
 * of that many sets. */
export function toRows(exercises) {
  const rows = [];
  for (const e of exercises) {
    const last = rows[rows.length - 1];
    if (last && same(last.e, e) && last.sets < MAX_SETS) last.sets += 1;
    else rows.push({ e: clone(e), sets: 1 });
  }
  return rows;
}

/** The form's rows as the regimen's exercises. */
export function fromRows(rows) {
  return rows.flatMap(r => Array.from({ length: r.sets }, () => clone(r.e)));
}

/** A number input with its bounds from the regimen's schema (enforced by the browser, shown
 * beside it). An empty field leaves the setting at its default, shown as the placeholder. */
export function numberField(id, label, value, spec, extra = '') {
  const range = spec.min === undefined && spec.max === undefined ? ''
    : `<span class="note">(${spec.min ?? '…'}–${spec.max ?? '…'})</span>`;
  const attr = (name, v) => (v === undefined ? '' : ` ${name}="${esc(v)}"`);
  return `<label for="${id}">${esc(label)} ${range}</label>
    <input id="${id}" type="number"${attr('min', spec.min)}${attr('max', spec.max)} step="${spec.integer ? 1 : 'any'}"
      value="${esc(value ?? '')}"${attr('placeholder', spec.default)} inputmode="decimal" data-field${extra}>`;
}

/** A field's label: the catalogue's (`prescribe-field-<name>`, in the console's language),
 * else its schema description's first sentence (it names the unit), for a field this console
 * has no words for yet. */
const labelOf = (name, spec) => tOr(`prescribe-field-${name.replaceAll('_', '-')}`,
  (spec.description.split(/\.\s|\n/)[0] || name).replace(/\.$/, '').replace(/[`[\]]/g, ''));
/** An exercise kind's name for a therapist: the catalogue's, else the words before the colon
 * of its schema description ("Sine road: …"), else the kind itself. */
export const kindName = k => (!k ? '' : tOr(`prescribe-kind-${k.kind}`,
  k.description.includes(':') ? k.description.split(':')[0] : k.kind));

/** The dial's range as a word the catalogue selects on. */
function rangeWords(deg) {
  if (deg <= 45) return 'small';
  if (deg <= 90) return 'quarter';
  return 'more';
}
/** The dial's pace as a word the catalogue selects on. */
function paceWords(s) {
  if (s >= 10) return 'slow';
  if (s >= 5) return 'moderate';
  return 'brisk';
}
const round1 = x => Math.round(x * 10) / 10;
/** One swing there and back, s, of a sine at `w` rad/s. */
const paceOf = w => (w > 0 ? round1(2 * Math.PI / w) : undefined);

/** The dial's target as a sine's range and pace (undefined when it is another shape). */
function dialSine(e) {
  const ref = e.reference || { signal: 'sine', amplitude_deg: 120, frequency_rad_s: 1 };
  return ref.signal === 'sine' ? ref : undefined;
}

/** The dial's range and pace in one sentence. */
export function dialWords(amplitudeDeg, paceS) {
  if (!(amplitudeDeg >= 0) || !(paceS > 0)) return '';
  return t('prescribe-dial-words', { degrees: number(Math.round(amplitudeDeg), 0), range: rangeWords(amplitudeDeg),
    seconds: number(round1(paceS)), pace: paceWords(paceS) });
}

/** An exercise's settings that are not its kind's own: what a level never changes. */
const GENERIC = new Set(['kind', 'duration_s', 'rest_s', 'haptic', 'assist', 'pedals']);

/** The preset of `presets` (for `e.kind`) whose settings `e` has, or undefined. */
function levelOf(e, presets) {
  const own = Object.fromEntries(Object.entries(e).filter(([k]) => !GENERIC.has(k)));
  if (e.kind === 'dial' && !own.reference) own.reference = { signal: 'sine', amplitude_deg: 120, frequency_rad_s: 1 };
  return presets.find(p => {
    const fields = Object.fromEntries(Object.entries(p.fields).filter(([k]) => !GENERIC.has(k)));
    return p.kind === e.kind && same(fields, own);
  });
}

/** Exercise `e` set to `preset`'s settings (its time, sets, rest, torque and assistance kept). */
function applyPreset(e, preset) {
  for (const k of Object.keys(e)) if (!GENERIC.has(k)) delete e[k];
  for (const [k, v] of Object.entries(preset.fields)) if (!GENERIC.has(k)) e[k] = clone(v);
}

export async function prescribeView(el, id, refreshMessages, me) {
  const [r, schema, patient, presets] = await Promise.all([
    api('GET', `/api/patients/${encodeURIComponent(id)}/regimen`), regimenSchema(),
    api('GET', `/api/patients/${encodeURIComponent(id)}`), regimenPresets()]);
  // The patient's own bounds: their wheel's ceiling, never above the schema's device maximum.
  const wheel = wheelBounds(patient.wheel);
  const modes = assistModes(schema);
  const kinds = exerciseKinds(schema);
  const limits = regimenLimits(schema);
  const adapt = difficultyFields(schema);
  const entry = entryFields(schema);
  const dial = dialSineFields(schema);
  const patient_spec = patientFields(schema);
  const cur = r.current;
  const model = r.current_fields || { exercise: [] };
  let rows = toRows(Array.isArray(model.exercise) ? model.exercise : []);
  el.id = 'prescribe';
  const kindOf = e => kinds.find(k => k.kind === e.kind);
  const exercisesNow = () => rows.reduce((n, row) => n + row.sets, 0);

  const levelFields = (i, e) => {
    const mine = presets.filter(p => p.kind === e.kind);
    if (!mine.length) return '';
    const at = levelOf(e, presets);
    const radios = mine.map(p => `<p class="choice"><input type="radio" name="ex${i}-level" id="ex${i}-level-${esc(p.level)}" value="${esc(p.level)}" data-level="${i}"${at === p ? ' checked' : ''}>
      <label for="ex${i}-level-${esc(p.level)}" class="inline"><strong>${esc(LEVELS.includes(p.level) ? t(`prescribe-level-${p.level}`) : p.level)}</strong>: ${esc(presetWords(p))}</label></p>`).join('');
    const own = at ? '' : `<p class="choice"><input type="radio" name="ex${i}-level" id="ex${i}-level-own" value="" checked disabled>
      <label for="ex${i}-level-own" class="inline"><strong>${esc(t('prescribe-level-own'))}</strong>: ${esc(t('prescribe-level-own-note'))}</label></p>`;
    return `<fieldset class="levels" id="ex${i}-levels" data-level-now="${esc(at ? at.level : 'own')}"><legend>${esc(t('prescribe-levels-legend'))}</legend>${radios}${own}</fieldset>`;
  };

  const timeFields = (i, row, k) => {
    const e = row.e;
    const duration = k && k.fields.find(([n]) => n === 'duration_s');
    let minutes = '';
    if (duration) {
      const spec = duration[1];
      const road = !['dial'].includes(e.kind);
      const shown = e.duration_s === undefined ? undefined : Math.round(e.duration_s / 60 * 100) / 100;
      minutes = numberField(`ex${i}-minutes`, t('prescribe-minutes-label'), shown,
        { min: 0.1, max: spec.max / 60, default: road ? t('prescribe-minutes-road') : (spec.default === undefined ? undefined : spec.default / 60) },
        ` data-initial="${esc(shown ?? '')}"`);
    }
    const sets = numberField(`ex${i}-sets`, t('prescribe-sets-label'), row.sets, { min: 1, max: MAX_SETS, integer: true });
    const rest = numberField(`ex${i}-rest`, t('prescribe-rest-label'), e.rest_s, { ...entry.rest, default: t('prescribe-rest-default') });
    return `<div class="dose">${minutes}${sets}${rest}</div>`;
  };

  const dialFields = (i, e) => {
    if (e.kind !== 'dial' || !dial) return '';
    const sine = dialSine(e);
    if (!sine) return `<p class="note">${esc(t('prescribe-dial-other'))}</p>`;
    const pace = paceOf(sine.frequency_rad_s);
    const fast = dial.frequency.max > 0 ? Math.ceil(2 * Math.PI / dial.frequency.max * 10) / 10 : 0.1;
    return `<div class="dose">${numberField(`ex${i}-dial-range`, t('prescribe-dial-range-label'), sine.amplitude_deg, { ...dial.amplitude, default: undefined }, ` data-initial="${esc(sine.amplitude_deg)}"`)}
      ${numberField(`ex${i}-dial-pace`, t('prescribe-dial-pace-label'), pace, { min: fast, max: MAX_PACE_S }, ` data-initial="${esc(pace ?? '')}"`)}</div>
      <p class="note" id="ex${i}-dial-words">${esc(dialWords(sine.amplitude_deg, pace))}</p>`;
  };

  const render = () => {
    const html = rows.map((row, i) => {
      const e = row.e;
      const k = kindOf(e);
      const details = k ? k.fields.filter(([name]) => name !== 'duration_s')
        .map(([name, spec]) => numberField(`ex${i}-${name}`, labelOf(name, spec), e[name], spec)).join('') : '';
      const ref = e.kind === 'dial' && dialSine(e) ? `<p class="note">${esc(t('prescribe-dial-sine', { degrees: number(dialSine(e).amplitude_deg, 2), rate: number(dialSine(e).frequency_rad_s, 4) }))}</p>` : '';
      return `
      <fieldset class="panel" data-exercise="${i}"><legend>${esc(t('prescribe-exercise-legend', { n: i + 1, name: kindName(k) || e.kind }))}</legend>
        ${k ? '' : `<p class="note">${esc(t('prescribe-kind-unknown'))}</p>`}
        ${levelFields(i, e)}
        ${timeFields(i, row, k)}
        ${dialFields(i, e)}
        ${numberField(`ex${i}-ceiling`, t('prescribe-ceiling-label'), e.haptic && e.haptic.ceiling_nm, wheel.torque({ ...limits.ceiling, default: undefined }))}
        ${['dial', 'strength', 'haptic-sweep'].includes(e.kind) ? '' : `<p><input type="checkbox" id="ex${i}-pedals"${e.pedals ? ' checked' : ''}>
          <label for="ex${i}-pedals" class="inline">${esc(t('prescribe-pedals-label'))}</label></p>`}
        ${assistFields(i, e.assist, modes, numberField, esc)}
        ${details || ref ? `<details class="exercise-details" id="ex${i}-details"><summary>${esc(t('prescribe-details-summary'))}</summary>${ref}${details}</details>` : ''}
        <p><button type="button" class="secondary" data-remove="${i}">${esc(t('prescribe-remove', { n: i + 1 }))}</button></p>
      </fieldset>`;
    }).join('');
    const full = exercisesNow() >= limits.maxExercises;
    el.innerHTML = `
    <section class="panel" aria-labelledby="rx-h"><h2 id="rx-h">${esc(t('prescribe-heading'))}</h2>
      <p id="rx-version" data-version="${esc(cur ? cur.version : '')}">${esc(cur ? t('prescribe-version', { version: cur.version, by: r.current_prescribed_by_email || t('prescribe-version-gone'), when: when(cur.prescribed_at_ms) }) : t('prescribe-version-none'))}</p>
      ${cur ? `<p id="rx-patient-words" data-language="${esc((model.patient && model.patient.language) || '')}" data-side="${esc((model.patient && model.patient.neglected_side) || 'none')}" data-speech="${model.patient && model.patient.speech === false ? 'off' : 'on'}">${esc(patientWords(model.patient))}</p>` : ''}
      ${wheel.line}
      <form id="rx-form" novalidate>
        ${numberField('rx-sessions', t('prescribe-sessions-label'), model.sessions_per_week, { ...limits.sessionsPerWeek, default: undefined })}
        ${limits.assessmentEveryDays ? numberField('rx-assessment-days', t('prescribe-assessment-label'), model.assessment && model.assessment.every_days, { ...limits.assessmentEveryDays, default: undefined }) : ''}
        ${limits.trunkCueDeg ? numberField('rx-trunk-cue', t('prescribe-trunk-cue-label'), model.trunk && model.trunk.cue_deg, { ...limits.trunkCueDeg, default: undefined }) : ''}
        ${patientFieldset(model.patient, patient_spec, numberField)}
        ${adapt ? difficultyForm(model.difficulty, adapt) : ''}
        ${html || `<p>${esc(t('prescribe-no-exercise'))}</p>`}
        <p id="rx-total" class="note"></p>
        <label for="rx-add">${esc(t('prescribe-add-label'))}</label>
        <select id="rx-add">${kinds.map(k => `<option value="${esc(k.kind)}">${esc(kindName(k))}</option>`).join('')}</select>
        <button type="button" class="secondary" id="rx-add-btn"${full ? ' disabled' : ''}>${esc(t('prescribe-add-button'))}</button>
        ${full ? `<p class="note">${esc(t('prescribe-full', { max: limits.maxExercises }))}</p>` : ''}
        <p class="note" id="rx-message-note">${esc(t('prescribe-message-note', { name: displayName(patient.pseudonym) }))}</p>
        <p><button type="submit">${esc(t('prescribe-save'))}</button></p>
      </form>
      <p id="rx-result" role="alert"></p>
      <details id="rx-toml"><summary>${esc(t('prescribe-text-summary'))}</summary>
        <form id="rx">
          <label for="toml">${esc(t('prescribe-text-label'))}</label>
          <textarea id="toml" spellcheck="false" lang="en">${esc(cur ? cur.toml : '')}</textarea>
          <p><button type="submit">${esc(t('prescribe-text-save'))}</button></p>
        </form>
      </details>
      <h3>${esc(t('prescribe-bounds-heading'))}</h3>
      <dl class="bounds" id="bounds" data-ceiling-nm="${esc(wheel.ceiling ?? limits.ceiling.max)}">
        <dt>${esc(t('prescribe-bounds-ceiling'))}</dt><dd>${esc(t('prescribe-bounds-ceiling-text', { nm: number(wheel.ceiling ?? limits.ceiling.max, 2), wheel: wheel.ceiling == null ? 'consumer' : 'patient' }))}</dd>
        <dt>${esc(t('prescribe-bounds-slew'))}</dt><dd>${esc(t('prescribe-bounds-slew-text'))}</dd>
        <dt>${esc(t('prescribe-bounds-session'))}</dt><dd>${esc(t('prescribe-bounds-session-text', { max: limits.maxExercises, minutes: Math.round(limits.maxPlannedS / 60) }))}</dd>
        <dt>${esc(t('prescribe-bounds-levels'))}</dt><dd>${esc(t('prescribe-bounds-levels-text'))}</dd>
        <dt>${esc(t('prescribe-bounds-other'))}</dt><dd>${esc(t('prescribe-bounds-other-text'))}</dd>
      </dl>
      <p class="note">${esc(t('prescribe-bounds-note'))}</p>
    </section>`;
    bind();
    total();
  };

  /** The planned minutes of the timed exercises and their rests, in words (the last
   * exercise's rest is not run: the session ends). */
  const total = () => {
    const all = fromRows(rows);
    let minutes = 0, rests = 0, untimed = 0;
    all.forEach((e, i) => {
      if (typeof e.duration_s === 'number') minutes += e.duration_s / 60; else untimed += 1;
      if (i < all.length - 1) rests += (e.rest_s || 0) / 60;
    });
    const out = el.querySelector('#rx-total');
    if (!all.length) { out.textContent = ''; return; }
    out.textContent = t('prescribe-total', { minutes: number(round1(minutes)), rests: number(round1(rests)), untimed });
  };

  const out = () => el.querySelector('#rx-result');
  const messageBox = () => document.getElementById('msg-text');
  const save = async (body, note = '') => {
    out().className = ''; out().textContent = t('prescribe-saving');
    const problem = note && messageProblem(note);
    if (problem) { out().className = 'error'; out().textContent = t('prescribe-message-problem', { problem }); return; }
    try {
      const v = await api('PUT', `/api/patients/${encodeURIComponent(id)}/regimen`, body);
      if (note) {
        await sendMessage(id, note);
        const box = messageBox();
        if (box) { box.value = ''; box.dispatchEvent(new Event('input')); }
        await refreshMessages();
      }
      const again = await api('GET', `/api/patients/${encodeURIComponent(id)}/regimen`);
      for (const key of Object.keys(model)) delete model[key];
      Object.assign(model, again.current_fields);
      rows = toRows(model.exercise || []);
      render();
      out().textContent = t('prescribe-saved', { version: v.version, message: note ? 'yes' : 'no' });
      out().dataset.saved = String(v.version);
      el.querySelector('#rx-version').textContent = t('prescribe-version-now', { version: v.version, by: me.email });
      el.querySelector('#rx-version').dataset.version = String(v.version);
    } catch (e) {
      out().className = 'error';
      out().textContent = e.message;
    }
  };
  const num = sel => { const v = el.querySelector(sel); return v && v.value !== '' ? Number(v.value) : undefined; };
  const readForm = () => {
    const sessions = num('#rx-sessions');
    if (sessions === undefined) delete model.sessions_per_week; else model.sessions_per_week = sessions;
    // Empty: no standard assessment scheduled.
    const assessDays = limits.assessmentEveryDays ? num('#rx-assessment-days') : undefined;
    if (assessDays === undefined) delete model.assessment; else model.assessment = { ...(model.assessment || {}), every_days: assessDays };
    // Empty: no cue to sit up.
    const cueDeg = limits.trunkCueDeg ? num('#rx-trunk-cue') : undefined;
    if (cueDeg === undefined) delete model.trunk; else model.trunk = { ...(model.trunk || {}), cue_deg: cueDeg };
    readPatient(el, model, num);
    if (adapt) readDifficulty(el, model, adapt, num);
    rows.forEach((row, i) => {
      const e = row.e;
      const k = kindOf(e);
      for (const [name] of k ? k.fields : []) {
        if (name === 'duration_s') continue;
        const v = num(`#ex${i}-${name}`);
        if (v === undefined) delete e[name]; else e[name] = v;
      }
      // Minutes are shown rounded: written back only where the therapist changed them.
      const minutesInput = el.querySelector(`#ex${i}-minutes`);
      if (minutesInput && minutesInput.value !== minutesInput.dataset.initial) {
        const minutes = num(`#ex${i}-minutes`);
        if (minutes === undefined) delete e.duration_s; else e.duration_s = Math.round(minutes * 60 * 10) / 10;
      }
      row.sets = Math.max(1, Math.min(MAX_SETS, Math.round(num(`#ex${i}-sets`) ?? 1)));
      const rest = num(`#ex${i}-rest`);
      if (rest === undefined) delete e.rest_s; else e.rest_s = rest;
      readDial(i, e);
      const ceiling = num(`#ex${i}-ceiling`);
      if (ceiling === undefined) { if (e.haptic) delete e.haptic.ceiling_nm; } else { e.haptic = { ...(e.haptic || {}), ceiling_nm: ceiling }; }
      if (e.haptic && !Object.keys(e.haptic).length) delete e.haptic;
      readAssist(el, i, e, num);
      const pedals = el.querySelector(`#ex${i}-pedals`);
      if (pedals && pedals.checked) e.pedals = true; else delete e.pedals;
    });
    model.exercise = fromRows(rows);
  };
  /** The dial's range and pace into its sine, only where the therapist changed them (a pace
   * shown rounded is not written back). */
  const readDial = (i, e) => {
    const range = el.querySelector(`#ex${i}-dial-range`), pace = el.querySelector(`#ex${i}-dial-pace`);
    if (!range || !pace) return;
    const sine = { ...dialSine(e) };
    if (range.value !== range.dataset.initial && range.value !== '') sine.amplitude_deg = Number(range.value);
    if (pace.value !== pace.dataset.initial && Number(pace.value) > 0) sine.frequency_rad_s = Math.round(2 * Math.PI / Number(pace.value) * 1e4) / 1e4;
    if (!same(sine, dialSine(e))) e.reference = { signal: 'sine', amplitude_deg: sine.amplitude_deg, frequency_rad_s: sine.frequency_rad_s };
  };
  const bind = () => {
    el.querySelector('#rx-form').addEventListener('submit', ev => {
      ev.preventDefault();
      const form = ev.target;
      if (!form.checkValidity()) { form.reportValidity(); out().className = 'error'; out().textContent = t('prescribe-out-of-bounds'); return; }
      readForm();
      if (model.exercise.length > limits.maxExercises) {
        out().className = 'error';
        out().textContent = t('prescribe-too-many', { count: model.exercise.length, max: limits.maxExercises });
        return;
      }
      const box = messageBox();
      save({ fields: model }, box ? box.value : '');
    });
    el.querySelector('#rx-add-btn').addEventListener('click', () => {
      readForm();
      const kind = el.querySelector('#rx-add').value;
      const e = { kind };
      const medium = presets.find(p => p.kind === kind && p.level === 'medium');
      if (medium) applyPreset(e, medium);
      rows.push({ e, sets: 1 });
      render();
    });
    el.querySelectorAll('[data-level]').forEach(radio => radio.addEventListener('change', () => {
      readForm();
      const row = rows[Number(radio.dataset.level)];
      const preset = presets.find(p => p.kind === row.e.kind && p.level === radio.value);
      if (preset) applyPreset(row.e, preset);
      render();
      const again = el.querySelector(`#${radio.id}`);
      if (again) again.focus();
    }));
    el.querySelectorAll('[id$="-dial-range"], [id$="-dial-pace"]').forEach(input => input.addEventListener('input', () => {
      const i = input.id.match(/^ex(\d+)-/)[1];
      const words = el.querySelector(`#ex${i}-dial-words`);
      if (words) words.textContent = dialWords(num(`#ex${i}-dial-range`), num(`#ex${i}-dial-pace`));
    }));
    el.querySelectorAll('[id$="-minutes"], [id$="-sets"], [id$="-rest"]').forEach(input => input.addEventListener('change', () => { readForm(); total(); }));
    el.querySelectorAll('[data-assist]').forEach(s => s.addEventListener('change', () => { readForm(); render(); }));
    el.querySelectorAll('[data-remove]').forEach(b => b.addEventListener('click', () => {
      readForm();
      rows.splice(Number(b.dataset.remove), 1);
      model.exercise = fromRows(rows);
      render();
    }));
    el.querySelector('#rx').addEventListener('submit', ev => {
      ev.preventDefault();
      save({ toml: el.querySelector('#toml').value });
    });
  };
  render();
}

/** The prescribe form's `[difficulty]` fields: adapt on or off, the bounds (from the schema),
 * and what the difficulty changes. */
function difficultyForm(d, adapt) {
  const on = !!d;
  const fields = adapt.fields.map(([name, spec]) => numberField(`rx-d-${name}`,
    tOr(`prescribe-difficulty-${name}`, labelOf(name, spec)), d && d[name], spec)).join('');
  const changes = d && d.changes ? d.changes : adapt.aspects;
  const boxes = adapt.aspects.map(a => `<label><input type="checkbox" id="rx-d-change-${esc(a)}" data-aspect="${esc(a)}"${changes.includes(a) ? ' checked' : ''}> ${esc(tOr(`prescribe-aspect-${a}`, a))}</label>`).join(' ');
  return `<fieldset class="panel" id="rx-difficulty"><legend>${esc(t('prescribe-difficulty-legend'))}</legend>
    <label><input type="checkbox" id="rx-d-adapt"${on && d.adapt !== false ? ' checked' : ''}> ${esc(t('prescribe-difficulty-adapt'))}</label>
    ${fields}
    <p>${esc(t('prescribe-difficulty-changes'))} ${boxes}</p>
    <p class="note">${esc(t('prescribe-difficulty-note'))}</p>
  </fieldset>`;
}

/** Reads the `[difficulty]` fields into `model` (none when adaptation is off and no bound set). */
function readDifficulty(el, model, adapt, num) {
  const on = el.querySelector('#rx-d-adapt').checked;
  const d = {};
  for (const [name] of adapt.fields) { const v = num(`#rx-d-${name}`); if (v !== undefined) d[name] = v; }
  const changes = [...el.querySelectorAll('[data-aspect]')].filter(b => b.checked).map(b => b.dataset.aspect);
  if (!on && !Object.keys(d).length) { delete model.difficulty; return; }
  d.adapt = on;
  if (changes.length !== adapt.aspects.length) d.changes = changes;
  model.difficulty = d;
}
