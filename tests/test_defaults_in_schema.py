"""Defaults only in the schemas: a configuration key's default is written once, in
``src/robomill/data/schemas/`` (package data), and read one way (:mod:`robomill.settings`). A
test walks the library and the rule scripts for a second copy of a default the schema
states: a mapping entry, a dataclass field or a ``.get(key, default)`` with a schema key and
the schema's value."""

from __future__ import annotations

import ast
import copy
import re
from pathlib import Path

import pytest
import yaml
from conftest import REPO

from robomill.settings import config_section, schema_default, schema_defaults, settings_from

SCHEMAS = REPO / "src" / "robomill" / "data" / "schemas"

#: found copies that are no configuration default, each with the reason
#: (file, key) -> why
ALLOWED = {
    ("src/robomill/experiment.py", "spindle_rpm"):
        "THESIS_PROCESS: the thesis' process, which decides whether a study is the thesis' "
        "(its comparisons), not a default; the default study is the thesis', so the values meet",
    ("src/robomill/experiment.py", "flutes"): "THESIS_PROCESS, as spindle_rpm",
    ("src/robomill/pipeline/config.py", "source"):
        "the `data: synthetic` shorthand written out (normalize_data), not a default",
    ("src/robomill/kinematics.py", "length_unit"):
        "a robot file's optional key (docs/data-contract.md), read where no configuration is",
    ("src/robomill/kinematics.py", "angle_unit"): "a robot file's optional key, as length_unit",
    ("src/robomill/io/robots.py", "tool"): "a robot file's optional key, as length_unit",
    ("src/robomill/synth/loadtests.py", "tool"): "a robot file's optional key, as length_unit",
    ("src/robomill/synth/cell.py", "tool_rotation"):
        "a cell file's optional key (the raw folder's cell.yaml), read where no configuration is",
    ("src/robomill/synth/loadtests.py", "redundancy_deg"):
        "left for the virtual cell's load tests, rewritten in parallel (cell)",
    ("src/robomill/modal/frf.py", "force_window_s"):
        "an attribute of an frf.nc written before the window was stored in it",
    ("src/robomill/modal/frf.py", "exponential_end"): "as force_window_s",
    ("src/robomill/plan/stability.py", "seed"):
        "plan.yaml's stability.seed: the plan request's own key (no configuration key), "
        "the bootstrap's draws; the same number as the configuration's seeds by choice",
    ("src/robomill/straightness/study.py", "ik_points"):
        "inverse-kinematics samples along a tracker path in the straightness analysis, not "
        "the dynamometer simulator's synth.dynamometer.ik_points along a cut",
}
#: whole files left as they are, with the reason
ALLOWED_FILES: dict[str, str] = {}


def _schema_defaults() -> dict[str, list]:
    """Key -> every non-trivial default the schemas state for a key of that name."""
    found: dict[str, list] = {}

    def walk(node):
        if not isinstance(node, dict):
            return
        for key, sub in (node.get("properties") or {}).items():
            if isinstance(sub, dict) and "default" in sub:
                d = sub["default"]
                if not (d is None or isinstance(d, bool) or d in (0, 1, "", [], {})):
                    found.setdefault(key, []).append(d)
            walk(sub)
        for k in ("items", "additionalProperties"):
            walk(node.get(k))

    for f in [SCHEMAS / "config.schema.yaml", *sorted((SCHEMAS / "config").glob("*.yaml"))]:
        walk(yaml.safe_load(f.read_text()))
    return found


def _same(a, b) -> bool:
    """Equal values of one kind (an int and a float of one value are; True and 1 are not)."""
    number = (int, float)
    return a == b and (type(a) is type(b) or (
        isinstance(a, number) and isinstance(b, number)
        and not isinstance(a, bool) and not isinstance(b, bool)))


def copies_of_schema_defaults(path: Path, text: str, defaults: dict[str, list]) -> list[tuple]:
    """``(file, line, key, value)`` of each mapping entry, annotated assignment (a dataclass
    field), ``.get(key, value)`` and function keyword default in ``text`` whose key (or
    argument) names a schema key and whose value is a default the schema states for it."""
    out = []
    for node in ast.walk(ast.parse(text)):
        pairs = []
        if isinstance(node, ast.Dict):
            pairs = [(k.value, v) for k, v in zip(node.keys, node.values, strict=True)
                     if isinstance(k, ast.Constant) and isinstance(k.value, str)]
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name) \
                and node.value is not None:
            pairs = [(node.target.id, node.value)]
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) \
                and node.func.attr == "get" and len(node.args) == 2 \
                and isinstance(node.args[0], ast.Constant):
            pairs = [(node.args[0].value, node.args[1])]
        elif isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            args = node.args
            positional = [*args.posonlyargs, *args.args]
            pairs = [(a.arg, d) for a, d in zip(positional[len(positional)
                                                           - len(args.defaults):],
                                                args.defaults, strict=True)]
            pairs += [(a.arg, d) for a, d in zip(args.kwonlyargs, args.kw_defaults, strict=True)
                      if d is not None]
        for key, value in pairs:
            if key not in defaults:
                continue
            try:
                literal = ast.literal_eval(value)
            except ValueError:
                continue
            if isinstance(literal, tuple):
                literal = list(literal)
            if any(_same(literal, d) for d in defaults[key]):
                out.append((str(path), node.lineno, key, literal,
                            "keyword" if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)
                            else "value"))
    return out


