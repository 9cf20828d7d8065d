"""Renderer.aovs(): the AOVs of the last frame against analytic values on a plane seen head-on
(depth = the plane's distance along the view axis, normal toward the camera, depth gradient 0,
albedo = its reflectance), motion 0 under a still camera and the analytic shift under a moving
one; and denoised() with an SVGF denoiser."""
import numpy as np
import pytest

PLANE = """LookAt 0 0 0  0 0 5  0 1 0
Camera "perspective" "float fov" 40
Film "rgb" "integer xresolution" 32 "integer yresolution" 24
WorldBegin
LightSource "infinite" "rgb L" [1 1 1]
Material "diffuse" "rgb reflectance" [0.25 0.5 0.75]
Shape "trianglemesh" "point3 P" [ -50 -50 5  50 -50 5  50 50 5  -50 50 5 ] "integer indices" [ 0 1 2 0 2 3 ]
"""


@pytest.fixture()
def plane(rl, tmp_path):
    path = tmp_path / "plane.pbrt"
    path.write_text(PLANE)
    return rl.load_scene(str(path))


def test_aovs_on_a_plane(rl, plane):
    r = rl.Renderer(plane, "pt", {"path.max_depth": 1}, spp=1, frames=2, aovs=True)
    r.render_frame()
    a = r.aovs()
    assert a["depth"].shape == (24, 32) and a["albedo"].shape == (24, 32, 3) and a["motion"].shape == (24, 32, 2)
    np.testing.assert_allclose(a["depth"], 5.0, rtol=1e-5)
    np.testing.assert_allclose(a["depth_gradient"], 0.0, atol=1e-4)
    np.testing.assert_allclose(a["normal"], np.broadcast_to([0, 0, -1], a["normal"].shape), atol=1e-6)
    np.testing.assert_allclose(a["albedo"], np.broadcast_to([0.25, 0.5, 0.75], a["albedo"].shape), rtol=1e-6)
    np.testing.assert_array_equal(a["emission"], 0)
    assert a["surface_id"].dtype == np.uint32 and (a["surface_id"] == 0).all()
    r.render_frame()  # the same camera: no motion
    np.testing.assert_allclose(r.aovs()["motion"], 0.0, atol=1e-4)


def test_motion_under_a_moving_camera(rl, plane):
    r = rl.Renderer(plane, "pt", {"path.max_depth": 1}, spp=1, frames=2, aovs=True)
    cam = rl.Camera.look_at([0, 0, 0], [0, 0, 5], [0, 1, 0], 40)
    r.render_frame(cam)
    moved = rl.Camera.look_at([0.1, 0, 0], [0.1, 0, 5], [0, 1, 0], 40)
    r.render_frame(moved)
    m = r.aovs()["motion"]
    # A sideways move by 0.1 at depth 5: the plane's points were 0.1 / (5 tan(20 deg)) x 12 pixels
    # to one side of where they are now (pbrt's fov spans the shorter axis: 24 pixels, 12 per half).
    shift = 0.1 / (5 * np.tan(np.radians(20))) * 12
    assert np.allclose(np.abs(m[..., 0]), shift, rtol=1e-3) and np.allclose(m[..., 1], 0, atol=1e-4)
    assert len(np.unique(np.sign(m[..., 0]))) == 1


def test_aovs_need_asking(rl, plane):
    r = rl.Renderer(plane, "pt", {"path.max_depth": 1}, spp=1, frames=1)
    with pytest.raises(RuntimeError, match="no frame rendered yet"):
        r.aovs()
    r.render_frame()
    with pytest.raises(RuntimeError, match="aovs=True"):
        r.aovs()
    assert r.denoised() is None


def test_denoised_frame(rl, plane):
    r = rl.Renderer(plane, "pt", {"path.max_depth": 1, "denoise.method": "svgf"}, spp=1, frames=4)
    for _ in range(4):
        r.render_frame()
    d = r.denoised()
    assert d.shape == r.image().shape and np.isfinite(d).all()
    assert not np.shares_memory(d, r.image())
    assert r.aovs()["depth"].shape == (24, 32)  # a denoiser builds the AOVs anyway
