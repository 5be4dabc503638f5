// One session's results exercise by exercise (GET /api/sessions/{id}/exercises): a column per
// exercise, a row per result any of them has, "—" where one does not apply. Every value
// escaped; the session's totals stay in the progress view.
import { api, esc, when } from '/console/api.js';

/** The results shown, in order: key, plain label, unit, decimals. */
const RESULTS = [
  ['rms_lateral_m', 'Lane keeping error (RMS lateral deviation)', 'm', 3],
  ['pct_in_lane', 'Time in lane', '%', 1],
  ['heading_rms_error_deg', 'Heading error (RMS)', '°', 1],
  ['cone_hits', 'Cones hit', '', 0],
  ['completion_time_s', 'Completion time', 's', 1],
  ['tracking_rms_error_deg', 'Tracking error, wheel to the ideal angle (RMS)', '°', 2],
  ['dial_mean_abs_error_deg', 'Dial angle error, mean absolute (as the thesis\'s Appendix E)', '°', 2],
  ['dial_rms_error_deg', 'Dial angle error (RMS)', '°', 2],
  ['strength_peak_left_nm', 'Strength pushing left, peak', 'N·m', 2],
  ['strength_sustained_left_nm', 'Strength pushing left, held 1 s', 'N·m', 2],
  ['strength_peak_right_nm', 'Strength pushing right, peak', 'N·m', 2],
  ['strength_sustained_right_nm', 'Strength pushing right, held 1 s', 'N·m', 2],
  ['sweep_spring_nm_per_rad', 'Haptic sweep: the spring stiffness of this level', 'N·m/rad', 3],
  ['sweep_damper_nm_s_per_rad', 'Haptic sweep: the damping of this level', 'N·m·s/rad', 3],
  ['sweep_inertia_kg_m2', 'Haptic sweep: the added weight (inertia) of this level', 'kg·m²', 4],
  ['sweep_frequency_rad_s', 'Haptic sweep: how fast the dial moves (frequency) at this level', 'rad/s', 2],
  ['movements', 'Movements', '', 0],
  ['active_pct', 'Time moving', '%', 0],
  ['sparc_median', 'Smoothness, SPARC (median; closer to 0 is smoother)', '', 2],
  ['ldlj_median', 'Smoothness, LDLJ (median)', '', 2],
  ['movement_peak_speed_deg_s_median', 'Peak speed of a movement (median)', '°/s', 0],
  ['wheel_rom_deg', 'Wheel range of motion', '°', 0],
  ['shoulder_elevation_rom_deg', 'Shoulder elevation range', '°', 0],
  ['elbow_flexion_rom_deg', 'Elbow flexion range', '°', 0],
];

/** The per-exercise table of session `sessionId` of patient `patientId`, into `el`. */
export async function exercisesView(el, patientId, sessionId) {
  const enc = encodeURIComponent;
  const [session, exercises] = await Promise.all([
    api('GET', `/api/sessions/${enc(sessionId)}`),
    api('GET', `/api/sessions/${enc(sessionId)}/exercises`),
  ]);
  const ended = session.end_reason ? `ended: ${session.end_reason}` : (session.closed_at_ms ? 'ended' : 'running');
  const head = `<h2 id="exercises-h">Session of ${esc(when(session.started_unix_ms))}, exercise by exercise</h2>
    <p class="note">${esc(ended)} · <a href="#/patients/${enc(patientId)}/progress">Back to the progress</a></p>`;
  if (!exercises.length) {
    el.innerHTML = `${head}<p>No results per exercise: the station that ran this session was older than them, or the session did not end in order.</p>`;
    return;
  }
  const cols = exercises.map(e => `<th scope="col">${esc(e.index + 1)}. ${esc(e.name)}</th>`).join('');
  const time = exercises.map(e => `<td class="num">${esc(e.active_s.toFixed(1))} of ${esc(e.prescribed_s.toFixed(0))}</td>`).join('');
  const rows = RESULTS.filter(([key]) => exercises.some(e => typeof e.scores[key] === 'number'))
    .map(([key, label, unit, digits]) => {
      const cells = exercises.map(e => {
        const v = e.scores[key];
        return `<td class="num">${typeof v === 'number' ? esc(v.toFixed(digits)) : '—'}</td>`;
      }).join('');
      return `<tr data-key="${esc(key)}"><th scope="row">${esc(label)}${unit ? ` (${esc(unit)})` : ''}</th>${cells}</tr>`;
    }).join('');
  el.innerHTML = `${head}
    <section class="panel" aria-labelledby="exercises-h">
      <table id="exercise-results"><caption class="note">Each exercise's own results; the session's totals are in the progress view.</caption>
        <thead><tr><th scope="col">Result</th>${cols}</tr></thead>
        <tbody><tr data-key="time"><th scope="row">Time: active of prescribed (s)</th>${time}</tr>${rows}</tbody></table>
    </section>`;
  el.dataset.exercises = String(exercises.length);
}
