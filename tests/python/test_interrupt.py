"""Ctrl-C stops a long render promptly with KeyboardInterrupt, and the renderer stays usable."""
import os
import subprocess
import sys
import textwrap

from conftest import CORNELL, ROOT

SCRIPT = textwrap.dedent(f"""
    import os, signal, sys, threading, time
    import restirlab as rl
    scene = rl.load_scene({CORNELL!r})
    r = rl.Renderer(scene, "pt", {{"film.width": 64, "film.height": 64}}, spp=200000)  # minutes of work
    sent = []
    def interrupt():
        sent.append(time.monotonic())
        os.kill(os.getpid(), signal.SIGINT)
    threading.Timer(0.5, interrupt).start()
    try:
        r.render_frame()
        print("not interrupted")
    except KeyboardInterrupt:
        print(f"interrupted after {{time.monotonic() - sent[0]:.3f}} s")
    r.reset({{"render.spp": 1}})
    r.render_frame()
    print("frame after interrupt:", r.frame)
""")


def test_ctrl_c_interrupts_a_frame():
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    p = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, env=env, cwd=ROOT, timeout=120)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert lines[0].startswith("interrupted after "), p.stdout
    assert float(lines[0].split()[2]) < 1.0
    assert lines[1] == "frame after interrupt: 1"
