/* marble.cl: the inverse walk of a marbling recipe, one pass per subsample.
 *
 * Conventions (shared/recipe-format.md): canvas units, origin top-left,
 * x right, y down; output pixel (i, j) has its centre at (i + 0.5, j + 0.5);
 * input pixels likewise; images are packed RGBA8 (R in the low byte).
 *
 * One source serves every device through build-time defines (-D):
 *   LANES    pixels per work-item along x, as one vector (16 on CPU/PoCL, 1 on GPUs)
 *   CHAINS   independent (row, subsample) jobs evaluated side by side per work-item
 *   ROWS     output rows per work-item (> 1 only without antialiasing)
 *   NSAMPLES subsamples per pixel; offsets and weights arrive in `samples`
 *   HAS_INPUT 1: sample the input image where no ink is hit; 0: blank sheet
 *   EDGES    0 clamp, 1 repeat, 2 mirror, 3 background (what lies outside the input)
 *   WALK     the recipe's structure: OP_<TYPE>(i) for every op, last op first;
 *            or WALK_LOOP with NOPS for long recipes (types read from the params)
 *   INK      INK_COLOR(i) for every ink op (resolves a hit to its colour)
 * Per-frame values live in `params`: PSTRIDE floats per op, packed by
 * marblevideo/renderer.py (see pack_params there for the layout). Changing
 * them never rebuilds the program.
 */

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#define PSTRIDE 12

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

#define CVT_F(v) CAT(convert_float, LANES)(v)
#define CVT_I(v) CAT(convert_int, LANES)(v)
#define CVT_U(v) CAT(convert_uint, LANES)(v)
#if LANES == 1
#undef CVT_F
#undef CVT_I
#undef CVT_U
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

/* Ink: a point strictly inside the (progress-scaled) circle is ink of op i.
 * Only the first hit of the walk counts, so later ops stay on top. */
inline void hit_ink(vf x, vf y, vi *ink, __constant const float *p, int i) {
    vf qx = x - p[0], qy = y - p[1];
    vi inside = (qx * qx + qy * qy) < p[2];
    *ink = select(*ink, (vi)i, inside & (*ink < 0));
}

/* drop: P = C + (P' - C) * sqrt(1 - r^2 / |P' - C|^2) outside the drop.
 * p: cx, cy, r^2, red, green, blue */
inline void inv_drop(vf *x, vf *y, vi *ink, __constant const float *p, int i) {
    vf qx = *x - p[0], qy = *y - p[1];
    vf d2 = qx * qx + qy * qy;
    *ink = select(*ink, (vi)i, (d2 < p[2]) & (*ink < 0));
    vf k = sqrt(fmax(1.0f - p[2] / fmax(d2, 1e-30f), 0.0f));
    *x = p[0] + qx * k;
    *y = p[1] + qy * k;
}

/* tine and comb: P = P' - alpha*lambda / (d + lambda) * M, d the distance to
 * the (nearest) tine line. p: ax, ay, mx, my, nx, ny, alpha*lambda, lambda,
 * spacing, 1/spacing, spacing/2 */
inline void inv_tine(vf *x, vf *y, __constant const float *p) {
    vf d = fabs((*x - p[0]) * p[4] + (*y - p[1]) * p[5]);
    vf s = p[6] / (d + p[7]);
    *x -= s * p[2];
    *y -= s * p[3];
}

inline void inv_comb(vf *x, vf *y, __constant const float *p) {
    vf d = fabs((*x - p[0]) * p[4] + (*y - p[1]) * p[5]);
    d = d - p[8] * floor(d * p[9]);                   /* fmod(d, spacing), d >= 0 */
    d = p[10] - fabs(d - p[10]);
    vf s = p[6] / (d + p[7]);
    *x -= s * p[2];
    *y -= s * p[3];
}

/* wave: v = P . (sin t, -cos t); shift = amplitude * sin(2 pi v / wavelength + phase)
 * along (cos t, sin t). p: amplitude, 1/wavelength, phase in turns, cos t, sin t */
inline void inv_wave(vf *x, vf *y, __constant const float *p) {
    vf v = *x * p[4] - *y * p[3];
    vf s = p[0] * sin_turns(v * p[1] + p[2]);
    *x -= s * p[3];
    *y -= s * p[4];
}

/* circle and vortex: rotate P' - C by -theta, theta = alpha*lambda/(d + lambda)/R,
 * d = |R - r| (circle) or R (vortex: r = 0 and R >= 0 make them one formula).
 * p: cx, cy, r, alpha*lambda / (2 pi), lambda  (theta in turns) */