def test_no_module_carries_a_default_the_schema_states():
    defaults = _schema_defaults()
    assert defaults["fs_hz"] and 815.0 in defaults["fs_hz"]  # the tracker's rate
    found = []
    for f in sorted([*REPO.glob("src/robomill/**/*.py"), *REPO.glob("workflow/scripts/*.py")]):
        rel = f.relative_to(REPO).as_posix()
        if rel in ALLOWED_FILES:
            continue
        found += [h for h in copies_of_schema_defaults(Path(rel), f.read_text(), defaults)
                  if (rel, h[2]) not in ALLOWED]
    assert found == [], "defaults written beside the schema's:\n" + "\n".join(map(str, found))


def test_no_workflow_file_reads_a_key_with_a_default_the_schema_states():
    """The workflow reads the validated configuration, whose keys the schema filled: no
    ``config.get("key", default)`` repeating a schema default in the Snakefile or a rule
    file."""
    defaults = _schema_defaults()
    get = re.compile(r"\.get\(\s*\"(\w+)\",\s*([^()]+?)\s*\)")
    found = []
    for f in [REPO / "Snakefile", *sorted((REPO / "workflow" / "rules").glob("*.smk"))]:
        for n, line in enumerate(f.read_text().splitlines(), 1):
            for key, value in get.findall(line):
                try:
                    literal = ast.literal_eval(value)
                except (ValueError, SyntaxError):
                    continue
                if any(_same(literal, d) for d in defaults.get(key, [])):
                    found.append((f.name, n, key, literal))
    assert found == [], found
    assert get.findall('x = cfg.get("map_robot", "kr360")') == [("map_robot", '"kr360"')]


def test_the_walk_finds_each_kind_of_copy():
    """The check can fail: a DEFAULTS table, a dataclass field, a .get default and keyword
    defaults, each the tracker's 815 Hz of synth.tracker.fs_hz (or its 13 Hz ripple), are
    found; another value or key is not."""
    text = ('DEFAULTS = {"fs_hz": 815.0, "noise_std_um": 4.0}\n'
            "class S:\n    fs_hz: float = 815.0\n    other_hz: float = 815.0\n"
            'rate = section.get("fs_hz", 815.0)\n'
            "def f(x, fs_hz=815.0, *, noise_std_um=4.0, ripple_hz=13.0):\n    pass\n")
    hits = copies_of_schema_defaults(Path("m.py"), text, _schema_defaults())
    assert sorted((h[1], h[2]) for h in hits) == [
        (1, "fs_hz"), (3, "fs_hz"), (5, "fs_hz"), (6, "fs_hz"), (6, "ripple_hz")]


def test_every_allowed_entry_is_still_there():
    """An allow-list entry whose copy is gone is struck from the list (it would hide the next
    one)."""
    defaults = _schema_defaults()
    for (rel, key) in ALLOWED:
        hits = copies_of_schema_defaults(Path(rel), (REPO / rel).read_text(), defaults)
        assert any(h[2] == key for h in hits), (rel, key)


# --- the loader ------------------------------------------------------------------------------

def _tracker_schema() -> dict:
    return yaml.safe_load((SCHEMAS / "config" / "synth_tracker.schema.yaml").read_text())


def test_a_section_is_filled_from_its_schema_where_the_configuration_lacks_a_key():
    props = _tracker_schema()["properties"]
    given = {"synth": {"tracker": {"fs_hz": 100.0}}}
    before = copy.deepcopy(given)
    tr = config_section(given, "synth.tracker")
    assert tr["fs_hz"] == 100.0
    assert tr["noise_std_um"] == props["noise_std_um"]["default"]
    assert set(tr) == {k for k, v in props.items() if "default" in v}
    assert given == before  # a copy
    assert config_section({}, "synth.tracker")["fs_hz"] == props["fs_hz"]["default"]


def test_nested_sections_and_dataclasses_read_the_same_schema():
    top = yaml.safe_load((SCHEMAS / "config.schema.yaml").read_text())
    noise = top["properties"]["plan"]["properties"]["waviness_noise"]["properties"]
    assert schema_defaults("plan.waviness_noise") == {
        k: v["default"] for k, v in noise.items()}
    forces = yaml.safe_load((SCHEMAS / "config" / "forces.schema.yaml").read_text())
    from robomill.forces.settings import ForceAnalysisSettings

    s = settings_from(ForceAnalysisSettings, {"forces": {"lowband_hz": 100.0}}, "forces")
    assert s.lowband_hz == 100.0
    assert s.welch_nperseg == forces["properties"]["welch_nperseg"]["default"]
    assert ForceAnalysisSettings().welch_nperseg == s.welch_nperseg
    with pytest.raises(KeyError, match="no_such_key"):
        schema_default("forces", "no_such_key")
    with pytest.raises(KeyError, match="no config section"):
        schema_defaults("forces.no_such_section")
