"""The cell file ``cell.yaml`` (robomill.io.cell): good files, every bad key, reachability."""

import copy
from pathlib import Path

import numpy as np
import pytest
import yaml

from robomill.io import RawDataError
from robomill.io.cell import parse_cell, read_cell, write_cell
from robomill.io.manifest import parse_manifest
from robomill.pipeline.config import load_config

REPO = Path(__file__).resolve().parents[1]
EXPERIMENT = {"spindle_rpm": 28000, "flutes": 2, "tool_diameter_mm": 6.0, "cut_length_mm": 40.0}


@pytest.fixture(scope="module")
def cell_cfg():
    return load_config(REPO / "config.yaml")["cell"]


def _good(cell_cfg):
    from robomill.io.cell import cell_mapping

    return cell_mapping(cell_cfg)


def test_round_trip_of_the_default_cell(cell_cfg, tmp_path):
    path = write_cell(cell_cfg, tmp_path / "cell.yaml")
    cell = read_cell(path)
    assert cell.robot.name == "irb1600" and cell.robot.n_joints == 6
    np.testing.assert_allclose(cell.q_home_deg, [0, 20, 10, 0, 60, 0])
    np.testing.assert_allclose(cell.tool_rotation, np.diag([1.0, -1.0, -1.0]))
    assert len(cell.transmissions) == 9
    assert cell.base_from_instrument == {}
    # the calibration's Fourier orders, formerly hand-copied into calibration.error_model
    assert cell.fourier_orders() == [[8.0, 120.0, 320.0, 2040.0], [8.3, 125.0, 332.0, 1875.0],
                                     [7.7, 115.0, 308.0, 1840.0], [80.0, 1120.0],
                                     [80.0, 1120.0], [50.0, 600.0]]


def test_registration_maps_instrument_points_to_the_base(cell_cfg):
    data = _good(cell_cfg)
    c, s = np.cos(np.pi / 6), np.sin(np.pi / 6)
    data["base_from_instrument"] = {"tracker": {"rotation": [[c, -s, 0], [s, c, 0], [0, 0, 1]],
                                                "translation_mm": [100.0, -50.0, 20.0]}}
    cell = parse_cell(data, "cell.yaml")
    p = np.array([[10.0, 0.0, 0.0], [0.0, 10.0, 5.0]])
    np.testing.assert_allclose(cell.to_base_mm("tracker", p),
                               [[100 + 10 * c, -50 + 10 * s, 20], [100 - 10 * s, -50 + 10 * c, 25]])
    np.testing.assert_allclose(cell.to_base_mm("ctrack", p), p)  # not registered: unchanged


def _delete(d, keys):
    for k in keys[:-1]:
        d = d[k]
    del d[keys[-1]]


def _set(d, keys, value):
    for k in keys[:-1]:
        d = d[k]
    d[keys[-1]] = value


ROT = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
MISSING = [
    (("robot",), r"<top>|key 'robot' is missing"),
    (("robot", "name"), r"robot\.name: key 'name' is missing"),
    (("robot", "convention"), r"robot\.convention: key 'convention' is missing"),
    (("robot", "joints"), r"robot\.joints: key 'joints' is missing"),
    (("robot", "joints", 0, "alpha"), r"robot\.joints\[0\]: key 'alpha' is missing"),
    (("q_home_deg",), r"q_home_deg: key 'q_home_deg' is missing"),
    (("tool_rotation",), r"tool_rotation: key 'tool_rotation' is missing"),
    (("transmissions",), r"transmissions: key 'transmissions' is missing"),
    (("transmissions", 2, "joint"), r"transmissions\[2\]: key 'joint' is missing"),
    (("transmissions", 2, "stage"), r"transmissions\[2\]: key 'stage' is missing"),
    (("transmissions", 2, "rev_per_joint_rev"),
     r"transmissions\[2\]: key 'rev_per_joint_rev' is missing"),
    (("transmissions", 2, "teeth"), r"transmissions\[2\]: key 'teeth' is missing"),
]


