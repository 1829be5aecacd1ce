"""FRF estimation: receptance FRFs H(response point, reference point) of any test layout
from the windowed accepted hits (H1, H2, coherence by pyFRF), FRF files combined, the
hammer's force spectrum, and the accelerance/mobility → receptance conversion.

H1 = S_xf/S_ff, H2 = S_xx/S_fx and the coherence γ² = |S_xf|²/(S_ff S_xx), averaged over the
accepted hits (Ewins, *Modal Testing*, 2000, §3.9); the thesis' 3×3 tool-tip matrix is the
special case :func:`frf_matrix`.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import xarray as xr

from robomill.modal.hits import HitGroup, impact_windows
from robomill.modal.layout import (
    AXES,
    AXIS_CODE,
    TOOLTIP,
    _point_key,
    frf_coords,
    point_label,
    points,
)


def frf_from_groups(groups: Sequence[HitGroup], fs_hz: int, *, force_window_s: float,
                    exponential_end: float) -> xr.Dataset:
    """Receptance FRFs H(response point, reference point) of any test layout, by
    :class:`pyFRF.FRF` on the windowed accepted hits of each group.

    Per group the hits are windowed (:func:`impact_windows`; the same exponential window on
    force and response) and averaged: H1 = S_xf/S_ff, H2 = S_xx/S_fx, γ² = |S_xf|²/(S_ff
    S_xx) (pyFRF; accelerance turned into receptance by pyFRF's ``frf_form``). The result
    spans every response point (``output``) and every reference point (``input``) measured;
    pairs never measured together are NaN (``n_hits`` 0). SISO, roving hammer (one response,
    many references), roving accelerometer (one reference, responses at many nodes),
    tri-axial responses and the 3×3 tool-tip matrix are all special cases.

    Raises
    ------
    ValueError
        A group without accepted hits, records of different lengths, or a pair measured in
        two groups.
    """
    import pyFRF

    fs_hz = int(fs_hz)
    outs = sorted({p for g in groups for p in g.responses}, key=_point_key)
    ins = sorted({g.reference for g in groups}, key=_point_key)
    n = None
    sigma = np.nan
    freq = None
    H = H2 = coh = nh = None
    for g in groups:
        if not g.hits:
            raise ValueError(f"no accepted hit at reference point {point_label(*g.reference)}: "
                             "the FRF column cannot be estimated")
        exc, resp = [], []
        for force, acc, trig in g.hits:
            if n is not None and force.size != n:
                raise ValueError(f"hit records of {force.size} and {n} samples: all hits of "
                                 "one test need the same record length")
            n = force.size
            w_f, w_e, sigma = impact_windows(n, fs_hz, trig, force_window_s=force_window_s,
                                             exponential_end=exponential_end)
            exc.append((force * w_f * w_e)[None, :])
            resp.append((np.asarray(acc, float).reshape(n, -1) * w_e[:, None]).T)
        frf = pyFRF.FRF(fs_hz, exc=np.array(exc), resp=np.array(resp), exc_type="f",
                        resp_type="a", window="none", frf_estimator="H1")
        with np.errstate(divide="ignore", invalid="ignore"):
            h1 = frf.get_FRF(frf_estimator="H1", frf_form="receptance")[:, 0, :]
            h2 = frf.get_FRF(frf_estimator="H2", frf_form="receptance")[:, 0, :]
            c = np.real(frf.get_coherence()).reshape(len(g.responses), -1)
        if freq is None:
            freq = frf.get_f_axis()
            shape = (len(outs), len(ins), freq.size)
            H, H2 = np.full(shape, np.nan + 0j), np.full(shape, np.nan + 0j)
            coh, nh = np.full(shape, np.nan), np.zeros(shape[:2], int)
        j = ins.index(g.reference)
        for k, p in enumerate(g.responses):
            i = outs.index(p)
            if nh[i, j]:
                raise ValueError(f"FRF {point_label(*p)}/{point_label(*g.reference)} measured "
                                 "in two groups of hits")
            H[i, j], H2[i, j], coh[i, j], nh[i, j] = h1[k], h2[k], c[k], len(g.hits)
    if freq is None:
        raise ValueError("no hit group: nothing to estimate")
    dims = ("output", "input", "frequency")
    ds = xr.Dataset(
        {"H": (dims, H, {"units": "m/N", "long_name": "receptance FRF, H1 estimator"}),
         "H2": (dims, H2, {"units": "m/N", "long_name": "receptance FRF, H2 estimator"}),
         "coherence": (dims, coh, {"units": "1", "long_name": "ordinary coherence"}),
         "n_hits": (("output", "input"), nh, {"units": "1",
                                              "long_name": "accepted hits averaged"})},
        coords=frf_coords(freq, outs, ins))
    ds.attrs["window_sigma_per_s"] = float(sigma)
    ds.attrs["fs_hz"] = fs_hz
    ds.attrs["record_samples"] = int(n)
    ds.attrs["force_window_s"] = float(force_window_s)
    ds.attrs["exponential_end"] = float(exponential_end)
    return ds


def frf_matrix(hits: dict[str, list[tuple[np.ndarray, np.ndarray, int]]], fs_hz: int, *,
               force_window_s: float, exponential_end: float) -> xr.Dataset:
    """The thesis' 3×3 tool-tip receptance matrix (:func:`frf_from_groups` on node 1).

    Parameters
    ----------
    hits
        Per input direction (``"X"``, ``"Y"``, ``"Z"``), the accepted hits as
        ``(force_N (n,), accel_ms2 (n, 3), trigger_index)``; all records of equal length.
    fs_hz
        Sampling rate (an integer, as pyFRF requires).

    Returns
    -------
    xr.Dataset
        ``H`` (H1) and ``H2`` complex [m/N], ``coherence`` [1] over ``output, input,
        frequency``; ``n_hits`` per pair; attribute ``window_sigma_per_s``.
    """
    for d in AXES:
        if not hits.get(d):
            raise ValueError(f"no accepted hit in direction {d}: the FRF column cannot be "
                             "estimated")
    groups = [HitGroup((1, AXIS_CODE[d]), TOOLTIP, list(hits[d])) for d in AXES]
    return frf_from_groups(groups, fs_hz, force_window_s=force_window_s,
                           exponential_end=exponential_end)


def combine_frfs(datasets: Sequence[xr.Dataset]) -> xr.Dataset:
    """One FRF dataset over the union of the points of several (same frequency axis).

    Raises
    ------
    ValueError
        Different frequency axes, or a response/reference pair in two datasets.
    """
    if len(datasets) == 1:
        return datasets[0]
    f = datasets[0]["frequency"].values
    for d in datasets[1:]:
        if d.sizes["frequency"] != f.size or not np.allclose(d["frequency"].values, f):
            raise ValueError("FRF files on different frequency axes cannot be combined")
    outs = sorted({p for d in datasets for p in points(d, "output")}, key=_point_key)
    ins = sorted({p for d in datasets for p in points(d, "input")}, key=_point_key)
    shape = (len(outs), len(ins), f.size)
    H = np.full(shape, np.nan + 0j)
    coh = np.full(shape, np.nan)
    for d in datasets:
        for a, o in enumerate(points(d, "output")):
            for b, i in enumerate(points(d, "input")):
                h = d["H"].values[a, b]
                if not np.isfinite(h).any():
                    continue
                ia, ib = outs.index(o), ins.index(i)
                if np.isfinite(H[ia, ib]).any():
                    raise ValueError(f"FRF {point_label(*o)}/{point_label(*i)} in two files")
                H[ia, ib] = h
                if "coherence" in d:
                    coh[ia, ib] = d["coherence"].values[a, b]
    dims = ("output", "input", "frequency")
    ds = xr.Dataset({"H": (dims, H, dict(datasets[0]["H"].attrs))},
                    coords=frf_coords(f, outs, ins))
    if np.isfinite(coh).any():
        ds["coherence"] = (dims, coh, {"units": "1", "long_name": "ordinary coherence"})
    return ds


def force_spectrum(groups: Sequence[HitGroup], ds: xr.Dataset) -> np.ndarray:
    """Mean one-sided auto-spectrum [N²/Hz] of the windowed hammer force over every accepted
    hit, on the FRF lines of ``ds`` (the input of :func:`robomill.modal.band.band_from_data`)."""
    fs = float(ds.attrs["fs_hz"])
    acc = []
    for g in groups:
        for force, _, trig in g.hits:
            w_f, w_e, _ = impact_windows(force.size, fs, trig,
                                         force_window_s=_force_window_s(ds),
                                         exponential_end=_exponential_end(ds))
            acc.append(2 * np.abs(np.fft.rfft(force * w_f * w_e)) ** 2 / (fs * force.size))
    s = np.mean(acc, axis=0)
    return s[: ds.sizes["frequency"]]


def _force_window_s(ds: xr.Dataset) -> float:
    return float(ds.attrs.get("force_window_s", 0.01))


def _exponential_end(ds: xr.Dataset) -> float:
    return float(ds.attrs.get("exponential_end", 0.05))


def to_receptance(frf: np.ndarray, f_hz: np.ndarray, form: str) -> np.ndarray:
    """Receptance [m/N] from an accelerance [(m/s²)/N], mobility [(m/s)/N] or receptance:
    ``H_x = H_a/(jω)² = H_v/(jω)`` (DC, where ω = 0, becomes NaN)."""
    power = {"receptance": 0, "mobility": 1, "accelerance": 2}[form]
    jw = 2j * np.pi * np.asarray(f_hz, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.asarray(frf, complex) / jw**power
    if power:
        out[..., np.asarray(f_hz) == 0] = np.nan
    return out
