// A stroke's steps at time t, as marblevideo/ops/stroke.py and stylus.py lay
// them (float64 here; the shader turns in float32): revision 3 (n = ceil(4 l / w)
// steps of length l / n, e_k = clamp(p n - k, 0, 1)) and revision 4 (`times`:
// steps at the fixed spacing w / 4 where the stylus has been, the one it is in
// partial). A step is { c: [cx, cy] per tine (C + o N0), h: [hx, hy] = (w/2) N }
// and turns by theta radians (A = c + h turned +theta g, B = c - h turned -theta g).
import { progress } from "./warp_ops.js";

// The path flattened [x0, y0, ...] and L_i per given point (a repeated point
// adds 0; pointAt passes over such empty spans as stylus.points_at does).
export function path(points) {
  const flat = [], arc = [0];
  for (const [x, y] of points) {
    const n = flat.length;
    if (n) {
      const dx = x - flat[n - 2], dy = y - flat[n - 1];
      arc.push(arc[arc.length - 1] + Math.sqrt(dx * dx + dy * dy));
    }
    flat.push(x, y);
  }
  return { flat, arc };
}

// The points at arc lengths `at` (stylus.points_at: searchsorted side right).
export function pointAt(pa, s) {
  const { flat, arc } = pa, last = arc.length - 1;
  let lo = 0, hi = arc.length; // first index with arc > s
  while (lo < hi) { const mid = (lo + hi) >> 1; if (arc[mid] > s) hi = mid; else lo = mid + 1; }
  const i = Math.min(Math.max(lo - 1, 0), last), j = Math.min(i + 1, last);
  const span = arc[j] - arc[i], share = span > 0 ? (s - arc[i]) / span : 0;
  return [flat[2 * i] + (flat[2 * j] - flat[2 * i]) * share, flat[2 * i + 1] + (flat[2 * j + 1] - flat[2 * i + 1]) * share];
}

function normal(a, b) {
  const ux = b[0] - a[0], uy = b[1] - a[1], len = Math.sqrt(ux * ux + uy * uy);
  return { n: [-uy / len, ux / len], len };
}

// One step from a to b: a centre per tine (offsets along n0) and its half.
function step(a, b, n0, tines, w) {
  const { n, len } = normal(a, b), mx = (a[0] + b[0]) / 2, my = (a[1] + b[1]) / 2;
  return { c: tines.map((o) => [mx + o * n0[0], my + o * n0[1]]), h: [(w / 2) * n[0], (w / 2) * n[1]], len };
}

// stylus.whole_count: the largest W with W d <= s.
export function wholeCount(s, d) {
  let k = Math.floor(s / d);
  // past 2^52 k + 1 is k: the loops below would not end
  if (!(k < 2 ** 52)) throw new Error(`stroke: ${s} / ${d} steps`);
  while ((k + 1) * d <= s) k += 1;
  while (k > 0 && k * d > s) k -= 1;
  return k;
}

// A stroke layout of op: { key, d, wholeTheta, count (whole steps acting),
// wholeStep(k), partial (a step with theta, or null) } at time t; drag given.
export function strokeAt(op, t, drag) {
  const w = op.width ?? 24, tines = (op.tines ?? [0]).map(Number), pa = path(op.points);
  // (a width of 0 would make infinitely many steps: loops without end; the server refuses it)
  if (!(w > 0)) throw new Error(`stroke: width ${w}`);
  const l = pa.arc[pa.arc.length - 1], p = progress(op, t), law = (len) => (drag * len * 16) / (9 * w);
  if (!(l > 0)) return { timed: !!op.times, d: w / 4, count: 0, partial: null, wholeTheta: 0, wholeStep: null };
  if (op.times) {
    const d = w / 4, s = travel(op.times, pa, t) * p, count = wholeCount(s, d);
    const q0 = pa.flat.slice(0, 2), n0 = normal(q0, pointAt(pa, Math.min(s, d))).n;
    const at = (k) => pointAt(pa, k * d);
    let partial = null;
    if (s > count * d) {
      const st = step(at(count), pointAt(pa, s), count > 0 ? n0 : normal(at(count), pointAt(pa, s)).n, tines, w);
      partial = { ...st, theta: law(st.len) };
    }
    return { timed: true, d, count, partial, wholeTheta: law(d), wholeStep: (k) => step(at(k), at(k + 1), n0, tines, w) };
  }
  const n = Math.max(1, Math.ceil((4 * l) / w)), d = l / n, at = (k) => pointAt(pa, k * d);
  const n0 = normal(at(0), at(1)).n, pn = p * n, count = Math.max(0, Math.min(n, Math.floor(pn)));
  const e = Math.min(1, Math.max(0, pn - count));
  const partial = count < n && e > 0 ? { ...step(at(count), at(count + 1), n0, tines, w), theta: law(d) * e } : null;
  return { timed: false, d, count, partial, wholeTheta: law(d), wholeStep: (k) => step(at(k), at(k + 1), n0, tines, w) };
}

// stylus.travel: the stylus' arc length s(t).
export function travel(times, pa, t) {
  const arc = pa.arc;
  if (t < times[0]) return 0;
  if (t >= times[times.length - 1]) return arc[arc.length - 1];
  let i = 0;
  while (i + 1 < times.length && times[i + 1] <= t) i++;
  return arc[i] + ((arc[i + 1] - arc[i]) * (t - times[i])) / (times[i + 1] - times[i]);
}
