// A stroke's whole steps accumulated into a float displacement map (RG32F,
// device size, rows bottom-up as the framebuffer): texel q holds
// W^-1(Q) - Q for its canvas point Q, W the whole steps folded so far. A chunk
// of CHUNK new whole steps is folded as map'(Q) = map(chunk^-1(Q)) (the newest
// step walked first), only inside the chunk's reach (1.5 w about each step's
// centre: scissored), so a growing stroke costs one small pass per chunk and the
// frame walks at most CHUNK - 1 whole steps (inside their reach) and the
// partial one. Folding by chunks, not by steps, keeps the map's resampling (a
// Catmull-Rom of a steep map near the path) to about one per point; the frame
// interpolates the map only in the 16x16 tiles the folded steps reach. The
// cache is kept while the stroke only grows (its points a
// prefix of the new ones, or the same path for a stroke without `times`).
import { setCommon, texture, uploadList } from "./warp_gl.js";

// Whole steps folded into the map at once (the frame walks fewer than this):
// fewer make cheaper frames and folds, more make fewer reads of the map (at 32,
// 16 and 8 a stroke of width 30 and drag 1.5 agreed with the reference on
// 98.9%, 98.7% and 98.2% of pixels). StrokeMap.chunk may change it.
export const CHUNK = 32;

export class StrokeMap {
  constructor(gl, step, vao, list) {
    this.gl = gl;
    this.list = list;
    this.step = step;
    this.vao = vao;
    this.targets = null;
    this.chunk = CHUNK;
    this.reset();
  }

  reset() {
    this.key = null;
    this.count = 0;
    this.marked = null;
    this.points = [];
  }

  target(w, h) {
    const gl = this.gl;
    if (this.targets && this.targets.w === w && this.targets.h === h) return this.targets;
    const make = () => {
      const tex = texture(gl);
      gl.texImage2D(gl.TEXTURE_2D, 0, gl.RG32F, w, h, 0, gl.RG, gl.FLOAT, null);
      const fb = gl.createFramebuffer();
      gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
      gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, tex, 0);
      return { tex, fb };
    };
    this.targets = { w, h, a: make(), b: make() };
    return this.targets;
  }

  stale(op, layout, drag, toCanvas, size) {
    const key = JSON.stringify([layout.timed, op.width ?? 24, op.tines ?? [0], drag, toCanvas, size, layout.timed ? 0 : op.points]);
    if (key !== this.key || layout.count < this.count) return key;
    if (!layout.timed) return null;
    const pts = this.points;
    if (op.points.length < pts.length) return key;
    for (let i = 0; i < pts.length; i++) if (op.points[i][0] !== pts[i][0] || op.points[i][1] !== pts[i][1]) return key;
    return null;
  }

  // Bring the map to the whole steps of layout (strokeAt's) but the last < CHUNK,
  // folded a chunk at a time; the rest are walked each frame (pending). Returns
  // the canvas rect the steps folded now reach, or null.
  update(op, layout, drag, toCanvas, size) {
    const gl = this.gl, [w, h] = size, tg = this.target(w, h);
    const key = this.stale(op, layout, drag, toCanvas, size);
    if (key !== null) {
      this.builds = (this.builds ?? 0) + 1;
      this.key = key;
      this.count = 0;
      this.marked = new Uint8Array(Math.ceil(w / 16) * Math.ceil(h / 16));
      gl.bindFramebuffer(gl.FRAMEBUFFER, tg.a.fb);
      gl.disable(gl.SCISSOR_TEST);
      gl.clearBufferfv(gl.COLOR, 0, [0, 0, 0, 0]);
    }
    this.points = op.points.map((p) => [p[0], p[1]]);
    const width = op.width ?? 24, chunk = this.exact ? Infinity : this.chunk;
    if (layout.count - this.count < chunk) return null;
    let folded = null;
    const { prog, u } = this.step;
    gl.useProgram(prog);
    gl.bindVertexArray(this.vao);
    gl.viewport(0, 0, w, h);
    gl.enable(gl.SCISSOR_TEST);
    for (; layout.count - this.count >= chunk; this.count += chunk) {
      const rows = stepRows(layout, this.count, this.count + chunk, width);
      const r = rows.rect;
      folded = folded ? [Math.min(folded[0], r[0]), Math.min(folded[1], r[1]), Math.max(folded[2], r[2]), Math.max(folded[3], r[3])] : [...r];
      this.mark(rows, toCanvas, w, h);
      const [x0, y0, x1, y1] = deviceRect(rows.rect, toCanvas, w, h);
      if (x1 <= x0 || y1 <= y0) continue;
      gl.scissor(x0, y0, x1 - x0, y1 - y0);
      gl.bindFramebuffer(gl.FRAMEBUFFER, tg.b.fb);
      this.bind(u, 3, true);
      gl.uniform1i(u.uHasMap, 1);
      setCommon(gl, u, toCanvas, size, width);
      setSteps(gl, u, this.list, rows);
      gl.drawArrays(gl.TRIANGLES, 0, 3);
      gl.bindFramebuffer(gl.READ_FRAMEBUFFER, tg.b.fb);
      gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, tg.a.fb);
      gl.blitFramebuffer(x0, y0, x1, y1, x0, y0, x1, y1, gl.COLOR_BUFFER_BIT, gl.NEAREST);
    }
    gl.bindFramebuffer(gl.READ_FRAMEBUFFER, null);
    gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, null);
    gl.disable(gl.SCISSOR_TEST);
    return folded;
  }

  // The whole steps not folded yet and the partial one, for the frame's walk.
  pending(layout, width) {
    return stepRows(layout, this.count, layout.count, width, layout.partial);
  }

  // Mark the 16x16 device tiles a chunk's steps reach (the map is 0 elsewhere;
  // the frame interpolates it only in marked tiles), and upload them.
  mark(rows, [a, b, c, d], w, h) {
    const gl = this.gl, tw = Math.ceil(w / 16), th = Math.ceil(h / 16), r = 1.5 * rows.width + 3;
    for (let i = 0; i < rows.n; i++) {
      const cx = rows.list[8 * i], cy = rows.list[8 * i + 1];
      const xs = [(cx - r - c) / a, (cx + r - c) / a], ys = [(cy - r - d) / b, (cy + r - d) / b];
      const x0 = Math.max(0, Math.floor(Math.min(...xs) / 16) - 1), x1 = Math.min(tw - 1, Math.floor(Math.max(...xs) / 16) + 1);
      const y0 = Math.max(0, Math.floor(Math.min(...ys) / 16) - 1), y1 = Math.min(th - 1, Math.floor(Math.max(...ys) / 16) + 1);
      for (let y = y0; y <= y1; y++) this.marked.fill(255, y * tw + x0, y * tw + x1 + 1);
    }
    this.tiles = this.tiles || texture(gl);
    gl.activeTexture(gl.TEXTURE4);
    gl.bindTexture(gl.TEXTURE_2D, this.tiles);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.R8, tw, th, 0, gl.RED, gl.UNSIGNED_BYTE, this.marked);
  }

  bind(u, unit, on) {
    const gl = this.gl;
    gl.activeTexture(gl.TEXTURE0 + unit);
    gl.bindTexture(gl.TEXTURE_2D, this.targets ? this.targets.a.tex : null);
    gl.uniform1i(u.uMap, unit);
    gl.uniform1i(u.uHasMap, on && this.count > 0 ? 1 : 0);
    gl.activeTexture(gl.TEXTURE4);
    gl.bindTexture(gl.TEXTURE_2D, this.tiles || null);
    gl.uniform1i(u.uTiles, 4);
  }
}

