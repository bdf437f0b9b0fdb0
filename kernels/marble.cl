/* marble.cl: the inverse walk of a marbling recipe, one pass per subsample,
 * the sampling of the input and every kernel (see prelude.cl for the defines).
 *
 * WALK (generated): op i of the recipe, last op first, as OP(i, type); or for
 * long recipes (and editors' renderers) a loop over NOPS ops, the first float of
 * `lists`, whose switch has a case per op type.
 * INK (generated): INK_COLOR(i) for every ink op (resolves a hit to its colour).
 */

/* Row of job j; constant-folds to 0 whenever ROWS == 1. */
#define ROW_OF(j) (ROWS == 1 ? 0 : (j) / NSAMPLES)
#define FOR_CHAINS for (int c = 0; c < CHAINS; c++)
#define PARAMS(i) (params + (i) * PSTRIDE)
/* Op i of type `name` in every chain (the generated WALK is a list of these, or
 * a loop whose switch has one case per op type). An op still this frame (type
 * code -1: not started yet) is skipped, by a branch every lane takes alike. */
#define OP(i, name)                                                            \
    if (PARAMS(i)[PSTRIDE - 1] >= 0.0f)                                        \
        FOR_CHAINS CAT(op_, name)(&px[c], &py[c], &ink[c], PARAMS(i), i, lists);
/* The colour of ink op i for the lanes whose walk ended there (INK lists these). */
#define INK_COLOR(i)                                                           \
    { vi m = ink[c] == i;                                                      \
      float r_ = PARAMS(i)[COLOR_SLOT], g_ = PARAMS(i)[COLOR_SLOT + 1];        \
      float b_ = PARAMS(i)[COLOR_SLOT + 2];                                    \
      cr = select(cr, (vf)r_, m);                                              \
      cg = select(cg, (vf)g_, m);                                              \
      cb = select(cb, (vf)b_, m); }

/* i mod n (0 <= result < n) for integer-valued floats below 2^24, exact on any
 * device: OpenCL lets i / n be 2.5 ulp off, and NVIDIA's 96.0f / 96.0f floors
 * to 0 (or -96 / 96 to -2), which sent whole wrapped columns to the far edge.
 * The product and difference are exact, so one step either way corrects it. */
inline vf wrap_index(vf i, float n) {
    vf m = i - n * floor(i / n);
    m = select(m, m - n, m >= n);
    return select(m, m + n, m < 0.0f);
}

/* Map an integer-valued float tap index into 0..n-1 by the `edges` mode;
 * with EDGES == 3 (background) an index outside gives -1. */
inline vi edge_index(vf i, int n) {
    float fn = (float)n;
#if EDGES == 0
    vf m = clamp(i, 0.0f, fn - 1.0f);
#elif EDGES == 1
    vf m = wrap_index(i, fn);
#elif EDGES == 2
    vf m = wrap_index(i, 2.0f * fn);
    m = clamp(select(m, 2.0f * fn - 1.0f - m, m >= fn), 0.0f, fn - 1.0f);
#else
    vf m = select(i, (vf)-1.0f, (i < 0.0f) | (i > fn - 1.0f));
#endif
    return CVT_I(m);
}

/* Gather one tap per lane from the packed RGBA input. The vector is built from
 * its components, which LLVM turns into a hardware gather; going through a
 * private array (store the indices, load lane by lane) ran 1.3-1.6x slower. */
#if LANES == 1
#define GATHER_LANES(b, i) ((b)[i])
#elif LANES == 4
#define GATHER_LANES(b, i) ((vu)((b)[(i).s0], (b)[(i).s1], (b)[(i).s2], (b)[(i).s3]))
#elif LANES == 8
#define GATHER_LANES(b, i) ((vu)((b)[(i).s0], (b)[(i).s1], (b)[(i).s2], (b)[(i).s3], \
                                 (b)[(i).s4], (b)[(i).s5], (b)[(i).s6], (b)[(i).s7]))
#else
#define GATHER_LANES(b, i) ((vu)((b)[(i).s0], (b)[(i).s1], (b)[(i).s2], (b)[(i).s3], \
                                 (b)[(i).s4], (b)[(i).s5], (b)[(i).s6], (b)[(i).s7], \
                                 (b)[(i).s8], (b)[(i).s9], (b)[(i).sa], (b)[(i).sb], \
                                 (b)[(i).sc], (b)[(i).sd], (b)[(i).se], (b)[(i).sf]))
#endif

#define CH(t, k) CVT_F(((t) >> (8 * (k))) & 0xffu)

/* The four taps of a bilinear footprint (left/right, top/bottom) blended by
 * the weights of the right (wx) and bottom (wy) taps, per channel. */
