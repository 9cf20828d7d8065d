"""Bad options raise OptionError (a ValueError) with the CLI's message, before anything renders."""
import pytest

from conftest import CORNELL, run_cli

CASES = [
    ("restir-pt", {"pt.shfit": "hybrid"}),               # a misspelt key: did you mean
    ("restir-pt", {"pt.shift": "sideways"}),             # a value not in the enum
    ("pt", {"film.width": 0}),                           # out of range
    ("pt", {"path.max_depth": "deep"}),                  # not an integer
    ("pt", {"di.light_candidates": 4}),                  # a key the integrator does not read
    ("restir-pt", {"path.max_depth": 100}),              # outside the integrator's depth range
]


@pytest.mark.parametrize("integrator,options", CASES)
def test_message_is_the_cli_message(rl, cornell, integrator, options):
    sets = [a for k, v in options.items() for a in ("--set", f"{k}={v}")]
    p = run_cli("render", CORNELL, "-q", "-o", "/nonexistent/never.exr", "--integrator", integrator, *sets, check=False)
    assert p.returncode == 1 and p.stderr.startswith("error: ")
    cli_message = p.stderr.strip().removeprefix("error: ")
    with pytest.raises(rl.OptionError) as e:
        rl.Renderer(cornell, integrator, options)
    assert str(e.value) == cli_message
    assert isinstance(e.value, ValueError)


def test_nested_keys_and_types(rl, cornell):
    nested = rl.Renderer(cornell, "restir-pt", {"pt": {"shift": "reconnection"}, "film": {"width": 8, "height": 8},
                                                 "pt.temporal": False, "output.exposure": 0.5})
    o = nested.options()
    assert o["pt.shift"] == "reconnection" and o["pt.temporal"] == "false" and o["film.width"] == "8"
    assert float(o["output.exposure"]) == 0.5
    with pytest.raises(rl.OptionError, match="unsupported value type 'list'"):
        rl.Renderer(cornell, "pt", {"film.width": [8]})
    with pytest.raises(rl.OptionError, match="unknown integrator|integrator"):
        rl.Renderer(cornell, "nope")


def test_reset_keeps_the_film(rl, cornell):
    r = rl.Renderer(cornell, "restir-di", {"film.width": 8, "film.height": 8})
    r.render_frame()
    r.reset({"di.spatial_neighbors": 2})
    assert r.frame == 0 and r.options()["di.spatial_neighbors"] == "2"
    with pytest.raises(rl.OptionError, match="fixed for a Renderer"):
        r.reset({"film.width": 16})


def test_scene_errors(rl, tmp_path):
    bad = tmp_path / "bad.pbrt"
    bad.write_text("WorldBegin\nShape \"sphere\" \"float radius\" [ -1 ]\nBogus\n")
    p = run_cli("render", bad, "-q", "-o", tmp_path / "x.exr", check=False)
    with pytest.raises(rl.SceneError) as e:
        rl.load_scene(str(bad))
    assert str(e.value) == p.stderr.strip().removeprefix("error: ")
