"""The virtual robot cell: one ground truth from which every instrument simulator draws.

The virtual cell joins the facts of the cell (``config.yaml: cell``: the robot's nominal
geometry and gear trains, the same mapping written to the raw folder as ``cell.yaml``) with
the planted truth of ``config.yaml: synth``: the gear eccentricities, the tool-tip modal
model, the cutting coefficients and the seed. Every simulator takes its physics from here, so
that instruments agree the way real ones do: the same eccentric gears make the tracker's
straightness error and the surface waviness; the same modes ring in the impact test and in
the cut (:mod:`robomill.synth.structure` moves them with the pose; every instrument of a cut
reads the one closed-loop cut of :mod:`robomill.synth.process`).

Geometry of the experiment (``config.yaml: experiment.layout``): the block frame R0 has its
origin at ``block_origin_mm`` in the robot base frame and axes parallel to the base axes; the
tool axis points down (−Z). Segment g of set s is a U whose corner is at
``(margin + (g−1)·segment_pitch, margin + (s−1)·set_pitch)`` in R0; its cuts run +Y from the
corner, then +X, then −Y, each ``cut_length_mm`` long, at the depth of the set.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import xarray as xr

from robomill.experiment import Cut, cut_endpoints_mm, cut_tool_rotation
from robomill.kinematics import SerialRobot, robot_from_mapping

ARCSEC = np.pi / (180.0 * 3600.0)


@dataclass(frozen=True)
class GearStage:
    """One rotating element of a joint transmission.

    ``rev_per_joint_rev`` revolutions of this element per revolution of the joint output;
    ``teeth`` its tooth count (mesh order = rev × teeth). Its transmission error, seen at the
    joint output, is ``runout_rad·sin(r q + φ_r) + mesh_rad·sin(r z q + φ_m)`` (once-per-rev
    eccentricity and tooth-mesh error; Slamani & Bonev 2013).
    """

    joint: int
    stage: str
    rev_per_joint_rev: float
    teeth: int
    runout_rad: float
    mesh_rad: float
    runout_phase_rad: float
    mesh_phase_rad: float

    def joint_error_rad(self, q_rad: np.ndarray) -> np.ndarray:
        r = self.rev_per_joint_rev
        return (self.runout_rad * np.sin(r * q_rad + self.runout_phase_rad)
                + self.mesh_rad * np.sin(r * self.teeth * q_rad + self.mesh_phase_rad))


@dataclass(frozen=True)
class Mode:
    """A tool-tip mode: natural frequency, damping ratio, modal stiffness and 3-D shape.

    The shape is a unit vector in the base frame (X, Y, Z); the receptance contribution is
    ``φ φᵀ / (k (1 − r² + 2jζr))``, r = ω/ω_n.
    """

    f_hz: float
    zeta: float
    k_N_m: float
    shape: tuple[float, float, float]

    @property
    def m_kg(self) -> float:
        return self.k_N_m / (2 * np.pi * self.f_hz) ** 2


@dataclass
class VirtualCell:
    """Ground truth of the simulated robot cell (``config.yaml: synth`` + ``experiment``)."""

    robot: SerialRobot
    gears: list[GearStage]
    modes: list[Mode]
    cutting: dict[str, float]
    experiment: dict[str, Any]
    seed: int
    config: dict[str, Any] = field(default_factory=dict)
    q_home_rad: np.ndarray = field(default_factory=lambda: np.zeros(6))
    tool_rotation_matrix: np.ndarray = field(
        default_factory=lambda: np.array([[1.0, 0, 0], [0, -1.0, 0], [0, 0, -1.0]]))
    spindle_modes: list[Mode] = field(default_factory=list)
    """Pose-independent modes of the spindle and tool (``synth.process.spindle_modes``)."""
    joint_stiffness_Nm_rad: np.ndarray | None = None
    """Planted joint stiffness K_θ of the robot (:mod:`robomill.synth.structure`)."""
    q_reference_rad: np.ndarray | None = None
    """The pose at which :attr:`modes` are the robot's modes (the impact test's pose)."""
    rigid_body_model: Any = None
    """The robot's rigid-body model for its mass matrix M(q) (:mod:`robomill.synth.inertia`;
    None without masses)."""
    robot_modes_law: str | None = None
    """``synth.process.robot_modes``: ``"eigen"`` moves the robot's modes by the eigenproblem
    of the joints and the calibrated mass matrix (shapes turning with the pose); anything else
    by the planted law (fixed shapes), :mod:`robomill.synth.structure`."""
    _structure: Any = field(default=None, repr=False, compare=False)

    @property
    def robot_structure(self) -> Any:
        """The arm's calibrated eigenmodel at :attr:`q_reference_rad`
        (:func:`robomill.synth.structure.robot_structure`; None without joint stiffness,
        reference pose or masses), computed once for the cell's current model."""
        from robomill.synth.structure import robot_structure

        key = (id(self.rigid_body_model), id(self.modes),
               None if self.q_reference_rad is None else np.asarray(self.q_reference_rad).tobytes(),
               None if self.joint_stiffness_Nm_rad is None
               else np.asarray(self.joint_stiffness_Nm_rad).tobytes())
        if self._structure is None or self._structure[0] != key:
            self._structure = (key, robot_structure(self))
        return self._structure[1]

    # ---- geometry of the cuts -------------------------------------------------------------
    def cut_endpoints_mm(self, cut: Cut, set_index: int | None = None) -> tuple[np.ndarray,
                                                                              np.ndarray]:
        """Start and end of a cut's TCP path in the robot base frame [mm] (slot floor;
        :func:`robomill.experiment.cut_endpoints_mm`)."""
        return cut_endpoints_mm(cut, self.experiment, set_index)

    def tool_rotation(self) -> np.ndarray:
        """TCP orientation while milling (``cell.tool_rotation``; default tool z axis down)."""
        return np.array(self.tool_rotation_matrix, float)

    def cut_path_mm(self, cut: Cut, s_mm: np.ndarray) -> np.ndarray:
        """Nominal TCP positions ``(len(s), 3)`` at path abscissae ``s_mm`` along a cut."""
        a, b = self.cut_endpoints_mm(cut)
        u = (b - a) / np.linalg.norm(b - a)
        return a + np.outer(np.asarray(s_mm, float), u)

    def cut_tool_rotation(self, cut: Cut) -> np.ndarray:
        """The tool's orientation while cutting ``cut``: R0 Rz(θ) for the cut's redundancy
        angle θ (``redundancy_deg``: rotation about the tool axis,
        :func:`robomill.experiment.cut_tool_rotation`, the analyses' own); R0 itself at
        θ = 0."""
        return cut_tool_rotation(cut, self.tool_rotation())

    def joint_path_rad(self, cut: Cut, s_mm: np.ndarray) -> np.ndarray:
        """Joint angles ``(len(s), 6)`` along the cut, by inverse kinematics (elbow-up branch
        nearest ``q_home_rad``) at the cut's tool orientation (:meth:`cut_tool_rotation`): the
        posture, hence the gear errors, the joint torques and the Jacobian every simulator
        carries them through, follow the cut's redundancy angle."""
        P = self.cut_path_mm(cut, s_mm)
        T = np.broadcast_to(np.eye(4), (len(P), 4, 4)).copy()
        T[:, :3, :3] = self.cut_tool_rotation(cut)
        T[:, :3, 3] = P
        return self.robot.ik_path(T, self.q_home_rad)

    # ---- gear-train errors ------------------------------------------------------------------
    def joint_error_rad(self, q_rad: np.ndarray) -> np.ndarray:
        """Planted joint positioning error ``(..., 6)`` from every gear stage at angles q."""
        q = np.asarray(q_rad, float)
        dq = np.zeros_like(q)
        for g in self.gears:
            dq[..., g.joint - 1] += g.joint_error_rad(q[..., g.joint - 1])
        return dq

    def tcp_error_mm(self, q_rad: np.ndarray) -> np.ndarray:
        """TCP position error ``(..., 3)`` [mm] from the gear errors, through the Jacobian."""
        J = self.robot.jacobian(q_rad)[..., :3, :]
        return np.einsum("...ij,...j->...i", J, self.joint_error_rad(q_rad))

    def gear_spatial_frequency_per_mm(self, cut: Cut, n_points: int = 41) -> list[dict]:
        """Spatial frequency of every gear element (runout and mesh) during a cut.

        Revolutions per mm of path: ``r · |Δq_j| / (2π · L)`` averaged over the cut (a
        straight path at constant speed: independent of feed).
        """
        L = float(self.experiment["cut_length_mm"])
        q = self.joint_path_rad(cut, np.linspace(0.0, L, n_points))
        rate = np.abs(q[-1] - q[0]) / L  # rad per mm, mean over the cut
        out = []
        for g in self.gears:
            f1 = g.rev_per_joint_rev * rate[g.joint - 1] / (2 * np.pi)
            out.append({"joint": g.joint, "stage": g.stage, "order": "runout",
                        "f_spatial_per_mm": f1})
            out.append({"joint": g.joint, "stage": g.stage, "order": "mesh",
                        "f_spatial_per_mm": f1 * g.teeth})
        return out

    # ---- modal model -----------------------------------------------------------------------
    def receptance_m_per_N(self, f_hz: np.ndarray) -> np.ndarray:
        """Tool-tip receptance matrix ``(3, 3, len(f))`` [m/N] in base axes X, Y, Z.

        .. math:: H(ω) = \\sum_r \\frac{φ_r φ_r^T}{k_r (1 − (ω/ω_r)^2 + 2jζ_r ω/ω_r)}
        """
        f = np.asarray(f_hz, float)
        H = np.zeros((3, 3, f.size), complex)
        for m in self.modes:
            r = f / m.f_hz
            phi = np.asarray(m.shape, float)
            H += np.einsum("i,j,f->ijf", phi, phi, 1.0 / (m.k_N_m * (1 - r**2 + 2j * m.zeta * r)))
        return H

    # ---- truth --------------------------------------------------------------------------
    def truth(self) -> xr.Dataset:
        """The planted ground truth as a labelled dataset (``results/synthetic/truth.nc``)."""
        from robomill.synth.structure import robot_modes_at

        gear = np.arange(len(self.gears))
        mode = np.arange(1, len(self.modes) + 1)
        # the robot's modes where the impact test is made (under the eigen law their shapes
        # are the eigenproblem's)
        modes = (robot_modes_at(self, self.q_reference_rad)
                 if self.q_reference_rad is not None else list(self.modes))

        def v(dim, data, units, long_name):
            return (dim, np.asarray(data), {"units": units, "long_name": long_name})

        ds = xr.Dataset(
            {
                "gear_joint": v("gear", [g.joint for g in self.gears], "1", "joint of gear"),
                "gear_stage": v("gear", [g.stage for g in self.gears], "1", "gear stage name"),
                "gear_rev_per_joint_rev": v("gear", [g.rev_per_joint_rev for g in self.gears],
                                            "1", "revolutions per joint revolution"),
                "gear_teeth": v("gear", [g.teeth for g in self.gears], "1", "tooth count"),
                "gear_runout_rad": v("gear", [g.runout_rad for g in self.gears], "rad",
                                     "once-per-revolution transmission error amplitude"),
                "gear_mesh_rad": v("gear", [g.mesh_rad for g in self.gears], "rad",
                                   "tooth-mesh transmission error amplitude"),
                "gear_runout_phase_rad": v("gear", [g.runout_phase_rad for g in self.gears],
                                           "rad", "runout phase"),
                "gear_mesh_phase_rad": v("gear", [g.mesh_phase_rad for g in self.gears], "rad",
                                         "mesh phase"),
                "mode_f_hz": v("mode", [m.f_hz for m in modes], "Hz", "natural frequency"),
                "mode_zeta": v("mode", [m.zeta for m in modes], "1", "damping ratio"),
                "mode_k_N_m": v("mode", [m.k_N_m for m in modes], "N/m",
                                "modal stiffness at the tool tip"),
                "mode_m_kg": v("mode", [m.m_kg for m in modes], "kg",
                               "modal mass at the tool tip"),
                "mode_shape": (("mode", "axis"), np.array([m.shape for m in modes]),
                               {"units": "1", "long_name": "unit mode shape at the tool "
                                                           "tip, at the impact test's pose"}),
            },
            coords={
                "gear": ("gear", gear, {"units": "1", "long_name": "gear index"}),
                "mode": ("mode", mode, {"units": "1", "long_name": "mode number"}),
                "axis": ("axis", ["X", "Y", "Z"], {"units": "1", "long_name": "base axis"}),
            },
            attrs={"seed": self.seed, "robot": self.robot.name},
        )
        if self.spindle_modes:
            sm = self.spindle_modes
            ds["spindle_mode_f_hz"] = v("spindle_mode", [m.f_hz for m in sm], "Hz",
                                        "spindle/tool natural frequency")
            ds["spindle_mode_zeta"] = v("spindle_mode", [m.zeta for m in sm], "1",
                                        "spindle/tool damping ratio")
            ds["spindle_mode_k_N_m"] = v("spindle_mode", [m.k_N_m for m in sm], "N/m",
                                         "spindle/tool modal stiffness at the tool tip")
            ds["spindle_mode_shape"] = (("spindle_mode", "axis"), np.array([m.shape for m in sm]),
                                        {"units": "1", "long_name": "unit spindle mode shape"})
        for name, value in self.cutting.items():
            unit = "N/mm^2" if name.endswith("N_mm2") else "N/mm"
            ds[f"cutting_{name}"] = ((), float(value), {"units": unit,
                                                        "long_name": f"cutting coefficient {name}"})
        return ds


