/* ops/shear.cl: tine, comb, wave, shift and rake (marblevideo/ops/shear.py): a
 * shift along a fixed direction that depends only on the coordinate across it,
 * subtracted. */

/* tine: P = P' - alpha*lambda / (d + lambda) * M, d the distance to the tine
 * line. p: ax, ay, mx, my, nx, ny, alpha*lambda, lambda */
inline void op_tine(OP_ARGS) {
    vf d = fabs((*x - p[0]) * p[4] + (*y - p[1]) * p[5]);
    vf s = p[6] * recip(d + p[7]);
    *x -= s * p[2];
    *y -= s * p[3];
}

/* comb: as tine, d the distance to the nearest tine. p: as tine, then
 * spacing, 1/spacing, spacing/2 */
inline void op_comb(OP_ARGS) {
    vf d = fabs((*x - p[0]) * p[4] + (*y - p[1]) * p[5]);
    d = d - p[8] * floor(d * p[9]);                   /* fmod(d, spacing), d >= 0 */
    d = p[10] - fabs(d - p[10]);
    vf s = p[6] * recip(d + p[7]);
    *x -= s * p[2];
    *y -= s * p[3];
}

/* wave: v = P . (sin t, -cos t); shift = amplitude * sin(2 pi v / wavelength + phase)
 * along (cos t, sin t). p: amplitude, 1/wavelength, phase in turns, cos t, sin t */
inline void op_wave(OP_ARGS) {
    vf v = *x * p[4] - *y * p[3];
    vf s = p[0] * sin_turns(v * p[1] + p[2]);
    *x -= s * p[3];
    *y -= s * p[4];
}

/* shift: the tank moved; P = P' - offset. p: dx, dy */
inline void op_shift(OP_ARGS) {
    *x -= p[0];
    *y -= p[1];
}

/* rake: P = P' - alpha * sum_i exp(-|d_i| / L) * M, d_i = (P' - A) . N - o_i.
 * p: ax, ay, mx, my, nx, ny, alpha, 1/L, where its data start in lists, n tines,
 * even (1: evenly spaced; lists holds o0, 1/s, s, s/L, 1/(1 - q), q = e^(-s/L);
 * 0: the offsets o_i). Evenly spaced tines o0 + k s sum in closed form: with
 * j the last tine at or below the point (-1 .. n-1) and b = d_j, the tines
 * 0..j give e^(-b/L) (1 - q^(j+1)) / (1 - q) and the tines j+1..n-1 give
 * e^(-(s-b)/L) (1 - q^(n-1-j)) / (1 - q): four exponentials for any n. */
inline void op_rake(OP_ARGS) {
    vf across = (*x - p[0]) * p[4] + (*y - p[1]) * p[5];
    const int at = (int)p[8], n = (int)p[9];
    vf sum = (vf)0.0f;
    if (p[10] != 0.0f) {
        const float o0 = lists[at], inv_s = lists[at + 1], step = lists[at + 2];
        const float ratio = lists[at + 3], g = lists[at + 4];
        vf j = clamp(floor((across - o0) * inv_s), -1.0f, (float)(n - 1));
        vf b = across - (o0 + j * step);
        /* no tine on a side: an argument of 0 and 1 - q^0 = 0 give exactly 0 */
        vf below = exp_neg(select(b, (vf)0.0f, j < 0.0f) * p[7]);
        vf above = exp_neg(select(step - b, (vf)0.0f, j >= (float)(n - 1)) * p[7]);
        sum = (below * (1.0f - exp_neg((j + 1.0f) * ratio)) +
               above * (1.0f - exp_neg(((float)(n - 1) - j) * ratio))) * g;
    } else {
        for (int k = 0; k < n; k++)
            sum += exp_neg(fabs(across - lists[at + k]) * p[7]);
    }
    vf s = p[6] * sum;
    *x -= s * p[2];
    *y -= s * p[3];
}
