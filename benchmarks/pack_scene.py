"""Pack generated scenes small, in chunks of a given size, to send them to a GPU host.

A 640x480/100-view scene is about 50 MB as PNGs. Packing drops what the GPU stages never read (depth/, gt_depth/:
only `engine preview` shows them) and stores images/ and gt/ as lossless WebP, checked pixel for pixel here, in
chunks of at most CHUNK_MB for transfers capped in size; `unpack_scene.py` on the GPU host (benchmarks/gpu.sh runs
it) writes them back as PNG.

    python benchmarks/pack_scene.py OUT_DIR CHUNK_MB SCENE...    ->  OUT_DIR/<scene>.tgz.<k>of<n>
"""

import io
import sys
import tarfile
from pathlib import Path

import cv2
import numpy as np

SKIP = {"depth", "gt_depth"}
WEBP = {"images", "gt"}


def _webp(path: Path) -> bytes:
    image = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    ok, data = cv2.imencode(".webp", image, [cv2.IMWRITE_WEBP_QUALITY, 101])  # above 100: lossless
    back = cv2.imdecode(np.frombuffer(data.tobytes(), np.uint8), cv2.IMREAD_UNCHANGED)
    if not ok or back.shape != image.shape or not np.array_equal(back, image):
        raise SystemExit(f"{path}: WebP round trip is not exact")
    return data.tobytes()


def _tar(scene: Path) -> bytes:
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w:gz") as tar:
        for path in sorted(scene.rglob("*")):
            rel = path.relative_to(scene)
            if path.is_dir() or rel.parts[0] in SKIP:
                continue
            name = f"{scene.name}/{rel}"
            if rel.parts[0] in WEBP and path.suffix == ".png":
                data = _webp(path)
                info = tarfile.TarInfo(name[:-4] + ".webp")
                info.size = len(data)
                tar.addfile(info, io.BytesIO(data))
            else:
                tar.add(path, arcname=name)
    return buffer.getvalue()


def main() -> None:
    out, chunk = Path(sys.argv[1]), int(float(sys.argv[2]) * 2**20)
    out.mkdir(parents=True, exist_ok=True)
    for scene in map(Path, sys.argv[3:]):
        data = _tar(scene)
        parts = [data[i:i + chunk] for i in range(0, len(data), chunk)]
        for k, part in enumerate(parts, 1):
            (out / f"{scene.name}.tgz.{k}of{len(parts)}").write_bytes(part)
        print(f"{scene.name}: {len(data) / 2**20:.1f} MB in {len(parts)} parts")


if __name__ == "__main__":
    main()
