/* i420.cl: 8-bit 4:2:0 frames to and from packed RGBA. */

/* ---- 8-bit 4:2:0 video frames (I420) ------------------------------------
 * I420: Y (w x h), then U and V (w/2 x h/2), rows in order; w and h even.
 * m: a 3x4 affine matrix, row-major in m.s0..s3 (first output), s4..s7, s8..sb,
 * applied to (a, b, c, 1) in float32 (marblevideo/yuv.py is the reference).
 * Work-item: YLANES pixels of two rows (one row of chroma); the vector part
 * does whole runs of YLANES, the last run of a row goes pixel by pixel. These
 * kernels do not depend on LANES. The matrix is a float16 argument read only
 * in macros (passing it to a function by value changes the ABI on AVX2). */
#ifndef YLANES
#define YLANES 16
#endif
/* YHALF: chroma samples of a run; TWICE: chroma sample k covers luma pixels 2k, 2k + 1 */
#if YLANES == 4
#define YHALF 2
#define TWICE ((uchar4)(0, 0, 1, 1))
#elif YLANES == 8
#define YHALF 4
#define TWICE ((uchar8)(0, 0, 1, 1, 2, 2, 3, 3))
#elif YLANES == 16
#define YHALF 8
#define TWICE ((uchar16)(0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7))
#else
#error "YLANES must be 4, 8 or 16"
#endif
typedef CAT(float, YLANES) yf;
typedef CAT(uint, YLANES) yu;
typedef CAT(float, YHALF) yhf;
#define CVT_YF(v) CAT(convert_float, YLANES)(v)
#define CVT_YU(v) CAT(convert_uint, YLANES)(v)
#define CVT_YB(v) CAT(convert_uchar, YLANES)(v)
#define CVT_YHB(v) CAT(convert_uchar, YHALF)(v)
#define VLOAD_Y(p) CAT(vload, YLANES)(0, (p))
#define VSTORE_Y(v, p) CAT(vstore, YLANES)((v), 0, (p))
#define VLOAD_YH(p) CAT(vload, YHALF)(0, (p))
#define VSTORE_YH(v, p) CAT(vstore, YHALF)((v), 0, (p))

#define CODE8(v) clamp(floor((v) + 0.5f), 0.0f, 255.0f)
#define ROW0(m, a, b, c) ((((m).s0 * (a) + (m).s1 * (b)) + (m).s2 * (c)) + (m).s3)
#define ROW1(m, a, b, c) ((((m).s4 * (a) + (m).s5 * (b)) + (m).s6 * (c)) + (m).s7)
#define ROW2(m, a, b, c) ((((m).s8 * (a) + (m).s9 * (b)) + (m).sa * (c)) + (m).sb)

/* Work-item: columns x0 .. x0 + YLANES - 1 of rows 2 cy and 2 cy + 1 of the
 * frame, and the row of each plane there (Q: the pointers' qualifiers). */
#define I420_ROWS(Q)                                                                 \
    const int nbx = (w + YLANES - 1) / YLANES, gid = get_global_id(0);              \
    const int x0 = (gid % nbx) * YLANES, cy = gid / nbx, cw = w / 2;                \
    if (2 * cy >= h)                                                                \
        return;                                                                     \
    Q uchar *yrow = yuv + (size_t)(2 * cy) * w;                                     \
    Q uchar *urow = yuv + (size_t)w * h + (size_t)cy * cw;                          \
    Q uchar *vrow = urow + (size_t)cw * (h / 2);

/* Opaque RGBA pixels (packed, R in the low byte) from Y'CbCr (y, u, v) through m;
 * CVT: convert_uint or its vector form. */
#define YUV_RGBA(CVT, y, u, v, m)                                                    \
    (CVT(CODE8(ROW0(m, y, u, v))) | (CVT(CODE8(ROW1(m, y, u, v))) << 8) |           \
     (CVT(CODE8(ROW2(m, y, u, v))) << 16) | 0xff000000u)

