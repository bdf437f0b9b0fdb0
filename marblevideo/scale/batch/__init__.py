"""A batch: many inputs through one recipe, each to an output named from a
template, serially or on a local process pool.

- Inputs are glob patterns (``'in/*.jpg'``, recursive ``**`` included), in
  sorted order, duplicates dropped; a pattern that matches nothing is a usage
  error.
- Outputs are ``str.format`` templates over each input: ``{stem}`` (name
  without extension), ``{name}``, ``{suffix}`` (with its dot), ``{parent}``
  (the input's folder) and ``{index}`` (0-based, in input order; ``{index:04d}``).
  Two inputs that would write one output are a usage error. The folders an
  output names are made as its item is rendered (a file in their place is a
  usage error, before any work).
- Every item is a normal render (:func:`marblevideo.api.render_still` or
  :func:`~marblevideo.api.render_video`, by the output's kind): atomic, and an
  input is never an output.
- The manifest (JSON, default ``marblevideo-batch.json`` beside the first
  output) records each finished item with the digest of the recipe and
  options and the size and time of its input. A re-run skips those (even
  with ``-y``) while their output is still there: an interrupted or failed
  batch resumes where it stopped. Any other existing output is skipped unless
  ``-y``. Failures are recorded, the others go on, and the run exits 1 naming
  the first.
- With ``jobs`` > 1, items run in that many worker processes (spawned; one
  OpenCL context each), each with ``POCL_MAX_PTHREAD_COUNT`` set to its share
  of the CPUs so that PoCL workers do not oversubscribe them.
- With ``cluster="ray"``, each item is one call on a Ray cluster's workers
  (:class:`marblevideo.scale.cluster.RayPool`: ``$RAY_ADDRESS``'s, else a local one;
  ``jobs`` workers, default one per GPU or CPU), each worker keeping one
  OpenCL context for all its items; paths are sent, never pixels, so the
  cluster's machines must see the inputs and outputs at the same paths. A
  worker that dies is restarted and its item retried; an item that kills its
  worker every time is recorded as failed.
"""

from __future__ import annotations

import glob
import hashlib
import json
import os
import string
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from marblevideo.errors import UsageError
from marblevideo.media.formats import is_sequence, output_format, output_kind, output_kinds
from marblevideo.media.progress import Progress
from marblevideo.media.tiled import check_still_size
from marblevideo.scale.batch.workers import on_processes, on_ray, render_item
from marblevideo.scale.cluster import require_ray

MANIFEST_NAME = "marblevideo-batch.json"
TEMPLATE_FIELDS = ("stem", "name", "suffix", "parent", "index")


@dataclass(frozen=True)
class Item:
    """One input and the output it makes."""

    src: Path
    dst: Path


@dataclass
class BatchResult:
    """What a batch did: outputs written, skipped (done before, or existing
    without ``-y``), and failures (output -> one-line error)."""

    written: list[Path] = field(default_factory=list)
    done_before: list[Path] = field(default_factory=list)
    existing: list[Path] = field(default_factory=list)
    failed: dict[Path, str] = field(default_factory=dict)

    def summary(self) -> str:
        parts = [f"{len(self.written)} written"]
        if self.done_before:
            parts.append(f"{len(self.done_before)} done before")
        if self.existing:
            parts.append(f"{len(self.existing)} existing skipped (use -y to replace)")
        if self.failed:
            parts.append(f"{len(self.failed)} failed")
        return ", ".join(parts)


def expand_inputs(patterns: list[str]) -> list[Path]:
    """The files the glob ``patterns`` match, sorted, each once; UsageError for a
    pattern that matches no file."""
    found: dict[Path, None] = {}
    for pattern in patterns:
        matches = sorted(p for p in glob.glob(pattern, recursive=True) if os.path.isfile(p))
        if not matches:
            raise UsageError(f"{pattern}: matches no file")
        found.update(dict.fromkeys(Path(p) for p in matches))
    return list(found)


