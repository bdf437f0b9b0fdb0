/* ops/ink.cl: drop and spray (marblevideo/ops/ink.py). p: cx, cy, r^2, red,
 * green, blue. A point strictly inside the (progress-scaled) circle is ink of
 * op i; only the first hit of the walk counts, so later ops stay on top. */

/* drop: P = C + (P' - C) * sqrt(1 - r^2 / |P' - C|^2) outside the drop. */
inline void op_drop(OP_ARGS) {
    vf qx = *x - p[0], qy = *y - p[1];
    vf d2 = qx * qx + qy * qy;
    *ink = select(*ink, (vi)i, (d2 < p[2]) & (*ink < 0));
    vf k = sqrt(fmax(1.0f - p[2] * recip(fmax(d2, 1e-30f)), 0.0f));
    *x = p[0] + qx * k;
    *y = p[1] + qy * k;
}

/* spray: ink inside, nothing moves. */
inline void op_spray(OP_ARGS) {
    vf qx = *x - p[0], qy = *y - p[1];
    vi inside = (qx * qx + qy * qy) < p[2];
    *ink = select(*ink, (vi)i, inside & (*ink < 0));
}
