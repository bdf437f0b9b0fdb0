/* prelude.cl: what every part of the program shares: build-time defines,
 * the vector types and the math helpers of the op sections.
 *
 * Conventions (docs/recipe-format.md): canvas units, origin top-left,
 * x right, y down; output pixel (i, j) has its centre at (i + 0.5, j + 0.5);
 * input pixels likewise; images are packed RGBA8 (R in the low byte).
 *
 * The program is this prelude, one file of op sections per op family
 * (kernels/ops/<family>.cl, one `op_<type>(OP_ARGS)` each) and the kernels'
 * files by concern (sampling.cl, walk.cl, adaptive.cl, tables.cl, i420.cl,
 * planar.cl, lattice.cl; marblevideo/opencl/program.py: KERNEL_FILES), after a
 * header that marblevideo/opencl/header.py generates from the op definitions:
 * each op's parameter offsets P_<TYPE>_<SLOT> (a section reads p[P_DROP_R2]),
 * its type code CODE_<TYPE>, CODE_STILL, PSTRIDE (floats per op in `params`;
 * the last, CODE_SLOT, holds the op's type code), COLOR_SLOT (where an ink
 * op's red, green, blue start), the edges modes EDGES_<MODE>, and WALK and INK
 * for the recipe's structure. Build-time defines (-D):
 *   LANES    pixels per work-item along x, as one vector: on CPUs the device's
 *            native float width (4 SSE, 8 AVX/AVX2, 16 AVX-512), 1 on GPUs
 *   YLANES   pixels per work-item of the I420 and quad kernels (4, 8 or 16)
 *   CHAINS   independent (row, subsample) jobs evaluated side by side per work-item
 *   ROWS     output rows per work-item (> 1 only without antialiasing)
 *   NSAMPLES subsamples per pixel; offsets and weights arrive in `samples`
 *   HAS_INPUT 1: sample the input image where no ink is hit; 0: blank sheet
 *   EDGES    what lies outside the input: EDGES_CLAMP, EDGES_REPEAT,
 *            EDGES_MIRROR or EDGES_BACKGROUND
 * Per-frame values live in `params`, packed by each op's definition
 * (marblevideo/ops: its `pack`). Changing them never rebuilds the program.
 *
 * No vector wider than the device's native width is passed by value to a
 * function (an x86 ABI change that clang warns about): vectors are LANES or
 * YLANES wide, both at most the native width on CPUs, and the wider kernel
 * arguments (the I420 matrix) are read only in macros.
 */

/* The address space of `lists`, the frame's variable-length data: a buffer
 * for the renderer; an exported program (marblevideo/export) holds its frames'
 * data as program-scope constants and defines it as __constant. */
#ifndef LIST_SPACE
#define LIST_SPACE __global
#endif

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)

#if LANES == 1
typedef float vf;
typedef int vi;
typedef uint vu;
#define IOTA 0.0f
#define ANY(m) ((m) != 0)
#define VLOAD(arr) ((arr)[0])
#define VSTORE(v, arr) ((arr)[0] = (v))
#else
typedef CAT(float, LANES) vf;
typedef CAT(int, LANES) vi;
typedef CAT(uint, LANES) vu;
#define ANY(m) any(m)
#define VLOAD(arr) CAT(vload, LANES)(0, (arr))
#define VSTORE(v, arr) CAT(vstore, LANES)((v), 0, (arr))
#if LANES == 4
#define IOTA ((vf)(0, 1, 2, 3))
#elif LANES == 8
#define IOTA ((vf)(0, 1, 2, 3, 4, 5, 6, 7))
#elif LANES == 16
#define IOTA ((vf)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15))
#else
#error "LANES must be 1, 4, 8 or 16"
#endif
#endif

#define AS_VF(v) CAT(as_float, LANES)(v)
#define AS_VI(v) CAT(as_int, LANES)(v)
#define CVT_F(v) CAT(convert_float, LANES)(v)
#define CVT_I(v) CAT(convert_int, LANES)(v)
#define CVT_U(v) CAT(convert_uint, LANES)(v)
#if LANES == 1
#undef CVT_F
#undef CVT_I
#undef CVT_U
#undef AS_VF
#undef AS_VI
#define AS_VF(v) as_float(v)
#define AS_VI(v) as_int(v)
#define CVT_F(v) convert_float(v)
#define CVT_I(v) convert_int(v)
#define CVT_U(v) convert_uint(v)
#endif

