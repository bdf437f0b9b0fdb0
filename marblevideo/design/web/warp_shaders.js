// GLSL ES 3.00 sources of the warp (warp.js): one full-screen pass that walks a
// device pixel's canvas point back through the ops above (a map), the changing
// op (its inverse, float32, as marblevideo/reference and kernels/ops/*.cl) and
// a stroke's accumulated whole steps (a displacement map), then samples the
// base bilinearly (pixel centres at +0.5, taps mapped by the recipe's edges);
// and one pass that folds a chunk of whole stroke steps into that map.
// Rows of the framebuffer run bottom-up: device pixel (x, y) with y down is
// gl_FragCoord (x + 0.5, H - y - 0.5); the base and the above map are uploaded
// top row first, so their texel (i, j) is device pixel (i, j).

export const VERTEX = `#version 300 es
void main() {
  vec2 v = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(v * 2.0 - 1.0, 0.0, 1.0);
}`;

const COMMON = `precision highp float;
precision highp int;
precision highp sampler2D;
uniform vec2 uSize;
uniform vec4 uToCanvas;
uniform int uHasMap;
uniform sampler2D uMap;
uniform sampler2D uTiles;
uniform float uWidth;
uniform sampler2D uList;
uniform int uListN;
uniform vec4 uRect;
out vec4 outColor;
const float TAU = 6.283185307179586;

vec2 rot(vec2 q, float t) { float c = cos(t), s = sin(t); return vec2(q.x * c - q.y * s, q.x * s + q.y * c); }
vec2 devicePoint() { return vec2(gl_FragCoord.x, uSize.y - gl_FragCoord.y); }

// SwiftShader (the CPU WebGL2 of a machine without a GPU) runs a SIMD group's
// lanes together; an if may cost both its sides, while a loop ends as soon as
// no lane goes on. So the costly blocks below sit in loops run once (or not at
// all): a group where every point is out of reach skips them. (Measured only
// together with the two changes above drawSource's: not apart.)

// One tine's step backwards: about B = c - h by +theta g, then A = c + h by -theta g.
vec2 turnBack(vec2 P, vec4 s, float theta, float w2) {
  vec2 b = s.xy - s.zw, a = s.xy + s.zw, qb = P - b;
  float g = max(0.0, 1.0 - dot(qb, qb) / w2);
  vec2 P1 = b + rot(qb, theta * g * g), qa = P1 - a;
  g = max(0.0, 1.0 - dot(qa, qa) / w2);
  return a + rot(qa, -theta * g * g);
}

vec4 L(int i) { return texelFetch(uList, ivec2(i & 1023, i >> 10), 0); }

// Whole stroke steps walked back one by one (list rows: cx, cy, hx, hy; theta,
// then the circle of the row's block of BLOCK rows: cx, cy, r^2), none for a
// point outside uRect (their reach, canvas units), a block skipped at its top
// row where the point is outside its circle (every point its rows can move:
// exact, as the kernels' blocks), a row where it is beyond the row's reach.
const int BLOCK = 8;
vec2 stepsBack(vec2 P) {
  float w2 = uWidth * uWidth, reach = 2.25 * w2;
  bool inside = all(greaterThanEqual(P, uRect.xy)) && all(lessThanEqual(P, uRect.zw));
  for (int k = (inside ? uListN : 0) - 1; k >= 0; k--) {
    vec4 t = L(2 * k + 1);
    if (k % BLOCK == BLOCK - 1 || k == uListN - 1) {
      vec2 b = P - t.yz;
      if (dot(b, b) >= t.w) { k -= k % BLOCK; continue; }
    }
    vec4 s = L(2 * k);
    vec2 q = P - s.xy;
    for (int once = dot(q, q) < reach ? 1 : 0; once > 0; once--) P = turnBack(P, s, t.x, w2);
  }
  return P;
}

// The accumulated displacement at canvas point Q, clamped at the edges: folding
// a chunk into the map reads it by Catmull-Rom (the map is smooth but steep near
// a stroke, and bilinear reads, one per fold, lose a pixel there); the frame's
// one read is bilinear (it agrees as well: the folds' reads are what count).
vec2 texMap(ivec2 i) { return texelFetch(uMap, clamp(i, ivec2(0), ivec2(uSize) - 1), 0).xy; }
vec4 catmull(float t) {
  float t2 = t * t, t3 = t2 * t;
  return 0.5 * vec4(-t3 + 2.0 * t2 - t, 3.0 * t3 - 5.0 * t2 + 2.0, -3.0 * t3 + 4.0 * t2 + t, t3 - t2);
}
vec2 displacement(vec2 Q) {
  vec2 dev = (Q - uToCanvas.zw) / uToCanvas.xy;
  vec2 f = vec2(dev.x, uSize.y - dev.y) - 0.5;
#if defined(KIND)
  vec2 g0 = floor(f), wt = f - g0;
  ivec2 i = ivec2(g0);
  vec2 lo = mix(texMap(i), texMap(i + ivec2(1, 0)), wt.x);
  return mix(lo, mix(texMap(i + ivec2(0, 1)), texMap(i + ivec2(1, 1)), wt.x), wt.y);
#else
  vec2 f0 = floor(f);
  vec4 wx = catmull(f.x - f0.x), wy = catmull(f.y - f0.y);
  ivec2 i0 = ivec2(f0) - 1;
  vec2 sum = vec2(0.0);
  for (int j = 0; j < 4; j++) {
    vec2 row = wx.x * texMap(i0 + ivec2(0, j)) + wx.y * texMap(i0 + ivec2(1, j))
      + wx.z * texMap(i0 + ivec2(2, j)) + wx.w * texMap(i0 + ivec2(3, j));
    sum += wy[j] * row;
  }
  return sum;
#endif
}

vec2 mapped(vec2 Q) {
  vec2 dev = (Q - uToCanvas.zw) / uToCanvas.xy;
  ivec2 tile = clamp(ivec2(floor(dev / 16.0)), ivec2(0), textureSize(uTiles, 0) - 1);
  bool inside = uHasMap == 1 && texelFetch(uTiles, tile, 0).r > 0.5;
  for (int once = inside ? 1 : 0; once > 0; once--) return Q + displacement(Q);
  return Q;
}
`;

