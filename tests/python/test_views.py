"""image() is a view of the renderer's buffer: no copy, valid while the renderer lives, and a
1000-frame loop does not grow the process; frame_buffer() hands over the integrator's own buffer
(DLPack)."""
import gc
import os

import numpy as np
import pytest

from conftest import CORNELL

W, H = 16, 16


def make(rl, cornell, integrator="restir-pt"):
    return rl.Renderer(cornell, integrator, {"film.width": W, "film.height": H}, spp=1, frames=8)


def data_pointer(a):
    return a.__array_interface__["data"][0]


def test_image_is_a_view(rl, cornell):
    r = make(rl, cornell)
    before = r.image()
    assert not before.any()  # the buffer exists before the first frame (zeros)
    r.render_frame()
    first = r.image().copy()
    r.render_frame()
    after = r.image()
    assert np.shares_memory(before, after) and data_pointer(before) == data_pointer(after)
    assert np.array_equal(before, after) and not np.array_equal(first, after)  # the frame was written in place
    before[3, 5, 1] = 1234.5  # a write through one view is seen by the other
    assert after[3, 5, 1] == np.float32(1234.5) and r.image()[3, 5, 1] == np.float32(1234.5)


def test_view_outlives_the_reference(rl, cornell):
    r = make(rl, cornell)
    r.render_frame()
    view = r.image()
    expected = view.copy()
    del r
    gc.collect()
    # Other allocations of the same size would reuse a freed buffer; the view still reads its frame.
    others = [make(rl, cornell) for _ in range(3)]
    for o in others:
        o.render_frame()
    assert np.array_equal(view, expected)
    del view
    gc.collect()


def rss_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def test_thousand_frames_do_not_grow(rl, cornell):
    r = make(rl, cornell)
    r.reset({"render.frames": 1000})
    total = 0.0
    for i in range(1000):
        r.render_frame()
        total += float(r.image()[0, 0, 0]) + sum(r.stage_times().values())
        if i == 199:  # warm-up: pools, caches and the allocator's arenas settle
            warm = rss_bytes()
    growth = rss_bytes() - warm
    print(f"RSS after 200 frames {warm / 2**20:.1f} MiB, growth over 800 more {growth / 1024:.0f} KiB")
    assert r.frame == 1000 and np.isfinite(total)
    assert growth < 1 << 20, f"RSS grew {growth} bytes over 800 frames"


def test_renderer_keeps_its_scene(rl):
    from conftest import CORNELL
    r = rl.Renderer(rl.load_scene(CORNELL), "pt", {"film.width": W, "film.height": H}, spp=1)  # no other reference
    gc.collect()
    r.render_frame()
    assert r.image().any()


@pytest.mark.parametrize("backend,integrator,sets", [
    ("cpu", "restir-di", {}),
    ("cpu-bvh", "restir-pt", {"path.max_depth": 3}),
    ("cpu", "pt", {"path.max_depth": 3}),
    ("cpu-bvh", "ssr", {"ssr.temporal": True}),
])
def test_frame_buffer_is_the_integrators_own_buffer(rl, backend, integrator, sets):
    """frame_buffer(): the integrator's buffer in the backend's memory as a DLPack array, no copy
    (host memory here; the GPU's on the CUDA backend): it equals image(), shows the next frame
    after render_frame(), and keeps the buffer alive across reset()."""
    r = rl.Renderer(rl.load_scene(CORNELL), integrator, {"film.width": 24, "film.height": 16, "render.backend": backend, **sets},
                    spp=1, frames=4)
    with pytest.raises(RuntimeError, match="no frame rendered"):
        r.frame_buffer()
    r.render_frame()
    fb = r.frame_buffer()
    assert fb.__dlpack_device__() == (1, 0)  # kDLCPU, device 0
    a = np.from_dlpack(fb)
    assert a.shape == (16, 24, 3) and a.dtype == np.float32
    assert np.array_equal(a, r.image())
    first = a.copy()
    r.render_frame()
    assert np.array_equal(a, r.image()) and not np.array_equal(a, first)  # a view of the buffer the next frame went into
    shown = a.copy()
    r.reset()  # a new integrator: the old one's buffer lives on while the array does
    r.render_frame()
    assert np.array_equal(a, shown)


@pytest.mark.parametrize("integrator,sets", [
    ("restir-pt", {"pt.direct": "restir-di"}),  # ReSTIR DI's image is added on the host
    ("restir-di", {"denoise.method": "asvgf"}),  # the previous frame is rendered into the buffer again
])
def test_frame_buffer_refused_where_the_buffer_is_not_the_frame(rl, integrator, sets):
    r = rl.Renderer(rl.load_scene(CORNELL), integrator, {"film.width": 8, "film.height": 8, **sets}, spp=1, frames=3)
    r.render_frame()
    r.render_frame()
    with pytest.raises(RuntimeError, match="use image"):
        r.frame_buffer()
