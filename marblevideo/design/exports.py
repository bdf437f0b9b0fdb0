"""The designer's Export links for other hosts (GET /api/export.SUFFIX, routes in
:mod:`marblevideo.design.routes`): the
design as ``marblevideo export`` writes it (:mod:`marblevideo.export`), a
generator where the designer draws on a blank sheet, else a filter of the input."""

from __future__ import annotations

from marblevideo.limits import DEFAULT_FPS

#: The files the page offers: ffmpeg's .cl, GStreamer's .frag and the .vert it
#: runs with, ISF's .fs.
EXPORTS = (".cl", ".frag", ".vert", ".fs")
TEXT = "text/plain; charset=utf-8"


def export_file(session, suffix: str) -> bytes:
    """The file of ``suffix`` (one of :data:`EXPORTS`) for the design of ``session``
    (a DesignSession) as it stands; raises UsageError (one line: the API's 400)
    for what the format cannot carry."""
    from marblevideo.export import FORMATS, export_source
    from marblevideo.export.shader import GSTREAMER_VERTEX

    if suffix == ".vert":
        return GSTREAMER_VERTEX.encode()
    _, recipe, _ = session.document.snapshot()
    sheet = session.backdrop.kind == "blank"
    return export_source(recipe, FORMATS[suffix], DEFAULT_FPS, sheet=sheet).encode()
