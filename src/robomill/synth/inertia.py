"""The planted robot's inertia at a pose: the virtual robot's true masses (the cell's
documented point masses ``cell.mass_model`` unless ``synth.ctrack.true_mass_model`` plants
others, as for the C-Track simulator's gravity, :func:`robomill.synth.ctrack.true_masses`) as
a rigid-body model (:mod:`robomill.inertia`: point masses on the links, Pinocchio's
composite-rigid-body algorithm [Featherstone 2008, §6.2]). The structure
(:mod:`robomill.synth.structure`) only evaluates the kinetic energy ½ ψᵀ M(q) ψ of a joint
motion ψ, never M⁻¹.

Featherstone, R. *Rigid Body Dynamics Algorithms*. Springer, 2008.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import pinocchio as pin

from robomill.inertia import mass_matrix_kg_m2, rigid_body_model
from robomill.kinematics import SerialRobot

__all__ = ["mass_matrix_kg_m2", "planted_rigid_body_model", "rigid_body_model"]


def planted_rigid_body_model(robot: SerialRobot, config: Mapping[str, Any]) -> pin.Model | None:
    """The virtual robot's rigid-body model (module docstring); None where the configuration
    states no masses (the modes then keep their planted masses at every pose)."""
    from robomill.synth.ctrack import true_masses_or_none

    masses = true_masses_or_none(config, robot.n_joints)
    if masses is None:
        return None
    return rigid_body_model(robot, masses.link, masses.mass_kg, masses.com_mm)