inline void blend_taps(vu t00, vu t10, vu t01, vu t11, vf wx, vf wy,
                       vf *r, vf *g, vf *b, vf *a) {
#define LERP2(k) mix(mix(CH(t00, k), CH(t10, k), wx), mix(CH(t01, k), CH(t11, k), wx), wy)
    *r = LERP2(0);
    *g = LERP2(1);
    *b = LERP2(2);
    *a = LERP2(3);
#undef LERP2
}

/* Left (top) tap of a footprint starting at f along an axis of n input pixels,
 * in padded coordinates, and its weight, for the edges mode. */
inline void padded_axis(vf f, int n, vi *tap, vf *weight) {
    vf i0 = floor(f);
    vf wt = f - i0;
    float fn = (float)n;
#if EDGES == 0
    vf m = clamp(i0, -1.0f, fn - 1.0f);  /* the border repeats the edge pixel */
#elif EDGES == 1
    vf m = wrap_index(i0, fn);  /* right border = column 0 */
#elif EDGES == 2
    /* Mirrored stretches run backwards: take the lower tap and swap the weights;
     * a footprint folded onto one pixel weighs only that pixel. */
    vf ma = CVT_F(edge_index(i0, n)), mb = CVT_F(edge_index(i0 + 1.0f, n));
    vf m = select(ma, mb, mb < ma);
    wt = select(select(wt, 1.0f - wt, mb < ma), (vf)0.0f, mb == ma);
#else
    vi outside = (i0 < -1.0f) | (i0 > fn - 1.0f);  /* both taps on background */
    vf m = select(i0, (vf)-1.0f, outside);
    wt = select(wt, (vf)0.0f, outside);
#endif
    *tap = CVT_I(m) + 1;
    *weight = wt;
}

/* The bilinear footprint at input pixel coordinates (ix, iy): the index of its
 * top-left tap in the padded input (sw + 2 wide; marble_pad has filled the
 * one-pixel border for the edges mode, so the other taps are always the next
 * column and row) and the weights of the right and bottom taps. */
inline void footprint(vf ix, vf iy, int sw, int sh, vi *tap, vf *wx, vf *wy) {
    vi tx, ty;
    padded_axis(clamp(ix - 0.5f, -4.0e6f, 4.0e6f), sw, &tx, wx);
    padded_axis(clamp(iy - 0.5f, -4.0e6f, 4.0e6f), sh, &ty, wy);
    *tap = ty * (sw + 2) + tx;
}

/* Bilinear between input pixel centres at input pixel coordinates (ix, iy),
 * from the padded input. */
inline void bilinear(__global const uint *src, int sw, int sh, vf ix, vf iy,
                     vf *r, vf *g, vf *b, vf *a) {
    vi i00;
    vf wx, wy;
    footprint(ix, iy, sw, sh, &i00, &wx, &wy);
    const int psw = sw + 2;
    vu t00 = GATHER_LANES(src, i00), t10 = GATHER_LANES(src + 1, i00);
    vu t01 = GATHER_LANES(src + psw, i00), t11 = GATHER_LANES(src + psw + 1, i00);
    blend_taps(t00, t10, t01, t11, wx, wy, r, g, b, a);
}

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

/* ---- Adaptive antialiasing: three passes --------------------------------
 * 1. marble_centres walks one sample at every pixel centre of a grid one pixel
 *    larger than the output on each side: ink index, and where the walk ended
 *    in input pixels. Grid point (gx, gy) is output pixel (gx - 1, gy - 1).
 * 2. marble_classify looks at each pixel's 3x3 neighbourhood. One ink all
 *    round: that ink. No ink all round: the background, or, over an input whose
 *    map is smooth there (second differences below SMOOTH input pixels), the
 *    full pattern's bilinear samples at positions interpolated quadratically
 *    from the nine walks. Anything else goes on a list.
 * 3. marble_list renders the listed pixels with the full pattern, LANES at a time.
 */
#ifndef SMOOTH
#define SMOOTH 0.25f
#endif

__kernel void marble_centres(__global int *inkmap, __global float *sxmap, __global float *symap,
                             int gstride, int gh, __constant const float *params, float4 gc,
                             float4 gi, __global const float *lists) {
    const int nbx = gstride / LANES;
    const int gid = get_global_id(0);
    const int x0 = (gid % nbx) * LANES, y0 = (gid / nbx) * CHAINS;
    if (y0 >= gh)
        return;
    vf px[CHAINS], py[CHAINS];
    vi ink[CHAINS];
    const vf ox = (vf)(float)x0 + IOTA - 0.5f;
    FOR_CHAINS {
        px[c] = ox * gc.s0 + gc.s2;
        py[c] = ((float)(y0 + c) - 0.5f) * gc.s1 + gc.s3;
        ink[c] = (vi)-1;
    }

    WALK

    FOR_CHAINS {
        if (y0 + c < gh) {
            size_t at = (size_t)(y0 + c) * gstride + x0;
#if LANES == 1
            inkmap[at] = ink[c];
#if HAS_INPUT
            sxmap[at] = px[c] * gi.s0 + gi.s2;
            symap[at] = py[c] * gi.s1 + gi.s3;
#endif
#else
            CAT(vstore, LANES)(ink[c], 0, inkmap + at);
#if HAS_INPUT
            CAT(vstore, LANES)(px[c] * gi.s0 + gi.s2, 0, sxmap + at);
            CAT(vstore, LANES)(py[c] * gi.s1 + gi.s3, 0, symap + at);
#endif
#endif
        }
    }
}

