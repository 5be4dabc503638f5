// The therapist's notes on a session (crates/hub/API.md, "session notes"): the clinic's own
// record, never sent to the station. A "Note" per session in the Progress list and a panel on
// the per-exercise page. Every text is put in with textContent, never as HTML.
import { api, when } from '/console/api.js';
import { t } from '/console/i18n.js';

/** Most characters in a note (the hub counts characters, not bytes, and refuses more). */
export const MAX_NOTE_CHARS = 2000;

const el = (tag, props = {}, ...children) => {
  const node = Object.assign(document.createElement(tag), props);
  node.append(...children);
  return node;
};

/** The problem with `text` as the hub would name it, or '' (the hub checks again). */
export function noteProblem(text) {
  const chars = [...text].length;
  if (!text.trim()) return t('notes-empty');
  if (chars > MAX_NOTE_CHARS) return t('notes-too-long', { chars, max: MAX_NOTE_CHARS });
  // eslint-disable-next-line no-control-regex
  if (/[\u0000-\u0008\u000b\u000c\u000e-\u001f\u007f-\u009f]/.test(text)) return t('notes-control');
  return '';
}

let made = 0;

/** Session `sessionId`'s notes and a form to add one, into `box`; `label` names the session
 * for the form's field. */
export async function fillNotes(box, sessionId, label) {
  const n = ++made;
  const url = `/api/sessions/${encodeURIComponent(sessionId)}/notes`;
  const list = el('ul', { className: 'notes' });
  const text = el('textarea', { id: `note-text-${n}`, maxLength: MAX_NOTE_CHARS, rows: 2, className: 'note-text' });
  const result = el('p', { className: 'note-result' });
  result.setAttribute('role', 'status');
  const refresh = async () => {
    const notes = await api('GET', url);
    list.replaceChildren(...notes.map(m => el('li', { className: 'session-note' },
      el('span', { className: 'note-body', textContent: m.text }), ' ',
      el('span', { className: 'note', textContent: t('notes-by', { by: m.therapist_email || t('notes-by-gone'), when: when(m.created_at_ms) }) }))));
    if (!notes.length) list.append(el('li', { className: 'note', textContent: t('notes-none') }));
    box.dataset.notes = String(notes.length);
  };
  const form = el('form', { noValidate: true, className: 'note-form' },
    el('label', { htmlFor: text.id, textContent: t('notes-add-label', { session: label }) }),
    text, el('p', {}, el('button', { type: 'submit', textContent: t('notes-save') })));
  form.addEventListener('submit', async ev => {
    ev.preventDefault();
    const problem = noteProblem(text.value);
    result.className = `note-result${problem ? ' error' : ''}`;
    if (problem) { result.textContent = problem; return; }
    try {
      await api('POST', url, { text: text.value });
      text.value = '';
      result.textContent = t('notes-saved');
      await refresh();
    } catch (e) { result.className = 'note-result error'; result.textContent = e.message; }
  });
  box.replaceChildren(list, form, result);
  await refresh();
}

/** A session's "Note" cell for the Progress list (HTML; opened, it loads the notes):
 * `sessionId` and `label` (its date and time) escaped by the caller's `esc`. */
export function noteCell(sessionId, label, esc) {
  return `<details class="session-notes" data-session="${esc(sessionId)}" data-label="${esc(label)}"><summary>${esc(t('notes-cell'))}</summary><div></div></details>`;
}

/** Makes every "Note" cell under `root` load its notes the first time it is opened. */
export function bindNoteCells(root) {
  root.querySelectorAll('details.session-notes').forEach(d => d.addEventListener('toggle', () => {
    if (!d.open || d.dataset.loaded) return;
    d.dataset.loaded = '1';
    fillNotes(d.querySelector('div'), d.dataset.session, d.dataset.label).catch(e => {
      d.querySelector('div').textContent = e.message;
    });
  }));
}

/** The notes panel under the per-exercise page `page` of session `sessionId`. */
export async function notesSection(page, sessionId) {
  const box = el('div', { id: 'session-notes-box' });
  const section = el('section', { className: 'panel', id: 'session-notes' },
    el('h2', { id: 'session-notes-h', textContent: t('notes-heading') }), box);
  section.setAttribute('aria-labelledby', 'session-notes-h');
  page.append(section);
  await fillNotes(box, sessionId, t('notes-this-session'));
}
