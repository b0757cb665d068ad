"""Parameters (DESIGN.md "Parameters"; issue 2 items 4 and 9): validation with one-line errors
that name the parameter and its range, ``--set``, versions, TOML presets and ``// @param``
annotations in GLSL — including a new annotated uniform that becomes a parameter with no
Python change."""

from __future__ import annotations

import shutil

import pytest

from app import DEFAULT_SHADER_ROOT
from app.errors import ParamError
from app.params import Param, ParamSet, param_name_from_uniform, parse_glsl_annotations
from app.runtime import scene_params


def one_line(exc: pytest.ExceptionInfo) -> str:
    text = str(exc.value)
    assert "\n" not in text, text
    return text


@pytest.fixture
def sun_size() -> Param:
    return Param("sky.sun_size", 0.05, 0.0, 1.0, "sun disk size", step=0.005, section="§1.7")


# ---- Param.validate ----------------------------------------------------------------------------

@pytest.mark.parametrize("value, why", [
    (5, "out of range"),
    ("5", "out of range"),
    (-0.1, "out of range"),
    ("1.0000001", "out of range"),
    ("abc", "not a number"),
    ("", "not a number"),
    (None, "not a number"),
    (float("nan"), "not finite"),
    ("nan", "not finite"),
    ("inf", "not finite"),
    (float("-inf"), "not finite"),
])
def test_bad_float_names_parameter_and_range(sun_size, value, why):
    with pytest.raises(ParamError) as info:
        sun_size.validate(value)
    text = one_line(info)
    assert text.startswith("sky.sun_size=")
    assert why in text
    assert "[0, 1]" in text


@pytest.mark.parametrize("value, expected", [(0, 0.0), (1, 1.0), ("0.25", 0.25), (" 0.5 ", 0.5),
                                             ("1e-1", 0.1)])
def test_good_float(sun_size, value, expected):
    out = sun_size.validate(value)
    assert isinstance(out, float) and out == pytest.approx(expected)


def test_bool_parsing():
    p = Param("fx.enabled", True, doc="on or off", kind="bool")
    for text in ("true", "True", "1", "yes", "on", True):
        assert p.validate(text) is True
    for text in ("false", "FALSE", "0", "no", "off", False):
        assert p.validate(text) is False
    with pytest.raises(ParamError) as info:
        p.validate("maybe")
    assert "fx.enabled" in one_line(info) and "true or false" in str(info.value)


def test_int_parsing():
    p = Param("fx.steps", 8, 1, 64, "march steps", kind="int")
    assert p.step == 1
    assert p.validate("12") == 12 and isinstance(p.validate("12"), int)
    assert p.validate(3.0) == 3 and isinstance(p.validate(3.0), int)
    for bad, why in (("2.5", "not an integer"), ("0", "out of range"), ("65", "out of range"),
                     ("x", "not a number")):
        with pytest.raises(ParamError) as info:
            p.validate(bad)
        text = one_line(info)
        assert "fx.steps" in text and why in text and "[1, 64]" in text and "integer" in text


def test_vec3_parsing():
    p = Param("sky.ecliptic", (0.0, 0.6, -1.0), -1.0, 1.0, "axis", kind="vec3")
    assert p.validate("0.1,0.2,0.3") == (0.1, 0.2, 0.3)
    assert p.validate("(0.1, 0.2, -0.3)") == (0.1, 0.2, -0.3)
    assert p.validate("0.1 0.2 0.3") == (0.1, 0.2, 0.3)
    assert p.validate([1, 0, -1]) == (1.0, 0.0, -1.0)
    for bad, why in (("1,2", "not three numbers"), ("0,0,0,0", "not three numbers"),
                     ("0,0,2", "out of range"), ("a,b,c", "not a number"),
                     (0.5, "not three numbers"), ("0,nan,0", "not finite")):
        with pytest.raises(ParamError) as info:
            p.validate(bad)
        text = one_line(info)
        assert "sky.ecliptic" in text and why in text and "[-1, 1]" in text


