// The sheet warped on the GPU (WebGL2) while one op changes: the page keeps an
// exact picture of the ops below that op (the base, device pixels, from the
// server) and draws base(inverse op(q)) for every device pixel q each frame,
// with ink inside drops, the ops above as an optional map from the server, and
// a stroke's whole steps folded by chunks into a float displacement map (the
// frame walks only the partial step and the whole steps of the chunk being
// laid; warp.exactSteps = true walks them all instead). Geometry: device point (x, y) (a
// pixel's centre is x = i + 0.5) is canvas point (x a + c, y b + d) for
// toCanvas = [a, b, c, d]; canvas point Q is base pixel point
// (Q.x a' + c', Q.y b' + d') for toBase = [a', b', c', d'].
import { FORWARD_KINDS, STEP, drawSource } from "./warp_shaders.js";
import { at, resolve, rgb255 } from "./warp_ops.js";
import { strokeAt } from "./warp_stroke.js";
import { StrokeMap, deviceRect, setSteps, stepRows } from "./warp_map.js";
import { program, setCommon, texture } from "./warp_gl.js";

const EDGES = { clamp: 0, repeat: 1, mirror: 2, background: 3 };
// The most steps of a stroke the page folds (marblevideo/ops/stroke.py MAX_STEPS; more: the server's frame).
const MAX_STEPS = 200000;

let canWarp = null;

// Whether this browser has WebGL2 with float render targets (asked once: a
// context made and given back, as browsers keep only a few alive).
export function supported() {
  if (canWarp !== null) return canWarp;
  try {
    const gl = new OffscreenCanvas(1, 1).getContext("webgl2");
    canWarp = !!(gl && gl.getExtension("EXT_color_buffer_float"));
    gl?.getExtension("WEBGL_lose_context")?.loseContext();
  } catch {
    canWarp = false;
  }
  return canWarp;
}

// A WebGL2 canvas of the sheet's device size -> a Warp, or null without WebGL2
// and float render targets.
export function createWarp(canvas) {
  let gl;
  try {
    // opaque (every pixel drawn is): shown as the sheet during a gesture
    // (sheetgl.js), the compositor need not blend it (1-4 fps more on SwiftShader)
    gl = canvas.getContext("webgl2", { premultipliedAlpha: false, preserveDrawingBuffer: true, antialias: false, alpha: false });
  } catch {
    return null;
  }
  if (!gl || !gl.getExtension("EXT_color_buffer_float")) return null;
  try {
    return new Warp(gl, canvas);
  } catch (e) {
    console.warn("warp:", e);
    return null;
  }
}

