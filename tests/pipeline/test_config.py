"""The config contract (bounce.pipeline.config, config/schema.yaml): a bad config stops the run before any job.

Protects: unknown keys rejected in every section, NaN/inf and out-of-range numbers rejected, the
scene's physical state and its spring law's supported domain checked by the model, the spring fragment
built from the law registry, every configured figure present, sample counts bounded by memory, dangling
and shadowing references caught, schema defaults filled in, and `snakemake -n` printing one line that
names the key.
"""

import copy
import functools
import subprocess
import sys
from pathlib import Path

import pytest
import yaml
from snakemake.utils import update_config

from bounce.pipeline.config import ConfigError, load_schema, validated

ROOT = Path(__file__).resolve().parents[2]
CONFIG = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())


@functools.cache
def _schema() -> dict:
    return load_schema()


def _validated(config: dict) -> dict:
    """validated() against config/schema.yaml read once for the module (load_schema: ~0.1 s a call); the default
    path, which reads it, is test_shipped_configs_are_valid's."""
    return validated(config, copy.deepcopy(_schema()))


def _with(path: str, value):
    """The full config with the value at the dotted ``path`` set (or the key added)."""
    cfg = copy.deepcopy(CONFIG)
    *parents, last = path.split(".")
    node = cfg
    for key in parents:
        node = node[int(key)] if isinstance(node, list) else node[key]
    node[last] = value
    return cfg


def test_shipped_configs_are_valid():
    validated(CONFIG)
    cfg = copy.deepcopy(CONFIG)
    update_config(cfg, yaml.safe_load((ROOT / "config" / "ci.yaml").read_text()))
    validated(cfg)


def test_a_check_reads_a_sweep_only_if_the_config_has_it():
    """A sweep's name is a dataset a check may declare (its gathered file) while config ``sweeps`` runs it."""
    assert "asymptotic-atlas" in _validated(CONFIG)["checks"]["main-theorem"]["inputs"]
    cfg = copy.deepcopy(CONFIG)
    del cfg["sweeps"]["asymptotic-atlas"]
    with pytest.raises(ConfigError, match="checks.main-theorem.inputs.*no dataset named 'asymptotic-atlas'"):
        _validated(cfg)


def test_defaults_come_from_the_schema():
    cfg = copy.deepcopy(CONFIG)
    del cfg["reduced"]["horizon"]["dps"]
    assert _validated(cfg)["reduced"]["horizon"]["dps"] == 40
    assert "dps" not in cfg["reduced"]["horizon"]  # the caller's dict is not modified


@pytest.mark.parametrize("path", [
    "scenes.rigid-fall.gama", "scenes.rigid-fall.stop.event", "sticky.inference.nn", "figures.rest-coeff.nmax",
    "reduced.horizon.tolerance", "reduced.switch.cases.drop-underdamped.psi", "reduced.least_model.scenes.rest-coeff.qoi.r",
    "methods.work_precision.trackTol", "methods.stability_map.sweeps.0.curve", "methods.scenes.drop.gama",
    "checks.main-theorem.atlas",  # the atlas is the sweep asymptotic-atlas now: its old key is refused
    "checks.contact-non-generic.n_samples",  # the Monte Carlo is the sweep contact-monte-carlo
])
def test_unknown_key_is_named(path):
    with pytest.raises(ConfigError) as err:
        _validated(_with(path, 1.0))
    message = str(err.value)
    assert "unknown key" in message and repr(path.rsplit(".", 1)[1]) in message
    assert message.startswith(path.rsplit(".", 1)[0].replace(".0.", ".0."))
    assert "\n" not in message


@pytest.mark.parametrize("path, value, words", [
    ("scenes.rigid-fall.gamma", float("nan"), "must be a finite number"),
    ("scenes.rigid-fall.mu", float("inf"), "must be a finite number"),
    ("scenes.rigid-fall.initial.psi", float("nan"), "finite"),
    ("scenes.rigid-fall.stop.t_max", float("nan"), "finite"),
    ("scenes.rigid-fall.gamma", 0.0, "must be > 0"),
    ("scenes.rigid-fall.gamma", 0.5, "must be < 0.5"),
    ("scenes.rigid-fall.mu", -1.0, "must be >= 0"),
    ("scenes.rigid-fall.stop.events", 1.0e12, "must be <= 50000000"),
    ("sticky.gamma", float("nan"), "finite"),
    ("reduced.horizon.regimes.chaotic.gamma", float("nan"), "finite"),
    ("methods.work_precision.n_h", 2.5, "integer"),
])
def test_bad_number_is_named(path, value, words):
    with pytest.raises(ConfigError, match=words) as err:
        _validated(_with(path, value))
    assert str(err.value).startswith(path)


