"""Stewart–Gough hexapod: kinematics, inverse and forward dynamics, sensitivity to force errors
[Rybak n.d., eqs 1–8]: the package, one subject per submodule.

The model:

* :mod:`~robomill.hexapod.geometry` — joints, legs, platform; inverse kinematics and the
  kinematic Jacobian.
* :mod:`~robomill.hexapod.dynamics` — the leg's Newton–Euler tip force, the platform's
  inverse and forward dynamics (seed eqs 6–8), energy, the closed-form static force.
* :mod:`~robomill.hexapod.motion` — forward dynamics integrated in time; acceleration
  programmes replayed open loop under their inverse-dynamics forces; the final drift when
  one actuator's force is off, and the instability rates that make it grow.
* :mod:`~robomill.hexapod.sensitivity` — the gathered drift map and the force accuracy a
  position tolerance needs.
* :mod:`~robomill.hexapod.figures` — the chapter's figures and its tables beside the seed's.
* :mod:`~robomill.hexapod.findings` — what chapter 6 states, from the stage's artefacts.

Apart from the model, what ties it to the configuration's shape:

* :mod:`~robomill.hexapod.config` — the ``hexapod`` config section → model objects (mm → m).
* :mod:`~robomill.hexapod.study` — the chapter's datasets and one sensitivity shard from the
  config section.

Importing this package imports none of them: every public name is loaded from its submodule
on first use (:mod:`robomill.lazy`); the rule scripts import the submodules they use, so a
rule depends only on those (:mod:`robomill.pipeline.codedeps`).

Units: SI throughout (m, kg, s, N, rad); the config and the datasets in mm, deg, N.
"""

from robomill.lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(__name__, {
    "config": ("hexapod_from_config", "programme_from_config", "solver_options",
               "vertical_from_config"),
    "dynamics": ("dynamic_model", "forward_acceleration", "inverse_dynamics", "leg_energy",
                 "leg_inertia", "leg_tip_force", "platform_inertia", "static_force_closed_form",
                 "total_energy"),
    "figures": ("VERTICAL_ROWS", "drift_map_figure", "forces_figure", "seed_table1",
                "trajectory_figure", "vertical_figure", "vertical_table"),
    "findings": ("hexapod_findings",),
    "geometry": ("G0_M_S2", "Hexapod", "Leg", "Legs", "euler_to_matrix", "inverse_kinematics",
                 "jacobian", "joint_circle", "matrix_to_euler", "skew", "tip_jacobian"),
    "motion": ("ForceLaw", "Programme", "Simulation", "pose_error", "programme_forces",
               "run_programme", "simulate", "state_vector", "unpack_state",
               "vertical_programme", "force_error_drift", "instability_rates"),
    "sensitivity": ("FORCE_ACCURACY_TOLERANCES_MM", "drift_antisymmetry",
                    "force_accuracy_requirement", "gather_sensitivity"),
    "study": ("ANGLES", "AXES", "dynamics_datasets", "sensitivity_shard"),
})
