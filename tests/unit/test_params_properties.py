"""Property tests (hypothesis) for what users type and the files they give (issue 11): a
parameter value of any type, a preset of any bytes, an output name of any characters — each is
accepted or refused with one short line, and nothing else ever escapes.
"""

from __future__ import annotations

import math
import os

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from app.errors import LINE_LIMIT, ParamError, UsageError, one_line, quote
from app.imageio import check_output_path
from app.params import Param, ParamSet

SETTINGS = settings(max_examples=150, deadline=None,
                    suppress_health_check=[HealthCheck.function_scoped_fixture])

PARAMS = [
    Param("sky.sun_size", 0.05, 0.0, 1.0, "sun disk size"),
    Param("sky.free", 1.0, doc="no range"),
    Param("sky.star_seed", 7, 0, 2**31 - 1, "seed", kind="int"),
    Param("sky.horizon", True, doc="hide below the horizon", kind="bool"),
    Param("sky.sun_color", (1.0, 1.0, 1.0), 0.0, 1.0, "sun colour", kind="color"),
    Param("sky.wind", (0.0, 0.0, 0.0, 0.0), -50.0, 50.0, "wind", kind="vec4"),
    Param("output.tonemap", "aces", doc="tone map", kind="choice",
          choices=("aces", "reinhard", "clamp")),
]

scalars = st.one_of(
    st.none(), st.booleans(), st.integers(), st.integers(min_value=10**300, max_value=10**400),
    st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=300),
    st.binary(max_size=50), st.sampled_from(["nan", "inf", "-inf", "1e999", "#ffffff", "#zzzzzz",
                                             "(1, 2, 3)", "1,2,3,4", "true", " 0.5 ", "0x10"]),
)
values = st.recursive(scalars, lambda inner: st.one_of(
    st.lists(inner, max_size=5), st.tuples(inner, inner, inner),
    st.dictionaries(st.text(max_size=5), inner, max_size=3)), max_leaves=20)


def deep(n: int) -> list:
    v: list = []
    for _ in range(n):
        v = [v]
    return v


@pytest.mark.parametrize("param", PARAMS, ids=lambda p: p.kind)
@SETTINGS
@given(value=values)
def test_validate_raises_only_param_error(param, value):
    try:
        out = param.validate(value)
    except ParamError as exc:
        text = str(exc)
        assert "\n" not in text and len(text) <= LINE_LIMIT, text
        assert param.name in text and "allowed" in text
        return
    # accepted: of the parameter's type, finite and in range
    items = out if isinstance(out, tuple) else (out,)
    for x in items:
        if isinstance(x, float):
            assert math.isfinite(x)
            if param.lo is not None:
                assert param.lo - 1e-9 <= x <= param.hi + 1e-9


@pytest.mark.parametrize("value", [deep(5000), 10**5000, [10**400] * 3, {"a": deep(3000)},
                                   "9" * 5000, float("nan"), [float("inf")] * 3],
                         ids=["deep", "int5000", "bigints", "deepdict", "str5000", "nan", "inf"])
def test_validate_pathological_values(value):
    for param in PARAMS:
        try:
            param.validate(value)
        except ParamError as exc:
            assert len(str(exc)) <= LINE_LIMIT


def _preset_set() -> ParamSet:
    return ParamSet(PARAMS)


@SETTINGS
@given(data=st.binary(max_size=400))
def test_preset_of_random_bytes(tmp_path, data):
    path = tmp_path / "p.toml"
    path.write_bytes(data)
    try:
        _preset_set().load_preset(path)
    except ParamError as exc:
        assert "\n" not in str(exc) and len(str(exc)) <= LINE_LIMIT


toml_values = st.one_of(
    st.integers().map(str), st.integers(min_value=10**20, max_value=10**60).map(str),
    st.floats().map(repr), st.sampled_from(["nan", "inf", "-inf", "true", "1979-05-27",
                                            "[1, 2, 3]", "[[[[1]]]]", "{a = 1}", '"x"', "''",
                                            "[" * 2000 + "]" * 2000, "9" * 5000]),
    st.text(max_size=20).map(lambda t: '"' + t.replace("\\", "").replace('"', "") + '"'))


@SETTINGS
@given(group=st.sampled_from(["sky", "output", "nosuch", "sky.sun_size"]),
       key=st.sampled_from(["sun_size", "free", "star_seed", "horizon", "sun_color", "wind",
                            "tonemap", "nope"]), value=toml_values)
def test_preset_of_random_toml(tmp_path, group, key, value):
    path = tmp_path / "p.toml"
    path.write_text(f"[{group}]\n{key} = {value}\n", encoding="utf-8")
    try:
        _preset_set().load_preset(path)
    except ParamError as exc:
        assert "\n" not in str(exc) and len(str(exc)) <= LINE_LIMIT


