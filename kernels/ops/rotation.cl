/* ops/rotation.cl: circle, vortex, turn, stir and oseen (marblevideo/ops/rotation.py): rotate
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

/* Rotate the lanes' points about (cx, cy) by `turns` (whole turns, clockwise on
 * screen; from 2^23 turns up float32 holds whole turns only: no rotation). */
inline void turn_about(vf *x, vf *y, float cx, float cy, vf turns) {
    vf qx = *x - cx, qy = *y - cy;
    vf sn, cs;
    sincos_turns(clamp(turns, -8388608.0f, 8388608.0f), &sn, &cs);
    *x = cx + qx * cs - qy * sn;
    *y = cy + qx * sn + qy * cs;
}

/* stir: rotate P' - C by -theta, theta = alpha sum_i sign(r_i) e^(-|R - |r_i|| / L) / R
 * (0 at R = 0). p: cx, cy, alpha / (2 pi), 1/L, then the rings as a series of
 * |r_i| with coefficients sign(r_i) (prelude's series_sum): where, n, even */
inline void op_stir(OP_ARGS) {
    vf qx = *x - p[0], qy = *y - p[1];
    vf R = sqrt(qx * qx + qy * qy);
    vf sum = series_sum(R, lists + (int)p[4], (int)p[5], p[6] != 0.0f, p[3]);
    turn_about(x, y, p[0], p[1], -p[2] * sum * recip(fmax(R, 1e-30f)));
}

/* oseen: rotate P' - C by -theta, theta = G (a + c R^(3/2))^(-4/3), a = (4 nu)^(3/4),
 * c = (2 pi / T)^(3/4). p: cx, cy, G / (2 pi) (0 when T = 0), a, c */
inline void op_oseen(OP_ARGS) {
    vf qx = *x - p[0], qy = *y - p[1];
    vf R = sqrt(qx * qx + qy * qy);
    vf z = p[3] + p[4] * R * sqrt(R);
    turn_about(x, y, p[0], p[1], -p[2] * recip(z * cbrt_pos(z)));
}
