"""Draw a chapter's figures in worker processes while its notebook goes on.

Rendering a figure to PNG (Matplotlib's ``savefig``: the tight-bounding-box layout pass,
the Agg draw, the PNG encoding) is most of a chapter's run: 2.5–3.2 s of the 3.8–4.9 s that
the cells of chapters 2, 3.1, 3.2 and 3.3 take on the 2-core development machine, all of it
in the one kernel process while the other core waits. Here the kernel only *builds* each
figure; worker processes draw them, in parallel with each other and with the cells that
follow.

* **Job side** (:class:`FigureServer`, started by
  :func:`robomill.pipeline.chapters.render_chapter` before the kernel): a pool of worker
  processes (:class:`concurrent.futures.ProcessPoolExecutor`, ``spawn``) that start while
  the kernel does, and a Unix socket (:mod:`multiprocessing.connection`) in a folder only
  this user can enter (``mkdtemp``); its path reaches the kernel in
  :data:`ADDRESS_VARIABLE`. The pool belongs to the job process, not the kernel, so the
  kernel has no child process to wait for at shutdown (ipykernel signals each child and
  waits for it to go; multiprocessing's resource tracker ignores those signals, which cost
  2.6 s per chapter when the pool lived in the kernel).
* **Kernel side** (:func:`client`, used by :meth:`robomill.pipeline.captions.Numbering.show`):
  each figure is sent pickled (:func:`robomill.pipeline.figure_cache.figure_blob`), with the
  kernel's ``rcParams`` and its cache key; the worker draws it with the same
  :func:`robomill.plotting.save_figure` under those ``rcParams``, so the file is the same
  bytes as a figure drawn in the kernel (tested). The chapter shows a placeholder with a
  display id meanwhile; :meth:`~robomill.pipeline.captions.Numbering.check` (every chapter's
  last cell) waits for all of them and replaces each placeholder by its image.
* **Cache** (:mod:`robomill.pipeline.figure_cache`, ``chapters.figure_cache``): a figure whose
  key an earlier run of the chapter drew is copied from the cache instead of drawn. The
  workers start with the job only when the chapter's cache is empty (a first run draws every
  figure); otherwise at the first figure the cache does not hold, so that a rerun whose
  figures are all unchanged starts none.

Outside a chapter job (a notebook opened by hand, ``make explore``) the variable is not set
and figures are drawn in the kernel as before; so is a figure that cannot be pickled, and
one whose worker failed (drawn again in the kernel, so that a drawing error reads as it
always did).

The job's script is the main module that ``spawn`` imports again in each worker:
``workflow/scripts/render_chapter.py`` renders only under ``if __name__ == "__main__"``.
"""

from __future__ import annotations

import logging
import os
import pickle
import threading
from collections.abc import Mapping
from concurrent.futures import Future
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from robomill.pipeline.figure_cache import FigureCache

log = logging.getLogger(__name__)

#: the environment variable holding the figure server's socket path (set for the kernel)
ADDRESS_VARIABLE = "ROBOMILL_FIGURE_SERVER"
#: the metadata key of a figure's placeholder output; a page still holding one is refused
BEING_DRAWN = "robomill/figure-being-drawn"
#: rcParams that belong to the kernel's own process, not to drawing one figure
_PROCESS_RC = ("backend", "backend_fallback", "interactive")


def usable_workers(requested: int) -> int:
    """The number of worker processes to start: ``requested`` (``chapters.figure_workers``),
    at most the processors this process may run on; none on a single processor, where a
    worker would only add its own start-up to the kernel's work."""
    try:
        cpus = len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        cpus = os.cpu_count() or 1
    return 0 if cpus < 2 else max(0, min(int(requested), cpus))


def drawing_rc() -> dict[str, Any]:
    """This process's ``rcParams`` that bear on drawing a figure (all but the backend)."""
    import matplotlib.pyplot as plt

    return {k: v for k, v in plt.rcParams.items() if k not in _PROCESS_RC}


def draw(blob: bytes, fig_dir: str, name: str, rc: Mapping[str, Any]) -> str:
    """Unpickle a figure and save it as ``<fig_dir>/<name>.png`` under ``rc`` (the sending
    kernel's ``rcParams``) with :func:`robomill.plotting.save_figure`; returns the path."""
    import matplotlib.pyplot as plt

    from robomill.plotting import save_figure

    fig = pickle.loads(blob)
    try:
        with plt.rc_context(dict(rc)):
            return str(save_figure(fig, fig_dir, name))
    finally:
        plt.close(fig)