@pytest.mark.parametrize("make", ["folder", "fifo", "devzero", "devnull", "huge", "latin1",
                                  "deep", "bigint"])
def test_preset_odd_files(tmp_path, make):
    path = tmp_path / "p.toml"
    if make == "folder":
        path.mkdir()
    elif make == "fifo":
        os.mkfifo(path)  # must be refused before opening: opening would block
    elif make == "devzero":
        path = "/dev/zero"
    elif make == "devnull":
        path = "/dev/null"
    elif make == "huge":
        path.write_bytes(b"#" * (2 << 20))
    elif make == "latin1":
        path.write_bytes("[sky]\nsun_size = 0.1 # é\n".encode("latin-1"))
    elif make == "deep":
        path.write_bytes(b"a = " + b"[" * 10000 + b"]" * 10000)
    else:
        path.write_bytes(b"[sky]\nsun_size = " + b"9" * 500 + b"\n")
    with pytest.raises(ParamError) as info:
        _preset_set().load_preset(path)
    text = str(info.value)
    assert "preset" in text and "allowed" in text and len(text) <= LINE_LIMIT, text


@SETTINGS
@given(name=st.text(min_size=0, max_size=300))
def test_output_names_of_any_characters(tmp_path, name):
    assume("\x00" not in name)
    try:
        p = check_output_path(str(tmp_path / name))
    except UsageError as exc:
        text = str(exc)
        assert "\n" not in text and len(text) <= LINE_LIMIT and "allowed" in text, text
        return
    assert p.suffix.lower() in (".png", ".exr") and len(os.fsencode(p.name)) <= 255


@SETTINGS
@given(text=st.text(max_size=3000))
def test_one_line_and_quote(text):
    line = one_line(f"x {text!r} y: allowed z {text}")
    assert "\n" not in line and len(line) <= LINE_LIMIT
    assert len(quote(text)) <= 60


# ---- rules between parameters: refused first exactly where the effect would refuse later -----

_CLOUDS = None


def _clouds_params():
    global _CLOUDS
    if _CLOUDS is None:
        from app.runtime import scene_params

        _CLOUDS = scene_params("clouds")
    return _CLOUDS


@SETTINGS
@given(cells=st.lists(st.integers(1, 64), min_size=6, max_size=6),
       heights=st.tuples(st.integers(0, 20000), st.integers(0, 20000)))
def test_a_joint_rule_refuses_exactly_what_the_bakes_and_the_march_refuse(cells, heights):
    """Cell counts and heights drawn inside their ranges: the scene's rules (checked before any
    work) refuse a set exactly when the bake specs or the cloud march would refuse it, and the
    message names the rule a user saw in ``natura params``."""
    import copy

    from app.bakes.params import DetailBake, ShapeBake

    params = copy.deepcopy(_clouds_params())
    names = ["bake_shape.cells_g", "bake_shape.cells_b", "bake_shape.cells_a",
             "bake_detail.cells_r", "bake_detail.cells_g", "bake_detail.cells_b"]
    for name, value in zip(names, cells):
        params.set(name, value)
    params.set("clouds.base_height", heights[0])
    params.set("clouds.max_height", heights[1])
    later = None
    try:
        ShapeBake.from_values(params.values("bake_shape"))
        DetailBake.from_values(params.values("bake_detail"))
        if heights[1] - heights[0] < 1:
            later = "clouds.max_height ≥ base_height + 1 m"
    except ParamError as exc:
        later = str(exc)
    try:
        params.check_joint()
    except ParamError as exc:
        assert later is not None, f"refused first, accepted later: {exc}"
        rules = [j.text for j in params.joints()]
        assert any(rule in str(exc) for rule in rules) and len(str(exc)) <= LINE_LIMIT
    else:
        assert later is None, f"accepted first, refused later: {later}"


@SETTINGS
@given(sizes=st.lists(st.floats(0.1, 5000.0), min_size=4, max_size=4),
       cascades=st.integers(1, 4), n=st.sampled_from(["64", "128", "256", "512"]))
def test_the_ocean_rule_refuses_exactly_what_its_cascades_refuse(sizes, cascades, n):
    from app.effects.ocean.effect import Ocean
    from app.params import ParamSet, with_joints
    from app.sim.ocean import cascade_bands

    params = ParamSet(with_joints(Ocean.python_params(), Ocean.joints))
    params.set("ocean.patch_sizes", tuple(sizes))
    params.set("ocean.cascades", cascades)
    params.set("ocean.fft_size", n)
    try:
        cascade_bands(int(n), sizes[:cascades])
        later = None
    except ParamError as exc:
        later = str(exc)
    try:
        params.check_joint()
    except ParamError as exc:
        assert later is not None and later in str(exc)
        assert str(exc).endswith("allowed falling patch sizes that hold their bands at "
                                 "ocean.fft_size")
    else:
        assert later is None
