// The live view's second panel: during a road exercise, the road and lane around the car from
// above (car-centred, heading up, at a fixed scale with a scale bar) with its recent path;
// during the dial task, the dial's target against the patient's wheel angle (nothing about
// lanes). The road comes from the station's summaries (`lane_width_m`, `road_left_m_<d>`: the
// road centre's offset to the car's left d m ahead along its heading); an older station that
// does not send it gets the path alone, drawn as before, and says so. The target is orange and
// dashed, the wheel blue, as in the tracking chart.

import { t, locale } from '/console/i18n.js';

/** A number for people in the console's language, `digits` decimals. */
const num = (v, digits) => new Intl.NumberFormat(locale(), { minimumFractionDigits: digits, maximumFractionDigits: digits }).format(v);

/** Distances ahead of the car the station gives the road at, m (PROTOCOL.md). */
export const AHEAD_M = [-20, -10, 0, 10, 20, 30, 40];
const BEHIND_SHOWN_M = 11, AHEAD_SHOWN_M = 31, SCALE_BAR_M = 10;

/** The road in a summary's `extra`: {lane, points: [[ahead, left], …]} or null. */
export function roadOf(x) {
  if (x.lane_width_m === undefined) return null;
  const points = AHEAD_M.filter(d => Number.isFinite(x[`road_left_m_${d}`])).map(d => [d, x[`road_left_m_${d}`]]);
  return points.length >= 2 ? { lane: x.lane_width_m, points } : null;
}

/** Sizes `canvas`'s drawing buffer to its laid-out size and clears it: [context, w, h]. */
export function fit(canvas) {
  const w = canvas.clientWidth || 300, h = canvas.clientHeight || 220;
  canvas.width = w; canvas.height = h;
  const g = canvas.getContext('2d');
  g.clearRect(0, 0, w, h);
  return [g, w, h];
}

/** Offsets of the polyline `pts` ([u, v] in pixels) by `off` pixels along its normals. */
function offset(pts, off) {
  return pts.map((p, i) => {
    const a = pts[Math.max(0, i - 1)], b = pts[Math.min(pts.length - 1, i + 1)];
    const du = b[0] - a[0], dv = b[1] - a[1], n = Math.hypot(du, dv) || 1;
    return [p[0] - dv / n * off, p[1] + du / n * off];
  });
}

function stroke(g, pts, style, width, dash = []) {
  g.strokeStyle = style; g.lineWidth = width; g.setLineDash(dash); g.lineJoin = 'round'; g.lineCap = 'round';
  g.beginPath();
  pts.forEach(([u, v], i) => (i ? g.lineTo(u, v) : g.moveTo(u, v)));
  g.stroke();
  g.setLineDash([]);
}

function car(g, u, v, yaw, size) {
  // A triangle pointing along `yaw` (screen angle, 0 = up).
  const p = (r, a) => [u + r * Math.sin(yaw + a), v - r * Math.cos(yaw + a)];
  g.fillStyle = '#d55e00'; g.strokeStyle = '#1b1b1b'; g.lineWidth = 1;
  g.beginPath(); g.moveTo(...p(size, 0)); g.lineTo(...p(size * 0.7, 2.5)); g.lineTo(...p(size * 0.7, -2.5)); g.closePath();
  g.fill(); g.stroke();
}

/** Draws the road panel for a summary; returns what the note under it says. */
export function drawRoad(canvas, cols, x, windowS) {
  const road = roadOf(x);
  canvas.dataset.mode = 'road';
  canvas.dataset.road = road ? '1' : '0';
  canvas.dataset.laneWidthM = road ? String(road.lane) : '';
  if (!road) return drawPath(canvas, cols, x, t('live-road-not-sent', { seconds: windowS }));
  const [g, w, h] = fit(canvas);
  const k = h / (BEHIND_SHOWN_M + AHEAD_SHOWN_M);             // px per m, fixed
  const u0 = w / 2, v0 = AHEAD_SHOWN_M * k;                    // the car
  const at = (ahead, left) => [u0 - left * k, v0 - ahead * k];
  const centre = road.points.map(([d, l]) => at(d, l));
  // The lane: its surface, both edges solid, the centre line dashed.
  stroke(g, centre, '#d0d0d0', road.lane * k);
  stroke(g, offset(centre, road.lane / 2 * k), '#4a4a4a', 2);
  stroke(g, offset(centre, -road.lane / 2 * k), '#4a4a4a', 2);
  stroke(g, centre, '#767676', 1, [6, 6]);
  // The car's recent path, turned into the car's frame.
  const yaw = x.car_yaw_rad || 0, cos = Math.cos(yaw), sin = Math.sin(yaw);
  const path = [];
  cols.x.forEach((px, i) => {
    if (px === null || cols.y[i] === null) return;
    const dx = px - x.car_x_m, dy = cols.y[i] - x.car_y_m;
    path.push(at(dx * cos + dy * sin, -dx * sin + dy * cos));
  });
  if (path.length > 1) stroke(g, path, '#0072b2', 3);
  car(g, u0, v0, 0, Math.max(9, 2.5 * k));
  // Scale bar, bottom left.
  const bar = SCALE_BAR_M * k, y = h - 12;
  g.strokeStyle = '#1b1b1b'; g.lineWidth = 2;
  g.beginPath(); g.moveTo(10, y - 5); g.lineTo(10, y); g.lineTo(10 + bar, y); g.lineTo(10 + bar, y - 5); g.stroke();
  g.fillStyle = '#1b1b1b'; g.font = '12px system-ui, sans-serif';
  g.fillText(`${num(SCALE_BAR_M, 0)} m`, 14 + bar, y);
  const under = x.road_left_m_0;
  canvas.dataset.scaleBarM = String(SCALE_BAR_M);
  const side = under === undefined ? '' : ' ' + t('live-road-car-side', {
    side: Math.abs(under) < 0.05 ? 'centre' : under < 0 ? 'left' : 'right', metres: num(Math.abs(under), 2) });
  return t('live-road-note', { lane: num(road.lane, 1), behind: BEHIND_SHOWN_M - 1, ahead: AHEAD_SHOWN_M - 1, bar: SCALE_BAR_M }) + side;
}

