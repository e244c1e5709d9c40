"""Tests of slidebeam.scene: loading, normalisation, overrides, error messages."""

from __future__ import annotations

import importlib.util
import math
import pathlib
import sys
import textwrap

import pytest

# load scene.py on its own: the package __init__ may import a compiled module not built yet
_p = pathlib.Path(__file__).resolve().parents[2] / "python" / "slidebeam" / "scene" / "parse.py"
_spec = importlib.util.spec_from_file_location("slidebeam_scene_standalone", _p)
scene = importlib.util.module_from_spec(_spec)
sys.modules[_spec.name] = scene
_spec.loader.exec_module(scene)


STEEL_STRIP = """[beam.section]
shape = "rectangle"
b = 0.005
h = 0.005
E = 2.07e11
nu = 0.3
"""  # a 5 mm square steel strip

FULL = """
[scene]
name = "rollup"
description = "roll-up of a strip"

[analysis]
type = "static"
steps = 20
t_end = 2.0

[petsc]
snes_rtol = 1e-10
snes_max_it = 50
ksp_type = "preonly"
snes_monitor = true
ksp_monitor = false
options_file = "rollup.opts"

[gravity]
g = [0.0, -9.80665, 0]

[[beam]]
name = "strip"
start = [0, 0, 0]
end = [10, 0, 0]
d2 = [0, 2, 0]
spans = 16
quadrature = "reduced"
velocity = [1, 0, 0]
""" + STEEL_STRIP + """rho = 7800

[[beam]]
name = "ring"
arc = { center = [0, 0, 0], radius = 100.0, normal = [0, 0, 2], start = [100, 0, 0], angle = 45 }
spans = 8
strain = "seed"
[beam.section]
EA = 1e4
kGA = 2e4
GJ = 100
EI2 = 101
EI3 = 102
rhoA = 1
rhoI2 = 10

[[beam]]
name = "frame"
polyline = [[0, 0, 0], [0, 10, 0], [-10, 10, 0]]
spans = 4
[beam.section]
shape = "circle"
r = 0.01
E = 1e9
nu = 0.25

[[support]]
type = "clamp"
beam = "strip"
at = "start"

[[support]]
type = "spherical"
beam = "frame"
at = 15.0

[[support]]
type = "clamp"
beam = "ring"
at = 78.53981633974483

[[support]]
type = "fixed"
beam = "strip"

[[load]]
type = "moment"
beam = "strip"
at = "end"
value = [0, 0, 62.83]
frame = "material"

[[load]]
type = "force"
beam = "ring"
at = 10
value = [0, 0, 1]
time_function = { type = "hat", t0 = 0.5, t1 = 1.0, t2 = 1.5 }

[[point_mass]]
beam = "frame"
at = "end"
mass = 2

[output]
every = 2
track = [{ beam = "strip", at = "end" }, { beam = "frame", at = 5 }]
"""

SMALL = """
[[beam]]
name = "strip"
start = [0, 0, 0]
end = [10, 0, 0]
spans = 16
""" + STEEL_STRIP


def _write(tmp_path: pathlib.Path, text: str, name: str = "case.toml") -> pathlib.Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


@pytest.fixture
def full(tmp_path: pathlib.Path):
    (tmp_path / "rollup.opts").write_text("-snes_view\n")
    return scene.load_scene(_write(tmp_path, FULL, "rollup.toml"))


# ----------------------------------------------------------------------------
# valid scenes


def test_full_scene_top_level(full, tmp_path):
    assert full.name == "rollup"
    assert full.description == "roll-up of a strip"
    assert full.file.endswith("rollup.toml")
    assert full.base_dir == str(tmp_path.resolve())
    (gravity,) = full.entries("gravity")
    assert gravity.vec["g"] == [0.0, -9.80665, 0.0]
    assert all(isinstance(g, float) for g in gravity.vec["g"])
    assert full.petsc_options == {
        "snes_rtol": "1e-10", "snes_max_it": "50", "ksp_type": "preonly", "snes_monitor": "",
    }
    assert full.petsc_options_file == str((tmp_path / "rollup.opts").resolve())
    a = full.analysis
    assert (a.type, a.steps, a.t_end, a.dt, a.dt_min) == ("static", 20, 2.0, None, None)
    assert (a.integrator, a.newmark_beta, a.newmark_gamma, a.hht_alpha) == ("energy-momentum", 0.25, 0.5, -0.1)
    assert full.beam_index("frame") == 2
    with pytest.raises(scene.SceneError, match="nope"):
        full.beam_index("nope")


