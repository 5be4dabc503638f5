// The console API (crates/hub/API.md): JSON over same-origin HTTPS with the login cookie.
import { has, languageTag, locale, t } from '/console/i18n.js';

export class ApiError extends Error {
  constructor(status, message) { super(message); this.status = status; }
}

/** Where the catalogue names the fields a refusal names: its own words, then the labels of
 * the clinic's thresholds and of the prescription form. */
const FIELD_WORDS = ['api-field-', 'attention-setting-', 'prescribe-field-'];

/** A name the hub gives in a refusal (`field`: `snooze_until_ms`; `what`: `session`) in the
 * console's words (`<prefix><name>`, `_` and spaces as `-`, the first prefix that has it),
 * else as the hub wrote it. */
function named(prefixes, name) {
  const tail = String(name).toLowerCase().replace(/[^a-z0-9]+/g, '-');
  const id = prefixes.map(p => p + tail).find(has);
  return id ? t(id) : String(name);
}

/** Why the hub refused (`why`: `{code, args}`, crates/hub-store/src/refusal.rs) in the console's
 * words (`api-why-<code>`), or null when the answer has none the catalogue knows. */
function whyWords(why) {
  const id = why && typeof why.code === 'string' ? `api-why-${why.code}` : null;
  if (!id || !has(id)) return null;
  const args = { ...(why.args || {}) };
  if (args.field !== undefined) args.field = named(FIELD_WORDS, args.field);
  if (args.what !== undefined) args.what = named(['api-thing-'], args.what);
  return t(id, args);
}

/** A refusal in the console's language: why the hub refused (`why`, worded from the
 * catalogue), else the catalogue's sentence for `status` (`api-error-<status>`, else
 * `api-error-other`). The hub writes `detail` in English; an English console shows the hub's
 * own words, which may say more (the value refused). */
export function refusalWords(status, detail, retryAfterS, why) {
  if (languageTag() === 'en' && detail) return detail;
  const words = whyWords(why);
  if (words) return words;
  const id = `api-error-${status}`;
  return has(id) ? t(id, { seconds: retryAfterS ?? 1 }) : t('api-error-other');
}

/** The hub's refusal `res` (not ok) as an ApiError in the console's words. */
export async function refusal(res) {
  let data = null;
  try { data = await res.json(); } catch { data = null; }
  const retry = Number(res.headers.get('Retry-After'));
  const retryAfterS = [429, 503].includes(res.status) && retry > 0 ? retry : undefined;
  const detail = (data && data.error) || `${res.status} ${res.statusText}`;
  const why = data && typeof data.why === 'object' ? data.why : null;
  const error = new ApiError(res.status, refusalWords(res.status, detail, retryAfterS, why));
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
