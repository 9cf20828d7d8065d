"""The module renders what the CLI renders: the same configuration gives the same EXR bit for bit,
N render_frame() calls give `--frames N`, and the metrics are `restir compare`'s."""
import json

import numpy as np
import pytest

from conftest import CORNELL, ROOT, run_cli


def cli_render(tmp_path, name, *args):
    out = tmp_path / f"{name}.exr"
    run_cli("render", CORNELL, "-q", "-o", out, *args)
    return out


@pytest.mark.parametrize("scene,integrator,frames,sets", [
    (CORNELL, "restir-pt", 5, {"pt.shift": "hybrid", "path.max_depth": 4}),
    (CORNELL, "restir-di", 4, {"di.spatial_neighbors": 3}),
    (CORNELL, "restir-gi", 3, {"path.max_depth": 3}),
    (CORNELL, "restir-di", 4, {"render.camera_path": str(ROOT / "scenes" / "cornell-box.camera.json")}),  # a moving camera
    (str(ROOT / "scenes" / "dynamic-room.pbrt"), "restir-pt", 3, {"path.max_depth": 3, "pt.shift": "random-replay"}),  # animated
])
def test_frames_equal_cli_sequence(rl, tmp_path, scene, integrator, frames, sets):
    args = ["--integrator", integrator, "--frames", frames, "--spp", 1, "--res", "48x32"]
    for k, v in sets.items():
        args += ["--set", f"{k}={v}"]
    out = tmp_path / f"{integrator}.exr"
    run_cli("render", scene, "-q", "-o", out, *args)
    cli = rl.read_image(str(out))
    r = rl.Renderer(rl.load_scene(scene), integrator, {"film.width": 48, "film.height": 32, **sets}, spp=1, frames=frames)
    for _ in range(frames):
        r.render_frame()
    img = r.image()
    assert img.shape == (32, 48, 3) and img.dtype == np.float32
    assert img.any()
    assert np.array_equal(img, cli), f"max difference {np.abs(img - cli).max()}"
    # The rays each stage traced: the sidecar's counts of the CLI's last frame.
    side = json.loads(out.with_suffix(".json").read_text())
    counts = r.ray_counts()
    assert counts.pop("frame") == {k: sum(s[k] for s in side["stage_rays"][-1].values()) for k in ("closest", "any", "queued")}
    assert counts == side["stage_rays"][-1] and counts["primary"]["closest"] == 48 * 32


def test_render_equals_cli_reference(rl, tmp_path):
    # rl.render: the scene's path, nested option keys; pt at 8 spp in one frame.
    cli = rl.read_image(str(cli_render(tmp_path, "pt", "--spp", 8, "--res", "40x40", "--set", "path.max_depth=5")))
    img = rl.render(CORNELL, "pt", {"path": {"max_depth": 5}, "film": {"width": 40, "height": 40}}, spp=8)
    assert np.array_equal(img, cli)


def test_metrics_equal_cli_compare(rl, tmp_path):
    test = cli_render(tmp_path, "test", "--integrator", "restir-di", "--frames", 2, "--spp", 1, "--res", "32x32")
    ref = cli_render(tmp_path, "ref", "--spp", 16, "--res", "32x32", "--set", "path.max_depth=1")
    cmp = json.loads(run_cli("compare", test, ref, "--json").stdout)
    t, r = rl.read_image(str(test)), rl.read_image(str(ref))
    # FLIP after the default tone mapping, which is what the test EXR records (compare uses its header)
    assert rl.metrics.mse(t, r) == pytest.approx(cmp["mse"], rel=1e-8)
    assert rl.metrics.relmse(t, r) == pytest.approx(cmp["relmse"], rel=1e-8)
    assert rl.metrics.mae(t, r) == pytest.approx(cmp["mae"], rel=1e-8)
    assert rl.metrics.flip(t, r) == pytest.approx(cmp["flip"], rel=1e-8)
    assert rl.metrics.relmse(t, t) == 0.0
    assert "restir.config" in rl.read_exr_metadata(str(test))


def test_camera_per_frame(rl, cornell):
    # A camera given per frame replaces the scene's; the scene's own camera reproduces the default.
    opts = {"film.width": 24, "film.height": 24}
    a = rl.Renderer(cornell, "pt", opts, spp=2)
    a.render_frame()
    b = rl.Renderer(cornell, "pt", opts, spp=2)
    b.render_frame(a.camera(0))
    assert np.array_equal(a.image(), b.image())
    b.render_frame(rl.Camera.look_at(eye=(0, 1, 6.8), target=(0, 1, 0), fov=30))
    assert not np.array_equal(a.image(), b.image())
    assert b.frame == 2


def test_seek_renders_the_sequences_frame(rl, tmp_path):
    """seek(k): pt, which keeps no history, renders the CLI's frame k of an animated sequence bit for
    bit (pose, camera key, random streams); a ReSTIR integrator starts over at k, so a renderer that
    ran frames before seeking equals a fresh one that seeks there."""
    scene = str(ROOT / "scenes" / "dynamic-room.pbrt")
    run_cli("render", scene, "-q", "--integrator", "pt", "--frames", 5, "--spp", 2, "--res", "40x24",
            "--frame-dir", tmp_path / "f", "-o", tmp_path / "last.exr")
    cli = [rl.read_image(str(tmp_path / "f" / f"frame_{k:04d}.exr")) for k in range(5)]
    r = rl.Renderer(rl.load_scene(scene), "pt", {"film.width": 40, "film.height": 24}, spp=2, frames=5)
    for k in (3, 1, 4):
        r.seek(k)
        assert r.frame == k
        r.render_frame()
        assert np.array_equal(r.image(), cli[k]), f"frame {k}"
        assert not np.array_equal(r.image(), cli[k - 1])  # the scene moves: another frame differs
    sets = {"film.width": 40, "film.height": 24, "path.max_depth": 3, "pt.shift": "random-replay"}
    ran = rl.Renderer(rl.load_scene(scene), "restir-pt", sets, spp=1, frames=5)
    fresh = rl.Renderer(rl.load_scene(scene), "restir-pt", sets, spp=1, frames=5)
    for _ in range(3):
        ran.render_frame()
    for s in (ran, fresh):
        s.seek(2)
        s.render_frame()
        s.render_frame()
    assert np.array_equal(ran.image(), fresh.image())
    with pytest.raises(rl.OptionError, match="render.frames = 5"):
        r.seek(5)
