"""The simulated state of one cut, integrated once and stored: the virtual cell's truth that
every instrument samples (``results/synthetic/truth/cuts/<cut>.nc``).

A lab's dynamometer, profilometer, tracker, microphone and accelerometer all look at one
physical cut; so do the simulators. :func:`write_cut_state` integrates the closed-loop cut
(:func:`robomill.synth.process.simulate_cut`) over the longest span any planned instrument
needs (:func:`span_mm`) and writes what happened: the force on the tool, the structure's
displacement, the gear trains' path error on its grid, the cut frame and the modes at the
cut's pose. A pass of the robot along the same path without material (an *air pass*,
``cutting=False``: the servo excitation and the path error remain, no force) is another
simulated span of the same cut: with ``air=True`` the file holds both passes, the variables
indexed by ``pass`` (``loaded``, ``air``). :func:`read_cut_state` gives back one pass as a
:class:`robomill.synth.process.SimulatedCut`, cut to the span an instrument asks for
(:meth:`~robomill.synth.process.SimulatedCut.span`): the same samples, bit for bit, as a
simulation of that span alone.

The file is float64 (an instrument sees the simulated state itself, not a rounded copy) and
carries no time axis (``t = i / fs_hz``).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

PASSES = ("loaded", "air")
"""The passes of a cut: the cut itself and the same path without material."""
AXES = ("x", "y", "z")


def span_mm(config: Mapping[str, Any], kinds: Iterable[str]) -> float | None:
    """The longest span of a cut [mm] that the instruments ``kinds`` (file kinds of the
    layout: ``force``, ``sound``, ``vibration``, ``profile``, ``tracker``) sample; None: the
    whole cut (a tracker run follows the whole path; a dynamometer record without
    ``record_length_mm``)."""
    from robomill.synth.dynamometer import record_length_mm
    from robomill.synth.profilometer import trace_end_mm

    whole = float(config["experiment"]["cut_length_mm"])
    spans = []
    for kind in set(kinds):
        if kind in ("force", "sound", "vibration"):
            spans.append(record_length_mm(config))
        elif kind == "profile":
            spans.append(trace_end_mm(config))
        elif kind == "tracker":
            spans.append(whole)
    if not spans or max(spans) >= whole:
        return None
    return max(spans)


SAMPLING_KINDS = ("force", "sound", "vibration", "profile", "tracker")
"""File kinds whose simulator samples the simulated cut."""


def planned_cut_states(config: Mapping[str, Any], files: Iterable[Mapping[str, Any]]
                       ) -> dict[str, dict[str, Any]]:
    """The cuts the virtual cell integrates for the planned raw ``files`` (layout entries:
    ``kind``, ``cut``, optional ``pass``), in order of first use: per cut id, ``length_mm``
    (:func:`span_mm` of the kinds that sample it; None: the whole cut) and ``air`` (an
    instrument records its air pass, ``pass: air``). A tracker's air run samples no
    simulated state (the tracker sees the gear error, its ripple and noise, not the arm's
    vibration in the air), so it asks for none."""
    kinds: dict[str, set] = {}
    air: dict[str, bool] = {}
    for f in files:
        cut = f.get("cut")
        if f.get("kind") not in SAMPLING_KINDS or not cut:
            continue
        is_air = str(f.get("pass") or "loaded") == "air"
        if f["kind"] == "tracker" and is_air:
            continue
        kinds.setdefault(str(cut), set()).add(str(f["kind"]))
        air[str(cut)] = air.get(str(cut), False) or is_air
    return {c: {"length_mm": span_mm(config, k), "air": air[c]} for c, k in kinds.items()}


def cut_state_dataset(sims: Mapping[str, Any]):
    """The dataset of one cut's passes ``{pass: SimulatedCut}`` (the same cut, span and
    rate)."""
    import xarray as xr

    passes = [p for p in PASSES if p in sims]
    first = sims[passes[0]]
    n = first.t_s.size

    def stack(name):
        arrays = [getattr(sims[p], name) for p in passes]
        if any(a.shape[0] != n for a in arrays):
            raise ValueError(f"cut {first.cut_id}: the passes {passes} differ in length")
        return np.stack(arrays)

    modes = first.modes
    attrs = {"cut": first.cut_id, "fs_hz": first.fs_hz, "feed_mm_s": first.feed_mm_s,
             "tooth_hz": first.tooth_hz, "n_full": int(first.n_full),
             "filter_lag": int(first.filter_lag), "path_dt_s": first.path_dt_s}

    def v(dims, data, units, long_name):
        return (dims, data, {"units": units, "long_name": long_name})

    return xr.Dataset(
        {
            "force_N": v(("pass", "sample", "axis"), stack("force_N"), "N",
                         "cutting force on the tool (cut frame), anti-alias filtered"),
            "deflection_m": v(("pass", "sample", "axis"), stack("deflection_m"), "m",
                              "structure's displacement of the tool (cut frame)"),
            "teeth_out": v("pass", [sims[p].teeth_out for p in passes], "1",
                           "fraction of deep tooth passages whose chip was <= 0"),
            "path_error_grid_m": v(("path_sample", "axis"), first.path_grid_m, "m",
                                   "gear trains' TCP error on its grid (cut frame)"),
            "frame": v(("base_axis", "axis"), first.frame, "1",
                       "rotation base <- cut frame"),
            "mode_f_hz": v("mode", [m.f_hz for m in modes], "Hz",
                           "natural frequency at the cut's pose"),
            "mode_zeta": v("mode", [m.zeta for m in modes], "1", "damping ratio"),
            "mode_k_N_m": v("mode", [m.k_N_m for m in modes], "N/m",
                            "modal stiffness at the cut's pose"),
            "mode_shape": v(("mode", "base_axis"), [list(m.shape) for m in modes], "1",
                            "tool-tip mode shape (base frame)"),
        },
        coords={
            "pass": v("pass", passes, "1", "loaded: the cut; air: its path without material"),
            "axis": v("axis", list(AXES), "1", "cut frame axis (x feed, y cross-feed, z up)"),
            "base_axis": v("base_axis", list(AXES), "1", "robot base axis"),
        },
        attrs=attrs,
    )


def write_cut_state(cell, cut, config: Mapping[str, Any], path: str | Path, *,
                    length_mm: float | None = None, air: bool = False) -> Path:
    """Integrate ``cut`` once over its first ``length_mm`` (None: the whole cut; and, with
    ``air``, its air pass over the same span) and write the state to ``path``."""
    from robomill.io import write_artefact
    from robomill.synth.process import simulate_cut

    sims = {p: simulate_cut(cell, cut, config, cutting=p == "loaded", length_mm=length_mm)
            for p in (PASSES if air else PASSES[:1])}
    return write_artefact(cut_state_dataset(sims), path, rule="synth_cuts",
                          config_section={k: config[k] for k in ("cell", "synth", "experiment")
                                          if k in config})


def _scalar(value):
    """An HDF5 attribute as a Python scalar (netCDF stores numbers as 1-element arrays)."""
    if isinstance(value, bytes):
        return value.decode()
    value = np.asarray(value)
    return value.reshape(-1)[0].item() if value.size == 1 else value


STATE_VARIABLES = ("force_N", "deflection_m", "path_error_m")
"""The per-sample arrays of a stored cut an instrument may read."""


def read_cut_state(path: str | Path, pass_: str = "loaded", length_mm: float | None = None,
                   variables: Iterable[str] = STATE_VARIABLES):
    """One pass of a stored cut (:func:`write_cut_state`) as a
    :class:`~robomill.synth.process.SimulatedCut` over its first ``length_mm`` (None: the
    whole cut): the same samples as :meth:`~robomill.synth.process.SimulatedCut.span` of
    the stored simulation. Only the arrays named in ``variables`` (of
    :data:`STATE_VARIABLES`) are read, and only that span of them; the others are read-only
    NaN (an instrument that reads the force only, say). Raises ``ValueError`` naming the file
    where it lacks the pass or the span."""
    import h5py

    from robomill.synth.cell import Mode
    from robomill.synth.process import SimulatedCut, path_error_at_m, span_samples

    variables = set(variables)
    unknown = variables - set(STATE_VARIABLES)
    if unknown:
        raise ValueError(f"unknown cut state variable(s) {sorted(unknown)} (expected "
                         f"{', '.join(STATE_VARIABLES)})")
    with h5py.File(path, "r") as f:
        passes = [p.decode() if isinstance(p, bytes) else str(p) for p in f["pass"][()]]
        if pass_ not in passes:
            raise ValueError(f"{path}: no {pass_!r} pass of the cut (has {passes}; expected "
                             "the virtual cell to have simulated it)")
        i = passes.index(pass_)
        a = {k: _scalar(v) for k, v in f.attrs.items()}
        fs, lag = float(a["fs_hz"]), int(a["filter_lag"])
        stored = int(f["force_N"].shape[1])
        n = span_samples(int(a["n_full"]), float(a["feed_mm_s"]), fs, lag, length_mm)
        if n > stored:
            raise ValueError(f"{path}: cut {a['cut']}: {n} samples asked of a simulation of "
                             f"{stored} (expected a span within the simulated one)")
        unread = np.broadcast_to(np.nan, (n, 3))
        force = f["force_N"][i, :n] if "force_N" in variables else unread
        if "force_N" in variables and lag and n < stored:  # a prefix's filter tail
            force[-lag:] = force[-lag - 1]
        defl = f["deflection_m"][i, :n] if "deflection_m" in variables else unread
        teeth_out = float(f["teeth_out"][i])
        grid = f["path_error_grid_m"][()]
        frame = f["frame"][()]
        modes = tuple(Mode(f_hz=float(fr), zeta=float(z), k_N_m=float(k),
                           shape=tuple(float(x) for x in sh))
                      for fr, z, k, sh in zip(f["mode_f_hz"][()], f["mode_zeta"][()],
                                              f["mode_k_N_m"][()], f["mode_shape"][()],
                                              strict=True))
    t = np.arange(n) / fs
    dt = float(a["path_dt_s"])
    path_error = path_error_at_m(t, grid, dt) if "path_error_m" in variables else unread
    return SimulatedCut(cut_id=str(a["cut"]), fs_hz=fs, t_s=t, force_N=force,
                        deflection_m=defl, path_error_m=path_error, frame=frame,
                        feed_mm_s=float(a["feed_mm_s"]), tooth_hz=float(a["tooth_hz"]),
                        modes=modes, teeth_out=teeth_out, n_full=int(a["n_full"]),
                        filter_lag=lag, path_grid_m=grid, path_dt_s=dt)
