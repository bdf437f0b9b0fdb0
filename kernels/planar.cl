/* planar.cl: the warp of Y'CbCr planes (see walk.cl, tables.cl). */

/* ---- Planar video frames: each plane warped at its own resolution --------
 * When a frame's input and output share one colour matrix, the warp runs on
 * the Y'CbCr planes themselves, as ffmpeg's filters do: every output sample is
 * a weighted sum of input samples of the same plane and ink is a constant, so
 * the luma equals the RGBA path's luma (which converts there and back) up to
 * its rounding and clamping; the chroma planes are walked at chroma resolution
 * (a chroma pixel covers 2 x 2 luma pixels) and sampled bilinearly there.
 * Ink colours arrive as 8-bit Y'CbCr codes in the params' colour slots, and
 * bgc holds the background's codes (for EDGES_BACKGROUND).
 *
 * A plane of pw x ph is sampled through its *quads*: quad t of the padded plane
 * (row stride pw + 2, as the padded RGBA input) packs the padded samples t,
 * t + 1, t + pw + 2 and t + pw + 3 in bytes 0..3, i.e. a whole bilinear
 * footprint, so that one 32-bit gather fetches it where the RGBA path needs
 * four. The padding follows the edges mode as marble_pad's does. */

inline uint padded_at(__global const uchar *plane, int pw, int ph, int px, int py, uint bg) {
    const int x = padded_sample(px, pw), y = padded_sample(py, ph);
    return (x < 0 || y < 0) ? bg : (uint)plane[(size_t)y * pw + x];
}

/* Quads (tx, ty), tx in 0..pw, ty in 0..ph, of the plane at yuv + off (pw x ph
 * bytes); bg: the background's code. Work-item: YLANES quads of one row; inside
 * the plane, four row loads; at the edges, sample by sample. Independent of LANES. */
__kernel void marble_quads(__global uint *quads, __global const uchar *yuv, int off, int pw,
                           int ph, uint bg) {
    const int psw = pw + 2, nbx = (pw + YLANES) / YLANES, gid = get_global_id(0);
    const int x0 = (gid % nbx) * YLANES, ty = gid / nbx;
    if (ty > ph)
        return;
    __global const uchar *plane = yuv + off;
    __global uint *out = quads + (size_t)ty * psw + x0;
    if (x0 >= 1 && x0 + YLANES <= pw && ty >= 1 && ty < ph) {
        __global const uchar *r0 = plane + (size_t)(ty - 1) * pw + x0 - 1;
        yu a = CVT_YU(VLOAD_Y(r0)), b = CVT_YU(VLOAD_Y(r0 + 1));
        yu c = CVT_YU(VLOAD_Y(r0 + pw));
        yu d = CVT_YU(VLOAD_Y(r0 + pw + 1));
        VSTORE_Y(a | (b << 8) | (c << 16) | (d << 24), out);
    } else {
        for (int l = 0; l < YLANES && x0 + l <= pw; l++) {
            const int tx = x0 + l;
            out[l] = padded_at(plane, pw, ph, tx, ty, bg) |
                     (padded_at(plane, pw, ph, tx + 1, ty, bg) << 8) |
                     (padded_at(plane, pw, ph, tx, ty + 1, bg) << 16) |
                     (padded_at(plane, pw, ph, tx + 1, ty + 1, bg) << 24);
        }
    }
}

/* Bilinear from quads t with the right (wx) and bottom (wy) weights. */
#define QUAD_LERP(t, wx, wy) mix(mix(CH(t, 0), CH(t, 1), wx), mix(CH(t, 2), CH(t, 3), wx), wy)

/* Store LANES samples (rounded, clamped) at out[0..], or only the first n. */
inline void store_codes(__global uchar *out, vf v, int n) {
#if LANES > 1
    if (n >= LANES) {
        CAT(vstore, LANES)(CAT(convert_uchar, LANES)(CODE8(v)), 0, out);
        return;
    }
#endif
    float tmp[LANES];
    VSTORE(v, tmp);
    for (int l = 0; l < LANES && l < n; l++)
        out[l] = convert_uchar(CODE8(tmp[l]));
}

