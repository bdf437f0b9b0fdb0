"""The designer's state behind its HTTP API: the recipe file, the backdrop, one
renderer, and the answers to the page's requests (see :mod:`marblevideo.design`).

Renders are exact OpenCL renders of the recipe (``marblevideo`` makes the same
picture); a *draft* is the same render without antialiasing, which the page
asks for while a hand is moving. One render runs at a time.
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import math
import struct
import threading
import time
from importlib import resources
from pathlib import Path
from urllib.parse import parse_qs

from marblevideo.controllers.api import signals_state
from marblevideo.controllers.values import ControllerSignals, SessionSignals
from marblevideo.design.layers import above_map, layers_answer, parse_view
from marblevideo.design.motion import DesignMotion
from marblevideo.errors import MarbleError, RecipeError, UsageError
from marblevideo.limits import MAX_FRAME_PIXELS, MAX_SIDE
from marblevideo.marbler import Marbler, blank_size, image_size
from marblevideo.recipe import Recipe, parse_recipe
from marblevideo.recipe.frame import fit
from marblevideo.serve.server import json_answer, request_json

RELOAD_POLL = 0.25
#: The page: ``index.html`` and its ES modules, served as ``/web/NAME``.
WEB = resources.files("marblevideo.design") / "web"


def page_info(mode: str, file, version: int, error, source: dict, size, recipe: Recipe) -> dict:
    """``/api/info``, the page's one description of what it edits, for the designer
    and for live mode: the frame's ``size``, how the canvas sits in it (output o =
    ``scale`` * c + ``offset``; a recipe without canvas takes the frame's), the
    animation's ``end`` (healing included), the file's number of ``ops``, its name as
    given (``file``) and its full ``path`` (the page keeps undo and redo under it)."""
    w, h = size
    canvas = recipe.canvas or (w, h)
    s, dx, dy = fit(canvas, w, h)
    return {
        "mode": mode,
        "version": version,
        "error": error,
        "file": str(file),
        "path": str(Path(file).resolve()),  # where undo and redo are kept, across reloads
        "input": source,
        "size": [w, h],
        "canvas": list(canvas),
        "scale": s,
        "offset": [dx, dy],
        "end": recipe.settled_time(),
        "ops": recipe.entries,
    }


class Answer(Exception):
    """An API error: HTTP status ``code`` and a one-line ``message``."""

    def __init__(self, code: int, message: str):
        super().__init__(message)
        self.code = code


def _number(query: dict, name: str, default: float | None) -> float | None:
    if name not in query:
        return default
    try:
        value = float(query[name][-1])
    except ValueError:
        raise Answer(400, f"{name}: expected a number, got {query[name][-1]!r}") from None
    if not math.isfinite(value):
        raise Answer(400, f"{name}: expected a finite number")
    return value


def _only(query: dict, count: int) -> tuple[int, ...] | None:
    """``ops=0,2,5``: the op indices to render (solo; hidden ones too), or None: all."""
    if "ops" not in query:
        return None
    text = query["ops"][-1].strip()
    try:
        only = tuple(int(i) for i in text.split(",")) if text else ()
    except ValueError:
        raise Answer(400, f"ops: expected op indices as 0,2,5, got {text!r}") from None
    if any(not 0 <= i < count for i in only):
        raise Answer(400, f"ops: an index is outside 0..{count - 1}")
    return only


def _view(query: dict) -> tuple[float, float, float, float] | None:
    """``view=x,y,w,h``: the window of the canvas shown (canvas units), or None."""
    if "view" not in query:
        return None
    try:
        return parse_view(query["view"][-1])
    except ValueError as exc:
        raise Answer(400, str(exc)) from None


def _size(query: dict, frame: tuple[int, int]) -> tuple[int, int]:
    """The render's size: ``w`` and ``h`` both given (1..MAX_SIDE), else the
    frame's, ``w`` wide at most when only ``w`` is given (the aspect kept); at most
    MAX_FRAME_PIXELS in all (a frame the size of a huge canvas must be asked smaller)."""
    w, h = frame
    width, height = _number(query, "w", None), _number(query, "h", None)
    if width is not None and height is not None:
        if not (1 <= width <= MAX_SIDE and 1 <= height <= MAX_SIDE):
            raise Answer(400, f"w, h: expected 1..{MAX_SIDE} pixels each")
        w, h = round(width), round(height)
    elif width is not None and 8 <= width < w:
        w, h = round(width), max(1, round(h * width / w))
    if w * h > MAX_FRAME_PIXELS:
        raise Answer(400, f"a frame of {w} x {h} pixels: more than {MAX_FRAME_PIXELS:,} (ask w, h)")
    return w, h


class DesignSession:
    """The recipe file (:class:`~marblevideo.serve.recipefile.RecipeFile`) drawn over
    a backdrop (:mod:`marblevideo.design.backdrop`) by one OpenCL renderer."""

    def __init__(self, document, backdrop, *, device: str | None = None, renderer=None):
        from marblevideo.opencl.renderer import Renderer

        self.document = document
        self.backdrop = backdrop
        self.renderer = renderer or Renderer(device, loop_walk=True)  # no build per edit
        self._render_lock = threading.Lock()
        self._parsed: dict[tuple, Recipe] = {}
        self.stop_event = threading.Event()
        self._watcher: threading.Thread | None = None
        self.last_render_ms: float | None = None
        self.controllers = ControllerSignals()  # OSC and MIDI over a live source (--osc, --midi)
        self.motion = DesignMotion(backdrop, lambda: document.snapshot()[1])  # live, video

    # -- what is shown ----------------------------------------------------------
    def out_size(self, recipe: Recipe) -> tuple[int, int]:
        """The frame's size in pixels: the input's, else the canvas's."""
        return self.backdrop.size or blank_size(recipe)

    def info(self) -> dict:
        """What the page needs besides the recipe: version, error, the frame's size
        and how the canvas sits in it (output o = scale * c + offset)."""
        _, recipe, version = self.document.snapshot()
        b = self.backdrop
        source = {"kind": b.kind, "name": b.name, "duration": b.duration}
        size = self.out_size(recipe)
        return page_info(
            "design", self.document.path, version, self.document.error, source, size, recipe
        )

    def _recipe(self, doc: dict, version: int | bytes, only) -> Recipe:
        """``doc`` (of ``version``: a number, or a POSTed body) with only the ops
        ``only``, validated; the last one is kept for the next frame."""
        key = (version, only)
        if key in self._parsed:
            return self._parsed[key]
        if only is not None:  # solo: the listed ops, hidden or not
            ops = [{k: v for k, v in doc["ops"][i].items() if k != "hidden"} for i in only]
            doc = {**doc, "ops": ops}
        try:
            recipe = parse_recipe(doc, str(self.document.path))
        except RecipeError as exc:
            raise Answer(400, str(exc)) from None
        self._parsed = {key: recipe}
        return recipe

    @contextlib.contextmanager
    def _rendering(self):
        """One render at a time, and none once closing."""
        with self._render_lock:
            if self.stop_event.is_set():
                raise Answer(503, "the designer is closing")
            yield

    def _doc(self, body: bytes | None) -> tuple[dict, int | bytes]:
        """(recipe document, version): the POSTed one, else the saved one."""
        if body is None:
            doc, _, version = self.document.snapshot()
        else:
            doc, version = _json(body), body
        if not isinstance(doc, dict) or not isinstance(doc.get("ops"), list):
            raise Answer(400, f"{self.document.path}: expected a recipe object with ops")
        return doc, version

    def render(self, query: dict, body: bytes | None = None):
        """The frame at ``t`` (RGBA) of ``w`` x ``h`` pixels (only ``w``: that
        wide at most), of the canvas window ``view`` (x,y,w,h in canvas units;
        default: the frame's), a draft (no antialiasing) when ``draft`` is 1; of
        the recipe ``body`` (JSON, not saved) when given, else of the saved one."""
        doc, version = self._doc(body)
        only = _only(query, len(doc["ops"]))
        recipe = self._recipe(doc, version, only)
        t = _number(query, "t", None)
        if t is None:
            t = recipe.end_time()
        if only is None:  # the motion strokes over a live source or a video (solo: none)
            recipe = self.motion.over(recipe, t)
        if query.get("draft", ["0"])[-1] == "1":
            recipe = dataclasses.replace(recipe, antialias="none")
        size, view = _size(query, self.out_size(recipe)), _view(query)
        with self._rendering():
            start = time.perf_counter()
            image = self.backdrop.frame(t)
            recipe = recipe.bind(SessionSignals(self.controllers))
            out = Marbler(recipe, renderer=self.renderer).render(image, t, size, view)
            self.last_render_ms = (time.perf_counter() - start) * 1000
        return out

    def layers(self, query: dict, body: bytes | None) -> bytes:
        """``POST /api/layers?k=K``: for a gesture on op K of the recipe ``body``,
        the exact picture of its ops below K and the map of the ops above K
        (:mod:`marblevideo.design.layers`), at ``t``, ``w`` x ``h``, ``view``."""
        doc, _ = self._doc(body)
        ops = doc["ops"]
        k = _number(query, "k", None)
        if k is None or k != int(k) or not 0 <= k <= len(ops):
            raise Answer(400, f"k: expected an op index 0..{len(ops)}")
        k = int(k)
        below, above = (self._part(doc, part) for part in (ops[:k], ops[k + 1 :]))
        t = _number(query, "t", None)
        above = self.motion.over(above, below.end_time() if t is None else t)  # on top
        size, view = _size(query, self.out_size(below)), _view(query)
        signals = SessionSignals(self.controllers)
        with self._rendering():
            image = self.backdrop.frame(below.end_time() if t is None else t)
            marbler = Marbler(below.bind(signals), renderer=self.renderer)
            base = marbler.render(image, t, size, view)
            amap = None
            if above.ops:
                top = Marbler(above.bind(signals), renderer=self.renderer)
                amap = above_map(self.renderer, *top.frame_at(image_size(image), t, size, view))
        return layers_answer(base, k, amap)

    def _part(self, doc: dict, ops: list) -> Recipe:
        try:
            return parse_recipe({**doc, "ops": ops}, str(self.document.path))
        except RecipeError as exc:
            raise Answer(400, str(exc)) from None

    def frame_png(self, query: dict, body: bytes | None = None) -> bytes:
        import cv2

        rgba = self.render(query, body)
        ok, data = cv2.imencode(
            ".png", cv2.cvtColor(rgba, cv2.COLOR_RGBA2BGR), [cv2.IMWRITE_PNG_COMPRESSION, 1]
        )
        if not ok:
            raise Answer(500, "cannot encode the frame as PNG")
        return data.tobytes()

    def frame_rgba(self, query: dict, body: bytes | None = None) -> bytes:
        """The frame as the page draws it, with nothing to encode or decode: its
        width and height (two little-endian uint32), then its RGBA bytes."""
        rgba = self.render(query, body)
        return struct.pack("<II", rgba.shape[1], rgba.shape[0]) + rgba.tobytes()

    def svg(self, query: dict) -> bytes:
        """The design at ``t`` as SVG (a blank sheet's: an input is not vector)."""
        from marblevideo.outputs.svg import design_svg

        if self.backdrop.kind != "blank":
            raise Answer(400, "SVG export is of a blank sheet's design; this one has an input")
        _, recipe, _ = self.document.snapshot()
        t = _number(query, "t", recipe.end_time())
        with self._rendering():
            text, _ = design_svg(recipe.at(t), self.out_size(recipe))
        return text.encode()

    # -- the HTTP API -------------------------------------------------------------
    web = WEB  # the page's static files (GET /web/NAME)

    def page(self) -> bytes:
        """The designer's page."""
        return (WEB / "index.html").read_bytes()

    def api(self, method: str, path: str, query: str, body: bytes | None):
        """Answer an API request: (status, body, content type)."""
        q = parse_qs(query, keep_blank_values=True)
        try:
            return self._answer(method, path, q, body)
        except Answer as exc:
            return json_answer({"error": str(exc)}, exc.code)
        except UsageError as exc:
            return json_answer({"error": str(exc)}, 400)
        except MarbleError as exc:
            return json_answer({"error": str(exc)}, 500)
        except Exception as exc:  # noqa: BLE001 - the designer keeps serving; one line
            return json_answer({"error": f"{path}: {type(exc).__name__}: {exc}"}, 500)

    def _answer(self, method: str, path: str, q: dict, body: bytes | None):
        from marblevideo.design.routes import answer

        try:
            return answer(self, method, path, q, body)
        except LookupError as exc:
            raise Answer(exc.args[0], f"{method} {path}: no such route") from None

    def recipe_answer(self) -> tuple[int, bytes, str]:
        """``GET /api/recipe``: the recipe as saved; 409 while FILE is broken on disk."""
        code, doc = self.document.answer()
        return code, json.dumps(doc, indent=1).encode(), "application/json"

    def signals(self) -> dict:
        """``GET /api/signals`` (:mod:`marblevideo.controllers.api`)."""
        return signals_state(self.controllers, self.document.snapshot()[1])

    def put(self, body: bytes | None) -> int:
        """Validate, save and show a new recipe: its version (400 when invalid). The
        page asks for the frame of the same bytes next: they are known valid."""
        version = self.document.put(_json(body))
        self._parsed = {(body, None): self.document.snapshot()[1]}
        return version

    # -- hot reload -----------------------------------------------------------------
    def start(self) -> None:
        """Watch FILE for changes made by other programs (controllers' time starts)."""
        self.controllers.start()
        threading.Thread(target=self._prebuild, name="marblevideo-build").start()
        self._watcher = threading.Thread(target=self._watch, name="marblevideo-watch", daemon=True)
        self._watcher.start()

    def _prebuild(self) -> None:
        """Build the programs the page asks for first, in the order it does: the
        quick frame's (no antialiasing), the exact one's, the layers' map's. Not a
        daemon: the OpenCL compiler must not be killed mid-build."""
        from marblevideo.opencl.program import Structure

        _, recipe, _ = self.document.snapshot()
        has_input = self.backdrop.kind != "blank"
        exact = Structure.of(recipe, has_input)
        for structure in (dataclasses.replace(exact, antialias="none"), exact,
                          dataclasses.replace(exact, has_input=True)):  # fmt: skip
            if self.stop_event.is_set():
                return
            with contextlib.suppress(Exception):  # reported by the render that needs it
                self.renderer.programs.get(structure)

    def _watch(self) -> None:
        while not self.stop_event.wait(RELOAD_POLL):
            self.document.check_reload()

    def close(self) -> None:
        """Stop watching FILE and rendering: a render under way is waited for (the
        process must not exit while OpenCL runs in a request's thread). The
        backdrop is its opener's to close."""
        with self._render_lock:
            self.stop_event.set()
        self.motion.close()
        if self._watcher is not None:
            self._watcher.join(5.0)


def _json(body: bytes | None):
    """A request's JSON body, or the 400 answer naming what is wrong with it."""
    try:
        return request_json(body)
    except ValueError as exc:
        raise Answer(400, str(exc)) from None