def test_color_parsing():
    p = Param("sky.sun_color", (1.0, 1.0, 1.0), 0.0, 1.0, "colour", kind="color")
    assert p.validate("#ff8000") == pytest.approx((1.0, 128 / 255, 0.0))
    assert p.validate("1, 0.5, 0") == (1.0, 0.5, 0.0)
    for bad in ("#gg0000", "#ff80", "1,1,1.5"):
        with pytest.raises(ParamError) as info:
            p.validate(bad)
        assert "sky.sun_color" in one_line(info) and "[0, 1]" in str(info.value)


def test_choice_parsing():
    p = Param("output.tonemap", "aces", doc="tone map", kind="choice",
              choices=("aces", "reinhard", "clamp"))
    assert p.validate(" reinhard ") == "reinhard"
    with pytest.raises(ParamError) as info:
        p.validate("filmic")
    text = one_line(info)
    assert "output.tonemap" in text and "aces, reinhard, clamp" in text


def test_declaration_checks_its_own_default():
    with pytest.raises(ParamError) as info:
        Param("fx.bad", 5.0, 0.0, 1.0)
    assert "fx.bad" in str(info.value) and "[0, 1]" in str(info.value)
    with pytest.raises(ValueError):
        Param("fx.odd", 1.0, 0.0, 2.0, kind="matrix")


def test_step_defaults_to_a_hundredth_of_the_range():
    assert Param("fx.a", 5.0, 0.0, 10.0).step == pytest.approx(0.1)
    assert Param("fx.b", 0.5, 0.0, 1.0, step=0.25).step == 0.25


# ---- ParamSet ----------------------------------------------------------------------------------

@pytest.fixture
def params(sun_size) -> ParamSet:
    return ParamSet([
        sun_size,
        Param("sky.sun_intensity", 2.0, 0.0, 20.0, "sun disk brightness"),
        Param("sky.sun_color", (1.0, 1.0, 1.0), 0.0, 1.0, "sun colour", kind="color"),
        Param("sky.horizon", True, doc="hide below the horizon", kind="bool"),
        Param("sky.star_seed", 7, 0, 2**31 - 1, "seed", kind="int"),
        Param("time.hour", 12.0, 0.0, 24.0, "hour of day", unit="h"),
        Param("output.tonemap", "aces", doc="tone map", kind="choice",
              choices=("aces", "reinhard", "clamp")),
        Param("output.exposure", 1.0, 0.001, 1000.0, "exposure"),
    ])


def test_set_from_string(params):
    params.set_from_string("sky.sun_size=0.1")
    assert params["sky.sun_size"] == 0.1
    params.set_from_string(" sky.sun_color = #000000 ")
    assert params["sky.sun_color"] == (0.0, 0.0, 0.0)
    params.set_from_string("sky.horizon=off")
    assert params["sky.horizon"] is False


@pytest.mark.parametrize("assignment, must_contain", [
    ("sky.sun_size=abc", ["sky.sun_size", "not a number", "[0, 1]"]),
    ("sky.sun_size=5", ["sky.sun_size", "out of range", "[0, 1]"]),
    ("sky.sun_size=", ["sky.sun_size", "[0, 1]"]),
    ("sky.sun_size", ["name=value"]),
    ("sky.star_seed=1.5", ["sky.star_seed", "integer"]),
    ("output.tonemap=filmic", ["output.tonemap", "aces, reinhard, clamp"]),
])
def test_set_from_string_errors(params, assignment, must_contain):
    before = params.values()
    with pytest.raises(ParamError) as info:
        params.set_from_string(assignment)
    text = one_line(info)
    for part in must_contain:
        assert part in text, text
    assert params.values() == before  # a failed set changes nothing


def test_unknown_parameter_lists_allowed_names(params):
    with pytest.raises(ParamError) as info:
        params.set_from_string("sky.sun_sise=0.1")
    text = one_line(info)
    assert "'sky.sun_sise'" in text
    # the same group's names when the group exists...
    for name in ("sky.sun_size", "sky.sun_intensity", "sky.sun_color", "sky.horizon",
                 "sky.star_seed"):
        assert name in text
    assert "time.hour" not in text
    # ...every name otherwise
    with pytest.raises(ParamError) as info:
        params["ocean.wave_height"]
    text = one_line(info)
    assert "ocean.wave_height" in text and "time.hour" in text and "sky.sun_size" in text
    with pytest.raises(ParamError):
        params.spec("nope")