@pytest.mark.parametrize(("keys", "message"), MISSING, ids=lambda v: ".".join(map(str, v))
                         if isinstance(v, tuple) else None)
def test_missing_key_is_named(cell_cfg, keys, message):
    data = _good(cell_cfg)
    _delete(data, keys)
    with pytest.raises(RawDataError, match=r"^cell\.yaml: .*" + message.split("|")[-1]):
        parse_cell(data, "cell.yaml")


def test_missing_registration_keys_are_named(cell_cfg):
    for key in ("rotation", "translation_mm"):
        data = _good(cell_cfg)
        reg = {"rotation": ROT, "translation_mm": [0, 0, 0]}
        del reg[key]
        data["base_from_instrument"] = {"tracker": reg}
        with pytest.raises(RawDataError, match=rf"base_from_instrument\.tracker: key '{key}'"):
            parse_cell(data, "cell.yaml")


WRONG = [  # (keys, value, message): wrong type and wrong shape of every key
    (("robot",), "irb1600", r"robot: not a YAML mapping"),
    (("robot", "convention"), "zyx", r"robot\.convention: unknown convention 'zyx'"),
    (("robot", "joints"), {"a": 1}, r"robot\.joints: joints is not a non-empty list"),
    (("robot", "joints", 1, "d"), "long", r"robot\.joints\[1\]\.d: value 'long' is not a number"),
    (("robot", "tool"), [0, 0], r"robot\.tool: tool is \[0, 0\]"),
    (("q_home_deg",), "home", r"q_home_deg: q_home_deg is 'home' \(expected a list of 6"),
    (("q_home_deg",), [0, 20, 10], r"q_home_deg: q_home_deg is \[0, 20, 10\]"),
    (("q_home_deg",), [0, 20, 10, 0, "a", 0], r"q_home_deg: "),
    (("tool_rotation",), 1.0, r"tool_rotation: tool_rotation is 1\.0 \(expected a 3×3"),
    (("tool_rotation",), [[1, 0, 0], [0, 1, 0]], r"tool_rotation: .*expected a 3×3"),
    (("tool_rotation",), [[1, 0, 0], [0, 1, 0], [0, 0, 2]], r"tool_rotation is not a rotation"),
    (("tool_rotation",), [[1, 0, 0], [0, 1, 0], [0, 0, -1]], r"tool_rotation is not a rotation"),
    (("transmissions",), {"joint": 1}, r"transmissions: transmissions is dict"),
    (("transmissions", 0), [1, "motor", 120, 17], r"transmissions\[0\]: list found"),
    (("transmissions", 0, "joint"), "1", r"transmissions\[0\]\.joint: joint is '1'"),
    (("transmissions", 0, "joint"), 7, r"transmissions\[0\]\.joint: joint is 7 \(expected an "
                                       r"integer joint number 1\.\.6"),
    (("transmissions", 0, "stage"), 3, r"transmissions\[0\]\.stage: stage is 3"),
    (("transmissions", 0, "rev_per_joint_rev"), -8.0,
     r"transmissions\[0\]\.rev_per_joint_rev: rev_per_joint_rev is -8\.0"),
    (("transmissions", 0, "rev_per_joint_rev"), "fast",
     r"transmissions\[0\]\.rev_per_joint_rev: rev_per_joint_rev is 'fast'"),
    (("transmissions", 0, "teeth"), 17.5, r"transmissions\[0\]\.teeth: teeth is 17\.5"),
    (("transmissions", 0, "runout_arcsec"), 0.6,
     r"transmissions\[0\]: unknown key\(s\) runout_arcsec"),
    (("transmissions", 1), {"joint": 1, "stage": "motor", "rev_per_joint_rev": 120.0,
                            "teeth": 17}, r"transmissions\[1\]: joint 1 stage 'motor' listed"),
    (("base_from_instrument",), [1, 2], r"base_from_instrument: base_from_instrument is list"),
    (("base_from_instrument",), {"faro": {}}, r"base_from_instrument\.faro: unknown instrument"),
    (("base_from_instrument",), {"tracker": ROT},
     r"base_from_instrument\.tracker: list found"),
    (("base_from_instrument",), {"tracker": {"rotation": [1, 0, 0], "translation_mm": [0, 0, 0]}},
     r"base_from_instrument\.tracker\.rotation: .*expected a 3×3"),
    (("base_from_instrument",), {"tracker": {"rotation": "eye", "translation_mm": [0, 0, 0]}},
     r"base_from_instrument\.tracker\.rotation: rotation|tracker\.rotation is 'eye'"),
    (("base_from_instrument",), {"ctrack": {"rotation": ROT, "translation_mm": [0, 0]}},
     r"base_from_instrument\.ctrack\.translation_mm: .*\[x, y, z\] in mm"),
    (("base_from_instrument",), {"ctrack": {"rotation": ROT, "translation_mm": "origin"}},
     r"base_from_instrument\.ctrack\.translation_mm: "),
    (("base_from_instrument",), {"ctrack": {"rotation": ROT, "translation_mm": [0, 0, 0],
                                            "scale": 1}}, r"unknown key\(s\) scale"),
    (("extra_key",), 1, r"<top level>: unknown key\(s\) extra_key"),
]


