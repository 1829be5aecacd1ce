"""The predict-then-cut set's tally (``benchmarks/predict_then_cut.py``), on a small table
whose answers are counted by hand: which cuts the nominal prediction gets right, which are
unsafe (predicted stable, judged chatter), and the Brier score of ``p_stable``."""

import sys
from pathlib import Path

import pandas as pd
import pytest

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "benchmarks"))
from predict_then_cut import agreement_table, set_summary  # noqa: E402


def test_the_tally_and_the_brier_score_by_hand():
    pred = pd.DataFrame({
        "cut": ["a", "b", "c", "d", "e"],
        "depth_mm": [0.5, 2.0, 0.5, 2.0, 1.0],
        "a_crit_mm": [1.0, 1.0, 1.0, 1.0, 1.0],
        "a_crit_low_mm": [0.6] * 5, "a_crit_high_mm": [1.6] * 5,
        "p_stable": [0.9, 0.2, 0.7, 0.1, 0.5]}).set_index("cut")
    # a: predicted stable, stable; b: predicted chatter, stable (a miss on the safe side);
    # c: predicted stable, chatter (unsafe); d: predicted chatter, chatter; e: undetermined
    verdicts = pd.Series({"a": 1.0, "b": 1.0, "c": 0.0, "d": 0.0, "e": float("nan")})
    t = agreement_table(pred, verdicts)
    assert list(t.index) == ["a", "b", "c", "d"]          # the undetermined cut is not judged
    assert t["agree"].tolist() == [True, False, False, True]
    assert t["unsafe"].tolist() == [False, False, True, False]
    s = set_summary(t)
    assert (s["n_judged"], s["n_agree"], s["n_unsafe"]) == (4, 2, 1)
    # (0.9 − 1)² + (0.2 − 1)² + (0.7 − 0)² + (0.1 − 0)² over 4
    assert s["brier_score"] == pytest.approx((0.01 + 0.64 + 0.49 + 0.01) / 4, abs=1e-4)


def test_a_set_option_that_is_no_list_of_positive_numbers_is_one_line():
    import argparse

    from predict_then_cut import positive_floats

    assert positive_floats("0.5,2.5") == [0.5, 2.5]
    for bad in ("0.5,x", "-1", "0", "", "nan"):
        with pytest.raises(argparse.ArgumentTypeError, match="positive numbers"):
            positive_floats(bad)


def test_a_feed_per_tooth_is_one_positive_number():
    import argparse

    from predict_then_cut import positive_float

    assert positive_float("0.025") == 0.025
    for bad in ("0.025,0.05", "0", "x"):
        with pytest.raises(argparse.ArgumentTypeError, match="positive number"):
            positive_float(bad)


def test_the_production_set_feeds_the_chip_by_hand():
    """f = f_z N n/60: 25 µm on 3 flutes at 12 000 rpm is 15 mm/s, at 28 000 rpm 35 mm/s;
    without a feed per tooth, 5 mm/s at every speed."""
    from predict_then_cut import FEED_MM_S, feed_mm_s

    assert feed_mm_s(12000.0) == feed_mm_s(28000.0, None, 3) == FEED_MM_S == 5.0
    assert feed_mm_s(12000.0, 0.025, 3) == pytest.approx(15.0, rel=1e-12)
    assert feed_mm_s(28000.0, 0.025, 3) == pytest.approx(35.0, rel=1e-12)


@pytest.mark.parametrize("text, expected", [("a: [1, 2\n", "not YAML"),
                                            ("a: 1\n", "expected a YAML list of cuts")])
def test_a_cut_list_that_is_no_list_of_cuts_is_one_line(tmp_path, capsys, text, expected):
    """``--cuts``: a file that is not YAML, or not a list of cuts, stops with one line naming
    it, before any study is read."""
    from predict_then_cut import main

    bad = tmp_path / "cuts.yaml"
    bad.write_text(text)
    assert main([str(tmp_path), "--config", "config.yaml", "--cuts", str(bad),
                 "--out", str(tmp_path / "out")]) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"predict_then_cut: {bad}: {expected}") and "\n" not in err


def test_the_two_regime_limit_and_its_tally_by_hand():
    """The candidate two-regime model (``benchmarks/modes_at_cuts.py``): the larger of the
    limits without and with the edge term, tallied against the verdicts as the nominal's."""
    from modes_at_cuts import tally, two_regime_mm

    t = pd.DataFrame({"depth_mm": [0.5, 2.0, 0.5, 2.0],
                      "verdict": ["stable", "stable", "chatter", "chatter"],
                      "plain_mm": [1.0, 1.0, 1.0, 1.0], "edge_mm": [0.3, 2.5, 0.2, 1.5]})
    t["two_mm"] = [two_regime_mm(p, e) for p, e in zip(t["plain_mm"], t["edge_mm"],
                                                       strict=True)]
    assert t["two_mm"].tolist() == [1.0, 2.5, 1.0, 1.5]
    # plain: a right, b a safe-side miss, c unsafe, d right
    assert tally(t, "plain_mm") == (2, 1)
    # two regimes: b now right (2.5 > 2.0); c still unsafe; d right (1.5 < 2.0)
    assert tally(t, "two_mm") == (3, 1)
    # the edge term alone: a wrong (0.3 < 0.5), b right, c right, d right
    assert tally(t, "edge_mm") == (3, 0)
