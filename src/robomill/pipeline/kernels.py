"""The chapters' Jupyter kernels and the papermill engine that runs a notebook on them.

:func:`start_kernel` starts a chapter's kernel (:func:`private_kernel_manager`: private
sockets, start-up patches, preloaded modules) before the job has imported papermill, and
:func:`stop_kernel` kills it; :func:`ready_client_class` is its client, ready as soon as the
kernel is. :data:`ENGINE` is the papermill engine :func:`robomill.pipeline.chapters.render_chapter`
executes the notebook with: papermill's own, writing the executed notebook once, at the end.
"""

from __future__ import annotations

import os
import subprocess
import time
from collections.abc import Mapping
from functools import cache
from pathlib import Path

#: Imported by every chapter kernel as it starts (an ``exec_lines`` of IPython, not a cell):
#: what the first cell of nearly every chapter imports, 0.7-0.9 s of it. A notebook that
#: never uses them loses nothing but that time, spent while the job does its own start-up.
PRELOAD_MODULES = ("pandas", "xarray", "IPython.display", "robomill.plotting",
                   "robomill.pipeline.captions", "robomill.pipeline.prose", "robomill.findings",
                   "robomill.io")

#: the kernel command-line option that imports :data:`PRELOAD_MODULES`
KERNEL_PRELOAD_ARGUMENT = ("--IPKernelApp.exec_lines=__import__('robomill.pipeline.kernels')"
                           ".pipeline.kernels.preload()")

#: IPython's history of a chapter kernel is kept in memory, as nbclient asks when it starts
#: the kernel itself (no history database shared by parallel chapters)
HISTORY_ARGUMENT = "--HistoryManager.hist_file=:memory:"

#: how long :func:`stop_kernel` waits for a killed kernel's process to end [s]
KILL_WAIT_S = 5.0

#: how long to wait for the kernel's IOPub message that answers a ``kernel_info`` request,
#: the sign that the client's IOPub subscription is connected [s] (jupyter_client's value)
IOPUB_CHECK_S = 0.2


def preload() -> None:
    """Import :data:`PRELOAD_MODULES` (in a chapter kernel, at start-up); one that fails is
    left for the notebook to import, and to report."""
    import importlib

    for name in PRELOAD_MODULES:
        try:
            importlib.import_module(name)
        except Exception:  # noqa: BLE001, S110 - the notebook's own import says what is wrong
            pass


@cache
def ready_client_class():
    """An asynchronous kernel client whose :meth:`wait_for_ready` returns once the kernel
    answers.

    jupyter_client's ``wait_for_ready`` sends ``kernel_info`` requests until one is answered
    on the shell channel and a message arrives on IOPub (so that no output of the first cell
    is missed), then reads IOPub until it has been silent for 0.2 s, to throw away the
    kernel's start-up status messages. That last wait is pure delay for a chapter: every
    kernel start pays it in full (0.2 s of the 0.55 s a chapter kernel takes to be ready on
    the 2-core development machine), and nbclient, which runs the chapter, reads IOPub
    only for the replies to its own requests (by ``parent_header.msg_id``), so stale status
    messages are ignored anyway. This client does the first two steps and leaves out the
    third.
    """
    from queue import Empty

    from jupyter_client.asynchronous import AsyncKernelClient

    class ReadyKernelClient(AsyncKernelClient):
        async def wait_for_ready(self, timeout: float | None = None) -> None:
            deadline = time.monotonic() + (float("inf") if timeout is None else timeout)
            while True:
                self.kernel_info()
                try:
                    reply = await self.shell_channel.get_msg(timeout=1)
                except Empty:
                    reply = None
                if reply is not None and reply["msg_type"] == "kernel_info_reply":
                    try:  # the kernel's status for that request: IOPub is subscribed
                        await self.iopub_channel.get_msg(timeout=IOPUB_CHECK_S)
                    except Empty:
                        pass  # not yet: ask again
                    else:
                        self._handle_kernel_info_reply(reply)
                        return
                if not await self.is_alive():
                    raise RuntimeError("Kernel died before replying to kernel_info")
                if time.monotonic() > deadline:
                    raise RuntimeError(f"Kernel didn't respond in {timeout:.0f} seconds")

    return ReadyKernelClient


