/* lattice.cl: the interpolated inverse map of animated frames (issue 35;
 * marblevideo/opencl/lattice.py drives it). Three passes:
 * 1. marble_centres (adaptive.cl) walks a *fine* lattice: point (i, j) at luma
 *    output coordinates (i H, j H) from the frame's top-left corner, H = S / 2,
 *    its walk's end in canvas units and its ink (the host hands it the luma
 *    geometry scaled by H and an identity canvas -> input map).
 * 2. marble_lattice_cells gives each cell of the coarse lattice (S x S output
 *    pixels; cell (i, j) has the fine points (2i .. 2i + 2, 2j .. 2j + 2)) a
 *    state: an ink index k where all nine points end on ink k; SMOOTH_CELL
 *    where none ends on ink, the bilinear interpolation of the four corners
 *    meets the five other walks within `tol` input pixels (so that the map's
 *    second differences at spacing H are at most 2 tol, and bilinear
 *    interpolation between neighbouring fine points, which the shading does,
 *    is off by about a quarter of that on a smooth map) and no step between
 *    neighbouring points is longer than `reach` canvas units (the walk squeezes
 *    the canvas there more than the lattice can follow); WALK_CELL otherwise.
 * 3. marble_lattice (RGBA) and marble_lattice_plane (a plane of I420) shade
 *    LANES pixels of ROWS rows: every subsample's end point bilinear between
 *    the four fine points round its pixel's centre (luma and chroma from the
 *    same lattice, found through `lat`: canvas -> fine lattice units), or,
 *    where a lane's cell says WALK_CELL, the exact walk for the whole
 *    work-item (shade_block, plane_block). Any op goes through the walk: the
 *    lattice knows no op.
 */
#define SMOOTH_CELL -1
#define WALK_CELL -2
/* rules: the checks that may put a cell on the exact walk (bits; the tests
 * switch them off one by one) */
#define RULE_INK 1
#define RULE_CENTRE 2
#define RULE_REACH 4

__kernel void marble_lattice_cells(__global int *state, __global const int *inkmap,
                                   __global const float *sxmap, __global const float *symap,
                                   int gstride, int ncx, int ncy, float4 gi, float tol,
                                   float reach, int rules) {
    const int gid = get_global_id(0);
    if (gid >= ncx * ncy)
        return;
    const size_t at = (size_t)(2 * (gid / ncx)) * gstride + 2 * (gid % ncx);
    const int k = inkmap[at + gstride + 1]; /* the centre's */
    int same = 1;
    float X[9], Y[9]; /* canvas units */
    for (int b = 0; b < 3; b++)
        for (int a = 0; a < 3; a++) {
            const size_t p = at + (size_t)b * gstride + a;
            same &= inkmap[p] == k;
            X[3 * b + a] = sxmap[p];
            Y[3 * b + a] = symap[p];
        }
    if (!same && (rules & RULE_INK)) {
        state[gid] = WALK_CELL;
        return;
    }
    if (k >= 0) {
        state[gid] = k;
        return;
    }
    /* the five non-corner points against the corners' bilinear interpolation */
#define OFF(P, q, a, b) fabs(P[q] - 0.5f * (P[a] + P[b]))
#define MISS(P) fmax(fmax(fmax(OFF(P, 1, 0, 2), OFF(P, 3, 0, 6)), \
                          fmax(OFF(P, 5, 2, 8), OFF(P, 7, 6, 8))), \
                     fabs(P[4] - 0.25f * (P[0] + P[2] + P[6] + P[8])))
    const float miss = fmax(MISS(X) * fabs(gi.s0), MISS(Y) * fabs(gi.s1)); /* input pixels */
#undef MISS
#undef OFF
    float step = 0.0f; /* the longest step between neighbouring points, canvas units */
    for (int b = 0; b < 3; b++)
        for (int a = 0; a < 2; a++) {
            const int h0 = 3 * b + a, v0 = 3 * a + b; /* along a row, along a column */
            step = fmax(step, fmax(fabs(X[h0 + 1] - X[h0]), fabs(Y[h0 + 1] - Y[h0])));
            step = fmax(step, fmax(fabs(X[v0 + 3] - X[v0]), fabs(Y[v0 + 3] - Y[v0])));
        }
    int walk = ((rules & RULE_CENTRE) && !(miss <= tol)) || ((rules & RULE_REACH) && !(step <= reach));
    walk |= isnan(miss) || isnan(step); /* an end point off float's range */
    state[gid] = walk ? WALK_CELL : SMOOTH_CELL;
}

