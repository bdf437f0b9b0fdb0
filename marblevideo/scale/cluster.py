"""Where a job's independent calls run: in this process (:class:`SerialPool`) or
on a Ray cluster (:class:`RayPool`), through one interface.

A call is ``fn(*args, renderer=renderer)``: ``fn`` a module-level function
(sent by reference), its arguments and result small (paths, options,
counts; never frames). Each worker holds one :class:`Worker`: one OpenCL
renderer (context and compiled programs) for all its calls, which starts
each call as a new renderer would (:meth:`Renderer.forget_frames`).
:meth:`run` yields ``(index, result)`` as calls finish, the result an
exception where the call failed (the caller decides what that means).

Ray is an optional extra (``pip install 'marblevideo[ray]'``), imported only
when a :class:`RayPool` is made. ``RAY_ADDRESS`` names a cluster to join;
without it a local Ray starts on this machine (bound to 127.0.0.1, no
dashboard, quiet) and stops with the pool. On CPUs each worker takes its
share of the cluster's CPUs (``num_cpus``) and PoCL as many threads
(``POCL_MAX_PTHREAD_COUNT``); on a cluster with GPUs each worker takes one
(``num_gpus=1``: Ray makes only that one visible to it). There are never
more workers than CPUs (GPUs), nor a worker bigger than a machine; workers
not started :data:`STARTUP` seconds after the first are let go, and a worker
that runs another version of marblevideo stops the job. A worker that dies
is restarted and its call retried (:data:`RETRIES` times); a call that kills
its worker every time fails with :class:`WorkerLost`, and a fresh worker
takes the next calls.
"""

from __future__ import annotations

import logging
import os
from collections.abc import Callable, Iterator
from pathlib import Path

from marblevideo.errors import MarbleError, MediaError, UsageError

RETRIES = 2
STARTUP = 60.0  # seconds the workers after the first have to start
CRASH_ENV = "MARBLEVIDEO_CRASH"  # fault injection for tests: a call's tag
CRASH_MARKER_ENV = "MARBLEVIDEO_CRASH_MARKER"  # crash once: while this file is missing
PACKAGE_ROOT = Path(__file__).resolve().parents[2]


class WorkerLost(MediaError):
    """A call whose worker died on every try."""


def crash_point(tag: str) -> None:
    """Fault injection for the tests, in Ray workers only: the process dies (a
    real crash, ``os._exit``) in the call tagged ``$MARBLEVIDEO_CRASH``; with
    ``$MARBLEVIDEO_CRASH_MARKER``, only while that file does not exist (the
    crash creates it: the call dies once)."""
    if os.environ.get(CRASH_ENV) != tag:
        return
    marker = os.environ.get(CRASH_MARKER_ENV)
    if marker:
        if os.path.exists(marker):
            return
        Path(marker).touch()
    os._exit(70)


class Worker:
    """One OpenCL renderer for many calls (see the module)."""

    def __init__(self, device: str | None = None, remote: bool = False):
        self.device, self.remote = device, remote
        self.renderer = None

    def call(self, fn: Callable, args: tuple, tag: str = ""):
        if self.remote:
            crash_point(tag)
        if self.renderer is None:
            from marblevideo.opencl.renderer import Renderer

            self.renderer = Renderer(self.device)
        self.renderer.forget_frames()
        return fn(*args, renderer=self.renderer)

    def where(self) -> tuple[str, str, int, str | None]:
        """(marblevideo's version, where it is imported from, process id, PoCL's threads)."""
        from marblevideo.version import __version__

        return __version__, str(PACKAGE_ROOT), os.getpid(), os.environ.get("POCL_MAX_PTHREAD_COUNT")


class SerialPool:
    """Calls one after another in this process, on one renderer."""

    def __init__(self, device: str | None = None):
        self.worker = Worker(device)

    def run(
        self, fn: Callable, calls: list[tuple], tags: list[str] | None = None
    ) -> Iterator[tuple[int, object]]:
        for index, args in enumerate(calls):
            try:
                yield index, self.worker.call(fn, args)
            except MarbleError as exc:
                yield index, exc

    def close(self) -> None:
        """Nothing to stop."""


def require_ray():
    """The ``ray`` module; UsageError (exit 2) when the extra is not installed."""
    try:
        import ray
    except ImportError:
        raise UsageError(
            "--cluster ray: Ray is not installed; pip install 'marblevideo[ray]'"
        ) from None
    return ray


