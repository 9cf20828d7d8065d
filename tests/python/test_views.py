"""image() is a view of the renderer's buffer: no copy, valid while the renderer lives, and a
1000-frame loop does not grow the process."""
import gc
import os

import numpy as np

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
