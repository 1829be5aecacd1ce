"""Impact-test modal identification of the tool tip (thesis §3.3, and beyond it).

The chain, each step a pure function on arrays:

1. :func:`check_hit` — automatic rejection of a hit: a **double hit** (the force rises above
   ``double_hit_fraction`` of its peak in two separate pulses) or an **overload** (a channel
   stays at its extreme value for ``overload_samples`` samples or more: a clipped,
   saturated channel). The reason is returned in words.
2. :func:`impact_windows` — a force window (1 from the record start to ``force_window_s``
   after the trigger, then a half-Hann taper) and an exponential window
   ``w(t) = exp(−σ (t − t_trig))`` after the trigger, ``σ = ln(1/end)/T`` (the window reaches
   ``end`` one record length T after the trigger). A window ``e^{−σt}`` on a free decay
   ``Σ A_r e^{p_r t}`` shifts every pole to ``p_r − σ`` and leaves the residues unchanged, so
   the identified poles are corrected by ``+σ`` (:func:`correct_window_damping`): the
   damping the window adds, ``Δζ ≈ σ/ω_n``, is removed.
3. :func:`frf_matrix` — per hit direction, the windowed hits go to :class:`pyFRF.FRF`, which
   averages the cross and auto spectra over the accepted hits and returns H1 = S_xf/S_ff,
   H2 = S_xx/S_fx and the coherence γ² = |S_xf|²/(S_ff S_xx): the full 3×3 receptance matrix
   H[output, input] (m/N) over frequency.
4. :func:`peak_picking` — the thesis' criteria on every FRF: the imaginary part has an
   extremum; the real part has a local maximum and a local minimum of opposite signs on
   either side; the coherence there exceeds 0.75.
5. :func:`stabilization` and :func:`select_poles` — poles by the least-squares
   complex-frequency (LSCF, common-denominator over all measured FRFs) method of sdypy-EMA for
   model orders 2…2·``max_order``; a pole is *stable* when the previous order has a pole
   within ``tol_f`` in frequency, ``tol_zeta`` in damping and with residue vectors of MAC ≥
   ``mac_min`` (residues by LSFD at each order). Stable poles are grouped by frequency;
   groups of at least ``min_stable`` orders are physical modes.
6. :func:`modal_constants` and :func:`modes_table` — residues by LSFD (sdypy-EMA, with lower
   and upper residual terms), the FRF synthesized from them, and per mode the residue matrix
   ``A_r = φ_r φ_rᵀ/(2jω_d m_r)`` turned into a unit shape φ_r, a modal mass m_r and a modal
   stiffness ``k_r = m_r ω_r²`` at the tool tip — the same definitions as the virtual cell
   (:meth:`robomill.synth.cell.VirtualCell.receptance_m_per_N`).

FRF convention (as in sdypy-EMA): ``H(ω) = Σ_r A_r/(jω − p_r) + A_r*/(jω − p_r*)``
(:func:`synthesize_frf`).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
import scipy.signal
import xarray as xr

AXES = ("X", "Y", "Z")
"""Output (accelerometer) and input (hammer) directions, base axes."""
CHANNELS = ("force_N", "ax_ms2", "ay_ms2", "az_ms2")
"""Channels of an impact record."""
COMPLEX_VARS = ("H", "H2", "H_synth")
"""Complex FRF variables, stored in netCDF as ``<name>_real`` and ``<name>_imag``."""


# ---- 1. hit rejection -------------------------------------------------------------------------
@dataclass(frozen=True)
class HitCheck:
    """Outcome of :func:`check_hit`: accepted or not, why, and the trigger sample."""

    accepted: bool
    reason: str
    trigger_index: int


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Start and end (exclusive) of every run of True in a boolean array."""
    d = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1), strict=True))


def check_hit(force_N: np.ndarray, accel_ms2: np.ndarray, fs_hz: float, *,
              trigger_fraction: float = 0.05, double_hit_fraction: float = 0.1,
              overload_samples: int = 3, flat_rtol: float = 1e-4,
              force_range_N: float | None = None,
              accel_range_ms2: float | None = None,
              channels: Sequence[str] | None = None) -> HitCheck:
    """Accept or reject one hit (thesis §3.3: double hits and overloads are rejected).

    Parameters
    ----------
    force_N
        Hammer force ``(n,)``.
    accel_ms2
        Accelerations ``(n, k)``: any number of response channels (``(n,)`` for one).
    fs_hz
        Sampling rate.
    trigger_fraction
        The trigger is the first sample whose force exceeds this fraction of the peak.
    double_hit_fraction
        Force pulses are the runs above this fraction of the peak; more than one is a double
        hit.
    overload_samples
        A channel whose |value| stays within ``flat_rtol`` of its maximum for this many
        consecutive samples is clipped (overload).
    force_range_N, accel_range_ms2
        Measurement ranges of the channels, when known: a sample reaching its range (within
        ``flat_rtol``) is an overload even if too short to show a flat top. Unknown
        (``None``): overload is detected from flat-topping (clipping) alone.
    channels
        Names of the channels in messages: force first, then one per response column
        (default ``force_N, ax_ms2, ay_ms2, az_ms2``).

    Returns
    -------
    HitCheck
        ``reason`` is ``"ok"`` or a sentence naming the defect.
    """
    force = np.asarray(force_N, float)
    acc = np.asarray(accel_ms2, float).reshape(force.size, -1)
    peak = float(np.max(force))
    if peak <= 0:
        return HitCheck(False, "no impact: the force never rises above zero", 0)
    trigger = int(np.argmax(force > trigger_fraction * peak))
    ranges = [force_range_N] + [accel_range_ms2] * acc.shape[1]
    names = list(channels) if channels is not None else list(CHANNELS)
    for name, x, rng in zip(names, [force, *acc.T], ranges, strict=False):
        ax = np.abs(x)
        top = ax.max()
        if top == 0:
            continue
        if rng is not None and top >= (1 - flat_rtol) * rng:
            n_at = int(np.sum(ax >= (1 - flat_rtol) * rng))
            return HitCheck(False, f"overload: channel {name} reaches its range ±{rng:.4g} "
                                   f"({n_at} samples)", trigger)
        longest = max((e - s for s, e in _runs(ax >= (1 - flat_rtol) * top)), default=0)
        if longest >= overload_samples:
            return HitCheck(False, f"overload: channel {name} is clipped at ±{top:.4g} for "
                                   f"{longest} consecutive samples", trigger)
    pulses = _runs(force > double_hit_fraction * peak)
    if len(pulses) > 1:
        s2, e2 = pulses[1]
        second = float(force[s2:e2].max())
        dt_ms = 1e3 * (s2 - pulses[0][1]) / fs_hz
        return HitCheck(False, f"double hit: a second impact of {second:.1f} N "
                               f"({second / peak:.2f} of the first) {dt_ms:.1f} ms after the "
                               "first pulse ends", trigger)
    return HitCheck(True, "ok", trigger)


# ---- 2. windows ---------------------------------------------------------------------------------
def exponential_window_rate(n: int, fs_hz: float, end_value: float) -> float:
    """Decay rate σ [1/s] of the exponential window: ``e^{−σT} = end_value``, T = n/fs."""
    return float(np.log(1.0 / end_value) / (n / fs_hz))


