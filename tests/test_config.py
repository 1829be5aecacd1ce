"""The configuration schema: defaults fill in, bad values are rejected naming the key."""

import copy
import re

import pytest

from robomill.io import ConfigError
from robomill.pipeline.config import load_config, validate_config


def test_default_config_validates_and_fills_defaults(config):
    assert config["data"]["source"] == "synthetic"
    assert config["data"]["raw_dir"] == "data/raw"
    assert config["chapters"]["kernel"] == "python3"


def test_tiny_config_validates(tiny_config):
    assert tiny_config["synth"]["sets"] == 1


@pytest.mark.parametrize(
    ("path", "value", "named"),
    [
        (("data", "source"), "files", "data.source"),
        (("experiment", "spindle_rpm"), -1, "experiment.spindle_rpm"),
        (("synth", "modes", 0, "zeta"), 2.0, "synth.modes[0].zeta"),
        (("experiment", "sets", 0, "depth_mm"), "deep", "experiment.sets[0].depth_mm"),
    ],
)
def test_bad_value_is_rejected_naming_the_key(repo, config, path, value, named):
    cfg = copy.deepcopy(config)
    node = cfg
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    with pytest.raises(ConfigError, match=named.replace("[", r"\[").replace("]", r"\]")):
        validate_config(cfg, repo / "src/robomill/data/schemas/config.schema.yaml")


def test_unknown_top_level_key_is_rejected(repo, config):
    cfg = {**config, "surfce": {}}
    with pytest.raises(ConfigError, match="surfce"):
        validate_config(cfg, repo / "src/robomill/data/schemas/config.schema.yaml")


def test_snakemake_rejects_bad_config(tmp_path, repo):
    """The workflow itself refuses a bad config before running anything, naming the key."""
    from conftest import run_snakemake

    bad = tmp_path / "bad.yaml"
    bad.write_text((repo / ".test/config.yaml").read_text().replace(
        "spindle_rpm: 28000", "spindle_rpm: -5"))
    proc = run_snakemake(tmp_path, "-n", "all", configfile=bad, timeout=120)
    assert proc.returncode != 0
    assert "spindle_rpm" in proc.stdout + proc.stderr


def test_load_config_reads_yaml_safely(tmp_path, repo):
    p = tmp_path / "c.yaml"
    p.write_text("!!python/object/apply:os.system ['true']\n")
    with pytest.raises(Exception, match="constructor|tag"):
        load_config(p, repo / "src/robomill/data/schemas/config.schema.yaml")


# ---- values as users write them ---------------------------------------------------
@pytest.mark.parametrize(("text", "wanted", "expected"), [
    ("10", ["integer"], (True, 10)),
    ("1e3", ["integer"], (True, 1000)),
    ("10.0", ["integer"], (True, 10)),
    ("10.5", ["integer"], (False, None)),
    ("6.0e8", ["number"], (True, 6.0e8)),
    ("6e8", ["number"], (True, 6.0e8)),
    ("-2.5E-3", ["number"], (True, -2.5e-3)),
    ("250", ["number"], (True, 250)),
    ("inf", ["number"], (False, None)),
    ("ten", ["number"], (False, None)),
    ("null", ["integer", "null"], (True, None)),
    ("12", ["integer", "null"], (True, 12)),
    ("yes", ["boolean"], (True, True)),
    ("Off", ["boolean"], (True, False)),
])
def test_coerce_value_reads_what_the_text_spells(text, wanted, expected):
    from robomill.pipeline.config import coerce_value

    ok, value = coerce_value(text, wanted)
    assert (ok, value) == expected
    if ok:
        assert type(value) is type(expected[1])


def test_yaml_1_1_exponent_floats_in_a_config_file_are_numbers(tmp_path, repo):
    """PyYAML reads `6.0e8` and `6e8` (no dot or no exponent sign) as text; the schema wants
    numbers there, so they are converted."""
    import yaml

    text = (repo / "config.yaml").read_text().replace("Kt_N_m2: 6.0e+8", "Kt_N_m2: 6.0e8", 1)
    text = text.replace("lowband_hz: 250.0 ", "lowband_hz: 2.5e2 ", 1)
    assert "Kt_N_m2: 6.0e8" in text and "lowband_hz: 2.5e2" in text
    p = tmp_path / "config.yaml"
    p.write_text(text)
    raw = yaml.safe_load(text)
    assert raw["chatter"]["cases"][0]["Kt_N_m2"] == "6.0e8"  # what PyYAML gives
    cfg = load_config(p, repo / "src/robomill/data/schemas/config.schema.yaml")
    assert cfg["chatter"]["cases"][0]["Kt_N_m2"] == 6.0e8
    assert cfg["forces"]["lowband_hz"] == 250.0


