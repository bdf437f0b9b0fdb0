/* ops/shear.cl: tine, comb, wave, shift and rake (marblevideo/ops/shear.py): a
 * shift along a fixed direction that depends only on the coordinate across it,
 * subtracted. */

/* tine: P = P' - alpha*lambda / (d + lambda) * M, d the distance to the tine
 * line. p: A (ax, ay), M (mx, my), N (nx, ny), alpha_lambda, lambda */
inline void op_tine(OP_ARGS) {
    vf d = fabs((*x - p[P_TINE_AX]) * p[P_TINE_NX] + (*y - p[P_TINE_AY]) * p[P_TINE_NY]);
    vf s = p[P_TINE_ALPHA_LAMBDA] * recip(d + p[P_TINE_LAMBDA]);
    *x -= s * p[P_TINE_MX];
    *y -= s * p[P_TINE_MY];
}

/* comb: as tine, d the distance to the nearest tine. p: as tine, then
 * spacing, inv_spacing (1/spacing), half_spacing */
inline void op_comb(OP_ARGS) {
    vf d = fabs((*x - p[P_COMB_AX]) * p[P_COMB_NX] + (*y - p[P_COMB_AY]) * p[P_COMB_NY]);
    d = d - p[P_COMB_SPACING] * floor(d * p[P_COMB_INV_SPACING]); /* fmod(d, spacing), d >= 0 */
    d = p[P_COMB_HALF_SPACING] - fabs(d - p[P_COMB_HALF_SPACING]);
    vf s = p[P_COMB_ALPHA_LAMBDA] * recip(d + p[P_COMB_LAMBDA]);
    *x -= s * p[P_COMB_MX];
    *y -= s * p[P_COMB_MY];
}

/* wave: v = P . (sin t, -cos t); shift = amplitude * sin(2 pi v / wavelength + phase)
 * along (cos t, sin t). p: amplitude, inv_wavelength, phase_turns, cos, sin (of t) */
inline void op_wave(OP_ARGS) {
    const float ct = p[P_WAVE_COS], st = p[P_WAVE_SIN];
    vf v = *x * st - *y * ct;
    vf s = p[P_WAVE_AMPLITUDE] * sin_turns(v * p[P_WAVE_INV_WAVELENGTH] + p[P_WAVE_PHASE_TURNS]);
    *x -= s * ct;
    *y -= s * st;
}

/* shift: the tank moved; P = P' - offset. p: dx, dy */
inline void op_shift(OP_ARGS) {
    *x -= p[P_SHIFT_DX];
    *y -= p[P_SHIFT_DY];
}

/* rake: P = P' - alpha * sum_i exp(-|d_i| / L) * M, d_i = (P' - A) . N - o_i.
 * p: A, M, N as tine's, alpha, inv_falloff (1/L), then the tines as a series
 * (prelude's series_sum): where their data start in lists, n, even */
inline void op_rake(OP_ARGS) {
    vf across = (*x - p[P_RAKE_AX]) * p[P_RAKE_NX] + (*y - p[P_RAKE_AY]) * p[P_RAKE_NY];
    vf sum = series_sum(across, lists + (int)p[P_RAKE_SERIES_AT], (int)p[P_RAKE_SERIES_N],
                        p[P_RAKE_SERIES_EVEN] != 0.0f, p[P_RAKE_INV_FALLOFF]);
    vf s = p[P_RAKE_ALPHA] * sum;
    *x -= s * p[P_RAKE_MX];
    *y -= s * p[P_RAKE_MY];
}
