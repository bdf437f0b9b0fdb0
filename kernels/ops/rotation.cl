/* ops/rotation.cl: circle, vortex, turn, stir and oseen (marblevideo/ops/rotation.py): rotate
 * P' - C by -theta, theta = alpha*lambda/(d + lambda)/R, d = |R - r| (circle)
 * or R (vortex: r = 0 and R >= 0 make them one formula).
 * p: cx, cy, radius (r), turns (alpha*lambda / (2 pi)), lambda (theta in
 * turns); a vortex packs the same slots (marblevideo/ops/rotation.py). */

inline void op_circle(OP_ARGS) {
    const float cx = p[P_CIRCLE_CX], cy = p[P_CIRCLE_CY];
    vf qx = *x - cx, qy = *y - cy;
    vf R = sqrt(qx * qx + qy * qy);
    vf turns = -p[P_CIRCLE_TURNS]
               * recip((fabs(R - p[P_CIRCLE_RADIUS]) + p[P_CIRCLE_LAMBDA]) * fmax(R, 1e-30f));
    /* From 2^23 turns up (R -> 0 included: inf) float32 holds whole turns only:
     * no rotation (theta = 0 at R = 0 as the contract says). */
    vf sn, cs;
    sincos_turns(clamp(turns, -8388608.0f, 8388608.0f), &sn, &cs);
    *x = cx + qx * cs - qy * sn;
    *y = cy + qx * sn + qy * cs;
}

inline void op_vortex(OP_ARGS) {
    op_circle(x, y, ink, p, i, lists);
}

/* turn: the whole tank turned by a about C; P = C + rot(P' - C, -a).
 * p: cx, cy, cos a, sin a */
inline void op_turn(OP_ARGS) {
    const float cx = p[P_TURN_CX], cy = p[P_TURN_CY], ca = p[P_TURN_COS], sa = p[P_TURN_SIN];
    vf qx = *x - cx, qy = *y - cy;
    *x = cx + qx * ca + qy * sa;
    *y = cy - qx * sa + qy * ca;
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

/* stir: rotate P' - C by -theta. With alpha (relative 0): theta = alpha sum_i sign(r_i)
 * e^(-|R - |r_i|| / L) / R (0 at R = 0); p: cx, cy, turns (alpha / (2 pi)), inv_falloff
 * (1/L), then the rings as a series of |r_i| with coefficients sign(r_i) (prelude's
 * series_sum): where, n, even. With turn th (relative 1): theta = th sum_i sign(r_i)
 * e^(-|R - |r_i|| / (L |r_i|)); turns th / 360 and, term by term at `where`, the n |r_i|,
 * the n sign(r_i) and the n 1 / (L |r_i|). */
inline void op_stir(OP_ARGS) {
    const float cx = p[P_STIR_CX], cy = p[P_STIR_CY];
    vf qx = *x - cx, qy = *y - cy;
    vf R = sqrt(qx * qx + qy * qy);
    LIST_SPACE const float *d = lists + (int)p[P_STIR_SERIES_AT];
    const int n = (int)p[P_STIR_SERIES_N];
    if (p[P_STIR_RELATIVE] != 0.0f) {
        vf sum = (vf)0.0f;
        for (int k = 0; k < n; k++)
            sum += d[n + k] * exp_neg(fabs(R - d[k]) * d[2 * n + k]);
        turn_about(x, y, cx, cy, -p[P_STIR_TURNS] * sum);
        return;
    }
    vf sum = series_sum(R, d, n, p[P_STIR_SERIES_EVEN] != 0.0f, p[P_STIR_INV_FALLOFF]);
    turn_about(x, y, cx, cy, -p[P_STIR_TURNS] * sum * recip(fmax(R, 1e-30f)));
}

/* oseen: rotate P' - C by -theta, theta = G (a + c R^(3/2))^(-4/3), a = (4 nu)^(3/4),
 * c = (2 pi / T)^(3/4). p: cx, cy, turns (G / (2 pi); 0 when T = 0), a, c */
inline void op_oseen(OP_ARGS) {
    const float cx = p[P_OSEEN_CX], cy = p[P_OSEEN_CY];
    vf qx = *x - cx, qy = *y - cy;
    vf R = sqrt(qx * qx + qy * qy);
    vf z = p[P_OSEEN_A] + p[P_OSEEN_C] * R * sqrt(R);
    turn_about(x, y, cx, cy, -p[P_OSEEN_TURNS] * recip(z * cbrt_pos(z)));
}
