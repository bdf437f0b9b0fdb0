/* prelude.cl: what every part of the OpenCL program shares: build-time
 * defines, the vector types (vf floats, vi ints, vu unsigned, vm masks: all
 * bits set where true) and the op sections' signature and walk macros. The math
 * helpers are in math.cl, written like the op sections in the dialect that also
 * compiles as GLSL (marblevideo/export/dialect.py).
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
typedef int vm;
#define IOTA 0.0f
#define ANY(m) ((m) != 0)
#define VLOAD(arr) ((arr)[0])
#define VSTORE(v, arr) ((arr)[0] = (v))
#else
typedef CAT(float, LANES) vf;
typedef CAT(int, LANES) vi;
typedef CAT(uint, LANES) vu;
typedef CAT(int, LANES) vm;
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