#if LANES == 1
#define GLOAD(buf, at) ((buf)[at])
#else
#define GLOAD(buf, at) CAT(vload, LANES)(0, (buf) + (at))
#endif

__kernel void marble_classify(__global uint *dst, int w, int h,
                              __global const int *inkmap, __global const float *sxmap,
                              __global const float *symap, int gstride,
                              __global int *list, __global int *count, KPARAMS) {
    const int nbx = (w + LANES - 1) / LANES;
    const int gid = get_global_id(0);
    /* Padding work-items past the last row read that row and store nothing:
     * every work-item must reach the barriers below. */
    const int x0 = (gid % nbx) * LANES, y = min(gid / nbx, h - 1);
    /* grid rows y .. y+2 and columns x0 .. x0+2 (+ lane) surround output (x0 + lane, y) */
    const size_t up = (size_t)y * gstride + x0, mid = up + gstride, dn = mid + gstride;
    vi k = GLOAD(inkmap, mid + 1);
    vi same = (GLOAD(inkmap, up) == k) & (GLOAD(inkmap, up + 1) == k) & (GLOAD(inkmap, up + 2) == k)
            & (GLOAD(inkmap, mid) == k) & (GLOAD(inkmap, mid + 2) == k)
            & (GLOAD(inkmap, dn) == k) & (GLOAD(inkmap, dn + 1) == k) & (GLOAD(inkmap, dn + 2) == k);
    vf cr = (vf)bgc.x, cg = (vf)bgc.y, cb = (vf)bgc.z, ca = (vf)255.0f;
    vi ink[1] = {k};
    { const int c = 0; INK }
#if HAS_INPUT
    vi blank = same & (k < 0);
    if (ANY(blank)) {
        /* quadratic model of the walk's end point around the pixel, per coordinate */
#define QUAD(m, a0, ax, ay, axx, ayy, axy)                                                 \
        vf a0 = GLOAD(m, mid + 1);                                                         \
        vf ax = 0.5f * (GLOAD(m, mid + 2) - GLOAD(m, mid));                                \
        vf ay = 0.5f * (GLOAD(m, dn + 1) - GLOAD(m, up + 1));                              \
        vf axx = GLOAD(m, mid + 2) + GLOAD(m, mid) - 2.0f * a0;                            \
        vf ayy = GLOAD(m, dn + 1) + GLOAD(m, up + 1) - 2.0f * a0;                          \
        vf axy = 0.25f * (GLOAD(m, dn + 2) - GLOAD(m, dn) - GLOAD(m, up + 2) + GLOAD(m, up));
        QUAD(sxmap, x0_, xx_, xy_, xxx_, xyy_, xxy_)
        QUAD(symap, y0_, yx_, yy_, yxx_, yyy_, yxy_)
#undef QUAD
        vf bend = fmax(fmax(fabs(xxx_), fabs(xyy_)), fmax(fabs(xxy_), fabs(yxx_)));
        bend = fmax(bend, fmax(fabs(yyy_), fabs(yxy_)));
        blank &= bend < SMOOTH;
        vf sr = (vf)0.0f, sg = (vf)0.0f, sb = (vf)0.0f, sa = (vf)0.0f;
        for (int s = 0; s < NSAMPLES; s++) {
            float dx = samples[3 * s], dy = samples[3 * s + 1], wgt = samples[3 * s + 2];
            float hx = 0.5f * dx * dx, hy = 0.5f * dy * dy, hxy = dx * dy;
            vf ix = x0_ + dx * xx_ + dy * xy_ + hx * xxx_ + hy * xyy_ + hxy * xxy_;
            vf iy = y0_ + dx * yx_ + dy * yy_ + hx * yxx_ + hy * yyy_ + hxy * yxy_;
            vf r, g, b, a;
            bilinear(src, sw, sh, ix, iy, &r, &g, &b, &a);
            sr += wgt * r;
            sg += wgt * g;
            sb += wgt * b;
            sa += wgt * a;
        }
        cr = select(cr, sr, blank);
        cg = select(cg, sg, blank);
        cb = select(cb, sb, blank);
        ca = select(ca, sa, blank);
    }
    vi done = (same & (k >= 0)) | blank;
#else
    vi done = same;
#endif
    const int n = gid / nbx < h ? min(LANES, w - x0) : 0;
    __global uint *out = dst + (size_t)y * w + x0;
    int flag[LANES];
    int mine = 0;
    if (n == LANES && !ANY(done == 0)) {
        store_row(out, pack_rgba(cr, cg, cb, ca), LANES);
    } else {
        uint tmp[LANES];
        VSTORE(done, flag);
        VSTORE(pack_rgba(cr, cg, cb, ca), tmp);
        for (int l = 0; l < n; l++) {
            if (flag[l])
                out[l] = tmp[l];
            else
                mine++;
        }
    }
    /* The list: local atomics inside the work-group and one global atomic for
     * it; a global atomic per work-item bounced its cache line between the
     * cores (3x slower in some of this VM's phases). */
    __local int group_count, group_base;
    if (get_local_id(0) == 0)
        group_count = 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    int at = mine ? atomic_add(&group_count, mine) : 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (get_local_id(0) == 0)
        group_base = group_count ? atomic_add(count, group_count) : 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    at += group_base;
    for (int l = 0; mine && l < n; l++)
        if (!flag[l])
            list[at++] = y * w + x0 + l;
}