def impact_windows(n: int, fs_hz: float, trigger_index: int, *, force_window_s: float,
                   exponential_end: float,
                   taper_s: float | None = None) -> tuple[np.ndarray, np.ndarray, float]:
    """Force and exponential windows for one hit record of ``n`` samples.

    The force window is 1 up to ``force_window_s`` after the trigger, then a half-Hann taper
    of ``taper_s`` (default ``force_window_s/4``), then 0. The exponential window is 1 before
    the trigger and ``exp(−σ (t − t_trig))`` after it (:func:`scipy.signal.windows.exponential`),
    σ from :func:`exponential_window_rate`. Apply the exponential window to force and response
    alike.

    Returns
    -------
    w_force, w_exp, sigma
    """
    sigma = exponential_window_rate(n, fs_hz, exponential_end)
    n_on = min(n, trigger_index + int(round(force_window_s * fs_hz)))
    n_taper = max(2, int(round((taper_s if taper_s is not None else force_window_s / 4)
                               * fs_hz)))
    w_force = np.zeros(n)
    w_force[:n_on] = 1.0
    taper = scipy.signal.windows.hann(2 * n_taper, sym=False)[n_taper:]
    m = min(n_taper, n - n_on)
    w_force[n_on:n_on + m] = taper[:m]
    w_exp = np.ones(n)
    tau = fs_hz / sigma  # decay constant in samples
    w_exp[trigger_index:] = scipy.signal.windows.exponential(n - trigger_index, center=0,
                                                              tau=tau, sym=False)
    return w_force, w_exp, sigma


# ---- 3. points and FRFs over any test layout ---------------------------------------------------
AXIS_CODE = {"X": 1, "Y": 2, "Z": 3}
"""UFF direction codes of the base axes (a negative code is the negative axis)."""
TOOLTIP = ((1, 1), (1, 2), (1, 3))
"""The tool-tip points of the thesis layout: node 1, +X, +Y, +Z."""


def parse_direction(text: str | int) -> int:
    """A direction as a signed UFF code: ``"X"``/``"+X"``/``1`` → 1, ``"-Y"``/``-2`` → −2.

    Raises
    ------
    ValueError
        Anything but ±X, ±Y, ±Z (or ±1, ±2, ±3).
    """
    if isinstance(text, (int, np.integer)) and not isinstance(text, bool):
        if abs(int(text)) in (1, 2, 3):
            return int(text)
    elif isinstance(text, str):
        t = text.strip().upper()
        sign = -1 if t.startswith("-") else 1
        t = t.lstrip("+-")
        if t in AXIS_CODE:
            return sign * AXIS_CODE[t]
    raise ValueError(f"direction {text!r} is not one of X, Y, Z, +X, -X, +Y, -Y, +Z, -Z")


def point_label(node: int, dir_code: int) -> str:
    """Label of a measurement point ``(node, ±direction)``: the axis letter, ``-`` before it
    for a negative direction, the node number before that unless it is node 1 (so the
    thesis layout keeps its labels ``X, Y, Z``): ``(1, 2)`` → ``"Y"``, ``(3, -1)`` →
    ``"3-X"``."""
    axis = "XYZ"[abs(int(dir_code)) - 1]
    return f"{'' if int(node) == 1 else int(node)}{'-' if dir_code < 0 else ''}{axis}"


def _point_key(p: tuple[int, int]) -> tuple[int, int, int]:
    return (int(p[0]), abs(int(p[1])), int(p[1]) < 0)


def frf_coords(freq_hz: np.ndarray, outputs: Sequence[tuple[int, int]] = TOOLTIP,
               inputs: Sequence[tuple[int, int]] = TOOLTIP) -> dict:
    """Labelled coordinates ``output, input, frequency`` of an FRF dataset.

    ``output``/``input`` carry the point labels (:func:`point_label`); ``output_node``,
    ``output_dir``, ``input_node``, ``input_dir`` the node numbers and signed UFF direction
    codes (X=1, Y=2, Z=3; negative: the negative axis) of each response and reference point.
    """
    out: dict = {}
    for dim, pts, what in (("output", outputs, "response (accelerometer)"),
                           ("input", inputs, "reference (hammer)")):
        pts = [(int(n), int(d)) for n, d in pts]
        out[dim] = (dim, [point_label(*p) for p in pts],
                    {"units": "1", "long_name": f"{what} point: node and direction"})
        out[f"{dim}_node"] = (dim, np.array([p[0] for p in pts]),
                              {"units": "1", "long_name": f"{what} node number"})
        out[f"{dim}_dir"] = (dim, np.array([p[1] for p in pts]),
                             {"units": "1", "long_name": f"{what} direction, UFF code "
                                                        "(X=1, Y=2, Z=3, negative axis < 0)"})
    out["frequency"] = ("frequency", np.asarray(freq_hz, float),
                        {"units": "Hz", "long_name": "frequency"})
    return out


def points(ds: xr.Dataset, dim: str) -> list[tuple[int, int]]:
    """The ``(node, direction code)`` points along ``output`` or ``input`` of an FRF dataset
    (datasets without node coordinates: node 1, the axis of each label)."""
    if f"{dim}_node" in ds.coords:
        return [(int(n), int(d)) for n, d in zip(ds[f"{dim}_node"].values,
                                                 ds[f"{dim}_dir"].values, strict=True)]
    return [(1, parse_direction(str(v))) for v in ds[dim].values]


@dataclass
class HitGroup:
    """Accepted hits of one reference point measured with the same response points.

    ``hits`` are ``(force_N (n,), accel_ms2 (n, k), trigger_index)``; ``responses`` the k
    response points ``(node, direction code)``, in the order of the acceleration columns.
    """

    reference: tuple[int, int]
    responses: tuple[tuple[int, int], ...]
    hits: list = field(default_factory=list)


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


