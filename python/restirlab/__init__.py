"""restir-lab from Python: scenes, frame loops, metrics and studies (issue 47).

Bindings over the C++ library (``_core``); this file adds only what is plainer in Python:
``render`` (a whole sequence), ``study`` (a results table for pandas) and the ``metrics`` module.
"""
from __future__ import annotations

import os
from dataclasses import dataclass

from . import metrics
from ._core import (BackendError, Camera, ImageError, IoError, OptionError, Renderer, RenderError, Scene,
                    SceneError, StudyError, build_id, integrators, load_scene, options_help, read_exr_metadata,
                    read_image, tonemap, write_exr, write_png)
from ._core import run_study as _run_study

__all__ = ["BackendError", "Camera", "ImageError", "IoError", "OptionError", "Renderer", "RenderError", "Scene",
           "SceneError", "StudyError", "StudyResult", "build_id", "integrators", "load_scene", "metrics",
           "options_help", "read_exr_metadata", "read_image", "render", "study", "tonemap", "write_exr", "write_png"]


def render(scene: Scene | str, integrator: str | None = None, options: dict | None = None, **settings) -> "numpy.ndarray":
    """The last frame of a whole sequence, as ``restir render`` writes it with ``-o``.

    ``settings``: spp, frames, seed, threads (the CLI's flags). Returns a float32 H x W x 3 array of its own.
    """
    if isinstance(scene, (str, os.PathLike)):
        scene = load_scene(os.fspath(scene))
    r = Renderer(scene, integrator, options, **settings)
    for _ in range(r.frames):
        r.render_frame()
    return r.image().copy()  # not a view: the renderer (BVH, history) is freed


@dataclass(frozen=True)
class StudyResult:
    """Where a study wrote its results: results.csv, results.json, plots and report.html."""
    out: str

    @property
    def csv(self) -> str:
        return os.path.join(self.out, "results.csv")

    @property
    def report(self) -> str:
        return os.path.join(self.out, "report.html")

    def to_pandas(self):
        import pandas as pd  # only this needs pandas
        return pd.read_csv(self.csv)


def study(name: str, out: str, *, quick: bool = False, jobs: int = 1, quiet: bool = True) -> StudyResult:
    """Runs ``restir study NAME --out OUT`` (a built-in name or a study JSON file); resumable as the CLI is."""
    status = _run_study(os.fspath(name), os.fspath(out), quick, jobs, quiet)
    if status != 0:
        raise StudyError(f"study {name}: finished with status {status} (see {out})")
    return StudyResult(os.fspath(out))
