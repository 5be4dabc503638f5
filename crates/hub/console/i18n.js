// The console's words (issue 40): Project Fluent catalogues (crates/i18n/console/<lang>/*.ftl)
// served by the hub as one text a language at /console/l10n/<tag>.ftl, formatted here with
// Fluent's JS package (vendored). The language is the therapist's choice, kept on the hub
// (GET/PUT /api/me/language), else the best match of the browser's languages, else English.
// A message missing from a language falls back to English, then to its id (logged once).
import { FluentBundle, FluentResource } from '/console/vendor/fluent-bundle-0.19.1/index.js';

/** The languages on offer, each named in its own language (English first, the fallback). */
const OFFERED = [
  { tag: 'en', name: 'English' },
  { tag: 'de', name: 'Deutsch' },
  { tag: 'es', name: 'Español' },
  { tag: 'zh', name: '简体中文' },
];
const FALLBACK = 'en';
const PSEUDO = 'en-XA';

let current = FALLBACK;
let bundle = null;
let english = null;
const loaded = new Map();
const missing = new Set();
const listeners = [];

async function load(tag) {
  if (!loaded.has(tag)) {
    const p = fetch(`/console/l10n/${encodeURIComponent(tag)}.ftl`, { credentials: 'same-origin' })
      .then(async res => {
        if (!res.ok) throw new Error(`${res.status}: ${await res.text()}`);
        const b = new FluentBundle(tag === PSEUDO ? 'en' : tag, { useIsolating: false });
        const errors = b.addResource(new FluentResource(await res.text()));
        errors.forEach(e => console.warn(`console words ${tag}:`, e));
        return b;
      });
    loaded.set(tag, p);
    p.catch(() => loaded.delete(tag));
  }
  return loaded.get(tag);
}

/** The offered language that best matches `wanted` (BCP 47 tags, most wanted first):
 * the pseudo-locale when asked for, else by primary language; English when none matches. */
export function bestLanguage(wanted) {
  for (const w of wanted || []) {
    if (!w) continue;
    if (w.toLowerCase() === PSEUDO.toLowerCase()) return PSEUDO;
    const primary = w.toLowerCase().split(/[-_]/)[0];
    const hit = OFFERED.find(l => l.tag === primary);
    if (hit) return hit.tag;
  }
  return FALLBACK;
}

/** The languages on offer: [{tag, name}], each named in its own language. */
export function languages() {
  return OFFERED.map(l => ({ ...l }));
}

/** The BCP 47 tag in force (for Intl.DateTimeFormat / NumberFormat). */
export function locale() {
  return current === PSEUDO ? 'en' : current;
}

/** The tag in force as chosen (`en-XA` for the pseudo-locale). */
export function languageTag() {
  return current;
}

/** Calls `fn(tag)` after every change of language (screens re-render). */
export function onLanguageChange(fn) {
  listeners.push(fn);
}

/** Puts `tag` in force (loading its words and English's), sets `<html lang>` and fills the
 * page's `data-l10n-id` elements. An unknown or unloadable tag leaves English in force. */
export async function useLanguage(tag) {
  english = await load(FALLBACK);
  try {
    bundle = await load(tag);
    current = tag;
  } catch (e) {
    console.warn(`console words: ${tag} could not be loaded, English instead:`, e);
    bundle = english;
    current = FALLBACK;
  }
  document.documentElement.lang = current;
  translate(document);
  listeners.forEach(fn => fn(current));
  return current;
}

/** Chooses and loads the language before the first screen renders: the therapist's choice on
 * the hub when logged in, else the browser's languages' best match, else English.
 * `{signedIn: false}` when the caller knows no one is logged in (no request to the hub). */
export async function startLanguage({ signedIn = true } = {}) {
  let chosen = null;
  if (signedIn) {
    try {
      const res = await fetch('/api/me/language', { credentials: 'same-origin' });
      if (res.ok) chosen = (await res.json()).language;
    } catch { /* offline: the browser's language */ }
  }
  return useLanguage(chosen || bestLanguage(navigator.languages || [navigator.language]));
}

/** Keeps `tag` as the therapist's language on the hub (null: follow the browser) and puts it
 * in force. */
export async function chooseLanguage(tag) {
  const res = await fetch('/api/me/language', {
    method: 'PUT', credentials: 'same-origin',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ language: tag }),
  });
  if (!res.ok) {
    let message = `${res.status}`;
    try { message = (await res.json()).error || message; } catch { /* plain answer */ }
    throw new Error(message);
  }
  return useLanguage(tag || bestLanguage(navigator.languages || [navigator.language]));
}

function formatIn(b, id, args) {
  if (!b) return null;
  const [name, attr] = id.split('.');
  const m = b.getMessage(name);
  if (!m) return null;
  const pattern = attr ? m.attributes[attr] : m.value;
  if (!pattern) return null;
  const errors = [];
  const text = b.formatPattern(pattern, args, errors);
  if (errors.length && !missing.has(`${id}!`)) {
    missing.add(`${id}!`);
    console.warn(`console words: ${id} in ${b.locales[0]}:`, errors);
  }
  return text;
}

/** True when a catalogue (the language in force, or English) has message `id`. */
export function has(id) {
  return Boolean(bundle?.hasMessage(id) || english?.hasMessage(id));
}

/** Message `id` (or `id.attribute`) with `args`, in the language in force; English when the
 * language lacks it; the id itself when no catalogue has it (logged once). */
export function t(id, args = {}) {
  const text = formatIn(bundle, id, args) ?? formatIn(english, id, args);
  if (text !== null) return text;
  if (!missing.has(id)) {
    missing.add(id);
    console.warn(`console words: no message ${id}`);
  }
  return id;
}

/** Fills every element under `root` carrying `data-l10n-id` (arguments from the JSON of
 * `data-l10n-args`): its text, and the attributes named in `data-l10n-attrs`
 * ("aria-label,title") from the message's attributes of those names. */
export function translate(root) {
  const els = [];
  if (root.nodeType === 1 && root.hasAttribute('data-l10n-id')) els.push(root);
  root.querySelectorAll('[data-l10n-id]').forEach(el => els.push(el));
  for (const el of els) {
    const id = el.getAttribute('data-l10n-id');
    let args = {};
    const raw = el.getAttribute('data-l10n-args');
    if (raw) { try { args = JSON.parse(raw); } catch { console.warn(`console words: bad data-l10n-args on ${id}`); } }
    const attrs = (el.getAttribute('data-l10n-attrs') || '').split(',').map(s => s.trim()).filter(Boolean);
    for (const a of attrs) el.setAttribute(a, t(`${id}.${a}`, args));
    const hasValue = (bundle && bundle.getMessage(id)?.value) || (english && english.getMessage(id)?.value);
    if (hasValue || !attrs.length) el.textContent = t(id, args);
  }
}