@pytest.mark.parametrize(("keys", "value", "message"), WRONG)
def test_wrong_type_or_shape_is_named(cell_cfg, keys, value, message):
    data = _good(cell_cfg)
    _set(data, keys, copy.deepcopy(value))
    with pytest.raises(RawDataError, match=r"^cell\.yaml: .*(" + message + ")"):
        parse_cell(data, "cell.yaml")


def test_unreadable_files_are_named(tmp_path):
    with pytest.raises(RawDataError, match="cell file does not exist"):
        read_cell(tmp_path / "cell.yaml")
    (tmp_path / "cell.yaml").write_text("robot: [unclosed\n")
    with pytest.raises(RawDataError, match="cell.yaml: not valid YAML"):
        read_cell(tmp_path / "cell.yaml")
    (tmp_path / "cell.yaml").write_text("- just a list\n")
    with pytest.raises(RawDataError, match="cell.yaml: not a YAML mapping"):
        read_cell(tmp_path / "cell.yaml")


def test_points_out_of_reach_point_at_base_from_instrument(cell_cfg):
    cell = parse_cell(_good(cell_cfg), "raw/cell.yaml")
    T = np.broadcast_to(np.eye(4), (3, 4, 4)).copy()
    T[:, :3, :3] = cell.tool_rotation
    # the tracker's own frame: 3 m away from the IRB 1600's base (its reach is about 1.45 m)
    T[:, :3, 3] = [[3100.0, 400.0, 50.0], [3110.0, 400.0, 50.0], [3120.0, 400.0, 50.0]]
    with pytest.raises(RawDataError, match=r"^tracker/px_f2\.csv: tracker points in the robot "
                       r"base frame: points are not reachable by robot 'irb1600' of raw/cell\.yaml"
                       r".*base_from_instrument\.tracker"):
        cell.joint_path_rad(T, data_file="tracker/px_f2.csv", instrument="tracker")
    # a reachable line is solved from q_home_deg
    T[:, :3, 3] = [[700.0, 0.0, 300.0], [710.0, 0.0, 300.0], [720.0, 0.0, 300.0]]
    q = cell.joint_path_rad(T, data_file="tracker/px_f2.csv", instrument="tracker")
    np.testing.assert_allclose(cell.robot.fk(q)[:, :3, 3], T[:, :3, 3], atol=1e-6)


def test_manifest_lists_at_most_one_cell_file():
    files = [{"path": "cell.yaml", "kind": "cell", "sha256": "0" * 64}]
    m = parse_manifest({"experiment": EXPERIMENT, "cuts": [], "files": files}, "manifest.yaml")
    assert m.cell_file == "cell.yaml"
    files = files + [{"path": "other/cell.yaml", "kind": "cell", "sha256": "1" * 64}]
    with pytest.raises(RawDataError, match=r"files\[1\]\.kind: second cell file "
                       r"'other/cell\.yaml' \(also files\[0\]\).*at most one"):
        parse_manifest({"experiment": EXPERIMENT, "cuts": [], "files": files}, "manifest.yaml")
    m = parse_manifest({"experiment": EXPERIMENT, "cuts": [], "files": []}, "manifest.yaml")
    assert m.cell_file is None