// Whole steps a..b-1 (and ``partial``, a step with its theta, when given) as
// list rows (cx, cy, hx, hy; theta, 0, 0, 0 per tine, in forward order), their
// count and their reach (1.5 w about each centre) in canvas units.
export function stepRows(layout, a, b, width, partial = null) {
  const rows = { list: [], n: 0, width, rect: [Infinity, Infinity, -Infinity, -Infinity] };
  for (let k = a; k < b; k++) addRows(rows, layout.wholeStep(k), layout.wholeTheta, width);
  if (partial) addRows(rows, partial, partial.theta, width);
  return rows;
}

function addRows(rows, st, theta, width) {
  const r = 1.5 * width + 1, rect = rows.rect;
  for (const [cx, cy] of st.c) {
    rows.list.push(cx, cy, st.h[0], st.h[1], theta, 0, 0, 0);
    rows.n += 1;
    rect[0] = Math.min(rect[0], cx - r);
    rect[1] = Math.min(rect[1], cy - r);
    rect[2] = Math.max(rect[2], cx + r);
    rect[3] = Math.max(rect[3], cy + r);
  }
}

// Rows walked together in stepsBack's blocks (warp_shaders.js BLOCK).
const BLOCK = 8;
// ``list`` (rows of 8 numbers: cx, cy, hx, hy, theta, -, -, -) with each row's
// numbers 5..7 the circle of its block (rows BLOCK k .. BLOCK k + BLOCK - 1): the
// centres' mean and the square of a radius past every centre's reach (1.5 w)
// by a canvas unit, so a point outside it is moved by none of the block's rows.
function withBlocks(list, width) {
  const out = Float32Array.from(list), n = list.length / 8, reach = 1.5 * width + 1;
  for (let b = 0; b < n; b += BLOCK) {
    const end = Math.min(n, b + BLOCK);
    let mx = 0, my = 0, r = 0;
    for (let i = b; i < end; i++) { mx += list[8 * i] / (end - b); my += list[8 * i + 1] / (end - b); }
    for (let i = b; i < end; i++) r = Math.max(r, Math.hypot(list[8 * i] - mx, list[8 * i + 1] - my));
    for (let i = b; i < end; i++) out.set([mx, my, (r + reach) ** 2], 8 * i + 5);
  }
  return out;
}

// The list texture (with its blocks' circles), its count and reach for stepsBack.
export function setSteps(gl, u, tex, rows) {
  uploadList(gl, tex, rows.n ? withBlocks(rows.list, rows.width) : rows.list);
  gl.uniform1i(u.uList, 1);
  gl.uniform1i(u.uListN, rows.n);
  gl.uniform4f(u.uRect, ...(rows.n ? rows.rect : [1, 1, -1, -1]));
}

// A canvas rect as a framebuffer rect [x0, y0, x1, y1] (rows bottom-up).
export function deviceRect([lx, ly, hx, hy], [a, b, c, d], w, h) {
  const xs = [(lx - c) / a, (hx - c) / a], ys = [(ly - d) / b, (hy - d) / b];
  const x0 = Math.max(0, Math.floor(Math.min(...xs)) - 1), x1 = Math.min(w, Math.ceil(Math.max(...xs)) + 1);
  const dy0 = Math.floor(Math.min(...ys)) - 1, dy1 = Math.ceil(Math.max(...ys)) + 1;
  return [x0, Math.max(0, h - dy1), x1, Math.min(h, h - dy0)];
}
