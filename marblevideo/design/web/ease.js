// Keyframe tracks as the renderer evaluates them (marblevideo.recipe.keyframes):
// tests/test_page_modules.py checks this module against Python on vectors
// Python makes.
import { isTrack } from "./values.js";

export const BEZIERS = {"ease-in": [0.42, 0, 1, 1], "ease-out": [0, 0, 0.58, 1], "ease-in-out": [0.42, 0, 0.58, 1]};

// A key's ease at segment progress u: linear, hold, the named CSS cubic-beziers
// or [x1, y1, x2, y2] (x solved by Newton from s = u, then bisection where that
// did not pin it).
export function eased(spec, u) {
  if (spec === undefined || spec === "linear") return u;
  if (spec === "hold") return u >= 1 ? 1 : 0;
  const [x1, y1, x2, y2] = BEZIERS[spec] || spec;
  const coef = (p1, p2) => { const c = 3 * p1, b = 3 * (p2 - p1) - c; return [1 - c - b, b, c]; };
  const [ax, bx, cx] = coef(x1, x2), [ay, by, cy] = coef(y1, y2);
  const xOf = (s) => ((ax * s + bx) * s + cx) * s, clip = (s) => Math.min(1, Math.max(0, s));
  u = clip(u);
  let s = u;
  for (let k = 0; k < 8; k++) {
    const slope = (3 * ax * s + 2 * bx) * s + cx;
    if (Math.abs(slope) > 1e-9) s = clip(s - (xOf(s) - u) / slope);
  }
  if (xOf(s - 1e-12) > u || xOf(s + 1e-12) < u) {
    let lo = 0, hi = 1;
    for (let k = 0; k < 60; k++) { const mid = 0.5 * (lo + hi); if (xOf(mid) < u) lo = mid; else hi = mid; }
    s = 0.5 * (lo + hi);
  }
  return ((ay * s + by) * s + cy) * s;
}

// A number's value at time tt (seconds): a constant, or its track's: the first
// key's before it, the last's after, eased between; null for other values.
export function valueAt(v, tt) {
  if (typeof v === "number") return v;
  if (!isTrack(v) || !v.keys.every((k) => typeof k.v === "number")) return null;
  const keys = v.keys;
  let i = -1;
  keys.forEach((k, n) => { if (k.t <= tt) i = n; });
  if (i < 0) return keys[0].v;
  if (i >= keys.length - 1) return keys[keys.length - 1].v;
  const a = keys[i], b = keys[i + 1];
  return a.v + (b.v - a.v) * eased(a.ease, (tt - a.t) / (b.t - a.t));
}
