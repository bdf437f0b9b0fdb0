/* walk.cl: the inverse walk of a marbling recipe, one pass per subsample,
 * shaded and stored as RGBA (the `marble` kernel; see prelude.cl for the
 * defines, sampling.cl for the input's sampling).
 *
 * WALK (generated): op i of the recipe, last op first, as OP(i, op_<type>) (or
 * OP_CHAINS for a section that walks every chain in one call); or for
 * long recipes (and editors' renderers) a loop over NOPS ops, the first float of
 * `lists`, whose switch has a case per op type.
 * INK (generated): INK_COLOR(i) for every ink op (resolves a hit to its colour).
 */

/* Row of job j; constant-folds to 0 whenever ROWS == 1. */
#define ROW_OF(j) (ROWS == 1 ? 0 : (j) / NSAMPLES)
#define KPARAMS __global const uint *src, int sw, int sh, __constant const float *params, \
                __constant const float *samples, float4 gc, float4 gi, float4 bgc, \
                __global const float *lists
#define KARGS src, sw, sh, params, samples, gc, gi, bgc, lists

/* The colour of chain c after its walk: ink, else the input (bilinear) or background. */
#if HAS_INPUT
#define SHADE(c, cr, cg, cb, ca)                                                          \
    cr = cg = cb = (vf)0.0f; ca = (vf)255.0f;                                              \
    if (ANY(ink[c] < 0))                                                                   \
        bilinear(src, sw, sh, px[c] * gi.s0 + gi.s2, py[c] * gi.s1 + gi.s3,        \
                 &cr, &cg, &cb, &ca);                                                      \
    ca = select(ca, (vf)255.0f, ink[c] >= 0);                                              \
    if (ANY(ink[c] >= 0)) { INK }
#else
#define SHADE(c, cr, cg, cb, ca)                                                          \
    cr = (vf)bgc.x; cg = (vf)bgc.y; cb = (vf)bgc.z; ca = (vf)255.0f;                       \
    if (ANY(ink[c] >= 0)) { INK }
#endif

/* Jobs g .. g + CHAINS - 1 of a work-item whose ROWS rows of LANES pixels have
 * their centres at (ox[r], oy[r]): chain c walks subsample (g + c) % NSAMPLES
 * of row ROW_OF(g + c), from canvas point (px[c], py[c]), no ink hit yet. */
#define START_JOBS(g, ox, oy)                                                  \
    vf px[CHAINS], py[CHAINS];                                                 \
    vi ink[CHAINS];                                                            \
    FOR_CHAINS {                                                               \
        int s_ = ((g) + c) % NSAMPLES, r_ = ROW_OF((g) + c);                   \
        px[c] = ((ox)[r_] + samples[3 * s_]) * gc.s0 + gc.s2;                \
        py[c] = ((oy)[r_] + samples[3 * s_ + 1]) * gc.s1 + gc.s3;            \
        ink[c] = (vi)-1;                                                       \
    }

/* The work-item's block of a w x h output: LANES pixels from column x0 of ROWS
 * rows from y0, whose centres are (ox[r], oy[r]); past the last row it returns. */
#define WALKED_BLOCK                                                           \
    const int nbx = (w + LANES - 1) / LANES, gid = get_global_id(0);          \
    const int x0 = (gid % nbx) * LANES, y0 = (gid / nbx) * ROWS;               \
    if (y0 >= h)                                                               \
        return;                                                                \
    vf ox[ROWS], oy[ROWS];                                                     \
    for (int r = 0; r < ROWS; r++) {                                           \
        ox[r] = (vf)(float)x0 + IOTA + 0.5f;                                   \
        oy[r] = (vf)((float)y0 + 0.5f) + (float)r;                             \
    }

/* Every subsample of ROWS x LANES pixels centred at (ox[r], oy[r]): the full
 * pattern, walked in CHAINS independent chains; weighted sums in acc. */
inline void shade_block(vf ox[ROWS], vf oy[ROWS], vf acc[ROWS][4], KPARAMS) {
    for (int r = 0; r < ROWS; r++)
        for (int k = 0; k < 4; k++)
            acc[r][k] = (vf)0.0f;
    for (int g = 0; g < ROWS * NSAMPLES; g += CHAINS) {
        START_JOBS(g, ox, oy)

        WALK

        FOR_CHAINS {
            vf cr, cg, cb, ca;
            SHADE(c, cr, cg, cb, ca)
            float wgt = samples[3 * ((g + c) % NSAMPLES) + 2];
            int row = ROW_OF(g + c);
            acc[row][0] += wgt * cr;
            acc[row][1] += wgt * cg;
            acc[row][2] += wgt * cb;
            acc[row][3] += wgt * ca;
        }
    }
}

inline vu pack_rgba(vf r, vf g, vf b, vf a) {
#define Q(v) CVT_U(clamp(floor((v) + 0.5f), 0.0f, 255.0f))
    return Q(r) | (Q(g) << 8) | (Q(b) << 16) | (Q(a) << 24);
#undef Q
}

/* Store LANES pixels at out[0..], or only the first n of them. */
inline void store_row(__global uint *out, vu packed, int n) {
    if (n >= LANES) {
#if LANES == 1
        out[0] = packed;
#else
        CAT(vstore, LANES)(packed, 0, out);
#endif
    } else {
        uint tmp[LANES];
        VSTORE(packed, tmp);
        for (int l = 0; l < n; l++)
            out[l] = tmp[l];
    }
}

/* gc: output -> canvas (sx, sy, ox, oy); gi: canvas -> input pixels (sx, sy, ox, oy).
 * bgc: background red, green, blue (0..255) and alpha 255.
 * Work-item: LANES pixels of ROWS rows; every subsample of the pattern. */
__kernel void marble(__global uint *dst, int w, int h, KPARAMS) {
    WALKED_BLOCK
    vf acc[ROWS][4];
    shade_block(ox, oy, acc, KARGS);
    for (int r = 0; r < ROWS && y0 + r < h; r++)
        store_row(dst + (size_t)(y0 + r) * w + x0,
                  pack_rgba(acc[r][0], acc[r][1], acc[r][2], acc[r][3]), w - x0);
}
