"""The library's compiled (numba) kernels: compiled once per virtual environment, one process
at a time, loaded from that cache by every later process.

numba caches a compiled kernel on disk (``cache=True``) in ``NUMBA_CACHE_DIR``; without it
next to the sources, so that every clone of the sources and every worktree compiled its own
and the first jobs of a fresh clone compiled the same kernel side by side. The workflow
(``Snakefile``) and the ``Makefile`` set ``NUMBA_CACHE_DIR`` to :func:`cache_dir`, a folder
of the virtual environment (``.venv/numba-cache``), and ``make venv`` compiles every kernel
there (``python -m robomill.kernels``). A process about to call a module's kernels first
calls :func:`ready` for it: under a lock of the cache folder it calls each kernel once on a
tiny input of the types the module uses, which compiles the kernel where the cache lacks it
(the sources changed) and only loads it otherwise; a second process waits for the first
instead of compiling the same kernel beside it.
"""

from __future__ import annotations

import contextlib
import functools
import importlib
import os
import sys
import time
from pathlib import Path

KERNEL_MODULES = ("robomill.synth.process", "robomill.chatter.modal_timedomain",
                  "robomill.chatter.timedomain", "robomill.chatter.envelope_kernel")
"""The modules with numba kernels; each has ``warm_kernels()``."""
CACHE_SUBDIR = "numba-cache"


def cache_dir() -> Path:
    """The kernels' cache folder: ``NUMBA_CACHE_DIR`` where set, else ``numba-cache`` in the
    running virtual environment (``sys.prefix``)."""
    return Path(os.environ.get("NUMBA_CACHE_DIR") or Path(sys.prefix) / CACHE_SUBDIR)


@contextlib.contextmanager
def one_compiler(folder: Path | None = None):
    """Hold the kernels' lock (an exclusive ``flock`` on ``.robomill-kernels.lock`` in the
    cache folder) for the duration: one process of the environment compiles at a time. Where
    the folder cannot be written (a read-only environment) there is no lock to take, and
    numba compiles in memory as it does without a cache."""
    import fcntl

    folder = Path(folder or cache_dir())
    try:
        folder.mkdir(parents=True, exist_ok=True)
        lock = open(folder / ".robomill-kernels.lock", "w")  # noqa: SIM115 (held below)
    except OSError:
        yield
        return
    with lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


@functools.cache
def ready(module: str) -> float:
    """Compile or load the kernels of ``module`` (one of :data:`KERNEL_MODULES`) in this
    process, holding :func:`one_compiler`; the seconds it took (0 after the first call)."""
    t0 = time.perf_counter()
    with one_compiler():
        importlib.import_module(module).warm_kernels()
    return time.perf_counter() - t0


def main() -> int:
    """``python -m robomill.kernels``: make every kernel ready in this environment's cache
    (``make venv``) and say how long each took."""
    os.environ.setdefault("NUMBA_CACHE_DIR", str(cache_dir()))
    for module in KERNEL_MODULES:
        print(f"robomill kernels: {module} ready in {ready(module):.1f} s ({cache_dir()})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
