// The therapist's messages to a patient (crates/hub/API.md, "messages"): a short note shown on
// the start card of the patient's next session, and when it was sent and seen. Every text is
// put in with textContent, never as HTML.
import { api, when } from '/console/api.js';
import { t } from '/console/i18n.js';

/** Most characters in a message (the hub counts characters, not bytes, and refuses more). */
export const MAX_MESSAGE_CHARS = 500;

/** The problem with `text` as the hub would name it, or '' (the hub checks again). */
export function messageProblem(text) {
  const chars = [...text].length;
  if (!text.trim()) return t('messages-empty');
  if (chars > MAX_MESSAGE_CHARS) return t('messages-too-long', { chars, max: MAX_MESSAGE_CHARS });
  // eslint-disable-next-line no-control-regex
  if (/[\u0000-\u001f\u007f-\u009f]/.test(text)) return t('messages-control');
  return '';
}

/** Posts `text` to patient `id`; the stored message. */
export function sendMessage(id, text) {
  return api('POST', `/api/patients/${encodeURIComponent(id)}/messages`, { text });
}

const el = (tag, props = {}, ...children) => {
  const node = Object.assign(document.createElement(tag), props);
  node.append(...children);
  return node;
};

/** The messages panel of patient `id` in `section`: the form and the list, newest first. */
export async function messagesPanel(section, id) {
  section.replaceChildren();
  section.className = 'panel print-hide';
  section.setAttribute('aria-labelledby', 'msg-h');
  const list = el('ol', { id: 'msg-list', className: 'messages' });
  const text = el('textarea', { id: 'msg-text', maxLength: MAX_MESSAGE_CHARS, rows: 2 });
  const count = el('span', { id: 'msg-count', className: 'note' });
  const result = el('p', { id: 'msg-result' });
  result.setAttribute('role', 'alert');
  const refresh = async () => {
    const messages = await api('GET', `/api/patients/${encodeURIComponent(id)}/messages`);
    list.replaceChildren(...messages.map(m => el('li', { className: 'message' },
      el('span', { className: 'message-text', textContent: m.text }), ' ',
      el('span', { className: 'note', textContent: t('messages-sent-at', { when: when(m.created_at_ms) }) }), ' · ',
      el('span', {
        className: m.seen_at_ms == null ? 'message-unseen note' : 'message-seen',
        textContent: m.seen_at_ms == null ? t('messages-not-seen') : t('messages-seen-at', { when: when(m.seen_at_ms) }),
      }))));
    if (!messages.length) list.append(el('li', { className: 'note', textContent: t('messages-none') }));
    section.dataset.messages = String(messages.length);
  };
  const counted = () => {
    const chars = [...text.value].length;
    count.textContent = t('messages-count', { chars, max: MAX_MESSAGE_CHARS });
    count.dataset.chars = String(chars);
  };
  text.addEventListener('input', counted);
  counted();
  const form = el('form', { id: 'msg-form', noValidate: true },
    el('label', { htmlFor: 'msg-text', textContent: t('messages-label') }),
    text, count,
    el('p', {}, el('button', { type: 'submit', textContent: t('messages-send') }), ' ',
      el('button', { type: 'button', id: 'msg-refresh', className: 'secondary', textContent: t('messages-refresh') })));
  form.addEventListener('submit', async ev => {
    ev.preventDefault();
    const problem = messageProblem(text.value);
    result.className = problem ? 'error' : '';
    if (problem) { result.textContent = problem; return; }
    try {
      await sendMessage(id, text.value);
      text.value = '';
      counted();
      result.textContent = t('messages-sent');
      await refresh();
    } catch (e) { result.className = 'error'; result.textContent = e.message; }
  });
  form.querySelector('#msg-refresh').addEventListener('click', () => refresh().catch(e => {
    result.className = 'error'; result.textContent = e.message;
  }));
  section.append(el('h2', { id: 'msg-h', textContent: t('messages-heading') }), form, result, list);
  await refresh();
  return refresh;
}
