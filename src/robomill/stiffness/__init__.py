"""Joint-stiffness model of a serial robot: identification, Cartesian and directional
stiffness, working-plane maps and the stiffness-optimal pose [Yi 2025]: the
package, one subject per submodule.

* :mod:`~robomill.stiffness.model` — the model [Yi 2025, eqs. 6–10]: Jacobian in SI units,
  TCP deflection X = J_v K_θ⁻¹ J_vᵀ F written linear in the joint compliances, Cartesian,
  translational and directional stiffness, the comprehensive index.
* :mod:`~robomill.stiffness.identify` — K_θ from load tests, observability and intervals,
  the identify/validate tables.
* :mod:`~robomill.stiffness.poses` — redundancy about the tool axis, batch IK toward TCP
  points, deflection under an end load, the stiffness-optimal pose.
* :mod:`~robomill.stiffness.maps` — working-plane stiffness maps and the Monte-Carlo
  workspace.
* :mod:`~robomill.stiffness.cuts` — stiffness along the experiment's cuts and the slot table.
* :mod:`~robomill.stiffness.figures` — the chapter's figures.
* :mod:`~robomill.stiffness.tables` — the chapter's tables, the seed's numbers beside ours.
* :mod:`~robomill.stiffness.findings` — what chapter 5 states, from the stage's artefacts.

Importing this package imports none of them: every public name is loaded from its submodule
on first use (:mod:`robomill.lazy`); the rule scripts import the submodules they use, so a
rule depends only on those (:mod:`robomill.pipeline.codedeps`).

Units inside are SI: Jacobians with linear rows in m/rad, forces in N, deflections in m,
joint stiffness in N·m/rad. A joint whose compliance the tests cannot observe is reported
with ``observable = False`` and treated as rigid (compliance 0) in predictions.
"""

from robomill.lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(__name__, {
    "cuts": ("cut_stiffness_table", "slot_stiffness_table", "stiffness_spread_pct",
             "waviness_by_direction"),
    "figures": ("beamframe_figure", "maps_figure", "optimal_figure", "slots_figure",
                "workspace_figure"),
    "findings": ("stiffness_findings",),
    "identify": ("Identification", "identify_from_tests", "identify_joint_stiffness",
                 "pose_group"),
    "maps": ("map_dataset", "monte_carlo_workspace", "plane_map", "workspace_dataset"),
    "model": ("GRAVITY_M_S2", "cartesian_stiffness", "compliance_from_table",
              "comprehensive_index_N_m", "design_matrix", "directional_stiffness_N_m", "jacobian_m",
              "predict_deflection_m", "translational_compliance_m_N"),
    "poses": ("deformation_m", "optimal_poses", "solve_poses", "tool_rotation_redundancy"),
    "tables": ("cut_stiffness_um", "joints_table", "maxima_table", "slot_means_um",
               "validation_table", "workspace_table"),
})
