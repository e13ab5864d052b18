"""Every report the CLI writes for the bundled examples reads into its root class of
``ncgear.reports`` (the class named as its schema's ``title``), number for number: every key a
field, every value of its JSON type, number lists as read-only float64 arrays (``_same``) — for
each of docs/schemas/, the reports without a Python function of their own too."""
import json
import pathlib

import pytest

from ncgear import reports
from conftest import ROOT, _same, cli

SCHEMAS = ROOT / "docs" / "schemas"
T = "assets/trajectories"
G1_DESIGN = "assets/loads/g1_m2_design.json"  # a bundled design.json with teeth (module 2)

# (schema, CLI arguments, report file under --out; None: the report is the --json stdout, and
# the command gets no --out). Mostly the runs of scripts/check_schemas.sh, one or two a schema.
RUNS = [
    ("design", ["design", f"{T}/g1_ellipse.csv", "--module", "2"], "design.json"),
    ("design", ["design", "assets/cases/designer_odd3.csv", "--alternatives"], "design.json"),
    ("pair", ["pair", "phi - 0.08*sin(2*phi)", "--teeth", "24", "--module", "1.5"], "pair.json"),
    ("simulate", ["simulate", G1_DESIGN, "--spacing", "140"], "simulate.json"),
    ("dynamics", ["dynamics", "assets/dynamics/backlash_oscillator.toml"], "dynamics.json"),
    ("dynamics", ["dynamics", "assets/dynamics/backlash_oscillator.toml", "--sweep", "0.6:1.0:0.1"],
     "dynamics.json"),
    ("dynamics_rotor", ["dynamics", "assets/dynamics/rotor_g1.toml"], "dynamics.json"),
    ("tolerance", ["tolerance", "assets/tolerance/paper_3k.toml", "--samples", "500", "--seed", "1"],
     "tolerance.json"),
    ("transplanter", ["tolerance", "assets/transplanter/g1_design.json", "--errors",
                      "assets/transplanter/g1_errors.toml", "--samples", "200", "--seed", "1"],
     "transplanter.json"),
    ("loads", ["loads", "assets/loads/g1_rotor.toml"], "loads.json"),
    ("tradeoff", ["tradeoff", f"{T}/g1_ellipse.csv"], "tradeoff.json"),
    ("synthesis", ["synthesize", "assets/synthesis/g1_five_poses.toml"], "synthesis.json"),
    ("orbit_model", ["orbit", "model", "assets/orbit/model.toml"], None),
    ("orbit_measure", ["orbit", "measure", "assets/orbit/signals.csv", "--model",
                       "assets/orbit/model.toml", "--frame", "derotate"], None),
    ("orbit_identify", ["orbit", "identify", "--model", "assets/orbit/model.toml", "--signals",
                        "assets/orbit/signals.csv", "--frame", "derotate"], None),
    ("compare", ["compare", "assets/compare/g1_track.csv", "--design",
                 "assets/transplanter/g1_design.json", "--fps", "500", "--px-per-mm", "3.2",
                 "--spacing", "140"], "compare.json"),
]


def root_class(schema):
    title = json.loads((SCHEMAS / f"{schema}.schema.json").read_text(encoding="utf-8"))["title"]
    return getattr(reports, title)


def test_every_schema_has_a_run():
    files = {p.name[: -len(".schema.json")] for p in SCHEMAS.glob("*.schema.json")}
    assert {r[0] for r in RUNS} == files


@pytest.mark.parametrize("schema,args,file", RUNS, ids=[f"{r[0]}-{i}" for i, r in enumerate(RUNS)])
def test_root_class_reads_the_cli_report(schema, args, file, tmp_path):
    out = ["--out", tmp_path] if file else []
    p = cli(*args, *out, "--json", check=False)
    assert p.returncode in (0, 3), p.stderr  # 3: a result that fails its own verification
    stdout = json.loads(p.stdout)
    raw = json.loads((tmp_path / file).read_text(encoding="utf-8")) if file else stdout
    cls = root_class(schema)
    value = reports.build(cls, raw)
    assert isinstance(value, cls)
    _same(value, raw, schema)
    if file:  # the --json stdout is the same report
        _same(reports.build(cls, stdout), stdout, f"{schema} (stdout)")


def test_a_bundled_design_file_reads_into_design_report():
    raw = json.loads((ROOT / G1_DESIGN).read_text(encoding="utf-8"))
    d = reports.build(reports.DesignReport, raw)
    _same(d, raw, G1_DESIGN)
    assert isinstance(d.teeth, reports.TrainTeethReport) and d.teeth.module_mm == 2.0
    assert isinstance(d.gears.sun, reports.Gear) and d.gears.sun.pitch.shape[1] == 2
    assert isinstance(d.units, reports.DesignUnits) and d.units.length == "mm"
    assert all(isinstance(c, reports.Check) for c in d.checks) and d.checks