def test_version_bumps_only_on_change(params):
    sky, time_ = params.version("sky"), params.version("time")
    params.set("sky.sun_size", 0.05)  # same value
    params.set_from_string("sky.sun_size=0.050")  # same value, as text
    assert params.version("sky") == sky
    params.set("sky.sun_size", 0.2)
    assert params.version("sky") == sky + 1
    assert params.version("time") == time_  # other groups untouched
    with pytest.raises(ParamError):
        params.set("sky.sun_size", 7)
    assert params.version("sky") == sky + 1 and params["sky.sun_size"] == 0.2
    params.reset("sky.sun_size")
    assert params.version("sky") == sky + 2 and params["sky.sun_size"] == 0.05
    params.reset()  # everything is already at its default
    assert params.version("sky") == sky + 2
    assert params.version("no_such_group") == 0


def test_redeclaring_a_python_parameter_is_an_error(params):
    with pytest.raises(ValueError):
        params.add(Param("sky.sun_size", 0.1, 0.0, 1.0))


def test_redeclared_glsl_parameter_keeps_a_still_valid_value():
    ps = ParamSet([Param("fx.gain", 1.0, 0.0, 2.0, source="glsl/fx.glsl")])
    ps.set("fx.gain", 1.5)
    # the shader was edited: wider range
    ps.add(Param("fx.gain", 1.0, 0.0, 4.0, source="glsl/fx.glsl"))
    assert ps["fx.gain"] == 1.5
    ps.add(Param("fx.gain", 0.5, 0.0, 1.0, source="glsl/fx.glsl"))  # narrower: 1.5 no longer fits
    assert ps["fx.gain"] == 0.5


# ---- presets -----------------------------------------------------------------------------------

def test_load_good_preset(params, tmp_path):
    path = tmp_path / "dusk.toml"
    path.write_text('# a preset\n[sky]\nsun_size = 0.1\nsun_color = [1.0, 0.5, 0.25]\n'
                    'horizon = false\nstar_seed = 42\n\n[time]\nhour = 18.5\n\n[output]\n'
                    'tonemap = "reinhard"\n')
    params.load_preset(path)
    assert params["sky.sun_size"] == 0.1
    assert params["sky.sun_color"] == (1.0, 0.5, 0.25)
    assert params["sky.horizon"] is False
    assert params["sky.star_seed"] == 42
    assert params["time.hour"] == 18.5
    assert params["output.tonemap"] == "reinhard"
    assert params["sky.sun_intensity"] == 2.0  # not listed: unchanged


@pytest.mark.parametrize("text, must_contain", [
    ("[sky\nsun_size = 0.1\n", ["not valid TOML"]),
    ("[sky]\nsun_size = = 0.1\n", ["not valid TOML"]),
    ("[sky]\nsun_sise = 0.1\n", ["unknown parameter", "sky.sun_sise", "sky.sun_size"]),
    ("[sky]\nsun_size = 3.0\n", ["sky.sun_size", "out of range", "[0, 1]"]),
    ("[sky]\nsun_size = \"big\"\n", ["sky.sun_size", "not a number"]),
    ("sun_size = 0.1\n", ["must be a table"]),
])
def test_bad_preset(params, tmp_path, text, must_contain):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(ParamError) as info:
        params.load_preset(path)
    message = one_line(info)
    for part in must_contain:
        assert part in message, message


def test_missing_preset(params, tmp_path):
    with pytest.raises(ParamError) as info:
        params.load_preset(tmp_path / "nope.toml")
    assert "nope.toml" in one_line(info) and "does not exist" in str(info.value)