inline void inv_circle(vf *x, vf *y, __constant const float *p) {
    vf qx = *x - p[0], qy = *y - p[1];
    vf R = sqrt(qx * qx + qy * qy);
    vf turns = -p[3] / ((fabs(R - p[2]) + p[4]) * fmax(R, 1e-30f));
    turns -= floor(turns + 0.5f); /* reduce first: at 2^22+ turns, + 0.25 is lost (cos = 0) */
    vf sn = sin_turns(turns), cs = sin_turns(turns + 0.25f);
    *x = p[0] + qx * cs - qy * sn;
    *y = p[1] + qx * sn + qy * cs;
}

/* Row of job j; constant-folds to 0 whenever ROWS == 1. */
#define ROW_OF(j) (ROWS == 1 ? 0 : (j) / NSAMPLES)
#define FOR_CHAINS for (int c = 0; c < CHAINS; c++)
#define PARAMS(i) (params + (i) * PSTRIDE)
#define OP_DROP(i) FOR_CHAINS inv_drop(&px[c], &py[c], &ink[c], PARAMS(i), i);
#define OP_SPRAY(i) FOR_CHAINS hit_ink(px[c], py[c], &ink[c], PARAMS(i), i);
#define OP_TINE(i) FOR_CHAINS inv_tine(&px[c], &py[c], PARAMS(i));
#define OP_COMB(i) FOR_CHAINS inv_comb(&px[c], &py[c], PARAMS(i));
#define OP_WAVE(i) FOR_CHAINS inv_wave(&px[c], &py[c], PARAMS(i));
#define OP_CIRCLE(i) FOR_CHAINS inv_circle(&px[c], &py[c], PARAMS(i));
#define OP_VORTEX(i) OP_CIRCLE(i)

/* Long recipes: one loop over the ops, the type code in the op's last slot. */
#define WALK_LOOP                                                              \
    for (int i = NOPS - 1; i >= 0; i--) {                                      \
        switch ((int)PARAMS(i)[PSTRIDE - 1]) {                                 \
        case 0: OP_DROP(i) break;                                              \
        case 1: OP_SPRAY(i) break;                                             \
        case 2: OP_TINE(i) break;                                              \
        case 3: OP_COMB(i) break;                                              \
        case 4: OP_WAVE(i) break;                                              \
        default: OP_CIRCLE(i) break;                                           \
        }                                                                      \
    }
#define INK_COLOR(i)                                                           \
    { vi m = ink[c] == i;                                                      \
      float r_ = PARAMS(i)[3], g_ = PARAMS(i)[4], b_ = PARAMS(i)[5];           \
      cr = select(cr, (vf)r_, m);                                              \
      cg = select(cg, (vf)g_, m);                                              \
      cb = select(cb, (vf)b_, m); }
#define INK_LOOP                                                               \
    for (int i = 0; i < NOPS; i++)                                             \
        if ((int)PARAMS(i)[PSTRIDE - 1] <= 1) INK_COLOR(i)

/* Map an integer-valued float tap index into 0..n-1 by the `edges` mode;
 * with EDGES == 3 (background) an index outside gives -1. */
inline vi edge_index(vf i, int n) {
    float fn = (float)n;
#if EDGES == 0
    vf m = clamp(i, 0.0f, fn - 1.0f);
#elif EDGES == 1
    vf m = clamp(i - fn * floor(i / fn), 0.0f, fn - 1.0f);
#elif EDGES == 2
    vf m = i - 2.0f * fn * floor(i / (2.0f * fn));
    m = clamp(select(m, 2.0f * fn - 1.0f - m, m >= fn), 0.0f, fn - 1.0f);
#else
    vf m = select(i, (vf)-1.0f, (i < 0.0f) | (i > fn - 1.0f));
#endif
    return CVT_I(m);
}

/* Gather one tap per lane from the packed RGBA input. */
inline vu gather(__global const uint *src, vi xi, vi yi, int sw, uint bg) {
    vi idx = yi * sw + xi;
#if EDGES == 3
    idx = select(idx, (vi)-1, (xi < 0) | (yi < 0));
#endif
    int at[LANES];
    uint tap[LANES];
    VSTORE(idx, at);
    for (int l = 0; l < LANES; l++)
#if EDGES == 3
        tap[l] = at[l] < 0 ? bg : src[at[l]];
#else
        tap[l] = src[at[l]];
#endif
    return VLOAD(tap);
}

