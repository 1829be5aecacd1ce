"""Robot calibration by the single-joint (circle point) method (thesis ch. 1): the
package, one subject per submodule.

Everything is expressed in one fixed measurement frame (the C-Track frame, registered to the
robot base; gravity along −z). The chain of the chapter:

1. :mod:`~robomill.calibration.geometry` — circle fits (a target on link i, joint i rotated
   alone, traces a circle → axis e_i and centre O_i; Stone 1986) and the vector model of
   eq. 1.4 with the Rodrigues rotations of eq. 1.3.
2. :mod:`~robomill.calibration.gravity` — point masses on the links and their joint torques.
3. :mod:`~robomill.calibration.joint_errors` — joint positioning errors by eq. 1.5 on the
   two-direction mean (cancels backlash) and their regression on the joint angle (Fourier
   terms at the gear orders + a low-order polynomial, chosen on held-out steps).
4. :mod:`~robomill.calibration.compliance` — joint compliance from load-disc tests,
   Δp = Σ_j c_j Δτ_j e_j × (p − O_j), and the base deflection of eq. 1.6, linear in the
   joint-2 torque and lumped into joint 2.
5. :mod:`~robomill.calibration.identification` — the calibrated model and the whole
   identification from the C-Track tables.
6. :mod:`~robomill.calibration.accuracy` — accuracy of the nominal, geometric and full models
   on points not used for identification.
7. :mod:`~robomill.calibration.dataset` — ``model.nc`` and the chapter's tables.
8. :mod:`~robomill.calibration.findings` — the numbers chapter 1 states.
9. :mod:`~robomill.calibration.tables` and :mod:`~robomill.calibration.figures` — the
   chapter's tables and figures.

Importing this package imports none of them: every public name is loaded from its submodule
on first use (:mod:`robomill.lazy`), so ``from robomill.calibration import identify`` keeps
working while the rule scripts import the submodules they use and a rule depends only on
those (:mod:`robomill.pipeline.codedeps`).

Lengths in mm, angles in rad, torques in N·m, compliances in rad/(N·m).
"""

from robomill.lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(__name__, {
    "accuracy": ("MODELS", "accuracy_by_region", "accuracy_points", "accuracy_table",
                 "error_stats", "improvement_ratios", "region_table", "workspace_regions"),
    "compliance": ("base_deflection", "base_deflection_eq16", "compliance_corrected",
                   "compliance_displacement", "fit_compliance", "linear_fit",
                   "single_joint_poses"),
    "dataset": ("circle_table", "joint_error_table", "model_from_dataset", "model_to_dataset"),
    "findings": ("calibration_findings",),
    "figures": ("accuracy_histogram_figure", "base_deflection_figure", "joint_circle_figure",
                "joint_errors_figure", "vector_model_figure"),
    "tables": ("a_prime_table", "compliance_table", "validation_table"),
    "geometry": ("CircleFit", "VectorModel", "fit_circle", "vector_model_from_serial"),
    "gravity": ("G_MM_S2", "MassModel", "gravity_torques_Nm", "mass_model_from_cell",
                "mass_model_from_mapping", "no_masses"),
    "identification": ("GRAVITY_NONE", "CalibratedModel", "Identification", "identify",
                       "identify_geometry"),
    "joint_errors": ("JointErrorFit", "fit_joint_error", "joint_angle_eq15", "step_errors"),
})