def test_written_cell_is_plain_yaml(cell_cfg, tmp_path):
    path = write_cell(cell_cfg, tmp_path / "cell.yaml")
    data = yaml.safe_load(path.read_text())
    assert list(data) == ["robot", "q_home_deg", "tool_rotation", "transmissions", "mass_model",
                          "controller_frames"]
    assert all(set(t) == {"joint", "stage", "rev_per_joint_rev", "teeth"}
               for t in data["transmissions"])


def test_the_own_data_page_non_thesis_example_is_valid():
    """docs/own-data.md "A study that is not the thesis'" (the README's example until issue
    31.4 moved it there): its cell.yaml and its cuts parse, and the PUMA 560 reaches the cuts'
    start points from its home posture."""
    import re

    from robomill.experiment import cut_endpoints_mm, cut_process

    text = (REPO / "docs" / "own-data.md").read_text()
    blocks = re.findall(r"```yaml\n(.*?)```", text, flags=re.S)
    cell_text = next(b for b in blocks if b.startswith("# cell.yaml"))
    manifest_text = next(b for b in blocks if b.startswith("# manifest.yaml"))
    cell = parse_cell(yaml.safe_load(cell_text), "cell.yaml")
    assert cell.robot.name == "puma560" and "tracker" in cell.base_from_instrument
    data = yaml.safe_load(manifest_text.replace("sha256: …", "sha256: '0'"))
    m = parse_manifest({**data, "files": []}, "manifest.yaml")
    assert [cut_process(c, m.experiment)["tooth_passing_hz"] for c in m.cuts] == \
        [600.0, 900.0, 1200.0]
    for c in m.cuts:
        a, b = cut_endpoints_mm(c, m.experiment)
        T = np.broadcast_to(np.eye(4), (2, 4, 4)).copy()
        T[:, :3, :3] = cell.tool_rotation
        T[:, :3, 3] = [a, b]
        q = cell.joint_path_rad(T, data_file=c.id, instrument="tracker")
        np.testing.assert_allclose(cell.robot.fk(q)[:, :3, 3], [a, b], atol=1e-6)


def test_mass_model_is_read_from_the_cell_file(cell_cfg, tmp_path):
    cell = read_cell(write_cell(cell_cfg, tmp_path / "cell.yaml"))
    mm = cell.mass_model
    assert [m.link for m in mm.links] == [1, 2, 3, 4, 5, 6]
    assert mm.links[1].mass_kg == 35.0 and mm.links[1].com_mm == (170.0, 0.0, 840.0)
    assert mm.tool.link == 6 and mm.tool.mass_kg == 5.0
    assert mm.as_dict() == _good(cell_cfg)["mass_model"]
    # optional: a cell file without one reads as None (the calibration then leaves gravity out)
    data = _good(cell_cfg)
    del data["mass_model"]
    assert parse_cell(data, "cell.yaml").mass_model is None
    data["mass_model"] = {"links": [{"link": 2, "mass_kg": 1.0, "com_mm": [0, 0, 0]}]}
    assert parse_cell(data, "cell.yaml").mass_model.tool is None