/** The path alone (an older station, a replay), fitted to the canvas; returns `what` with the
 * width shown. */
export function drawPath(canvas, cols, x, what) {
  const [g, w, h] = fit(canvas);
  const pts = cols.x.map((px, i) => [px, cols.y[i]]).filter(p => p[0] !== null);
  if (!pts.length) return t('live-path-none');
  const xs = pts.map(p => p[0]), ys = pts.map(p => p[1]);
  const cx = (Math.min(...xs) + Math.max(...xs)) / 2, cy = (Math.min(...ys) + Math.max(...ys)) / 2;
  const span = Math.max(20, Math.max(...xs) - Math.min(...xs), Math.max(...ys) - Math.min(...ys)) * 1.1;
  const k = Math.min(w, h) / span;
  const at = (px, py) => [w / 2 + (px - cx) * k, h / 2 - (py - cy) * k];
  stroke(g, pts.map(p => at(...p)), '#0072b2', 3);
  const [u, v] = at(x.car_x_m, x.car_y_m);
  car(g, u, v, Math.PI / 2 - (x.car_yaw_rad || 0), 12);
  return t('live-path-across', { what, metres: num(span, 0) });
}

/** The dial task: the target and the wheel as two hands on a dial; returns the note. */
export function drawDial(canvas, x) {
  canvas.dataset.mode = 'dial';
  canvas.dataset.road = '';
  canvas.dataset.laneWidthM = '';
  const [g, w, h] = fit(canvas);
  const r = Math.min(w, h) / 2 - 14, cu = w / 2, cv = h / 2 + 4;
  g.fillStyle = '#ffffff'; g.strokeStyle = '#4a4a4a'; g.lineWidth = 2;
  g.beginPath(); g.arc(cu, cv, r, 0, 2 * Math.PI); g.fill(); g.stroke();
  for (let deg = -180; deg < 180; deg += 30) {
    const a = deg * Math.PI / 180, inner = deg % 90 ? 0.93 : 0.86;
    g.beginPath(); g.moveTo(cu - r * inner * Math.sin(a), cv - r * inner * Math.cos(a));
    g.lineTo(cu - r * Math.sin(a), cv - r * Math.cos(a)); g.stroke();
  }
  // Positive angles turn left (anticlockwise), 0 straight up.
  const hand = (a, colour, width, dash) => stroke(g, [[cu, cv], [cu - r * 0.92 * Math.sin(a), cv - r * 0.92 * Math.cos(a)]], colour, width, dash);
  const target = x.wheel_target_rad, angle = x.wheel_angle_rad;
  if (Number.isFinite(target)) hand(target, '#e69f00', 5, [8, 5]);
  if (Number.isFinite(angle)) hand(angle, '#0072b2', 4);
  g.fillStyle = '#1b1b1b'; g.beginPath(); g.arc(cu, cv, 4, 0, 2 * Math.PI); g.fill();
  const deg = v => num(v * 180 / Math.PI, 0);
  if (!Number.isFinite(target) || !Number.isFinite(angle)) return t('live-dial-waiting');
  const off = (angle - target) * 180 / Math.PI;
  return t('live-dial-note', { target: deg(target), wheel: deg(angle), off: num(Math.abs(off), 0),
    side: Math.abs(off) < 0.5 ? 'on' : off > 0 ? 'left' : 'right' });
}
