"""Classical inpainters that need no weights: OpenCV's Telea and Navier-Stokes, and cv2.xphoto's FSR
(frequency-selective reconstruction) and shift-map (exemplar-based: copies whole patches from elsewhere in
the image, so texture survives where diffusion-style fills blur)."""

from __future__ import annotations

import cv2
import numpy as np

from engine.base.errors import InputError
from engine.base.plugins import Needs
from engine.base.requirements import pinned
from engine.inpaint.registry import Inpainter, register

RADIUS = 5  # px of neighbourhood Telea and Navier-Stokes look at


class OpenCvInpainter(Inpainter):
    """OpenCV's inpainters run in C++ without Python's lock, so a run's views can go at once. Their cost grows
    with the hole's area: a photo's object footprint (300k pixels of a 1 MP view) took Telea 6 s, so a hole
    above max_hole_px is filled downscaled (engine.inpaint.coarse), where a smooth fill loses nothing."""

    max_hole_px = 20_000

    def parallel_views(self) -> str:
        return "threads"


@register("telea")
class Telea(OpenCvInpainter):
    summary = "OpenCV Telea: smooth fill from the hole's border"
    def inpaint_rgb(self, image, mask, prompt):
        return cv2.inpaint(image, mask.astype(np.uint8), RADIUS, cv2.INPAINT_TELEA)


@register("navier-stokes")
class NavierStokes(OpenCvInpainter):
    summary = "OpenCV Navier-Stokes: smooth fill along isophotes"
    def inpaint_rgb(self, image, mask, prompt):
        return cv2.inpaint(image, mask.astype(np.uint8), RADIUS, cv2.INPAINT_NS)


class XphotoInpainter(OpenCvInpainter):
    """cv2.xphoto comes with OpenCV's contrib modules only: without them (a plain opencv-python install beside
    ours) the inpainter refuses at once, naming the package, instead of failing inside a view's worker."""

    needs = Needs(packages=("opencv-contrib",))

    def __init__(self, **options) -> None:
        super().__init__(**options)
        if not hasattr(cv2, "xphoto"):
            raise InputError(f"the {self.name} inpainter needs OpenCV's contrib modules (cv2.xphoto), which this "
                             f"OpenCV {cv2.__version__} lacks: pip uninstall -y opencv-python-headless "
                             f"opencv-python; pip install '{pinned('opencv-contrib-python-headless')}'")


def _xphoto(image: np.ndarray, mask: np.ndarray, method: int) -> np.ndarray:
    """cv2.xphoto.inpaint takes the mask the other way round: non-zero marks the *known* pixels."""
    known = (~mask).astype(np.uint8) * 255
    out = np.zeros_like(image)
    cv2.xphoto.inpaint(image, known, out, method)
    return out


@register("fsr")
class FrequencySelective(XphotoInpainter):
    """FSR models each block around the hole as a sum of frequencies: its cost grows with the hole, 30 s for a
    108k-pixel hole of a 1 MP view, so a larger hole than max_hole_px is filled downscaled (engine.inpaint.coarse),
    where its smooth fill loses nothing."""

    summary = "OpenCV xphoto frequency-selective reconstruction"
    max_hole_px = 6000
    def inpaint_rgb(self, image, mask, prompt):
        return _xphoto(image, mask, cv2.xphoto.INPAINT_FSR_FAST)


@register("shiftmap")
class ShiftMap(XphotoInpainter):
    summary = "OpenCV xphoto shift-map: texture synthesis by copying patches"
    max_hole_px = 6000  # 130 s a 1 MP view at full size
    def inpaint_rgb(self, image, mask, prompt):
        # shift-map works in Lab, as its authors' OpenCV sample does
        lab = cv2.cvtColor(image, cv2.COLOR_RGB2Lab)
        return cv2.cvtColor(_xphoto(lab, mask, cv2.xphoto.INPAINT_SHIFTMAP), cv2.COLOR_Lab2RGB)
