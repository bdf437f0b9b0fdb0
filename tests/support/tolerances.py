"""The tests' tolerances, in one table: what each one bounds, and why it is not 0.

Levels are 8-bit code values (0..255); a share is of pixels (or plane samples).
"""

from marblevideo.opencl.selfcheck import LEVELS, SHARE

#: The device (float32 walk) against the NumPy reference (float64): a pixel agrees
#: within LEVELS in every channel, and at least SHARE of pixels agree (the rest sit
#: on ink edges a float32 walk can land on the other side of). `devices --check`
#: uses the same two numbers.
KERNEL_LEVELS, KERNEL_SHARE = LEVELS, SHARE
#: Planar I420 frames on the device against render_planes (the same float32
#: sampling): at most PLANAR_MAX levels apart, and no more than PLANAR_DIFFERING of
#: samples apart at all (reused maps' 1/32768-pixel weights).
PLANAR_MAX, PLANAR_DIFFERING = 1, 1e-3
#: A lossy encode (x264 crf <= 23) against the frames put in: mean absolute levels,
#: and where the frames were also resized or marbled by the RGBA route.
LOSSY_MEAN, LOSSY_MEAN_RESAMPLED = 4, 6
#: Our I420 <-> RGBA conversions against FFmpeg's swscale, which rounds with less
#: precision: largest and mean difference, and chroma on gradients.
SWSCALE_MAX, SWSCALE_MEAN, SWSCALE_CHROMA_MAX = 3, 1.5, 2
#: An SVG rasterized by cairosvg against the raster render (outlines within 0.5
#: px; cairo antialiases by area, the kernel by its subsamples): the share of
#: pixels within SVG_LEVELS.
SVG_LEVELS, SVG_SHARE = 32, 0.985
#: Zoom fidelity: an SVG at the default tolerance, rasterized at 2x and 4x its
#: size, against the 16-sample raster render at that size: the share of pixels
#: within ZOOM_LEVELS. Rasterized ZOOM_SUPERSAMPLE times finer (or more) and averaged, so
#: that stripes thinner than a pixel are averaged by area (a rasterizer that
#: composites shape by shape, cairo, blends them with the shape beneath).
ZOOM_LEVELS, ZOOM_SHARE, ZOOM_SUPERSAMPLE = 24, 0.99, 4
#: Forward then inverse maps in float64: the contract's inverses are exact.
ROUND_TRIP = 1e-9
