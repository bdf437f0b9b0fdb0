/* tables.cl: reused maps (see walk.cl for the walk, sampling.cl for the padded input). */

/* ---- Reused maps: a table of where every subsample lands ------------------
 * Over an input, a frame whose values, geometry and sizes equal the last
 * frame's lands every subsample where it landed before (a static recipe over a
 * video). marble_table walks each subsample once and records the first tap of
 * its bilinear footprint in the *padded* input (one border pixel all round,
 * written each frame by marble_pad for the edges mode, so the other three taps
 * are always the next column and row) with its weights; marble_apply then only
 * gathers and blends. Table planes, one per subsample, of h rows of tstride:
 *   taps: index into the padded input (row stride sw + 2), or for ink its
 *         packed RGBA colour
 *   wts:  wx | wy << 15 in 1/32768ths of a pixel; bit 31 set for ink
 * Weights in 1/32768ths move a sample by at most 1/65536 pixel, so a blend
 * differs from marble's by at most one level (in a few pixels per million). */
#define WSCALE 32768.0f

/* Subsample s of the work-item's LANES pixels of row y in a table. */
#define TABLE_AT(s, y) (((size_t)(s) * h + (y)) * tstride + x0)

/* The bilinear weights (right, bottom) of a table entry. */
inline void table_weights(vu q, vf *wx, vf *wy) {
    *wx = CVT_F(q & 0x7fffu) * (1.0f / WSCALE);
    *wy = CVT_F((q >> 15) & 0x7fffu) * (1.0f / WSCALE);
}

/* The work-item of a table reader: LANES pixels of row y from column x0; past
 * the last row it returns. */
#define TABLE_ROW                                                              \
    const int nbx = (w + LANES - 1) / LANES, gid = get_global_id(0);          \
    const int x0 = (gid % nbx) * LANES, y = gid / nbx;                         \
    if (y >= h)                                                                \
        return;


__kernel void marble_table(__global uint *taps, __global uint *wts, int w, int h, int tstride,
                           KPARAMS) {
    WALKED_BLOCK
    for (int g = 0; g < ROWS * NSAMPLES; g += CHAINS) {
        START_JOBS(g, ox, oy)

        WALK

        FOR_CHAINS {
            const int y = y0 + ROW_OF(g + c);
            if (g + c < ROWS * NSAMPLES && y < h) {
                vi i00;
                vf wx, wy;
                footprint(px[c] * gi.s0 + gi.s2, py[c] * gi.s1 + gi.s3, sw, sh, &i00, &wx, &wy);
                vu tap = CVT_U(i00);
                vu q = min(CVT_U(wx * WSCALE + 0.5f), 32767u)
                     | (min(CVT_U(wy * WSCALE + 0.5f), 32767u) << 15);
                vf cr = 0.0f, cg = 0.0f, cb = 0.0f;
                if (ANY(ink[c] >= 0)) { INK }
                vi hit = ink[c] >= 0;
                tap = select(tap, pack_rgba(cr, cg, cb, (vf)255.0f), hit);
                q = select(q, (vu)0x80000000u, hit);
                size_t at = TABLE_AT((g + c) % NSAMPLES, y);
                VSTORE(tap, taps + at);
                VSTORE(q, wts + at);
            }
        }
    }
}

/* Work-item: LANES pixels of one row; every subsample from the table. */
__kernel void marble_apply(__global uint *dst, int w, int h, __global const uint *taps,
                           __global const uint *wts, int tstride, __global const uint *src,
                           int sw, __constant const float *samples) {
    TABLE_ROW
    const int psw = sw + 2;
    vf ar = 0.0f, ag = 0.0f, ab = 0.0f, aa = 0.0f;
    for (int s = 0; s < NSAMPLES; s++) {
        size_t at = TABLE_AT(s, y);
        vu tap = VLOAD(taps + at), q = VLOAD(wts + at);
        vi hit = CVT_I(q >> 31) != 0;
        vf r = CH(tap, 0), g = CH(tap, 1), b = CH(tap, 2), a = (vf)255.0f;
        if (ANY(hit == 0)) { /* skipped where every lane is on ink */
            vi i00 = select(CVT_I(tap), (vi)0, hit);
            vu t00 = GATHER_LANES(src, i00), t10 = GATHER_LANES(src + 1, i00);
            vu t01 = GATHER_LANES(src + psw, i00), t11 = GATHER_LANES(src + psw + 1, i00);
            vf wx, wy, fr, fg, fb, fa;
            table_weights(q, &wx, &wy);
            blend_taps(t00, t10, t01, t11, wx, wy, &fr, &fg, &fb, &fa);
            r = select(fr, r, hit);
            g = select(fg, g, hit);
            b = select(fb, b, hit);
            a = select(fa, a, hit);
        }
        float wgt = samples[3 * s + 2];
        ar += wgt * r;
        ag += wgt * g;
        ab += wgt * b;
        aa += wgt * a;
    }
    store_row(dst + (size_t)y * w + x0, pack_rgba(ar, ag, ab, aa), w - x0);
}