/* sin(2*pi*t) without the library sin: exact range reduction in turns, a
 * fold to [-1/4, 1/4] turn and an odd Taylor polynomial (error < 1e-7). */
inline vf sin_turns(vf t) {
    vf u = t - floor(t + 0.5f);                        /* [-0.5, 0.5) */
    vf f = select(u, copysign((vf)0.5f, u) - u, fabs(u) > 0.25f);
    vf x = f * 6.28318530718f;
    vf x2 = x * x;
    return x * (1.0f + x2 * (-1.6666667e-1f + x2 * (8.3333333e-3f + x2 * (-1.9841270e-4f
               + x2 * (2.7557319e-6f + x2 * -2.5052108e-8f)))));
}

/* sin and cos of 2*pi*t from one range reduction: the half angle h = pi*u,
 * u in [-1/2, 1/2), has Taylor polynomials good to 6e-8 on [-pi/2, pi/2];
 * then sin = 2 sin(h) cos(h), cos = 1 - 2 sin(h)^2. Fewer live values than two
 * sin_turns calls, which spilled registers with 4 chains of 16 lanes. */
inline void sincos_turns(vf t, vf *sn, vf *cs) {
    vf h = (t - floor(t + 0.5f)) * 3.14159265359f;
    vf h2 = h * h;
    vf s = h * (1.0f + h2 * (-1.6666667e-1f + h2 * (8.3333333e-3f + h2 * (-1.9841270e-4f
               + h2 * (2.7557319e-6f + h2 * -2.5052108e-8f)))));
    vf c = 1.0f + h2 * (-0.5f + h2 * (4.1666667e-2f + h2 * (-1.3888889e-3f + h2 * (2.4801587e-5f
               + h2 * (-2.7557319e-7f + h2 * 2.0876757e-9f)))));
    *sn = 2.0f * s * c;
    *cs = 1.0f - 2.0f * s * s;
}

/* e^-x for x >= 0 (0 from x = 87 on), without the library exp: 2^t with
 * t = -x log2(e) split into a whole n and f in [-1/2, 1/2), 2^f by its Taylor
 * polynomial (relative error < 2e-7) and 2^n put into the exponent bits. */
inline vf exp_neg(vf x) {
    vf t = fmin(x, 87.0f) * -1.44269504089f;
    vf n = floor(t + 0.5f);
    vf f = (t - n) * 0.69314718056f;
    vf q = 1.0f + f * (1.0f + f * (0.5f + f * (1.6666667e-1f + f * (4.1666667e-2f
               + f * (8.3333333e-3f + f * (1.3888889e-3f + f * 1.9841270e-4f))))));
    vf scale = AS_VF((CVT_I(n) + 127) << 23);
    return select(q * scale, (vf)0.0f, x >= 87.0f);
}

/* sum_k c_k e^(-|u - o_k| / L) (inv_l = 1/L) over a rake's tines or a stir's
 * rings, their data at d (marblevideo/ops/series.py). Term by term: n positions
 * o_k, then n coefficients c_k. In closed form (even), for o_k = o0 + k s and
 * c_k = c0 sigma^k (sigma = +-1): with j the last o_k at or below u (-1 .. n-1)
 * and b = u - o_j, the terms up to j sum to c_j e^(-b/L) (1 - (sigma q)^(j+1))
 * / (1 - sigma q) and those above to c_(j+1) e^(-(s-b)/L) (1 - (sigma
 * q)^(n-1-j)) / (1 - sigma q), q = e^(-s/L): four exponentials for any n; a
 * side without terms gets an argument of 0 and a factor of exactly 0.
 * d: o0, 1/s, s, s/L, 1/(1 - sigma q), c0, sigma, sigma^(n-1). */
