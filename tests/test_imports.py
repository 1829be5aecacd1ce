"""The pipeline's entry points keep jsonschema's slow optional IRI checker out (validation
still works) and SciPy's docstring re-parsing skipped; ``import robomill`` alone changes
nothing (robomill._imports)."""

import subprocess
import sys

CHECK = """
import robomill.pipeline, jsonschema, sys
assert sys.modules["rfc3987_syntax"] is None, "rfc3987_syntax was imported"
schema = {"type": "object", "properties": {"n": {"type": "integer", "minimum": 1}},
          "required": ["n"]}
jsonschema.validate({"n": 2}, schema)
try:
    jsonschema.validate({"n": 0}, schema)
except jsonschema.ValidationError as exc:
    print("rejected:", exc.message)
"""


def test_importing_the_pipeline_first_skips_the_iri_checker_and_still_validates():
    out = subprocess.run([sys.executable, "-c", CHECK], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr
    assert "rejected: 0 is less than the minimum of 1" in out.stdout


def test_skip_is_a_no_op_once_jsonschema_is_loaded():
    code = ("import jsonschema, sys\nfrom robomill._imports import skip_iri_format_checks\n"
            "print(skip_iri_format_checks(), sys.modules.get('rfc3987_syntax') is not None)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["False", "True"]


SCIPY_CHECK = """
import robomill.pipeline
import numpy as np
import scipy.signal as ss
from scipy._lib import _array_api
print(_array_api.FunctionDoc.__module__)
t = np.arange(8192) / 1000.0
f, p = ss.welch(np.sin(2 * np.pi * 50.0 * t), fs=1000.0, nperseg=1000)
print(float(f[np.argmax(p)]))
print("Array API Standard Support" in ss.welch.__doc__)
print(ss.welch.__doc__.startswith("Estimate power spectral density"))
print(ss.welch in _array_api.xp_capabilities_table)
"""


def _run(code: str) -> list[str]:
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0, out.stderr
    return out.stdout.split("\n")


def test_scipy_keeps_its_docstrings_unparsed_and_works_after_importing_the_pipeline():
    module, peak_hz, note, own_doc, recorded = _run(SCIPY_CHECK)[:5]
    assert module == "robomill._imports"
    assert float(peak_hz) == 50.0  # a planted 50 Hz sine, 1 Hz bins
    assert note == "False" and own_doc == "True"  # the docstring is SciPy's own, unchanged
    assert recorded == "True"  # the decorator still records the function's capabilities


def test_scipy_alone_appends_the_note_this_hook_skips():
    """Without robomill SciPy re-parses the docstring (the cost the hook removes); if a
    SciPy release stops doing it, this fails and the hook can go."""
    note = _run("import scipy.signal as ss\n"
                "print('Array API Standard Support' in ss.welch.__doc__)")[0]
    assert note == "True"


def test_scipy_hook_is_a_no_op_once_scipy_is_loaded():
    out = _run("import scipy.signal\nfrom robomill._imports import skip_scipy_capability_notes\n"
               "from scipy._lib import _array_api\n"
               "print(skip_scipy_capability_notes(), _array_api.FunctionDoc.__module__)")
    assert out[0].split() == ["False", "scipy._lib._docscrape"]


def test_the_cli_and_the_chapter_kernels_apply_the_patches_too():
    out = _run("import sys\nfrom robomill.cli import main\n"
               "try:\n    main(['--help'])\nexcept SystemExit:\n    pass\n"
               "print(sys.modules.get('rfc3987_syntax', 'absent'))")
    assert out[-2] == "None"  # blocked by main() before any verb ran
    from robomill._imports import KERNEL_STARTUP_ARGUMENT
    from robomill.pipeline.kernels import KERNEL_PRELOAD_ARGUMENT, private_kernel_manager

    code = KERNEL_STARTUP_ARGUMENT.split("=", 1)[1]
    out = _run(f"{code}\nimport scipy.signal\nfrom scipy._lib import _array_api\n"
               "print(_array_api.FunctionDoc.__module__)")
    assert out[0] == "robomill._imports"
    manager = private_kernel_manager("python3", __import__("pathlib").Path("/tmp"))()
    command = manager.format_kernel_cmd()
    assert command[-2:] == [KERNEL_STARTUP_ARGUMENT, KERNEL_PRELOAD_ARGUMENT]  # patches first


def test_importing_robomill_alone_patches_nothing():
    out = _run("import sys, robomill\nimport scipy.signal as ss\n"
               "print('rfc3987_syntax' in sys.modules and sys.modules['rfc3987_syntax'] is None)\n"
               "print('Array API Standard Support' in ss.welch.__doc__)")
    assert out[:2] == ["False", "True"]


FINAL_COLLECTION_CHECK = """
import atexit, gc, sys
# registered before the pipeline's handler, so it runs after it (atexit is last in, first out)
atexit.register(lambda: print("frozen at exit:", gc.get_freeze_count() > 0, flush=True))
import {module}
unclosed = open(sys.argv[1], "w")  # never closed: flushed when the process ends
unclosed.write("written")
cycle = []
cycle.append(cycle)
print("frozen before exit:", gc.get_freeze_count() > 0, flush=True)
"""


def _exit_run(module: str, tmp_path) -> tuple[list[str], str]:
    target = tmp_path / f"{module}.txt"
    out = subprocess.run([sys.executable, "-c", FINAL_COLLECTION_CHECK.format(module=module),
                          str(target)], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    return out.stdout.splitlines(), target.read_text()


def test_the_pipeline_skips_the_final_collection_and_still_flushes_files(tmp_path):
    lines, written = _exit_run("robomill.pipeline", tmp_path)
    assert lines == ["frozen before exit: False", "frozen at exit: True"]
    assert written == "written"
    import robomill.pipeline  # noqa: F401 (registers the handler in this process too)
    from robomill._imports import skip_final_collection

    assert skip_final_collection() is False  # registered once per process


def test_importing_robomill_alone_leaves_the_final_collection(tmp_path):
    lines, written = _exit_run("robomill", tmp_path)
    assert lines == ["frozen before exit: False", "frozen at exit: False"]
    assert written == "written"