def check_and_group(hits: Sequence, *, trigger_fraction: float = 0.05,
                    double_hit_fraction: float = 0.1, overload_samples: int = 3,
                    force_range_N: float | None = None,
                    accel_range_ms2: float | None = None) -> tuple[pd.DataFrame, list[HitGroup]]:
    """Check every hit (:func:`check_hit`) and group the accepted ones by reference point and
    response points (:class:`HitGroup`, input of :func:`frf_from_groups`).

    Parameters
    ----------
    hits
        ``(record, meta)`` pairs: a :class:`robomill.io.impact.HitRecord` and its manifest
        metadata (``path``, ``hit``, ``range_N``, ``range_ms2``; the per-file ranges win over
        ``force_range_N``/``accel_range_ms2``; neither: overload by flat-topping alone).

    Returns
    -------
    table
        One row per hit: ``direction, hit, path, accepted, reason, peak_force_N, trigger_s,
        reference, responses``.
    groups
        The accepted hits, grouped, in order of first appearance.
    """
    rows, groups = [], {}
    for rec, meta in hits:
        r_n = meta.get("range_N") if meta.get("range_N") is not None else force_range_N
        r_a = meta.get("range_ms2") if meta.get("range_ms2") is not None else accel_range_ms2
        names = ["force_N", *(rec.columns or [point_label(*p) for p in rec.responses])]
        c = check_hit(rec.force_N, rec.accel_ms2, rec.fs_hz, trigger_fraction=trigger_fraction,
                      double_hit_fraction=double_hit_fraction,
                      overload_samples=overload_samples, force_range_N=r_n,
                      accel_range_ms2=r_a, channels=names)
        ref = tuple(rec.reference)
        rows.append({"direction": point_label(1, ref[1]), "hit": meta.get("hit"),
                     "path": meta.get("path", rec.source), "accepted": c.accepted,
                     "reason": c.reason, "peak_force_N": float(np.max(rec.force_N)),
                     "trigger_s": c.trigger_index / rec.fs_hz,
                     "reference": point_label(*ref),
                     "responses": " ".join(point_label(*p) for p in rec.responses)})
        key = (ref, tuple(rec.responses))
        g = groups.setdefault(key, HitGroup(ref, tuple(rec.responses), []))
        if c.accepted:
            g.hits.append((rec.force_N, rec.accel_ms2, c.trigger_index))
    return pd.DataFrame(rows), list(groups.values())


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
    hit, on the FRF lines of ``ds`` (the input of :func:`band_from_data`)."""
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


HIT_COLUMNS = ["direction", "hit", "path", "accepted", "reason", "peak_force_N", "trigger_s",
               "reference", "responses"]
"""Columns of ``results/modal/hits.csv``."""


def hit_table_empty() -> pd.DataFrame:
    """The hit table of a study whose impact files are FRFs (no hit to check)."""
    return pd.DataFrame(columns=HIT_COLUMNS)


def empty_traces() -> xr.Dataset:
    """The hit-trace artefact of a study whose impact files are FRFs (no hit records)."""
    return xr.Dataset(coords={"hit_file": ("hit_file", np.array([], dtype=str),
                                           {"units": "1", "long_name": "raw file of the hit"})})


def hit_traces(hits: Sequence, table: pd.DataFrame, fs_hz: float,
               keep_s: float = 1.0) -> xr.Dataset:
    """The first ``keep_s`` of every hit for the chapter's plots: ``force_N`` and the first
    response along each of +X, +Y, +Z (``ax_ms2, ay_ms2, az_ms2``; NaN where that axis was
    not measured) over ``hit_file, time``."""
    n_keep = min(min(r.force_N.size for r, _ in hits), int(round(keep_s * fs_hz)))
    data = np.full((4, len(hits), n_keep), np.nan)
    for k, (rec, _) in enumerate(hits):
        data[0, k] = rec.force_N[:n_keep]
        for axis in (1, 2, 3):
            cols = [j for j, p in enumerate(rec.responses) if abs(p[1]) == axis]
            if cols:
                j = cols[0]
                data[axis, k] = np.sign(rec.responses[j][1]) * rec.accel_ms2[:n_keep, j]
    names = [("force_N", "N", "hammer force"), ("ax_ms2", "m/s^2", "tool-tip acceleration X"),
             ("ay_ms2", "m/s^2", "tool-tip acceleration Y"),
             ("az_ms2", "m/s^2", "tool-tip acceleration Z")]
    return xr.Dataset(
        {name: (("hit_file", "time"), data[c], {"units": unit, "long_name": long})
         for c, (name, unit, long) in enumerate(names)},
        coords={"hit_file": ("hit_file", table["path"].tolist(),
                             {"units": "1", "long_name": "raw file of the hit"}),
                "time": ("time", np.arange(n_keep) / fs_hz, {"units": "s", "long_name": "time"}),
                "direction": ("hit_file", table["direction"].tolist(),
                              {"units": "1", "long_name": "hit direction"}),
                "accepted": ("hit_file", table["accepted"].to_numpy(),
                             {"units": "1", "long_name": "hit accepted"})})


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


def split_complex(ds: xr.Dataset) -> xr.Dataset:
    """Complex variables → ``<name>_real`` and ``<name>_imag`` (netCDF4 has no complex type)."""
    ds = ds.copy()
    for name in list(ds.data_vars):
        if np.iscomplexobj(ds[name].values):
            attrs = dict(ds[name].attrs)
            for part, fn in (("real", np.real), ("imag", np.imag)):
                ds[f"{name}_{part}"] = ds[name].copy(data=fn(ds[name].values)).assign_attrs(
                    {**attrs, "long_name": f"{part} part of {attrs.get('long_name', name)}"})
            ds = ds.drop_vars(name)
    return ds


def join_complex(ds: xr.Dataset) -> xr.Dataset:
    """Inverse of :func:`split_complex`: ``<name>_real`` + ``<name>_imag`` → complex ``name``."""
    ds = ds.copy()
    for name in [v[:-5] for v in ds.data_vars if str(v).endswith("_real")]:
        if f"{name}_imag" in ds:
            attrs = dict(ds[f"{name}_real"].attrs)
            attrs["long_name"] = attrs.get("long_name", name).removeprefix("real part of ")
            ds[name] = (ds[f"{name}_real"] + 1j * ds[f"{name}_imag"]).assign_attrs(attrs)
            ds = ds.drop_vars([f"{name}_real", f"{name}_imag"])
    return ds


# ---- 4. thesis peak picking -------------------------------------------------------------------
def peak_picking(ds: xr.Dataset, *, band_hz: Sequence[float], coherence_min: float = 0.75,
                 prominence: float = 0.05, real_window_hz: float = 3.0) -> pd.DataFrame:
    """Natural-frequency candidates by the thesis' criteria, on each measured FRF.

    A candidate is an extremum of Im H (a peak of |Im H| with prominence at least
    ``prominence`` × its largest value in the band). Criteria (thesis §3.3):
    ``real_sign_change`` — the nearest local extrema of Re H below and above it (within
    ``real_window_hz``) are a maximum and a minimum of opposite signs; ``coherence_ok`` —
    γ² > ``coherence_min`` at the candidate (FRFs imported without coherence: NaN, and the
    criterion is not applied). ``natural_frequency`` = both.

    Returns
    -------
    pandas.DataFrame
        ``output, input, f_hz, imag_extremum_m_N, real_below_m_N, real_above_m_N, coherence,
        real_sign_change, coherence_ok, natural_frequency``.
    """
    f = ds["frequency"].values
    sel = np.flatnonzero((f >= band_hz[0]) & (f <= band_hz[1]))
    df = f[1] - f[0]
    w = max(2, int(round(real_window_hz / df)))
    rows = []
    for o in ds["output"].values.tolist():
        for i in ds["input"].values.tolist():
            h = ds["H"].sel(output=o, input=i).values[sel]
            if not np.isfinite(h).any():
                continue  # a pair this layout did not measure
            coh = (ds["coherence"].sel(output=o, input=i).values[sel] if "coherence" in ds
                   else np.full(sel.size, np.nan))
            im, re = h.imag, h.real
            peaks, _ = scipy.signal.find_peaks(np.abs(im), prominence=prominence
                                               * np.nanmax(np.abs(im)))
            maxima = set(scipy.signal.argrelextrema(re, np.greater)[0])
            minima = set(scipy.signal.argrelextrema(re, np.less)[0])
            extrema = np.array(sorted(maxima | minima))
            for k in peaks:
                below = extrema[(extrema < k) & (extrema >= k - w)]
                above = extrema[(extrema > k) & (extrema <= k + w)]
                lo = int(below[-1]) if below.size else None
                hi = int(above[0]) if above.size else None
                sign_change = (lo is not None and hi is not None
                               and ((lo in maxima and hi in minima)
                                    or (lo in minima and hi in maxima))
                               and np.sign(re[lo]) != np.sign(re[hi]))
                rows.append({"output": o, "input": i, "f_hz": float(f[sel][k]),
                             "imag_extremum_m_N": float(im[k]),
                             "real_below_m_N": float(re[lo]) if lo is not None else np.nan,
                             "real_above_m_N": float(re[hi]) if hi is not None else np.nan,
                             "coherence": float(coh[k]),
                             "real_sign_change": bool(sign_change),
                             "coherence_ok": bool(np.isnan(coh[k]) or coh[k] > coherence_min)})
    out = pd.DataFrame(rows, columns=["output", "input", "f_hz", "imag_extremum_m_N",
                                      "real_below_m_N", "real_above_m_N", "coherence",
                                      "real_sign_change", "coherence_ok"])
    out["natural_frequency"] = out["real_sign_change"] & out["coherence_ok"]
    return out


# ---- 5. poles: LSCF stabilization chart ---------------------------------------------------------
def _frf_rows(ds: xr.Dataset, var: str = "H") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The measured FRFs as rows ``(n_measured, nf)`` (output-major; a pair is measured when
    it has a finite value above DC), their frequencies (DC dropped), and the flat indices of
    the measured pairs in the ``(output, input)`` grid."""
    f = ds["frequency"].values
    h = ds[var].transpose("output", "input", "frequency").values
    h = h.reshape(h.shape[0] * h.shape[1], -1)
    keep = f > 0
    measured = np.flatnonzero(np.isfinite(h[:, keep]).any(axis=1))
    return h[measured][:, keep], f[keep], measured


