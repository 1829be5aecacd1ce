"""The science subpackages split by issue 31 import nothing on ``import`` (their public names
are loaded from the submodules on first use, :mod:`robomill.lazy`), and every name the former
single modules offered is still importable from the package."""

import subprocess
import sys

import pytest

PACKAGES = {
    "robomill.chatter": ["sdm_lobes", "sdm_spectral_radius", "sem_lobes", "sem_spectral_radius",
                         "zoa_lobes", "CuttingModel", "LinearTool", "ModeXY",
                         "immersion_angles", "tool_from_modes", "chatter_findings",
                         "onset_table", "coupling_table", "case_lobes_figure",
                         "robot_lobes_figure"],
    "robomill.calibration": ["fit_circle", "VectorModel", "MassModel", "gravity_torques_Nm",
                             "joint_angle_eq15", "fit_joint_error", "fit_compliance",
                             "base_deflection_eq16", "CalibratedModel", "identify",
                             "GRAVITY_NONE", "accuracy_table", "model_to_dataset",
                             "model_from_dataset", "improvement_ratios", "region_table",
                             "calibration_findings", "a_prime_table", "validation_table",
                             "compliance_table", "joint_circle_figure",
                             "accuracy_histogram_figure"],
    "robomill.hexapod": ["Hexapod", "Leg", "inverse_kinematics", "inverse_dynamics",
                         "forward_acceleration", "run_programme", "force_error_drift",
                         "instability_rates", "hexapod_from_config", "programme_from_config",
                         "dynamics_datasets", "sensitivity_shard", "gather_sensitivity",
                         "force_accuracy_requirement", "drift_antisymmetry", "G0_M_S2"],
    "robomill.stiffness": ["jacobian_m", "identify_joint_stiffness", "identify_from_tests",
                           "compliance_from_table", "solve_poses", "optimal_poses",
                           "map_dataset", "workspace_dataset", "cut_stiffness_table",
                           "slot_stiffness_table", "GRAVITY_M_S2"],
}


@pytest.mark.parametrize("package", sorted(PACKAGES))
def test_importing_the_package_loads_none_of_its_submodules(package):
    code = (f"import sys, {package}\n"
            f"print(sorted(m for m in sys.modules if m.startswith('{package}.')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == "[]"


@pytest.mark.parametrize("package", sorted(PACKAGES))
def test_public_names_resolve_from_their_submodule(package):
    import importlib

    pkg = importlib.import_module(package)
    for name in PACKAGES[package]:
        value = getattr(pkg, name)
        assert name in pkg.__all__ and name in dir(pkg)
        owner = getattr(value, "__module__", None)
        if owner is not None and callable(value):
            assert owner.startswith(package + "."), (name, owner)
    with pytest.raises(AttributeError, match="no attribute 'not_a_name'"):
        pkg.not_a_name  # noqa: B018


def test_what_the_workflow_imports_while_parsed_stays_light():
    """The Snakefile and its rule files import these on every snakemake call, before any job:
    none may pull in the science stack (plan/outputs.py did: ~1 s per call)."""
    code = ("import sys; import robomill.plan, robomill.pipeline.codedeps, robomill.experiment, "
            "robomill.io.manifest, robomill.io.cell, robomill.io.synthetic_layout, "
            "robomill.pipeline.config; "
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('scipy', 'xarray', "
            "'matplotlib') or m.startswith(('robomill.plan.', 'robomill.straightness.'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == "[]", out


def test_a_table_of_single_strings_is_refused_not_spelt_out():
    """A module mapped to one string would export its letters; it is a TypeError instead."""
    from robomill.lazy import lazy_exports

    with pytest.raises(TypeError, match="maps a module to a list of names; 'model' maps to"):
        lazy_exports("robomill.chatter", {"model": "CuttingModel"})
    with pytest.raises(ValueError, match="'fit' is exported from both"):
        lazy_exports("robomill.chatter", {"model": ("fit",), "figures": ("fit",)})


def test_every_package_uses_the_one_lazy_helper():
    """No package writes its own ``__getattr__``: each binds :func:`robomill.lazy.lazy_exports`
    (the only module-level ``def __getattr__`` is the helper's own, inside it)."""
    import ast
    from pathlib import Path

    src = Path(__file__).resolve().parents[1] / "src" / "robomill"
    own = [str(p.relative_to(src)) for p in sorted(src.rglob("*.py"))
           for node in ast.parse(p.read_text()).body
           if isinstance(node, ast.FunctionDef) and node.name == "__getattr__"]
    assert own == []


def test_rules_follow_a_lazily_exported_name_to_its_module(tmp_path):
    """``from robomill.io import write_artefact`` ties a rule to ``io/artefacts.py``."""
    from pathlib import Path

    from robomill.pipeline.codedeps import code_files

    src = Path(__file__).resolve().parents[1] / "src"
    script = tmp_path / "script.py"
    script.write_text("from robomill.io import write_artefact\n")
    files = {Path(f).relative_to(src).as_posix() for f in code_files([script], src)}
    assert "robomill/io/artefacts.py" in files
    assert "robomill/pipeline/catalog.py" not in files
