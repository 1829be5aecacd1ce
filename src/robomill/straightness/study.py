"""The straightness run driver and gathering: one tracker run end to end (profile, spectrum,
gear frequencies through the cell's inverse kinematics, matched peaks) and every run's
artefacts stacked into the study's tables and dataset.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill.kinematics import SerialRobot
from robomill.settings import schema_default
from robomill.straightness.attribution import PEAK_COLUMNS, classify_peaks, match_peaks_to_gears
from robomill.straightness.gears import gear_spatial_frequencies, joint_path_for_line
from robomill.straightness.profile import (
    Profile,
    ProfileSpectrum,
    profile_spectrum,
    spatial_profile,
    spectrum_peaks,
)


# ---------------------------------------------------------------------------------------------
# one tracker run, end to end
# ---------------------------------------------------------------------------------------------
def analyse_run(t_s: np.ndarray | None, points_mm: np.ndarray, *, robot: SerialRobot,
                gears: Sequence[Any], tool_rotation: np.ndarray, q0_rad: np.ndarray,
                ds_mm: float, trim_mm: float, nfft: int, fmin_cycles: float,
                fmax_per_mm: float, threshold: float, n_peaks: int, tol_bins: float,
                detrend_order: int = 1, ik_points: int = 41,
                merge_bins: float = schema_default("straightness", "merge_bins"),
                local_prominence_ratio: float = 0.0, local_floor_halfwidth_bins: float = 0.0
                ) -> tuple[Profile, ProfileSpectrum, pd.DataFrame, pd.DataFrame]:
    """Profile, spectrum, gear frequencies and gear-matched peaks of one tracker run.

    The gear spatial frequencies are computed for the measured path: the best line's ends
    (tracker coordinates are those of the robot base frame) through inverse kinematics at
    the tool orientation ``tool_rotation``. Peaks are searched from ``fmin_cycles/L``
    (fewer cycles than that in the record are indistinguishable from the removed line) up to
    ``fmax_per_mm``, each a local maximum standing ``local_prominence_ratio`` above its local
    floor within ±``local_floor_halfwidth_bins``/L (:func:`spectrum_peaks`), its frequency
    interpolated within the bin; the match tolerance is ``tol_bins/L``, and gear lines closer than
    ``merge_bins/L`` (the Hann window's resolution, 2 bins) are merged: the peak lists every
    candidate (:func:`match_peaks_to_gears`). ``t_s`` is ``None`` for a stream without a
    time base (:func:`spatial_profile`): everything here is in space.
    """
    prof = spatial_profile(t_s, points_mm, ds_mm=ds_mm, trim_mm=trim_mm,
                           detrend_order=detrend_order)
    spec = profile_spectrum(prof, nfft=nfft)
    q, s = joint_path_for_line(robot, prof.start_mm, prof.end_mm, tool_rotation, q0_rad,
                               ik_points)
    gears_df = gear_spatial_frequencies(q, s, gears)
    peaks = spectrum_peaks(spec, fmin_per_mm=fmin_cycles * spec.resolution_per_mm,
                           fmax_per_mm=fmax_per_mm, threshold=threshold, n_peaks=n_peaks,
                           local_ratio=local_prominence_ratio,
                           floor_halfwidth_bins=local_floor_halfwidth_bins)
    peaks = match_peaks_to_gears(peaks, gears_df,
                                 tolerance_per_mm=tol_bins * spec.resolution_per_mm,
                                 resolution_per_mm=merge_bins * spec.resolution_per_mm)
    return prof, spec, gears_df, peaks

def analyse_tracker_run(t_s: np.ndarray | None, points_mm: np.ndarray, cell: Any, *,
                        data_file: str, redundancy_deg: float = 0.0, **settings: Any
                        ) -> tuple[Profile, ProfileSpectrum, pd.DataFrame, pd.DataFrame]:
    """:func:`analyse_run` for a tracker file in the cell described by ``cell``
    (:class:`robomill.io.cell.Cell`, read from ``cell.yaml``).

    The points are first registered to the robot base frame with the cell's
    ``base_from_instrument.tracker`` (if any); the robot, its home posture (IK seed), the tool
    orientation and the gear trains are the cell's; the tool turned by the cut's
    ``redundancy_deg`` about its axis, R0 Rz(θ) (the manifest's cut key, 0 by default). A path
    out of the robot's reach raises
    :class:`~robomill.errors.RawDataError` naming ``data_file`` and pointing at
    ``base_from_instrument`` (not the inverse kinematics' ``RuntimeError``).
    """
    from robomill.errors import RawDataError

    base = cell.to_base_mm("tracker", points_mm)
    tool_rotation = np.asarray(cell.tool_rotation, float)
    if redundancy_deg:
        from robomill.stiffness.poses import tool_rotation_redundancy

        tool_rotation = tool_rotation_redundancy(tool_rotation, np.deg2rad(redundancy_deg))
    try:
        return analyse_run(t_s, base, robot=cell.robot, gears=cell.transmissions,
                           tool_rotation=tool_rotation, q0_rad=cell.q_home_rad,
                           **settings)
    except RuntimeError:
        prof = spatial_profile(t_s, base, ds_mm=settings["ds_mm"], trim_mm=settings["trim_mm"])
        T = np.broadcast_to(np.eye(4), (2, 4, 4)).copy()
        T[:, :3, :3] = tool_rotation
        T[:, :3, 3] = [prof.start_mm, prof.end_mm]
        cell.joint_path_rad(T, data_file=data_file, instrument="tracker")  # raises RawDataError
        raise RawDataError(data_file, f"the path is not reachable by robot '{cell.robot.name}'",
                           where="tracker points in the robot base frame",
                           expected="points in the base frame of the robot of "
                                    f"{cell.path}: register the tracker frame with "
                                    "base_from_instrument.tracker in cell.yaml") from None


_RUN_COORDS = {  # run coordinate: (units, long name), from each run's attrs
    "direction": ("1", "cut direction"),
    "feed_mm_s": ("mm/s", "commanded feed"),
    "cut": ("1", "cut whose path the run follows"),
    "resolution_per_mm": ("1/mm", "frequency resolution 1/L"),
    "length_mm": ("mm", "analysed path length L"),
    "speed_mm_s": ("mm/s", "measured speed"),
    "fmin_per_mm": ("1/mm", "lowest analysed frequency"),
    "floor_um2": ("um^2", "median power in the band"),
}


def gather_profiles(runs: Sequence[xr.Dataset], run_ids: Sequence[str]) -> xr.Dataset:
    """Stack the per-run :func:`profile_dataset` artefacts along ``run`` (outer join of their
    axes); each run's attrs (direction, feed, resolution, …) become ``run`` coordinates,
    and ``time_base`` (``time`` or ``none``) when a run has no time base. The inputs are not
    modified."""
    if len(runs) != len(run_ids):
        raise ValueError(f"gather_profiles: {len(runs)} runs but {len(run_ids)} run ids")
    missing = [(r, k) for r, ds in zip(run_ids, runs, strict=True) for k in _RUN_COORDS
               if k not in ds.attrs]
    if missing:
        raise ValueError(f"gather_profiles: run attribute(s) missing: {missing[:5]}")
    coords = {k: ("run", [ds.attrs[k] for ds in runs], {"units": u, "long_name": n})
              for k, (u, n) in _RUN_COORDS.items()}
    parts = []
    for r, ds in zip(run_ids, runs, strict=True):
        part = ds.expand_dims(run=[r])
        part.attrs = {}
        parts.append(part)
    if any("time_base" in ds.attrs for ds in runs):  # a stream without a time base among them
        coords["time_base"] = ("run", [ds.attrs.get("time_base", "time") for ds in runs],
                               {"units": "1", "long_name": "time base of the stream (none: "
                                "analysed in space only)"})
    prof = xr.concat(parts, dim="run", join="outer").assign_coords(coords)
    prof["run"].attrs = {"units": "1",
                         "long_name": "tracker run id (manifest run, else <dir>_f<feed>)"}
    return prof


def gather_gears(per_run: Sequence[pd.DataFrame]) -> pd.DataFrame:
    """All runs' gear spatial frequencies, with the temporal frequency f·v they have at the
    run's feed (``f_temporal_hz``)."""
    gears = pd.concat(list(per_run), ignore_index=True)
    gears["f_temporal_hz"] = gears["f_spatial_per_mm"] * gears["feed_mm_s"]
    return gears


def gather_peaks(per_run: Sequence[pd.DataFrame], profiles: xr.Dataset, *,
                 tol_bins: float) -> pd.DataFrame:
    """All runs' peaks, classified across feeds (:func:`classify_peaks`) with each run's
    resolution from ``profiles`` (:func:`gather_profiles`); columns :data:`PEAK_COLUMNS`
    (plus ``n_candidates``, ``candidates``, ``merged`` when present, and ``time_base`` when a
    run has none: its peaks are not classified temporal/spatial, :data:`NO_TIME_BASE`), then
    ``run``: each row's run id, the key that joins it to ``profiles``'s ``run``."""
    peaks = pd.concat(list(per_run), ignore_index=True)
    peaks["joint"] = peaks["joint"].astype("Int64")
    peaks[["stage", "order"]] = peaks[["stage", "order"]].fillna("")
    if "candidates" in peaks:
        peaks["candidates"] = peaks["candidates"].fillna("")
        peaks["merged"] = peaks["merged"].astype(bool)
    runs = [str(r) for r in profiles["run"].values]
    res = dict(zip(runs, profiles["resolution_per_mm"].values.astype(float), strict=True))
    untimed = []
    if "time_base" in profiles.coords:
        untimed = [r for r, b in zip(runs, profiles["time_base"].values, strict=True)
                   if b == "none"]
        peaks["time_base"] = ["none" if r in untimed else "time" for r in peaks["run"]]
    peaks = classify_peaks(peaks, res, tol_bins=tol_bins, untimed=untimed)
    extra = [c for c in ("n_candidates", "candidates", "merged", "time_base") if c in peaks]
    return peaks[PEAK_COLUMNS + extra + ["run"]]