def connect(ray, num_cpus: int | None = None) -> bool:
    """Join ``$RAY_ADDRESS``'s cluster, or start a local one (``num_cpus``: its
    CPUs, default all) whose workers import this very package; True when this
    call connected (the pool then disconnects, stopping a local Ray). An
    existing connection (``ray.init`` by the caller) is used as it is."""
    if ray.is_initialized():
        return False
    quiet = {"include_dashboard": False, "logging_level": logging.ERROR, "log_to_driver": False}
    address = os.environ.get("RAY_ADDRESS")
    try:
        if address:
            ray.init(address=address, **quiet)
        else:
            path = [str(PACKAGE_ROOT), *filter(None, [os.environ.get("PYTHONPATH")])]
            ray.init(
                address="local",
                num_cpus=num_cpus,
                _node_ip_address="127.0.0.1",
                runtime_env={"env_vars": {"PYTHONPATH": os.pathsep.join(path)}},
                **quiet,
            )
    except (ConnectionError, RuntimeError, ValueError) as exc:
        where = address or "a local Ray"
        raise MediaError(f"--cluster ray: cannot start or reach {where}: {exc}") from None
    return True


class RayPool:
    """Calls on Ray actors, each holding a :class:`Worker` (see the module):
    ``workers`` of them (default: one per GPU of the cluster, else one per CPU)."""

    def __init__(self, workers: int | None = None, device: str | None = None):
        if workers is not None and workers < 1:
            raise UsageError(f"--jobs: expected a count >= 1, got {workers}")
        self.ray = ray = require_ray()
        self.started = connect(ray)
        self.device = device
        self.actors: list = []
        try:
            self.count, self.options, threads = self.sizes(workers)
            env = {"POCL_MAX_PTHREAD_COUNT": str(threads)}
            for name in (CRASH_ENV, CRASH_MARKER_ENV):
                if name in os.environ:
                    env[name] = os.environ[name]
            self.actor_class = ray.remote(Worker).options(
                max_restarts=RETRIES,
                max_task_retries=RETRIES,
                runtime_env={"env_vars": env},
                **self.options,
            )
            self.actors = [self.new_actor() for _ in range(self.count)]
            self.check_workers()
        except BaseException:
            self.close()
            raise

    def sizes(self, workers: int | None) -> tuple[int, dict, int]:
        """(workers, their Ray resources, PoCL threads each): one per GPU, else
        each CPU worker its share of the CPUs, no more than a machine has, and no
        more workers than CPUs (a worker that cannot be placed would wait forever)."""
        ray = self.ray
        resources = ray.cluster_resources()
        gpus, cpus = int(resources.get("GPU", 0)), max(1, int(resources.get("CPU", 1)))
        biggest = max(
            (int(n["Resources"].get("CPU", 0)) for n in ray.nodes() if n.get("Alive")), default=1
        )
        if gpus:
            count = min(workers or gpus, gpus)
            return count, {"num_gpus": 1, "num_cpus": 1}, max(1, cpus // count)
        count = min(workers or cpus, cpus)
        threads = max(1, min(cpus // count, biggest))
        return count, {"num_cpus": threads}, threads

    def check_workers(self) -> None:
        """Wait for the first worker (a cluster may be scaling up), then
        :data:`STARTUP` seconds for the others (those not up by then are let go),
        and check that each runs this version of marblevideo."""
        from marblevideo.version import __version__

        ray = self.ray
        asked = {actor.where.remote(): actor for actor in self.actors}
        ray.wait(list(asked), num_returns=1)
        ready, late = ray.wait(list(asked), num_returns=len(asked), timeout=STARTUP)
        for ref in late:
            ray.kill(asked[ref])
            self.actors.remove(asked[ref])
        for version, path, _, _ in ray.get(ready):
            if version != __version__:
                raise MediaError(
                    f"--cluster ray: a worker runs marblevideo {version} ({path}), this is "
                    f"{__version__}; install the same on every machine"
                )

    def new_actor(self):
        return self.actor_class.remote(self.device, True)

    def where(self) -> list[tuple[str, str, int, str | None]]:
        """Each worker's :meth:`Worker.where`."""
        return self.ray.get([actor.where.remote() for actor in self.actors])

    def run(
        self, fn: Callable, calls: list[tuple], tags: list[str] | None = None
    ) -> Iterator[tuple[int, object]]:
        ray = self.ray
        tags = tags or [""] * len(calls)
        waiting = list(range(len(calls)))[::-1]
        idle = list(self.actors)
        running: dict = {}
        while waiting or running:
            while idle and waiting:
                index = waiting.pop()
                actor = idle.pop()
                running[actor.call.remote(fn, calls[index], tags[index])] = (index, actor)
            done, _ = ray.wait(list(running), num_returns=1)
            index, actor = running.pop(done[0])
            try:
                result = ray.get(done[0])
            except ray.exceptions.RayActorError:
                ray.kill(actor)
                self.actors.remove(actor)
                actor = self.new_actor()
                self.actors.append(actor)
                result = WorkerLost(f"its worker died {RETRIES + 1} times")
            except ray.exceptions.RayTaskError as exc:
                cause = exc.cause
                if not isinstance(cause, MarbleError):
                    cause = MediaError(f"{type(cause).__name__}: {cause}")
                result = cause
            idle.append(actor)
            yield index, result

    def close(self) -> None:
        """Stop the workers (and the local Ray this pool started)."""
        for actor in self.actors:
            self.ray.kill(actor)
        self.actors = []
        if self.started:
            self.ray.shutdown()
            self.started = False