/* m[i] in every lane, for indices i that rise along the lanes (a row of
 * pixels meets a few lattice points, in order): a scalar load and a select per
 * distinct index, cheaper on PoCL than a gather; a gather where they span
 * more than 2 LANES. */
inline vu rising_gather(__global const uint *m, vi i) {
#if LANES == 1
    return m[i];
#else
    int at[LANES];
    VSTORE(i, at);
    const int lo = at[0], hi = at[LANES - 1];
    if (hi - lo > 2 * LANES || hi < lo)
        return GATHER_LANES(m, i);
    vu out = (vu)m[lo];
    for (int k = lo + 1; k <= hi; k++)
        out = select(out, (vu)m[k], i >= k);
    return out;
#endif
}

#define LATTICE_ARGS __global const int *state, __global const uint *lx, __global const uint *ly, \
                     int lstride, int ncx, int ncy, float4 lat

/* The quarter cell (H x H, between four fine points) of each lane's centre
 * (ox, oy) of a plane whose output -> canvas map is gc: the state of its cell,
 * the fine lattice coordinates (u, v) of the centre within it (0..1 inside;
 * beyond at the frame's right and bottom edges) and the index of its top-left
 * fine point. */
inline vi lattice_cell(vf ox, vf oy, float4 gc, float4 lat, int ncx, int ncy, int lstride,
                       __global const int *state, vf *u, vf *v, vi *corner) {
    vf fu = (ox * gc.s0 + gc.s2 - lat.s2) * lat.s0, fv = (oy * gc.s1 + gc.s3 - lat.s3) * lat.s1;
    vf cu = clamp(floor(fu), 0.0f, (float)(2 * ncx - 1));
    vf cv = clamp(floor(fv), 0.0f, (float)(2 * ncy - 1));
    *u = fu - cu;
    *v = fv - cv;
    vi icu = CVT_I(cu), icv = CVT_I(cv);
    *corner = icv * lstride + icu;
    return AS_VI(rising_gather((__global const uint *)state, (icv >> 1) * ncx + (icu >> 1)));
}

/* One coordinate of the end point of subsample (dx, dy) (output pixels) of the
 * pixels at (u, v) in their quarter cells at `corner`, bilinear there, in input
 * pixels (scale g, offset o): t[0] + dx t[1] + dy (t[2] + dx t[3]); du, dv: fine
 * lattice units per output pixel. */
inline void lattice_taylor(__global const uint *m, vi corner, int lstride, vf u, vf v, float du,
                           float dv, float g, float o, vf t[4]) {
    vf p00 = AS_VF(rising_gather(m, corner)), p10 = AS_VF(rising_gather(m + 1, corner));
    vf p01 = AS_VF(rising_gather(m + lstride, corner));
    vf p11 = AS_VF(rising_gather(m + lstride + 1, corner));
    vf b = p10 - p00, c = p01 - p00, d = (p11 - p10) - c;
    t[0] = (p00 + u * (b + v * d) + v * c) * g + o;
    t[1] = (b + v * d) * (du * g);
    t[2] = (c + u * d) * (dv * g);
    t[3] = d * (du * dv * g);
}

/* The interpolated end point (ix, iy) of subsample s from lattice_taylor's tx, ty. */
#define LATTICE_AT(s, tx, ty, ix, iy)                                                    \
    const float dx_ = samples[3 * (s)], dy_ = samples[3 * (s) + 1];                      \
    vf ix = tx[0] + dx_ * tx[1] + dy_ * (tx[2] + dx_ * tx[3]);                            \
    vf iy = ty[0] + dx_ * ty[1] + dy_ * (ty[2] + dx_ * ty[3]);

/* The state of every lane of the work-item's rows; whether any says WALK_CELL. */
#define LATTICE_STATES                                                                    \
    vf u[ROWS], v[ROWS];                                                                  \
    vi corner[ROWS], st[ROWS];                                                            \
    int exact = 0;                                                                        \
    for (int r = 0; r < ROWS; r++) {                                                      \
        st[r] = lattice_cell(ox[r], oy[r], gc, lat, ncx, ncy, lstride, state, &u[r], &v[r], \
                             &corner[r]);                                                 \
        exact |= ANY(st[r] == WALK_CELL);                                                 \
    }                                                                                     \
    const float du = gc.s0 * lat.s0, dv = gc.s1 * lat.s1;

