"""The live page's edits of the recipe file itself (``marblevideo live
--preview``), as the designer's HTTP API (:mod:`marblevideo.design`) names them:

- ``GET /api/recipe``: the recipe file as the session took it, as JSON; 409
  while the file on disk is broken: ``{"error": ..., "last_good": ...}``
  (:meth:`~marblevideo.recipefile.RecipeFile.answer`).
- ``PUT /api/recipe``: a recipe, validated and saved atomically; the session
  takes it at once, as any save (sliders reset). 400 with the one-line
  JSON-path error, nothing saved, when invalid.
- ``POST /api/save-sliders``: the sliders' values written into the recipe file
  (each into the op it belongs to), so what the sliders did is kept. The drops
  of a layout are not entries of the file, so their sliders are left out (named
  in the answer's ``skipped``).
"""

from __future__ import annotations

import json

from marblevideo.errors import MediaError, RecipeError


def file_indices(recipe) -> list[int | None]:
    """The index in the file's ``ops`` of each op of ``recipe`` (layouts expanded,
    hidden ops left out); None for the drops a layout stands for."""
    return [None if op.layout is not None else op.entry for op in recipe.ops]


def with_sliders(doc: dict, recipe, overrides: dict) -> tuple[dict, list[str]]:
    """``doc`` (the file's JSON) with the slider ``overrides`` ({(op, name): value})
    written in, and the sliders left out."""
    doc = json.loads(json.dumps(doc))
    indices = file_indices(recipe)
    skipped = []
    for (i, name), value in sorted(overrides.items()):
        n = indices[i]
        if n is None:
            skipped.append(f"ops[{i}].{name} (a drop of the layout ops[{recipe.ops[i].layout[1]}])")
        else:
            doc["ops"][n][name] = value
    return doc, skipped


def live_api(session, method: str, path: str, body: bytes | None):
    """Answer an API request of the live page: (status, body, content type)."""
    from marblevideo.controllers.api import controllers_api

    answer = controllers_api(session, method, path)  # meters and learn
    if answer is not None:
        return json_answer(answer[1], answer[0])
    try:
        if (method, path) == ("GET", "/api/recipe"):
            code, doc = session.file.answer()
            return json_answer(doc, code)
        if (method, path) == ("PUT", "/api/recipe"):
            return json_answer({"version": session.put(request_json(body))})
        if (method, path) == ("POST", "/api/save-sliders"):
            doc, recipe, _ = session.file.snapshot()  # the file's JSON and what it renders
            overrides = session.controls.snapshot()[0]
            doc, skipped = with_sliders(doc, recipe, overrides)
            return json_answer({"version": session.put(doc), "skipped": skipped})
    except (RecipeError, ValueError) as exc:
        return json_answer({"error": str(exc)}, 400)
    except (OSError, MediaError) as exc:
        return json_answer({"error": f"{session.recipe_path}: {exc}"}, 500)
    return json_answer({"error": f"{method} {path}: no such route"}, 404)


def request_json(body: bytes | None):
    """A request's JSON body; ValueError, in one line, when it is not JSON (a
    recursion too deep for the parser included)."""
    try:
        return json.loads(body or b"null")
    except (ValueError, RecursionError) as exc:
        raise ValueError(f"request body: invalid JSON: {exc}") from None


def json_answer(obj, code: int = 200):
    """``obj`` as a JSON answer: (status, body, content type)."""
    return code, json.dumps(obj).encode(), "application/json"
