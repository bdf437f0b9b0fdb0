/* glsl/prelude.glsl: the op sections' dialect in GLSL 3.30 and GLSL ES 3.00
 * (marblevideo/export/dialect.py turns kernels/math.cl, edges.cl and ops/*.cl
 * into GLSL; this file stands where kernels/prelude.cl stands for OpenCL).
 * One pixel per invocation: LANES, CHAINS and ROWS are 1, the lane types are
 * scalars, a mask is a bool. Every float of the frames' data is in MV_DATA (an
 * op's row, the lists): a data pointer of the dialect is an offset into it. */

#define vf float
#define vi int
#define vu uint
#define vm bool

float select(float a, float b, bool m) { return m ? b : a; }
int select(int a, int b, bool m) { return m ? b : a; }
#define ANY(m) (m)
#define AS_VF(v) intBitsToFloat(v)
#define AS_VI(v) floatBitsToInt(v)
#define CVT_F(v) float(v)
#define CVT_I(v) int(v)
#define native_recip(x) (1.0 / (x))
float copysign(float a, float b) { return b < 0.0 ? -abs(a) : abs(a); }

/* Row k of a table whose rows cover frames first .. first + count - 1. */
#define MV_STEP(k, first, count) clamp((k) - (first), 0, (count) - 1)
/* Op i's row at the frame `frame` (a variable of the walk's scope): its offset. */
#define PARAMS(i) ((MV_ROW_AT[i] + MV_STEP(frame, MV_FIRST[i], MV_COUNT[i])) * PSTRIDE)
/* The walk of kernels/prelude.cl, one chain: px, py, ink are arrays of one. */
#define OP(i, section)                                                         \
    if (MV_DATA[PARAMS(i) + CODE_SLOT] >= 0.0)                                 \
        section(px[0], py[0], ink[0], PARAMS(i), i, lists);
#define OP_CHAINS(i, section)                                                  \
    if (MV_DATA[PARAMS(i) + CODE_SLOT] >= 0.0)                                 \
        section(px, py, ink, PARAMS(i), i, lists);
#define INK_COLOR(i)                                                           \
    { bool m_ = ink[0] == i;                                                   \
      cr = select(cr, MV_DATA[PARAMS(i) + COLOR_SLOT], m_);                    \
      cg = select(cg, MV_DATA[PARAMS(i) + COLOR_SLOT + 1], m_);                \
      cb = select(cb, MV_DATA[PARAMS(i) + COLOR_SLOT + 2], m_); }
