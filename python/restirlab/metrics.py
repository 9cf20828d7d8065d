"""Error metrics of a test image against a reference, the study's own (src/image/metrics.h, flip.h).

Each takes two float32 H x W x 3 linear images (Renderer.image(), render(), read_image()).
"""
from ._core import flip, mae, mse, relmse

__all__ = ["flip", "mae", "mse", "relmse"]
