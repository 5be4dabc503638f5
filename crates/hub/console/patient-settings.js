// The patient's station settings in the prescribe form (issue 40): the regimen's `[patient]`
// table (crates/regimen/src/patient.rs) — the language of the station's screens and voice, the
// side of space the patient neglects, speech on or off and its volume, the countdown after a
// rest. They travel with the prescription (the same PUT that saves the exercises); the saved
// prescription says them in words. Bounds come from the regimen's schema.
import { esc } from '/console/api.js';
import { t } from '/console/i18n.js';

/** The station's languages (i18n::LANGUAGES), each named in its own language: a patient or
 * relative finds theirs whatever the console's language. */
export const STATION_LANGUAGES = [
  { tag: 'en', name: 'English' },
  { tag: 'de', name: 'Deutsch' },
  { tag: 'es', name: 'Español' },
  { tag: 'zh', name: '中文（简体）' },
];
const SIDES = ['none', 'left', 'right'];
const DEFAULT_VOLUME_PCT = 80;

/** The `[patient]` fieldset (HTML) for `p` (the regimen's `patient`, maybe undefined);
 * `numberField` is the form's, `spec` the schema's bounds (patientFields). */
export function patientFieldset(p, spec, numberField) {
  const s = p || {};
  const side = SIDES.includes(s.neglected_side) ? s.neglected_side : 'none';
  const languages = [`<option value="">${esc(t('patient-language-station'))}</option>`,
    ...STATION_LANGUAGES.map(l => `<option value="${esc(l.tag)}" lang="${esc(l.tag)}"${s.language === l.tag ? ' selected' : ''}>${esc(l.name)}</option>`)].join('');
  const sides = SIDES.map(v => `<p class="choice"><input type="radio" name="rx-p-side" id="rx-p-side-${v}" value="${v}"${side === v ? ' checked' : ''} aria-describedby="rx-p-side-${v}-note">
      <label for="rx-p-side-${v}" class="inline"><strong>${esc(t(`patient-side-${v}`))}</strong></label>
      <span class="note" id="rx-p-side-${v}-note">${esc(t(`patient-side-${v}-note`))}</span></p>`).join('');
  const volume = spec ? spec.volume : { min: 0, max: 100, integer: true };
  const countdown = spec ? spec.startAfterRest : { min: 0, max: 60 };
  return `<fieldset class="panel" id="rx-patient"><legend>${esc(t('patient-legend'))}</legend>
    <p class="note">${esc(t('patient-intro'))}</p>
    <label for="rx-p-language">${esc(t('patient-language-label'))}</label>
    <select id="rx-p-language" data-language-now="${esc(s.language || '')}">${languages}</select>
    <fieldset class="sides" id="rx-p-side" data-side-now="${esc(side)}"><legend>${esc(t('patient-side-legend'))}</legend>${sides}</fieldset>
    <p><input type="checkbox" id="rx-p-speech"${s.speech === false ? '' : ' checked'}>
      <label for="rx-p-speech" class="inline">${esc(t('patient-speech-label'))}</label></p>
    ${numberField('rx-p-volume', t('patient-volume-label'), s.speech_volume_pct, { ...volume, integer: true, default: DEFAULT_VOLUME_PCT })}
    ${numberField('rx-p-countdown', t('patient-countdown-label'), s.start_after_rest_s, { ...countdown, default: t('patient-countdown-wait') })}
  </fieldset>`;
}

/** Reads the fieldset into `model.patient` (`num(sel)` the form's number reader): no table
 * when every setting is the station's default and the regimen had none. */
export function readPatient(el, model, num) {
  const before = model.patient || {};
  const p = {};
  const language = el.querySelector('#rx-p-language').value;
  if (language) p.language = language;
  const side = el.querySelector('input[name="rx-p-side"]:checked');
  p.neglected_side = side ? side.value : 'none';
  const speech = el.querySelector('#rx-p-speech').checked;
  // Speech is on by default: written only when turned off, or when the regimen said so.
  if (!speech) p.speech = false; else if (before.speech === true) p.speech = true;
  const volume = num('#rx-p-volume');
  if (volume !== undefined) p.speech_volume_pct = Math.round(volume);
  const countdown = num('#rx-p-countdown');
  if (countdown !== undefined) p.start_after_rest_s = countdown;
  const onlyDefaults = Object.keys(p).length === 1 && p.neglected_side === 'none';
  if (onlyDefaults && !model.patient) delete model.patient; else model.patient = p;
}

/** The saved settings in one sentence for the prescription's heading. */
export function patientWords(p) {
  const s = p || {};
  const lang = STATION_LANGUAGES.find(l => l.tag === s.language);
  return t('patient-saved-words', {
    language: lang ? lang.name : t('patient-language-station'),
    side: SIDES.includes(s.neglected_side) ? s.neglected_side : 'none',
    speech: s.speech === false ? 'off' : 'on',
    volume: s.speech_volume_pct ?? DEFAULT_VOLUME_PCT,
    countdown: s.start_after_rest_s === undefined ? 'wait' : 'count',
    seconds: s.start_after_rest_s ?? 0,
  });
}