@pytest.mark.parametrize("path, value, words", [
    # issue 25 item 9: accepted before (the law's own checks never ran on a config, and a had no maximum)
    ("scenes.nonlin-hertz.spring.rho", 1e-6, r"^scenes\.nonlin-hertz: spring rho must be > gamma 2\^\(a\+1\) = 0.0282843"),
    ("scenes.nonlin-hertz.spring.a", 1e300, r"^scenes\.nonlin-hertz\.spring\.a: must be <= 50"),
    ("scenes.nonlin-hertz.spring.b", float("inf"), r"^scenes\.nonlin-hertz\.spring\.b: must be a finite number"),
    ("scenes.nonlin-hertz.mu", 1e4, r"^scenes\.nonlin-hertz: mu must be <= "),
    ("methods.scenes.drop-hertz.spring.rho", 1e-3, r"^methods\.scenes\.drop-hertz: spring rho must be > gamma"),
    ("scenes.nonlin-hertz.spring", {"law": "power", "rho": 1.0, "a": 0.5}, r"^scenes\.nonlin-hertz\.spring: 'b' is a required"),
    ("scenes.nonlin-hertz.spring", {"law": "linear", "rho": 1.0}, r"^scenes\.nonlin-hertz\.spring: unknown key 'rho'; allowed: law$"),
    ("scenes.nonlin-hertz.spring", {"law": "cubic"}, r"^scenes\.nonlin-hertz\.spring\.law: 'cubic' is not one of \['linear', 'power'\]"),
    ("figures.rigid-fall.samples", 1e12, r"^figures\.rigid-fall\.samples: must be <= 10000000, got .* \(a count of dense-output"),
    ("reduced.switch.samples", 10**9, r"^reduced\.switch\.samples: must be <= 10000000"),
    ("figures", {}, r"^figures: 'rigid-fall' is a required property$"),
])
def test_spring_domain_figures_and_samples_are_closed(path, value, words):
    """One line naming the key (before: accepted, or a KeyError traceback when the Snakefile read ``figures``)."""
    with pytest.raises(ConfigError, match=words) as err:
        _validated(_with(path, value))
    assert "\n" not in str(err.value)


def test_spring_fragment_is_built_from_the_registry():
    """config/schema.yaml holds no law names or parameters: load_schema puts in bounce.springs.schema_fragment."""
    from bounce.pipeline.config import load_schema
    from bounce.springs import SPRING_LAWS

    raw = yaml.safe_load((ROOT / "config" / "schema.yaml").read_text())["$defs"]["spring"]
    assert set(raw) == {"description"}
    spring = load_schema()["$defs"]["spring"]
    assert spring["properties"]["law"]["enum"] == list(SPRING_LAWS)
    power = next(b["then"] for b in spring["allOf"] if b["if"]["properties"]["law"]["const"] == "power")
    assert power["required"] == ["rho", "a", "b"] and power["properties"]["a"]["maximum"] == 50.0


def test_every_configured_figure_is_required():
    """The schema requires exactly the figure blocks the registry reads (bounce.figures.FIGURES), so a validated
    config always has them (``figures: {}`` was a KeyError traceback in the Snakefile's figure_table)."""
    from bounce.pipeline.catalogue import figure_table
    from bounce.pipeline.config import load_schema

    read = set()

    class Recorder(dict):
        def __getitem__(self, key):
            read.add(key)
            return CONFIG["figures"][key]

    figure_table({**_validated(CONFIG), "figures": Recorder()})
    assert set(load_schema()["properties"]["figures"]["required"]) == read


def test_scene_below_the_floor_is_refused_by_the_model():
    with pytest.raises(ConfigError, match=r"^scenes\.rigid-fall: x0 must be >= 0"):
        _validated(_with("scenes.rigid-fall.initial", {"psi": 0.0, "psidot": 0.0, "xi": 0.5, "xidot": 0.0}))