def private_kernel_manager(kernel: str, socket_dir: Path,
                           env: Mapping[str, str] | None = None):
    """A kernel manager class whose kernels talk over Unix sockets in ``socket_dir``.

    Chapter jobs run in parallel, each starting a kernel. Over TCP, jupyter_client picks five
    free ports by binding and releasing them and the kernel binds them later; two jobs
    starting together can pick the same ports, and one of them then waits for a kernel that
    never answers ("Kernel didn't respond", papermill issue 511; seen here with ch2 and ch5).
    IPC sockets in a folder private to the job cannot collide.

    The kernel also applies :mod:`robomill._imports`' start-up patches before the first cell
    (:data:`~robomill._imports.KERNEL_STARTUP_ARGUMENT`), as the pipeline's other entry points
    do, then imports :data:`PRELOAD_MODULES`, and gets ``env`` added to its environment (the
    job's figure workers, :meth:`robomill.pipeline.figure_workers.FigureServer.environment`).
    Its clients are :func:`ready_client_class`'s; the manager remembers them, so that
    :func:`stop_kernel` closes the one papermill made.
    """
    from jupyter_client.manager import AsyncKernelManager

    from robomill._imports import KERNEL_STARTUP_ARGUMENT

    prefix = str(Path(socket_dir) / "kernel")
    extra_env = dict(env or {})

    class PrivateSocketKernelManager(AsyncKernelManager):
        def __init__(self, **kwargs):
            kwargs.setdefault("kernel_name", kernel)
            super().__init__(transport="ipc", ip=prefix, **kwargs)
            self.client_factory = ready_client_class()
            self.clients = []

        def format_kernel_cmd(self, extra_arguments=None):
            return super().format_kernel_cmd([*(extra_arguments or []),
                                              KERNEL_STARTUP_ARGUMENT, KERNEL_PRELOAD_ARGUMENT])

        def client(self, **kwargs):
            made = super().client(**kwargs)
            self.clients.append(made)
            return made

        async def start_kernel(self, **kw):
            if extra_env:
                kw["env"] = {**(kw.get("env") or os.environ), **extra_env}
            return await super().start_kernel(**kw)

    return PrivateSocketKernelManager


def start_kernel(kernel: str, socket_dir: Path, env: Mapping[str, str] | None = None,
                 cwd: str | Path | None = None):
    """Start a chapter kernel now (:func:`private_kernel_manager`, with its history in
    memory, in ``cwd``) and return its manager, for papermill's ``km``; it answers once
    started and its :data:`PRELOAD_MODULES` are imported. End it with :func:`stop_kernel`.

    The manager is started on this thread's event loop (``jupyter_core.utils.run_sync``),
    the loop nbclient then runs the notebook on.
    """
    from jupyter_core.utils import run_sync

    manager = private_kernel_manager(kernel, socket_dir, env)()
    run_sync(manager.start_kernel)(extra_arguments=[HISTORY_ARGUMENT],
                                   cwd=str(cwd) if cwd else None)
    return manager


