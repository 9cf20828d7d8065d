#!/usr/bin/env python3
"""A ReSTIR PT sequence rendered frame by frame, each frame's error against a path-traced reference.

  python examples/render_sequence.py [--scene scenes/teapot.pbrt] [--frames 8] [--out out/py]
Writes OUT/restir-pt.exr and .png (the last frame, as `restir render -o --png` would) and prints the
error and the stage times of every frame.
"""
import argparse
import os

import restirlab as rl


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scene", default="scenes/teapot.pbrt")
    p.add_argument("--frames", type=int, default=8)
    p.add_argument("--size", default="160x90", help="WxH")
    p.add_argument("--out", default="out/py")
    args = p.parse_args()
    w, h = map(int, args.size.split("x"))
    film = {"film.width": w, "film.height": h}
    scene = rl.load_scene(args.scene)
    ref = rl.render(scene, "pt", film, spp=256)
    r = rl.Renderer(scene, "restir-pt", {**film, "pt.shift": "hybrid"}, spp=1, frames=args.frames)
    for f in range(args.frames):
        r.render_frame()
        stages = ", ".join(f"{k} {v:.1f}" for k, v in r.stage_times().items())
        print(f"frame {f}: {r.frame_ms:6.1f} ms  relMSE {rl.metrics.relmse(r.image(), ref):.4f}  ({stages})")
    os.makedirs(args.out, exist_ok=True)
    rl.write_exr(f"{args.out}/restir-pt.exr", r.image(), {"restir.scene": args.scene})
    rl.write_png(f"{args.out}/restir-pt.png", r.image())
    print(f"wrote {args.out}/restir-pt.exr and .png; FLIP of the last frame {rl.metrics.flip(r.image(), ref):.4f}")


if __name__ == "__main__":
    main()
