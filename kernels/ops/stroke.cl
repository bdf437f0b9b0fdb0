/* ops/stroke.cl: stroke (marblevideo/ops/stroke.py), a stylus drawn along a path
 * as a train of vortex-pair steps, walked back last step first: each step turns
 * P' about B = C - h by +t g(|P' - B|), then about A = C + h by -t g(|P1 - A|),
 * g(r) = (1 - r^2 / w^2)^2 inside w. A step moves nothing farther than 3w/2
 * from its centre C (one squared distance skips it), and a stroke nothing
 * outside its steps' bounding box.
 * The host packs the acting steps in forward order: a revision-3 stroke's prefix
 * (e_k folded into t), or a timed stroke's whole steps and its one partial step
 * (ops/stylus.py), so both walk the same loop.
 * p: steps_at, steps_n (where the steps start in `lists`, how many), inv_w2
 * (1/w^2), reach2 ((3w/2)^2), the box xmin, ymin, xmax, ymax. A step: cx, cy,
 * hx, hy, t (radians) */

/* Turn the lanes' points about (cx, cy) by t g(r); from r = w on (g = 0) the
 * points are kept exactly (cx + (x - cx) could round). |t g| <= 16/9 radians
 * (|drag| <= 4, a step, whole or partial, at most w/4 long), where Taylor
 * polynomials to x^13 and x^14 are good to 5e-9, with no range reduction: about
 * twice as fast as sincos_turns here (the walk through a wide stroke is mostly
 * these turns). */
inline void stroke_turn(vf *x, vf *y, float cx, float cy, float t, float inv_w2) {
    vf qx = *x - cx, qy = *y - cy;
    vf g = fmax(1.0f - (qx * qx + qy * qy) * inv_w2, 0.0f);
    vf a = t * g * g, a2 = a * a;
    vf sn = a * (1.0f + a2 * (-1.6666667e-1f + a2 * (8.3333333e-3f + a2 * (-1.9841270e-4f
               + a2 * (2.7557319e-6f + a2 * (-2.5052108e-8f + a2 * 1.6059044e-10f))))));
    vf cs = 1.0f + a2 * (-0.5f + a2 * (4.1666667e-2f + a2 * (-1.3888889e-3f + a2 * (2.4801587e-5f
               + a2 * (-2.7557319e-7f + a2 * (2.0876757e-9f + a2 * -1.1470746e-11f))))));
    vi inside = g > 0.0f;
    *x = select(*x, cx + qx * cs - qy * sn, inside);
    *y = select(*y, cy + qx * sn + qy * cs, inside);
}

inline void op_stroke(OP_ARGS) {
    if (!ANY((*x >= p[P_STROKE_XMIN]) & (*x <= p[P_STROKE_XMAX]) & (*y >= p[P_STROKE_YMIN])
             & (*y <= p[P_STROKE_YMAX])))
        return;
    __global const float *s = lists + (int)p[P_STROKE_STEPS_AT];
    const float inv_w2 = p[P_STROKE_INV_W2], reach2 = p[P_STROKE_REACH2];
    for (int k = (int)p[P_STROKE_STEPS_N] - 1; k >= 0; k--) {
        __global const float *q = s + 5 * k;
        vf dx = *x - q[0], dy = *y - q[1];
        if (!ANY(dx * dx + dy * dy < reach2))
            continue;
        stroke_turn(x, y, q[0] - q[2], q[1] - q[3], q[4], inv_w2);
        stroke_turn(x, y, q[0] + q[2], q[1] + q[3], -q[4], inv_w2);
    }
}