def test_command_line_numbers_are_converted_and_bad_ones_get_the_fix(repo, config):
    """`--config forces='{decimation: 10}'` reaches the config as {'decimation': '10'}
    (Snakemake parses nested values with YAML's BaseLoader: all text)."""
    from snakemake.cli import parse_config

    over = parse_config(["forces={decimation: 10, lowband_hz: 2.5e+2}", "data=/some/folder"])
    assert over["forces"] == {"decimation": "10", "lowband_hz": "2.5e+2"}
    cfg = copy.deepcopy(config)
    cfg["forces"] = {**cfg["forces"], **over["forces"]}
    cfg["data"] = over["data"]
    out = validate_config(cfg, repo / "src/robomill/data/schemas/config.schema.yaml")
    assert out["forces"]["decimation"] == 10 and out["forces"]["lowband_hz"] == 250.0
    assert out["data"] == {"source": "raw", "raw_dir": "/some/folder", "raw_dirs": []}
    cfg["forces"]["decimation"] = "10.5"
    with pytest.raises(ConfigError, match=re.escape(
            "config key 'forces.decimation': '10.5' is not an integer or null (expected an "
            "integer or null: write e.g. decimation: 10 in the config file, or --config "
            "forces='{decimation: 10}' on the command line)")):
        validate_config(cfg, repo / "src/robomill/data/schemas/config.schema.yaml")
    cfg["forces"]["decimation"] = 10
    cfg["chatter"]["cases"][0]["Kt_N_m2"] = "6.0e8 N/m2"
    with pytest.raises(ConfigError, match=r"chatter.cases\[0\].Kt_N_m2': '6.0e8 N/m2' is not "
                                          r"a number"):
        validate_config(cfg, repo / "src/robomill/data/schemas/config.schema.yaml")


@pytest.mark.parametrize(("value", "expected"), [
    ("/data/run1", {"source": "raw", "raw_dir": "/data/run1", "raw_dirs": []}),
    ("synthetic", {"source": "synthetic", "raw_dir": "data/raw", "raw_dirs": []}),
    ({"source": "raw", "raw_dir": "x"}, {"source": "raw", "raw_dir": "x", "raw_dirs": []}),
])
def test_data_folder_shorthand(repo, config, value, expected):
    cfg = copy.deepcopy(config)
    cfg["data"] = value
    schema = repo / "src/robomill/data/schemas/config.schema.yaml"
    assert validate_config(cfg, schema)["data"] == expected


def test_a_bad_key_stops_the_workflow_with_one_line_naming_it(tmp_path):
    """The workflow validates with the same function (and C YAML loader) as the library; a
    bad value is one line naming its key, not Snakemake's schema dump or a stack."""
    from conftest import run_snakemake

    proc = run_snakemake(tmp_path, "-n", "all", "--config", 'surface={"lambda_c_mm": -3}',
                         timeout=300)
    assert proc.returncode == 1
    said = [x for x in proc.stderr.splitlines()
            if x.strip() and not x.startswith(("Using workflow specific profile", "Config file"))]
    assert said == ["robomill: config key 'surface.lambda_c_mm': -3 is less than or equal to "
                    "the minimum of 0 (schema surface.schema.yaml)"]


# ---- the workflow's validation, kept for the next run -----------------------------
def _schemas_copy(repo, tmp_path):
    import shutil

    dest = tmp_path / "schemas"
    shutil.copytree(repo / "src/robomill/data/schemas", dest)
    return dest / "config.schema.yaml"


def test_cached_validation_gives_the_fresh_answer_and_skips_the_second_one(
        repo, tmp_path, monkeypatch):
    import yaml

    import robomill.pipeline.config as cfgmod

    raw = yaml.safe_load((repo / "config.yaml").read_text())
    schema = _schemas_copy(repo, tmp_path)
    fresh = validate_config(raw, schema)
    calls = []
    real = cfgmod.validate_config
    monkeypatch.setattr(cfgmod, "validate_config", lambda *a: calls.append(1) or real(*a))
    cache = tmp_path / "cache"
    first = cfgmod.validate_config_cached(raw, schema, cache)
    second = cfgmod.validate_config_cached(copy.deepcopy(raw), schema, cache)
    assert first == fresh and second == fresh
    assert calls == [1]  # the second run read the kept answer
    assert len(list(cache.glob("*.pickle"))) == 1
    # another configuration is validated afresh
    other = copy.deepcopy(raw)
    other["experiment"]["spindle_rpm"] = 12000
    assert cfgmod.validate_config_cached(other, schema, cache)["experiment"]["spindle_rpm"] \
        == 12000
    assert calls == [1, 1]


def test_a_changed_schema_or_a_torn_entry_is_validated_afresh(repo, tmp_path, monkeypatch):
    import os

    import yaml

    import robomill.pipeline.config as cfgmod

    raw = yaml.safe_load((repo / "config.yaml").read_text())
    schema = _schemas_copy(repo, tmp_path)
    cache = tmp_path / "cache"
    cfgmod.validate_config_cached(raw, schema, cache)
    # a section's schema now refuses the configuration's value: the kept answer is not used
    section = schema.parent / "config" / "chapters.schema.yaml"
    text = section.read_text()
    assert "kernel" in text
    section.write_text(text.replace("    type: string\n",
                                    "    type: string\n    pattern: '^nope$'\n", 1))
    st = section.stat()
    os.utime(section, ns=(st.st_atime_ns, st.st_mtime_ns + 10**9))
    with pytest.raises(ConfigError, match="chapters.kernel"):
        cfgmod.validate_config_cached(raw, schema, cache)
    assert len(list(cache.glob("*.pickle"))) == 1  # the refusal is not kept
    section.write_text(text)
    os.utime(section, ns=(st.st_atime_ns, st.st_mtime_ns + 2 * 10**9))
    calls = []
    real = cfgmod.validate_config
    monkeypatch.setattr(cfgmod, "validate_config", lambda *a: calls.append(1) or real(*a))
    good = cfgmod.validate_config_cached(raw, schema, cache)
    for entry in cache.glob("*.pickle"):
        entry.write_bytes(b"torn")
    assert cfgmod.validate_config_cached(raw, schema, cache) == good
    assert calls == [1, 1]
