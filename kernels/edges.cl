/* edges.cl: what lies outside the input, by the edges mode (EDGES, one of the
 * generated EDGES_* codes): an integer tap index mapped into the input, for
 * the renderer's sampling (sampling.cl) and the exported programs alike. */

/* i mod n (0 <= result < n) for integer-valued floats below 2^24, exact on any
 * device: OpenCL lets i / n be 2.5 ulp off, so an exact multiple (96 / 96) can
 * floor one too low or high and send a wrapped column to the far edge (1.5%
 * of pixels off the reference with edges=repeat on NVIDIA's OpenCL). The
 * product and difference are exact, so one step either way corrects it. */
inline vf wrap_index(vf i, float n) {
    vf m = i - n * floor(i / n);
    m = select(m, m - n, m >= n);
    return select(m, m + n, m < 0.0f);
}

/* Map an integer-valued float tap index into 0..n-1 by the `edges` mode;
 * with EDGES_BACKGROUND an index outside gives -1. */
inline vi edge_index(vf i, int n) {
    float fn = (float)n;
#if EDGES == EDGES_CLAMP
    vf m = clamp(i, 0.0f, fn - 1.0f);
#elif EDGES == EDGES_REPEAT
    vf m = wrap_index(i, fn);
#elif EDGES == EDGES_MIRROR
    vf m = wrap_index(i, 2.0f * fn);
    m = clamp(select(m, 2.0f * fn - 1.0f - m, m >= fn), 0.0f, fn - 1.0f);
#else
    vf m = select(i, (vf)-1.0f, (i < 0.0f) | (i > fn - 1.0f));
#endif
    return CVT_I(m);
}
