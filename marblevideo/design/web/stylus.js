// A path drawn in time (a stroke tool's gesture, recipe format revision 4's
// stroke ``times``): each pointer move's canvas point and the seconds since the
// press, from the events' timeStamp (milliseconds, performance.now()'s clock).
// A point is kept only where the pointer has moved at least ``gap`` device
// pixels (1 at first) from the last kept one, so the points so far are always a
// prefix of the finished path and the stroke being drawn renders, at the time
// of its newest point, exactly as the finished stroke does. Past MAX_POINTS
// every other point is dropped (the first and the newest kept) and the gap
// doubles. Times are non-decreasing, to the millisecond. Reads no page state.
import { round3 } from "./values.js";

//: marblevideo.ops.stroke.MAX_POINTS: a stroke's most points (and times).
export const MAX_POINTS = 4096;

// A path begun at canvas point ``at``, device pixel ``dev``, event time ``stamp``.
export const startPath = (at, dev, stamp) => ({points: [at], seconds: [0], devs: [dev], stamp, gap: 1});

function halve(p) {
  const keep = (_, k) => k % 2 === 0 || k === p.points.length - 1;
  p.points = p.points.filter(keep); p.seconds = p.seconds.filter(keep); p.devs = p.devs.filter(keep);
  p.gap *= 2;
}
// The pointer at ``at`` (device pixel ``dev``) at event time ``stamp``: whether
// the path took it as a new point.
export function addPoint(p, at, dev, stamp) {
  const last = p.devs.at(-1);
  if (Math.hypot(dev[0] - last[0], dev[1] - last[1]) < p.gap) return false;
  const s = Math.max(p.seconds.at(-1), round3((stamp - p.stamp) / 1000));
  p.points.push(at); p.seconds.push(s); p.devs.push(dev);
  if (p.points.length > MAX_POINTS) halve(p);
  return true;
}
// The times of the path's points for a press at time ``t0`` (seconds), and the newest's.
export const timesFrom = (p, t0) => p.seconds.map((s) => round3(t0 + s));
export const lastTime = (p, t0) => round3(t0 + p.seconds.at(-1));
// Whether the path was drawn (two points or more), rather than clicked.
export const drawn = (p) => p.points.length > 1;
