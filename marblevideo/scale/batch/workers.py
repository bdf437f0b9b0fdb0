"""A batch's workers (:mod:`marblevideo.scale.batch`): one item's render, and every
item of a batch on local worker processes or on Ray workers.

Items are :class:`marblevideo.scale.batch.Item` (``src``, ``dst`` paths); each
finished one is told to ``finished(item, error)``, ``error`` None when it was
written, else its one-line message.
"""

from __future__ import annotations

import concurrent.futures
import contextlib
import multiprocessing
import os
import signal
import time
from dataclasses import replace
from pathlib import Path

from marblevideo.errors import MarbleError, MediaError
from marblevideo.media.formats import output_kind
from marblevideo.scale.cluster import RayPool


def render_item(recipe, item, options: dict, overwrite: bool, renderer=None) -> str | None:
    """Render one item (on ``renderer`` where given); None when done, else its
    one-line error."""
    from marblevideo.api import render_still, render_video

    try:
        item.dst.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        return f"{item.dst.parent}: cannot make the folder: {exc.strerror or exc}"
    try:
        if output_kind(item.dst) == "still":
            render_still(
                item.src, recipe, item.dst, overwrite=overwrite, renderer=renderer, **options
            )
        else:
            render_video(
                item.src, recipe, item.dst, overwrite=overwrite, quiet=True, renderer=renderer,
                **options,
            )  # fmt: skip
    except MarbleError as exc:
        return str(exc)
    return None


def _init_worker(threads: int) -> None:
    os.environ.setdefault("POCL_MAX_PTHREAD_COUNT", str(threads))
    # Ctrl-C reaches the whole process group: the batch itself decides (on_processes)
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def on_processes(recipe: str, todo: list, options, overwrite, jobs: int, finished) -> None:
    """Every item of ``todo`` on ``jobs`` worker processes; ``finished(item, error)``
    as each ends. An interrupt here (Ctrl-C, SIGTERM; workers ignore Ctrl-C) stops
    the workers at once: what was queued is dropped, the temporary files of the
    renders cut short are removed, and outputs finished meanwhile are recorded."""
    threads = max(1, (os.cpu_count() or 1) // jobs)
    context = multiprocessing.get_context("spawn")  # OpenCL does not survive fork
    pool = concurrent.futures.ProcessPoolExecutor(
        jobs, mp_context=context, initializer=_init_worker, initargs=(threads,)
    )
    futures, recorded, started = {}, set(), time.time()
    try:
        for item in todo:
            futures[pool.submit(render_item, recipe, item, options, overwrite)] = item
        for future in concurrent.futures.as_completed(futures):
            try:
                error = future.result()
            except concurrent.futures.process.BrokenProcessPool:
                raise MediaError("a batch worker died; run again to resume") from None
            finished(futures[future], error)
            recorded.add(future)  # (after: an interrupt inside finished records it again)
    except BaseException:
        workers = list((pool._processes or {}).values())  # private: no public way
        for worker in workers:  # stopped at once
            with contextlib.suppress(OSError):
                worker.kill()
        # One shutdown, that waits: the pool's thread sees the workers dead, fails
        # what is left and joins them. (A shutdown(wait=False) first would let go
        # of that thread, and a later wait would return at once, while a killed
        # worker could still be renaming its output: written, never recorded.)
        pool.shutdown(wait=True, cancel_futures=True)
        for worker in workers:  # dead, before their outputs are looked at
            worker.join()
        for future, item in futures.items():
            if future in recorded:
                continue
            if _succeeded(future) or _written_since(item.dst, started):  # as it came
                finished(item, None)
            else:  # a render cut short leaves its temporary file (media.output)
                for tmp in item.dst.parent.glob(f".{item.dst.stem}.*.part{item.dst.suffix}"):
                    tmp.unlink(missing_ok=True)
        raise
    pool.shutdown()


def _written_since(path: Path, started: float) -> bool:
    """Whether ``path`` was put in place since ``started`` (a worker killed between
    its rename and its answer); a second's slack for file-system clocks."""
    try:
        return path.stat().st_mtime >= started - 1
    except OSError:
        return False


def _succeeded(future: concurrent.futures.Future) -> bool:
    return (
        future.done()
        and not future.cancelled()
        and future.exception() is None
        and (future.result() is None)
    )


def on_ray(recipe, todo: list, options: dict, overwrite: bool, jobs, finished) -> None:
    """Every item of ``todo`` on Ray workers; ``finished(item, error)`` as each ends."""
    if not todo:
        return
    pool = RayPool(jobs, options.get("device"))
    try:
        # the workers' folders are not this one: absolute paths
        calls = [
            (
                recipe,
                replace(item, src=item.src.resolve(), dst=item.dst.resolve()),
                options,
                overwrite,
            )
            for item in todo
        ]
        for index, error in pool.run(render_item, calls, [str(item.src) for item in todo]):
            finished(todo[index], None if error is None else str(error))
    finally:
        pool.close()
