// The tools, built from GET /api/ops: each op type's tools (a gesture and how
// the op's values are made from it, marblevideo.ops.gestures) and settings.
// This module evaluates the same expressions as Python's gestures.evaluate; it
// reads neither the page nor the store (the toolbar and gestures do).
import { round1 } from "./values.js";

const each = (f, v) => (Array.isArray(v) ? v.map((x) => each(f, x)) : f(v));

// 1.25 turns clockwise on screen, from the left of c going up (a French curl).
function loop(c, r) {
  const pts = [];
  for (let k = 0; k <= 40; k++) {
    const ang = Math.PI + 2.5 * Math.PI * k / 40;
    pts.push([round1(c[0] + r * Math.cos(ang)), round1(c[1] + r * Math.sin(ang))]);
  }
  return pts;
}

export const OPERATIONS = {
  mul: (a) => a.reduce((x, y) => x * y),
  add: (a) => a.reduce((x, y) => x + y),
  div: ([x, y]) => x / y,
  sub: ([x, y]) => x - y,
  min: (a) => Math.min(...a),
  max: (a) => Math.max(...a),
  abs: Math.abs,
  round1: (v) => each(round1, v),
  positive: (v) => Math.max(0.1, round1(v)),  // a size: to 0.1, at least 0.1
  or: ([x, y]) => (x !== 0 ? x : y),  // the first unless it is 0
  loop: ([c, r]) => loop(c, r),
  centred: ([n, s]) => [...Array(n).keys()].map((k) => (k - (n - 1) / 2) * s),
};

// "a", "a.0", "setting.width", "op.spacing.1": a measure or an item of one.
export function lookup(env, name) {
  const [first, ...rest] = name.split(".");
  let value = env[first];
  if (value === undefined) throw new Error(`tool expression: no measure ${first}`);
  for (const part of rest) value = value[Array.isArray(value) ? Number(part) : part];
  return value;
}

export function evaluate(expr, env) {
  if (typeof expr === "number") return expr;
  if (typeof expr === "string") return lookup(env, expr);
  if (Array.isArray(expr)) return expr.map((x) => evaluate(x, env));
  const [[op, args]] = Object.entries(expr);
  if (op === "clicked") return evaluate(env.clicked ? args[0] : args[1], env);
  return OPERATIONS[op](evaluate(args, env));
}

// The measures of a gesture from canvas point a to b on a canvas whose smaller
// side is ``side``, drawn at ``scale`` frame pixels per canvas unit; ``more``:
// color, inks, seed, path, setting (marblevideo.ops.gestures.gesture_env).
export function gestureEnv(a, b, side, scale, more = {}) {
  let dx = b[0] - a[0], dy = b[1] - a[1], len = Math.hypot(dx, dy);
  const clicked = len < 3 / scale;
  if (clicked) { dx = side / 10; dy = 0; len = side / 10; }
  const angle = round1(Math.atan2(dy, dx) * 180 / Math.PI);
  const tip = [a[0] + dx, a[1] + dy];
  return {a, b, dx, dy, len, tip, clicked, angle, side, pi: Math.PI, ...more};
}

// The op ``tool`` makes in the gesture ``env``, its values in ``make``'s order.
export function makeOp(tool, env) {
  const op = {type: tool.type}, scope = {...env, op};
  for (const [name, expr] of Object.entries(tool.make)) op[name] = evaluate(expr, scope);
  return op;
}

// The tool table: every op type's tools in the order /api/ops gives them.
export function buildTools(types) {
  const table = [];
  for (const [type, def] of Object.entries(types)) {
    for (const t of def.tools) table.push({...t, type, settings: def.settings});
  }
  return table;
}

// Whether ``tool`` draws in time (stylus.js): a path tool whose op takes
// ``times`` (``types``: /api/ops's answer).
export const drawsInTime = (tool, types) => tool.gesture === "path" && types[tool.type].params.some((p) => p.name === "times");

// A setting's value: the number typed in its field (``raw``, a string) when it
// is one (> 0 where positive), clamped and rounded as the setting says; else its default.
export function settingValue(s, env, raw = "") {
  const text = String(raw).trim(), v = Number(text);
  if (text === "" || !Number.isFinite(v) || (s.positive && v <= 0)) return evaluate(s.default, env);
  let x = v;
  if (s.low !== null) x = Math.max(s.low, x);
  if (s.high !== null) x = Math.min(s.high, x);
  return s.integer ? Math.round(x) : x;
}

// Ramer-Douglas-Peucker to ``tol``; the ends are kept.
export function simplifyPath(points, tol) {
  if (points.length < 3) return points.slice();
  const keep = points.map((_, k) => k === 0 || k === points.length - 1), stack = [[0, points.length - 1]];
  while (stack.length) {
    const [i, j] = stack.pop(), [ax, ay] = points[i], [bx, by] = points[j];
    const len = Math.hypot(bx - ax, by - ay);
    let far = -1, worst = tol;
    for (let k = i + 1; k < j; k++) {
      const [px, py] = points[k];
      const d = len > 0 ? Math.abs((bx - ax) * (ay - py) - (ax - px) * (by - ay)) / len : Math.hypot(px - ax, py - ay);
      if (d > worst) { worst = d; far = k; }
    }
    if (far >= 0) { keep[far] = true; stack.push([i, far], [far, j]); }
  }
  return points.filter((_, k) => keep[k]);
}

// A path gesture's points: the drawn path simplified to a frame pixel, without
// repeats, at most 4096; a click is a short path to the right.
export function pathPoints(drawn, a, b, side, scale) {
  let pts = simplifyPath(drawn.length > 1 ? drawn : [a, b], 1 / scale);
  pts = pts.filter((p, k) => k === 0 || p[0] !== pts[k - 1][0] || p[1] !== pts[k - 1][1]).slice(0, 4096);
  return pts.length < 2 ? [a, [round1(a[0] + side / 10), a[1]]] : pts;
}