def _gears_from_config(transmissions: Sequence[Mapping], errors: Sequence[Mapping],
                       rng: np.random.Generator) -> list[GearStage]:
    """The planted gear stages: the cell's nominal ``transmissions`` (``config.yaml: cell``)
    with the error amplitudes of ``synth.gears`` matched by (joint, stage); a transmission
    without an entry has no error. Phases are drawn in the order of the transmissions."""
    from robomill.errors import ConfigError

    planted = {(int(g["joint"]), str(g["stage"])): g for g in errors}
    known = {(int(t["joint"]), str(t["stage"])) for t in transmissions}
    unknown = sorted(set(planted) - known)
    if unknown:
        raise ConfigError(f"config key 'synth.gears': joint {unknown[0][0]} stage "
                          f"{unknown[0][1]!r} is not a transmission of config key "
                          "'cell.transmissions'")
    out = []
    for t in transmissions:
        g = planted.get((int(t["joint"]), str(t["stage"])), {})
        phases = rng.uniform(0, 2 * np.pi, size=2)
        out.append(GearStage(
            joint=int(t["joint"]), stage=str(t["stage"]),
            rev_per_joint_rev=float(t["rev_per_joint_rev"]), teeth=int(t["teeth"]),
            runout_rad=float(g.get("runout_arcsec", 0.0)) * ARCSEC,
            mesh_rad=float(g.get("mesh_arcsec", 0.0)) * ARCSEC,
            runout_phase_rad=float(g.get("runout_phase_rad", phases[0])),
            mesh_phase_rad=float(g.get("mesh_phase_rad", phases[1]))))
    return out


