// The patient's wheel in the prescribe form (GET /api/patients/{id}'s `wheel`, told by their
// station in each Hello): the line that names it, and every torque bound of the form made the
// patient's own (never above the wheel's effective ceiling nor the schema's device maximum).
import { esc } from '/console/api.js';
import { t, locale } from '/console/i18n.js';

const nm = x => `${new Intl.NumberFormat(locale(), { maximumFractionDigits: 2 }).format(x)} N·m`;

/** The wheel line (HTML, escaped) and `torque(spec)`: a torque field's schema bounds with the
 * patient's ceiling as its maximum. */
export function wheelBounds(wheel) {
  if (!wheel) {
    return {
      line: `<p id="rx-wheel" data-ceiling-nm="">${esc(t('wheel-none'))}</p>`,
      torque: spec => spec,
      ceiling: null,
    };
  }
  const ceiling = wheel.stated_ceiling_nm;
  return {
    line: `<p id="rx-wheel" data-ceiling-nm="${esc(ceiling)}">${esc(t('wheel-line', { model: wheel.model, rated: nm(wheel.rated_torque_nm), ceiling: nm(ceiling), known: wheel.unknown ? 'no' : 'yes' }))}</p>`,
    torque: spec => ({ ...spec, max: spec.max === undefined ? ceiling : Math.min(spec.max, ceiling) }),
    ceiling,
  };
}
