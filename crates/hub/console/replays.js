// The Replay tab (issue 29): a patient's sessions newest first, by date and time and exercise
// name, each whose recording has fully arrived opening the replay view
// (#/patients/{id}/replay/{session}); one without its recording yet says so in words.
import { api, esc, when } from '/console/api.js';
import { t } from '/console/i18n.js';
import { exercisesWords } from '/console/words.js';

/** A recording on its way with no part noted for this long, ms, has stopped arriving: the
 * hub's `RECORDING_STALLED_AFTER_MS` (crates/hub-store/src/db/words.rs). */
const STALLED_AFTER_MS = 10 * 60 * 1000;

/** Why a session cannot be replayed yet, in words. */
function notYet(s) {
  const lastPart = s.recording_last_part_ms;
  if (s.recording_arriving_percent != null && lastPart != null && Date.now() - lastPart > STALLED_AFTER_MS) {
    return t('replay-list-stalled', { percent: s.recording_arriving_percent, at: when(lastPart) });
  }
  if (s.recording_arriving_percent != null) {
    return t('replay-list-arriving', { percent: s.recording_arriving_percent });
  }
  if (!s.closed_at_ms && !s.end_reason) return t('replay-list-running');
  return t('replay-list-not-arrived');
}

/** The list of patient `id`'s sessions to replay, in `el`. */
export async function replayList(el, id) {
  const sessions = await api('GET', `/api/patients/${encodeURIComponent(id)}/sessions`);
  const pid = encodeURIComponent(id);
  const rows = sessions.map(s => {
    const started = esc(when(s.started_unix_ms));
    const open = s.recording_uploaded
      ? `<a href="#/patients/${pid}/replay/${encodeURIComponent(s.session_id)}">${started}</a>`
      : started;
    return `<tr data-recording="${s.recording_uploaded ? '1' : '0'}"><th scope="row">${open}</th>
      <td>${esc(exercisesWords(s))}</td>
      <td>${esc(s.recording_uploaded ? t('replay-list-ready') : notYet(s))}</td></tr>`;
  }).join('');
  const ready = sessions.filter(s => s.recording_uploaded).length;
  el.innerHTML = `<section class="panel" aria-labelledby="replays-h"><h2 id="replays-h">${esc(t('replay-list-heading'))}</h2>
    <p class="note" id="replays-note">${esc(sessions.length ? t('replay-list-note', { ready, count: sessions.length }) : t('replay-list-none'))}</p>
    ${sessions.length ? `<table id="replays"><caption class="note">${esc(t('replay-list-caption'))}</caption>
      <thead><tr><th scope="col">${esc(t('replay-list-col-started'))}</th><th scope="col">${esc(t('replay-list-col-exercise'))}</th><th scope="col">${esc(t('replay-list-col-recording'))}</th></tr></thead>
      <tbody>${rows}</tbody></table>` : ''}</section>`;
  el.dataset.replays = String(ready);
}