def test_full_scene_beams(full):
    strip, ring, frame = full.beams
    assert [b.index for b in full.beams] == [0, 1, 2]
    assert strip.geometry.kind == "line"
    assert strip.geometry.points == ((0.0, 0.0, 0.0), (10.0, 0.0, 0.0))
    assert strip.geometry.length == 10.0
    assert strip.d2 == (0.0, 1.0, 0.0)
    assert (strip.spans, strip.quadrature, strip.strain, strip.formulation) == (16, "reduced", "simo-reissner", "director")
    assert strip.velocity == (1.0, 0.0, 0.0) and strip.angular_velocity == (0.0, 0.0, 0.0)

    g = ring.geometry
    assert g.kind == "arc" and g.points == ()
    assert g.center == (0.0, 0.0, 0.0) and g.radius == 100.0 and g.normal == (0.0, 0.0, 1.0)
    assert g.start == (100.0, 0.0, 0.0) and g.angle_deg == 45.0
    assert g.length == pytest.approx(100.0 * math.pi / 4, rel=1e-14)
    # no quadrature given: "auto", and the ring's spans are slender (EA h^2 / EI >= 1000)
    assert ring.d2 is None and ring.strain == "seed" and ring.quadrature == "assumed_strain"
    assert scene.span_slenderness(ring.section, g.length / ring.spans) >= scene.AUTO_SLENDERNESS
    end = g.point_at(g.length)
    assert end == pytest.approx((100 / math.sqrt(2), 100 / math.sqrt(2), 0.0), abs=1e-10)

    assert frame.geometry.kind == "polyline"
    assert frame.geometry.points == ((0.0, 0.0, 0.0), (0.0, 10.0, 0.0), (-10.0, 10.0, 0.0))
    assert frame.geometry.length == 20.0
    assert frame.geometry.point_at(15.0) == pytest.approx((-5.0, 10.0, 0.0))


def test_rectangle_section_numbers(full):
    b = 0.005
    sec = full.beams[0].section
    E, nu, rho = 2.07e11, 0.3, 7800.0
    G = E / (2 * (1 + nu))
    A, I = b * b, b**4 / 12
    J_roark = b**4 * (1 / 3 - 0.21 * (1 - 1 / 12))  # = 0.140833 b^4
    assert sec.EA == pytest.approx(E * A, rel=1e-14)
    assert sec.EI2 == pytest.approx(E * I, rel=1e-14) and sec.EI3 == pytest.approx(E * I, rel=1e-14)
    assert sec.GJ == pytest.approx(G * J_roark, rel=1e-14)
    # exact Saint-Venant value for a square is 0.1406 b^4; Roark's fit is within 0.2 %
    assert sec.GJ / G == pytest.approx(0.1406 * b**4, rel=2e-3)
    assert sec.kGA2 == pytest.approx(5 / 6 * G * A, rel=1e-14) and sec.kGA3 == sec.kGA2
    assert sec.rhoA == pytest.approx(rho * A) and sec.rhoI2 == pytest.approx(rho * I)


def test_rectangle_properties_orientation():
    # b along d2, h along d3: I2 = b h^3/12 (about d2), I3 = h b^3/12
    A, I2, I3, J = scene.rectangle_properties(0.02, 0.01)
    assert A == pytest.approx(2e-4)
    assert I2 == pytest.approx(0.02 * 0.01**3 / 12)
    assert I3 == pytest.approx(0.01 * 0.02**3 / 12)
    # Roark: a = 0.02, c = 0.01, tabulated beta = 0.229 for a/c = 2 (J = beta a c^3)
    assert J / (0.02 * 0.01**3) == pytest.approx(0.229, rel=5e-3)


def test_circle_and_explicit_sections(full):
    r, E, nu = 0.01, 1e9, 0.25
    G = E / (2 * (1 + nu))
    circ = full.beams[2].section
    assert circ.EA == pytest.approx(E * math.pi * r**2)
    assert circ.EI2 == pytest.approx(E * math.pi * r**4 / 4) and circ.EI3 == circ.EI2
    assert circ.GJ == pytest.approx(G * math.pi * r**4 / 2)
    assert circ.kGA2 == pytest.approx(0.9 * G * math.pi * r**2)
    assert circ.rhoA == 0.0
    expl = full.beams[1].section
    assert expl == scene.Section(EA=1e4, kGA2=2e4, kGA3=2e4, GJ=100.0, EI2=101.0, EI3=102.0,
                                 rhoA=1.0, rhoI2=10.0, rhoI3=0.0)


