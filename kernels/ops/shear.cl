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
 * p: ax, ay, mx, my, nx, ny, alpha, 1/L, then the tines as a series (prelude's
 * series_sum): where their data start in lists, n, even */
inline void op_rake(OP_ARGS) {
    vf across = (*x - p[0]) * p[4] + (*y - p[1]) * p[5];
    vf sum = series_sum(across, lists + (int)p[8], (int)p[9], p[10] != 0.0f, p[7]);
    vf s = p[6] * sum;
    *x -= s * p[2];
    *y -= s * p[3];
}