#define CH(t, k) CVT_F(((t) >> (8 * (k))) & 0xffu)

/* Bilinear between input pixel centres at input pixel coordinates (ix, iy). */
inline void bilinear(__global const uint *src, int sw, int sh, uint bg, vf ix, vf iy,
                     vf *r, vf *g, vf *b, vf *a) {
    vf fx = clamp(ix - 0.5f, -4.0e6f, 4.0e6f), fy = clamp(iy - 0.5f, -4.0e6f, 4.0e6f);
    vf x0 = floor(fx), y0 = floor(fy);
    vf wx = fx - x0, wy = fy - y0;
    vi xa = edge_index(x0, sw), xb = edge_index(x0 + 1.0f, sw);
    vi ya = edge_index(y0, sh), yb = edge_index(y0 + 1.0f, sh);
    vu t00 = gather(src, xa, ya, sw, bg), t10 = gather(src, xb, ya, sw, bg);
    vu t01 = gather(src, xa, yb, sw, bg), t11 = gather(src, xb, yb, sw, bg);
#define LERP2(k) mix(mix(CH(t00, k), CH(t10, k), wx), mix(CH(t01, k), CH(t11, k), wx), wy)
    *r = LERP2(0);
    *g = LERP2(1);
    *b = LERP2(2);
    *a = LERP2(3);
#undef LERP2
}

/* geo: output -> canvas (sx, sy, ox, oy), canvas -> input pixels (sx, sy, ox, oy).
 * bgc: background red, green, blue (0..255) and bg, the same packed RGBA8. */
__kernel void marble(__global uint *dst, int w, int h,
                     __global const uint *src, int sw, int sh,
                     __constant const float *params,
                     __constant const float *samples,
                     float8 geo, float4 bgc, uint bg) {
    const int nbx = (w + LANES - 1) / LANES;
    const int gid = get_global_id(0);
    const int bx = gid % nbx, by = gid / nbx;
    const int x0 = bx * LANES, y0 = by * ROWS;
    if (y0 >= h)
        return;

    vf acc[ROWS][4];
    for (int r = 0; r < ROWS; r++)
        for (int k = 0; k < 4; k++)
            acc[r][k] = (vf)0.0f;
    const vf ox = (vf)(float)x0 + IOTA + 0.5f;

    for (int g = 0; g < ROWS * NSAMPLES; g += CHAINS) {
        vf px[CHAINS], py[CHAINS];
        vi ink[CHAINS];
        FOR_CHAINS {
            int s = (g + c) % NSAMPLES;
            int row = ROW_OF(g + c);
            px[c] = (ox + samples[3 * s]) * geo.s0 + geo.s2;
            py[c] = ((float)(y0 + row) + 0.5f + samples[3 * s + 1]) * geo.s1 + geo.s3;
            ink[c] = (vi)-1;
        }

        WALK

        FOR_CHAINS {
            vf cr, cg, cb, ca = (vf)255.0f;
#if HAS_INPUT
            cr = cg = cb = 0.0f;
            if (ANY(ink[c] < 0))
                bilinear(src, sw, sh, bg, px[c] * geo.s4 + geo.s6, py[c] * geo.s5 + geo.s7,
                         &cr, &cg, &cb, &ca);
            ca = select(ca, (vf)255.0f, ink[c] >= 0);
#else
            cr = bgc.x;
            cg = bgc.y;
            cb = bgc.z;
#endif
            if (ANY(ink[c] >= 0)) {
                INK
            }
            float wgt = samples[3 * ((g + c) % NSAMPLES) + 2];
            int row = ROW_OF(g + c);
            acc[row][0] += wgt * cr;
            acc[row][1] += wgt * cg;
            acc[row][2] += wgt * cb;
            acc[row][3] += wgt * ca;
        }
    }

    for (int r = 0; r < ROWS; r++) {
        int y = y0 + r;
        if (y >= h)
            break;
#define Q(k) CVT_U(clamp(floor(acc[r][k] + 0.5f), 0.0f, 255.0f))
        vu packed = Q(0) | (Q(1) << 8) | (Q(2) << 16) | (Q(3) << 24);
#undef Q
        __global uint *out = dst + (size_t)y * w + x0;
        if (x0 + LANES <= w) {
#if LANES == 1
            out[0] = packed;
#else
            CAT(vstore, LANES)(packed, 0, out);
#endif
        } else {
            uint tmp[LANES];
            VSTORE(packed, tmp);
            for (int l = 0; l < w - x0; l++)
                out[l] = tmp[l];
        }
    }
}
