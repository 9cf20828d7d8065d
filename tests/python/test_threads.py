"""render_frame() releases the GIL: other Python threads run meanwhile, and one that calls into the
same renderer is refused rather than raced."""
import threading
import time


def test_gil_released_while_rendering(rl, cornell):
    r = rl.Renderer(cornell, "pt", {"film.width": 64, "film.height": 64}, spp=8)
    start = time.perf_counter()
    r.render_frame()
    spp = max(8, int(8 * 0.5 / (time.perf_counter() - start)))  # one frame of about 0.5 s on this machine
    r.reset({"render.spp": spp})
    ticks, errors, stop = [0], [], threading.Event()

    def other():
        while not stop.is_set():
            ticks[0] += 1
            time.sleep(0.001)

    def intruder():
        time.sleep(0.1)
        try:
            r.render_frame()
        except RuntimeError as e:
            errors.append(str(e))

    threads = [threading.Thread(target=other), threading.Thread(target=intruder)]
    for t in threads:
        t.start()
    start = time.perf_counter()
    r.render_frame()
    elapsed = time.perf_counter() - start
    stop.set()
    for t in threads:
        t.join()
    assert elapsed > 0.15, "the frame must outlast the intruder's start for this test to mean anything"
    assert ticks[0] > 20  # the other thread ran while the frame rendered
    assert errors == ["Renderer.render_frame: the renderer is rendering in another thread"]
    assert r.frame == 1
