// One recipe op resolved at time t into what the warp's shader needs (warp.js):
// its values at t (keyframe tracks by ease.js), its progress (start/end times
// heal, each op's law as marblevideo/ops), layouts expanded to drops as
// marblevideo/ops/layouts.py. Canvas units, y down, angles in degrees
// (positive turns clockwise on screen), colours 0..1. null: the page cannot
// (a signal, an unknown type): the caller asks the server.
import { valueAt } from "./ease.js";
import { isSignal, isTrack } from "./values.js";

// The contract's p(t) of start/end times h(t) of heal.
export function progress(op, t) {
  let p = 1;
  const s = op.start, e = op.end;
  if (s !== undefined && e !== undefined) p = t < s ? 0 : t >= e ? 1 : (t - s) / (e - s);
  else if (s !== undefined) p = t < s ? 0 : 1;
  if (op.heal) {
    const [t0, t1] = op.heal;
    const h = t < t0 ? 1 : t >= t1 ? 0 : 1 - (t - t0) / (t1 - t0);
    p *= h;
  }
  return p;
}

let parser = null;
// A colour ("#rrggbb", "#rgb", [r, g, b] 0..255, a CSS name) as [r, g, b] 0..255.
export function rgb255(c) {
  if (Array.isArray(c)) return c.map(Number);
  let s = String(c).trim();
  if (!s.startsWith("#")) {
    parser = parser || new OffscreenCanvas(1, 1).getContext("2d");
    parser.fillStyle = "#000000";
    parser.fillStyle = s;
    s = parser.fillStyle;
  }
  if (s.length === 4) s = "#" + [...s.slice(1)].map((ch) => ch + ch).join("");
  return [1, 3, 5].map((i) => parseInt(s.slice(i, i + 2), 16));
}

// A value at t: numbers and points (componentwise), colours (0..255 components).
export function at(v, t, color = false) {
  if (isSignal(v)) throw new Error("signal");
  if (isTrack(v)) {
    const keys = v.keys.map((k) => ({ ...k, v: color ? rgb255(k.v) : k.v }));
    if (typeof keys[0].v === "number") return valueAt({ keys }, t);
    return keys[0].v.map((_, i) => valueAt({ keys: keys.map((k) => ({ ...k, v: k.v[i] })) }, t));
  }
  return color ? rgb255(v) : v;
}

const ROT = (x, y, deg) => {
  const a = (deg * Math.PI) / 180, c = Math.cos(a), s = Math.sin(a);
  return [x * c - y * s, x * s + y * c];
};

function splitmix(seed) {
  const M = (1n << 64n) - 1n;
  let state = BigInt(seed) & M;
  return () => {
    state = (state + 0x9e3779b97f4a7c15n) & M;
    let z = state;
    z = ((z ^ (z >> 30n)) * 0xbf58476d1ce4e5b9n) & M;
    z = ((z ^ (z >> 27n)) * 0x94d049bb133111ebn) & M;
    z ^= z >> 31n;
    return Number(z >> 11n) / 2 ** 53;
  };
}

// A layout's drops (centre, radius) in order, as layouts.py places them.
function placed(op) {
  const n = op.count;
  if (op.type === "rings") return Array.from({ length: n }, (_, k) => [op.center, op.width * Math.sqrt(2 * (n - k) - 1)]);
  if (op.type === "line-drops") {
    const [a, b] = [op.from, op.to], step = n > 1 ? 1 / (n - 1) : 0;
    return Array.from({ length: n }, (_, k) => [[a[0] + (b[0] - a[0]) * k * step, a[1] + (b[1] - a[1]) * k * step], op.radius]);
  }
  if (op.type === "grid-drops") {
    const out = [], [cols, rows] = op.size;
    for (let j = 0; j < rows; j++) {
      for (let m = 0; m < cols; m++) {
        const i = j % 2 === 0 ? m : cols - 1 - m;
        const [dx, dy] = ROT(i * op.spacing[0], j * op.spacing[1], op.angle || 0);
        out.push([[op.origin[0] + dx, op.origin[1] + dy], op.radius]);
      }
    }
    return out;
  }
  const draw = splitmix(op.seed), out = [];
  for (let k = 0; k < n; k++) {
    const u1 = draw(), u2 = draw();
    let ox, oy;
    if (op.distribution === "normal") {
      const g = Math.sqrt(-2 * Math.log(1 - u1));
      ox = (g * Math.cos(2 * Math.PI * u2) * op.size[0]) / Math.sqrt(8);
      oy = (g * Math.sin(2 * Math.PI * u2) * op.size[1]) / Math.sqrt(8);
    } else [ox, oy] = [(u1 - 0.5) * op.size[0], (u2 - 0.5) * op.size[1]];
    const [dx, dy] = ROT(ox, oy, op.angle || 0);
    out.push([[op.center[0] + dx, op.center[1] + dy], op.radius]);
  }
  return out;
}

