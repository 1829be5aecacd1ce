"""The static load of a cut on the virtual cell's robot: where the tool sits while it cuts.

The mean cutting force of the cut (Altintas 2012, eq. 2.25, the planted coefficients
``synth.cutting``, the cut's own chip load and engagement;
:func:`robomill.forces.mean_milling_forces`) rotated from the cut frame (feed u, wall normal
ẑ × u, tool axis ẑ) to the base frame, acts on the planted joint stiffness K_θ of the cell's
robot (the ``synth.loadtests`` entry of ``cell.robot.name``): the tool point moves by
δ(q) = C(q) F̄, C = J_v K_θ⁻¹ J_vᵀ (the joint model of the load tests; force only, the tool
free to rotate). A tracker run recorded while the tool cuts (a loaded pass) follows the path
displaced by δ along it; an air pass (the same path without material) does not. Without a
planted joint stiffness there is no deflection.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from robomill.experiment import Cut, cut_process, feed_direction


def planted_compliance(config: Mapping[str, Any]) -> np.ndarray | None:
    """Planted joint compliances 1/K_θ [rad/(N·m)] of the cell's robot; None when the load tests
    plant none for it."""
    name = config["cell"]["robot"].get("name")
    for e in (config["synth"].get("loadtests") or {}).get("robots") or []:
        if e.get("name") == name:
            return 1.0 / np.asarray(e["k_Nm_rad"], float)
    return None


def mean_force_base_N(cell: Any, cut: Cut) -> np.ndarray:
    """The cut's mean cutting force on the tool in the base frame [N] ``(3,)``."""
    from robomill.forces import CuttingCoefficients, mean_milling_forces
    from robomill.forces.model import engagement_angles_rad

    p = cut_process(cut, cell.experiment)
    c = cell.cutting
    k = CuttingCoefficients(c["Ktc_N_mm2"], c["Krc_N_mm2"], c["Kac_N_mm2"], c["Kte_N_mm"],
                            c["Kre_N_mm"], c["Kae_N_mm"])
    entry, exit_ = engagement_angles_rad(float(p["radial_immersion"]), p["milling"])
    F = mean_milling_forces(float(p["feed_per_tooth_mm"]), cut.depth_mm, k,
                            flutes=int(p["flutes"]), entry_rad=entry, exit_rad=exit_)
    u = feed_direction(cut)
    z = np.array([0.0, 0.0, 1.0])
    return np.stack([u, np.cross(z, u), z], -1) @ F


def static_deflection_mm(config: Mapping[str, Any], cell: Any, cut: Cut,
                         q_rad: np.ndarray) -> np.ndarray:
    """δ = C(q) F̄ [mm] ``(m, 3)`` at the postures ``q_rad`` ``(m, n)`` along the cut (zeros
    without a planted joint stiffness)."""
    compliance = planted_compliance(config)
    q = np.asarray(q_rad, float)
    if compliance is None:
        return np.zeros((len(q), 3))
    from robomill.stiffness import jacobian_m, translational_compliance_m_N

    C = translational_compliance_m_N(jacobian_m(cell.robot, q), compliance)  # (m, 3, 3) m/N
    return np.einsum("mij,j->mi", C, mean_force_base_N(cell, cut)) * 1e3
