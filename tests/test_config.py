"""The configuration schema: defaults fill in, bad values are rejected naming the key."""

import copy

import pytest

from robomill.config import load_config, validate_config
from robomill.io import ConfigError


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
        validate_config(cfg, repo / "workflow/schemas/config.schema.yaml")


def test_unknown_top_level_key_is_rejected(repo, config):
    cfg = {**config, "surfce": {}}
    with pytest.raises(ConfigError, match="surfce"):
        validate_config(cfg, repo / "workflow/schemas/config.schema.yaml")


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
        load_config(p, repo / "workflow/schemas/config.schema.yaml")