@pytest.mark.parametrize("path, value, words", [
    ("gas_scenes.ring-dimers.ell", 50.0, r"^gas_scenes\.ring-dimers: ell must be > n times the grains' length"),
    ("gas_scenes.column-dimers.gamma", 0.6, r"gas_scenes\.column-dimers\.gamma"),
    ("gas_scenes.ring-dimers.initial", {"speed": -1.0}, r"gas_scenes\.ring-dimers\.initial\.speed"),
    ("gas_scenes.ring-dimers.model", "soft", r"gas_scenes\.ring-dimers\.model"),
])
def test_gas_scene_is_refused_naming_it(path, value, words):
    """A gas scene is built with the gas model's own validation before any job (an ell too short for its grains), and
    closed by the schema."""
    with pytest.raises(ConfigError, match=words):
        _validated(_with(path, value))


@pytest.mark.parametrize("path, value, words", [
    ("reduced.least_model.scenes.no-such-scene", {"qoi": {"impact_states": {"tol": 1e-3}}}, "no scene named 'no-such-scene'"),
    ("figures.rest-coeff.scene", "nosuch", "no scene named 'nosuch'"),
    ("methods.work_precision.scene", "nosuch", "no scene in methods.scenes named 'nosuch'"),
    ("scenes.sticky-convergence", CONFIG["scenes"]["rigid-fall"], "taken by a derived dataset"),
    ("scenes.alpha-atlas", CONFIG["scenes"]["rigid-fall"], "taken by a derived dataset"),
    ("checks.nonlinear-atlas.inputs", ["no-such-sweep"], "no dataset named 'no-such-sweep'"),
    ("checks.main-theorem.inputs", ["asymptotic-underdamped", "asymptotic-atlass"], "no dataset named 'asymptotic-atlass'"),
    ("figures.gas-spacetime.gas_scene", "nosuch", "no gas scene named 'nosuch'"),
    ("report.sections.beyond.subjects", ["lem:alpha-map"], r"listed twice \['lem:alpha-map'\], missing \['beyond:gases'\]"),
    ("report.sections.appendix.subjects", ["lem:nosuch"], r"unknown \['lem:nosuch'\]"),
    ("report.choices", [{"text": "t", "keys": ["checks.restitution.few"]}],
     r"report.choices\[0\].keys: 'checks.restitution.few' is not a key"),
    ("sweeps.our-r-band.plateau_flight", 3.0, r"^these settings must be equal .*checks.restitution.plateau_flight = 2.0, "
     r"checks.our-r.plateau_flight = 2.0, sweeps.our-r-band.plateau_flight = 3.0$"),
    ("checks.our-r.our_r_threshold", 0.1, r"checks.our-r.our_r_threshold = 0.1, sweeps.our-r-band.our_r_threshold = 0.05"),
])
def test_dangling_or_shadowing_reference(path, value, words):
    with pytest.raises(ConfigError, match=words):
        _validated(_with(path, value))


def test_snakemake_dry_run_stops_with_one_line(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("scenes:\n  rigid-fall: {gama: 0.01}\n")
    proc = subprocess.run([sys.executable, "-m", "snakemake", "-n", "--quiet", "--cores", "1", "--configfile", str(bad)],
                          cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert proc.returncode != 0
    lines = [ln for ln in proc.stderr.splitlines() if ln.startswith("config error:")]
    assert lines == ["config error: scenes.rigid-fall: unknown key 'gama'; allowed: description, gamma, initial, keep, "
                     "mu, spring, stop"], proc.stderr
    assert "Traceback" not in proc.stderr


def test_ci_sized_config_writes_to_its_own_folder(tmp_path):
    """config/ci.yaml sets workdir: ci-run, so a CI-sized run never writes over the full results/."""
    proc = subprocess.run([sys.executable, "-m", "snakemake", "-n", "--quiet", "--cores", "1", "-s", str(ROOT / "Snakefile"),
                           "--configfile", str(ROOT / "config" / "ci.yaml")],
                          cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert (tmp_path / "ci-run" / ".snakemake").is_dir() and not (tmp_path / ".snakemake").exists()


def test_jsonschema_is_imported_without_the_iri_grammar_and_leaves_it_importable():
    """bounce.pipeline.config skips rfc3987_syntax (~2.7 s at import) only while jsonschema imports: no 'iri' checker,
    the module not loaded, and importable afterwards by anyone else (the block is not left in sys.modules)."""
    pytest.importorskip("rfc3987_syntax")
    code = ("import sys, bounce.pipeline.config, jsonschema; "
            "assert 'rfc3987_syntax' not in sys.modules; "
            "assert 'iri' not in jsonschema.FormatChecker.checkers; "
            "import rfc3987_syntax; print('ok')")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.stdout.strip() == "ok", out.stderr