class Warp {
  constructor(gl, canvas) {
    this.gl = gl;
    this.canvas = canvas;
    this.programs = new Map();
    this.step_ = program(gl, STEP);
    this.vao = gl.createVertexArray();
    this.base = texture(gl);
    this.above = null;
    this.list = texture(gl);
    this.toCanvas = [1, 1, 0, 0];
    this.toBase = [1, 1, 0, 0];
    this.baseSize = [1, 1];
    this.map = new StrokeMap(gl, this.step_, this.vao, this.list);
    gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false);
    gl.pixelStorei(gl.UNPACK_COLORSPACE_CONVERSION_WEBGL, gl.NONE);
    gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, false);
  }

  // The draw program of an op kind and edges mode (compiled once).
  program(kind, edges, forward = false, above = !!this.above) {
    const key = `${kind} ${edges} ${above} ${forward}`;
    if (!this.programs.has(key)) this.programs.set(key, program(this.gl, drawSource(kind, edges, above, forward)));
    return this.programs.get(key);
  }

  // Ahead of a gesture on ``op``: SwiftShader compiles a program at its first
  // draw (70-120 ms on two busy cores), so the programs the gesture will draw
  // with (``above``: with a map of the ops above; ``before``: forward, then
  // plain) each draw one pixel now, once; the GPU process runs them while the
  // page goes on. The next frame draws the whole canvas.
  warm(op, t, edges = "clamp", above = false, before = null) {
    try {
      const plan = resolve(op, t);
      if (!plan || !(edges in EDGES)) return;
      const stroke = plan.kind === "stroke";  // (its steps' program: drawn with no steps)
      const forward = !stroke && before && forwardable(op, before, t) ? [true, false] : [false];
      const keys = forward.map((fw) => [fw, `${stroke ? 8 : plan.kind} ${EDGES[edges]} ${above} ${fw}`]).filter(([, key]) => !this.warmed?.has(key));
      if (!keys.length) return;
      // the pixel drawn on is put back after (the canvas may be what the sheet shows)
      const gl = this.gl, kept = new Uint8Array(4);
      gl.bindFramebuffer(gl.FRAMEBUFFER, null);
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, kept);
      for (const [fw, key] of keys) {
        (this.warmed = this.warmed || new Set()).add(key);
        const warmed = stroke ? { kind: 8, p: [], list: [], rows: { list: [], n: 0, rect: [1, 1, -1, -1] } } : { ...plan, forward: fw ? plan.p : null };
        this.drawPlan(op, t, warmed, [255, 255, 255], EDGES[edges], above);
      }
      gl.enable(gl.SCISSOR_TEST);
      gl.scissor(0, 0, 1, 1);
      gl.clearColor(...[...kept].map((v) => v / 255));
      gl.clear(gl.COLOR_BUFFER_BIT);
      gl.disable(gl.SCISSOR_TEST);
      this.lastStroke = null;
    } catch (e) {
      console.warn("warp:", e);
    }
  }

  setBase(image, width, height) {
    this.lastStroke = null;
    const gl = this.gl;
    gl.bindTexture(gl.TEXTURE_2D, this.base);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA8, width, height, 0, gl.RGBA, gl.UNSIGNED_BYTE, image.data ?? image);
    this.baseSize = [width, height];
  }

  // Float32Array width*height*4 (top row first) for the ops above, or null.
  setAbove(map) {
    this.lastStroke = null;
    const gl = this.gl, { width, height } = this.canvas;
    if (!map) { this.above = null; return; }
    this.above = this.above || texture(gl);
    gl.bindTexture(gl.TEXTURE_2D, this.above);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, width, height, 0, gl.RGBA, gl.FLOAT, map);
  }

  setGeometry(toCanvas, toBase) {
    this.lastStroke = null;
    this.toCanvas = [...toCanvas];
    this.toBase = [...toBase];
  }

  // Draw base(inv_op(q)) at time t over the recipe's background and edges (the
  // background shows where edges is "background"); false when the page cannot
  // (a signal, an unknown op, a WebGL failure): the caller asks the server.
  // ``before``: the base is the exact frame with that op (the op as it was) on
  // top, taken off forward: base(before(inv_op(q))) (only where forwardable).
  draw(op, t, background = "#ffffff", edges = "clamp", before = null) {
    try {
      const plan = resolve(op, t), bg = rgb255(at(background, t, true));
      if (!plan || !(edges in EDGES)) return false;
      if (before) {
        const old = forwardPlan(before, t, plan);
        if (!old || this.above) return false;
        plan.forward = old.p;
      }
      this.drawPlan(op, t, plan, bg, EDGES[edges]);
      return true;
    } catch (e) {
      console.warn("warp:", e);
      return false;
    }
  }

  // Live mode: the base is a live frame that shows ``before`` at time ``tb``, the
  // same stroke drawn in time as ``op`` but less far (its points and times a
  // prefix of op's; the same width, tines and drag). Draw it as ``op`` at ``t``:
  // the steps laid since walked back (the newest first), then the frame's partial
  // step taken off forward, so base(S_before(S_op^-1(q))) is the frame of ``op``
  // with nothing resampled but the base. (A step forward is the step walked back
  // with its half-vector negated: each turn keeps the distance to its centre.)
  // False where that does not hold (the caller shows the frame as it is).
  drawStrokeSince(op, t, before, tb, background = "#ffffff", edges = "clamp") {
    try {
      const plan = resolve(op, t), old = resolve(before, tb), bg = rgb255(at(background, t, true));
      if (!plan || !old || plan.kind !== "stroke" || old.kind !== "stroke" || !(edges in EDGES)) return false;
      if (!grownFrom(op, before) || plan.drag !== old.drag || this.above) return false;
      const now = strokeAt(op, t, plan.drag), was = strokeAt(before, tb, old.drag), w = op.width ?? 24;
      if (!(now.count <= MAX_STEPS) || now.count < was.count) return false;
      const tines = (op.tines ?? [0]).length;
      if (tines > 1 && was.count === 0) return false;  // N0 (the tines' offsets) not settled yet
      const back = stepRows(now, was.count, now.count, w, now.partial);
      const rows = undoneRows(stepRows(was, was.count, was.count, w, was.partial));
      rows.list.push(...back.list);
      rows.n += back.n;
      rows.rect = union(rows.rect, back.rect);
      this.lastStroke = null;
      this.drawPlan(op, t, { kind: 8, p: [], list: [], rows }, bg, EDGES[edges]);
      return true;
    } catch (e) {
      console.warn("warp:", e);
      return false;
    }
  }

  // (``warm``: whether a map is above, for a one-pixel draw of that program; see warm)
  drawPlan(op, t, plan, bg, edges, warm = null) {
    const gl = this.gl, { width, height } = this.canvas;
    let kind = plan.kind, p = plan.p, list = plan.list;
    let steps = { list, n: 0, rect: [1, 1, -1, -1] }, clip = null;
    if (plan.rows) steps = plan.rows;  // a stroke's rows as given (drawStrokeSince): no map
    else if (kind === "stroke") {
      const layout = strokeAt(op, t, plan.drag), builds = this.map.builds ?? 0;
      if (!(layout.count <= MAX_STEPS)) throw new Error(`stroke: ${layout.count} steps`);
      this.map.exact = !!this.exactSteps;
      const folded = this.map.update(op, layout, plan.drag, this.toCanvas, [width, height]);
      kind = 8;
      p = [];
      const sw = op.width ?? 24, last = this.lastStroke;
      steps = this.map.pending(layout, sw);
      // a stroke growing over the same layers changes the frame only where the
      // steps made whole since the last frame, that frame's partial step, this
      // one's and the steps folded now reach (the newest steps act first on the
      // way back: a point out of their reach walks the same steps as before)
      const partial = layout.partial ? stepRows(layout, 0, 0, sw, layout.partial).rect : null;
      if (last && (this.map.builds ?? 0) === builds && layout.count >= last.count) {
        const made = stepRows(layout, last.count, layout.count, sw);
        clip = union(union(made.n ? made.rect : null, folded), union(last.partial, partial)) || [1, 1, -1, -1];
      }
      this.lastStroke = { count: layout.count, partial };
    } else this.lastStroke = null;
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.viewport(0, 0, width, height);
    this.dirty = [0, 0, width, height];
    if (warm !== null) {
      gl.enable(gl.SCISSOR_TEST);
      gl.scissor(0, 0, 1, 1);
    } else if (clip) {
      const [x0, y0, x1, y1] = deviceRect(clip, this.toCanvas, width, height);
      this.dirty = [x0, y0, Math.max(0, x1 - x0), Math.max(0, y1 - y0)];
      if (x1 <= x0 || y1 <= y0) return;
      gl.enable(gl.SCISSOR_TEST);
      gl.scissor(x0, y0, x1 - x0, y1 - y0);
    } else gl.disable(gl.SCISSOR_TEST);
    const { prog, u } = this.program(kind, edges, !!plan.forward, warm ?? !!this.above);
    gl.useProgram(prog);
    setSteps(gl, u, this.list, steps);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, this.base);
    gl.uniform1i(u.uBase, 0);
    gl.uniform2f(u.uBaseSize, ...this.baseSize);
    const wrap = [gl.CLAMP_TO_EDGE, gl.REPEAT, gl.MIRRORED_REPEAT, gl.CLAMP_TO_EDGE][edges];
    const filter = edges === 3 ? gl.NEAREST : gl.LINEAR;
    for (const [k, v] of [[gl.TEXTURE_WRAP_S, wrap], [gl.TEXTURE_WRAP_T, wrap], [gl.TEXTURE_MIN_FILTER, filter], [gl.TEXTURE_MAG_FILTER, filter]]) {
      gl.texParameteri(gl.TEXTURE_2D, k, v);
    }
    gl.uniform3f(u.uBg, ...bg.map((v) => v / 255));
    gl.uniform4f(u.uToBase, ...this.toBase);
    setParams(gl, u, "uQ", p);
    if (plan.forward) setParams(gl, u, "uF", plan.forward);
    gl.activeTexture(gl.TEXTURE2);
    gl.bindTexture(gl.TEXTURE_2D, this.above || this.list);
    gl.uniform1i(u.uAbove, 2);
    this.map.bind(u, 3, kind === 8 && !plan.rows);
    setCommon(gl, u, this.toCanvas, [width, height], op.width ?? 24);
    gl.bindVertexArray(this.vao);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    gl.disable(gl.SCISSOR_TEST);
  }

  // A stroke about to be drawn point by point: its map starts afresh.
  strokeBegin(op) {
    this.map.reset();
    this.lastStroke = null;
    return op;
  }

  // The stroke grown (its points a prefix of the new ones) drawn at t (default:
  // its newest point's time): only new whole steps are folded into the map.
  strokeExtend(op, t, background = "#ffffff", edges = "clamp") {
    return this.draw(op, t ?? op.times?.[op.times.length - 1] ?? 0, background, edges);
  }

  // How many times the stroke map was laid from scratch (tests: a growing stroke lays it once).
  get strokeBuilds() {
    return this.map.builds ?? 0;
  }

  // The last draw's pixels into an ImageData of the canvas' size, kept and
  // reused (RGBA, top row first): all of them, or (``all`` false) only those
  // the draw changed since the one before. Returns { image, rect: [x, y, w, h] }
  // (device pixels, y down) for putImageData's dirty rect. A readPixels and
  // putImageData cost a few ms a 930x620 frame on SwiftShader, where drawing
  // the WebGL canvas into a 2D one cost 15-25 ms.
  read(all = true) {
    const gl = this.gl, { width, height } = this.canvas;
    if (!this.image || this.image.width !== width || this.image.height !== height) {
      this.image = new ImageData(width, height);
      all = true;
    }
    const [x, y, w, h] = all || !this.dirty ? [0, 0, width, height] : this.dirty;
    if (w > 0 && h > 0) {
      if (!this.rows || this.rows.length < w * h * 4) this.rows = new Uint8Array(w * h * 4);
      gl.bindFramebuffer(gl.FRAMEBUFFER, null);
      gl.readPixels(x, y, w, h, gl.RGBA, gl.UNSIGNED_BYTE, this.rows);
      const data = this.image.data, row = w * 4;
      for (let j = 0; j < h; j++) data.set(this.rows.subarray(j * row, (j + 1) * row), ((height - 1 - y - j) * width + x) * 4);
    }
    return { image: this.image, rect: [x, height - y - h, w, h] };
  }

  // The canvas' pixels, RGBA, top row first.
  readPixels() {
    const gl = this.gl, { width, height } = this.canvas, out = new Uint8Array(width * height * 4);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, out);
    const row = width * 4, flipped = new Uint8Array(out.length);
    for (let y = 0; y < height; y++) flipped.set(out.subarray(y * row, (y + 1) * row), (height - 1 - y) * row);
    return flipped;
  }
}