inline vf series_sum(vf u, LIST_SPACE const float *d, int n, int even, float inv_l) {
    if (!even) {
        vf sum = (vf)0.0f;
        for (int k = 0; k < n; k++)
            sum += d[n + k] * exp_neg(fabs(u - d[k]) * inv_l);
        return sum;
    }
    const float step = d[2], ratio = d[3], sigma = d[6];
    vf j = clamp(floor((u - d[0]) * d[1]), -1.0f, (float)(n - 1));
    vf b = u - (d[0] + j * step);
    vf sj = 1.0f + (sigma - 1.0f) * (j - 2.0f * floor(0.5f * j)); /* sigma^j */
    vf below = exp_neg(select(b, (vf)0.0f, j < 0.0f) * inv_l);
    vf above = exp_neg(select(step - b, (vf)0.0f, j >= (float)(n - 1)) * inv_l);
    below *= 1.0f - sj * sigma * exp_neg((j + 1.0f) * ratio);
    above *= sigma * (1.0f - d[7] * sj * exp_neg(((float)(n - 1) - j) * ratio));
    return (d[5] * d[4]) * sj * (below + above);
}

/* z^(1/3) for z > 0, without the library: a guess from the exponent bits (within
 * 4%), then three Newton steps (relative error < 1e-7). */
inline vf cbrt_pos(vf z) {
    vf y = AS_VF(AS_VI(z) / 3 + 709921077);
    for (int k = 0; k < 3; k++)
        y = (2.0f * y + z / (y * y)) * (1.0f / 3.0f);
    return y;
}

/* 1/x for x > 0: the device's fast reciprocal and one Newton step (full float
 * precision from an estimate of 12+ bits; 12% faster walks on PoCL than a
 * division). x is capped at 1e30 so that an infinite x gives ~0, not NaN. */
inline vf recip(vf x) {
    x = fmin(x, 1e30f);
    vf y = native_recip(x);
    return y * (2.0f - x * y);
}

/* The fixed signature of an op section: the point (x, y) of each lane walked
 * back through op i (P' -> P, in place), `ink` set to i where the point is ink
 * of op i and no later op's (ink < 0 so far), `p` the op's packed floats,
 * `lists` the frame's variable-length data (the number of ops, then each op's
 * data where it packed it). */
#define OP_ARGS vf *x, vf *y, vi *ink, __constant const float *p, int i, \
                LIST_SPACE const float *lists

/* The walk's macros, shared by the renderer's kernels (walk.cl) and the exported
 * programs: a work-item's CHAINS chains hold their points in px[c], py[c] and
 * ink[c]; PARAMS(i) is op i's packed row (in the renderer's frame buffer
 * `params`; an export redefines it) and `lists` the frame's list data. */
#define FOR_CHAINS for (int c = 0; c < CHAINS; c++)
#define PARAMS(i) (params + (i) * PSTRIDE)
/* Op i in every chain through its section `section` (op_<type>; the generated
 * WALK is a list of these, or a loop whose switch has one case per op type). An
 * op still this frame (CODE_STILL: not started yet) is skipped, by a branch
 * every lane takes alike. */
#define OP(i, section)                                                         \
    if (PARAMS(i)[CODE_SLOT] >= 0.0f)                                          \
        FOR_CHAINS section(&px[c], &py[c], &ink[c], PARAMS(i), i, lists);
/* The same for a chained section (OpDef.chained), called once for every chain. */
#define OP_CHAINS(i, section)                                                  \
    if (PARAMS(i)[CODE_SLOT] >= 0.0f)                                          \
        section(px, py, ink, PARAMS(i), i, lists);
/* The colour of ink op i for the lanes whose walk ended there (INK lists these). */
#define INK_COLOR(i)                                                           \
    { vi m = ink[c] == i;                                                      \
      float r_ = PARAMS(i)[COLOR_SLOT], g_ = PARAMS(i)[COLOR_SLOT + 1];        \
      float b_ = PARAMS(i)[COLOR_SLOT + 2];                                    \
      cr = select(cr, (vf)r_, m);                                              \
      cg = select(cg, (vf)g_, m);                                              \
      cb = select(cb, (vf)b_, m); }