def test_full_scene_supports_loads_masses_output(full):
    quarter = 100.0 * math.pi / 4
    s0, s1, s2, s3 = full.entries("support")
    assert (s0.type, s0.num["beam"], s0.num["s"], s0.label) == ("clamp", 0, 0.0, "clamp[strip@start]")
    assert (s1.type, s1.num["beam"], s1.num["s"]) == ("spherical", 2, 15.0)
    assert s2.type == "clamp" and s2.num["s"] == quarter  # a float equal to L is normalised to L
    assert (s3.type, s3.num, s3.label) == ("fixed", {"beam": 0.0}, "fixed[strip]")
    assert [(s.type, s.beam, s.at) for s in full.supports] == [
        ("clamp", 0, 0.0), ("spherical", 2, 15.0), ("clamp", 1, quarter), ("fixed", 0, None)]

    m, f = full.entries("load")
    assert (m.type, m.num["beam"], m.num["s"], m.vec["value"], m.text["frame"]) == (
        "moment", 0, 10.0, [0.0, 0.0, 62.83], "material")
    # default time function of a static analysis: ramp from 0 to t_end
    assert scene.TimeFunction.of_entry(m) == scene.TimeFunction("ramp", 0.0, 2.0, math.inf)
    assert (f.type, f.num["beam"], f.num["s"], f.text["frame"]) == ("force", 1, 10.0, "spatial")
    assert scene.TimeFunction.of_entry(f) == scene.TimeFunction("hat", 0.5, 1.0, 1.5)

    (pm,) = full.entries("point_mass")
    assert (pm.num, pm.label) == ({"beam": 2.0, "s": 20.0, "mass": 2.0}, "point_mass[frame@end]")
    out = full.output
    assert out.every == 2 and out.samples_per_span == 8
    assert out.track == (scene.TrackPoint(0, 10.0), scene.TrackPoint(2, 5.0))


def test_defaults(tmp_path):
    sc = scene.load_scene(_write(tmp_path, SMALL, "tiny.toml"))
    assert sc.name == "tiny" and sc.description == ""
    assert sc.analysis == scene.Analysis("static", 10, 1.0, None, "energy-momentum", 0.25, 0.5, -0.1, None)
    assert sc.effects == () and sc.supports == () and sc.sliding_joints == ()
    assert sc.petsc_options == {} and sc.petsc_options_file is None
    assert sc.output == scene.Output(1, (scene.TrackPoint(0, 10.0),), 8)
    assert sc.beams[0].section.rhoA == 0.0


def test_scene_from_dict_dynamic_default_time_function():
    data = {
        "analysis": {"type": "dynamic", "dt": 0.01, "t_end": 2},
        "beam": [{"name": "a", "start": [0, 0, 0], "end": [0, 0, 3], "spans": 2,
                  "section": {"EA": 1, "kGA2": 2, "kGA3": 3, "GJ": 1, "EI2": 1, "EI3": 1, "rhoA": 1}}],
        "load": [{"type": "force", "beam": "a", "at": "end", "value": [1, 0, 0]}],
    }
    sc = scene.scene_from_dict(data)
    assert sc.file == "<dict>" and sc.name == "scene"
    assert sc.analysis.t_end == 2.0 and isinstance(sc.analysis.t_end, float)
    assert sc.analysis.dt_min == pytest.approx(0.01 / 16)
    assert sc.effects[0].text["tf_type"] == "constant"
    assert sc.effects[0].num["s"] == 3.0
    assert (sc.beams[0].section.kGA2, sc.beams[0].section.kGA3) == (2.0, 3.0)


@pytest.mark.parametrize("spans, quadrature, expected", [
    (4, None, "assumed_strain"),    # 6 mm steel rope, 5 m spans: EA h^2/EI = 4 h^2/r^2 = 2.8e6
    (400, None, "full"),            # 0.05 m spans: 278 (short, stocky spans)
    (385, None, "full"),            # 0.05195 m: 299.8
    (384, None, "assumed_strain"),  # 0.05208 m: 301.4
    (211, None, "assumed_strain"),  # 0.0948 m: 998 (a wire's spans: full quadrature locks by 2 %)
    (4, "full", "full"),            # a stated quadrature wins
    (400, "assumed_strain", "assumed_strain"),
])
def test_auto_quadrature_follows_the_span_slenderness(spans, quadrature, expected):
    """quadrature = "auto" (the default): assumed strains where max(EA, kGA) h^2 / EI >= 300."""
    beam = {"name": "rope", "start": [0, 0, 0], "end": [20, 0, 0], "spans": spans,
            "section": {"shape": "circle", "r": 0.006, "E": 1e11, "nu": 0.3, "rho": 7850}}
    if quadrature:
        beam["quadrature"] = quadrature
    sc = scene.scene_from_dict({"analysis": {"type": "static"}, "beam": [beam]})
    assert sc.beams[0].quadrature == expected
    assert scene.span_slenderness(sc.beams[0].section, 20.0 / spans) == pytest.approx(
        sc.beams[0].section.EA * (20.0 / spans) ** 2 / sc.beams[0].section.EI2)


