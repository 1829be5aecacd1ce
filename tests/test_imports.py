"""robomill keeps jsonschema's slow optional IRI checker out, and validation still works."""

import subprocess
import sys

CHECK = """
import robomill, jsonschema, sys
assert sys.modules["rfc3987_syntax"] is None, "rfc3987_syntax was imported"
schema = {"type": "object", "properties": {"n": {"type": "integer", "minimum": 1}},
          "required": ["n"]}
jsonschema.validate({"n": 2}, schema)
try:
    jsonschema.validate({"n": 0}, schema)
except jsonschema.ValidationError as exc:
    print("rejected:", exc.message)
"""


def test_importing_robomill_first_skips_the_iri_checker_and_still_validates():
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
