/* export/ffmpeg.cl: the kernels of a recipe exported for ffmpeg
 * (marblevideo/export/opencl.py): `marble` for the program_opencl filter (over
 * the input frames) and `marble_sheet` for the openclsrc source (a blank
 * sheet), one pixel per work-item (LANES, CHAINS and ROWS 1), every subsample
 * of the recipe's pattern walked through the same op sections as the renderer's.
 *
 * Generated before this file (marblevideo/export/frames.py has the layout):
 *   MV_ROWS        op rows, PSTRIDE floats each; op i at frame k reads row
 *                  MV_ROW_AT[i] + clamp(k - MV_FIRST[i], 0, MV_COUNT[i] - 1)
 *   MV_LISTS       the ops' list data (the number of ops first)
 *   MV_BACKGROUND  (r, g, b) rows, 0..255, from frame MV_BACKGROUND_FIRST
 *                  (MV_BACKGROUND_COUNT of them)
 *   MV_SAMPLES     the pattern: (dx, dy, weight) per subsample, NSAMPLES of them
 *   MV_CANVAS_W, MV_CANVAS_H  the recipe's canvas; 0: the frame's own size
 * Frame `index` is the recipe at index / fps (fixed at export). Images are RGBA
 * with 8-bit channels (ffmpeg's format=rgba); colours are 0..255 inside.
 */

/* Row `k` of a table whose rows cover frames first .. first + count - 1. */
#define MV_STEP(k, first, count) clamp((k) - (first), 0, (count) - 1)
/* Op i's row at the frame `frame` (a variable of the walk's scope). */
#undef PARAMS
#define PARAMS(i) (MV_ROWS + (MV_ROW_AT[i] + MV_STEP(frame, MV_FIRST[i], MV_COUNT[i])) * PSTRIDE)

__constant sampler_t MV_NEAREST =
    CLK_NORMALIZED_COORDS_FALSE | CLK_ADDRESS_CLAMP_TO_EDGE | CLK_FILTER_NEAREST;

/* Canvas point (x, y) walked back through the ops at frame `frame` (in place):
 * the number of the ink op that holds it (-1: none) and that ink's colour. */
inline int walk_back(float *x, float *y, float3 *rgb, int frame) {
    __constant const float *lists = MV_LISTS;
    vf px[1] = {*x}, py[1] = {*y};
    vi ink[1] = {-1};
    WALK
    vf cr = 0.0f, cg = 0.0f, cb = 0.0f;
    const int c = 0;
    if (ink[0] >= 0) { INK }
    *x = px[0];
    *y = py[0];
    *rgb = (float3)(cr, cg, cb);
    return ink[0];
}

/* Input pixel (ix, iy) by the edges mode, 0..255; `bg` outside with
 * EDGES_BACKGROUND (edge_index gives -1 there). */
inline float4 texel(__read_only image2d_t src, int ix, int iy, float4 bg) {
    if (ix < 0 || iy < 0)
        return bg;
    return read_imagef(src, MV_NEAREST, (int2)(ix, iy)) * 255.0f;
}

/* Bilinear between input pixel centres at input pixel coordinates (ix, iy),
 * each tap placed by the edges mode (as the renderer's padded footprint:
 * a mirrored pair of taps is the same pair in the other order). Taps are read
 * with a nearest sampler at whole pixels and blended here: exact on any device
 * (PoCL emulates linear sampling in software). */
inline float4 sample_input(__read_only image2d_t src, float ix, float iy, float4 bg) {
    const int sw = get_image_width(src), sh = get_image_height(src);
    float fx = clamp(ix - 0.5f, -4.0e6f, 4.0e6f), fy = clamp(iy - 0.5f, -4.0e6f, 4.0e6f);
    float x0 = floor(fx), y0 = floor(fy);
    float wx = fx - x0, wy = fy - y0;
    int ax = edge_index(x0, sw), bx = edge_index(x0 + 1.0f, sw);
    int ay = edge_index(y0, sh), by = edge_index(y0 + 1.0f, sh);
    float4 top = mix(texel(src, ax, ay, bg), texel(src, bx, ay, bg), wx);
    float4 bottom = mix(texel(src, ax, by, bg), texel(src, bx, by, bg), wx);
    return mix(top, bottom, wy);
}