/* RGBA frames: marble's pixels, from the lattice where it can be trusted. */
__kernel void marble_lattice(__global uint *dst, int w, int h, LATTICE_ARGS, KPARAMS) {
    WALKED_BLOCK
    vf acc[ROWS][4];
    LATTICE_STATES
    if (exact) {
        shade_block(ox, oy, acc, KARGS);
    } else {
        for (int r = 0; r < ROWS; r++) {
            vf cr = 0.0f, cg = 0.0f, cb = 0.0f, kx[4], ky[4];
            vi ink[1] = {st[r]}, hit = st[r] >= 0;
            if (ANY(hit)) { const int c = 0; INK }
            acc[r][0] = cr;
            acc[r][1] = cg;
            acc[r][2] = cb;
            acc[r][3] = (vf)255.0f;
            if (!ANY(hit == 0))
                continue;
            lattice_taylor(lx, corner[r], lstride, u[r], v[r], du, dv, gi.s0, gi.s2, kx);
            lattice_taylor(ly, corner[r], lstride, u[r], v[r], du, dv, gi.s1, gi.s3, ky);
            vf sr = 0.0f, sg = 0.0f, sb = 0.0f, sa = 0.0f;
            for (int s = 0; s < NSAMPLES; s++) {
                LATTICE_AT(s, kx, ky, ix, iy)
                vf pr, pg, pb, pa;
                bilinear(src, sw, sh, ix, iy, &pr, &pg, &pb, &pa);
                const float wgt = samples[3 * s + 2];
                sr += wgt * pr;
                sg += wgt * pg;
                sb += wgt * pb;
                sa += wgt * pa;
            }
            acc[r][0] = select(sr, cr, hit);
            acc[r][1] = select(sg, cg, hit);
            acc[r][2] = select(sb, cb, hit);
            acc[r][3] = select(sa, acc[r][3], hit);
        }
    }
    for (int r = 0; r < ROWS && y0 + r < h; r++)
        store_row(dst + (size_t)(y0 + r) * w + x0,
                  pack_rgba(acc[r][0], acc[r][1], acc[r][2], acc[r][3]), w - x0);
}

/* I420 planes: marble_plane's samples, from the lattice where it can be trusted. */
__kernel void marble_lattice_plane(__global uchar *dst, int off0, int off1, int w, int h,
                                   __global const uint *q0, __global const uint *q1, int chroma,
                                   LATTICE_ARGS, KPARAMS) {
    WALKED_BLOCK
    vf acc[ROWS][2];
    LATTICE_STATES
    if (exact) {
        plane_block(ox, oy, acc, q0, q1, chroma, KARGS);
    } else {
        for (int r = 0; r < ROWS; r++) {
            vf cr = 0.0f, cg = 0.0f, cb = 0.0f, kx[4], ky[4];
            vi ink[1] = {st[r]}, hit = st[r] >= 0;
            if (ANY(hit)) { const int c = 0; INK }
            acc[r][0] = chroma ? cg : cr;
            acc[r][1] = cb;
            if (!ANY(hit == 0))
                continue;
            lattice_taylor(lx, corner[r], lstride, u[r], v[r], du, dv, gi.s0, gi.s2, kx);
            lattice_taylor(ly, corner[r], lstride, u[r], v[r], du, dv, gi.s1, gi.s3, ky);
            vf s0 = 0.0f, s1 = 0.0f;
            for (int s = 0; s < NSAMPLES; s++) {
                LATTICE_AT(s, kx, ky, ix, iy)
                vi i;
                vf wx, wy;
                footprint(ix, iy, sw, sh, &i, &wx, &wy);
                const float wgt = samples[3 * s + 2];
                s0 += wgt * QUAD_LERP(GATHER_LANES(q0, i), wx, wy);
                if (chroma)
                    s1 += wgt * QUAD_LERP(GATHER_LANES(q1, i), wx, wy);
            }
            acc[r][0] = select(s0, acc[r][0], hit);
            acc[r][1] = select(s1, acc[r][1], hit);
        }
    }
    for (int r = 0; r < ROWS && y0 + r < h; r++) {
        const size_t at = (size_t)(y0 + r) * w + x0;
        store_codes(dst + off0 + at, acc[r][0], w - x0);
        if (chroma)
            store_codes(dst + off1 + at, acc[r][1], w - x0);
    }
}
