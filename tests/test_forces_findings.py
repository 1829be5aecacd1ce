"""Chapter 3.1's findings on the dominant peak (robomill.forces.findings) from planted tables,
and the chapter's sentences following them (notebooks/templates/ch3_1.yaml)."""

import numpy as np
import pandas as pd
import pytest

from robomill.findings import Findings
from robomill.forces.findings import forces_findings
from robomill.pipeline.prose import Prose, load_templates

MODES = pd.DataFrame({"mode": [1, 2, 3], "f_n_hz": [20.0, 60.0, 72.0]})
KW = dict(mode_match_hz=3.0, band_hz=(15.0, 250.0), prominence_db=12.0)


def _peaks(hz):
    return pd.DataFrame({"cut": [f"c{i}" for i in range(len(hz))], "dominant_hz": hz})


def test_every_peak_near_a_mode_passes_with_its_threshold():
    """Peaks 61.0, 59.5, 70.0, 71.0 Hz, one cut without a peak: nearest modes 60, 60, 72, 72
    Hz, offsets 1.0, 0.5, 2.0, 1.0 Hz (max 2.0, median 1.0): all within 3 Hz."""
    f = forces_findings(_peaks([61.0, 59.5, np.nan, 70.0, 71.0]), MODES, **KW).values()
    assert (f["n_cuts"], f["n_dominant"], f["n_dominant_none"]) == (5, 4, 1)
    assert f["dominant_hz_range"] == [59.5, 71.0]
    assert f["mode_offset_max_hz"] == pytest.approx(2.0)
    assert f["mode_offset_median_hz"] == pytest.approx(1.0)
    assert f["modes_hit_hz"] == [60.0, 72.0] and f["modes_hit_cuts"] == [2, 2]
    assert f["verdict_dominant_at_modes"] == "pass" and f["threshold_dominant_at_modes"] == 3.0
    assert f["modes_hz"] == [20.0, 60.0, 72.0]


def test_a_peak_far_from_every_mode_fails_and_the_threshold_decides():
    """A peak at 45 Hz is 15 Hz from the 60 Hz mode: it fails at 3 Hz, passes at 20 Hz."""
    peaks = _peaks([61.0, 45.0])
    f = forces_findings(peaks, MODES, **KW).values()
    assert f["verdict_dominant_at_modes"] == "fail"
    assert f["mode_offset_max_hz"] == pytest.approx(15.0)
    wide = forces_findings(peaks, MODES, **{**KW, "mode_match_hz": 20.0})
    assert wide["dominant_at_modes"].verdict == "pass"
    assert wide["dominant_at_modes"].config_key == "forces.mode_match_hz"


def test_no_modes_or_no_peaks_give_no_verdict():
    f = forces_findings(_peaks([61.0]), None, **KW).values()
    assert f["has_modes"] is False and f["modes_hz"] is None
    assert "verdict_dominant_at_modes" not in f
    f = forces_findings(_peaks([np.nan, np.nan]), MODES, **KW).values()
    assert f["dominant_hz_range"] is None and f["n_dominant"] == 0
    assert "verdict_dominant_at_modes" not in f


def test_chapter_3_1_prose_follows_its_findings():
    """Rendered from altered findings: the numbers and the verdict follow them; no thesis
    explanation is stated as a fact of a study that has no modes or no peaks."""
    say = Prose(load_templates("ch3_1"), forces_findings(
        _peaks([61.0, 59.5, 70.0]), MODES, **KW))
    text = " ".join(say("dominant", "modes", "verdict", ref_peaks="[T]").split())
    assert "lies between **59.5 and 70.0 Hz**" in text and "15–250 Hz" in text
    assert "within 3 Hz of an identified mode" in text and "20.0, 60.0, 72.0 Hz" in text
    far = " ".join(Prose(load_templates("ch3_1"), forces_findings(
        _peaks([61.0, 45.0]), MODES, **KW))("verdict").split())
    assert "more than 3 Hz" in far and "up to 15.0 Hz" in far and "chip load" not in far
    bare = Prose(load_templates("ch3_1"), forces_findings(_peaks([202.8]), None, **KW))
    text = " ".join(bare("dominant", "modes", "verdict", "no_match", "no_modes",
                         ref_peaks="[T]").split())
    assert "202.8" in text and "no impact test" in text and "chip load" not in text
    none = Prose(load_templates("ch3_1"), forces_findings(_peaks([np.nan]), MODES, **KW))
    text = " ".join(none("dominant", "no_match", ref_peaks="[T]").split())
    assert "**none** in every cut" in text and "none is matched" in text
    assert "not compared" in Prose(load_templates("ch3_1"), Findings("forces"))("against")
