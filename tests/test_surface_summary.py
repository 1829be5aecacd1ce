"""Chapter-2 summaries: direction means, feed correlations, cells within 1.5×."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from robomill import surface


def _metrics():
    feed = np.array([2.0, 4.0, 6.0, 2.0, 4.0, 6.0])
    return pd.DataFrame({"direction": ["px"] * 3 + ["py"] * 3, "feed_mm_s": feed,
                         "waviness_rms_um": [1.0, 2.0, 3.0, 3.0, 4.0, 5.0],
                         "roughness_rms_um": 0.5 - 0.05 * feed})


def test_direction_means_are_the_means_of_each_direction():
    m = surface.direction_means(_metrics())
    assert m.loc["px", "waviness_rms_um"] == pytest.approx(2.0)
    assert m.loc["py", "waviness_rms_um"] == pytest.approx(4.0)
    assert m["n_cuts"].tolist() == [3, 3]


def test_feed_correlation_has_the_planted_signs():
    r = surface.feed_correlation(_metrics())
    assert 0 < r["waviness"] < 1
    assert r["roughness"] == pytest.approx(-1.0)
    assert np.isnan(surface.feed_correlation(_metrics().iloc[:1])["waviness"])


def test_comparison_summary_counts_cells_within_the_factor():
    cmp_ = pd.DataFrame({"table": ["2.1", "2.1", "2.1", "2.2"],
                         "ratio": [1.0, 2.0, 0.9, 0.5], "within_1.5x": [True, False, True, False]})
    s = surface.comparison_summary(cmp_)
    assert s.loc["2.1"].tolist() == [2, 3, 1.0]
    assert s.loc["2.2", "within"] == 0 and s.loc["2.2", "median_ratio"] == 0.5
