#!/usr/bin/env python3
"""The Python module's cost per frame against the CLI's, measured in one run (issue 47).

Both render the same ReSTIR PT sequence at 640x360 (1 spp per frame); the CLI's frame times are its
own (`frame_ms` of the JSON sidecar), Python's are the wall time of each render_frame() call as a
script sees it (binding, GIL release, the Ctrl-C poll included). Frame 0 of each run is left out
(no temporal history yet); runs alternate CLI / Python so that a machine's drift hits both. Prints
the median ratio (and the fastest frames', less sensitive to other processes on a shared machine);
the target is within 2 %.

  PYTHONPATH=build/python build/pyenv/bin/python bench/python_overhead.py [--frames 10] [--runs 3]
"""
import argparse
import json
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import restirlab as rl

ROOT = Path(__file__).resolve().parents[1]


def cli_frames(restir, scene, args, out):
    subprocess.run([restir, "render", scene, "-q", "--integrator", "restir-pt", "--spp", "1", "--frames", str(args.frames),
                    "--res", "640x360", "-o", str(out)], check=True, cwd=ROOT)
    return json.loads(out.with_suffix(".json").read_text())["frame_ms"][1:]


def python_frames(scene, args):
    r = rl.Renderer(scene, "restir-pt", {"film.width": 640, "film.height": 360}, spp=1, frames=args.frames)
    wall, inner = [], []
    for _ in range(args.frames):
        t = time.perf_counter()
        r.render_frame()
        wall.append(1e3 * (time.perf_counter() - t))
        inner.append(r.frame_ms)
    return wall[1:], inner[1:]


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scene", default="scenes/cornell-box.pbrt")
    p.add_argument("--frames", type=int, default=10)
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--restir", default=str(ROOT / "build" / "bin" / "restir"))
    args = p.parse_args()
    scene_path = str(ROOT / args.scene)
    scene = rl.load_scene(scene_path)
    cli, wall, inner = [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        for i in range(args.runs):
            cli += cli_frames(args.restir, scene_path, args, Path(tmp) / f"cli{i}.exr")
            w, n = python_frames(scene, args)
            wall += w
            inner += n
    c, w, n = statistics.median(cli), statistics.median(wall), statistics.median(inner)
    print(f"{args.scene}, restir-pt, 640x360, {args.runs} runs x {args.frames - 1} frames: median ms per frame")
    print(f"  CLI (its frame_ms)                 {c:9.2f}")
    print(f"  Python, render_frame() wall time   {w:9.2f}")
    print(f"  Python, the renderer's frame_ms    {n:9.2f}")
    print(f"ratio Python / CLI: {w / c:.4f} ({100 * (w / c - 1):+.2f} %; target within 2 %)")
    # The fastest frame of each: what a frame costs when no other process takes the cores.
    print(f"ratio of the fastest frames: {min(wall) / min(cli):.4f}")
    print(f"the binding's own cost (wall / frame_ms): {w / n:.4f} ({w - n:.3f} ms per frame)")


if __name__ == "__main__":
    main()