def test_preset_text_round_trip(params, tmp_path):
    params.set("sky.sun_size", 1e-5)
    params.set("sky.sun_intensity", 13.37)
    params.set("sky.sun_color", "#ff8000")
    params.set("sky.horizon", False)
    params.set("sky.star_seed", 2**31 - 1)
    params.set("time.hour", 0.1 + 0.2)  # a float that needs every digit
    params.set("output.tonemap", "clamp")
    path = tmp_path / "round.toml"
    path.write_text(params.preset_text("round trip"), encoding="utf-8")

    fresh = ParamSet(list(params))
    for p in fresh:
        fresh.reset(p.name)
    assert fresh.values() != params.values()
    fresh.load_preset(path)
    assert fresh.values() == params.values()


def test_scene_preset_round_trip(tmp_path):
    params = scene_params("sky")
    params.set_from_string("sky.sun_size=0.125")
    params.set_from_string("sky.sun_color=0.9,0.8,0.7")
    params.set_from_string("time.hour=6.25")
    path = tmp_path / "sky.toml"
    path.write_text(params.preset_text())
    fresh = scene_params("sky")
    assert fresh.values() != params.values()
    fresh.load_preset(path)
    assert fresh.values() == params.values()


# ---- GLSL annotations --------------------------------------------------------------------------

ANNOTATED = """\
// a shader file
uniform float uSunSize; // @param 0.05 [0, 1] step=0.005 §1.7 sun disk size
uniform vec3 uSunColor;   // @param (1, 0.5, 0.25) [0, 1] color §1.7 sun colour
uniform vec3 uAxis;       // @param (0, 0.6, -1) [-1, 1] rotation axis
uniform bool uHorizonOcclusion; // @param true the Earth hides what is below the horizon
uniform int uSteps;       // @param 8 [1, 64] unit=steps march steps
uniform float uFogDensity; // @param 0.02 [0, 1] unit=1/m §2.3 fog density
uniform float uPlain;     // not annotated
uniform mat3 uMatrix;
"""


def test_annotations_become_parameters():
    found = {p.name: p for p in parse_glsl_annotations(ANNOTATED, "sky", "glsl/sky/test.glsl",
                                                       "spec/000")}
    assert list(found) == ["sky.sun_size", "sky.sun_color", "sky.axis", "sky.horizon_occlusion",
                           "sky.steps", "sky.fog_density"]

    p = found["sky.sun_size"]
    assert (p.kind, p.default, p.lo, p.hi, p.step) == ("float", 0.05, 0.0, 1.0, 0.005)
    assert p.section == "spec/000 §1.7"
    assert p.doc == "sun disk size"
    assert p.uniform == "uSunSize" and p.source == "glsl/sky/test.glsl" and p.group == "sky"

    c = found["sky.sun_color"]
    assert (c.kind, c.default, c.lo, c.hi, c.doc) == ("color", (1.0, 0.5, 0.25), 0.0, 1.0,
                                                      "sun colour")
    v = found["sky.axis"]
    assert (v.kind, v.default, v.lo, v.hi, v.section) == ("vec3", (0.0, 0.6, -1.0), -1.0, 1.0, "")

    b = found["sky.horizon_occlusion"]
    assert (b.kind, b.default, b.lo, b.hi) == ("bool", True, None, None)
    assert b.doc == "the Earth hides what is below the horizon"

    i = found["sky.steps"]
    assert (i.kind, i.default, i.lo, i.hi, i.step, i.unit, i.doc) == ("int", 8, 1, 64, 1, "steps",
                                                                      "march steps")
    assert isinstance(i.default, int)
    f = found["sky.fog_density"]
    assert (f.unit, f.section, f.doc) == ("1/m", "spec/000 §2.3", "fog density")


def test_an_annotation_doc_goes_on_below_in_its_column():
    text = ("uniform float uA; // @param 0.5 [0, 1] step=0.1 unit=m §1.6 first part,\n"
            "                  //   and the rest\n"
            "                  // still the doc\n"
            "uniform float uB; // @param 1 [0, 2] its own doc\n"
            "                     // not the doc: another column\n"
            "// nor this\n")
    found = {p.name: p for p in parse_glsl_annotations(text, "fx", "glsl/fx/wrapped.glsl")}
    a, b = found["fx.a"], found["fx.b"]
    assert (a.default, a.lo, a.hi, a.step, a.unit, a.section) == (0.5, 0.0, 1.0, 0.1, "m", "§1.6")
    assert a.doc == "first part, and the rest still the doc"
    assert b.doc == "its own doc"


