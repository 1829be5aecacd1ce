"""Figure and table numbering of the chapters (robomill.pipeline.captions)."""

import pytest

from robomill.pipeline.captions import Numbering


def test_numbers_follow_the_thesis_or_continue_in_sequence():
    num = Numbering("2")
    assert num.figure("detrend", "Measured and detrended profile", number=9) == "Figure 2.9"
    assert num.figure("next", "Continues after the largest") == "Figure 2.10"
    assert num.figure("set1", "Set 1", number=17, part="a") == "Figure 2.17a"
    assert num.figure("set2", "Set 2", number=17, part="b") == "Figure 2.17b"
    assert num.table("rms", "RMS") == "Table 2.1"
    assert num.table("peaks", "Peaks") == "Table 2.2"
    assert num.file("detrend") == "fig2_9_detrend"
    assert num.file("set1") == "fig2_17_set1"
    assert num.labels() == ["Figure 2.9", "Figure 2.10", "Figure 2.17a", "Figure 2.17b",
                            "Table 2.1", "Table 2.2"]


def test_caption_and_reference_text():
    num = Numbering("3")
    num.figure("deviation", "Deviation along +Y", number=12)
    assert num.ref("deviation") == "Figure 3.12"
    assert num.caption_text("deviation") == "Figure 3.12 — Deviation along +Y."
    md = num.caption("deviation").data
    assert "<b>Figure 3.12</b> — Deviation along +Y." in md
    num.check()


def test_check_names_what_was_never_shown_or_referred_to():
    num = Numbering("5")
    num.figure("a", "shown only")
    num.figure("b", "referred only")
    num.table("c", "neither")
    num.caption_text("a")
    num.ref("b")
    with pytest.raises(ValueError) as info:
        num.check()
    msg = str(info.value)
    assert "Figure 5.1 ('a') never referred to" in msg
    assert "Figure 5.2 ('b') never shown" in msg
    assert "Table 5.1 ('c') never shown and never referred to" in msg


def test_duplicates_and_unknown_keys_are_refused():
    num = Numbering("6")
    num.figure("a", "x", number=1)
    with pytest.raises(ValueError, match="declared twice"):
        num.figure("a", "again")
    with pytest.raises(ValueError, match=r"Figure 6.1 is used by both 'a' and 'b'"):
        num.figure("b", "same number", number=1)
    with pytest.raises(KeyError, match="no figure or table 'zz'.*declared: a"):
        num.ref("zz")


def test_show_saves_the_figure_under_its_number_and_captions_it(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    num = Numbering("6", fig_dir=str(tmp_path / "figs"))
    num.figure("drift", "Drift of the platform", number=11)
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    num.show(fig, "drift")
    assert (tmp_path / "figs" / "fig6_11_drift.png").stat().st_size > 0
    num.ref("drift")
    num.check()  # shown (captioned) and referred to
    with pytest.raises(ValueError, match="fig_dir"):
        Numbering("6").show(fig, "drift")
