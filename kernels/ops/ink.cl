/* ops/ink.cl: drop and spray (marblevideo/ops/ink.py). p: the circle (cx, cy,
 * r2 = r^2) and its colour (at COLOR_SLOT). A point strictly inside the
 * (progress-scaled) circle is ink of op i; only the first hit of the walk
 * counts, so later ops stay on top. */

/* drop: P = C + (P' - C) * sqrt(1 - r^2 / |P' - C|^2) outside the drop.
 * run_offset, run_moves: a run of concentric drops walked as one
 * (marblevideo/ops/ink.py, link_concentric_drops): the r^2 of the run's drops
 * walked before this one, and whether this one moves the point (by the whole
 * run's r^2). */
inline void op_drop(OP_ARGS) {
    const float cx = p[P_DROP_CX], cy = p[P_DROP_CY], r2 = p[P_DROP_R2];
    vf qx = *x - cx, qy = *y - cy;
    vf d2 = qx * qx + qy * qy;
    const float off = p[P_DROP_RUN_OFFSET], moves = p[P_DROP_RUN_MOVES];
    *ink = select(*ink, (vi)i, (d2 - off < r2) & (*ink < 0));
    if (moves != 0.0f) { /* uniform: one branch for every lane */
        vf k = sqrt(fmax(1.0f - (r2 + off) * recip(fmax(d2, 1e-30f)), 0.0f));
        *x = cx + qx * k;
        *y = cy + qy * k;
    }
}

/* spray: ink inside, nothing moves. */
inline void op_spray(OP_ARGS) {
    vf qx = *x - p[P_SPRAY_CX], qy = *y - p[P_SPRAY_CY];
    vm inside = (qx * qx + qy * qy) < p[P_SPRAY_R2];
    *ink = select(*ink, (vi)i, inside & (*ink < 0));
}
