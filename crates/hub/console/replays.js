// The Replay tab (issue 29): a patient's sessions newest first, by date and time and exercise
// name, each whose recording has fully arrived opening the replay view
// (#/patients/{id}/replay/{session}); one without its recording yet says so in words.
import { api, esc, when } from '/console/api.js';

/** Why a session cannot be replayed yet, in words. */
function notYet(s) {
  if (!s.closed_at_ms && !s.end_reason) return 'Still running: its recording arrives after the session ends.';
  return 'Its recording has not arrived yet (the station uploads it after the session, when it can reach the hub).';
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
      <td>${esc(s.exercise_name || s.exercise)}</td>
      <td>${s.recording_uploaded ? 'Recording ready: open it by its date and time.' : esc(notYet(s))}</td></tr>`;
  }).join('');
  const ready = sessions.filter(s => s.recording_uploaded).length;
  el.innerHTML = `<section class="panel" aria-labelledby="replays-h"><h2 id="replays-h">Replay a session</h2>
    <p class="note" id="replays-note">${sessions.length ? `${ready} of ${sessions.length} session${sessions.length === 1 ? '' : 's'} can be replayed from the recording the station uploaded: the arm, the car and the charts as they were, with play, pause and seek.`
      : 'No session yet: a session can be replayed once the station has uploaded its recording.'}</p>
    ${sessions.length ? `<table id="replays"><caption class="note">The patient's sessions, newest first</caption>
      <thead><tr><th scope="col">Started</th><th scope="col">Exercise</th><th scope="col">Recording</th></tr></thead>
      <tbody>${rows}</tbody></table>` : ''}</section>`;
  el.dataset.replays = String(ready);
}
