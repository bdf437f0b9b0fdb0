// WebGL2 plumbing the warp's passes share (warp.js, warp_map.js): programs,
// textures, and the uniforms of the geometry and the stroke steps walked.
import { VERTEX } from "./warp_shaders.js";

const LIST_WIDTH = 1024;

export function program(gl, fragment) {
  const prog = gl.createProgram();
  for (const [type, src] of [[gl.VERTEX_SHADER, VERTEX], [gl.FRAGMENT_SHADER, fragment]]) {
    const sh = gl.createShader(type);
    gl.shaderSource(sh, src);
    gl.compileShader(sh);
    if (!gl.getShaderParameter(sh, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(sh));
    gl.attachShader(prog, sh);
  }
  gl.linkProgram(prog);
  if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(prog));
  const names = {};
  const n = gl.getProgramParameter(prog, gl.ACTIVE_UNIFORMS);
  for (let i = 0; i < n; i++) {
    const name = gl.getActiveUniform(prog, i).name.replace(/\[0\]$/, "");
    names[name] = gl.getUniformLocation(prog, name);
  }
  return { prog, u: names };
}

export function texture(gl, filter = gl.NEAREST) {
  const tex = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, tex);
  for (const [k, v] of [[gl.TEXTURE_MIN_FILTER, filter], [gl.TEXTURE_MAG_FILTER, filter], [gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE], [gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE]]) {
    gl.texParameteri(gl.TEXTURE_2D, k, v);
  }
  return tex;
}

// The uniforms both passes share: the geometry and the stroke's width.
export function setCommon(gl, u, toCanvas, size, width) {
  gl.uniform2f(u.uSize, ...size);
  gl.uniform4f(u.uToCanvas, ...toCanvas);
  gl.uniform1f(u.uWidth, width);
}

// Values (RGBA32F texels, LIST_WIDTH a row) into the list texture on unit 1.
export function uploadList(gl, tex, values) {
  const texels = Math.max(1, Math.ceil(values.length / 4)), rows = Math.ceil(texels / LIST_WIDTH);
  const data = new Float32Array(rows * LIST_WIDTH * 4);
  data.set(values);
  gl.activeTexture(gl.TEXTURE1);
  gl.bindTexture(gl.TEXTURE_2D, tex);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, LIST_WIDTH, rows, 0, gl.RGBA, gl.FLOAT, data);
}