@pytest.mark.parametrize("analysis, output, every", [
    ({"type": "dynamic", "dt": 1e-3, "t_end": 1.0}, {}, 5),        # 1000 steps: 200 records
    ({"type": "dynamic", "dt": 1e-3, "t_end": 0.399}, {}, 1),      # fewer than 400 steps: all
    ({"type": "dynamic", "dt": 1e-4, "t_end": 20.0}, {}, 1000),
    ({"type": "dynamic", "dt": 1e-3, "t_end": 1.0}, {"every": 1}, 1),  # the scene's own choice
    ({"type": "static", "steps": 5000}, {}, 1),                    # statics record every load step
])
def test_default_output_interval_gives_about_200_records(analysis, output, every):
    data = {
        "analysis": analysis,
        "beam": [{"name": "a", "start": [0, 0, 0], "end": [0, 0, 3], "spans": 2,
                  "section": {"EA": 1, "kGA2": 2, "kGA3": 3, "GJ": 1, "EI2": 1, "EI3": 1, "rhoA": 1}}],
        "output": output,
    }
    assert scene.scene_from_dict(data).output.every == every


@pytest.mark.parametrize("value, words", [(-1.0, "a size in GB >= 0"), ("1 GB", "must be a number")])
def test_warn_size_gb_is_checked(value, words):
    data = {"beam": [{"name": "a", "start": [0, 0, 0], "end": [0, 0, 3], "spans": 2,
                      "section": {"EA": 1, "kGA2": 2, "kGA3": 3, "GJ": 1, "EI2": 1, "EI3": 1}}],
            "output": {"warn_size_gb": value}}
    with pytest.raises(scene.SceneError, match=words) as err:
        scene.scene_from_dict(data)
    assert "warn_size_gb" in str(err.value) and "[output]" in str(err.value)


# ----------------------------------------------------------------------------
# time functions


def test_time_function_values():
    const = scene.TimeFunction("constant")
    assert [const.value(t) for t in (-1.0, 0.0, 1e9)] == [1.0, 1.0, 1.0]
    ramp = scene.TimeFunction("ramp", 1.0, 3.0)
    assert [ramp.value(t) for t in (0.0, 1.0, 2.0, 2.5, 3.0, 10.0)] == [0.0, 0.0, 0.5, 0.75, 1.0, 1.0]
    hat = scene.TimeFunction("hat", 0.0, 1.0, 3.0)
    assert [hat.value(t) for t in (-1.0, 0.0, 0.5, 1.0, 2.0, 3.0, 4.0)] == [0.0, 0.0, 0.5, 1.0, 0.5, 0.0, 0.0]
    step = scene.TimeFunction("step", 1.0, 2.0)
    assert [step.value(t) for t in (0.5, 1.0, 1.5, 2.0, 3.0)] == [0.0, 1.0, 1.0, 0.0, 0.0]
    forever = scene.TimeFunction("step", 1.0)
    assert forever.value(1e12) == 1.0 and forever.value(0.0) == 0.0


def test_time_function_parsing_defaults():
    base = {"beam": [{"name": "a", "start": [0, 0, 0], "end": [1, 0, 0], "spans": 1,
                      "section": {"EA": 1, "kGA": 1, "GJ": 1, "EI2": 1, "EI3": 1}}]}
    tfs = [{"type": "step", "t0": 0.5}, {"type": "ramp", "t1": 2}, {"type": "constant"}]
    base["load"] = [{"type": "force", "beam": "a", "at": 0.5, "value": [0, 0, 1], "time_function": tf} for tf in tfs]
    sc = scene.scene_from_dict(base)
    assert [scene.TimeFunction.of_entry(ld) for ld in sc.entries("load")] == [
        scene.TimeFunction("step", 0.5, math.inf, math.inf),
        scene.TimeFunction("ramp", 0.0, 2.0, math.inf),
        scene.TimeFunction("constant", 0.0, math.inf, math.inf),
    ]


# ----------------------------------------------------------------------------
# overrides


def test_override_by_index_and_name(tmp_path):
    path = _write(tmp_path, SMALL)
    assert scene.load_scene(path, ["beam.0.spans=32"]).beams[0].spans == 32
    assert scene.load_scene(path, ["beam.strip.spans=33"]).beams[0].spans == 33
    assert scene.load_scene(path, ["beam.strip.quadrature=reduced"]).beams[0].quadrature == "reduced"
    assert scene.load_scene(path, ["beam.0.section.b=0.01"]).beams[0].section.EA == pytest.approx(2.07e11 * 5e-5)


def test_override_analysis(tmp_path):
    path = _write(tmp_path, SMALL)
    dyn = ['analysis.type="dynamic"', "beam.0.section.rho=1.0"]
    sc = scene.load_scene(path, [*dyn, "analysis.dt=0.001", "analysis.t_end=0.02"])
    assert (sc.analysis.type, sc.analysis.dt, sc.analysis.t_end) == ("dynamic", 0.001, 0.02)
    assert sc.analysis.dt_min == pytest.approx(0.001 / 16)
    with pytest.raises(scene.SceneError, match="'dt'"):
        scene.load_scene(path, dyn)
    with pytest.raises(scene.SceneError, match="needs mass.*rhoA"):
        scene.load_scene(path, ['analysis.type="dynamic"', "analysis.dt=0.001"])


