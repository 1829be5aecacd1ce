"""Gravity torques on the joints of the calibrated robot (thesis §1.4): point masses fixed to
links and the torque their weight applies about each joint axis.

The mass model comes from the cell file (:func:`mass_model_from_cell`) or a mapping
(:func:`mass_model_from_mapping`); a compliant joint deflects by c_j τ_j
(:mod:`robomill.calibration.compliance`). Lengths in mm, masses in kg, torques in N·m.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from robomill.calibration.geometry import VectorModel

G_MM_S2 = np.array([0.0, 0.0, -9.81])
"""Gravity acceleration [m/s²] in the measurement frame (z up)."""


@dataclass
class MassModel:
    """Point masses fixed to links (zero-configuration positions in the measurement frame).

    ``link`` is 1..n (the link a mass rides on); torques about joint j come from every mass on
    links ≥ j.
    """

    link: np.ndarray
    mass_kg: np.ndarray
    com_mm: np.ndarray

    def __post_init__(self):
        self.link = np.asarray(self.link, int)
        self.mass_kg = np.asarray(self.mass_kg, float)
        self.com_mm = np.asarray(self.com_mm, float).reshape(-1, 3)

    def plus(self, link: int, mass_kg: float, com_mm: np.ndarray) -> MassModel:
        """A copy with one more point mass (payload, load discs)."""
        return MassModel(np.r_[self.link, link], np.r_[self.mass_kg, mass_kg],
                         np.vstack([self.com_mm, np.asarray(com_mm, float)]))


def gravity_torques_Nm(model: VectorModel, masses: MassModel, theta: np.ndarray) -> np.ndarray:
    """Joint torques ``(..., n)`` [N·m] of gravity on the point masses at ``theta``.

    .. math:: τ_j = e_j · \\sum_{k: link_k ≥ j} (c_k − O_j) × m_k g

    (the torque gravity applies about axis j; a compliant joint deflects by c_j τ_j).
    """
    theta = np.asarray(theta, float)
    R, t = model.link_poses(theta)
    e, o = model.joint_lines(theta)
    tau = np.zeros(theta.shape)
    for link, m, c0 in zip(masses.link, masses.mass_kg, masses.com_mm, strict=True):
        c = np.einsum("...ij,j->...i", R[..., link - 1, :, :], c0) + t[..., link - 1, :]
        F = m * G_MM_S2
        for j in range(link):
            tau[..., j] += np.einsum("...i,...i->...", e[..., j, :],
                                     np.cross(c - o[..., j, :], F)) * 1e-3
    return tau


def mass_model_from_mapping(spec: Mapping, n_links: int | None = None) -> MassModel:
    """``{links: [{link, mass_kg, com_mm}], tool: {mass_kg, com_mm}}`` → :class:`MassModel`.

    The tool (spindle and tool, optional) rides on the last link: ``n_links`` when given,
    else the highest link listed.
    """
    links = list(spec["links"])
    n = n_links or max(int(x["link"]) for x in links)
    mm = MassModel([int(x["link"]) for x in links], [float(x["mass_kg"]) for x in links],
                   np.array([x["com_mm"] for x in links], float))
    tool = spec.get("tool")
    if tool:
        mm = mm.plus(n, float(tool["mass_kg"]), np.asarray(tool["com_mm"], float))
    return mm


def mass_model_from_cell(cell) -> MassModel | None:
    """The gravity model of a :class:`robomill.io.cell.Cell`: its ``mass_model`` (links, then
    the tool on the last link) as a :class:`MassModel`, or None when the cell file states no
    mass model (the identification then runs without the gravity term,
    :func:`~robomill.calibration.identification.identify`)."""
    spec = cell.mass_model
    if spec is None:
        return None
    points = spec.point_masses()
    return MassModel([m.link for m in points], [m.mass_kg for m in points],
                     np.array([m.com_mm for m in points], float))


def no_masses() -> MassModel:
    """An empty :class:`MassModel` (gravity torques identically zero)."""
    return MassModel(np.zeros(0, int), np.zeros(0), np.zeros((0, 3)))
