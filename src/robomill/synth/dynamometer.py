"""Kistler dynamometer: ``forces/<cut>.h5`` (or ``.csv``) with ``t_s, Fx_N, Fy_N, Fz_N``.

The record of one cut is the force of the cut itself (:func:`robomill.synth.process.simulate_cut`:
the closed loop of the chip, the cutting force and the structure at the cut's pose, with
regeneration, run-out, the teeth leaving the cut, the gear trains' path error and the process
noise), sampled from the cut the virtual cell simulated once (:mod:`robomill.synth.cutstate`,
the same cut the tracker and the profilometer see) as the dynamometer measures it:

- **dynamometer dynamics**: a second-order low-pass per axis, unit static gain, natural
  frequency ``dynamometer_f_n_hz`` and damping ``dynamometer_zeta`` (*assumed*: chosen so that
  the tooth-passing harmonics near it dominate the full-band spectrum above 10 kHz as in thesis
  Fig 3.4; a Kistler 9255B alone is stiffer, the block and clamping lower it);
- **acquisition anti-alias filter**: the cut is integrated ``synth.process.oversample`` times
  faster than the record's rate and low-pass filtered at ``anti_alias_fraction`` × fs before
  decimation (:mod:`robomill.synth.process`);
- **noise**: white, ``noise_N`` standard deviation per axis (charge amplifier, *assumed*).

The record covers the first ``record_length_mm`` of the cut (null: the whole cut) and is
written block by block (``chunk_samples``). Forces are on the tool in R0 axes (see
``docs/data-contract.md``).
"""

from __future__ import annotations

import zlib
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from robomill.settings import config_section

INSTRUMENT_NUMBER = 2
"""Stream number of this instrument in per-file random generators."""



def settings(config: Mapping[str, Any]) -> dict[str, Any]:
    """``synth.dynamometer``, the schema's defaults filled
    (:func:`robomill.settings.config_section`)."""
    return config_section(config, "synth.dynamometer")



def truth(config: Mapping[str, Any], cell) -> Any:
    """Planted dynamometer parameters for ``truth.nc``."""
    import xarray as xr

    s = settings(config)
    return xr.Dataset({
        "dynamometer_f_n_hz": ((), float(s["dynamometer_f_n_hz"]),
                               {"units": "Hz", "long_name": "dynamometer natural frequency"}),
        "dynamometer_zeta": ((), float(s["dynamometer_zeta"]),
                             {"units": "1", "long_name": "dynamometer damping ratio"}),
        "dynamometer_noise_N": ((), float(s["noise_N"]),
                                {"units": "N", "long_name": "dynamometer noise std per axis"}),
    })


def record_length_mm(config: Mapping[str, Any]) -> float:
    """Length of the cut the dynamometer records [mm] (``record_length_mm`` or the cut)."""
    s = settings(config)
    return float(s["record_length_mm"] or config["experiment"]["cut_length_mm"])


def _dynamometer_filter(f_n_hz: float, zeta: float, fs_hz: float):
    """Bilinear (prewarped at f_n) 2nd-order low-pass ω²/(s² + 2ζωs + ω²), unit DC gain."""
    import scipy.signal

    wn = 2 * np.pi * f_n_hz
    if f_n_hz >= fs_hz / 2:
        raise ValueError(f"dynamometer_f_n_hz {f_n_hz} must be below Nyquist {fs_hz / 2}")
    g = 2 * fs_hz * np.tan(wn / (2 * fs_hz)) / wn
    return scipy.signal.bilinear([(wn * g) ** 2], [1.0, 2 * zeta * wn * g, (wn * g) ** 2],
                                 fs=fs_hz)


def simulate_blocks(cell, cut, config: Mapping[str, Any], sim
                    ) -> tuple[int, float, Iterator[tuple[np.ndarray, np.ndarray]]]:
    """The record of one cut as ``(n_samples, fs_hz, blocks)``; ``blocks`` yields
    ``(t_s, force_N (n, 3))`` of at most ``chunk_samples`` samples (R0 axes, on the tool).
    ``sim``: the simulated cut (:class:`robomill.synth.process.SimulatedCut`, at least
    ``record_length_mm`` long)."""
    import scipy.signal

    s = settings(config)
    rng = np.random.default_rng([cell.seed, INSTRUMENT_NUMBER, zlib.crc32(cut.id.encode())])
    sim = sim.span(record_length_mm(config))
    fs = sim.fs_hz
    n = min(int(round(record_length_mm(config) / cut.feed_mm_s * fs)), sim.t_s.size)
    b, a = _dynamometer_filter(float(s["dynamometer_f_n_hz"]), float(s["dynamometer_zeta"]), fs)
    chunk = int(s["chunk_samples"])
    noise = float(s["noise_N"])

    def blocks():
        zi = None
        for i0 in range(0, n, chunk):
            sl = slice(i0, min(i0 + chunk, n))
            F = sim.force_N[sl] @ sim.frame.T
            if zi is None:  # start at rest under the first (static) force
                zi = scipy.signal.lfilter_zi(b, a)[:, None] * F[0][None, :]
            F, zi = scipy.signal.lfilter(b, a, F, axis=0, zi=zi)
            F += rng.normal(0.0, noise, size=F.shape)
            yield sim.t_s[sl], F

    return n, fs, blocks()


def simulate_file(config: Mapping[str, Any], cut, path: str | Path, sim, cell=None,
                  progress=None) -> Path:
    """Simulate one cut's record from the simulated cut ``sim`` and write it to ``path``
    (``.h5`` or ``.csv``) block by block; ``progress(fraction)`` is called after each
    block."""
    from robomill.io.atomic import atomic_path
    from robomill.io.forces import write_forces_csv, write_forces_h5
    from robomill.synth.cell import cell_from_config

    cell = cell or cell_from_config(config)
    n, fs, blocks = simulate_blocks(cell, cut, config, sim)
    if progress is not None:
        inner = blocks

        def reporting():
            done = 0
            for t, F in inner:
                yield t, F
                done += len(t)
                progress(done / n)

        blocks = reporting()
    path = Path(path)
    with atomic_path(path) as tmp:
        if path.suffix == ".csv":
            write_forces_csv(tmp, blocks)
        else:
            write_forces_h5(tmp, n, fs, blocks, dtype=settings(config)["dtype"])
    return path
