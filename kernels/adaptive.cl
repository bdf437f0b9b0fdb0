/* adaptive.cl: adaptive antialiasing (see walk.cl for the walk). */

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