def test_hht_defaults_are_the_standard_companions():
    data = {
        "analysis": {"type": "dynamic", "dt": 0.01, "integrator": "hht", "hht_alpha": -0.2},
        "beam": [{"name": "a", "start": [0, 0, 0], "end": [0, 0, 3], "spans": 2,
                  "section": {"EA": 1, "kGA": 2, "GJ": 1, "EI2": 1, "EI3": 1, "rhoA": 1}}],
    }
    a = scene.scene_from_dict(data).analysis
    assert (a.newmark_beta, a.newmark_gamma) == pytest.approx((1.2**2 / 4, 0.7))
    data["analysis"]["integrator"] = "newmark"
    a = scene.scene_from_dict(data).analysis
    assert (a.newmark_beta, a.newmark_gamma) == (0.25, 0.5)
    # Newmark's trapezoidal parameters kept under HHT: first order and unstable with constraints
    data["analysis"].update(integrator="hht", newmark_beta=0.25, newmark_gamma=0.5)
    with pytest.raises(scene.SceneError, match=r"newmark_gamma.*needs gamma >= 1/2 - alpha = 0.7"):
        scene.scene_from_dict(data)


@pytest.mark.parametrize("override, bad", [
    ("beam.3.spans=2", "beam.3"),
    ("beam.nosuch.spans=2", "nosuch"),
    ("nosuch.key=1", "nosuch"),
    ("beam.0.spans.x=1", "spans"),
    ("spans", "spans"),
])
def test_override_unknown_path(tmp_path, override, bad):
    path = _write(tmp_path, SMALL)
    with pytest.raises(scene.SceneError) as info:
        scene.load_scene(path, [override])
    text = str(info.value)
    assert "case.toml" in text and override in text and bad.split(".")[-1] in text


def test_override_unknown_leaf_key_is_rejected(tmp_path):
    with pytest.raises(scene.SceneError, match="unknown key 'spanz'.*did you mean 'spans'"):
        scene.load_scene(_write(tmp_path, SMALL), ["beam.0.spanz=3"])


# ----------------------------------------------------------------------------
# bad input: str(err) must name file, table and key


def _error(tmp_path: pathlib.Path, text: str) -> scene.SceneError:
    with pytest.raises(scene.SceneError) as info:
        scene.load_scene(_write(tmp_path, text, "bad.toml"))
    return info.value


def _assert_names(err: scene.SceneError, *parts: str) -> None:
    text = str(err)
    assert "bad.toml" in text, text
    for part in parts:
        assert part in text, (part, text)


def test_malformed_toml(tmp_path):
    text = SMALL + "spans = = 3\n"
    err = _error(tmp_path, text)
    _assert_names(err, "TOML", f"line {text.count(chr(10))}, column 9")
    assert err.file.endswith("bad.toml")


def test_missing_file(tmp_path):
    with pytest.raises(scene.SceneError, match="cannot read"):
        scene.load_scene(tmp_path / "nope.toml")


def test_unknown_top_level_table(tmp_path):
    err = _error(tmp_path, SMALL + "[solver]\nx = 1\n")
    _assert_names(err, "top level", "key 'solver'", "unknown key")
    assert err.key == "solver" and err.detail.startswith("unknown key")