// Whether a frame of ``op`` at t can take ``before`` (the op as it was) off
// forward: the same kind, a forwardable one (not an oseen vortex, whose twist
// packs the picture too tight to take off), and the same list (the pass has one;
// a single drop has none: its row is in its numbers).
export function forwardable(op, before, t) {
  const plan = resolve(op, t);
  return !!plan && FORWARD_KINDS.includes(plan.kind) && !!forwardPlan(before, t, plan);
}
function forwardPlan(before, t, plan) {
  const old = resolve(before, t);
  if (!old || old.kind !== plan.kind || !FORWARD_KINDS.includes(old.kind)) return null;
  if (old.kind === 6 && old.p[2] === 2) return null;  // oseen: its twist loses the picture
  if (old.list.length !== plan.list.length || old.list.some((v, i) => v !== plan.list[i])) return null;
  return old;
}

// An op's first 16 parameters into the uniforms ``${name}0`` .. ``${name}3`` (vec4 each).
function setParams(gl, u, name, p) {
  const params = new Float32Array(16);
  params.set(p.slice(0, 16));
  for (let i = 0; i < 4; i++) gl.uniform4fv(u[`${name}${i}`], params.subarray(4 * i, 4 * i + 4));
}

// Whether stroke ``op`` is ``before`` drawn further: both drawn in time, the same
// width and tines, before's points and times a prefix of op's.
function grownFrom(op, before) {
  const same = (a, b) => JSON.stringify(a) === JSON.stringify(b);
  const prefix = (a, b) => Array.isArray(a) && Array.isArray(b) && a.length <= b.length && same(a, b.slice(0, a.length));
  return (op.width ?? 24) === (before.width ?? 24) && same(op.tines ?? [0], before.tines ?? [0])
    && prefix(before.times, op.times) && prefix(before.points, op.points);
}
// Rows (stepRows') that take their steps off forward when walked back: in the
// reverse order, each with its half-vector negated.
function undoneRows(rows) {
  const out = [];
  for (let i = rows.n - 1; i >= 0; i--) {
    const r = rows.list.slice(8 * i, 8 * i + 8);
    r[2] = -r[2];
    r[3] = -r[3];
    out.push(...r);
  }
  rows.list = out;
  return rows;
}

// The smallest canvas rect [x0, y0, x1, y1] holding both (each may be null).
function union(a, b) {
  if (!a || !b) return a || b || null;
  return [Math.min(a[0], b[0]), Math.min(a[1], b[1]), Math.max(a[2], b[2]), Math.max(a[3], b[3])];
}
