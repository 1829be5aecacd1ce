"""The planner's stability model takes the axial force where the study identified K_ac: the
members' other draws stay those of the planar model, a study without K_ac gets the planar
model exactly, and the nominal member's depth is the one the chatter package's solver gives
for the same modes written out by hand in the cut frame."""

import numpy as np
import pandas as pd
import pytest

from robomill.chatter.lobes_zoa import zoa_lobes
from robomill.chatter.model import CuttingModel, ModeXY, tool_from_modes
from robomill.plan.measured import Measured
from robomill.plan.poses import cut_frames
from robomill.plan.stability import StabilitySettings, draw_members, member_depths_m

MODES = pd.DataFrame({"f_n_hz": [60.0, 72.0, 31.0], "zeta": [0.05, 0.04, 0.05],
                      "k_modal_N_m": [2.0e6, 3.0e6, 1.5e6], "shape_x": [0.30, 0.10, 0.90],
                      "shape_y": [0.20, -0.50, 0.40], "shape_z": [0.93, 0.86, -0.17]})


def coefficients(kac=222.0):
    names = ["Ktc", "Krc", "Kac", "Kte", "Kre", "Kae"]
    value = [796.0, 168.0, kac, 27.7, 30.8, 6.7]
    return pd.DataFrame({"name": names, "value": value,
                         "ci_low": [0.9 * v for v in value], "ci_high": [1.1 * v for v in value]})


def members(kac=222.0):
    return draw_members(Measured(modes=MODES, coefficients=coefficients(kac)),
                        StabilitySettings(members=8))


def depths(mem, rpm):
    frame = cut_frames(np.array([90.0]))                     # feed along +Y
    return member_depths_m(mem, {"nominal": np.ones((1, 3))}, frame, rpm, flutes=4,
                           entry_rad=0.0, exit_rad=np.pi)


def test_kac_adds_a_draw_and_changes_no_other():
    with_kac, without = members(), members(np.nan)
    assert without.ka is None
    assert with_kac.ka[0] == pytest.approx(222.0 / 796.0, rel=1e-12)
    assert np.unique(with_kac.ka).size == 8                  # drawn from its interval
    for name in ("f_hz", "zeta", "k_N_m", "kt_N_mm2", "kr", "joint_z"):
        np.testing.assert_array_equal(getattr(with_kac, name), getattr(without, name))


def test_nominal_depth_is_the_solvers_on_the_modes_by_hand():
    """Feed +Y: the cut frame's feed is base Y, its normal ẑ × Y = −X, its axis Z, so a base
    shape (x, y, z) reads (y, −x, z)."""
    rpm = np.array([9000.0, 20000.0])
    modes = [ModeXY(f, z, k, (sy, -sx, sz)) for f, z, k, sx, sy, sz in MODES.itertuples(False)]
    cut = CuttingModel(4, 796e6, 168 / 796, 0.0, np.pi, Ka=222 / 796)
    ref, _ = zoa_lobes(tool_from_modes(modes), cut, rpm)
    np.testing.assert_allclose(depths(members(), rpm)[0, 0], ref, rtol=2e-3)
    planar = [ModeXY(m.f_hz, m.zeta, m.k_N_m, m.shape[:2]) for m in modes]
    ref2, _ = zoa_lobes(tool_from_modes(planar), CuttingModel(4, 796e6, 168 / 796, 0.0, np.pi),
                        rpm)
    np.testing.assert_allclose(depths(members(np.nan), rpm)[0, 0], ref2, rtol=2e-3)
    assert np.all(np.abs(ref / ref2 - 1) > 0.05)
