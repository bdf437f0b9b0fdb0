/* sampling.cl: how the walks' end points read the input (see prelude.cl for the
 * defines, edges.cl for the edges mode): the one-pixel border of the padded
 * input (marble_pad) and bilinear sampling from it, gathered lane by lane from
 * packed RGBA8. */

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
#if EDGES == EDGES_CLAMP
    vf m = clamp(i0, -1.0f, fn - 1.0f);  /* the border repeats the edge pixel */
#elif EDGES == EDGES_REPEAT
    vf m = wrap_index(i0, fn);  /* right border = column 0 */
#elif EDGES == EDGES_MIRROR
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

/* Padded coordinate i (0 .. n + 1) of an axis of n samples (pixels) -> the sample, or
 * -1 for the background. */
inline int padded_sample(int i, int n) {
#if EDGES == EDGES_REPEAT
    return (i - 1 + n) % n;
#elif EDGES == EDGES_BACKGROUND
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