def check_template(template: str) -> None:
    """UsageError for a template with a field other than :data:`TEMPLATE_FIELDS`
    or with no field at all (every input would write one file)."""
    try:
        names = [f[1] for f in string.Formatter().parse(template) if f[1] is not None]
    except ValueError as exc:
        raise UsageError(f"-o {template}: {exc}") from None
    for name in names:
        if name.split(".")[0].split("[")[0] not in TEMPLATE_FIELDS:
            known = ", ".join("{" + f + "}" for f in TEMPLATE_FIELDS)
            raise UsageError(f"-o {template}: unknown field {{{name}}}; use {known}")
    if not names:
        raise UsageError(f"-o {template}: name each output from its input, e.g. out/{{stem}}.png")


def plan_items(inputs: list[Path], template: str) -> list[Item]:
    """Each input with its output; UsageError when two share an output or an
    output is an input."""
    check_template(template)
    items, owners = [], {}
    sources = {p.resolve() for p in inputs}
    for index, src in enumerate(inputs):
        fields = {
            "stem": src.stem,
            "name": src.name,
            "suffix": src.suffix,
            "parent": str(src.parent),
            "index": index,
        }
        try:
            dst = Path(template.format(**fields))
        except (ValueError, IndexError, KeyError) as exc:
            raise UsageError(f"-o {template}: {exc}") from None
        if dst.resolve() in owners:
            first = owners[dst.resolve()]
            raise UsageError(f"-o {template}: {first} and {src} would both write {dst}")
        if dst.resolve() in sources:
            raise UsageError(f"-o {template}: {dst} is one of the inputs")
        owners[dst.resolve()] = src
        items.append(Item(src, dst))
    return items


def check_folders(items: list[Item]) -> None:
    """UsageError for an output folder that cannot be one: a file stands at it or
    above it. Missing folders are made as their first item is rendered."""
    for folder in sorted({item.dst.parent for item in items}):
        for part in (folder, *folder.parents):
            if part.exists():
                if not part.is_dir():
                    raise UsageError(f"{folder}: cannot be an output folder; {part} is a file")
                break


def check_outputs(items: list[Item], size: tuple[int, int] | None) -> None:
    """UsageError for an output a batch cannot write: an unknown extension (the
    kinds listed), vectors, or a still of ``size`` too big for its format."""
    for item in items:
        kind, ext = output_kind(item.dst), item.dst.suffix.lower()
        if kind == "vector":
            raise UsageError(f"{item.dst}: a batch writes stills and videos, not {ext} vectors")
        if kind == "video" and output_format(item.dst) is None and not is_sequence(item.dst):
            raise UsageError(f"{item.dst}: unknown output extension {ext!r}; use {output_kinds()}")
        if kind == "still" and size is not None:
            check_still_size(item.dst, ext, size)


def job_digest(recipe_text: str, options: dict) -> str:
    """What makes an output: the recipe's text and the options, hashed."""
    blob = json.dumps({"recipe": recipe_text, "options": options}, sort_keys=True)
    return hashlib.sha256(blob.encode()).hexdigest()


def _source_stamp(src: Path) -> list[float]:
    stat = src.stat()
    return [stat.st_size, stat.st_mtime]


