/* ops/rotation.cl: circle, vortex and turn (marblevideo/ops/rotation.py): rotate
 * P' - C by -theta, theta = alpha*lambda/(d + lambda)/R, d = |R - r| (circle)
 * or R (vortex: r = 0 and R >= 0 make them one formula).
 * p: cx, cy, r, alpha*lambda / (2 pi), lambda  (theta in turns) */

inline void op_circle(OP_ARGS) {
    vf qx = *x - p[0], qy = *y - p[1];
    vf R = sqrt(qx * qx + qy * qy);
    vf turns = -p[3] * recip((fabs(R - p[2]) + p[4]) * fmax(R, 1e-30f));
    /* From 2^23 turns up (R -> 0 included: inf) float32 holds whole turns only:
     * no rotation (theta = 0 at R = 0 as the contract says). */
    vf sn, cs;
    sincos_turns(clamp(turns, -8388608.0f, 8388608.0f), &sn, &cs);
    *x = p[0] + qx * cs - qy * sn;
    *y = p[1] + qx * sn + qy * cs;
}

inline void op_vortex(OP_ARGS) {
    op_circle(x, y, ink, p, i, lists);
}

/* turn: the whole tank turned by a about C; P = C + rot(P' - C, -a).
 * p: cx, cy, cos a, sin a */
inline void op_turn(OP_ARGS) {
    vf qx = *x - p[0], qy = *y - p[1];
    *x = p[0] + qx * p[2] + qy * p[3];
    *y = p[1] - qx * p[3] + qy * p[2];
}