def cell_from_config(config: Mapping[str, Any]) -> VirtualCell:
    """Build the virtual cell from the whole (validated) configuration mapping: the facts of
    ``cell`` (robot, home, tool rotation, transmissions) with the planted truth of ``synth``."""
    syn, facts = config["synth"], config["cell"]
    rng = np.random.default_rng(int(syn["seed"]))
    robot = robot_from_mapping(facts["robot"])
    modes = _modes_from_config(syn["modes"])
    q_home = np.deg2rad(np.asarray(facts.get("q_home_deg", [0, 0, 0, 0, 0, 0]), float))
    gears = _gears_from_config(facts["transmissions"], syn["gears"], rng)
    R = np.asarray(facts.get("tool_rotation", [[1, 0, 0], [0, -1, 0], [0, 0, -1]]), float)
    from robomill.settings import config_section
    from robomill.synth.structure import joint_stiffness_Nm_rad, reference_pose_rad

    process = syn.get("process") or {}
    cell = VirtualCell(robot=robot, gears=gears, modes=modes,
                       cutting={k: float(v) for k, v in syn["cutting"].items()},
                       experiment=dict(config["experiment"]), seed=int(syn["seed"]),
                       config=dict(config), q_home_rad=q_home, tool_rotation_matrix=R,
                       spindle_modes=_modes_from_config(process.get("spindle_modes") or []),
                       joint_stiffness_Nm_rad=joint_stiffness_Nm_rad(config))
    if cell.joint_stiffness_Nm_rad is not None and "process" in syn:
        from robomill.synth.inertia import planted_rigid_body_model

        cell.q_reference_rad = reference_pose_rad(cell, config)
        cell.robot_modes_law = config_section(config, "synth.process")["robot_modes"]
        cell.rigid_body_model = planted_rigid_body_model(robot, config)
    return cell


def _modes_from_config(entries: Sequence[Mapping]) -> list[Mode]:
    """Modes ``{f_hz, zeta, k_N_m, shape}`` of the configuration, shapes normalized."""
    modes = []
    for m in entries:
        shape = np.asarray(m["shape"], float)
        shape = shape / np.linalg.norm(shape)
        modes.append(Mode(float(m["f_hz"]), float(m["zeta"]), float(m["k_N_m"]),
                          tuple(float(x) for x in shape)))
    return modes
