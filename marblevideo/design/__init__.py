"""``marblevideo design``: draw a recipe by hand in the browser, over a blank
sheet, a photo, a video frame or a live source.

The page (``web/index.html`` and its ES modules, ``GET /web/NAME``) is served
by the HTTP server of both modes (:class:`marblevideo.serve.server.Server`) on
127.0.0.1 only, and does
everything through this HTTP API, which scripts and tests may use too (described
as OpenAPI 3.1 at ``GET /api/openapi.json``, from the one table the session
answers from: :mod:`marblevideo.design.routes`):

- ``GET /api/recipe``: the recipe as saved in FILE (JSON). While FILE on disk
  is broken (another program saved an invalid recipe), ``409 {"error": "FILE:
  ops[0].radius: ... (keeping the previous recipe)", "last_good": {...},
  "version": N}``: the error with its JSON path and the recipe still shown.
- ``PUT /api/recipe`` (``Content-Type: application/json``, body: a recipe):
  validated, saved atomically to FILE and shown; answers ``{"version": N,
  ...}`` as ``/api/info``. An invalid recipe is ``400 {"error": "FILE:
  ops[1].lambda: must be > 0, got -2"}`` (the recipe format's one-line
  JSON-path message) and nothing is saved.
- ``GET /api/frame.png?t=T&w=W&draft=1&ops=0,2``: the OpenCL render of the
  saved recipe at ``t`` seconds (default: the recipe's end), at most ``W``
  pixels wide (default: the frame's size), without antialiasing with
  ``draft=1``, of only the listed ops with ``ops`` (solo: they are drawn even
  when hidden; an op with ``"hidden": true`` in FILE is otherwise left out).
- ``POST /api/frame.png?...`` (body: a recipe): the same, of a recipe that is
  not saved. The page renders its own copy of the recipe this way (as
  ``frame.rgba``), its drafts while a hand is moving too, so what it shows
  never races a save or a reload.
- ``GET /api/frame.rgba?...``, ``POST /api/frame.rgba?...``: the same frames
  as raw pixels, which the page draws with nothing to encode or decode: the
  width and height as two little-endian uint32, then width x height x 4 bytes
  of RGBA, rows top to bottom.
- ``GET /api/design.svg?t=T``: a blank sheet's design as SVG.
- ``GET /api/info``: the page's ``mode`` (``design``; ``live`` for ``marblevideo
  live --preview``), the recipe's ``version`` (counts changes, from the page or
  from FILE on disk), ``error`` (FILE changed on disk into an invalid recipe:
  the previous one stays), ``file``, ``input`` (``kind``: blank, image, video
  or live; ``name``; ``duration`` in seconds), the frame's ``size`` [w, h] in
  pixels, the ``canvas`` [W, H] and where it sits in the frame (``scale`` s and
  ``offset`` [dx, dy]: pixel = s * canvas point + offset, the recipe format's
  geometry), the recipe's ``end`` time and number of ``ops``.
- ``GET /api/motion``: the ``fields`` of the recipe's ``motion`` block as the
  page edits them, and over a live source or a video the motion of the newest
  frame seen (``active``, ``t``, ``frames``, ``level``, ``regions``,
  ``strokes``; with ``?shapes=0`` the two lists empty), whose strokes the
  renders carry (:mod:`marblevideo.design.motion`; live mode:
  :mod:`marblevideo.design.live`). Over a blank sheet or a still nothing is
  tracked: the renders have no motion strokes.
- ``GET /api/ops``: every op and layout type with its parameters (name, kind,
  help, whether optional and keyable, slider ranges as data) and the tools that
  draw it (:mod:`marblevideo.design.describe`).

``marblevideo live --preview`` serves the same page in "live" mode
(:mod:`marblevideo.design.live`): ``/api/info`` says ``"mode": "live"``, the
sheet shows the live frames, and edits go to the live recipe file.

Errors are JSON ``{"error": "..."}`` with status 400 (a bad request or recipe, a
frame of more than :data:`~marblevideo.limits.MAX_FRAME_PIXELS`, a blank sheet's
recipe without a canvas,
a body nested deeper than :data:`~marblevideo.limits.MAX_DEPTH` levels), 403 (a
write from another origin: :mod:`marblevideo.serve.server`), 404/405 (no such
route), 409 (FILE is broken on disk) or 500. Hot reload: FILE is polled; when another
program saves it, ``version`` moves on and the page follows.
"""
