"""The ``hexapod`` config section → model objects (millimetres → metres): the adapters that
tie the model to the configuration's shape, apart from the science.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from robomill.hexapod.geometry import Hexapod, Leg, joint_circle
from robomill.hexapod.motion import Programme, vertical_programme


def hexapod_from_config(section: Mapping[str, Any]) -> Hexapod:
    """Build a :class:`Hexapod` from the ``hexapod`` config section (millimetres → metres)."""
    g = section["geometry"]
    lg = section["leg"]
    p = section["platform"]
    mm = 1e-3
    return Hexapod(
        base_m=joint_circle(g["base_radius_mm"] * mm, g["base_half_angle_deg"],
                            g["base_phase_deg"]),
        platform_m=joint_circle(g["platform_radius_mm"] * mm, g["platform_half_angle_deg"],
                                g["platform_phase_deg"]),
        mass_kg=float(p["mass_kg"]),
        com_m=np.asarray(p["com_mm"], float) * mm,
        inertia_kg_m2=np.diag(np.asarray(p["inertia_kg_m2"], float)),
        leg=Leg(m1_kg=lg["cylinder_mass_kg"], c1_m=lg["cylinder_com_mm"] * mm,
                I1_kg_m2=lg["cylinder_inertia_kg_m2"], m2_kg=lg["piston_mass_kg"],
                c2_m=lg["piston_com_mm"] * mm, I2_kg_m2=lg["piston_inertia_kg_m2"],
                damping_N_s_m=lg["damping_N_s_m"]),
        gravity_m_s2=np.array([0.0, 0.0, -float(section["gravity_m_s2"])]),
    )


def programme_from_config(section: Mapping[str, Any]) -> Programme:
    """The seed's acceleration programme from the ``hexapod`` config (mm → m)."""
    pr = section["programme"]
    acc = np.asarray(pr["accel_mm_s2"], float) * 1e-3
    edges = np.asarray(pr["edges_s"], float)
    if acc.shape != (len(edges) - 1, 3):
        raise ValueError(f"hexapod.programme: {len(edges) - 1} segments need as many "
                         f"[x, y, z] rows in accel_mm_s2, got shape {acc.shape}")
    return Programme(edges_s=edges, accel_m_s2=acc,
                     start_m=np.asarray(section["start_mm"], float) * 1e-3)


def vertical_from_config(section: Mapping[str, Any]) -> Programme:
    """The seed's vertical move from the ``hexapod`` config (mm → m)."""
    v = section["vertical"]
    return vertical_programme(np.asarray(section["start_mm"], float) * 1e-3,
                              v["rise_mm"] * 1e-3, v["duration_s"])


def solver_options(section: Mapping[str, Any]) -> dict[str, Any]:
    """``rtol``, ``atol`` and ``method`` for :func:`~robomill.hexapod.motion.run_programme`
    from the config."""
    s = section["solver"]
    return {"rtol": float(s["rtol"]), "atol": float(s["atol"]), "method": s["method"]}
