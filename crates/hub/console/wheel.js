// The patient's wheel in the prescribe form (GET /api/patients/{id}'s `wheel`, told by their
// station in each Hello): the line that names it, and every torque bound of the form made the
// patient's own (never above the wheel's effective ceiling nor the schema's device maximum).
import { esc } from '/console/api.js';

const nm = x => `${Number(x.toFixed(2))} N·m`;

/** The wheel line (HTML, escaped) and `torque(spec)`: a torque field's schema bounds with the
 * patient's ceiling as its maximum. */
export function wheelBounds(wheel) {
  if (!wheel) {
    return {
      line: '<p id="rx-wheel">No wheel seen yet: bounds are the device maximum (the station caps them at its own wheel\'s ceiling).</p>',
      torque: spec => spec,
      ceiling: null,
    };
  }
  const ceiling = wheel.stated_ceiling_nm;
  const unknown = wheel.unknown ? ' (a model the station does not know: its force is kept low)' : '';
  return {
    line: `<p id="rx-wheel">Wheel: ${esc(wheel.model)}, rated ${esc(nm(wheel.rated_torque_nm))}, effective ceiling ${esc(nm(ceiling))}${esc(unknown)}.</p>`,
    torque: spec => ({ ...spec, max: spec.max === undefined ? ceiling : Math.min(spec.max, ceiling) }),
    ceiling,
  };
}