/* I420 frame -> RGBA pixels at dst[off + y * stride + x] (inside the padded input). */
__kernel void marble_from_i420(__global uint *dst, int off, int stride,
                               __global const uchar *yuv, int w, int h, float16 m) {
    I420_ROWS(__global const)
    __global uint *out = dst + off + (size_t)(2 * cy) * stride;
    if (x0 + YLANES <= w) {
        yf u = CVT_YF(shuffle(VLOAD_YH(urow + x0 / 2), TWICE));
        yf v = CVT_YF(shuffle(VLOAD_YH(vrow + x0 / 2), TWICE));
        for (int r = 0; r < 2; r++) {
            yf y = CVT_YF(VLOAD_Y(yrow + (size_t)r * w + x0));
            VSTORE_Y(YUV_RGBA(CVT_YU, y, u, v, m), out + (size_t)r * stride + x0);
        }
    } else {
        for (int x = x0; x < w; x++) {
            float u = urow[x / 2], v = vrow[x / 2];
            for (int r = 0; r < 2; r++) {
                float y = yrow[(size_t)r * w + x];
                out[(size_t)r * stride + x] = YUV_RGBA(convert_uint, y, u, v, m);
            }
        }
    }
}

#define CHANNEL(p, k) CVT_YF(((p) >> (8 * (k))) & 0xffu)
#define CHANNEL1(p, k) (float)(((p) >> (8 * (k))) & 0xffu)
/* the mean of a 2x2, summed in the vector part's order: rows, then columns */
#define MEAN4(p00, p01, p10, p11, k) \
    (((CHANNEL1(p00, k) + CHANNEL1(p10, k)) + (CHANNEL1(p01, k) + CHANNEL1(p11, k))) * 0.25f)
#define LUMA(p, m) \
    convert_uchar(CODE8(ROW0(m, CHANNEL1(p, 0), CHANNEL1(p, 1), CHANNEL1(p, 2))))

/* RGBA w x h (rows of w pixels) -> I420; chroma from the mean RGB of each 2x2. */
__kernel void marble_to_i420(__global uchar *yuv, __global const uint *src, int w, int h,
                             float16 m) {
    I420_ROWS(__global)
    __global const uint *in = src + (size_t)(2 * cy) * w;
    if (x0 + YLANES <= w) {
        yu p0 = VLOAD_Y(in + x0), p1 = VLOAD_Y(in + w + x0);
        yf r0 = CHANNEL(p0, 0), g0 = CHANNEL(p0, 1), b0 = CHANNEL(p0, 2);
        yf r1 = CHANNEL(p1, 0), g1 = CHANNEL(p1, 1), b1 = CHANNEL(p1, 2);
        VSTORE_Y(CVT_YB(CODE8(ROW0(m, r0, g0, b0))), yrow + x0);
        VSTORE_Y(CVT_YB(CODE8(ROW0(m, r1, g1, b1))), yrow + w + x0);
        yf rs = r0 + r1, gs = g0 + g1, bs = b0 + b1;
        yhf r = (rs.even + rs.odd) * 0.25f, g = (gs.even + gs.odd) * 0.25f;
        yhf b = (bs.even + bs.odd) * 0.25f;
        VSTORE_YH(CVT_YHB(CODE8(ROW1(m, r, g, b))), urow + x0 / 2);
        VSTORE_YH(CVT_YHB(CODE8(ROW2(m, r, g, b))), vrow + x0 / 2);
    } else {
        for (int x = x0; x < w; x += 2) {
            const uint p00 = in[x], p01 = in[x + 1], p10 = in[w + x], p11 = in[w + x + 1];
            yrow[x] = LUMA(p00, m);
            yrow[x + 1] = LUMA(p01, m);
            yrow[w + x] = LUMA(p10, m);
            yrow[w + x + 1] = LUMA(p11, m);
            float r = MEAN4(p00, p01, p10, p11, 0), g = MEAN4(p00, p01, p10, p11, 1);
            float b = MEAN4(p00, p01, p10, p11, 2);
            urow[x / 2] = convert_uchar(CODE8(ROW1(m, r, g, b)));
            vrow[x / 2] = convert_uchar(CODE8(ROW2(m, r, g, b)));
        }
    }
}