BAD_SCENES = [  # (what is wrong, the scene text, what the message must name)
    ("unknown_beam_key_with_suggestion", SMALL.replace("spans = 16", "spans = 16\nspanz = 3"),
     ("[[beam]] #1 ('strip')", "key 'spanz'", "did you mean 'spans'?")),
    ("unknown_key_in_section", SMALL + "rhoo = 3\n",
     ("[[beam]] #1 ('strip').section", "key 'rhoo'", "did you mean 'rho'?")),
    ("zero_length_line", SMALL.replace("end = [10, 0, 0]", "end = [0, 0, 0]"),
     ("[[beam]] #1 ('strip')", "key 'end'", "zero length")),
    ("negative_b", SMALL.replace("b = 0.005", "b = -0.005"),
     ("[[beam]] #1 ('strip').section", "key 'b'", "> 0")),
    ("non_finite_number", SMALL.replace("E = 2.07e11", "E = nan"),
     ("section", "key 'E'", "finite")),
    ("support_on_missing_beam", SMALL + '[[support]]\ntype = "clamp"\nbeam = "x"\nat = "start"\n',
     ("[[support]] #1", "key 'beam'", "beam 'x' does not exist (beams: strip)")),
    ("clamp_beyond_the_beam", SMALL + '[[support]]\ntype = "clamp"\nbeam = "strip"\nat = 12.0\n',
     ("[[support]] #1", "key 'at'", "[0, L]")),
    ("fixed_with_at", SMALL + '[[support]]\ntype = "fixed"\nbeam = "strip"\nat = 5.0\n',
     ("[[support]] #1", "key 'at'", "unknown key")),
    ("spherical_off_the_beam",
     SMALL + '[[support]]\ntype = "spherical"\nbeam = "strip"\nat = 5.0\nposition = [5, 1, 0]\n',
     ("[[support]] #1", "key 'position'", "must sit on its beam")),
    ("load_beyond_the_end", SMALL + '[[load]]\ntype = "force"\nbeam = "strip"\nat = 10.5\nvalue = [0, 0, 1]\n',
     ("[[load]] #1", "key 'at'", "[0, L]", "10.5")),
    ("material_force_rejected",
     SMALL + '[[load]]\ntype = "force"\nbeam = "strip"\nat = "end"\nvalue = [0, 0, 1]\nframe = "material"\n',
     ("[[load]] #1", "key 'frame'")),
    ("bad_time_function", SMALL + '[[load]]\ntype = "force"\nbeam = "strip"\nat = "end"\nvalue = [0, 0, 1]\n'
     'time_function = { type = "hat", t1 = 2, t2 = 1 }\n',
     ("[[load]] #1.time_function", "key 't2'", "> t1")),
    ("two_geometry_kinds", SMALL.replace("spans = 16", "spans = 16\npolyline = [[0, 0, 0], [1, 0, 0]]"),
     ("[[beam]] #1 ('strip')", "key 'polyline'", "geometry given twice")),
    ("no_geometry", SMALL.replace("start = [0, 0, 0]\nend = [10, 0, 0]\n", ""),
     ("[[beam]] #1 ('strip')", "missing geometry", "'polyline'", "'arc'")),
    ("d2_parallel_to_axis", SMALL.replace("spans = 16", "spans = 16\nd2 = [-3, 0, 0]"),
     ("[[beam]] #1 ('strip')", "key 'd2'", "parallel")),
    ("mixed_section", SMALL + "EA = 1e4\n",
     ("[[beam]] #1 ('strip').section", "key 'EA'", "cannot be mixed")),
    ("duplicate_beam_names", SMALL + SMALL,
     ("[[beam]] #2 ('strip')", "key 'name'", "duplicate beam name 'strip'")),
    ("no_beams", "[analysis]\nsteps = 3\n",
     ("top level", "key 'beam'", "at least one")),
    ("options_file_missing", '[petsc]\noptions_file = "missing.opts"\n' + SMALL,
     ("[petsc]", "key 'options_file'", "missing.opts")),
]


@pytest.mark.parametrize("text, names", [e[1:] for e in BAD_SCENES], ids=[e[0] for e in BAD_SCENES])
def test_bad_scene_is_named(tmp_path, text, names):
    """A scene with one thing wrong: the message names the table entry, the key and what is expected."""
    _assert_names(_error(tmp_path, text), *names)


@pytest.mark.parametrize("value, expect", [
    ('"ten"', "must be an integer, got a string 'ten'"),
    ("2.5", "must be an integer, got a float 2.5"),
    ("true", "must be an integer, got true"),
    ("-3", "must be a positive integer, got -3"),
    ("0", "must be a positive integer, got 0"),
])
def test_bad_spans(tmp_path, value, expect):
    err = _error(tmp_path, SMALL.replace("spans = 16", f"spans = {value}"))
    _assert_names(err, "[[beam]] #1 ('strip')", "key 'spans'", expect)


def test_load_at_end_with_round_off_is_clamped(tmp_path):
    sc = scene.load_scene(_write(tmp_path, SMALL + '[[load]]\ntype = "force"\nbeam = "strip"\n'
                                                   "at = 10.000000000000001\nvalue = [0, 0, 1]\n"))
    assert sc.entries("load")[0].num["s"] == 10.0


def test_arc_start_off_circle(tmp_path):
    geo = 'arc = { center = [0, 0, 0], radius = 100.0, normal = [0, 0, 1], start = [100, 0, 1], angle = 45 }'
    err = _error(tmp_path, SMALL.replace("start = [0, 0, 0]\nend = [10, 0, 0]", geo))
    _assert_names(err, "[[beam]] #1 ('strip').arc", "key 'start'")


def test_explicit_section_needs_kga(tmp_path):
    data = {"beam": [{"name": "a", "start": [0, 0, 0], "end": [1, 0, 0], "spans": 1,
                      "section": {"EA": 1, "kGA2": 1, "GJ": 1, "EI2": 1, "EI3": 1}}]}
    with pytest.raises(scene.SceneError) as info:
        scene.scene_from_dict(data, file="x.toml")
    assert "x.toml" in str(info.value) and "key 'kGA'" in str(info.value)


