"""The designer's page over ``marblevideo live --preview``: the same page, in
"live" mode (``GET /api/info`` says ``"mode": "live"``).

:class:`LiveDesign` stands in front of a running
:class:`~marblevideo.live.session.LiveSession` and answers the designer's API
(:mod:`marblevideo.design`) from it, so the op list, the parameter editors
(keys at the clock's time, points as handles, colours) and the drawing tools
edit the live recipe file:

- ``GET /api/info``: as the designer's, with ``"mode": "live"``, the input
  ``kind`` ``live`` and the frame's ``size`` the source's.
- ``GET /api/ops``: every op and layout type with its parameters.
- ``GET /api/recipe``: the live recipe file as the session took it; 409 while
  the file on disk is broken: ``{"error": ..., "last_good": ...}``
  (:meth:`~marblevideo.serve.recipefile.RecipeFile.answer`).
- ``PUT /api/recipe``: validated, saved atomically, taken from the next frame;
  400 with the one-line JSON-path error and nothing saved when invalid. It
  answers ``/api/info`` with the new ``version``.
- ``PUT /api/preview``: ``{"recipe": ..., "version": V, "sent": MS}``, an unsaved recipe
  the live frames show instead of the saved one while the file is at version V
  (the stroke being drawn; ``recipe`` null clears it), for a few seconds after
  each send (:mod:`marblevideo.live.preview`); 400 when invalid. It answers
  the file's ``version`` and the preview's ``serial``: the live frames that
  show it come with ``X-Preview-Serial: serial`` (``/frame.jpg``; and
  ``X-Frame-Time``, the clock time each frame was marbled at). ``sent``
  (optional): when the page sent it (its clock, ms); a send that comes after a
  newer one was taken is not shown, ``serial`` 0 (a page may have two on their way).
- ``GET /api/signals``, ``POST /api/learn``: the controllers' meters and learn
  (:mod:`marblevideo.controllers.api`).
- ``GET /api/motion``: the recipe's motion as of the last frame: ``active``,
  ``level`` (0..1), the ``regions`` followed and the motion ``strokes`` rendered
  (:meth:`marblevideo.live.stirring.LiveMotion.state`; canvas units; with
  ``?shapes=0`` the two lists are left empty), and the
  ``fields`` of a ``motion`` block the page edits
  (:func:`marblevideo.design.describe.describe_motion`).

The page draws the newest marbled frame (``GET /frame.jpg?after=SEQ``) and
polls ``/stats`` (fps, latency, the clock); ``POST /control`` pauses, seeks
(``time``) and loops the animation clock. There are no renders of unsaved
recipes (``/api/frame.*``): the frame shown is the live one.
"""

from __future__ import annotations

from marblevideo.controllers.api import controllers_api
from marblevideo.design.describe import describe_motion, describe_ops
from marblevideo.design.session import WEB, page_info
from marblevideo.errors import MediaError, RecipeError
from marblevideo.serve.server import json_answer, request_json


class LiveDesign:
    """The designer's page and API over the live session ``live``; everything
    else (the stream, ``/stats``, ``/control``) is the live session's."""

    def __init__(self, live):
        self.live = live

    def info(self) -> dict:
        live = self.live
        _, recipe, version = live.file.snapshot()
        source = {"kind": "live", "name": live.source.name, "duration": None}
        size = live.source.size
        return page_info("live", live.recipe_path, version, live.file.error, source, size, recipe)

    web = WEB  # the page's static files (GET /web/NAME)

    def page(self) -> bytes:
        """The designer's page (it reads the mode from ``/api/info``)."""
        return (WEB / "index.html").read_bytes()

    def api(self, method: str, path: str, query: str, body: bytes | None):
        """Answer an API request: (status, body, content type)."""
        if (method, path) == ("GET", "/api/info"):
            return json_answer(self.info())
        if (method, path) == ("GET", "/api/ops"):
            return json_answer(describe_ops())
        if (method, path) == ("GET", "/api/motion"):
            state = self.live.motion.state(shapes="shapes=0" not in query.split("&"))
            return json_answer({**state, "fields": describe_motion()})
        answer = controllers_api(self.live, method, path)  # meters and learn
        if answer is not None:
            return json_answer(answer[1], answer[0])
        try:
            if (method, path) == ("GET", "/api/recipe"):
                code, doc = self.live.file.answer()
                return json_answer(doc, code)
            if (method, path) == ("PUT", "/api/recipe"):
                version = self.live.put(request_json(body))
                return json_answer({**self.info(), "version": version})
            if (method, path) == ("PUT", "/api/preview"):
                return json_answer(self._preview(request_json(body)))
        except (RecipeError, ValueError) as exc:
            return json_answer({"error": str(exc)}, 400)
        except (OSError, MediaError) as exc:
            return json_answer({"error": f"{self.live.recipe_path}: {exc}"}, 500)
        return json_answer({"error": f"{method} {path}: no such route"}, 404)

    def _preview(self, request) -> dict:
        keys = set(request) if isinstance(request, dict) else set()
        if not {"recipe", "version"} <= keys <= {"recipe", "version", "sent"}:
            raise ValueError('preview: expected {"recipe": ..., "version": V[, "sent": MS]}')
        serial = self.live.show_preview(request["recipe"], request["version"], request.get("sent"))
        return {"version": self.live.file.snapshot()[2], "serial": serial}

    # the live session's own routes
    def stats(self) -> dict:
        return self.live.stats()

    def control(self, request) -> dict:
        return self.live.control(request)

    def latest_jpeg(self, after: int, timeout: float = 1.0):
        return self.live.latest_jpeg(after, timeout)