def _start_worker() -> None:
    """Pool initializer: Matplotlib on Agg with the chapters' style, before the first
    figure arrives."""
    import matplotlib

    matplotlib.use("Agg")
    import robomill.plotting  # noqa: F401  (style; pyplot)


def _outcome(future: Future) -> str | None:
    """None for a figure drawn, else what went wrong, in one line."""
    exc = future.exception()
    if exc is None:
        return None
    first = (str(exc).strip().splitlines() or [""])[0]
    return f"{type(exc).__name__}: {first}" if first else type(exc).__name__


# ---------------------------------------------------------------------------------------
# job side


class FigureServer:
    """Worker processes that draw the figures of one chapter run, and the socket through
    which its kernel sends them (a context manager; see the module docstring).

    Parameters
    ----------
    workers
        Worker processes (``chapters.figure_workers``, capped by :func:`usable_workers`);
        with none, :meth:`environment` is empty and the kernel draws its own figures.
    folder
        A folder only this user can enter, private to this job, for the socket file.
    cache
        The chapter's :class:`~robomill.pipeline.figure_cache.FigureCache`, or None to draw
        every figure.
    """

    def __init__(self, workers: int, folder: str | Path, cache: FigureCache | None = None
                 ) -> None:
        self.workers = usable_workers(workers)
        self.address = str(Path(folder) / "figures")
        self.cache = cache if self.workers else None
        #: cache keys of the figures this run showed; figures reused from the cache, drawn
        self.used_keys: set[str] = set()
        self.reused = self.drawn = 0
        self._pool = None
        self._listener = None
        self._thread: threading.Thread | None = None
        self._conn = None
        self._closing = False

    def __enter__(self) -> FigureServer:
        if not self.workers:
            return self
        from multiprocessing.connection import Listener

        if self.cache is None or not len(self.cache):
            self._start_pool()  # now, while the kernel starts: every figure will be drawn
        self._listener = Listener(self.address, family="AF_UNIX")
        self._thread = threading.Thread(target=self._serve, name="figure-server", daemon=True)
        self._thread.start()
        return self

    def _start_pool(self):
        """The worker processes, started (all of them) on the first call."""
        if self._pool is None:
            import multiprocessing
            from concurrent.futures import ProcessPoolExecutor

            self._pool = ProcessPoolExecutor(self.workers, initializer=_start_worker,
                                             mp_context=multiprocessing.get_context("spawn"))
            for _ in range(self.workers):  # start each now, not at its first figure
                self._pool.submit(int)
        return self._pool

    def environment(self) -> dict[str, str]:
        """The variable that tells the kernel where to send its figures (empty without
        workers)."""
        return {ADDRESS_VARIABLE: self.address} if self.workers else {}

    def _serve(self) -> None:
        """Answer one kernel connection after another (a kernel started again gets a new
        one) until :meth:`__exit__`."""
        while not self._closing:
            try:
                self._conn = self._listener.accept()
            except OSError:
                return
            try:
                self._answer(self._conn)
            except Exception:  # noqa: BLE001 - keep serving; the kernel redraws what is lost
                log.exception("figure server: a request failed")
            finally:
                self._conn.close()

    def _answer(self, conn) -> None:
        """One kernel's requests: ``("draw", ident, blob, fig_dir, name, rc, key)`` queues a
        figure (or copies it from the cache: ``key`` is its cache key, None for none);
        ``("wait",)`` answers ``{ident: None or what went wrong}`` for every figure queued
        since the last wait, once all are drawn, and keeps each one drawn in the cache."""
        pending: dict[str, Future] = {}
        to_keep: dict[str, tuple[str, str]] = {}  # ident: (key, PNG) of figures drawn
        while True:
            try:
                request = conn.recv()
            except (EOFError, OSError):
                return
            if request[0] == "draw":
                _, ident, blob, fig_dir, name, rc, key = request
                png = str(Path(fig_dir) / f"{name}.png")
                if key is not None:
                    self.used_keys.add(key)
                pending[ident] = Future()
                if key is not None and self.cache is not None and self.cache.fetch(key, png):
                    pending[ident].set_result(png)
                    self.reused += 1
                    continue
                try:
                    pending[ident] = self._start_pool().submit(draw, blob, fig_dir, name, rc)
                except Exception as exc:  # noqa: BLE001 - a broken pool: report it
                    pending[ident].set_exception(exc)
                    continue
                self.drawn += 1
                if key is not None and self.cache is not None:
                    to_keep[ident] = (key, png)
            elif request[0] == "wait":
                outcomes = {ident: _outcome(f) for ident, f in pending.items()}
                for ident, (key, png) in to_keep.items():
                    if outcomes[ident] is None:
                        try:
                            self.cache.store(key, png)
                        except OSError as exc:  # a full disk: the figure is drawn anyway
                            log.warning("figure cache: %s not kept (%s)", png, exc)
                conn.send(outcomes)
                pending.clear()
                to_keep.clear()

    def keep_only_used(self) -> None:
        """Empty the cache of every figure this run did not show (after a successful
        chapter: a figure that changed leaves only its new PNG)."""
        if self.cache is not None:
            self.cache.keep_only(self.used_keys)

    def __exit__(self, *exc_info) -> None:
        if self._thread is not None:
            from multiprocessing.connection import Client

            self._closing = True
            if self._conn is not None and not self._conn.closed:
                _hang_up(self._conn)  # a kernel still connected
            if self._thread.is_alive():  # waiting in accept(): wake it with a connection
                try:
                    Client(self.address, family="AF_UNIX").close()
                except OSError:
                    pass
            self._thread.join(timeout=10)
        if self._listener is not None:
            self._listener.close()
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None
            _stop_resource_tracker()