/* Work-item: ROWS groups of LANES listed pixels (wherever they are), each group
 * in the place of a row of shade_block. */
__kernel void marble_list(__global uint *dst, int w, __global const int *list, int count,
                          KPARAMS) {
    const int first = get_global_id(0) * LANES * ROWS;
    if (first >= count)
        return;
    int at[ROWS][LANES];
    vf ox[ROWS], oy[ROWS];
    for (int r = 0; r < ROWS; r++) {
        for (int l = 0; l < LANES; l++)
            at[r][l] = list[min(first + r * LANES + l, count - 1)];
        vi idx = VLOAD(at[r]);
        vi yi = idx / w;
        ox[r] = CVT_F(idx - yi * w) + 0.5f;
        oy[r] = CVT_F(yi) + 0.5f;
    }
    vf acc[ROWS][4];
    shade_block(ox, oy, acc, KARGS);
    for (int r = 0; r < ROWS; r++) {
        uint tmp[LANES];
        VSTORE(pack_rgba(acc[r][0], acc[r][1], acc[r][2], acc[r][3]), tmp);
        for (int l = 0; l < LANES && first + r * LANES + l < count; l++)
            dst[at[r][l]] = tmp[l];
    }
}

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

/* Padded coordinate i (0 .. n + 1) of an axis of n samples (pixels) -> the sample, or
 * -1 for the background. */
inline int padded_sample(int i, int n) {
#if EDGES == 1
    return (i - 1 + n) % n;
#elif EDGES == 3
    return (i < 1 || i > n) ? -1 : i - 1;
#else
    return clamp(i - 1, 0, n - 1); /* clamp; mirror repeats the edge sample too */
#endif
}

/* The border of the padded input (sw + 2) x (sh + 2), whose inside holds the
 * frame: clamp and mirror repeat the edge pixel, repeat wraps round, background
 * is bg. Work-item i: one border pixel, top row, bottom row, left, right. */
__kernel void marble_pad(__global uint *src, int sw, int sh, uint bg) {
    const int psw = sw + 2, psh = sh + 2;
    const int i = get_global_id(0);
    int px, py;
    if (i < psw) {
        px = i;
        py = 0;
    } else if (i < 2 * psw) {
        px = i - psw;
        py = psh - 1;
    } else if (i < 2 * psw + sh) {
        px = 0;
        py = i - 2 * psw + 1;
    } else if (i < 2 * psw + 2 * sh) {
        px = psw - 1;
        py = i - 2 * psw - sh + 1;
    } else {
        return;
    }
    const int x = padded_sample(px, sw), y = padded_sample(py, sh);
    src[py * psw + px] = (x < 0 || y < 0) ? bg : src[(y + 1) * psw + x + 1];
}

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

/* ---- Planar video frames: each plane warped at its own resolution --------
 * When a frame's input and output share one colour matrix, the warp runs on
 * the Y'CbCr planes themselves, as ffmpeg's filters do: every output sample is
 * a weighted sum of input samples of the same plane and ink is a constant, so
 * the luma equals the RGBA path's luma (which converts there and back) up to
 * its rounding and clamping; the chroma planes are walked at chroma resolution
 * (a chroma pixel covers 2 x 2 luma pixels) and sampled bilinearly there.
 * Ink colours arrive as 8-bit Y'CbCr codes in the params' colour slots, and
 * bgc holds the background's codes (for EDGES 3).
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