// A chunk of whole steps folded into the displacement map: out = map_old(chunk^-1(P)) - P.
export const STEP = `#version 300 es
${COMMON}
void main() {
  vec2 P = devicePoint() * uToCanvas.xy + uToCanvas.zw;
  outColor = vec4(mapped(stepsBack(P)) - P, 0.0, 1.0);
}`;

// The draw pass specialised to one kind of op (warp_ops.js' kinds; 8 a stroke),
// edges mode (0 clamp, 1 repeat, 2 mirror, 3 background) and whether a map of
// the ops above is given, so each program holds only its own op's code: one
// shader for every kind, switched by uniform ifs, took 695 ms a 1024x768 drop
// frame on SwiftShader under load 17, this 90 ms under load 15 (and a uniform
// array, even unindexed, cost a stroke frame 240 ms more: the shaders have none).
// ``forward``: the base is the exact frame of the recipe with the op as it was
// (its numbers uF0..uF3) on top, which the pass takes off forward (base(old(inv_op(q))));
// for the kinds in FORWARD_KINDS, with no map above.
export const FORWARD_KINDS = [2, 3, 4, 5, 6, 7, 9, 10, 11];
export function drawSource(kind, edges, above, forward = false) {
  return `#version 300 es
#define KIND ${kind}
#define EDGES ${edges}
#define ABOVE ${above ? 1 : 0}
#define FORWARD ${forward ? 1 : 0}
${COMMON}${DRAW}`;
}