/* A plane of w x h walked afresh: luma (chroma 0: quads q0, codes to
 * dst + off0) or both chroma planes at the same points (chroma 1: q0 and q1,
 * to dst + off0 and dst + off1). sw, sh: the input plane's size. Work-item:
 * LANES samples of ROWS rows; every subsample of the pattern. */
/* Every subsample of ROWS x LANES samples of a plane centred at (ox[r], oy[r]),
 * walked in CHAINS chains: weighted sums of plane 0 (q0) and, with chroma, of
 * plane 1 (q1) in acc. */
inline void plane_block(vf ox[ROWS], vf oy[ROWS], vf acc[ROWS][2], __global const uint *q0,
                        __global const uint *q1, int chroma, KPARAMS) {
    for (int r = 0; r < ROWS; r++)
        acc[r][0] = acc[r][1] = (vf)0.0f;
    for (int g = 0; g < ROWS * NSAMPLES; g += CHAINS) {
        START_JOBS(g, ox, oy)

        WALK

        FOR_CHAINS {
            vf cr = 0.0f, cg = 0.0f, cb = 0.0f;
            if (ANY(ink[c] >= 0)) { INK }
            vi hit = ink[c] >= 0;
            vf v0 = chroma ? cg : cr, v1 = cb;
            if (ANY(hit == 0)) {
                vi i;
                vf wx, wy;
                footprint(px[c] * gi.s0 + gi.s2, py[c] * gi.s1 + gi.s3, sw, sh, &i, &wx, &wy);
                i = select(i, (vi)0, hit);
                v0 = select(QUAD_LERP(GATHER_LANES(q0, i), wx, wy), v0, hit);
                if (chroma)
                    v1 = select(QUAD_LERP(GATHER_LANES(q1, i), wx, wy), v1, hit);
            }
            float wgt = samples[3 * ((g + c) % NSAMPLES) + 2];
            int row = ROW_OF(g + c);
            acc[row][0] += wgt * v0;
            acc[row][1] += wgt * v1;
        }
    }
}

__kernel void marble_plane(__global uchar *dst, int off0, int off1, int w, int h,
                           __global const uint *q0, __global const uint *q1, int chroma,
                           KPARAMS) {
    WALKED_BLOCK
    vf acc[ROWS][2];
    plane_block(ox, oy, acc, q0, q1, chroma, KARGS);
    for (int r = 0; r < ROWS && y0 + r < h; r++) {
        const size_t at = (size_t)(y0 + r) * w + x0;
        store_codes(dst + off0 + at, acc[r][0], w - x0);
        if (chroma)
            store_codes(dst + off1 + at, acc[r][1], w - x0);
    }
}

/* marble_plane from a table that marble_table wrote for this plane (taps hold
 * the quad's index, or for ink its Y'CbCr codes). Work-item: LANES samples of a row. */
__kernel void marble_apply_plane(__global uchar *dst, int off0, int off1, int w, int h,
                                 __global const uint *q0, __global const uint *q1, int chroma,
                                 __global const uint *taps, __global const uint *wts,
                                 int tstride, __constant const float *samples) {
    TABLE_ROW
    vf acc0 = 0.0f, acc1 = 0.0f;
    for (int s = 0; s < NSAMPLES; s++) {
        const size_t at = TABLE_AT(s, y);
        vu tap = VLOAD(taps + at), q = VLOAD(wts + at);
        vi hit = CVT_I(q >> 31) != 0;
        vf v0 = CH(tap, chroma), v1 = CH(tap, 2);
        if (ANY(hit == 0)) { /* skipped where every lane is on ink */
            vi i = select(CVT_I(tap), (vi)0, hit);
            vf wx, wy;
            table_weights(q, &wx, &wy);
            v0 = select(QUAD_LERP(GATHER_LANES(q0, i), wx, wy), v0, hit);
            if (chroma)
                v1 = select(QUAD_LERP(GATHER_LANES(q1, i), wx, wy), v1, hit);
        }
        float wgt = samples[3 * s + 2];
        acc0 += wgt * v0;
        acc1 += wgt * v1;
    }
    const size_t at = (size_t)y * w + x0;
    store_codes(dst + off0 + at, acc0, w - x0);
    if (chroma)
        store_codes(dst + off1 + at, acc1, w - x0);
}
