"""Recipe colours. The contract's forms are ``"#rrggbb"`` and ``[r, g, b]``
(0..255); marblevideo also reads ``"#rgb"`` and the CSS color names (the 147 of
:mod:`webcolors`' CSS3 list and CSS Color 4's ``rebeccapurple``), in any case.
Components are sRGB, 0..255 floats once read.
"""

from __future__ import annotations

import webcolors

#: CSS color name (lower case) -> "#rrggbb", by name.
CSS_NAMES: dict[str, str] = dict(
    sorted(
        {
            **{n: webcolors.name_to_hex(n, spec=webcolors.CSS3) for n in webcolors.names()},
            "rebeccapurple": "#663399",
        }.items()
    )
)
#: ``#rgb`` or ``#rrggbb``, hex digits in either case.
HEX_PATTERN = "^#([0-9a-fA-F]{3}){1,2}$"
#: Any CSS color name in any case (JSON Schema patterns have no flags, so each
#: letter is a class such as ``[rR]``).
NAME_PATTERN = "^(" + "|".join("".join(f"[{c}{c.upper()}]" for c in n) for n in CSS_NAMES) + ")$"
#: The shapes a colour may take, as messages name them.
SHAPES = '"#rrggbb", "#rgb", a CSS color name or [r, g, b]'


def color_components(value: str | list) -> tuple[float, float, float]:
    """A valid colour (a hex string, a CSS name or [r, g, b]) as (r, g, b) in 0..255."""
    if isinstance(value, str):
        rgb = webcolors.hex_to_rgb(CSS_NAMES.get(value.lower(), value))
        return float(rgb.red), float(rgb.green), float(rgb.blue)
    r, g, b = (float(c) for c in value)
    return r, g, b