def stop_kernel(manager) -> None:
    """Kill the kernel of :func:`start_kernel` at once and close its clients' channels.

    Every output of the chapter has been received when this is called, and a chapter kernel
    has nothing to save. The polite way (jupyter_client 8 interrupts the kernel, asks it to
    shut down, waits half of its 5 s ``shutdown_wait_time``, then terminates it) took 0.14 s
    and, when the interrupt disturbed the kernel's handling of the request, 2.6 s: one chapter
    ``--forcerun`` in three or four on the 2-core development machine (traced: the kernel was
    still alive at the SIGTERM).

    The kernel's process group is sent ``SIGKILL`` and the process is reaped here, blocking
    until it has gone: jupyter_client's ``shutdown_kernel(now=True)`` first interrupts the
    kernel, then kills it and polls every 0.1 s until it is gone, which cost 0.1 s at the end
    of every chapter. It still runs afterwards, for its clean-up (the process handle, sockets,
    connection file); it then finds the process gone and waits for nothing."""
    from jupyter_core.utils import run_sync

    for made in manager.clients:
        made.stop_channels()
    manager.clients.clear()
    provisioner = getattr(manager, "provisioner", None)
    process = getattr(provisioner, "process", None)  # a local kernel's Popen
    if process is not None and process.poll() is None:
        run_sync(provisioner.kill)()  # SIGKILL to the kernel's process group
        try:
            process.wait(timeout=KILL_WAIT_S)
        except subprocess.TimeoutExpired:  # shutdown_kernel below waits and warns
            pass
    if manager.has_kernel:
        run_sync(manager.shutdown_kernel)(now=True)  # cleans up its resources too
    else:
        run_sync(manager.cleanup_resources)()


#: the name under which :func:`register_engine` registers the chapters' papermill engine
ENGINE = "robomill"


@cache
def register_engine() -> str:
    """Register (once) and name the chapters' papermill engine: papermill's nbclient engine,
    except that the executed notebook is written once, when execution ends, not also at every
    cell's start and end; its Python parameters are written without Black
    (:func:`_plain_python_parameters`).

    Papermill writes the whole notebook (validated, deep-copied, encoded as JSON with every
    figure) twice per cell so that a long run can be watched; a chapter's staged notebook is
    read by nobody until the chapter ends, and those 60 writes of ch3_3_modal took 0.3 s of the
    job's processor time while the kernel and the figure workers wanted it. The notebook is
    still written when execution ends in any way (papermill's ``notebook_complete``, in a
    ``finally``): after a failing cell, a timeout or a dead kernel the kept notebook shows the
    cells that ran, as before.
    """
    from papermill.engines import NBClientEngine, NotebookExecutionManager, papermill_engines

    class EndSavingManager(NotebookExecutionManager):
        _ending = False

        def save(self, **kwargs):
            if self._ending:
                super().save(**kwargs)

        def notebook_complete(self, **kwargs):
            self._ending = True
            return super().notebook_complete(**kwargs)

    class EndSavingEngine(NBClientEngine):
        @classmethod
        def execute_notebook(cls, nb, kernel_name, output_path=None, progress_bar=True,
                             log_output=False, autosave_cell_every=30, **kwargs):
            nb_man = EndSavingManager(nb, output_path=output_path, progress_bar=progress_bar,
                                      log_output=log_output,
                                      autosave_cell_every=autosave_cell_every)
            nb_man.notebook_start()
            try:
                cls.execute_managed_notebook(nb_man, kernel_name, log_output=log_output,
                                             **kwargs)
            finally:
                nb_man.cleanup_pbar()
                nb_man.notebook_complete()
            return nb_man.nb

    papermill_engines.register(ENGINE, EndSavingEngine)
    _plain_python_parameters()
    return ENGINE


def _plain_python_parameters() -> None:
    """Have papermill write a Python chapter's injected parameters as ``name = value`` lines,
    without passing them through Black when Black happens to be installed (it is, for
    snakefmt, in the development environment): importing and running it took 0.1 s of every
    chapter job, and the executed notebook no longer depends on whether a formatter is
    installed."""
    from papermill.translators import PythonTranslator, papermill_translators

    class PlainPythonTranslator(PythonTranslator):
        @classmethod
        def codify(cls, parameters, comment="Parameters"):
            return super(PythonTranslator, cls).codify(parameters, comment)

    papermill_translators.register("python", PlainPythonTranslator)
