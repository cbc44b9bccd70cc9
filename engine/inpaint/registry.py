"""Stage 4: 2D inpainters behind one interface, found by name.

    inpainter = create("fsr")                       # or "lama", with options such as model=PATH
    filled = inpainter.inpaint(image, mask, kind="rgb")   # uint8 (H, W, 3), mask bool (H, W)
    filled = inpainter.inpaint(depth, mask, kind="depth") # float32 (H, W) z-depth

Adding an inpainter is one new file in engine/inpaint/inpainters/ (or on SPLATFILL_PLUGINS): a subclass of
`Inpainter` decorated with `@register("name")`, with a one-line `summary` and what it `needs` (weights, a
GPU, a key, packages) for the CLI, the Blender menus and the README's table. Every such file is imported
when the registry is first asked, so nothing else changes.

Depth goes through the same image path the paper uses (a grey image over a depth range,
engine.inpaint.depth_range), unless an inpainter handles float depth itself. Pixels outside the mask are
always returned unchanged.
"""

from __future__ import annotations

from pathlib import Path
from typing import ClassVar

import numpy as np

from engine.base.errors import InputError
from engine.base.plugins import Needs, Registry
from engine.inpaint.coarse import fill_coarse
from engine.inpaint.depth_range import decode_depth, encode_depth

INPAINTERS: Registry[Inpainter] = Registry("inpainter", "engine.inpaint.inpainters")


def register(name: str):
    def add(cls: type[Inpainter]) -> type[Inpainter]:
        cls.name = name
        return INPAINTERS.add(name, cls)

    return add


class Inpainter:
    """Fill `mask` (True = fill) in an RGB image or a depth map."""

    name: ClassVar[str] = ""
    summary: ClassVar[str] = ""
    needs: ClassVar[Needs] = Needs()
    uses_mask: ClassVar[bool] = True  # False: paints the object out of the original image from a prompt
    max_hole_px: ClassVar[int] = 0  # a larger hole is filled downscaled (engine.inpaint.coarse); 0: never

    def parallel_views(self) -> str:
        """How a run may inpaint several views at once: "threads" for CPU work that lets go of Python's lock
        (OpenCV, torch on the CPU), "processes" for work bound by Python itself (many small steps each), ""
        for one view at a time (models on a GPU, remote services)."""
        return ""

    def default_prompt(self, scene_root: Path) -> str | None:
        """The prompt for a scene when the user gives none (None: this inpainter needs no prompt)."""
        return None

    def __init__(self, depth_range: str = "foreground", **options) -> None:
        if depth_range not in ("global", "foreground"):
            raise InputError(f"depth range {depth_range!r} unknown: use 'global' or 'foreground'")
        self.depth_range = depth_range
        if options:
            raise InputError(f"inpainter {self.name!r} takes no options {sorted(options)}")

    def inpaint(self, image: np.ndarray, mask: np.ndarray, kind: str = "rgb", prompt: str | None = None
                ) -> np.ndarray:
        mask = np.asarray(mask, dtype=bool)
        if not mask.any():
            return image.copy()
        if kind == "rgb":
            filled = fill_coarse(lambda im, m: self.inpaint_rgb(im, m, prompt),
                                 np.ascontiguousarray(image, dtype=np.uint8), mask, self.max_hole_px)
        elif kind == "depth":
            filled = self.inpaint_depth(np.asarray(image, dtype=np.float32), mask, prompt)
        else:
            raise InputError(f"kind must be 'rgb' or 'depth', not {kind!r}")
        return np.where(mask[..., None] if image.ndim == 3 else mask, filled, image).astype(image.dtype)

    def inpaint_rgb(self, image: np.ndarray, mask: np.ndarray, prompt: str | None) -> np.ndarray:
        raise NotImplementedError

    def inpaint_depth(self, depth: np.ndarray, mask: np.ndarray, prompt: str | None) -> np.ndarray:
        grey, near, far = encode_depth(depth, mask, self.depth_range)
        filled = fill_coarse(lambda im, m: self.inpaint_grey(im, m, prompt), np.repeat(grey[..., None], 3, axis=2),
                             mask, self.max_hole_px)
        return decode_depth(filled.mean(axis=2), near, far)

    def inpaint_grey(self, grey: np.ndarray, mask: np.ndarray, prompt: str | None) -> np.ndarray:
        """Depth encoded as a grey RGB image; an inpainter with depth-specific settings overrides this."""
        return self.inpaint_rgb(grey, mask, prompt)


def names() -> list[str]:
    return INPAINTERS.names()


def classes() -> dict[str, type[Inpainter]]:
    """Every registered inpainter class by name (to describe them without building one)."""
    return INPAINTERS.classes()


def create(name: str, **options) -> Inpainter:
    """The inpainter registered as `name`, built with `options` (e.g. model=PATH for lama)."""
    return INPAINTERS.get(name)(**options)
