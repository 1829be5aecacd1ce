"""The chapters' Jupyter kernels: started early, on private sockets, with the chapters' common
modules already imported.

:func:`start_kernel` starts a chapter's kernel before the job has imported papermill (the
kernel starts in its own process while the job does its own start-up), and returns its
manager, which :func:`robomill.pipeline.chapters.render_chapter` gives papermill as ``km``
(nbclient's ``NotebookClient(km=...)``: a manager whose kernel is running is used as it is);
:func:`stop_kernel` shuts it down. Only jupyter_client's documented manager is used: its
``transport``/``ip`` settings, ``start_kernel`` and ``shutdown_kernel``.
"""

from __future__ import annotations

from pathlib import Path

#: Imported by every chapter kernel as it starts (an ``exec_lines`` of IPython, not a cell):
#: what the first cell of nearly every chapter imports, 0.7-0.9 s of it. A notebook that
#: never uses them loses nothing but that time, spent while the job does its own start-up.
PRELOAD_MODULES = ("pandas", "xarray", "IPython.display", "robomill.plotting",
                   "robomill.pipeline.captions", "robomill.pipeline.prose", "robomill.findings",
                   "robomill.io")

#: the kernel command-line option that imports :data:`PRELOAD_MODULES` (IPython's
#: ``IPKernelApp.exec_lines``: run at start-up, not counted as executed cells)
KERNEL_PRELOAD_ARGUMENT = ("--IPKernelApp.exec_lines=__import__('robomill.pipeline.kernels')"
                           ".pipeline.kernels.preload()")

#: IPython's history of a chapter kernel is kept in memory, as nbclient asks when it starts
#: the kernel itself (no history database shared by parallel chapters)
HISTORY_ARGUMENT = "--HistoryManager.hist_file=:memory:"


def preload() -> None:
    """Import :data:`PRELOAD_MODULES` (in a chapter kernel, at start-up); one that fails is
    left for the notebook to import, and to report."""
    import importlib

    for name in PRELOAD_MODULES:
        try:
            importlib.import_module(name)
        except Exception:  # noqa: BLE001, S110 - the notebook's own import says what is wrong
            pass


def start_kernel(kernel: str, socket_dir: str | Path, cwd: str | Path | None = None):
    """Start a chapter kernel now and return its manager (for papermill's ``km``); it answers
    once started, and imports :data:`PRELOAD_MODULES` before the first cell. End it with
    :func:`stop_kernel`.

    The kernel talks over Unix sockets in ``socket_dir`` (jupyter_client's ``transport="ipc"``
    with ``ip`` the sockets' path prefix). Chapter jobs run in parallel, each starting a
    kernel; over TCP, jupyter_client picks five free ports by binding and releasing them and
    the kernel binds them later, so two jobs starting together can pick the same ports and
    one then waits for a kernel that never answers ("Kernel didn't respond", papermill issue
    511). Sockets in a folder private to the job cannot collide.

    The manager is started on this thread's event loop (``jupyter_core.utils.run_sync``),
    the loop nbclient then runs the notebook on.
    """
    from jupyter_client.manager import AsyncKernelManager
    from jupyter_core.utils import run_sync

    manager = AsyncKernelManager(kernel_name=kernel, transport="ipc",
                                 ip=str(Path(socket_dir) / "kernel"))
    run_sync(manager.start_kernel)(extra_arguments=[HISTORY_ARGUMENT, KERNEL_PRELOAD_ARGUMENT],
                                   cwd=str(cwd) if cwd else None)
    return manager


def stop_kernel(manager) -> None:
    """Shut the kernel of :func:`start_kernel` down at once (``shutdown_kernel(now=True)``:
    every output of the chapter has been received when this is called, and a chapter kernel
    has nothing to save), and free its sockets and connection file."""
    from jupyter_core.utils import run_sync

    if manager.has_kernel:
        run_sync(manager.shutdown_kernel)(now=True)
    else:
        run_sync(manager.cleanup_resources)()
