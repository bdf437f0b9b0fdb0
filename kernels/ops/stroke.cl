/* ops/stroke.cl: stroke (marblevideo/ops/stroke.py), a stylus drawn along a path
 * as a train of vortex-pair steps, walked back last step first: each step turns
 * P' about B = C - h by +t g(|P' - B|), then about A = C + h by -t g(|P1 - A|),
 * g(r) = (1 - r^2 / w^2)^2 inside w.
 * The host packs the acting steps in forward order: a revision-3 stroke's prefix
 * (e_k folded into t), or a timed stroke's whole steps and its one partial step
 * (ops/stylus.py), so both walk the same loop.
 * What is skipped, every skip exact (a skipped turn would have kept every lane):
 * a stroke where no lane is in its steps' bounding box; a block of `block`
 * consecutive steps where none is inside the block's circle (every point its
 * steps can move; marblevideo/ops/stepblocks.py); a step where none is within
 * 3w/2 of its centre C; a turn where none is within w of its centre.
 * A chained section (OpDef.chained): x, y, ink point to the work-item's CHAINS
 * chains, walked together, so that one test serves them all and their turns'
 * independent polynomials interleave.
 * p: steps_at, steps_n (where the steps start in `lists`, how many), inv_w2
 * (1/w^2), reach2 ((3w/2)^2), the box xmin, ymin, xmax, ymax, block (steps per
 * block). A step: cx, cy, hx, hy, t (radians); after the steps, a block's
 * circle: cx, cy, r^2. */

/* Whether any lane of the CHAINS chains at (x, y) lies within sqrt(r2) of (cx, cy). */
inline bool stroke_near(const vf *x, const vf *y, float cx, float cy, float r2) {
    vm near = (vm)0;
    for (int c = 0; c < CHAINS; c++) {
        vf dx = x[c] - cx, dy = y[c] - cy;
        near |= dx * dx + dy * dy < r2;
    }
    return ANY(near);
}

/* Turn the chains' points about (cx, cy) by t g(r); from r = w on (g = 0) the
 * points are kept exactly (cx + (x - cx) could round), and when no lane of any
 * chain is within w, nothing is computed. |t g| <= 16/9 radians
 * (|drag| <= 4, a step, whole or partial, at most w/4 long), where Taylor
 * polynomials to x^13 and x^14 are good to 5e-9, with no range reduction: about
 * twice as fast as sincos_turns here (the walk through a wide stroke is mostly
 * these turns). The chains' polynomials are independent: one loop over them
 * keeps several in flight (one chain's alone is a chain of dependent FMAs). */
inline void stroke_turn(vf *x, vf *y, float cx, float cy, float t, float inv_w2) {
    vf g[CHAINS];
    vm near = (vm)0;
    for (int c = 0; c < CHAINS; c++) {
        vf qx = x[c] - cx, qy = y[c] - cy;
        g[c] = fmax(1.0f - (qx * qx + qy * qy) * inv_w2, 0.0f);
        near |= g[c] > 0.0f;
    }
    if (!ANY(near))
        return;
    for (int c = 0; c < CHAINS; c++) {
        vf qx = x[c] - cx, qy = y[c] - cy;
        vf a = t * g[c] * g[c], a2 = a * a;
        vf sn = a * (1.0f + a2 * (-1.6666667e-1f + a2 * (8.3333333e-3f + a2 * (-1.9841270e-4f
                   + a2 * (2.7557319e-6f + a2 * (-2.5052108e-8f + a2 * 1.6059044e-10f))))));
        vf cs = 1.0f + a2 * (-0.5f + a2 * (4.1666667e-2f + a2 * (-1.3888889e-3f
                   + a2 * (2.4801587e-5f + a2 * (-2.7557319e-7f + a2 * (2.0876757e-9f
                   + a2 * -1.1470746e-11f))))));
        vm inside = g[c] > 0.0f;
        x[c] = select(x[c], cx + qx * cs - qy * sn, inside);
        y[c] = select(y[c], cy + qx * sn + qy * cs, inside);
    }
}

inline void op_stroke(OP_ARGS) {
    vm inbox = (vm)0;
    for (int c = 0; c < CHAINS; c++)
        inbox |= ((x[c] >= p[P_STROKE_XMIN]) & (x[c] <= p[P_STROKE_XMAX])
                     & (y[c] >= p[P_STROKE_YMIN]) & (y[c] <= p[P_STROKE_YMAX]));
    if (!ANY(inbox))
        return;
    const int n = (int)p[P_STROKE_STEPS_N], per = (int)p[P_STROKE_BLOCK];
    LIST_SPACE const float *s = lists + (int)p[P_STROKE_STEPS_AT];
    LIST_SPACE const float *blocks = s + 5 * n;
    const float inv_w2 = p[P_STROKE_INV_W2], reach2 = p[P_STROKE_REACH2];
    for (int b = (n + per - 1) / per - 1; b >= 0; b--) {
        if (!stroke_near(x, y, blocks[3 * b], blocks[3 * b + 1], blocks[3 * b + 2]))
            continue;
        for (int k = min(n, (b + 1) * per) - 1; k >= b * per; k--) {
            LIST_SPACE const float *q = s + 5 * k;
            if (!stroke_near(x, y, q[0], q[1], reach2))
                continue;
            stroke_turn(x, y, q[0] - q[2], q[1] - q[3], q[4], inv_w2);
            stroke_turn(x, y, q[0] + q[2], q[1] + q[3], -q[4], inv_w2);
        }
    }
}
