"""Findings (robomill.findings), their prose (robomill.pipeline.prose) and the reference data
(robomill.references): round trip, plain YAML, absent fields, the one file of source numbers."""

import numpy as np
import pytest
import yaml

from robomill import references
from robomill.findings import Findings, comparison_rows, read_findings, write_findings
from robomill.pipeline.prose import Prose, render
from robomill.pipeline.scorecard import load_checks


def test_findings_round_trip_as_plain_yaml(tmp_path):
    f = Findings("demo")
    f.add("n_modes", np.int64(3), artefact="results/x/modes.csv", what="rows")
    f.add("modes_hz", np.array([20.5, 35.25]), "Hz")
    f.add("missing", np.nan)
    f.add("close", np.bool_(True), verdict="possible", threshold=0.15,
          config_key="modal.coupling_tolerance")
    path = tmp_path / "findings.yaml"
    write_findings(f, path)
    raw = yaml.safe_load(path.read_text())  # plain YAML: no python tags, numbers as numbers
    assert "!!python" not in path.read_text()
    values = {d["key"]: d["value"] for d in raw["findings"]}
    assert values == {"n_modes": 3, "modes_hz": [20.5, 35.25], "missing": None, "close": True}
    back = read_findings(path)
    assert back.values()["modes_hz"] == [20.5, 35.25]
    assert back["close"].threshold == 0.15
    assert back["close"].config_key == "modal.coupling_tolerance"
    assert back.values()["threshold_close"] == 0.15


def test_a_verdict_needs_its_threshold_and_config_key():
    with pytest.raises(ValueError, match="threshold"):
        Findings("x").add("ok", True, verdict="pass")


def test_bad_findings_file_is_one_clear_error(tmp_path):
    p = tmp_path / "findings.yaml"
    p.write_text("findings:\n- value: 3\n")
    with pytest.raises(ValueError, match=r"findings\[0\].*'key'"):
        read_findings(p)


def test_prose_fills_fields_and_falls_back_to_absent():
    t = {"text": "{n} modes: {hz:.1f} Hz", "absent": "no modes"}
    assert render(t, {"n": 2, "hz": [20.04, 35.26]}) == "2 modes: 20.0, 35.3 Hz"
    assert render(t, {"n": 2}) == "no modes"  # missing field
    assert render(t, {"n": 2, "hz": None}) == "no modes"  # null field
    assert render(t, {"n": 2, "hz": "text"}) == "no modes"  # cannot format
    assert render("{a[1]:g}", {"a": [1, 2]}) == "2"
    assert render("{a[5]:g}", {"a": [1, 2]}) == ""  # index out of range: absent, no error


def test_prose_when_unless_cases_and_separator():
    t = {"when": ["a", "b"], "unless": "c", "text": "{x:|; }", "absent": "off"}
    assert render(t, {"a": 1, "b": 1, "c": 0, "x": ["p", "q"]}) == "p; q"
    assert render(t, {"a": 1, "b": 0, "x": ["p"]}) == "off"
    assert render(t, {"a": 1, "b": 1, "c": 1, "x": ["p"]}) == "off"
    c = {"by": "kind", "cases": {"flip": "flip at {f:.0f}"}, "absent": "other"}
    assert render(c, {"kind": "flip", "f": 210.2}) == "flip at 210"
    assert render(c, {"kind": "hopf", "f": 1.0}) == "other"
    say = Prose({"a": "A={a}", "b": {"text": "B={b}"}}, {"a": 1})
    assert say("a", "b") == "A=1"  # an absent sentence leaves no gap
    with pytest.raises(KeyError, match="no template"):
        say("zzz")


def test_comparison_rows_keep_ours_the_source_the_verdict_and_the_citation():
    rows = comparison_rows([{"source": "thesis", "where": "Table 9", "quantity": "q",
                             "ours": np.float64(1.5), "source_value": 2.0, "unit": "Hz",
                             "tolerance": "± 10 %", "verdict": "miss", "reason": "why"}])
    assert rows == [{"quantity": "q", "ours": 1.5, "source_value": 2.0, "unit": "Hz",
                     "tolerance": "± 10 %", "verdict": "miss", "reason": "why",
                     "citation": "thesis, Table 9"}]


def test_every_reference_has_a_value_and_a_citation():
    refs = references.load_references()
    assert len(refs) > 120
    for key, ref in refs.items():
        assert ref["source"] and ref["where"] and ref["quantity"], key
        # a number or a range; a text only for the source's setup (thesis.cell.*)
        assert isinstance(ref["value"], int | float | list) or (
            key.startswith("thesis.cell.") and isinstance(ref["value"], str)), key


def test_scorecard_numbers_come_from_references_once():
    text = (references.resources.files("robomill.data") / "scorecard.yaml").read_text()
    raw = yaml.safe_load(text)["checks"]
    assert all("source_value" not in c and "reference" in c for c in raw)
    checks = load_checks()
    by_key = {c["reference"]: c for c in checks}
    ref = references.reference("thesis.modal.modes.f_n_hz.mode_3")
    assert by_key["thesis.modal.modes.f_n_hz.mode_3"]["source_value"] == ref["value"] == 60.0
    assert by_key["thesis.modal.modes.f_n_hz.mode_3"]["where"] == ref["where"]


def test_module_constants_are_reference_keys():
    from robomill.modal.peaks import THESIS_NATURAL_HZ

    assert THESIS_NATURAL_HZ == tuple(
        references.value(f"thesis.modal.modes.f_n_hz.mode_{m}") for m in range(1, 7))
    with pytest.raises(KeyError, match="no entry"):
        references.value("thesis.nothing")
