/* math.cl: the op sections' math helpers, without the library's sin, exp or
 * division, so that every device (and every export) rounds alike. Written in
 * the op sections' dialect: OpenCL C that marblevideo/export/dialect.py also
 * turns into GLSL (vf, vi, vm, select, the casts, pointers into `lists`). */

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

/* sin and cos of 2*pi*t from one range reduction: the half angle h = pi*u,
 * u in [-1/2, 1/2), has Taylor polynomials good to 6e-8 on [-pi/2, pi/2];
 * then sin = 2 sin(h) cos(h), cos = 1 - 2 sin(h)^2. Fewer live values than two
 * sin_turns calls, which spilled registers with 4 chains of 16 lanes. */
inline void sincos_turns(vf t, vf *sn, vf *cs) {
    vf h = (t - floor(t + 0.5f)) * 3.14159265359f;
    vf h2 = h * h;
    vf s = h * (1.0f + h2 * (-1.6666667e-1f + h2 * (8.3333333e-3f + h2 * (-1.9841270e-4f
               + h2 * (2.7557319e-6f + h2 * -2.5052108e-8f)))));
    vf c = 1.0f + h2 * (-0.5f + h2 * (4.1666667e-2f + h2 * (-1.3888889e-3f + h2 * (2.4801587e-5f
               + h2 * (-2.7557319e-7f + h2 * 2.0876757e-9f)))));
    *sn = 2.0f * s * c;
    *cs = 1.0f - 2.0f * s * s;
}

/* e^-x for x >= 0 (0 from x = 87 on), without the library exp: 2^t with
 * t = -x log2(e) split into a whole n and f in [-1/2, 1/2), 2^f by its Taylor
 * polynomial (relative error < 2e-7) and 2^n put into the exponent bits. */
inline vf exp_neg(vf x) {
    vf t = fmin(x, 87.0f) * -1.44269504089f;
    vf n = floor(t + 0.5f);
    vf f = (t - n) * 0.69314718056f;
    vf q = 1.0f + f * (1.0f + f * (0.5f + f * (1.6666667e-1f + f * (4.1666667e-2f
               + f * (8.3333333e-3f + f * (1.3888889e-3f + f * 1.9841270e-4f))))));
    vf scale = AS_VF((CVT_I(n) + 127) << 23);
    return select(q * scale, (vf)0.0f, x >= 87.0f);
}

/* sum_k c_k e^(-|u - o_k| / L) (inv_l = 1/L) over a rake's tines or a stir's
 * rings, their data at d (marblevideo/ops/series.py). Term by term: n positions
 * o_k, then n coefficients c_k. In closed form (even), for o_k = o0 + k s and
 * c_k = c0 sigma^k (sigma = +-1): with j the last o_k at or below u (-1 .. n-1)
 * and b = u - o_j, the terms up to j sum to c_j e^(-b/L) (1 - (sigma q)^(j+1))
 * / (1 - sigma q) and those above to c_(j+1) e^(-(s-b)/L) (1 - (sigma
 * q)^(n-1-j)) / (1 - sigma q), q = e^(-s/L): four exponentials for any n; a
 * side without terms gets an argument of 0 and a factor of exactly 0.
 * d: o0, 1/s, s, s/L, 1/(1 - sigma q), c0, sigma, sigma^(n-1). */
inline vf series_sum(vf u, LIST_SPACE const float *d, int n, bool even, float inv_l) {
    if (!even) {
        vf sum = (vf)0.0f;
        for (int k = 0; k < n; k++)
            sum += d[n + k] * exp_neg(fabs(u - d[k]) * inv_l);
        return sum;
    }
    const float step = d[2], ratio = d[3], sigma = d[6];
    vf j = clamp(floor((u - d[0]) * d[1]), -1.0f, (float)(n - 1));
    vf b = u - (d[0] + j * step);
    vf sj = 1.0f + (sigma - 1.0f) * (j - 2.0f * floor(0.5f * j)); /* sigma^j */
    vf below = exp_neg(select(b, (vf)0.0f, j < 0.0f) * inv_l);
    vf above = exp_neg(select(step - b, (vf)0.0f, j >= (float)(n - 1)) * inv_l);
    below *= 1.0f - sj * sigma * exp_neg((j + 1.0f) * ratio);
    above *= sigma * (1.0f - d[7] * sj * exp_neg(((float)(n - 1) - j) * ratio));
    return (d[5] * d[4]) * sj * (below + above);
}

/* z^(1/3) for z > 0, without the library: a guess from the exponent bits (within
 * 4%), then three Newton steps (relative error < 1e-7). */
inline vf cbrt_pos(vf z) {
    vf y = AS_VF(AS_VI(z) / 3 + 709921077);
    for (int k = 0; k < 3; k++)
        y = (2.0f * y + z / (y * y)) * (1.0f / 3.0f);
    return y;
}

/* 1/x for x > 0: the device's fast reciprocal and one Newton step (full float
 * precision from an estimate of 12+ bits; 12% faster walks on PoCL than a
 * division). x is capped at 1e30 so that an infinite x gives ~0, not NaN. */
inline vf recip(vf x) {
    x = fmin(x, 1e30f);
    vf y = native_recip(x);
    return y * (2.0f - x * y);
}