class Manifest:
    """The batch's record of finished and failed items (see the module)."""

    def __init__(self, path: Path, digest: str):
        self.path, self.digest = path, digest
        self.items: dict[str, dict] = {}
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except FileNotFoundError:
            return
        except (OSError, ValueError) as exc:
            raise UsageError(f"{path}: not a readable batch manifest ({exc})") from None
        if isinstance(data, dict) and isinstance(data.get("items"), dict):
            self.items = data["items"]

    def done(self, item: Item) -> bool:
        entry = self.items.get(str(item.dst))
        return (
            entry is not None
            and entry.get("status") == "done"
            and entry.get("digest") == self.digest
            and entry.get("source") == [str(item.src), *_source_stamp(item.src)]
            and item.dst.exists()
        )

    def record(self, item: Item, error: str | None) -> None:
        self.items[str(item.dst)] = {
            "status": "failed" if error else "done",
            "digest": self.digest,
            "source": [str(item.src), *_source_stamp(item.src)],
            **({"error": error} if error else {}),
        }
        self.save()

    def save(self) -> None:
        """Write atomically (a temporary file renamed), so a kill keeps the last one."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        tmp = self.path.with_name(f".{self.path.name}.part")
        tmp.write_text(json.dumps({"items": self.items}, indent=1, sort_keys=True))
        os.replace(tmp, self.path)


def run_batch(
    patterns: list[str],
    recipe: str | os.PathLike,
    template: str,
    *,
    overwrite: bool = False,
    jobs: int | None = None,
    cluster: str | None = None,
    manifest: str | os.PathLike | None = None,
    progress: str = "auto",
    notify: Callable[[str], None] | None = None,
    **options,
) -> BatchResult:
    """Render every input the glob ``patterns`` match through ``recipe`` (a file
    or preset) to outputs named by ``template`` (see the module). ``options``
    are :func:`~marblevideo.api.render_still`'s (``size``, ``fit``, ``time``,
    ``device``); ``time`` only where every output is a still. ``jobs``: local
    worker processes (default 1), or with ``cluster="ray"`` Ray workers (see the
    module). Raises UsageError before any work for bad patterns, templates,
    recipes or options; returns what was done (failures included: the caller
    decides the exit status)."""
    recipe, items = _planned(patterns, recipe, template, jobs, cluster, options)
    recipe_text = Path(recipe).read_text(encoding="utf-8")
    digest = job_digest(recipe_text, {k: repr(v) for k, v in options.items()})
    book = Manifest(Path(manifest) if manifest else items[0].dst.parent / MANIFEST_NAME, digest)
    result = BatchResult()
    todo = []
    for item in items:
        if book.done(item):
            result.done_before.append(item.dst)
        elif item.dst.exists() and not overwrite:
            result.existing.append(item.dst)
        else:
            todo.append(item)
    if notify and (result.done_before or result.existing):
        skipped = result.summary().split(", ", 1)[1]  # without "0 written"
        notify(f"{len(todo)} of {len(items)} to render; {skipped}")
    with Progress(len(todo), progress, unit="item") as bar:

        def finished(item: Item, error: str | None) -> None:
            book.record(item, error)
            if error:
                result.failed[item.dst] = error
            else:
                result.written.append(item.dst)
            bar.update()

        _render_all(recipe, todo, options, overwrite, (cluster, jobs), finished)
    return result


def _planned(patterns, recipe, template: str, jobs, cluster, options: dict):
    """(the recipe's file, the batch's items): every check made before any work
    (exit 2): the options, the recipe, the inputs and outputs."""
    from marblevideo.bundled import recipe_file
    from marblevideo.recipe import load_recipe
    from marblevideo.signals.follow import check as check_signals

    if jobs is not None and jobs < 1:
        raise UsageError(f"--jobs: expected a count >= 1, got {jobs}")
    if cluster not in (None, "ray"):
        raise UsageError(f"--cluster: expected ray, got {cluster!r}")
    if cluster == "ray":
        require_ray()
    recipe = recipe_file(recipe)
    loaded = load_recipe(recipe)  # a bad recipe stops the batch before any work
    items = plan_items(expand_inputs(patterns), template)
    for item in items:  # so does a signal with nothing to follow
        check_signals(loaded, item.src)
    if "time" in options and any(output_kind(item.dst) != "still" for item in items):
        raise UsageError("--time: applies to still outputs; this batch writes videos")
    check_folders(items)
    check_outputs(items, options.get("size"))
    return recipe, items


def _render_all(recipe, todo: list[Item], options, overwrite, where: tuple, finished) -> None:
    """Every item of ``todo``: on Ray, on worker processes or here, by ``where``
    = (cluster, jobs); ``finished(item, error)`` as each ends."""
    from marblevideo.recipe import load_recipe

    cluster, jobs = where
    if cluster == "ray":
        on_ray(load_recipe(recipe), todo, options, overwrite, jobs, finished)
    elif (jobs or 1) == 1 or len(todo) <= 1:
        for item in todo:
            finished(item, render_item(recipe, item, options, overwrite))
    else:
        on_processes(str(recipe), todo, options, overwrite, jobs, finished)