def test_missing_section(tmp_path):
    text = SMALL[: SMALL.index("[beam.section]")]
    err = _error(tmp_path, text)
    _assert_names(err, "[[beam]] #1 ('strip')", "key 'section'", "missing")


def test_bad_analysis_values(tmp_path):
    err = _error(tmp_path, '[analysis]\nintegrator = "newmrak"\n' + SMALL)
    _assert_names(err, "[analysis]", "key 'integrator'", "did you mean 'newmark'?")
    err = _error(tmp_path, '[analysis]\nhht_alpha = -0.5\n' + SMALL)
    _assert_names(err, "[analysis]", "key 'hht_alpha'", "[-1/3, 0]")


def test_keys_that_say_the_same_are_refused_together(tmp_path):
    """Pairs of keys that say the same thing: the number of steps of a dynamic analysis (t_end
    and dt, not steps), the shear stiffness of both axes (kGA, or kGA2 and kGA3)."""
    err = _error(tmp_path, '[analysis]\ntype = "dynamic"\nt_end = 1.0\ndt = 0.1\nsteps = 10\n' + SMALL)
    _assert_names(err, "[analysis]", "key 'steps'", "t_end and dt")
    text = SMALL.split("[beam.section]")[0] + ("[beam.section]\nEA = 1.0\nkGA = 1.0\nkGA2 = 1.0\nkGA3 = 1.0\n"
                                               "GJ = 1.0\nEI2 = 1.0\nEI3 = 1.0\n")
    err = _error(tmp_path, text)
    _assert_names(err, "section", "key 'kGA'", "kGA2 and kGA3")


def test_error_attributes():
    err = scene.SceneError("must be > 0", file="a.toml", table="[[beam]] #1 ('s')", key="spans")
    assert str(err) == "a.toml: [[beam]] #1 ('s'), key 'spans': must be > 0"
    assert (err.file, err.table, err.key, err.detail) == ("a.toml", "[[beam]] #1 ('s')", "spans", "must be > 0")
    assert str(scene.SceneError("oops")) == "oops"


def _two_legs(joint):
    return {
        "beam": [{"name": "a", "start": [0, 0, 0], "end": [0, 1, 0], "spans": 2,
                  "section": {"EA": 1, "kGA": 1, "GJ": 1, "EI2": 1, "EI3": 1}},
                 {"name": "b", "start": [0, 1, 0], "end": [-1, 1, 0], "spans": 2,
                  "section": {"EA": 1, "kGA": 1, "GJ": 1, "EI2": 1, "EI3": 1}}],
        "rigid_joint": [joint],
    }


def _model_error(data: dict) -> str:
    """The message of the SceneError that building the model of a scene raises (checks an
    effect makes itself, with the model's beams at hand)."""
    from slidebeam.run.model import build_model
    from slidebeam.scene import SceneError, scene_from_dict  # the package's (this file loads parse.py alone)

    with pytest.raises(SceneError) as info:
        build_model(scene_from_dict(data))
    return str(info.value)


def test_rigid_joint_parses_and_checks_its_ends():
    sc = scene.scene_from_dict(_two_legs({"beams": ["a", "b"], "at": ["end", "start"]}))
    (joint,) = sc.entries("rigid_joint")
    assert (joint.num, joint.label) == ({"beam_a": 0.0, "beam_b": 1.0, "s_a": 1.0, "s_b": 0.0},
                                        "rigid_joint[a@end-b@start]")
    assert scene.scene_from_dict(_two_legs({"beams": ["a", "b"]})).effects == sc.effects  # default at
    text = _model_error(_two_legs({"beams": ["a", "b"], "at": ["start", "start"]}))
    assert "[[rigid_joint]] #1, key 'beams'" in text and "do not meet" in text and "distance" in text, text
    for joint, words in (
        ({"beams": ["a", "a"]}, ("2 different beams")),
        ({"beams": ["a", "c"]}, ("'c' does not exist")),
        ({"beams": ["a"]}, ("2 beam names")),
        ({"beams": ["a", "b"], "at": ["end", 0.5]}, ("'start'/'end'")),
        ({"beams": ["a", "b"], "where": 1}, ("where")),
    ):
        with pytest.raises(scene.SceneError) as info:
            scene.scene_from_dict(_two_legs(joint))
        text = str(info.value)
        assert "[[rigid_joint]] #1" in text and all(w in text for w in words), text


