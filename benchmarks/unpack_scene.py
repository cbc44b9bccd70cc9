"""On the GPU host: join every scene whose parts have all arrived in PARTS and unpack it into SCENES, WebP
back to PNG (lossless both ways), then mark it ready for the runner.

    python3 benchmarks/unpack_scene.py PARTS SCENES
"""

import io
import re
import sys
import tarfile
from pathlib import Path

import cv2

parts_dir, scenes = Path(sys.argv[1]), Path(sys.argv[2])
names = {}
for path in parts_dir.iterdir():
    match = re.fullmatch(r"(.+)\.tgz\.(\d+)of(\d+)", path.name)
    if match:
        names.setdefault((match[1], int(match[3])), {})[int(match[2])] = path
for (name, count), got in sorted(names.items()):
    if len(got) < count or (scenes / name / ".ready").exists():
        continue
    data = b"".join(got[k].read_bytes() for k in range(1, count + 1))
    with tarfile.open(fileobj=io.BytesIO(data), mode="r:gz") as tar:
        tar.extractall(scenes, filter="data")
    for webp in (scenes / name).rglob("*.webp"):
        cv2.imwrite(str(webp.with_suffix(".png")), cv2.imread(str(webp), cv2.IMREAD_UNCHANGED))
        webp.unlink()
    (scenes / name / ".ready").touch()
    print(f"unpacked {name}")