LINK = {"link": 1, "mass_kg": 60.0, "com_mm": [40.0, 0.0, 300.0]}
MASS_BAD = [  # (mass_model value, message): missing keys, wrong types, wrong shapes, range
    ([LINK], r"mass_model: mass_model is list \(expected a mapping \{links: "),
    ({"tool": {"mass_kg": 5.0, "com_mm": [0, 0, 0]}}, r"mass_model: key 'links' is missing"),
    ({"links": [LINK], "payload": 1}, r"mass_model: unknown key\(s\) payload"),
    ({"links": LINK}, r"mass_model\.links: links is \{"),
    ({"links": []}, r"mass_model\.links: links is an empty list"),
    ({"links": [[1, 60.0, [0, 0, 0]]]}, r"mass_model\.links\[0\]: list found"),
    ({"links": [{"link": 1, "com_mm": [0, 0, 0]}]},
     r"mass_model\.links\[0\]: key 'mass_kg' is missing"),
    ({"links": [{"mass_kg": 1.0, "com_mm": [0, 0, 0]}]},
     r"mass_model\.links\[0\]: key 'link' is missing"),
    ({"links": [{"link": 1, "mass_kg": 1.0}]}, r"mass_model\.links\[0\]: key 'com_mm' is missing"),
    ({"links": [{**LINK, "inertia": 1}]}, r"mass_model\.links\[0\]: unknown key\(s\) inertia"),
    ({"links": [{**LINK, "mass_kg": "heavy"}]},
     r"mass_model\.links\[0\]\.mass_kg: mass_kg is 'heavy' \(expected a number of kilograms"),
    ({"links": [{**LINK, "mass_kg": -1.0}]}, r"mass_model\.links\[0\]\.mass_kg: mass_kg is -1\.0"),
    ({"links": [{**LINK, "com_mm": [40.0, 0.0]}]},
     r"mass_model\.links\[0\]\.com_mm: .*com_mm is \[40\.0, 0\.0\] \(expected \[x, y, z\] in mm"),
    ({"links": [{**LINK, "com_mm": "centre"}]}, r"mass_model\.links\[0\]\.com_mm: "),
    ({"links": [{**LINK, "link": 7}]},
     r"mass_model\.links\[0\]\.link: link is 7 \(expected an integer link number 1\.\.6"),
    ({"links": [{**LINK, "link": 0}]}, r"mass_model\.links\[0\]\.link: link is 0"),
    ({"links": [{**LINK, "link": 1.5}]}, r"mass_model\.links\[0\]\.link: link is 1\.5"),
    ({"links": [LINK], "tool": [5.0, [0, 0, 0]]}, r"mass_model\.tool: list found"),
    ({"links": [LINK], "tool": {"mass_kg": 5.0}}, r"mass_model\.tool: key 'com_mm' is missing"),
    ({"links": [LINK], "tool": {"mass_kg": 5.0, "com_mm": [0, 0, 0, 0]}},
     r"mass_model\.tool\.com_mm: .*com_mm is \[0, 0, 0, 0\]"),
    ({"links": [LINK], "tool": {**LINK}}, r"mass_model\.tool: unknown key\(s\) link"),
]


@pytest.mark.parametrize(("value", "message"), MASS_BAD)
def test_bad_mass_model_is_named(cell_cfg, value, message):
    data = _good(cell_cfg)
    data["mass_model"] = copy.deepcopy(value)
    with pytest.raises(RawDataError, match=r"^cell\.yaml: " + message):
        parse_cell(data, "cell.yaml")


def test_old_configurations_setting_the_moved_mass_model_are_refused_with_the_fix():
    from robomill.errors import ConfigError
    from robomill.pipeline.config import validate_config

    cfg = yaml.safe_load((REPO / "config.yaml").read_text())
    old = copy.deepcopy(cfg)
    old["calibration"]["mass_model"] = cfg["cell"]["mass_model"]
    with pytest.raises(ConfigError, match=r"config key 'calibration\.mass_model' was moved: .*"
                       r"move the mapping \{links, tool\} from calibration: to cell: as "
                       r"cell\.mass_model"):
        validate_config(old, REPO / "src/robomill/data/schemas/config.schema.yaml")
    old = copy.deepcopy(cfg)
    old["synth"]["ctrack"]["mass_model"] = cfg["cell"]["mass_model"]
    with pytest.raises(ConfigError, match=r"'synth\.ctrack\.mass_model' was moved: .*"
                       r"synth\.ctrack\.true_mass_model"):
        validate_config(old, REPO / "src/robomill/data/schemas/config.schema.yaml")
    # the cell's mass model is optional (null removes it in an overlay)
    cfg["cell"]["mass_model"] = None
    assert validate_config(cfg, REPO / "src/robomill/data/schemas/config.schema.yaml")["cell"][
        "mass_model"] is None
