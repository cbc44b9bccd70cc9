"""The packages the engine declares (engine/requirements.txt), by the module each one provides: a module that is
missing is named with the line that installs it, not reported as a bug of ours."""

from __future__ import annotations

from pathlib import Path

REQUIREMENTS = Path(__file__).resolve().parents[1] / "requirements.txt"
# top-level module -> the distribution engine/requirements.txt names
DISTRIBUTIONS = {"cv2": "opencv-contrib-python-headless", "OpenImageIO": "OpenImageIO", "pycolmap": "pycolmap",
                 "plyfile": "plyfile", "gsplat": "gsplat", "torch": "torch", "numpy": "numpy", "tqdm": "tqdm",
                 "imageio_ffmpeg": "imageio-ffmpeg", "onnxruntime": "onnxruntime", "diffusers": "diffusers",
                 "transformers": "transformers", "accelerate": "accelerate", "google": "google-genai"}


def pinned(distribution: str) -> str:
    """The requirement line that names `distribution` (its pin), else the bare name."""
    lines = REQUIREMENTS.read_text().splitlines() if REQUIREMENTS.is_file() else []
    for line in lines:
        spec = line.split("#")[0].strip()
        name = spec.split("=")[0].split("<")[0].split(">")[0].strip()
        if name.lower() == distribution.lower():
            return spec
    return distribution


def missing_package_line(module: str) -> str | None:
    """One line naming the declared package that provides `module` and how to install it; None when `module`
    is none of the engine's declared packages (then its absence is a bug of ours)."""
    distribution = DISTRIBUTIONS.get(module.split(".")[0])
    if distribution is None:
        return None
    return (f"the engine needs the package {distribution} (module {module}), which this Python lacks: "
            f"pip install '{pinned(distribution)}' (or pip install -r {REQUIREMENTS})")