export const LAYOUTS = ["rings", "line-drops", "grid-drops", "scatter-drops"];

// A layout as its list of drop ops (windows cut as layouts.expand does).
export function expand(op) {
  const drops = placed(op), n = drops.length, colors = op.colors;
  return drops.map(([center, radius], k) => {
    const drop = { type: "drop", center, radius, color: colors[k % colors.length] };
    if (op.start !== undefined && op.end !== undefined) {
      const span = (op.end - op.start) / n;
      drop.start = op.start + k * span;
      drop.end = op.start + (k + 1) * span;
    } else if (op.start !== undefined) drop.start = op.start;
    if (op.heal) drop.heal = op.heal;
    return drop;
  });
}

// The ink circles of a drop, spray or layout at t: [cx, cy, r, moves, red, green, blue] (0..1).
function inks(op, t) {
  const ops = LAYOUTS.includes(op.type) ? expand(op) : [op];
  const out = [];
  for (const d of ops) {
    const p = progress(d, t), r = at(d.radius, t) * Math.sqrt(p);
    if (!(r > 0)) continue;
    const c = at(d.center, t), col = at(d.color, t, true);
    out.push([c[0], c[1], r, d.type === "drop" ? 1 : 0, ...col.map((v) => v / 255)]);
  }
  return out;
}

const rad = (deg) => (deg * Math.PI) / 180;

// sum_k c_k e^(-|u - o_k| / L) in closed form, as marblevideo/ops/series.py
// packs it for the kernels' series_sum (the same limits: at least 4 terms
// evenly spaced at least 0.05 L apart, the c_k all equal or alternating in
// sign): [o0, 1/s, s, s/L, 1/(1 - sigma q), c0, sigma, sigma^(n-1)], q = e^(-s/L),
// positions sorted; null: summed term by term.
export function closedSeries(positions, coefficients, falloff) {
  const n = positions.length;
  if (n < 4) return null;
  const pairs = positions.map((o, k) => [o, coefficients[k]]).sort((a, b) => a[0] - b[0] || a[1] - b[1]);
  const o = pairs.map((q) => q[0]), c = pairs.map((q) => q[1]), step = (o[n - 1] - o[0]) / (n - 1);
  if (!(step > 0) || o.some((ok, k) => Math.abs(ok - (o[0] + k * step)) > 1e-9 * step)) return null;
  const ratio = step / falloff;
  if (!(ratio >= 0.05)) return null;
  let sigma;
  if (c.every((ck) => ck === c[0])) sigma = 1;
  else if (c.every((ck, k) => ck === c[0] * (k % 2 ? -1 : 1))) sigma = -1;
  else return null;
  const g = sigma > 0 ? 1 / -Math.expm1(-ratio) : 1 / (1 + Math.exp(-ratio));
  return [o[0], 1 / step, step, ratio, g, c[0], sigma, n % 2 ? 1 : sigma];
}

// The op at t as { kind, p: [16 numbers], list: [numbers] } for the shader
// (kinds and slots as warp_shaders.js reads them), or { kind: "stroke", ... }
// for warp.js, or null when the page cannot.
export function resolve(op, t) {
  try {
    return resolveOrThrow(op, t);
  } catch {
    return null;
  }
}

