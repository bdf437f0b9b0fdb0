"""The designer's HTTP API as one table (:data:`ROUTES`): each route's method,
path, summary, query parameters, body and answer. The session answers from it
(:meth:`~marblevideo.design.session.DesignSession.api`) and ``GET
/api/openapi.json`` is it as an OpenAPI 3.1 document (:func:`openapi`), so the
description and the dispatch cannot part. The two routes the HTTP server
answers itself for the designer (the page and its files:
:mod:`marblevideo.serve.server`) are rows without a ``call``.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass

from marblevideo.controllers.api import learn
from marblevideo.design.describe import describe_ops
from marblevideo.design.exports import EXPORTS, TEXT, export_file
from marblevideo.limits import MAX_SIDE
from marblevideo.version import __version__

JSON = "application/json"
RAW = "application/octet-stream"
VIEW = "x,y,w,h: the window of the canvas shown, in canvas units (default: the frame's)"

#: The query parameters, by name: (JSON schema, description).
QUERY: dict[str, tuple[dict, str]] = {
    "t": ({"type": "number"}, "time in seconds (default: the recipe's end)"),
    "w": ({"type": "number", "minimum": 1, "maximum": MAX_SIDE}, "width in pixels"),
    "h": ({"type": "number", "minimum": 1, "maximum": MAX_SIDE}, "height in pixels (with w)"),
    "view": ({"type": "string"}, VIEW),
    "draft": ({"type": "string", "enum": ["0", "1"]}, "1: no antialiasing"),
    "ops": ({"type": "string"}, "only these op indices, as 0,2,5 (solo: hidden ones too)"),
    "k": ({"type": "integer", "minimum": 0}, "the op under the gesture"),
    "shapes": ({"type": "string", "enum": ["0", "1"]}, "0: the regions and strokes left out"),
}
FRAME = ("t", "w", "h", "view", "draft", "ops")
#: The error answers' bodies: one line.
ERROR = {
    "type": "object",
    "required": ["error"],
    "properties": {"error": {"type": "string", "pattern": "^[^\\n]*$"}},
}
#: What each error status means (every route may answer 400 and 500; 403, 413 and
#: 415 are the server's for a write).
STATUS = {
    400: "a bad request or recipe: one line naming what is wrong",
    403: "a write from another origin",
    404: "no such route or file",
    405: "no such method on this route",
    409: "FILE is broken on disk: the error, the last good recipe and its version",
    413: "the request body is too large",
    415: "the body is not application/json",
    500: "the design cannot be made (one line)",
    503: "the designer is closing",
}


@dataclass(frozen=True)
class Route:
    """One route: ``call(session, query, body)`` answers it with JSON-able data,
    bytes (of ``answer``'s type) or a whole (status, body, content type); none: the
    HTTP server answers it itself."""

    method: str
    path: str
    summary: str
    call: Callable | None = None
    answer: str = JSON
    query: tuple[str, ...] = ()
    body: str | None = None  # the body's schema: "Recipe", or "any" JSON
    errors: tuple[int, ...] = (400,)


def _frame(kind: str) -> Callable:
    def call(session, q, body):
        doc = None if body is None else body or b"null"
        return session.frame_png(q, doc) if kind == "png" else session.frame_rgba(q, doc)

    return call


_RENDERED = "the OpenCL render of the saved recipe at t, w x h (only w: at most that wide)"
ROUTES: tuple[Route, ...] = (
    Route("GET", "/", "the designer's page", answer="text/html", errors=()),
    Route("GET", "/web/{name}", "one of the page's files (its ES modules, its style)",
          answer="text/javascript", errors=(404,)),
    Route("GET", "/api/openapi.json", "this document", lambda s, q, b: openapi(), errors=()),
    Route("GET", "/api/recipe", "the recipe as saved in FILE",
          lambda s, q, b: s.recipe_answer(), errors=(409,)),
    Route("PUT", "/api/recipe", "validate, save and show a recipe: /api/info with its version",
          lambda s, q, b: {"version": s.put(b), **s.info()}, body="Recipe",
          errors=(400, 403, 413, 415)),
    Route("GET", "/api/info", "what the page edits: mode, version, sizes, where the canvas sits",
          lambda s, q, b: s.info(), errors=()),
    Route("GET", "/api/ops", "every op and layout type, its parameters and tools",
          lambda s, q, b: describe_ops(), errors=()),
    Route("GET", "/api/frame.png", _RENDERED, _frame("png"), "image/png", FRAME),
    Route("POST", "/api/frame.png", "the same, of the recipe sent (not saved)", _frame("png"),
          "image/png", FRAME, "Recipe", (400, 403, 413, 415)),
    Route("GET", "/api/frame.rgba", "the frame as width, height (uint32 LE) and RGBA bytes",
          _frame("rgba"), RAW, FRAME),
    Route("POST", "/api/frame.rgba", "the same, of the recipe sent (not saved)", _frame("rgba"),
          RAW, FRAME, "Recipe", (400, 403, 413, 415)),
    Route("POST", "/api/layers", "for a gesture on op k: the picture below it, the map above",
          lambda s, q, b: s.layers(q, b or b"null"), RAW, ("k", "t", "w", "h", "view"),
          "Recipe", (400, 403, 413, 415)),
    Route("GET", "/api/design.svg", "a blank sheet's design at t as SVG",
          lambda s, q, b: s.svg(q), "image/svg+xml", ("t",)),
    *(Route("GET", f"/api/export{x}", f"the design as a {x} file for another host",
            lambda s, q, b, x=x: export_file(s, x), TEXT) for x in EXPORTS),
    Route("GET", "/api/signals", "the controllers' meters and the values the recipe reads",
          lambda s, q, b: s.signals(), errors=()),
    Route("POST", "/api/learn", "learn the next controller moved", lambda s, q, b:
          learn(s.controllers), body="any", errors=(403, 413, 415)),
    Route("GET", "/api/motion", "the recipe's motion fields and the newest frame's motion",
          lambda s, q, b: s.motion.state(q), query=("shapes",), errors=()),
)  # fmt: skip
#: (method, path) -> route, of the routes the session answers.
TABLE = {(r.method, r.path): r for r in ROUTES if r.call is not None}


def answer(session, method: str, path: str, q: dict, body: bytes | None):
    """(status, body, content type) of the route; LookupError for none (its 404 or 405)."""
    route = TABLE.get((method, path))
    if route is None:
        raise LookupError(405 if any(p == path for _, p in TABLE) else 404)
    data = route.call(session, q, body)
    if isinstance(data, tuple):
        return data
    if isinstance(data, bytes):
        return 200, data, route.answer
    return 200, json.dumps(data).encode(), JSON


def _components() -> dict:
    """The recipe's JSON Schema (``marblevideo schema``) as the document's schemas."""
    from marblevideo.recipe.schema import schema

    text = json.dumps(schema()).replace('"#/$defs/', '"#/components/schemas/')
    recipe = json.loads(text)
    defs = recipe.pop("$defs")
    for key in ("$schema", "$id"):
        recipe.pop(key, None)
    return {**defs, "Recipe": recipe, "Error": ERROR}


def _operation(route: Route) -> dict:
    params = [
        {"name": n, "in": "query", "required": False, "schema": QUERY[n][0],
         "description": QUERY[n][1]} for n in route.query
    ]  # fmt: skip
    if "{name}" in route.path:
        name = {"name": "name", "in": "path", "required": True, "schema": {"type": "string"}}
        params.append(name)
    error = {"content": {JSON: {"schema": {"$ref": "#/components/schemas/Error"}}}}
    responses = {"200": {"description": "the answer", "content": {route.answer: {}}}}
    responses |= {str(c): {"description": STATUS[c], **error} for c in sorted({*route.errors, 500})}
    op = {"summary": route.summary, "operationId": f"{route.method} {route.path}",
          "parameters": params, "responses": responses}  # fmt: skip
    if route.body is not None:
        body = {"$ref": "#/components/schemas/Recipe"} if route.body == "Recipe" else {}
        content = {JSON: {"schema": body}}
        op["requestBody"] = {"required": route.body == "Recipe", "content": content}
    return op


def openapi() -> dict:
    """The API as an OpenAPI 3.1 document (``GET /api/openapi.json``)."""
    paths: dict[str, dict] = {}
    for route in ROUTES:
        paths.setdefault(route.path, {})[route.method.lower()] = _operation(route)
    return {
        "openapi": "3.1.0",
        "info": {"title": "marblevideo design", "version": __version__,
                 "description": "The designer's HTTP API (marblevideo.design), 127.0.0.1 only"},
        "paths": paths,
        "components": {"schemas": _components()},
    }  # fmt: skip