/* Output pixel (x, y) of a w x h frame of the recipe at frame `index`: every
 * subsample walked from its canvas point (gc: output -> canvas, sx, sy, ox, oy)
 * and shaded by its ink, else the input at gi (canvas -> input pixels), else
 * (no input) the background; the weighted sum rounded as the renderer's. */
#define MARBLE_PIXEL(x, y, index, gc, gi, INPUT)                                        \
    const int frame = min((uint)(index), (uint)INT_MAX);                              \
    __constant const float *bg_ =                                                     \
        MV_BACKGROUND + 3 * MV_STEP(frame, MV_BACKGROUND_FIRST, MV_BACKGROUND_COUNT);  \
    const float4 bg = (float4)(bg_[0], bg_[1], bg_[2], 255.0f);                        \
    float4 acc = (float4)0.0f;                                                        \
    for (int k = 0; k < NSAMPLES; k++) {                                              \
        float cx = ((float)(x) + 0.5f + MV_SAMPLES[3 * k]) * gc.s0 + gc.s2;           \
        float cy = ((float)(y) + 0.5f + MV_SAMPLES[3 * k + 1]) * gc.s1 + gc.s3;       \
        float3 rgb;                                                                   \
        float4 colour;                                                                \
        if (walk_back(&cx, &cy, &rgb, frame) >= 0)                                    \
            colour = (float4)(rgb, 255.0f);                                           \
        else                                                                          \
            colour = INPUT;                                                           \
        acc += MV_SAMPLES[3 * k + 2] * colour;                                        \
    }                                                                                 \
    write_imagef(dst, (int2)(x, y), clamp(floor(acc + 0.5f), 0.0f, 255.0f) / 255.0f);

/* program_opencl: the input frame marbled. The canvas is fitted into the output
 * and the input stretched over the whole output, as the renderer's default
 * (recipe/frame.py geometry: the contract's mapping). */
__kernel void marble(__write_only image2d_t dst, unsigned int index, __read_only image2d_t src) {
    const int x = get_global_id(0), y = get_global_id(1);
    const int w = get_image_width(dst), h = get_image_height(dst);
    if (x >= w || y >= h)
        return;
    const float sw = get_image_width(src), sh = get_image_height(src);
    const float cw = MV_CANVAS_W > 0.0f ? MV_CANVAS_W : sw;
    const float ch = MV_CANVAS_H > 0.0f ? MV_CANVAS_H : sh;
    const float s = fmin(w / cw, h / ch), dx = (w - s * cw) * 0.5f, dy = (h - s * ch) * 0.5f;
    const float kx = sw / w, ky = sh / h;
    const float4 gc = (float4)(1.0f / s, 1.0f / s, -dx / s, -dy / s);
    const float4 gi = (float4)(s * kx, s * ky, dx * kx, dy * ky);
    MARBLE_PIXEL(x, y, index, gc, gi, sample_input(src, cx * gi.s0 + gi.s2, cy * gi.s1 + gi.s3, bg))
}

/* openclsrc: a blank sheet, the canvas fitted into the frame and centred (the
 * contract's mapping); a recipe without a canvas takes the frame's size. */
__kernel void marble_sheet(__write_only image2d_t dst, unsigned int index) {
    const int x = get_global_id(0), y = get_global_id(1);
    const int w = get_image_width(dst), h = get_image_height(dst);
    if (x >= w || y >= h)
        return;
    const float cw = MV_CANVAS_W > 0.0f ? MV_CANVAS_W : (float)w;
    const float ch = MV_CANVAS_H > 0.0f ? MV_CANVAS_H : (float)h;
    const float s = fmin(w / cw, h / ch), dx = (w - s * cw) * 0.5f, dy = (h - s * ch) * 0.5f;
    const float4 gc = (float4)(1.0f / s, 1.0f / s, -dx / s, -dy / s);
    MARBLE_PIXEL(x, y, index, gc, gc, bg)
}