const DRAW = `
uniform vec4 uToBase;
uniform sampler2D uBase;
uniform vec2 uBaseSize;
uniform vec3 uBg;
uniform vec4 uQ0, uQ1, uQ2, uQ3; // the op's numbers (warp_ops.js' p), four a vector
#if FORWARD
uniform vec4 uF0, uF1, uF2, uF3; // the op's numbers before the gesture (the exact frame's)
#endif
// the numbers the op's functions read: uQ, then (FORWARD) uF
vec4 Q0, Q1, Q2, Q3;
uniform sampler2D uAbove;

bool inkHit = false;
vec3 inkColor = vec3(0.0);

vec2 drops(vec2 P) {
  for (int k = int(Q0.x) - 1; k >= 0; k--) {
    vec4 a = L(2 * k);
    vec2 q = P - a.xy;
    float R = length(q);
    if (R < a.z) { inkHit = true; inkColor = L(2 * k + 1).rgb; return P; }
    if (a.w > 0.5 && R > 0.0) P = a.xy + q * (sqrt(max((R - a.z) * (R + a.z), 0.0)) / R);
  }
  return P;
}

// One drop (kind 11): Q1 its centre, radius and whether it pushes, Q2 its colour.
vec2 drop(vec2 P) {
  vec2 q = P - Q1.xy;
  float R = length(q);
  if (R < Q1.z) { inkHit = true; inkColor = Q2.rgb; return P; }
  return Q1.w > 0.5 && R > 0.0 ? Q1.xy + q * (sqrt(max((R - Q1.z) * (R + Q1.z), 0.0)) / R) : P;
}

// sum_k c_k e^(-|u - o_k| / L) over n evenly spaced terms in closed form, as
// kernels/prelude.cl series_sum (two geometric series either side of u: four
// exponentials for any n). Q2, Q3: o0, 1/s, s, s/L; 1/(1 - sigma q), c0,
// sigma, sigma^(n-1) (warp_ops.js closedSeries).
float seriesSum(float u, float invL, float n) {
  float o0 = Q2.x, step = Q2.z, ratio = Q2.w, sigma = Q3.z;
  float j = clamp(floor((u - o0) * Q2.y), -1.0, n - 1.0);
  float b = u - (o0 + j * step);
  float sj = 1.0 + (sigma - 1.0) * (j - 2.0 * floor(0.5 * j));
  float below = exp(-(j < 0.0 ? 0.0 : b) * invL);
  float above = exp(-(j >= n - 1.0 ? 0.0 : step - b) * invL);
  below *= 1.0 - sj * sigma * exp(-(j + 1.0) * ratio);
  above *= sigma * (1.0 - Q3.w * sj * exp(-(n - 1.0 - j) * ratio));
  return Q3.y * Q3.x * sj * (below + above);
}

vec2 shears(vec2 P) {
  vec2 A = vec2(Q0.x, Q0.y), M = vec2(Q0.z, Q0.w), N = vec2(-M.y, M.x);
  float across = dot(P - A, N), shift;
#if KIND == 2
  {
    float d = abs(across), s = Q1.z, lam = Q1.y;
    if (s > 0.0) d = 0.5 * s - abs(d - s * floor(d / s) - 0.5 * s);
    shift = Q1.x * lam / (d + lam);
  }
#elif KIND == 9
  shift = Q1.x * seriesSum(across, Q1.y, Q1.z);
#else
  {
    float sum = 0.0;
    for (int k = 0; k < int(Q1.z); k++) sum += exp(-abs(across - L(k).x) * Q1.y);
    shift = Q1.x * sum;
  }
#endif
  return P - shift * M;
}

#if KIND == 10
// A stir whose rings are a closed-form series: theta = alpha sum(R) / R.
vec2 rotations(vec2 P) {
  vec2 C = vec2(Q0.x, Q0.y), q = P - C;
  float R = length(q);
  return C + rot(q, R > 0.0 ? -Q0.w * seriesSum(R, Q1.x, Q1.z) / R : 0.0);
}
#else
vec2 rotations(vec2 P) {
  vec2 C = vec2(Q0.x, Q0.y), q = P - C;
  int sub = int(Q0.z);
  float R = length(q), a = Q0.w, b = Q1.x, c = Q1.y, theta = 0.0;
  if (sub == 0) {
    float d = c < 0.0 ? R : abs(R - c);
    theta = R > 0.0 ? a * b / (d + b) / R : 0.0;
  } else if (sub == 1) {
    theta = a;
  } else if (sub == 2) {
    theta = a * pow(b + c * R * sqrt(R), -4.0 / 3.0);
  } else {
    float sum = 0.0;
    for (int k = 0; k < int(Q1.z); k++) { vec4 r = L(k); sum += r.y * exp(-abs(R - r.x) * r.z); }
    theta = sub == 4 ? a * sum : (R > 0.0 ? a * sum / R : 0.0);
  }
  return C + rot(q, -theta);
}
#endif

vec2 jiggle(vec2 P) {
  vec2 M = vec2(Q0.x, Q0.y), N = vec2(-M.y, M.x);
  float inv = Q0.z, ph = Q0.w, A = Q1.x, B = Q1.y, ka = TAU * inv * A;
  float so = dot(P, M), s = so, lo = so - abs(A), hi = so + abs(A);
  for (int k = 0; k < 12; k++) {
    float tau = TAU * fract(s * inv + ph);
    float g = s + A * sin(tau) - so;
    if (g < 0.0) lo = s; else if (g > 0.0) hi = s;
    float nxt = s - g / (1.0 + ka * cos(tau));
    s = (nxt <= lo || nxt >= hi) ? 0.5 * (lo + hi) : nxt;
  }
  float tau = TAU * fract(s * inv + ph);
  return P - A * sin(tau) * M - B * cos(tau) * N;
}

vec2 wave(vec2 P) {
  vec2 M = vec2(Q0.x, Q0.y);
  float across = P.x * M.y - P.y * M.x;
  return P - Q0.z * sin(TAU * fract(across * Q0.w + Q1.x)) * M;
}

vec2 inverseOp(vec2 P) {
#if KIND == 1
  return drops(P);
#elif KIND == 11
  return drop(P);
#elif KIND == 2 || KIND == 5 || KIND == 9
  return shears(P);
#elif KIND == 3
  return wave(P);
#elif KIND == 4
  return P - vec2(Q0.x, Q0.y);
#elif KIND == 6 || KIND == 10
  return rotations(P);
#elif KIND == 7
  return jiggle(P);
#elif KIND == 8
  return mapped(stepsBack(P));
#else
  return P;
#endif
}

#if EDGES == 3
vec4 tap(vec2 i) {
  vec2 n = uBaseSize;
  if (any(lessThan(i, vec2(0.0))) || any(greaterThanEqual(i, n))) return vec4(uBg, 1.0);
  return texelFetch(uBase, ivec2(i), 0);
}
#endif

// Bilinear between pixel centres: the texture unit's own (its wrap mode is the
// edges mode) or, for background edges, four taps.
vec4 sampleBase(vec2 P) {
  vec2 f = P * uToBase.xy + uToBase.zw;
#if EDGES != 3
  return texture(uBase, f / uBaseSize);
#else
  f -= 0.5;
  vec2 f0 = floor(f), w = f - f0;
  vec4 a = mix(tap(f0), tap(f0 + vec2(1.0, 0.0)), w.x);
  vec4 b = mix(tap(f0 + vec2(0.0, 1.0)), tap(f0 + vec2(1.0, 1.0)), w.x);
  return mix(a, b, w.y);
#endif
}

#if FORWARD
// The op before the gesture, forward (the kinds whose inverse moves a point along
// a line or circle it does not leave: forward is the same step the other way).
vec2 forwardOp(vec2 P) {
#if KIND == 11
  // one drop (Q1, as drop() reads it: centre, radius, whether it pushes): the plane
  // pushed out from its centre, P' = C + q sqrt(1 + r^2 / |q|^2) (drop() is its inverse)
  vec2 q = P - Q1.xy;
  float R2 = dot(q, q);
  return Q1.w > 0.5 && R2 > 0.0 ? Q1.xy + q * sqrt(1.0 + Q1.z * Q1.z / R2) : P;
#elif KIND == 2 || KIND == 5 || KIND == 9
  return 2.0 * P - shears(P);
#elif KIND == 3
  return 2.0 * P - wave(P);
#elif KIND == 4
  return P + vec2(Q0.x, Q0.y);
#elif KIND == 6 || KIND == 10
  // rot(q, theta) = 2 cos(theta) q - rot(q, -theta), cos(theta) = q.rot(q, -theta) / |q|^2
  vec2 C = vec2(Q0.x, Q0.y), q = P - C, back = rotations(P) - C;
  float r2 = dot(q, q);
  return r2 > 0.0 ? C + (2.0 * dot(q, back) / r2) * q - back : P;
#elif KIND == 7
  vec2 M = vec2(Q0.x, Q0.y), N = vec2(-M.y, M.x);
  float tau = TAU * fract(dot(P, M) * Q0.z + Q0.w);
  return P + Q1.x * sin(tau) * M + Q1.y * cos(tau) * N;
#else
  return P;
#endif
}
#endif

void main() {
  Q0 = uQ0; Q1 = uQ1; Q2 = uQ2; Q3 = uQ3;
  vec2 P = devicePoint() * uToCanvas.xy + uToCanvas.zw;
#if ABOVE
  vec4 a = texelFetch(uAbove, ivec2(int(gl_FragCoord.x), int(uSize.y - gl_FragCoord.y)), 0);
  if (a.w < 0.0) { outColor = vec4(a.rgb, 1.0); return; }
  P = a.xy;
#endif
  P = inverseOp(P);
#if FORWARD
  // the base is the exact frame, the op before the gesture on top: taken off
  // forward from where the layers' base would be sampled (the edges mode taken
  // first, in base pixels, as the texture unit does)
  vec2 f = P * uToBase.xy + uToBase.zw, n = uBaseSize;
#if EDGES == 0
  f = clamp(f, vec2(0.5), n - 0.5);
#elif EDGES == 1
  f = mod(f, n);
#elif EDGES == 2
  f = mod(f, 2.0 * n);
  f = mix(f, 2.0 * n - f, step(n, f));
#else
  if (!inkHit && (any(lessThan(f, vec2(0.0))) || any(greaterThanEqual(f, n)))) { outColor = vec4(uBg, 1.0); return; }
#endif
  P = (f - uToBase.zw) / uToBase.xy;
  Q0 = uF0; Q1 = uF1; Q2 = uF2; Q3 = uF3;
  P = forwardOp(P);
#endif
  outColor = inkHit ? vec4(inkColor, 1.0) : sampleBase(P);
}`;
