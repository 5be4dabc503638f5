// One session's results exercise by exercise (GET /api/sessions/{id}/exercises): a column per
// exercise, a row per result any of them has, "—" where one does not apply. Every value
// escaped; the session's totals stay in the progress view.
import { api, esc, when } from '/console/api.js';
import { endText, headerWords, measureWords, numberWords, plainName } from '/console/words.js';
import { t, locale } from '/console/i18n.js';

/** The results shown, in order: key, and for the haptic sweep's levels (not measures of the
 * patient, so not in the words table) its plain label, unit and decimals; every other result's
 * words come from the ONE table of measure words. */
const RESULTS = [
  ['rms_lateral_m'],
  ['pct_in_lane'],
  ['heading_rms_error_deg'],
  ['cone_hits'],
  ['completion_time_s'],
  ['tracking_rms_error_deg'],
  ['dial_mean_abs_error_deg'],
  ['dial_rms_error_deg'],
  ['strength_peak_left_nm'],
  ['strength_sustained_left_nm'],
  ['strength_peak_right_nm'],
  ['strength_sustained_right_nm'],
  ['sweep_spring_nm_per_rad', 'exercises-sweep-spring', 'N·m/rad', 3],
  ['sweep_damper_nm_s_per_rad', 'exercises-sweep-damper', 'N·m·s/rad', 3],
  ['sweep_inertia_kg_m2', 'exercises-sweep-inertia', 'kg·m²', 4],
  ['sweep_frequency_rad_s', 'exercises-sweep-frequency', 'rad/s', 2],
  ['movements'],
  ['active_pct'],
  ['sparc_median'],
  ['ldlj_median'],
  ['movement_peak_speed_deg_s_median'],
  ['wheel_rom_deg'],
  ['shoulder_elevation_rom_deg'],
  ['elbow_flexion_rom_deg'],
];

/** The per-exercise table of session `sessionId` of patient `patientId`, into `el`. */
export async function exercisesView(el, patientId, sessionId) {
  const enc = encodeURIComponent;
  const [session, exercises] = await Promise.all([
    api('GET', `/api/sessions/${enc(sessionId)}`),
    api('GET', `/api/sessions/${enc(sessionId)}/exercises`),
  ]);
  const words = await measureWords();
  // How it ended in the one wording of every page, in the console's language.
  const ended = session.end_kind || session.end_reason ? endText(session) : t(session.closed_at_ms ? 'exercises-ended' : 'exercises-running');
  const head = `<h2 id="exercises-h">${esc(t('exercises-heading', { when: when(session.started_unix_ms) }))}</h2>
    <p class="note">${esc(ended)} · <a href="#/patients/${enc(patientId)}/progress">${esc(t('exercises-back'))}</a></p>`;
  if (!exercises.length) {
    el.innerHTML = `${head}<p>${esc(t('exercises-none'))}</p>`;
    return;
  }
  const whole = new Intl.NumberFormat(locale(), { maximumFractionDigits: 0 });
  const cols = exercises.map(e => `<th scope="col">${esc(t('exercises-column', { n: e.index + 1, name: plainName(e.kind) }))}</th>`).join('');
  const time = exercises.map(e => `<td class="num" data-active-s="${esc(e.active_s)}" data-prescribed-s="${esc(e.prescribed_s)}">${esc(t('exercises-time-cell', { active: whole.format(e.active_s), prescribed: whole.format(e.prescribed_s) }))}</td>`).join('');
  const rows = RESULTS.filter(([key]) => exercises.some(e => typeof e.scores[key] === 'number'))
    .map(([key, label, unit, digits]) => {
      const m = words.measures.get(key) || { name: t(label), unit, decimals: digits };
      const cells = exercises.map(e => `<td class="num">${esc(numberWords(m, e.scores[key]))}</td>`).join('');
      return `<tr data-key="${esc(key)}"><th scope="row">${esc(headerWords(m))}</th>${cells}</tr>`;
    }).join('');
  el.innerHTML = `${head}
    <section class="panel" aria-labelledby="exercises-h">
      <table id="exercise-results"><caption class="note">${esc(t('exercises-caption'))}</caption>
        <thead><tr><th scope="col">${esc(t('exercises-col-result'))}</th>${cols}</tr></thead>
        <tbody><tr data-key="time"><th scope="row">${esc(t('exercises-time-row'))}</th>${time}</tr>${rows}</tbody></table>
    </section>`;
  el.dataset.exercises = String(exercises.length);
}
