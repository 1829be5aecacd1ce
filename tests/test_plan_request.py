"""plan.yaml validation (robomill.plan.request): good requests expand their grids, bad ones
give one line naming the file, the field and what was expected."""

import copy

import numpy as np
import pytest
import yaml

from robomill.plan.request import PlanRequestError, parse_request, read_request

GOOD = {
    "kind": "plan",
    "operation": {"milling": "down", "radial_immersion": 0.5, "length_mm": 30,
                  "directions": ["px", 45]},
    "tool": {"diameter_mm": 8, "flutes": 3},
    "placement": {"box": {"min_mm": [500, -100, 0], "max_mm": [600, 100, 0], "n": [3, 2, 1]}},
    "rotations_deg": {"min": -30, "max": 30, "n": 3},
    "spindle_rpm": {"min": 10000, "max": 20000, "n": 11},
    "depth_mm": [0.3, 0.1],
    "feed_mm_s": [2, 4],
    "constraints": {"min_stability_margin": 0.2, "max_force_N": 150},
}


def test_good_request_expands():
    r = parse_request(GOOD, "p.yaml")
    assert r.placements_mm.shape == (6, 3)
    assert np.allclose(r.placements_mm[:3, 0], [500, 550, 600])
    assert np.allclose(r.rotations_deg, [-30, 0, 30])
    assert len(r.spindle_rpm) == 11 and r.spindle_rpm[-1] == 20000
    assert list(r.depth_mm) == [0.1, 0.3]
    assert list(r.direction_deg) == [0.0, 45.0]
    assert r.width_mm == pytest.approx(4.0)
    assert r.constraints["max_force_N"] == 150 and r.constraints["max_waviness_um"] is None


def test_default_request_of_the_study_is_valid():
    r = read_request("plan.yaml")
    assert r.milling == "slot" and r.width_mm == r.tool_diameter_mm


def _bad(path, value):
    d = copy.deepcopy(GOOD)
    node = d
    for k in path[:-1]:
        node = node[k]
    if value is KeyError:
        del node[path[-1]]
    else:
        node[path[-1]] = value
    return d


@pytest.mark.parametrize("path,value,message", [
    (("kind",), "plans", r"p.yaml: kind: expected 'plan', got 'plans'"),
    (("tool", "flutes"), 2.5, r"p.yaml: tool.flutes: expected a positive integer, got 2.5"),
    (("tool", "diameter_mm"), -6, r"tool.diameter_mm: expected a positive number, got -6"),
    (("operation", "milling"), "climb", r"operation.milling: expected one of slot, up, down"),
    (("operation", "radial_immersion"), 1.5, r"operation.radial_immersion: expected a fraction"),
    (("operation", "directions"), ["north"], r"operation.directions\[0\]: expected one of px"),
    (("operation", "length_mm"), KeyError, r"operation.length_mm: missing"),
    (("spindle_rpm",), {"min": 20000, "max": 10000, "n": 5},
     r"spindle_rpm.max: expected ≥ min \(20000\), got 10000"),
    (("depth_mm",), [], r"depth_mm: expected a non-empty list of numbers"),
    (("feed_mm_s",), [1, "fast"], r"feed_mm_s\[1\]: expected a positive number, got 'fast'"),
    (("placement",), {"box": {"min_mm": [0, 0], "max_mm": [1, 1, 1], "n": [1, 1, 1]}},
     r"placement.box.min_mm: expected \[x, y, z\] in mm"),
    (("placement",), {"circle": 3}, r"placement: expected a mapping with 'box'"),
    (("constraints",), {"max_speed": 3}, r"constraints.max_speed: unknown constraint"),
    (("constraints",), {"max_force_N": 0}, r"constraints.max_force_N: expected a positive"),
    (("rotation",), 3, r"p.yaml: rotation: unknown field"),
])
def test_bad_fields_give_one_line(path, value, message):
    with pytest.raises(PlanRequestError, match=message) as e:
        parse_request(_bad(path, value), "p.yaml")
    assert "\n" not in str(e.value)


def test_bad_files(tmp_path):
    with pytest.raises(PlanRequestError, match="does not exist"):
        read_request(tmp_path / "none.yaml")
    p = tmp_path / "plan.yaml"
    p.write_text("kind: plan\noperation: [\n")
    with pytest.raises(PlanRequestError, match=r"plan.yaml: line \d+: not valid YAML"):
        read_request(p)
    p.write_text(yaml.safe_dump(GOOD))
    assert read_request(p).flutes == 3
