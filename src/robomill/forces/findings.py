"""Chapter 3.1's findings on the dominant low-frequency force peak: where it lies, in how
many cuts none stands out, and whether it sits at the identified modes of the impact test
(chapter 3.3) within ``forces.mode_match_hz`` — a verdict with its threshold, computed here,
rendered by the chapter (:mod:`robomill.pipeline.prose`)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from robomill.findings import Findings
from robomill.forces.peaks import nearest_modes

_PEAKS = "results/forces/peaks.csv"
_MODES = "results/modal/modes.csv"


def forces_findings(peaks: pd.DataFrame, modes: pd.DataFrame | None, *,
                    mode_match_hz: float, band_hz: Sequence[float],
                    prominence_db: float) -> Findings:
    """The dominant-peak findings of the forces stage.

    Parameters
    ----------
    peaks
        ``results/forces/peaks.csv`` (columns ``cut``, ``dominant_hz``; NaN where no peak
        stands out of its local floor).
    modes
        ``results/modal/modes.csv`` (``mode``, ``f_n_hz``), or ``None`` where the study has
        no impact test.
    mode_match_hz
        ``forces.mode_match_hz``: a dominant peak within this distance of an identified mode
        is "at the mode"; the verdict ``dominant_at_modes`` is ``pass`` when every dominant
        peak is (the thesis' reading: the tool-tip vibration modulates the chip load).
    band_hz, prominence_db
        ``forces.dominant_band_hz`` and ``forces.dominant_prominence_db`` (stated with the
        peaks).

    Returns
    -------
    Findings
        ``n_cuts``, ``n_dominant``, ``n_dominant_none``, ``dominant_hz_range`` (``[min, max]``
        or ``None``), ``dominant_band_hz``, ``dominant_prominence_db``, ``has_modes``,
        ``modes_hz``; with modes and peaks ``mode_offset_max_hz``, ``mode_offset_median_hz``
        (absolute peak − nearest mode), ``modes_hit_hz``/``modes_hit_cuts`` (the modes
        nearest to a peak, most often first) and the verdict ``dominant_at_modes``.
    """
    found = Findings("forces")
    dom = pd.to_numeric(peaks["dominant_hz"], errors="coerce").to_numpy(float)
    have = np.isfinite(dom)
    found.add("n_cuts", int(dom.size), artefact=_PEAKS, what="rows")
    found.add("n_dominant", int(have.sum()), artefact=_PEAKS, what="dominant_hz not empty")
    found.add("n_dominant_none", int((~have).sum()), artefact=_PEAKS,
              what="dominant_hz empty: no local maximum rises above its floor")
    found.add("dominant_hz_range", [float(dom[have].min()), float(dom[have].max())]
              if have.any() else None, "Hz", artefact=_PEAKS, what="dominant_hz")
    found.add("dominant_band_hz", [float(b) for b in band_hz], "Hz")
    found.add("dominant_prominence_db", float(prominence_db), "dB")
    has_modes = modes is not None and len(modes) > 0
    found.add("has_modes", bool(has_modes), artefact=_MODES)
    found.add("modes_hz", [float(f) for f in modes["f_n_hz"]] if has_modes else None, "Hz",
              artefact=_MODES, what="f_n_hz")
    if not (has_modes and have.any()):
        return found
    near = nearest_modes(dom[have], modes)
    off = near["offset_hz"].abs().to_numpy(float)
    found.add("mode_offset_max_hz", float(off.max()), "Hz", artefact=_PEAKS,
              what="|dominant_hz - nearest f_n_hz|, largest")
    found.add("mode_offset_median_hz", float(np.median(off)), "Hz", artefact=_PEAKS,
              what="|dominant_hz - nearest f_n_hz|, median")
    hits = near.groupby("nearest_mode_hz").size().sort_values(ascending=False, kind="stable")
    found.add("modes_hit_hz", [float(f) for f in hits.index], "Hz", artefact=_MODES)
    found.add("modes_hit_cuts", [int(n) for n in hits.to_numpy()], artefact=_PEAKS)
    found.add("dominant_at_modes", bool(off.max() <= mode_match_hz),
              verdict="pass" if off.max() <= mode_match_hz else "fail",
              threshold=float(mode_match_hz), config_key="forces.mode_match_hz",
              artefact=_PEAKS, what="every dominant peak within the threshold of a mode")
    return found
