// The regimen's JSON Schema (GET /api/regimen/schema, derived from the regimen's Rust types
// with the validator's bounds): what the prescribe form may offer — exercise kinds, their
// fields, descriptions and ranges — read from it, none written here.
import { api } from '/console/api.js';

let cached = null;

/** The schema, fetched once per page. */
export async function regimenSchema() {
  if (!cached) cached = api('GET', '/api/regimen/schema').catch(e => { cached = null; throw e; });
  return cached;
}

/** `s` with its `$ref` followed (the referenced definition, with the referring object's own
 * keywords beside it) and its `allOf` parts merged in. */
function resolve(root, s) {
  if (!s || typeof s !== 'object') return {};
  let out = { ...s };
  if (out.$ref) {
    const name = out.$ref.replace(/^#\/\$defs\//, '');
    const { $ref, ...rest } = out;
    void $ref;
    out = merge(resolve(root, root.$defs[name]), rest);
  }
  for (const part of out.allOf || []) out = merge(out, resolve(root, part));
  return out;
}

function merge(a, b) {
  const out = { ...a, ...b };
  if (a.properties || b.properties) out.properties = { ...(a.properties || {}), ...(b.properties || {}) };
  return out;
}

/** The non-null alternative of an optional value (`anyOf: [x, {type: null}]`). */
function nonNull(root, s) {
  const r = resolve(root, s);
  const alt = (r.anyOf || r.oneOf || []).find(a => resolve(root, a).type !== 'null');
  return alt && !r.properties ? resolve(root, alt) : r;
}

const types = s => [].concat(s.type || []);
const isNumeric = s => types(s).some(t => t === 'number' || t === 'integer');

/** A numeric field's bounds as the form uses them: `min`, `max` (either may be undefined),
 * `integer`, the `default` and the description. */
export function numberSpec(root, s) {
  const r = nonNull(root, s);
  return {
    min: r.minimum ?? r.exclusiveMinimum,
    max: r.maximum ?? r.exclusiveMaximum,
    integer: types(r).includes('integer'),
    default: r.default,
    description: r.description || '',
  };
}

/** The exercise kinds a regimen may list, in the schema's order: `{kind, description,
 * fields}`, `fields` the kind's numeric fields as [name, numberSpec]. */
export function exerciseKinds(root) {
  const entry = resolve(root, root.properties.exercise.items);
  const variants = (entry.oneOf || entry.anyOf || []).map(v => resolve(root, v));
  return variants.filter(v => v.properties && v.properties.kind && v.properties.kind.const).map(v => ({
    kind: v.properties.kind.const,
    description: v.description || '',
    fields: Object.entries(v.properties)
      .filter(([name, p]) => name !== 'kind' && isNumeric(nonNull(root, p)))
      .map(([name, p]) => [name, numberSpec(root, p)]),
  }));
}

/** The regimen-wide fields: sessions a week, the haptic ceiling of an exercise, how many
 * exercises, and the longest planned session (s). */
export function regimenLimits(root) {
  const entry = resolve(root, root.properties.exercise.items);
  const haptic = nonNull(root, entry.properties.haptic);
  return {
    sessionsPerWeek: numberSpec(root, root.properties.sessions_per_week),
    // How often the station runs the standard assessment first (`[assessment] every_days`).
    assessmentEveryDays: root.properties.assessment
      ? numberSpec(root, nonNull(root, root.properties.assessment).properties.every_days) : null,
    // The trunk's excursion that brings the gentle cue to sit up (`[trunk] cue_deg`).
    trunkCueDeg: root.properties.trunk
      ? numberSpec(root, nonNull(root, root.properties.trunk).properties.cue_deg) : null,
    ceiling: numberSpec(root, haptic.properties.ceiling_nm),
    maxExercises: root.properties.exercise.maxItems,
    maxPlannedS: root['x-max-planned-session-s'],
  };
}

/** The `[difficulty]` table's numeric fields (the therapist's bounds on a difficulty that
 * follows the patient) as [name, numberSpec], and the aspects it may change. */
export function difficultyFields(root) {
  const d = root.properties.difficulty ? nonNull(root, root.properties.difficulty) : null;
  if (!d || !d.properties) return null;
  const changes = resolve(root, d.properties.changes.items);
  return {
    fields: ['target_success', 'lowest', 'highest', 'start'].filter(n => d.properties[n])
      .map(n => [n, numberSpec(root, d.properties[n])]),
    aspects: (changes.enum || (changes.oneOf || []).map(v => resolve(root, v).const)).filter(Boolean),
  };
}

/** The assistance modes an exercise may prescribe (`[exercise.assist.mode]`), in the schema's
 * order: `{kind, description, fields}`, `fields` the mode's numeric fields as [name, numberSpec]
 * and `motion` the numeric fields of its motion part (a hybrid's), if any. */
export function assistModes(root) {
  const entry = resolve(root, root.properties.exercise.items);
  if (!entry.properties || !entry.properties.assist) return [];
  const spec = nonNull(root, entry.properties.assist);
  const mode = resolve(root, spec.properties && spec.properties.mode);
  const numeric = v => Object.entries(v.properties || {})
    .filter(([name, p]) => name !== 'kind' && isNumeric(nonNull(root, p)))
    .map(([name, p]) => [name, numberSpec(root, p)]);
  return (mode.oneOf || mode.anyOf || []).map(v => resolve(root, v))
    .filter(v => v.properties && v.properties.kind && v.properties.kind.const)
    .map(v => ({
      kind: v.properties.kind.const,
      description: v.description || '',
      fields: numeric(v),
      motion: v.properties.motion ? numeric(nonNull(root, v.properties.motion)) : [],
    }));
}

/** The per-exercise settings every kind shares: `rest` (the rest after it, s) as a numberSpec. */
export function entryFields(root) {
  const entry = resolve(root, root.properties.exercise.items);
  const rest = entry.properties && entry.properties.rest_s;
  return { rest: rest ? numberSpec(root, rest) : { min: 0, description: '' } };
}

/** The dial's swing (its target's `sine` signal): `amplitude` (deg each way) and `frequency`
 * (rad/s) as numberSpecs; null when the schema has no such signal. */
export function dialSineFields(root) {
  const signal = root.$defs && root.$defs.DialSignal;
  if (!signal) return null;
  const sine = (signal.oneOf || signal.anyOf || []).map(v => resolve(root, v))
    .find(v => v.properties && v.properties.signal && v.properties.signal.const === 'sine');
  if (!sine) return null;
  return { amplitude: numberSpec(root, sine.properties.amplitude_deg), frequency: numberSpec(root, sine.properties.frequency_rad_s) };
}

/** The `[patient]` table's numeric fields (the voice's volume, %, and the countdown after a
 * rest, s) as numberSpecs; null when the schema has no such table. */
export function patientFields(root) {
  const p = root.properties.patient ? nonNull(root, root.properties.patient) : null;
  if (!p || !p.properties) return null;
  return {
    volume: numberSpec(root, p.properties.speech_volume_pct),
    startAfterRest: numberSpec(root, p.properties.start_after_rest_s),
  };
}