function resolveOrThrow(op, t) {
  const ty = op.type;
  if (ty === "drop" || ty === "spray" || LAYOUTS.includes(ty)) {
    const list = inks(op, t), rows = list.flatMap((row) => [...row, 0]);
    // one drop (kind 11): its row in the uniforms too, read with no texture fetch
    // (SwiftShader: 31-35 ms a 930x620 frame from the list, 22 ms from uniforms)
    if (list.length === 1) return { kind: 11, p: [1, 0, 0, 0, ...rows], list: [] };
    return { kind: list.length ? 1 : 0, p: [list.length], list: rows };
  }
  const p = progress(op, t), v = (name) => at(op[name], t);
  if (ty === "stroke") return { kind: "stroke", p, drag: Math.max(-4, Math.min(4, v("drag") ?? 1)) };
  if (p <= 0) return { kind: 0, p: [], list: [] };
  if (ty === "tine" || ty === "comb") {
    const a = rad(v("angle")), pt = v("point");
    return { kind: 2, p: [pt[0], pt[1], Math.cos(a), Math.sin(a), v("alpha") * p, v("lambda"), ty === "comb" ? v("spacing") : 0], list: [] };
  }
  if (ty === "wave") {
    const a = rad(v("angle"));
    return { kind: 3, p: [Math.cos(a), Math.sin(a), v("amplitude") * p, 1 / v("wavelength"), v("phase") / 360], list: [] };
  }
  if (ty === "shift") {
    const o = v("offset");
    return { kind: 4, p: [o[0] * p, o[1] * p], list: [] };
  }
  if (ty === "rake") {
    const a = rad(v("angle")), pt = v("point"), n = op.count, s = op.spacing, L = v("falloff");
    const tines = op.tines ? op.tines.map(Number) : Array.from({ length: n }, (_, k) => (k - (n - 1) / 2) * s);
    const head = [pt[0], pt[1], Math.cos(a), Math.sin(a), v("alpha") * p, 1 / L, tines.length, 0];
    const closed = closedSeries(tines, tines.map(() => 1), L);
    if (closed) return { kind: 9, p: [...head, ...closed], list: [] };
    return { kind: 5, p: head, list: tines.flatMap((o) => [o, 1, 0, 0]) };
  }
  return rotation(op, t, p, v);
}

// Rotations (kind 6): p = [cx, cy, sub, a, b, c, n]; theta(R) by sub:
// 0 circle/vortex (a = alpha, b = lambda, c = radius or -1 for a vortex),
// 1 turn (a = angle radians), 2 oseen (a = G, b = (4 nu)^(3/4), c = (2 pi / T)^(3/4)),
// 3 stir by arc (a = alpha, rings |r|, sign, 1/L), 4 stir by turn (a = radians, rings |r|, sign, 1/(L |r|)).
// Drops, sprays and layouts are kind 1 (p = [n], their rows in the list) or, one
// drop, kind 11 (p = [1, 0, 0, 0, its row]: the shader reads it from uniforms).
// Jiggle is kind 7: p = [mx, my, 1/w, phase turns, A, B]. A closed-form series
// (closedSeries: its 8 numbers in p[8..15]) makes a rake kind 9 (kind 5's p) and
// a stir by arc kind 10 (p = [cx, cy, 3, alpha, 1/L, 0, n, 0]).
function rotation(op, t, p, v) {
  const ty = op.type;
  if (ty === "jiggle") {
    const a = rad(v("angle")), w = v("wavelength"), lim = (0.99 * w) / (2 * Math.PI);
    const major = Math.max(-lim, Math.min(lim, v("major") * p));
    const ph = (((v("phase") / 360) % 1) + 1) % 1;
    return { kind: 7, p: [Math.cos(a), Math.sin(a), 1 / w, ph, major, v("minor") * p], list: [] };
  }
  const c = v("center");
  const rot = (sub, a, b = 0, cc = 0, n = 0, list = []) => ({ kind: 6, p: [c[0], c[1], sub, a, b, cc, n], list });
  if (ty === "circle") return rot(0, v("alpha") * p, v("lambda"), v("radius"));
  if (ty === "vortex") return rot(0, v("alpha") * p, v("lambda"), -1);
  if (ty === "turn") return rot(1, rad(v("angle") * p));
  if (ty === "oseen") {
    const time = v("time") * p;
    if (time <= 0) return { kind: 0, p: [], list: [] };
    return rot(2, v("circulation"), (4 * v("viscosity")) ** 0.75, ((2 * Math.PI) / time) ** 0.75);
  }
  if (ty === "stir") {
    const radii = op.radii.map(Number), L = v("falloff"), relative = op.turn !== undefined;
    const list = radii.flatMap((r) => [Math.abs(r), Math.sign(r), 1 / (relative ? L * Math.abs(r) : L), 0]);
    if (relative) return rot(4, rad(v("turn") * p), 0, 0, radii.length, list);
    const closed = closedSeries(radii.map(Math.abs), radii.map(Math.sign), L);
    if (closed) return { kind: 10, p: [c[0], c[1], 3, v("alpha") * p, 1 / L, 0, radii.length, 0, ...closed], list: [] };
    return rot(3, v("alpha") * p, 0, 0, radii.length, list);
  }
  throw new Error(`unknown op ${ty}`);
}
