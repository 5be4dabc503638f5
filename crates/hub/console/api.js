// The console API (crates/hub/API.md): JSON over same-origin HTTPS with the login cookie.
import { languageTag, locale, t } from '/console/i18n.js';

export class ApiError extends Error {
  constructor(status, message) { super(message); this.status = status; }
}

/** Statuses whose answer names what was refused (a field, a line, a thing): the hub's own
 * words follow the catalogue's sentence. */
const DETAILED = [400, 404, 409, 413, 422];

/** A refusal in the console's language: the catalogue's sentence for `status`
 * (`api-error-<status>`, else `api-error-other`), with the hub's `detail` where it names what
 * was refused. The hub writes English; an English console shows its words as they are. */
export function refusalWords(status, detail, retryAfterS) {
  if (languageTag() === 'en') return detail;
  const id = `api-error-${status}`;
  const said = t(id, { seconds: retryAfterS ?? 1 });
  const lead = said === id ? t('api-error-other') : said;
  return DETAILED.includes(status) && detail ? t('api-error-detail', { lead, detail }) : lead;
}

/** The hub's refusal `res` (not ok) as an ApiError in the console's words. */
export async function refusal(res) {
  let data = null;
  try { data = await res.json(); } catch { data = null; }
  const retry = Number(res.headers.get('Retry-After'));
  const retryAfterS = [429, 503].includes(res.status) && retry > 0 ? retry : undefined;
  const detail = (data && data.error) || `${res.status} ${res.statusText}`;
  const error = new ApiError(res.status, refusalWords(res.status, detail, retryAfterS));
  error.detail = detail;
  if (retryAfterS) error.retryAfterS = retryAfterS;
  return error;
}

export async function api(method, path, body) {
  const init = { method, credentials: 'same-origin', headers: {} };
  if (body === undefined && method !== 'GET' && method !== 'HEAD') body = {};
  if (body !== undefined) {
    // Every change is sent as JSON: a type no cross-site form or `no-cors` request can send,
    // which the hub requires (e.g. of POST /api/logout).
    init.headers['Content-Type'] = 'application/json';
    init.body = JSON.stringify(body);
  }
  const res = await fetch(path, init);
  if (res.status === 204) return null;
  if (!res.ok) throw await refusal(res);
  const text = await res.text();
  try { return text ? JSON.parse(text) : null; } catch { return null; }
}

/** Text made safe to put into HTML. */
export function esc(s) {
  return String(s ?? '').replace(/[&<>"']/g, c => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;' }[c]));
}

/** A date and time for people in the language in force, from milliseconds since the epoch. */
export function when(ms) {
  if (ms == null) return '—';
  return new Date(ms).toLocaleString(locale(), { dateStyle: 'medium', timeStyle: 'short' });
}
