"""The numba kernels compiled once per environment (robomill.kernels): the warm-up of each
module compiles the very specialisation its simulations use (a real call adds none), and the
kernels' lock keeps a second process out while one holds it."""

from __future__ import annotations

import copy
import fcntl

import numpy as np
import pytest

from robomill import kernels


def _signatures():
    from robomill.chatter import modal_timedomain, timedomain
    from robomill.synth import process

    return {"synth": len(process._integrate.signatures),
            "modal": len(modal_timedomain._run.signatures),
            "seed": len(timedomain._integrate.signatures)}


def test_the_warm_up_compiles_what_the_simulations_call(config):
    from robomill.chatter.modal_timedomain import ModalCut, simulate_modal_cut
    from robomill.chatter.timedomain import SeedParams, SeedSimulation
    from robomill.io.synthetic_layout import synthetic_cuts
    from robomill.synth.cell import cell_from_config
    from robomill.synth.process import simulate_cut

    for module in kernels.KERNEL_MODULES:
        kernels.ready(module)
    warmed = _signatures()
    assert warmed == {"synth": 1, "modal": 1, "seed": 1}
    c = copy.deepcopy(config)
    c["experiment"]["cut_length_mm"] = 0.5
    simulate_cut(cell_from_config(c), synthetic_cuts(c)[0], c)
    simulate_modal_cut(ModalCut(np.array([50.0, 80.0]), np.array([0.05, 0.03]),
                                np.array([1e7, 2e7]), np.array([[0.0, 1.0], [1.0, 0.0]]),
                                28000.0, 2, 0.0, np.pi, 1e-5, 5e-4, 796e6, 168e6, 222e6),
                       duration_s=2e-3)
    SeedSimulation(SeedParams(), 2e-4, duration_s=0.01).run(0.005)
    assert _signatures() == warmed  # nothing compiled beside the warm-up's


def test_one_process_at_a_time_holds_the_kernels_lock(tmp_path):
    with kernels.one_compiler(tmp_path):
        with open(tmp_path / ".robomill-kernels.lock") as other, \
                pytest.raises(BlockingIOError):
            fcntl.flock(other, fcntl.LOCK_EX | fcntl.LOCK_NB)
    with open(tmp_path / ".robomill-kernels.lock") as other:
        fcntl.flock(other, fcntl.LOCK_EX | fcntl.LOCK_NB)  # free once released


def test_the_cache_is_the_environments_unless_set(monkeypatch, tmp_path):
    import sys
    from pathlib import Path

    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    assert kernels.cache_dir() == Path(sys.prefix) / "numba-cache"
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    assert kernels.cache_dir() == tmp_path


def test_a_cache_folder_that_cannot_be_made_takes_no_lock_and_stops_nothing(tmp_path):
    blocker = tmp_path / "a_file"
    blocker.write_text("")  # a folder cannot be made below a file (read-only environments)
    with kernels.one_compiler(blocker / "cache"):
        ran = True
    assert ran and not (blocker / "cache").exists()