def test_no_annotations_no_parameters():
    assert parse_glsl_annotations("uniform float uX;\nvoid main() {}\n// @param in a comment\n",
                                  "fx") == []


@pytest.mark.parametrize("line, why", [
    ("uniform float uA; // @param [0, 1] no default", "default"),
    ("uniform float uA; // @param 0.5 no range", "range"),
    ("uniform float uA; // @param 5 [0, 1] default out of range", "out of range"),
    ("uniform vec3 uA; // @param (1, 2) [0, 1] two components", "default"),
    ("uniform int uA; // @param 2.5 [0, 4] not an integer", "integer"),
    ("uniform mat3 uA; // @param 1 [0, 1] unsupported type", "unsupported"),
])
def test_malformed_annotation_names_file_and_line(line, why):
    text = f"#version 330 core\n// header\n{line}\n"
    with pytest.raises(ParamError) as info:
        parse_glsl_annotations(text, "fx", "glsl/fx/broken.glsl")
    message = one_line(info)
    assert message.startswith("glsl/fx/broken.glsl:3:"), message
    assert why in message


@pytest.mark.parametrize("uniform, name", [
    ("uSunSize", "sun_size"), ("u_sun_size", "sun_size"), ("fogDensity", "fog_density"),
    ("uX", "x"),
    ("sunSize2", "sun_size2"), ("uniformity", "uniformity"),
])
def test_param_names_from_uniforms(uniform, name):
    assert param_name_from_uniform(uniform) == name


def test_real_sky_annotations_are_parameters():
    params = scene_params("sky")
    p = params.spec("sky.sun_size")
    assert (p.default, p.lo, p.hi, p.uniform) == (0.05, 0.0, 1.0, "uSunSize")
    assert p.source.endswith("sky/sky_radiance.glsl")
    assert "§1.7" in p.section
    assert params.spec("sky.sun_color").kind == "color"


def test_annotating_a_uniform_in_a_copy_adds_a_parameter(tmp_path):
    copy = tmp_path / "glsl"
    shutil.copytree(DEFAULT_SHADER_ROOT, copy)
    radiance = copy / "sky" / "sky_radiance.glsl"
    with radiance.open("a", encoding="utf-8") as f:
        f.write("uniform float uHazeAmount; // @param 0.3 [0, 2] step=0.01 unit=km §9.9 haze over"
                " the sea\n")

    before = scene_params("sky")
    after = scene_params("sky", shader_root=copy)
    assert "sky.haze_amount" not in before
    assert set(after.values()) - set(before.values()) == {"sky.haze_amount"}
    p = after.spec("sky.haze_amount")
    assert (p.default, p.lo, p.hi, p.step, p.unit, p.doc) == (0.3, 0.0, 2.0, 0.01, "km",
                                                              "haze over the sea")
    assert p.uniform == "uHazeAmount" and p.section.endswith("§9.9")
    assert after["sky.haze_amount"] == 0.3

    # and it validates like any other parameter
    after = scene_params("sky", shader_root=copy, sets=["sky.haze_amount=1.5"])
    assert after["sky.haze_amount"] == 1.5
    with pytest.raises(ParamError) as info:
        scene_params("sky", shader_root=copy, sets=["sky.haze_amount=3"])
    assert "sky.haze_amount" in one_line(info) and "[0, 2]" in str(info.value)


def test_a_malformed_annotation_in_a_copy_names_the_file(tmp_path):
    copy = tmp_path / "glsl"
    shutil.copytree(DEFAULT_SHADER_ROOT, copy)
    radiance = copy / "sky" / "sky_radiance.glsl"
    line = len(radiance.read_text().splitlines()) + 1
    with radiance.open("a", encoding="utf-8") as f:
        f.write("uniform float uBroken; // @param 9 [0, 1] default out of range\n")
    with pytest.raises(ParamError) as info:
        scene_params("sky", shader_root=copy)
    assert f"sky_radiance.glsl:{line}:" in one_line(info)

