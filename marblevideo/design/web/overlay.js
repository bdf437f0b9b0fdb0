// The overlay over the sheet (a view of the store): the selected op's handles,
// and the gesture under way (a dashed line and the number it sets, or the path
// drawn). Also where the handles are: what a press on one moves.
import { overlay, toPixel } from "./sheet.js";
import { get } from "./store.js";

const octx = overlay.getContext("2d");
const lineWidth = () => Math.max(1.5, overlay.width / 500);

// The handles of op i of ``doc``: its points (not motions) and every point of its paths.
export function pointsOf(i, s = get()) {
  const op = s.doc.ops[i], found = [];
  if (!op || !s.types[op.type]) return found;
  for (const p of s.types[op.type].params) {
    const v = op[p.name];
    if (p.handle && Array.isArray(v)) found.push([p.name, v]);
    if (p.kind === "pointList" && Array.isArray(v)) found.push(...v.map((q, k) => [`${p.name}.${k}`, q]));
  }
  return found;
}
// "center", or "points.3": one point of a path, moved to ``at``.
export function setHandle(op, handle, at) {
  const [name, k] = handle.split(".");
  if (k === undefined) op[name] = at;
  else op[name][Number(k)] = at;
}
// The selected op's handle under frame pixel px, or null.
export function handleAt(px, s = get()) {
  if (s.selected === null) return null;
  for (const [name, v] of pointsOf(s.selected, s)) {
    const [x, y] = toPixel(v);
    if (Math.hypot(x - px[0], y - px[1]) < 8 * lineWidth()) return name;
  }
  return null;
}

export const overlayOf = (s) => [
  s.doc, s.selected, s.gesture, s.info.size, s.view, s.screen, s.showMotion && s.motion,
];
export function showOverlay(s) {
  octx.clearRect(0, 0, overlay.width, overlay.height);
  const w = lineWidth(), g = s.gesture;
  octx.lineWidth = w;
  if (s.selected !== null) {
    for (const [, v] of pointsOf(s.selected, s)) {
      const [x, y] = toPixel(v);
      octx.strokeStyle = "#fff"; octx.fillStyle = "rgba(40,120,255,0.8)";
      octx.beginPath(); octx.arc(x, y, 4 * w, 0, 2 * Math.PI); octx.fill(); octx.stroke();
    }
  }
  if (g && g.path) drawPath(g.path, w);
  else if (g && g.line) drawLine(g.a, g.b, g.label, w);
  overlay.dataset.label = g && g.line && !g.path ? g.label : "";
  drawMotion(s.showMotion ? s.motion : null, w);
}
// Live mode's motion (shown): each region followed as a circle, each motion
// stroke as a polyline; data-circles lists the circles drawn ([x, y, r] in the sheet's device pixels).
function drawMotion(m, w) {
  const circles = [];
  if (m) {
    octx.strokeStyle = "rgba(255,80,200,0.9)"; octx.lineWidth = w;
    for (const op of m.strokes) {
      octx.beginPath();
      op.points.map(toPixel).forEach(([x, y], k) => (k ? octx.lineTo(x, y) : octx.moveTo(x, y)));
      octx.stroke();
    }
    octx.strokeStyle = "rgba(80,255,120,0.95)"; octx.lineWidth = 2 * w;
    for (const region of m.regions) {
      const [x, y] = toPixel(region.center), r = Math.max(2 * w, region.radius * get().info.scale);
      octx.beginPath(); octx.arc(x, y, r, 0, 2 * Math.PI); octx.stroke();
      circles.push([Math.round(x), Math.round(y), Math.round(r)]);
    }
  }
  overlay.dataset.circles = JSON.stringify(circles);
  overlay.dataset.motionT = m && m.t !== null ? m.t.toFixed(3) : "";
}
function drawLine(from, to, label, w) {
  const [a, b] = [from, to].map(toPixel);
  octx.strokeStyle = "rgba(255,255,255,0.8)"; octx.setLineDash([4 * w, 3 * w]);
  octx.beginPath(); octx.moveTo(a[0], a[1]); octx.lineTo(b[0], b[1]); octx.stroke();
  octx.setLineDash([]);
  octx.font = `${8 * w}px system-ui, sans-serif`;
  octx.strokeStyle = "rgba(0,0,0,0.8)"; octx.fillStyle = "#fff";
  octx.strokeText(label, b[0] + 6 * w, b[1] - 6 * w); octx.fillText(label, b[0] + 6 * w, b[1] - 6 * w);
}
function drawPath(points, w) {
  octx.strokeStyle = "rgba(255,255,255,0.8)"; octx.setLineDash([4 * w, 3 * w]);
  octx.beginPath();
  points.map(toPixel).forEach(([x, y], k) => (k ? octx.lineTo(x, y) : octx.moveTo(x, y)));
  octx.stroke(); octx.setLineDash([]);
}
