"""Impact hits: automatic rejection (double hit, overload), the force and exponential
windows, grouping of the accepted hits, and the hit table and traces of the chapter.

Rejection (thesis §3.3): a **double hit** (the force rises above ``double_hit_fraction`` of
its peak in two separate pulses) or an **overload** (a channel stays at its extreme value for
``overload_samples`` samples or more: a clipped, saturated channel); the reason is returned
in words. Windows: a force window (1 from the record start to ``force_window_s`` after the
trigger, then a half-Hann taper) and an exponential window ``w(t) = exp(−σ (t − t_trig))``
after the trigger, ``σ = ln(1/end)/T`` (the window reaches ``end`` one record length T after
the trigger; its damping is removed from the poles by
:func:`robomill.modal.lscf.correct_window_damping`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
import scipy.signal
import xarray as xr

from robomill.modal.layout import point_label
from robomill.settings import schema_default

CHANNELS = ("force_N", "ax_ms2", "ay_ms2", "az_ms2")
"""Channels of an impact record."""


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
              trigger_fraction: float = schema_default("modal", "trigger_fraction"),
              double_hit_fraction: float = schema_default("modal", "double_hit_fraction"),
              overload_samples: int = schema_default("modal", "overload_samples"),
              flat_rtol: float = 1e-4,
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


@dataclass
class HitGroup:
    """Accepted hits of one reference point measured with the same response points.

    ``hits`` are ``(force_N (n,), accel_ms2 (n, k), trigger_index)``; ``responses`` the k
    response points ``(node, direction code)``, in the order of the acceleration columns.
    """

    reference: tuple[int, int]
    responses: tuple[tuple[int, int], ...]
    hits: list = field(default_factory=list)


def check_and_group(hits: Sequence, *,
                    trigger_fraction: float = schema_default("modal", "trigger_fraction"),
                    double_hit_fraction: float = schema_default("modal", "double_hit_fraction"),
                    overload_samples: int = schema_default("modal", "overload_samples"),
                    force_range_N: float | None = None,
                    accel_range_ms2: float | None = None) -> tuple[pd.DataFrame, list[HitGroup]]:
    """Check every hit (:func:`check_hit`) and group the accepted ones by reference point and
    response points (:class:`HitGroup`, input of :func:`robomill.modal.frf.frf_from_groups`).

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
