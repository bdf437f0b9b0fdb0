/* glsl/marble.glsl: a pixel of a recipe exported as a shader
 * (marblevideo/export/shader.py), after the prelude, the op sections and the
 * frames' data (the tables of marblevideo/export/frames.py, every float in
 * MV_DATA: rows from 0, lists from MV_LISTS_AT, backgrounds from
 * MV_BACKGROUND_AT, the pattern from MV_SAMPLES_AT).
 *
 * The host part defines, before this file:
 *   MV_TEXEL(ix, iy)  the input's pixel (ix, iy), row 0 at the top, 0..1 RGBA
 *                     (with HAS_INPUT 1)
 * Output pixel (ox, oy) counts rows from the top; colours are 0..255 inside. */

/* Canvas point (x, y) walked back through the ops at frame `frame` (in place):
 * the number of the ink op that holds it (-1: none) and that ink's colour. */
int walk_back(inout float x, inout float y, out vec3 rgb, int frame) {
    float px[1];
    float py[1];
    int ink[1];
    px[0] = x;
    py[0] = y;
    ink[0] = -1;
    int lists = MV_LISTS_AT;
    WALK
    float cr = 0.0, cg = 0.0, cb = 0.0;
    if (ink[0] >= 0) { INK }
    x = px[0];
    y = py[0];
    rgb = vec3(cr, cg, cb);
    return ink[0];
}

#if HAS_INPUT
/* Input pixel (ix, iy) by the edges mode (edge_index gives -1 outside with
 * EDGES_BACKGROUND: `bg`), 0..255. */
vec4 texel(int ix, int iy, vec4 bg) {
    if (ix < 0 || iy < 0)
        return bg;
    return MV_TEXEL(ix, iy) * 255.0;
}

/* Bilinear between the input's pixel centres at input pixel coordinates (ix, iy)
 * of an sw x sh input, each tap placed by the edges mode. */
vec4 sample_input(float ix, float iy, int sw, int sh, vec4 bg) {
    float fx = clamp(ix - 0.5, -4.0e6, 4.0e6), fy = clamp(iy - 0.5, -4.0e6, 4.0e6);
    float x0 = floor(fx), y0 = floor(fy);
    float wx = fx - x0, wy = fy - y0;
    int ax = edge_index(x0, sw), bx = edge_index(x0 + 1.0, sw);
    int ay = edge_index(y0, sh), by = edge_index(y0 + 1.0, sh);
    vec4 top = mix(texel(ax, ay, bg), texel(bx, ay, bg), wx);
    vec4 bottom = mix(texel(ax, by, bg), texel(bx, by, bg), wx);
    return mix(top, bottom, wy);
}
#endif

/* Output pixel (ox, oy) of a w x h frame at time t (seconds, on the table's
 * clock: frame round(t * MV_FPS)), over an sw x sh input (HAS_INPUT) or a blank
 * sheet, as 0..1 RGBA. The canvas is fitted into the frame (the input stretched
 * over it), as the renderer's default geometry. */
vec4 marble_pixel(float ox, float oy, float w, float h, float t, int sw, int sh) {
    int frame = int(clamp(floor(t * MV_FPS + 0.5), 0.0, 2147483520.0));
    float cw = MV_CANVAS_W > 0.0 ? MV_CANVAS_W : (HAS_INPUT == 1 ? float(sw) : w);
    float ch = MV_CANVAS_H > 0.0 ? MV_CANVAS_H : (HAS_INPUT == 1 ? float(sh) : h);
    float s = min(w / cw, h / ch), dx = (w - s * cw) * 0.5, dy = (h - s * ch) * 0.5;
    int b = MV_BACKGROUND_AT + 3 * MV_STEP(frame, MV_BACKGROUND_FIRST, MV_BACKGROUND_COUNT);
    vec4 bg = vec4(MV_DATA[b], MV_DATA[b + 1], MV_DATA[b + 2], 255.0);
    vec4 acc = vec4(0.0);
    for (int k = 0; k < NSAMPLES; k++) {
        int at = MV_SAMPLES_AT + 3 * k;
        float cx = (ox + 0.5 + MV_DATA[at]) / s - dx / s;
        float cy = (oy + 0.5 + MV_DATA[at + 1]) / s - dy / s;
        vec3 rgb;
        vec4 colour = bg;
        if (walk_back(cx, cy, rgb, frame) >= 0)
            colour = vec4(rgb, 255.0);
#if HAS_INPUT
        else
            colour = sample_input((cx * s + dx) * float(sw) / w, (cy * s + dy) * float(sh) / h,
                                  sw, sh, bg);
#endif
        acc += MV_DATA[at + 2] * colour;
    }
    return clamp(floor(acc + 0.5), 0.0, 255.0) / 255.0;
}