def _stop_resource_tracker() -> None:
    """End and reap the process that ``multiprocessing`` started beside the workers to track
    their semaphores (its resource tracker), once the pool is gone.

    Left alone it ends only when the job has exited, as an orphan, and where nothing adopts
    orphans and reaps them (a container whose first process is not an init) it stays a
    zombie after every chapter. The pool's semaphores are released first (a collection: they
    sit in reference cycles), while the tracker still listens; otherwise releasing them later
    would start a new tracker."""
    import gc
    from multiprocessing import resource_tracker

    gc.collect()
    stop = getattr(resource_tracker._resource_tracker, "_stop", None)  # Python 3.8+
    if stop is not None:
        stop()


def _hang_up(conn) -> None:
    """End a connection that another thread may be reading: ``shutdown`` wakes that read
    with an end of file (closing the descriptor would not)."""
    import socket

    try:
        with socket.socket(fileno=os.dup(conn.fileno())) as sock:
            sock.shutdown(socket.SHUT_RDWR)
    except OSError:
        pass


# ---------------------------------------------------------------------------------------
# kernel side


class FigureClient:
    """The kernel's connection to its job's :class:`FigureServer`."""

    def __init__(self, address: str) -> None:
        from multiprocessing.connection import Client

        self._conn = Client(address, family="AF_UNIX")

    def send(self, ident: str, fig, fig_dir: str | Path, name: str) -> bytes | None:
        """Queue ``fig`` to be saved as ``<fig_dir>/<name>.png``, with its cache key
        (:func:`~robomill.pipeline.figure_cache.figure_key`); returns the pickled figure
        (to draw it here should its worker fail), or None with nothing sent when the figure
        cannot be pickled, so that the caller draws it itself."""
        from robomill.pipeline.figure_cache import figure_blob, figure_key

        rc = drawing_rc()
        try:
            blob = figure_blob(fig)
        except Exception as exc:  # noqa: BLE001 - any pickling failure: draw it here
            log.debug("figure %s is drawn in the kernel: %s", name, exc)
            return None
        try:
            key = figure_key(blob, rc)
        except Exception as exc:  # noqa: BLE001 - no key: drawn, not cached
            log.warning("figure %s has no cache key (%s): it is drawn", name, exc)
            key = None
        self._conn.send(("draw", ident, blob, str(fig_dir), name, rc, key))
        return blob

    def wait(self) -> dict[str, str | None]:
        """Block until every figure sent is drawn: ``{ident: None, or what went wrong}``;
        every figure counts as not drawn when the server cannot be reached."""
        try:
            self._conn.send(("wait",))
            return self._conn.recv()
        except (EOFError, OSError) as exc:
            log.warning("figure workers lost (%s): drawing in the kernel", exc)
            return {}


_client: FigureClient | None = None


def client() -> FigureClient | None:
    """The kernel's :class:`FigureClient`, connected on first use; None outside a chapter
    job (no :data:`ADDRESS_VARIABLE`) or when the server cannot be reached (the figures are
    then drawn in the kernel)."""
    global _client
    address = os.environ.get(ADDRESS_VARIABLE)
    if _client is None and address:
        try:
            _client = FigureClient(address)
        except OSError as exc:
            log.warning("figure workers at %s unreachable (%s): drawing in the kernel",
                        address, exc)
            os.environ.pop(ADDRESS_VARIABLE, None)
    return _client