def test_damping_refuses_both_retardation_keys():
    """retardation_time (every strain) and retardation_times (each strain) together contradict
    each other: the entry and the key are named (the array used to win silently: tau = 0.01 with
    six zeros gave no damping at all). Either alone is taken."""
    data = _two_legs({"beams": ["a", "b"], "at": ["end", "start"]})
    data["damping"] = [{"beam": "a", "retardation_time": 0.01, "retardation_times": [0.0] * 6}]
    text = _model_error(data)
    assert "[[damping]] #1, key 'retardation_times'" in text and "not both" in text, text
    from slidebeam.run.model import build_model

    for damping in ({"retardation_time": 0.01}, {"retardation_times": [0.0] * 6}, {"mass_proportional": 0.1}):
        data["damping"] = [{"beam": "a", **damping}]
        build_model(scene.scene_from_dict(data))


def _slider(joint: dict) -> dict:
    section = {"EA": 1, "kGA": 1, "GJ": 1, "EI2": 1, "EI3": 1}
    return {
        "beam": [{"name": "carrier", "start": [0, 0, 0], "end": [2, 0, 0], "spans": 4, "section": section},
                 {"name": "hanger", "start": [0.5, 0, 0], "end": [0.5, 0, -1], "spans": 1, "section": section}],
        "sliding_joint": [joint],
    }


def test_sliding_joint_parses_and_checks_its_input():
    sc = scene.scene_from_dict(_slider({"slider": "hanger", "carrier": "carrier"}))
    assert sc.sliding_joints == (scene.SlidingJoint(1, 0.0, 0, "exact", "stop", None, carriers=(0,)),)
    sc = scene.scene_from_dict(_slider({"slider": "hanger", "at": "end", "carrier": "carrier",
                                        "discrete_gradient": "midpoint", "at_carrier_end": "fail", "tolerance": 1e-3}))
    assert sc.sliding_joints == (scene.SlidingJoint(1, 1.0, 0, "midpoint", "fail", 1e-3, form="spatial",
                                                    carriers=(0,)),)
    data = _slider({"slider": "hanger", "carrier": ["carrier", "next"]})
    data["beam"].append(dict(data["beam"][0], name="next", start=[2, 0, 0], end=[3, 0, 0]))
    assert scene.scene_from_dict(data).sliding_joints[0].carriers == (0, 2)  # a track
    data["sliding_joint"][0]["carrier"] = ["carrier", 3]
    with pytest.raises(scene.SceneError, match=r"carrier.*a beam's name or a list of beams' names"):
        scene.scene_from_dict(data)
    data["sliding_joint"][0]["carrier"] = ["carrier", "nope"]
    with pytest.raises(scene.SceneError, match=r"carrier.*beam 'nope' does not exist"):
        scene.scene_from_dict(data)
    assert sc.sliding_joints[0].form == "spatial"  # the seed's midpoint form: the spatial constraint
    sc = scene.scene_from_dict(_slider({"slider": "hanger", "carrier": "carrier"}))
    assert sc.sliding_joints[0].form == "frame"  # director sliders: the frame-projected joint
    sc = scene.scene_from_dict(_slider({"slider": "hanger", "carrier": "carrier", "form": "spatial"}))
    assert sc.sliding_joints[0].form == "spatial"
    cable = _slider({"slider": "hanger", "carrier": "carrier"})
    cable["beam"][1].update(formulation="ancf", section={"EA": 1, "EI": 1, "rhoA": 1})
    assert scene.scene_from_dict(cable).sliding_joints[0].form == "spatial"  # a cable has no directors
    cable["sliding_joint"][0]["form"] = "frame"
    text = _model_error(cable)
    assert "[[sliding_joint]] #1, key 'form'" in text and "'hanger' is an ANCF cable" in text, text
    text = _model_error(_slider({"slider": "hanger", "carrier": "hanger"}))
    assert "[[sliding_joint]] #1, key 'carrier'" in text and "cannot slide on itself" in text, text
    for joint, words in (
        ({"slider": "hanger", "carrier": "carier"}, ("'carier' does not exist", "did you mean 'carrier'")),
        ({"carrier": "carrier"}, ("slider")),
        ({"slider": "hanger", "carrier": "carrier", "discrete_gradient": "seed"}, ("discrete_gradient", "exact")),
        ({"slider": "hanger", "carrier": "carrier", "at_carrier_end": "clamp"}, ("at_carrier_end", "stop")),
        ({"slider": "hanger", "carrier": "carrier", "form": "material"}, ("form", "frame", "spatial")),
        ({"slider": "hanger", "carrier": "carrier", "tolerance": -1.0}, ("tolerance", "> 0")),
        ({"slider": "hanger", "carrier": "carrier", "at": 3.0}, ("at", "[0, L]")),
        ({"slider": "hanger", "carrier": "carrier", "friction": 0.1}, ("unknown key 'friction'")),
    ):
        with pytest.raises(scene.SceneError) as info:
            scene.scene_from_dict(_slider(joint))
        text = str(info.value)
        assert "[[sliding_joint]] #1" in text and all(w in text for w in words), text
