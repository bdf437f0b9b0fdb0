/* ops/ink.cl: drop and spray (marblevideo/ops/ink.py). p: cx, cy, r^2, red,
 * green, blue. A point strictly inside the (progress-scaled) circle is ink of
 * op i; only the first hit of the walk counts, so later ops stay on top. */

/* drop: P = C + (P' - C) * sqrt(1 - r^2 / |P' - C|^2) outside the drop.
 * p[6], p[7]: a run of concentric drops walked as one (marblevideo/ops/ink.py,
 * link_concentric_drops): the r^2 of the run's drops walked before this one,
 * and whether this one moves the point (by the whole run's r^2). */
inline void op_drop(OP_ARGS) {
    vf qx = *x - p[0], qy = *y - p[1];
    vf d2 = qx * qx + qy * qy;
    const float off = p[6], moves = p[7];
    *ink = select(*ink, (vi)i, (d2 - off < p[2]) & (*ink < 0));
    if (moves != 0.0f) { /* uniform: one branch for every lane */
        vf k = sqrt(fmax(1.0f - (p[2] + off) * recip(fmax(d2, 1e-30f)), 0.0f));
        *x = p[0] + qx * k;
        *y = p[1] + qy * k;
    }
}

/* spray: ink inside, nothing moves. */
inline void op_spray(OP_ARGS) {
    vf qx = *x - p[0], qy = *y - p[1];
    vi inside = (qx * qx + qy * qy) < p[2];
    *ink = select(*ink, (vi)i, inside & (*ink < 0));
}
