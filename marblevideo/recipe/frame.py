"""Per-frame parameters: what the renderers consume.

A :class:`~marblevideo.recipe.Recipe` evaluated at a time ``t`` gives a
:class:`FrameSpec`: every keyframe track resolved to a plain value and every
op's ``start``/``end`` progress already applied (drop and spray radius scaled
by sqrt(p), tine/comb/circle/vortex alpha by p, wave amplitude by p). Both
renderers, the NumPy reference and the OpenCL kernel, read only this.

Conventions (see docs/recipe-format.md): canvas units, origin top-left,
x right, y down; angles in degrees; colors are (r, g, b) floats in 0..255.

:class:`Geometry` holds the two per-axis affine maps of a render:
output pixel coordinates -> canvas point, and canvas point -> input pixel
coordinates. Pixel (i, j) covers [i, i+1] x [j, j+1]; its centre is
(i + 0.5, j + 0.5), in output and input alike.
"""

from __future__ import annotations

from dataclasses import dataclass, field

Value = float | tuple[float, ...]

EDGE_MODES = ("clamp", "repeat", "mirror", "background")
#: How an input of another aspect than the output fills it (``--fit``): stretched
#: per axis (the contract's), scaled to cover it and cropped, or scaled to fit
#: inside it on the recipe's background. A blank sheet's canvas is by default
#: scaled to fit and centred (the contract's, as "pad"); "crop" scales it to
#: cover the output, "stretch" per axis.
FIT_MODES = ("stretch", "crop", "pad")


@dataclass(frozen=True)
class OpState:
    """One op at one instant: ``values`` maps each parameter name of the op's
    definition (:mod:`marblevideo.ops`) to a float (numbers) or a tuple (points,
    colors)."""

    type: str
    values: dict[str, Value] = field(hash=False)

    def __getitem__(self, name: str) -> Value:
        return self.values[name]


@dataclass(frozen=True)
class FrameSpec:
    """Everything needed to render one frame, independent of image sizes."""

    ops: tuple[OpState, ...]
    background: tuple[float, float, float]
    antialias: str
    edges: str
    canvas: tuple[float, float]


@dataclass(frozen=True)
class Geometry:
    """Per-axis affine maps of one render.

    canvas = (ox * to_canvas[0] + to_canvas[2], oy * to_canvas[1] + to_canvas[3])
    for an output point (ox, oy); input pixel coordinates are
    (cx * to_input[0] + to_input[2], cy * to_input[1] + to_input[3]).
    """

    out_w: int
    out_h: int
    to_canvas: tuple[float, float, float, float]
    to_input: tuple[float, float, float, float]


def stretch_note(input_size: tuple[int, int], out_size: tuple[int, int]) -> str | None:
    """The notice for an input stretched to an output of another aspect (over 1 %),
    or None."""
    (iw, ih), (w, h) = input_size, out_size
    if abs((w / h) / (iw / ih) - 1) <= 0.01:
        return None
    return f"{iw}x{ih} stretched to {w}x{h} (another aspect; --fit crop or pad keeps it)"


def canvas_note(canvas: tuple[float, float], out_size: tuple[int, int]) -> str | None:
    """The notice for a blank sheet's canvas shown in an output of another aspect
    (over 1 %) without ``--fit``, or None."""
    (cw, ch), (w, h) = canvas, out_size
    if abs((w / h) / (cw / ch) - 1) <= 0.01:
        return None
    return (
        f"canvas {cw:g}x{ch:g} fitted into {w}x{h} and centred (another aspect: what the "
        "ops carry past the canvas may be cut; --fit crop fills the frame, stretch distorts)"
    )


def fit(canvas: tuple[float, float], w: int, h: int) -> tuple[float, float, float]:
    """Scale and offsets that show ``canvas`` uniformly scaled and centred in w x h:
    output point o = s * c + (dx, dy)."""
    cw, ch = canvas
    s = min(w / cw, h / ch)
    return s, (w - s * cw) / 2.0, (h - s * ch) / 2.0


def geometry(
    canvas: tuple[float, float],
    out_size: tuple[int, int],
    input_size: tuple[int, int] | None = None,
    view: tuple[float, float, float, float] | None = None,
    fit_mode: str | None = None,
) -> Geometry:
    """Build the maps for an output of ``out_size`` = (w, h).

    Without ``view`` the canvas is fitted into the output frame (contract's
    geometry). With ``view`` = (x, y, w, h) in canvas units, that window is
    fitted instead (deep zoom); the input stays attached to the canvas as in
    the unzoomed frame. An input fills the (unzoomed) output frame, stretched
    per axis when its aspect differs (``fit_mode`` "stretch", the contract's).
    With "crop" or "pad" the frame of the input's own size, made as the
    contract says, is scaled uniformly to cover the output (cropped) or to fit
    inside it (centred; what lies outside the input is then the renderer's
    ``edges`` business, and the marbler uses the background). Without an input
    (``input_size`` None), "crop" scales the canvas uniformly to cover the
    output and "stretch" per axis to fill it, both centred; None or "pad" is
    the contract's mapping.
    """
    w, h = out_size
    if input_size is not None and fit_mode in ("crop", "pad"):
        iw, ih = input_size
        pick = max if fit_mode == "crop" else min
        k = pick(w / iw, h / ih)  # input frame -> output
        ex, ey = (w - k * iw) / 2.0, (h - k * ih) / 2.0
        s, dx, dy = fit(canvas, iw, ih)  # canvas -> input frame
        unzoomed = (1.0 / (k * s), 1.0 / (k * s), (-ex / k - dx) / s, (-ey / k - dy) / s)
        to_input = (s, s, dx, dy)
    elif input_size is None and fit_mode in ("crop", "stretch"):
        sx, sy = w / canvas[0], h / canvas[1]
        if fit_mode == "crop":
            sx = sy = max(sx, sy)
        dx, dy = (w - sx * canvas[0]) / 2.0, (h - sy * canvas[1]) / 2.0
        unzoomed = (1.0 / sx, 1.0 / sy, -dx / sx, -dy / sy)
        to_input = (sx, sy, dx, dy)
    else:
        s, dx, dy = fit(canvas, w, h)
        unzoomed = (1.0 / s, 1.0 / s, -dx / s, -dy / s)
        if input_size is None:
            to_input = (s, s, dx, dy)
        else:
            kx, ky = input_size[0] / w, input_size[1] / h
            to_input = (s * kx, s * ky, dx * kx, dy * ky)
    if view is None:
        to_canvas = unzoomed
    else:
        vx, vy, vw, vh = view
        vs, vdx, vdy = fit((vw, vh), w, h)
        to_canvas = (1.0 / vs, 1.0 / vs, vx - vdx / vs, vy - vdy / vs)
    return Geometry(w, h, to_canvas, to_input)
