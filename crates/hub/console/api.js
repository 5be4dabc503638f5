// The console API (crates/hub/API.md): JSON over same-origin HTTPS with the login cookie.
import { locale } from '/console/i18n.js';

export class ApiError extends Error {
  constructor(status, message) { super(message); this.status = status; }
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
  const text = await res.text();
  let data = null;
  try { data = text ? JSON.parse(text) : null; } catch { data = null; }
  if (!res.ok) {
    const error = new ApiError(res.status, (data && data.error) || `${res.status} ${res.statusText}`);
    const retry = Number(res.headers.get('Retry-After'));
    if (res.status === 429 && retry > 0) error.retryAfterS = retry;
    throw error;
  }
  return data;
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
