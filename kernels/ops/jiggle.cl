/* ops/jiggle.cl: jiggle (marblevideo/ops/jiggle.py): the tank shaken. The
 * forward map moves P by A sin(tau) along M and B cos(tau) along N, tau in turns
 * = s / wavelength + phase, s = P . M. The inverse solves s + A sin(tau(s)) = s'
 * by Newton's method kept inside the bracket s' - |A| .. s' + |A| (the left side
 * grows with s while |k A| < 1), in u = s - s', from the phase of s' reduced
 * once. */

#ifndef JIGGLE_STEPS
#define JIGGLE_STEPS 40
#endif

/* JIGGLE_PHASE(t0): the phase of s' = P' . M in turns, reduced to [0, 1). Near
 * |k A| -> 1 an error in it grows 1 / (1 - |k A|) times in the root, and float32
 * holds s' only to 1e-4 at 2000 units: so where the device has float64 the
 * phase is taken in float64, from M, 1/wavelength and the phase packed as
 * float pairs (value = p[P_JIGGLE_<NAME>] + p[P_JIGGLE_<NAME>_LO]). */
#if defined(cl_khr_fp64)
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#define PAIR(name) ((double)p[P_JIGGLE_##name] + (double)p[P_JIGGLE_##name##_LO])
/* the phase of the points v.part (x) and w.part (y) into t.part, in float64 */
#define JIGGLE_PHASE_OF(T, CD, CF, xs, ys, ts)                                 \
    {                                                                          \
        T s_ = CD(xs) * PAIR(MX) + CD(ys) * PAIR(MY);                          \
        T t_ = s_ * PAIR(INV_WAVELENGTH) + PAIR(PHASE_TURNS);                  \
        ts = CF(t_ - floor(t_));                                               \
    }
#if LANES == 1
#define JIGGLE_PHASE(t0) JIGGLE_PHASE_OF(double, convert_double, convert_float, *x, *y, t0)
#else
/* in two halves: a double vector of LANES lanes is twice the native width */
#if LANES == 4
#define JIGGLE_HALF 2
#elif LANES == 8
#define JIGGLE_HALF 4
#else
#define JIGGLE_HALF 8
#endif
#define JIGGLE_PHASE(t0)                                                       \
    {                                                                          \
        JIGGLE_PHASE_OF(CAT(double, JIGGLE_HALF), CAT(convert_double, JIGGLE_HALF), \
                        CAT(convert_float, JIGGLE_HALF), (*x).lo, (*y).lo, t0.lo) \
        JIGGLE_PHASE_OF(CAT(double, JIGGLE_HALF), CAT(convert_double, JIGGLE_HALF), \
                        CAT(convert_float, JIGGLE_HALF), (*x).hi, (*y).hi, t0.hi) \
    }
#endif
#else
#define JIGGLE_PHASE(t0)                                                       \
    {                                                                          \
        t0 = (*x * p[P_JIGGLE_MX] + *y * p[P_JIGGLE_MY]) * p[P_JIGGLE_INV_WAVELENGTH] \
             + p[P_JIGGLE_PHASE_TURNS];                                        \
        t0 -= floor(t0);                                                       \
    }
#endif

/* p: mx, my, inv_wavelength, phase_turns, major (A), minor (B), ka (k A), then
 * the low parts of the first four (see JIGGLE_PHASE) */
inline void op_jiggle(OP_ARGS) {
    const float mx = p[P_JIGGLE_MX], my = p[P_JIGGLE_MY], inv_w = p[P_JIGGLE_INV_WAVELENGTH];
    const float a = p[P_JIGGLE_MAJOR], b = p[P_JIGGLE_MINOR], ka = p[P_JIGGLE_KA];
    vf t0;
    JIGGLE_PHASE(t0)
    vf u = (vf)0.0f, lo = (vf)-fabs(a), hi = (vf)fabs(a);  /* u = s - s' */
    vf sn, cs;
    for (int k = 0; k < JIGGLE_STEPS; k++) {
        sincos_turns(t0 + u * inv_w, &sn, &cs);
        vf g = u + a * sn;               /* s + A sin(tau) - s' */
        lo = select(lo, u, g < 0.0f);
        hi = select(hi, u, g > 0.0f);
        vf next = u - g / (1.0f + ka * cs);
        next = select(next, 0.5f * (lo + hi), (next <= lo) | (next >= hi));
        vf moved = fabs(next - u);
        u = next;
        if (!ANY(moved > 1e-5f))
            break;
    }
    sincos_turns(t0 + u * inv_w, &sn, &cs);
    vf along = a * sn, across = b * cs;
    *x -= along * mx - across * my;
    *y -= along * my + across * mx;
}

#if defined(cl_khr_fp64)
#undef PAIR
#pragma OPENCL EXTENSION cl_khr_fp64 : disable
#endif