def _lsfd(poles: np.ndarray, frf: np.ndarray, freq: np.ndarray, band_hz: Sequence[float]):
    """Residues (n_frf, n_poles) and reconstructed FRF by sdypy-EMA's LSFD in the band."""
    from sdypy.EMA.EMA import LSFD

    lo = int(np.searchsorted(freq, band_hz[0]))
    hi = int(np.searchsorted(freq, band_hz[1], side="right"))
    with warnings.catch_warnings(), np.errstate(divide="ignore", invalid="ignore"):
        warnings.simplefilter("ignore", RuntimeWarning)
        A, H, LR, UR = LSFD(np.asarray(poles), frf, freq, True, True, lo, hi,
                            frf_form="receptance")
    return A, H, LR, UR


def _mac(a: np.ndarray, b: np.ndarray) -> float:
    """Modal assurance criterion of two complex vectors (sdypy-EMA's ``MAC``)."""
    from sdypy.EMA import MAC

    with warnings.catch_warnings():  # MAC stores |a^H b|^2/(a^H a b^H b) in a real array
        warnings.simplefilter("ignore", np.exceptions.ComplexWarning)
        return float(np.real(MAC(a, b)))


def pole_f_zeta(poles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Natural frequency [Hz] and damping ratio of poles ``p = −ζω_n ± jω_n√(1−ζ²)``."""
    p = np.asarray(poles, complex)
    wn = np.abs(p)
    with np.errstate(divide="ignore", invalid="ignore"):
        return wn / (2 * np.pi), -p.real / wn


def stabilization(ds: xr.Dataset, *, band_hz: Sequence[float], max_order: int = 40,
                  tol_f: float = 0.01, tol_zeta: float = 0.05, mac_min: float = 0.95,
                  zeta_max: float = 0.2) -> pd.DataFrame:
    """Stabilization chart: LSCF poles (sdypy-EMA) at every model order, with their status.

    For each order (denominator degree 2, 4, …, 2·``max_order``) the poles with positive
    imaginary part, frequency in ``band_hz`` and 0 < ζ < ``zeta_max`` are kept; their residues
    over all measured FRFs (any layout: :func:`_frf_rows`) come from LSFD at that order.
    Each pole is compared with the nearest pole of the previous order: status ``new``,
    ``f`` (frequency within ``tol_f`` relative), ``fd`` (and damping within ``tol_zeta``
    relative), ``stable`` (and MAC of the residue vectors ≥ ``mac_min``).

    Returns
    -------
    pandas.DataFrame
        ``order, f_hz, zeta, pole_real, pole_imag, status`` (poles of the windowed FRFs).
    """
    from sdypy import EMA

    frf, freq, _ = _frf_rows(ds)
    frf = np.nan_to_num(frf)
    model = EMA.Model(frf=frf, freq=freq, lower=band_hz[0], upper=band_hz[1],
                      pol_order_high=int(max_order), frf_form="receptance")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model.get_poles(method="lscf", show_progress=False)
    rows = []
    prev = None
    for idx, poles in enumerate(model.all_poles):
        order = 2 * (idx + 1)
        fp, zp = pole_f_zeta(poles)
        keep = ((poles.imag > 0) & (fp >= band_hz[0]) & (fp <= band_hz[1]) & (zp > 0)
                & (zp < zeta_max))
        p = poles[keep]
        if p.size == 0:
            prev = None
            continue
        A, *_ = _lsfd(p, model.frf, model.freq, band_hz)
        fk, zk = pole_f_zeta(p)
        for m in range(p.size):
            status = "new"
            if prev is not None:
                pf, pz, pA = prev
                j = int(np.argmin(np.abs(pf - fk[m])))
                if abs(pf[j] - fk[m]) <= tol_f * fk[m]:
                    status = "f"
                    if abs(pz[j] - zk[m]) <= tol_zeta * zk[m]:
                        status = "fd"
                        if _mac(A[:, m], pA[:, j]) >= mac_min:
                            status = "stable"
            rows.append({"order": order, "f_hz": fk[m], "zeta": zk[m],
                         "pole_real": p[m].real, "pole_imag": p[m].imag, "status": status})
        prev = (fk, zk, A)
    return pd.DataFrame(rows, columns=["order", "f_hz", "zeta", "pole_real", "pole_imag",
                                       "status"])


def select_poles(stab: pd.DataFrame, *, cluster_tol: float = 0.01,
                 min_stable: int = 5) -> pd.DataFrame:
    """Physical poles from a stabilization chart.

    Stable poles are sorted by frequency and split into groups where consecutive
    frequencies differ by more than ``cluster_tol`` (relative); a group with poles at
    ``min_stable`` or more distinct orders is a mode. Its representative is the pole of the
    group nearest the group's median frequency and median damping (highest order on ties).

    Returns
    -------
    pandas.DataFrame
        ``f_hz, zeta, pole_real, pole_imag, order, n_stable`` per mode, by frequency.
    """
    st = stab[stab["status"] == "stable"].sort_values("f_hz").reset_index(drop=True)
    if st.empty:
        return pd.DataFrame(columns=["f_hz", "zeta", "pole_real", "pole_imag", "order",
                                     "n_stable"])
    f = st["f_hz"].to_numpy()
    breaks = np.flatnonzero(np.diff(f) > cluster_tol * f[1:]) + 1
    out = []
    for g in np.split(np.arange(len(st)), breaks):
        grp = st.iloc[g]
        n_orders = grp["order"].nunique()
        if n_orders < min_stable:
            continue
        fm, zm = grp["f_hz"].median(), grp["zeta"].median()
        score = np.abs(grp["f_hz"] - fm) / fm + np.abs(grp["zeta"] - zm) / zm
        best = grp.assign(score=score).sort_values(["score", "order"],
                                                   ascending=[True, False]).iloc[0]
        out.append({"f_hz": best["f_hz"], "zeta": best["zeta"],
                    "pole_real": best["pole_real"], "pole_imag": best["pole_imag"],
                    "order": int(best["order"]), "n_stable": int(n_orders)})
    return pd.DataFrame(out)


def correct_window_damping(poles: np.ndarray, sigma_per_s: float) -> np.ndarray:
    """Remove the exponential window's decay from identified poles: ``p + σ``.

    The window ``e^{−σt}`` (from the trigger) turns every term ``A e^{pt}`` of the impulse
    response into ``A e^{(p−σ)t}``, i.e. adds ``Δζ ≈ σ/ω_n`` of damping.
    """
    return np.asarray(poles, complex) + float(sigma_per_s)


# ---- 6. residues, mode shapes, modal mass and stiffness ------------------------------------------
def synthesize_frf(poles: np.ndarray, residues: np.ndarray, f_hz: np.ndarray) -> np.ndarray:
    """FRF from poles and residues: ``H(ω) = Σ_r A_r/(jω − p_r) + A_r*/(jω − p_r*)``.

    ``residues`` has shape ``(..., n_modes)`` (e.g. ``(3, 3, n_modes)``); returns
    ``(..., len(f_hz))``.
    """
    jw = 2j * np.pi * np.asarray(f_hz, float)
    p = np.asarray(poles, complex)
    A = np.asarray(residues, complex)
    return (np.einsum("...r,rf->...f", A, 1.0 / (jw[None, :] - p[:, None]))
            + np.einsum("...r,rf->...f", A.conj(), 1.0 / (jw[None, :] - p.conj()[:, None])))


def modal_residues(f_hz: Sequence[float], zeta: Sequence[float], k_N_m: Sequence[float],
                   shapes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Poles and residue matrices of the cell's modal model (unit shapes, modal stiffness).

    ``p_r = −ζ_r ω_r + jω_r√(1−ζ_r²)``, ``A_r = φ_r φ_rᵀ/(2jω_d m_r)``, ``m_r = k_r/ω_r²``,
    so that :func:`synthesize_frf` equals ``Σ φφᵀ/(k(1 − r² + 2jζr))``.

    Returns
    -------
    poles (n_modes,), residues (3, 3, n_modes)
    """
    wn = 2 * np.pi * np.asarray(f_hz, float)
    z = np.asarray(zeta, float)
    wd = wn * np.sqrt(1 - z**2)
    m = np.asarray(k_N_m, float) / wn**2
    phi = np.asarray(shapes, float)
    A = np.einsum("ri,rj->ijr", phi, phi) / (2j * wd * m)
    return -z * wn + 1j * wd, A


def modal_constants(ds: xr.Dataset, poles: np.ndarray, *,
                    band_hz: Sequence[float]) -> tuple[np.ndarray, np.ndarray]:
    """Residues ``(n_output, n_input, n_modes)`` of the measured FRFs at the given (windowed)
    poles by LSFD (sdypy-EMA, lower and upper residuals), and the synthesized FRF
    ``(n_output, n_input, n_freq)`` on the dataset's frequencies (NaN outside the band, at
    DC and for pairs the layout did not measure)."""
    frf, freq, measured = _frf_rows(ds)
    A, H, _, _ = _lsfd(np.asarray(poles, complex), np.nan_to_num(frf), freq, band_hz)
    n_o, n_i = ds.sizes["output"], ds.sizes["input"]
    f_all = ds["frequency"].values
    res = np.full((n_o * n_i, A.shape[1]), np.nan + 0j)
    res[measured] = A
    synth = np.full((n_o * n_i, f_all.size), np.nan + 0j)
    inside = (freq >= band_hz[0]) & (freq <= band_hz[1])
    rows = synth[measured]
    rows[:, np.flatnonzero(f_all > 0)[inside]] = H[:, inside]
    synth[measured] = rows
    return res.reshape(n_o, n_i, -1), synth.reshape(n_o, n_i, -1)


def _unit_phase(v: np.ndarray) -> np.ndarray:
    """A complex vector scaled to unit norm and turned so that its largest component is real
    and positive."""
    v = np.asarray(v, complex)
    k = int(np.nanargmax(np.abs(v)))
    return v / np.linalg.norm(v) * np.exp(-1j * np.angle(v[k]))


def driving_points(outputs: Sequence[tuple[int, int]],
                   inputs: Sequence[tuple[int, int]]) -> list[tuple[int, int, int]]:
    """Driving points of a layout: ``(i_output, i_input, sign)`` where response and reference
    are the same node and axis (``sign`` −1 when their directions are opposite)."""
    out = []
    for i, (no, do) in enumerate(outputs):
        for j, (ni, di) in enumerate(inputs):
            if no == ni and abs(do) == abs(di):
                out.append((i, j, int(np.sign(do) * np.sign(di))))
    return out


@dataclass
class ModeShapes:
    """Complex unit mode shapes over the measured points (see :func:`mode_shapes`)."""

    points: list[tuple[int, int]]
    """``(node, direction code)`` of each component."""
    shapes: np.ndarray
    """``(n_modes, n_points)`` complex, unit norm, largest component real positive."""
    m_modal_kg: np.ndarray
    """Modal mass of the unit shape (NaN without a driving point)."""
    driving_point: str
    """Label of the driving point used for the scaling ('' when none)."""


def mode_shapes(poles: np.ndarray, residues: np.ndarray,
                outputs: Sequence[tuple[int, int]],
                inputs: Sequence[tuple[int, int]]) -> ModeShapes:
    """Mode shapes over the measured points and, where a driving point exists, modal masses.

    With ``R = 2jω_d A_r`` ≈ ``u uᵀ`` (``u`` the mass-normalised shape; Ewins, *Modal
    Testing*, 2000, §4.4: residue ``A_jk = u_j u_k/(2jω_d)`` for a lightly damped mode):

    * one reference point: the shape over the response points is the column ``R[:, ref]``;
    * one response point (roving hammer): the row ``R[resp, :]`` over the reference points;
    * several of both: the column of the driving-point reference (the reference with the
      largest residues when there is none).

    The shape is normalised to unit norm (complex; :func:`_unit_phase`). With a driving point
    ``p`` (same node and axis in response and reference), ``u_p² = R_pp`` scales it: the
    modal mass of the unit shape is ``m = |R_pp| / ‖ψ‖²`` with the sign of ``Re R_pp``
    (negative: non-physical). Without one the shape stays unscaled and ``m`` is NaN.
    """
    outputs = [tuple(p) for p in outputs]
    inputs = [tuple(p) for p in inputs]
    dps = driving_points(outputs, inputs)
    if len(inputs) == 1:
        pts, axis = outputs, "column"
    elif len(outputs) == 1:
        pts, axis = inputs, "row"
    else:
        pts, axis = outputs, "column"
    shapes = np.full((len(poles), len(pts)), np.nan + 0j)
    masses = np.full(len(poles), np.nan)
    dp_label = ""
    for r, p in enumerate(np.asarray(poles, complex)):
        R = 2j * p.imag * residues[:, :, r]
        if dps:
            i, j, sgn = max(dps, key=lambda d: np.abs(np.nan_to_num(R[d[0], d[1]])))
            dp_label = point_label(*outputs[i])
        else:
            i = j = None
            sgn = 1
        if axis == "column":
            jj = j if j is not None else int(np.nanargmax(np.nansum(np.abs(R), axis=0)))
            psi = R[:, jj]
        else:
            ii = i if i is not None else 0
            psi = R[ii, :]
        # points with an unmeasured pair get NaN; the shape over the others is normalised
        ok = np.isfinite(psi)
        if ok.any():
            shapes[r, ok] = _unit_phase(psi[ok])
        if i is not None and ok.any():
            Rpp = sgn * R[i, j]
            masses[r] = np.sign(Rpp.real) * np.abs(Rpp) / np.sum(np.abs(psi[ok]) ** 2)
    return ModeShapes(list(pts), shapes, masses, dp_label)


def mac_matrix(shapes: np.ndarray) -> np.ndarray:
    """Modal assurance criterion between every pair of (complex) mode shapes ``(n_modes,
    n_points)``: ``MAC_rs = |φ_rᴴ φ_s|² / ((φ_rᴴ φ_r)(φ_sᴴ φ_s))`` (Allemang & Brown 1982),
    over the points where both are measured."""
    phi = np.nan_to_num(np.asarray(shapes, complex))
    num = np.abs(phi.conj() @ phi.T) ** 2
    nrm = np.real(np.sum(phi.conj() * phi, axis=1))
    with np.errstate(divide="ignore", invalid="ignore"):
        return num / np.outer(nrm, nrm)


def _is_tooltip(outputs, inputs) -> bool:
    return ([tuple(p) for p in outputs] == list(TOOLTIP)
            and [tuple(p) for p in inputs] == list(TOOLTIP))


MODE_COLUMNS = ["mode", "f_n_hz", "zeta", "k_modal_N_m", "m_modal_kg", "shape_x", "shape_y",
                "shape_z", "zeta_windowed", "rank1", "n_stable", "driving_point", "coherence",
                "physical", "flags"]
"""Columns of the mode table (``results/modal/modes.csv``)."""


def modes_table(poles: np.ndarray, residues: np.ndarray, *,
                poles_measured: np.ndarray | None = None,
                n_stable: Sequence[int] | None = None,
                outputs: Sequence[tuple[int, int]] = TOOLTIP,
                inputs: Sequence[tuple[int, int]] = TOOLTIP,
                coherence: Sequence[float] | None = None,
                coherence_min: float = 0.75) -> tuple[pd.DataFrame, ModeShapes]:
    """Modal parameters from (window-corrected) poles and residues, and the mode shapes.

    The 3×3 tool-tip matrix (outputs = inputs = node 1 +X, +Y, +Z): ``R = 2jω_d A_r`` ≈
    ``φφᵀ/m`` (real, symmetric, rank one for a proportionally damped mode); its largest
    eigenpair ``(λ, v)`` of the symmetric real part gives the unit shape ``φ = v`` (largest
    component positive), ``m = 1/λ`` and ``k = m ω_n²``; ``rank1`` = λ / Σ|eigenvalues|.
    Any other layout: :func:`mode_shapes` (``rank1`` NaN); ``m`` and ``k`` only with a
    driving point.

    Sanity flags (column ``flags``, ``physical`` False when any): a negative modal mass or
    stiffness (the driving-point residue has the wrong sign: a sign or direction mix-up, or a
    computational pole); no driving point (no modal mass or stiffness); the mean coherence of
    the measured FRFs at the natural frequency below ``coherence_min``.

    Returns
    -------
    pandas.DataFrame
        :data:`MODE_COLUMNS`; ``shape_x, shape_y, shape_z`` are the real unit shape at node 1
        where those points were measured (NaN otherwise).
    ModeShapes
        The complex shapes over all measured points.
    """
    f, z = pole_f_zeta(poles)
    tooltip = _is_tooltip(outputs, inputs)
    general = mode_shapes(poles, residues, outputs, inputs)
    shapes = general.shapes.copy()
    rows = []
    for r, p in enumerate(np.asarray(poles, complex)):
        wn = 2 * np.pi * f[r]
        flags = []
        if tooltip:
            R = 2j * p.imag * residues[:, :, r]
            S = np.real(R + R.T) / 2
            lam, vec = np.linalg.eigh(S)
            i = int(np.argmax(np.abs(lam)))
            v = vec[:, i] * np.sign(vec[np.argmax(np.abs(vec[:, i])), i])
            m = 1.0 / lam[i]
            rank1 = float(np.abs(lam[i]) / np.sum(np.abs(lam)))
            comp = {d: v[d - 1] for d in (1, 2, 3)}
            shapes[r] = v
            dp = "X, Y, Z"
        else:
            m = general.m_modal_kg[r]
            rank1 = np.nan
            comp = {abs(d): (np.sign(d) * shapes[r, k]).real
                    for k, (n, d) in enumerate(general.points) if n == 1}
            dp = general.driving_point
            if not dp:
                flags.append("no driving point: shape unscaled, no modal mass or stiffness")
        if np.isfinite(m) and m <= 0:
            flags.append(f"negative modal mass {m:.3g} kg and stiffness {m * wn**2:.3g} N/m "
                         "(non-physical: sign or direction mix-up, or a computational pole)")
        coh = float(coherence[r]) if coherence is not None else np.nan
        if np.isfinite(coh) and coh < coherence_min:
            flags.append(f"coherence {coh:.2f} at {f[r]:.4g} Hz below {coherence_min:g}")
        row = {"mode": r + 1, "f_n_hz": f[r], "zeta": z[r], "k_modal_N_m": m * wn**2,
               "m_modal_kg": m, "shape_x": comp.get(1, np.nan),
               "shape_y": comp.get(2, np.nan), "shape_z": comp.get(3, np.nan)}
        row["zeta_windowed"] = (pole_f_zeta(poles_measured)[1][r]
                                if poles_measured is not None else z[r])
        row["rank1"] = rank1
        row["n_stable"] = int(n_stable[r]) if n_stable is not None else 0
        row["driving_point"] = dp
        row["coherence"] = coh
        row["physical"] = not any(fl.startswith("negative") for fl in flags)
        row["flags"] = "; ".join(flags)
        rows.append(row)
    pts = list(TOOLTIP) if tooltip else general.points
    ms = ModeShapes(pts, shapes, np.array([row["m_modal_kg"] for row in rows], float)
                    if rows else np.array([]), "X, Y, Z" if tooltip else general.driving_point)
    return pd.DataFrame(rows, columns=MODE_COLUMNS), ms


def coherence_at(ds: xr.Dataset, f_hz: Sequence[float]) -> np.ndarray:
    """Mean coherence of the measured FRFs at the lines nearest ``f_hz`` (NaN where the
    dataset has no coherence)."""
    if "coherence" not in ds:
        return np.full(len(f_hz), np.nan)
    f = ds["frequency"].values
    c = ds["coherence"].transpose("output", "input", "frequency").values
    c = c.reshape(-1, f.size)
    out = []
    for fr in f_hz:
        k = int(np.argmin(np.abs(f - fr)))
        col = c[:, k]
        out.append(float(np.nanmean(col)) if np.isfinite(col).any() else np.nan)
    return np.array(out)


def band_from_data(ds: xr.Dataset, *, force_spectrum: np.ndarray | None = None,
                   coherence_min: float = 0.75, force_drop_db: float = 10.0,
                   smooth_hz: float = 2.0,
                   no_coherence_low_fraction: float = 0.02) -> tuple[float, float]:
    """The analysis band from the data: where the hammer excited the structure and the
    coherence shows it.

    Upper limit: the first line above which the hammer's force auto-spectrum ``force_spectrum``
    (over ``ds.frequency``) stays ``force_drop_db`` below its mean over the lowest 5 % of the
    lines (the usual "10 dB" rule for a hammer tip, Ewins 2000 §3.6), and the last line where
    the median coherence of the measured FRFs (smoothed over ``smooth_hz``) reaches
    ``coherence_min``. Lower limit: the first line above DC where that smoothed median
    coherence reaches ``coherence_min``. Without coherence (FRFs imported without type-6
    sets) the lowest lines cannot be judged, and a receptance converted from an accelerance
    there is noise divided by ω²: the band then starts at ``no_coherence_low_fraction`` of
    its upper limit (assumed 2 %: 20 Hz for a 1 kHz export).

    Returns
    -------
    (f_lo_hz, f_hi_hz)

    Raises
    ------
    ValueError
        When the coherence never reaches ``coherence_min``.
    """
    f = ds["frequency"].values
    lo, hi = float(f[f > 0][0]), float(f[-1])
    if force_spectrum is not None:
        s = np.asarray(force_spectrum, float)
        ref = np.mean(s[(f > 0) & (f <= f[-1] * 0.05 + f[1])])
        above = s >= ref * 10 ** (-force_drop_db / 10)
        above[f <= 0] = True
        below = np.flatnonzero(~above)
        if below.size:
            hi = min(hi, float(f[below[0]]))
    if "coherence" in ds and np.isfinite(ds["coherence"].values).any():
        c = ds["coherence"].transpose("output", "input", "frequency").values
        with warnings.catch_warnings():  # DC and unmeasured pairs are all-NaN lines
            warnings.simplefilter("ignore", RuntimeWarning)
            med = np.nanmedian(c.reshape(-1, f.size), axis=0)
        w = max(1, int(round(smooth_hz / (f[1] - f[0]))))
        med = np.convolve(np.nan_to_num(med), np.ones(w) / w, mode="same")
        good = np.flatnonzero((med >= coherence_min) & (f > 0) & (f <= hi))
        if good.size == 0:
            raise ValueError(f"the coherence never reaches {coherence_min:g}: no usable band "
                             "(set modal.band_hz)")
        lo, hi = max(lo, float(f[good[0]])), min(hi, float(f[good[-1]]))
    else:
        lo = max(lo, float(f[np.searchsorted(f, no_coherence_low_fraction * hi)]))
    return lo, hi


BAND_COVERAGE_MIN = 0.5
"""A set band covering less than this share of the band the data support is flagged
(assumed: half)."""


@dataclass
class BandChoice:
    """The analysis band and where it came from (:func:`choose_band`)."""

    band_hz: tuple[float, float]
    source: str
    """``modal.band_hz``, ``experiment.modal_band_hz`` (the manifest) or ``data``."""
    data_band_hz: tuple[float, float] | None
    """The band from the data (:func:`band_from_data`); None where it cannot be found."""
    coverage: float
    """Share of ``data_band_hz`` inside ``band_hz`` (1 for a band from the data; NaN when
    the data band is unknown)."""
    flag: str
    """A sanity flag (empty when none): a set band covering a small part of the data band."""


def band_coverage(band_hz: Sequence[float], data_band_hz: Sequence[float]) -> float:
    """Share of the interval ``data_band_hz`` that ``band_hz`` covers:
    ``|band ∩ data| / |data|`` (0 when disjoint)."""
    lo, hi = max(band_hz[0], data_band_hz[0]), min(band_hz[1], data_band_hz[1])
    width = float(data_band_hz[1] - data_band_hz[0])
    return max(0.0, float(hi - lo)) / width if width > 0 else float("nan")


def choose_band(ds: xr.Dataset, *, band_hz: Sequence[float] | None = None,
                experiment_band_hz: Sequence[float] | None = None,
                force_spectrum: np.ndarray | None = None, coherence_min: float = 0.75,
                coverage_min: float = BAND_COVERAGE_MIN) -> BandChoice:
    """The modal analysis band, in order: ``band_hz`` (``config.yaml: modal.band_hz``) if
    set, else ``experiment_band_hz`` (the manifest's ``experiment.modal_band_hz``: the band
    of interest is a choice of the experiment design, e.g. the thesis' 10–100 Hz), else the
    band from the hammer spectrum and the coherence (:func:`band_from_data`).

    A set band (the first two sources) is compared with the band the data support: when it
    covers less than ``coverage_min`` of it (:func:`band_coverage`) the choice carries a
    sanity flag (modes of the measured band may be left out); it is also flagged when the
    data band cannot be found (the coherence never reaches ``coherence_min``).

    Raises
    ------
    ValueError
        When no band is set and the data give none (see :func:`band_from_data`), or a set
        band is not two increasing non-negative frequencies.
    """
    try:
        data_band = band_from_data(ds, force_spectrum=force_spectrum,
                                   coherence_min=coherence_min)
    except ValueError:
        if band_hz is None and experiment_band_hz is None:
            raise
        data_band = None
    for given, source in ((band_hz, "modal.band_hz"),
                          (experiment_band_hz, "experiment.modal_band_hz")):
        if given is None:
            continue
        band = tuple(float(b) for b in given)
        if len(band) != 2 or not 0 <= band[0] < band[1]:
            raise ValueError(f"{source} {list(given)!r} is not a band (expected [f_lo_hz, "
                             "f_hi_hz], 0 <= f_lo_hz < f_hi_hz)")
        if data_band is None:
            return BandChoice(band, source, None, float("nan"),
                              f"{source} {band[0]:.4g}-{band[1]:.4g} Hz: the data give no "
                              f"band to compare with (coherence below {coherence_min:g})")
        cov = band_coverage(band, data_band)
        flag = (f"{source} {band[0]:.4g}-{band[1]:.4g} Hz covers {100 * cov:.0f} % of the "
                f"band the data support ({data_band[0]:.4g}-{data_band[1]:.4g} Hz)"
                if cov < coverage_min else "")
        return BandChoice(band, source, data_band, cov, flag)
    return BandChoice(data_band, "data", data_band, 1.0, "")


@dataclass
class Identification:
    """Everything :func:`identify` finds."""

    stabilization: pd.DataFrame
    selected: pd.DataFrame
    modes: pd.DataFrame
    residues: np.ndarray
    H_synth: np.ndarray
    shapes: ModeShapes | None = None
    mac: np.ndarray | None = None


def identify(ds: xr.Dataset, *, band_hz: Sequence[float], max_order: int = 40,
             tol_f: float = 0.01, tol_zeta: float = 0.05, mac_min: float = 0.95,
             zeta_max: float = 0.2, cluster_tol: float = 0.01,
             min_stable: int = 5, coherence_min: float = 0.75) -> Identification:
    """Stabilization chart over all measured FRFs → selected poles → residues (LSFD) →
    window-corrected modes, shapes over the measured points, MAC matrix, sanity flags."""
    stab = stabilization(ds, band_hz=band_hz, max_order=max_order, tol_f=tol_f,
                         tol_zeta=tol_zeta, mac_min=mac_min, zeta_max=zeta_max)
    sel = select_poles(stab, cluster_tol=cluster_tol, min_stable=min_stable)
    if sel.empty:
        raise ValueError("no stable pole in the band: lower min_stable or raise max_order")
    p_meas = sel["pole_real"].to_numpy() + 1j * sel["pole_imag"].to_numpy()
    residues, synth = modal_constants(ds, p_meas, band_hz=band_hz)
    p_true = correct_window_damping(p_meas, ds.attrs.get("window_sigma_per_s", 0.0))
    modes, shapes = modes_table(p_true, residues, poles_measured=p_meas,
                                n_stable=sel["n_stable"].to_numpy(),
                                outputs=points(ds, "output"), inputs=points(ds, "input"),
                                coherence=coherence_at(ds, pole_f_zeta(p_meas)[0]),
                                coherence_min=coherence_min)
    return Identification(stab, sel, modes, residues, synth, shapes,
                          mac_matrix(shapes.shapes))


def shapes_table(shapes: ModeShapes) -> pd.DataFrame:
    """Long table of the complex mode shapes: ``mode, point, node, direction, shape_real,
    shape_imag, shape_abs, shape_phase_deg`` (``results/modal/mode_shapes.csv``)."""
    rows = []
    for r in range(shapes.shapes.shape[0]):
        for k, (n, d) in enumerate(shapes.points):
            v = shapes.shapes[r, k]
            rows.append({"mode": r + 1, "point": point_label(n, d), "node": n, "direction": d,
                         "shape_real": v.real, "shape_imag": v.imag, "shape_abs": abs(v),
                         "shape_phase_deg": float(np.degrees(np.angle(v)))})
    return pd.DataFrame(rows, columns=["mode", "point", "node", "direction", "shape_real",
                                       "shape_imag", "shape_abs", "shape_phase_deg"])


# ---- 7. what the chapter reports: peak groups, truth check, mode coupling -----------------------
THESIS_NATURAL_HZ = (20.0, 35.0, 60.0, 67.0, 70.0, 72.0)
"""The natural frequencies the thesis finds at the tool tip (§3.3) [Hz]."""

COUPLING_TOLERANCE = 0.15
"""A mode is "close" to the vibration frequency within this fraction of it (thesis §3.3)."""


def group_peaks(peaks: pd.DataFrame, line_hz: float, *,
                reference_hz: Sequence[float] | None = THESIS_NATURAL_HZ,
                gap_lines: float = 3.0) -> pd.DataFrame:
    """Group the thesis-criteria peaks of every FRF into natural frequencies.

    The candidates of :func:`peak_picking` that meet both criteria (``natural_frequency``)
    are sorted by frequency and split where two neighbours are more than ``gap_lines``
    spectral lines (``line_hz`` each) apart; a group's frequency is the median of its
    members' (thesis §3.3: a frequency counts when it meets both criteria on at least one
    FRF).

    Parameters
    ----------
    peaks
        ``results/modal/peak_picking.csv`` (columns ``output, input, f_hz,
        natural_frequency``).
    line_hz
        Spacing of the FRF's frequency lines [Hz].
    reference_hz
        Frequencies to match each group with (nearest); ``None``: no ``reference_hz``
        column values (NaN).
    gap_lines
        Largest gap inside a group, in lines.

    Returns
    -------
    pandas.DataFrame
        ``group`` (1, 2, …), ``f_hz`` (median), ``n_frfs`` (members), ``frfs``
        (``"output/input"`` of each member, comma separated), ``reference_hz`` (nearest
        reference frequency) and ``offset_hz`` (``f_hz − reference_hz``).
    """
    cols = ["group", "f_hz", "n_frfs", "frfs", "reference_hz", "offset_hz"]
    ok = peaks[peaks["natural_frequency"].astype(bool)].sort_values("f_hz", kind="stable")
    if ok.empty:
        return pd.DataFrame(columns=cols)
    gid = (ok["f_hz"].diff() > gap_lines * float(line_hz)).cumsum().to_numpy() + 1
    rows = []
    ref = None if reference_hz is None else np.asarray(reference_hz, float)
    for g in np.unique(gid):
        m = ok[gid == g]
        f_hz = float(np.median(m["f_hz"]))
        near = float(ref[np.argmin(np.abs(ref - f_hz))]) if ref is not None and ref.size \
            else np.nan
        rows.append({"group": int(g), "f_hz": f_hz, "n_frfs": len(m),
                     "frfs": ", ".join(f"{o}/{i}" for o, i in zip(m["output"], m["input"],
                                                                   strict=True)),
                     "reference_hz": near, "offset_hz": f_hz - near})
    return pd.DataFrame(rows, columns=cols)


def truth_check(modes: pd.DataFrame, f_true_hz: Sequence[float], zeta_true: Sequence[float],
                k_true_N_m: Sequence[float], shape_true: np.ndarray) -> pd.DataFrame:
    """Identified modes against planted ones (synthetic runs).

    Each planted mode is matched with the identified mode nearest in frequency; errors are
    relative, ``100 (identified/true − 1)`` %, and the shapes are compared by the modal
    assurance criterion ``MAC = |φ_trueᴴ φ|² / (φ_trueᴴ φ_true · φᴴ φ)`` (Allemang & Brown
    1982) of the tool-tip shape ``(shape_x, shape_y, shape_z)``.

    Parameters
    ----------
    modes
        ``results/modal/modes.csv`` (``mode, f_n_hz, zeta, k_modal_N_m, shape_x, shape_y,
        shape_z``).
    f_true_hz, zeta_true, k_true_N_m
        The planted natural frequencies [Hz], damping ratios and modal stiffnesses [N/m].
    shape_true
        ``(n_true, 3)`` planted tool-tip shapes.

    Returns
    -------
    pandas.DataFrame
        ``true_mode, f_true_hz, zeta_true, k_true_N_m, mode, f_n_hz, zeta, f_err_pct,
        zeta_err_pct, k_err_pct, shape_mac``.
    """
    cols = ["true_mode", "f_true_hz", "zeta_true", "k_true_N_m", "mode", "f_n_hz", "zeta",
            "f_err_pct", "zeta_err_pct", "k_err_pct", "shape_mac"]
    shape_true = np.atleast_2d(np.asarray(shape_true, float))
    rows = []
    if len(modes) == 0:
        return pd.DataFrame(columns=cols)
    f_id = modes["f_n_hz"].to_numpy(float)
    for r, (ft, zt, kt) in enumerate(zip(f_true_hz, zeta_true, k_true_N_m, strict=True)):
        m = modes.iloc[int(np.argmin(np.abs(f_id - ft)))]
        phi = m[["shape_x", "shape_y", "shape_z"]].to_numpy(float)
        rows.append({"true_mode": r + 1, "f_true_hz": float(ft), "zeta_true": float(zt),
                     "k_true_N_m": float(kt), "mode": int(m["mode"]),
                     "f_n_hz": float(m["f_n_hz"]), "zeta": float(m["zeta"]),
                     "f_err_pct": 100 * (m["f_n_hz"] / ft - 1),
                     "zeta_err_pct": 100 * (m["zeta"] / zt - 1),
                     "k_err_pct": 100 * (m["k_modal_N_m"] / kt - 1),
                     "shape_mac": _mac(shape_true[r], phi)})
    return pd.DataFrame(rows, columns=cols)


def mode_coupling(modes: pd.DataFrame, vibration_hz: float, *,
                  tolerance: float = COUPLING_TOLERANCE) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Which modes lie near the vibration frequency seen while cutting (thesis §3.3).

    The thesis concludes that two modes close to the cutting vibration frequency, excited
    together with non-parallel shapes, drive an elliptical tool path (mode coupling). A mode
    is close when ``|f_n/f_vib − 1| ≤ tolerance``; for each pair of close modes the angle
    between their unit tool-tip shapes is ``arccos |φ_a · φ_b|`` (0° parallel, 90°
    orthogonal).

    Parameters
    ----------
    modes
        ``results/modal/modes.csv`` (``mode, f_n_hz, shape_x, shape_y, shape_z``).
    vibration_hz
        The dominant vibration frequency while cutting [Hz] (chapter 3.1's median
        ``dominant_hz``).
    tolerance
        Relative distance that counts as close (thesis: ±15 %).

    Returns
    -------
    (pandas.DataFrame, pandas.DataFrame)
        Per mode: ``mode, f_n_hz, vibration_hz, offset_fraction, close``; per pair of
        close modes: ``mode_a, mode_b, f_a_hz, f_b_hz, shape_angle_deg``.
    """
    if not np.isfinite(vibration_hz) or vibration_hz <= 0:
        raise ValueError(f"vibration frequency must be a positive number of Hz, got "
                         f"{vibration_hz!r}")
    f_n = modes["f_n_hz"].to_numpy(float)
    offset = f_n / float(vibration_hz) - 1
    per_mode = pd.DataFrame({"mode": modes["mode"].to_numpy(int), "f_n_hz": f_n,
                             "vibration_hz": float(vibration_hz), "offset_fraction": offset,
                             "close": np.abs(offset) <= tolerance})
    close = modes[per_mode["close"].to_numpy()]
    shapes = close[["shape_x", "shape_y", "shape_z"]].to_numpy(float)
    norms = np.linalg.norm(shapes, axis=1)
    rows = []
    for a in range(len(close)):
        for b in range(a + 1, len(close)):
            cos = abs(float(shapes[a] @ shapes[b])) / (norms[a] * norms[b])
            rows.append({"mode_a": int(close.iloc[a]["mode"]),
                         "mode_b": int(close.iloc[b]["mode"]),
                         "f_a_hz": float(close.iloc[a]["f_n_hz"]),
                         "f_b_hz": float(close.iloc[b]["f_n_hz"]),
                         "shape_angle_deg": float(np.degrees(np.arccos(min(1.0, cos))))})
    pairs = pd.DataFrame(rows, columns=["mode_a", "mode_b", "f_a_hz", "f_b_hz",
                                        "shape_angle_deg"])
    return per_mode, pairs


def synthesis_misfit(ds: xr.Dataset, H_synth: np.ndarray, band_hz: Sequence[float]
                     ) -> pd.DataFrame:
    """Relative misfit ``‖H_synth − H‖₂ / ‖H‖₂`` [%] per FRF over the analysis band.

    The norms run over the frequency lines inside ``band_hz`` where the synthesized FRF is
    finite; a pair the layout did not measure is NaN.

    Returns
    -------
    pandas.DataFrame
        Index ``out <output>``, columns ``in <input>``: the misfit in percent.
    """
    f = ds["frequency"].values
    H = ds["H"].transpose("output", "input", "frequency").values
    Hs = np.asarray(H_synth)
    inb = (f >= band_hz[0]) & (f <= band_hz[1]) & np.isfinite(Hs).any(axis=(0, 1))
    with np.errstate(invalid="ignore", divide="ignore"):
        err = (np.linalg.norm((Hs - H)[..., inb], axis=-1)
               / np.linalg.norm(H[..., inb], axis=-1))
    return pd.DataFrame(100 * err, index=[f"out {o}" for o in ds["output"].values],
                        columns=[f"in {i}" for i in ds["input"].values])
